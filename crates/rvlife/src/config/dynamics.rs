//! `[dynamics]`: the raw section (engineering units) and its conversion to the SI parameters of
//! the multibody model ([`DynamicsParams`]; docs/model.md section 8), one subsection at a time.
//!
//! Defaults: the paper's section 4.2 set-up (input ramped by `STEP(time, 0, 0, 0.1, 9000 deg/s)`,
//! sinusoidal output torque of 412 N m amplitude and 0.3 s period, TE over 0.1-0.8 s), material
//! densities of the paper's Table 2, and sizes of typical RV-40E-class bodies (stated with each
//! key).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::dynamics::params::{
    disc_inertia, Drive, DynamicsParams, Impact, ImpactLaw, Inertias, LoadProfile, Method,
};
use crate::dynamics::{Damping, ModalSettings};
use crate::error::{Error, Result};
use crate::geometry::Profile;
use crate::reducer::Reducer;

/// `[dynamics]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsConfig {
    /// Add the dynamic TE to every stage of `rvlife run`.
    #[serde(default)]
    pub enabled: bool,
    /// Simulated time, s. Range: (0, 60] s.
    #[serde(default = "d_end")]
    pub end_time_s: f64,
    /// TE statistics window `[start, end]`, s. Range: 0 <= start < end <= end_time_s.
    #[serde(default = "d_window")]
    pub window_s: [f64; 2],
    /// Sampling interval of the time series, s. Range: (0, window length] s, at most 2e6 samples.
    #[serde(default = "d_interval")]
    pub output_interval_s: f64,
    /// Relative tolerance of the integrator (absolute tolerances scale with it).
    /// Range: [1e-10, 1e-2].
    #[serde(default = "d_rtol")]
    pub relative_tolerance: f64,
    /// Time integrator: `"esdirk34"` (implicit, steps set by accuracy) or `"tsit45"` (explicit,
    /// steps set by the stiffest mode) ([`crate::dynamics::ode`]).
    #[serde(default = "d_integrator")]
    pub integrator: String,
    /// Mesh angles per tooth of the tabulated gap field. Range: whole number, 64 to 65 536.
    #[serde(default = "d_gap_points")]
    pub gap_points_per_tooth: i64,
    /// Input drive.
    #[serde(default)]
    pub drive: DriveConfig,
    /// Output load.
    #[serde(default)]
    pub load: DynLoadConfig,
    /// Disc-pin impact contact.
    #[serde(default)]
    pub impact: ImpactConfig,
    /// Densities, sizes and overrides of the inertias.
    #[serde(default)]
    pub inertia: InertiaConfig,
    /// The discs: `"rigid"` (the default) or `"flexible"` (the FE disc of `[fem]`, modally
    /// reduced, [`crate::fem::modal`]).
    #[serde(default = "d_disc")]
    pub disc: String,
    /// Modal reduction of the flexible disc.
    #[serde(default)]
    pub flexible: FlexibleConfig,
}

fn d_disc() -> String {
    "rigid".into()
}

/// `[dynamics.flexible]`: the modal reduction of the flexible disc.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlexibleConfig {
    /// Cut-off frequency, kHz: every fixed-interface mode of the disc (bores held) below it is
    /// kept; the rest enter through their residual flexibility. Range: (0, 1e4] kHz.
    #[serde(default = "d_cutoff")]
    pub cutoff_khz: f64,
    /// Modal damping ratio of every mode (structural steel, 0.5-2 %). Range: [0, 1].
    #[serde(default = "d_modal_zeta")]
    pub damping_ratio: f64,
    /// Largest number of modes per disc. Range: whole number, 1 to 1000.
    #[serde(default = "d_max_modes")]
    pub max_modes: i64,
}

fn d_cutoff() -> f64 {
    30.0
}
fn d_modal_zeta() -> f64 {
    0.02
}
fn d_max_modes() -> i64 {
    128
}

impl Default for FlexibleConfig {
    fn default() -> Self {
        FlexibleConfig {
            cutoff_khz: d_cutoff(),
            damping_ratio: d_modal_zeta(),
            max_modes: d_max_modes(),
        }
    }
}

fn d_end() -> f64 {
    0.8
}
fn d_window() -> [f64; 2] {
    [0.1, 0.8]
}
fn d_interval() -> f64 {
    2e-4
}
fn d_integrator() -> String {
    "esdirk34".into()
}
fn d_rtol() -> f64 {
    2e-4
}
fn d_gap_points() -> i64 {
    1024
}

impl Default for DynamicsConfig {
    fn default() -> Self {
        DynamicsConfig {
            enabled: false,
            end_time_s: d_end(),
            window_s: d_window(),
            output_interval_s: d_interval(),
            relative_tolerance: d_rtol(),
            integrator: d_integrator(),
            gap_points_per_tooth: d_gap_points(),
            drive: Default::default(),
            load: Default::default(),
            impact: Default::default(),
            inertia: Default::default(),
            disc: d_disc(),
            flexible: Default::default(),
        }
    }
}

