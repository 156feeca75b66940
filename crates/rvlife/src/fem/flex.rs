//! Loaded tooth contact of a flexible disc, flexible TE, torsional stiffness and disc stress.
//!
//! For crank angle `phi` and disc torque `T` the unknowns are the disc rotation `beta` and the
//! pin forces `F_j >= 0`. With the rigid gaps `g_j(beta)` measured exactly on the actual profile
//! (`crate::contact::pin_geometry`), the disc compliance `C` between the contact points
//! (`DiscModel::compliance_at`) and the local Hertz approach `w_j(F_j)` ([`FlexibleLaw`]):
//!
//! - contact: `w_j(F_j) + sum_k C_jk F_k + g_j(beta) = 0` where `F_j > 0`,
//!   and `sum_k C_jk F_k + g_j(beta) >= 0` where `F_j = 0` (a linear complementarity problem
//!   with a monotone nonlinearity: the stationarity conditions of a convex energy);
//! - moment: `sum_j F_j l_j(beta) = T`.
//!
//! It is solved by Newton's method on the active set with a ratio test that drops pins whose
//! force would turn negative and adds the most-penetrating open pin after each converged
//! sweep, starting from the rigid solution of the static analysis with the disc's centre fixed
//! ([`crate::statics::StaticAnalysis`] with rigid support).

use std::f64::consts::{PI, TAU};

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::Serialize;

use crate::contact::{pin_geometry, ApproachLaw, ContactModel, PinGeometry};
use crate::error::{Error, Result};
use crate::fem::mesh::LoopKind;
use crate::fem::{outline_radii, DiscModel, DiscSet};
use crate::geometry::{Profile, Vec2};
use crate::reducer::{Reducer, Support};
use crate::statics::{PinLoad, StaticAnalysis, StaticSolution};

/// The local (Hertz) part of the contact compliance when the disc body is an FE model loaded by
/// pressure patches of half-width `w`: the pin term of the contact law unchanged, the disc term
/// `2F/(pi B) C1 ln(w / b)` (the half-plane approach from the Hertz half-width `b` out to the
/// patch; the FE supplies the rest). The difference of the mean surface displacements of two
/// elliptic loads of half-widths `b` and `w` on a half-plane is exactly
/// `2F/(pi B) C1 ln(w/b)` (Johnson, *Contact Mechanics*, 1985, section 2.8).
#[derive(Debug, Clone, Copy)]
pub struct FlexibleLaw {
    /// The rigid model's contact law.
    pub model: ContactModel,
    /// Patch half-width `w`, m.
    pub patch: f64,
}

impl FlexibleLaw {
    /// Local approach (m) and its derivative `dw/dF` (m/N) at force `force` (N) on a flank of
    /// curvature `curvature` (1/m). Forces below 1e-3 N use the derivative at 1e-3 N.
    pub(crate) fn approach(&self, force: f64, curvature: f64) -> (f64, f64) {
        let m = &self.model;
        let f = force.max(1e-3);
        if let ApproachLaw::Linear { stiffness } = m.law {
            return (force.max(0.0) / stiffness, 1.0 / stiffness);
        }
        let c0 = match m.law {
            ApproachLaw::Johnson => -0.5,
            _ => 1.0 / 3.0,
        };
        let (c1, c2) = m.materials.compliances();
        let k = 2.0 / (PI * m.width);
        let b = m.hertz(f, curvature).half_width;
        let disc_log = (self.patch / b).ln();
        let (disc, disc_slope) = if disc_log > 0.0 {
            (c1 * disc_log, c1)
        } else {
            (0.0, 0.0)
        };
        let pin = c2 * (c0 + (4.0 * m.pin_radius / b).ln());
        // A pin seated in a housing groove (section 3.4) adds the groove contact's approach
        // `F (h0 - h1 ln F)`, outside the disc body like the pin's own.
        let (groove, groove_slope) = match &m.groove {
            Some(gr) => {
                let (h0, h1) = m.groove_coefficients(gr, c0);
                (h0 - h1 * f.ln(), h0 - h1 * f.ln() - h1)
            }
            None => (0.0, 0.0),
        };
        // A pin bent between its ends (section 3.5) adds F c.
        let w_at = |ff: f64| k * ff * (disc + pin) + ff * (m.pin_compliance + groove);
        let slope =
            k * (disc + pin) - 0.5 * k * (disc_slope + c2) + m.pin_compliance + groove_slope;
        (w_at(force.max(0.0)), slope.max(1e-3 * k * c2))
    }
}

/// One pin of a flexible contact solution.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FlexPin {
    /// Pin index.
    pub pin: usize,
    /// Profile parameter of the contact point, rad.
    pub profile_parameter: f64,
    /// Normal force, N.
    pub force: f64,
    /// Lever arm about the disc centre, m.
    pub lever_arm: f64,
    /// Rigid gap at the solved rotation, m (negative: overlap).
    pub rigid_gap: f64,
    /// Normal deflection of the disc body at the contact, m.
    pub body_deflection: f64,
    /// Contact point (disc frame), m.
    #[serde(skip)]
    pub point: Vec2,
    /// Outward normal (disc frame).
    #[serde(skip)]
    pub normal: Vec2,
}

/// Loaded contact of the flexible disc at one crank angle.
#[derive(Debug, Clone, Serialize)]
pub struct FlexSolution {
    /// Crank angle, rad.
    pub crank_angle: f64,
    /// Disc torque, N m.
    pub disc_torque: f64,
    /// Disc rotation beyond nominal, rad (the output's lag).
    pub disc_rotation: f64,
    /// The rigid disc's rotation under the same torque, rad.
    pub rigid_rotation: f64,
    /// Rotation at first contact without load (the rigid STE), rad.
    pub first_contact_rotation: f64,
    /// Pins that carry a force.
    pub pins: Vec<FlexPin>,
}

