//! `[materials]`: the elastic constants of disc and pins (paper Table 2) and the static
//! capacity of their contact (docs/model.md sections 3 and 15).

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::contact::Materials;
use crate::error::Result;

/// `[materials]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialsConfig {
    /// Cycloid disc.
    pub disc: MaterialConfig,
    /// Pins.
    pub pin: MaterialConfig,
    /// Largest Hertz pressure the disc-pin contact may carry, MPa (default 4000: the static
    /// capacity of hardened bearing steel in line contact, ISO 76:2006 section 6.2.1, where the
    /// permanent set reaches 1e-4 of the roller diameter). Every torque the study applies is
    /// checked against it on the unworn disc before any analysis. Range: [10, 1e5] MPa.
    #[serde(default = "default_max_pressure")]
    pub max_contact_pressure_mpa: f64,
}

fn default_max_pressure() -> f64 {
    4000.0
}

/// One material (`[materials.disc]`, `[materials.pin]`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialConfig {
    /// Young's modulus, GPa. Range: [0.1, 1e7] GPa (soft polymers up; beyond diamond's 1200 GPa
    /// a rigid limit, as the tests of the rigid limit use).
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio. Range: [0, 0.499].
    pub poisson_ratio: f64,
}

/// `[materials]` checked, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialParams {
    /// Elastic constants of disc and pins, Pa.
    pub elastic: Materials,
    /// Largest Hertz pressure the contact may carry, Pa (its static capacity).
    pub max_contact_pressure: f64,
}

impl MaterialConfig {
    /// Young's modulus (Pa) and Poisson's ratio of `[materials.<name>]`.
    fn validate(&self, name: &str) -> Result<(f64, f64)> {
        Ok((
            check(
                &format!("materials.{name}.youngs_modulus_gpa"),
                self.youngs_modulus_gpa,
                Range::closed(0.1, 1e7, "GPa"),
            )? * 1e9,
            check(
                &format!("materials.{name}.poisson_ratio"),
                self.poisson_ratio,
                Range::closed(0.0, 0.499, ""),
            )?,
        ))
    }
}

impl MaterialsConfig {
    /// The elastic constants and the largest contact pressure, SI.
    ///
    /// # Errors
    /// [`crate::Error::Invalid`] naming the key, the value and its range.
    pub fn validate(&self) -> Result<MaterialParams> {
        let (e1, nu1) = self.disc.validate("disc")?;
        let (e2, nu2) = self.pin.validate("pin")?;
        Ok(MaterialParams {
            elastic: Materials {
                disc_youngs_modulus: e1,
                disc_poisson_ratio: nu1,
                pin_youngs_modulus: e2,
                pin_poisson_ratio: nu2,
            },
            max_contact_pressure: check(
                "materials.max_contact_pressure_mpa",
                self.max_contact_pressure_mpa,
                Range::closed(10.0, 1e5, "MPa"),
            )? * 1e6,
        })
    }
}
