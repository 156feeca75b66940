//! `[dynamics.load]`: the output load of the multibody simulation (none, constant, sinusoidal,
//! or a table read from a CSV file; docs/model.md section 8).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::dynamics::{non_negative, positive};
use crate::dynamics::params::LoadProfile;
use crate::error::{Error, Result};

/// `[dynamics.load]`: output load `kind = "none" | "constant" | "sinusoidal" | "table"`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynLoadConfig {
    /// Load kind.
    #[serde(default = "d_load_kind")]
    pub kind: String,
    /// Constant torque, N m (`constant`; default: rated torque).
    #[serde(default)]
    pub torque_nm: Option<f64>,
    /// Ramp time of the constant torque (`STEP` from 0), s.
    #[serde(default)]
    pub ramp_s: f64,
    /// Amplitude, N m (`sinusoidal`; default: rated torque).
    #[serde(default)]
    pub amplitude_nm: Option<f64>,
    /// Period, s (`sinusoidal`).
    #[serde(default = "d_period")]
    pub period_s: f64,
    /// Mean, N m (`sinusoidal`).
    #[serde(default)]
    pub offset_nm: f64,
    /// Phase, degrees (`sinusoidal`).
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
pub fn read_load_table(path: &Path, end_time: f64) -> Result<LoadProfile> {
    let origin = path.display().to_string();
    let cfg_err = |message: String| Error::Config {
        path: origin.clone(),
        message,
    };
    let mut rdr = csv::ReaderBuilder::new()
        .flexible(true)
        .from_path(path)
        .map_err(|e| cfg_err(format!("cannot read the load table: {e}")))?;
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
pub(super) fn load_peaks(load: &LoadProfile) -> Vec<(String, f64)> {
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
