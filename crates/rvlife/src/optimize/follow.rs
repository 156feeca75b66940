//! What a design search's report shows beyond its candidates (docs/model.md section 19.5):
//! the best design's and the base design's studies at every stage, and the sensitivity of
//! the best design's goal to each varied key.

use super::evaluate::{evaluate, Candidate, Status};
use super::run::Outcome;
use super::Problem;
use crate::error::Result;
use crate::study::Study;

/// Step of the sensitivity, as a fraction of each key's range (each side of the best).
pub const SENSITIVITY_STEP: f64 = 0.05;

/// The first goal of the best design against one varied key, the others held.
#[derive(Debug, Clone)]
pub struct Sensitivity {
    /// The key.
    pub key: String,
    /// `(key's value, first goal's score)` below, at and above the best value (inside the
    /// range; a candidate that fails is left out).
    pub points: Vec<(f64, f64)>,
    /// The score's change per unit of the key (central or one-sided difference; `None`
    /// with fewer than two points).
    pub slope: Option<f64>,
}

/// The follow-up of a search: the best and base designs' studies, and the sensitivity.
#[derive(Debug)]
pub struct FollowUp {
    /// The best design's study (as its candidate ran it).
    pub best: Option<Study>,
    /// The base design's study.
    pub start: Option<Study>,
    /// One per varied key.
    pub sensitivity: Vec<Sensitivity>,
}

/// Runs the follow-up of `outcome` (module docs): the studies of the best and base
/// candidates again (their results are not kept by the search) and `2 d` candidates around
/// the best, [`SENSITIVITY_STEP`] of each range either side. `progress(done, total)` after
/// each of its `2 + 2 d` steps (a study or a candidate; those with nothing to do count too).
///
/// # Errors
/// The studies' failures.
pub fn follow_up(
    problem: &Problem,
    outcome: &Outcome,
    progress: &dyn Fn(usize, usize),
) -> Result<FollowUp> {
    let total = 2 + 2 * problem.variables.len();
    let done = std::cell::Cell::new(0);
    let step = || {
        done.set(done.get() + 1);
        progress(done.get(), total);
    };
    let study_of = |i: Option<usize>| -> Result<Option<Study>> {
        let Some(c) = i.map(|i| &outcome.candidates[i]) else {
            step();
            return Ok(None);
        };
        let model = problem.model(&c.unit)?;
        let s = crate::study::run(&model, &|_, _| {})?;
        step();
        Ok(Some(s))
    };
    let best = study_of(outcome.best)?;
    let start = study_of(outcome.start)?;
    let mut sensitivity = Vec::new();
    if let Some(b) = outcome.best.map(|i| &outcome.candidates[i]) {
        let score = |c: &Candidate| {
            (c.status == Status::Ok)
                .then(|| c.scores.first().copied().flatten())
                .flatten()
        };
        for (k, v) in problem.variables.iter().enumerate() {
            let mut points = Vec::new();
            for d in [-SENSITIVITY_STEP, 0.0, SENSITIVITY_STEP] {
                let mut u = b.unit.clone();
                u[k] = (u[k] + d).clamp(0.0, 1.0);
                if d == 0.0 {
                    if let Some(s) = score(b) {
                        points.push((b.values[k], s));
                    }
                    continue;
                }
                if u[k] == b.unit[k] {
                    step();
                    continue;
                }
                let c = evaluate(problem, &u, usize::MAX, "sensitivity");
                step();
                if let Some(s) = score(&c) {
                    points.push((c.values[k], s));
                }
            }
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let slope = match (points.first(), points.last()) {
                (Some(a), Some(z)) if points.len() >= 2 && z.0 > a.0 => {
                    Some((z.1 - a.1) / (z.0 - a.0))
                }
                _ => None,
            };
            sensitivity.push(Sensitivity {
                key: v.key.clone(),
                points,
                slope,
            });
        }
    }
    while done.get() < total {
        step();
    }
    Ok(FollowUp {
        best,
        start,
        sensitivity,
    })
}
