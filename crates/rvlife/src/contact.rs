//! Loaded tooth contact between the cycloid disc and the pins.
//!
//! - Hertz line contact of a pin (radius `rrp`) on the disc flank (curvature from the actual
//!   profile): half-width, maximum pressure (Johnson, *Contact Mechanics*, 1985, eq 4.43) and the
//!   approach laws of physics-notes section 4 (paper eqs 6-7 with the Hertz half-width, or
//!   Johnson's eq 5.38-style form), or a linear spring for checks against Li's closed form.
//! - The gap of every pin measured from the actual (modified, worn) profile, exactly, by
//!   projecting the pin centre on the profile ([`pin_geometry`]).
//! - The disc rotation that balances the disc's torque share ([`solve`]): the extra rotation
//!   beyond the nominal `-phi / Zc` that takes up the backlash and compresses the contacts
//!   until `sum_j F_j l_j = T_disc` (physics-notes section 4, done on true gaps instead of Li's
//!   `delta_i = l_i beta - gap_i` linearisation).
//!
//! Sign conventions: a positive disc torque `T_disc` turns the disc counter-clockwise against
//! the pins of the flank `0 < mesh angle < pi`; the solved `disc_rotation` is then positive.
//! The lever arm `l_j = (p_c x n)_z` of pin `j` (contact point `p_c` from the disc centre,
//! outward normal `n`) is positive on that flank; the pin pushes on the disc with the moment
//! `-F_j l_j`.

pub mod elastic;

use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentRoot;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::geometry::{cross, mesh_angle, rotate, CycloidGeometry, Profile, Vec2};
pub use crate::reducer::statics::PinLoad;

/// Elastic constants of the disc and the pins, Pa (paper Table 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Materials {
    /// Young's modulus of the disc `E1`, Pa.
    pub disc_youngs_modulus: f64,
    /// Poisson's ratio of the disc `nu1`.
    pub disc_poisson_ratio: f64,
    /// Young's modulus of the pins `E2`, Pa.
    pub pin_youngs_modulus: f64,
    /// Poisson's ratio of the pins `nu2`.
    pub pin_poisson_ratio: f64,
}

impl Materials {
    /// Compliances `(1 - nu1^2)/E1`, `(1 - nu2^2)/E2`, 1/Pa.
    pub fn compliances(&self) -> (f64, f64) {
        (
            (1.0 - self.disc_poisson_ratio.powi(2)) / self.disc_youngs_modulus,
            (1.0 - self.pin_poisson_ratio.powi(2)) / self.pin_youngs_modulus,
        )
    }

    /// Contact modulus `E*` with `1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2` (paper eq 13), Pa.
    pub fn contact_modulus(&self) -> f64 {
        let (c1, c2) = self.compliances();
        1.0 / (c1 + c2)
    }
}

/// The approach (normal compliance) law of one pin-tooth line contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ApproachLaw {
    /// Paper eq 6 with the Hertz half-width of eq 11 (default):
    /// `delta = 2F/(pi B) [C1 (1/3 + ln(4 rho/b)) + C2 (1/3 + ln(4 rrp/b))]`.
    Paper,
    /// Johnson's form: `delta = F/(pi B) sum_k C_k (2 ln(4 R_k / b) - 1)`, about 11 % stiffer.
    Johnson,
    /// A linear spring `F = k delta` (stiffness in N/m), for checks against Li's closed form.
    Linear {
        /// Stiffness, N/m.
        stiffness: f64,
    },
}

/// Hertz line-contact model of a pin on the disc flank.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    /// The approach law.
    pub law: ApproachLaw,
    /// The materials.
    pub materials: Materials,
    /// Contact length (disc width) `B`, m.
    pub width: f64,
    /// Pin radius `rrp`, m.
    pub pin_radius: f64,
    /// Cap on the disc's radius of curvature in the reduced radius (and, with
    /// `disc_depth = None`, in the disc term of the approach law), m. Near the inflection of the
    /// profile (mesh angle about 35 deg) the flank is nearly flat and the 2D approach
    /// `ln(4 rho / b)` has no finite limit; the cap (default: the pin circle radius, the size of
    /// the disc) stands for the finite body.
    pub max_radius: f64,
    /// Reference depth `d` of the disc term of the approach law, `C1 (c0 + ln(4 d / b))`, m.
    /// `Some(d)`: the same depth at every flank point (default `d = Rp`: the approach of the
    /// flank relative to the disc body at the scale of the disc, where the bearings hold it), so
    /// that concave, flat and convex flanks differ only through the Hertz half-width. `None`:
    /// the paper's eq 6 as printed, the local flank radius of curvature (capped at
    /// `max_radius`): concave root contacts (radius about 3-5 mm) come out about 65 % stiffer in
    /// the disc term than mid-flank ones (capped at 64 mm), which is an artefact of the 2D
    /// half-space reference, not a property of the disc.
    pub disc_depth: Option<f64>,
}

