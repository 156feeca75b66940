//! `[cycloid]` and `[cycloid.modification]`: the cycloid stage and its profile modifications
//! (docs/model.md section 2). The measured profile is fitted after `[wear]`, whose grid it
//! needs ([`super::cross_section`]).

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::range::{check, whole, Range};
use crate::error::Result;
use crate::geometry::{CycloidGeometry, Modification};

/// `[cycloid]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CycloidConfig {
    /// Pins `Zp`; disc teeth `Zc = Zp - 1`. Range: whole number, 3 to 1000.
    pub pins: i64,
    /// Eccentricity `a`, mm. Range: [0.01, 1e4] mm.
    pub eccentricity_mm: f64,
    /// Pin circle radius `Rp`, mm. Range: [0.01, 1e4] mm.
    pub pin_circle_radius_mm: f64,
    /// Pin radius `rrp`, mm. Range: [0.01, 1e4] mm.
    pub pin_radius_mm: f64,
    /// Disc width `B`, mm. Range: [0.01, 1e4] mm.
    pub width_mm: f64,
    /// Profile modifications.
    #[serde(default)]
    pub modification: ModificationConfig,
    /// A measured profile (CSV `x_mm,y_mm` or DXF polyline, mm, disc frame; path relative to
    /// the config file), fitted as a deviation map over the described profile.
    #[serde(default)]
    pub measured_profile: Option<PathBuf>,
}

/// `[cycloid.modification]`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModificationConfig {
    /// Equidistant modification `drrp`, mm. Range: any finite number (the physical check of
    /// the unworn stage bounds it: [`super::physical`]).
    #[serde(default)]
    pub equidistant_mm: f64,
    /// Offset modification `dRp`, mm. Range: any finite number (bounded like
    /// `equidistant_mm`).
    #[serde(default)]
    pub offset_mm: f64,
    /// Rotation modification, degrees. Range: [-0.5, 0.5] deg (real ones are a few arcmin;
    /// the static analysis follows 34 arcmin of twist from the nominal pose).
    #[serde(default)]
    pub rotation_deg: f64,
}

/// Millimetres of a stage size: from a watch-size drive (0.01 mm) to beyond the largest
/// reducers built (10 m).
pub(super) const SIZE_MM: Range = Range::closed(0.01, 1e4, "mm");

impl CycloidConfig {
    /// The stage geometry and the modifications, SI.
    ///
    /// # Errors
    /// [`crate::Error::Invalid`] naming the key, the value and its range.
    pub fn validate(&self) -> Result<(CycloidGeometry, Modification)> {
        let mm = |key: &str, v: f64| check(key, v, SIZE_MM).map(|v| v * 1e-3);
        let geometry = CycloidGeometry {
            pins: whole("cycloid.pins", self.pins, 3, 1000)?,
            eccentricity: mm("cycloid.eccentricity_mm", self.eccentricity_mm)?,
            pin_circle_radius: mm("cycloid.pin_circle_radius_mm", self.pin_circle_radius_mm)?,
            pin_radius: mm("cycloid.pin_radius_mm", self.pin_radius_mm)?,
            width: mm("cycloid.width_mm", self.width_mm)?,
        };
        Ok((geometry, self.modification.validate()?))
    }
}

impl ModificationConfig {
    /// The modifications, SI (m, m, rad).
    ///
    /// # Errors
    /// [`crate::Error::Invalid`] naming the key, the value and its range.
    pub fn validate(&self) -> Result<Modification> {
        Ok(Modification {
            equidistant: check(
                "cycloid.modification.equidistant_mm",
                self.equidistant_mm,
                Range::finite("mm"),
            )? * 1e-3,
            offset: check(
                "cycloid.modification.offset_mm",
                self.offset_mm,
                Range::finite("mm"),
            )? * 1e-3,
            rotation: check(
                "cycloid.modification.rotation_deg",
                self.rotation_deg,
                Range::closed(-0.5, 0.5, "deg (30 arcmin)"),
            )?
            .to_radians(),
        })
    }
}
