//! `[reducer.structure]`: the dimensions of the parts around the crank bearings and the meshes
//! that the series parts of docs/model.md section 5.9 are computed from (the crankshafts, the
//! input shaft), and the structure compliance that stands for what the model leaves out. The
//! closed forms are [`crate::reducer::structure`]'s; this file checks the keys and applies the
//! defaults (estimates for the RV-E class, scaled with the stage, each marked as such).

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::error::{Error, Result};
use crate::geometry::CycloidGeometry;
use crate::reducer::structure::{CrankBeam, HousingRing};

/// `[reducer.structure]` (RV only; every key optional).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StructureConfig {
    /// Diameter of the crankshafts at their bearings, mm (default 0.4 of the crank circle
    /// radius, 16.2 mm on the example: **estimate**). It sets the crank's bending and torsion
    /// and the journals of the default roller sets. Range: [1, 1000] mm.
    #[serde(default)]
    pub crank_diameter_mm: Option<f64>,
    /// Distance between a crank's two crank-carrier bearings (the span of its bending), mm
    /// (default 4 disc widths, 35 mm on the example: the two discs and the bearings side by
    /// side between the carrier plates, **estimate**). Range: [1, 1e4] mm, more than
    /// `eccentric_spacing_mm`.
    #[serde(default)]
    pub crank_span_mm: Option<f64>,
    /// Distance between the mid-planes of a crank's two eccentrics, mm (default 1.2 disc
    /// widths, 10.5 mm on the example: the discs with a spacer, **estimate**). Range: [0, 1e4]
    /// mm, less than `crank_span_mm`.
    #[serde(default)]
    pub eccentric_spacing_mm: Option<f64>,
    /// Length of a crank twisted between its planet and its eccentrics, mm (default 3 disc
    /// widths, 26.25 mm on the example, **estimate**). Range: [1, 1e4] mm.
    #[serde(default)]
    pub crank_torsion_length_mm: Option<f64>,
    /// Diameter of the input shaft that carries the sun, mm (default the sun's pitch radius,
    /// 13.5 mm on the example: about the 14 mm shaft of a 400 W servo motor, **estimate**).
    /// Range: [1, 1000] mm.
    #[serde(default)]
    pub input_shaft_diameter_mm: Option<f64>,
    /// Length of the input shaft twisted between the locked input and the sun, mm (default
    /// 80 mm scaled with the stage, **estimate**). Range: [1, 1e4] mm.
    #[serde(default)]
    pub input_shaft_length_mm: Option<f64>,
    /// Outside diameter of the case round the pins, mm (default 190 mm scaled with the stage:
    /// about the RV-40E's case in the catalogue's outline drawing, **estimate**). The housing
    /// ring runs from the pins' grooves (pin circle radius plus pin radius) to it. Range:
    /// (2 (Rp + rrp) + 2 mm, 1e4] mm.
    #[serde(default)]
    pub housing_outer_diameter_mm: Option<f64>,
    /// Axial width of the housing ring that carries the pins, mm (default 3 disc widths, the
    /// pins' length, **estimate**). Range: [1, 1e4] mm.
    #[serde(default)]
    pub housing_width_mm: Option<f64>,
    /// Output twist per output torque of what the model leaves out (the housing, the carrier's
    /// plates and bolted joints, ...), arcmin per kN m (default 0): taken at the crank seats,
    /// it adds `c T` to the twist under a pure torque `T`. `rvlife calibrate --measured` fits
    /// it to a measured hysteresis curve or a catalogue stiffness. Range: [0, 1000] arcmin/(kN
    /// m).
    #[serde(default)]
    pub compliance_arcmin_per_knm: f64,
    /// The discs' body in the static analysis: `"elastic"` (default: the compliance of the
    /// disc between its pins' contacts and its crank bores, and its bores' ovalisation under
    /// the needles, from a finite-element solve of the disc of `[fem]`'s mesh, docs/model.md
    /// section 5.13) or `"rigid"` (the paper's rigid disc: only the contact law's depth term).
    /// RV reducers on roller bearings; a single-stage drive's discs stay rigid (not modelled).
    #[serde(default)]
    pub disc_body: Option<String>,
}

/// `[reducer.structure]` checked, SI: the dimensions the series parts of the reducer
/// (`crate::reducer::structure::SeriesCompliances`) were computed from, the keys' values or
/// their estimates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StructureParams {
    /// The crankshaft as a beam (`None` for a single-stage drive).
    pub crank: Option<CrankBeam>,
    /// Length of a crank twisted between its planet and its eccentrics, m.
    pub crank_torsion_length: f64,
    /// Input shaft diameter and length, m.
    pub input_shaft: (f64, f64),
    /// The housing ring behind the pins (`None` for a single-stage drive).
    pub housing: Option<HousingRing>,
    /// Structure compliance, rad/(N m).
    pub compliance: f64,
    /// Whether the discs' body and bores are elastic in the static analysis
    /// (`disc_body = "elastic"`).
    pub elastic_disc: bool,
}

/// Radians of an arcmin per kN m, the unit of `compliance_arcmin_per_knm`, in rad/(N m).
const ARCMIN_PER_KNM: f64 = std::f64::consts::PI / (180.0 * 60.0) * 1e-3;

