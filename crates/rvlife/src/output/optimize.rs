//! A design search's results directory (`rvlife optimize`), written all-or-nothing
//! ([`super::staging`]):
//! - `candidates.csv`: every candidate in the order evaluated: `candidate`, `phase`,
//!   `status`, `feasible`, the varied keys, each goal's value and score (`accuracy_life_h`
//!   and `life_score`, `b10_h` and `b10_score`, or the quantity), each constraint's quantity
//!   (the column named as the constraint was written), `limited_by`;
//! - `pareto.csv`: the same columns for the feasible candidates no other dominates (with one
//!   goal, the best alone);
//! - `optimum.toml`: the best feasible design's config (the base config with the varied keys
//!   set, comments kept): `rvlife run optimum.toml` repeats its study with every model;
//! - `summary.json`: the search (keys, ranges, goals, constraints, seed, evaluations), the
//!   best and base designs, the front's candidates and the sensitivity;
//! - `report.html` and `plots/`: the convergence, the Pareto front (several goals), the best
//!   design's lost motion and backlash against hours beside the base design's, and the
//!   sensitivity of the first goal to each key at the best design.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::json;

use super::candidates::{candidate_json, goal_columns, row, tables_csv};
use super::html::{esc, inline_svg, page_head};
use super::write_json;
use crate::error::{Error, Result};
use crate::optimize::{Candidate, FollowUp, Goal, Outcome, Problem};

/// Writes the search's files (module documentation) into the existing, empty `dir`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written; the config edit's errors for `optimum.toml`.
pub fn write_files(dir: &Path, p: &Problem, o: &Outcome, follow: &FollowUp) -> Result<()> {
    let (candidates, front) = tables_csv(p, o)?;
    let csv = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| Error::io(&path, e))
    };
    csv("candidates.csv", candidates)?;
    csv("pareto.csv", front)?;
    if let Some(b) = o.best.map(|i| &o.candidates[i]) {
        let mut text = format!(
            "# rvlife optimize: the best feasible design of {} candidates (candidate {}, {}); \
             the varied keys set below\n",
            o.candidates.len(),
            b.index,
            p.variables
                .iter()
                .zip(&b.values)
                .map(|(v, x)| format!("{} = {x}", v.key))
                .collect::<Vec<_>>()
                .join(", ")
        );
        text.push_str(&p.text_of(&b.values, false)?);
        let path = dir.join("optimum.toml");
        std::fs::write(&path, text).map_err(|e| Error::io(&path, e))?;
    }
    let summary = json!({
        "rvlife_version": env!("CARGO_PKG_VERSION"),
        "varied": p.variables.iter().map(|v| json!({"key": v.key, "lo": v.lo, "hi": v.hi, "integer": v.integer})).collect::<Vec<_>>(),
        "goals": p.goals.iter().map(Goal::name).collect::<Vec<_>>(),
        "constraints": p.constraints.iter().map(|c| c.text.clone()).collect::<Vec<_>>(),
        "seed": p.settings.seed,
        "evaluations": p.settings.evaluations,
        "evaluated": o.candidates.len(),
        "stopped": o.stopped,
        "best": o.best.map(|i| candidate_json(p, &o.candidates[i])),
        "start": o.start.map(|i| candidate_json(p, &o.candidates[i])),
        "front": o.front,
        "sensitivity": follow.sensitivity.iter().map(|s| json!({"key": s.key, "points": s.points, "slope": s.slope})).collect::<Vec<_>>(),
    });
    write_json(&dir.join("summary.json"), &summary)?;
    report(dir, p, o, follow)
}

