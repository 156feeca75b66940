//! Cycloid disc profile: closed form with modifications, wear maps, curvature, closest points.
//!
//! Conventions (physics-notes sections 2 and 3), all SI (metres, radians):
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
//!   tooth, stored on a uniform grid of mesh angles and interpolated with a periodic monotone
//!   cubic (C1, so closest-point searches see a continuous tangent; no overshoot).

use std::f64::consts::{PI, TAU};

use nalgebra::{Complex, Vector2};

use crate::error::{Error, Result};

/// A 2D point or vector in metres.
pub type Vec2 = Vector2<f64>;

/// z-component of the cross product `a x b`.
#[inline]
pub fn cross(a: &Vec2, b: &Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Rotates `v` by `angle` (radians, counter-clockwise).
#[inline]
pub fn rotate(v: &Vec2, angle: f64) -> Vec2 {
    let (s, c) = angle.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Nominal geometry of the cycloid stage (SI units).
///
/// Source: paper Table 1 for the example values; physics-notes section 2 for the constraints.
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
    pub fn disc_teeth(&self) -> usize {
        self.pins - 1
    }

    /// Short-amplitude coefficient `K1 = a Zp / Rp` (paper eq 4).
    pub fn k1(&self) -> f64 {
        self.eccentricity * self.pins as f64 / self.pin_circle_radius
    }

    /// Centre of pin `j` in the fixed frame, m (physics-notes section 3).
    pub fn pin_centre(&self, j: usize) -> Vec2 {
        let g = TAU * j as f64 / self.pins as f64;
        Vec2::new(
            self.pin_circle_radius * g.cos(),
            self.pin_circle_radius * g.sin(),
        )
    }

    /// Disc pitch radius `r_c = a Zc`, m: the lever arm scale of Li's method (physics-notes 4).
    pub fn disc_pitch_radius(&self) -> f64 {
        self.eccentricity * self.disc_teeth() as f64
    }
}

/// Profile modifications (physics-notes section 2), SI.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Modification {
    /// Equidistant modification `drrp`, m (positive thins the teeth).
    pub equidistant: f64,
    /// Offset (radial shift) modification `dRp`, m (negative thins the teeth).
    pub offset: f64,
    /// Rotation modification `delta`, rad (counter-clockwise turn of the whole profile).
    pub rotation: f64,
}

/// Wear depth along the inward profile normal as a function of mesh angle, identical on every
/// tooth. Uniform grid of `n` mesh angles `t_m = 2 pi m / n`, depths in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct WearMap {
    depth: Vec<f64>,
    /// Node slopes of the monotone cubic, per grid step (derived from `depth`).
    slope: Vec<f64>,
}