impl FlexSolution {
    /// Largest pin force, N.
    pub(crate) fn max_force(&self) -> f64 {
        self.pins.iter().map(|p| p.force).fold(0.0, f64::max)
    }
}

/// Pins that can touch within `reach` rad of rotation from `beta` (plus 1 um).
fn candidates(profile: &Profile, phi: f64, beta: f64, s: f64, reach: f64) -> Result<Vec<usize>> {
    let zp = profile.geometry().pins;
    let mut out = Vec::new();
    for j in 0..zp {
        let g = pin_geometry(profile, j, phi, beta)?;
        if g.gap - s * g.lever_arm * reach < 1e-6 {
            out.push(j);
        }
    }
    Ok(out)
}

/// Solves the loaded contact of the flexible disc with its centre fixed on the eccentric (the
/// rigid support of `sa`, [`Support::Rigid`]) at crank angle `phi` (rad) under the output
/// torque `torque` (N m; its sign picks the flank): the disc carries the equivalent disc torque
/// `load_share T Zc/(Zp + Z1/Z2)`. The rigid solution of `sa` at the same crank angle and
/// torque is the start (its disc rotation and first contact are reported beside the flexible
/// rotation). A zero torque gives the rigid first contact.
///
/// # Errors
/// [`Error::Invalid`] if `sa`'s reducer has no rigid support; the rigid solve's failures;
/// [`Error::Numerical`] if the Newton iteration does not converge in 200 steps.
pub(crate) fn solve_flexible(
    sa: &StaticAnalysis,
    disc: &DiscModel,
    phi: f64,
    torque: f64,
) -> Result<FlexSolution> {
    let red = sa.reducer();
    let Support::Rigid { load_share } = red.support else {
        return Err(Error::invalid(
            "contact.support",
            "\"bearings\"",
            "the fixed-centre flexible disc needs support = \"rigid\"",
        ));
    };
    let profile = sa.profile();
    let model = &red.contact;
    let factor = red.twist_factor();
    let disc_torque = load_share * torque * factor;
    // The rigid disc's rotation at a fixed crank is its output twist over the twist factor
    // (docs/model.md section 6).
    let rigid = sa.solve(phi, torque)?;
    let rigid_rotation = rigid.twist / factor;
    let first_contact_rotation = rigid.first_contact_twist / factor;
    if disc_torque == 0.0 {
        return Ok(FlexSolution {
            crank_angle: phi,
            disc_torque,
            disc_rotation: rigid_rotation,
            rigid_rotation,
            first_contact_rotation,
            pins: Vec::new(),
        });
    }
    let law = FlexibleLaw {
        model: *model,
        patch: disc.params.patch,
    };
    let s = disc_torque.signum();
    let cand = candidates(profile, phi, rigid_rotation, s, 5e-3)?;
    let mut force: Vec<f64> = cand.iter().map(|&j| rigid.discs[0].pins[j].force).collect();
    let mut active: Vec<bool> = force.iter().map(|f| *f > 0.0).collect();
    let mut beta = rigid_rotation;
    let n = cand.len();
    let tol_gap = 1e-13;
    let tol_m = 1e-10 * disc_torque.abs();
    let mut geoms: Vec<PinGeometry> = Vec::with_capacity(n);
    let mut c = Vec::new();
    let mut converged_all = false;
    for _ in 0..200 {
        geoms.clear();
        for &j in &cand {
            geoms.push(pin_geometry(profile, j, phi, beta)?);
        }
        c = disc.compliance_at(&geoms.iter().map(|g| g.t).collect::<Vec<_>>());
        let body = |i: usize, force: &[f64]| -> f64 {
            (0..n).map(|k| c[i * n + k] * force[k]).sum::<f64>()
        };
        let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
        let na = idx.len();
        let mut r = DVector::<f64>::zeros(na + 1);
        let mut jac = DMatrix::<f64>::zeros(na + 1, na + 1);
        let mut moment = 0.0;
        for (a, &i) in idx.iter().enumerate() {
            let (w, dw) = law.approach(force[i], geoms[i].curvature);
            r[a] = w + body(i, &force) + geoms[i].gap;
            for (b, &k) in idx.iter().enumerate() {
                jac[(a, b)] = c[i * n + k];
            }
            jac[(a, a)] += dw;
            jac[(a, na)] = -geoms[i].lever_arm;
            jac[(na, a)] = geoms[i].lever_arm;
            moment += force[i] * geoms[i].lever_arm;
        }
        r[na] = moment - disc_torque;
        let converged = r.iter().take(na).all(|v| v.abs() < tol_gap) && r[na].abs() < tol_m;
        if converged {
            // Complementarity of the open pins: add the most-penetrating one.
            let worst = (0..n)
                .filter(|&i| !active[i])
                .map(|i| (i, body(i, &force) + geoms[i].gap))
                .filter(|(_, g)| *g < -tol_gap)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match worst {
                Some((i, _)) => {
                    active[i] = true;
                    force[i] = 0.0;
                    continue;
                }
                None => {
                    converged_all = true;
                    break;
                }
            }
        }
        let delta = jac
            .lu()
            .solve(&(-r))
            .ok_or_else(|| Error::numerical("flexible contact", "singular Newton matrix"))?;
        // Ratio test: the largest step that keeps every active force >= 0.
        let mut alpha = 1.0;
        let mut blocking = None;
        for (a, &i) in idx.iter().enumerate() {
            if force[i] + delta[a] < 0.0 {
                let al = force[i] / (-delta[a]);
                if al < alpha {
                    alpha = al;
                    blocking = Some(i);
                }
            }
        }
        for (a, &i) in idx.iter().enumerate() {
            force[i] = (force[i] + alpha * delta[a]).max(0.0);
        }
        beta += alpha * delta[na];
        if let Some(i) = blocking {
            active[i] = false;
            force[i] = 0.0;
        }
        if !beta.is_finite() {
            return Err(Error::numerical("flexible contact", "rotation diverged"));
        }
    }
    if !converged_all {
        return Err(Error::numerical(
            "flexible contact",
            format!(
                "the contact of the flexible disc did not converge in 200 Newton steps at crank \
                 angle {:.4} deg, disc torque {disc_torque:.6e} N m",
                phi.to_degrees()
            ),
        ));
    }
    let pins = (0..n)
        .filter(|&i| force[i] > 0.0)
        .map(|i| FlexPin {
            pin: cand[i],
            profile_parameter: geoms[i].t,
            force: force[i],
            lever_arm: geoms[i].lever_arm,
            rigid_gap: geoms[i].gap,
            body_deflection: (0..n).map(|k| c[i * n + k] * force[k]).sum(),
            point: geoms[i].point,
            normal: geoms[i].normal,
        })
        .collect();
    Ok(FlexSolution {
        crank_angle: phi,
        disc_torque,
        disc_rotation: beta,
        rigid_rotation,
        first_contact_rotation,
        pins,
    })
}

