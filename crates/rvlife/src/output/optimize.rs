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

use super::candidates::{candidate_json, goal_columns, plots, row, tables_csv};
use super::html::{esc, inline_svg, page_head};
use super::write_json;
use crate::error::{Error, Result};
use crate::optimize::{FollowUp, Goal, Outcome, Problem};

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
    let dir_plots = dir.join("plots");
    std::fs::create_dir_all(&dir_plots).map_err(|e| Error::io(&dir_plots, e))?;
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
    for plot in plots(p, o, follow) {
        let curves: Vec<(String, Vec<(f64, f64)>)> = plot
            .curves
            .iter()
            .map(|c| (c.name.clone(), c.points.clone()))
            .collect();
        if plot.against_hours {
            curves_against_hours(&dir_plots, plot.stem, plot.title, &plot.y_label, &curves)?;
        } else {
            let joined: Vec<bool> = plot.curves.iter().map(|c| c.joined).collect();
            curves_against(
                &dir_plots,
                plot.stem,
                plot.title,
                (&plot.x_label, &plot.y_label),
                &curves,
                &joined,
            )?;
        }
        inline_svg(
            &mut h,
            &dir_plots.join(format!("{}.svg", plot.stem)),
            plot.caption,
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
