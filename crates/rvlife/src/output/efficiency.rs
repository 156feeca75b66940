//! The efficiency map as CSV (`rvlife efficiency --out`, the Python package's `efficiency`):
//! one row per operating point, the columns of [`COLUMNS`].

use crate::efficiency::OperatingPoint;
use crate::error::Result;

/// One column of the map: its name (with its unit) and its value at an operating point.
pub type Column = (&'static str, fn(&OperatingPoint) -> f64);

/// The map's columns.
pub const COLUMNS: [Column; 14] = [
    ("torque_nm", |p| p.torque_nm),
    ("output_speed_rpm", |p| p.output_speed_rpm),
    ("temperature_c", |p| p.temperature_c),
    ("efficiency", |p| p.efficiency),
    ("output_power_w", |p| p.output_power_w),
    ("input_power_w", |p| p.input_power_w),
    ("loss_disc_pins_w", |p| p.loss_disc_pins_w),
    ("loss_pin_grooves_w", |p| p.loss_pin_grooves_w),
    ("loss_crank_bearings_w", |p| p.loss_crank_bearings_w),
    ("loss_gear_meshes_w", |p| p.loss_gear_meshes_w),
    ("lambda_min", |p| p.lambda_min),
    ("lambda_mean", |p| p.lambda_mean),
    ("film_min_um", |p| p.film_min_um),
    ("pin_friction_coefficient", |p| p.pin_friction_coefficient),
];

/// The map's CSV bytes: the header of [`COLUMNS`], then a row per point (6 decimals).
///
/// # Errors
/// As [`super::rows_bytes`].
pub fn csv_bytes(points: &[OperatingPoint]) -> Result<Vec<u8>> {
    let header: Vec<&str> = COLUMNS.iter().map(|c| c.0).collect();
    let rows: Vec<Vec<String>> = points
        .iter()
        .map(|p| COLUMNS.iter().map(|c| format!("{:.6}", (c.1)(p))).collect())
        .collect();
    let header: Vec<String> = header.into_iter().map(String::from).collect();
    super::rows_bytes(&header, &rows)
}

/// Writes the map's CSV ([`csv_bytes`]) to `path`.
///
/// # Errors
/// [`crate::Error::Io`] on write failures.
#[cfg(feature = "files")]
pub fn write_csv(path: &std::path::Path, points: &[OperatingPoint]) -> Result<()> {
    std::fs::write(path, csv_bytes(points)?).map_err(|e| crate::Error::io(path, e))
}
