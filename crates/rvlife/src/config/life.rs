//! `[life]`: the accuracy spec, whose first threshold crossed ends the accuracy life
//! (docs/model.md section 11).

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::error::Result;

/// `[life]`: the accuracy spec. The accuracy life is the working hours at which the first of
/// the given thresholds is crossed.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LifeConfig {
    /// Largest lost motion (catalogue, +-3 % of rated torque), arcmin. Range: (0, 600] arcmin.
    #[serde(default)]
    pub lost_motion_arcmin: Option<f64>,
    /// Largest backlash, arcmin. Range: (0, 600] arcmin.
    #[serde(default)]
    pub backlash_arcmin: Option<f64>,
    /// Largest angular transmission error (peak-to-peak over an output revolution), arcmin.
    /// Range: (0, 600] arcmin.
    #[serde(default)]
    pub angular_te_arcmin: Option<f64>,
    /// Smallest torsional stiffness, N m/arcmin. Range: (0, 1e9] N m/arcmin.
    #[serde(default)]
    pub torsional_stiffness_min_nm_per_arcmin: Option<f64>,
    /// How far beyond the last stage the wear integration steps on to find the crossing, h
    /// (default 10 x the last stage). Range: (0, 1e7] h.
    #[serde(default)]
    pub max_hours: Option<f64>,
}

/// The validated `[life]` thresholds (engineering units, as the study reports them).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct LifeThresholds {
    /// Largest lost motion, arcmin.
    pub lost_motion_arcmin: Option<f64>,
    /// Largest backlash, arcmin.
    pub backlash_arcmin: Option<f64>,
    /// Largest angular TE, arcmin.
    pub angular_te_arcmin: Option<f64>,
    /// Smallest torsional stiffness, N m/arcmin.
    pub torsional_stiffness_min_nm_per_arcmin: Option<f64>,
    /// Horizon of the search beyond the last stage, h (`None`: 10 x the last stage).
    pub max_hours: Option<f64>,
}

impl LifeThresholds {
    /// The horizon of a Monte Carlo run's lives, h: `max_hours`, else ten times the last of
    /// `stage_hours` (the lives beyond it are censored; docs/model.md section 12.3).
    pub fn horizon_h(&self, stage_hours: &[f64]) -> f64 {
        self.max_hours
            .unwrap_or(10.0 * stage_hours.last().copied().unwrap_or(0.0))
    }

    /// The threshold of the `[life]` key `key` (`lost_motion_arcmin`, ...), if set.
    pub fn threshold(&self, key: &str) -> Option<f64> {
        match key {
            "lost_motion_arcmin" => self.lost_motion_arcmin,
            "backlash_arcmin" => self.backlash_arcmin,
            "angular_te_arcmin" => self.angular_te_arcmin,
            "torsional_stiffness_min_nm_per_arcmin" => self.torsional_stiffness_min_nm_per_arcmin,
            _ => None,
        }
    }

    /// Whether any threshold is set.
    pub fn any(&self) -> bool {
        self.lost_motion_arcmin.is_some()
            || self.backlash_arcmin.is_some()
            || self.angular_te_arcmin.is_some()
            || self.torsional_stiffness_min_nm_per_arcmin.is_some()
    }
}

impl LifeConfig {
    /// Checks the thresholds (positive, finite).
    ///
    /// # Errors
    /// `Error::Invalid` naming the key, the value and the allowed range.
    pub fn validate(&self) -> Result<LifeThresholds> {
        let t = |key: &str, v: Option<f64>, hi: f64, unit| {
            v.map(|x| check(&format!("life.{key}"), x, Range::positive(hi, unit)))
                .transpose()
        };
        Ok(LifeThresholds {
            lost_motion_arcmin: t(
                "lost_motion_arcmin",
                self.lost_motion_arcmin,
                600.0,
                "arcmin",
            )?,
            backlash_arcmin: t("backlash_arcmin", self.backlash_arcmin, 600.0, "arcmin")?,
            angular_te_arcmin: t("angular_te_arcmin", self.angular_te_arcmin, 600.0, "arcmin")?,
            torsional_stiffness_min_nm_per_arcmin: t(
                "torsional_stiffness_min_nm_per_arcmin",
                self.torsional_stiffness_min_nm_per_arcmin,
                1e9,
                "N m/arcmin",
            )?,
            max_hours: t("max_hours", self.max_hours, 1e7, "h")?,
        })
    }
}
