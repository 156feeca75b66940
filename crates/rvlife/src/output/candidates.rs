//! A design search's tables in memory (`rvlife optimize`; the page and Python too): the texts
//! of `candidates.csv` and `pareto.csv` (columns in [`super::optimize`]'s documentation), a
//! candidate as JSON, and the convergence of the search.

use serde_json::{json, Value as Json};

use super::f;
use crate::error::{Error, Result};
use crate::optimize::{Candidate, Goal, Outcome, Problem};

/// The columns of a goal: its value, and its score for the life and B10.
pub(crate) fn goal_columns(g: &Goal) -> Vec<String> {
    match g {
        Goal::Life => vec!["accuracy_life_h".into(), "life_score".into()],
        Goal::B10 { .. } => vec!["b10_h".into(), "b10_score".into()],
        Goal::Quantity { .. } => vec![g.name()],
    }
}

/// The header of `candidates.csv` and `pareto.csv`.
fn header(p: &Problem) -> Vec<String> {
    let mut h: Vec<String> = ["candidate", "phase", "status", "feasible"]
        .map(String::from)
        .to_vec();
    h.extend(p.variables.iter().map(|v| v.key.clone()));
    for g in &p.goals {
        h.extend(goal_columns(g));
    }
    h.extend(p.constraints.iter().map(|c| c.text.clone()));
    h.push("limited_by".into());
    h
}

/// A number's cell (empty when absent).
fn opt(v: Option<f64>) -> String {
    v.filter(|x| x.is_finite()).map(f).unwrap_or_default()
}

/// A candidate's row.
pub(crate) fn row(p: &Problem, c: &Candidate) -> Vec<String> {
    let mut r = vec![
        c.index.to_string(),
        c.phase.clone(),
        c.status.text(),
        c.feasible().to_string(),
    ];
    r.extend(p.variables.iter().zip(&c.values).map(|(v, x)| {
        if v.integer {
            format!("{x:.0}")
        } else {
            f(*x)
        }
    }));
    for (k, g) in p.goals.iter().enumerate() {
        r.push(opt(c.goals[k]));
        if !matches!(g, Goal::Quantity { .. }) {
            r.push(opt(c.scores[k]));
        }
    }
    r.extend(c.constraints.iter().map(|v| opt(*v)));
    r.push(match (&c.limited_by, c.goals.first()) {
        (Some(k), _) => k.clone(),
        (None, Some(None)) if c.scores.first().is_some_and(|s| s.is_some()) => "within spec".into(),
        _ => String::new(),
    });
    r
}

/// A candidate as JSON (values by key, goals and scores by goal name).
pub fn candidate_json(p: &Problem, c: &Candidate) -> Json {
    json!({
        "candidate": c.index,
        "phase": c.phase,
        "status": c.status.text(),
        "feasible": c.feasible(),
        "values": p.variables.iter().zip(&c.values).map(|(v, x)| (v.key.clone(), json!(x))).collect::<serde_json::Map<_, _>>(),
        "goals": p.goals.iter().zip(&c.goals).map(|(g, x)| (g.name(), json!(x))).collect::<serde_json::Map<_, _>>(),
        "scores": p.goals.iter().zip(&c.scores).map(|(g, x)| (g.name(), json!(x))).collect::<serde_json::Map<_, _>>(),
        "constraints": p.constraints.iter().zip(&c.constraints).map(|(k, x)| (k.text.clone(), json!(x))).collect::<serde_json::Map<_, _>>(),
        "limited_by": c.limited_by,
    })
}

/// The texts of `candidates.csv` and `pareto.csv` (module documentation).
///
/// # Errors
/// [`Error::Numerical`] if a row does not fit the header (a bug).
pub fn tables_csv(p: &Problem, o: &Outcome) -> Result<(String, String)> {
    let head = header(p);
    let rows: Vec<Vec<String>> = o.candidates.iter().map(|c| row(p, c)).collect();
    let front: Vec<Vec<String>> = o.front.iter().map(|&i| rows[i].clone()).collect();
    let text = |rows: &[Vec<String>]| -> Result<String> {
        String::from_utf8(super::rows_bytes(&head, rows)?)
            .map_err(|e| Error::numerical("CSV table", e.to_string()))
    };
    Ok((text(&rows)?, text(&front)?))
}

/// The convergence of `o`: `(candidates evaluated, best feasible first goal so far)` from the
/// first feasible candidate on, the goal in its own sense (a life's or B10's score, a
/// quantity's value, maximised or minimised).
pub fn convergence(p: &Problem, o: &Outcome) -> Vec<(f64, f64)> {
    let mut best = f64::INFINITY;
    let mut conv = Vec::new();
    for c in &o.candidates {
        if c.feasible() && c.point.objectives[0].is_finite() {
            best = best.min(c.point.objectives[0]);
        }
        if best.is_finite() {
            let shown = match &p.goals[0] {
                Goal::Quantity {
                    maximise: false, ..
                } => best,
                _ => -best,
            };
            conv.push((c.index as f64 + 1.0, shown));
        }
    }
    conv
}
