//! The state of a study while it runs (argmin's `IterState`): what the workers have made so
//! far (the wear history, each stage's outcome, the new reducer's play, the accuracy life's
//! trials started ahead) and the bookkeeping beside it (the steps done, the first stage whose
//! static analysis failed), shared by the workers of [`super::Executor::run`] and turned into
//! the [`Study`] once they are done ([`StudyState::finish`]).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

use super::analyses::{record_row, Outcome};
use super::observer::{Observer, Observers};
use super::parts::{finish, until_limit};
use super::stage::{no_load, NoLoad};
use super::trials::LifeTrials;
use super::{unworn, Study};
use crate::config::Model;
use crate::error::Result;
use crate::geometry::Profile;
use crate::quantities::{AccuracyPoint, StageSummary};
use crate::wear::WearHistory;

/// A running study's state: written once per slot by whichever worker finishes it (each slot a
/// [`OnceLock`]), read by the others.
pub(super) struct StudyState<'a> {
    model: &'a Model,
    observers: &'a Observers<'a>,
    /// Steps of the whole study ([`Observer::progress`]).
    total: usize,
    /// Wear-rate evaluations done so far.
    wear_done: AtomicUsize,
    /// Stage analyses done so far.
    done: AtomicUsize,
    /// The lowest stage whose static analysis failed (`usize::MAX`: none): the stages after it
    /// are skipped, as the study reports only the stages before a failure.
    failed: AtomicUsize,
    /// Each stage's outcome, by index.
    slots: Vec<OnceLock<Outcome>>,
    /// The 0 h stage analysed beside the wear integration (it needs no wear).
    first: OnceLock<Outcome>,
    /// The wear history, once integrated.
    wear: OnceLock<WearHistory>,
    /// The new reducer's play, against which every stage's play is split once the stages are
    /// done ([`super::stage::UnwornPlay::split`]).
    new_play: OnceLock<Result<NoLoad>>,
    /// The accuracy life's trials made ahead of the assembly ([`Self::take_ahead`]).
    ahead: Mutex<Option<LifeTrials>>,
    /// The last stage's accuracy when its static analysis finds it within the spec: the start
    /// of the search beyond the stages.
    ahead_start: Mutex<Option<AccuracyPoint>>,
    /// Whether a worker has taken up the trials between two stages.
    crossing_asked: AtomicBool,
}

impl<'a> StudyState<'a> {
    /// Nothing done yet of the `total` steps of a study of `model` with `n_stages` stages.
    pub(super) fn new(
        model: &'a Model,
        observers: &'a Observers<'a>,
        total: usize,
        n_stages: usize,
    ) -> Self {
        StudyState {
            model,
            observers,
            total,
            wear_done: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            failed: AtomicUsize::new(usize::MAX),
            slots: (0..n_stages).map(|_| OnceLock::new()).collect(),
            first: OnceLock::new(),
            wear: OnceLock::new(),
            new_play: OnceLock::new(),
            ahead: Mutex::new(None),
            ahead_start: Mutex::new(None),
            crossing_asked: AtomicBool::new(false),
        }
    }

    fn report(&self) {
        self.observers.progress(
            self.wear_done.load(Ordering::Relaxed) + self.done.load(Ordering::Relaxed),
            self.total,
        )
    }

    /// The wear integration has made `done` rate evaluations.
    pub(super) fn wear_progress(&self, done: usize) {
        self.wear_done.fetch_max(done, Ordering::Relaxed);
        self.report();
    }

    /// One more analysis done.
    pub(super) fn tick(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
        self.report();
    }

    /// Whether stage `i` is skipped: a stage before it failed its static analysis.
    pub(super) fn skips(&self, i: usize) -> bool {
        i > self.failed.load(Ordering::Relaxed)
    }

    /// Stage `i` failed its static analysis.
    pub(super) fn failed_at(&self, i: usize) {
        self.failed.fetch_min(i, Ordering::Relaxed);
    }

    /// Stage `i` has its static results `summary`: the observers hear it, and when it is the
    /// last stage and within the spec, the accuracy life's search beyond the stages likely
    /// follows: its start is kept for the next worker free ([`Self::take_ahead`]).
    pub(super) fn static_done(&self, i: usize, summary: &StageSummary) {
        self.observers.stage(i, summary);
        let model = self.model;
        let start = AccuracyPoint::of(summary);
        if i + 1 == self.slots.len()
            && model.life.any()
            && !crate::life::outside(&model.life, &start)
        {
            if let Ok(mut slot) = self.ahead_start.lock() {
                *slot = Some(start);
            }
        }
    }

