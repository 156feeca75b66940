//! One candidate of a design search: its study (or Monte Carlo), its goals' and constraints'
//! values, and the point the search ranks (docs/model.md section 19).

use super::goal::{Goal, StageAt};
use super::point::Point;
use super::Problem;
use crate::config::Model;
use crate::quantities::AccuracyPoint;
use crate::study::Study;

/// How a candidate's evaluation ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Status {
    /// Its study ran.
    Ok,
    /// Its config was refused (the message names the key).
    Invalid(String),
    /// Its study failed (the solver's message).
    Failed(String),
}

impl Status {
    /// `ok`, `invalid: ...`, `failed: ...`.
    pub fn text(&self) -> String {
        match self {
            Status::Ok => "ok".into(),
            Status::Invalid(m) => format!("invalid: {m}"),
            Status::Failed(m) => format!("failed: {m}"),
        }
    }
}

/// One evaluated candidate (serialised: a cluster's workers send it back).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Candidate {
    /// Its place in the order of evaluation (0-based).
    pub index: usize,
    /// The search phase that proposed it (`start`, `sample`, `simplex`, `generation 3`).
    pub phase: String,
    /// Where it lies in the unit box.
    pub unit: Vec<f64>,
    /// The varied keys' values, in their units.
    pub values: Vec<f64>,
    /// Each goal's value in its unit: the life and B10 in hours (`None`: beyond the horizon),
    /// a quantity in its own.
    pub goals: Vec<Option<f64>>,
    /// Each goal's score (the life's and B10's, docs/model.md section 19; a quantity's
    /// value).
    pub scores: Vec<Option<f64>>,
    /// Each constraint's quantity value.
    pub constraints: Vec<Option<f64>>,
    /// What the search ranks.
    pub point: Point,
    /// The threshold that limits the life (`None`: within spec to the horizon, or no life
    /// goal).
    pub limited_by: Option<String>,
    /// How the evaluation ended.
    pub status: Status,
}

impl Candidate {
    /// Whether its study ran and every constraint holds (a refused or failed candidate is
    /// never feasible, constraints or not).
    pub fn feasible(&self) -> bool {
        self.status == Status::Ok && self.point.feasible()
    }
}

/// The life's score (docs/model.md section 19) and the life (h; `None` within spec to the
/// horizon) of a study with `[life]` thresholds: `L/H` for a life `L` within the horizon
/// `H` (`life.max_hours`, else ten times the last stage), `1 +` the smallest relative
/// margin at the last stage for a design within spec to the horizon, the (negative) margin
/// of the new reducer for one out of spec new: continuous across the three, so a search can
/// rank designs that all outlast the horizon, or all fail new.
pub fn life_score(model: &Model, study: &Study) -> Option<(f64, Option<f64>, Option<String>)> {
    let life = study.life.as_ref()?;
    let last = study.stages.last()?;
    let horizon = model.life.horizon_h(&model.wear.stage_hours);
    let worst = |s: &crate::study::Stage| {
        crate::life::margins(&model.life, &AccuracyPoint::of(&s.summary))
            .into_iter()
            .map(|m| m.1)
            .fold(f64::INFINITY, f64::min)
    };
    let by = life.limited_by.map(str::to_string);
    Some(match life.accuracy_life_h {
        Some(l) if l <= 0.0 => (worst(&study.stages[0]).min(0.0), Some(l), by),
        Some(l) => ((l / horizon).min(1.0), Some(l), by),
        None if life.horizon_h < horizon * (1.0 - 1e-9) => (life.horizon_h / horizon, None, by),
        None => (1.0 + worst(last).max(0.0), None, by),
    })
}

/// The B10 score of a Monte Carlo's records: `B10/H` (`H` the Monte Carlo's horizon), `1 +`
/// the fraction of samples beyond the horizon over 0.9 where B10 lies beyond it, and B10 (h).
fn b10_score(model: &Model, records: &[crate::montecarlo::SampleRecord]) -> (f64, Option<f64>) {
    let horizon = model.life.horizon_h(&model.wear.stage_hours);
    let d = crate::montecarlo::life_distribution(records, horizon);
    match d.b10_h {
        Some(b) => ((b / horizon).min(1.0), Some(b)),
        None => (1.0 + (d.censored_fraction - 0.9).max(0.0), None),
    }
}