/// Hertz quantities of one loaded contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzState {
    /// Normal force, N.
    pub force: f64,
    /// Contact half-width `b`, m (paper eq 11).
    pub half_width: f64,
    /// Maximum Hertz pressure `p0 = 2F/(pi b B)`, Pa.
    pub max_pressure: f64,
    /// Mean pressure `F/(2 b B)`, Pa (paper eq 19).
    pub mean_pressure: f64,
}

impl ContactModel {
    /// Reduced radius `R*` with `1/R* = 1/rrp + k` (`k` the disc curvature, negative where the
    /// flank is concave), capped at `max_radius`; m.
    pub fn reduced_radius(&self, disc_curvature: f64) -> f64 {
        let inv = 1.0 / self.pin_radius + disc_curvature;
        if inv <= 1.0 / self.max_radius {
            self.max_radius
        } else {
            (1.0 / inv).min(self.max_radius)
        }
    }

    /// Hertz half-width, maximum and mean pressure of force `force` (N) on a flank of
    /// curvature `disc_curvature` (1/m). Zero force gives zeros.
    pub fn hertz(&self, force: f64, disc_curvature: f64) -> HertzState {
        if force <= 0.0 {
            return HertzState {
                force: 0.0,
                half_width: 0.0,
                max_pressure: 0.0,
                mean_pressure: 0.0,
            };
        }
        let r = self.reduced_radius(disc_curvature);
        let e = self.materials.contact_modulus();
        let b = (4.0 * force * r / (std::f64::consts::PI * self.width * e)).sqrt();
        HertzState {
            force,
            half_width: b,
            max_pressure: 2.0 * force / (std::f64::consts::PI * b * self.width),
            mean_pressure: force / (2.0 * b * self.width),
        }
    }

    /// Constant `c0` and the two radii of the logarithmic laws.
    fn log_law_terms(&self, disc_curvature: f64) -> (f64, f64, f64) {
        let c0 = match self.law {
            ApproachLaw::Johnson => -0.5,
            _ => 1.0 / 3.0,
        };
        let rho = match self.disc_depth {
            Some(d) => d,
            None if disc_curvature.abs() < 1.0 / self.max_radius => self.max_radius,
            None => 1.0 / disc_curvature.abs(),
        };
        (c0, rho, self.pin_radius)
    }

    /// Coefficients `(g0, g1)` of the logarithmic laws written as `delta = F (g0 - g1 ln F)`
    /// (F in N, delta in m), on a flank of curvature `disc_curvature`; `None` for the linear
    /// law.
    fn log_coefficients(&self, disc_curvature: f64) -> Option<(f64, f64)> {
        if let ApproachLaw::Linear { .. } = self.law {
            return None;
        }
        let pi = std::f64::consts::PI;
        let (c0, rho, rp) = self.log_law_terms(disc_curvature);
        let (c1, c2) = self.materials.compliances();
        let r = self.reduced_radius(disc_curvature);
        let e = self.materials.contact_modulus();
        // b = sqrt(cb F); ln(4R/b) = ln(4R) - ln(cb)/2 - ln(F)/2.
        let cb = 4.0 * r / (pi * self.width * e);
        let k = 2.0 / (pi * self.width);
        let g0 = k
            * (c1 * (c0 + (4.0 * rho).ln() - 0.5 * cb.ln())
                + c2 * (c0 + (4.0 * rp).ln() - 0.5 * cb.ln()));
        let g1 = 0.5 * k * (c1 + c2);
        Some((g0, g1))
    }