    /// Finds the new reducer's play on the unworn `profile` (once).
    pub(super) fn find_new_play(&self, profile: &Profile) {
        let _ = self.new_play.set(no_load(self.model, profile));
    }

    /// Stage `i`'s outcome.
    pub(super) fn set_stage(&self, i: usize, outcome: Outcome) {
        let _ = self.slots[i].set(outcome);
    }

    /// The outcome of the 0 h stage analysed beside the wear integration.
    pub(super) fn set_first(&self, outcome: Outcome) {
        let _ = self.first.set(outcome);
    }

    /// Whether the 0 h stage was analysed beside the wear integration.
    pub(super) fn has_first(&self) -> bool {
        self.first.get().is_some()
    }

    /// The wear history, once integrated.
    pub(super) fn set_wear(&self, wear: WearHistory) {
        let _ = self.wear.set(wear);
    }

    /// The wear history, when integrated.
    pub(super) fn wear(&self) -> Option<&WearHistory> {
        self.wear.get()
    }

    /// The accuracy life's trials (docs/model.md section 11), taken up by the next worker free
    /// (before any further stage) as soon as the stages show where they go: beyond the last
    /// stage when its static analysis finds it within the spec (the search beyond the stages
    /// then likely follows, and its wear integration runs beside the other stages' analyses),
    /// or between two stages when the first stage outside the spec and every stage before it
    /// are done (made by the one worker that claims it first).
    pub(super) fn take_ahead(&self) {
        let model = self.model;
        let Some(wear) = self.wear.get() else {
            return;
        };
        let start = self.ahead_start.lock().ok().and_then(|mut s| s.take());
        if let Some(start) = start {
            let trials = LifeTrials::ahead(model, wear, start);
            if let Ok(mut slot) = self.ahead.lock() {
                *slot = trials;
            }
        }
        if self.crossing_asked.load(Ordering::Relaxed) {
            return;
        }
        let points = self
            .slots
            .iter()
            .enumerate()
            .take(wear.hours.len())
            .map(|(i, slot)| {
                let stage = match (i, slot.get(), self.first.get()) {
                    (0, None, Some(f)) => f,
                    (_, Some(o), _) => o,
                    _ => return None,
                };
                Some(match stage {
                    Outcome::Done(done) => Some(AccuracyPoint::of(&done.0.summary)),
                    _ => None,
                })
            });
        let claim = || !self.crossing_asked.swap(true, Ordering::Relaxed);
        let Some(trials) = LifeTrials::crossing_ahead(model, wear, points, claim) else {
            return;
        };
        if let (Some(t), Ok(mut slot)) = (trials, self.ahead.lock()) {
            *slot = Some(t);
        }
    }

    /// The study once every worker is done: the stages in order up to the validity limit
    /// ([`until_limit`]), each stage's play split against the new reducer's (found on the
    /// unworn `profile` here if no worker found it), its dynamics and flexible results
    /// recorded, then the accuracy life and, with `shares`, each part's share of the twist
    /// ([`finish`]; the observers hear its notices).
    ///
    /// # Errors
    /// A stage's failure that is not the validity limit, the new reducer's play, those of
    /// [`finish`].
    pub(super) fn finish(self, profile: &Profile, shares: bool) -> Result<Study> {
        let (model, observers) = (self.model, self.observers);
        let mut wear = self
            .wear
            .into_inner()
            .expect("the wear history is set before the study finishes");
        let n = wear.hours.len();
        let mut slots = self.slots;
        slots.truncate(n);
        // The 0 h stage analysed beside the wear (the wear history then starts at 0 h unworn).
        if let Some(f) = self.first.into_inner() {
            if n > 0 && unworn(&wear, 0) && slots[0].get().is_none() {
                let _ = slots[0].set(f);
            }
        }
        let new = self
            .new_play
            .into_inner()
            .unwrap_or_else(|| no_load(model, profile))?;
        let outcomes = slots.into_iter().map(|slot| match slot.into_inner() {
            Some(Outcome::Done(b)) => {
                let (mut stage, play, rest) = *b;
                play.split(&mut stage.summary, new);
                Some(Ok((stage, rest)))
            }
            Some(Outcome::Failed(f)) => Some(Err(f)),
            Some(Outcome::Skipped) | None => None,
        });
        let mut stages = Vec::with_capacity(n);
        let mut rows = Vec::with_capacity(n);
        for (stage, rest) in until_limit(model, &mut wear, outcomes)? {
            rows.push(rest?);
            stages.push(stage);
        }
        for (st, row) in stages.iter_mut().zip(rows) {
            record_row(st, row);
        }
        let ahead = self.ahead.into_inner().ok().flatten();
        finish(model, wear, stages, ahead, &|t| observers.notice(t), shares)
    }
}
