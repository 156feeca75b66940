//! Time integration behind a small trait, so that the ODE crate can be swapped.
//!
//! [`Tsit45`] is the explicit Runge-Kutta 5(4) pair of Tsitouras (Comput. Math. Appl. 62, 2011)
//! with PI step-size control and dense output, from the `diffsol` crate. Its steps are bounded
//! by stability: the contact modes (10-15 kHz) and, with flexible discs, the highest elastic
//! mode kept.
//!
//! [`Esdirk34`] is the L-stable singly diagonally implicit Runge-Kutta 3(4) pair ESDIRK34
//! (Kennedy and Carpenter, NASA/TM-2016-219173; the `diffsol` tableau) with a Newton iteration
//! on each stage and a dense LU of the Newton matrix. Its steps are set by accuracy, not by the
//! stiff modes. The Jacobian is a forward finite difference of the right-hand side, one column
//! per state, step `sqrt(eps)` times each state's scale (its magnitude or its absolute
//! tolerance over the relative tolerance); `diffsol` re-evaluates it when the step size changes
//! or every 50 steps. Its sparsity is used: each column is [`OdeSystem::rhs_column`], which a
//! system may evaluate on the terms its state enters only (the reducer recomputes the pin
//! contacts of the disc that the state moves and reuses the other's from the base point: with
//! rigid discs 14 of the 28 columns recompute no contact and 12 one disc's; with flexible
//! discs of 8 modes 44 of the 60 recompute one disc's).

use std::cell::{Cell, RefCell};

use diffsol::{NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod, OdeSolverStopReason};

use crate::error::{Error, Result};

/// A first-order ODE system `dy/dt = f(t, y)`.
pub trait OdeSystem {
    /// Number of states.
    fn states(&self) -> usize;
    /// Initial state at `t = 0`.
    fn initial(&self) -> Vec<f64>;
    /// Right-hand side `dy = f(t, y)`.
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]);
    /// Absolute tolerances per state for relative tolerance `rtol`.
    fn absolute_tolerances(&self, rtol: f64) -> Vec<f64>;
    /// The right-hand side at the base point of a finite-difference Jacobian; a system may
    /// keep parts of it for [`OdeSystem::rhs_column`]. Default: [`OdeSystem::rhs`].
    fn rhs_base(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.rhs(t, y, dy);
    }
    /// The right-hand side at `y`, which differs from the point of the last
    /// [`OdeSystem::rhs_base`] in state `j` only (at the same `t`): a system may recompute
    /// only the terms that state `j` enters (the sparsity of its Jacobian). It must equal
    /// [`OdeSystem::rhs`] to rounding. Default: [`OdeSystem::rhs`].
    fn rhs_column(&self, t: f64, y: &[f64], j: usize, dy: &mut [f64]) {
        let _ = j;
        self.rhs(t, y, dy);
    }
}

/// Integration counters.
#[derive(Debug, Clone, Copy, Default)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Full right-hand-side evaluations.
    pub rhs_evaluations: usize,
    /// Finite-difference Jacobian columns evaluated by [`OdeSystem::rhs_column`] (implicit
    /// methods).
    pub jacobian_columns: usize,
}

/// An integrator with error control and dense output.
pub trait Integrator {
    /// Integrates `sys` from 0 to `t_end` (s) and calls `sample(t, y)` at every time of `times`
    /// (increasing, within `[0, t_end]`) with the interpolated state.
    ///
    /// # Errors
    /// [`Error::Numerical`] if the integrator fails; any error of `sample` stops it.
    fn integrate(
        &self,
        sys: &dyn OdeSystem,
        t_end: f64,
        times: &[f64],
        sample: &mut dyn FnMut(f64, &[f64]) -> Result<()>,
    ) -> Result<Stats>;
}

/// Largest number of integrator steps of one simulation: about ten minutes at the example's
/// 0.13 ms per step on the reference machine (the default work budget, [`crate::budget`]).
/// The example takes 25 000.
pub(crate) const MAX_STEPS: usize = 4_500_000;

/// Tsitouras 5(4) from `diffsol` with relative tolerance `rtol`.

#[derive(Debug, Clone, Copy)]
pub struct Tsit45 {
    /// Relative tolerance.
    pub rtol: f64,
    /// End a step at every sample time (instead of sampling the dense output).
    pub exact_samples: bool,
}

