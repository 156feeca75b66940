//! The disc-pin gap as a smooth field over the plane of the disc, tabulated once per profile
//! from the exact closest-point projection of `Profile::project`.
//!
//! A pin centre `q` (profile frame, m) is located by polar-like coordinates attached to the
//! nominal pin-centre path `C(t) = Rp e^{i(1 - Zp/Zc) t} - a e^{-i (Zp/Zc) t}` (paper eq 24 with
//! `rrp = 0`): the path parameter `t` whose point has the same polar angle as `q`, and the radial
//! offset `rho = |q| - |C(t)|`. Because `arg C(t) = -t/Zc + atan2(a sin t, Rp - a cos t)` is
//! strictly monotone (`a Zc < Rp - a`, i.e. `K1 < 1`), `t(q)` is unique and smooth, and
//! `|C(t)| = sqrt(Rp^2 + a^2 - 2 a Rp cos t)` is closed form. `t` and `|C(t)|` depend on the
//! polar angle of `q` only and are tabulated once per geometry against the slope of `q` in the
//! frame of its tooth (`PathAngleTable`, within 2e-11 rad and 1e-13 m), so an evaluation needs
//! no `atan2` and no `sin_cos`.
//!
//! Along each radial line the gap (distance from the actual profile minus the pin radius) is
//! linear to within `(rho - rho_0)^2 / (2 R)` (R: local radius of curvature, >= 4.6 mm for the
//! paper's stage); the table stores, per mesh angle, the touching offset `rho_0` (where the gap
//! is zero) and the radial slope `s` there (the radial component of the flank normal), both from
//! exact projections: `gap(t, rho) = s(t mod 2 pi) (rho - rho_0(t mod 2 pi))`. Within 2 um of
//! contact, where the impact force acts, the error is below 2 nm (tested); further out it
//! stays within a few per cent of the gap, and only the sign matters there.
//! `rho_0` and `s` are periodic cubic Hermite splines (C1), and `GapField::eval` returns the exact
//! gradient of this interpolant, so contact forces derived from it conserve energy. The field is
//! the contact geometry of both analyses of the reducer model (static and dynamic).
//!
//! **Contact bands.** A loaded pin meets the flank over its Hertz band, whose width grows with
//! its force (0.03 mm at 13 N, 0.5 mm at 4 kN on the example's worn root). The analyses see the
//! worn flank through a band ([`Band`]):
//! - single: the flank averaged over the band of one force (Li's largest pin force at
//!   the rated torque). On the example's 7500 h disc this lets pins of 13-430 N near the wear
//!   peak reach up to 0.40 um further into the exact flank than a non-Hertzian line contact on
//!   it allows (`crate::contact::elastic`): their contacts are far narrower than the band.
//! - envelope (default): the upper envelope of the flank averaged over a narrow band (`NARROW_BAND` of
//!   the force: the contacts at the lost-motion measuring torque) and over the band. A concave
//!   feature narrower than the wide band (a valley of the worn flank) is bridged, as a loaded
//!   contact bridges it, while a convex one (a ridge, the shoulder of a wear scar) keeps the
//!   height it has at the narrow band, where a wide average lets the pin sink into the shoulder
//!   that carries it. Every pin of the static analysis's fine scan then stays within 5 % of the
//!   law's approach plus 0.1 um of the elastic contact on the exact flank, at 0, 1250 and
//!   7500 h, and the worn-disc results barely depend on the band force. A disc can move onto
//!   other pins part of the way up the load (on the example's 6250 h disc at crank angle 3 deg
//!   the two root pins carry everything up to 295 N m and 21 pins from 300 N m), which the
//!   static analysis follows in load steps.
//!
//! Both averages smooth the exact flank below their own scale (near-conformal roots, where the
//! exact closest point jumps between feet nanometres apart in distance).

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use crate::contact::ContactModel;
use crate::error::Result;
use nalgebra::Matrix2;

use crate::geometry::{band_shape, cubic_hermite, Profile, Vec2};

/// Periodic cubic Hermite spline on a uniform grid over `[0, 2 pi)` with central-difference
/// (Catmull-Rom) node slopes: C1, exact for quadratics away from nothing (periodic).
#[derive(Debug, Clone)]
struct PeriodicSpline {
    value: Vec<f64>,
    /// Node slopes per grid step.
    slope: Vec<f64>,
    inv_dt: f64,
}

impl PeriodicSpline {
    fn new(value: Vec<f64>) -> Self {
        let n = value.len();
        let slope = (0..n)
            .map(|i| 0.5 * (value[(i + 1) % n] - value[(i + n - 1) % n]))
            .collect();
        PeriodicSpline {
            value,
            slope,
            inv_dt: n as f64 / TAU,
        }
    }

    /// The nodes `i`, `j` of the cell holding `t` (any real, wrapped) and the position `u` in
    /// `[0, 1)` within it.
    #[inline]
    fn locate(&self, t: f64) -> (usize, usize, f64) {
        let n = self.value.len();
        let s = t * self.inv_dt;
        let k = s.floor();
        // k mod n, by a mask where n is a power of two (the default node counts).
        let i = if n.is_power_of_two() {
            (k as i64 as usize) & (n - 1)
        } else {
            (k as i64).rem_euclid(n as i64) as usize
        };
        let j = if i + 1 == n { 0 } else { i + 1 };
        (i, j, s - k)
    }

    /// The cell holding `t` (any real, wrapped): its node values and slopes `(p1, m1, p2, m2)`
    /// and the position `u` in `[0, 1)` within it.
    #[inline]
    fn cell(&self, t: f64) -> ((f64, f64, f64, f64), f64) {
        let (i, j, u) = self.locate(t);
        (
            (self.value[i], self.slope[i], self.value[j], self.slope[j]),
            u,
        )
    }

