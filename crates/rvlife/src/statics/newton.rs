//! The loaded equilibrium: the potential's minimum over every coordinate but the input (Newton
//! with the analytic tangent, backtracking, Levenberg-Marquardt's trust region), its cold start
//! (the inner coordinates' equilibrium at a fixed twist) and the condensed stiffness
//! (docs/model.md section 5.3).

use super::*;

/// Largest move of a coordinate in the first step of the torque-controlled Newton method from a
/// cold start, in multiples of the twist estimate at the pin circle
/// ([`StaticAnalysis::twist_guess`]); doubled after each full step it bounds.
const STEP_LIMIT_GUESSES: f64 = 16.0;

/// Fraction of [`RESIDUAL_TOLERANCE`] within which a torque-controlled solve whose steps no
/// longer reduce the residual fourfold is accepted (it aims at a hundredth; the solution's
/// check allows the whole tolerance).
const STALL_FRACTION: f64 = 0.1;

/// Fraction of [`RESIDUAL_TOLERANCE`] at which the torque-controlled solve stops (the
/// solution's check allows the whole tolerance). Where a pin has just touched, its contact
/// law's curvature (the force's second derivative in the approach, large at small approach)
/// holds Newton's method near a thousandfold reduction of the residual per step instead of
/// squaring it, so a tighter aim costs a whole step (an evaluation and a tangent) for
/// twists that move by about 1e-15 m at the pin circle (the residual's 1e-9 of the force
/// scale over the contacts' stiffness).
const CONVERGED_FRACTION: f64 = 0.3;

/// Twist beyond first contact (rad) at which an iterate of the torque-controlled solve is lost:
/// four times the analysis' range (`MAX_TWIST`), a quarter of a tooth of the example (a step
/// bounded to a quarter of the range cannot pass a pin's flank, where the potential rises).
const LOST_TWIST: f64 = 4.0 * MAX_TWIST;

/// Most steps of the torque-controlled solve (`StaticAnalysis::torque_controlled`): Newton's
/// and the trust region's.
pub(super) const TORQUE_CONTROL_STEPS: usize = 100;

impl<'a> StaticAnalysis<'a> {
    /// Largest scaled residual of the inner coordinates (every one but input and output):
    /// forces in N, moments divided by the pin circle radius.
    pub(super) fn inner_residual(&self, g: &[f64]) -> f64 {
        let n = self.red.layout().dofs();
        let rp = self.red.geometry.pin_circle_radius;
        (2..n)
            .map(|i| g[i].abs() / if is_angle(i) { rp } else { 1.0 })
            .fold(0.0, f64::max)
    }