/// Relative tolerance of the body-deflection fixed point of `solve_flexible_bearings`: the
/// largest change of a pin's gap offset in the last sweep, over the largest offset. At this
/// value the example's study takes 3.9 static solves per flexible solve (4.8 at 1e-4, 5.6 at
/// 1e-5, 7.3 at 1e-7); against 1e-5 its flexible TE means, backlash, lost motion and stiffness
/// move by less than 3e-5 of themselves, its TE peak-to-peak values and stress maxima by less
/// than 5e-4, a tenth of the mesh's discretisation error (the 0.125 mm flank mesh is within
/// 5e-3 of the 0.25 mm one).
pub(crate) const FLEX_OFFSET_TOLERANCE: f64 = 1e-3;

/// Flexible discs on their bearings: the static equilibrium of the reducer model
/// ([`StaticAnalysis`]: both discs free on the crank bearings, load share from the equilibrium)
/// with each disc's body deflection added to its pins' gaps, started from `rigid`, the
/// rigid-disc solution of `sa` at the crank angle and output torque wanted (its first-contact
/// twist is kept).
///
/// For the loaded pins of each disc (contact parameters `t_j`, forces `F_j`, flank curvatures
/// `kappa_j`) the gap offset is `sum_k C(t_j, t_k) F_k + w_flex(F_j) - w(F_j)`: the FE body's
/// normal approach ([`DiscModel::compliance_at`], disc clamped at its crank bores), plus the
/// local Hertz approach of the FE-loaded disc ([`FlexibleLaw`]) in place of the whole-body
/// approach of the rigid law `w` (the static solution's overlap). Open pins facing the loaded
/// flank (the driving flank for a positive torque, the other for a negative one) get the body
/// term (the flank under them moves with the body), so a pin at the edge of
/// the contact zone does not flip between open and loaded from one sweep to the next. The
/// offsets are iterated to a fixed point, each sweep a warm-started static solve, with Anderson
/// mixing of the last [`ANDERSON_DEPTH`] sweeps ([`AndersonMixing`]; at a tolerance of 1e-9:
/// 8 sweeps per solve on the example's 10 um disc and 9.5 at 7500 h, where plain sweeps took
/// 14 and 23; the same fixed point to 1e-10); where a pin at the edge of the contact zone makes the sweeps alternate
/// (the change does not shrink by a tenth) the mixing history is dropped and the step halved,
/// down to 1/64. It stops when the offsets change by less than [`FLEX_OFFSET_TOLERANCE`] of the
/// largest, or, at the smallest step, when the output twist moves by less than
/// [`SETTLED_TWIST`] over [`SETTLED_SWEEPS`] sweeps while the offsets cycle. Each disc's body compliance is that of its FE model at its own contact parameters
/// mapped onto the model ([`DiscSet`]: disc 2 of an RV reducer is disc 1's part turned by pi).
///
/// Returns the solution and the offsets (m, `2 x Zp`, disc-major).
///
/// # Errors
/// [`Error::Numerical`] if a static solve fails or the fixed point is not reached in 400
/// sweeps (naming the crank angle and torque).
pub(crate) fn solve_flexible_bearings(
    sa: &StaticAnalysis,
    red: &Reducer,
    discs: &DiscSet,
    rigid: StaticSolution,
) -> Result<(StaticSolution, Vec<f64>)> {
    let (phi, torque, psi0) = (
        rigid.crank_angle,
        rigid.output_torque,
        rigid.first_contact_twist,
    );
    let zp = red.geometry.pins;
    let sense = torque.signum();
    let law = FlexibleLaw {
        model: red.contact,
        patch: discs.params().patch,
    };
    let mut offsets = vec![0.0; 2 * zp];
    let mut sol = rigid;
    if torque == 0.0 {
        return Ok((sol, offsets));
    }
    let (mut omega, mut last_change) = (1.0_f64, f64::INFINITY);
    let mut mixing = AndersonMixing::new(ANDERSON_DEPTH);
    let mut settled: Vec<f64> = Vec::new();
    for _ in 0..400 {
        let mut target = vec![0.0; 2 * zp];
        for (d, dl) in sol.discs.iter().enumerate() {
            // Every pin facing the loaded flank: the loaded ones and the open ones the body's
            // deflection moves the flank under.
            let facing: Vec<&PinLoad> = dl
                .pins
                .iter()
                .filter(|p| p.force > 0.0 || faces_loaded_flank(p.profile_parameter, sense))
                .collect();
            let ts: Vec<f64> = facing.iter().map(|p| p.profile_parameter).collect();
            let c = discs.compliance_at(d, &ts);
            let n = facing.len();
            for (a, p) in facing.iter().enumerate() {
                let body: f64 = (0..n).map(|b| c[a * n + b] * facing[b].force).sum();
                // The whole-body approach of the rigid law is the overlap of the static
                // solution's gap (which holds the current offset): `-gap` where loaded.
                let (local, whole) = if p.force > 0.0 {
                    (law.approach(p.force, p.curvature).0, -p.gap)
                } else {
                    (0.0, 0.0)
                };
                target[d * zp + p.pin] = body + local - whole;
            }
        }
        let scale = target
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
            .max(1e-15);
        let change = target
            .iter()
            .zip(&offsets)
            .fold(0.0_f64, |m, (t, o)| m.max((t - o).abs()));
        if change <= FLEX_OFFSET_TOLERANCE * scale {
            return Ok((sol, offsets));
        }
        // At the smallest step, a cycle of a pin at the edge of the contact zone whose twist
        // has settled ends the sweeps.
        if omega <= MIN_MIXING_STEP {
            settled.push(sol.twist);
            if settled.len() >= SETTLED_SWEEPS {
                let tail = &settled[settled.len() - SETTLED_SWEEPS..];
                let (lo, hi) = tail
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                        (a.min(t), b.max(t))
                    });
                if hi - lo <= SETTLED_TWIST {
                    return Ok((sol, offsets));
                }
            }
        }
        // Where a pin at the edge of the contact zone makes the sweeps alternate (the change
        // does not shrink by a tenth): forget the mixing history and halve the step (to 1/64).
        if change > 0.9 * last_change {
            omega = (0.5 * omega).max(MIN_MIXING_STEP);
            mixing.clear();
        }
        last_change = change;
        offsets = mixing.next(&offsets, &target, omega);
        sol = sa.solve_with_offsets(phi, torque, psi0, Some(&sol), &offsets)?;
    }
    Err(Error::numerical(
        "flexible contact",
        format!(
            "the body deflection of the discs did not settle in 400 sweeps at crank angle \
             {:.4} deg, output torque {torque:.6e} N m",
            phi.to_degrees()
        ),
    ))
}