/// `report.html` and its plots.
fn report(dir: &Path, p: &Problem, o: &Outcome, follow: &FollowUp) -> Result<()> {
    use crate::output::plot::{curves_against, curves_against_hours};
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| Error::io(&plots, e))?;
    let goal0 = &p.goals[0];
    let score_label = match goal0 {
        Goal::Life => "life score (life / horizon; 1 + margin within spec)".to_string(),
        Goal::B10 { .. } => "B10 score (B10 / horizon)".to_string(),
        Goal::Quantity { .. } => goal0.name(),
    };
    let mut h = String::new();
    page_head(&mut h, "rvlife design search");
    let _ = writeln!(
        h,
        "<h1>Design search: {} candidates{}</h1>\n<p>Varied: {}. Goal{}: {}. Constraints: {}. \
         Seed {}.</p>",
        o.candidates.len(),
        if o.stopped { " (stopped early)" } else { "" },
        p.variables
            .iter()
            .map(|v| format!("<code>{}</code> in [{}, {}]", esc(&v.key), v.lo, v.hi))
            .collect::<Vec<_>>()
            .join(", "),
        if p.goals.len() > 1 { "s" } else { "" },
        esc(&p
            .goals
            .iter()
            .map(Goal::name)
            .collect::<Vec<_>>()
            .join(", ")),
        if p.constraints.is_empty() {
            "none".to_string()
        } else {
            esc(&p
                .constraints
                .iter()
                .map(|c| c.text.clone())
                .collect::<Vec<_>>()
                .join(", "))
        },
        p.settings.seed
    );
    // Best and base designs.
    h.push_str("<table>\n<tr><th>design</th><th>candidate</th>");
    for v in &p.variables {
        let _ = write!(h, "<th>{}</th>", esc(&v.key));
    }
    for g in &p.goals {
        for c in goal_columns(g) {
            let _ = write!(h, "<th>{}</th>", esc(&c));
        }
    }
    h.push_str("</tr>\n");
    for (name, i) in [("best", o.best), ("base", o.start)] {
        let Some(c) = i.map(|i| &o.candidates[i]) else {
            continue;
        };
        let r = row(p, c);
        let _ = write!(h, "<tr><td>{name}</td><td>{}</td>", c.index);
        for cell in &r[4..4 + p.variables.len()] {
            let _ = write!(h, "<td>{}</td>", esc(cell));
        }
        let goal_cells = p.goals.iter().map(|g| goal_columns(g).len()).sum::<usize>();
        for cell in &r[4 + p.variables.len()..4 + p.variables.len() + goal_cells] {
            let _ = write!(h, "<td>{}</td>", esc(cell));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    // Convergence: the best feasible first goal so far.
    let conv = super::candidates::convergence(p, o);
    if !conv.is_empty() {
        curves_against(
            &plots,
            "convergence",
            "best feasible design so far",
            ("candidates evaluated", &score_label),
            &[("best so far".to_string(), conv)],
        )?;
        inline_svg(
            &mut h,
            &plots.join("convergence.svg"),
            "the first goal of the best feasible candidate so far against the candidates evaluated",
        )?;
    }
    // The Pareto front of the first two goals.
    if p.goals.len() >= 2 && !o.front.is_empty() {
        let xy = |c: &Candidate| -> Option<(f64, f64)> {
            let v = |k: usize| match &p.goals[k] {
                Goal::Quantity { .. } => c.goals[k],
                _ => c.goals[k].or(c.scores[k]
                    .map(|s| s.min(1.0) * p.base.life.horizon_h(&p.base.wear.stage_hours))),
            };
            Some((v(1)?, v(0)?))
        };
        let mut curves = vec![(
            "Pareto front".to_string(),
            o.front
                .iter()
                .filter_map(|&i| xy(&o.candidates[i]))
                .collect(),
        )];
        let others: Vec<(f64, f64)> = o
            .candidates
            .iter()
            .filter(|c| c.feasible() && !o.front.contains(&c.index))
            .filter_map(xy)
            .collect();
        if let Some(s) = o.start.and_then(|i| xy(&o.candidates[i])) {
            curves.push(("base design".to_string(), vec![s]));
        }
        curves.push(("other feasible candidates".to_string(), others));
        curves.retain(|c| !c.1.is_empty());
        let unit = |k: usize| match &p.goals[k] {
            Goal::Life => "accuracy life (h; the horizon within spec)".to_string(),
            Goal::B10 { .. } => "B10 life (h)".to_string(),
            g => g.name(),
        };
        curves_against(
            &plots,
            "pareto",
            "Pareto front",
            (&unit(1), &unit(0)),
            &curves,
        )?;
        inline_svg(
            &mut h,
            &plots.join("pareto.svg"),
            "the first goal against the second: the front of the feasible candidates, the base \
             design and the other feasible candidates",
        )?;
    }
    // Accuracy against hours, best beside base.
    let mut curves = Vec::new();
    for (name, s) in [("best", &follow.best), ("base", &follow.start)] {
        let Some(s) = s else { continue };
        curves.push((
            format!("{name}: lost motion"),
            s.stages
                .iter()
                .map(|x| (x.hours, x.summary.lost_motion_arcmin))
                .collect(),
        ));
        curves.push((
            format!("{name}: backlash"),
            s.stages
                .iter()
                .map(|x| (x.hours, x.summary.backlash_arcmin))
                .collect(),
        ));
    }
    if !curves.is_empty() {
        curves_against_hours(
            &plots,
            "accuracy",
            "accuracy of the best and the base design",
            "arcmin",
            &curves,
        )?;
        inline_svg(
            &mut h,
            &plots.join("accuracy.svg"),
            "lost motion and backlash against working hours, the best design beside the base",
        )?;
    }
    // Sensitivity at the best design.
    let sens: Vec<(String, Vec<(f64, f64)>)> = follow
        .sensitivity
        .iter()
        .zip(&p.variables)
        .filter(|(s, _)| s.points.len() >= 2)
        .map(|(s, v)| {
            let best = o.best.map_or(0.0, |i| {
                o.candidates[i].values[p.variables.iter().position(|w| w.key == v.key).unwrap_or(0)]
            });
            (
                s.key.clone(),
                s.points
                    .iter()
                    .map(|(x, y)| ((x - best) / (v.hi - v.lo), *y))
                    .collect(),
            )
        })
        .collect();
    if !sens.is_empty() {
        curves_against(
            &plots,
            "sensitivity",
            "sensitivity at the best design",
            ("key's change (fraction of its range)", &score_label),
            &sens,
        )?;
        inline_svg(
            &mut h,
            &plots.join("sensitivity.svg"),
            "the first goal with one key moved 5 % of its range either side of the best design, \
             the others held",
        )?;
    }
    h.push_str(
        "<p>Files: <code>candidates.csv</code> (every candidate), <code>pareto.csv</code>, \
         <code>optimum.toml</code> (the best design's config), <code>summary.json</code>, \
         <code>plots/</code>.</p>\n</body>\n</html>\n",
    );
    let path = dir.join("report.html");
    std::fs::write(&path, h).map_err(|e| Error::io(&path, e))
}