    /// Equilibrium of every coordinate but input and output at the carrier twist fixed in `z`
    /// (deviations, updated in place): Newton's method with backtracking on the residual norm.
    /// Returns the converged evaluation and the tangent. `force_floor` (N) is the least force
    /// scale of the convergence test.
    pub(super) fn inner_solve(
        &self,
        fr: &Frame,
        z: &mut [f64],
        k_struct: &DMatrix<f64>,
        memory: &mut [Vec<PinMemory>],
        force_floor: f64,
    ) -> Result<(Eval, DMatrix<f64>)> {
        let n = self.red.layout().dofs();
        let m = n - 2;
        let rp = self.red.geometry.pin_circle_radius;
        let merit = |e: &Eval| -> f64 {
            (2..n)
                .map(|i| {
                    let x = e.g[i] / if is_angle(i) { rp } else { 1.0 };
                    x * x
                })
                .sum()
        };
        let mut ev = self.eval_bearings(fr, z, memory, true)?;
        let mut stalled = 0;
        // The tangent is kept while the residual falls at least fourfold per step (a modified
        // Newton method), and rebuilt otherwise.
        let mut kt: Option<DMatrix<f64>> = None;
        // Levenberg-Marquardt damping of the Newton step (relative to the diagonal), raised
        // when a step of the exact tangent finds no descent away from the round-off floor (a
        // disc on a ridge of a worn flank, where the tangent is indefinite), reset after a
        // descent.
        let mut damping = 0.0;
        // Whether the line search also takes the elastic energy as its merit: from the first
        // step that the residual norm cut below a sixteenth (the search on it crawls there).
        let mut energy_merit = false;
        // The residual of every step so far (the last one decides whether the tangent is
        // rebuilt): a solve whose residual has not halved in eight steps is crawling (each step of the tangent runs a body that is free inside its
        // bearing's clearance far into a contact the tangent does not see, and the
        // backtracking keeps a sliver of it); from then on each step goes to the energy's
        // minimum along it ([`StaticAnalysis::line_minimum`]).
        let mut history: Vec<f64> = Vec::with_capacity(100);
        for _ in 0..100 {
            let res = self.inner_residual(&ev.g);
            let scale = ev.scale.max(force_floor).max(1e-300);
            // Whether `kt` is the tangent at the current state `ev`.
            let last_res = history.last().copied().unwrap_or(f64::INFINITY);
            let fresh = kt.is_none() || res > 0.25 * last_res;
            if fresh {
                kt = Some(self.tangent(k_struct, &ev, fr, z));
            }
            history.push(res);
            let crawl = history.len() > 8 && res > 0.5 * history[history.len() - 9];
            // Converged to a hundredth of the acceptance tolerance, or at the round-off floor of
            // the forces (the residual stopped falling): return the tangent at the solution.
            if res <= 0.01 * RESIDUAL_TOLERANCE * scale || stalled >= 2 {
                let kt = match kt {
                    Some(kt) if fresh => kt,
                    _ => self.tangent(k_struct, &ev, fr, z),
                };
                return Ok((ev, kt));
            }
            let kt = kt.as_ref().expect("tangent built above");
            let rhs = DVector::from_iterator(m, (2..n).map(|i| ev.g[i]));
            // A coordinate without stiffness (a disc or crank free inside its bearing's
            // clearance while no pin touches it that way) makes the tangent singular: damped
            // against the largest diagonal term, it stays where it is while the others settle.
            let largest = (2..n).map(|i| kt[(i, i)].abs()).fold(0.0, f64::max);
            let damped = |d: f64| {
                let mut k = kt.view((2, 2), (m, m)).into_owned();
                for i in 0..m {
                    k[(i, i)] += d * kt[(2 + i, 2 + i)].abs().max(1e-9 * largest);
                }
                k.lu().solve(&rhs)
            };
            let first = if damping > 0.0 {
                damped(damping)
            } else {
                kt.view((2, 2), (m, m)).into_owned().lu().solve(&rhs)
            };
            let step = match first {
                Some(step) => step,
                None => {
                    damping = damping.max(1e-3);
                    damped(damping).ok_or_else(|| {
                        self.fail(fr.phi, "the inner stiffness matrix is singular")
                    })?
                }
            };
            if crawl {
                if let Some(next) = self.line_minimum(fr, z, &step, memory, &ev)? {
                    let fell = self.inner_residual(&next.g) < 0.999 * res;
                    stalled = if fell { 0 } else { stalled + 1 };
                    damping = 0.0;
                    ev = next;
                    continue;
                }
            }
            let m0 = merit(&ev);
            let base: Vec<f64> = z[..n].to_vec();
            // The elastic energy at the base and its slope along the step (`-g . step`),
            // formed only when a trial fails the residual test.
            let mut energy0: Option<(f64, f64)> = None;
            let mut alpha = 1.0;
            loop {
                for i in 0..m {
                    z[2 + i] = base[2 + i] + alpha * step[i];
                }
                // A trial step long enough to take a contact out of the law's validity (a
                // Newton step across a sharp feature of a worn flank) is shortened like one
                // that raises the residual.
                let trial = match self.eval_bearings(fr, z, memory, true) {
                    Ok(trial) => trial,
                    Err(_) if alpha >= 1e-4 => {
                        alpha *= 0.5;
                        continue;
                    }
                    Err(e) => return Err(e),
                };
                let mt = merit(&trial);
                // Accepted where the residual falls, or where the elastic energy falls enough
                // along a descent direction (Armijo; the equilibrium at a fixed twist is the
                // energy's minimum over the inner coordinates): near a bearing's clearance edge
                // or a pin that opens, the residual norm can rise along a step that nears the
                // minimum, and a line search on it alone crawls.
                // (Above the round-off floor of the forces only, and for a decrease the energy's
                // own round-off cannot fake.)
                let residual_falls = mt <= m0 * (1.0 - 1e-4 * alpha);
                let accepted = residual_falls
                    || energy_merit && res > ev.roundoff && {
                        let (e0, slope) = *energy0.get_or_insert_with(|| {
                            let slope = -(0..m).map(|i| ev.g[2 + i] * step[i]).sum::<f64>();
                            (self.inner_energy(fr, &base, &ev), slope)
                        });
                        let fall = -1e-4 * alpha * slope;
                        fall > 1e-12 * e0.abs() && self.inner_energy(fr, z, &trial) <= e0 - fall
                    };
                energy_merit |= alpha < 0.0625;
                if accepted {
                    stalled = 0;
                    damping = 0.0;
                    ev = trial;
                    break;
                }
                if alpha < 1e-4 && res > 1e-6 * scale && res > 0.5 * ev.roundoff && damping < 1e8 {
                    // No descent along this step, above the round-off floor of the contact
                    // forces: damp it and try again from the same state.
                    damping = if damping == 0.0 { 1e-3 } else { 10.0 * damping };
                    z[..n].copy_from_slice(&base);
                    break;
                }
                if res <= 1e-6 * scale || res <= 0.5 * ev.roundoff || alpha < 1e-4 {
                    // At the round-off floor (or lost): keep the better of the two states.
                    stalled += 1;
                    if mt < m0 {
                        ev = trial;
                    } else {
                        z[..n].copy_from_slice(&base);
                    }
                    break;
                }
                alpha *= 0.5;
            }
        }
        Err(self.fail(
            fr.phi,
            "the bearing equilibrium did not converge in 100 Newton steps",
        ))
    }

