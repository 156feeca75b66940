//! The accuracy-life study: wear over working hours, and at every stage the worn profile, the
//! static TE and lost motion, the loaded TE at the rated torque, and the contact loads.
//!
//! Pipeline: [`crate::wear::integrate`] gives the wear map at each stage; each stage's
//! profile is the modified profile with that map (or, in the paper's model, with a uniform
//! equidistant offset equal to the maximum wear, paper section 3.1); [`crate::te`] gives STE,
//! lost motion and loaded TE on it; with `[dynamics] enabled`, [`crate::dynamics::simulate`]
//! gives the dynamic TE of the whole reducer with it; with `[fem] enabled`,
//! [`crate::fem::flex::analyse_stage`] gives the flexible-disc TE, torsional stiffness and disc
//! stress on a plane-stress FE model of the worn disc.
//!
//! The study's pieces: [`Executor`] runs it (the schedule over the threads, after argmin's
//! executor) with its state (`state`) and the [`Observer`]s that hear it; `analyses` runs one
//! stage's analyses on a worker and `stage` is its static part; `results` holds the study and
//! its summary, `trials` searches the accuracy life between and beyond the stages, and
//! [`parts`] is the study in parts that the web page's workers assemble.

use crate::budget;
use crate::config::Model;
use crate::error::{Error, Result};
use crate::wear::WearHistory;

pub(crate) mod admission;
mod analyses;
mod executor;
mod observer;
pub mod parts;
mod results;
mod stage;
mod state;
mod trials;

pub use admission::SERIES_KEYS;
pub use executor::Executor;
pub use observer::{Notices, Observer, Progress};
pub use results::{PaperComparison, Study, Summary};
pub use stage::{ProfileAnalysis, Stage};
#[cfg(test)]
pub(crate) use {
    results::is_papers_reducer, stage::analyse_profile, trials::study_life, trials::LifeTrials,
};

/// The validated model of `cfg` ([`crate::config::Config::validate`]) whose study fits the
/// work budget ([`check_work`]) and whose unworn stage passes the physical checks
/// ([`admission::check_stage`], docs/model.md section 15.2): what every command and every
/// design of a sweep runs on. In that order: the sections' ranges, the budget (so that a
/// config too large is refused without a static analysis), the physical checks on the
/// checked sections, then the parts the analyses add (`Config::assemble`: the friction, the
/// FE disc's series compliance), so that a stage the checks refuse is refused by its key
/// before the FE disc is built on it.
///
/// # Errors
/// [`Error::Invalid`] naming the key, the value and the allowed range, or the key that drives
/// the work beyond the budget (a key the file does not set named as a default).
pub(crate) fn validated(cfg: &crate::config::Config) -> Result<Model> {
    admitted(cfg, budgeted(cfg)?)
}

/// The sections of `cfg` checked (`Config::validate_unassembled`) and its work against the
/// budget ([`check_work`]): the start of [`validated`], no static analysis.
///
/// # Errors
/// Those of the sections and of the work budget, keys named as the file writes them.
pub(crate) fn budgeted(cfg: &crate::config::Config) -> Result<Model> {
    let model = cfg.validate_unassembled()?;
    check_work(&model).map_err(|e| cfg.explain_default(e))?;
    Ok(model)
}

/// The model of `cfg` from [`budgeted`], through the physical checks of its unworn stage
/// ([`admission::check_stage`]) and assembled (`Config::assemble`): the end of [`validated`],
/// for a caller that checks the work of many configs before any static analysis (a sweep).
///
/// # Errors
/// Those of the physical checks and of the assembly, keys named as the file writes them.
pub(crate) fn admitted(cfg: &crate::config::Config, model: Model) -> Result<Model> {
    admission::check_stage(
        &model,
        &cfg.cycloid.modification,
        admission::Blame::Written(cfg),
    )
    .map_err(|e| cfg.explain_default(e))?;
    cfg.assemble(model)
}

/// The estimated work of a study of `model`, in static solves ([`crate::budget`]): `(wear
/// integration, stages' analyses)` ([`check_work`]).
pub(crate) fn study_work(model: &Model) -> (f64, f64) {
    let w = &model.wear;
    let positions = crate::wear::revolution_positions(&model.reducer);
    let wear = w.scheduled_updates() * w.rate_evaluation_solves(model.load.levels.len(), positions);
    let stages = w.stage_hours.len() as f64 * model.budget().per_stage;
    (wear, stages)
}

