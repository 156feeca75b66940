//! `[reducer]` with `[reducer.gears]`, `[reducer.bearings]` and `[reducer.output_pins]`: the
//! drive (an RV reducer with its planetary first stage, or a single-stage cycloid drive), the
//! rating, the sun-planet meshes and the crank bearings (docs/model.md sections 1 and 5). The
//! mechanical model [`Reducer`] is assembled from these and `[contact]`, `[materials]` and
//! `[errors]` in [`super::cross_section`].

use serde::{Deserialize, Serialize};
/// Largest radial internal clearance of a crank bearing as a fraction of its pitch diameter:
/// about the top of group C5 of ISO 5753-1 for cylindrical and needle roller bearings of 18
/// to 30 mm bore (90 to 95 um), where robot reducers run group C2 or tighter; larger values
/// describe no bearing that is built.
pub const MAX_CLEARANCE_FRACTION: f64 = 0.005;

use super::range::{check, whole, Range};
use super::structure::{StructureConfig, StructureParams};
use crate::error::{Error, Result};
use crate::geometry::CycloidGeometry;
use crate::reducer::estimates::{
    carrier_seat_estimate, journal_estimates, roller_diameter_estimate,
};
use crate::reducer::structure::{shaft_torsion_stiffness, SeriesCompliances};
use crate::reducer::{BearingLaw, Bearings, Drive, Mesh, OutputPins, RadialBearing};

/// `[reducer]`: the drive (RV with its planetary first stage, or single-stage) and the rating.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReducerConfig {
    /// `"rv"` (default): planetary first stage, cranks on the output carrier, two discs;
    /// `"single_stage"`: the input shaft is the eccentric, output by pins in holes.
    #[serde(default = "default_drive")]
    pub drive: String,
    /// Sun (input) gear teeth `Z1` (RV; required there). Range: whole number, 1 to 10 000.
    #[serde(default)]
    pub sun_teeth: Option<u32>,
    /// Planet gear teeth `Z2` (RV; required there). Range: whole number, 1 to 10 000.
    #[serde(default)]
    pub planet_teeth: Option<u32>,
    /// Number of planets / crankshafts (RV; required there). Range: whole number, 1 to 12
    /// (the multibody model takes 2 or 3).
    #[serde(default)]
    pub planets: Option<u32>,
    /// Number of discs (single-stage: default 2; RV: 2). Range: whole number, 1 to 3.
    #[serde(default)]
    pub discs: Option<i64>,
    /// Eccentric phase of each disc, degrees (single-stage; default `360 d / discs`). Range:
    /// one value per disc, each in [-360, 360] deg.
    #[serde(default)]
    pub disc_phases_deg: Option<Vec<f64>>,
    /// The pins-in-holes output mechanism (single-stage).
    #[serde(default)]
    pub output_pins: Option<OutputPinsConfig>,
    /// Input speed, rpm. Range: (0, 1e6] rpm.
    pub input_speed_rpm: f64,
    /// Rated output torque, N m. Range: [0.1, 1e7] N m (from miniature cycloid drives up).
    pub rated_torque_nm: f64,
    /// The sun-planet meshes.
    #[serde(default)]
    pub gears: GearsConfig,
    /// The crank bearings.
    #[serde(default)]
    pub bearings: BearingsConfig,
    /// The crankshafts' and the input shaft's dimensions and the structure compliance.
    #[serde(default)]
    pub structure: StructureConfig,
}

fn default_drive() -> String {
    "rv".into()
}

/// `[reducer.output_pins]`: the output mechanism of a single-stage drive, pins on the output
/// flange in holes of the discs. Sizes left out default from the stage (module docs of
/// `crate::geometry::CycloidGeometry::scaled_from_root`: the paper's proportions scaled by the
/// tooth-root radius).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputPinsConfig {
    /// Number of pins (default 8). Range: whole number, 3 to 64.
    #[serde(default)]
    pub count: Option<i64>,
    /// Radius of their circle, mm (default: the RV crank circle's scaling, 40.5 mm for the
    /// paper's stage). Range: [0.01, 1e4] mm, the holes inside the tooth roots.
    #[serde(default)]
    pub circle_radius_mm: Option<f64>,
    /// Pin radius, mm (default: 8 mm scaled; the hole's radius is this plus the eccentricity
    /// plus the clearance). Range: [0.01, 1e4] mm.
    #[serde(default)]
    pub pin_radius_mm: Option<f64>,
    /// Radial clearance of a pin in its hole beyond the eccentricity, um (default 0). Range:
    /// [0, 1000] um.
    #[serde(default)]
    pub hole_clearance_um: f64,
    /// Contact stiffness of one pin on one disc, N/um (default: the crank-disc bearing's).
    /// Range: [1, 1e7] N/um.
    #[serde(default)]
    pub stiffness_n_per_um: Option<f64>,
}

