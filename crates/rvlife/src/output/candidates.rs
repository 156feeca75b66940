//! A design search's tables and plots in memory (`rvlife optimize`; the page and Python too):
//! the texts of `candidates.csv` and `pareto.csv` (columns in [`super::optimize`]'s
//! documentation), a candidate as JSON, and the data of the report's four plots
//! ([`plots`]: convergence, Pareto front, accuracy against hours, sensitivity), which the
//! HTML report draws with plotters and the page with its charts.

use std::collections::BTreeMap;

use super::f;
use crate::error::{Error, Result};
use crate::optimize::{Candidate, FollowUp, Goal, Outcome, Problem};

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

/// A candidate as the search's results report it (`summary.json`'s `best` and `start` of
/// `rvlife optimize`, the page's): values by key, goals and scores by goal name, constraints
/// by their text; a goal beyond the horizon, a score or a constraint not evaluated is `null`.
#[derive(Debug, Clone, serde::Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct CandidateSummary {
    /// Its number, from 0 in the order evaluated.
    pub candidate: usize,
    /// The search phase that proposed it (`start`, `sample`, `simplex`, `generation 3`).
    pub phase: String,
    /// `ok` or why its evaluation failed.
    pub status: String,
    /// Evaluated and within every constraint.
    pub feasible: bool,
    /// The varied keys' values, in the keys' units.
    pub values: BTreeMap<String, f64>,
    /// Each goal's value (h for a life or B10, the quantity's unit).
    pub goals: BTreeMap<String, Option<f64>>,
    /// Each goal's score (what the search minimises).
    pub scores: BTreeMap<String, Option<f64>>,
    /// Each constraint's value.
    pub constraints: BTreeMap<String, Option<f64>>,
    /// The `[life]` key of the threshold crossed first, if one is.
    pub limited_by: Option<String>,
}

