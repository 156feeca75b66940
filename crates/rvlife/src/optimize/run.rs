//! A design search's run: its candidates in the order the optimisers ask for them, the best
//! one and the Pareto front (docs/model.md section 19).

use super::evaluate::{evaluate, Candidate, Status};
use super::point::{pareto_front, Point};
use super::search;
use super::Problem;
use crate::error::Result;

/// What a search found: every candidate in the order evaluated, the best feasible one (by
/// [`Point::merit`]: the first goal's, constraints as penalties), and the Pareto front of the
/// feasible ones (several goals; the best alone with one).
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Every candidate evaluated.
    pub candidates: Vec<Candidate>,
    /// The index of the best feasible candidate (`None`: none is feasible).
    pub best: Option<usize>,
    /// The indices of the Pareto front's candidates, by the first goal.
    pub front: Vec<usize>,
    /// The index of the base design's candidate, if its values lie in the ranges.
    pub start: Option<usize>,
    /// Whether the search ended early (the user stopped it).
    pub stopped: bool,
}

/// Runs the search of `problem` (docs/model.md section 19): the single-goal search
/// ([`search::minimise`]) for one goal, NSGA-II for several, one study per candidate (a
/// candidate whose keys round to an earlier one's, an integer key, is that one), at most
/// `problem.settings.evaluations`. `progress(done, total, candidate)` after each; `stop()`
/// before each (true: end the search and keep what it has).
///
/// # Errors
/// NSGA-II's set-up failures.
pub fn run(
    problem: &Problem,
    progress: &dyn Fn(usize, usize, &Candidate),
    stop: &dyn Fn() -> bool,
) -> Result<Outcome> {
    let total = problem.settings.evaluations;
    let candidates: std::cell::RefCell<Vec<Candidate>> = std::cell::RefCell::new(Vec::new());
    let stopped = std::cell::Cell::new(false);
    let mut evaluate = |u: &[f64], phase: &str| -> Option<Point> {
        let values = problem.values(u);
        if let Some(c) = candidates.borrow().iter().find(|c| c.values == values) {
            return Some(c.point.clone());
        }
        if candidates.borrow().len() >= total {
            return None;
        }
        if stop() {
            stopped.set(true);
            return None;
        }
        let index = candidates.borrow().len();
        let c = evaluate(problem, u, index, phase);
        let point = c.point.clone();
        progress(index + 1, total, &c);
        candidates.borrow_mut().push(c);
        Some(point)
    };
    let start = problem.start.as_ref().map(|s| {
        problem
            .variables
            .iter()
            .zip(s)
            .map(|(v, &x)| v.unit(x))
            .collect::<Vec<f64>>()
    });
    let dim = problem.variables.len();
    if problem.goals.len() == 1 {
        search::minimise(dim, &problem.settings, start.as_deref(), &mut evaluate);
    } else {
        #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
        {
            if let Some(s) = &start {
                let _ = evaluate(s, "start");
            }
            super::pareto::nsga2(
                dim,
                problem.goals.len(),
                problem.constraints.len(),
                &problem.settings,
                &mut evaluate,
            )?;
        }
    }
    let candidates = candidates.into_inner();
    let ok = |c: &Candidate| c.status == Status::Ok && c.point.feasible();
    let best = candidates
        .iter()
        .filter(|c| ok(c))
        .min_by(|a, b| a.point.merit().total_cmp(&b.point.merit()))
        .map(|c| c.index);
    let points: Vec<&Point> = candidates.iter().map(|c| &c.point).collect();
    let mut front = pareto_front(&points);
    front.retain(|&i| candidates[i].status == Status::Ok);
    front.sort_by(|&a, &b| points[a].objectives[0].total_cmp(&points[b].objectives[0]));
    let start_index = candidates
        .iter()
        .find(|c| c.phase == "start")
        .map(|c| c.index);
    Ok(Outcome {
        candidates,
        best,
        front,
        start: start_index,
        stopped: stopped.get(),
    })
}