impl Integrator for Tsit45 {
    fn integrate(
        &self,
        sys: &dyn OdeSystem,
        t_end: f64,
        times: &[f64],
        sample: &mut dyn FnMut(f64, &[f64]) -> Result<()>,
    ) -> Result<Stats> {
        let n = sys.states();
        let y0 = sys.initial();
        let evals = Cell::new(0usize);
        let fail = |e: diffsol::error::DiffsolError| Error::numerical("dynamics", e.to_string());
        let problem = OdeBuilder::<NalgebraMat<f64>>::new()
            .rtol(self.rtol)
            .atol(sys.absolute_tolerances(self.rtol))
            .h0(1e-7)
            .rhs(|y: &[f64], _p: &[f64], t: f64, dy: &mut [f64]| {
                evals.set(evals.get() + 1);
                sys.rhs(t, y, dy);
            })
            .init(
                |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
                n,
            )
            .build()
            .map_err(fail)?;
        let solver = problem.tsit45().map_err(fail)?;
        let steps = drive(solver, self.exact_samples, t_end, times, sample)?;
        Ok(Stats {
            steps,
            rhs_evaluations: evals.get(),
            ..Stats::default()
        })
    }
}

/// Steps `solver` to `t_end` and samples the state at `times`: the dense output, or (`exact`)
/// the state of a step ended at each sample time. Returns the step count.
fn drive<'a, Eqn, S>(
    mut solver: S,
    exact: bool,
    t_end: f64,
    times: &[f64],
    sample: &mut dyn FnMut(f64, &[f64]) -> Result<()>,
) -> Result<usize>
where
    Eqn: diffsol::OdeEquations<T = f64, V = diffsol::NalgebraVec<f64>> + 'a,
    S: OdeSolverMethod<'a, Eqn>,
{
    let fail = |e: diffsol::error::DiffsolError| Error::numerical("dynamics", e.to_string());
    let n = diffsol::Vector::len(solver.state().y);
    let target = |next: usize| times.get(next).map_or(t_end, |t| t.min(t_end));
    let mut next = 0;
    let mut steps = 0;
    let mut buf = vec![0.0; n];
    // Samples at t = 0.
    while next < times.len() && times[next] <= 0.0 {
        buf.copy_from_slice(solver.state().y.batch_as_slice(0));
        sample(times[next], &buf)?;
        next += 1;
    }
    solver
        .set_stop_time(if exact { target(next) } else { t_end })
        .map_err(fail)?;
    loop {
        let reason = solver.step().map_err(fail)?;
        steps += 1;
        let t_now = solver.state().t;
        let stopped = matches!(reason, OdeSolverStopReason::TstopReached);
        if exact {
            if stopped {
                // The solver reaches a stop time to within rounding.
                let reached = t_now + 1e-12 * t_end;
                while next < times.len() && target(next) <= reached {
                    buf.copy_from_slice(solver.state().y.batch_as_slice(0));
                    sample(times[next], &buf)?;
                    next += 1;
                }
                if reached >= t_end {
                    break;
                }
                solver.set_stop_time(target(next)).map_err(fail)?;
            }
        } else {
            while next < times.len() && times[next] <= t_now {
                let y = solver.interpolate(times[next]).map_err(fail)?;
                buf.copy_from_slice(y.batch_as_slice(0));
                sample(times[next], &buf)?;
                next += 1;
            }
            if stopped || t_now >= t_end {
                break;
            }
        }
        // The work budget: extrapolated from the steps so far, checked early and then
        // every 10 000 steps (so that a simulation that cannot finish in budget stops at
        // once rather than at the end).
        if steps % 10_000 == 0 && t_now > 0.0 {
            let estimate = steps as f64 * t_end / t_now;
            if estimate > MAX_STEPS as f64 {
                return Err(Error::invalid(
                    "dynamics.end_time_s",
                    t_end,
                    format!(
                        "the simulation would need about {estimate:.2e} integrator steps \
                             ({steps} steps reached t = {t_now:.3e} s), more than the work budget \
                             of {MAX_STEPS} steps (about 10 min); shorten the simulated time, \
                             or check the loads and stiffnesses that make the steps short"
                    ),
                ));
            }
        }
    }
    Ok(steps)
}

/// ESDIRK34 from `diffsol` with relative tolerance `rtol` and a finite-difference Jacobian.
#[derive(Debug, Clone, Copy)]
pub struct Esdirk34 {
    /// Relative tolerance.
    pub rtol: f64,
    /// End a step at every sample time (instead of sampling the dense output, a cubic Hermite
    /// interpolant whose error between steps exceeds the step error: pin forces sampled from
    /// it at the default tolerance differ by up to 3 % of the largest force).
    pub exact_samples: bool,
}

