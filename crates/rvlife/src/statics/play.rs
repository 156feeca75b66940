//! The no-load limit as a contact problem (docs/model.md section 5.10): the twist each way at
//! which the unloaded reducer first stops, with every pin-flank contact, every crank bearing's
//! clearance, every output pin in its hole and every sun-planet mesh as a constraint on the
//! reducer's coordinates.
//!
//! With no load every elastic part is undeformed, so the mechanism can take any configuration
//! in which no pin penetrates a flank (`gap_j >= 0`), every bearing's centres lie within half
//! its clearance of each other (`|r_b| <= c_b/2`), every output pin within its hole and every
//! mesh within its play; the `T -> 0+` limit of the loaded twist is the largest carrier twist
//! `s psi` over that set (the loaded equilibrium minimises `-T psi` plus an elastic energy that
//! vanishes on the set and is infinitely stiff off it as `T -> 0`). The set is curved (the
//! flanks, the bearings' circles), so the limit is found by sequential convex programming:
//! each iteration linearises the gaps and the elements' relative positions at the current
//! configuration and solves the second-order cone programme
//!
//! ```text
//! max s psi   s.t.   gap_j + grad gap_j . dz >= 0           (every pin of every disc)
//!                    |r_b + J_b dz| <= c_b / 2               (every element with room)
//!                    r_b + J_b dz = 0                        (every element without)
//!                    |dz_i| <= Delta                         (trust region)
//! ```
//!
//! with Clarabel (Goulart and Chen, *Clarabel: an interior-point solver for conic programs
//! with quadratic objectives*, 2024), a small multiple of `|dz|^2` in the objective so that
//! coordinates the twist does not depend on stay where they are. The bearings' circles enter
//! exactly as cones; an output pin's hole as its linearised distance to the wall; only the
//! flanks' curvature and the rotations are linearised, so the iteration converges as Newton's
//! method where the limit is a vertex of the constraints.
//!
//! The programmes are steps of a trust-region method on the exact penalty `-s psi + mu
//! violation` (Fletcher's sequential linear programming with elastic slacks on the violated
//! rows; Nocedal and Wright, *Numerical Optimization*, 2nd ed., section 18.5). It stops when
//! a programme predicts less than [`TWIST_TOLERANCE`] of progress at the pin circle while the
//! configuration meets the constraints to [`FEASIBILITY`]; where it ends outside them, `mu`
//! was below a multiplier and is raised. From a start outside the constraints (part errors
//! that close the rigid play) the violation alone is minimised first; a start from which no
//! configuration within the constraints is found is a reducer whose parts interfere: preload
//! (docs/model.md section 5.12). Every limit that does not converge within
//! [`MAX_ITERATIONS`] programmes, twice, fails loudly naming the crank angle.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

use super::*;
use crate::reducer::ElementLaw;

/// Convergence of the no-load limit: a step that moves the twist by less than this at the pin
/// circle radius (m) ends the iteration (1e-13 m is 1.6e-12 rad, 5e-9 arcmin for the example).
pub(crate) const TWIST_TOLERANCE: f64 = 1e-13;

/// Progress (m at the pin circle) below which a configuration within the constraints is
/// taken as the limit where the solver cannot finish the next programme (a degenerate vertex
/// with many pins touching at once): 1e-10 m is 5e-6 arcmin on the example.
pub(crate) const LOOSE_TOLERANCE: f64 = 1e-10;

/// Most convex programmes of one no-load limit.
pub(crate) const MAX_ITERATIONS: usize = 200;

/// Length unit of the convex programme, per metre: micrometres, so that gaps, clearances and
/// steps are of order one for the solver's absolute tolerances (1e-8, 1e-14 m).
const UNIT: f64 = 1e6;

/// Weight of the step's square in the programme's objective, per unit length of the
/// programme: a tie-break among configurations of equal twist, far below the twist's weight
/// of 1 at every step the programme takes.
const STEP_WEIGHT: f64 = 1e-7;

/// Smallest trust region of the programme, in its units (1e-13 m): a region cut below it ends
/// the iteration where it is.
const MIN_TRUST: f64 = 1e-7;