/// `[dynamics.drive]`: `kind = "speed"` (prescribed `STEP` ramp) or `"torque"` (motor torque).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveConfig {
    /// `"speed"` or `"torque"`.
    #[serde(default = "d_speed_kind")]
    pub kind: String,
    /// Final input speed, deg/s (`speed`; paper: 9000).
    /// Range: finite, non-zero, |speed| <= 1e6 deg/s.
    #[serde(default = "d_speed")]
    pub speed_deg_s: f64,
    /// Start of the speed ramp, s. Range: [0, end_time_s] s.
    #[serde(default)]
    pub ramp_start_s: f64,
    /// End of the speed ramp (or of the torque ramp), s.
    /// Range: after ramp_start_s, within end_time_s.
    #[serde(default = "d_ramp")]
    pub ramp_end_s: f64,
    /// Motor torque, N m (`torque`). Range: |torque| <= 1e5 N m.
    #[serde(default)]
    pub torque_nm: Option<f64>,
    /// Initial input speed, deg/s (`torque`). Range: |speed| <= 1e6 deg/s.
    #[serde(default)]
    pub initial_speed_deg_s: f64,
}

fn d_speed_kind() -> String {
    "speed".into()
}
fn d_speed() -> f64 {
    9000.0
}
fn d_ramp() -> f64 {
    0.1
}

impl Default for DriveConfig {
    fn default() -> Self {
        DriveConfig {
            kind: d_speed_kind(),
            speed_deg_s: d_speed(),
            ramp_start_s: 0.0,
            ramp_end_s: d_ramp(),
            torque_nm: None,
            initial_speed_deg_s: 0.0,
        }
    }
}

/// `[dynamics.impact]`: MSC Adams IMPACT parameters of every disc-pin contact.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactConfig {
    /// Stiffness `k` in `F = k d^e`, N/m^e (default: fitted to the config's Hertz line-contact
    /// law; give it together with `exponent`).
    /// Range: (0, 1e30], with a contact stiffness in [1e5, 1e13] N/m at the reference force.
    #[serde(default)]
    pub stiffness_n_per_m_e: Option<f64>,
    /// Exponent `e` (default: fitted with the stiffness). Range: [1, 3].
    #[serde(default)]
    pub exponent: Option<f64>,
    /// Maximum damping `c_max`, N s/m (default: from `damping_ratio`). Range: [0, 1e9] N s/m.
    #[serde(default)]
    pub max_damping_n_s_per_m: Option<f64>,
    /// Damping ratio of a disc on the contact stiffness at the reference force, used when
    /// `max_damping_n_s_per_m` is not given.
    /// Range: [0, 10].
    #[serde(default = "d_impact_zeta")]
    pub damping_ratio: f64,
    /// Penetration `d_max` at which the damping is full, um. Range: (0, 1000] um.
    #[serde(default = "d_pen")]
    pub penetration_um: f64,
    /// Coulomb friction coefficient (0: off). Range: [0, 1].
    #[serde(default)]
    pub friction_coefficient: f64,
    /// Sliding speed over which the friction is smoothed (`tanh`), mm/s. Range: (0, 1e6] mm/s.
    #[serde(default = "d_fv")]
    pub friction_velocity_mm_s: f64,
}

fn d_impact_zeta() -> f64 {
    0.1
}
fn d_pen() -> f64 {
    1.0
}
fn d_fv() -> f64 {
    1.0
}

impl Default for ImpactConfig {
    fn default() -> Self {
        ImpactConfig {
            stiffness_n_per_m_e: None,
            exponent: None,
            max_damping_n_s_per_m: None,
            damping_ratio: d_impact_zeta(),
            penetration_um: d_pen(),
            friction_coefficient: 0.0,
            friction_velocity_mm_s: d_fv(),
        }
    }
}

