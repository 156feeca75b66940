//! The disc as a config describes it, and the profiles built from it: the stage, its
//! modifications, and the deviation map of a measured profile, which every profile of a study
//! carries under its wear (docs/model.md sections 2 and 14).

use super::{CycloidGeometry, MeasuredProfile, Modification, Profile, WearMap};
use crate::error::Result;

/// `[cycloid]` checked, SI: what every profile of a study is built from.
#[derive(Debug, Clone)]
pub struct CycloidParams {
    /// Nominal stage geometry.
    pub geometry: CycloidGeometry,
    /// Profile modifications.
    pub modification: Modification,
    /// The measured profile (`cycloid.measured_profile`), whose normal deviation map every
    /// profile built here carries under its wear; `None` without one.
    pub measured: Option<MeasuredProfile>,
}

impl CycloidParams {
    /// The profile with these modifications and the wear map `wear`, on the measured
    /// profile's deviation map when there is one (the deviation added to the wear depth,
    /// resampled linearly when the grids differ).
    ///
    /// # Errors
    /// Those of [`Profile::new`] (an undercut or folded profile, a bad map).
    pub fn profile(&self, wear: Option<WearMap>) -> Result<Profile> {
        let Some(m) = &self.measured else {
            return Profile::new(self.geometry.clone(), self.modification, wear);
        };
        let n = wear
            .as_ref()
            .map_or(m.deviation.len(), |w| w.depths().len());
        let dev = resample(&m.deviation, n);
        let depth: Vec<f64> = match &wear {
            Some(w) => w.depths().iter().zip(&dev).map(|(a, b)| a + b).collect(),
            None => dev,
        };
        Profile::new(
            self.geometry.clone(),
            self.modification,
            Some(WearMap::deviation(depth)?),
        )
    }

    /// Largest wear depth (m) of a profile built here: its map's depth less the measured
    /// deviation (which is not wear).
    pub(crate) fn wear_depth(&self, profile: &Profile) -> f64 {
        let Some(w) = profile.wear() else {
            return 0.0;
        };
        match &self.measured {
            None => w.max_depth(),
            Some(m) => {
                let dev = resample(&m.deviation, w.depths().len());
                w.depths()
                    .iter()
                    .zip(&dev)
                    .map(|(a, b)| a - b)
                    .fold(0.0, f64::max)
            }
        }
    }

    /// The nominal disc: the same stage without modifications or measured deviation.
    pub fn nominal(&self) -> CycloidParams {
        CycloidParams {
            geometry: self.geometry.clone(),
            modification: Modification::default(),
            measured: None,
        }
    }
}

/// `v` (periodic, uniform grid) linearly resampled to `n` points.
fn resample(v: &[f64], n: usize) -> Vec<f64> {
    if v.len() == n {
        return v.to_vec();
    }
    (0..n)
        .map(|i| {
            let s = i as f64 * v.len() as f64 / n as f64;
            let k = s.floor() as usize % v.len();
            let u = s - s.floor();
            v[k] * (1.0 - u) + v[(k + 1) % v.len()] * u
        })
        .collect()
}