/// First weight of the constraints' violation in the penalty the iteration decreases, per
/// unit of the twist's arc at the pin circle. The penalty is exact once the weight exceeds
/// every multiplier of the problem (a contact's force per unit of torque at the pin circle);
/// where the iteration ends on a configuration that violates the constraints by more than
/// [`FEASIBILITY`] it was not, and the weight is raised a hundredfold (the region opened
/// again), up to [`MAX_PENALTY`].
const PENALTY: f64 = 10.0;

/// First weight of the violation in the second attempt ([`PENALTY`]).
const RETRY_PENALTY: f64 = 1e4;

/// Largest weight of the violation ([`PENALTY`]).
const MAX_PENALTY: f64 = 1e8;

/// Progress, as a fraction of the violation, below which the minimisation of the violation
/// alone ends ([`StaticAnalysis::penalty_iteration`] with `s = 0`): its least value is reached
/// to this fraction, so a least violation of 1e-12 m or more (preload) is told from zero.
const VIOLATION_PROGRESS: f64 = 1e-5;

/// Penetration of a pin (m) in the rigid kinematics of a reducer without play beyond which its
/// parts interfere (preload): about the first contacts' round-off at the pin circle (1e-9
/// rad of twist, `te::PLAY_ROUND_OFF`, at a pin circle of 0.1 m).
const INTERFERENCE: f64 = 1e-10;

/// Largest violation of the constraints (m, summed over them) of an accepted no-load limit.
const FEASIBILITY: f64 = 1e-12;

/// The no-load limit of one direction.
#[derive(Debug, Clone)]
pub(crate) enum NoLoad {
    /// The reducer turns freely to this twist (rad), where the configuration `rest` (a
    /// zero-torque solution of the direction, from which loaded solves start; `None` without
    /// play) first stops it.
    Limit {
        twist: f64,
        rest: Option<Box<StaticSolution>>,
    },
    /// Its parts interfere: no configuration leaves every pin and element unloaded. With
    /// play, `least` is the configuration that violates the constraints least (deviations,
    /// the layout's coordinates: where a neighbouring state's contact problem starts);
    /// `None` without play.
    Preloaded { least: Option<Vec<f64>> },
}

/// How one trust-region iteration ends.
enum Outcome {
    /// At the limit (twist, rad) and its configuration, within the constraints.
    Limit(f64, Vec<f64>),
    /// On this configuration, which violates the constraints at the largest weight.
    Violating(Vec<f64>),
    /// Within [`MAX_ITERATIONS`] programmes, neither.
    Unconverged,
}

/// One linear row `a . x` of the programme and its right-hand side (`a . x + s = b`).
struct Row {
    a: Vec<f64>,
    b: f64,
}

/// The constraints of the no-load problem linearised at one configuration, in the
/// programme's units: equalities, inequalities (`b - a . x >= 0`), second-order cones, and how
/// far the configuration violates them (the sum of the gaps' penetrations, the elements'
/// excess over their room and the equalities' residuals, micrometres).
struct Linearised {
    zero: Vec<Row>,
    nonneg: Vec<Row>,
    cones: Vec<[Row; 3]>,
    violation: f64,
}

impl<'a> StaticAnalysis<'a> {
    /// The no-load limit in direction `direction` at crank angle `phi` (both in the analysis'
    /// terms: the meshes' play is taken up exactly), starting from the rigid first contact
    /// `psi0` (rad, [`StaticAnalysis::first_contact`] of that direction). Without play, or
    /// with rigid support, the rigid first contact itself.
    ///
    /// # Errors
    /// [`Error::Numerical`] naming the crank angle if the programme fails or does not converge
    /// in [`MAX_ITERATIONS`], or the contact geometry cannot be evaluated.
    pub(crate) fn no_load(&self, phi: f64, direction: f64, psi0: f64) -> Result<NoLoad> {
        self.no_load_from(phi, direction, psi0, None)
    }