/// `[dynamics.inertia]`: densities (paper Table 2), simple body sizes, and overrides.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InertiaConfig {
    /// Disc density, kg/m^3 (GCr15). Range: (0, 1e5] kg/m^3.
    #[serde(default = "d_rho_steel")]
    pub disc_density_kg_m3: f64,
    /// Crankshaft and planet density, kg/m^3 (GCr15). Range: (0, 1e5] kg/m^3.
    #[serde(default = "d_rho_steel")]
    pub crank_density_kg_m3: f64,
    /// Carrier and output shaft density, kg/m^3 (20CrMnTi). Range: (0, 1e5] kg/m^3.
    #[serde(default = "d_rho_out")]
    pub output_density_kg_m3: f64,
    /// Radius of the crank bores in the disc, mm (default: the paper's 13 mm scaled with the
    /// disc's root radius, `crate::geometry::CycloidGeometry::scaled_from_root`).
    /// Range: (0, 1e4] mm, clear of the tooth roots and the centre.
    #[serde(default)]
    pub crank_bore_radius_mm: Option<f64>,
    /// Crankshaft journal radius, mm. Range: (0, 1e4] mm.
    #[serde(default = "d_journal")]
    pub crankshaft_radius_mm: f64,
    /// Crankshaft length, mm. Range: (0, 1e5] mm.
    #[serde(default = "d_crank_len")]
    pub crankshaft_length_mm: f64,
    /// Axial thickness of carrier + output flange (a solid disk of the pin-circle radius minus
    /// the pin radius), mm. Range: (0, 1e5] mm.
    #[serde(default = "d_carrier")]
    pub carrier_thickness_mm: f64,
    /// Input shaft radius, mm. Range: (0, 1e4] mm.
    #[serde(default = "d_in_r")]
    pub input_shaft_radius_mm: f64,
    /// Input shaft length, mm. Range: (0, 1e5] mm.
    #[serde(default = "d_in_len")]
    pub input_shaft_length_mm: f64,
    /// Extra inertia of what the output drives, kg m^2. Range: [0, 1e6] kg m^2.
    #[serde(default)]
    pub load_inertia_kg_m2: f64,
    /// Override: disc mass, kg. Range: (0, 1e6] kg.
    #[serde(default)]
    pub disc_mass_kg: Option<f64>,
    /// Override: disc inertia about its centre, kg m^2. Range: (0, 1e6] kg m^2.
    #[serde(default)]
    pub disc_inertia_kg_m2: Option<f64>,
    /// Override: crankshaft + planet mass, kg. Range: (0, 1e6] kg.
    #[serde(default)]
    pub crank_mass_kg: Option<f64>,
    /// Override: crankshaft + planet inertia about the crank axis, kg m^2. Range: (0, 1e6] kg m^2.
    #[serde(default)]
    pub crank_inertia_kg_m2: Option<f64>,
    /// Override: carrier + output shaft inertia (without `load_inertia_kg_m2`), kg m^2.
    /// Range: (0, 1e6] kg m^2.
    #[serde(default)]
    pub output_inertia_kg_m2: Option<f64>,
    /// Override: input shaft + sun inertia, kg m^2. Range: (0, 1e6] kg m^2.
    #[serde(default)]
    pub input_inertia_kg_m2: Option<f64>,
}

fn d_rho_steel() -> f64 {
    7830.0
}
fn d_rho_out() -> f64 {
    7860.0
}
fn d_journal() -> f64 {
    10.0
}
fn d_crank_len() -> f64 {
    60.0
}
fn d_carrier() -> f64 {
    30.0
}
fn d_in_r() -> f64 {
    8.0
}
fn d_in_len() -> f64 {
    100.0
}

impl Default for InertiaConfig {
    fn default() -> Self {
        InertiaConfig {
            disc_density_kg_m3: d_rho_steel(),
            crank_density_kg_m3: d_rho_steel(),
            output_density_kg_m3: d_rho_out(),
            crank_bore_radius_mm: None,
            crankshaft_radius_mm: d_journal(),
            crankshaft_length_mm: d_crank_len(),
            carrier_thickness_mm: d_carrier(),
            input_shaft_radius_mm: d_in_r(),
            input_shaft_length_mm: d_in_len(),
            load_inertia_kg_m2: 0.0,
            disc_mass_kg: None,
            disc_inertia_kg_m2: None,
            crank_mass_kg: None,
            crank_inertia_kg_m2: None,
            output_inertia_kg_m2: None,
            input_inertia_kg_m2: None,
        }
    }
}

fn positive(field: &str, v: f64, max: f64, unit: &'static str) -> Result<f64> {
    check(&format!("dynamics.{field}"), v, Range::positive(max, unit))
}

fn non_negative(field: &str, v: f64, max: f64, unit: &'static str) -> Result<f64> {
    check(
        &format!("dynamics.{field}"),
        v,
        Range::non_negative(max, unit),
    )
}

