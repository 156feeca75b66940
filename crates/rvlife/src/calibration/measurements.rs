//! A measurements file of `rvlife calibrate --measured`: which quantities it may hold, and
//! its reading and checks.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::quantities::{self, Quantity, StageSummary};

/// The option that names the measurements in messages.
const OPTION: &str = "--measured";

/// One measurable quantity: a quantity of the stage table ([`crate::quantities`]) that a
/// measurements file may hold as a column (its name, with the unit), and whether the running-in
/// play adds to it.
#[derive(Debug, Clone, Copy)]
pub struct Measurable {
    /// The quantity: its name is the column, its unit the column's.
    pub quantity: &'static Quantity,
    /// True if the running-in play `b0` adds to it (backlash, lost motion).
    pub running_in: bool,
}

impl Measurable {
    /// Column name in the measurements file.
    pub fn column(&self) -> &'static str {
        self.quantity.name
    }

    /// Unit of the column (as in its name).
    pub fn unit(&self) -> &'static str {
        self.quantity.unit
    }

    /// The stage's value.
    pub(super) fn value(&self, s: &StageSummary) -> f64 {
        s.value(self.quantity).number().unwrap_or(f64::NAN)
    }
}

/// The columns a measurements file may have besides `hours`: quantities of the stage table.
/// A quantity the study gains can be measured by adding it here.
pub(crate) const QUANTITIES: &[Measurable] = &[
    Measurable {
        quantity: &quantities::LOST_MOTION,
        running_in: true,
    },
    Measurable {
        quantity: &quantities::BACKLASH,
        running_in: true,
    },
    Measurable {
        quantity: &quantities::ANGULAR_TE,
        running_in: false,
    },
    Measurable {
        quantity: &quantities::MAX_WEAR,
        running_in: false,
    },
];

/// Largest working hours accepted in a measurements file, h (the range of `wear.stage_hours`).
pub(crate) const MAX_HOURS: f64 = 1e7;
/// Largest measured value accepted (arcmin or um).
pub(crate) const MAX_VALUE: f64 = 1e4;

/// Measured values of one quantity.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// Column name (an entry of `QUANTITIES`).
    pub column: &'static str,
    /// Index into `QUANTITIES`.
    #[serde(skip)]
    pub quantity: usize,
    /// Working hours of each value, h.
    pub hours: Vec<f64>,
    /// Measured values, in the column's unit.
    pub values: Vec<f64>,
}

/// A measurements file: one series per quantity column (an empty cell is a value not
/// measured at that row's hours).
#[derive(Debug, Clone, Serialize)]
pub struct Measurements {
    /// The file.
    pub path: PathBuf,
    /// The quantity columns in file order.
    pub series: Vec<Series>,
}

pub(super) fn bad(path: &Path, what: impl Into<String>) -> Error {
    Error::invalid(OPTION, path.display(), what)
}

impl Measurements {
    /// Reads and checks a CSV file with a header: a column `hours` (h, in `[0, 1e7]`) and one
    /// or more of the `QUANTITIES` columns (values finite, in `[0, 1e4]` of their unit; an
    /// empty cell is no value). `#` starts a comment line.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--measured` and the file: it cannot be read; no `hours`
    /// column; unknown or repeated columns (listing the allowed ones); a column of a quantity
    /// the study does not compute yet; a cell that is not a number or out of range (with its
    /// row and column); no quantity column or no value at all.
    pub fn read(path: &Path) -> Result<Measurements> {
        let text =
            crate::input::read_text(path).map_err(|e| bad(path, format!("cannot be read: {e}")))?;
        Self::parse(path, &text)
    }

