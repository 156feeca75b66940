//! `[te]`: how the transmission error and the catalogue quantities are sampled
//! (docs/model.md section 6).

use serde::{Deserialize, Serialize};

use super::range::{check, whole, Range};
use crate::error::Result;
use crate::te::TeParams;

/// `[te]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TeConfig {
    /// Crank angles per mesh cycle for the TE curves. Range: whole number, 2 to 10 000.
    #[serde(default = "default_te_samples")]
    pub samples_per_mesh_cycle: i64,
    /// Torque of the loaded TE, N m (default: rated torque). Range: any finite number (the
    /// physical check bounds it).
    #[serde(default)]
    pub loaded_torque_nm: Option<f64>,
    /// Measuring torque of lost motion, as a fraction of the rated torque (Nabtesco: lost
    /// motion is the twist between the hysteresis curve's midpoints within +-3 % of rated
    /// torque). Range: [1e-4, 0.5].
    #[serde(default = "default_measuring")]
    pub measuring_torque_fraction: f64,
}

fn default_measuring() -> f64 {
    0.03
}

fn default_te_samples() -> i64 {
    24
}

impl Default for TeConfig {
    fn default() -> Self {
        TeConfig {
            samples_per_mesh_cycle: default_te_samples(),
            loaded_torque_nm: None,
            measuring_torque_fraction: default_measuring(),
        }
    }
}

impl TeConfig {
    /// The TE settings, SI; the loaded-TE torque defaults to `rated_torque` (N m).
    ///
    /// # Errors
    /// [`crate::Error::Invalid`] naming the key, the value and its range.
    pub fn validate(&self, rated_torque: f64) -> Result<TeParams> {
        let te_samples = whole(
            "te.samples_per_mesh_cycle",
            self.samples_per_mesh_cycle,
            2,
            10_000,
        )?;
        let loaded_torque = match self.loaded_torque_nm {
            Some(t) => check("te.loaded_torque_nm", t, Range::finite("N m"))?,
            None => rated_torque,
        };
        let measuring_torque_fraction = check(
            "te.measuring_torque_fraction",
            self.measuring_torque_fraction,
            Range::closed(1e-4, 0.5, "of the rated torque"),
        )?;
        Ok(TeParams {
            samples: te_samples,
            loaded_torque,
            measuring_torque_fraction,
        })
    }
}