/// `[reducer.gears]`: the sun-planet stage (read by the static and the dynamic analysis).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GearsConfig {
    /// Planet pitch radius, mm (paper Table 1: 27). Default: the planet's share `Z2/(Z1 + Z2)`
    /// of the crank circle, which scales the paper's 40.5 mm with the disc's root radius
    /// (`crate::geometry::CycloidGeometry::scaled_from_root`). Range: [1, 1e4] mm.
    #[serde(default)]
    pub planet_pitch_radius_mm: Option<f64>,
    /// Pressure angle, degrees (paper Table 1: 30). Range: [10, 45] deg.
    #[serde(default = "d_pressure")]
    pub pressure_angle_deg: f64,
    /// Face width of sun and planets, mm. Range: [0.5, 1e3] mm.
    #[serde(default = "d_face")]
    pub face_width_mm: f64,
    /// Mesh stiffness along the line of action, N/um (ISO 6336-1: c_gamma about 20 N/(mm um)
    /// times the face width). Range: [1, 1e7] N/um (a 1 mm plastic gear to the stiffest steel
    /// meshes; below it the stage cannot carry its load).
    #[serde(default = "d_mesh_k")]
    pub mesh_stiffness_n_per_um: f64,
    /// Damping ratio of the mesh mode (dynamics only). Range: [0, 10].
    #[serde(default = "d_zeta")]
    pub mesh_damping_ratio: f64,
    /// Total backlash along the line of action, um. Range: [0, 1e4] um.
    #[serde(default)]
    pub backlash_um: f64,
}

fn d_pressure() -> f64 {
    30.0
}
fn d_face() -> f64 {
    10.0
}
fn d_mesh_k() -> f64 {
    200.0
}
fn d_zeta() -> f64 {
    0.05
}

impl Default for GearsConfig {
    fn default() -> Self {
        GearsConfig {
            planet_pitch_radius_mm: None,
            pressure_angle_deg: d_pressure(),
            face_width_mm: d_face(),
            mesh_stiffness_n_per_um: d_mesh_k(),
            mesh_damping_ratio: d_zeta(),
            backlash_um: 0.0,
        }
    }
}