    /// Values and derivatives (per radian) of three splines on one grid (the same node count)
    /// at `t` (any real, wrapped), the cell found once.
    #[inline]
    fn eval3(splines: [&PeriodicSpline; 3], t: f64) -> ([f64; 3], [f64; 3]) {
        let (i, j, u) = splines[0].locate(t);
        debug_assert!(splines
            .iter()
            .all(|x| x.value.len() == splines[0].value.len()));
        let (mut v, mut d) = ([0.0; 3], [0.0; 3]);
        for (x, sp) in splines.iter().enumerate() {
            let (a, b) = cubic_hermite(sp.value[i], sp.slope[i], sp.value[j], sp.slope[j], u);
            v[x] = a;
            d[x] = b * sp.inv_dt;
        }
        (v, d)
    }

    /// Value, first and second derivative (per radian) at `t` (the second derivative of the
    /// cubic within the cell holding `t`).
    #[inline]
    fn eval2(&self, t: f64) -> (f64, f64, f64) {
        let ((p1, m1, p2, m2), u) = self.cell(t);
        let (v, d) = cubic_hermite(p1, m1, p2, m2, u);
        let dd = (12.0 * u - 6.0) * (p1 - p2) + (6.0 * u - 4.0) * m1 + (6.0 * u - 2.0) * m2;
        (v, d * self.inv_dt, dd * self.inv_dt * self.inv_dt)
    }
}

/// The narrow contact band of an envelope [`Band`] as a fraction of its force: a sixteenth, a
/// quarter of the half-width (Li's largest force at 3 % of the rated torque is about a
/// thirtieth of that at the rated torque).
pub(crate) const NARROW_BAND: f64 = 1.0 / 16.0;

/// The offset and slope tables (`n` nodes over one tooth, arc steps `ds` from [`Profile::arc_steps`])
/// averaged over the Hertz band of `force` (N) on the unworn flank at each node: the
/// semi-elliptic average over `+-b` of arc length, applied twice.
fn band_average(
    profile: &Profile,
    contact: &ContactModel,
    force: f64,
    ds: &[f64],
    offset: &[f64],
    slope: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let n = offset.len();
    let dt = TAU / n as f64;
    let weights: Vec<Vec<(usize, f64)>> = (0..n)
        .into_par_iter()
        .with_min_len(128)
        .map(|i| {
            let b = contact
                .hertz(force, profile.macro_curvature(i as f64 * dt))
                .half_width;
            let w = band_shape(ds, i, b);
            let total: f64 = w.iter().map(|&(k, x)| x * ds[k]).sum();
            w.iter().map(|&(k, x)| (k, x * ds[k] / total)).collect()
        })
        .collect();
    let pass = |v: &[f64]| -> Vec<f64> {
        weights
            .par_iter()
            .with_min_len(128)
            .map(|w| w.iter().map(|&(k, x)| x * v[k]).sum())
            .collect()
    };
    (pass(&pass(offset)), pass(&pass(slope)))
}

/// How a [`GapField`] sees the worn flank through the contact band.
#[derive(Debug, Clone, Copy)]
pub struct Band<'c> {
    /// The contact law (Hertz half-widths).
    pub contact: &'c ContactModel,
    /// Band force, N.
    pub force: f64,
    /// `false`: the flank averaged over the band of `force`; `true`: the upper envelope of the
    /// flank averaged over the bands of `NARROW_BAND` times `force` and of `force`.
    pub envelope: bool,
}

/// Gap of one pin: value and gradient.
#[derive(Debug, Clone, Copy)]
pub struct GapEval {
    /// Gap between pin surface and disc flank, m (negative: penetration).
    pub gap: f64,
    /// Gradient of the gap with respect to the pin centre in the profile frame (unitless; about
    /// the outward flank normal).
    pub grad: Vec2,
    /// Flank curvature for the contact law at this mesh angle, 1/m.
    pub curvature: f64,
    /// Gradient of that curvature with respect to the pin centre in the profile frame, 1/m^2.
    pub curvature_grad: Vec2,
}

/// The tabulated gap field of one disc profile (see the module docs).
#[derive(Debug, Clone)]
pub struct GapField {
    a: f64,
    rp: f64,
    zc: f64,
    /// Touching offset `rho_0` (m) per mesh angle.
    offset: PeriodicSpline,
    /// Radial slope `s` of the gap at touching per mesh angle.
    slope: PeriodicSpline,
    /// Flank curvature of the contact law at the touching foot per mesh angle, 1/m.
    curvature: PeriodicSpline,
    /// The path parameter as a function of the polar angle (`None`: Newton's method at every
    /// evaluation, where no table up to [`PathAngleTable::MAX_NODES`] nodes meets its
    /// tolerance).
    angle: Option<std::sync::Arc<PathAngleTable>>,
    /// Per mesh angle, before any band average: the touching offset (m), the slope and the
    /// curvature (1/m), and the touching foot's profile parameter (rad), for
    /// [`GapField::new_after`].
    nodes: std::sync::Arc<Vec<Node>>,
}

/// One node of a [`GapField`] before any band average: `((offset, slope, curvature), foot)`,
/// the touching offset (m), the slope, the contact law's curvature (1/m) and the touching
/// foot's profile parameter (rad).
type Node = ((f64, f64, f64), f64);

/// Largest amount (m) by which a worn flank may stand out of the one before it for
/// [`GapField::new_after`] to keep the touching nodes the two share: wear only removes
/// material, but the wear map's spline undershoots where the wear of one step starts (up to
/// 1.7 nm in the example's integration to 75 000 h). A node kept then differs from the node
/// found afresh only where another foot lay within that of its own, as at the near-conformal
/// roots, whose flank both band averages smooth anyway (module docs).
const RECEDE_TOLERANCE: f64 = 5e-9;

