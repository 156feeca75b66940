//! The outputs: every results directory and file rvlife writes, all-or-nothing
//! ([`staging`]: written into a temporary directory beside the target, renamed onto it only
//! when complete), and the plots and the HTML report.
//!
//! - [`study`]: the results directory of `rvlife run` and of `rvlife dynamics --out`;
//! - [`montecarlo`]: Monte Carlo's records, percentiles and summary, shards and their merge;
//! - [`calibration`]: the fit of `rvlife calibrate --measured`;
//! - [`export`]: a profile as CSV, DXF or SVG;
//! - [`plot`] and [`html`]: the plots (SVG and PNG) and `report.html`.
//!
//! Every stage quantity comes from the table of [`crate::quantities`].

pub mod calibration;
pub mod export;
pub mod html;
mod mc_report;
pub mod montecarlo;
pub mod plot;
pub mod staging;
pub mod study;
pub mod sweep;

use std::path::Path;

use crate::error::{Error, Result};

pub use staging::{check_output_file, interrupted, remove_pending, write_file_atomically, Staging};
pub use study::{write_dynamics_files, write_files};

pub(crate) fn csv_err(path: &Path) -> impl Fn(csv::Error) -> Error + '_ {
    move |e| Error::io(path, std::io::Error::other(e.to_string()))
}

pub(crate) fn write_rows(path: &Path, header: &[String], rows: &[Vec<String>]) -> Result<()> {
    let mut w = csv::Writer::from_path(path).map_err(csv_err(path))?;
    w.write_record(header).map_err(csv_err(path))?;
    for r in rows {
        w.write_record(r).map_err(csv_err(path))?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Writes `value` as pretty JSON with a final newline.
pub(crate) fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| Error::io(path, std::io::Error::other(e.to_string())))?;
    std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))
}

pub(crate) fn f(v: f64) -> String {
    format!("{v:.6}")
}

pub(crate) fn hours_tag(h: f64) -> String {
    if h.fract() == 0.0 {
        format!("{h:.0}h")
    } else {
        format!("{h}h").replace('.', "p")
    }
}
