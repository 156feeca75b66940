//! The one range check of configuration values: every key of every section is checked through
//! [`check`] (real numbers) or [`whole`] (counts), so that every message has the same form:
//! the key as the user wrote it, the value, and the allowed range with its unit.

use std::cell::RefCell;

use crate::error::{Error, Result};

/// A key's allowed values as the validator checked them, recorded by [`recording`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Checked {
    /// Dotted key as the config writes it (`cycloid.eccentricity_mm`).
    pub key: String,
    /// The allowed range in the words of the validator's message (`must be a finite number in
    /// (0, 100] mm`).
    pub allowed: String,
    /// The unit of the range (`mm`; empty for counts and pure numbers).
    pub unit: String,
}

thread_local! {
    /// The checks of the validation that [`recording`] runs on this thread.
    static RECORD: RefCell<Option<Vec<Checked>>> = const { RefCell::new(None) };
}

/// Runs `f` (a config validation), returning its result and every key it checked with its
/// allowed range, in order (a key checked twice once). Only this thread's checks are recorded.
pub(crate) fn recording<T>(f: impl FnOnce() -> T) -> (T, Vec<Checked>) {
    RECORD.with(|r| *r.borrow_mut() = Some(Vec::new()));
    let out = f();
    let checked = RECORD.with(|r| r.borrow_mut().take()).unwrap_or_default();
    (out, checked)
}

fn record(key: &str, allowed: impl FnOnce() -> String, unit: &str) {
    RECORD.with(|r| {
        if let Some(list) = r.borrow_mut().as_mut() {
            if !list.iter().any(|c| c.key == key) {
                list.push(Checked {
                    key: key.to_string(),
                    allowed: allowed(),
                    unit: unit.to_string(),
                });
            }
        }
    });
}

/// An allowed range of a real value, with the unit named in the message.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Range {
    lo: f64,
    lo_open: bool,
    hi: f64,
    unit: &'static str,
}

impl Range {
    /// `[lo, hi]`.
    pub(crate) const fn closed(lo: f64, hi: f64, unit: &'static str) -> Self {
        Range {
            lo,
            lo_open: false,
            hi,
            unit,
        }
    }

    /// `(0, hi]`.
    pub(crate) const fn positive(hi: f64, unit: &'static str) -> Self {
        Range {
            lo: 0.0,
            lo_open: true,
            hi,
            unit,
        }
    }

    /// `[0, hi]`.
    pub(crate) const fn non_negative(hi: f64, unit: &'static str) -> Self {
        Range::closed(0.0, hi, unit)
    }

    /// Any finite number.
    pub(crate) const fn finite(unit: &'static str) -> Self {
        Range::closed(f64::MIN, f64::MAX, unit)
    }

    fn contains(&self, v: f64) -> bool {
        v.is_finite()
            && v <= self.hi
            && if self.lo_open {
                v > self.lo
            } else {
                v >= self.lo
            }
    }

    fn words(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        if self.lo == f64::MIN && self.hi == f64::MAX {
            return format!("must be a finite number{unit}");
        }
        let open = if self.lo_open { "(" } else { "[" };
        format!(
            "must be a finite number in {open}{}, {}]{unit}",
            short(bound(self.lo)),
            short(bound(self.hi))
        )
    }
}

/// A range's bound rounded to 12 significant digits, so that one computed from others reads
/// as written (`0.8 - 0.1` is `0.7`, not `0.7000000000000001`); the check itself uses the
/// exact bound.
fn bound(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// A bound as a reader expects it: `0.5`, `1e7`.
fn short(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-3) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// `v` if it lies in `range`; otherwise [`Error::Invalid`] naming `key`, `v` and the range.
pub(crate) fn check(key: &str, v: f64, range: Range) -> Result<f64> {
    record(key, || range.words(), range.unit);
    if range.contains(v) {
        Ok(v)
    } else {
        Err(Error::invalid(key, short(v), range.words()))
    }
}

/// `v` as a count if it is a whole number in `[lo, hi]`; otherwise [`Error::Invalid`].
pub(crate) fn whole(key: &str, v: i64, lo: i64, hi: i64) -> Result<usize> {
    record(
        key,
        || format!("must be a whole number from {lo} to {hi}"),
        "",
    );
    if (lo..=hi).contains(&v) {
        Ok(v as usize)
    } else {
        Err(Error::invalid(
            key,
            v,
            format!("must be a whole number from {lo} to {hi}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_key_value_and_range() {
        let e = check("wear.x_um", -1.0, Range::positive(1e3, "um")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid wear.x_um = -1: must be a finite number in (0, 1000] um"
        );
        let e = check("a", f64::NAN, Range::finite("")).unwrap_err();
        assert_eq!(e.to_string(), "invalid a = NaN: must be a finite number");
        let e = check("b", 1e300, Range::closed(0.0, 1e7, "h")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid b = 1e300: must be a finite number in [0, 1e7] h"
        );
        // A computed bound reads as written (0.8 - 0.1 and 3 x 19.9 in binary are not).
        let e = check("d", 1.0, Range::positive(0.8 - 0.1, "s")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid d = 1: must be a finite number in (0, 0.7] s"
        );
        let e = check("e", 0.0, Range::closed(1.0, 3.0 * 19.9, "mm")).unwrap_err();
        assert!(e.to_string().ends_with("[1, 59.7] mm"), "{e}");
        assert_eq!(whole("c", 5, 1, 10).unwrap(), 5);
        assert!(whole("c", 11, 1, 10).is_err());
    }
}
