//! Cycloid disc profile: closed form with modifications, wear maps, curvature, closest points.
//!
//! Conventions (docs/model.md sections 1 and 2), all SI (metres, radians):
//! - pin `j` (0-based) sits at `Rp (cos 2 pi j / Zp, sin 2 pi j / Zp)` in the fixed pin ring;
//! - the disc frame has its origin at the disc centre; the profile is given by the closed form
//!   of paper eq 24 (eq 3 with modifications) with parameter `t` in `[0, 2 pi Zc)`:
//!   `z(t) = (Rp' - rrp'/S) e^{i(1 - Zp/Zc)t} - (a - K1 rrp'/S) e^{-i (Zp/Zc) t}`,
//!   `S = sqrt(1 + K1^2 - 2 K1 cos t)`, `K1 = a Zp / Rp` with the nominal `Rp`,
//!   `Rp' = Rp + offset`, `rrp' = rrp + equidistant`, then turned by the rotation modification;
//! - `t` advances one tooth per `2 pi` and runs clockwise; its value modulo `2 pi` is the
//!   *mesh angle* of a point: 0 at the tooth root (deepest point of a tooth space), `pi` at the
//!   tooth tip. The flank `0 < t < pi` carries a positive (counter-clockwise) disc torque; the
//!   flank `pi < t < 2 pi` carries a negative one;
//! - a wear map is a depth `h(t)` (metres, >= 0) along the inward normal, the same on every
//!   tooth, stored on a uniform grid of mesh angles and interpolated with a periodic cubic
//!   spline (C2, so closest-point searches see a continuous tangent and curvature).

use std::f64::consts::{PI, TAU};

use nalgebra::Vector2;

use crate::error::{Error, Result};

/// A 2D point or vector in metres.
pub type Vec2 = Vector2<f64>;

