//! What a study tells while it runs, after argmin's observers: the [`Observer`]s an
//! [`super::Executor`] is given hear its progress, its notices and each stage's static results
//! as they come, from whichever worker made them. The study's own bookkeeping (the steps done,
//! the first stage that failed, the accuracy life's trials started ahead) is kept in its state
//! ([`super::state`]), not in an observer: an observer only listens.

use crate::quantities::StageSummary;

/// Hears a study as it runs ([`super::Executor::observe`]). Every method has a default that
/// ignores the event; the methods are called from the study's worker threads (hence `Sync`),
/// each as soon as its event happens, so stages arrive in any order.
pub trait Observer: Sync {
    /// `done` of `total` steps are done: the wear-rate evaluations so far, plus the stages'
    /// static analyses, multibody simulations and flexible analyses done (each one step).
    /// `total` is fixed for the study (the evaluations as scheduled, `last stage /
    /// wear.profile_update_hours`); the last report, when the study has its results, is
    /// `(total, total)`. The workers report as they finish, so two reports may arrive out of
    /// order: the largest `done` heard so far is the progress.
    fn progress(&self, done: usize, total: usize) {
        let _ = (done, total);
    }

    /// One line of text for the user: the accuracy life's search goes on beyond the last stage
    /// (a wear integration per step: it can take as long as the study).
    fn notice(&self, text: &str) {
        let _ = text;
    }

    /// Stage `index` (from 0, in the order of `wear.stage_hours`) has its static results:
    /// `summary` as the stage's analysis made it, before its play is split by source against
    /// the new reducer's and before its dynamics and flexible analysis.
    fn stage(&self, index: usize, summary: &StageSummary) {
        let _ = (index, summary);
    }
}

/// An [`Observer`] of the progress alone: `f(done, total)` ([`Observer::progress`]).
pub struct Progress<F>(pub F);

impl<F: Fn(usize, usize) + Sync> Observer for Progress<F> {
    fn progress(&self, done: usize, total: usize) {
        (self.0)(done, total)
    }
}

/// An [`Observer`] of the notices alone: `f(line)` ([`Observer::notice`]).
pub struct Notices<F>(pub F);

impl<F: Fn(&str) + Sync> Observer for Notices<F> {
    fn notice(&self, text: &str) {
        (self.0)(text)
    }
}

/// The observers of one study, each told every event in the order they were added.
pub(super) struct Observers<'a>(pub(super) Vec<&'a dyn Observer>);

impl Observer for Observers<'_> {
    fn progress(&self, done: usize, total: usize) {
        self.0.iter().for_each(|o| o.progress(done, total))
    }

    fn notice(&self, text: &str) {
        self.0.iter().for_each(|o| o.notice(text))
    }

    fn stage(&self, index: usize, summary: &StageSummary) {
        self.0.iter().for_each(|o| o.stage(index, summary))
    }
}