impl Integrator for Esdirk34 {
    fn integrate(
        &self,
        sys: &dyn OdeSystem,
        t_end: f64,
        times: &[f64],
        sample: &mut dyn FnMut(f64, &[f64]) -> Result<()>,
    ) -> Result<Stats> {
        let n = sys.states();
        let y0 = sys.initial();
        let atol = sys.absolute_tolerances(self.rtol);
        let scale: Vec<f64> = atol.iter().map(|a| a / self.rtol).collect();
        let evals = Cell::new(0usize);
        let columns = Cell::new(0usize);
        // f at the last point the Jacobian was taken at, so that its n columns cost n + 1
        // right-hand sides.
        let base: RefCell<(f64, Vec<f64>, Vec<f64>)> =
            RefCell::new((f64::NAN, vec![f64::NAN; n], vec![0.0; n]));
        let work = RefCell::new((vec![0.0; n], vec![0.0; n]));
        let fail = |e: diffsol::error::DiffsolError| Error::numerical("dynamics", e.to_string());
        let rhs = |y: &[f64], _p: &[f64], t: f64, dy: &mut [f64]| {
            evals.set(evals.get() + 1);
            sys.rhs(t, y, dy);
        };
        let jac = |x: &[f64], _p: &[f64], t: f64, v: &[f64], jv: &mut [f64]| {
            let mut b = base.borrow_mut();
            if b.0 != t || b.1 != x {
                b.0 = t;
                b.1.copy_from_slice(x);
                evals.set(evals.get() + 1);
                sys.rhs_base(t, x, &mut b.2);
            }
            // diffsol builds the dense Jacobian one unit column at a time.
            let mut nonzero = v.iter().enumerate().filter(|(_, vi)| **vi != 0.0);
            let column = match (nonzero.next(), nonzero.next()) {
                (Some((j, _)), None) => Some(j),
                _ => None,
            };
            let ratio = v
                .iter()
                .zip(x)
                .zip(&scale)
                .map(|((vi, xi), s)| vi.abs() / xi.abs().max(*s))
                .fold(0.0, f64::max);
            if ratio == 0.0 {
                jv.fill(0.0);
                return;
            }
            let h = f64::EPSILON.sqrt() / ratio;
            let mut w = work.borrow_mut();
            let (xp, fp) = &mut *w;
            for ((a, xi), vi) in xp.iter_mut().zip(x).zip(v) {
                *a = xi + h * vi;
            }
            match column {
                Some(j) => {
                    columns.set(columns.get() + 1);
                    sys.rhs_column(t, xp, j, fp);
                }
                None => {
                    evals.set(evals.get() + 1);
                    sys.rhs(t, xp, fp);
                }
            }
            for ((o, f1), f0) in jv.iter_mut().zip(fp.iter()).zip(&b.2) {
                *o = (f1 - f0) / h;
            }
        };
        let mut problem = OdeBuilder::<NalgebraMat<f64>>::new()
            .rtol(self.rtol)
            .atol(atol.clone())
            .h0(1e-7)
            .rhs_implicit(rhs, jac)
            .init(
                |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
                n,
            )
            .build()
            .map_err(fail)?;
        // diffsol counts Newton failures over the whole run (each is followed by a Jacobian
        // update or a step cut); contact onsets cause a few every mesh cycle. The step-size
        // floor and the work budget are what stop a run that cannot proceed.
        problem.ode_options.max_nonlinear_solver_failures = usize::MAX / 2;
        let solver = problem.esdirk34::<NalgebraLU<f64>>().map_err(fail)?;
        let steps = drive(solver, self.exact_samples, t_end, times, sample)?;
        Ok(Stats {
            steps,
            rhs_evaluations: evals.get(),
            jacobian_columns: columns.get(),
        })
    }
}

/// Integrates with `method` at tolerance `rtol` (see [`Integrator::integrate`]), sampling the
/// dense output, or (`exact_samples`) ending a step at every sample time.
///
/// # Errors
/// As [`Integrator::integrate`].
pub fn integrate(
    sys: &dyn OdeSystem,
    method: super::params::Method,
    rtol: f64,
    exact_samples: bool,
    t_end: f64,
    times: &[f64],
    mut sample: impl FnMut(f64, &[f64]) -> Result<()>,
) -> Result<Stats> {
    match method {
        super::params::Method::Tsit45 => Tsit45 {
            rtol,
            exact_samples,
        }
        .integrate(sys, t_end, times, &mut sample),
        super::params::Method::Esdirk34 => Esdirk34 {
            rtol,
            exact_samples,
        }
        .integrate(sys, t_end, times, &mut sample),
    }
}