/// `[reducer.bearings]`: the crank bearings (read by the static and the dynamic analysis;
/// docs/model.md section 5.9). `model = "rollers"` (default): roller sets with a Palmgren line
/// contact per roller ([`RadialBearing`]); `"linear"`: isotropic linear springs (the earlier
/// model, `crank_*_stiffness_n_per_um`). Each model reads only its own keys.
///
/// Defaults of the roller sets are **estimates** for the RV-E class, scaled with the stage:
/// needle rollers as long as 0.9 of the disc width, 18 on each eccentric; a tapered roller
/// pair per crank, 16 rollers per row, 0.9 of the disc width long, contact angle 15 deg;
/// radial internal clearances 0 (zero-clearance assembly by selective fit).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingsConfig {
    /// `"rollers"` (default) or `"linear"`.
    #[serde(default = "d_model")]
    pub model: String,
    /// Linear model: radial stiffness of one crank-carrier bearing pair, N/um. Range:
    /// [1, 1e6] N/um.
    #[serde(default = "d_kcc")]
    pub crank_carrier_stiffness_n_per_um: f64,
    /// Linear model: radial stiffness of one crank-disc (eccentric needle) bearing, N/um.
    /// Range: [1, 1e6] N/um.
    #[serde(default = "d_kcd")]
    pub crank_disc_stiffness_n_per_um: f64,
    /// Rollers: needle rollers on each eccentric. Range: whole number, 6 to 200.
    #[serde(default = "d_cd_rollers")]
    pub crank_disc_rollers: i64,
    /// Rollers: needle length, mm (default 0.9 of the disc width). Range: [0.5, 500] mm.
    #[serde(default)]
    pub crank_disc_roller_length_mm: Option<f64>,
    /// Rollers: rollers per row of a crank-carrier bearing (two rows per crank). Range: whole
    /// number, 6 to 200.
    #[serde(default = "d_cc_rollers")]
    pub crank_carrier_rollers: i64,
    /// Rollers: crank-carrier roller length, mm (default 0.9 of the disc width). Range:
    /// [0.5, 500] mm.
    #[serde(default)]
    pub crank_carrier_roller_length_mm: Option<f64>,
    /// Rollers: needle diameter, mm (default: the needles filling 0.75 of their pitch circle
    /// round the eccentric's journal, [`roller_diameter_estimate`]). Range: [0.5, 100] mm, the
    /// needles fitting round their pitch circle.
    #[serde(default)]
    pub crank_disc_roller_diameter_mm: Option<f64>,
    /// Rollers: pitch diameter of the needle set, mm (default: the eccentric's journal plus one
    /// needle diameter). Range: [2, 1000] mm, more than the needle
    /// diameter.
    #[serde(default)]
    pub crank_disc_pitch_diameter_mm: Option<f64>,
    /// Rollers: mean diameter of the crank-carrier rollers, mm (default as for the needles,
    /// round the crank's journal). Range: [0.5, 100] mm, the rollers fitting round their pitch
    /// circle.
    #[serde(default)]
    pub crank_carrier_roller_diameter_mm: Option<f64>,
    /// Rollers: pitch diameter of the crank-carrier roller set, mm (default: the crank's
    /// journal plus one roller diameter). Range: [2, 1000] mm, more than the roller diameter.
    #[serde(default)]
    pub crank_carrier_pitch_diameter_mm: Option<f64>,
    /// Rollers: contact angle of the tapered crank-carrier rollers, deg. Range: [0, 45] deg.
    #[serde(default = "d_cc_angle")]
    pub crank_carrier_contact_angle_deg: f64,
    /// Radial internal clearance of both bearings, um (ISO 5753-1: the total radial play, ring
    /// to ring), unless the bearing's own key is given. Range: [0, 1000] um and at most
    /// [`MAX_CLEARANCE_FRACTION`] of each bearing's pitch diameter.
    #[serde(default)]
    pub clearance_um: Option<f64>,
    /// Radial internal clearance of each crank-disc bearing, um. Range: [0, 1000] um and at
    /// most [`MAX_CLEARANCE_FRACTION`] of its pitch diameter (the journal's estimate with
    /// `model = "linear"`): 108 um on the example.
    #[serde(default)]
    pub crank_disc_clearance_um: Option<f64>,
    /// Radial internal clearance of each crank-carrier bearing, um. Range: [0, 1000] um and
    /// at most [`MAX_CLEARANCE_FRACTION`] of its pitch diameter (the journal's estimate with
    /// `model = "linear"`): 95 um on the example.
    #[serde(default)]
    pub crank_carrier_clearance_um: Option<f64>,
    /// Bending stiffness of the crankshaft at one eccentric under a load there, N/um (default
    /// Timoshenko's beam of `[reducer.structure]`'s crank:
    /// [`crate::reducer::structure::CrankBeam::flexibility`]; RV with rollers only, or a
    /// single-stage drive's eccentric shaft when given). In an RV reducer the
    /// other eccentric's load moves it too, by the beam's ratio of cross to direct flexibility.
    /// Range: [1, 1e7] N/um.
    #[serde(default)]
    pub crank_bending_stiffness_n_per_um: Option<f64>,
    /// Stiffness of the carrier at each crank's seat, in series with the crank-carrier bearing
    /// pair, N/um (default from beam theory of the carrier's pillars:
    /// [`crate::reducer::structure::carrier_seat_stiffness`] of pillars filling the discs'
    /// pillar holes; RV with rollers only). Range: [1, 1e7] N/um.
    #[serde(default)]
    pub carrier_stiffness_n_per_um: Option<f64>,
    /// Torsional stiffness of a crankshaft between its planet and its eccentrics, in series
    /// with the sun-planet mesh, N m/rad (default from beam theory of `[reducer.structure]`'s
    /// crank: [`shaft_torsion_stiffness`]; RV with rollers only). Range: [1, 1e7] N m/rad.
    #[serde(default)]
    pub crank_torsion_stiffness_nm_per_rad: Option<f64>,
    /// Damping ratio of the bearing modes (dynamics only). Range: [0, 10].
    #[serde(default = "d_zeta")]
    pub damping_ratio: f64,
}

fn d_model() -> String {
    "rollers".into()
}
fn d_kcc() -> f64 {
    1000.0
}
fn d_kcd() -> f64 {
    500.0
}
fn d_cd_rollers() -> i64 {
    18
}
fn d_cc_rollers() -> i64 {
    16
}
fn d_cc_angle() -> f64 {
    15.0
}

impl Default for BearingsConfig {
    fn default() -> Self {
        BearingsConfig {
            model: d_model(),
            crank_carrier_stiffness_n_per_um: d_kcc(),
            crank_disc_stiffness_n_per_um: d_kcd(),
            crank_disc_rollers: d_cd_rollers(),
            crank_disc_roller_length_mm: None,
            crank_carrier_rollers: d_cc_rollers(),
            crank_carrier_roller_length_mm: None,
            crank_disc_roller_diameter_mm: None,
            crank_disc_pitch_diameter_mm: None,
            crank_carrier_roller_diameter_mm: None,
            crank_carrier_pitch_diameter_mm: None,
            crank_carrier_contact_angle_deg: d_cc_angle(),
            clearance_um: None,
            crank_disc_clearance_um: None,
            crank_carrier_clearance_um: None,
            crank_bending_stiffness_n_per_um: None,
            carrier_stiffness_n_per_um: None,
            crank_torsion_stiffness_nm_per_rad: None,
            damping_ratio: d_zeta(),
        }
    }
}