    /// The elastic energy's minimum along the inner step `step` (the coordinates `2..n` of
    /// `z`, evaluated as `ev`): the root of the energy's slope along the step,
    /// `s(a) = -g(z + a step) . step` (the generalised forces `g` are the energy's negative
    /// gradient), bracketed by `s(0) < 0` and the first of `a = 1, 1/2, 1/4, ...` whose
    /// evaluation succeeds, and found by the Illinois method to a thousandth of `s(0)`; the
    /// full step where the slope is still negative there. `z` is left at the point returned.
    /// `None` (with `z` unchanged) where the step is no descent direction or no trial point can
    /// be evaluated.
    pub(super) fn line_minimum(
        &self,
        fr: &Frame,
        z: &mut [f64],
        step: &DVector<f64>,
        memory: &mut [Vec<PinMemory>],
        ev: &Eval,
    ) -> Result<Option<Eval>> {
        let n = self.red.layout().dofs();
        let m = n - 2;
        let base: Vec<f64> = z[..n].to_vec();
        let slope = |g: &[f64]| -> f64 { -(0..m).map(|i| g[2 + i] * step[i]).sum::<f64>() };
        let s0 = slope(&ev.g);
        if s0.is_nan() || s0 >= 0.0 {
            return Ok(None);
        }
        let at = |z: &mut [f64], a: f64, memory: &mut [Vec<PinMemory>]| {
            for i in 0..m {
                z[2 + i] = base[2 + i] + a * step[i];
            }
            self.eval_bearings(fr, z, memory, true).ok()
        };
        // The far end of the bracket: the longest step of 1, 1/2, 1/4, ... that evaluates.
        let mut hi = 1.0;
        let far = loop {
            if let Some(e) = at(z, hi, memory) {
                break e;
            }
            hi *= 0.5;
            if hi < 1e-12 {
                z[..n].copy_from_slice(&base);
                return Ok(None);
            }
        };
        let mut s_hi = slope(&far.g);
        if s_hi <= 0.0 {
            return Ok(Some(far));
        }
        let (mut lo, mut s_lo) = (0.0, s0);
        // Which end moved last (the Illinois method halves the other end's slope when the
        // same end moves twice).
        let mut last_side = 0i8;
        let (mut best, mut best_a) = (far, hi);
        for _ in 0..60 {
            let a = hi - s_hi * (hi - lo) / (s_hi - s_lo);
            let a = if a > lo && a < hi { a } else { 0.5 * (lo + hi) };
            let Some(e) = at(z, a, memory) else {
                // Not evaluable there: the minimum is nearer.
                hi = a;
                continue;
            };
            let s = slope(&e.g);
            (best, best_a) = (e, a);
            if s.abs() <= 1e-3 * s0.abs() || hi - lo <= 1e-12 * hi {
                break;
            }
            if s < 0.0 {
                lo = a;
                s_lo = s;
                if last_side == -1 {
                    s_hi *= 0.5;
                }
                last_side = -1;
            } else {
                hi = a;
                s_hi = s;
                if last_side == 1 {
                    s_lo *= 0.5;
                }
                last_side = 1;
            }
        }
        for i in 0..m {
            z[2 + i] = base[2 + i] + best_a * step[i];
        }
        Ok(Some(best))
    }

