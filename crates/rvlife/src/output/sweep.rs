//! A design sweep's results directory (`rvlife sweep`), written all-or-nothing
//! ([`super::staging`]):
//! - `sweep.csv`: the tidy table, one row per design and stage: `design`, the varied keys,
//!   `status`, `accuracy_life_h`, `limited_by`, then every column of `stages.csv` (the
//!   quantity table, [`crate::quantities::STAGE`]); a failed design has one row with its
//!   reason and empty quantities;
//! - `designs.csv`: one row per design: `design`, the varied keys, `status`,
//!   `accuracy_life_h`, `limited_by`, `horizon_h`, `verdict`;
//! - `designs/design_<k>.toml`: each design's config (the base with its keys set, comments
//!   kept): `rvlife run designs/design_3.toml` repeats that study;
//! - `summary.json`: the varied keys and their values, and per design its values, status,
//!   verdict and accuracy life;
//! - `report.html` and `plots/accuracy_life.{svg,png}`: the designs' verdicts and the accuracy
//!   life (or, without a spec, the last stage's lost motion) against the first varied key, one
//!   line per combination of the others.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::{json, Value as Json};

use super::html::{esc, inline_svg, page_head};
use super::{f, write_json, write_rows};
use crate::error::{Error, Result};
use crate::sweep::{Outcome, Vary};