/// The rating of `[reducer]`, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rating {
    /// Rated output torque, N m: the hysteresis curve's end points, the default of every load.
    pub rated_torque: f64,
    /// Nominal input speed, rpm.
    pub input_speed_rpm: f64,
}

/// `[reducer]` and its subsections checked, SI: what [`super::cross_section`] assembles the
/// mechanical model from.
#[derive(Debug, Clone)]
pub(super) struct ReducerParts {
    /// `drive = "single_stage"`.
    pub single: bool,
    /// Overall ratio (`1 + (Z2/Z1) Zp`; `-Zc` for a single-stage drive).
    pub ratio: f64,
    /// Cranks (RV: the planets; 0 for a single-stage drive).
    pub cranks: usize,
    /// The drive, a single-stage drive's output pins with their stiffness defaulted.
    pub drive: Drive,
    /// Crank circle radius (single-stage: the output pins' circle), m.
    pub crank_circle_radius: f64,
    /// Eccentric phase of each disc, rad.
    pub disc_phases: Vec<f64>,
    /// The stage's sun-planet mesh (a single-stage drive: its RV twin's with `Z1/Z2 = -1`).
    pub mesh: Mesh,
    /// The sun-planet mesh of the RV reducer (a single-stage drive: its RV twin's, a 1:3
    /// first stage, never read by an analysis).
    pub rv_mesh: Mesh,
    /// Damping ratios of the mesh and of the bearings (the dynamic analysis applies them).
    pub damping: (f64, f64),
    /// The crank bearings (with the parts in series summed in).
    pub bearings: Bearings,
    /// The parts in series with the bearings and the meshes, each on its own.
    pub series: SeriesCompliances,
    /// The dimensions they were computed from.
    pub structure: StructureParams,
    /// The rating.
    pub rating: Rating,
}

impl ReducerConfig {
    /// The drive, ratio, rating, meshes and bearings for the cycloid stage `geometry` (which
    /// sets the sizes left out: [`CycloidGeometry::scaled_from_root`]).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and its range, or a key that does not
    /// apply to the drive.
    pub(super) fn validate(&self, geometry: &CycloidGeometry) -> Result<ReducerParts> {
        let single = match self.drive.as_str() {
            "rv" => false,
            "single_stage" => true,
            other => {
                return Err(Error::invalid(
                    "reducer.drive",
                    format!("\"{other}\""),
                    "must be \"rv\" or \"single_stage\"",
                ))
            }
        };
        let first_stage = |key: &str, v: Option<u32>, lo: i64, hi: i64| -> Result<usize> {
            match (v, single) {
                (Some(_), true) => Err(Error::invalid(
                    format!("reducer.{key}"),
                    "given",
                    "applies only to drive = \"rv\" (a single-stage drive has no first stage)",
                )),
                (None, true) => Ok(0),
                (Some(x), false) => whole(&format!("reducer.{key}"), x as i64, lo, hi),
                (None, false) => Err(Error::invalid(
                    format!("reducer.{key}"),
                    "missing",
                    "required for drive = \"rv\"",
                )),
            }
        };
        let z1 = first_stage("sun_teeth", self.sun_teeth, 1, 10_000)?;
        let z2 = first_stage("planet_teeth", self.planet_teeth, 1, 10_000)?;
        let planets = first_stage("planets", self.planets, 1, 12)?;
        let (disc_phases, output_pins) = self.discs(single, geometry)?;
        let ratio = if single {
            -(geometry.disc_teeth() as f64)
        } else {
            1.0 + z2 as f64 / z1 as f64 * geometry.pins as f64
        };
        let input_speed_rpm = check(
            "reducer.input_speed_rpm",
            self.input_speed_rpm,
            Range::positive(1e6, "rpm"),
        )?;
        // From miniature cycloid drives (0.1 N m) up.
        let rated_torque = check(
            "reducer.rated_torque_nm",
            self.rated_torque_nm,
            Range::closed(0.1, 1e7, "N m"),
        )?;
        // A single-stage drive's multibody and FE data are those of its RV twin (the same
        // stage on a 1:3 first stage with two cranks on the output pin circle): never read,
        // since both analyses are refused for it.
        let (rv_mesh, mesh_zeta) = if single {
            self.gears.validate(10, 30, geometry)?
        } else {
            self.gears.validate(z1, z2, geometry)?
        };
        let crank_circle = if single {
            0.0
        } else {
            rv_mesh.sun_pitch_radius + rv_mesh.planet_pitch_radius
        };
        let structure =
            self.structure
                .validate(geometry, crank_circle, rv_mesh.sun_pitch_radius)?;
        let cranks_of_stage = if single { 2 } else { planets };
        let (mut bearings, bearing_zeta, series) = self.bearings.validate(
            geometry,
            crank_circle,
            &structure,
            &rv_mesh,
            cranks_of_stage,
        )?;
        // The housing ring under the pins' loads, a twist compliance taken at the seats, and
        // the parts in series summed into the bearings' and the meshes' stiffness.
        let series = match (structure.housing, single, self.bearings.model.as_str()) {
            (Some(ring), false, "rollers") => series.with_housing(
                &ring,
                geometry,
                &disc_phases,
                rv_mesh.sun_planet_ratio,
                planets,
                crank_circle,
            ),
            _ => series,
        };
        let mut rv_mesh = rv_mesh;
        series.put_in_series(&mut bearings.disc, &mut bearings.carrier, &mut rv_mesh);
        let (drive, cranks, crank_circle_radius, mesh) = match output_pins {
            Some(mut w) => {
                if w.stiffness <= 0.0 {
                    w.stiffness = bearings.disc.reference_stiffness();
                }
                let mut m = rv_mesh;
                m.sun_planet_ratio = -1.0;
                (Drive::SingleStage(w), 0, w.circle_radius, m)
            }
            None => (
                Drive::Rv,
                planets,
                rv_mesh.sun_pitch_radius + rv_mesh.planet_pitch_radius,
                rv_mesh,
            ),
        };
        Ok(ReducerParts {
            single,
            ratio,
            cranks,
            drive,
            crank_circle_radius,
            disc_phases,
            mesh,
            rv_mesh,
            damping: (mesh_zeta, bearing_zeta),
            bearings,
            series,
            structure,
            rating: Rating {
                rated_torque,
                input_speed_rpm,
            },
        })
    }