    /// Change of the contact force with the flank curvature at a fixed approach, `dF/dkappa`
    /// (N m), for a contact carrying `force` (N) with stiffness `stiffness` (N/m) on a flank of
    /// curvature `disc_curvature` (1/m): from `delta = F (g0(kappa) - g1 ln F)`,
    /// `dF/dkappa = -F g0'(kappa) dF/ddelta` (`g0'` by a central difference of the closed
    /// form). Zero for the linear law or no force.
    pub fn force_curvature_derivative(
        &self,
        force: f64,
        stiffness: f64,
        disc_curvature: f64,
    ) -> f64 {
        if force <= 0.0 {
            return 0.0;
        }
        let h = 1e-6 * disc_curvature.abs().max(1.0);
        match (
            self.log_coefficients(disc_curvature + h),
            self.log_coefficients(disc_curvature - h),
        ) {
            (Some((gp, _)), Some((gm, _))) => -force * stiffness * (gp - gm) / (2.0 * h),
            _ => 0.0,
        }
    }

    /// Elastic energy `int_0^delta F d(delta)` (J) stored in the contact at approach `delta` (m):
    /// for the logarithmic laws, with `delta = F (g0 - g1 ln F)`, exactly
    /// `F^2/2 (g0 - g1/2 - g1 ln F)`; `k delta^2 / 2` for the linear law. Zero for
    /// `delta <= 0`.
    ///
    /// # Errors
    /// As [`ContactModel::force`].
    pub fn potential(&self, delta: f64, disc_curvature: f64) -> Result<f64> {
        if delta <= 0.0 {
            return Ok(0.0);
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return Ok(0.5 * stiffness * delta * delta);
        }
        let (f, _) = self.force(delta, disc_curvature)?;
        let (g0, g1) = self
            .log_coefficients(disc_curvature)
            .expect("logarithmic law");
        Ok(0.5 * f * f * (g0 - 0.5 * g1 - g1 * f.ln()))
    }

    /// Approach `delta` (m) of the force `force` (N) on a flank of curvature `disc_curvature`.
    pub fn approach(&self, force: f64, disc_curvature: f64) -> f64 {
        if force <= 0.0 {
            return 0.0;
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return force / stiffness;
        }
        let (c0, rho, rp) = self.log_law_terms(disc_curvature);
        let (c1, c2) = self.materials.compliances();
        let b = self.hertz(force, disc_curvature).half_width;
        2.0 * force / (std::f64::consts::PI * self.width)
            * (c1 * (c0 + (4.0 * rho / b).ln()) + c2 * (c0 + (4.0 * rp / b).ln()))
    }

    /// Force (N) and contact stiffness `dF/ddelta` (N/m) at approach `delta` (m): the inverse of
    /// [`ContactModel::approach`], by Newton's method in `ln F` (the law is `F` times a function
    /// linear in `ln F`).
    ///
    /// # Errors
    /// [`Error::Numerical`] if the approach is beyond the range where the logarithmic law
    /// increases with force (half-width comparable with the radii).
    pub fn force(&self, delta: f64, disc_curvature: f64) -> Result<(f64, f64)> {
        if delta <= 0.0 {
            return Ok((0.0, 0.0));
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return Ok((stiffness * delta, stiffness));
        }
        self.force_from(delta, disc_curvature, f64::NAN)
    }

    /// [`ContactModel::force`] with a starting guess `f_guess` (N) for the Newton iteration (a
    /// warm start from the previous force of the same contact; ignored if not positive).
    ///
    /// # Errors
    /// As [`ContactModel::force`].
    pub fn force_from(&self, delta: f64, disc_curvature: f64, f_guess: f64) -> Result<(f64, f64)> {
        if delta <= 0.0 {
            return Ok((0.0, 0.0));
        }
        if let ApproachLaw::Linear { stiffness } = self.law {
            return Ok((stiffness * delta, stiffness));
        }
        let (g0, g1) = self
            .log_coefficients(disc_curvature)
            .expect("logarithmic law");
        // delta = e^u (g0 - g1 u) with u = ln F; solve ln delta = u + ln(g0 - g1 u).
        let target = delta.ln();
        let warm = if f_guess > 0.0 {
            f_guess.ln()
        } else {
            f64::NAN
        };
        let mut u = if g0 - g1 * warm > 2.0 * g1 {
            warm
        } else {
            (delta / (g0 - g1 * 10.0_f64.ln()).max(1e-30)).ln()
        };
        for _ in 0..60 {
            let g = g0 - g1 * u;
            if g <= g1 {
                return Err(Error::numerical(
                    "contact law",
                    format!(
                        "approach {:.3e} m is beyond the validity of the line-contact law",
                        delta
                    ),
                ));
            }
            let f = u + g.ln() - target;
            let fp = 1.0 - g1 / g;
            let step = f / fp;
            u -= step;
            // Relative to |u|: at approaches of 1e-30 m, u = ln F is about -60 and its ulp
            // alone is 7e-15. Newton's error after a step is `c step^2` with
            // `c = |f''| / (2 |f'|) = g1^2 / (2 g (g - g1))`; a step whose square makes that
            // smaller than the tolerance ends the iteration too (a warm start then takes one
            // logarithm in place of two).
            let tol = 1e-14 * u.abs().max(1.0);
            if step.abs() < tol || g1 * g1 / (2.0 * g * (g - g1)) * step * step < 0.1 * tol {
                let force = u.exp();
                let g = g0 - g1 * u;
                let stiffness = 1.0 / (g - g1);
                return Ok((force, stiffness));
            }
        }
        Err(Error::numerical(
            "contact law",
            format!("force for approach {delta:e} m did not converge"),
        ))
    }
}

