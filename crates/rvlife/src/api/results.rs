//! The results of the commands, typed and serialisable: what `rvlife <command> --json` prints
//! (the object of these fields, keys sorted) and what the Python package returns. Fields that
//! are stage quantities carry the name and unit of [`crate::quantities`] (the `te` command's
//! static TE keeps its historical `te_*` names: `te_mean_arcmin` is the quantity
//! [`crate::quantities::STE_MEAN`] of a single profile).

use serde::Serialize;

/// `rvlife contact --json`: the static equilibrium at one crank angle under an output torque,
/// input locked (docs/model.md section 5).
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct ContactResult {
    /// Crank angle, deg.
    pub crank_deg: f64,
    /// Output torque, N m (positive counter-clockwise).
    pub torque_nm: f64,
    /// How the discs are held: `"bearings"` or `"rigid"`.
    pub support: &'static str,
    /// Carrier twist beyond nominal, arcmin (the loaded TE).
    pub twist_arcmin: f64,
    /// Twist at first contact in the torque's direction, arcmin.
    pub first_contact_arcmin: f64,
    /// Largest pin force, N.
    pub max_force_n: f64,
    /// Pins carrying a force, both discs.
    pub pins_in_contact: usize,
    /// Largest Hertz pressure, MPa.
    pub max_pressure_mpa: f64,
    /// Tangent torsional stiffness `dT/dpsi`, N m/arcmin.
    pub torsional_stiffness_nm_per_arcmin: f64,
    /// Relative residual of the equilibrium.
    pub residual: f64,
    /// Round-off floor of the residual, relative.
    pub residual_roundoff_floor: f64,
    /// Largest wear depth of the profile, um.
    pub max_wear_um: f64,
    /// Each disc (two with bearings, one with rigid support).
    pub discs: Vec<ContactDisc>,
}

/// One disc of a [`ContactResult`].
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct ContactDisc {
    /// Translation of the disc centre from its nominal position, um (x, y).
    pub translation_um: [f64; 2],
    /// Disc rotation beyond nominal, arcmin.
    pub rotation_arcmin: f64,
    /// Moment of the pin forces about the disc centre, N m.
    pub pin_moment_nm: f64,
    /// Largest pin force, N.
    pub max_force_n: f64,
    /// Pins carrying a force.
    pub pins_in_contact: usize,
    /// Every pin's force, N (`Zp` values in pin order).
    pub pin_forces_n: Vec<f64>,
    /// Every pin (`Zp` entries in pin order).
    pub pins: Vec<ContactPin>,
}

/// One pin of a [`ContactDisc`].
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct ContactPin {
    /// Pin index `j`.
    pub pin: usize,
    /// Mesh angle of the contact, deg (0 root, 180 tip).
    pub mesh_angle_deg: f64,
    /// Gap at the solved pose, um (negative: the contact's approach).
    pub gap_um: f64,
    /// Normal force, N.
    pub force_n: f64,
    /// Lever arm about the disc centre, mm.
    pub lever_arm_mm: f64,
    /// Hertz half-width, um.
    pub half_width_um: f64,
    /// Maximum Hertz pressure, MPa.
    pub max_pressure_mpa: f64,
}

