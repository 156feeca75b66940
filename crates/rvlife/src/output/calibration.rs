//! The files of `rvlife calibrate --measured --out`: the fit, its residuals and its plot.

use std::path::Path;

use crate::calibration::Calibration;
use crate::error::{Error, Result};

/// Writes `calibration.json` (the [`Calibration`]), `residuals.csv` (`hours`, `quantity`,
/// `measured`, `model`, `residual`, in the quantity's unit) and the plot `calibration.svg`/`.png`
/// ([`super::plot::calibration`]) into the existing directory `dir`.
///
/// # Errors
/// [`Error::Io`] on write failures.
pub fn write_files(cal: &Calibration, dir: &Path) -> Result<()> {
    let p = dir.join("calibration.json");
    let text = serde_json::to_string_pretty(cal)
        .map_err(|e| Error::io(&p, std::io::Error::other(e.to_string())))?;
    std::fs::write(&p, text + "\n").map_err(|e| Error::io(&p, e))?;
    let p = dir.join("residuals.csv");
    let err = |e: csv::Error| Error::io(&p, std::io::Error::other(e.to_string()));
    let mut w = csv::Writer::from_path(&p).map_err(err)?;
    w.write_record(["hours", "quantity", "measured", "model", "residual"])
        .map_err(err)?;
    for r in &cal.residuals {
        w.write_record([
            format!("{}", r.hours),
            r.column.to_string(),
            format!("{:.6}", r.measured),
            format!("{:.6}", r.model),
            format!("{:.6}", r.residual),
        ])
        .map_err(err)?;
    }
    w.flush().map_err(|e| Error::io(&p, e))?;
    crate::output::plot::calibration(cal, dir)
}