/// Smallest step of the sweeps of `solve_flexible_bearings` (where they alternate).
const MIN_MIXING_STEP: f64 = 1.0 / 64.0;

/// Sweeps at the smallest step over which `solve_flexible_bearings` takes a twist that moves
/// by at most [`SETTLED_TWIST`] as settled.
const SETTLED_SWEEPS: usize = 16;

/// Spread of the output twist (rad) over [`SETTLED_SWEEPS`] sweeps at the smallest step below
/// which `solve_flexible_bearings` ends where its offsets cycle (a pin at the edge of the
/// contact zone opening and closing at a force of nearly zero: 1e-10 rad of spread, offsets
/// cycling by 4 % of the largest, on the example with 80 / 50 um in its crank-disc /
/// crank-carrier bearings): the round-off of the twist tables (`te::PLAY_ROUND_OFF`).
const SETTLED_TWIST: f64 = 1e-9;

/// Depth (previous sweeps remembered) of the Anderson mixing of `solve_flexible_bearings`.
pub(crate) const ANDERSON_DEPTH: usize = 4;

/// Anderson mixing of a fixed-point iteration `x = g(x)` (D. G. Anderson, *Iterative procedures
/// for nonlinear integral equations*, J. ACM 12, 1965; the form of H. F. Walker and P. Ni,
/// *Anderson acceleration for fixed-point iterations*, SIAM J. Numer. Anal. 49, 2011): with the
/// residuals `f_i = g(x_i) - x_i` of the last `depth + 1` sweeps, the next iterate is
/// `x_k + beta f_k - (dX + beta dF) gamma`, `gamma` the least-squares fit of `f_k` by the
/// differences `dF` of consecutive residuals (`dX` those of the iterates), solved by SVD
/// (nalgebra). With no history it is the damped sweep `x_k + beta f_k`. No maintained Rust crate
/// offers it (conflux, 2021, has only the type-I form on ndarray).
#[derive(Debug, Clone)]
struct AndersonMixing {
    depth: usize,
    /// `(x_i, f_i)` of the last sweeps, oldest first.
    history: std::collections::VecDeque<(Vec<f64>, Vec<f64>)>,
}

impl AndersonMixing {
    fn new(depth: usize) -> Self {
        AndersonMixing {
            depth,
            history: std::collections::VecDeque::with_capacity(depth + 1),
        }
    }

    fn clear(&mut self) {
        self.history.clear();
    }

    /// The next iterate from the current `x` and `g(x)`, with damping `beta` in `(0, 1]`.
    fn next(&mut self, x: &[f64], g: &[f64], beta: f64) -> Vec<f64> {
        let f: Vec<f64> = g.iter().zip(x).map(|(g, x)| g - x).collect();
        self.history.push_back((x.to_vec(), f.clone()));
        if self.history.len() > self.depth + 1 {
            self.history.pop_front();
        }
        let mut next: Vec<f64> = x.iter().zip(&f).map(|(x, f)| x + beta * f).collect();
        let k = self.history.len() - 1;
        if k == 0 {
            return next;
        }
        let n = x.len();
        let h = &self.history;
        let df = DMatrix::from_fn(n, k, |r, c| h[c + 1].1[r] - h[c].1[r]);
        let dx = DMatrix::from_fn(n, k, |r, c| h[c + 1].0[r] - h[c].0[r]);
        let Ok(gamma) = df
            .clone()
            .svd(true, true)
            .solve(&DVector::from_vec(f), 1e-12 * df.norm())
        else {
            return next;
        };
        if gamma.iter().any(|v| !v.is_finite()) {
            return next;
        }
        let step = (dx + df * beta) * gamma;
        for (v, s) in next.iter_mut().zip(step.iter()) {
            *v -= s;
        }
        next
    }
}