/// `rvlife te --json`: the static TE over a mesh cycle and an output revolution, the catalogue
/// quantities, and with a torque the loaded TE (docs/model.md section 6).
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct TeResult {
    /// Largest wear depth of the profile (less a measured deviation), um.
    pub max_wear_um: f64,
    /// Angular TE over the output revolution, arcmin ([`crate::quantities::ANGULAR_TE`]).
    pub angular_te_arcmin: f64,
    /// How the discs are held: `"bearings"` or `"rigid"`.
    pub support: &'static str,
    /// Mean forward STE over a mesh cycle, arcmin ([`crate::quantities::STE_MEAN`]).
    pub te_mean_arcmin: f64,
    /// Peak-to-peak forward STE over a mesh cycle, arcmin
    /// ([`crate::quantities::STE_PEAK_TO_PEAK`]).
    pub te_peak_to_peak_arcmin: f64,
    /// Mean reverse STE, arcmin ([`crate::quantities::STE_REVERSE_MEAN`]).
    pub te_reverse_mean_arcmin: f64,
    /// Backlash, arcmin ([`crate::quantities::BACKLASH`]).
    pub backlash_arcmin: f64,
    /// Largest play, arcmin ([`crate::quantities::BACKLASH_MAX`]).
    pub backlash_max_arcmin: f64,
    /// Lost motion, arcmin ([`crate::quantities::LOST_MOTION`]).
    pub lost_motion_arcmin: f64,
    /// The lost motion's measuring torque, N m.
    pub measuring_torque_nm: f64,
    /// Torsional stiffness `b/a`, N m/arcmin ([`crate::quantities::TORSIONAL_STIFFNESS`]).
    pub torsional_stiffness_nm_per_arcmin: f64,
    /// Crank angles per mesh cycle.
    pub samples_per_mesh_cycle: usize,
    /// The loaded TE, with a torque. (Its keys are the object's own: TypeScript has no
    /// flattened option, so the page's type adds them, `TeView`.)
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    #[cfg_attr(feature = "ts", ts(skip))]
    pub loaded: Option<LoadedTeResult>,
    /// Input angle over the output revolution, deg.
    pub input_deg: Vec<f64>,
    /// Forward STE over the output revolution, arcmin.
    pub te_arcmin: Vec<f64>,
}

/// The loaded TE of a [`TeResult`] at one output torque.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct LoadedTeResult {
    /// Output torque, N m.
    pub torque_nm: f64,
    /// Mean loaded TE over a mesh cycle, arcmin ([`crate::quantities::LOADED_TE_MEAN`]).
    pub loaded_te_mean_arcmin: f64,
    /// Peak-to-peak loaded TE, arcmin ([`crate::quantities::LOADED_TE_PEAK_TO_PEAK`]).
    pub loaded_te_peak_to_peak_arcmin: f64,
    /// Largest pin force over a mesh cycle, N ([`crate::quantities::MAX_FORCE`]).
    pub max_force_n: f64,
    /// Fewest pins in contact on one disc ([`crate::quantities::PINS_IN_CONTACT`]).
    pub pins_in_contact: usize,
    /// Loaded TE over the output revolution, arcmin.
    pub loaded_te_arcmin: Vec<f64>,
}

/// A hysteresis curve (output torque 0 -> +rated -> -rated -> +rated, input locked) and its
/// catalogue quantities.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct TwistCurve {
    /// Output torque along the sweep, N m.
    pub torque_nm: Vec<f64>,
    /// Twist along the sweep, arcmin.
    pub twist_arcmin: Vec<f64>,
    /// Backlash, arcmin ([`crate::quantities::BACKLASH`]).
    pub backlash_arcmin: f64,
    /// Lost motion, arcmin ([`crate::quantities::LOST_MOTION`]).
    pub lost_motion_arcmin: f64,
    /// Hysteresis loss, arcmin ([`crate::quantities::HYSTERESIS_LOSS`]).
    pub hysteresis_loss_arcmin: f64,
    /// Torsional stiffness `b/a`, N m/arcmin ([`crate::quantities::TORSIONAL_STIFFNESS`]).
    pub torsional_stiffness_nm_per_arcmin: f64,
}

