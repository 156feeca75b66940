//! `[fem]`: the raw section of the flexible disc (engineering units) and its conversion to the
//! SI parameters of the disc model ([`FemParams`]).

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::error::{Error, Result};
use crate::fem::plane::PlaneStress;
use crate::fem::{outline_radii, FemParams, Hole, BYTES_PER_NODE};
use crate::geometry::{Profile, Vec2};

fn invalid(field: &str, v: f64, words: impl Into<String>) -> Error {
    Error::invalid(format!("fem.{field}"), v, words.into())
}

fn range(field: &str, v: f64, lo: f64, hi: f64, unit: &'static str) -> Result<f64> {
    check(&format!("fem.{field}"), v, Range::closed(lo, hi, unit))
}

/// `[fem]`: the flexible disc (engineering units; see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FemConfig {
    /// Adds the flexible results to every stage of `rvlife run`.
    #[serde(default)]
    pub enabled: bool,
    /// Diameter of the crank bearing bores, mm (default: twice `dynamics.inertia.crank_bore_radius_mm`).
    /// Range: [1, root radius] mm, holes clear of the teeth and of each other.
    #[serde(default)]
    pub crank_bore_diameter_mm: Option<f64>,
    /// Radius of the circle of the crank bores, mm (default: the sun-planet centre distance of
    /// `dynamics.gears`). Range: [1, root radius] mm.
    #[serde(default)]
    pub crank_circle_radius_mm: Option<f64>,
    /// Number of output-pin (carrier pillar) holes; 0 for none. Range: whole number, 0 to 24.
    #[serde(default = "d_holes")]
    pub output_pin_holes: u32,
    /// Diameter of the output-pin holes, mm (default: the paper's 22 mm scaled with the disc's
    /// root radius, `crate::geometry::CycloidGeometry::scaled_from_root`).
    /// Range: [0.5, root radius] mm.
    #[serde(default)]
    pub output_pin_hole_diameter_mm: Option<f64>,
    /// Radius of the circle of the output-pin holes, mm (default: the crank circle radius).
    /// Range: [0, root radius] mm.
    #[serde(default)]
    pub output_pin_circle_radius_mm: Option<f64>,
    /// Angle of the first output-pin hole from the first crank bore, deg (default `180/holes`:
    /// between the bores). Range: [-360, 360] deg.
    #[serde(default)]
    pub output_pin_hole_phase_deg: Option<f64>,
    /// Diameter of the centre hole (input shaft passage), mm; 0 for none (default: the paper's
    /// 30 mm scaled with the disc's root radius, `crate::geometry::CycloidGeometry::scaled_from_root`).
    /// Range: [0, 2 x root radius] mm.
    #[serde(default)]
    pub centre_hole_diameter_mm: Option<f64>,
    /// Element size along the tooth outline, mm.
    /// Range: [0.01, 5] mm, the mesh within max_memory_gb.
    #[serde(default = "d_flank")]
    pub flank_element_size_mm: f64,
    /// Largest element size inside the disc, mm. Range: [flank_element_size_mm, 50] mm.
    #[serde(default = "d_max_size")]
    pub max_element_size_mm: f64,
    /// Half-width of the pressure patch that stands for a pin load, mm.
    /// Range: [1.5 x flank_element_size_mm, 5] mm.
    #[serde(default = "d_patch")]
    pub load_patch_half_width_mm: f64,
    /// Load stations per tooth flank. Range: whole number, 4 to 200.
    #[serde(default = "d_stations")]
    pub stations_per_flank: u32,
    /// Crank angles per crank revolution of the flexible analysis. Range: whole number, 4 to 3600.
    #[serde(default = "d_cranks")]
    pub crank_angles: u32,
    /// Measuring torque of the flexible STE, as a fraction of the rated torque (lost-motion
    /// convention of RV catalogues: +-3 % of the rated torque). Range: [1e-4, 0.5].
    #[serde(default = "d_ste_fraction")]
    pub ste_torque_fraction: f64,
    /// Memory the disc model may use, GB; a finer mesh is refused. Range: [0.01, 1024] GB.
    #[serde(default = "d_memory")]
    pub max_memory_gb: f64,
}

