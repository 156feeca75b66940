//! Time integration behind a small trait, so that the ODE crate can be swapped.
//!
//! [`Tsit45`] is the explicit Runge-Kutta 5(4) pair of Tsitouras (Comput. Math. Appl. 62, 2011)
//! with PI step-size control and dense output, from the `diffsol` crate.

use std::cell::Cell;

use diffsol::{NalgebraMat, OdeBuilder, OdeSolverMethod, OdeSolverStopReason};

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
}

/// Integration counters.
#[derive(Debug, Clone, Copy, Default)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: usize,
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
pub const MAX_STEPS: usize = 4_500_000;

/// Tsitouras 5(4) from `diffsol` with relative tolerance `rtol`.

#[derive(Debug, Clone, Copy)]
pub struct Tsit45 {
    /// Relative tolerance.
    pub rtol: f64,
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
        let mut solver = problem.tsit45().map_err(fail)?;
        solver.set_stop_time(t_end).map_err(fail)?;
        let mut next = 0;
        let mut steps = 0;
        let mut buf = vec![0.0; n];
        // Samples at t = 0.
        while next < times.len() && times[next] <= 0.0 {
            buf.copy_from_slice(solver.state().y.batch_as_slice(0));
            sample(times[next], &buf)?;
            next += 1;
        }
        loop {
            let reason = solver.step().map_err(fail)?;
            steps += 1;
            let t_now = solver.state().t;
            while next < times.len() && times[next] <= t_now {
                let y = solver.interpolate(times[next]).map_err(fail)?;
                buf.copy_from_slice(y.batch_as_slice(0));
                sample(times[next], &buf)?;
                next += 1;
            }
            if matches!(reason, OdeSolverStopReason::TstopReached) || t_now >= t_end {
                break;
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
        Ok(Stats {
            steps,
            rhs_evaluations: evals.get(),
        })
    }
}

/// Integrates with [`Tsit45`] at tolerance `rtol` (see [`Integrator::integrate`]).
///
/// # Errors
/// As [`Integrator::integrate`].
pub fn integrate(
    sys: &dyn OdeSystem,
    rtol: f64,
    t_end: f64,
    times: &[f64],
    mut sample: impl FnMut(f64, &[f64]) -> Result<()>,
) -> Result<Stats> {
    Tsit45 { rtol }.integrate(sys, t_end, times, &mut sample)
}