/// The path parameter `t` and the path radius `|C(t)|` of a pin centre `q` (module docs),
/// tabulated in the disc frame without an angle: `q` is turned back by the whole teeth its
/// guess names (`k = round(-t_guess / 2 pi)` teeth of `2 pi / Zc`, a table of the `Zc` turns),
/// and the turned centre `q'` is located by its slope `s = q'_y / q'_x` (the tangent of its
/// polar angle, `|atan s| <` [`PathAngleTable::HALF_WIDTH`]); then `t = t'(s) - 2 pi k` (one
/// tooth on, `t` falls by `2 pi`). `t'(s)` and `|C(t'(s))|` are cubic Hermite splines over `s`
/// with the exact node slopes `dt/ds = -Zc / ((1 - Zc mu'(t)) (1 + s^2))` and
/// `d|C|/ds = (a Rp sin t / |C|) dt/ds` (error falling as the fourth power of the node
/// spacing). The node count is doubled from 3072 until, at every cell midpoint, `t` is within
/// [`PathAngleTable::TOLERANCE`] of Newton's solution and the radius within
/// [`PathAngleTable::RADIUS_TOLERANCE`] of the closed form (24 576 nodes for the example,
/// 768 KiB), the doublings that the fourth-power law says fail by more than 8 times skipped.
/// [`GapField::eval`] then needs no `atan2` and no `sin_cos` per pin, where Newton's
/// method takes two or three of each; a centre outside the table's sector (a guess more than
/// about 0.17 rad of polar angle off) is located by Newton's method.
#[derive(Debug, Clone)]
struct PathAngleTable {
    /// Per node `s_j = -s_max + j h`, `j = 0..n`: `t'`, `dt'/ds h` (rad), `|C|`, `d|C|/ds h` (m).
    nodes: Vec<[f64; 4]>,
    /// `tan HALF_WIDTH`.
    s_max: f64,
    /// `1 / h`.
    inv_h: f64,
    /// `(cos, sin)` of the turn `-2 pi k / Zc` for `k = 0..Zc`.
    turns: Vec<(f64, f64)>,
}

impl PathAngleTable {
    /// Largest error of `t` accepted at the cell midpoints, rad: the radius `|C|` and the
    /// splines of the gap field (in `t`) then disagree by `d|C|/dt` (at most `a`) times it,
    /// below 2e-13 m for eccentricities up to 10 mm.
    const TOLERANCE: f64 = 2e-11;
    /// Largest error of the tabulated path radius accepted at the cell midpoints, m.
    const RADIUS_TOLERANCE: f64 = 1e-13;
    /// Half-width of the table's sector in polar angle, rad: half a tooth (0.08 rad for 39
    /// teeth) plus a guess a quarter tooth off in `t` (at most 0.072 rad of polar angle for
    /// the example) plus `asin(a / Rp)` (0.020 rad), with room to spare.
    const HALF_WIDTH: f64 = 0.25;
    /// Most nodes tried.
    const MAX_NODES: usize = 3 << 16;

    /// [`PathAngleTable::new`], remembered for the last few geometries of the process (the
    /// table depends on `a`, `rp` and `zc` only, and every gap field of a study shares them).
    fn shared(a: f64, rp: f64, zc: f64) -> Option<std::sync::Arc<Self>> {
        type Memo = Vec<([u64; 3], Option<std::sync::Arc<PathAngleTable>>)>;
        static MEMO: std::sync::Mutex<Memo> = std::sync::Mutex::new(Vec::new());
        let key = [a.to_bits(), rp.to_bits(), zc.to_bits()];
        let Ok(table) = crate::geometry::remembered(&MEMO, key, || {
            Ok::<_, std::convert::Infallible>(Self::new(a, rp, zc).map(std::sync::Arc::new))
        });
        table
    }

    /// The table for the path of eccentricity `a`, pin circle radius `rp` (m) and `zc` teeth,
    /// or `None` if no table up to [`Self::MAX_NODES`] meets [`Self::TOLERANCE`] and
    /// [`Self::RADIUS_TOLERANCE`], or a tooth spans more than [`Self::HALF_WIDTH`] of polar
    /// angle (the sector would not hold a pin with a guess off by a quarter tooth).
    fn new(a: f64, rp: f64, zc: f64) -> Option<Self> {
        if !(TAU / zc < Self::HALF_WIDTH && a < rp) {
            return None;
        }
        // t, dt/ds, |C| and d|C|/ds at slope s.
        let at = |s: f64| -> [f64; 4] {
            let theta = s.atan();
            let (t, dmu, sin_t, cos_t) = path_parameter(a, rp, zc, theta, -zc * theta);
            let dt = -zc / (1.0 - zc * dmu) / (1.0 + s * s);
            let rc = (rp * rp + a * a - 2.0 * a * rp * cos_t).sqrt();
            [t, dt, rc, a * rp * sin_t / rc * dt]
        };
        let s_max = Self::HALF_WIDTH.tan();
        let mut turns: Vec<(f64, f64)> = (0..zc as usize)
            .map(|k| {
                let (sin, cos) = (-TAU * k as f64 / zc).sin_cos();
                (cos, sin)
            })
            .collect();
        let mut n = 3072;
        while n <= Self::MAX_NODES {
            let h = 2.0 * s_max / n as f64;
            let nodes = (0..=n)
                .into_par_iter()
                .map(|j| {
                    let [t, dt, r, dr] = at(-s_max + j as f64 * h);
                    [t, dt * h, r, dr * h]
                })
                .collect();
            let table = PathAngleTable {
                nodes,
                s_max,
                inv_h: 1.0 / h,
                turns,
            };
            let (worst, worst_radius) = (0..n)
                .into_par_iter()
                .map(|j| {
                    let s = -s_max + (j as f64 + 0.5) * h;
                    let exact = at(s);
                    let (t, _, r, _) = table.cell(s);
                    ((t - exact[0]).abs(), (r - exact[2]).abs())
                })
                .reduce(|| (0.0, 0.0), |m, e| (m.0.max(e.0), m.1.max(e.1)));
            if worst <= Self::TOLERANCE && worst_radius <= Self::RADIUS_TOLERANCE {
                return Some(table);
            }
            // The error falls as the fourth power of the spacing: the doublings it leaves
            // more than 8 times over the tolerance are skipped (they would fail).
            let over = (worst / Self::TOLERANCE).max(worst_radius / Self::RADIUS_TOLERANCE);
            n *= 2;
            let mut left = over / 16.0;
            while left > 8.0 && n < Self::MAX_NODES {
                n *= 2;
                left /= 16.0;
            }
            turns = table.turns;
        }
        None
    }