/// Whether a pin with contact parameter `t` (rad) faces the driving flank `[0, pi]` of its
/// tooth, with a margin of [`FACING_MARGIN`] round both ends (a pin at the root or tip is
/// loaded on one side of the end and open on the other from one sweep to the next; its body
/// deflection must not vanish when it opens).
#[cfg(test)]
pub(crate) fn faces_driving_flank(t: f64) -> bool {
    faces_loaded_flank(t, 1.0)
}

/// Whether a pin with contact parameter `t` (rad) faces the flank that a torque of sign `sense`
/// loads: the driving flank `[0, pi]` for `sense >= 0`, the other flank `[pi, 2 pi]` for a
/// negative one, with a margin of [`FACING_MARGIN`] round both ends.
pub(crate) fn faces_loaded_flank(t: f64, sense: f64) -> bool {
    let local = t.rem_euclid(TAU);
    if sense >= 0.0 {
        local <= PI + FACING_MARGIN || local >= TAU - FACING_MARGIN
    } else {
        local >= PI - FACING_MARGIN || local <= FACING_MARGIN
    }
}

/// Margin of `faces_driving_flank` in profile parameter, rad.
pub(crate) const FACING_MARGIN: f64 = 0.3;

/// Disc 1 of a flexible bearing solution as a [`FlexSolution`] (for [`disc_stress`]); its
/// rotations are the reducer's output twists: loaded, rigid (`rigid`) and at first contact
/// (`psi0`), rad.
fn disc_one(sol: &StaticSolution, offsets: &[f64], psi0: f64, rigid: f64) -> FlexSolution {
    let d = &sol.discs[0];
    FlexSolution {
        crank_angle: sol.crank_angle,
        disc_torque: d.torque,
        disc_rotation: sol.twist,
        rigid_rotation: rigid,
        first_contact_rotation: psi0,
        pins: d
            .pins
            .iter()
            .filter(|p| p.force > 0.0)
            .map(|p| FlexPin {
                pin: p.pin,
                profile_parameter: p.profile_parameter,
                force: p.force,
                lever_arm: p.lever_arm,
                rigid_gap: p.gap - offsets[p.pin],
                body_deflection: offsets[p.pin],
                point: p.point,
                normal: p.normal,
            })
            .collect(),
    }
}

/// Pins carrying less than this fraction of the largest pin force keep the stress round their
/// patch in `disc_stress`'s maxima (their patch stress is a few per cent of a loaded one's).
pub(crate) const PATCH_EXCLUSION_FORCE: f64 = 0.05;

/// Von Mises stress of the disc under one loaded contact state.
#[derive(Debug, Clone, Serialize)]
pub struct DiscStress {
    /// Crank angle, rad.
    pub crank_angle: f64,
    /// Output torque, N m.
    pub torque: f64,
    /// Largest von Mises stress away from the load patches (further than two patch half-widths
    /// from every contact carrying `PATCH_EXCLUSION_FORCE` of the largest force), Pa.
    pub max_von_mises: f64,
    /// Largest von Mises stress on the outline in the tooth-root zone (radius within 25 % of the
    /// tooth height above the root), away from the load patches as for `max_von_mises`, Pa.
    pub max_root_stress: f64,
    /// Von Mises stress at every mesh node, Pa.
    #[serde(skip)]
    pub nodal: Vec<f64>,
}

/// Stress of the disc under the pin forces of `sol` (disc frame loads as pressure patches).
pub(crate) fn disc_stress(
    profile: &Profile,
    disc: &DiscModel,
    sol: &FlexSolution,
    torque: f64,
) -> DiscStress {
    let mesh = &disc.fe.mesh;
    let mut load = vec![0.0; 2 * mesh.nodes.len()];
    for p in &sol.pins {
        for (i, v) in disc.patch_load(&p.point, &(-p.normal)) {
            load[i] += v * p.force;
        }
    }
    let u = disc.fe.solve(&load);
    let st = disc.fe.stresses(&u);
    let nodal: Vec<f64> = (0..mesh.nodes.len()).map(|i| st.von_mises(i)).collect();
    let w = disc.params.patch;
    // The contact stress under a patch is the Hertz problem's, not the body's: nodes within two
    // patch half-widths of a pin carrying at least [`PATCH_EXCLUSION_FORCE`] of the largest
    // force are left out (not around every pin with a force: one at the edge of the contact
    // zone carries a vanishing force that a rounding error switches on or off).
    let fmax = sol.pins.iter().map(|p| p.force).fold(0.0, f64::max);
    let loaded: Vec<Vec2> = sol
        .pins
        .iter()
        .filter(|p| p.force >= PATCH_EXCLUSION_FORCE * fmax)
        .map(|p| p.point)
        .collect();
    let max_von_mises = mesh
        .nodes
        .iter()
        .zip(&nodal)
        .filter(|(x, _)| loaded.iter().all(|p| (*x - p).norm() > 2.0 * w))
        .map(|(_, v)| *v)
        .fold(0.0, f64::max);
    let (root, tip) = outline_radii(profile);
    let zone = root + 0.25 * (tip - root);
    let max_root_stress = mesh
        .boundary
        .iter()
        .filter(|e| e.kind == LoopKind::Outline)
        .flat_map(|e| e.nodes)
        .filter(|&i| mesh.nodes[i].norm() < zone)
        .filter(|&i| loaded.iter().all(|p| (mesh.nodes[i] - p).norm() > 2.0 * w))
        .map(|i| nodal[i])
        .fold(0.0, f64::max);
    DiscStress {
        crank_angle: sol.crank_angle,
        torque,
        max_von_mises,
        max_root_stress,
        nodal,
    }
}

/// The stage's stress is evaluated at every crank angle whose largest pin force is within this
/// fraction of the largest over the revolution (not only at the largest: near-equal forces at
/// crank angles half a revolution apart load the disc at different places, and which of them
/// is the larger by 1e-8 must not decide the stress reported).
pub(crate) const STRESS_FORCE_BAND: f64 = 0.99;