impl StructureConfig {
    /// The structure of the stage `geometry` with a crank circle of `crank_circle_radius` (m;
    /// 0 for a single-stage drive, where no key applies) and a sun of pitch radius
    /// `sun_pitch_radius` (m).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and its range, or a key that does not
    /// apply to a single-stage drive.
    pub(super) fn validate(
        &self,
        geometry: &CycloidGeometry,
        crank_circle_radius: f64,
        sun_pitch_radius: f64,
    ) -> Result<StructureParams> {
        let key = |k: &str| format!("reducer.structure.{k}");
        let mm = |k: &str, v: Option<f64>, lo: f64, hi: f64, default: f64| -> Result<f64> {
            match v {
                Some(v) => Ok(check(&key(k), v, Range::closed(lo, hi, "mm"))? * 1e-3),
                None => Ok(default),
            }
        };
        let compliance = check(
            &key("compliance_arcmin_per_knm"),
            self.compliance_arcmin_per_knm,
            Range::non_negative(1e3, "arcmin/(kN m)"),
        )? * ARCMIN_PER_KNM;
        let elastic_disc = match self.disc_body.as_deref() {
            None | Some("elastic") => true,
            Some("rigid") => false,
            Some(other) => {
                return Err(Error::invalid(
                    key("disc_body"),
                    format!("\"{other}\""),
                    "must be \"elastic\" or \"rigid\"",
                ))
            }
        };
        if crank_circle_radius <= 0.0 {
            let given = [
                ("crank_diameter_mm", self.crank_diameter_mm),
                ("crank_span_mm", self.crank_span_mm),
                ("eccentric_spacing_mm", self.eccentric_spacing_mm),
                ("crank_torsion_length_mm", self.crank_torsion_length_mm),
                ("input_shaft_diameter_mm", self.input_shaft_diameter_mm),
                ("input_shaft_length_mm", self.input_shaft_length_mm),
                ("housing_outer_diameter_mm", self.housing_outer_diameter_mm),
                ("housing_width_mm", self.housing_width_mm),
                (
                    "compliance_arcmin_per_knm",
                    (compliance > 0.0).then_some(self.compliance_arcmin_per_knm),
                ),
            ];
            if let Some((k, _)) = given.iter().find(|(_, v)| v.is_some()) {
                return Err(Error::invalid(
                    key(k),
                    "given",
                    "applies only to drive = \"rv\" (a single-stage drive has no cranks, no \
                     first stage and no carrier)",
                ));
            }
            return Ok(StructureParams {
                crank: None,
                crank_torsion_length: 0.0,
                input_shaft: (0.0, 0.0),
                housing: None,
                compliance: 0.0,
                elastic_disc: false,
            });
        }
        let b = geometry.width;
        let diameter = mm(
            "crank_diameter_mm",
            self.crank_diameter_mm,
            1.0,
            1e3,
            0.4 * crank_circle_radius,
        )?;
        let span = mm("crank_span_mm", self.crank_span_mm, 1.0, 1e4, 4.0 * b)?;
        let spacing = mm(
            "eccentric_spacing_mm",
            self.eccentric_spacing_mm,
            0.0,
            1e4,
            1.2 * b,
        )?;
        if spacing >= span {
            let k = if self.eccentric_spacing_mm.is_some() {
                "eccentric_spacing_mm"
            } else {
                "crank_span_mm"
            };
            return Err(Error::invalid(
                key(k),
                format!(
                    "{:.3} mm",
                    if k == "crank_span_mm" { span } else { spacing } * 1e3
                ),
                format!(
                    "the eccentrics ({:.3} mm apart) must lie between the crank's bearings \
                     ({:.3} mm apart): eccentric_spacing_mm < crank_span_mm",
                    spacing * 1e3,
                    span * 1e3
                ),
            ));
        }
        let torsion_length = mm(
            "crank_torsion_length_mm",
            self.crank_torsion_length_mm,
            1.0,
            1e4,
            3.0 * b,
        )?;
        let shaft_d = mm(
            "input_shaft_diameter_mm",
            self.input_shaft_diameter_mm,
            1.0,
            1e3,
            sun_pitch_radius,
        )?;
        let shaft_l = mm(
            "input_shaft_length_mm",
            self.input_shaft_length_mm,
            1.0,
            1e4,
            geometry.scaled_from_root(80.0) * 1e-3,
        )?;
        let groove = geometry.pin_circle_radius + geometry.pin_radius;
        let outer = 0.5
            * mm(
                "housing_outer_diameter_mm",
                self.housing_outer_diameter_mm,
                1.0,
                1e4,
                geometry.scaled_from_root(190.0) * 1e-3,
            )?;
        if outer < groove + 1e-3 {
            return Err(Error::invalid(
                key("housing_outer_diameter_mm"),
                format!("{:.3} mm", 2.0 * outer * 1e3),
                format!(
                    "must exceed the pins' grooves by at least 1 mm of wall: more than {:.3} mm \
                     (2 x (pin circle radius + pin radius) + 2 mm)",
                    2.0 * (groove + 1e-3) * 1e3
                ),
            ));
        }
        let housing_width = mm("housing_width_mm", self.housing_width_mm, 1.0, 1e4, 3.0 * b)?;
        Ok(StructureParams {
            housing: Some(HousingRing {
                inner_radius: groove,
                outer_radius: outer,
                width: housing_width,
            }),
            crank: Some(CrankBeam {
                diameter,
                span,
                eccentric_spacing: spacing,
            }),
            crank_torsion_length: torsion_length,
            input_shaft: (shaft_d, shaft_l),
            compliance,
            elastic_disc,
        })
    }
}
