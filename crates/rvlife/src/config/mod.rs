//! The study configuration: TOML in engineering units, checked and converted to SI.
//!
//! One file per section, each holding the section's raw struct (what the user writes, unknown
//! keys rejected with their path) beside the `validate` that checks it and converts it to the
//! parameters of the analysis that reads it; every range goes through the one helper of
//! `range` and is written in the field's doc comment. The validated [`Model`] is composed of
//! those parameter structs ([`model`]); the rules that span sections (sizes defaulted from the
//! stage) come after the sections, in [`cross_section`]. The validators check ranges and
//! convert; the physical checks of the unworn stage run after them, in the gate every command
//! passes (`crate::study::admission`, docs/model.md section 15.2).
//!
//! | section | file | checked into |
//! |---|---|---|
//! | `[reducer]`, `[reducer.gears]`, `[reducer.bearings]`, `[reducer.output_pins]`, `[reducer.structure]` | `reducer.rs`, `structure.rs` | [`crate::reducer::Reducer`] (with the next three), [`Rating`] |
//! | `[cycloid]`, `[cycloid.modification]` | `cycloid.rs` | [`crate::geometry::CycloidParams`] |
//! | `[materials]` | `materials.rs` | [`MaterialParams`] |
//! | `[contact]` | `contact.rs` | [`crate::contact::ContactModel`], [`crate::reducer::Support`] |
//! | `[errors]` | `errors.rs` | [`crate::reducer::errors::PartErrors`] |
//! | `[load]` | `load.rs` | [`crate::wear::LoadLevel`]s |
//! | `[wear]` | `wear.rs` | [`crate::wear::WearParams`] |
//! | `[te]` | `te.rs` | [`crate::te::TeParams`] |
//! | `[dynamics]` | `dynamics.rs` | [`crate::dynamics::DynamicsParams`] |
//! | `[fem]` | `fem.rs` | [`crate::fem::FemParams`] |
//! | `[tolerances]` | `tolerances.rs` | [`Tolerances`] |
//! | `[life]` | `life.rs` | [`LifeThresholds`] |
//! | `[lubrication]` | `lubrication.rs` | [`crate::tribology::Lubrication`] |
//!
//! [`Config::example`] is the paper's RV-40E class reducer (paper Tables 1-2, docs/model.md
//! section 16), printed by `rvlife example`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

mod contact;
pub mod cross_section;
mod cycloid;
mod dynamics;
pub mod edit;
mod errors;
mod fem;
mod life;
mod load;
mod lubrication;
mod materials;
pub mod model;
mod presets;
pub(crate) mod range;
mod reducer;
pub mod schema;
mod structure;
mod te;
mod tolerances;
mod wear;

pub use contact::ContactConfig;
pub use cycloid::{CycloidConfig, ModificationConfig};
pub(crate) use dynamics::load_peaks;
pub use dynamics::{DriveConfig, DynamicsConfig, FlexibleConfig, ImpactConfig, InertiaConfig};
pub use errors::ErrorsConfig;
pub use fem::FemConfig;
pub use life::{LifeConfig, LifeThresholds};
pub(crate) use load::MAX_TORQUE_NM;
pub use load::{LoadConfig, LoadParams};
pub use lubrication::LubricationConfig;
pub use materials::{MaterialConfig, MaterialParams, MaterialsConfig};
pub(crate) use model::bearing_rates;
pub use model::{Model, Section};
pub use presets::{preset_text, Preset, PRESETS};
pub use reducer::{BearingsConfig, GearsConfig, OutputPinsConfig, Rating, ReducerConfig};
pub use structure::{StructureConfig, StructureParams};
pub use te::TeConfig;
pub use tolerances::{
    SelectiveAssembly, SelectiveAssemblyConfig, Tolerance, ToleranceConfig, Tolerances,
    TolerancesConfig,
};
pub use wear::WearConfig;

use crate::error::{Error, Result};

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
    /// Oil, temperature, surfaces and friction: the losses and efficiency, and the wear's
    /// dependence on the oil film.
    #[serde(default)]
    pub lubrication: LubricationConfig,
    /// Directory of the config file (for relative paths); not a key.
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
    /// The dotted keys the file sets (`cycloid.pins`), to tell a key the user wrote from a
    /// default in messages; `None` for the built-in example (every key written). Not a key.
    #[serde(skip)]
    pub written: Option<BTreeSet<String>>,
    /// Work budget, minutes of estimated computing on the reference machine (2 cores): a
    /// config whose estimate exceeds it is refused before the work starts, naming the key that
    /// drives it ([`crate::budget`]). Not a key: the command line's `--work-budget-min`.
    #[serde(skip, default = "crate::budget::default_minutes")]
    pub work_budget_minutes: f64,
}

impl Config {
    /// Parses TOML text; `origin` names the source in errors (a path or `<built-in>`).
    ///
    /// # Errors
    /// [`Error::Config`] for syntax errors, wrong types and unknown keys (with the key path).
    pub(crate) fn from_toml_str(text: &str, origin: &str) -> Result<Config> {
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
        Config::from_toml_in(
            &Config::read_text(path)?,
            &path.display().to_string(),
            path.parent(),
        )
    }

    /// The text of the config file at `path` (a regular file within the size cap,
    /// [`crate::input::read_text`]), for callers that keep it beside the config (a Monte Carlo
    /// run's `config.toml`, a design sweep's base).
    ///
    /// # Errors
    /// [`Error::Config`] naming the path if the file cannot be read.
    pub fn read_text(path: &Path) -> Result<String> {
        crate::input::read_text(path).map_err(|message| Error::Config {
            path: path.display().to_string(),
            message,
        })
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

    /// The built-in example: the paper's RV-40E-class reducer with the play and modifications
    /// of its class and the catalogue's accuracy spec (`rvlife example`).
    pub fn example() -> Config {
        Config::from_toml_str(EXAMPLE_TOML, "<built-in>").expect("the built-in example parses")
    }

    /// A path of the config (a measured profile, a duty cycle, a load table) as read: relative
    /// to the config file's folder.
    pub(crate) fn path(&self, p: &Path) -> PathBuf {
        match &self.base_dir {
            Some(dir) if p.is_relative() => dir.join(p),
            _ => p.to_path_buf(),
        }
    }

    /// Marks the key of an [`Error::Invalid`] that the user's file does not set, with what its
    /// default depends on ([`cross_section::default_source`]).
    pub(crate) fn explain_default(&self, e: Error) -> Error {
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
                let source = cross_section::default_source(&field);
                Error::Invalid {
                    field: format!("{field} (not in your file: {source})"),
                    value,
                    allowed,
                }
            }
            other => other,
        }
    }
}

/// The dotted keys a TOML text sets (`cycloid.modification.offset_mm`), or `None` if it does
/// not parse.
fn written_keys(text: &str) -> Option<BTreeSet<String>> {
    fn walk(prefix: &str, t: &toml::Table, out: &mut BTreeSet<String>) {
        for (k, v) in t {
            let key = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            // A table is written too (`pin_radial_um = { }` is the user's, empty or not).
            if let toml::Value::Table(sub) = v {
                walk(&key, sub, out);
            }
            out.insert(key);
        }
    }
    let table: toml::Table = text.parse().ok()?;
    let mut out = BTreeSet::new();
    walk("", &table, &mut out);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn example_parses_and_validates() {
        let m = Config::example().validate().unwrap();
        assert_eq!(m.cycloid.geometry.pins, 40);
        assert!((m.reducer.ratio - 81.0).abs() < 1e-12);
        assert_eq!(m.wear.stage_hours.len(), 7);
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