impl DynamicsConfig {
    /// Checks the section and converts it to SI for the reducer `reducer` (its meshes and
    /// bearings get their damping here, from the damping ratios `damping` and the body masses)
    /// with the nominal disc profile `profile` and the rated torque (N m, the default load and
    /// the reference force). `path` resolves a relative load-table path. The gap table's
    /// resolution is the reducer's (`dynamics.gap_points_per_tooth`, checked with it).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the `dynamics.*` key, the value and the allowed range;
    /// [`Error::Config`] for an unreadable load table.
    pub fn validate(
        &self,
        reducer: &Reducer,
        damping: (f64, f64),
        profile: &Profile,
        rated_torque: f64,
        path: impl Fn(&Path) -> PathBuf,
    ) -> Result<DynamicsParams> {
        let geo = &reducer.geometry;
        let planets = reducer.cranks;
        let t = self.timing()?;
        if !(2..=3).contains(&planets) {
            return Err(Error::invalid(
                "reducer.planets",
                planets,
                "the dynamic model needs 2 or 3 planets (crankshafts)",
            ));
        }
        let inertia = self.inertia.validate(reducer, profile)?;
        let damping = damping_of(reducer, damping, &inertia);
        // Impact contact: by default the stage's contact law at every mesh angle; the damping
        // from the linearised stiffness at Li's largest pin force at the rated torque, on the
        // flank point of largest lever arm (Li: cos t = K1).
        let f_ref = 2.0 * rated_torque * reducer.twist_factor()
            / (geo.disc_pitch_radius() * geo.pins as f64);
        let impact = self.impact.validate(reducer, profile, f_ref, &inertia)?;
        let drive = self.drive.validate(t.end_time)?;
        let load = self.load.validate(rated_torque, t.end_time, path)?;
        let flexible = self.flexible_settings(&impact)?;
        Ok(DynamicsParams {
            flexible,
            damping,
            contact: impact,
            inertia,
            drive,
            load,
            end_time: t.end_time,
            window: t.window,
            output_interval: t.output_interval,
            rtol: t.rtol,
            integrator: t.integrator,
            gap_points: reducer.gap_points,
            reference_force: f_ref,
        })
    }

    /// The simulated time, the statistics window, the output interval and the integrator.
    fn timing(&self) -> Result<Timing> {
        let end_time = positive("end_time_s", self.end_time_s, 60.0, "s")?;
        let [w0, w1] = self.window_s;
        if !(w0.is_finite() && w1.is_finite() && w0 >= 0.0 && w0 < w1 && w1 <= end_time) {
            return Err(Error::invalid(
                "dynamics.window_s",
                format!("[{w0}, {w1}]"),
                format!("must satisfy 0 <= start < end <= end_time_s ({end_time} s)"),
            ));
        }
        let output_interval = positive(
            "output_interval_s",
            self.output_interval_s,
            w1 - w0,
            "s (the window length)",
        )?;
        if end_time / output_interval > 2e6 {
            return Err(Error::invalid(
                "dynamics.output_interval_s",
                output_interval,
                "gives more than 2e6 samples; use a larger interval",
            ));
        }
        let rtol = self.relative_tolerance;
        if !(rtol.is_finite() && (1e-10..=1e-2).contains(&rtol)) {
            return Err(Error::invalid(
                "dynamics.relative_tolerance",
                rtol,
                "must be in [1e-10, 1e-2]",
            ));
        }
        let integrator = match self.integrator.as_str() {
            "tsit45" => Method::Tsit45,
            "esdirk34" => Method::Esdirk34,
            other => {
                return Err(Error::invalid(
                    "dynamics.integrator",
                    format!("\"{other}\""),
                    "must be \"esdirk34\" or \"tsit45\"",
                ))
            }
        };
        Ok(Timing {
            end_time,
            window: (w0, w1),
            output_interval,
            rtol,
            integrator,
        })
    }

    /// The modal reduction of the flexible disc (`disc = "flexible"`), or `None` (rigid discs).
    fn flexible_settings(&self, impact: &Impact) -> Result<Option<ModalSettings>> {
        Ok(match self.disc.as_str() {
            "rigid" => None,
            "flexible" => {
                if !matches!(impact.law, ImpactLaw::Hertz) {
                    return Err(Error::invalid(
                        "dynamics.impact.stiffness_n_per_m_e",
                        format!("{:?}", self.impact.stiffness_n_per_m_e),
                        "must be left out with disc = \"flexible\": the flexible disc uses the \
                         [contact] law with its disc term cut at the load patch (the FE body \
                         supplies the rest)",
                    ));
                }
                let fc = &self.flexible;
                let max_modes = fc.max_modes;
                if !(1..=1000).contains(&max_modes) {
                    return Err(Error::invalid(
                        "dynamics.flexible.max_modes",
                        max_modes,
                        "must be a whole number from 1 to 1000",
                    ));
                }
                Some(ModalSettings {
                    cutoff_hz: positive("flexible.cutoff_khz", fc.cutoff_khz, 1e4, "kHz")? * 1e3,
                    damping_ratio: non_negative(
                        "flexible.damping_ratio",
                        fc.damping_ratio,
                        1.0,
                        "",
                    )?,
                    max_modes: max_modes as usize,
                    density: self.inertia.disc_density_kg_m3,
                })
            }
            other => {
                return Err(Error::invalid(
                    "dynamics.disc",
                    format!("\"{other}\""),
                    "must be \"rigid\" or \"flexible\"",
                ))
            }
        })
    }
}

/// The time settings of `[dynamics]`, SI.
struct Timing {
    end_time: f64,
    window: (f64, f64),
    output_interval: f64,
    rtol: f64,
    integrator: Method,
}