/// z-component of the cross product `a x b`.
#[inline]
pub(crate) fn cross(a: &Vec2, b: &Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Rotates `v` by `angle` (radians, counter-clockwise).
#[inline]
pub(crate) fn rotate(v: &Vec2, angle: f64) -> Vec2 {
    rotate_by(v, angle.sin_cos())
}

/// [`rotate`] by the angle whose `(sine, cosine)` is given (formed once for many vectors).
#[inline]
pub(crate) fn rotate_by(v: &Vec2, (s, c): (f64, f64)) -> Vec2 {
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Nominal geometry of the cycloid stage (SI units).
///
/// Source: paper Table 1 for the example values; docs/model.md section 2 for the constraints.
#[derive(Debug, Clone, PartialEq)]
pub struct CycloidGeometry {
    /// Number of pins `Zp` (>= 3); the disc has `Zc = Zp - 1` teeth.
    pub pins: usize,
    /// Eccentricity `a`, m.
    pub eccentricity: f64,
    /// Pin circle radius `Rp`, m.
    pub pin_circle_radius: f64,
    /// Pin radius `rrp`, m.
    pub pin_radius: f64,
    /// Disc (face) width `B`, m.
    pub width: f64,
}

impl CycloidGeometry {
    /// Checks the ranges: `Zp >= 3`, all sizes positive and finite, `0 < K1 < 1`,
    /// pin radius below half the pin pitch.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the config key (`cycloid.*`), the value and the allowed range.
    pub fn validate(&self) -> Result<()> {
        if self.pins < 3 {
            return Err(Error::invalid(
                "cycloid.pins",
                self.pins,
                "must be at least 3",
            ));
        }
        for (field, v) in [
            ("cycloid.eccentricity_mm", self.eccentricity),
            ("cycloid.pin_circle_radius_mm", self.pin_circle_radius),
            ("cycloid.pin_radius_mm", self.pin_radius),
            ("cycloid.width_mm", self.width),
        ] {
            if !v.is_finite() || v <= 0.0 {
                return Err(Error::invalid(
                    field,
                    v * 1e3,
                    "must be a finite number > 0",
                ));
            }
        }
        let k1 = self.k1();
        if k1 >= 1.0 {
            return Err(Error::invalid(
                "cycloid.eccentricity_mm",
                self.eccentricity * 1e3,
                format!(
                    "gives the short-amplitude coefficient K1 = a Zp / Rp = {k1:.4}; it must be < 1 \
                     (eccentricity below {:.4} mm for {} pins on a {:.3} mm pin circle)",
                    self.pin_circle_radius / self.pins as f64 * 1e3,
                    self.pins,
                    self.pin_circle_radius * 1e3
                ),
            ));
        }
        let half_pitch = self.pin_circle_radius * (PI / self.pins as f64).sin();
        if self.pin_radius >= half_pitch {
            return Err(Error::invalid(
                "cycloid.pin_radius_mm",
                self.pin_radius * 1e3,
                format!(
                    "must be below half the pin pitch ({:.4} mm): neighbouring pins overlap",
                    half_pitch * 1e3
                ),
            ));
        }
        Ok(())
    }

    /// Number of disc teeth `Zc = Zp - 1`.
    pub(crate) fn disc_teeth(&self) -> usize {
        self.pins - 1
    }

    /// Short-amplitude coefficient `K1 = a Zp / Rp` (paper eq 4).
    pub(crate) fn k1(&self) -> f64 {
        self.eccentricity * self.pins as f64 / self.pin_circle_radius
    }

    /// Centre of pin `j` in the fixed frame, m (docs/model.md section 1).
    pub(crate) fn pin_centre(&self, j: usize) -> Vec2 {
        let g = TAU * j as f64 / self.pins as f64;
        Vec2::new(
            self.pin_circle_radius * g.cos(),
            self.pin_circle_radius * g.sin(),
        )
    }

    /// A size outside `[cycloid]` that defaults from the stage, mm: the paper's value
    /// `paper_mm` (RV-40E class: crank circle 40.5, crank bore radius 13, pillar holes 22 and
    /// centre hole 30 mm diameter) scaled by the disc's tooth-root radius `Rp - rrp - a`
    /// against the paper's [`PAPER_ROOT_RADIUS_MM`] (geometric similarity with the paper's
    /// reducer; docs/model.md section 15). The paper's geometry gets the paper's values.
    pub(crate) fn scaled_from_root(&self, paper_mm: f64) -> f64 {
        let root_mm = (self.pin_circle_radius - self.pin_radius - self.eccentricity) * 1e3;
        let scaled = paper_mm * root_mm / PAPER_ROOT_RADIUS_MM;
        // The paper's own stage: its values exactly, not their round-off.
        if (root_mm / PAPER_ROOT_RADIUS_MM - 1.0).abs() < 1e-12 {
            paper_mm
        } else {
            scaled
        }
    }

    /// Disc pitch radius `r_c = a Zc`, m: the lever arm scale of Li's method (docs/model.md section 5).
    pub(crate) fn disc_pitch_radius(&self) -> f64 {
        self.eccentricity * self.disc_teeth() as f64
    }
}

/// Tooth-root radius of the paper's disc, mm: `Rp - rrp - a` = 64 - 3 - 1.3.
pub(crate) const PAPER_ROOT_RADIUS_MM: f64 = 59.7;

/// Profile modifications (docs/model.md section 2), SI.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Modification {
    /// Equidistant modification `drrp`, m (positive thins the teeth).
    pub equidistant: f64,
    /// Offset (radial shift) modification `dRp`, m (negative thins the teeth).
    pub offset: f64,
    /// Rotation modification `delta`, rad (counter-clockwise turn of the whole profile).
    pub rotation: f64,
}

mod measured;
mod params;
pub(crate) mod portable;
mod profile;
mod wear_map;

pub(crate) use measured::read_points;
pub use measured::{fit, MeasuredProfile};
pub use params::CycloidParams;
pub use profile::{Profile, ProfilePoint, Projection, ToothTable};
pub(crate) use wear_map::cubic_hermite;
pub use wear_map::WearMap;

/// Grid nodes within half-width `b` (m of arc length) of node `centre`, with the semi-elliptic
/// weight `sqrt(1 - (x/b)^2)` of the Hertz pressure (Johnson, *Contact Mechanics*, 1985,
/// eq 4.43), 1 at the centre; `ds` is the arc length of each step of a periodic grid (m).
pub(crate) fn band_shape(ds: &[f64], centre: usize, b: f64) -> Vec<(usize, f64)> {
    let n = ds.len();
    let mut weights = vec![(centre, 1.0)];
    for dir in [-1isize, 1] {
        let mut dist = 0.0;
        let mut k = centre as isize;
        loop {
            let next = (k + dir).rem_euclid(n as isize);
            dist += 0.5 * (ds[k as usize] + ds[next as usize]);
            if dist >= b || weights.len() >= n {
                break;
            }
            let x = dist / b;
            weights.push((next as usize, (1.0 - x * x).sqrt()));
            k = next;
        }
    }
    weights
}

/// Most entries a [`remembered`] memo keeps (the oldest goes first).
const MEMO_ENTRIES: usize = 8;

/// The value `build` makes for `key`, remembered in `memo` for the last [`MEMO_ENTRIES`] keys
/// of the process: tables that depend on a few numbers of the geometry only, which every
/// profile or gap field of a study shares. A failed build is not remembered; a poisoned lock
/// builds without remembering.
///
/// # Errors
/// Those of `build`.
pub(crate) fn remembered<K: PartialEq, V: Clone, E>(
    memo: &std::sync::Mutex<Vec<(K, V)>>,
    key: K,
    build: impl FnOnce() -> std::result::Result<V, E>,
) -> std::result::Result<V, E> {
    if let Ok(memo) = memo.lock() {
        if let Some((_, v)) = memo.iter().find(|(k, _)| *k == key) {
            return Ok(v.clone());
        }
    }
    let value = build()?;
    if let Ok(mut memo) = memo.lock() {
        if memo.len() >= MEMO_ENTRIES {
            memo.remove(0);
        }
        memo.push((key, value.clone()));
    }
    Ok(value)
}

/// Mesh angle (rad, in `[0, 2 pi)`) of a profile parameter.
pub(crate) fn mesh_angle(t: f64) -> f64 {
    t.rem_euclid(TAU)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn paper_geometry() -> CycloidGeometry {
        CycloidGeometry {
            pins: 40,
            eccentricity: 1.3e-3,
            pin_circle_radius: 64e-3,
            pin_radius: 3e-3,
            width: 8.75e-3,
        }
    }

    #[test]
    fn closed_form_is_offset_of_pin_centre_path() {
        // The profile point at t, moved out by rrp along its normal, is the pin-centre path.
        let prof = Profile::new(paper_geometry(), Modification::default(), None).unwrap();
        for k in 0..997 {
            let t = k as f64 * 0.2357;
            let pt = prof.point(t);
            let (c, _, _) = prof.closed_form(t, 0.0);
            let back = pt.p + pt.normal * 3e-3;
            assert!(
                (back - c).norm() < 1e-15,
                "t = {t}: {:e}",
                (back - c).norm()
            );
        }
    }

    #[test]
    fn profile_tip_and_root_radii() {
        let prof = Profile::new(paper_geometry(), Modification::default(), None).unwrap();
        // Root: Rp - a - rrp; tip: Rp + a - rrp.
        assert!((prof.point(0.0).p.norm() - 59.7e-3).abs() < 1e-15);
        assert!((prof.point(PI).p.norm() - 62.3e-3).abs() < 1e-15);
    }

    #[test]
    fn pin_path_min_radius_matches_notes() {
        let prof = Profile::new(paper_geometry(), Modification::default(), None).unwrap();
        let r = prof.pin_path_min_convex_radius();
        assert!((r - 4.61e-3).abs() < 0.01e-3, "{r}");
    }

    #[test]
    fn undercut_rejected() {
        let mut g = paper_geometry();
        g.pin_radius = 4.8e-3;
        let e = Profile::new(g, Modification::default(), None).unwrap_err();
        assert!(e.to_string().contains("undercut"), "{e}");
    }

    #[test]
    fn k1_at_least_one_rejected() {
        let mut g = paper_geometry();
        g.eccentricity = 1.6e-3;
        let e = Profile::new(g, Modification::default(), None).unwrap_err();
        assert!(e.to_string().contains("K1"), "{e}");
    }

    #[test]
    fn uniform_wear_equals_equidistant_modification() {
        let g = paper_geometry();
        let worn = Profile::new(
            g.clone(),
            Modification::default(),
            Some(WearMap::uniform(64, 10e-6).unwrap()),
        )
        .unwrap();
        let eq = Profile::new(
            g,
            Modification {
                equidistant: 10e-6,
                ..Default::default()
            },
            None,
        )
        .unwrap();
        for k in 0..200 {
            let t = k as f64 * 0.31;
            let a = worn.point(t);
            let b = eq.point(t);
            assert!((a.p - b.p).norm() < 1e-15);
            assert!((a.curvature - b.curvature).abs() < 1e-6 * b.curvature.abs().max(1.0));
        }
    }

    #[test]
    fn wear_map_interpolates_nodes_and_is_periodic() {
        let d: Vec<f64> = (0..36)
            .map(|m| (m as f64 * 0.3).sin().abs() * 1e-5)
            .collect();
        let w = WearMap::new(d.clone()).unwrap();
        for (m, &v) in d.iter().enumerate() {
            let t = TAU * m as f64 / 36.0;
            assert!((w.eval(t).0 - v).abs() < 1e-18);
            assert!((w.eval(t + TAU).0 - v).abs() < 1e-18);
        }
    }
}