/// Of the stress states `states` (at least one), the one with the largest von Mises stress,
/// carrying the largest root stress of all.
fn worst_stress(states: impl Iterator<Item = DiscStress>) -> DiscStress {
    let states: Vec<DiscStress> = states.collect();
    let root = states.iter().map(|s| s.max_root_stress).fold(0.0, f64::max);
    let mut worst = states
        .into_iter()
        .max_by(|a, b| a.max_von_mises.total_cmp(&b.max_von_mises))
        .expect("the crank angle of the largest force is in the band");
    worst.max_root_stress = root;
    worst
}

/// Flexible-disc analysis of one wear stage over one crank revolution.
#[derive(Debug, Clone, Serialize)]
pub struct FlexibleStage {
    /// Crank angles, rad (`crank_angles` points over one revolution).
    pub crank_angle: Vec<f64>,
    /// Output torque of the STE measurement (`ste_torque_fraction` x rated), N m.
    pub ste_torque: f64,
    /// Rated output torque, N m.
    pub rated_torque: f64,
    /// Rigid STE (first contact, no load), rad.
    pub rigid_ste: Vec<f64>,
    /// Rigid-disc TE at the rated torque, rad.
    pub rigid_loaded_te: Vec<f64>,
    /// Flexible-disc TE at the STE measuring torque, rad.
    pub flexible_ste: Vec<f64>,
    /// Flexible-disc TE at the rated torque, rad.
    pub flexible_loaded_te: Vec<f64>,
    /// Largest pin force of the flexible solution at the rated torque, N.
    pub max_force: Vec<f64>,
    /// Rigid first contact in the reverse sense (the other flank, no load), rad.
    pub rigid_ste_reverse: Vec<f64>,
    /// Flexible-disc TE at minus the STE measuring torque, rad.
    pub flexible_ste_reverse: Vec<f64>,
    /// Flexible-disc TE at minus the rated torque, rad.
    pub flexible_loaded_te_reverse: Vec<f64>,
    /// Secant torsional stiffness of the stage between the STE torque and the rated torque,
    /// from the mean TEs, mean of both senses (catalogue definition), N m/rad.
    pub torsional_stiffness: f64,
    /// Output torques of the flexible hysteresis curve, N m (from minus to plus rated; the
    /// curve of this frictionless model is the same loading and unloading).
    pub hysteresis_torque: Vec<f64>,
    /// Flexible output twist at each of those torques, mean over `HYSTERESIS_CRANK_ANGLES`
    /// crank angles of the revolution, rad.
    pub hysteresis_twist: Vec<f64>,
    /// Stress at the rated torque: of the crank angles whose largest pin force is within
    /// `STRESS_FORCE_BAND` of the largest, the state with the largest von Mises stress (its
    /// root stress the largest of them).
    pub stress: DiscStress,
}

/// Crank angles over one revolution at which the flexible hysteresis curve is averaged.
pub(crate) const HYSTERESIS_CRANK_ANGLES: usize = 12;

/// Torques of the flexible hysteresis curve as fractions of the rated torque; the STE measuring
/// fraction `f` is added each way.
const HYSTERESIS_LEVELS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

/// The torques (N m, ascending) of the flexible hysteresis curve: `+-f rated` and
/// `+-HYSTERESIS_LEVELS rated`.
fn hysteresis_torques(rated: f64, f: f64) -> Vec<f64> {
    let mut t: Vec<f64> = std::iter::once(f)
        .chain(HYSTERESIS_LEVELS)
        .flat_map(|x| [x * rated, -x * rated])
        .collect();
    t.sort_by(f64::total_cmp);
    t
}

/// Torsional stiffness `b/a` of both senses, N m/rad (catalogue definition, as
/// [`crate::te::Accuracy::torsional_stiffness`]): `(T_r - T_m)` over the mean of the two
/// senses' mean twists between the measuring torque `T_m` and the rated torque `T_r`.
fn two_sense_stiffness(st: &FlexibleStage) -> f64 {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let a = 0.5
        * ((mean(&st.flexible_loaded_te) - mean(&st.flexible_ste))
            + (mean(&st.flexible_ste_reverse) - mean(&st.flexible_loaded_te_reverse)));
    if a > 0.0 {
        (st.rated_torque - st.ste_torque) / a
    } else {
        f64::INFINITY
    }
}