    /// [`StaticAnalysis::no_load`] whose programmes start from the configuration `from`
    /// (deviations, the length of the layout's coordinates, as a [`NoLoad`] of a neighbouring
    /// state holds them: the same crank angle at fewer hours of wear) instead of the rigid
    /// mode at `psi0`; a `from` of another length is ignored. The limit is the same to
    /// [`TWIST_TOLERANCE`]; a start near it takes fewer programmes.
    ///
    /// # Errors
    /// As [`StaticAnalysis::no_load`].
    pub(crate) fn no_load_from(
        &self,
        phi: f64,
        direction: f64,
        psi0: f64,
        from: Option<&[f64]>,
    ) -> Result<NoLoad> {
        let s = sense(direction);
        if self.red.support != Support::Bearings {
            return Ok(NoLoad::Limit {
                twist: psi0,
                rest: None,
            });
        }
        if self.red.max_half_play() <= 0.0 {
            // Without play the unloaded mechanism has one configuration per twist, the rigid
            // kinematics: the limit is the rigid first contact unless a pin that neither way's
            // first contact sees (one near the line of centres, whose gap the twist hardly
            // moves) already penetrates there.
            return Ok(if self.penetrates_at(phi, psi0)? {
                NoLoad::Preloaded { least: None }
            } else {
                NoLoad::Limit {
                    twist: psi0,
                    rest: None,
                }
            });
        }
        let (phi_free, shift) = self.play_taken_up(phi, s);
        // A zero-torque state of the direction at configuration `z` (what a solve started from
        // it reads: the direction's sense with no load).
        let state = |z: Vec<f64>| {
            Box::new(StaticSolution {
                crank_angle: phi,
                output_torque: s * f64::MIN_POSITIVE,
                twist: z[Layout::OUT] + shift,
                first_contact_twist: psi0,
                stiffness: 0.0,
                discs: Vec::new(),
                residual: 0.0,
                roundoff_floor: 0.0,
                deviations: z,
                twist_direction: Vec::new(),
            })
        };
        Ok(match self.no_load_free(phi_free, s, psi0 - shift, from)? {
            Ok((twist, z)) => NoLoad::Limit {
                twist: twist + shift,
                rest: Some(state(z)),
            },
            Err(least) => NoLoad::Preloaded { least: Some(least) },
        })
    }

    /// Whether a pin of a disc penetrates its flank by more than [`INTERFERENCE`] in the
    /// rigid kinematics at crank angle `phi` and carrier twist `psi` (rad): parts that
    /// interfere there, so that a reducer without play is preloaded (docs/model.md section
    /// 5.12).
    ///
    /// # Errors
    /// [`Error::Numerical`] if the contact geometry cannot be evaluated.
    fn penetrates_at(&self, phi: f64, psi: f64) -> Result<bool> {
        for d in 0..self.discs() {
            let (pose, _) = self.mode_pose(phi, d, psi);
            for j in 0..self.red.geometry.pins {
                if self.eval_pin(&pose, j, f64::NAN)?.gap < -INTERFERENCE {
                    return Ok(true);
                }
            }
        }
        Ok(false)
    }

