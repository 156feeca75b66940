//! The study configuration: TOML in engineering units, checked and converted to SI.
//!
//! Keys carry their unit in their name (`pin_radius_mm`, `torque_nm`). Unknown keys are
//! rejected with their path; every value is range-checked by [`Config::validate`] with an error
//! naming the key, the value and the allowed range. [`Config::example`] is the paper's RV-40E
//! class reducer (paper Tables 1-2, physics-notes section 7), printed by `rvlife example`.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::contact::{ApproachLaw, ContactModel, Materials};
use crate::dynamics::{DynamicsConfig, DynamicsParams};
use crate::error::{Error, Result};
use crate::fem::{FemConfig, FemParams};
use crate::geometry::{CycloidGeometry, Modification, Profile, WearMap};

/// The built-in example: the paper's reducer, fully commented.
pub const EXAMPLE_TOML: &str = include_str!("example.toml");

/// Whole configuration file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// First stage, speed and rating.
    pub reducer: ReducerConfig,
    /// Cycloid stage.
    pub cycloid: CycloidConfig,
    /// Elastic constants.
    pub materials: MaterialsConfig,
    /// Contact law.
    #[serde(default)]
    pub contact: ContactConfig,
    /// Load spectrum for wear.
    pub load: LoadConfig,
    /// Wear model and working-hour stages.
    pub wear: WearConfig,
    /// Transmission-error sampling.
    #[serde(default)]
    pub te: TeConfig,
    /// Multibody dynamics (dynamic TE).
    #[serde(default)]
    pub dynamics: DynamicsConfig,
    /// The disc as a finite-element body (rigid-flexible model).
    #[serde(default)]
    pub fem: FemConfig,
    /// Directory of the config file (for relative paths); not a key.
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
}

/// `[reducer]`: the planetary first stage and the rating.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReducerConfig {
    /// Sun (input) gear teeth `Z1`.
    pub sun_teeth: u32,
    /// Planet gear teeth `Z2`.
    pub planet_teeth: u32,
    /// Number of planets / crankshafts (2 or 3).
    pub planets: u32,
    /// Input speed, rpm.
    pub input_speed_rpm: f64,
    /// Rated output torque, N m.
    pub rated_torque_nm: f64,
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
    /// Share of the output torque carried by one disc (paper eq 8-9: 0.55).
    pub load_share: f64,
    /// Profile modifications.
    #[serde(default)]
    pub modification: ModificationConfig,
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
}

fn default_law() -> String {
    "paper".into()
}

impl Default for ContactConfig {
    fn default() -> Self {
        ContactConfig {
            law: default_law(),
            linear_stiffness_n_per_um: None,
            max_curvature_radius_mm: None,
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
}

fn default_te_samples() -> i64 {
    24
}

impl Default for TeConfig {
    fn default() -> Self {
        TeConfig {
            samples_per_mesh_cycle: default_te_samples(),
            loaded_torque_nm: None,
        }
    }
}

/// Wear model choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WearModelKind {
    /// Archard with sliding distance `2 b |v_d - v_p| / v_d` from the real kinematics
    /// (Flodin and Andersson 1997), contact from true gaps, profile updates.
    Flodin,
    /// The paper's eqs 11-20 as printed.
    Paper,
}

/// One level of the load spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoadLevel {
    /// Output torque, N m (negative loads the other flank).
    pub torque: f64,
    /// Input speed, rpm.
    pub speed_rpm: f64,
    /// Share of the working time, 0..1 (the levels sum to 1).
    pub fraction: f64,
}