fn d_holes() -> u32 {
    2
}
fn d_flank() -> f64 {
    0.25
}
fn d_max_size() -> f64 {
    4.0
}
fn d_patch() -> f64 {
    0.5
}
fn d_stations() -> u32 {
    14
}
fn d_cranks() -> u32 {
    72
}
fn d_ste_fraction() -> f64 {
    0.03
}
fn d_memory() -> f64 {
    2.0
}

impl Default for FemConfig {
    fn default() -> Self {
        FemConfig {
            enabled: false,
            crank_bore_diameter_mm: None,
            crank_circle_radius_mm: None,
            output_pin_holes: d_holes(),
            output_pin_hole_diameter_mm: None,
            output_pin_circle_radius_mm: None,
            output_pin_hole_phase_deg: None,
            centre_hole_diameter_mm: None,
            flank_element_size_mm: d_flank(),
            max_element_size_mm: d_max_size(),
            load_patch_half_width_mm: d_patch(),
            stations_per_flank: d_stations(),
            crank_angles: d_cranks(),
            ste_torque_fraction: d_ste_fraction(),
            max_memory_gb: d_memory(),
        }
    }
}

impl FemConfig {
    /// Checks the section for the disc `profile` with `cranks` crank bores, `default_bore_radius`
    /// and `default_crank_circle` (m, from the dynamics section) and the disc material `E`, `nu`
    /// (Pa).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the `fem.*` key, the value and the allowed range: holes that cut
    /// the tooth roots or each other, sizes out of range, or a mesh whose estimated memory
    /// exceeds `fem.max_memory_gb`.
    pub fn validate(
        &self,
        profile: &Profile,
        cranks: usize,
        default_bore_radius: f64,
        default_crank_circle: f64,
        youngs_modulus: f64,
        poisson_ratio: f64,
    ) -> Result<FemParams> {
        let (root, _) = outline_radii(profile);
        let root_mm = root * 1e3;
        let flank = range(
            "flank_element_size_mm",
            self.flank_element_size_mm,
            0.01,
            5.0,
            "mm",
        )? * 1e-3;
        let max_size = range(
            "max_element_size_mm",
            self.max_element_size_mm,
            self.flank_element_size_mm,
            50.0,
            "mm (at least the flank element size)",
        )? * 1e-3;
        let patch = range(
            "load_patch_half_width_mm",
            self.load_patch_half_width_mm,
            1.5 * self.flank_element_size_mm,
            5.0,
            "mm (at least 1.5 flank elements, so that the mesh resolves the patch)",
        )? * 1e-3;
        let bore_d = self
            .crank_bore_diameter_mm
            .unwrap_or(2e3 * default_bore_radius);
        let centre_d = self
            .centre_hole_diameter_mm
            .unwrap_or_else(|| profile.geometry().scaled_from_root(30.0));
        let hole_d = self
            .output_pin_hole_diameter_mm
            .unwrap_or_else(|| profile.geometry().scaled_from_root(22.0));
        let bore_r = range("crank_bore_diameter_mm", bore_d, 1.0, root_mm, "mm")? * 0.5e-3;
        let circle = self
            .crank_circle_radius_mm
            .unwrap_or(default_crank_circle * 1e3);
        let circle = range("crank_circle_radius_mm", circle, 1.0, root_mm, "mm")? * 1e-3;
        // Ligament the mesh needs between two boundaries: two flank elements.
        let lig = 2.0 * flank;
        let mut bores = Vec::new();
        for k in 0..cranks {
            let a = TAU * k as f64 / cranks as f64;
            bores.push(Hole {
                centre: crate::geometry::portable::unit(a) * circle,
                radius: bore_r,
            });
        }
        let mut holes = Vec::new();
        let centre_r = range(
            "centre_hole_diameter_mm",
            centre_d,
            0.0,
            2.0 * root_mm,
            "mm",
        )? * 0.5e-3;
        let n_holes = self.output_pin_holes as usize;
        if n_holes > 24 {
            return Err(invalid(
                "output_pin_holes",
                n_holes as f64,
                "must be a whole number from 0 to 24",
            ));
        }
        if n_holes > 0 {
            let hole_r = range("output_pin_hole_diameter_mm", hole_d, 0.5, root_mm, "mm")? * 0.5e-3;
            let pc = self.output_pin_circle_radius_mm.unwrap_or(circle * 1e3);
            let pc = range("output_pin_circle_radius_mm", pc, 0.0, root_mm, "mm")? * 1e-3;
            let phase = self
                .output_pin_hole_phase_deg
                .unwrap_or(180.0 / n_holes as f64);
            let phase =
                range("output_pin_hole_phase_deg", phase, -360.0, 360.0, "deg")?.to_radians();
            for k in 0..n_holes {
                let a = phase + TAU * k as f64 / n_holes as f64;
                holes.push(Hole {
                    centre: crate::geometry::portable::unit(a) * pc,
                    radius: hole_r,
                });
            }
        }
        if centre_r > 0.0 {
            holes.push(Hole {
                centre: Vec2::zeros(),
                radius: centre_r,
            });
        }
        // Every hole inside the root circle, and no two holes touching.
        let named: Vec<(&str, f64, &Hole)> = bores
            .iter()
            .map(|h| ("crank_bore_diameter_mm", bore_d, h))
            .chain(holes.iter().map(|h| {
                if h.centre.norm() == 0.0 {
                    ("centre_hole_diameter_mm", centre_d, h)
                } else {
                    ("output_pin_hole_diameter_mm", hole_d, h)
                }
            }))
            .collect();
        for (field, v, h) in &named {
            let outer = h.centre.norm() + h.radius;
            if outer > root - lig {
                return Err(invalid(
                    field,
                    *v,
                    format!(
                        "the hole reaches {:.3} mm from the disc centre and cuts the teeth: it \
                         must stay inside the tooth-root radius {:.3} mm minus {:.3} mm",
                        outer * 1e3,
                        root_mm,
                        lig * 1e3
                    ),
                ));
            }
        }
        for (i, (fa, va, a)) in named.iter().enumerate() {
            for (fb, _, b) in named.iter().skip(i + 1) {
                let gap = (a.centre - b.centre).norm() - a.radius - b.radius;
                if gap < lig {
                    return Err(invalid(
                        fa,
                        *va,
                        format!(
                            "this hole and the one of `fem.{fb}` leave a ligament of {:.3} mm; \
                             holes must not cut each other (at least {:.3} mm between them)",
                            gap * 1e3,
                            lig * 1e3
                        ),
                    ));
                }
            }
        }
        let stations = self.stations_per_flank;
        if !(4..=200).contains(&stations) {
            return Err(invalid(
                "stations_per_flank",
                stations as f64,
                "must be a whole number from 4 to 200",
            ));
        }
        let crank_angles = self.crank_angles;
        if !(4..=3600).contains(&crank_angles) {
            return Err(invalid(
                "crank_angles",
                crank_angles as f64,
                "must be a whole number from 4 to 3600",
            ));
        }
        let ste = range(
            "ste_torque_fraction",
            self.ste_torque_fraction,
            1e-4,
            0.5,
            "",
        )?;
        let mem = range("max_memory_gb", self.max_memory_gb, 0.01, 1024.0, "GB")?;
        let params = FemParams {
            bores,
            holes,
            material: PlaneStress {
                youngs_modulus,
                poisson_ratio,
                thickness: profile.geometry().width,
            },
            flank_size: flank,
            max_size,
            patch,
            stations_per_flank: stations as usize,
            crank_angles: crank_angles as usize,
            ste_torque_fraction: ste,
            max_memory: mem * 1e9,
        };
        let est = params.estimated_nodes(profile) * BYTES_PER_NODE;
        if est > params.max_memory {
            return Err(invalid(
                "flank_element_size_mm",
                self.flank_element_size_mm,
                format!(
                    "the mesh would need about {:.1} GB, more than fem.max_memory_gb = {} GB: \
                     use a larger element size",
                    est / 1e9,
                    mem
                ),
            ));
        }
        Ok(params)
    }
}