    /// `t'`, `dt'/ds`, `|C|` and `d|C|/ds` at slope `s` (within `+-s_max`).
    #[inline]
    fn cell(&self, s: f64) -> (f64, f64, f64, f64) {
        let n = self.nodes.len() - 1;
        let x = (s + self.s_max) * self.inv_h;
        let i = (x as usize).min(n - 1);
        let f = x - i as f64;
        let (p, q) = (&self.nodes[i], &self.nodes[i + 1]);
        let (t, dt) = cubic_hermite(p[0], p[1], q[0], q[1], f);
        let (r, dr) = cubic_hermite(p[2], p[3], q[2], q[3], f);
        (t, dt * self.inv_h, r, dr * self.inv_h)
    }

    /// The path parameter `t` of the pin centre `q` (profile frame, m) with the guess
    /// `t_guess`, `dt/dq` (rad/m), the path radius `|C(t)|` (m) and `d|C|/dq`; `None` when `q`
    /// lies outside the sector of the tooth the guess names.
    #[inline]
    fn eval(&self, q: &Vec2, t_guess: f64) -> Option<(f64, Vec2, f64, Vec2)> {
        let k = (-t_guess * (1.0 / TAU)).round();
        // k mod Zc without an integer division (exact for whole k far beyond any crank turn).
        let zc = self.turns.len() as f64;
        let mut m = k - zc * (k / zc).floor();
        if m >= zc {
            m -= zc;
        } else if m < 0.0 {
            m += zc;
        }
        let (c, sn) = self.turns[m as usize];
        let x = c * q.x - sn * q.y;
        let y = sn * q.x + c * q.y;
        let inv_x = 1.0 / x;
        let s = y * inv_x;
        if !(x > 0.0 && s.abs() < self.s_max) {
            return None;
        }
        let (t, dt, r, dr) = self.cell(s);
        // ds/dq' = (-y / x^2, 1 / x), turned back to the profile frame.
        let (gx, gy) = (-s * inv_x, inv_x);
        let ds_dq = Vec2::new(c * gx + sn * gy, c * gy - sn * gx);
        Some((t - TAU * k, ds_dq * dt, r, ds_dq * dr))
    }
}

/// The path parameter `t` whose path point has the (unwrapped) polar angle `theta` (module
/// docs), by Newton's method on `G(t) = t + Zc (theta - mu(t))` from `t_guess`: `t`, `mu'(t)`,
/// `sin t`, `cos t`. Stops when a step is below 1e-9 rad (or after 16), keeping the derivatives
/// at the previous iterate and moving sin and cos to first order: one more step would move `t`
/// by about `(G''/2G') step^2 < 1e-17` rad (the gap by less than 1e-19 m).
#[inline]
fn path_parameter(a: f64, rp: f64, zc: f64, theta: f64, t_guess: f64) -> (f64, f64, f64, f64) {
    let mu = |t: f64| {
        let (s, c) = t.sin_cos();
        let den = rp * rp + a * a - 2.0 * a * rp * c;
        ((a * s).atan2(rp - a * c), (a * rp * c - a * a) / den, s, c)
    };
    let mut t = t_guess;
    let mut iterations = 0;
    loop {
        let (m, dmu, sin_t, cos_t) = mu(t);
        let step = (t + zc * (theta - m)) / (1.0 - zc * dmu);
        t -= step;
        iterations += 1;
        if step.abs() < 1e-9 || iterations == 16 {
            return (t, dmu, sin_t - step * cos_t, cos_t + step * sin_t);
        }
    }
}

impl GapField {
    /// Tabulates the gap of `profile` on `points` mesh angles per tooth (>= 16), in parallel
    /// over runs of neighbouring mesh angles: Newton's method on the radial offset finds the
    /// touching offset (about three local projections per mesh angle, the first from the
    /// neighbour's foot), confirmed by one exact global projection (`touching_node`); the
    /// slope is the foot normal's radial component there, the curvature that of the contact
    /// law at the touching foot.
    ///
    /// # Errors
    /// [`crate::Error::Numerical`] if a projection fails.
    ///
    /// With a `band` the offset and slope tables are then filtered over its Hertz band: every
    /// node becomes the semi-elliptic average over `+-b` of arc length (two passes), `b` the
    /// half-width of the band's force (N) on the unworn flank there; with `envelope`, over the
    /// bands of `NARROW_BAND` times that force and of that force, and the field takes the
    /// upper envelope of the two, the flank that stands further out (see the module docs).
    pub fn new(profile: &Profile, points: usize, band: Option<Band>) -> Result<Self> {
        Self::new_after(profile, points, band, None)
    }

