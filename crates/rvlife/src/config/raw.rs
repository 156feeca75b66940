//! Raw TOML sections of the study configuration, in engineering units, as the user wrote them
//! (unknown keys rejected). [`super::Config::validate`] checks them and converts them to the
//! model's SI values.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// `[reducer]`: the drive (RV with its planetary first stage, or single-stage) and the rating.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReducerConfig {
    /// `"rv"` (default): planetary first stage, cranks on the output carrier, two discs;
    /// `"single_stage"`: the input shaft is the eccentric, output by pins in holes.
    #[serde(default = "default_drive")]
    pub drive: String,
    /// Sun (input) gear teeth `Z1` (RV).
    #[serde(default)]
    pub sun_teeth: Option<u32>,
    /// Planet gear teeth `Z2` (RV).
    #[serde(default)]
    pub planet_teeth: Option<u32>,
    /// Number of planets / crankshafts (RV: 2 or 3).
    #[serde(default)]
    pub planets: Option<u32>,
    /// Number of discs (single-stage: 1 to 3, default 2; RV: 2).
    #[serde(default)]
    pub discs: Option<i64>,
    /// Eccentric phase of each disc, degrees (single-stage; default `360 d / discs`).
    #[serde(default)]
    pub disc_phases_deg: Option<Vec<f64>>,
    /// The pins-in-holes output mechanism (single-stage).
    #[serde(default)]
    pub output_pins: Option<OutputPinsConfig>,
    /// Input speed, rpm.
    pub input_speed_rpm: f64,
    /// Rated output torque, N m.
    pub rated_torque_nm: f64,
    /// The sun-planet meshes.
    #[serde(default)]
    pub gears: GearsConfig,
    /// The crank bearings.
    #[serde(default)]
    pub bearings: BearingsConfig,
}

fn default_drive() -> String {
    "rv".into()
}

/// `[reducer.output_pins]`: the output mechanism of a single-stage drive, pins on the output
/// flange in holes of the discs. Sizes left out default from the stage (module docs of
/// [`super::Config`]: the paper's proportions scaled by the tooth-root radius).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputPinsConfig {
    /// Number of pins (default 8).
    #[serde(default)]
    pub count: Option<i64>,
    /// Radius of their circle, mm (default: the RV crank circle's scaling, 40.5 mm for the
    /// paper's stage).
    #[serde(default)]
    pub circle_radius_mm: Option<f64>,
    /// Pin radius, mm (default: 8 mm scaled; the hole's radius is this plus the eccentricity
    /// plus the clearance).
    #[serde(default)]
    pub pin_radius_mm: Option<f64>,
    /// Radial clearance of a pin in its hole beyond the eccentricity, um (default 0).
    #[serde(default)]
    pub hole_clearance_um: f64,
    /// Contact stiffness of one pin on one disc, N/um (default: the crank-disc bearing's).
    #[serde(default)]
    pub stiffness_n_per_um: Option<f64>,
}

/// `[cycloid]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CycloidConfig {
    /// Pins `Zp`; disc teeth `Zc = Zp - 1`.
    pub pins: i64,
    /// Eccentricity `a`, mm.
    pub eccentricity_mm: f64,
    /// Pin circle radius `Rp`, mm.
    pub pin_circle_radius_mm: f64,
    /// Pin radius `rrp`, mm.
    pub pin_radius_mm: f64,
    /// Disc width `B`, mm.
    pub width_mm: f64,
    /// Profile modifications.
    #[serde(default)]
    pub modification: ModificationConfig,
    /// A measured profile (CSV `x_mm,y_mm` or DXF polyline, mm, disc frame; path relative to
    /// the config file), fitted as a deviation map over the described profile.
    #[serde(default)]
    pub measured_profile: Option<PathBuf>,
}

/// `[cycloid.modification]`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModificationConfig {
    /// Equidistant modification `drrp`, mm.
    #[serde(default)]
    pub equidistant_mm: f64,
    /// Offset modification `dRp`, mm.
    #[serde(default)]
    pub offset_mm: f64,
    /// Rotation modification, degrees.
    #[serde(default)]
    pub rotation_deg: f64,
}

/// `[materials]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialsConfig {
    /// Cycloid disc.
    pub disc: MaterialConfig,
    /// Pins.
    pub pin: MaterialConfig,
    /// Largest Hertz pressure the disc-pin contact may carry, MPa (default 4000: the static
    /// capacity of hardened bearing steel in line contact, ISO 76:2006 section 6.2.1, where the
    /// permanent set reaches 1e-4 of the roller diameter). Every torque the study applies is
    /// checked against it on the unworn disc before any analysis.
    #[serde(default = "default_max_pressure")]
    pub max_contact_pressure_mpa: f64,
}