/// `rvlife hysteresis --json`: the curve averaged over a mesh cycle (also at the top level) and
/// at one crank angle (docs/model.md section 6).
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct HysteresisResult {
    /// Largest wear depth of the profile, um.
    pub max_wear_um: f64,
    /// How the discs are held: `"bearings"` or `"rigid"`.
    pub support: &'static str,
    /// Rated torque, N m.
    pub rated_torque_nm: f64,
    /// Measuring torque of lost motion, fraction of the rated torque.
    pub measuring_torque_fraction: f64,
    /// How the torsional stiffness is defined.
    pub torsional_stiffness_definition: &'static str,
    /// Crank angle of [`HysteresisResult::at_crank_angle`], deg.
    pub crank_deg: f64,
    /// The curve at that crank angle.
    pub at_crank_angle: TwistCurve,
    /// Crank angles per mesh cycle of the mean.
    pub samples_per_mesh_cycle: usize,
    /// The mean curve's torques, N m.
    pub torque_nm: Vec<f64>,
    /// The mean curve's twists, arcmin.
    pub twist_arcmin: Vec<f64>,
    /// The mean curve's backlash, arcmin.
    pub backlash_arcmin: f64,
    /// The mean curve's lost motion, arcmin.
    pub lost_motion_arcmin: f64,
    /// The mean curve's hysteresis loss, arcmin.
    pub hysteresis_loss_arcmin: f64,
    /// The mean curve's torsional stiffness, N m/arcmin.
    pub torsional_stiffness_nm_per_arcmin: f64,
    /// The curve averaged over a mesh cycle.
    pub mesh_cycle_mean: TwistCurve,
    /// Each part's share of the elastic twist at the rated torque, mean over the mesh cycle
    /// (docs/model.md section 5.9; empty for the rigid support).
    pub twist_shares: Vec<TwistShareResult>,
}

/// One part's share of the elastic twist ([`crate::statics::twist_shares`]).
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct TwistShareResult {
    /// The part ([`crate::statics::TwistShare::part`]).
    pub part: &'static str,
    /// Its share of the elastic twist beyond the no-load point, 0..1.
    pub share: f64,
    /// The elastic twist it takes, arcmin.
    pub twist_arcmin: f64,
}

/// The points of a profile (`rvlife profile` writes them as CSV), one list per column, each
/// `Zc points_per_tooth` long.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct ProfilePoints {
    /// Points per tooth.
    pub points_per_tooth: usize,
    /// Largest wear depth of the profile, um.
    pub max_wear_um: f64,
    /// x in the disc frame, mm.
    pub x_mm: Vec<f64>,
    /// y in the disc frame, mm.
    pub y_mm: Vec<f64>,
    /// Mesh angle, deg (0 root, 180 tip).
    pub mesh_angle_deg: Vec<f64>,
    /// Wear depth along the normal, um.
    pub wear_um: Vec<f64>,
}

/// One stage quantity as every front end lists it (Python's `rvlife.quantities()`, the web
/// page's table headers and axis titles), from its declaration in
/// [`crate::quantities::STAGE`].
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct QuantityDoc {
    /// Its name with its unit (`lost_motion_arcmin`): the key of `summary.json`.
    pub name: &'static str,
    /// Its unit (`arcmin`; empty for a pure number).
    pub unit: &'static str,
    /// A short label (`lost motion`).
    pub label: &'static str,
    /// What it is, with its definition and source.
    pub description: &'static str,
    /// The models that produce it: `static`, `dynamics`, `flexible` or `lubrication`.
    pub models: &'static str,
    /// Its columns in `stages.csv` (its name, or a smallest-largest pair's two).
    pub columns: Vec<&'static str>,
}

/// The table of stage quantities, in the order of `summary.json` and `stages.csv`
/// ([`crate::quantities::STAGE`]), one [`QuantityDoc`] each.
pub fn quantity_table() -> Vec<QuantityDoc> {
    use crate::quantities::{Models, STAGE};
    STAGE
        .iter()
        .map(|q| QuantityDoc {
            name: q.name,
            unit: q.unit,
            label: q.label,
            description: q.description,
            models: match q.models {
                Models::Static => "static",
                Models::Dynamics => "dynamics",
                Models::Flexible => "flexible",
                Models::Lubrication => "lubrication",
            },
            columns: q.columns(),
        })
        .collect()
}
