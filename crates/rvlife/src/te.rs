//! Static and loaded transmission error and lost motion of the cycloid stage
//! (paper eqs 21-23, physics-notes section 6).
//!
//! The disc is tied to the output carrier by the crankshafts, so its extra rotation beyond the
//! nominal `psi = -phi/Zc` is the output's rotation error. With a rigid first stage the output
//! error is `TE = theta_out - theta_in / i_H` (eq 21); the coupling of that error back into the
//! crank angle (`(1 + Z1/Z2) TE`) moves the TE curve along by less than a microradian of crank
//! angle and is neglected.
//!
//! - **STE** (no load, rigid bodies): for each crank angle, the rotation at which the actual disc
//!   first touches a pin, turning in the driving direction ([`crate::contact::first_contact`]).
//! - **Driving direction and sign**: the forward direction is the one in which the output load
//!   presses the flank `0 < mesh angle < pi` (input angle `theta_in = i_H phi / Zc` increasing).
//!   TE is reported as the lag of the output behind its nominal position in the driving
//!   direction, so wear and thinning modifications give a positive TE, as in the paper's figures.
//! - **Lost motion**: the play between the two directions at one crank angle,
//!   `beta_forward - beta_reverse`; reported as the maximum and the mean over a revolution.
//! - **Loaded TE**: the rotation of the loaded-contact solution at a given output torque.
//!
//! All pins and all teeth are identical (the wear map is the same on every tooth), so every
//! quantity is periodic in the crank angle with the mesh period `2 pi / Zp`; curves are computed
//! over one mesh cycle and repeated `Zc Zp` times to span one output revolution.

use std::f64::consts::TAU;

use rayon::prelude::*;
use serde::Serialize;

use crate::contact::{first_contact, solve, ContactModel, ContactSolution};
use crate::error::{Error, Result};
use crate::geometry::Profile;

/// Radians to arcminutes.
pub const ARCMIN_PER_RAD: f64 = 180.0 * 60.0 / std::f64::consts::PI;

/// Crank angles (rad) of `samples` points over one mesh cycle `[0, 2 pi / Zp)`.
pub fn mesh_cycle_angles(pins: usize, samples: usize) -> Vec<f64> {
    (0..samples)
        .map(|k| TAU * k as f64 / (pins as f64 * samples as f64))
        .collect()
}

/// Static transmission error over one mesh cycle.
#[derive(Debug, Clone, Serialize)]
pub struct StaticTe {
    /// Crank angles, rad.
    pub crank_angle: Vec<f64>,
    /// Forward-direction TE (output lag at first contact), rad.
    pub forward: Vec<f64>,
    /// Reverse-direction TE (output lag at first contact turning the other way), rad.
    pub reverse: Vec<f64>,
}

/// Summary statistics of a curve, rad.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CurveStats {
    /// Mean, rad.
    pub mean: f64,
    /// Peak-to-peak, rad.
    pub peak_to_peak: f64,
    /// Maximum, rad.
    pub max: f64,
    /// Minimum, rad.
    pub min: f64,
}

impl CurveStats {
    /// Statistics of `v` (non-empty).
    pub fn of(v: &[f64]) -> CurveStats {
        let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        CurveStats {
            mean: v.iter().sum::<f64>() / v.len() as f64,
            peak_to_peak: max - min,
            max,
            min,
        }
    }
}

impl StaticTe {
    /// Statistics of the forward STE.
    pub fn stats(&self) -> CurveStats {
        CurveStats::of(&self.forward)
    }
    /// Lost motion at each crank angle, rad.
    pub fn lost_motion(&self) -> Vec<f64> {
        self.forward
            .iter()
            .zip(&self.reverse)
            .map(|(f, r)| f + r)
            .collect()
    }
    /// Statistics of the lost motion.
    pub fn lost_motion_stats(&self) -> CurveStats {
        CurveStats::of(&self.lost_motion())
    }
}