fn default_max_pressure() -> f64 {
    4000.0
}

/// One material.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    /// Young's modulus, GPa.
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
}

/// `[contact]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactConfig {
    /// `"paper"` (default), `"johnson"` or `"linear"`.
    #[serde(default = "default_law")]
    pub law: String,
    /// Stiffness of the `"linear"` law, N/um.
    #[serde(default)]
    pub linear_stiffness_n_per_um: Option<f64>,
    /// Cap on the flank radius of curvature in the contact law, mm (default: pin circle radius).
    #[serde(default)]
    pub max_curvature_radius_mm: Option<f64>,
    /// Reference depth of the disc term of the approach law: `"body"` (default: the pin circle
    /// radius at every flank point) or `"local_radius"` (the paper's eq 6 as printed: the local
    /// flank radius, capped at `max_curvature_radius_mm`).
    #[serde(default = "default_disc_depth")]
    pub disc_depth: String,
    /// How the discs are held: `"bearings"` (default: both discs on their crank bearings, the
    /// load share from the equilibrium) or `"rigid"` (the paper's and Li's model: one disc, its
    /// centre fixed on the eccentric, carrying `load_share` of the output torque).
    #[serde(default = "default_support")]
    pub support: String,
    /// Share of the output torque on the disc with `support = "rigid"` (paper eqs 8-9: 0.55).
    #[serde(default)]
    pub load_share: Option<f64>,
    /// Force whose Hertz half-width sets the band over which the contact geometry averages the
    /// worn flank, N (default: Li's largest pin force at the rated torque).
    #[serde(default)]
    pub band_force_n: Option<f64>,
    /// How the contact geometry sees the worn flank: `"envelope"` (default: the upper envelope
    /// of the flank averaged over a sixteenth of `band_force_n` and over `band_force_n`) or
    /// `"single"` (averaged over the band of `band_force_n`).
    #[serde(default = "default_band")]
    pub band: String,
}

fn default_band() -> String {
    "envelope".into()
}

fn default_law() -> String {
    "paper".into()
}

fn default_disc_depth() -> String {
    "body".into()
}

fn default_support() -> String {
    "bearings".into()
}

impl Default for ContactConfig {
    fn default() -> Self {
        ContactConfig {
            law: default_law(),
            linear_stiffness_n_per_um: None,
            max_curvature_radius_mm: None,
            disc_depth: default_disc_depth(),
            support: default_support(),
            load_share: None,
            band_force_n: None,
            band: default_band(),
        }
    }
}

/// `[load]`: the output-torque spectrum the reducer works under.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadConfig {
    /// `"constant"`, `"sinusoidal"` or `"duty_cycle"`.
    pub kind: String,
    /// Constant output torque, N m (`constant`; default: the rated torque).
    #[serde(default)]
    pub torque_nm: Option<f64>,
    /// Amplitude, N m (`sinusoidal`), >= 0.
    #[serde(default)]
    pub amplitude_nm: Option<f64>,
    /// Mean, N m (`sinusoidal`).
    #[serde(default)]
    pub offset_nm: Option<f64>,
    /// Period, s (`sinusoidal`; the wear average does not depend on it).
    #[serde(default)]
    pub period_s: Option<f64>,
    /// Torque levels the sine is split into for the wear average (`sinusoidal`), >= 4.
    #[serde(default)]
    pub levels: Option<i64>,
    /// CSV file with columns `duration_s,torque_nm,speed_rpm` (`duty_cycle`), relative to the
    /// config file.
    #[serde(default)]
    pub file: Option<PathBuf>,
}