    /// [`StaticAnalysis::no_load`] of the analysed reducer at its crank angle `phi`, direction
    /// `s` (+-1), from the rigid first contact `psi0`: the twist and the configuration, or,
    /// where no configuration within the constraints is found from the start (preload), the
    /// one that violates them least.
    ///
    /// A trust-region iteration on the exact penalty `-s psi + mu violation`
    /// ([`StaticAnalysis::penalty_iteration`]): a step is taken where the penalty falls by at
    /// least a tenth of what the programme predicts, the region doubled where the step reached
    /// it and the prediction held, and cut to a quarter of the step where it did not (a
    /// flank's curvature the programme does not see). It ends when the programme predicts
    /// less than [`TWIST_TOLERANCE`] of progress within the constraints.
    ///
    /// # Errors
    /// [`Error::Numerical`] naming the crank angle when neither attempt converges.
    #[allow(clippy::type_complexity)]
    fn no_load_free(
        &self,
        phi: f64,
        s: f64,
        psi0: f64,
        from: Option<&[f64]>,
    ) -> Result<std::result::Result<(f64, Vec<f64>), Vec<f64>>> {
        let red = &*self.red;
        let n = red.layout().dofs();
        let fr = self.frame(phi);
        let rp = red.geometry.pin_circle_radius;
        // Variable i is coordinate i + 1 (the input is locked), in micrometres, angles as arcs
        // at the pin circle.
        let scale: Vec<f64> = (1..n)
            .map(|i| if is_angle(i) { UNIT * rp } else { UNIT })
            .collect();
        let mut start = vec![0.0; n];
        match from {
            Some(z) if z.len() == n => start.copy_from_slice(z),
            _ => self.mode_deviation(&fr, psi0, &mut start),
        }
        let max_trust = 4.0 * UNIT * red.max_half_play() + 1.0;
        let fail = |what: &str| {
            self.fail(
                phi,
                &format!("the no-load limit (direction {s:+}) {what} in {MAX_ITERATIONS} contact problems"),
            )
        };
        // From a start that violates the constraints (part errors that close the rigid play),
        // first a configuration that meets them: the violation alone minimised. Where none
        // is found near the start, the parts interfere.
        let mut hints = vec![f64::NAN; self.discs() * red.geometry.pins];
        if self.linearise(&fr, &start, &scale, &mut hints)?.violation > FEASIBILITY * UNIT {
            // Where the iteration runs out of programmes (a flank's kink, as below), once more
            // from the start in a region of a sixty-fourth.
            let mut found = Outcome::Unconverged;
            for trust in [max_trust, max_trust / 64.0] {
                found = self.penalty_iteration(0.0, &fr, &scale, start.clone(), 1.0, trust, 1.0)?;
                if !matches!(found, Outcome::Unconverged) {
                    break;
                }
            }
            match found {
                Outcome::Limit(_, z) => start = z,
                Outcome::Violating(least) => return Ok(Err(least)),
                Outcome::Unconverged => return Err(fail("found no configuration")),
            }
        }
        // A flank's kink (a pin in the middle of a tooth root or on a tip, where the closest
        // point jumps between the flanks) can hold the iteration on a point that violates the
        // constraints while they can be met: once more from the start with the violation
        // weighed heavily from the first step and a small region.
        for (penalty, trust) in [(PENALTY, max_trust), (RETRY_PENALTY, max_trust / 64.0)] {
            if let Outcome::Limit(twist, z) =
                self.penalty_iteration(s, &fr, &scale, start.clone(), penalty, trust, MAX_PENALTY)?
            {
                return Ok(Ok((twist, z)));
            }
        }
        Err(fail("did not converge"))
    }

