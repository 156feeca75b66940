//! `rvlife optimize`: the design search for accuracy life and the console's summary.

use std::path::Path;

use rvlife::optimize::{Candidate, Goal, Problem, Settings};
use rvlife::Result;

use crate::{progress_bar, sweep::config_text};

/// The command line's `rvlife optimize` (see its help): the search is built and validated,
/// and its whole work checked, before the first study; the first SIGINT stops it after the
/// running candidate and writes what it found.
#[allow(clippy::too_many_arguments)]
pub(crate) fn optimize(
    config: Option<&Path>,
    budget: f64,
    vary: &[String],
    objective: &str,
    constraints: &[String],
    settings: Settings,
    out: &Path,
    force: bool,
) -> Result<()> {
    let (text, origin, base_dir) = config_text(config)?;
    let problem = Problem::new(
        &text,
        &origin,
        base_dir.as_deref(),
        budget,
        vary,
        objective,
        constraints,
        settings,
    )?;
    let staging = rvlife::output::Staging::prepare(out, force)?;
    let start = std::time::Instant::now();
    let pb = progress_bar(settings.evaluations as u64);
    pb.set_message("candidates");
    let best = std::sync::Mutex::new(f64::INFINITY);
    rvlife::output::stop_on_signal(true);
    let outcome = rvlife::optimize::run(
        &problem,
        &|done, total, c: &Candidate| {
            pb.set_length(total as u64);
            pb.set_position(done as u64);
            let mut b = best
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if c.feasible() && c.point.merit() < *b {
                *b = c.point.merit();
                pb.set_message(format!("best {}", goal_text(&problem, c)));
            }
        },
        &rvlife::output::stop_requested,
    );
    rvlife::output::stop_on_signal(false);
    let outcome = outcome?;
    pb.set_message("follow-up");
    let follow = rvlife::optimize::follow_up(&problem, &outcome, &|done, total| {
        pb.set_length(total as u64);
        pb.set_position(done as u64);
    })?;
    pb.set_message("writing");
    staging
        .commit(|dir| rvlife::output::optimize::write_files(dir, &problem, &outcome, &follow))?;
    pb.finish_and_clear();
    say!(
        "rvlife optimize: {} candidates{} ({} feasible), {:.1} s; results in {}",
        outcome.candidates.len(),
        if outcome.stopped {
            " (stopped by the user)"
        } else {
            ""
        },
        outcome.candidates.iter().filter(|c| c.feasible()).count(),
        start.elapsed().as_secs_f64(),
        out.display()
    );
    for (name, i) in [("base", outcome.start), ("best", outcome.best)] {
        let Some(c) = i.map(|i| &outcome.candidates[i]) else {
            if name == "best" {
                say!("no feasible candidate: loosen the constraints or widen the ranges");
            }
            continue;
        };
        let keys: Vec<String> = problem
            .variables
            .iter()
            .zip(&c.values)
            .map(|(v, x)| format!("{} = {}", crate::sweep::short_key(&v.key), fmt(*x)))
            .collect();
        say!(
            "{name:>5} (candidate {}): {}; {}",
            c.index,
            keys.join(", "),
            goal_text(&problem, c)
        );
    }
    if problem.goals.len() > 1 {
        say!(
            "Pareto front: {} candidates (pareto.csv)",
            outcome.front.len()
        );
    }
    Ok(())
}

/// A key's value as the console shows it (6 significant digits).
fn fmt(x: f64) -> String {
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A candidate's goals as the console shows them (`life 2163 h`, `life > 75000 h (margin
/// 12 %)`, `lost_motion_arcmin 0.7201`).
fn goal_text(p: &Problem, c: &Candidate) -> String {
    let horizon = p.base.life.horizon_h(&p.base.wear.stage_hours);
    p.goals
        .iter()
        .enumerate()
        .map(|(k, g)| match (g, c.goals[k], c.scores[k]) {
            (Goal::Life, Some(h), _) => format!("life {h:.0} h"),
            (Goal::Life, None, Some(s)) if s >= 1.0 => {
                format!(
                    "life > {horizon:.0} h (margin {:.1} % there)",
                    100.0 * (s - 1.0)
                )
            }
            (Goal::B10 { .. }, Some(h), _) => format!("B10 {h:.0} h"),
            (Goal::B10 { .. }, None, Some(_)) => format!("B10 > {horizon:.0} h"),
            (g, Some(v), _) => format!("{} {v:.4}", g.name()),
            (g, _, _) => format!("{} -", g.name()),
        })
        .collect::<Vec<_>>()
        .join(", ")
}