/// The damping of `reducer`'s meshes and bearings from the damping ratios `(mesh, bearings)`
/// and the body masses of `inertia`.
fn damping_of(reducer: &Reducer, (zeta_m, zeta_b): (f64, f64), inertia: &Inertias) -> Damping {
    let mesh0 = reducer.mesh;
    let r_bp = mesh0.planet_base_radius;
    let m_eq = inertia.crank / (r_bp * r_bp);
    Damping {
        mesh: 2.0 * zeta_m * (mesh0.stiffness * m_eq).sqrt(),
        carrier: 2.0
            * zeta_b
            * (reducer.bearings.carrier.reference_stiffness() * inertia.crank_mass).sqrt(),
        disc: 2.0
            * zeta_b
            * (reducer.bearings.disc.reference_stiffness() * inertia.disc_mass).sqrt(),
    }
}

impl InertiaConfig {
    /// The inertias of the bodies of `reducer`, from the densities and sizes (and the disc's
    /// area from the nominal `profile`), or the overrides.
    fn validate(&self, reducer: &Reducer, profile: &Profile) -> Result<Inertias> {
        let geo = &reducer.geometry;
        let planets = reducer.cranks;
        let mesh0 = reducer.mesh;
        let (r_p, r_s, face) = (
            mesh0.planet_pitch_radius,
            mesh0.sun_pitch_radius,
            mesh0.face_width,
        );
        let crank_circle_radius = reducer.crank_circle_radius;
        let root = geo.pin_circle_radius - geo.pin_radius - geo.eccentricity;
        // Inertias.
        let ic = self;
        let rho_d = positive(
            "inertia.disc_density_kg_m3",
            ic.disc_density_kg_m3,
            1e5,
            "kg/m^3",
        )?;
        let rho_c = positive(
            "inertia.crank_density_kg_m3",
            ic.crank_density_kg_m3,
            1e5,
            "kg/m^3",
        )?;
        let rho_o = positive(
            "inertia.output_density_kg_m3",
            ic.output_density_kg_m3,
            1e5,
            "kg/m^3",
        )?;
        let bore = positive(
            "inertia.crank_bore_radius_mm",
            ic.crank_bore_radius_mm
                .unwrap_or_else(|| geo.scaled_from_root(13.0)),
            1e4,
            "mm",
        )? * 1e-3;
        let crowded = crank_circle_radius + bore >= root || bore >= crank_circle_radius;
        if crowded && ic.crank_bore_radius_mm.is_none() {
            // The bores at their default: the crank circle is what moved them.
            return Err(Error::invalid(
                "reducer.gears.planet_pitch_radius_mm",
                format!("{:.3} mm", reducer.mesh.planet_pitch_radius * 1e3),
                format!(
                    "puts the crank circle at {:.2} mm, where the crank bores ({:.2} mm radius, \
                     dynamics.inertia.crank_bore_radius_mm's default) leave no material round \
                     the centre or before the tooth roots ({:.2} mm): the crank circle must lie \
                     between {:.2} and {:.2} mm",
                    crank_circle_radius * 1e3,
                    bore * 1e3,
                    root * 1e3,
                    bore * 1e3,
                    (root - bore) * 1e3
                ),
            ));
        }
        if crowded {
            return Err(Error::invalid(
                "dynamics.inertia.crank_bore_radius_mm",
                bore * 1e3,
                format!(
                    "must leave material between the bores ({:.2} mm crank circle) and the tooth roots ({:.2} mm)",
                    crank_circle_radius * 1e3,
                    root * 1e3
                ),
            ));
        }
        let journal = positive(
            "inertia.crankshaft_radius_mm",
            ic.crankshaft_radius_mm,
            1e4,
            "mm",
        )? * 1e-3;
        let crank_len = positive(
            "inertia.crankshaft_length_mm",
            ic.crankshaft_length_mm,
            1e5,
            "mm",
        )? * 1e-3;
        let carrier_t = positive(
            "inertia.carrier_thickness_mm",
            ic.carrier_thickness_mm,
            1e5,
            "mm",
        )? * 1e-3;
        let in_r = positive(
            "inertia.input_shaft_radius_mm",
            ic.input_shaft_radius_mm,
            1e4,
            "mm",
        )? * 1e-3;
        let in_len = positive(
            "inertia.input_shaft_length_mm",
            ic.input_shaft_length_mm,
            1e5,
            "mm",
        )? * 1e-3;
        let load_j = non_negative(
            "inertia.load_inertia_kg_m2",
            ic.load_inertia_kg_m2,
            1e6,
            "kg m^2",
        )?;
        let pi = std::f64::consts::PI;
        let cyl = |rho: f64, r: f64, l: f64| {
            let m = rho * pi * r * r * l;
            (m, 0.5 * m * r * r)
        };
        let (md, jd) = disc_inertia(profile, planets, bore, crank_circle_radius, rho_d);
        let (mp, jp) = cyl(rho_c, r_p, face);
        let (mj, jj) = cyl(rho_c, journal, crank_len);
        let (_, jo) = cyl(rho_o, geo.pin_circle_radius - geo.pin_radius, carrier_t);
        let (_, js) = cyl(rho_c, r_s, face);
        let (_, jsh) = cyl(rho_c, in_r, in_len);
        let over = |field: &str, v: Option<f64>, default: f64, unit: &'static str| -> Result<f64> {
            match v {
                Some(x) => positive(&format!("inertia.{field}"), x, 1e6, unit),
                None => Ok(default),
            }
        };
        let inertia = Inertias {
            input: over(
                "input_inertia_kg_m2",
                ic.input_inertia_kg_m2,
                js + jsh,
                "kg m^2",
            )?,
            output: over(
                "output_inertia_kg_m2",
                ic.output_inertia_kg_m2,
                jo,
                "kg m^2",
            )? + load_j,
            crank_mass: over("crank_mass_kg", ic.crank_mass_kg, mp + mj, "kg")?,
            crank: over(
                "crank_inertia_kg_m2",
                ic.crank_inertia_kg_m2,
                jp + jj,
                "kg m^2",
            )?,
            disc_mass: over("disc_mass_kg", ic.disc_mass_kg, md, "kg")?,
            disc: over("disc_inertia_kg_m2", ic.disc_inertia_kg_m2, jd, "kg m^2")?,
        };
        Ok(inertia)
    }
}