    /// The disc phases (rad) and, for a single-stage drive, its output mechanism, from
    /// `reducer.discs`, `reducer.disc_phases_deg` and `[reducer.output_pins]` (sizes left out
    /// scaled from the stage like the RV crank circle: [`CycloidGeometry::scaled_from_root`]).
    fn discs(
        &self,
        single: bool,
        geometry: &CycloidGeometry,
    ) -> Result<(Vec<f64>, Option<OutputPins>)> {
        if !single {
            let only = "applies only to drive = \"single_stage\" (an RV reducer has two discs \
                        180 deg apart and takes its output through the cranks)";
            if self.discs.is_some_and(|d| d != 2) {
                return Err(Error::invalid(
                    "reducer.discs",
                    self.discs.unwrap_or(0),
                    only,
                ));
            }
            if self.disc_phases_deg.is_some() {
                return Err(Error::invalid("reducer.disc_phases_deg", "given", only));
            }
            if self.output_pins.is_some() {
                return Err(Error::invalid("reducer.output_pins", "given", only));
            }
            return Ok((vec![0.0, std::f64::consts::PI], None));
        }
        let n = whole("reducer.discs", self.discs.unwrap_or(2), 1, 3)?;
        let phases = match &self.disc_phases_deg {
            None => (0..n)
                .map(|d| std::f64::consts::TAU * d as f64 / n as f64)
                .collect(),
            Some(p) => {
                if p.len() != n {
                    return Err(Error::invalid(
                        "reducer.disc_phases_deg",
                        format!("a list of {} values", p.len()),
                        format!("must hold one phase per disc: {n} values (reducer.discs)"),
                    ));
                }
                p.iter()
                    .enumerate()
                    .map(|(i, &x)| {
                        check(
                            &format!("reducer.disc_phases_deg[{i}]"),
                            x,
                            Range::closed(-360.0, 360.0, "deg"),
                        )
                        .map(f64::to_radians)
                    })
                    .collect::<Result<Vec<f64>>>()?
            }
        };
        let pins = self.output_pins.clone().unwrap_or_default();
        Ok((phases, Some(pins.validate(geometry)?)))
    }
}