/// Runs the flexible analysis of one stage: rigid and flexible TE at the STE measuring torque
/// and at the rated torque (output torques), at `disc.params.crank_angles` crank angles over one
/// crank revolution (the load moves once round the disc relative to the bores), in parallel,
/// in both senses; the torsional stiffness (mean of both senses); the hysteresis curve from
/// minus to plus the rated torque (mean over `HYSTERESIS_CRANK_ANGLES` crank angles); and
/// the stress at the crank angle of the largest forward pin force.
///
/// The reducer's disc body in series with its bearings
/// ([`crate::reducer::structure::SeriesCompliances::disc_body`]) is left out: the FE disc is
/// that body. With bearing support (the default) both discs sit on their bearings and the TEs are the
/// reducer's output twists (`solve_flexible_bearings`). With the rigid support the disc is
/// analysed with its centre on the eccentric at a fixed crank angle and carries the equivalent
/// disc torque `share T Zc/(Zp + Z1/Z2)` (share: `load_share`); its rotation `beta` is
/// reported as the output twist `beta Zc/(Zp + Z1/Z2)` (docs/model.md section 6).
///
/// # Errors
/// Contact solver failures.
pub fn analyse_stage(
    profile: &Profile,
    reducer: &Reducer,
    discs: &DiscSet,
    rated_torque: f64,
) -> Result<FlexibleStage> {
    // The FE disc is the disc's body: not again in series with the bearings.
    let reducer = &reducer.without_disc_body();
    // The fixed-centre model is disc 1 carrying its load share.
    let disc = discs.disc(0).0;
    let factor = reducer.twist_factor();
    let n = disc.params.crank_angles;
    let phis: Vec<f64> = (0..n).map(|k| TAU * k as f64 / n as f64).collect();
    let ste_torque = disc.params.ste_torque_fraction * rated_torque;
    if reducer.support == Support::Bearings {
        return analyse_stage_bearings(profile, reducer, discs, rated_torque, phis, ste_torque);
    }
    let sa = StaticAnalysis::new(reducer, profile)?;
    let rows: Vec<(FlexSolution, FlexSolution)> = phis
        .par_iter()
        .map(|&phi| -> Result<(FlexSolution, FlexSolution)> {
            let lo = solve_flexible(&sa, disc, phi, ste_torque)?;
            let hi = solve_flexible(&sa, disc, phi, rated_torque)?;
            Ok((lo, hi))
        })
        .collect::<Result<_>>()?;
    let reverse: Vec<(FlexSolution, FlexSolution)> = phis
        .par_iter()
        .map(|&phi| -> Result<(FlexSolution, FlexSolution)> {
            let lo = solve_flexible(&sa, disc, phi, -ste_torque)?;
            let hi = solve_flexible(&sa, disc, phi, -rated_torque)?;
            Ok((lo, hi))
        })
        .collect::<Result<_>>()?;
    let hysteresis_torque = hysteresis_torques(rated_torque, disc.params.ste_torque_fraction);
    // The curve's levels at plus and minus the STE and the rated torque are the rows' (the same
    // solves at the same crank angles).
    let hysteresis_twist = curve_mean(&phis, &hysteresis_torque, |k, t| {
        Ok(factor
            * match t {
                t if t == ste_torque => rows[k].0.disc_rotation,
                t if t == rated_torque => rows[k].1.disc_rotation,
                t if t == -ste_torque => reverse[k].0.disc_rotation,
                t if t == -rated_torque => reverse[k].1.disc_rotation,
                t => solve_flexible(&sa, disc, phis[k], t)?.disc_rotation,
            })
    })?;
    let flexible_ste: Vec<f64> = rows.iter().map(|r| factor * r.0.disc_rotation).collect();
    let flexible_loaded_te: Vec<f64> = rows.iter().map(|r| factor * r.1.disc_rotation).collect();
    let torsional_stiffness =
        secant_stiffness(ste_torque, rated_torque, &flexible_ste, &flexible_loaded_te);
    let worst = rows.iter().map(|r| r.1.max_force()).fold(0.0, f64::max);
    let stress = worst_stress(
        rows.iter()
            .filter(|r| r.1.max_force() >= STRESS_FORCE_BAND * worst)
            .map(|r| disc_stress(profile, disc, &r.1, rated_torque)),
    );
    let mut st = FlexibleStage {
        crank_angle: phis,
        ste_torque,
        rated_torque,
        rigid_ste: rows
            .iter()
            .map(|r| factor * r.1.first_contact_rotation)
            .collect(),
        rigid_loaded_te: rows.iter().map(|r| factor * r.1.rigid_rotation).collect(),
        flexible_ste,
        flexible_loaded_te,
        max_force: rows.iter().map(|r| r.1.max_force()).collect(),
        rigid_ste_reverse: reverse
            .iter()
            .map(|r| factor * r.1.first_contact_rotation)
            .collect(),
        flexible_ste_reverse: reverse.iter().map(|r| factor * r.0.disc_rotation).collect(),
        flexible_loaded_te_reverse: reverse.iter().map(|r| factor * r.1.disc_rotation).collect(),
        torsional_stiffness,
        hysteresis_torque,
        hysteresis_twist,
        stress,
    };
    st.torsional_stiffness = two_sense_stiffness(&st);
    Ok(st)
}

/// Mean over every `n / HYSTERESIS_CRANK_ANGLES`-th crank angle of `phis` of `twist(k, T)`
/// (rad; `k` the index of the crank angle in `phis`) at each torque of `torques`, in parallel.
fn curve_mean(
    phis: &[f64],
    torques: &[f64],
    twist: impl Fn(usize, f64) -> Result<f64> + Sync,
) -> Result<Vec<f64>> {
    let step = (phis.len() / HYSTERESIS_CRANK_ANGLES).max(1);
    let sub: Vec<usize> = (0..phis.len()).step_by(step).collect();
    torques
        .par_iter()
        .map(|&t| -> Result<f64> {
            let mut sum = 0.0;
            for &k in &sub {
                sum += twist(k, t)?;
            }
            Ok(sum / sub.len() as f64)
        })
        .collect()
}

/// Secant torsional stiffness (N m/rad) between torques `lo_torque` and `hi_torque` (N m)
/// from the means of the TE curves `lo` and `hi` (rad); infinite if the mean does not grow.
fn secant_stiffness(lo_torque: f64, hi_torque: f64, lo: &[f64], hi: &[f64]) -> f64 {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let d_theta = mean(hi) - mean(lo);
    if d_theta > 0.0 {
        (hi_torque - lo_torque) / d_theta
    } else {
        f64::INFINITY
    }
}