    /// [`GapField::new`] for a flank worn on from that of `before`, the field of the same
    /// disc's profile with less wear (`(field, profile)`, the previous evaluation of a wear
    /// integration): a node whose touching foot lies where the wear map has not changed (the
    /// cell of the foot and its neighbours, [`WearMap`]'s `grown_from`) keeps `before`'s node.
    /// The distance from its pin centre to that part of the flank is the same, and to every
    /// other part no smaller (wear only removes material; to the spline's undershoot,
    /// below [`RECEDE_TOLERANCE`]), so its exact global projection would find the same foot
    /// and the same touching offset, slope and curvature. The other nodes are found afresh,
    /// each started from its own node before. Without `before`, or where the maps are not one
    /// worn on from the other, as [`GapField::new`].
    ///
    /// # Errors
    /// As [`GapField::new`].
    ///
    /// [`WearMap`]: crate::geometry::WearMap
    pub(crate) fn new_after(
        profile: &Profile,
        points: usize,
        band: Option<Band>,
        before: Option<(&GapField, &Profile)>,
    ) -> Result<Self> {
        let geo = profile.geometry();
        let (a, rp) = (geo.eccentricity, geo.pin_circle_radius);
        let zc = geo.disc_teeth() as f64;
        let n = points.max(16);
        let kept = before.and_then(|(field, old)| {
            let same = field.nodes.len() == n
                && old.geometry() == geo
                && old.modification() == profile.modification();
            let cells = profile.wear()?.grown_from(old.wear(), RECEDE_TOLERANCE)?;
            same.then_some((field, cells))
        });
        let nodes: Vec<Node> = match kept {
            Some((field, cells)) => {
                let m = cells.len();
                let unchanged = |foot: f64| {
                    let c = (foot.rem_euclid(TAU) / TAU * m as f64).floor() as usize;
                    [m - 1, 0, 1].iter().all(|&k| cells[(c + k) % m])
                };
                (0..n)
                    .into_par_iter()
                    .with_min_len(16)
                    .map(|i| {
                        let (row, foot) = field.nodes[i];
                        if unchanged(foot) {
                            return Ok((row, foot));
                        }
                        let t = TAU * i as f64 / n as f64;
                        Self::touching_node(profile, t, Some((foot, row.0)))
                    })
                    .collect::<Result<Vec<_>>>()?
            }
            None => {
                // The nodes in runs of `RUN` (in parallel), each node's first projection
                // started from its predecessor's foot (the foot moves smoothly along the
                // tooth).
                const RUN: usize = 32;
                (0..n.div_ceil(RUN))
                    .into_par_iter()
                    .map(|run| -> Result<Vec<Node>> {
                        let mut out = Vec::with_capacity(RUN);
                        let mut seed: Option<(f64, f64)> = None;
                        for i in run * RUN..((run + 1) * RUN).min(n) {
                            let t = TAU * i as f64 / n as f64;
                            let (row, foot) = Self::touching_node(profile, t, seed)?;
                            out.push((row, foot));
                            seed = Some((foot + TAU / n as f64, row.0));
                        }
                        Ok(out)
                    })
                    .collect::<Result<Vec<_>>>()?
                    .into_iter()
                    .flatten()
                    .collect()
            }
        };
        let mut offset = Vec::with_capacity(n);
        let mut slope = Vec::with_capacity(n);
        let mut curvature = Vec::with_capacity(n);
        for &((o, s, k), _) in &nodes {
            offset.push(o);
            slope.push(s);
            curvature.push(k);
        }
        if let Some(Band {
            contact,
            force,
            envelope,
        }) = band
        {
            let ds = profile.arc_steps(n);
            if envelope {
                let (narrow, wide) = rayon::join(
                    || band_average(profile, contact, NARROW_BAND * force, &ds, &offset, &slope),
                    || band_average(profile, contact, force, &ds, &offset, &slope),
                );
                // The upper envelope (the flank that stands further out) of the two; where
                // they agree to a picometre (an unworn flank) the narrow band's tables.
                for i in 0..n {
                    (offset[i], slope[i]) = if wide.0[i] > narrow.0[i] + 1e-12 {
                        (wide.0[i], wide.1[i])
                    } else {
                        (narrow.0[i], narrow.1[i])
                    };
                }
            } else {
                (offset, slope) = band_average(profile, contact, force, &ds, &offset, &slope);
            }
        }
        Ok(GapField {
            a,
            rp,
            zc,
            offset: PeriodicSpline::new(offset),
            slope: PeriodicSpline::new(slope),
            curvature: PeriodicSpline::new(curvature),
            angle: PathAngleTable::shared(a, rp, zc),
            nodes: std::sync::Arc::new(nodes),
        })
    }