/// A varied key's value as a CSV cell: as the user wrote it (`1.25`, `40`, `paper`).
fn cell(v: &Json) -> String {
    match v {
        Json::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The leading columns of `sweep.csv` and `designs.csv`: `design`, the varied keys, `status`,
/// `accuracy_life_h`, `limited_by`.
fn lead_header(varies: &[Vary]) -> Vec<String> {
    let mut header = vec!["design".to_string()];
    header.extend(varies.iter().map(|v| v.key.clone()));
    header.extend(["status", "accuracy_life_h", "limited_by"].map(String::from));
    header
}

/// An outcome's cells of [`lead_header`] (empty where absent).
fn lead_cells(o: &Outcome) -> Vec<String> {
    let life = o.study.as_ref().ok().and_then(|s| s.life.as_ref());
    let mut cells = vec![o.design.index.to_string()];
    cells.extend(o.design.values.iter().map(|(_, v)| cell(v)));
    cells.push(o.status());
    cells.push(
        life.and_then(|l| l.accuracy_life_h)
            .map(f)
            .unwrap_or_default(),
    );
    cells.push(
        life.and_then(|l| l.limited_by)
            .unwrap_or_default()
            .to_string(),
    );
    cells
}

/// The tidy table of `sweep.csv` (module documentation): header and rows.
pub fn table(varies: &[Vary], outcomes: &[Outcome]) -> (Vec<String>, Vec<Vec<String>>) {
    // The columns of every design's stages (the losses' where any design has them).
    let all: Vec<_> = outcomes
        .iter()
        .filter_map(|o| o.study.as_ref().ok())
        .flat_map(|s| s.stages.iter().map(|x| x.summary.clone()))
        .collect();
    let quantities = crate::quantities::written(&all);
    let (stage_header, _) = crate::quantities::stages_csv_of(&quantities, &[]);
    let mut header = lead_header(varies);
    header.extend(stage_header.iter().cloned());
    let mut rows = Vec::new();
    for o in outcomes {
        let lead = lead_cells(o);
        match &o.study {
            Ok(study) => {
                let stages: Vec<_> = study.stages.iter().map(|s| s.summary.clone()).collect();
                let (_, stage_rows) = crate::quantities::stages_csv_of(&quantities, &stages);
                for r in stage_rows {
                    let mut row = lead.clone();
                    row.extend(r);
                    rows.push(row);
                }
            }
            Err(_) => {
                let mut row = lead;
                row.extend(stage_header.iter().map(|_| String::new()));
                rows.push(row);
            }
        }
    }
    (header, rows)
}

/// Writes the sweep's files (module documentation) into the existing, empty `dir`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub fn write_files(dir: &Path, varies: &[Vary], outcomes: &[Outcome]) -> Result<()> {
    let (header, rows) = table(varies, outcomes);
    write_rows(&dir.join("sweep.csv"), &header, &rows)?;
    let mut header = lead_header(varies);
    header.extend(["horizon_h", "verdict"].map(String::from));
    let verdicts: Vec<String> = outcomes
        .iter()
        .map(|o| match &o.study {
            Ok(s) => s.verdict(),
            Err(e) => format!("failed: {e}"),
        })
        .collect();
    let rows: Vec<Vec<String>> = outcomes
        .iter()
        .zip(&verdicts)
        .map(|(o, verdict)| {
            let horizon = o.study.as_ref().ok().and_then(|s| s.life.as_ref());
            let mut r = lead_cells(o);
            r.push(horizon.map(|l| f(l.horizon_h)).unwrap_or_default());
            r.push(verdict.clone());
            r
        })
        .collect();
    write_rows(&dir.join("designs.csv"), &header, &rows)?;
    let designs = dir.join("designs");
    std::fs::create_dir_all(&designs).map_err(|e| Error::io(&designs, e))?;
    for o in outcomes {
        let p = designs.join(format!("design_{}.toml", o.design.index));
        std::fs::write(&p, &o.design.text).map_err(|e| Error::io(&p, e))?;
    }
    let summary = json!({
        "rvlife_version": env!("CARGO_PKG_VERSION"),
        "varied": varies.iter().map(|v| json!({"key": v.key, "values": v.values})).collect::<Vec<_>>(),
        "designs": outcomes.iter().zip(&verdicts).map(|(o, verdict)| json!({
            "design": o.design.index,
            "values": o.design.values.iter().map(|(k, v)| (k.clone(), v.clone())).collect::<serde_json::Map<_, _>>(),
            "status": o.status(),
            "verdict": verdict,
            "accuracy_life": o.study.as_ref().ok().and_then(|s| s.life.clone()),
        })).collect::<Vec<_>>(),
    });
    write_json(&dir.join("summary.json"), &summary)?;
    report(dir, varies, outcomes, &verdicts)
}

/// The plotted number of a design: its accuracy life (h; a design within spec over its whole
/// horizon at that horizon), or without a spec its last stage's lost motion (arcmin); `None`
/// for a failed design.
fn plotted(o: &Outcome, with_spec: bool) -> Option<f64> {
    let s = o.study.as_ref().ok()?;
    if with_spec {
        let life = s.life.as_ref()?;
        Some(life.accuracy_life_h.unwrap_or(life.horizon_h))
    } else {
        s.stages.last().map(|st| st.summary.lost_motion_arcmin)
    }
}

/// `report.html` and its plot.
fn report(dir: &Path, varies: &[Vary], outcomes: &[Outcome], verdicts: &[String]) -> Result<()> {
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| Error::io(&plots, e))?;
    let with_spec = outcomes
        .iter()
        .any(|o| o.study.as_ref().is_ok_and(|s| s.model.life.any()));
    // The first varied key along x (its position when it is not a number), one curve per
    // combination of the others.
    let x_of = |o: &Outcome| -> f64 {
        let v = &o.design.values[0].1;
        v.as_f64()
            .unwrap_or_else(|| varies[0].values.iter().position(|w| w == v).unwrap_or(0) as f64)
    };
    let mut curves: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for o in outcomes {
        let label: Vec<String> = o.design.values[1..]
            .iter()
            .map(|(k, v)| format!("{} = {}", k.rsplit('.').next().unwrap_or(k), cell(v)))
            .collect();
        let label = if label.is_empty() {
            "designs".to_string()
        } else {
            label.join(", ")
        };
        let k = match curves.iter().position(|c| c.0 == label) {
            Some(k) => k,
            None => {
                curves.push((label, Vec::new()));
                curves.len() - 1
            }
        };
        if let Some(y) = plotted(o, with_spec) {
            curves[k].1.push((x_of(o), y));
        }
    }
    let (what, unit) = if with_spec {
        ("accuracy life", "h")
    } else {
        ("lost motion at the last stage", "arcmin")
    };
    let drawn = curves.iter().any(|c| !c.1.is_empty()) && !varies.is_empty();
    if drawn {
        crate::output::plot::curves_against(
            &plots,
            "accuracy_life",
            &format!("{what} of each design"),
            (&varies[0].key, &format!("{what} ({unit})")),
            &curves,
            &[],
        )?;
    }
    let mut h = String::new();
    page_head(&mut h, "rvlife design sweep");
    let _ = writeln!(
        h,
        "<h1>Design sweep: {} designs</h1>\n<p>Varied: {}.</p>",
        outcomes.len(),
        varies
            .iter()
            .map(|v| format!(
                "<code>{}</code> = {}",
                esc(&v.key),
                esc(&v.values.iter().map(cell).collect::<Vec<_>>().join(", "))
            ))
            .collect::<Vec<_>>()
            .join("; ")
    );
    if drawn {
        let caption = if with_spec {
            "accuracy life against the first varied key; a design within spec over its whole \
             horizon is drawn at that horizon (its row says so); a failed design is not drawn"
        } else {
            "no accuracy spec ([life]) in the config: the last stage's lost motion instead"
        };
        inline_svg(&mut h, &plots.join("accuracy_life.svg"), caption)?;
    }
    h.push_str("<table>\n<tr><th>design</th>");
    for v in varies {
        let _ = write!(h, "<th>{}</th>", esc(&v.key));
    }
    h.push_str("<th>verdict</th></tr>\n");
    for (o, verdict) in outcomes.iter().zip(verdicts) {
        let _ = write!(h, "<tr><td>{}</td>", o.design.index);
        for (_, v) in &o.design.values {
            let _ = write!(h, "<td>{}</td>", esc(&cell(v)));
        }
        let _ = writeln!(h, "<td>{}</td></tr>", esc(verdict));
    }
    h.push_str(
        "</table>\n<p>Files: <code>sweep.csv</code> (one row per design and stage), \
         <code>designs.csv</code>, <code>designs/</code> (each design's config), \
         <code>summary.json</code>, <code>plots/</code>.</p>\n</body>\n</html>\n",
    );
    let path = dir.join("report.html");
    std::fs::write(&path, h).map_err(|e| Error::io(&path, e))
}