/// The configuration converted to SI and checked.
#[derive(Debug, Clone)]
pub struct Model {
    /// Nominal stage geometry.
    pub geometry: CycloidGeometry,
    /// Modifications.
    pub modification: Modification,
    /// Contact model.
    pub contact: ContactModel,
    /// Share of the output torque on one disc.
    pub load_share: f64,
    /// Overall ratio `i_H = 1 + (Z2/Z1) Zp` (physics-notes section 1).
    pub ratio: f64,
    /// Rated output torque, N m.
    pub rated_torque: f64,
    /// Nominal input speed, rpm.
    pub input_speed_rpm: f64,
    /// Load spectrum.
    pub spectrum: Vec<LoadLevel>,
    /// Wear model.
    pub wear_model: WearModelKind,
    /// Archard coefficient, m^2/N.
    pub archard: f64,
    /// Stages, h.
    pub stage_hours: Vec<f64>,
    /// Profile update step, h (0 = off).
    pub update_hours: f64,
    /// Largest wear increment between updates, m.
    pub max_wear_step: f64,
    /// Crank steps per mesh cycle for wear.
    pub wear_steps: usize,
    /// Pin rolling fraction.
    pub pin_rolling_fraction: f64,
    /// Overlap ratio of the paper's model.
    pub overlap_ratio: f64,
    /// TE samples per mesh cycle.
    pub te_samples: usize,
    /// Torque of the loaded TE, N m.
    pub loaded_torque: f64,
    /// Parameters of the multibody model (always checked; see `dynamics_enabled`).
    pub dynamics: DynamicsParams,
    /// Whether `rvlife run` adds the dynamic TE to every stage.
    pub dynamics_enabled: bool,
    /// Parameters of the flexible disc (always checked; see `fem_enabled`).
    pub fem: FemParams,
    /// Whether the study runs the flexible-disc analysis.
    pub fem_enabled: bool,
}

impl Model {
    /// Mesh cycles per hour of every disc tooth at input speed `n_in` (rpm):
    /// `60 n_in Zp / i_H` (physics-notes section 1: one mesh cycle per crank revolution relative
    /// to the carrier). The paper's eq 19 uses `n_in` instead; see [`crate::wear`].
    pub fn mesh_cycles_per_hour(&self, speed_rpm: f64) -> f64 {
        60.0 * speed_rpm * self.geometry.pins as f64 / self.ratio
    }

    /// The profile with this model's modifications and the given wear map.
    pub fn profile(&self, wear: Option<WearMap>) -> Result<Profile> {
        Profile::new(self.geometry.clone(), self.modification, wear)
    }
}

fn finite(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::invalid(field, v, "must be a finite number"))
    }
}

fn positive(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::invalid(field, v, "must be a finite number > 0"))
    }
}

fn in_range(field: &str, v: f64, lo: f64, hi: f64, words: &str) -> Result<f64> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(Error::invalid(field, v, words))
    }
}

fn count(field: &str, v: i64, min: i64, max: i64) -> Result<usize> {
    if v >= min && v <= max {
        Ok(v as usize)
    } else {
        Err(Error::invalid(
            field,
            v,
            format!("must be a whole number from {min} to {max}"),
        ))
    }
}

