//! `[load]`: the output-torque spectrum the discs wear under (docs/model.md section 7): one
//! constant torque, a sine split into levels, or a duty cycle read from a CSV file.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::range::{check, whole, Range};
use crate::error::{Error, Result};
use crate::wear::LoadLevel;

/// Largest output torque a config or a command may name, N m: the top of
/// `reducer.rated_torque_nm`'s range (beyond any reducer; the physical check bounds a torque
/// by what the stage carries).
pub(crate) const MAX_TORQUE_NM: f64 = 1e7;

/// `[load]` checked: the load spectrum.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadParams {
    /// The load levels (their time shares sum to 1).
    pub levels: Vec<LoadLevel>,
    /// The key that sets the number of levels (`load.levels`, `load.file`; `load.kind` for a
    /// constant load), for the work budget's message.
    pub levels_key: &'static str,
    /// The key that sets each level's torque (`load.torque_nm`, `load.amplitude_nm`, a duty
    /// cycle's row), for the refusal of a torque the stage does not carry; one per level.
    pub level_keys: Vec<String>,
}

/// `[load]`: the output-torque spectrum the reducer works under.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadConfig {
    /// `"constant"`, `"sinusoidal"` or `"duty_cycle"`.
    pub kind: String,
    /// Constant output torque, N m (`constant`; default: the rated torque). Range: [-1e7, 1e7]
    /// N m (the largest rated torque; the physical check bounds it by the stage).
    #[serde(default)]
    pub torque_nm: Option<f64>,
    /// Amplitude, N m (`sinusoidal`; default: the rated torque). Range: [0, 1e7] N m.
    #[serde(default)]
    pub amplitude_nm: Option<f64>,
    /// Mean, N m (`sinusoidal`). Range: [-1e7, 1e7] N m.
    #[serde(default)]
    pub offset_nm: Option<f64>,
    /// Period, s (`sinusoidal`; the wear average does not depend on it). Range: (0, 1e9] s.
    #[serde(default)]
    pub period_s: Option<f64>,
    /// Torque levels the sine is split into for the wear average (`sinusoidal`, default 24).
    /// Range: whole number, 4 to 10 000.
    #[serde(default)]
    pub levels: Option<i64>,
    /// CSV file with columns `duration_s,torque_nm,speed_rpm` (`duty_cycle`), relative to the
    /// config file.
    #[serde(default)]
    pub file: Option<PathBuf>,
}

impl LoadConfig {
    /// The load spectrum for the rated torque `rated` (N m, the default torque) and the input
    /// speed `speed` (rpm), with every level's key; `path` resolves the duty cycle's file.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key or the duty cycle's row; [`Error::Config`] for an
    /// unreadable duty cycle.
    pub(super) fn validate(
        &self,
        rated: f64,
        speed: f64,
        path: impl Fn(&Path) -> PathBuf,
    ) -> Result<LoadParams> {
        let (levels, level_keys) = self.levels(rated, speed, path)?;
        let levels_key = match self.kind.as_str() {
            "duty_cycle" => "load.file",
            "sinusoidal" => "load.levels",
            _ => "load.kind",
        };
        Ok(LoadParams {
            levels,
            levels_key,
            level_keys,
        })
    }

    /// The load levels of [`LoadConfig::validate`] and the key of each.
    fn levels(
        &self,
        rated: f64,
        speed: f64,
        path: impl Fn(&Path) -> PathBuf,
    ) -> Result<(Vec<LoadLevel>, Vec<String>)> {
        let l = self;
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
                    Range::closed(-MAX_TORQUE_NM, MAX_TORQUE_NM, "N m"),
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
                    Range::non_negative(MAX_TORQUE_NM, "N m"),
                )?;
                let off = check(
                    "load.offset_nm",
                    l.offset_nm.unwrap_or(0.0),
                    Range::closed(-MAX_TORQUE_NM, MAX_TORQUE_NM, "N m"),
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
                let path = path(file);
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

/// Longest duration of one duty-cycle row, s (about 31 700 years): the durations must add up
/// to a finite total for the time shares.
pub(crate) const MAX_ROW_DURATION_S: f64 = 1e12;

/// Reads a duty-cycle CSV with header `duration_s,torque_nm,speed_rpm`: one load level per
/// distinct `(torque, speed)` pair, with the share of the total duration of its rows (the
/// shares sum to 1 to round-off), and the first row (1-based) of every level.
///
/// # Errors
/// [`Error::Config`] if unreadable; [`Error::Invalid`] naming the row for a bad value (a
/// duration must lie in `(0, MAX_ROW_DURATION_S]`).
fn read_duty_cycle_rows(path: &Path) -> Result<(Vec<LoadLevel>, Vec<usize>)> {
    let origin = path.display().to_string();
    let file = crate::input::open(path).map_err(|e| Error::Config {
        path: origin.clone(),
        message: format!("cannot read the duty cycle: {e}"),
    })?;
    let mut rdr = csv::Reader::from_reader(file);
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