/// `[wear]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearConfig {
    /// `"flodin"` (default: sliding from the real kinematics, profile updates) or `"paper"`
    /// (eqs 11-20 as printed, Li's forces, no updates, TE from the uniform maximum wear).
    #[serde(default = "default_wear_model")]
    pub model: String,
    /// Dimensional Archard coefficient `k = K/H`, mm^3/(N m).
    #[serde(default)]
    pub archard_coefficient_mm3_per_n_m: Option<f64>,
    /// The same coefficient in m^2/N (= 1/Pa); give exactly one of the two.
    #[serde(default)]
    pub archard_coefficient_m2_per_n: Option<f64>,
    /// Working-hour stages at which results are reported, h, increasing, >= 0.
    pub stage_hours: Vec<f64>,
    /// Profile update step, h (0: wear rate from the new profile only).
    #[serde(default)]
    pub profile_update_hours: f64,
    /// Largest wear increment between profile updates, um: the update step is shortened so that
    /// no point wears more than this between two rebuilds of the load sharing.
    #[serde(default = "default_max_step")]
    pub max_wear_step_um: f64,
    /// Crank angles solved per mesh cycle (wear map resolution = pins x this).
    #[serde(default = "default_steps")]
    pub crank_steps_per_mesh_cycle: i64,
    /// Fraction of the disc-pin sliding taken up by pins turning in their grooves, 0..1
    /// (0: pins do not turn, the conservative default).
    #[serde(default)]
    pub pin_rolling_fraction: f64,
    /// Overlap ratio `eps_a` of the paper's eq 19 (`paper` model only).
    #[serde(default = "default_overlap")]
    pub overlap_ratio: f64,
}

fn default_wear_model() -> String {
    "flodin".into()
}
fn default_max_step() -> f64 {
    1.0
}
fn default_steps() -> i64 {
    18
}
fn default_overlap() -> f64 {
    1.3
}

/// `[te]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TeConfig {
    /// Crank angles per mesh cycle for the TE curves.
    #[serde(default = "default_te_samples")]
    pub samples_per_mesh_cycle: i64,
    /// Torque of the loaded TE, N m (default: rated torque).
    #[serde(default)]
    pub loaded_torque_nm: Option<f64>,
    /// Measuring torque of lost motion, as a fraction of the rated torque (Nabtesco: lost
    /// motion is the twist between the hysteresis curve's midpoints within +-3 % of rated
    /// torque).
    #[serde(default = "default_measuring")]
    pub measuring_torque_fraction: f64,
}

fn default_measuring() -> f64 {
    0.03
}

fn default_te_samples() -> i64 {
    24
}

impl Default for TeConfig {
    fn default() -> Self {
        TeConfig {
            samples_per_mesh_cycle: default_te_samples(),
            loaded_torque_nm: None,
            measuring_torque_fraction: default_measuring(),
        }
    }
}

/// `[reducer.gears]`: the sun-planet stage (read by the static and the dynamic analysis).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GearsConfig {
    /// Planet pitch radius, mm (paper Table 1: 27). Default: the planet's share `Z2/(Z1 + Z2)`
    /// of the crank circle, which scales the paper's 40.5 mm with the disc's root radius
    /// ([`crate::config::scaled_from_root`]).
    #[serde(default)]
    pub planet_pitch_radius_mm: Option<f64>,
    /// Pressure angle, degrees (paper Table 1: 30).
    #[serde(default = "d_pressure")]
    pub pressure_angle_deg: f64,
    /// Face width of sun and planets, mm.
    #[serde(default = "d_face")]
    pub face_width_mm: f64,
    /// Mesh stiffness along the line of action, N/um (ISO 6336-1: c_gamma about 20 N/(mm um)
    /// times the face width).
    #[serde(default = "d_mesh_k")]
    pub mesh_stiffness_n_per_um: f64,
    /// Damping ratio of the mesh mode.
    #[serde(default = "d_zeta")]
    pub mesh_damping_ratio: f64,
    /// Total backlash along the line of action, um.
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

/// `[reducer.bearings]`: crank bearings as radial spring-dampers (read by the static and the
/// dynamic analysis).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingsConfig {
    /// Radial stiffness of one crank-carrier bearing pair, N/um (tapered roller bearings).
    #[serde(default = "d_kcc")]
    pub crank_carrier_stiffness_n_per_um: f64,
    /// Radial stiffness of one crank-disc (eccentric needle) bearing, N/um.
    #[serde(default = "d_kcd")]
    pub crank_disc_stiffness_n_per_um: f64,
    /// Damping ratio of the bearing modes.
    #[serde(default = "d_zeta")]
    pub damping_ratio: f64,
    /// Radial clearance, um.
    #[serde(default)]
    pub clearance_um: f64,
}

fn d_kcc() -> f64 {
    1000.0
}
fn d_kcd() -> f64 {
    500.0
}

impl Default for BearingsConfig {
    fn default() -> Self {
        BearingsConfig {
            crank_carrier_stiffness_n_per_um: d_kcc(),
            crank_disc_stiffness_n_per_um: d_kcd(),
            damping_ratio: d_zeta(),
            clearance_um: 0.0,
        }
    }
}
