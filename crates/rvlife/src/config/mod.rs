//! The study configuration: TOML in engineering units, checked and converted to SI.
//!
//! Keys carry their unit in their name (`pin_radius_mm`, `torque_nm`). Unknown keys are
//! rejected with their path; every value is range-checked by [`Config::validate`] with an error
//! naming the key, the value and the allowed range. [`Config::example`] is the paper's RV-40E
//! class reducer (paper Tables 1-2, physics-notes section 7), printed by `rvlife example`.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

mod accuracy;
mod dynamics;
mod fem;
mod physical;
mod presets;
mod range;
mod raw;

pub use accuracy::{
    iso_it, ErrorsConfig, LifeConfig, LifeThresholds, Tolerance, ToleranceConfig, Tolerances,
    TolerancesConfig,
};
pub use dynamics::{
    read_load_table, DriveConfig, DynLoadConfig, DynamicsConfig, ImpactConfig, InertiaConfig,
};
pub use fem::FemConfig;
pub use physical::PROBES_PER_MESH_CYCLE;
pub use presets::{preset_text, Preset, PRESETS};
pub(crate) use range::{check, whole, Range};
pub use raw::{
    BearingsConfig, ContactConfig, CycloidConfig, GearsConfig, LoadConfig, MaterialConfig,
    MaterialsConfig, ModificationConfig, OutputPinsConfig, ReducerConfig, TeConfig, WearConfig,
};

use crate::contact::{ApproachLaw, ContactModel, Materials};

use crate::error::{Error, Result};
use crate::fem::FemParams;
use crate::geometry::{CycloidGeometry, Modification, Profile, WearMap};
use crate::reducer::dynamics::DynamicsParams;
use crate::reducer::{Bearings, Drive, Mesh, OutputPins, Reducer, Support};

/// The built-in example: the paper's reducer, fully commented.
pub const EXAMPLE_TOML: &str = include_str!("../example.toml");

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
    /// Known part errors of this reducer.
    #[serde(default)]
    pub errors: ErrorsConfig,
    /// Tolerance distributions of the part errors (Monte Carlo).
    #[serde(default)]
    pub tolerances: TolerancesConfig,
    /// Accuracy spec: the thresholds that end the accuracy life.
    #[serde(default)]
    pub life: LifeConfig,
    /// Directory of the config file (for relative paths); not a key.
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
    /// The dotted keys the file sets (`cycloid.pins`), to tell a key the user wrote from a
    /// default in messages; `None` for the built-in example (every key written). Not a key.
    #[serde(skip)]
    pub written: Option<std::collections::BTreeSet<String>>,
    /// Work budget, minutes of estimated computing on the reference machine (2 cores): a
    /// config whose estimate exceeds it is refused before the work starts, naming the key that
    /// drives it ([`crate::budget`]). Not a key: the command line's `--work-budget-min`.
    #[serde(skip, default = "crate::budget::default_minutes")]
    pub work_budget_minutes: f64,
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
    /// The reducer's mechanical model: bodies, bearings, meshes, the pin contact law and the
    /// disc support of the static analysis.
    pub reducer: Reducer,
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
    /// Measuring torque of lost motion, as a fraction of the rated torque (catalogue: 0.03).
    pub measuring_torque_fraction: f64,
    /// Parameters of the multibody model (always checked; see `dynamics_enabled`).
    pub dynamics: DynamicsParams,
    /// Whether `rvlife run` adds the dynamic TE to every stage.
    pub dynamics_enabled: bool,
    /// Parameters of the flexible disc (always checked; see `fem_enabled`).
    pub fem: FemParams,
    /// Whether the study runs the flexible-disc analysis.
    pub fem_enabled: bool,
    /// Largest Hertz pressure the contact may carry, Pa (`materials.max_contact_pressure_mpa`).
    pub max_contact_pressure: f64,
    /// Work budget in contact-solve equivalents ([`crate::budget`]).
    pub work_budget: f64,
    /// The key that sets the Archard coefficient, as the user wrote it.
    pub archard_key: &'static str,
    /// Tolerance distributions of the part errors (`[tolerances]`; empty: none).
    pub tolerances: Tolerances,
    /// Accuracy thresholds (`[life]`; none set: no accuracy life).
    pub life: LifeThresholds,
    /// The measured profile (`cycloid.measured_profile`), whose deviation map every profile of
    /// this model carries under its wear ([`Model::profile`]).
    pub measured: Option<crate::measured::MeasuredProfile>,
}

impl Model {
    /// Mesh cycles per hour of every disc tooth at input speed `n_in` (rpm):
    /// `60 n_in Zp / i_H` (physics-notes section 1: one mesh cycle per crank revolution relative
    /// to the carrier). The paper's eq 19 uses `n_in` instead; see [`crate::wear`].
    pub fn mesh_cycles_per_hour(&self, speed_rpm: f64) -> f64 {
        60.0 * speed_rpm * self.geometry.pins as f64 / self.ratio.abs()
    }