impl ImpactConfig {
    /// The impact contact of `reducer`'s law (or the power law given), its damping from the
    /// linearised stiffness at the reference force `f_ref` (N) on the flank of the nominal
    /// `profile` and the disc mass of `inertia`.
    fn validate(
        &self,
        reducer: &Reducer,
        profile: &Profile,
        f_ref: f64,
        inertia: &Inertias,
    ) -> Result<Impact> {
        let geo = &reducer.geometry;
        // Impact contact: by default the stage's contact law at every mesh angle; the damping
        // from the linearised stiffness at Li's largest pin force at the rated torque, on the
        // flank point of largest lever arm (Li: cos t = K1).
        let im = self;
        let curvature = profile.macro_curvature(geo.k1().acos());
        let law = match (im.stiffness_n_per_m_e, im.exponent) {
            (None, None) => ImpactLaw::Hertz,
            (Some(k), Some(e)) => {
                let k = positive("impact.stiffness_n_per_m_e", k, 1e30, "N/m^e")?;
                if !(e.is_finite() && (1.0..=3.0).contains(&e)) {
                    return Err(Error::invalid(
                        "dynamics.impact.exponent",
                        e,
                        "must be in [1, 3]",
                    ));
                }
                ImpactLaw::Power {
                    stiffness: k,
                    exponent: e,
                }
            }
            _ => {
                return Err(Error::invalid(
                    "dynamics.impact.stiffness_n_per_m_e",
                    "given without exponent (or the reverse)",
                    "give both stiffness_n_per_m_e and exponent, or neither (the contact law)",
                ))
            }
        };
        let k_lin = law.stiffness_at(&reducer.contact, f_ref, curvature);
        if !(k_lin.is_finite() && (1e5..=1e13).contains(&k_lin)) {
            return Err(Error::invalid(
                "dynamics.impact.stiffness_n_per_m_e",
                format!("{law:?}"),
                format!(
                    "gives a contact stiffness of {k_lin:.3e} N/m at the reference force {f_ref:.0} N; \
                     physical values lie in [1e5, 1e13] N/m"
                ),
            ));
        }
        let zeta_c = non_negative("impact.damping_ratio", im.damping_ratio, 10.0, "")?;
        let max_damping = match im.max_damping_n_s_per_m {
            Some(c) => non_negative("impact.max_damping_n_s_per_m", c, 1e9, "N s/m")?,
            None => 2.0 * zeta_c * (k_lin * inertia.disc_mass).sqrt(),
        };
        let impact = Impact {
            law,
            max_damping,
            penetration: positive("impact.penetration_um", im.penetration_um, 1e3, "um")? * 1e-6,
            friction: non_negative(
                "impact.friction_coefficient",
                im.friction_coefficient,
                1.0,
                "",
            )?,
            friction_velocity: positive(
                "impact.friction_velocity_mm_s",
                im.friction_velocity_mm_s,
                1e6,
                "mm/s",
            )? * 1e-3,
        };
        Ok(impact)
    }
}