/// Geometry of one pin against the actual profile at one disc pose.
#[derive(Debug, Clone, Copy)]
pub struct PinGeometry {
    /// Pin index `j`.
    pub pin: usize,
    /// Profile parameter of the closest profile point, rad.
    pub t: f64,
    /// Gap between pin and flank along the normal, m (negative: penetration).
    pub gap: f64,
    /// Lever arm `l = (p_c x n)_z` about the disc centre, m.
    pub lever_arm: f64,
    /// Contact point in the disc frame, m.
    pub point: Vec2,
    /// Outward unit normal of the flank at the contact point (disc frame).
    pub normal: Vec2,
    /// Flank curvature at the contact point for the contact law, 1/m (negative: concave): that
    /// of the modified profile ([`Profile::macro_curvature`]).
    pub curvature: f64,
}

/// Disc pose for crank angle `phi` and extra rotation `beta` (rad): the disc centre
/// `a (cos phi, sin phi)` (m, pin-ring frame) and the disc rotation `psi = -phi/Zc + beta` (rad)
/// (physics-notes section 3).
pub fn disc_pose(geo: &CycloidGeometry, phi: f64, beta: f64) -> (Vec2, f64) {
    let zc = geo.disc_teeth() as f64;
    let centre = Vec2::new(geo.eccentricity * phi.cos(), geo.eccentricity * phi.sin());
    (centre, -phi / zc + beta)
}

/// Pose of a disc in the pin-ring frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscPose {
    /// Crank angle `phi` whose kinematics the pose is near (rad): it gives the kinematic guess
    /// of every contact parameter ([`Profile::contact_parameter_guess`]).
    pub crank_angle: f64,
    /// Disc centre, m.
    pub centre: Vec2,
    /// Angle of the profile frame, rad (counter-clockwise).
    pub angle: f64,
}

impl DiscPose {
    /// The pose of crank angle `phi` turned by `beta` beyond nominal ([`disc_pose`]).
    pub fn at(geo: &CycloidGeometry, phi: f64, beta: f64) -> Self {
        let (centre, angle) = disc_pose(geo, phi, beta);
        DiscPose {
            crank_angle: phi,
            centre,
            angle,
        }
    }

    /// Centre of pin `j` in the profile frame, m.
    pub fn pin_in_disc(&self, geo: &CycloidGeometry, j: usize) -> Vec2 {
        rotate(&(geo.pin_centre(j) - self.centre), -self.angle)
    }
}

/// Measures pin `j` against the actual profile at disc pose `pose`: the global closest point
/// within the search window ([`Profile::project`]), or, with `hint = Some(t)` (the contact
/// parameter found at a nearby pose, rad), a warm-started local search that falls back to the
/// global one when the foot leaves its bracket.
///
/// # Errors
/// [`Error::Numerical`] if the projection fails.
pub fn pin_at_pose(
    profile: &Profile,
    j: usize,
    pose: &DiscPose,
    hint: Option<f64>,
) -> Result<PinGeometry> {
    let geo = profile.geometry();
    let q = pose.pin_in_disc(geo, j);
    let proj = match hint.and_then(|t| profile.project_near(&q, t)) {
        Some(p) => p,
        None => {
            let t0 = profile.contact_parameter_guess(j, pose.crank_angle, pose.angle);
            profile.project(&q, t0)?
        }
    };
    Ok(pin_geometry_of(profile, j, proj))
}