    /// Share of the output torque on one disc for the closed-form estimates (Li's distribution,
    /// the paper's wear model, reference forces): `load_share` with rigid support, 1/2 with
    /// bearings (two discs).
    pub fn disc_share(&self) -> f64 {
        match self.reducer.support {
            Support::Rigid { load_share } => load_share,
            Support::Bearings => 0.5,
        }
    }

    /// Torque (N m) on one disc at a fixed crank angle equivalent to the output torque
    /// `torque`: `share T Zc/(Zp + Z1/Z2)` (physics-notes section 6: the first stage turns the
    /// cranks when the output twists with the input locked).
    pub fn equivalent_disc_torque(&self, torque: f64) -> f64 {
        self.disc_share() * torque * self.reducer.twist_factor()
    }

    /// The profile with this model's modifications and the given wear map, on the measured
    /// profile's deviation map when there is one (the deviation added to the wear depth,
    /// resampled linearly when the grids differ).
    ///
    /// # Errors
    /// Those of [`Profile::new`].
    pub fn profile(&self, wear: Option<WearMap>) -> Result<Profile> {
        let Some(m) = &self.measured else {
            return Profile::new(self.geometry.clone(), self.modification, wear);
        };
        let n = wear
            .as_ref()
            .map_or(m.deviation.len(), |w| w.depths().len());
        let dev = resample(&m.deviation, n);
        let depth: Vec<f64> = match &wear {
            Some(w) => w.depths().iter().zip(&dev).map(|(a, b)| a + b).collect(),
            None => dev,
        };
        Profile::new(
            self.geometry.clone(),
            self.modification,
            Some(WearMap::deviation(depth)?),
        )
    }

    /// Largest wear depth (m) of a profile of this model: its map's depth less the measured
    /// deviation (which is not wear).
    pub fn wear_depth(&self, profile: &Profile) -> f64 {
        let Some(w) = profile.wear() else {
            return 0.0;
        };
        match &self.measured {
            None => w.max_depth(),
            Some(m) => {
                let dev = resample(&m.deviation, w.depths().len());
                w.depths()
                    .iter()
                    .zip(&dev)
                    .map(|(a, b)| a - b)
                    .fold(0.0, f64::max)
            }
        }
    }
}