    /// The trust-region iteration of [`StaticAnalysis::no_load_free`] from configuration `z`
    /// with the first weight `penalty` (raised up to `max_penalty`) and region `trust`, for
    /// the largest twist in direction `s` (+-1), or, with `s = 0`, for the least violation
    /// alone.
    #[allow(clippy::too_many_arguments)]
    fn penalty_iteration(
        &self,
        s: f64,
        fr: &Frame,
        scale: &[f64],
        mut z: Vec<f64>,
        mut penalty: f64,
        mut trust: f64,
        max_penalty: f64,
    ) -> Result<Outcome> {
        let red = &*self.red;
        let nv = z.len() - 1;
        let rp = red.geometry.pin_circle_radius;
        let max_trust = 4.0 * UNIT * red.max_half_play() + 1.0;
        let mut hints = vec![f64::NAN; self.discs() * red.geometry.pins];
        let mut here = self.linearise(fr, &z, scale, &mut hints)?;
        let merit = |z: &[f64], lin: &Linearised, penalty: f64| {
            -s * z[Layout::OUT] * rp * UNIT + penalty * lin.violation
        };
        let tolerance = TWIST_TOLERANCE * UNIT;
        let mut last_predicted = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            // A programme the solver cannot finish (a degenerate vertex: many pins touching
            // at once, as on the line of centres) is retried in a smaller region, where it is
            // better conditioned, down to the smallest region.
            let solved = self.programme(nv, s, &here, trust, penalty);
            let (x, slack) = match &solved {
                Ok((x, slack)) => (x.clone(), *slack),
                Err(_) => (Vec::new(), 0.0),
            };
            let predicted = match solved {
                Ok(_) => s * x[0] + penalty * (here.violation - slack),
                Err(_) => f64::NAN,
            };
            if predicted.is_nan() {
                // At the limit to within `LOOSE_TOLERANCE` and within the constraints: there.
                if last_predicted <= LOOSE_TOLERANCE * UNIT && here.violation <= FEASIBILITY * UNIT
                {
                    return Ok(Outcome::Limit(z[Layout::OUT], z));
                }
                trust *= 0.25;
            }
            last_predicted = predicted;
            // The violation alone is minimised to a hundred-thousandth of itself: where it is
            // not zero (preload) its least value lies in a valley along which the twist is
            // free, and the programmes' progress along it, a few millionths of the violation,
            // would never fall to the twist's tolerance.
            let converged = if s == 0.0 {
                predicted <= tolerance.max(VIOLATION_PROGRESS * here.violation)
            } else {
                predicted <= tolerance
            };
            if converged || trust < MIN_TRUST {
                // Converged on the penalty. A configuration that still violates the
                // constraints: the weight was below a multiplier (raise it and go on), or,
                // at the largest weight, no configuration satisfies them (preload).
                if here.violation <= FEASIBILITY * UNIT {
                    return Ok(Outcome::Limit(z[Layout::OUT], z));
                }
                if penalty >= max_penalty {
                    return Ok(Outcome::Violating(z));
                }
                // The violation alone (`s = 0`): a heavier weight scales the whole objective
                // and moves nothing but the steps' tie-break, so a least violation reached in
                // an open region (as open as a raise would make it) is the answer; only a
                // region that collapsed is raised and opened again.
                if s == 0.0 && trust >= max_trust / 16.0 {
                    return Ok(Outcome::Violating(z));
                }
                // A hundredfold, with the region opened again: a pin on the line of centres
                // closes only to second order in the twist, so its multiplier, and the weight
                // that moves the twist back, is large.
                penalty = (100.0 * penalty).min(max_penalty);
                trust = trust.max(max_trust / 16.0);
                continue;
            }
            if predicted.is_nan() {
                continue;
            }
            let reach = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let mut trial = z.clone();
            for i in 0..nv {
                trial[i + 1] += x[i] / scale[i];
            }
            let there = self.linearise(fr, &trial, scale, &mut hints)?;
            let actual = merit(&z, &here, penalty) - merit(&trial, &there, penalty);
            if actual >= 0.1 * predicted {
                if actual >= 0.75 * predicted && reach >= 0.99 * trust {
                    trust = (2.0 * trust).min(max_trust);
                }
                z = trial;
                here = there;
            } else {
                trust = 0.25 * reach;
            }
        }
        Ok(Outcome::Unconverged)
    }

    /// Every constraint of the no-load problem linearised at configuration `z` (frame `fr`;
    /// `hints`: the pins' path parameters, updated), in the programme's units, with the
    /// configuration's violation of them.
    ///
    /// # Errors
    /// [`Error::Numerical`] if the contact geometry cannot be evaluated.
    fn linearise(
        &self,
        fr: &Frame,
        z: &[f64],
        scale: &[f64],
        hints: &mut [f64],
    ) -> Result<Linearised> {
        let red = &*self.red;
        let nv = z.len() - 1;
        let zp = red.geometry.pins;
        let mut lin = Linearised {
            zero: Vec::new(),
            nonneg: Vec::new(),
            cones: Vec::new(),
            violation: 0.0,
        };
        self.structure_rows(fr, z, scale, &mut lin);
        for d in 0..self.discs() {
            let pose = self.pose_from(fr, z, d);
            let rot = Rotation2::new(pose.angle);
            let id = red.layout().disc(d) - 1;
            for j in 0..zp {
                let hint = &mut hints[d * zp + j];
                let p = self.eval_pin_from(&pose, &rot, j, *hint, f64::NAN, 0.0)?;
                *hint = p.t;
                // gap + grad . dz >= 0 as `b - a . dz >= 0`: `a` is minus the gap's gradient
                // over the disc's centre and angle (the pin centre relative to the disc moves
                // by `-dc - dpsi J rel`).
                let mut a = vec![0.0; nv];
                a[id] = UNIT * p.w.x / scale[id];
                a[id + 1] = UNIT * p.w.y / scale[id + 1];
                a[id + 2] = UNIT * cross(&p.rel, &p.w) / scale[id + 2];
                lin.violation += (-p.gap * UNIT).max(0.0);
                lin.nonneg.push(Row { a, b: p.gap * UNIT });
            }
        }
        Ok(lin)
    }

    /// The rows of the structure at configuration `z` (frame `fr`), linearised by central
    /// differences of [`Reducer::elements`] over every variable (lengths by 1e-7 m, angles by
    /// 1e-6 rad: the elements are linear in the lengths and smooth in the angles, so the
    /// differences are exact to about 1e-15 of the derivatives): an element or mesh without
    /// room as equalities, a mesh with play as two inequalities, an element with room as a
    /// second-order cone `(room, r + J dz)`, all in the programme's units.
    fn structure_rows(&self, fr: &Frame, z: &[f64], scale: &[f64], lin: &mut Linearised) {
        let red = &*self.red;
        let n = z.len();
        let q0 = &fr.q0[..n];
        let at = |z: &[f64]| {
            let (mut radial, mut meshes) = (Vec::new(), Vec::new());
            red.elements(q0, z, &mut radial, &mut meshes);
            let radial: Vec<(Vec2, f64, bool)> = radial
                .iter()
                .map(|e| (e.r, e.room, matches!(e.law, ElementLaw::PinInHole(_))))
                .collect();
            let meshes: Vec<(f64, f64)> =
                meshes.iter().map(|m| (m.deflection, m.half_play)).collect();
            (radial, meshes)
        };
        let (radial, meshes) = at(z);
        let mut jr = vec![vec![Vec2::zeros(); n - 1]; radial.len()];
        let mut jm = vec![vec![0.0; n - 1]; meshes.len()];
        let mut zz = z.to_vec();
        for i in 1..n {
            let h = if is_angle(i) { 1e-6 } else { 1e-7 };
            zz[i] = z[i] + h;
            let (rp, mp) = at(&zz);
            zz[i] = z[i] - h;
            let (rm, mm) = at(&zz);
            zz[i] = z[i];
            let f = UNIT / (2.0 * h * scale[i - 1]);
            for (e, row) in jr.iter_mut().enumerate() {
                row[i - 1] = (rp[e].0 - rm[e].0) * f;
            }
            for (m, row) in jm.iter_mut().enumerate() {
                row[i - 1] = (mp[m].0 - mm[m].0) * f;
            }
        }
        for (&(delta, half), g) in meshes.iter().zip(jm) {
            let (delta, half) = (delta * UNIT, half * UNIT);
            lin.violation += (delta.abs() - half).max(0.0);
            if half <= 0.0 {
                lin.zero.push(Row { a: g, b: -delta });
            } else {
                lin.nonneg.push(Row {
                    a: g.clone(),
                    b: half - delta,
                });
                lin.nonneg.push(Row {
                    a: g.iter().map(|v| -v).collect(),
                    b: half + delta,
                });
            }
        }
        for (&(r, room, ring), j) in radial.iter().zip(jr) {
            let r = r * UNIT;
            lin.violation += (r.norm() - room * UNIT).max(0.0);
            if ring {
                // An output pin in its hole: `|r|` is of the size of the eccentricity, its
                // room a micrometre or two above it, so the cone would ask the solver for a
                // relative precision it does not have. Its distance to the wall instead,
                // linearised like a gap (the wall's curvature seen by the iteration).
                let n = r / r.norm();
                lin.nonneg.push(Row {
                    a: j.iter().map(|v| n.dot(v)).collect(),
                    b: room * UNIT - r.norm(),
                });
                continue;
            }
            let jx: Vec<f64> = j.iter().map(|v| v.x).collect();
            let jy: Vec<f64> = j.iter().map(|v| v.y).collect();
            if room <= 0.0 {
                lin.zero.push(Row { a: jx, b: -r.x });
                lin.zero.push(Row { a: jy, b: -r.y });
            } else {
                lin.cones.push([
                    Row {
                        a: vec![0.0; n - 1],
                        b: room * UNIT,
                    },
                    Row {
                        a: jx.iter().map(|v| -v).collect(),
                        b: r.x,
                    },
                    Row {
                        a: jy.iter().map(|v| -v).collect(),
                        b: r.y,
                    },
                ]);
            }
        }
    }

    /// One convex programme, the penalty linearised (Fletcher's `S l1 QP` without the
    /// curvature): `min -s x_0 + penalty sum v + STEP_WEIGHT |x|^2 / 2` over the step `x`
    /// and one elastic slack `v >= 0` per inequality and per cone of `lin` (`b - a . x + v >= 0`,
    /// `|r + J x| <= room + v`), its equalities exact and `|x_i| <= trust`. Always feasible
    /// (`x = 0` with the violations as slacks). The step and the sum of the slacks; the
    /// solver's status if it fails.
    fn programme(
        &self,
        nv: usize,
        s: f64,
        lin: &Linearised,
        trust: f64,
        penalty: f64,
    ) -> std::result::Result<(Vec<f64>, f64), SolverStatus> {
        // Only the inequalities the trust region can reach (`|a . x| <= |a|_1 trust`: the
        // others hold for every step), and a slack only where the configuration violates a
        // row (elsewhere `x = 0` satisfies it).
        let reachable: Vec<&Row> = lin
            .nonneg
            .iter()
            .filter(|r| r.b <= trust * r.a.iter().map(|v| v.abs()).sum::<f64>())
            .collect();
        let violated_cone = |c: &[Row; 3]| c[0].b < c[1].b.hypot(c[2].b);
        let ni = reachable.len();
        let nz = lin.zero.len();
        let ns = reachable.iter().filter(|r| r.b < 0.0).count()
            + lin.cones.iter().filter(|c| violated_cone(c)).count();
        let nx = nv + ns;
        // Columns: the step, then the slacks. Row blocks: equalities; inequalities, slacks
        // non-negative, trust region (all in the non-negative cone); cones.
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nx];
        let mut b = Vec::with_capacity(nz + ni + ns + 2 * nv + 3 * lin.cones.len());
        let mut row = 0;
        let mut put = |a: &[f64], extra: Option<(usize, f64)>, rhs: f64, b: &mut Vec<f64>| {
            for (c, &v) in a.iter().enumerate() {
                if v != 0.0 {
                    cols[c].push((row, v));
                }
            }
            if let Some((c, v)) = extra {
                cols[c].push((row, v));
            }
            b.push(rhs);
            row += 1;
        };
        for r in &lin.zero {
            put(&r.a, None, r.b, &mut b);
        }
        let mut slack = nv;
        for r in &reachable {
            let extra = (r.b < 0.0).then(|| {
                slack += 1;
                (slack - 1, -1.0)
            });
            put(&r.a, extra, r.b, &mut b);
        }
        let cone_slacks: Vec<Option<usize>> = lin
            .cones
            .iter()
            .map(|c| {
                violated_cone(c).then(|| {
                    slack += 1;
                    slack - 1
                })
            })
            .collect();
        for k in nv..nx {
            put(&[], Some((k, -1.0)), 0.0, &mut b);
        }
        for i in 0..nv {
            put(&[], Some((i, 1.0)), trust, &mut b);
            put(&[], Some((i, -1.0)), trust, &mut b);
        }
        for (cone, slack) in lin.cones.iter().zip(&cone_slacks) {
            put(&cone[0].a, slack.map(|k| (k, -1.0)), cone[0].b, &mut b);
            put(&cone[1].a, None, cone[1].b, &mut b);
            put(&cone[2].a, None, cone[2].b, &mut b);
        }
        let m = b.len();
        let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
        for col in &cols {
            for &(r, v) in col {
                rowval.push(r);
                nzval.push(v);
            }
            colptr.push(rowval.len());
        }
        let a = CscMatrix::new(m, nx, colptr, rowval, nzval);
        let p = CscMatrix::new(
            nx,
            nx,
            (0..=nx).map(|c| c.min(nv)).collect(),
            (0..nv).collect(),
            vec![STEP_WEIGHT; nv],
        );
        let mut q = vec![penalty; nx];
        q[..nv].iter_mut().for_each(|v| *v = 0.0);
        q[0] = -s;
        let mut kinds = Vec::new();
        if nz > 0 {
            kinds.push(SupportedConeT::ZeroConeT(nz));
        }
        kinds.push(SupportedConeT::NonnegativeConeT(ni + ns + 2 * nv));
        kinds.extend(
            lin.cones
                .iter()
                .map(|_| SupportedConeT::SecondOrderConeT(3)),
        );
        // Without iterative refinement of the KKT solves: the interior-point iteration ends on
        // its own residuals whatever the solves' accuracy, and the programmes are small and
        // well scaled (micrometres); the study's no-load limits and curves come out the same
        // to every printed digit, in a tenth less time.
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(200)
            .iterative_refinement_enable(false)
            .build()
            .map_err(|_| SolverStatus::Unsolved)?;
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &kinds, settings)
            .map_err(|_| SolverStatus::Unsolved)?;
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                let x = &solver.solution.x;
                Ok((x[..nv].to_vec(), x[nv..].iter().map(|v| v.max(0.0)).sum()))
            }
            other => Err(other),
        }
    }
}