fn pin_geometry_of(profile: &Profile, j: usize, proj: crate::geometry::Projection) -> PinGeometry {
    let pt = proj.point;
    PinGeometry {
        pin: j,
        t: pt.t,
        gap: proj.distance - profile.geometry().pin_radius,
        lever_arm: cross(&pt.p, &pt.normal),
        point: pt.p,
        normal: pt.normal,
        curvature: profile.macro_curvature(pt.t),
    }
}

/// Measures pin `j` against the actual profile for crank angle `phi` (rad, direction of the
/// eccentric in the pin-ring frame) and extra disc rotation `beta` (rad), the disc centre on the
/// eccentric: [`pin_at_pose`] with the global search.
///
/// # Errors
/// [`Error::Numerical`] if the projection fails.
pub fn pin_geometry(profile: &Profile, j: usize, phi: f64, beta: f64) -> Result<PinGeometry> {
    pin_at_pose(
        profile,
        j,
        &DiscPose::at(profile.geometry(), phi, beta),
        None,
    )
}

/// Geometry of every pin at one pose (see [`pin_geometry`]), in pin order.
pub fn pin_geometries(profile: &Profile, phi: f64, beta: f64) -> Result<Vec<PinGeometry>> {
    (0..profile.geometry().pins)
        .map(|j| pin_geometry(profile, j, phi, beta))
        .collect()
}

/// Extra disc rotation (rad) at which the disc first touches a pin when turned from the nominal
/// position in direction `direction` (+1: counter-clockwise, the flank `0 < mesh angle < pi`;
/// -1: clockwise), for crank angle `phi`. Zero for an unmodified, unworn disc.
///
/// This is the fixed-crank, single-disc view of the flexible-disc analysis; the reducer's own
/// static TE, along the locked-input mode over both discs, is
/// [`crate::reducer::statics::StaticAnalysis::first_contact`].
///
/// Solved exactly on the actual profile: from the linear estimates `gap_j / l_j` over every pin
/// that closes in this direction (no lever-arm cut-off), each nearby candidate's own touching
/// rotation is solved, then every pin is checked at the result (a pin that closes faster than
/// linearly can touch first).
///
/// # Errors
/// [`Error::Numerical`] if no pin can stop the disc or a projection fails.
pub fn first_contact(profile: &Profile, phi: f64, direction: f64) -> Result<f64> {
    let s = direction.signum();
    let lmin = 0.0;
    let geoms = pin_geometries(profile, phi, 0.0)?;
    let mut beta = geoms
        .iter()
        .filter(|g| s * g.lever_arm > lmin)
        .map(|g| g.gap / g.lever_arm)
        .min_by(|a, b| (s * a).total_cmp(&(s * b)))
        .ok_or_else(|| Error::numerical("first contact", "no pin on the driving flank"))?;
    // Candidates: pins whose linear estimate is near the minimum; each is solved exactly for
    // its own touching rotation (Newton on gap_j(beta) = 0, d gap_j / d beta = -l_j).
    let mut best = f64::INFINITY;
    // Near candidates first; if none of them can be solved, every driving pin.
    for margin in [0.25 * beta.abs() + 1e-6, f64::INFINITY] {
        for (j, g0) in geoms.iter().enumerate() {
            if s * g0.lever_arm <= lmin {
                continue;
            }
            let est = g0.gap / g0.lever_arm;
            if s * (est - beta) > margin {
                continue;
            }
            if let Some(b) = touching_rotation(profile, j, phi, est, s)? {
                best = best.min(s * b);
            }
        }
        if best.is_finite() {
            break;
        }
    }
    if !best.is_finite() {
        return Err(Error::numerical(
            "first contact",
            format!("no pin stops the disc at crank angle {phi} rad"),
        ));
    }
    // A pin whose gap closes faster than its linear estimate can touch earlier than the
    // candidates: check every driving pin at the result and take any that already penetrates.
    for _ in 0..10 {
        beta = s * best;
        let mut improved = false;
        for (j, g0) in geoms.iter().enumerate() {
            if s * g0.lever_arm <= lmin {
                continue;
            }
            let g = pin_geometry(profile, j, phi, beta)?;
            if g.gap < -1e-12 {
                if let Some(b) = touching_rotation(profile, j, phi, beta, s)? {
                    if s * b < best {
                        best = s * b;
                        improved = true;
                    }
                }
            }
        }
        if !improved {
            break;
        }
    }
    beta = s * best;
    Ok(beta)
}