/// `v` (periodic, uniform grid) linearly resampled to `n` points.
fn resample(v: &[f64], n: usize) -> Vec<f64> {
    if v.len() == n {
        return v.to_vec();
    }
    (0..n)
        .map(|i| {
            let s = i as f64 * v.len() as f64 / n as f64;
            let k = s.floor() as usize % v.len();
            let u = s - s.floor();
            v[k] * (1.0 - u) + v[(k + 1) % v.len()] * u
        })
        .collect()
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
        Config::from_toml_in(&text, &path.display().to_string(), path.parent())
    }

    /// Parses TOML text as if read from a file in `base_dir` (relative paths in it, such as a
    /// measured profile, are taken from there; `None`: the working directory), recording the
    /// keys it writes so that errors about defaults say so ([`Config::from_file`] without the
    /// file).
    ///
    /// # Errors
    /// [`Error::Config`] for syntax errors, wrong types and unknown keys (with the key path).
    pub fn from_toml_in(text: &str, origin: &str, base_dir: Option<&Path>) -> Result<Config> {
        let mut c = Config::from_toml_str(text, origin)?;
        c.base_dir = base_dir.map(Path::to_path_buf);
        c.written = written_keys(text);
        Ok(c)
    }

    /// The built-in example (the paper's reducer).
    pub fn example() -> Config {
        Config::from_toml_str(EXAMPLE_TOML, "<built-in>").expect("the built-in example parses")
    }

    /// Checks every value and converts to SI: the reducer's mechanical model ([`Reducer`]), the
    /// load spectrum, the wear and TE settings, and the `[dynamics]` and `[fem]` sections; then
    /// the physics of the unworn stage (the modifications keep the disc in mesh, every torque
    /// of the config is carried: [`PROBES_PER_MESH_CYCLE`]) and the work the config needs
    /// against the budget ([`crate::budget`]).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and the allowed range. A key the file does
    /// not set (a default) is named as such, with what its default depends on.
    pub fn validate(&self) -> Result<Model> {
        self.validate_inner().map_err(|e| self.explain_default(e))
    }

    /// Marks the key of an [`Error::Invalid`] that the user's file does not set.
    fn explain_default(&self, e: Error) -> Error {
        let Some(written) = &self.written else {
            return e;
        };
        match e {
            Error::Invalid {
                field,
                value,
                allowed,
            } => {
                let is_key = field.contains('.')
                    && field
                        .chars()
                        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || "._".contains(c));
                let prefix = format!("{field}.");
                if !is_key
                    || written.contains(&field)
                    || written.iter().any(|w| w.starts_with(&prefix))
                {
                    return Error::Invalid {
                        field,
                        value,
                        allowed,
                    };
                }
                let source = default_source(&field);
                Error::Invalid {
                    field: format!("{field} (not in your file: {source})"),
                    value,
                    allowed,
                }
            }
            other => other,
        }
    }

    /// The disc phases (rad) and, for a single-stage drive, its output mechanism, from
    /// `reducer.discs`, `reducer.disc_phases_deg` and `[reducer.output_pins]` (sizes left out
    /// scaled from the stage like the RV crank circle: [`scaled_from_root`]).
    fn single_stage(
        &self,
        single: bool,
        geometry: &CycloidGeometry,
    ) -> Result<(Vec<f64>, Option<OutputPins>)> {
        let r = &self.reducer;
        if !single {
            let only = "applies only to drive = \"single_stage\" (an RV reducer has two discs \
                        180 deg apart and takes its output through the cranks)";
            if r.discs.is_some_and(|d| d != 2) {
                return Err(Error::invalid("reducer.discs", r.discs.unwrap_or(0), only));
            }
            if r.disc_phases_deg.is_some() {
                return Err(Error::invalid("reducer.disc_phases_deg", "given", only));
            }
            if r.output_pins.is_some() {
                return Err(Error::invalid("reducer.output_pins", "given", only));
            }
            return Ok((vec![0.0, std::f64::consts::PI], None));
        }
        let n = whole("reducer.discs", r.discs.unwrap_or(2), 1, 3)?;
        let phases = match &r.disc_phases_deg {
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
        let w = r.output_pins.clone().unwrap_or_default();
        let key = |k: &str| format!("reducer.output_pins.{k}");
        let count = whole(&key("count"), w.count.unwrap_or(8), 3, 64)?;
        let mm =
            |k: &str, v: f64| check(&key(k), v, Range::closed(0.01, 1e4, "mm")).map(|v| v * 1e-3);
        let circle = mm(
            "circle_radius_mm",
            w.circle_radius_mm
                .unwrap_or_else(|| scaled_from_root(geometry, 40.5)),
        )?;
        let pin = mm(
            "pin_radius_mm",
            w.pin_radius_mm
                .unwrap_or_else(|| scaled_from_root(geometry, 8.0)),
        )?;
        let clearance = check(
            &key("hole_clearance_um"),
            w.hole_clearance_um,
            Range::non_negative(1e3, "um"),
        )? * 1e-6;
        let stiffness = match w.stiffness_n_per_um {
            Some(k) => check(&key("stiffness_n_per_um"), k, Range::positive(1e7, "N/um"))? * 1e6,
            None => 0.0,
        };
        // The holes (pin radius + eccentricity + clearance) must lie inside the tooth roots,
        // clear of the centre and of each other.
        let hole = pin + geometry.eccentricity + clearance;
        let root = geometry.pin_circle_radius - geometry.pin_radius - geometry.eccentricity;
        let neighbours = 2.0 * circle * (std::f64::consts::PI / count as f64).sin();
        let fits = circle + hole < root && circle - hole > 0.0 && neighbours > 2.0 * hole;
        if !fits {
            let k = if w.circle_radius_mm.is_some() || w.pin_radius_mm.is_none() {
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
        Ok((
            phases,
            Some(OutputPins {
                count,
                circle_radius: circle,
                hole_clearance: clearance,
                stiffness,
            }),
        ))
    }

    fn validate_inner(&self) -> Result<Model> {
        let r = &self.reducer;
        let c = &self.cycloid;
        // From a watch-size drive (0.01 mm) to beyond the largest reducers built (10 m).
        let mm =
            |key: &str, v: f64| check(key, v, Range::closed(0.01, 1e4, "mm")).map(|v| v * 1e-3);
        let pins = whole("cycloid.pins", c.pins, 3, 1000)?;
        let geometry = CycloidGeometry {
            pins,
            eccentricity: mm("cycloid.eccentricity_mm", c.eccentricity_mm)?,
            pin_circle_radius: mm("cycloid.pin_circle_radius_mm", c.pin_circle_radius_mm)?,
            pin_radius: mm("cycloid.pin_radius_mm", c.pin_radius_mm)?,
            width: mm("cycloid.width_mm", c.width_mm)?,
        };
        let m = &c.modification;
        let modification = Modification {
            equidistant: check(
                "cycloid.modification.equidistant_mm",
                m.equidistant_mm,
                Range::finite("mm"),
            )? * 1e-3,
            offset: check(
                "cycloid.modification.offset_mm",
                m.offset_mm,
                Range::finite("mm"),
            )? * 1e-3,
            // Real rotation modifications are a few arcminutes; the static analysis follows
            // 34 arcmin of twist from the nominal pose.
            rotation: check(
                "cycloid.modification.rotation_deg",
                m.rotation_deg,
                Range::closed(-0.5, 0.5, "deg (30 arcmin)"),
            )?
            .to_radians(),
        };
        // Geometry, K1 and undercut checks.
        let nominal_profile = Profile::new(geometry.clone(), modification, None)?;
        let mat = |name: &str, m: &MaterialConfig| -> Result<(f64, f64)> {
            Ok((
                check(
                    &format!("materials.{name}.youngs_modulus_gpa"),
                    m.youngs_modulus_gpa,
                    Range::positive(1e7, "GPa"),
                )? * 1e9,
                check(
                    &format!("materials.{name}.poisson_ratio"),
                    m.poisson_ratio,
                    Range::closed(0.0, 0.499, ""),
                )?,
            ))
        };
        let (e1, nu1) = mat("disc", &self.materials.disc)?;
        let (e2, nu2) = mat("pin", &self.materials.pin)?;
        let contact = self.contact_model(&geometry, (e1, nu1, e2, nu2))?;
        let single = match r.drive.as_str() {
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
        let z1 = first_stage("sun_teeth", r.sun_teeth, 1, 10_000)?;
        let z2 = first_stage("planet_teeth", r.planet_teeth, 1, 10_000)?;
        let planets = first_stage("planets", r.planets, 1, 12)?;
        let (disc_phases, output_pins) = self.single_stage(single, &geometry)?;
        let ratio = if single {
            -(geometry.disc_teeth() as f64)
        } else {
            1.0 + z2 as f64 / z1 as f64 * pins as f64
        };
        let input_speed_rpm = check(
            "reducer.input_speed_rpm",
            r.input_speed_rpm,
            Range::positive(1e6, "rpm"),
        )?;
        // From miniature cycloid drives (0.1 N m) up.
        let rated_torque = check(
            "reducer.rated_torque_nm",
            r.rated_torque_nm,
            Range::closed(0.1, 1e7, "N m"),
        )?;
        let support = match self.contact.support.as_str() {
            "bearings" => {
                if self.contact.load_share.is_some() {
                    return Err(Error::invalid(
                        "contact.load_share",
                        "given",
                        "applies only to support = \"rigid\" (with bearings the load share \
                         comes out of the equilibrium)",
                    ));
                }
                Support::Bearings
            }
            "rigid" => Support::Rigid {
                load_share: check(
                    "contact.load_share",
                    self.contact.load_share.unwrap_or(0.55),
                    Range::positive(1.0, ""),
                )?,
            },
            other => {
                return Err(Error::invalid(
                    "contact.support",
                    format!("\"{other}\""),
                    "must be \"bearings\" or \"rigid\"",
                ))
            }
        };
        // A single-stage drive's multibody and FE data are those of its RV twin (the same
        // stage on a 1:3 first stage with two cranks on the output pin circle): never read,
        // since both analyses are refused for it.
        let (mesh, mesh_zeta) = if single {
            self.reducer.gears.validate(10, 30, &geometry)?
        } else {
            self.reducer.gears.validate(z1, z2, &geometry)?
        };
        let (bearings, bearing_zeta) = self.reducer.bearings.validate()?;
        let (drive, cranks, crank_circle_radius, stage_mesh) = match output_pins {
            Some(mut w) => {
                if w.stiffness <= 0.0 {
                    w.stiffness = bearings.disc_stiffness;
                }
                let mut m = mesh;
                m.sun_planet_ratio = -1.0;
                (Drive::SingleStage(w), 0, w.circle_radius, m)
            }
            None => (
                Drive::Rv,
                planets,
                mesh.sun_pitch_radius + mesh.planet_pitch_radius,
                mesh,
            ),
        };
        let reducer = Reducer {
            geometry: geometry.clone(),
            ratio,
            cranks,
            crank_circle_radius,
            mesh: stage_mesh,
            bearings,
            contact,
            support,
            contact_band_force: 0.0,
            contact_envelope: match self.contact.band.as_str() {
                "single" => false,
                "envelope" => true,
                other => {
                    return Err(Error::invalid(
                        "contact.band",
                        format!("\"{other}\""),
                        "must be \"single\" or \"envelope\"",
                    ))
                }
            },
            gap_points: whole(
                "dynamics.gap_points_per_tooth",
                self.dynamics.gap_points_per_tooth,
                64,
                65536,
            )?,
            errors: self.errors.validate(pins, cranks)?,
            drive,
            disc_phases,
        };
        let mut reducer = reducer;
        reducer.contact_band_force = match self.contact.band_force_n {
            Some(f) => check("contact.band_force_n", f, Range::positive(1e7, "N"))?,
            // Li's largest pin force at the rated torque on one disc (physics-notes section 4).
            None => {
                4.0 * 0.5 * rated_torque * reducer.twist_factor()
                    / (geometry.disc_pitch_radius() * pins as f64)
            }
        };
        let (spectrum, level_keys) = self.load_spectrum(rated_torque, input_speed_rpm)?;
        let max_contact_pressure = check(
            "materials.max_contact_pressure_mpa",
            self.materials.max_contact_pressure_mpa,
            Range::closed(10.0, 1e5, "MPa"),
        )? * 1e6;
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
        let archard_key = if w.archard_coefficient_m2_per_n.is_some() {
            "wear.archard_coefficient_m2_per_n"
        } else {
            "wear.archard_coefficient_mm3_per_n_m"
        };
        let archard = match (
            w.archard_coefficient_mm3_per_n_m,
            w.archard_coefficient_m2_per_n,
        ) {
            (Some(k), None) => {
                check(
                    "wear.archard_coefficient_mm3_per_n_m",
                    k,
                    Range::positive(1e6, "mm^3/(N m)"),
                )? * 1e-9
            }
            (None, Some(k)) => check(
                "wear.archard_coefficient_m2_per_n",
                k,
                Range::positive(1e-3, "m^2/N"),
            )?,
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
            check(&field, h, Range::closed(0.0, 1e7, "h"))?;
            if h <= prev {
                return Err(Error::invalid(field, h, "stages must increase strictly"));
            }
            prev = h;
        }
        let update_hours = check(
            "wear.profile_update_hours",
            w.profile_update_hours,
            Range::closed(0.0, 1e7, "h (0: no profile updates)"),
        )?;
        if update_hours > 0.0 && prev / update_hours > 100_000.0 {
            return Err(Error::invalid(
                "wear.profile_update_hours",
                update_hours,
                "would need more than 100000 profile updates; use a larger step",
            ));
        }
        let max_wear_step = check(
            "wear.max_wear_step_um",
            w.max_wear_step_um,
            Range::closed(0.01, 1000.0, "um"),
        )? * 1e-6;
        let wear_steps = whole(
            "wear.crank_steps_per_mesh_cycle",
            w.crank_steps_per_mesh_cycle,
            2,
            1000,
        )?;
        let measured = match &c.measured_profile {
            None => None,
            Some(p) => {
                let path = match &self.base_dir {
                    Some(dir) if p.is_relative() => dir.join(p),
                    _ => p.clone(),
                };
                let points = crate::measured::read_points(&path)?;
                Some(crate::measured::fit(
                    &nominal_profile,
                    &points,
                    pins * wear_steps,
                    &path,
                )?)
            }
        };
        let pin_rolling_fraction = check(
            "wear.pin_rolling_fraction",
            w.pin_rolling_fraction,
            Range::closed(0.0, 1.0, ""),
        )?;
        let overlap_ratio = check(
            "wear.overlap_ratio",
            w.overlap_ratio,
            Range::positive(100.0, ""),
        )?;
        let te_samples = whole(
            "te.samples_per_mesh_cycle",
            self.te.samples_per_mesh_cycle,
            2,
            10_000,
        )?;
        let loaded_torque = match self.te.loaded_torque_nm {
            Some(t) => check("te.loaded_torque_nm", t, Range::finite("N m"))?,
            None => rated_torque,
        };
        let measuring_torque_fraction = check(
            "te.measuring_torque_fraction",
            self.te.measuring_torque_fraction,
            Range::closed(1e-4, 0.5, "of the rated torque"),
        )?;
        // A disabled section is checked only as far as the enabled analyses read it: if it
        // does not validate, its defaults stand in (nothing reads them), so that `te` and
        // `contact` never fail on a `[dynamics]` or `[fem]` they do not use. The `dynamics`
        // command enables its section.
        if single {
            for (key, on) in [
                ("dynamics.enabled", self.dynamics.enabled),
                ("fem.enabled", self.fem.enabled),
            ] {
                if on {
                    return Err(Error::invalid(
                        key,
                        "true",
                        "the multibody and finite-element models are built for RV reducers; \
                         set enabled = false for drive = \"single_stage\"",
                    ));
                }
            }
        }
        let twin = Reducer {
            drive: Drive::Rv,
            cranks: 2,
            crank_circle_radius: mesh.sun_pitch_radius + mesh.planet_pitch_radius,
            mesh,
            disc_phases: vec![0.0, std::f64::consts::PI],
            errors: Default::default(),
            ..reducer.clone()
        };
        let rv = if single { &twin } else { &reducer };
        let planets = rv.cranks;
        let dynamics_of = |d: &DynamicsConfig| {
            d.validate(
                rv,
                (mesh_zeta, bearing_zeta),
                &nominal_profile,
                rated_torque,
                self.base_dir.as_deref(),
            )
        };
        let dynamics = match dynamics_of(&self.dynamics) {
            Err(e) if self.dynamics.enabled => return Err(e),
            Err(e) => dynamics_of(&DynamicsConfig::default()).map_err(|_| e)?,
            Ok(d) => d,
        };
        let default_bore = scaled_from_root(&geometry, 13.0);
        let fem_of = |f: &FemConfig, bore_mm: f64| {
            f.validate(
                &nominal_profile,
                planets,
                bore_mm * 1e-3,
                rv.crank_circle_radius,
                e1,
                nu1,
            )
        };
        let bore = self
            .dynamics
            .inertia
            .crank_bore_radius_mm
            .unwrap_or(default_bore);
        // The flexible disc of the dynamics reads `[fem]` (its mesh and holes).
        let fem_read =
            self.fem.enabled || (self.dynamics.enabled && self.dynamics.disc == "flexible");
        let fem = match fem_of(&self.fem, bore) {
            Err(e) if fem_read => return Err(e),
            Err(e) => fem_of(&FemConfig::default(), default_bore).map_err(|_| e)?,
            Ok(f) => f,
        };
        // The multibody model carries one modal FE disc: every disc must be its part turned by
        // a symmetry of the holes (checked here, before any work).
        if self.dynamics.enabled && self.dynamics.disc == "flexible" {
            let zc = geometry.disc_teeth();
            if let Some(d) = (0..reducer.discs())
                .find(|&d| crate::fem::mount_teeth(zc, reducer.profile_turn(d), &fem).is_none())
            {
                return Err(Error::invalid(
                    "dynamics.disc",
                    "\"flexible\"",
                    format!(
                        "needs every disc to be disc 1's part turned onto itself: disc {} is \
                         turned by its eccentric phase ({:.1} deg) and half a tooth, which maps \
                         the crank bores and holes of [fem] onto themselves only for an even \
                         number of cranks and an odd tooth count (here {planets} cranks, {zc} \
                         teeth); use \"rigid\" discs, or the quasi-static flexible disc of \
                         [fem] (fem.enabled), which models each disc",
                        d + 1,
                        reducer.phase(d).to_degrees()
                    ),
                ));
            }
        }
        let model = Model {
            max_contact_pressure,
            work_budget: crate::budget::solves_in_minutes(check(
                "--work-budget-min",
                self.work_budget_minutes,
                Range::positive(1e6, "min"),
            )?),
            archard_key,
            tolerances: self.tolerances.validate(&geometry)?,
            life: self.life.validate()?,
            measured,
            dynamics,
            dynamics_enabled: self.dynamics.enabled,
            fem,
            fem_enabled: self.fem.enabled,
            geometry,
            modification,
            reducer,
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
            measuring_torque_fraction,
        };
        let levels_key = match self.load.kind.as_str() {
            "duty_cycle" => "load.file",
            "sinusoidal" => "load.levels",
            _ => "load.kind",
        };
        crate::budget::check_config(&model, levels_key)?;
        physical::check_mesh(
            &model,
            &nominal_profile,
            &c.modification,
            model.geometry.pin_circle_radius,
        )?;
        let mut uses = vec![
            ("reducer.rated_torque_nm".to_string(), rated_torque),
            ("reducer.rated_torque_nm".to_string(), -rated_torque),
            ("te.loaded_torque_nm".to_string(), loaded_torque),
        ];
        for dir in [1.0, -1.0] {
            let peak = model
                .spectrum
                .iter()
                .zip(&level_keys)
                .filter(|(l, _)| l.torque * dir > 0.0)
                .max_by(|a, b| (a.0.torque * dir).total_cmp(&(b.0.torque * dir)));
            if let Some((l, key)) = peak {
                uses.push((key.clone(), l.torque));
            }
        }
        if model.dynamics_enabled {
            uses.extend(dynamics::load_peaks(&model.dynamics.load));
        }
        physical::check_torques(&model, &nominal_profile, &uses)?;
        Ok(model)
    }

    /// The `[contact]` law for the stage `geometry` and the elastic constants
    /// `(E1, nu1, E2, nu2)` (Pa).
    fn contact_model(
        &self,
        geometry: &CycloidGeometry,
        (e1, nu1, e2, nu2): (f64, f64, f64, f64),
    ) -> Result<ContactModel> {
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
                    stiffness: check(
                        "contact.linear_stiffness_n_per_um",
                        k,
                        Range::positive(1e7, "N/um"),
                    )? * 1e6,
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
            Some(v) => {
                check(
                    "contact.max_curvature_radius_mm",
                    v,
                    Range::positive(1e5, "mm"),
                )? * 1e-3
            }
            None => geometry.pin_circle_radius,
        };
        let disc_depth = match self.contact.disc_depth.as_str() {
            "body" => Some(geometry.pin_circle_radius),
            "local_radius" => None,
            other => {
                return Err(Error::invalid(
                    "contact.disc_depth",
                    format!("\"{other}\""),
                    "must be \"body\" or \"local_radius\"",
                ))
            }
        };
        Ok(ContactModel {
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
            disc_depth,
        })
    }

    /// The load spectrum and, for every level, the key that sets its torque.
    fn load_spectrum(&self, rated: f64, speed: f64) -> Result<(Vec<LoadLevel>, Vec<String>)> {
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
                let t = check(
                    "load.torque_nm",
                    l.torque_nm.unwrap_or(rated),
                    Range::finite("N m"),
                )?;
                Ok((
                    vec![LoadLevel {
                        torque: t,
                        speed_rpm: speed,
                        fraction: 1.0,
                    }],
                    vec!["load.torque_nm".to_string()],
                ))
            }
            "sinusoidal" => {
                unused("torque_nm", l.torque_nm.is_some())?;
                unused("file", l.file.is_some())?;
                let amp = check(
                    "load.amplitude_nm",
                    l.amplitude_nm.unwrap_or(rated),
                    Range::non_negative(f64::MAX, "N m"),
                )?;
                let off = check(
                    "load.offset_nm",
                    l.offset_nm.unwrap_or(0.0),
                    Range::finite("N m"),
                )?;
                if let Some(p) = l.period_s {
                    check("load.period_s", p, Range::positive(1e9, "s"))?;
                }
                let n = whole("load.levels", l.levels.unwrap_or(24), 4, 10_000)?;
                let levels: Vec<LoadLevel> = (0..n)
                    .map(|k| {
                        let ph = std::f64::consts::TAU * (k as f64 + 0.5) / n as f64;
                        LoadLevel {
                            torque: off + amp * ph.sin(),
                            speed_rpm: speed,
                            fraction: 1.0 / n as f64,
                        }
                    })
                    .collect();
                let key = if amp > 0.0 {
                    "load.amplitude_nm"
                } else {
                    "load.offset_nm"
                };
                Ok((levels, vec![key.to_string(); n]))
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
                let (levels, rows) = read_duty_cycle_rows(&path)?;
                let keys = rows
                    .iter()
                    .map(|r| format!("{} row {r} column torque_nm", path.display()))
                    .collect();
                Ok((levels, keys))
            }
            other => Err(Error::invalid(
                "load.kind",
                format!("\"{other}\""),
                "must be \"constant\", \"sinusoidal\" or \"duty_cycle\"",
            )),
        }
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
                .unwrap_or_else(|| scaled_from_root(geometry, 40.5) * z2 as f64 / (z1 + z2) as f64),
            Range::positive(1e4, "mm"),
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
            Range::positive(1e3, "mm"),
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
                Range::positive(1e7, "N/um"),
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
    /// The crank bearings of `[reducer.bearings]`, and their damping ratio (applied by the
    /// dynamic analysis).
    fn validate(&self) -> Result<(Bearings, f64)> {
        let key = |k: &str| format!("reducer.bearings.{k}");
        let bearings = Bearings {
            carrier_stiffness: check(
                &key("crank_carrier_stiffness_n_per_um"),
                self.crank_carrier_stiffness_n_per_um,
                Range::positive(1e7, "N/um"),
            )? * 1e6,
            carrier_damping: 0.0,
            disc_stiffness: check(
                &key("crank_disc_stiffness_n_per_um"),
                self.crank_disc_stiffness_n_per_um,
                Range::positive(1e7, "N/um"),
            )? * 1e6,
            disc_damping: 0.0,
            clearance: check(
                &key("clearance_um"),
                self.clearance_um,
                Range::non_negative(1e3, "um"),
            )? * 1e-6,
        };
        let zeta = check(
            &key("damping_ratio"),
            self.damping_ratio,
            Range::non_negative(10.0, ""),
        )?;
        Ok((bearings, zeta))
    }
}

/// Longest duration of one duty-cycle row, s (about 31 700 years): the durations must add up
/// to a finite total for the time shares.
pub const MAX_ROW_DURATION_S: f64 = 1e12;

/// Reads a duty-cycle CSV with header `duration_s,torque_nm,speed_rpm`: one load level per
/// distinct `(torque, speed)` pair, with the share of the total duration of its rows (the
/// shares sum to 1 to round-off).
///
/// # Errors
/// [`Error::Config`] if unreadable; [`Error::Invalid`] naming the row for a bad value (a
/// duration must lie in `(0, MAX_ROW_DURATION_S]`).
pub fn read_duty_cycle(path: &Path) -> Result<Vec<LoadLevel>> {
    read_duty_cycle_rows(path).map(|(levels, _)| levels)
}

/// [`read_duty_cycle`], with the first row (1-based) of every level.
fn read_duty_cycle_rows(path: &Path) -> Result<(Vec<LoadLevel>, Vec<usize>)> {
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
        check(
            &format!("{origin} row {} column duration_s", i + 1),
            v[0],
            Range::positive(MAX_ROW_DURATION_S, "s"),
        )?;
        check(
            &format!("{origin} row {} column speed_rpm", i + 1),
            v[2],
            Range::positive(1e6, "rpm"),
        )?;
        rows.push((v[0], v[1], v[2]));
    }
    if rows.is_empty() {
        return Err(Error::Config {
            path: origin,
            message: "the duty cycle has no rows".into(),
        });
    }
    // Rows of the same torque and speed are one level; shares of the total time, summed with
    // the durations scaled by the longest so that no sum can overflow.
    let longest = rows.iter().map(|r| r.0).fold(0.0, f64::max);
    let mut levels: Vec<LoadLevel> = Vec::new();
    let mut first_rows: Vec<usize> = Vec::new();
    let mut index = std::collections::HashMap::new();
    for (i, &(d, t, n)) in rows.iter().enumerate() {
        let k = *index.entry((t.to_bits(), n.to_bits())).or_insert_with(|| {
            levels.push(LoadLevel {
                torque: t,
                speed_rpm: n,
                fraction: 0.0,
            });
            first_rows.push(i + 1);
            levels.len() - 1
        });
        levels[k].fraction += d / longest;
    }
    let total: f64 = levels.iter().map(|l| l.fraction).sum();
    for l in &mut levels {
        l.fraction /= total;
    }
    let sum: f64 = levels.iter().map(|l| l.fraction).sum();
    if !(sum - 1.0).abs().le(&1e-9) || levels.iter().any(|l| !l.fraction.is_finite()) {
        return Err(Error::invalid(
            format!("{origin} column duration_s"),
            format!("shares summing to {sum}"),
            "the durations must give time shares that sum to 1",
        ));
    }
    Ok((levels, first_rows))
}

