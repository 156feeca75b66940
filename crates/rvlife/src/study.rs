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
//! The study's pieces: `stage` analyses one stage, `results` holds the study and its summary,
//! `trials` searches the accuracy life between and beyond the stages, and [`parts`] is the
//! study in parts that [`run`] and the web page's workers assemble.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

use crate::budget;
use crate::config::Model;
use crate::error::{Error, Result};
use crate::fem::DiscSet;
use crate::quantities::{AccuracyPoint, StageSummary};
use crate::wear::WearHistory;

mod executor;
pub mod parts;
mod results;
mod stage;
mod trials;

pub use results::{PaperComparison, Study, Summary};
pub use stage::{ProfileAnalysis, Stage};
pub(crate) use trials::LifeTrials;
#[cfg(test)]
pub(crate) use {results::is_papers_reducer, stage::analyse_profile, trials::study_life};

use executor::{record_row, Bookkeeping, Outcome, StageRunner};
use parts::{finish, until_limit};
use stage::{no_load, NoLoad};

/// The validated model of `cfg` ([`crate::config::Config::validate`]) whose study fits the
/// work budget ([`check_work`]): what every command and every design of a sweep runs on.
///
/// # Errors
/// [`Error::Invalid`] naming the key, the value and the allowed range, or the key that drives
/// the work beyond the budget (a key the file does not set named as a default).
pub(crate) fn validated(cfg: &crate::config::Config) -> Result<Model> {
    let model = cfg.validate()?;
    check_work(&model).map_err(|e| cfg.explain_default(e))?;
    Ok(model)
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

/// Runs the study. `progress(done, total)` reports the work in steps (wear-rate evaluations,
/// then stages, then, when dynamics are on, one multibody simulation per stage, run in
/// parallel).
///
/// Stops at the working hours where the worn profile leaves the model's validity (see
/// [`crate::wear::integrate`]; also when a worn stage's analysis fails) and reports the stages
/// before it, with [`crate::wear::WearHistory::limit`] set.
///
/// # Errors
/// Solver failures on the unworn profile; interfering modifications; [`Error::Invalid`] naming
/// `wear.stage_hours` when no stage lies within the validity; the work budget.
pub fn run(model: &Model, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Study> {
    run_with_notices(model, progress, &|_| {})
}

/// [`run`], telling `notice` (one line of text each) when the accuracy life's search goes on
/// beyond the last stage (a wear integration per step: it can take as long as the study).
///
/// # Errors
/// As [`run`].
pub fn run_with_notices(
    model: &Model,
    progress: &(dyn Fn(usize, usize) + Sync),
    notice: &dyn Fn(&str),
) -> Result<Study> {
    run_inner(model, progress, notice, true)
}

/// [`run`] without each part's share of the twist (`Study::twist_shares` empty): the stages
/// and the life alone, what the calibration's reference studies read.
///
/// # Errors
/// As [`run`].
pub(crate) fn run_stages(model: &Model) -> Result<Study> {
    run_inner(model, &|_, _| {}, &|_| {}, false)
}

/// [`run_with_notices`], with the twist shares when `shares`.
fn run_inner(
    model: &Model,
    progress: &(dyn Fn(usize, usize) + Sync),
    notice: &dyn Fn(&str),
    shares: bool,
) -> Result<Study> {
    let w = &model.wear;
    let n_stages = w.stage_hours.len();
    let wear_total = parts::wear_steps(model);
    let dyn_total = if model.dynamics.enabled { n_stages } else { 0 };
    let fem_total = if model.fem.enabled { n_stages } else { 0 };
    let total = wear_total + n_stages + dyn_total + fem_total;
    // The unworn disc's FE models are built beside the wear integration (they need the
    // unworn profile only); every worn stage's are then the same meshes moved onto its
    // outline (one topology and symbolic factorisation for the study; results smooth in the
    // wear).
    let flexible_dynamics = model.dynamics.enabled && model.dynamics.params.flexible.is_some();
    let base_profile = model.profile()?;
    let rates = crate::config::bearing_rates(model)?;
    // The new reducer's play, against which every stage's play is split once the stages are
    // done ([`UnwornPlay::split`]): made by the first worker free, beside the wear
    // integration.
    let new_play: OnceLock<Result<NoLoad>> = OnceLock::new();
    let make_new_play = || {
        let _ = new_play.set(no_load(model, &base_profile));
    };
    // Progress (the wear-rate evaluations so far plus the stage analyses done) and the first
    // stage that failed.
    let books = Bookkeeping::new(total, progress);
    let runner = StageRunner {
        model,
        rates,
        base_profile: &base_profile,
        books: &books,
    };
    // A first stage at 0 h needs no wear: it is analysed beside the wear integration (on the
    // unworn disc's FE models).
    let unworn_first = w.stage_hours.first() == Some(&0.0);
    let slots: Vec<OnceLock<Outcome>> = (0..n_stages).map(|_| OnceLock::new()).collect();
    let first: OnceLock<Outcome> = OnceLock::new();
    let wear_slot: OnceLock<WearHistory> = OnceLock::new();
    // The accuracy life's trials, taken up by the next worker free (before any further stage)
    // as soon as the stages show where they go: beyond the last stage when its static analysis
    // finds it within the spec (the search beyond the stages then likely follows, and its wear
    // integration runs beside the other stages' analyses), or between two stages when the
    // first stage outside the spec and every stage before it are done.
    let ahead: Mutex<Option<LifeTrials>> = Mutex::new(None);
    let ahead_start: Mutex<Option<AccuracyPoint>> = Mutex::new(None);
    let crossing_asked = AtomicBool::new(false);
    let take_ahead = || {
        let Some(wear) = wear_slot.get() else {
            return;
        };
        let start = ahead_start.lock().ok().and_then(|mut s| s.take());
        if let Some(start) = start {
            let trials = LifeTrials::ahead(model, wear, start);
            if let Ok(mut slot) = ahead.lock() {
                *slot = trials;
            }
        }
        if crossing_asked.load(Ordering::Relaxed) {
            return;
        }
        let points = slots
            .iter()
            .enumerate()
            .take(wear.hours.len())
            .map(|(i, slot)| {
                let stage = match (i, slot.get(), first.get()) {
                    (0, None, Some(f)) => f,
                    (_, Some(o), _) => o,
                    _ => return None,
                };
                Some(match stage {
                    Outcome::Done(done) => Some(AccuracyPoint::of(&done.0.summary)),
                    _ => None,
                })
            });
        // Known once every stage up to the first outside the spec is done; made by the one
        // worker that claims it first.
        let claim = || !crossing_asked.swap(true, Ordering::Relaxed);
        let Some(trials) = LifeTrials::crossing_ahead(model, wear, points, claim) else {
            return;
        };
        if let (Some(t), Ok(mut slot)) = (trials, ahead.lock()) {
            *slot = Some(t);
        }
    };
    let on_static = |i: usize, summary: &StageSummary| {
        let start = AccuracyPoint::of(summary);
        if i + 1 == n_stages && model.life.any() && !crate::life::outside(&model.life, &start) {
            if let Ok(mut slot) = ahead_start.lock() {
                *slot = Some(start);
            }
        }
    };
    let stage = |i: usize, hours: f64, map: &[f64], pin_map: &[f64], base: Option<&DiscSet>| {
        runner.run(i, hours, map, pin_map, base, &|summary| {
            on_static(i, summary)
        })
    };
    let wear_progress = |d: usize, _: usize| books.wear(d);
    if model.fem.enabled || flexible_dynamics {
        // The FE disc is built beside the wear integration, then the stages in parallel, the
        // most worn first (they take longest, so the cores finish together): the static
        // analysis, then the FE disc moved onto the worn outline, and the multibody simulation
        // and the flexible analysis side by side.
        let (wear, base) = rayon::join(
            || parts::wear_history_with(model, rates, &wear_progress, &|_| {}),
            || -> Result<DiscSet> {
                make_new_play();
                let base = DiscSet::build(&base_profile, &model.fem.params, &model.reducer)?;
                if unworn_first {
                    let _ = first.set(stage(0, 0.0, &[], &[], Some(&base)));
                }
                Ok(base)
            },
        );
        let _ = wear_slot.set(wear?);
        let base = base?;
        let wear = wear_slot.get().expect("set above");
        let mut order: Vec<usize> = (0..wear.hours.len())
            .filter(|&i| !(i == 0 && first.get().is_some() && unworn(wear, 0)))
            .collect();
        order.sort_by(|&a, &b| wear.hours[b].total_cmp(&wear.hours[a]));
        let next = AtomicUsize::new(0);
        rayon::scope(|s| {
            for _ in 0..rayon::current_num_threads().min(order.len()) {
                s.spawn(|_| loop {
                    take_ahead();
                    let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
                        break;
                    };
                    let _ = slots[i].set(stage(
                        i,
                        wear.hours[i],
                        &wear.maps[i],
                        &wear.pin_maps[i],
                        Some(&base),
                    ));
                });
            }
        });
    } else {
        // Without an FE disc each stage is analysed as soon as the wear integration has passed
        // it, beside the integration; the stages left when it ends are taken the most worn
        // first (each worker takes its latest task first).
        rayon::scope(|s| {
            s.spawn(|_| make_new_play());
            if unworn_first {
                s.spawn(|_| {
                    let _ = first.set(stage(0, 0.0, &[], &[], None));
                    take_ahead();
                });
            }
            let wear = parts::wear_history_with(model, rates, &wear_progress, &|sw| {
                if unworn_first && sw.index == 0 && sw.is_unworn() {
                    return;
                }
                let (stage, slots, take_ahead) = (&stage, &slots, &take_ahead);
                s.spawn(move |_| {
                    let i = sw.index;
                    let _ = slots[i].set(stage(i, sw.hours, &sw.map, &sw.pin_map, None));
                    take_ahead();
                });
            });
            let _ = wear_slot.set(wear?);
            take_ahead();
            Ok::<(), Error>(())
        })?;
    }
    // A worker that finished its last stage before the trials were asked for.
    take_ahead();
    let mut wear = wear_slot
        .into_inner()
        .expect("the wear history is set above");
    let n = wear.hours.len();
    let mut slots = slots;
    slots.truncate(n);
    // The 0 h stage analysed beside the wear (the wear history then starts at 0 h unworn).
    if let Some(f) = first.into_inner() {
        if n > 0 && unworn(&wear, 0) && slots[0].get().is_none() {
            let _ = slots[0].set(f);
        }
    }
    let new = new_play
        .into_inner()
        .unwrap_or_else(|| no_load(model, &base_profile))?;
    let outcomes = slots.into_iter().map(|slot| match slot.into_inner() {
        Some(Outcome::Done(b)) => {
            let (mut stage, play, rest) = *b;
            play.split(&mut stage.summary, new);
            Some(Ok((stage, rest)))
        }
        Some(Outcome::Failed(f)) => Some(Err(f)),
        Some(Outcome::Skipped) | None => None,
    });
    let mut stages = Vec::with_capacity(n_stages);
    let mut rows = Vec::with_capacity(n_stages);
    for (stage, rest) in until_limit(model, &mut wear, outcomes)? {
        rows.push(rest?);
        stages.push(stage);
    }
    for (st, row) in stages.iter_mut().zip(rows) {
        record_row(st, row);
    }
    let ahead = ahead.into_inner().ok().flatten();
    finish(model, wear, stages, ahead, notice, shares)
}