/// Rotation (rad) at which pin `j` touches the flank, near the linear estimate `est`, turning in
/// direction `s`: Newton on `gap_j(beta) = 0` (`d gap / d beta = -l_j`); where the gap has a kink
/// (the foot jumps across a worn dent) and Newton cycles, Brent's method on a bracket.
fn touching_rotation(
    profile: &Profile,
    j: usize,
    phi: f64,
    est: f64,
    s: f64,
) -> Result<Option<f64>> {
    let mut b = est;
    for _ in 0..12 {
        let g = pin_geometry(profile, j, phi, b)?;
        if s * g.lever_arm <= 0.0 {
            return Ok(None);
        }
        if g.gap.abs() < 1e-14 {
            return Ok(Some(b));
        }
        b += g.gap / g.lever_arm;
    }
    struct Gap<'a>(&'a Profile, usize, f64);
    impl CostFunction for Gap<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, b: &f64) -> std::result::Result<f64, argmin::core::Error> {
            Ok(pin_geometry(self.0, self.1, self.2, *b)?.gap)
        }
    }
    // gap decreases with s * beta: bracket from the open side to the closed side.
    let mut w = 1e-7 + 0.1 * est.abs();
    for _ in 0..40 {
        let (lo, hi) = (est - w, est + w);
        let (glo, ghi) = (
            pin_geometry(profile, j, phi, lo)?.gap,
            pin_geometry(profile, j, phi, hi)?.gap,
        );
        if glo * ghi < 0.0 {
            let res = Executor::new(Gap(profile, j, phi), BrentRoot::new(lo, hi, 1e-16))
                .configure(|st| st.max_iters(200))
                .timer(false)
                .run()
                .map_err(|e| Error::numerical("first contact", e.to_string()))?;
            return Ok(res.state.best_param);
        }
        w *= 2.0;
    }
    Ok(None)
}

/// Solution of the loaded tooth contact at one crank angle.
#[derive(Debug, Clone, Serialize)]
pub struct ContactSolution {
    /// Crank angle `phi`, rad.
    pub crank_angle: f64,
    /// Torque on this disc, N m.
    pub disc_torque: f64,
    /// Extra disc rotation beyond nominal (backlash take-up plus contact compliance), rad.
    pub disc_rotation: f64,
    /// Extra rotation at first contact (no load), rad.
    pub first_contact_rotation: f64,
    /// Every pin, in index order (`Zp` entries).
    pub pins: Vec<PinLoad>,
}

impl ContactSolution {
    /// Largest pin force, N.
    pub fn max_force(&self) -> f64 {
        self.pins.iter().map(|p| p.force).fold(0.0, f64::max)
    }
    /// Largest Hertz pressure, Pa.
    pub fn max_pressure(&self) -> f64 {
        self.pins.iter().map(|p| p.max_pressure).fold(0.0, f64::max)
    }
    /// Number of pins carrying a force.
    pub fn pins_in_contact(&self) -> usize {
        self.pins.iter().filter(|p| p.force > 0.0).count()
    }
    /// Sum of the pins' moments on the disc, `sum F_j l_j`, N m (equals the disc torque).
    pub fn pin_moment(&self) -> f64 {
        self.pins.iter().map(|p| p.force * p.lever_arm).sum()
    }
    /// Torsional stiffness of the stage at this pose, `sum k_j l_j^2`, N m/rad.
    pub fn torsional_stiffness(&self) -> f64 {
        self.pins
            .iter()
            .map(|p| p.stiffness * p.lever_arm * p.lever_arm)
            .sum()
    }
}

/// Moment `sum F_j l_j` (N m) and its derivative `sum k_j l_j^2` (N m/rad) over the pins in
/// `active` at rotation `beta`.
fn moment_and_stiffness(
    profile: &Profile,
    model: &ContactModel,
    phi: f64,
    beta: f64,
    active: &[usize],
) -> Result<(f64, f64)> {
    let mut m = 0.0;
    let mut k = 0.0;
    for &j in active {
        let g = pin_geometry(profile, j, phi, beta)?;
        let (f, kj) = model.force(-g.gap, g.curvature)?;
        m += f * g.lever_arm;
        k += kj * g.lever_arm * g.lever_arm;
    }
    Ok((m, k))
}