/// Static TE of the profile at `samples` crank angles over one mesh cycle.
///
/// # Errors
/// [`Error::Invalid`] if the modifications interfere (negative lost motion: the disc cannot be
/// assembled without preload); solver failures.
pub fn static_te(profile: &Profile, samples: usize) -> Result<StaticTe> {
    let phis = mesh_cycle_angles(profile.geometry().pins, samples);
    let pairs: Vec<(f64, f64)> = phis
        .par_iter()
        .map(|&phi| {
            Ok((
                first_contact(profile, phi, 1.0)?,
                first_contact(profile, phi, -1.0)?,
            ))
        })
        .collect::<Result<_>>()?;
    let forward: Vec<f64> = pairs.iter().map(|p| p.0).collect();
    let reverse: Vec<f64> = pairs.iter().map(|p| -p.1).collect();
    if let Some(k) = (0..samples).find(|&k| forward[k] + reverse[k] < -1e-9) {
        return Err(Error::invalid(
            "cycloid.modification",
            format!(
                "lost motion {:.4} arcmin at crank angle {:.3} deg",
                (forward[k] + reverse[k]) * ARCMIN_PER_RAD,
                phis[k].to_degrees()
            ),
            "the modified disc interferes with the pins (negative clearance); \
             thin the teeth (equidistant > 0 or offset < 0)",
        ));
    }
    Ok(StaticTe {
        crank_angle: phis,
        forward,
        reverse,
    })
}

/// Loaded TE over one mesh cycle.
#[derive(Debug, Clone, Serialize)]
pub struct LoadedTe {
    /// Output torque, N m.
    pub torque: f64,
    /// Crank angles, rad.
    pub crank_angle: Vec<f64>,
    /// Output lag in the direction of the load, rad.
    pub te: Vec<f64>,
    /// Contact solutions at each crank angle.
    pub solutions: Vec<ContactSolution>,
}

impl LoadedTe {
    /// Statistics of the loaded TE.
    pub fn stats(&self) -> CurveStats {
        CurveStats::of(&self.te)
    }
    /// Largest pin force over the cycle, N.
    pub fn max_force(&self) -> f64 {
        self.solutions
            .iter()
            .map(|s| s.max_force())
            .fold(0.0, f64::max)
    }
    /// Largest Hertz pressure over the cycle, Pa.
    pub fn max_pressure(&self) -> f64 {
        self.solutions
            .iter()
            .map(|s| s.max_pressure())
            .fold(0.0, f64::max)
    }
    /// Fewest and most pins in contact over the cycle.
    pub fn pins_in_contact(&self) -> (usize, usize) {
        let it = self.solutions.iter().map(|s| s.pins_in_contact());
        (it.clone().min().unwrap_or(0), it.max().unwrap_or(0))
    }
    /// The solution with the largest pin force.
    pub fn worst(&self) -> &ContactSolution {
        self.solutions
            .iter()
            .max_by(|a, b| a.max_force().total_cmp(&b.max_force()))
            .expect("at least two samples")
    }
}

/// Loaded TE at output torque `torque` (N m; the disc carries `load_share` of it).
///
/// # Errors
/// Solver failures.
pub fn loaded_te(
    profile: &Profile,
    model: &ContactModel,
    load_share: f64,
    torque: f64,
    samples: usize,
) -> Result<LoadedTe> {
    let phis = mesh_cycle_angles(profile.geometry().pins, samples);
    let solutions: Vec<ContactSolution> = phis
        .par_iter()
        .map(|&phi| solve(profile, model, phi, load_share * torque))
        .collect::<Result<_>>()?;
    let s = if torque < 0.0 { -1.0 } else { 1.0 };
    Ok(LoadedTe {
        torque,
        crank_angle: phis,
        te: solutions.iter().map(|x| s * x.disc_rotation).collect(),
        solutions,
    })
}

/// Repeats a mesh-cycle curve over one output revolution (`Zc Zp` mesh cycles) and returns
/// `(input angle in degrees, value)` pairs, the input angle being `i_H phi / Zc`.
pub fn over_revolution(
    crank_angle: &[f64],
    values: &[f64],
    pins: usize,
    ratio: f64,
) -> (Vec<f64>, Vec<f64>) {
    let zc = (pins - 1) as f64;
    let period = TAU / pins as f64;
    let cycles = (pins - 1) * pins;
    let mut x = Vec::with_capacity(cycles * values.len());
    let mut y = Vec::with_capacity(cycles * values.len());
    for c in 0..cycles {
        for (phi, v) in crank_angle.iter().zip(values) {
            x.push((ratio * (phi + c as f64 * period) / zc).to_degrees());
            y.push(*v);
        }
    }
    (x, y)
}