/// The dotted keys a TOML text sets (`cycloid.modification.offset_mm`), or `None` if it does
/// not parse.
fn written_keys(text: &str) -> Option<std::collections::BTreeSet<String>> {
    fn walk(prefix: &str, t: &toml::Table, out: &mut std::collections::BTreeSet<String>) {
        for (k, v) in t {
            let key = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            if let toml::Value::Table(sub) = v {
                walk(&key, sub, out);
            } else {
                out.insert(key);
            }
        }
    }
    let table: toml::Table = text.parse().ok()?;
    let mut out = std::collections::BTreeSet::new();
    walk("", &table, &mut out);
    Some(out)
}

/// Tooth-root radius of the paper's disc, mm: `Rp - rrp - a` = 64 - 3 - 1.3.
pub const PAPER_ROOT_RADIUS_MM: f64 = 59.7;

/// A size outside `[cycloid]` that defaults from the stage, mm: the paper's value `paper_mm`
/// (RV-40E class: crank circle 40.5, crank bore radius 13, pillar holes 22 and centre hole 30
/// mm diameter) scaled by the disc's tooth-root radius `Rp - rrp - a` against the paper's
/// [`PAPER_ROOT_RADIUS_MM`] (geometric similarity with the paper's reducer). The paper's
/// geometry gets the paper's values.
pub fn scaled_from_root(geometry: &CycloidGeometry, paper_mm: f64) -> f64 {
    let root_mm = (geometry.pin_circle_radius - geometry.pin_radius - geometry.eccentricity) * 1e3;
    let scaled = paper_mm * root_mm / PAPER_ROOT_RADIUS_MM;
    // The paper's own stage: its values exactly, not their round-off.
    if (root_mm / PAPER_ROOT_RADIUS_MM - 1.0).abs() < 1e-12 {
        paper_mm
    } else {
        scaled
    }
}

