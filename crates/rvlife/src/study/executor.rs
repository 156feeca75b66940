//! The study's executor, after argmin's `Executor`: [`Executor::run`] takes a validated model,
//! the [`Observer`]s that hear it run, and whether the twist shares are wanted, and schedules
//! the study's work on the threads (rayon): the wear integration, each stage's analyses
//! ([`StageRunner`]) and the accuracy life's trials, all writing into one [`StudyState`],
//! which then becomes the [`Study`].
//!
//! Two schedules, by what the stages need:
//! - **with an FE disc** (`[fem] enabled`, or the multibody model's flexible disc): the unworn
//!   disc's FE models are built beside the wear integration (they need the unworn profile
//!   only; every worn stage's are the same meshes moved onto its outline: one topology and
//!   symbolic factorisation for the study, results smooth in the wear), then the stages in
//!   parallel, the most worn first (they take longest, so the cores finish together);
//! - **without**: each stage is analysed as soon as the wear integration has passed it,
//!   beside the integration; the stages left when it ends are taken the most worn first (each
//!   worker takes its latest task first).
//!
//! Either way the 0 h stage, which needs no wear, is analysed beside the integration, and a
//! worker takes up the accuracy life's trials before any further stage as soon as the stages
//! show where they go ([`StudyState::take_ahead`]).

use std::sync::atomic::{AtomicUsize, Ordering};

use super::analyses::{dynamics_and_flexible, Outcome};
use super::observer::{Observer, Observers};
use super::parts;
use super::stage::{static_part, Failure};
use super::state::StudyState;
use super::{unworn, Study};
use crate::config::Model;
use crate::error::{Error, Result};
use crate::fem::DiscSet;
use crate::geometry::Profile;
use crate::wear::BearingWearRates;

/// Runs the accuracy-life study of a validated model (docs/model.md sections 7-11): the easy
/// call is [`super::run`]; the executor adds observers and the choice of results.
///
/// ```no_run
/// # fn main() -> rvlife::error::Result<()> {
/// use rvlife::study::{Executor, Notices, Progress};
/// let model = rvlife::config::Config::example().validate()?;
/// let progress = Progress(|done, total| eprintln!("{done}/{total}"));
/// let notices = Notices(|line: &str| eprintln!("{line}"));
/// let study = Executor::new(&model).observe(&progress).observe(&notices).run()?;
/// # Ok(())
/// # }
/// ```
pub struct Executor<'a> {
    model: &'a Model,
    observers: Vec<&'a dyn Observer>,
    shares: bool,
}

impl<'a> Executor<'a> {
    /// The study of `model` (validated: [`crate::config::Config::validate`]), with no observer
    /// and each part's share of the twist.
    pub fn new(model: &'a Model) -> Self {
        Executor {
            model,
            observers: Vec::new(),
            shares: true,
        }
    }

    /// Adds `observer`, told every event after the observers added before it.
    pub fn observe(mut self, observer: &'a dyn Observer) -> Self {
        self.observers.push(observer);
        self
    }

    /// Leaves out each part's share of the twist (`Study::twist_shares` empty): the stages and
    /// the life alone, what the calibration's reference studies read.
    pub(crate) fn without_shares(mut self) -> Self {
        self.shares = false;
        self
    }

    /// Runs the study: the wear over working hours, every stage's analyses, the accuracy life.
    ///
    /// Stops at the working hours where the worn profile leaves the model's validity (see
    /// [`crate::wear::integrate`]; also when a worn stage's analysis fails) and reports the
    /// stages before it, with [`crate::wear::WearHistory::limit`] set.
    ///
    /// # Errors
    /// Solver failures on the unworn profile; interfering modifications; [`Error::Invalid`]
    /// naming `wear.stage_hours` when no stage lies within the validity; the work budget.
    pub fn run(self) -> Result<Study> {
        let model = self.model;
        let observers = Observers(self.observers);
        let n_stages = model.wear.stage_hours.len();
        let per_stage = 1 + usize::from(model.dynamics.enabled) + usize::from(model.fem.enabled);
        let total = parts::wear_steps(model) + n_stages * per_stage;
        let base_profile = model.profile()?;
        let state = StudyState::new(model, &observers, total, n_stages);
        let runner = StageRunner {
            model,
            rates: crate::config::bearing_rates(model)?,
            base_profile: &base_profile,
            state: &state,
        };
        let flexible_dynamics = model.dynamics.enabled && model.dynamics.params.flexible.is_some();
        if model.fem.enabled || flexible_dynamics {
            with_fe_disc(&runner)?;
        } else {
            beside_wear(&runner)?;
        }
        // A worker that finished its last stage before the trials were asked for.
        state.take_ahead();
        let study = state.finish(&base_profile, self.shares)?;
        // The count of wear-rate evaluations is an estimate (more where `wear.max_wear_step_um`
        // asks for them, fewer where the study stops at the validity limit): the end is told
        // as the whole.
        observers.progress(total, total);
        Ok(study)
    }
}

