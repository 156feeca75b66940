//! The disc profile: the closed form with its modifications and wear map, evaluated points,
//! curvature and closest points (docs/model.md section 2).

use std::f64::consts::TAU;

use nalgebra::Complex;

use super::wear_map::cubic_hermite;
use super::{cross, mesh_angle, rotate, rotate_by, CycloidGeometry, Modification, Vec2, WearMap};
use crate::error::{Error, Result};

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
    /// The worn tooth tabulated for closest-point searches.
    table: ToothTable,
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
            table: ToothTable::default(),
        };
        let mut profile = profile;
        let unworn = UnwornTooth::shared(&profile, ToothTable::nodes_per_tooth(&profile))?;
        profile.table = ToothTable::new(&profile, unworn)?;
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

    /// Closed form (paper eq 24) and its first two derivatives in `t`, without wear, for a
    /// given offset radius `r` (the equidistant radius `rrp'`; `r = 0` gives the pin-centre path).
    pub(crate) fn closed_form(&self, t: f64, r: f64) -> (Vec2, Vec2, Vec2) {
        let k1 = self.k1;
        // The same bits on every platform: the FE disc is meshed on these points.
        let (st, ct) = super::portable::sin_cos(t);
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
        let (s2t, c2t) = super::portable::sin_cos(-be * t + self.modification.rotation);
        let e2 = Complex::new(c2t, s2t);
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
        self.eval_d1_folds(t).0
    }

    /// [`Profile::eval_d1`] and whether the worn flank folds over itself at `t`: its tangent
    /// turned against the unworn one (`dp_worn . dp <= 0`, wear deeper than the local convex
    /// radius or too steep along the profile); `false` without wear.
    fn eval_d1_folds(&self, t: f64) -> ((Vec2, Vec2, Vec2), bool) {
        self.worn_at(t, self.closed_form(t, self.r_mod))
    }

    /// [`Profile::eval_d1_folds`] at `t` from the profile without wear there (`unworn`: the
    /// closed form's position and first two derivatives).
    fn worn_at(&self, t: f64, unworn: (Vec2, Vec2, Vec2)) -> ((Vec2, Vec2, Vec2), bool) {
        let (p, dp, ddp) = unworn;
        match &self.wear {
            None => ((p, dp, ddp), false),
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
                ((pw, dpw, ddpw), dpw.dot(&dp) <= 0.0)
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

    /// Curvature (1/m, positive convex) of the modified profile without wear at parameter `t`:
    /// the macro-geometry that sets the Hertz contact. Wear changes depths by microns over
    /// millimetres of flank; the curvature of the wear map itself is grid-scale roughness finer
    /// than the contact band and is left out of the contact law.
    pub(crate) fn macro_curvature(&self, t: f64) -> f64 {
        self.table.curvature(mesh_angle(t))
    }

    /// [`Profile::macro_curvature`] from the closed form (the tabulated one interpolates it).
    fn macro_curvature_exact(&self, t: f64) -> f64 {
        let (_, dp, ddp) = self.closed_form(t, self.r_mod);
        -cross(&dp, &ddp) / dp.norm().powi(3)
    }

    /// Closest point of the profile to `q` (disc frame, m): the global minimum of the distance
    /// over the mesh-angle window `t0 +- pi/2` ([`PROJECTION_WINDOW`], a quarter tooth), whatever the number
    /// of local minima in it (a pin bridging a wear dent, or sitting in a near-conformal root,
    /// has several). `t0` is the kinematic guess of the foot ([`Profile::contact_parameter_guess`]).
    ///
    /// Algorithm: the distance to the tabulated tooth is bounded below on each cell of 8 table
    /// nodes by `(d_a + d_b - L h) / 2` (`d_a`, `d_b` the distances to the cell's end nodes, `L`
    /// the largest `|dz/dt|`, `h` the cell width); cells whose bound is above the best distance
    /// found so far are skipped, every discrete local minimum of the node distances in the others
    /// is polished by safeguarded Newton on the tabulated tooth, and the best is kept. The foot's
    /// position and normal are then evaluated exactly.
    ///
    /// # Errors
    /// [`Error::Numerical`] if the closest point lies on the edge of the window (the guess was
    /// more than a quarter tooth off).
    pub(crate) fn project(&self, q: &Vec2, t0: f64) -> Result<Projection> {
        self.project_from(q, t0, None)
    }

    /// [`Profile::project`] with a known local foot `foot` (rad, the parameter of a local
    /// projection of `q`, [`Profile::project_near`]) as the global search's first candidate,
    /// in place of the one polished from `t0` (ignored unless it lies within half the search
    /// window of `t0`). The result is the global closest point as with `project`.
    ///
    /// # Errors
    /// As [`Profile::project`].
    pub(crate) fn project_from(&self, q: &Vec2, t0: f64, foot: Option<f64>) -> Result<Projection> {
        let (k, turn) = self.tooth_of(t0);
        let ql = rotate(q, turn);
        let tl = t0 - TAU * k;
        let seed = match foot.map(|f| f - TAU * k) {
            Some(f) if (f - tl).abs() < 0.5 * PROJECTION_WINDOW => Some(f),
            _ => self
                .table
                .polish(&ql, tl, tl - 8.0 * self.table.dt, tl + 8.0 * self.table.dt),
        };
        let t = self
            .table
            .global_foot(&ql, tl, PROJECTION_WINDOW, seed)
            .ok_or_else(|| {
                Error::numerical(
                    "profile projection",
                    format!(
                    "the closest point to ({:.6e}, {:.6e}) m lies on the edge of the search window \
                     around mesh angle {:.3} deg",
                    q.x,
                    q.y,
                    tl.to_degrees()
                ),
                )
            })?;
        Ok(self.finish_projection(&ql, t, k, turn))
    }

    /// Closest point near a known foot: safeguarded Newton on the tabulated tooth over
    /// `t_prev +- 8` table steps (a warm start inside a solver, where the pose moves by
    /// micrometres between calls). `None` if the foot leaves that bracket; callers then use
    /// [`Profile::project`], and solvers confirm their converged pose with it.
    pub(crate) fn project_near(&self, q: &Vec2, t_prev: f64) -> Option<Projection> {
        let (ql, t, k, turn) = self.near_foot(q, t_prev)?;
        Some(self.finish_projection(&ql, t, k, turn))
    }

    /// The local foot of [`Profile::project_near`] on the tabulated tooth: `q` turned onto
    /// tooth 0, the foot's tooth-0 parameter (rad), the tooth index and its turn (rad); `None`
    /// where the foot leaves the bracket of `t_prev +- 8` table steps.
    fn near_foot(&self, q: &Vec2, t_prev: f64) -> Option<(Vec2, f64, f64, f64)> {
        let (k, turn) = self.tooth_of(t_prev);
        let ql = rotate(q, turn);
        let tl = t_prev - TAU * k;
        let w = 8.0 * self.table.dt;
        let t = self.table.polish(&ql, tl, tl - w, tl + w)?;
        ((t - tl).abs() < w * 0.999).then_some((ql, t, k, turn))
    }

    /// Parameter step of the tabulated tooth, rad.
    pub(crate) fn table_step(&self) -> f64 {
        self.table.dt
    }

    /// Tooth index `k` of parameter `t` and the turn (rad) that takes tooth `k` onto tooth 0:
    /// `z(t + 2 pi k) = z(t) e^{-2 pi i k / Zc}`.
    fn tooth_of(&self, t: f64) -> (f64, f64) {
        let k = (t / TAU).floor();
        (k, TAU * k / self.zc)
    }

    /// The projection result for the foot `t` (tooth-0 parameter, from the tabulated tooth) of
    /// `ql` (tooth-0 frame): the foot polished by Newton's method on the exact profile (the
    /// table's tangent is accurate to about 1e-8 m/rad, which would tilt the normal by 1e-6),
    /// then evaluated exactly.
    fn finish_projection(&self, ql: &Vec2, t: f64, k: f64, turn: f64) -> Projection {
        let mut t = t;
        let mut ev = self.eval_d1(t);
        for _ in 0..4 {
            let (p, dp, ddp) = ev;
            let d = p - ql;
            let g = dp.norm_squared();
            let fp = g + d.dot(&ddp);
            // The tabulated foot is within about 1e-8 rad of the exact one: a Newton step beyond
            // half a table step, or where the distance is not convex, would leave its basin.
            if fp <= 1e-6 * g {
                break;
            }
            let step = d.dot(&dp) / fp;
            if step.abs() > 0.5 * self.table.step() {
                break;
            }
            t -= step;
            ev = self.eval_d1(t);
            // Newton converges quadratically: after a step of 1e-9 m along the flank the foot is
            // within about 1e-14 m (radii of 70 um or more between pin centre and flank
            // evolute), far below what the normal or the distance can feel.
            if step.abs() * g.sqrt() < 1e-9 {
                break;
            }
        }
        let mut point = ProfilePoint::from_derivatives(t, ev.0, ev.1, ev.2);
        let distance = (ql - point.p).dot(&point.normal);
        let back = (-turn).sin_cos();
        point.t = t + TAU * k;
        point.p = rotate_by(&point.p, back);
        point.dp = rotate_by(&point.dp, back);
        point.normal = rotate_by(&point.normal, back);
        Projection { point, distance }
    }

    /// [`Profile::project_near`] on the tabulated tooth alone, without the exact evaluation
    /// that finishes a projection: the foot's parameter (rad), the signed distance (m) and the
    /// outward unit normal of the tabulated tooth there (disc frame). The table's position is
    /// within about 1e-13 m of the exact profile and its tangent within 1e-8 m/rad, so the
    /// distance is that close and the normal within about 1e-6 rad: good for the iterations of
    /// a search whose result is then projected exactly.
    pub(crate) fn project_near_table(&self, q: &Vec2, t_prev: f64) -> Option<(f64, f64, Vec2)> {
        let (ql, t, k, turn) = self.near_foot(q, t_prev)?;
        let (z, dz, _) = self.table.eval(t);
        let tangent = dz / dz.norm();
        let normal = Vec2::new(-tangent.y, tangent.x);
        Some((t + TAU * k, (ql - z).dot(&normal), rotate(&normal, -turn)))
    }

    /// Position of the actual profile at parameter `t` (rad), m, disc frame: [`Profile::point`]'s
    /// `p` without its normal and curvature (which cost two more evaluations on a worn
    /// profile).
    pub fn position(&self, t: f64) -> Vec2 {
        self.eval_d1(t).0
    }

    /// Arc length (m) of each step of a grid of `n` profile parameters over one tooth (at
    /// `t = 2 pi i / n`, the speed `|dp/dt|` there times the step), evaluated in parallel.
    pub(crate) fn arc_steps(&self, n: usize) -> Vec<f64> {
        use rayon::prelude::*;
        let dt = TAU / n as f64;
        (0..n)
            .into_par_iter()
            .with_min_len(128)
            .map(|i| self.eval_d1(i as f64 * dt).1.norm() * dt)
            .collect()
    }

    /// Samples the closed profile: `points_per_tooth` points per tooth, `Zc` teeth, in the
    /// direction of increasing `t` (clockwise). Returns positions in metres.
    pub fn sample(&self, points_per_tooth: usize) -> Vec<Vec2> {
        let n = points_per_tooth.max(8) * self.geo.disc_teeth();
        let dt = TAU * self.zc / n as f64;
        (0..n).map(|k| self.eval_d1(k as f64 * dt).0).collect()
    }

    /// Smallest convex radius of curvature of the pin-centre path (m), over one tooth.
    /// The profile is undercut when `rrp + drrp` exceeds it (docs/model.md section 2: about
    /// 4.61 mm for the paper's stage).
    pub(crate) fn pin_path_min_convex_radius(&self) -> f64 {
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

    /// Checks that the modified profile without wear is not undercut, on 2000 parameters over
    /// one tooth: the equidistant of the pin-centre path turns back (`dp . dpath <= 0`) where
    /// its radius exceeds the path's local convex radius.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `cycloid.pin_radius_mm + cycloid.modification.equidistant_mm`.
    fn check_undercut(&self) -> Result<()> {
        let n = 2000;
        for k in 0..n {
            let t = TAU * k as f64 / n as f64;
            let (_, dp, _) = self.closed_form(t, self.r_mod);
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
        }
        Ok(())
    }

    /// Initial guess of the profile parameter at which pin `j` touches the disc, for the disc
    /// centre at `a (cos phi, sin phi)` turned by `psi` (rad, counter-clockwise).
    ///
    /// For the unmodified stage with `psi = -phi / Zc` this is exact:
    /// `t_j = -phi - 2 pi j Zc / Zp` (mesh angle `2 pi j / Zp - phi` modulo `2 pi`).
    pub(crate) fn contact_parameter_guess(&self, j: usize, phi: f64, psi: f64) -> f64 {
        let zp = self.geo.pins as f64;
        let extra = psi + phi / self.zc + self.modification.rotation;
        -phi - TAU * j as f64 * self.zc / zp + self.zc * extra
    }
}

/// Half-width (rad of profile parameter: a quarter tooth) of the window searched for a closest
/// point around the kinematic guess. The concave root (mesh angles within about +-35 degrees of
/// 0, radius 3.07 mm against a 3 mm pin in the paper's stage) is nearly conformal with the pin:
/// there the foot of a pin that is a few micrometres off touching can lie anywhere on the root
/// arc, so the window spans the whole root from any guess in it.
pub(crate) const PROJECTION_WINDOW: f64 = std::f64::consts::FRAC_PI_2;

/// The actual (worn) tooth tabulated on a uniform grid of the profile parameter: exact
/// positions and tangents at the nodes, cubic Hermite in between (position error of order
/// `h^4 |d4z/dt4| / 384`, below 1e-13 m with 2048 or more nodes per tooth). The nodes include
/// every node of the wear map, whose depth is a cubic within each of its cells, so the worn
/// tooth is smooth within every table cell. The grid spans `[-0.6, 2 pi + 0.6]` rad so that a
/// window around any parameter of tooth 0 needs no wrap.
#[derive(Debug, Clone, Default)]
pub struct ToothTable {
    t_start: f64,
    dt: f64,
    p: Vec<Vec2>,
    dp: Vec<Vec2>,
    /// The profile without wear at the nodes of one tooth, shared with every worn profile of
    /// its geometry: its curvature (1/m) and the curvature's central-difference slopes per
    /// node step make the periodic cubic Hermite of [`Profile::macro_curvature`].
    unworn: std::sync::Arc<UnwornTooth>,
    /// Upper bound of `|dz/dt|` over each cell of [`SCAN_CELL`] nodes (cell `c` spans nodes
    /// `SCAN_CELL c ..= SCAN_CELL (c + 1)`), m/rad.
    lipschitz: Vec<f64>,
    /// Upper bound of the concave curvature (1/m, 0 where convex) over each cell, with a
    /// margin: the distance from a point can have a local maximum (and so a second local
    /// minimum) only where the concave curvature reaches the inverse of that distance.
    concavity: Vec<f64>,
    /// The largest of `concavity` over each group of [`SUPER_CELL`] cells.
    concavity_super: Vec<f64>,
    /// The largest of `lipschitz`, m/rad.
    lipschitz_max: f64,
}

/// Cells per group in the first pass of the unimodality check.
const SUPER_CELL: usize = 8;

/// Table nodes per cell of the Lipschitz-pruned scan.
const SCAN_CELL: usize = 8;

/// What a [`ToothTable`] takes from the modified profile without wear, shared by every worn
/// profile of the same geometry and modification (a study builds hundreds): the closed form
/// and the macro curvature at the table's nodes of one tooth and the curvature's
/// central-difference slopes, after the undercut check ([`Profile::check_undercut`]).
#[derive(Debug, Default)]
struct UnwornTooth {
    /// [`Profile::closed_form`] at the nodes `t = j 2 pi / per_tooth`, `j = 0..per_tooth`.
    nodes: Vec<(Vec2, Vec2, Vec2)>,
    kappa: Vec<f64>,
    kappa_slope: Vec<f64>,
}

impl UnwornTooth {
    /// The unworn tooth of `profile` on `per_tooth` nodes, remembered for the last few
    /// geometries of the process (keyed by every quantity [`Profile::closed_form`] reads).
    ///
    /// # Errors
    /// Those of [`Profile::check_undercut`].
    fn shared(profile: &Profile, per_tooth: usize) -> Result<std::sync::Arc<Self>> {
        type Memo = Vec<([u64; 8], std::sync::Arc<UnwornTooth>)>;
        static MEMO: std::sync::Mutex<Memo> = std::sync::Mutex::new(Vec::new());
        let key = [
            profile.k1.to_bits(),
            profile.rp_mod.to_bits(),
            profile.r_mod.to_bits(),
            profile.geo.eccentricity.to_bits(),
            profile.alpha.to_bits(),
            profile.beta.to_bits(),
            profile.modification.rotation.to_bits(),
            per_tooth as u64,
        ];
        super::remembered(&MEMO, key, || {
            profile.check_undercut()?;
            let dt = TAU / per_tooth as f64;
            let kappa: Vec<f64> = (0..per_tooth)
                .map(|i| profile.macro_curvature_exact(i as f64 * dt))
                .collect();
            let kappa_slope = (0..per_tooth)
                .map(|i| {
                    0.5 * (kappa[(i + 1) % per_tooth] - kappa[(i + per_tooth - 1) % per_tooth])
                })
                .collect();
            let nodes = (0..per_tooth)
                .map(|i| profile.closed_form(i as f64 * dt, profile.r_mod))
                .collect();
            Ok(std::sync::Arc::new(UnwornTooth {
                nodes,
                kappa,
                kappa_slope,
            }))
        })
    }
}

impl ToothTable {
    /// Nodes per tooth of the table of `profile`: 2048, raised to a multiple of the wear map's
    /// points so that every map node is a table node.
    fn nodes_per_tooth(profile: &Profile) -> usize {
        match &profile.wear {
            Some(w) => {
                let n = w.depths().len();
                n * 2048usize.div_ceil(n)
            }
            None => 2048,
        }
    }

    /// The table of `profile` (nodes of one tooth evaluated, in parallel, and turned onto the
    /// neighbouring teeth: `z(t + 2 pi k) = z(t) e^(-2 pi i k / Zc)`), with `unworn` its
    /// profile's without wear.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the wear map where the worn flank folds over itself at a node
    /// ([`Profile::eval_d1_folds`]).
    fn new(profile: &Profile, unworn: std::sync::Arc<UnwornTooth>) -> Result<Self> {
        use rayon::prelude::*;
        let per_tooth = Self::nodes_per_tooth(profile);
        let dt = TAU / per_tooth as f64;
        let m = ((PROJECTION_WINDOW + 0.1) / dt).ceil() as usize;
        let count = per_tooth + 2 * m + 1;
        let t_start = -(m as f64) * dt;
        // One tooth, t = j dt for j = 0..per_tooth.
        let tooth: Vec<((Vec2, Vec2, Vec2), bool)> = (0..per_tooth)
            .into_par_iter()
            .with_min_len(256)
            .map(|j| profile.worn_at(j as f64 * dt, unworn.nodes[j]))
            .collect();
        if let Some(j) = tooth.iter().position(|x| x.1) {
            let t = j as f64 * dt;
            let h = profile.wear.as_ref().map_or(0.0, |w| w.eval(t).0);
            return Err(Error::invalid(
                "wear map",
                format!("{:.2} um at mesh angle {:.2} deg", h * 1e6, t.to_degrees()),
                "the worn profile folds over itself: wear deeper than the local convex radius \
                 or too steep along the profile",
            ));
        }
        // Node i is t = (i - m) dt = j dt + 2 pi k.
        let turns: Vec<(f64, f64)> = (-1..=1)
            .map(|k: i64| (-TAU * k as f64 / profile.zc).sin_cos())
            .collect();
        let mut p = Vec::with_capacity(count);
        let mut dp = Vec::with_capacity(count);
        for i in 0..count {
            let shifted = i as i64 - m as i64;
            let k = shifted.div_euclid(per_tooth as i64);
            let j = shifted.rem_euclid(per_tooth as i64) as usize;
            let (pj, dpj, _) = tooth[j].0;
            if k == 0 {
                p.push(pj);
                dp.push(dpj);
            } else {
                let turn = turns[(k + 1) as usize];
                p.push(rotate_by(&pj, turn));
                dp.push(rotate_by(&dpj, turn));
            }
        }
        // Per cell, the largest node speed with 5 % for the Hermite bulge between nodes, and
        // the largest concave curvature from the tangent's turning between nodes (the mean over
        // each node step), raised by the largest change between neighbouring steps.
        let cells = count.div_ceil(SCAN_CELL);
        let lipschitz: Vec<f64> = (0..cells)
            .map(|c| {
                let (a, b) = (c * SCAN_CELL, ((c + 1) * SCAN_CELL).min(count - 1));
                1.05 * dp[a..=b].iter().map(|v| v.norm()).fold(0.0, f64::max)
            })
            .collect();
        let turn = |i: usize| {
            // Signed curvature between nodes i and i + 1: turning of the tangent over the arc.
            let (u, v) = (dp[i], dp[i + 1]);
            let ang = cross(&u, &v).atan2(u.dot(&v));
            let arc = 0.5 * (u.norm() + v.norm()) * dt;
            -ang / arc
        };
        let steps: Vec<f64> = (0..count - 1).map(|i| -turn(i)).collect();
        let concavity: Vec<f64> = (0..cells)
            .map(|c| {
                let a = (c * SCAN_CELL).saturating_sub(1);
                let b = ((c + 1) * SCAN_CELL + 1).min(count - 2);
                let k = (a..b).map(|i| steps[i].max(0.0)).fold(0.0, f64::max);
                // The curvature within a step departs from the step's mean by at most the
                // change between neighbouring steps.
                let var = (a..b)
                    .map(|i| (steps[i + 1] - steps[i]).abs())
                    .fold(0.0, f64::max);
                1.01 * (k + var) + 1.0
            })
            .collect();
        let concavity_super = concavity
            .chunks(SUPER_CELL)
            .map(|c| c.iter().copied().fold(0.0, f64::max))
            .collect();
        let lipschitz_max = lipschitz.iter().copied().fold(0.0, f64::max);
        Ok(ToothTable {
            t_start,
            dt,
            p,
            dp,
            unworn,
            lipschitz,
            concavity,
            concavity_super,
            lipschitz_max,
        })
    }

    /// Table step, rad.
    pub fn step(&self) -> f64 {
        self.dt
    }

    /// Position, first and second derivative (m, m/rad, m/rad^2) of the tabulated tooth at
    /// parameter `t` (rad, within the table's span; clamped to its end cells outside).
    #[inline]
    pub(crate) fn eval(&self, t: f64) -> (Vec2, Vec2, Vec2) {
        let s = (t - self.t_start) / self.dt;
        let i = (s.floor().max(0.0) as usize).min(self.p.len() - 2);
        let u = s - i as f64;
        let (p1, p2) = (self.p[i], self.p[i + 1]);
        let (m1, m2) = (self.dp[i] * self.dt, self.dp[i + 1] * self.dt);
        let (u2, u3) = (u * u, u * u * u);
        let z = p1 * (2.0 * u3 - 3.0 * u2 + 1.0)
            + m1 * (u3 - 2.0 * u2 + u)
            + p2 * (-2.0 * u3 + 3.0 * u2)
            + m2 * (u3 - u2);
        let dz = ((p1 - p2) * (6.0 * u2 - 6.0 * u)
            + m1 * (3.0 * u2 - 4.0 * u + 1.0)
            + m2 * (3.0 * u2 - 2.0 * u))
            / self.dt;
        let ddz = ((p1 - p2) * (12.0 * u - 6.0) + m1 * (6.0 * u - 4.0) + m2 * (6.0 * u - 2.0))
            / (self.dt * self.dt);
        (z, dz, ddz)
    }

    /// Curvature of the modified profile without wear at mesh angle `m` (rad, in `[0, 2 pi)`),
    /// 1/m: the periodic cubic Hermite of the node values (relative error below 1e-7).
    pub(crate) fn curvature(&self, m: f64) -> f64 {
        let (kappa, slope) = (&self.unworn.kappa, &self.unworn.kappa_slope);
        let n = kappa.len();
        let s = m / self.dt;
        let i = (s.floor().max(0.0) as usize) % n;
        let j = (i + 1) % n;
        let u = s - s.floor();
        cubic_hermite(kappa[i], slope[i], kappa[j], slope[j], u).0
    }

    fn node_t(&self, i: usize) -> f64 {
        self.t_start + i as f64 * self.dt
    }

    /// Foot of the normal from `q` in `[lo, hi]` (rad), starting at `t0`: Newton on
    /// `f = (z - q) . z'` with bisection whenever a step leaves the bracket (kept on the sign of
    /// `f`). `None` if the distance does not fall into the bracket from both ends (no interior
    /// minimum).
    pub(crate) fn polish(&self, q: &Vec2, t0: f64, lo: f64, hi: f64) -> Option<f64> {
        let f_at = |t: f64| {
            let (z, dz, ddz) = self.eval(t);
            let d = z - q;
            (
                d.dot(&dz),
                dz.norm_squared() + d.dot(&ddz),
                dz.norm_squared(),
            )
        };
        let (mut lo, mut hi) = (lo, hi);
        if f_at(lo).0 >= 0.0 || f_at(hi).0 <= 0.0 {
            return None;
        }
        let mut t = t0.clamp(lo, hi);
        for _ in 0..80 {
            let (f, fp, g) = f_at(t);
            if f < 0.0 {
                lo = t;
            } else {
                hi = t;
            }
            let newton = if fp > 1e-9 * g { t - f / fp } else { f64::NAN };
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            // Converged when the foot moves by less than 1e-15 m along the flank.
            if (next - t).abs() * g.sqrt() < 1e-15 || hi - lo < 1e-14 {
                return Some(next);
            }
            t = next;
        }
        Some(t)
    }

    /// Global minimum of the distance from `q` over `[tc - w, tc + w]` (see
    /// [`Profile::project`]): the first of [`ToothTable::local_minima`] with no margin.
    pub(crate) fn global_foot(&self, q: &Vec2, tc: f64, w: f64, seed: Option<f64>) -> Option<f64> {
        self.local_minima(q, tc, w, seed, 0.0).map(|v| v[0].1)
    }

    /// Every local minimum of the distance from `q` over `[tc - w, tc + w]` whose distance is
    /// within `margin` (m) of the global minimum, as `(distance, t)` pairs, closest first,
    /// starting from the local foot `seed` if one is known (it makes the best distance tight
    /// from the start, so that most cells are pruned; the node step that holds it is not
    /// polished again). `None` if the global minimum lies on the
    /// window's edge (minima on the edge are left out).
    ///
    /// Only cells whose Lipschitz bound on the distance is within `margin` of the best can hold
    /// such a minimum; if none of them can hold a local maximum of the distance either
    /// (concave curvature times the largest distance in the cell below 1), the seed is the
    /// only minimum.
    pub(crate) fn local_minima(
        &self,
        q: &Vec2,
        tc: f64,
        w: f64,
        seed: Option<f64>,
        margin: f64,
    ) -> Option<Vec<(f64, f64)>> {
        let last = self.p.len() - 1;
        let node = |t: f64| (((t - self.t_start) / self.dt).round().max(0.0) as usize).min(last);
        let (first_node, last_node) = (node(tc - w), node(tc + w));
        let edge = 1.5 * self.dt;
        let inside =
            |t: f64| t - self.node_t(first_node) >= edge && self.node_t(last_node) - t >= edge;
        let dist = |i: usize| (self.p[i] - q).norm();
        let mut feet: Vec<(f64, f64)> = seed
            .map(|t| ((self.eval(t).0 - q).norm(), t))
            .into_iter()
            .collect();
        let mut best = feet.first().map_or(f64::INFINITY, |f| f.0);
        let h = SCAN_CELL as f64 * self.dt;
        let c0 = first_node / SCAN_CELL;
        let c1 = last_node.div_ceil(SCAN_CELL);
        if let Some(&(_, tf)) = feet.first() {
            // First pass over groups of cells: the distance within a group is at most the best
            // plus the largest speed times the parameter distance from the foot, so a group
            // whose concave curvature stays below the inverse of that bound is cleared without
            // computing a distance (most of a convex or gently concave flank).
            let mut unimodal = true;
            'groups: for sc in c0 / SUPER_CELL..=(c1.saturating_sub(1)) / SUPER_CELL {
                let first = (sc * SUPER_CELL).max(c0);
                let last = ((sc + 1) * SUPER_CELL).min(c1);
                let ta = self.node_t(first * SCAN_CELL);
                let tb = self.node_t(last * SCAN_CELL);
                let far = (ta - tf).abs().max((tb - tf).abs());
                if self.concavity_super[sc] * (best + margin + self.lipschitz_max * far) < 1.0 {
                    continue;
                }
                let mut da = dist((first * SCAN_CELL).clamp(first_node, last_node));
                for c in first..last {
                    let b = ((c + 1) * SCAN_CELL).clamp(first_node, last_node);
                    let db = dist(b);
                    let slack = 0.5 * self.lipschitz[c] * h;
                    if 0.5 * (da + db) - slack <= best + margin + 1e-12
                        && self.concavity[c] * (da.max(db) + slack) >= 1.0
                    {
                        unimodal = false;
                        break 'groups;
                    }
                    da = db;
                }
            }
            if unimodal {
                return inside(tf).then_some(feet);
            }
        }
        let mut da = dist((c0 * SCAN_CELL).clamp(first_node, last_node));
        for c in c0..c1 {
            let a = (c * SCAN_CELL).clamp(first_node, last_node);
            let b = ((c + 1) * SCAN_CELL).clamp(first_node, last_node);
            if b <= a {
                continue;
            }
            let db = dist(b);
            let bound = 0.5 * (da + db - self.lipschitz[c] * h);
            let d_next = db;
            if bound <= best + margin + 1e-12 {
                // Every minimum is an upward sign change of f = (z - q) . z' between two
                // nodes (the nodes' exact tangents give f there); each is polished in its step.
                let fk = |i: usize| (self.p[i] - q).dot(&self.dp[i]);
                let mut f0 = fk(a);
                for k in a..b {
                    let f1 = fk(k + 1);
                    let (tl, th) = (self.node_t(k), self.node_t(k + 1));
                    // The seed's own step holds the seed's minimum, polished already (one
                    // sign change of `f` a step).
                    let seeded = seed.is_some_and(|t| tl <= t && t <= th);
                    if f0 < 0.0 && f1 >= 0.0 && !seeded {
                        let near = dist(k).min(dist(k + 1)) - self.lipschitz[c] * self.dt;
                        if near <= best + margin {
                            // A foot on a node can test as either side of it: widen the bracket.
                            let t = self.polish(q, 0.5 * (tl + th), tl, th).or_else(|| {
                                self.polish(q, 0.5 * (tl + th), tl - self.dt, th + self.dt)
                            });
                            if let Some(t) = t {
                                let dd = (self.eval(t).0 - q).norm();
                                if feet.iter().all(|f| (f.1 - t).abs() > 1e-7) {
                                    feet.push((dd, t));
                                }
                                best = best.min(dd);
                            }
                        }
                    }
                    f0 = f1;
                }
            }
            da = d_next;
        }
        feet.sort_by(|a, b| a.0.total_cmp(&b.0));
        let &(best, t_best) = feet.first()?;
        if !inside(t_best) {
            return None;
        }
        feet.retain(|f| f.0 <= best + margin && inside(f.1));
        Some(feet)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    /// The example's profile worn by a smooth dent (2-12 um over the tooth).
    fn worn() -> Profile {
        let model = Config::example().validate().unwrap();
        let n = model.wear_inputs().grid_points();
        let depth = (0..n)
            .map(|m| 7e-6 - 5e-6 * (TAU * m as f64 / n as f64).cos())
            .collect();
        model
            .cycloid
            .profile(Some(WearMap::new(depth).unwrap()))
            .unwrap()
    }

    /// Every node of the tabulated tooth, those turned onto the neighbouring teeth included,
    /// is the profile evaluated at its parameter: positions within 1e-15 m and tangents within
    /// 1e-15 m/rad (the turn's round-off; the profile spans 0.1 m), new and worn.
    #[test]
    fn tooth_table_nodes_are_the_profile() {
        let new = Config::example().validate().unwrap().profile().unwrap();
        for (name, p) in [("new", new), ("worn", worn())] {
            let table = &p.table;
            assert!(table.t_start < -PROJECTION_WINDOW && table.p.len() as f64 * table.dt > TAU);
            for i in 0..table.p.len() {
                let (z, dz, _) = p.eval_d1(table.node_t(i));
                assert!((table.p[i] - z).norm() < 1e-15, "{name} node {i}");
                assert!((table.dp[i] - dz).norm() < 1e-15, "{name} node {i}");
            }
        }
    }

    /// Wear deeper than the flank's local convex radius turns it back on itself
    /// (`dp_w . dp = |dp|^2 (1 - h kappa) <= 0`): 20 mm of uniform wear (the tips' convex
    /// radius is a few millimetres) is refused, naming the wear map, the depth and the mesh
    /// angle; 0.1 mm is a profile.
    #[test]
    fn folded_wear_map_rejected() {
        let model = Config::example().validate().unwrap();
        let n = model.wear_inputs().grid_points();
        let uniform = |h: f64| model.cycloid.profile(Some(WearMap::uniform(n, h).unwrap()));
        let e = uniform(20e-3).unwrap_err().to_string();
        assert!(
            e.contains("wear map") && e.contains("folds over itself"),
            "{e}"
        );
        assert!(e.contains("20000.00 um at mesh angle"), "{e}");
        assert!(uniform(1e-4).is_ok());
    }
}
