//! The work budget: the computing a config needs is estimated before the work starts, in
//! static contact solves, and a config whose estimate exceeds the budget is refused naming the
//! key that drives it, with the estimate.
//!
//! Unit costs were measured on the reference machine (2 cores, release build, the built-in
//! example; `cargo bench -p rvlife --bench study`): one static solve [`SOLVE_SECONDS`], the
//! set-up of the static analysis of one profile (its gap field) [`SETUP_SOLVES`] solves, the
//! rest of a wear-rate evaluation [`RATE_SOLVES`] solves. The
//! estimate counts one core, so it errs long. The default budget is [`DEFAULT_MINUTES`]
//! minutes; `--work-budget-min` changes it.
//!
//! - Before the work ([`check_config`]): wear-rate evaluations (`last stage /
//!   wear.profile_update_hours`) x (load levels x (`wear.crank_steps_per_mesh_cycle` +
//!   set-up) + the rest of an evaluation),
//!   plus stages x (`te.samples_per_mesh_cycle` x the hysteresis and loaded-TE torques +
//!   set-up).
//! - After the first wear rate ([`check_wear_updates`]): the profile updates that
//!   `wear.max_wear_step_um` asks for at the largest wear rate found,
//!   `last stage x max rate / max_wear_step`.

use crate::config::{Model, WearModelKind};
use crate::error::{Error, Result};
use crate::study::HYSTERESIS_LEVELS;

/// Seconds of one static contact solve of the example on the reference machine.
pub const SOLVE_SECONDS: f64 = 0.22e-3;

/// Cost of setting up the static analysis of one profile (its gap field), in static solves
/// (1.4 ms measured).
pub const SETUP_SOLVES: f64 = 7.0;

/// Fixed cost of one wear-rate evaluation besides its contact solves (the worn profile, the
/// band filter, the spreading of the wear over the contact bands), in static solves: the
/// example measured 11.7 ms per evaluation with one load level (1987 evaluations in 23.4 s).
pub const RATE_SOLVES: f64 = 28.0;

/// Default work budget, minutes.
pub const DEFAULT_MINUTES: f64 = 10.0;

/// [`DEFAULT_MINUTES`] (the serde default of [`crate::config::Config::work_budget_minutes`]).
pub fn default_minutes() -> f64 {
    DEFAULT_MINUTES
}

/// The budget of `minutes` in static solves.
pub fn solves_in_minutes(minutes: f64) -> f64 {
    minutes * 60.0 / SOLVE_SECONDS
}

fn minutes(solves: f64) -> f64 {
    solves * SOLVE_SECONDS / 60.0
}

/// Static solves of one wear-rate evaluation.
fn per_rate_evaluation(model: &Model) -> f64 {
    match model.wear_model {
        // Li's closed form: no contact solves.
        WearModelKind::Paper => 1.0,
        WearModelKind::Flodin => {
            RATE_SOLVES + model.spectrum.len() as f64 * (SETUP_SOLVES + model.wear_steps as f64)
        }
    }
}

/// Static solves of the analyses of all stages.
fn stage_work(model: &Model) -> f64 {
    let per_angle = 4.0 * (HYSTERESIS_LEVELS as f64 + 1.0) + 1.0;
    model.stage_hours.len() as f64 * (SETUP_SOLVES + model.te_samples as f64 * per_angle)
}

/// Wear-rate evaluations the profile-update step asks for.
fn scheduled_updates(model: &Model) -> f64 {
    let last = model.stage_hours.last().copied().unwrap_or(0.0);
    if model.wear_model == WearModelKind::Paper || model.update_hours <= 0.0 {
        1.0
    } else {
        (last / model.update_hours).ceil().max(1.0)
    }
}

/// Checks the work of `model` before it starts (see the module docs). `levels_key` names the
/// key that sets the number of load levels (`load.levels`, `load.file`).
///
/// # Errors
/// [`Error::Invalid`] naming the key whose value is furthest above the example's, with the
/// estimate and the budget.
pub(crate) fn check_config(model: &Model, levels_key: &str) -> Result<()> {
    let updates = scheduled_updates(model);
    let wear = updates * per_rate_evaluation(model);
    let stages = stage_work(model);
    let total = wear + stages;
    if total <= model.work_budget {
        return Ok(());
    }
    // The factor furthest above the example's value drives it.
    let levels = model.spectrum.len() as f64;
    let candidates = [
        (
            levels_key.to_string(),
            format!("{levels} levels"),
            levels / 24.0,
        ),
        (
            "wear.profile_update_hours".to_string(),
            format!("{}", model.update_hours),
            updates / 30.0,
        ),
        (
            "wear.crank_steps_per_mesh_cycle".to_string(),
            model.wear_steps.to_string(),
            model.wear_steps as f64 / 18.0,
        ),
        (
            "wear.stage_hours".to_string(),
            format!("{} stages", model.stage_hours.len()),
            model.stage_hours.len() as f64 / 7.0,
        ),
        (
            "te.samples_per_mesh_cycle".to_string(),
            model.te_samples.to_string(),
            model.te_samples as f64 / 24.0,
        ),
    ];
    let (key, value, _) = candidates
        .iter()
        .fold(&candidates[0], |a, b| if b.2 > a.2 { b } else { a });
    Err(Error::invalid(
        key.as_str(),
        value,
        format!(
            "the study would need about {total:.2e} contact solves (~{:.0} min: {updates} \
             wear-rate evaluations x {levels} load levels x {} crank steps, {} stages x {} TE \
             samples), more than the work budget of {:.0} min (--work-budget-min); lower it",
            minutes(total),
            model.wear_steps,
            model.stage_hours.len(),
            model.te_samples,
            minutes(model.work_budget),
        ),
    ))
}