impl OutputPinsConfig {
    /// The output pins of a single-stage drive (a stiffness of 0 when left out: the
    /// crank-disc bearing's, set by [`ReducerConfig::validate`]).
    fn validate(&self, geometry: &CycloidGeometry) -> Result<OutputPins> {
        let key = |k: &str| format!("reducer.output_pins.{k}");
        let count = whole(&key("count"), self.count.unwrap_or(8), 3, 64)?;
        let mm =
            |k: &str, v: f64| check(&key(k), v, Range::closed(0.01, 1e4, "mm")).map(|v| v * 1e-3);
        let circle = mm(
            "circle_radius_mm",
            self.circle_radius_mm
                .unwrap_or_else(|| geometry.scaled_from_root(40.5)),
        )?;
        let pin = mm(
            "pin_radius_mm",
            self.pin_radius_mm
                .unwrap_or_else(|| geometry.scaled_from_root(8.0)),
        )?;
        let clearance = check(
            &key("hole_clearance_um"),
            self.hole_clearance_um,
            Range::non_negative(1e3, "um"),
        )? * 1e-6;
        let stiffness = match self.stiffness_n_per_um {
            Some(k) => {
                check(
                    &key("stiffness_n_per_um"),
                    k,
                    Range::closed(1.0, 1e7, "N/um"),
                )? * 1e6
            }
            None => 0.0,
        };
        // The holes (pin radius + eccentricity + clearance) must lie inside the tooth roots,
        // clear of the centre and of each other.
        let hole = pin + geometry.eccentricity + clearance;
        let root = geometry.pin_circle_radius - geometry.pin_radius - geometry.eccentricity;
        let neighbours = 2.0 * circle * (std::f64::consts::PI / count as f64).sin();
        let fits = circle + hole < root && circle - hole > 0.0 && neighbours > 2.0 * hole;
        if !fits {
            let k = if self.circle_radius_mm.is_some() || self.pin_radius_mm.is_none() {
                "circle_radius_mm"
            } else {
                "pin_radius_mm"
            };
            return Err(Error::invalid(
                key(k),
                format!(
                    "{:.3} mm",
                    if k == "pin_radius_mm" { pin } else { circle } * 1e3
                ),
                format!(
                    "the holes (radius {:.3} mm: pin + eccentricity + clearance) at radius \
                     {:.3} mm must clear the tooth roots (radius {:.3} mm), the centre and \
                     each other ({} holes)",
                    hole * 1e3,
                    circle * 1e3,
                    root * 1e3,
                    count
                ),
            ));
        }
        Ok(OutputPins {
            count,
            circle_radius: circle,
            hole_clearance: clearance,
            stiffness,
        })
    }
}

impl GearsConfig {
    /// The sun-planet mesh of `[reducer.gears]` for sun and planet teeth `z1`, `z2` and the
    /// cycloid stage `geometry` (the default planet pitch radius), and the mesh's damping ratio
    /// (applied by the dynamic analysis).
    fn validate(&self, z1: usize, z2: usize, geometry: &CycloidGeometry) -> Result<(Mesh, f64)> {
        let key = |k: &str| format!("reducer.gears.{k}");
        let r_p = check(
            &key("planet_pitch_radius_mm"),
            self.planet_pitch_radius_mm
                .unwrap_or_else(|| geometry.scaled_from_root(40.5) * z2 as f64 / (z1 + z2) as f64),
            Range::closed(1.0, 1e4, "mm"),
        )? * 1e-3;
        let alpha = check(
            &key("pressure_angle_deg"),
            self.pressure_angle_deg,
            Range::closed(10.0, 45.0, "deg"),
        )?
        .to_radians();
        let face = check(
            &key("face_width_mm"),
            self.face_width_mm,
            Range::closed(0.5, 1e3, "mm"),
        )? * 1e-3;
        let r_s = r_p * z1 as f64 / z2 as f64;
        let mesh = Mesh {
            pressure_angle: alpha,
            sun_pitch_radius: r_s,
            planet_pitch_radius: r_p,
            face_width: face,
            sun_base_radius: r_s * alpha.cos(),
            planet_base_radius: r_p * alpha.cos(),
            sun_planet_ratio: z1 as f64 / z2 as f64,
            stiffness: check(
                &key("mesh_stiffness_n_per_um"),
                self.mesh_stiffness_n_per_um,
                Range::closed(1.0, 1e7, "N/um"),
            )? * 1e6,
            damping: 0.0,
            backlash: check(
                &key("backlash_um"),
                self.backlash_um,
                Range::non_negative(1e4, "um"),
            )? * 1e-6,
        };
        let zeta = check(
            &key("mesh_damping_ratio"),
            self.mesh_damping_ratio,
            Range::non_negative(10.0, ""),
        )?;
        Ok((mesh, zeta))
    }
}