/// What the default of a key not set in the user's file depends on.
fn default_source(key: &str) -> &'static str {
    match key {
        "fem.crank_bore_diameter_mm" => {
            "its default is 2 x dynamics.inertia.crank_bore_radius_mm; set it in [fem]"
        }
        "dynamics.inertia.crank_bore_radius_mm"
        | "fem.output_pin_hole_diameter_mm"
        | "fem.centre_hole_diameter_mm"
        | "reducer.gears.planet_pitch_radius_mm" => {
            "its default scales the paper's reducer with the disc's root radius Rp - rrp - a \
             of [cycloid]; set it to change it"
        }
        "fem.crank_circle_radius_mm" => {
            "its default is the crank circle, sun + planet pitch radius from [reducer.gears] \
             and the tooth numbers; set it in [fem]"
        }
        "fem.output_pin_circle_radius_mm" => {
            "its default is the crank circle radius; set it in [fem]"
        }
        "fem.output_pin_hole_phase_deg" => {
            "its default is 180 / fem.output_pin_holes; set it in [fem]"
        }
        "contact.band_force_n" => {
            "its default is Li's largest pin force at reducer.rated_torque_nm; set it in [contact]"
        }
        "te.loaded_torque_nm"
        | "load.torque_nm"
        | "load.amplitude_nm"
        | "dynamics.load.torque_nm"
        | "dynamics.load.amplitude_nm" => "its default is reducer.rated_torque_nm",
        _ => "a built-in default; set the key to change it",
    }
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