    /// One node of the gap table at mesh angle `t`: `((offset, slope, curvature), foot)`, the
    /// radial offset (m) at which the pin touches the flank, the foot normal's radial
    /// component there, the contact law's curvature (1/m) at the touching foot and that foot's
    /// parameter (rad).
    ///
    /// Newton's method on the offset, each projection local from the previous foot on the
    /// tabulated tooth ([`Profile::project_near_table`]); `seed`: the neighbouring node's foot
    /// (rad) and touching offset (m), where the iteration starts (without one, from offset 0
    /// and the foot of its global projection). The touching offset is then projected exactly
    /// and globally ([`Profile::project_from`]), which gives the gap, slope and curvature
    /// returned; where another foot lies closer there (a worn flank's scar) the local iteration
    /// is repeated once from that foot and confirmed alike, and where that fails too, from
    /// offset 0 with exact global projections.
    fn touching_node(
        profile: &Profile,
        t: f64,
        seed: Option<(f64, f64)>,
    ) -> Result<((f64, f64, f64), f64)> {
        let geo = profile.geometry();
        let r = geo.pin_radius;
        let c = Self::path(
            geo.eccentricity,
            geo.pin_circle_radius,
            geo.disc_teeth() as f64,
            t,
        );
        let e = c / c.norm();
        // Gap, its radial derivative (the foot normal along the radius: the distance gradient
        // is the unit normal at the closest point), the curvature and the foot at offset
        // `rho`: globally, exact.
        let exact = |rho: f64| -> Result<(f64, f64, f64, f64)> {
            let pr = profile.project(&(c + e * rho), t)?;
            Ok((
                pr.distance - r,
                pr.point.normal.dot(&e).max(0.05),
                profile.macro_curvature(pr.point.t),
                pr.point.t,
            ))
        };
        // Newton's method on the offset from the seed, each projection local from the previous
        // foot on the tabulated tooth (`None` where the foot leaves its bracket).
        let local = |(foot, rho): (f64, f64)| -> Option<(f64, f64)> {
            let table = |rho: f64, near: f64| {
                profile
                    .project_near_table(&(c + e * rho), near)
                    .map(|(tf, d, normal)| (d - r, normal.dot(&e).max(0.05), tf))
            };
            let (mut rho0, (mut g1, mut s, mut tf)) = (rho, table(rho, foot)?);
            for _ in 0..8 {
                rho0 -= g1 / s;
                (g1, s, tf) = table(rho0, tf)?;
                if g1.abs() < 1e-12 {
                    break;
                }
            }
            Some((rho0, tf))
        };
        // The same from offset 0 with global projections (no seed, or the local foot was not
        // the closest).
        let global = || -> Result<(f64, f64, f64, f64, f64)> {
            let mut rho0 = 0.0;
            let (mut g1, mut s, mut k, mut tf) = exact(rho0)?;
            for _ in 0..8 {
                rho0 -= g1 / s;
                (g1, s, k, tf) = exact(rho0)?;
                if g1.abs() < 1e-12 {
                    break;
                }
            }
            Ok((rho0, g1, s, k, tf))
        };
        // The local result confirmed by one exact global projection at its offset, which
        // gives its exact gap, slope and curvature where it finds the same foot (within two
        // table steps of the tabulated one); otherwise the foot it found instead (`Err`).
        let confirm = |(rho0, tf): (f64, f64)| -> Result<std::result::Result<_, f64>> {
            let pr = profile.project_from(&(c + e * rho0), t, Some(tf))?;
            Ok(if (pr.point.t - tf).abs() <= 2.0 * profile.table_step() {
                Ok((
                    rho0,
                    pr.distance - r,
                    pr.point.normal.dot(&e).max(0.05),
                    profile.macro_curvature(pr.point.t),
                    pr.point.t,
                ))
            } else {
                Err(pr.point.t)
            })
        };
        let start = match seed {
            Some(s) => s,
            None => (exact(0.0)?.3, 0.0),
        };
        // Where another foot was closer (a worn flank's scar), the local iteration once more
        // from that foot, before the global one.
        let first = local(start);
        let confirmed = match first.map(&confirm).transpose()? {
            Some(Ok(x)) => Some(x),
            Some(Err(foot)) => {
                let rho0 = first.map_or(start.1, |f| f.0);
                match local((foot, rho0)).map(&confirm).transpose()? {
                    Some(Ok(x)) => Some(x),
                    _ => None,
                }
            }
            None => None,
        };
        let (rho0, g1, s, k, tf) = match confirmed {
            Some(x) => x,
            None => global()?,
        };
        Ok(((rho0 - g1 / s, s, k), tf))
    }

    /// Nominal pin-centre path `C(t)` in the profile frame, m.
    fn path(a: f64, rp: f64, zc: f64, t: f64) -> Vec2 {
        let beta = (zc + 1.0) / zc;
        let (s1, c1) = ((1.0 - beta) * t).sin_cos();
        let (s2, c2) = (beta * t).sin_cos();
        Vec2::new(rp * c1 - a * c2, rp * s1 + a * s2)
    }

    /// Gap and its gradient for a pin centre `q` (profile frame, m); `t_guess` is the path
    /// parameter expected for this pin (within about a quarter tooth; see
    /// [`Profile::contact_parameter_guess`]), and the parameter found is returned with it.
    #[inline]
    pub(crate) fn eval(&self, q: &Vec2, t_guess: f64) -> (GapEval, f64) {
        let r2 = q.norm_squared();
        let rq = r2.sqrt();
        // The path parameter, the path radius and their gradients (the table's own
        // derivatives when tabulated, so that the gradient is that of the gap evaluated).
        let (t, dt_dq, rc, drc_dq) = match self.angle.as_ref().and_then(|a| a.eval(q, t_guess)) {
            Some(x) => x,
            None => self.path_by_newton(q, r2, t_guess),
        };
        let rho = rq - rc;
        let drho_dq = q / rq - drc_dq;
        let ([r0, s, curvature], [dr0, ds, dk]) =
            PeriodicSpline::eval3([&self.offset, &self.slope, &self.curvature], t);
        let gap = s * (rho - r0);
        let grad = dt_dq * (ds * (rho - r0) - s * dr0) + drho_dq * s;
        (
            GapEval {
                gap,
                grad,
                curvature,
                curvature_grad: dt_dq * dk,
            },
            t,
        )
    }
}

impl GapField {
    /// The nodes before any band average: `((offset, slope, curvature), foot)` per mesh angle.
    #[cfg(test)]
    pub(crate) fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// [`GapField::eval`]'s path parameter `t`, `dt/dq`, path radius `|C(t)|` and `d|C|/dq`
    /// by Newton's method on the polar angle of `q` (`r2 = |q|^2`), unwrapped near the guess
    /// (`arg C(t) = -t/Zc + mu(t)`, `|mu| < asin(a/Rp)`, far below pi): where no table met
    /// its tolerance, or `q` lies outside the table's sector.
    #[cold]
    fn path_by_newton(&self, q: &Vec2, r2: f64, t_guess: f64) -> (f64, Vec2, f64, Vec2) {
        let (a, rp, zc) = (self.a, self.rp, self.zc);
        let theta = q.y.atan2(q.x);
        let pred = -t_guess / zc;
        let x = theta - pred + PI;
        let theta = pred + x - TAU * (x / TAU).floor() - PI;
        let (t, dmu, sin_t, cos_t) = path_parameter(a, rp, zc, theta, t_guess);
        // dtheta/dq = (-q_y, q_x)/|q|^2, dt/dtheta = -Zc / (1 - Zc mu'),
        // d|C|/dt = a Rp sin t / |C|.
        let dtheta_dq = Vec2::new(-q.y, q.x) / r2;
        let dt_dq = dtheta_dq * (-zc / (1.0 - zc * dmu));
        let rc = (rp * rp + a * a - 2.0 * a * rp * cos_t).sqrt();
        (t, dt_dq, rc, dt_dq * (a * rp * sin_t / rc))
    }
}