impl BearingsConfig {
    /// The crank bearings of `[reducer.bearings]` for the stage `geometry`, a crank circle of
    /// radius `crank_circle_radius` (m; 0 for a single-stage drive, whose eccentric has no
    /// crank to bend), the crankshafts and input shaft of `structure`, the sun-planet `mesh`
    /// and `cranks` cranks; their damping ratio (applied by the dynamic analysis) and the parts
    /// in series with them and with the meshes (docs/model.md section 5.9; the bearings'
    /// `series_stiffness` is left infinite, for the caller to sum the parts into).
    fn validate(
        &self,
        geometry: &CycloidGeometry,
        crank_circle_radius: f64,
        structure: &StructureParams,
        mesh: &Mesh,
        cranks: usize,
    ) -> Result<(Bearings, f64, SeriesCompliances)> {
        let key = |k: &str| format!("reducer.bearings.{k}");
        // The radial internal clearance of the bearing of pitch diameter `size` (m): within
        // `[0, 1000]` um and at most `MAX_CLEARANCE_FRACTION` of its size.
        let clearance = |k: &str, own: Option<f64>, size: f64| -> Result<f64> {
            let (name, v) = match (own, self.clearance_um) {
                (Some(v), _) => (key(k), v),
                (None, Some(v)) => (key("clearance_um"), v),
                (None, None) => return Ok(0.0),
            };
            let v = check(&name, v, Range::non_negative(1e3, "um"))?;
            let max_um = MAX_CLEARANCE_FRACTION * size * 1e6;
            if v > max_um {
                return Err(Error::invalid(
                    name,
                    format!("{v} um"),
                    format!(
                        "must be at most {:.1} um: {} % of the bearing's pitch diameter \
                         {:.2} mm, about the top of group C5 of ISO 5753-1 for roller bearings \
                         of its size (robot reducers are built with C2 or less)",
                        (max_um * 10.0).floor() / 10.0,
                        MAX_CLEARANCE_FRACTION * 100.0,
                        size * 1e3
                    ),
                ));
            }
            Ok(v * 1e-6)
        };
        let length = |k: &str, v: Option<f64>| -> Result<f64> {
            match v {
                Some(v) => Ok(check(&key(k), v, Range::closed(0.5, 500.0, "mm"))? * 1e-3),
                None => Ok(0.9 * geometry.width),
            }
        };
        // Diameter and pitch diameter of a roller set of `count` rollers round a journal of
        // diameter `journal` (m): the keys' values or the estimate, the rollers fitting round
        // their pitch circle.
        let set = |dk: &str,
                   dv: Option<f64>,
                   pk: &str,
                   pv: Option<f64>,
                   count: usize,
                   journal: f64|
         -> Result<(f64, f64)> {
            let d = match dv {
                Some(v) => check(&key(dk), v, Range::closed(0.5, 100.0, "mm"))? * 1e-3,
                None => roller_diameter_estimate(count, journal),
            };
            let pitch = match pv {
                Some(v) => check(&key(pk), v, Range::closed(2.0, 1000.0, "mm"))? * 1e-3,
                None => journal + d,
            };
            if pitch <= d {
                return Err(Error::invalid(
                    key(pk),
                    format!("{:.3} mm", pitch * 1e3),
                    format!(
                        "must exceed the roller diameter {:.3} mm (a roller set's pitch circle \
                         runs through the rollers' centres)",
                        d * 1e3
                    ),
                ));
            }
            if count as f64 * d > std::f64::consts::PI * pitch {
                let (name, v) = if dv.is_some() || pv.is_none() {
                    (key(dk), d * 1e3)
                } else {
                    (key(pk), pitch * 1e3)
                };
                return Err(Error::invalid(
                    name,
                    format!("{v:.3} mm"),
                    format!(
                        "leaves {count} rollers of {:.3} mm no room on a pitch circle of {:.3} \
                         mm: at most {:.3} mm of roller diameter there (count x diameter <= pi \
                         x pitch diameter)",
                        d * 1e3,
                        pitch * 1e3,
                        std::f64::consts::PI * pitch / count as f64 * 1e3
                    ),
                ));
            }
            Ok((d, pitch))
        };
        // Checked whatever the model, so that a wrong value is never silently kept.
        let linear = (
            BearingLaw::Linear {
                stiffness: check(
                    &key("crank_carrier_stiffness_n_per_um"),
                    self.crank_carrier_stiffness_n_per_um,
                    Range::closed(1.0, 1e6, "N/um"),
                )? * 1e6,
            },
            BearingLaw::Linear {
                stiffness: check(
                    &key("crank_disc_stiffness_n_per_um"),
                    self.crank_disc_stiffness_n_per_um,
                    Range::closed(1.0, 1e6, "N/um"),
                )? * 1e6,
            },
        );
        let (carrier_law, disc_law, (carrier_size, disc_size)) = match self.model.as_str() {
            "rollers" => {
                let angle = check(
                    &key("crank_carrier_contact_angle_deg"),
                    self.crank_carrier_contact_angle_deg,
                    Range::closed(0.0, 45.0, "deg"),
                )?
                .to_radians();
                let zc = whole(
                    &key("crank_carrier_rollers"),
                    self.crank_carrier_rollers,
                    6,
                    200,
                )?;
                let zd = whole(&key("crank_disc_rollers"), self.crank_disc_rollers, 6, 200)?;
                let (crank_journal, eccentric_journal) =
                    journal_estimates(geometry, structure.crank.as_ref());
                let (dc, pc) = set(
                    "crank_carrier_roller_diameter_mm",
                    self.crank_carrier_roller_diameter_mm,
                    "crank_carrier_pitch_diameter_mm",
                    self.crank_carrier_pitch_diameter_mm,
                    zc,
                    crank_journal,
                )?;
                let (dd, pd) = set(
                    "crank_disc_roller_diameter_mm",
                    self.crank_disc_roller_diameter_mm,
                    "crank_disc_pitch_diameter_mm",
                    self.crank_disc_pitch_diameter_mm,
                    zd,
                    eccentric_journal,
                )?;
                (
                    BearingLaw::rollers(
                        zc,
                        2,
                        length(
                            "crank_carrier_roller_length_mm",
                            self.crank_carrier_roller_length_mm,
                        )?,
                        dc,
                        pc,
                        angle,
                    ),
                    BearingLaw::rollers(
                        zd,
                        1,
                        length(
                            "crank_disc_roller_length_mm",
                            self.crank_disc_roller_length_mm,
                        )?,
                        dd,
                        pd,
                        0.0,
                    ),
                    (pc, pd),
                )
            }
            "linear" => {
                let (crank_journal, eccentric_journal) =
                    journal_estimates(geometry, structure.crank.as_ref());
                (linear.0, linear.1, (crank_journal, eccentric_journal))
            }
            other => {
                return Err(Error::invalid(
                    key("model"),
                    format!("\"{other}\""),
                    "must be \"rollers\" or \"linear\"",
                ))
            }
        };
        // A part in series with a bearing or a mesh, SI: the key's value (range [1, 1e7] in
        // its unit, times `si`), or the beam-theory estimate where the crank bearings are
        // roller sets in an RV reducer (the linear model keeps the earlier springs alone).
        // `None`: the estimate does not apply to this stage (the key must be given).
        let estimates = crank_circle_radius > 0.0 && self.model == "rollers";
        let series =
            |k: &str, v: Option<f64>, unit: &'static str, si: f64, estimate: Option<f64>| {
                Ok::<f64, Error>(match v {
                    Some(v) => check(&key(k), v, Range::closed(1.0, 1e7, unit))? * si,
                    None if estimates => estimate.ok_or_else(|| {
                        Error::invalid(
                            key(k),
                            "left out",
                            "must be given for this stage: its estimate needs pillars at least \
                             1 mm thick, and the discs' pillar holes (22 mm scaled with the \
                             stage) less twice the eccentricity leave less",
                        )
                    })?,
                    None => f64::INFINITY,
                })
            };
        // The crank's 2x2 flexibility at its eccentrics (Timoshenko's beam), or the key's
        // direct stiffness with the beam's ratio of cross to direct term.
        let beam = structure.crank.map(|c| c.flexibility());
        let direct = series(
            "crank_bending_stiffness_n_per_um",
            self.crank_bending_stiffness_n_per_um,
            "N/um",
            1e6,
            beam.map(|(d, _)| 1.0 / d),
        )?;
        let direct = 1.0 / direct;
        let cross = beam.map_or(0.0, |(d, c)| direct * c / d);
        let carrier = series(
            "carrier_stiffness_n_per_um",
            self.carrier_stiffness_n_per_um,
            "N/um",
            1e6,
            carrier_seat_estimate(geometry),
        )?;
        let torsion = series(
            "crank_torsion_stiffness_nm_per_rad",
            self.crank_torsion_stiffness_nm_per_rad,
            "N m/rad",
            1.0,
            structure
                .crank
                .map(|c| shaft_torsion_stiffness(c.diameter, structure.crank_torsion_length)),
        )?;
        let (shaft_d, shaft_l) = structure.input_shaft;
        let shaft = if estimates {
            shaft_torsion_stiffness(shaft_d, shaft_l)
        } else {
            f64::INFINITY
        };
        let r = crank_circle_radius;
        let parts = SeriesCompliances {
            crank_bending_own: direct - cross,
            crank_bending_shared: cross,
            carrier: 1.0 / carrier,
            housing: 0.0,
            disc_body: 0.0,
            disc_bores: 0.0,
            structure: structure.compliance * cranks as f64 * r * r,
            // A twist `F r_bp/k_t` moves the planet's base circle by `F r_bp^2/k_t`; the sun's
            // torque `n F r_bs` twists the input shaft by `n F r_bs/k_s`, moving each mesh by
            // `r_bs` times that.
            crank_torsion: mesh.planet_base_radius.powi(2) / torsion,
            input_shaft: cranks as f64 * mesh.sun_base_radius.powi(2) / shaft,
        };
        let bearings = Bearings {
            carrier: RadialBearing {
                law: carrier_law,
                clearance: clearance(
                    "crank_carrier_clearance_um",
                    self.crank_carrier_clearance_um,
                    carrier_size,
                )?,
                series_stiffness: f64::INFINITY,
                damping: 0.0,
            },
            disc: RadialBearing {
                law: disc_law,
                clearance: clearance(
                    "crank_disc_clearance_um",
                    self.crank_disc_clearance_um,
                    disc_size,
                )?,
                series_stiffness: f64::INFINITY,
                damping: 0.0,
            },
        };
        let zeta = check(
            &key("damping_ratio"),
            self.damping_ratio,
            Range::non_negative(10.0, ""),
        )?;
        Ok((bearings, zeta, parts))
    }
}
