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

use crate::geometry::Vec2;

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

pub(crate) fn at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(0.0)
}

impl PartErrors {
    /// Whether every error is zero (the nominal reducer).
    pub(crate) fn is_zero(&self) -> bool {
        let zero = |v: &[f64]| v.iter().all(|&x| x == 0.0);
        zero(&self.pin_radial)
            && zero(&self.pin_tangential)
            && zero(&self.pin_radius)
            && self.pin_circle_offset == Vec2::zeros()
            && zero(&self.crank_eccentricity)
            && zero(&self.crank_phase)
    }

    /// Radius error of pin `j`, m.
    pub(crate) fn pin_radius_error(&self, j: usize) -> f64 {
        at(&self.pin_radius, j)
    }

    /// Whether the cranks carry any error.
    pub(crate) fn has_crank_errors(&self) -> bool {
        self.crank_eccentricity
            .iter()
            .chain(&self.crank_phase)
            .any(|&x| x != 0.0)
    }
}
