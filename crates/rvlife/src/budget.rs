//! The work budget's cost model: the computing a run needs is estimated before the work starts,
//! in static contact solves, and a run whose estimate exceeds the budget is refused naming the
//! key that drives it, with the estimate (docs/model.md section 15). The estimates themselves
//! are made by whoever runs the work: the study (`crate::study::check_work`, called by
//! [`crate::api::validated`]), the wear integration (the profile updates its wear rate asks
//! for) and Monte Carlo (`crate::montecarlo::check_work`).
//!
//! Unit costs were measured on the reference machine (2 cores, release build, the built-in
//! example; `cargo bench -p rvlife --bench study`): one static solve `SOLVE_SECONDS`, the
//! set-up of the static analysis of one profile (its gap field) `SETUP_SOLVES` solves, the
//! rest of a wear-rate evaluation `RATE_SOLVES` solves. The estimate counts one core, so it
//! errs long. The default budget is [`DEFAULT_MINUTES`] minutes; `--work-budget-min` changes
//! it.

use crate::te::{torque_fractions, HYSTERESIS_LEVELS};

/// Seconds of one static contact solve of the example on the reference machine.
pub(crate) const SOLVE_SECONDS: f64 = 0.22e-3;

/// Cost of setting up the static analysis of one profile (its gap field), in static solves
/// (1.4 ms measured).
pub(crate) const SETUP_SOLVES: f64 = 7.0;

/// Fixed cost of one wear-rate evaluation besides its contact solves (the worn profile, the
/// band filter, the spreading of the wear over the contact bands), in static solves: the
/// example measured 11.7 ms per evaluation with one load level (1987 evaluations in 23.4 s).
pub(crate) const RATE_SOLVES: f64 = 28.0;

/// Default work budget, minutes.
pub const DEFAULT_MINUTES: f64 = 10.0;

/// Smallest work budget, minutes (6 s): below it no analysis of a reducer fits, and a refusal
/// would blame the config's keys for the budget's value.
pub const MIN_MINUTES: f64 = 0.1;

/// Static solves of one Monte Carlo sample at one working-hour point: the revolution TE's
/// touching pins and the hysteresis at the measuring and rated torque, both directions, at
/// each crank angle, with the bearings' play and the life's bracket beyond the stages (100
/// samples of the example, 7 stages and 3 points beyond, 4 crank angles: 68.8 s of one core's
/// computing, 34.9 s wall on 2 cores, with the nominal wear's 1.5 s; estimated 1.1 min).
pub(crate) const MONTE_CARLO_SOLVES_PER_ANGLE: f64 = 75.0;

/// [`DEFAULT_MINUTES`] (the serde default of [`crate::config::Config::work_budget_minutes`]).
pub(crate) fn default_minutes() -> f64 {
    DEFAULT_MINUTES
}

/// The budget of `minutes` in static solves.
pub(crate) fn solves_in_minutes(minutes: f64) -> f64 {
    minutes * 60.0 / SOLVE_SECONDS
}

/// Minutes of `solves` static solves.
pub fn minutes(solves: f64) -> f64 {
    solves * SOLVE_SECONDS / 60.0
}

/// Static solves of the analyses of one stage: the set-up and, at each of `te_samples` crank
/// angles, the hysteresis curve (both senses, the study's grid [`torque_fractions`]) and the
/// loaded TE; with part `errors`, [`PART_ERROR_STAGE_FACTOR`] times that (the revolution STE,
/// the zero-torque angular TE and the no-load splits).
pub(crate) fn stage_solves(te_samples: usize, errors: bool) -> f64 {
    let solved = torque_fractions(0.03, HYSTERESIS_LEVELS, true).len() - 1;
    let per_angle = 4.0 * solved as f64 + 1.0;
    let nominal = SETUP_SOLVES + te_samples as f64 * per_angle;
    if errors {
        PART_ERROR_STAGE_FACTOR * nominal
    } else {
        nominal
    }
}

/// A stage's analyses with part errors against without: the example with `[errors]` of a
/// micrometre (a 3-stage study, no dynamics) measured 4 times the stage work besides the
/// wear's 8 mesh cycles (its whole study 5.8 times the nominal's).
pub(crate) const PART_ERROR_STAGE_FACTOR: f64 = 4.0;

/// Static solves of one wear-rate evaluation: `levels` load levels of `crank_steps` crank
/// angles each (the paper's wear model, Li's closed form: 1).
pub(crate) fn per_rate_evaluation(paper: bool, levels: usize, crank_steps: usize) -> f64 {
    if paper {
        1.0
    } else {
        RATE_SOLVES + levels as f64 * (SETUP_SOLVES + crank_steps as f64)
    }
}

/// Wear-rate evaluations the profile-update step `update_hours` (h) asks for up to `last`
/// hours (1 for the paper's wear model or without updates).
pub(crate) fn scheduled_updates(paper: bool, last: f64, update_hours: f64) -> f64 {
    if paper || update_hours <= 0.0 {
        1.0
    } else {
        (last / update_hours).ceil().max(1.0)
    }
}

/// A run's work budget and the cost of its stages' analyses besides the wear, in static
/// solves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// The budget, static solves.
    pub solves: f64,
    /// Static solves of one stage's analyses (`stage_solves`).
    pub per_stage: f64,
}