/// The rotation that balances `disc_torque`: safeguarded Newton on `R(beta) = sum F_j l_j - T`
/// with the tangent stiffness `sum k_j l_j^2`, bisecting whenever a step leaves the bracket;
/// Brent's method (argmin) if that has not converged in 60 steps.
fn equilibrium(
    profile: &Profile,
    model: &ContactModel,
    phi: f64,
    disc_torque: f64,
    beta0: f64,
    active: &[usize],
) -> Result<f64> {
    let s = disc_torque.signum();
    let r = |b: f64| -> Result<(f64, f64)> {
        let (m, k) = moment_and_stiffness(profile, model, phi, b, active)?;
        Ok((s * (m - disc_torque), k))
    };
    // In the signed variable x = s (beta - beta0) >= 0 the residual rises from -|T|.
    let tol = 1e-11 * disc_torque.abs();
    // Lower bracket: first contact, or below it if pins that cannot stop the disc on their own
    // (root and tip pins) already push it there.
    let mut lo = 0.0;
    let mut down = 2e-5;
    while r(beta0 + s * lo)?.0 > 0.0 {
        lo -= down;
        down *= 2.0;
        if down > 1.0 {
            return Err(Error::numerical(
                "loaded contact",
                "could not bracket the rotation",
            ));
        }
    }
    let origin = lo;
    let mut hi = f64::INFINITY;
    let mut x = lo + 2e-5;
    for _ in 0..60 {
        let (res, k) = r(beta0 + s * x)?;
        if res.abs() <= tol {
            return Ok(beta0 + s * x);
        }
        if res > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let newton = x - res / k.max(1e-300);
        let next = if k > 0.0 && newton > lo && newton < hi.min(origin + 4.0 * (x - origin)) {
            newton
        } else if hi.is_finite() {
            0.5 * (lo + hi)
        } else {
            origin + 2.0 * (x - origin)
        };
        if (next - x).abs() <= 1e-15 * (1.0 + x.abs()) {
            return Ok(beta0 + s * next);
        }
        x = next;
    }
    if !hi.is_finite() {
        return Err(Error::numerical(
            "loaded contact",
            "could not bracket the rotation",
        ));
    }
    struct Res<'a>(&'a dyn Fn(f64) -> Result<(f64, f64)>);
    impl CostFunction for Res<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> std::result::Result<f64, argmin::core::Error> {
            Ok((self.0)(*x)?.0)
        }
    }
    let f = |x: f64| r(beta0 + s * x);
    let result = Executor::new(Res(&f), BrentRoot::new(lo, hi, 1e-15))
        .configure(|st| st.max_iters(200))
        .timer(false)
        .run()
        .map_err(|e| Error::numerical("loaded contact", e.to_string()))?;
    let x = result
        .state
        .best_param
        .ok_or_else(|| Error::numerical("loaded contact", "Brent returned no rotation"))?;
    Ok(beta0 + s * x)
}

/// Solves the loaded tooth contact of one disc, its centre fixed on the eccentric at crank
/// angle `phi` (rad), under the disc torque
/// `disc_torque` (N m, = load share x output torque; sign gives the flank): finds the extra
/// rotation `beta` with `sum_j F_j(delta_j(beta)) l_j(beta) = T_disc`, `delta_j = -gap_j`
/// measured exactly on the actual profile (physics-notes section 4), by Brent's method
/// (argmin `BrentRoot`) between first contact and a bracketing rotation.
///
/// A zero torque returns the first-contact pose (counter-clockwise) with zero forces.
///
/// # Errors
/// [`Error::Numerical`] if the contact law leaves its range or the solver fails.
pub fn solve(
    profile: &Profile,
    model: &ContactModel,
    phi: f64,
    disc_torque: f64,
) -> Result<ContactSolution> {
    solve_checked(profile, model, phi, disc_torque, true)
}

/// [`solve`] without the final moment check: the starting point of the flexible-disc solver,
/// which checks its own equilibrium (on worn discs this fixed-crank solve can stop short of
/// balance where the closest point jumps between two feet).
pub(crate) fn solve_start(
    profile: &Profile,
    model: &ContactModel,
    phi: f64,
    disc_torque: f64,
) -> Result<ContactSolution> {
    solve_checked(profile, model, phi, disc_torque, false)
}