/// The schedule with an FE disc (see the module's docs).
///
/// # Errors
/// Those of the wear integration and of the FE disc.
fn with_fe_disc(runner: &StageRunner) -> Result<()> {
    let (model, state) = (runner.model, runner.state);
    let unworn_first = model.wear.stage_hours.first() == Some(&0.0);
    let (wear, base) = rayon::join(
        || parts::wear_history_with(model, runner.rates, &|d, _| state.wear_progress(d), &|_| {}),
        || -> Result<DiscSet> {
            state.find_new_play(runner.base_profile);
            let base = DiscSet::build(runner.base_profile, &model.fem.params, &model.reducer)?;
            if unworn_first {
                state.set_first(runner.run(0, 0.0, &[], &[], Some(&base)));
            }
            Ok(base)
        },
    );
    state.set_wear(wear?);
    let base = base?;
    let wear = state.wear().expect("set above");
    let mut order: Vec<usize> = (0..wear.hours.len())
        .filter(|&i| !(i == 0 && state.has_first() && unworn(wear, 0)))
        .collect();
    order.sort_by(|&a, &b| wear.hours[b].total_cmp(&wear.hours[a]));
    let next = AtomicUsize::new(0);
    rayon::scope(|s| {
        for _ in 0..rayon::current_num_threads().min(order.len()) {
            s.spawn(|_| loop {
                state.take_ahead();
                let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
                    break;
                };
                let outcome = runner.run(
                    i,
                    wear.hours[i],
                    &wear.maps[i],
                    &wear.pin_maps[i],
                    Some(&base),
                );
                state.set_stage(i, outcome);
            });
        }
    });
    Ok(())
}

/// The schedule without an FE disc (see the module's docs).
///
/// # Errors
/// Those of the wear integration.
fn beside_wear(runner: &StageRunner) -> Result<()> {
    let (model, state) = (runner.model, runner.state);
    let unworn_first = model.wear.stage_hours.first() == Some(&0.0);
    rayon::scope(|s| {
        s.spawn(|_| state.find_new_play(runner.base_profile));
        if unworn_first {
            s.spawn(|_| {
                state.set_first(runner.run(0, 0.0, &[], &[], None));
                state.take_ahead();
            });
        }
        let wear =
            parts::wear_history_with(model, runner.rates, &|d, _| state.wear_progress(d), &|sw| {
                if unworn_first && sw.index == 0 && sw.is_unworn() {
                    return;
                }
                s.spawn(move |_| {
                    let i = sw.index;
                    state.set_stage(i, runner.run(i, sw.hours, &sw.map, &sw.pin_map, None));
                    state.take_ahead();
                });
            });
        state.set_wear(wear?);
        state.take_ahead();
        Ok::<(), Error>(())
    })
}

/// What every stage of one study is analysed with: the model, the bearings' clearance growth,
/// the unworn profile (against which the FE disc is moved) and the study's state (its
/// bookkeeping).
pub(super) struct StageRunner<'a> {
    pub(super) model: &'a Model,
    pub(super) rates: BearingWearRates,
    pub(super) base_profile: &'a Profile,
    pub(super) state: &'a StudyState<'a>,
}

impl StageRunner<'_> {
    /// Stage `i` at `hours` with the wear depth `map` and the pins' wear `pin_map`: its static
    /// part ([`static_part`]), then its dynamics and flexible analysis
    /// ([`dynamics_and_flexible`], on the FE disc `base` moved onto its outline). Skipped when
    /// a stage before it has failed its static analysis; a tick after each analysis, the
    /// static part's summary to [`StudyState::static_done`].
    pub(super) fn run(
        &self,
        i: usize,
        hours: f64,
        map: &[f64],
        pin_map: &[f64],
        base: Option<&DiscSet>,
    ) -> Outcome {
        let books = self.state;
        if books.skips(i) {
            return Outcome::Skipped;
        }
        let (stage, staged, play) = match static_part(
            self.model,
            self.rates,
            hours,
            map,
            pin_map,
            self.base_profile,
        ) {
            Ok(x) => x,
            Err(f) => {
                if matches!(f, Failure::Static(..)) {
                    books.failed_at(i);
                }
                return Outcome::Failed(f);
            }
        };
        books.static_done(i, &stage.summary);
        books.tick();
        let rest = if books.skips(i) {
            Ok((None, None))
        } else {
            dynamics_and_flexible(&staged, &stage.profile, base, self.base_profile, &|| {
                books.tick()
            })
        };
        Outcome::Done(Box::new((stage, play, rest)))
    }
}
