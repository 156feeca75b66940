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
//!
//! Without the `files` feature (the WebAssembly build) only the in-memory outputs are built:
//! [`export::profile_bytes`] and [`study::data_files`], the results directory's data files as
//! bytes; nothing is written to disk and no plot is drawn.

#[cfg(feature = "files")]
pub mod calibration;
pub mod export;
#[cfg(feature = "files")]
pub mod html;
#[cfg(feature = "files")]
mod mc_report;
#[cfg(feature = "files")]
pub mod montecarlo;
#[cfg(feature = "files")]
pub mod plot;
#[cfg(feature = "files")]
pub mod staging;
pub mod study;
#[cfg(feature = "files")]
pub mod sweep;

#[cfg(feature = "files")]
use std::path::Path;

use crate::error::{Error, Result};

#[cfg(feature = "files")]
pub use staging::{check_output_file, interrupted, remove_pending, write_file_atomically, Staging};
#[cfg(feature = "files")]
pub use study::{write_dynamics_files, write_files};

#[cfg(feature = "files")]
pub(crate) fn write_rows(path: &Path, header: &[String], rows: &[Vec<String>]) -> Result<()> {
    std::fs::write(path, rows_bytes(header, rows)?).map_err(|e| Error::io(path, e))
}

/// A CSV table's bytes: `header`, then `rows` (RFC 4180 quoting by the `csv` crate).
///
/// # Errors
/// [`Error::Numerical`] if a row's length differs from the header's.
pub(crate) fn rows_bytes<S: AsRef<[u8]>>(
    header: &[S],
    rows: &[impl AsRef<[S]>],
) -> Result<Vec<u8>> {
    let err = |e: csv::Error| Error::numerical("CSV table", e.to_string());
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header).map_err(err)?;
    for r in rows {
        w.write_record(r.as_ref()).map_err(err)?;
    }
    w.into_inner()
        .map_err(|e| Error::numerical("CSV table", e.to_string()))
}

/// `value` as pretty JSON with a final newline.
pub(crate) fn json_bytes(value: &impl serde::Serialize) -> Result<Vec<u8>> {
    let text =
        serde_json::to_string_pretty(value).map_err(|e| Error::numerical("JSON", e.to_string()))?;
    Ok((text + "\n").into_bytes())
}

/// Writes `value` as pretty JSON with a final newline.
#[cfg(feature = "files")]
pub(crate) fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    std::fs::write(path, json_bytes(value)?).map_err(|e| Error::io(path, e))
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