impl DriveConfig {
    /// The input drive over the simulated time `end_time` (s).
    fn validate(&self, end_time: f64) -> Result<Drive> {
        let d = self;
        Ok(match d.kind.as_str() {
            "speed" => {
                let s = d.speed_deg_s;
                if !(s.is_finite() && s != 0.0 && s.abs() <= 1e6) {
                    return Err(Error::invalid(
                        "dynamics.drive.speed_deg_s",
                        s,
                        "must be a finite non-zero number, |speed| <= 1e6 deg/s",
                    ));
                }
                let t0 = non_negative("drive.ramp_start_s", d.ramp_start_s, end_time, "s")?;
                let t1 = d.ramp_end_s;
                if !(t1.is_finite() && t1 > t0 && t1 <= end_time) {
                    return Err(Error::invalid(
                        "dynamics.drive.ramp_end_s",
                        t1,
                        format!("must be after ramp_start_s ({t0} s) and within end_time_s ({end_time} s)"),
                    ));
                }
                Drive::Speed {
                    speed: s.to_radians(),
                    t0,
                    t1,
                }
            }
            "torque" => {
                let t = d.torque_nm.ok_or_else(|| {
                    Error::invalid(
                        "dynamics.drive.torque_nm",
                        "missing",
                        "required with kind = \"torque\"",
                    )
                })?;
                if !(t.is_finite() && t.abs() <= 1e5) {
                    return Err(Error::invalid(
                        "dynamics.drive.torque_nm",
                        t,
                        "must be finite, |torque| <= 1e5 N m",
                    ));
                }
                let w = d.initial_speed_deg_s;
                if !(w.is_finite() && w.abs() <= 1e6) {
                    return Err(Error::invalid(
                        "dynamics.drive.initial_speed_deg_s",
                        w,
                        "must be finite, |speed| <= 1e6 deg/s",
                    ));
                }
                Drive::Torque {
                    torque: t,
                    ramp: non_negative("drive.ramp_end_s", d.ramp_end_s, end_time, "s")?,
                    initial_speed: w.to_radians(),
                }
            }
            other => {
                return Err(Error::invalid(
                    "dynamics.drive.kind",
                    format!("\"{other}\""),
                    "must be \"speed\" or \"torque\"",
                ))
            }
        })
    }
}

/// `[dynamics.load]`: output load `kind = "none" | "constant" | "sinusoidal" | "table"`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynLoadConfig {
    /// Load kind.
    #[serde(default = "d_load_kind")]
    pub kind: String,
    /// Constant torque, N m (`constant`; default: rated torque). Range: |torque| <= 1e6 N m.
    #[serde(default)]
    pub torque_nm: Option<f64>,
    /// Ramp time of the constant torque (`STEP` from 0), s. Range: [0, end_time_s] s.
    #[serde(default)]
    pub ramp_s: f64,
    /// Amplitude, N m (`sinusoidal`; default: rated torque). Range: [0, 1e6] N m.
    #[serde(default)]
    pub amplitude_nm: Option<f64>,
    /// Period, s (`sinusoidal`). Range: (0, 1e6] s.
    #[serde(default = "d_period")]
    pub period_s: f64,
    /// Mean, N m (`sinusoidal`). Range: |torque| <= 1e6 N m.
    #[serde(default)]
    pub offset_nm: f64,
    /// Phase, degrees (`sinusoidal`). Range: any finite number.
    #[serde(default)]
    pub phase_deg: f64,
    /// CSV with columns `time_s,torque_nm` (`table`), relative to the config file; linear
    /// between rows; must cover the simulated time.
    #[serde(default)]
    pub file: Option<PathBuf>,
}

fn d_load_kind() -> String {
    "sinusoidal".into()
}
fn d_period() -> f64 {
    0.3
}

impl Default for DynLoadConfig {
    fn default() -> Self {
        DynLoadConfig {
            kind: d_load_kind(),
            torque_nm: None,
            ramp_s: 0.0,
            amplitude_nm: None,
            period_s: d_period(),
            offset_nm: 0.0,
            phase_deg: 0.0,
            file: None,
        }
    }
}

impl DynLoadConfig {
    /// The load for the rated torque `rated` (N m, the default) over the simulated time
    /// `end_time` (s); `path` resolves the table's file.
    pub(super) fn validate(
        &self,
        rated: f64,
        end_time: f64,
        path: impl Fn(&Path) -> PathBuf,
    ) -> Result<LoadProfile> {
        let torque_ok = |field: &str, v: f64| -> Result<f64> {
            if v.is_finite() && v.abs() <= 1e6 {
                Ok(v)
            } else {
                Err(Error::invalid(
                    format!("dynamics.load.{field}"),
                    v,
                    "must be finite, |torque| <= 1e6 N m",
                ))
            }
        };
        match self.kind.as_str() {
            "none" => Ok(LoadProfile::None),
            "constant" => Ok(LoadProfile::Constant {
                torque: torque_ok("torque_nm", self.torque_nm.unwrap_or(rated))?,
                ramp: non_negative("load.ramp_s", self.ramp_s, end_time, "s")?,
            }),
            "sinusoidal" => {
                let amp = torque_ok("amplitude_nm", self.amplitude_nm.unwrap_or(rated))?;
                if amp < 0.0 {
                    return Err(Error::invalid(
                        "dynamics.load.amplitude_nm",
                        amp,
                        "must be >= 0",
                    ));
                }
                if !self.phase_deg.is_finite() {
                    return Err(Error::invalid(
                        "dynamics.load.phase_deg",
                        self.phase_deg,
                        "must be finite",
                    ));
                }
                Ok(LoadProfile::Sinusoidal {
                    amplitude: amp,
                    period: positive("load.period_s", self.period_s, 1e6, "s")?,
                    offset: torque_ok("offset_nm", self.offset_nm)?,
                    phase: self.phase_deg.to_radians(),
                })
            }
            "table" => {
                let file = self.file.as_ref().ok_or_else(|| {
                    Error::invalid(
                        "dynamics.load.file",
                        "missing",
                        "required with kind = \"table\"",
                    )
                })?;
                read_load_table(&path(file), end_time)
            }
            other => Err(Error::invalid(
                "dynamics.load.kind",
                format!("\"{other}\""),
                "must be \"none\", \"constant\", \"sinusoidal\" or \"table\"",
            )),
        }
    }
}