/// Evaluates the candidate at `u` (unit box) of `problem`: validates its config, runs its
/// study when a goal or constraint reads it (and, for a B10 goal, its Monte Carlo at
/// [`crate::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE`] with the problem's seed: every candidate
/// draws the same random numbers), reads the goals and constraints. A config refused or a
/// study that fails gives a candidate of that status whose point is infeasible and worst
/// (objectives `+inf`), so the search goes on.
pub fn evaluate(problem: &Problem, u: &[f64], index: usize, phase: &str) -> Candidate {
    let values = problem.values(u);
    let n_goals = problem.goals.len();
    let failed = |status: Status| Candidate {
        index,
        phase: phase.to_string(),
        unit: u.to_vec(),
        values: values.clone(),
        goals: vec![None; n_goals],
        scores: vec![None; n_goals],
        constraints: vec![None; problem.constraints.len()],
        point: Point {
            objectives: vec![f64::INFINITY; n_goals],
            violations: vec![1.0; problem.constraints.len()],
        },
        limited_by: None,
        status,
    };
    let model = match problem.model(u) {
        Ok(m) => m,
        Err(e) => return failed(Status::Invalid(e.to_string())),
    };
    // A B10 goal alone reads only its Monte Carlo (`Problem::needs_study`).
    let study = if problem.needs_study() {
        match crate::study::run(&model, &|_, _| {}) {
            Ok(s) => Some(s),
            Err(e) => return failed(Status::Failed(e.to_string())),
        }
    } else {
        None
    };
    let hours: Vec<f64> = study
        .iter()
        .flat_map(|st| st.stages.iter().map(|s| s.hours))
        .collect();
    let at = |q: &crate::quantities::Quantity, at: &StageAt| {
        let study = study.as_ref()?;
        at.index(&hours)
            .and_then(|i| study.stages[i].summary.value(q).number())
    };
    let mut goals = Vec::with_capacity(n_goals);
    let mut scores = Vec::with_capacity(n_goals);
    let mut objectives = Vec::with_capacity(n_goals);
    let mut limited_by = None;
    for g in &problem.goals {
        let (value, score, objective) = match g {
            Goal::Life => match study.as_ref().and_then(|st| life_score(&model, st)) {
                Some((score, life, by)) => {
                    limited_by = by;
                    (life, Some(score), -score)
                }
                None => (None, None, f64::INFINITY),
            },
            Goal::B10 { samples } => {
                let plan = crate::montecarlo::Plan {
                    samples: *samples,
                    seed: problem.settings.seed,
                    shard: (1, 1),
                    full_wear: false,
                    samples_per_mesh_cycle: crate::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE,
                };
                match crate::montecarlo::run(&model, &plan, &|_, _| {}) {
                    Ok(records) => {
                        let (score, b10) = b10_score(&model, &records);
                        (b10, Some(score), -score)
                    }
                    Err(e) => return failed(Status::Failed(e.to_string())),
                }
            }
            Goal::Quantity {
                quantity,
                at: stage,
                maximise,
            } => {
                let v = at(quantity, stage);
                let o = match v {
                    Some(v) if v.is_finite() => {
                        if *maximise {
                            -v
                        } else {
                            v
                        }
                    }
                    _ => f64::INFINITY,
                };
                (v, v, o)
            }
        };
        goals.push(value);
        scores.push(score);
        objectives.push(objective);
    }
    let constraints: Vec<Option<f64>> = problem
        .constraints
        .iter()
        .map(|c| at(c.quantity, &c.at))
        .collect();
    let violations = problem
        .constraints
        .iter()
        .zip(&constraints)
        .map(|(c, v)| c.violation(*v))
        .collect();
    Candidate {
        index,
        phase: phase.to_string(),
        unit: u.to_vec(),
        values,
        goals,
        scores,
        constraints,
        point: Point {
            objectives,
            violations,
        },
        limited_by,
        status: Status::Ok,
    }
}