impl WearMap {
    /// A map from depths on a uniform mesh-angle grid (`depth[m]` at `t = 2 pi m / n`), m.
    ///
    /// # Errors
    /// [`Error::Invalid`] if fewer than 4 points or a depth is negative or not finite.
    pub fn new(depth: Vec<f64>) -> Result<Self> {
        if depth.len() < 4 {
            return Err(Error::invalid(
                "wear map",
                format!("{} points", depth.len()),
                "needs at least 4 points per tooth",
            ));
        }
        if let Some((m, v)) = depth
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite() || **v < 0.0)
        {
            return Err(Error::invalid(
                format!("wear map point {m}"),
                v,
                "wear depth must be finite and >= 0",
            ));
        }
        let n = depth.len();
        // Node slopes by the harmonic mean of the neighbouring secants (zero at extrema).
        let slope = (0..n)
            .map(|i| {
                let a = depth[i] - depth[(i + n - 1) % n];
                let b = depth[(i + 1) % n] - depth[i];
                if a * b <= 0.0 {
                    0.0
                } else {
                    2.0 * a * b / (a + b)
                }
            })
            .collect();
        Ok(WearMap { depth, slope })
    }

    /// Uniform depth `h` (m) on `n` points: the paper's conservative wear model (uniform
    /// equidistant offset by the maximum wear, paper section 3.1).
    pub fn uniform(n: usize, h: f64) -> Result<Self> {
        Self::new(vec![h; n.max(4)])
    }

    /// Depths on the grid, m.
    pub fn depths(&self) -> &[f64] {
        &self.depth
    }

    /// Mesh angles of the grid, rad.
    pub fn angles(&self) -> Vec<f64> {
        let n = self.depth.len() as f64;
        (0..self.depth.len()).map(|m| TAU * m as f64 / n).collect()
    }

    /// Largest depth, m.
    pub fn max_depth(&self) -> f64 {
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

    /// Depth `h` (m) and its derivative `dh/dt` (m/rad) at mesh angle `t` (any real; wrapped).
    ///
    /// Periodic monotone cubic Hermite interpolation (Fritsch and Carlson, SIAM J. Numer. Anal.
    /// 17, 1980): C1, and never below the smaller neighbouring node, so a map of non-negative
    /// depths never adds material.
    pub fn eval(&self, t: f64) -> (f64, f64) {
        let (h, dh, _) = self.eval2(t);
        (h, dh)
    }

    /// Depth (m), `dh/dt` (m/rad) and `d2h/dt2` (m/rad^2, piecewise linear) at mesh angle `t`.
    pub fn eval2(&self, t: f64) -> (f64, f64, f64) {
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

/// One evaluated point of a profile, in the disc frame.
#[derive(Debug, Clone, Copy)]
pub struct ProfilePoint {
    /// Profile parameter `t`, rad (global; `t mod 2 pi` is the mesh angle).
    pub t: f64,
    /// Position, m.
    pub p: Vec2,
    /// `dp/dt`, m/rad.
    pub dp: Vec2,
    /// Outward unit normal (pointing out of the disc material, towards the pins).
    pub normal: Vec2,
    /// Curvature, 1/m: positive where the profile is convex (tooth tip), negative where concave.
    pub curvature: f64,
}

impl ProfilePoint {
    /// The point at parameter `t` from the position and its first two derivatives in `t`
    /// (clockwise parametrisation: the outward normal is the tangent turned by +90 degrees).
    fn from_derivatives(t: f64, p: Vec2, dp: Vec2, ddp: Vec2) -> Self {
        let speed = dp.norm();
        let tangent = dp / speed;
        ProfilePoint {
            t,
            p,
            dp,
            normal: Vec2::new(-tangent.y, tangent.x),
            curvature: -cross(&dp, &ddp) / speed.powi(3),
        }
    }
}

/// Where a point lies relative to a profile: the closest profile point and the signed distance.
#[derive(Debug, Clone, Copy)]
pub struct Projection {
    /// The closest point on the profile.
    pub point: ProfilePoint,
    /// Signed distance from the profile, m: positive outside the disc material.
    pub distance: f64,
}

/// The actual disc profile: nominal geometry, modifications and an optional wear map.
#[derive(Debug, Clone)]
pub struct Profile {
    geo: CycloidGeometry,
    modification: Modification,
    wear: Option<WearMap>,
    zc: f64,
    k1: f64,
    rp_mod: f64,
    r_mod: f64,
    alpha: f64,
    beta: f64,
    /// Mesh-angle intervals (rad, within one tooth) where the worn flank is concave with a radius
    /// below 1.02 pin radii and deeper than the pin can reach by more than 1 nm: only there can a
    /// pin meet the flank at two points.
    dents: Vec<(f64, f64)>,
    /// Deepest of the dents beyond the pin's reach, m.
    dent_depth: f64,
}

impl Profile {
    /// Builds and checks a profile.
    ///
    /// # Errors
    /// [`Error::Invalid`] if the geometry is invalid (see [`CycloidGeometry::validate`]), if the
    /// modified profile is undercut (loops where `rrp + drrp` exceeds the local convex radius of
    /// the pin-centre path), or if the wear map is deeper than the local convex radius.
    pub fn new(
        geo: CycloidGeometry,
        modification: Modification,
        wear: Option<WearMap>,
    ) -> Result<Self> {
        geo.validate()?;
        for (field, v) in [
            (
                "cycloid.modification.equidistant_mm",
                modification.equidistant * 1e3,
            ),
            ("cycloid.modification.offset_mm", modification.offset * 1e3),
            (
                "cycloid.modification.rotation_deg",
                modification.rotation.to_degrees(),
            ),
        ] {
            if !v.is_finite() {
                return Err(Error::invalid(field, v, "must be a finite number"));
            }
        }
        let zc = geo.disc_teeth() as f64;
        let zp = geo.pins as f64;
        let rp_mod = geo.pin_circle_radius + modification.offset;
        let r_mod = geo.pin_radius + modification.equidistant;
        if r_mod <= 0.0 {
            return Err(Error::invalid(
                "cycloid.modification.equidistant_mm",
                modification.equidistant * 1e3,
                format!(
                    "must be greater than minus the pin radius ({:.4} mm)",
                    -geo.pin_radius * 1e3
                ),
            ));
        }
        if rp_mod <= geo.eccentricity + r_mod {
            return Err(Error::invalid(
                "cycloid.modification.offset_mm",
                modification.offset * 1e3,
                "leaves no disc: pin circle radius + offset must exceed eccentricity + pin radius",
            ));
        }
        let profile = Profile {
            k1: geo.k1(),
            geo,
            modification,
            wear,
            zc,
            rp_mod,
            r_mod,
            alpha: 1.0 - zp / zc,
            beta: zp / zc,
            dents: Vec::new(),
            dent_depth: 0.0,
        };
        let mut profile = profile;
        profile.check_undercut()?;
        (profile.dents, profile.dent_depth) = profile.find_dents();
        Ok(profile)
    }

    /// The nominal geometry.
    pub fn geometry(&self) -> &CycloidGeometry {
        &self.geo
    }

    /// The modifications.
    pub fn modification(&self) -> &Modification {
        &self.modification
    }

    /// The wear map, if any.
    pub fn wear(&self) -> Option<&WearMap> {
        self.wear.as_ref()
    }

    /// The same modified profile with another wear map.
    pub fn with_wear(&self, wear: Option<WearMap>) -> Result<Self> {
        Profile::new(self.geo.clone(), self.modification, wear)
    }

    /// Closed form (paper eq 24) and its first two derivatives in `t`, without wear, for a
    /// given offset radius `r` (the equidistant radius `rrp'`; `r = 0` gives the pin-centre path).
    fn closed_form(&self, t: f64, r: f64) -> (Vec2, Vec2, Vec2) {
        let k1 = self.k1;
        let (st, ct) = t.sin_cos();
        let s2 = 1.0 + k1 * k1 - 2.0 * k1 * ct;
        let s = s2.sqrt();
        let s3 = s2 * s;
        let s5 = s3 * s2;
        // u = 1/S and its derivatives.
        let u = 1.0 / s;
        let du = -k1 * st / s3;
        let ddu = -k1 * ct / s3 + 3.0 * k1 * k1 * st * st / s5;
        let a = self.rp_mod - r * u;
        let da = -r * du;
        let dda = -r * ddu;
        let b = self.geo.eccentricity - k1 * r * u;
        let db = -k1 * r * du;
        let ddb = -k1 * r * ddu;
        let (al, be) = (self.alpha, self.beta);
        // alpha = 1 - beta, so e^{i(alpha t + delta)} = e^{it} e^{i(-beta t + delta)}.
        let e2 = Complex::from_polar(1.0, -be * t + self.modification.rotation);
        let e1 = Complex::new(ct, st) * e2;
        let i = Complex::new(0.0, 1.0);
        let z = e1 * a - e2 * b;
        let dz = e1 * (da + i * (al * a)) - e2 * (db - i * (be * b));
        let ddz = e1 * (dda + i * (2.0 * al * da) - al * al * a)
            - e2 * (ddb - i * (2.0 * be * db) - be * be * b);
        (
            Vec2::new(z.re, z.im),
            Vec2::new(dz.re, dz.im),
            Vec2::new(ddz.re, ddz.im),
        )
    }

    /// Position and exact tangent `dp/dt` of the actual (worn) profile, plus an approximate
    /// second derivative (wear-map terms dropped) good enough for Newton steps.
    fn eval_d1(&self, t: f64) -> (Vec2, Vec2, Vec2) {
        let (p, dp, ddp) = self.closed_form(t, self.r_mod);
        match &self.wear {
            None => (p, dp, ddp),
            Some(w) => {
                let (h, dh, ddh) = w.eval2(t);
                let speed = dp.norm();
                let tangent = dp / speed;
                let normal = Vec2::new(-tangent.y, tangent.x);
                let k = -cross(&dp, &ddp) / speed.powi(3);
                // Worn point moved inward by h along the normal; dn/dt = k dp/dt.
                let pw = p - normal * h;
                let dpw = dp * (1.0 - h * k) - normal * dh;
                // d2/dt2 of p - h n with dn/dt = k dp/dt; the dk/dt term (h k' ~ 1e-2 |dp|) is
                // dropped: this derivative only steers Newton steps.
                let ddpw = ddp * (1.0 - h * k) - dp * (2.0 * dh * k) - normal * ddh;
                (pw, dpw, ddpw)
            }
        }
    }

    /// Evaluates the actual profile at parameter `t` (rad): position, tangent, outward normal and
    /// curvature (exact for the closed form; for a worn profile the curvature uses a central
    /// difference of the exact tangent with a step of 1e-5 rad).
    pub fn point(&self, t: f64) -> ProfilePoint {
        let (p, dp, ddp_exact) = self.eval_d1(t);
        let ddp = if self.wear.is_some() {
            let e = 1e-5;
            (self.eval_d1(t + e).1 - self.eval_d1(t - e).1) / (2.0 * e)
        } else {
            ddp_exact
        };
        ProfilePoint::from_derivatives(t, p, dp, ddp)
    }

    /// Like [`Profile::point`] but, for a worn profile, with the curvature from the analytic
    /// second derivative of [`Profile::eval_d1`] (the wear map's own second derivative included,
    /// the drift of the flank curvature along the wear left out), which skips the finite
    /// difference.
    fn point_approx(&self, t: f64) -> ProfilePoint {
        let (p, dp, ddp) = self.eval_d1(t);
        ProfilePoint::from_derivatives(t, p, dp, ddp)
    }

    /// Curvature (1/m, positive convex) of the modified profile without wear at parameter `t`:
    /// the macro-geometry that sets the Hertz contact. Wear changes depths by microns over
    /// millimetres of flank; the curvature of the wear map itself is grid-scale roughness finer
    /// than the contact band and is left out of the contact law.
    pub fn macro_curvature(&self, t: f64) -> f64 {
        let (_, dp, ddp) = self.closed_form(t, self.r_mod);
        -cross(&dp, &ddp) / dp.norm().powi(3)
    }

    /// Closest point of the profile to `q` (disc frame, m), searched by Newton's method from
    /// parameter `t0`, which must lie within about a quarter tooth of the answer.
    ///
    /// # Errors
    /// [`Error::Numerical`] if Newton's method does not converge in 50 steps.
    pub fn project(&self, q: &Vec2, t0: f64) -> Result<Projection> {
        // Work on the tooth of t0 turned to tooth 0: z(t + 2 pi k) = z(t) e^{-2 pi i k / Zc}.
        let k = (t0 / TAU).floor();
        let turn = TAU * k / self.zc;
        let ql = rotate(q, turn);
        let tl = t0 - TAU * k;
        let first = self.newton_foot(&ql, tl);
        let dist2 = |t: f64| (self.eval_d1(t).0 - ql).norm_squared();
        // Near a wear dent the distance can have several local minima (a pin bridging the dent),
        // which differ by less than the dent depth: look for them only for pins within the
        // deepest dent (plus 0.1 um) of touching, or when Newton failed, by starting Newton from
        // the dent edges.
        let r = self.geo.pin_radius;
        let gate = self.dent_depth + 1e-7;
        let near_contact = first.is_none_or(|t| dist2(t).sqrt() - r < gate);
        let mut best = first.map(|t| (dist2(t), t));
        let centre = first.unwrap_or(tl);
        const WINDOW: f64 = 0.08;
        if near_contact && self.near_dent(centre, WINDOW) {
            // Sample the distance densely over the window (about 4.6 degrees of mesh angle,
            // 0.33 degree apart, finer than the dents) and polish every local minimum of the samples with Newton, so
            // that the gap is the nearest foot whatever the starting guess.
            let n = 28;
            let h = 2.0 * WINDOW / n as f64;
            let samples: Vec<(f64, f64)> = (0..=n)
                .map(|i| {
                    let ti = centre - WINDOW + h * i as f64;
                    (ti, dist2(ti))
                })
                .collect();
            for w in samples.windows(3) {
                if w[1].1 <= w[0].1 && w[1].1 <= w[2].1 {
                    let tc = self
                        .newton_foot(&ql, w[1].0)
                        .filter(|tc| (tc - w[1].0).abs() <= h);
                    let (d, tc) = match tc {
                        Some(tc) => (dist2(tc), tc),
                        None => (w[1].1, w[1].0),
                    };
                    if best.is_none_or(|(b, _)| d < b - 1e-24) {
                        best = Some((d, tc));
                    }
                }
            }
        }
        let t = match best {
            Some((_, t)) => t,
            None => self.bracketed_foot(&ql, tl)?,
        };
        let mut point = self.point_approx(t);
        let distance = (ql - point.p).dot(&point.normal);
        point.t = t + TAU * k;
        point.p = rotate(&point.p, -turn);
        point.dp = rotate(&point.dp, -turn);
        point.normal = rotate(&point.normal, -turn);
        Ok(Projection { point, distance })
    }

    /// The dent zones and the deepest of them beyond the pin's reach (m, 0 without dents): the
    /// largest amount by which a local foot of the normal can overestimate a gap.
    fn find_dents(&self) -> (Vec<(f64, f64)>, f64) {
        let Some(w) = &self.wear else {
            return (Vec::new(), 0.0);
        };
        let n = 4 * w.depths().len();
        let limit = -1.0 / (1.02 * self.geo.pin_radius);
        let dt = TAU / n as f64;
        let mut zones: Vec<(f64, f64)> = Vec::new();
        for i in 0..n {
            let t = i as f64 * dt;
            // Curvature of the worn flank from the analytic derivatives (the wear map's
            // second derivative included, the drift of the flank curvature along it left out).
            if self.point_approx(t).curvature < limit {
                let (lo, hi) = (t - dt, t + dt);
                match zones.last_mut() {
                    Some(last) if last.1 >= lo => last.1 = hi,
                    _ => zones.push((lo, hi)),
                }
            }
        }
        // Depth of each zone below its chord beyond the pin's sagitta over that chord. Keep only
        // dents deeper than 1 nm beyond what the pin can reach: shallower ones change a gap by
        // less than a nanometre, far below any contact approach.
        let r = self.geo.pin_radius;
        let mut deepest: f64 = 0.0;
        zones.retain(|&(lo, hi)| {
            let (a, b) = (self.eval_d1(lo).0, self.eval_d1(hi).0);
            let c = (b - a).norm();
            let dir = (b - a) / c.max(1e-300);
            let depth = (0..=16)
                .map(|i| {
                    let p = self.eval_d1(lo + (hi - lo) * i as f64 / 16.0).0;
                    cross(&dir, &(p - a)).abs()
                })
                .fold(0.0, f64::max);
            let excess = depth - (r - (r * r - 0.25 * c * c).max(0.0).sqrt());
            deepest = deepest.max(excess);
            c == 0.0 || c >= 2.0 * r || excess > 1e-9
        });
        (zones, deepest)
    }

    /// Mesh-angle intervals (rad) where the worn flank is concave with a radius below 1.02 pin
    /// radii (wear dents a pin cannot enter), where closest points are searched globally.
    pub fn dent_zones(&self) -> &[(f64, f64)] {
        &self.dents
    }

    /// True if a dent zone meets the mesh-angle window `[t - w, t + w]` (`t` any parameter).
    fn near_dent(&self, t: f64, w: f64) -> bool {
        let m = mesh_angle(t);
        self.dents.iter().any(|&(lo, hi)| {
            [-TAU, 0.0, TAU]
                .iter()
                .any(|off| hi + off >= m - w && lo + off <= m + w)
        })
    }

    /// Newton's method for the foot of the normal from `q`, with gradient steps where the
    /// distance is not convex (a pin near the centre of a concave root); `None` if it does not
    /// settle in 30 steps.
    ///
    fn newton_foot(&self, q: &Vec2, t0: f64) -> Option<f64> {
        // Converged when the step is below 1e-10 rad: the foot moves by ~1e-13 m along the
        // flank and the distance by (1e-13 m)^2 / rho, nothing. The wear map's second derivative
        // jumps at its nodes, where Newton can settle into a tiny two-cycle: accept that too.
        let mut t = t0;
        let mut last = f64::INFINITY;
        for _ in 0..30 {
            let (p, dp, ddp) = self.eval_d1(t);
            let d = p - q;
            let f = d.dot(&dp);
            let g = dp.norm_squared();
            let mut fp = g + d.dot(&ddp);
            if fp <= 1e-6 * g {
                fp = g;
            }
            let step = f / fp;
            if step.abs() > 0.3 {
                return None;
            }
            t -= step;
            last = step.abs();
            // Or when the distance no longer changes: |d D| = |f dt| with D = |p - q|^2 / 2, so
            // the distance moves by |f dt| / |p - q| < 1e-15 m (a pin in a worn, conformal root
            // where the foot is ill-defined but the gap is not).
            if last < 1e-10 || (f * step).abs() < 1e-15 * d.norm() {
                return Some(t);
            }
        }
        (last < 1e-8).then_some(t)
    }

    /// Robust fallback: the nearest of 25 samples over +-0.1 rad around `t0`, refined by
    /// golden-section search (argmin `GoldenSectionSearch`) on the distance between its
    /// neighbours.
    fn bracketed_foot(&self, q: &Vec2, t0: f64) -> Result<f64> {
        use argmin::core::{CostFunction, Executor};
        use argmin::solver::goldensectionsearch::GoldenSectionSearch;
        struct Dist<'a>(&'a Profile, Vec2);
        impl CostFunction for Dist<'_> {
            type Param = f64;
            type Output = f64;
            fn cost(&self, t: &f64) -> std::result::Result<f64, argmin::core::Error> {
                Ok((self.0.eval_d1(*t).0 - self.1).norm_squared())
            }
        }
        let (w, n) = (0.1, 24);
        let h = 2.0 * w / n as f64;
        let best = (0..=n)
            .map(|i| t0 - w + h * i as f64)
            .min_by(|a, b| {
                let da = (self.eval_d1(*a).0 - q).norm_squared();
                let db = (self.eval_d1(*b).0 - q).norm_squared();
                da.total_cmp(&db)
            })
            .unwrap_or(t0);
        if let Some(t) = self.newton_foot(q, best) {
            if (t - best).abs() <= h {
                return Ok(t);
            }
        }
        let solver = GoldenSectionSearch::new(best - h, best + h)
            .and_then(|s| s.with_tolerance(1e-10))
            .map_err(|e| Error::numerical("profile projection", e.to_string()))?;
        let res = Executor::new(Dist(self, *q), solver)
            .configure(|s| s.param(best).max_iters(200))
            .timer(false)
            .run()
            .map_err(|e| Error::numerical("profile projection", e.to_string()))?;
        res.state
            .best_param
            .ok_or_else(|| Error::numerical("profile projection", "no closest point found"))
    }

    /// Samples the closed profile: `points_per_tooth` points per tooth, `Zc` teeth, in the
    /// direction of increasing `t` (clockwise). Returns positions in metres.
    pub fn sample(&self, points_per_tooth: usize) -> Vec<Vec2> {
        let n = points_per_tooth.max(8) * self.geo.disc_teeth();
        let dt = TAU * self.zc / n as f64;
        (0..n).map(|k| self.eval_d1(k as f64 * dt).0).collect()
    }

    /// Smallest convex radius of curvature of the pin-centre path (m), over one tooth.
    /// The profile is undercut when `rrp + drrp` exceeds it (physics-notes section 2: about
    /// 4.61 mm for the paper's stage).
    pub fn pin_path_min_convex_radius(&self) -> f64 {
        let n = 4000;
        (0..n)
            .map(|k| {
                let t = TAU * k as f64 / n as f64;
                let (_, dp, ddp) = self.closed_form(t, 0.0);
                -cross(&dp, &ddp) / dp.norm().powi(3)
            })
            .filter(|k| *k > 0.0)
            .map(|k| 1.0 / k)
            .fold(f64::INFINITY, f64::min)
    }

    fn check_undercut(&self) -> Result<()> {
        let n = 2000;
        for k in 0..n {
            let t = TAU * k as f64 / n as f64;
            let (_, dp, ddp) = self.closed_form(t, self.r_mod);
            let (_, dpath, _) = self.closed_form(t, 0.0);
            if dp.dot(&dpath) <= 0.0 {
                return Err(Error::invalid(
                    "cycloid.pin_radius_mm + cycloid.modification.equidistant_mm",
                    format!("{:.4} mm", self.r_mod * 1e3),
                    format!(
                        "the profile is undercut: the equidistant radius must stay below the \
                         smallest convex radius of the pin-centre path, {:.4} mm",
                        self.pin_path_min_convex_radius() * 1e3
                    ),
                ));
            }
            if let Some(w) = &self.wear {
                let (h, dh) = w.eval(t);
                let kk = -cross(&dp, &ddp) / dp.norm().powi(3);
                let normal = Vec2::new(-dp.y, dp.x) / dp.norm();
                let dpw = dp * (1.0 - h * kk) - normal * dh;
                if dpw.dot(&dp) <= 0.0 {
                    return Err(Error::invalid(
                        "wear map",
                        format!("{:.2} um at mesh angle {:.2} deg", h * 1e6, t.to_degrees()),
                        "the worn profile folds over itself: wear deeper than the local convex \
                         radius or too steep along the profile",
                    ));
                }
            }
        }
        Ok(())
    }

    /// Initial guess of the profile parameter at which pin `j` touches the disc, for the disc
    /// centre at `a (cos phi, sin phi)` turned by `psi` (rad, counter-clockwise).
    ///
    /// For the unmodified stage with `psi = -phi / Zc` this is exact:
    /// `t_j = -phi - 2 pi j Zc / Zp` (mesh angle `2 pi j / Zp - phi` modulo `2 pi`).
    pub fn contact_parameter_guess(&self, j: usize, phi: f64, psi: f64) -> f64 {
        let zp = self.geo.pins as f64;
        let extra = psi + phi / self.zc + self.modification.rotation;
        -phi - TAU * j as f64 * self.zc / zp + self.zc * extra
    }
}

/// Mesh angle (rad, in `[0, 2 pi)`) of a profile parameter.
pub fn mesh_angle(t: f64) -> f64 {
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
