//! `[errors]`: the known part errors of one reducer (pins, pin circle, cranks), checked into
//! the [`PartErrors`] the static analysis places the parts with (docs/model.md section 10).

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::error::{Error, Result};
use crate::geometry::Vec2;
use crate::reducer::errors::PartErrors;

/// `[errors]`: known part errors of one reducer (measured, or a case to study), engineering
/// units. Per-pin lists hold `cycloid.pins` values, per-crank lists `reducer.planets` values;
/// an absent list is all zero. Range of every listed error: [-1000, 1000] um, [-600, 600]
/// arcmin (part errors beyond a millimetre or 10 degrees are not errors).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorsConfig {
    /// Radial position error of each pin centre (outward positive), um.
    #[serde(default)]
    pub pin_radial_um: Vec<f64>,
    /// Tangential position error of each pin centre (counter-clockwise positive), um.
    #[serde(default)]
    pub pin_tangential_um: Vec<f64>,
    /// Radius error of each pin (oversize positive), um.
    #[serde(default)]
    pub pin_radius_um: Vec<f64>,
    /// Radial run-out of the pin circle (total indicator reading), um. Range: [0, 1000] um.
    #[serde(default)]
    pub pin_circle_runout_um: f64,
    /// Direction of the pin circle's largest radius, degrees from pin 1. Range: [-360, 360]
    /// deg.
    #[serde(default)]
    pub pin_circle_runout_deg: f64,
    /// Eccentricity error of each crank (larger positive), um.
    #[serde(default)]
    pub crank_eccentricity_um: Vec<f64>,
    /// Phase error of each crank's eccentrics (ahead positive), arcmin.
    #[serde(default)]
    pub crank_phase_arcmin: Vec<f64>,
}

impl ErrorsConfig {
    /// Checks the lists' lengths and values (|error| up to 1 mm, 600 arcmin) and converts to
    /// SI.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key (`errors.pin_radial_um`), the value and the allowed
    /// range (a list of the wrong length names its length and the one needed).
    pub fn validate(&self, pins: usize, cranks: usize) -> Result<PartErrors> {
        let list = |key: &str, v: &[f64], n: usize, what: &str, unit, si: f64| {
            if !(v.is_empty() || v.len() == n) {
                return Err(Error::invalid(
                    format!("errors.{key}"),
                    format!("a list of {} values", v.len()),
                    format!("must hold one value per {what}: {n} values (or be left out)"),
                ));
            }
            let hi = if unit == "um" { 1000.0 } else { 600.0 };
            v.iter()
                .enumerate()
                .map(|(i, &x)| {
                    check(
                        &format!("errors.{key}[{i}]"),
                        x,
                        Range::closed(-hi, hi, unit),
                    )
                    .map(|x| x * si)
                })
                .collect::<Result<Vec<f64>>>()
        };
        let um = 1e-6;
        let arcmin = (1.0_f64 / 60.0).to_radians();
        let runout = check(
            "errors.pin_circle_runout_um",
            self.pin_circle_runout_um,
            Range::non_negative(1000.0, "um"),
        )? * um;
        let dir = check(
            "errors.pin_circle_runout_deg",
            self.pin_circle_runout_deg,
            Range::closed(-360.0, 360.0, "deg"),
        )?
        .to_radians();
        Ok(PartErrors {
            pin_radial: list("pin_radial_um", &self.pin_radial_um, pins, "pin", "um", um)?,
            pin_tangential: list(
                "pin_tangential_um",
                &self.pin_tangential_um,
                pins,
                "pin",
                "um",
                um,
            )?,
            pin_radius: list("pin_radius_um", &self.pin_radius_um, pins, "pin", "um", um)?,
            pin_circle_offset: Vec2::new(dir.cos(), dir.sin()) * (0.5 * runout),
            crank_eccentricity: list(
                "crank_eccentricity_um",
                &self.crank_eccentricity_um,
                cranks,
                "crank (reducer.planets)",
                "um",
                um,
            )?,
            crank_phase: list(
                "crank_phase_arcmin",
                &self.crank_phase_arcmin,
                cranks,
                "crank (reducer.planets)",
                "arcmin",
                arcmin,
            )?,
        })
    }
}