fn solve_checked(
    profile: &Profile,
    model: &ContactModel,
    phi: f64,
    disc_torque: f64,
    check: bool,
) -> Result<ContactSolution> {
    if !disc_torque.is_finite() || !phi.is_finite() {
        return Err(Error::invalid(
            "contact input",
            format!("crank {phi}, torque {disc_torque}"),
            "must be finite",
        ));
    }
    let s = if disc_torque < 0.0 { -1.0 } else { 1.0 };
    let zp = profile.geometry().pins;
    let beta0 = first_contact(profile, phi, s)?;
    let geoms0 = pin_geometries(profile, phi, beta0)?;
    // Pins that can touch within 2e-3 rad of rotation (far beyond any elastic take-up), with
    // 1 um to spare; a pin that closes faster than linearly (one in a near-conformal root: the
    // groove turns about a centre offset from the pin's and the gap falls as (beta R)^2/(2 rho_c))
    // can still be missed, so the solution is checked against every pin and re-solved with the
    // missed ones.
    let mut active: Vec<usize> = geoms0
        .iter()
        .filter(|g| g.gap - s * g.lever_arm * 2e-3 < 1e-6)
        .map(|g| g.pin)
        .collect();
    let (beta, geoms) = loop {
        let beta = if disc_torque == 0.0 {
            beta0
        } else {
            equilibrium(profile, model, phi, disc_torque, beta0, &active)?
        };
        let geoms = pin_geometries(profile, phi, beta)?;
        let missed: Vec<usize> = geoms
            .iter()
            .filter(|g| g.gap < 0.0 && !active.contains(&g.pin))
            .map(|g| g.pin)
            .collect();
        if missed.is_empty() || disc_torque == 0.0 {
            break (beta, geoms);
        }
        active.extend(missed);
    };
    let mut pins = Vec::with_capacity(zp);
    for g in &geoms {
        let (f, k) = if disc_torque == 0.0 {
            (0.0, 0.0)
        } else {
            model.force(-g.gap, g.curvature)?
        };
        let h = model.hertz(f, g.curvature);
        pins.push(PinLoad {
            pin: g.pin,
            profile_parameter: g.t,
            mesh_angle: mesh_angle(g.t),
            gap: g.gap,
            force: f,
            lever_arm: g.lever_arm,
            half_width: h.half_width,
            max_pressure: h.max_pressure,
            curvature: g.curvature,
            stiffness: k,
            point: g.point,
            normal: g.normal,
        });
    }
    let sol = ContactSolution {
        crank_angle: phi,
        disc_torque,
        disc_rotation: beta,
        first_contact_rotation: beta0,
        pins,
    };
    let residual = (sol.pin_moment() - disc_torque).abs();
    let balanced = residual <= 1e-9 * disc_torque.abs();
    if check && disc_torque != 0.0 && (residual.is_nan() || !balanced) {
        return Err(Error::numerical(
            "loaded contact",
            format!(
                "the moment balance is off by {:.3e} of the disc torque {disc_torque:.6e} N m \
                 at crank angle {:.4} deg",
                residual / disc_torque.abs(),
                phi.to_degrees()
            ),
        ));
    }
    Ok(sol)
}

/// Li Lixing's closed-form load distribution (physics-notes section 4, paper eqs 5, 9, 10) for
/// an unmodified rigid disc with linear springs: `l_j = a Zc sin(t_j) / S(t_j)` with mesh angle
/// `t_j = 2 pi j / Zp - phi`, `F_j = T_disc l_j / sum l^2` over the pins with `l_j > 0`.
/// Returns `Zp` forces, N (zero on the unloaded flank); negative torques load the other flank.
pub fn li_load_distribution(geo: &CycloidGeometry, phi: f64, disc_torque: f64) -> Vec<f64> {
    let zp = geo.pins as f64;
    let k1 = geo.k1();
    let s = disc_torque.signum();
    let levers: Vec<f64> = (0..geo.pins)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / zp - phi;
            let sq = (1.0 + k1 * k1 - 2.0 * k1 * t.cos()).sqrt();
            geo.disc_pitch_radius() * t.sin() / sq
        })
        .collect();
    let sum2: f64 = levers.iter().filter(|l| s * **l > 0.0).map(|l| l * l).sum();
    levers
        .iter()
        .map(|l| {
            if s * l > 0.0 {
                disc_torque * l / sum2
            } else {
                0.0
            }
        })
        .collect()
}