    /// Potential energy (J) of the configuration `z` evaluated as `ev` without the output
    /// torque's: the elastic energy ([`StaticAnalysis::elastic_energy`]) less the work of the
    /// frame's applied forces, `- Q_a . z`. The merit of the inner solve's line search where the
    /// residual does not fall.
    pub(super) fn inner_energy(&self, fr: &Frame, z: &[f64], ev: &Eval) -> f64 {
        let n = self.red.layout().dofs();
        let applied: f64 = (0..n).map(|i| fr.applied[i] * z[i]).sum();
        self.elastic_energy(fr, z, ev) - applied
    }

    /// Elastic energy (J) of the configuration `z` evaluated as `ev`: the meshes' and the
    /// crank bearings' ([`crate::reducer::Reducer::structural_energy`]) plus each loaded
    /// contact's ([`crate::contact::PreparedLaw::energy_at_force`]).
    pub(super) fn elastic_energy(&self, fr: &Frame, z: &[f64], ev: &Eval) -> f64 {
        let n = self.red.layout().dofs();
        let contacts: f64 = ev
            .pins
            .iter()
            .flatten()
            .map(|p| self.contact_law.energy_at_force(p.force, p.curvature))
            .sum();
        self.red.structural_energy(&fr.q0[..n], &z[..n]) + contacts
    }