impl GapField {
    /// Hessian of the gap (1/m, profile frame, symmetric 2 x 2) at pin centre `q` (m) whose
    /// path parameter `t` was found by [`GapField::eval`]: the exact second derivative of the
    /// interpolant `s(t) (rho - rho_0(t))` with `t(q)` and `rho(q)` of the module docs (within a
    /// spline cell; the splines are C1, so it jumps at the knots).
    pub(crate) fn hessian(&self, q: &Vec2, t: f64) -> Matrix2<f64> {
        let (a, rp, zc) = (self.a, self.rp, self.zc);
        let (x, y) = (q.x, q.y);
        let r2 = q.norm_squared();
        let rq = r2.sqrt();
        let (sn, cs) = t.sin_cos();
        let den = rp * rp + a * a - 2.0 * a * rp * cs;
        let rc = den.sqrt();
        let num = a * rp * cs - a * a;
        let dmu = num / den;
        let ddmu = (-a * rp * sn * den - num * 2.0 * a * rp * sn) / (den * den);
        // t(q) = t(theta(q)) with dt/dtheta = k(t) = -Zc / (1 - Zc mu'(t)).
        let k = -zc / (1.0 - zc * dmu);
        let dk = -zc * zc * ddmu / ((1.0 - zc * dmu) * (1.0 - zc * dmu));
        let gth = Vec2::new(-y, x) / r2;
        let hth = Matrix2::new(2.0 * x * y, y * y - x * x, y * y - x * x, -2.0 * x * y) / (r2 * r2);
        let gt = gth * k;
        let tt = gt * gt.transpose();
        let ht = tt * (dk / k) + hth * k;
        // rho = |q| - |C(t)|.
        let drc = a * rp * sn / rc;
        let ddrc = a * rp * cs / rc - drc * drc / rc;
        let grho = *q / rq - gt * drc;
        let hrho = (Matrix2::identity() - *q * q.transpose() / r2) / rq - tt * ddrc - ht * drc;
        // gap = s(t) D with D = rho - rho_0(t).
        let (r0, dr0, ddr0) = self.offset.eval2(t);
        let (s, ds, dds) = self.slope.eval2(t);
        let d = rq - rc - r0;
        let gd = grho - gt * dr0;
        let hd = hrho - tt * ddr0 - ht * dr0;
        let td = gt * gd.transpose();
        tt * (dds * d) + (td + td.transpose()) * ds + ht * (ds * d) + hd * s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tabulated path parameter equals Newton's solution to 2e-11 rad and the tabulated path
    /// radius the closed form to 1e-13 m at 20 000 polar angles over three teeth (cell
    /// midpoints and quarter points included), at radii 0.9 and 1.1 `Rp` and with guesses up to
    /// a quarter tooth off, with the example's geometry; the table's gradients equal central
    /// differences of its values within 1e-6.
    #[test]
    fn path_angle_table_matches_newton() {
        let geo = crate::config::Config::paper()
            .validate()
            .unwrap()
            .reducer
            .geometry;
        let (a, rp, zc) = (
            geo.eccentricity,
            geo.pin_circle_radius,
            geo.disc_teeth() as f64,
        );
        let table = PathAngleTable::new(a, rp, zc).expect("a table meets the tolerance");
        let (mut worst, mut worst_r, mut worst_d) = (0.0_f64, 0.0_f64, 0.0_f64);
        let mut outside = 0;
        for k in 0..20_000 {
            let theta = -0.3 + 3.0 * TAU / zc * k as f64 / 20_000.0;
            let t0 = path_parameter(a, rp, zc, theta, -zc * theta).0;
            let (t, _, _, cos_t) = path_parameter(a, rp, zc, theta, t0);
            let exact = (rp * rp + a * a - 2.0 * a * rp * cos_t).sqrt();
            for (radius, off) in [(0.9, 0.0), (1.1, 1.5), (1.0, -1.5)] {
                let q = Vec2::new(theta.cos(), theta.sin()) * (radius * rp);
                let Some((tt, dt, rc, drc)) = table.eval(&q, t + off) else {
                    outside += 1;
                    continue;
                };
                worst = worst.max((tt - t).abs());
                worst_r = worst_r.max((rc - exact).abs());
                let h = 1e-7 * rp;
                for e in [Vec2::new(h, 0.0), Vec2::new(0.0, h)] {
                    let (tp, _, rp_, _) = table.eval(&(q + e), t + off).unwrap();
                    let (tm, _, rm, _) = table.eval(&(q - e), t + off).unwrap();
                    let (fd_t, fd_r) = ((tp - tm) / (2.0 * h), (rp_ - rm) / (2.0 * h));
                    let (an_t, an_r) = (dt.dot(&e) / h, drc.dot(&e) / h);
                    worst_d = worst_d
                        .max((fd_t - an_t).abs() / dt.norm())
                        .max((fd_r - an_r).abs() / (a * zc / rp));
                }
            }
        }
        eprintln!(
            "t within {worst:.2e} rad, radius within {worst_r:.2e} m, gradients within \
             {worst_d:.2e}; {outside} outside the sector"
        );
        assert_eq!(outside, 0);
        assert!(worst < 2e-11);
        assert!(worst_r < 1e-13);
        assert!(worst_d < 1e-6);
    }
    use crate::contact::pin_geometry;
    use crate::geometry::{Modification, WearMap};

    /// The tabulated gap equals the exact projected gap of the contact module near contact, and
    /// its gradient equals a finite difference of itself.
    #[test]
    fn matches_exact_gaps_and_own_gradient() {
        let n = 256;
        let depth: Vec<f64> = (0..n)
            .map(|i| 10e-6 * (1.0 + (TAU * i as f64 / n as f64).sin()).powi(2) / 4.0)
            .collect();
        let m = Modification {
            equidistant: 5e-6,
            ..Default::default()
        };
        let geo = crate::config::Config::paper()
            .validate()
            .unwrap()
            .cycloid
            .geometry;
        let profile = Profile::new(geo, m, Some(WearMap::new(depth).unwrap())).unwrap();
        let field = GapField::new(&profile, 2048, None).unwrap();
        for &phi in &[0.0, 0.3, 1.1] {
            for &beta in &[-2e-4, 0.0, 3e-4] {
                for j in 0..40 {
                    let pg = pin_geometry(&profile, j, phi, beta).unwrap();
                    if pg.gap > 20e-6 {
                        continue;
                    }
                    let (c, psi) = crate::contact::pin::disc_pose(profile.geometry(), phi, beta);
                    let p = profile.geometry().pin_centre(j);
                    let q = crate::geometry::rotate(&(p - c), -psi);
                    let tg = profile.contact_parameter_guess(j, phi, psi);
                    let (g, _) = field.eval(&q, tg);
                    // Within 2 um of touching (where forces act) to 2 nm; further out the
                    // linear model drifts by about (rho - rho_0)^2 / 2R, a few per cent.
                    let tol = if pg.gap.abs() < 2e-6 {
                        2e-9
                    } else {
                        5e-2 * pg.gap.abs()
                    };
                    assert!(
                        (g.gap - pg.gap).abs() < tol,
                        "phi {phi} beta {beta} pin {j}: {} vs {}",
                        g.gap,
                        pg.gap
                    );
                    let h = 1e-8;
                    for (k, d) in [Vec2::new(h, 0.0), Vec2::new(0.0, h)].iter().enumerate() {
                        let gp = field.eval(&(q + d), tg).0.gap;
                        let gm = field.eval(&(q - d), tg).0.gap;
                        let fd = (gp - gm) / (2.0 * h);
                        assert!((fd - g.grad[k]).abs() < 1e-5, "{fd} vs {}", g.grad[k]);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod banded_tests {
    use super::*;
    use crate::geometry::WearMap;

    /// On a worn flank with a steep scar edge and a ripple, the banded field (the envelope of
    /// two band averages) stands out at least as far as each average, its gradient equals
    /// central differences of its gap and its Hessian central differences of its gradient, at
    /// pins from touching to 20 um of approach; on the unworn flank it is the exact one.
    #[test]
    fn banded_field_is_the_envelope_with_consistent_derivatives() {
        let model = crate::config::Config::paper().validate().unwrap();
        let red = &model.reducer;
        let n = 720;
        let depth: Vec<f64> = (0..n)
            .map(|i| {
                let m = 360.0 * i as f64 / n as f64;
                let edge = ((m - 5.0) / 15.0).clamp(0.0, 1.0);
                let edge = edge * edge * (3.0 - 2.0 * edge);
                let ripple = if m > 20.0 && m < 90.0 {
                    4e-6 * (TAU * (m - 20.0) / 9.0).sin()
                } else {
                    0.0
                };
                if m < 120.0 {
                    40e-6 * edge + ripple
                } else {
                    0.0
                }
            })
            .collect();
        let profile = model
            .cycloid
            .profile(Some(WearMap::new(depth).unwrap()))
            .unwrap();
        let band = Some(Band {
            envelope: true,
            ..red.contact_band()
        });
        let field = GapField::new(&profile, red.gap_points, band).unwrap();
        let (mut wide, mut narrow) = (0, 0);
        for i in 0..60 {
            let t = TAU * (2.0 + 1.5 * i as f64) / 360.0;
            let c = GapField::path(field.a, field.rp, field.zc, t);
            let e = c / c.norm();
            for delta in [0.3e-6, 1.5e-6, 4e-6, 9e-6, 20e-6] {
                let mut rho = 0.0;
                for _ in 0..30 {
                    let (g, _) = field.eval(&(c + e * rho), t);
                    rho -= (g.gap + delta) / g.grad.dot(&e);
                }
                let q = c + e * rho;
                let (g, tq) = field.eval(&q, t);
                assert!((g.gap + delta).abs() < 1e-12);
                let h = 1e-9;
                let hess = field.hessian(&q, tq);
                for (k, d) in [Vec2::new(h, 0.0), Vec2::new(0.0, h)].iter().enumerate() {
                    let (gp, _) = field.eval(&(q + d), t);
                    let (gm, _) = field.eval(&(q - d), t);
                    let fd = (gp.gap - gm.gap) / (2.0 * h);
                    assert!(
                        (fd - g.grad[k]).abs() < 1e-5,
                        "t {t}: {fd} vs {}",
                        g.grad[k]
                    );
                    let fdh = (gp.grad - gm.grad) / (2.0 * h);
                    let scale = hess.abs().max() + 1.0;
                    for r in 0..2 {
                        assert!(
                            (fdh[r] - hess[(r, k)]).abs() < 2e-3 * scale,
                            "t {t}: H[{r},{k}] {} vs {}",
                            hess[(r, k)],
                            fdh[r]
                        );
                    }
                }
            }
        }
        // The envelope: against each band's average, node by node.
        let exact = GapField::new(&profile, red.gap_points, None).unwrap();
        let f = red.contact_band_force;
        let ds = profile.arc_steps(exact.offset.value.len());
        let average = |f: f64| {
            band_average(
                &profile,
                &red.contact,
                f,
                &ds,
                &exact.offset.value,
                &exact.slope.value,
            )
            .0
        };
        let (narrow_avg, wide_avg) = (average(NARROW_BAND * f), average(f));
        for i in 0..field.offset.value.len() {
            let (o, a, b) = (field.offset.value[i], narrow_avg[i], wide_avg[i]);
            assert!(
                o >= a && o >= b - 1e-12 && (o == a || o == b),
                "{o} {a} {b}"
            );
            if o == b && b > a {
                wide += 1;
            } else {
                narrow += 1;
            }
        }
        assert!(wide > 10 && narrow > 10, "{wide} {narrow}");
        // Unworn: the exact flank to round-off (every pin touches at the nominal pose).
        let new = model.profile().unwrap();
        let banded = GapField::new(&new, 256, band).unwrap();
        assert!(banded.offset.value.iter().all(|o| o.abs() < 1e-15));
    }
}
