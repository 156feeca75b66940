//! A roller bearing's radial law tabulated for the multibody model (docs/model.md section
//! 5.9): the force `F(x)` and stiffness `F'(x)` of [`RadialBearing::radial_force`] at a total
//! displacement `x` (bearing and series parts) as a cubic Hermite interpolant of `ln F`
//! against `ln (x - c/2)`, from the exact law at the nodes. The law is a sum of power laws
//! (`Q ~ delta^(10/9)` per roller, the series spring linear), nearly straight in those
//! coordinates; where a roller comes into contact its force's curvature is singular, so the
//! grid takes a node there and nodes closing in on it from above. The multibody model
//! evaluates its bearings at every right-hand side; one table look-up (a bisection, a
//! logarithm and an exponential) replaces the series solve's two or three roller sums.
//!
//! Accuracy (tested at 12 500 displacements from 1 nm to 1 mm beyond the clearance on both
//! crank bearings of every built-in reducer, with clearances of 0 to 40 um, with and without
//! their series parts): the force within 1e-7 of the exact law's, relative (5.3e-8 seen). The
//! multibody model takes only the force (its Jacobian is by differences); the static analysis
//! evaluates the exact law.

use super::bearing::{BearingLaw, RadialBearing, DEAD_BAND_STIFFNESS};
use crate::geometry::Vec2;

/// Displacements beyond the clearance (m) from which the table starts and at which it ends:
/// below, the law is continued as the power law of the first node; above, evaluated exactly.
const SPAN: (f64, f64) = (1e-12, 1e-3);

/// Nodes per factor e of the displacement beyond the clearance (about 64 per decade).
const NODES_PER_E: f64 = 28.0;

/// Nodes above a roller's first contact `u_c`: at `u_c (1 + e)` for `e` from
/// `ONSET_STEPS.0` up to `ONSET_STEPS.1`, each `ONSET_STEPS.2` times the last (the roller's
/// force grows as `(u - u_c)^(10/9)`, so the nodes keep the interval below a quarter of its
/// distance from `u_c`; nearer than `1e-6 u_c` the roller's force is below 1e-7 of the
/// bearing's).
const ONSET_STEPS: (f64, f64, f64) = (1e-6, 2.0, 1.15);

/// A roller bearing's [`RadialBearing::radial_force`] as a table (the module's).
#[derive(Debug, Clone)]
pub(crate) struct BearingTable {
    bearing: RadialBearing,
    /// At each node: `ln u` (`u = x - c/2`, m), `ln F` (the force without the dead-band
    /// spring, N) and `s = d ln F / d ln u`.
    ln_u: Vec<f64>,
    ln_f: Vec<f64>,
    slope: Vec<f64>,
    /// The dead-band spring's stiffness (N/m; 0 without a dead band).
    dead_band: f64,
}

impl BearingTable {
    /// The table of `bearing`, or `None` for a linear bearing (whose law costs less than a
    /// look-up).
    pub(crate) fn new(bearing: &RadialBearing) -> Option<Self> {
        let BearingLaw::Rollers { count, .. } = bearing.law else {
            return None;
        };
        let half = 0.5 * bearing.clearance;
        let dead_band = if bearing.has_dead_band() {
            DEAD_BAND_STIFFNESS
        } else {
            0.0
        };
        let (lo, hi) = (SPAN.0.ln(), SPAN.1.ln());
        let n = ((hi - lo) * NODES_PER_E).ceil() as usize;
        let mut us: Vec<f64> = (0..=n)
            .map(|i| (lo + (hi - lo) * i as f64 / n as f64).exp())
            .collect();
        // Each roller's first contact (`d cos(psi_i) = c/2`) in the total displacement, and
        // nodes closing in on it from above.
        if half > 0.0 {
            for i in 1..=count / 2 {
                let c = (std::f64::consts::TAU * i as f64 / count as f64).cos();
                if c <= 0.0 {
                    break;
                }
                let d = half / c;
                let own = bearing.own_force(d).0;
                let x = d + if bearing.series_stiffness.is_finite() {
                    own / bearing.series_stiffness
                } else {
                    0.0
                };
                // A node just below the contact, where the law's slope is its left limit (the
                // roller's stiffness rises as (u - u_c)^(1/9): a step at any resolution; the
                // series solve places the contact to about 1e-8 of u_c).
                let u = x - half;
                us.push(u * (1.0 - ONSET_STEPS.0));
                let mut e = ONSET_STEPS.0;
                while e <= ONSET_STEPS.1 {
                    us.push(u * (1.0 + e));
                    e *= ONSET_STEPS.2;
                }
            }
        }
        us.retain(|u| (SPAN.0..=SPAN.1).contains(u));
        us.sort_by(f64::total_cmp);
        us.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * *b);
        let mut table = BearingTable {
            bearing: *bearing,
            ln_u: Vec::with_capacity(us.len()),
            ln_f: Vec::with_capacity(us.len()),
            slope: Vec::with_capacity(us.len()),
            dead_band,
        };
        for u in us {
            let (f, k) = bearing.radial_force(half + u);
            let (f, k) = (f - dead_band * (half + u), k - dead_band);
            if !(f > 0.0 && k > 0.0) {
                continue;
            }
            table.ln_u.push(u.ln());
            table.ln_f.push(f.ln());
            table.slope.push(k * u / f);
        }
        (table.ln_u.len() >= 2).then_some(table)
    }

    /// Radial force (N) at the total displacement `x` (m): the force of
    /// [`RadialBearing::radial_force`], to the module's accuracy.
    #[inline]
    pub(crate) fn radial_force(&self, x: f64) -> f64 {
        let half = 0.5 * self.bearing.clearance;
        let u = x - half;
        let reg = self.dead_band * x;
        if u.is_nan() || u <= 0.0 {
            return reg;
        }
        let last = self.ln_u.len() - 1;
        let lu = u.ln();
        if lu >= self.ln_u[last] {
            return self.bearing.radial_force(x).0;
        }
        let ln_f = if lu <= self.ln_u[0] {
            self.ln_f[0] + self.slope[0] * (lu - self.ln_u[0])
        } else {
            let i = self.ln_u.partition_point(|&v| v <= lu) - 1;
            let h = self.ln_u[i + 1] - self.ln_u[i];
            let t = (lu - self.ln_u[i]) / h;
            let (y0, y1) = (self.ln_f[i], self.ln_f[i + 1]);
            let (m0, m1) = (self.slope[i] * h, self.slope[i + 1] * h);
            let (t2, t3) = (t * t, t * t * t);
            (2.0 * t3 - 3.0 * t2 + 1.0) * y0
                + (t3 - 2.0 * t2 + t) * m0
                + (-2.0 * t3 + 3.0 * t2) * y1
                + (t3 - t2) * m1
        };
        ln_f.exp() + reg
    }

    /// The bearing's force on the first end (N) at the relative position `r` (m) and velocity
    /// `rd` (m/s): [`RadialBearing::force`] with the tabulated radial force.
    #[inline]
    pub(crate) fn force(&self, r: Vec2, rd: Vec2) -> Vec2 {
        self.bearing.force_with(r, rd, |x| self.radial_force(x))
    }
}
