//! Wear maps: a depth along the inward profile normal against mesh angle, the same on every
//! tooth, as a periodic C2 cubic spline (docs/model.md section 2).

use std::f64::consts::TAU;

use crate::error::{Error, Result};

/// Wear depth along the inward profile normal as a function of mesh angle, identical on every
/// tooth. Uniform grid of `n` mesh angles `t_m = 2 pi m / n`, depths in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct WearMap {
    depth: Vec<f64>,
    /// Node slopes of the periodic C2 cubic spline, per grid step (derived from `depth`).
    slope: Vec<f64>,
}

impl WearMap {
    /// A map from depths on a uniform mesh-angle grid (`depth[m]` at `t = 2 pi m / n`), m.
    ///
    /// # Errors
    /// [`Error::Invalid`] if fewer than 4 points or a depth is negative or not finite.
    pub fn new(depth: Vec<f64>) -> Result<Self> {
        if let Some((m, v)) = depth.iter().enumerate().find(|(_, v)| **v < 0.0) {
            return Err(Error::invalid(
                format!("wear map point {m}"),
                v,
                "wear depth must be finite and >= 0",
            ));
        }
        Self::deviation(depth)
    }

    /// A normal deviation map (a measured profile, with its wear): like [`WearMap::new`] but
    /// negative depths (material in excess of the described profile) are allowed.
    ///
    /// # Errors
    /// [`Error::Invalid`] if fewer than 4 points or a depth is not finite.
    pub fn deviation(depth: Vec<f64>) -> Result<Self> {
        if depth.len() < 4 {
            return Err(Error::invalid(
                "wear map",
                format!("{} points", depth.len()),
                "needs at least 4 points per tooth",
            ));
        }
        if let Some((m, v)) = depth.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::invalid(
                format!("wear map point {m}"),
                v,
                "wear depth must be finite",
            ));
        }
        let n = depth.len();
        // Node slopes of the periodic C2 cubic spline: m_{i-1} + 4 m_i + m_{i+1} =
        // 3 (y_{i+1} - y_{i-1}) (per grid step), solved by Gauss-Seidel sweeps (the cyclic
        // system is diagonally dominant, the error at least halves each sweep) until a sweep
        // moves no slope by more than the round-off of the largest (at most 80 sweeps).
        let rhs: Vec<f64> = (0..n)
            .map(|i| 3.0 * (depth[(i + 1) % n] - depth[(i + n - 1) % n]))
            .collect();
        let mut slope = vec![0.0; n];
        for _ in 0..80 {
            // The sweep in order i = 0..n, the wrapped neighbours of the end points apart.
            let update = |i: usize, before: f64, after: f64, slope: &mut [f64]| {
                let next = 0.25 * (rhs[i] - before - after);
                let moved = (next - slope[i]).abs();
                slope[i] = next;
                (moved, next.abs())
            };
            let (mut moved, mut largest) = update(0, slope[n - 1], slope[1], &mut slope);
            for i in 1..n - 1 {
                let (d, v) = update(i, slope[i - 1], slope[i + 1], &mut slope);
                moved = moved.max(d);
                largest = largest.max(v);
            }
            let (d, v) = update(n - 1, slope[n - 2], slope[0], &mut slope);
            if moved.max(d) <= 1e-16 * largest.max(v) {
                break;
            }
        }
        Ok(WearMap { depth, slope })
    }

    /// Uniform depth `h` (m) on `n` points: the paper's conservative wear model (uniform
    /// equidistant offset by the maximum wear, paper section 3.1).
    pub fn uniform(n: usize, h: f64) -> Result<Self> {
        Self::new(vec![h; n.max(4)])
    }

    /// Depths on the grid, m.
    pub(crate) fn depths(&self) -> &[f64] {
        &self.depth
    }

    /// Mesh angles of the grid, rad.
    pub fn angles(&self) -> Vec<f64> {
        let n = self.depth.len() as f64;
        (0..self.depth.len()).map(|m| TAU * m as f64 / n).collect()
    }

    /// Largest depth, m.
    pub(crate) fn max_depth(&self) -> f64 {
        self.depth.iter().copied().fold(0.0, f64::max)
    }

    /// The Hermite cell of mesh angle `t`: node depths `p1`, `p2`, node slopes `m1`, `m2` (per
    /// grid step), local coordinate `u` in `[0, 1)` and the grid step `dt` (rad).
    #[inline]
    fn cell(&self, t: f64) -> (f64, f64, f64, f64, f64, f64) {
        let n = self.depth.len();
        let dt = TAU / n as f64;
        let s = t / dt;
        let k = s.floor();
        let u = s - k;
        let i = (k as i64).rem_euclid(n as i64) as usize;
        let j = if i + 1 == n { 0 } else { i + 1 };
        (
            self.depth[i],
            self.slope[i],
            self.depth[j],
            self.slope[j],
            u,
            dt,
        )
    }

    /// The cells of this map that `before` (`None`: no wear) already had, for a worn flank
    /// grown from `before`'s by wear alone: per cell `i` (from node `i` to `i + 1`), whether
    /// its node depths and slopes are within [`WearMap::UNCHANGED`] of `before`'s (the worn
    /// profile there is `before`'s to far below a picometre). `None` if the maps differ in
    /// size, or if this map lies above `before`'s anywhere (sampled at 8 points per cell) by
    /// more than `tolerance` (m): material was added, not worn off.
    pub(crate) fn grown_from(&self, before: Option<&WearMap>, tolerance: f64) -> Option<Vec<bool>> {
        let n = self.depth.len();
        let zeros = vec![0.0; n];
        let (d0, s0) = match before {
            Some(b) if b.depth.len() == n => (&b.depth[..], &b.slope[..]),
            Some(_) => return None,
            None => (&zeros[..], &zeros[..]),
        };
        let (dd, ds): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|i| (self.depth[i] - d0[i], self.slope[i] - s0[i]))
            .unzip();
        let mut cells = Vec::with_capacity(n);
        for i in 0..n {
            let j = if i + 1 == n { 0 } else { i + 1 };
            let grown = (0..=8)
                .all(|k| cubic_hermite(dd[i], ds[i], dd[j], ds[j], k as f64 / 8.0).0 >= -tolerance);
            if !grown {
                return None;
            }
            cells.push(
                [dd[i], ds[i], dd[j], ds[j]]
                    .iter()
                    .all(|x| x.abs() <= Self::UNCHANGED),
            );
        }
        Some(cells)
    }

    /// Depth or slope change (m) below which [`WearMap::grown_from`] takes a cell as unchanged:
    /// the round-off of the spline's slopes (solved to 1e-16 of the largest).
    pub(crate) const UNCHANGED: f64 = 1e-15;

    /// Depth `h` (m) and its derivative `dh/dt` (m/rad) at mesh angle `t` (any real; wrapped).
    ///
    /// Periodic cubic spline interpolation (C2: the worn flank's curvature is continuous, so the
    /// interpolant adds no curvature steps at the grid nodes that could make a pin touch the
    /// flank at two points a grid step apart). Where wear starts abruptly the spline can
    /// undershoot zero by a small fraction of the step in depth; the study's maps are filtered
    /// at the contact-band scale first, which keeps that below a nanometre.
    pub(crate) fn eval(&self, t: f64) -> (f64, f64) {
        let (h, dh, _) = self.eval2(t);
        (h, dh)
    }

    /// Depth (m), `dh/dt` (m/rad) and `d2h/dt2` (m/rad^2, continuous and piecewise linear) at
    /// mesh angle `t`.
    pub(crate) fn eval2(&self, t: f64) -> (f64, f64, f64) {
        let (p1, m1, p2, m2, u, dt) = self.cell(t);
        let (h, dh_du) = cubic_hermite(p1, m1, p2, m2, u);
        let dh = dh_du / dt;
        let ddh = ((12.0 * u - 6.0) * p1
            + (6.0 * u - 4.0) * m1
            + (-12.0 * u + 6.0) * p2
            + (6.0 * u - 2.0) * m2)
            / (dt * dt);
        (h, dh, ddh)
    }
}

/// Cubic Hermite segment between values `p1`, `p2` with slopes `m1`, `m2` (per unit of `u`):
/// value and derivative `d/du` at `u` in `[0, 1]`.
#[inline]
pub(crate) fn cubic_hermite(p1: f64, m1: f64, p2: f64, m2: f64, u: f64) -> (f64, f64) {
    let (u2, u3) = (u * u, u * u * u);
    let v = (2.0 * u3 - 3.0 * u2 + 1.0) * p1
        + (u3 - 2.0 * u2 + u) * m1
        + (-2.0 * u3 + 3.0 * u2) * p2
        + (u3 - u2) * m2;
    let d = (6.0 * u2 - 6.0 * u) * (p1 - p2)
        + (3.0 * u2 - 4.0 * u + 1.0) * m1
        + (3.0 * u2 - 2.0 * u) * m2;
    (v, d)
}