    /// Equilibrium under the output torque `torque` with every coordinate but the input free
    /// (torque control): the minimum of the potential energy `U - T psi` over all of them at
    /// once (docs/model.md section 5.3), from the locked-input mode at `psi0` plus the twist
    /// estimate or from a neighbouring solution. Newton's method with the tangent made
    /// positive definite (shifted by a multiple of its diagonal until its Cholesky
    /// factorisation exists) and a backtracking line search that accepts a step where the
    /// residual norm falls or where the potential falls by Armijo's rule; once a line search
    /// finds neither (or a trial cannot be evaluated), Levenberg-Marquardt's trust region for
    /// the rest of the solve (`StaticAnalysis::trust_region_step`). The potential's decrease
    /// is the forces' work along the step by the trapezoid rule, `(r(z) + r(z + s)) . s / 2`.
    /// The loaded solve of [`StaticAnalysis::solve`] (bearing support): `None` after
    /// `TORQUE_CONTROL_STEPS` steps, where the trust region finds no decrease above the point
    /// where a stalled solve is accepted, where an iterate is lost (`LOST_TWIST` beyond first
    /// contact) or where a cold start's inner equilibrium fails; the caller then applies the
    /// torque in load steps, each solved by this method from the one before.
    pub(super) fn torque_controlled(
        &self,
        fr: &Frame,
        torque: f64,
        start: &Start,
        z: &mut [f64],
        k_struct: &DMatrix<f64>,
        memory: &mut [Vec<PinMemory>],
    ) -> Result<Option<(Eval, DMatrix<f64>)>> {
        let n = self.red.layout().dofs();
        let m = n - 1;
        let rp = self.red.geometry.pin_circle_radius;
        let force_floor = torque.abs() / rp;
        let s = sense(torque);
        match start.near {
            // The neighbour's deviations, moved along the mode by the change of first contact
            // and, at another torque, along its twist direction by the first-order change of
            // the twist (the Euler predictor of path following).
            Some(near) => {
                let (mut a, mut b) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
                self.mode_deviation(fr, near.first_contact_twist, &mut a[..n]);
                self.mode_deviation(fr, start.psi0, &mut b[..n]);
                for i in 0..n {
                    z[i] = near.deviations[i] + b[i] - a[i];
                }
                let dt = torque - near.torque;
                if near.direction.len() == n && near.stiffness > 0.0 && dt * torque > 0.0 {
                    let dpsi = dt / near.stiffness;
                    for (zi, di) in z.iter_mut().zip(near.direction) {
                        *zi += di * dpsi;
                    }
                }
                z[Layout::SUN] = 0.0;
            }
            None => self.mode_deviation(fr, start.psi0 + s * self.twist_guess(torque), z),
        }
        // Residual of coordinate i (output torque included), and scaled: moments over the pin
        // circle radius.
        let residual = |g: &[f64; MAX_DOFS], i: usize| -> f64 {
            if i == Layout::OUT {
                g[i] + torque
            } else {
                g[i]
            }
        };
        let scaled = |g: &[f64; MAX_DOFS], i: usize| -> f64 {
            residual(g, i) / if is_angle(i) { rp } else { 1.0 }
        };
        let merit = |e: &Eval| -> f64 { (1..n).map(|i| scaled(&e.g, i).powi(2)).sum() };
        let mut ev = self.eval_bearings(fr, z, memory, true)?;
        if start.near.is_none() {
            // Cold: along the mode until its torque reaches the target (Newton then starts
            // from the stiff side, where its steps do not overshoot into new contacts).
            let mut x = self.twist_guess(torque);
            for _ in 0..20 {
                let mode_torque = self.mode_torque(fr, start.psi0 + s * x, &ev.g);
                if s * mode_torque >= torque.abs() || x > 0.5 * MAX_TWIST {
                    break;
                }
                x *= 2.0;
                self.mode_deviation(fr, start.psi0 + s * x, z);
                // A failed evaluation ends the method (the caller applies the load in steps).
                let Ok(next) = self.eval_bearings(fr, z, memory, true) else {
                    return Ok(None);
                };
                ev = next;
            }
            // Settled: the other coordinates in equilibrium at that twist (a strongly convex
            // problem; the rigid mode leaves them out of balance by about the force scale).
            if start.settle {
                match self.inner_solve(fr, z, k_struct, memory, force_floor) {
                    Ok((settled, _)) => ev = settled,
                    Err(_) => return Ok(None),
                }
            }
        }
        let mut kt: Option<DMatrix<f64>> = None;
        let mut last_res = f64::INFINITY;
        // Whether `kt` is the exact tangent (not the floored stand-in).
        let mut exact = true;
        // From a cold start no coordinate moves farther than `STEP_LIMIT_GUESSES` twist
        // estimates at the pin circle in the first step (its floored tangent far from the
        // equilibrium gave steps of metres), the bound doubling after each full step it cut;
        // from a neighbour, and at most, a quarter of the analysis' range.
        let widest = 0.25 * MAX_TWIST * rp;
        let mut limit = if start.near.is_none() {
            (STEP_LIMIT_GUESSES * self.twist_guess(torque) * rp).min(widest)
        } else {
            widest
        };
        // Where a solve whose steps no longer reduce the residual fourfold is accepted: the
        // forces' round-off floor, or a tenth of the check's tolerance.
        let stalled_at = |e: &Eval, scale: f64| -> f64 {
            (0.5 * e.roundoff).max(STALL_FRACTION * RESIDUAL_TOLERANCE * scale)
        };
        // Levenberg-Marquardt's trust region, once a line search has failed: the shift of
        // the tangent relative to its diagonal, kept from step to step.
        let mut trust: Option<f64> = None;
        for _ in 0..TORQUE_CONTROL_STEPS {
            let res = (1..n).map(|i| scaled(&ev.g, i).abs()).fold(0.0, f64::max);
            let scale = ev.scale.max(force_floor).max(1e-300);
            // Far from the equilibrium the bearings may be unloaded, where the rollers' tangent
            // stiffness vanishes and the exact Newton step overshoots: their stiffness is
            // floored until the residual is within a thousandth of the force scale.
            let floored = res > 1e-3 * scale;
            // A tangent is closed form per loaded pin, cheaper than an evaluation: it is rebuilt
            // at every step unless the residual fell a thousandfold.
            let fresh = kt.is_none() || res > 1e-3 * last_res || (exact == floored);
            if fresh {
                kt = Some(if floored {
                    self.tangent_floored(k_struct, &ev, fr, z)
                } else {
                    self.tangent(k_struct, &ev, fr, z)
                });
                exact = !floored;
            }
            last_res = res;
            if res <= CONVERGED_FRACTION * RESIDUAL_TOLERANCE * scale {
                let kt = match kt {
                    Some(kt) if fresh && exact => kt,
                    _ => self.tangent(k_struct, &ev, fr, z),
                };
                return Ok(Some((ev, kt)));
            }
            let kt = kt.as_ref().expect("tangent built above");
            let k = kt.view((1, 1), (m, m)).into_owned();
            let r = DVector::from_iterator(m, (1..n).map(|i| residual(&ev.g, i)));
            // The Newton step of the tangent made positive definite: shifted by `lambda` times
            // its diagonal, from none up by tenfold steps until its Cholesky factorisation
            // exists (an indefinite tangent, a disc on a ridge of a worn flank, gets no step
            // towards a saddle of the potential).
            let largest = (0..m).map(|i| k[(i, i)].abs()).fold(0.0, f64::max);
            let diag: Vec<f64> = (0..m)
                .map(|i| k[(i, i)].abs().max(1e-9 * largest))
                .collect();
            if let Some(lambda) = trust.as_mut() {
                match self
                    .trust_region_step(fr, z, memory, &k, &r, &diag, limit, lambda, &residual)?
                {
                    Some(trial) => {
                        let stalls = merit(&trial) > 0.25 * merit(&ev);
                        ev = trial;
                        if stalls && res <= stalled_at(&ev, scale) {
                            let kt = self.tangent(k_struct, &ev, fr, z);
                            return Ok(Some((ev, kt)));
                        }
                    }
                    None if res <= stalled_at(&ev, scale) => {
                        let kt = self.tangent(k_struct, &ev, fr, z);
                        return Ok(Some((ev, kt)));
                    }
                    None => return Ok(None),
                }
                if (z[Layout::OUT] - start.psi0).abs() > LOST_TWIST {
                    return Ok(None);
                }
                continue;
            }
            let mut lambda = 0.0_f64;
            let mut step = loop {
                if let Some(step) = shifted_step(&k, &diag, lambda, &r) {
                    break step;
                }
                lambda = if lambda == 0.0 { 1e-8 } else { 10.0 * lambda };
                if lambda > 1e8 {
                    return Ok(None);
                }
            };
            let bounded = self.bound_step(&mut step, limit);
            // The potential's slope along the step is `-r . s`; `r . s` is positive (the
            // shifted tangent is positive definite), so the step descends.
            let descent = r.dot(&step);
            let m0 = merit(&ev);
            let base: Vec<f64> = z[..n].to_vec();
            let mut alpha = 1.0;
            loop {
                for i in 0..m {
                    z[1 + i] = base[1 + i] + alpha * step[i];
                }
                let Ok(trial) = self.eval_bearings(fr, z, memory, true) else {
                    // A trial beyond the contact law's range: a shorter one, then the trust
                    // region from here on.
                    if alpha >= 1e-3 {
                        alpha *= 0.5;
                        continue;
                    }
                    z[..n].copy_from_slice(&base);
                    trust = Some(1e-4);
                    break;
                };
                let mt = merit(&trial);
                // Accepted where the residual falls, or where the potential falls by Armijo's
                // rule: its decrease, the forces' work along the step by the trapezoid rule,
                // at least 1e-4 of the slope's prediction.
                let residual_falls = mt <= m0 * (1.0 - 1e-4 * alpha);
                let energy_falls = residual_falls || {
                    let r1: f64 = (1..n).map(|i| residual(&trial.g, i) * step[i - 1]).sum();
                    0.5 * alpha * (descent + r1) >= 1e-4 * alpha * descent
                };
                if energy_falls {
                    // A full step that the bound cut: the bound doubles (a trust radius).
                    if bounded && alpha == 1.0 {
                        limit = (2.0 * limit).min(widest);
                    }
                    let stalls = mt > 0.25 * m0;
                    ev = trial;
                    // At the round-off floor of the contact forces a step barely reduces the
                    // residual: accept there.
                    if stalls && res <= stalled_at(&ev, scale) {
                        let kt = self.tangent(k_struct, &ev, fr, z);
                        return Ok(Some((ev, kt)));
                    }
                    break;
                }
                if alpha < 1e-3 {
                    // At the round-off floor of the contact forces the residual no longer
                    // falls: accept there (the caller's check applies the floor).
                    if res <= stalled_at(&ev, scale) {
                        let kt = self.tangent(k_struct, &ev, fr, z);
                        return Ok(Some((ev, kt)));
                    }
                    // No descent along Newton's direction: the trust region from here on.
                    z[..n].copy_from_slice(&base);
                    trust = Some(1e-4);
                    break;
                }
                alpha *= 0.5;
            }
            // An iterate this far beyond the analysis' range is lost.
            if (z[Layout::OUT] - start.psi0).abs() > LOST_TWIST {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// One step of Levenberg-Marquardt's trust region on the potential `U - T psi` (Moré 1978)
    /// from the deviations `z` (updated in place) with the tangent `k` over the coordinates
    /// `1..n`, its residual `r` and the diagonal scaling `diag`: the shift `lambda` (relative
    /// to `diag`, updated in place) rises until the shifted tangent is positive definite and
    /// its step, no coordinate moved more than `limit` (m at the pin circle), realises at least
    /// 1e-4 of the model's decrease `r . s - s K s / 2`; the decrease realised is the forces'
    /// work along the step by the trapezoid rule. The evaluation there, or `None` where the
    /// shift passes 1e12 (`z` then unchanged).
    ///
    /// # Errors
    /// None of its own (a failed evaluation raises the shift).
    #[allow(clippy::too_many_arguments)]
    fn trust_region_step(
        &self,
        fr: &Frame,
        z: &mut [f64],
        memory: &mut [Vec<PinMemory>],
        k: &DMatrix<f64>,
        r: &DVector<f64>,
        diag: &[f64],
        limit: f64,
        lambda: &mut f64,
        residual: &dyn Fn(&[f64; MAX_DOFS], usize) -> f64,
    ) -> Result<Option<Eval>> {
        let n = self.red.layout().dofs();
        let m = n - 1;
        let base: Vec<f64> = z[..n].to_vec();
        while *lambda <= 1e12 {
            let Some(mut step) = shifted_step(k, diag, *lambda, r) else {
                *lambda = (4.0 * *lambda).max(1e-6);
                continue;
            };
            self.bound_step(&mut step, limit);
            let predicted = r.dot(&step) - 0.5 * step.dot(&(k * &step));
            for i in 0..m {
                z[1 + i] = base[1 + i] + step[i];
            }
            let Ok(trial) = self.eval_bearings(fr, z, memory, true) else {
                z[..n].copy_from_slice(&base);
                *lambda = (8.0 * *lambda).max(1e-4);
                continue;
            };
            // The forces' work along the step: near the solution the difference of two
            // energies is below their round-off, and farther out the sum of the elements'
            // energies (`StaticAnalysis::inner_energy`) departed from it by 1e-10 J on steps of
            // 5e-10 J (Monte Carlo samples of the example at the rated torque).
            let r1: f64 = (1..n).map(|i| residual(&trial.g, i) * step[i - 1]).sum();
            let actual = 0.5 * (r.dot(&step) + r1);
            let rho = if predicted > 0.0 {
                actual / predicted
            } else {
                -1.0
            };
            if rho > 1e-4 {
                *lambda = if rho > 0.75 {
                    0.25 * *lambda
                } else if rho < 0.25 {
                    (4.0 * *lambda).max(1e-4)
                } else {
                    *lambda
                };
                return Ok(Some(trial));
            }
            z[..n].copy_from_slice(&base);
            *lambda = (8.0 * *lambda).max(1e-4);
        }
        Ok(None)
    }

    /// Scales the step `step` of the coordinates `1..n` (m and rad) so that no coordinate moves
    /// farther than `limit` (m; angles at the pin circle), keeping its direction.
    fn bound_step(&self, step: &mut DVector<f64>, limit: f64) -> bool {
        let rp = self.red.geometry.pin_circle_radius;
        let longest = (0..step.len())
            .map(|i| step[i].abs() * if is_angle(1 + i) { rp } else { 1.0 })
            .fold(0.0, f64::max);
        if longest > limit {
            *step *= limit / longest;
            true
        } else {
            false
        }
    }

    /// Output torque (N m) that balances the generalised forces `g` along the locked-input mode
    /// at twist `psi`: `-sum_i g_i dz_i/dpsi` (the mode's virtual work; its tangent by a
    /// central difference of [`StaticAnalysis::mode_deviation`]).
    pub(super) fn mode_torque(&self, fr: &Frame, psi: f64, g: &[f64; MAX_DOFS]) -> f64 {
        let n = self.red.layout().dofs();
        let h = 1e-6;
        let (mut a, mut b) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
        self.mode_deviation(fr, psi - h, &mut a[..n]);
        self.mode_deviation(fr, psi + h, &mut b[..n]);
        -(0..n)
            .map(|i| g[i] * (b[i] - a[i]) / (2.0 * h))
            .sum::<f64>()
    }

    /// `dz/dpsi` of the inner coordinates at fixed inner forces: `-K_ii^-1 K_io` (zero for the
    /// input and output entries).
    pub(super) fn condensation_direction(&self, kt: &DMatrix<f64>) -> Vec<f64> {
        let n = self.red.layout().dofs();
        let m = n - 2;
        let o = Layout::OUT;
        let kii = kt.view((2, 2), (m, m)).into_owned();
        let kio = DVector::from_iterator(m, (2..n).map(|i| kt[(i, o)]));
        let mut out = vec![0.0; n];
        if let Some(x) = kii.lu().solve(&kio) {
            for i in 0..m {
                out[2 + i] = -x[i];
            }
        }
        out
    }

    /// Condensed torsional stiffness `K_oo - K_oi K_ii^-1 K_io` (N m/rad) with the condensation
    /// direction `dz` ([`StaticAnalysis::condensation_direction`]) already known.
    pub(super) fn condensed_along(&self, kt: &DMatrix<f64>, dz: &[f64]) -> f64 {
        let n = self.red.layout().dofs();
        let o = Layout::OUT;
        kt[(o, o)] + (2..n).map(|i| kt[(o, i)] * dz[i]).sum::<f64>()
    }
}

/// The step `(K + lambda D)^-1 r` of the tangent `k` shifted by `lambda` times the diagonal
/// `diag` (`D`), by Cholesky's factorisation; `None` where the shifted tangent is not positive
/// definite.
fn shifted_step(
    k: &DMatrix<f64>,
    diag: &[f64],
    lambda: f64,
    r: &DVector<f64>,
) -> Option<DVector<f64>> {
    let mut a = k.clone();
    for (i, d) in diag.iter().enumerate() {
        a[(i, i)] += lambda * d;
    }
    a.cholesky().map(|chol| chol.solve(r))
}