/// Candidate `c` of the search `p` as [`CandidateSummary`].
pub fn candidate_json(p: &Problem, c: &Candidate) -> CandidateSummary {
    let by_goal = |xs: &[Option<f64>]| -> BTreeMap<String, Option<f64>> {
        p.goals
            .iter()
            .zip(xs)
            .map(|(g, x)| (g.name(), *x))
            .collect()
    };
    CandidateSummary {
        candidate: c.index,
        phase: c.phase.clone(),
        status: c.status.text(),
        feasible: c.feasible(),
        values: p
            .variables
            .iter()
            .zip(&c.values)
            .map(|(v, x)| (v.key.clone(), *x))
            .collect(),
        goals: by_goal(&c.goals),
        scores: by_goal(&c.scores),
        constraints: p
            .constraints
            .iter()
            .zip(&c.constraints)
            .map(|(k, x)| (k.text.clone(), *x))
            .collect(),
        limited_by: c.limited_by.clone(),
    }
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

/// One curve of a search's plot: its legend, its points `(x, y)` in the plot's units and
/// whether the points are joined by a line (false: a cloud of candidates).
#[derive(Debug, Clone, serde::Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS), ts(rename = "SearchCurve"))]
pub struct Curve {
    /// Legend text.
    pub name: String,
    /// Points `(x, y)`, in the order drawn.
    pub points: Vec<(f64, f64)>,
    /// Joined by a line (else markers alone).
    pub joined: bool,
}

/// One plot of a search's report (declared once here for the HTML report and the page).
#[derive(Debug, Clone, serde::Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS), ts(rename = "SearchPlot"))]
pub struct Plot {
    /// File stem in `plots/` (`convergence`, `pareto`, `accuracy`, `sensitivity`).
    pub stem: &'static str,
    /// Title.
    pub title: &'static str,
    /// The x axis's title with its unit (`working hours (h)` when `against_hours`).
    pub x_label: String,
    /// The y axis's title with its unit.
    pub y_label: String,
    /// The x axis is working hours (drawn as the study's plots are).
    pub against_hours: bool,
    /// What the plot shows, one sentence (the figure's caption).
    pub caption: &'static str,
    /// The curves (none empty).
    pub curves: Vec<Curve>,
}

/// The first goal's axis title with its unit: a life's or B10's score, or the quantity.
fn score_label(g: &Goal) -> String {
    match g {
        Goal::Life => "life score (life / horizon; 1 + margin within spec)".to_string(),
        Goal::B10 { .. } => "B10 score (B10 / horizon)".to_string(),
        Goal::Quantity { .. } => g.name(),
    }
}

/// The report's plots of the search `o` with its follow-up (docs/model.md section 19.5), in
/// order and only those with data:
/// - `convergence`: the best feasible first goal so far against the candidates evaluated;
/// - `pareto` (two goals or more): the first goal against the second for the front (sorted
///   along the second goal, joined), the base design and the other feasible candidates
///   (markers); a life or B10 in hours (a score's horizon where the candidate is within spec
///   to it);
/// - `accuracy`: lost motion and backlash (arcmin) against working hours, the best design
///   beside the base;
/// - `sensitivity`: the first goal's score with one key moved either side of the best design,
///   against the move as a fraction of the key's range.
pub fn plots(p: &Problem, o: &Outcome, follow: &FollowUp) -> Vec<Plot> {
    let mut plots = Vec::new();
    let mut push = |plot: Plot| {
        let mut plot = plot;
        plot.curves.retain(|c| !c.points.is_empty());
        if !plot.curves.is_empty() {
            plots.push(plot);
        }
    };
    let curve = |name: &str, points: Vec<(f64, f64)>, joined: bool| Curve {
        name: name.to_string(),
        points,
        joined,
    };
    push(Plot {
        stem: "convergence",
        title: "best feasible design so far",
        x_label: "candidates evaluated".into(),
        y_label: score_label(&p.goals[0]),
        against_hours: false,
        caption: "the first goal of the best feasible candidate so far against the candidates \
                  evaluated",
        curves: vec![curve("best so far", convergence(p, o), true)],
    });
    if p.goals.len() >= 2 {
        let horizon = p.base.life.horizon_h(&p.base.wear.stage_hours);
        let xy = |c: &Candidate| -> Option<(f64, f64)> {
            let v = |k: usize| match &p.goals[k] {
                Goal::Quantity { .. } => c.goals[k],
                _ => c.goals[k].or(c.scores[k].map(|s| s.min(1.0) * horizon)),
            };
            Some((v(1)?, v(0)?))
        };
        let mut front: Vec<(f64, f64)> = o
            .front
            .iter()
            .filter_map(|&i| xy(&o.candidates[i]))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        let others: Vec<(f64, f64)> = o
            .candidates
            .iter()
            .filter(|c| c.feasible() && !o.front.contains(&c.index))
            .filter_map(xy)
            .collect();
        let base: Vec<(f64, f64)> = o
            .start
            .and_then(|i| xy(&o.candidates[i]))
            .into_iter()
            .collect();
        let unit = |k: usize| match &p.goals[k] {
            Goal::Life => "accuracy life (h; the horizon within spec)".to_string(),
            Goal::B10 { .. } => "B10 life (h)".to_string(),
            g => g.name(),
        };
        push(Plot {
            stem: "pareto",
            title: "Pareto front",
            x_label: unit(1),
            y_label: unit(0),
            against_hours: false,
            caption: "the first goal against the second: the front of the feasible candidates, \
                      the base design and the other feasible candidates",
            curves: vec![
                curve("Pareto front", front, true),
                curve("base design", base, false),
                curve("other feasible candidates", others, false),
            ],
        });
    }
    let mut accuracy = Vec::new();
    for (name, s) in [("best", &follow.best), ("base", &follow.start)] {
        let Some(s) = s else { continue };
        let of = |q: fn(&crate::study::Stage) -> f64| -> Vec<(f64, f64)> {
            s.stages.iter().map(|x| (x.hours, q(x))).collect()
        };
        accuracy.push(curve(
            &format!("{name}: lost motion"),
            of(|x| x.summary.lost_motion_arcmin),
            true,
        ));
        accuracy.push(curve(
            &format!("{name}: backlash"),
            of(|x| x.summary.backlash_arcmin),
            true,
        ));
    }
    push(Plot {
        stem: "accuracy",
        title: "accuracy of the best and the base design",
        x_label: "working hours (h)".into(),
        y_label: "arcmin".into(),
        against_hours: true,
        caption: "lost motion and backlash against working hours, the best design beside the base",
        curves: accuracy,
    });
    let best = o.best.map(|i| &o.candidates[i]);
    let sensitivity = follow
        .sensitivity
        .iter()
        .zip(p.variables.iter().enumerate())
        .filter(|(s, _)| s.points.len() >= 2)
        .map(|(s, (k, v))| {
            let at = best.map_or(0.0, |b| b.values[k]);
            let points = s
                .points
                .iter()
                .map(|(x, y)| ((x - at) / (v.hi - v.lo), *y))
                .collect();
            curve(&s.key, points, true)
        })
        .collect();
    push(Plot {
        stem: "sensitivity",
        title: "sensitivity at the best design",
        x_label: "key's change (fraction of its range)".into(),
        y_label: score_label(&p.goals[0]),
        against_hours: false,
        caption: "the first goal with one key moved 5 % of its range either side of the best \
                  design, the others held",
        curves: sensitivity,
    });
    plots
}
