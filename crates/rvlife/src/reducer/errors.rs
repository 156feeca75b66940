//! Part errors of one reducer: pin positions and radii, the pin circle's run-out, the cranks'
//! eccentricities and phases (SI).
//!
//! With every error zero the reducer is the nominal one and the cycloid stage repeats every
//! mesh cycle; with any error the symmetry is gone and the transmission error is a function of
//! the position over a whole output revolution ([`crate::te::revolution`]).
//!
//! How each error enters the static analysis ([`crate::statics::StaticAnalysis`]):
//! - **pin position** (radial, tangential) and **pin-circle run-out**: the pin centre moves;
//!   the gaps are measured from the displaced centre (exact);
//! - **pin radius**: the gap of that pin shrinks by the radius error (exact for the gap; the
//!   Hertz curvature keeps the nominal radius, a relative error of `dr / r_p`, 1e-3 for 5 um);
//! - **crank eccentricity and phase**: each crank's eccentric carries its disc's bore to
//!   `(e + de_k) u(alpha + dphi_k)` instead of `e u(alpha)`. A disc sits on all the cranks; it
//!   takes the rigid-body pose that fits the bores' displacements in least squares (equal
//!   bearing stiffness): the mean displacement as a translation, and the rotation
//!   `sum_k b_k x (v_k - v_mean) / sum_k |b_k|^2` about its centre (`b_k`: bore `k` from the
//!   disc centre). The misfit beyond that rigid fit (tens of nanometres for arcminute phase
//!   errors) is taken up by the bearings and not modelled.
//!
//! Profile modification errors are not here: they change the profile itself, and a sampled
//! reducer is given its own [`crate::geometry::Modification`] (exact).

use crate::geometry::{cross, rotate, Vec2};

use super::Reducer;

/// Part errors of one reducer (SI). An empty per-pin or per-crank vector means all zero.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartErrors {
    /// Radial position error of each pin centre (outward positive), m; `Zp` values or empty.
    pub pin_radial: Vec<f64>,
    /// Tangential position error of each pin centre (counter-clockwise positive), m; `Zp`
    /// values or empty.
    pub pin_tangential: Vec<f64>,
    /// Radius error of each pin (oversize positive), m; `Zp` values or empty.
    pub pin_radius: Vec<f64>,
    /// Offset of the pin circle's centre from the output axis, m: half the pin circle's radial
    /// run-out (total indicator reading) in the direction of its largest radius.
    pub pin_circle_offset: Vec2,
    /// Eccentricity error of each crank's eccentrics (larger positive), m; one value per crank
    /// or empty.
    pub crank_eccentricity: Vec<f64>,
    /// Phase error of each crank's eccentrics (ahead, counter-clockwise, positive), rad; one
    /// value per crank or empty.
    pub crank_phase: Vec<f64>,
}

fn at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(0.0)
}

impl PartErrors {
    /// Whether every error is zero (the nominal reducer).
    pub fn is_zero(&self) -> bool {
        let zero = |v: &[f64]| v.iter().all(|&x| x == 0.0);
        zero(&self.pin_radial)
            && zero(&self.pin_tangential)
            && zero(&self.pin_radius)
            && self.pin_circle_offset == Vec2::zeros()
            && zero(&self.crank_eccentricity)
            && zero(&self.crank_phase)
    }

    /// Displacement of pin `j`'s centre from its nominal position, fixed frame, m: radial and
    /// tangential errors along the pin's own directions plus the pin circle's offset.
    pub fn pin_displacement(&self, red: &Reducer, j: usize) -> Vec2 {
        let g = std::f64::consts::TAU * j as f64 / red.geometry.pins as f64;
        let (er, et) = (Vec2::new(g.cos(), g.sin()), Vec2::new(-g.sin(), g.cos()));
        er * at(&self.pin_radial, j) + et * at(&self.pin_tangential, j) + self.pin_circle_offset
    }

    /// Radius error of pin `j`, m.
    pub fn pin_radius_error(&self, j: usize) -> f64 {
        at(&self.pin_radius, j)
    }

    /// Whether the cranks carry any error.
    pub fn has_crank_errors(&self) -> bool {
        self.crank_eccentricity
            .iter()
            .chain(&self.crank_phase)
            .any(|&x| x != 0.0)
    }

    /// Rigid-body correction of a disc's pose from the crank errors: translation (m, fixed
    /// frame) and rotation (rad), for the disc's eccentric direction `alpha` (rad, fixed frame)
    /// and the carrier angle `carrier` (rad). Least-squares fit of the bores' displacements
    /// (module documentation). Zero without crank errors.
    pub fn disc_correction(&self, red: &Reducer, alpha: f64, carrier: f64) -> (Vec2, f64) {
        if !self.has_crank_errors() || red.cranks == 0 {
            return (Vec2::zeros(), 0.0);
        }
        let e = red.geometry.eccentricity;
        let n = red.cranks;
        let v: Vec<Vec2> = (0..n)
            .map(|k| {
                let (de, dp) = (at(&self.crank_eccentricity, k), at(&self.crank_phase, k));
                let a1 = alpha + dp;
                // (e + de) u(alpha + dp) - e u(alpha), without cancellation for small dp.
                let half = 0.5 * dp;
                let chord = Vec2::new(
                    -(alpha + half).sin() * 2.0 * half.sin(),
                    (alpha + half).cos() * 2.0 * half.sin(),
                );
                chord * e + Vec2::new(a1.cos(), a1.sin()) * de
            })
            .collect();
        let mean = v.iter().fold(Vec2::zeros(), |s, x| s + x) / n as f64;
        let bores: Vec<Vec2> = (0..n).map(|k| rotate(&red.seat(k), carrier)).collect();
        let centroid = bores.iter().fold(Vec2::zeros(), |s, b| s + b) / n as f64;
        let (mut num, mut den) = (0.0, 0.0);
        for (b, vk) in bores.iter().zip(&v) {
            let r = b - centroid;
            num += cross(&r, &(vk - mean));
            den += r.norm_squared();
        }
        let rot = if den > 0.0 { num / den } else { 0.0 };
        (mean, rot)
    }

    /// An upper bound (m) of how much these errors change any pin's gap at any pose, to first
    /// order: the largest pin displacement and radius error, plus the largest disc translation
    /// and the rotation's effect at the pin circle (`|v_k| <= |de_k| + e |dphi_k|`; the fitted
    /// rotation is at most `2 max |v_k| / R_c`), with a factor 1.5 of margin.
    pub fn gap_bound(&self, red: &Reducer) -> f64 {
        let amax = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let pins = (0..red.geometry.pins)
            .map(|j| self.pin_displacement(red, j).norm())
            .fold(0.0_f64, f64::max);
        let e = red.geometry.eccentricity;
        let v = (0..red.cranks)
            .map(|k| at(&self.crank_eccentricity, k).abs() + e * at(&self.crank_phase, k).abs())
            .fold(0.0_f64, f64::max);
        let rc = red.crank_circle_radius.max(1e-12);
        let rp = red.geometry.pin_circle_radius + red.geometry.pin_radius;
        1.5 * (pins + amax(&self.pin_radius) + v * (1.0 + 2.0 * rp / rc))
    }
}