impl Config {
    /// Parses TOML text; `origin` names the source in errors (a path or `<built-in>`).
    ///
    /// # Errors
    /// [`Error::Config`] for syntax errors, wrong types and unknown keys (with the key path).
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Config> {
        let de = toml::Deserializer::parse(text).map_err(|e| Error::Config {
            path: origin.into(),
            message: e.to_string().trim().to_string(),
        })?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner().message().trim().to_string();
            Error::Config {
                path: origin.into(),
                message: if path == "." || path.is_empty() {
                    inner
                } else {
                    format!("at `{path}`: {inner}")
                },
            }
        })
    }

    /// Reads a config file.
    ///
    /// # Errors
    /// [`Error::Config`] if the file cannot be read or parsed.
    pub fn from_file(path: &Path) -> Result<Config> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::Config {
            path: path.display().to_string(),
            message: format!("cannot read the file: {e}"),
        })?;
        let mut c = Config::from_toml_str(&text, &path.display().to_string())?;
        c.base_dir = path.parent().map(Path::to_path_buf);
        Ok(c)
    }

    /// The built-in example (the paper's reducer).
    pub fn example() -> Config {
        Config::from_toml_str(EXAMPLE_TOML, "<built-in>").expect("the built-in example parses")
    }

    /// Checks every value and converts to SI.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and the allowed range.
    pub fn validate(&self) -> Result<Model> {
        let r = &self.reducer;
        let c = &self.cycloid;
        let pins = count("cycloid.pins", c.pins, 3, 1000)?;
        let geometry = CycloidGeometry {
            pins,
            eccentricity: positive("cycloid.eccentricity_mm", c.eccentricity_mm)? * 1e-3,
            pin_circle_radius: positive("cycloid.pin_circle_radius_mm", c.pin_circle_radius_mm)?
                * 1e-3,
            pin_radius: positive("cycloid.pin_radius_mm", c.pin_radius_mm)? * 1e-3,
            width: positive("cycloid.width_mm", c.width_mm)? * 1e-3,
        };
        let modification = Modification {
            equidistant: finite(
                "cycloid.modification.equidistant_mm",
                c.modification.equidistant_mm,
            )? * 1e-3,
            offset: finite("cycloid.modification.offset_mm", c.modification.offset_mm)? * 1e-3,
            rotation: finite(
                "cycloid.modification.rotation_deg",
                c.modification.rotation_deg,
            )?
            .to_radians(),
        };
        // Geometry, K1 and undercut checks.
        let nominal_profile = Profile::new(geometry.clone(), modification, None)?;
        let load_share = in_range(
            "cycloid.load_share",
            c.load_share,
            f64::MIN_POSITIVE,
            1.0,
            "must be in (0, 1]",
        )?;
        let mat = |name: &str, m: &MaterialConfig| -> Result<(f64, f64)> {
            Ok((
                positive(
                    &format!("materials.{name}.youngs_modulus_gpa"),
                    m.youngs_modulus_gpa,
                )? * 1e9,
                in_range(
                    &format!("materials.{name}.poisson_ratio"),
                    m.poisson_ratio,
                    0.0,
                    0.499,
                    "must be in [0, 0.5)",
                )?,
            ))
        };
        let (e1, nu1) = mat("disc", &self.materials.disc)?;
        let (e2, nu2) = mat("pin", &self.materials.pin)?;
        let law = match self.contact.law.as_str() {
            "paper" => ApproachLaw::Paper,
            "johnson" => ApproachLaw::Johnson,
            "linear" => {
                let k = self.contact.linear_stiffness_n_per_um.ok_or_else(|| {
                    Error::invalid(
                        "contact.linear_stiffness_n_per_um",
                        "missing",
                        "required with law = \"linear\"",
                    )
                })?;
                ApproachLaw::Linear {
                    stiffness: positive("contact.linear_stiffness_n_per_um", k)? * 1e6,
                }
            }
            other => {
                return Err(Error::invalid(
                    "contact.law",
                    format!("\"{other}\""),
                    "must be \"paper\", \"johnson\" or \"linear\"",
                ))
            }
        };
        let max_radius = match self.contact.max_curvature_radius_mm {
            Some(v) => positive("contact.max_curvature_radius_mm", v)? * 1e-3,
            None => geometry.pin_circle_radius,
        };
        let contact = ContactModel {
            law,
            materials: Materials {
                disc_youngs_modulus: e1,
                disc_poisson_ratio: nu1,
                pin_youngs_modulus: e2,
                pin_poisson_ratio: nu2,
            },
            width: geometry.width,
            pin_radius: geometry.pin_radius,
            max_radius,
        };
        let z1 = count("reducer.sun_teeth", r.sun_teeth as i64, 1, 10_000)?;
        let z2 = count("reducer.planet_teeth", r.planet_teeth as i64, 1, 10_000)?;
        count("reducer.planets", r.planets as i64, 1, 12)?;
        let ratio = 1.0 + z2 as f64 / z1 as f64 * pins as f64;
        let input_speed_rpm = positive("reducer.input_speed_rpm", r.input_speed_rpm)?;
        let rated_torque = positive("reducer.rated_torque_nm", r.rated_torque_nm)?;
        let spectrum = self.load_spectrum(rated_torque, input_speed_rpm)?;
        let w = &self.wear;
        let wear_model = match w.model.as_str() {
            "flodin" => WearModelKind::Flodin,
            "paper" => WearModelKind::Paper,
            other => {
                return Err(Error::invalid(
                    "wear.model",
                    format!("\"{other}\""),
                    "must be \"flodin\" or \"paper\"",
                ))
            }
        };
        let archard = match (
            w.archard_coefficient_mm3_per_n_m,
            w.archard_coefficient_m2_per_n,
        ) {
            (Some(k), None) => positive("wear.archard_coefficient_mm3_per_n_m", k)? * 1e-9,
            (None, Some(k)) => positive("wear.archard_coefficient_m2_per_n", k)?,
            _ => {
                return Err(Error::invalid(
                    "wear.archard_coefficient_mm3_per_n_m",
                    "missing or given twice",
                    "give exactly one of archard_coefficient_mm3_per_n_m and \
                     archard_coefficient_m2_per_n",
                ))
            }
        };
        if w.stage_hours.is_empty() || w.stage_hours.len() > 1000 {
            return Err(Error::invalid(
                "wear.stage_hours",
                format!("{} entries", w.stage_hours.len()),
                "must list 1 to 1000 stages",
            ));
        }
        let mut prev = -1.0;
        for (i, &h) in w.stage_hours.iter().enumerate() {
            let field = format!("wear.stage_hours[{i}]");
            in_range(&field, h, 0.0, 1e7, "must be in [0, 1e7] h")?;
            if h <= prev {
                return Err(Error::invalid(field, h, "stages must increase strictly"));
            }
            prev = h;
        }
        let update_hours = in_range(
            "wear.profile_update_hours",
            w.profile_update_hours,
            0.0,
            1e7,
            "must be in [0, 1e7] h (0: no profile updates)",
        )?;
        if update_hours > 0.0 && prev / update_hours > 100_000.0 {
            return Err(Error::invalid(
                "wear.profile_update_hours",
                update_hours,
                "would need more than 100000 profile updates; use a larger step",
            ));
        }
        let max_wear_step = in_range(
            "wear.max_wear_step_um",
            w.max_wear_step_um,
            0.01,
            1000.0,
            "must be in [0.01, 1000] um",
        )? * 1e-6;
        let wear_steps = count(
            "wear.crank_steps_per_mesh_cycle",
            w.crank_steps_per_mesh_cycle,
            2,
            1000,
        )?;
        let pin_rolling_fraction = in_range(
            "wear.pin_rolling_fraction",
            w.pin_rolling_fraction,
            0.0,
            1.0,
            "must be in [0, 1]",
        )?;
        let overlap_ratio = positive("wear.overlap_ratio", w.overlap_ratio)?;
        let te_samples = count(
            "te.samples_per_mesh_cycle",
            self.te.samples_per_mesh_cycle,
            2,
            10_000,
        )?;
        let loaded_torque = match self.te.loaded_torque_nm {
            Some(t) => finite("te.loaded_torque_nm", t)?,
            None => rated_torque,
        };
        let dynamics = self.dynamics.validate(
            &nominal_profile,
            &contact,
            z1,
            z2,
            r.planets as usize,
            ratio,
            rated_torque,
            load_share,
            self.base_dir.as_deref(),
        )?;
        let fem = self.fem.validate(
            &nominal_profile,
            r.planets as usize,
            self.dynamics.inertia.crank_bore_radius_mm * 1e-3,
            dynamics.crank_circle_radius,
            contact.materials.disc_youngs_modulus,
            contact.materials.disc_poisson_ratio,
        )?;
        Ok(Model {
            dynamics,
            dynamics_enabled: self.dynamics.enabled,
            fem,
            fem_enabled: self.fem.enabled,
            geometry,
            modification,
            contact,
            load_share,
            ratio,
            rated_torque,
            input_speed_rpm,
            spectrum,
            wear_model,
            archard,
            stage_hours: w.stage_hours.clone(),
            update_hours,
            max_wear_step,
            wear_steps,
            pin_rolling_fraction,
            overlap_ratio,
            te_samples,
            loaded_torque,
        })
    }

    fn load_spectrum(&self, rated: f64, speed: f64) -> Result<Vec<LoadLevel>> {
        let l = &self.load;
        let unused = |name: &str, v: bool| -> Result<()> {
            if v {
                Err(Error::invalid(
                    format!("load.{name}"),
                    "given",
                    format!("does not apply to load kind \"{}\"", l.kind),
                ))
            } else {
                Ok(())
            }
        };
        match l.kind.as_str() {
            "constant" => {
                unused("amplitude_nm", l.amplitude_nm.is_some())?;
                unused("file", l.file.is_some())?;
                let t = finite("load.torque_nm", l.torque_nm.unwrap_or(rated))?;
                Ok(vec![LoadLevel {
                    torque: t,
                    speed_rpm: speed,
                    fraction: 1.0,
                }])
            }
            "sinusoidal" => {
                unused("torque_nm", l.torque_nm.is_some())?;
                unused("file", l.file.is_some())?;
                let amp = l.amplitude_nm.unwrap_or(rated);
                if !amp.is_finite() || amp < 0.0 {
                    return Err(Error::invalid(
                        "load.amplitude_nm",
                        amp,
                        "must be a finite number >= 0",
                    ));
                }
                let off = finite("load.offset_nm", l.offset_nm.unwrap_or(0.0))?;
                if let Some(p) = l.period_s {
                    positive("load.period_s", p)?;
                }
                let n = count("load.levels", l.levels.unwrap_or(24), 4, 10_000)?;
                Ok((0..n)
                    .map(|k| {
                        let ph = std::f64::consts::TAU * (k as f64 + 0.5) / n as f64;
                        LoadLevel {
                            torque: off + amp * ph.sin(),
                            speed_rpm: speed,
                            fraction: 1.0 / n as f64,
                        }
                    })
                    .collect())
            }
            "duty_cycle" => {
                unused("torque_nm", l.torque_nm.is_some())?;
                unused("amplitude_nm", l.amplitude_nm.is_some())?;
                let file = l.file.as_ref().ok_or_else(|| {
                    Error::invalid(
                        "load.file",
                        "missing",
                        "required with kind = \"duty_cycle\"",
                    )
                })?;
                let path = match &self.base_dir {
                    Some(d) if file.is_relative() => d.join(file),
                    _ => file.clone(),
                };
                read_duty_cycle(&path)
            }
            other => Err(Error::invalid(
                "load.kind",
                format!("\"{other}\""),
                "must be \"constant\", \"sinusoidal\" or \"duty_cycle\"",
            )),
        }
    }
}