/// [`analyse_stage`] with the discs on their bearings ([`solve_flexible_bearings`]): the TEs
/// are the reducer's output twists.
fn analyse_stage_bearings(
    profile: &Profile,
    reducer: &Reducer,
    discs: &DiscSet,
    rated_torque: f64,
    phis: Vec<f64>,
    ste_torque: f64,
) -> Result<FlexibleStage> {
    let sa = StaticAnalysis::new(reducer, profile)?;
    type Row = (f64, f64, StaticSolution, StaticSolution, Vec<f64>);
    let rows: Vec<Row> = phis
        .par_iter()
        .map(|&phi| -> Result<Row> {
            let psi0 = sa.first_contact(phi, 1.0)?;
            let rigid_lo = sa.solve_from(phi, ste_torque, psi0)?;
            let rigid_hi = sa.solve_from(phi, rated_torque, psi0)?;
            let rigid = rigid_hi.twist;
            let (lo, _) = solve_flexible_bearings(&sa, reducer, discs, rigid_lo)?;
            let (hi, offsets) = solve_flexible_bearings(&sa, reducer, discs, rigid_hi)?;
            Ok((psi0, rigid, lo, hi, offsets))
        })
        .collect::<Result<_>>()?;
    let reverse: Vec<(f64, f64, f64)> = phis
        .par_iter()
        .map(|&phi| -> Result<(f64, f64, f64)> {
            let psi0 = sa.first_contact(phi, -1.0)?;
            let rigid_lo = sa.solve_from(phi, -ste_torque, psi0)?;
            let rigid_hi = sa.solve_from(phi, -rated_torque, psi0)?;
            let (lo, _) = solve_flexible_bearings(&sa, reducer, discs, rigid_lo)?;
            let (hi, _) = solve_flexible_bearings(&sa, reducer, discs, rigid_hi)?;
            Ok((psi0, lo.twist, hi.twist))
        })
        .collect::<Result<_>>()?;
    let hysteresis_torque = hysteresis_torques(rated_torque, discs.params().ste_torque_fraction);
    // The curve's levels at plus and minus the STE and the rated torque are the rows' (the same
    // solves at the same crank angles).
    let hysteresis_twist = curve_mean(&phis, &hysteresis_torque, |k, t| match t {
        t if t == ste_torque => Ok(rows[k].2.twist),
        t if t == rated_torque => Ok(rows[k].3.twist),
        t if t == -ste_torque => Ok(reverse[k].1),
        t if t == -rated_torque => Ok(reverse[k].2),
        t => {
            let phi = phis[k];
            let psi0 = sa.first_contact(phi, t.signum())?;
            let rigid = sa.solve_from(phi, t, psi0)?;
            Ok(solve_flexible_bearings(&sa, reducer, discs, rigid)?.0.twist)
        }
    })?;
    let flexible_ste: Vec<f64> = rows.iter().map(|r| r.2.twist).collect();
    let flexible_loaded_te: Vec<f64> = rows.iter().map(|r| r.3.twist).collect();
    let torsional_stiffness =
        secant_stiffness(ste_torque, rated_torque, &flexible_ste, &flexible_loaded_te);
    let worst = rows
        .iter()
        .map(|r| r.3.discs[0].max_force())
        .fold(0.0, f64::max);
    // Disc 1's pins in its model's frame.
    let (model1, mount1) = discs.disc(0);
    let stress = worst_stress(
        rows.iter()
            .filter(|r| r.3.discs[0].max_force() >= STRESS_FORCE_BAND * worst)
            .map(|r| {
                let mut one = disc_one(&r.3, &r.4, r.0, r.1);
                for p in &mut one.pins {
                    p.point = mount1.model_frame(&p.point);
                    p.normal = mount1.model_frame(&p.normal);
                }
                disc_stress(profile, model1, &one, rated_torque)
            }),
    );
    let mut st = FlexibleStage {
        crank_angle: phis,
        ste_torque,
        rated_torque,
        rigid_ste: rows.iter().map(|r| r.0).collect(),
        rigid_loaded_te: rows.iter().map(|r| r.1).collect(),
        flexible_ste,
        flexible_loaded_te,
        max_force: rows.iter().map(|r| r.3.max_force()).collect(),
        rigid_ste_reverse: reverse.iter().map(|r| r.0).collect(),
        flexible_ste_reverse: reverse.iter().map(|r| r.1).collect(),
        flexible_loaded_te_reverse: reverse.iter().map(|r| r.2).collect(),
        torsional_stiffness,
        hysteresis_torque,
        hysteresis_twist,
        stress,
    };
    st.torsional_stiffness = two_sense_stiffness(&st);
    Ok(st)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Anderson mixing solves a linear fixed point `x = A x + b` (contraction about 0.9, 12
    /// unknowns) to 1e-12 in 12 sweeps, where plain iteration needs 285 (bounds: 40 and 200).
    #[test]
    fn anderson_mixing_accelerates_a_linear_fixed_point() {
        let n = 12;
        let a = DMatrix::from_fn(n, n, |i, j| {
            let base = if i == j { 0.9 } else { 0.0 };
            base + 0.004 * ((i * 7 + j * 3) % 5) as f64 - 0.008
        });
        let b = DVector::from_fn(n, |i, _| (i as f64).sin());
        let exact = (DMatrix::identity(n, n) - &a)
            .lu()
            .solve(&b)
            .expect("I - A is regular");
        let g = |x: &[f64]| -> Vec<f64> {
            let v = &a * DVector::from_column_slice(x) + &b;
            v.iter().copied().collect()
        };
        let sweeps = |depth: usize| {
            let mut mix = AndersonMixing::new(depth);
            let mut x = vec![0.0; n];
            for k in 0..1000 {
                let gx = g(&x);
                let err = x
                    .iter()
                    .zip(exact.iter())
                    .fold(0.0_f64, |m, (u, v)| m.max((u - v).abs()));
                if err < 1e-12 {
                    return k;
                }
                x = if depth == 0 {
                    gx
                } else {
                    mix.next(&x, &gx, 1.0)
                };
            }
            1000
        };
        let (plain, mixed) = (sweeps(0), sweeps(ANDERSON_DEPTH));
        eprintln!("plain {plain} sweeps, Anderson({ANDERSON_DEPTH}) {mixed}");
        assert!(plain > 200);
        assert!(mixed < 40, "Anderson mixing took {mixed} sweeps");
    }
}