/// Checks, once the largest wear rate `max_rate` (m/h) of the unworn profile is known, the
/// profile updates that `wear.max_wear_step_um` asks for over `horizon` hours.
///
/// # Errors
/// [`Error::Invalid`] naming `wear.max_wear_step_um` if it is below its default of 1 um,
/// otherwise the Archard coefficient key, with the estimate and the budget.
pub(crate) fn check_wear_updates(model: &Model, horizon: f64, max_rate: f64) -> Result<()> {
    if model.wear_model == WearModelKind::Paper || model.update_hours <= 0.0 {
        return Ok(());
    }
    let updates = (horizon * max_rate / model.max_wear_step)
        .ceil()
        .max(scheduled_updates(model));
    let total = updates * per_rate_evaluation(model) + stage_work(model);
    if total <= model.work_budget {
        return Ok(());
    }
    let (key, value) = if model.max_wear_step < 0.999e-6 {
        (
            "wear.max_wear_step_um".to_string(),
            format!("{}", model.max_wear_step * 1e6),
        )
    } else if model.archard_key.ends_with("m2_per_n") {
        (
            model.archard_key.to_string(),
            format!("{:.4e}", model.archard),
        )
    } else {
        (
            model.archard_key.to_string(),
            format!("{:.4e}", model.archard * 1e9),
        )
    };
    Err(Error::invalid(
        key,
        value,
        format!(
            "the largest wear rate, {:.3e} um/h on the unworn disc, needs about {updates:.2e} \
             profile updates of at most wear.max_wear_step_um = {} um over {horizon} h: about \
             {total:.2e} contact solves (~{:.0} min), more than the work budget of {:.0} min \
             (--work-budget-min)",
            max_rate * 1e6,
            model.max_wear_step * 1e6,
            minutes(total),
            minutes(model.work_budget),
        ),
    ))
}

/// Static solves of one Monte Carlo sample at one working-hour point: the revolution TE's
/// touching pins and the hysteresis at the measuring and rated torque, both directions, at
/// `per_cycle` crank angles (1 000 samples of the example, 7 stages, 4 crank angles: estimated
/// 2.1 min, measured 1.0 min wall on 2 cores).
pub const MONTE_CARLO_SOLVES_PER_ANGLE: f64 = 20.0;

/// Checks the work of a Monte Carlo run of `samples` samples (this shard's) before it starts:
/// `samples x points x per_cycle x` [`MONTE_CARLO_SOLVES_PER_ANGLE`], `points` the stages and
/// half the points beyond them where the life is looked for; with `full_wear` each sample
/// also integrates its own wear (the study's wear work, times the 8 mesh cycles of a reducer
/// with errors, times `horizon`, the hours integrated over the last stage's).
///
/// # Errors
/// [`Error::Invalid`] naming `--samples` with the estimate and the budget.
pub fn check_montecarlo(
    model: &Model,
    samples: usize,
    points: usize,
    per_cycle: usize,
    full_wear: bool,
    horizon: f64,
) -> Result<()> {
    let mut per_sample = points as f64 * per_cycle as f64 * MONTE_CARLO_SOLVES_PER_ANGLE;
    if full_wear {
        per_sample +=
            8.0 * horizon.max(1.0) * scheduled_updates(model) * per_rate_evaluation(model);
    }
    let total = samples as f64 * per_sample;
    if total <= model.work_budget {
        return Ok(());
    }
    Err(Error::invalid(
        "--samples",
        samples,
        format!(
            "the estimated work, {:.1} min ({} samples x {:.0} solves), exceeds the work \
             budget of {:.1} min: fewer samples, --shard I/N across machines, or a larger \
             --work-budget-min",
            minutes(total),
            samples,
            per_sample,
            minutes(model.work_budget)
        ),
    ))
}
