//! The outputs: every results directory and file rvlife writes, all-or-nothing
//! ([`staging`]: written into a temporary directory beside the target, renamed onto it only
//! when complete), and the plots and the HTML report.
//!
//! - [`study`]: the results directory of `rvlife run` and of `rvlife dynamics --out`;
//! - [`montecarlo`]: Monte Carlo's records, percentiles and summary, shards and their merge
//!   (the merge itself, without files, in [`mc_shards`]);
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
pub mod candidates;
pub mod efficiency;
pub mod export;
#[cfg(feature = "files")]
pub mod html;
#[cfg(feature = "files")]
mod mc_report;
pub mod mc_shards;
pub mod mc_verdict;
#[cfg(feature = "files")]
pub mod montecarlo;
#[cfg(feature = "files")]
pub mod optimize;
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
pub use staging::{
    check_output_dir, check_output_file, interrupted, remove_pending, stop_on_signal,
    stop_requested, take_signal, write_file_atomically, Staging,
};
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

/// A number as the report prints it: up to 6 significant digits, no trailing noise.
pub(crate) fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{v:.4e}");
    }
    let decimals = (5 - mag).clamp(0, 9) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

pub(crate) fn f(v: f64) -> String {
    fixed(v, 6)
}

/// `v` with `decimals` digits after the point: the text of `format!("{v:.decimals$}")`, byte
/// for byte, without its exact decimal expansion where none is needed. `|v| 10^decimals` is
/// rounded to an integer in floating point (its error at most 1.2e-4 below 1e12) wherever its
/// fraction lies more than 1e-3 from one half, so that the exact value rounds the same way;
/// elsewhere (and for non-finite values, more than 9 decimals or 1e12 and above) the
/// standard formatting.
pub(crate) fn fixed(v: f64, decimals: usize) -> String {
    let mut s = String::with_capacity(24);
    push_fixed(&mut s, v, decimals);
    s
}

/// A CSV table of numbers as [`rows_bytes`] writes it: the `header`, then `rows` rows of `cols`
/// columns, the value of row `i`, column `j` and its decimals `value(i, j)`, each as
/// [`fixed`] gives it (the fields of numbers and of plain names need no quotes).
pub(crate) fn numbers_bytes(
    header: &[impl AsRef<str>],
    rows: usize,
    cols: usize,
    value: impl Fn(usize, usize) -> (f64, usize),
) -> Vec<u8> {
    let mut s = header
        .iter()
        .map(|h| h.as_ref())
        .collect::<Vec<_>>()
        .join(",");
    s.reserve(rows * cols * 14);
    s.push('\n');
    for i in 0..rows {
        for j in 0..cols {
            if j > 0 {
                s.push(',');
            }
            let (v, decimals) = value(i, j);
            push_fixed(&mut s, v, decimals);
        }
        s.push('\n');
    }
    s.into_bytes()
}

/// Appends [`fixed`]`(v, decimals)` to `s`.
pub(crate) fn push_fixed(s: &mut String, v: f64, decimals: usize) {
    use std::fmt::Write;
    const POW10: [u64; 10] = [
        1,
        10,
        100,
        1_000,
        10_000,
        100_000,
        1_000_000,
        10_000_000,
        100_000_000,
        1_000_000_000,
    ];
    if let Some(&p) = POW10.get(decimals) {
        let y = v.abs() * p as f64;
        if y < 1e12 && (y - y.floor() - 0.5).abs() > 1e-3 {
            let n = y.round() as u64;
            if v.is_sign_negative() {
                s.push('-');
            }
            let mut digits = itoa::Buffer::new();
            s.push_str(digits.format(n / p));
            if decimals > 0 {
                s.push('.');
                let fraction = digits.format(n % p);
                s.extend(std::iter::repeat_n('0', decimals - fraction.len()));
                s.push_str(fraction);
            }
            return;
        }
    }
    let _ = write!(s, "{v:.decimals$}");
}

pub(crate) fn hours_tag(h: f64) -> String {
    if h.fract() == 0.0 {
        format!("{h:.0}h")
    } else {
        format!("{h}h").replace('.', "p")
    }
}

#[cfg(test)]
mod tests {
    use super::fixed;
    use rand::{Rng, SeedableRng};

    /// [`fixed`] against the standard formatting, byte for byte: 400 000 values over every
    /// scale from 1e-14 to 1e13 of both signs, the halfway points `(k + 1/2) 10^-d` and their
    /// neighbours one ulp away (where the fast path must give way), zeros and non-finite values.
    #[test]
    fn fixed_is_the_standard_formatting() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut values = vec![
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            f64::NAN,
            f64::INFINITY,
            -f64::INFINITY,
        ];
        for _ in 0..200_000 {
            let v: f64 = 10f64.powf(rng.random_range(-14.0..13.0)) * rng.random_range(1.0..10.0);
            values.push(if rng.random_bool(0.5) { -v } else { v });
        }
        for d in 0..10usize {
            for _ in 0..20_000 {
                let k: u64 = rng.random_range(0..10_000_000);
                let half = (k as f64 + 0.5) / 10f64.powi(d as i32);
                values.extend([half, f64::from_bits(half.to_bits() + 1), -half]);
                if half > 0.0 {
                    values.push(f64::from_bits(half.to_bits() - 1));
                }
            }
        }
        for &v in &values {
            for d in 0..12usize {
                assert_eq!(fixed(v, d), format!("{v:.d$}"), "{v:e} to {d} decimals");
            }
        }
    }
}