/// Checks the work of a study of `model` against its budget before it starts
/// ([`crate::budget`]): wear-rate evaluations (`last stage / wear.profile_update_hours`) x
/// (load levels x (`wear.crank_steps_per_mesh_cycle` + set-up) + the rest of an evaluation),
/// plus stages x (`te.samples_per_mesh_cycle` x the hysteresis and loaded-TE torques +
/// set-up). The profile updates that `wear.max_wear_step_um` asks for are checked by the wear
/// integration once the first wear rate is known.
///
/// # Errors
/// [`Error::Invalid`] naming the key whose value is furthest above the example's (the key that
/// sets the load levels for them: `load.levels`, `load.file`), with the estimate and the
/// budget.
pub(crate) fn check_work(model: &Model) -> Result<()> {
    let w = &model.wear;
    let updates = w.scheduled_updates();
    let (wear, stages) = study_work(model);
    let total = wear + stages;
    if total <= model.work_budget {
        return Ok(());
    }
    // The factor furthest above the example's value drives it.
    let levels = model.load.levels.len() as f64;
    let candidates = [
        (
            model.load.levels_key.to_string(),
            format!("{levels} levels"),
            levels / 24.0,
        ),
        (
            "wear.profile_update_hours".to_string(),
            format!("{}", w.update_hours),
            updates / 30.0,
        ),
        (
            "wear.crank_steps_per_mesh_cycle".to_string(),
            w.crank_steps.to_string(),
            w.crank_steps as f64 / 18.0,
        ),
        (
            "wear.stage_hours".to_string(),
            format!("{} stages", w.stage_hours.len()),
            w.stage_hours.len() as f64 / 7.0,
        ),
        (
            "te.samples_per_mesh_cycle".to_string(),
            model.te.samples.to_string(),
            model.te.samples as f64 / 24.0,
        ),
    ];
    let (key, value, _) = candidates
        .iter()
        .fold(&candidates[0], |a, b| if b.2 > a.2 { b } else { a });
    Err(Error::invalid(
        key.as_str(),
        value,
        format!(
            "the study would need about {total:.2e} contact solves (~{:.1} min: {updates} \
             wear-rate evaluations x {levels} load levels x {} crank steps, {} stages x {} TE \
             samples), more than the work budget of {:.1} min (--work-budget-min); lower it",
            budget::minutes(total),
            w.crank_steps,
            w.stage_hours.len(),
            model.te.samples,
            budget::minutes(model.work_budget),
        ),
    ))
}

/// Whether stage `i` of `wear` is unworn (no wear of the disc or the pins).
fn unworn(wear: &WearHistory, i: usize) -> bool {
    parts::unworn(&wear.maps[i], wear.pin_maps.get(i).map_or(&[], |m| m))
}

/// The hysteresis curve of `model`'s new reducer, mean over a mesh cycle (`model.te.samples`
/// crank angles), `levels` torque levels each way ([`crate::te::hysteresis`]): the curve the
/// structure's calibration fits and the sensitivity moves.
///
/// # Errors
/// Those of the profile and of the static solves.
pub(crate) fn new_reducer_curve(model: &Model, levels: usize) -> Result<crate::te::TwistTable> {
    let red = &model.reducer;
    let (_, mean) = crate::te::hysteresis(
        red,
        &model.profile()?,
        &crate::te::mesh_cycle_angles(red.geometry.pins, model.te.samples),
        model.rating.rated_torque,
        model.te.measuring_torque_fraction,
        levels,
    )?;
    Ok(mean)
}

/// Runs the study (the easy call of [`Executor`]): `progress(done, total)` reports the work in
/// steps (wear-rate evaluations, then stages, then, when dynamics are on, one multibody
/// simulation per stage, run in parallel; [`Observer::progress`]).
///
/// Stops at the working hours where the worn profile leaves the model's validity (see
/// [`crate::wear::integrate`]; also when a worn stage's analysis fails) and reports the stages
/// before it, with [`crate::wear::WearHistory::limit`] set.
///
/// # Errors
/// Solver failures on the unworn profile; interfering modifications; [`Error::Invalid`] naming
/// `wear.stage_hours` when no stage lies within the validity; the work budget.
pub fn run(model: &Model, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Study> {
    Executor::new(model).observe(&Progress(progress)).run()
}

/// [`run`] without each part's share of the twist (`Study::twist_shares` empty): the stages and
/// the life alone, what the calibration's reference studies read.
///
/// # Errors
/// As [`run`].
pub(crate) fn run_stages(model: &Model) -> Result<Study> {
    Executor::new(model).without_shares().run()
}