/// Reads a duty-cycle CSV with header `duration_s,torque_nm,speed_rpm`.
///
/// # Errors
/// [`Error::Config`] if unreadable; [`Error::Invalid`] naming the row for a bad value.
pub fn read_duty_cycle(path: &Path) -> Result<Vec<LoadLevel>> {
    let origin = path.display().to_string();
    let mut rdr = csv::Reader::from_path(path).map_err(|e| Error::Config {
        path: origin.clone(),
        message: format!("cannot read the duty cycle: {e}"),
    })?;
    let headers = rdr
        .headers()
        .map_err(|e| Error::Config {
            path: origin.clone(),
            message: e.to_string(),
        })?
        .clone();
    let want = ["duration_s", "torque_nm", "speed_rpm"];
    if headers.iter().map(str::trim).collect::<Vec<_>>() != want {
        return Err(Error::Config {
            path: origin,
            message: format!(
                "header must be `duration_s,torque_nm,speed_rpm`, found `{}`",
                headers.iter().collect::<Vec<_>>().join(",")
            ),
        });
    }
    let mut rows = Vec::new();
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| Error::Config {
            path: origin.clone(),
            message: e.to_string(),
        })?;
        let mut v = [0.0; 3];
        for (k, name) in want.iter().enumerate() {
            let field = format!("{origin} row {} column {name}", i + 1);
            let s = rec.get(k).unwrap_or("").trim();
            v[k] = s
                .parse::<f64>()
                .map_err(|_| Error::invalid(&field, format!("\"{s}\""), "must be a number"))?;
            if !v[k].is_finite() {
                return Err(Error::invalid(&field, v[k], "must be finite"));
            }
        }
        positive(&format!("{origin} row {} column duration_s", i + 1), v[0])?;
        positive(&format!("{origin} row {} column speed_rpm", i + 1), v[2])?;
        rows.push((v[0], v[1], v[2]));
    }
    if rows.is_empty() {
        return Err(Error::Config {
            path: origin,
            message: "the duty cycle has no rows".into(),
        });
    }
    let total: f64 = rows.iter().map(|r| r.0).sum();
    Ok(rows
        .into_iter()
        .map(|(d, t, n)| LoadLevel {
            torque: t,
            speed_rpm: n,
            fraction: d / total,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn example_parses_and_validates() {
        let m = Config::example().validate().unwrap();
        assert_eq!(m.geometry.pins, 40);
        assert!((m.ratio - 81.0).abs() < 1e-12);
        assert_eq!(m.stage_hours.len(), 7);
    }

    #[test]
    fn unknown_key_is_named_with_its_path() {
        let text = EXAMPLE_TOML.replace(
            "[cycloid.modification]",
            "[cycloid.modification]\nbogus = 1",
        );
        let e = Config::from_toml_str(&text, "x.toml").unwrap_err();
        let s = e.to_string();
        assert!(
            s.contains("bogus") && s.contains("cycloid.modification"),
            "{s}"
        );
    }

    #[test]
    fn nan_is_rejected() {
        let text = EXAMPLE_TOML.replace("pin_radius_mm = 3.0", "pin_radius_mm = nan");
        let e = Config::from_toml_str(&text, "x")
            .unwrap()
            .validate()
            .unwrap_err();
        assert!(e.to_string().contains("cycloid.pin_radius_mm"), "{e}");
    }
}