    /// [`Measurements::read`] on the text of the file.
    ///
    /// # Errors
    /// As [`Measurements::read`].
    pub fn parse(path: &Path, text: &str) -> Result<Measurements> {
        let allowed: Vec<&str> = std::iter::once("hours")
            .chain(QUANTITIES.iter().map(Measurable::column))
            .collect();
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .flexible(false)
            .from_reader(text.as_bytes());
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| bad(path, format!("is not a CSV file with a header: {e}")))?
            .iter()
            .map(str::to_string)
            .collect();
        let unknown: Vec<&str> = header
            .iter()
            .map(String::as_str)
            .filter(|c| !allowed.contains(c))
            .collect();
        if !unknown.is_empty() {
            return Err(bad(
                path,
                format!(
                    "unknown column(s) {}; allowed: {}",
                    unknown.join(", "),
                    allowed.join(", ")
                ),
            ));
        }
        for (i, c) in header.iter().enumerate() {
            if header[..i].contains(c) {
                return Err(bad(path, format!("column {c} is given twice")));
            }
        }
        let Some(hours_col) = header.iter().position(|c| c == "hours") else {
            return Err(bad(
                path,
                format!(
                    "has no `hours` column (working hours, h); columns: {}",
                    header.join(", ")
                ),
            ));
        };
        let mut series = Vec::new();
        let mut cols = Vec::new();
        for (i, c) in header.iter().enumerate() {
            if i == hours_col {
                continue;
            }
            let q = QUANTITIES
                .iter()
                .position(|q| q.column() == c)
                .expect("checked against the allowed columns");
            series.push(Series {
                column: QUANTITIES[q].column(),
                quantity: q,
                hours: Vec::new(),
                values: Vec::new(),
            });
            cols.push(i);
        }
        if series.is_empty() {
            return Err(bad(
                path,
                format!(
                    "has no measured quantity; give one or more of the columns {}",
                    allowed[1..].join(", ")
                ),
            ));
        }
        // Each row's hours and values (bit patterns; an empty cell as NaN's), for copies.
        let mut seen: std::collections::HashMap<Vec<u64>, usize> = Default::default();
        for (r, rec) in rdr.records().enumerate() {
            let row = r + 2; // 1-based, after the header
            let rec = rec.map_err(|e| bad(path, format!("row {row}: {e}")))?;
            let cell = |i: usize| -> Result<Option<f64>> {
                let s = rec.get(i).unwrap_or("");
                if s.is_empty() {
                    return Ok(None);
                }
                s.parse::<f64>().map(Some).map_err(|_| {
                    bad(
                        path,
                        format!("row {row}, column {}: {s:?} is not a number", header[i]),
                    )
                })
            };
            let Some(h) = cell(hours_col)? else {
                return Err(bad(path, format!("row {row}: the hours cell is empty")));
            };
            if !(h.is_finite() && (0.0..=MAX_HOURS).contains(&h)) {
                return Err(bad(
                    path,
                    format!("row {row}, column hours = {h}: must be a finite number in [0, 1e7] h"),
                ));
            }
            let mut key = vec![h.to_bits()];
            for &i in &cols {
                key.push(cell(i)?.unwrap_or(f64::NAN).to_bits());
            }
            if let Some(first) = seen.insert(key, row) {
                return Err(bad(
                    path,
                    format!(
                        "rows {first} and {row} are the same measurement (the same hours and \
                         values): a copy adds no information but would narrow the fit's \
                         confidence interval as if it were a new measurement; remove the copy \
                         (repeated measurements at the same hours with different values are \
                         kept)"
                    ),
                ));
            }
            for (s, &i) in series.iter_mut().zip(&cols) {
                if let Some(v) = cell(i)? {
                    if !(v.is_finite() && (0.0..=MAX_VALUE).contains(&v)) {
                        return Err(bad(
                            path,
                            format!(
                                "row {row}, column {} = {v}: must be a finite number in \
                                 [0, 1e4] {}",
                                header[i],
                                QUANTITIES[s.quantity].unit()
                            ),
                        ));
                    }
                    s.hours.push(h);
                    s.values.push(v);
                }
            }
        }
        series.retain(|s| !s.values.is_empty());
        if series.is_empty() {
            return Err(bad(path, "has no measured values (no data rows)"));
        }
        Ok(Measurements {
            path: path.to_path_buf(),
            series,
        })
    }

    /// Number of measured values over all series.
    pub fn len(&self) -> usize {
        self.series.iter().map(|s| s.values.len()).sum()
    }

    /// True if there are no measured values (never after [`Measurements::read`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Largest measured working hours, h.
    pub fn max_hours(&self) -> f64 {
        self.series
            .iter()
            .flat_map(|s| s.hours.iter().copied())
            .fold(0.0, f64::max)
    }

    /// Checks that the measurements can determine the parameters: `N >= p + 1` values (`p` =
    /// 1 for `k`, plus 1 with `fit_running_in` for the play `b0`, plus 1 with `fit_factor` for
    /// the running-in factor `r`), some hours above 0, and with `fit_running_in` a backlash or
    /// lost-motion column.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--measured` (or `--fit-running-in`).
    pub fn check_for_fit(&self, fit_running_in: bool, fit_factor: bool) -> Result<()> {
        let p = 1 + usize::from(fit_running_in) + usize::from(fit_factor);
        if self.len() < p + 1 {
            let names = match (fit_running_in, fit_factor) {
                (false, false) => "k",
                (true, false) => "k and b0",
                (false, true) => "k and the running-in factor r",
                (true, true) => "k, the running-in factor r and b0",
            };
            return Err(bad(
                &self.path,
                format!(
                    "has {} measured value(s); fitting {} parameter(s) ({}) needs at least {} \
                     (parameters + 1, for the residual variance)",
                    self.len(),
                    p,
                    names,
                    p + 1
                ),
            ));
        }
        if self.max_hours() <= 0.0 {
            return Err(bad(
                &self.path,
                "all measurements are at 0 h, where there is no wear: the Archard coefficient \
                 cannot be found; give measurements after some working hours",
            ));
        }
        if fit_running_in
            && !self
                .series
                .iter()
                .any(|s| QUANTITIES[s.quantity].running_in)
        {
            return Err(Error::invalid(
                "--fit-running-in",
                "set",
                format!(
                    "the running-in play adds to backlash and lost motion, and {} has neither \
                     column (backlash_arcmin, lost_motion_arcmin)",
                    self.path.display()
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three copies of one point are one point: a row repeated (the same hours and values) is
    /// refused naming both rows, while repeated measurements at the same hours with different
    /// values, or the same values at other hours, are kept.
    #[test]
    fn a_copied_row_is_refused_and_repeated_measurements_are_kept() {
        let p = Path::new("m.csv");
        let e = Measurements::parse(
            p,
            "hours,lost_motion_arcmin\n1000,0.9\n1000,0.9\n1000,0.9\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("m.csv") && e.contains("rows 2 and 3"), "{e}");
        let e = Measurements::parse(
            p,
            "hours,backlash_arcmin,lost_motion_arcmin\n500,0.5,\n1000,,0.9\n1000.0,,0.90\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("rows 3 and 4"), "{e}");
        let m = Measurements::parse(
            p,
            "hours,lost_motion_arcmin\n1000,0.9\n1000,0.91\n2000,0.9\n",
        )
        .unwrap();
        assert_eq!(m.len(), 3);
        let m = Measurements::parse(
            p,
            "hours,backlash_arcmin,lost_motion_arcmin\n1000,0.5,\n1000,,0.5\n",
        )
        .unwrap();
        assert_eq!(m.len(), 2);
    }
}