/// Reads a load table CSV with header `time_s,torque_nm`: strictly increasing times, no empty or
/// non-numeric cells, covering `[0, end_time]` s.
///
/// # Errors
/// [`Error::Config`] if unreadable; [`Error::Invalid`] naming the file, row and column of a bad
/// cell, an unsorted time, or a table that does not cover the simulated time.
pub(crate) fn read_load_table(path: &Path, end_time: f64) -> Result<LoadProfile> {
    let origin = path.display().to_string();
    let cfg_err = |message: String| Error::Config {
        path: origin.clone(),
        message,
    };
    let file = crate::input::open(path)
        .map_err(|e| cfg_err(format!("cannot read the load table: {e}")))?;
    let mut rdr = csv::ReaderBuilder::new().flexible(true).from_reader(file);
    let headers = rdr.headers().map_err(|e| cfg_err(e.to_string()))?.clone();
    if headers.iter().map(str::trim).collect::<Vec<_>>() != ["time_s", "torque_nm"] {
        return Err(cfg_err(format!(
            "header must be `time_s,torque_nm`, found `{}`",
            headers.iter().collect::<Vec<_>>().join(",")
        )));
    }
    let (mut time, mut torque) = (Vec::new(), Vec::new());
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| cfg_err(e.to_string()))?;
        let mut v = [0.0; 2];
        for (k, name) in ["time_s", "torque_nm"].iter().enumerate() {
            let field = format!("{origin} row {} column {name}", i + 1);
            let s = rec.get(k).unwrap_or("").trim();
            if s.is_empty() {
                return Err(Error::invalid(
                    field,
                    "empty",
                    "the table has a gap: every row needs both values",
                ));
            }
            v[k] = s
                .parse::<f64>()
                .map_err(|_| Error::invalid(&field, format!("\"{s}\""), "must be a number"))?;
            if !v[k].is_finite() {
                return Err(Error::invalid(
                    &field,
                    v[k],
                    "must be finite (no NaN or inf)",
                ));
            }
        }
        if let Some(&last) = time.last() {
            if v[0] <= last {
                return Err(Error::invalid(
                    format!("{origin} row {} column time_s", i + 1),
                    v[0],
                    format!("times must increase strictly (previous row: {last})"),
                ));
            }
        }
        time.push(v[0]);
        torque.push(v[1]);
    }
    if time.len() < 2 {
        return Err(cfg_err("the load table needs at least 2 rows".into()));
    }
    if time[0] > 0.0 || *time.last().unwrap_or(&0.0) < end_time {
        return Err(Error::invalid(
            format!("{origin} column time_s"),
            format!("[{}, {}]", time[0], time[time.len() - 1]),
            format!("must cover the simulated time [0, {end_time}] s"),
        ));
    }
    Ok(LoadProfile::Table { time, torque })
}

/// The largest output torque of the dynamic load in each direction, with the key that sets
/// it (for the physical check of the unworn stage, [`super::physical`]).
pub(crate) fn load_peaks(load: &LoadProfile) -> Vec<(String, f64)> {
    match load {
        LoadProfile::None => Vec::new(),
        LoadProfile::Constant { torque, .. } => {
            vec![("dynamics.load.torque_nm".to_string(), *torque)]
        }
        LoadProfile::Sinusoidal {
            amplitude, offset, ..
        } => {
            let key = if *amplitude > 0.0 {
                "dynamics.load.amplitude_nm"
            } else {
                "dynamics.load.offset_nm"
            };
            vec![
                (key.to_string(), offset + amplitude),
                (key.to_string(), offset - amplitude),
            ]
        }
        LoadProfile::Table { torque, .. } => {
            let hi = torque.iter().copied().fold(0.0, f64::max);
            let lo = torque.iter().copied().fold(0.0, f64::min);
            vec![
                ("dynamics.load.file".to_string(), hi),
                ("dynamics.load.file".to_string(), lo),
            ]
        }
    }
}
