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

/// One candidate a search asks for: where it lies in the unit box, its index in the order of
/// evaluation, the phase that asks for it.
pub type Job = (Vec<f64>, usize, String);

/// Evaluates the candidates a search asks for together elsewhere (a cluster's workers, each
/// with [`super::evaluate::evaluate`] on the same problem), returning them in the order of
/// the jobs.
pub type Batch<'a> = dyn Fn(&[Job]) -> Result<Vec<Candidate>> + 'a;

/// The candidates as the search asks for them: each evaluated once (a candidate whose keys
/// round to an earlier one's, an integer key, is that one), at most the problem's evaluations,
/// here one at a time or by `batch` where the search asks for several together.
struct Recorder<'a> {
    problem: &'a Problem,
    batch: Option<&'a Batch<'a>>,
    progress: &'a dyn Fn(usize, usize, &Candidate),
    stop: &'a dyn Fn() -> bool,
    candidates: Vec<Candidate>,
    stopped: bool,
    error: Option<crate::error::Error>,
}

impl Recorder<'_> {
    /// The point of the candidate evaluated before with these `values`.
    fn known(&self, values: &[f64]) -> Option<Point> {
        self.candidates
            .iter()
            .find(|c| c.values == values)
            .map(|c| c.point.clone())
    }

    /// Whether no more candidates may be evaluated (the budget spent, the user's stop, a
    /// batch's failure).
    fn closed(&mut self) -> bool {
        if self.candidates.len() >= self.problem.settings.evaluations || self.error.is_some() {
            return true;
        }
        if (self.stop)() {
            self.stopped = true;
        }
        self.stopped
    }

    /// Keeps `c` (after reporting it).
    fn keep(&mut self, c: Candidate) -> Point {
        (self.progress)(c.index + 1, self.problem.settings.evaluations, &c);
        let point = c.point.clone();
        self.candidates.push(c);
        point
    }
}

impl search::Evaluator for Recorder<'_> {
    fn one(&mut self, u: &[f64], phase: &str) -> Option<Point> {
        self.many(&[u.to_vec()], phase).pop().flatten()
    }

    fn many(&mut self, xs: &[Vec<f64>], phase: &str) -> Vec<Option<Point>> {
        let mut out: Vec<Option<Point>> = vec![None; xs.len()];
        // Each point is known already, the same as an earlier job of this batch, or a new job.
        let mut jobs: Vec<Job> = Vec::new();
        let mut job_of: Vec<Option<usize>> = vec![None; xs.len()];
        let mut job_values: Vec<Vec<f64>> = Vec::new();
        for (i, u) in xs.iter().enumerate() {
            let values = self.problem.values(u);
            if let Some(p) = self.known(&values) {
                out[i] = Some(p);
            } else if let Some(j) = job_values.iter().position(|v| *v == values) {
                job_of[i] = Some(j);
            } else if self.candidates.len() + jobs.len() < self.problem.settings.evaluations
                && !(jobs.is_empty() && self.closed())
            {
                job_of[i] = Some(jobs.len());
                jobs.push((
                    u.clone(),
                    self.candidates.len() + jobs.len(),
                    phase.to_string(),
                ));
                job_values.push(values);
            } else {
                break;
            }
        }
        let points: Vec<Point> = match self.batch {
            Some(batch) if !jobs.is_empty() => match batch(&jobs) {
                Ok(cs) if cs.len() == jobs.len() => cs.into_iter().map(|c| self.keep(c)).collect(),
                Ok(cs) => {
                    self.error = Some(crate::error::Error::numerical(
                        "optimize",
                        format!(
                            "a batch of {} candidates came back with {}",
                            jobs.len(),
                            cs.len()
                        ),
                    ));
                    Vec::new()
                }
                Err(e) => {
                    self.error = Some(e);
                    Vec::new()
                }
            },
            _ => {
                let mut ps = Vec::with_capacity(jobs.len());
                for (u, index, phase) in &jobs {
                    if !ps.is_empty() && self.closed() {
                        break;
                    }
                    let c = evaluate(self.problem, u, *index, phase);
                    ps.push(self.keep(c));
                }
                ps
            }
        };
        for (o, j) in out.iter_mut().zip(job_of) {
            if let Some(p) = j.and_then(|j| points.get(j)) {
                *o = Some(p.clone());
            }
        }
        // `None` from the first point not evaluated on.
        if let Some(first) = out.iter().position(Option::is_none) {
            out.truncate(first);
            out.resize(xs.len(), None);
        }
        out
    }
}

/// Runs the search of `problem` (docs/model.md section 19): the single-goal search
/// ([`search::minimise`]) for one goal, NSGA-II for several, one study per candidate (a
/// candidate whose keys round to an earlier one's, an integer key, is that one), at most
/// `problem.settings.evaluations`, each in this process. `progress(done, total, candidate)`
/// after each; `stop()` before each (true: end the search and keep what it has).
///
/// # Errors
/// NSGA-II's set-up failures.
pub fn run(
    problem: &Problem,
    progress: &dyn Fn(usize, usize, &Candidate),
    stop: &dyn Fn() -> bool,
) -> Result<Outcome> {
    run_batched(problem, None, progress, stop)
}

/// [`run`] with the candidates the search asks for together (the Latin hypercube, each
/// generation of NSGA-II) evaluated by `batch` (a cluster), the others one at a time in this
/// process: the same candidates in the same order as [`run`].
///
/// # Errors
/// NSGA-II's set-up failures; `batch`'s first failure (the search ends there).
pub fn run_batched(
    problem: &Problem,
    batch: Option<&Batch<'_>>,
    progress: &dyn Fn(usize, usize, &Candidate),
    stop: &dyn Fn() -> bool,
) -> Result<Outcome> {
    let mut recorder = Recorder {
        problem,
        batch,
        progress,
        stop,
        candidates: Vec::new(),
        stopped: false,
        error: None,
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
        search::minimise(dim, &problem.settings, start.as_deref(), &mut recorder);
    } else {
        if let Some(s) = &start {
            let _ = search::Evaluator::one(&mut recorder, s, "start");
        }
        super::pareto::nsga2(
            dim,
            problem.goals.len(),
            problem.constraints.len(),
            &problem.settings,
            &mut recorder,
        )?;
    }
    if let Some(e) = recorder.error {
        return Err(e);
    }
    let candidates = recorder.candidates;
    let best = candidates
        .iter()
        .filter(|c| c.feasible())
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
        stopped: recorder.stopped,
    })
}
