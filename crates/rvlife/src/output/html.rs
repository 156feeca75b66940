//! `report.html`: one self-contained page of a study (inline SVG plots, inline CSS, no script
//! and no network reference), as an engineer reads it: the verdict (the accuracy life against
//! the spec, with the duty), a drawing of the stage, each accuracy quantity against hours with its threshold and the
//! life, the reducer and the model options, the stage table (every quantity of `stages.csv` in
//! its declared order, labels with units, sensible rounding), the accuracy life, the paper
//! comparison (the paper's reducer only) and the detailed plots.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Error, Result};
use crate::quantities::{Quantity, Sense, Value, LIFE, STAGE};
use crate::study::{Study, Summary};

/// Escapes `&`, `<`, `>` and `"` for HTML text and attribute values.
pub(super) fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

pub(super) use super::num;

/// A JSON value as table text (numbers by [`num`], arrays joined, null as a dash).
fn json_text(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Null => "-".into(),
        serde_json::Value::Number(n) => n.as_f64().map_or_else(|| n.to_string(), num),
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Array(a) => a.iter().map(json_text).collect::<Vec<_>>().join(", "),
        other => other.to_string(),
    }
}

/// A two-column table of `(name, value)` rows.
pub(super) fn key_value_table(out: &mut String, rows: &[(String, String)]) {
    out.push_str("<table class=\"kv\">\n");
    for (k, v) in rows {
        let _ = writeln!(out, "<tr><th>{}</th><td>{}</td></tr>", esc(k), esc(v));
    }
    out.push_str("</table>\n");
}

/// The `(key, value)` pairs of a serialisable struct's JSON object (nested objects flattened
/// with `.`).
fn fields(value: &serde_json::Value, prefix: &str, out: &mut Vec<(String, String)>) {
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            let key = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                serde_json::Value::Object(_) => fields(v, &key, out),
                _ => out.push((key, json_text(v))),
            }
        }
    }
}

/// The plots of the accuracy quantities against hours, shown right after the verdict.
const HOURS_PLOTS: [&str; 4] = [
    "te_hours",
    "lost_motion_sources",
    "angular_te_sources",
    "dte_hours",
];

/// A value of a quantity in `unit` as the stage table shows it: arcmin to 4 decimals (1e-4
/// arcmin, 0.4 um at the pitch radius), um to 2, N and MPa whole, N m/arcmin to 1; others by
/// [`num`]. Zero as `0`.
fn rounded(unit: &str, v: f64) -> String {
    let decimals = match unit {
        "arcmin" => 4,
        "um" => 2,
        "N" | "MPa" => 0,
        "N m/arcmin" => 1,
        _ => return num(v),
    };
    let s = format!("{v:.decimals$}");
    let zero = s
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.');
    if zero {
        "0".into()
    } else {
        s
    }
}

/// Starts a report page titled `title`: the document head with its inline style and the
/// heading.
pub(super) fn page_head(h: &mut String, title: &str) {
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>{0}</title>\n<style>\n\
         body {{ font-family: sans-serif; margin: 2em auto; max-width: 1100px; color: #222; }}\n\
         h1 {{ font-size: 1.6em; }} h2 {{ font-size: 1.25em; margin-top: 1.6em; \
         border-bottom: 1px solid #ccc; }}\n\
         table {{ border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }}\n\
         th, td {{ border: 1px solid #ccc; padding: 2px 6px; text-align: right; }}\n\
         th {{ background: #f2f2f2; }} table.kv th {{ text-align: left; }}\n\
         figure {{ margin: 1em 0; }} figure svg {{ max-width: 100%; height: auto; }}\n\
         figcaption {{ font-size: 0.9em; color: #555; }}\n\
         </style>\n</head>\n<body>\n<h1>{0}</h1>\n",
        esc(title)
    );
}

/// Appends the SVG file `path` inline as a figure, captioned with its file name under `plots/`
/// and `caption`. A file without an `<svg` element is skipped.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read.
pub(super) fn inline_svg(h: &mut String, path: &Path, caption: &str) -> Result<()> {
    let svg = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let Some(i) = svg.find("<svg") else {
        return Ok(());
    };
    // Inline SVG in HTML needs no namespace declaration: the page then names no address.
    let body = svg[i..].replacen(" xmlns=\"http://www.w3.org/2000/svg\"", "", 1);
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    let sep = if caption.is_empty() { "" } else { ": " };
    let _ = write!(
        h,
        "<figure id=\"{0}\">\n{1}\n<figcaption>plots/{0}.svg{2}{3}</figcaption>\n</figure>\n",
        esc(stem),
        body.trim_end(),
        sep,
        esc(caption)
    );
    Ok(())
}

/// Writes `report.html` into the results directory `dir`, whose `plots/` already holds the
/// study's SVG plots.
///
/// # Errors
/// [`Error::Io`] if a plot cannot be read or the report cannot be written.
pub(crate) fn write_report(study: &Study, summary: &Summary, dir: &Path) -> Result<()> {
    let m = &study.model;
    let g = &m.cycloid.geometry;
    let mut h = String::with_capacity(2 << 20);
    page_head(&mut h, "rvlife report");
    let _ = writeln!(
        h,
        "<p>rvlife {} &middot; cycloid drive of {} pins, {} disc teeth, ratio i<sub>H</sub> = \
         {:.2} &middot; {} stages up to {:.0} h.</p>",
        summary.rvlife_version,
        g.pins,
        g.disc_teeth(),
        m.reducer.ratio,
        study.stages.len(),
        study.stages.last().map_or(0.0, |s| s.hours)
    );
    // The answer first: the accuracy life against the spec, with the duty it assumes.
    let _ = writeln!(
        h,
        "<h2>Verdict</h2>\n<p class=\"verdict\"><strong>{}</strong></p>",
        esc(&study.verdict())
    );
    let plots = dir.join("plots");
    let stage = plots.join("stage.svg");
    if stage.exists() {
        h.push_str("<h2>The stage</h2>\n");
        inline_svg(
            &mut h,
            &stage,
            "the disc over its pins at crank angle 0, with its crank bores and holes; in red the \
             flank worn most by the last stage",
        )?;
    }
    h.push_str(
        "<h2>Accuracy against hours</h2>\n<p>Each quantity of the spec against the working hours, \
         its threshold dashed and the accuracy life dotted.</p>\n",
    );
    for stem in HOURS_PLOTS {
        let p = plots.join(format!("{stem}.svg"));
        if p.exists() {
            inline_svg(&mut h, &p, "")?;
        }
    }

    h.push_str("<h2>Reducer</h2>\n");
    let mm = |v: f64| num(v * 1e3);
    let um = |v: f64| num(v * 1e6);
    key_value_table(
        &mut h,
        &[
            ("pins Zp".into(), g.pins.to_string()),
            ("disc teeth Zc".into(), g.disc_teeth().to_string()),
            ("pin circle radius (mm)".into(), mm(g.pin_circle_radius)),
            ("pin radius (mm)".into(), mm(g.pin_radius)),
            ("eccentricity (mm)".into(), mm(g.eccentricity)),
            ("disc width (mm)".into(), mm(g.width)),
            (
                "equidistant modification (um)".into(),
                um(m.cycloid.modification.equidistant),
            ),
            (
                "offset modification (um)".into(),
                um(m.cycloid.modification.offset),
            ),
            (
                "rotation modification (arcmin)".into(),
                num(m.cycloid.modification.rotation.to_degrees() * 60.0),
            ),
            ("overall ratio i_H".into(), num(m.reducer.ratio)),
            ("rated torque (N m)".into(), num(m.rating.rated_torque)),
            ("input speed (rpm)".into(), num(m.rating.input_speed_rpm)),
        ],
    );

    if !study.twist_shares.is_empty() {
        h.push_str(
            "<h2>Where the twist goes</h2>\n<p>Each part's share of the new reducer's elastic \
             twist at the rated torque: the twist that goes when that part alone is made rigid \
             (mean over a mesh cycle; the parts share the load through parallel paths, so the \
             shares add to 100 % only nearly).</p>\n",
        );
        let rows: Vec<(String, String)> = study
            .twist_shares
            .iter()
            .map(|s| {
                (
                    s.part.to_string(),
                    format!(
                        "{} % ({} arcmin)",
                        num(100.0 * s.share),
                        num(s.twist * crate::units::ARCMIN_PER_RAD)
                    ),
                )
            })
            .collect();
        key_value_table(&mut h, &rows);
    }

    h.push_str("<h2>Model options</h2>\n");
    let mut opts: Vec<(String, String)> = vec![
        ("wear model".into(), format!("{:?}", m.wear.model)),
        (
            "Archard coefficient (mm^3/(N m))".into(),
            num(summary.archard_coefficient_mm3_per_n_m),
        ),
        (
            "stage hours (h)".into(),
            m.wear
                .stage_hours
                .iter()
                .map(|v| num(*v))
                .collect::<Vec<_>>()
                .join(", "),
        ),
        (
            "profile update interval (h)".into(),
            num(m.wear.update_hours),
        ),
        (
            "STE samples per mesh cycle".into(),
            m.te.samples.to_string(),
        ),
        ("loaded-TE torque (N m)".into(), num(m.te.loaded_torque)),
        (
            "lost-motion measuring torque (% of rated)".into(),
            num(m.te.measuring_torque_fraction * 100.0),
        ),
        (
            "dynamic model".into(),
            if m.dynamics.enabled {
                format!(
                    "on: {} discs, {:?} integrator, rtol {}, {} s simulated",
                    if m.dynamics.params.flexible.is_some() {
                        "flexible"
                    } else {
                        "rigid"
                    },
                    m.dynamics.params.integrator,
                    num(m.dynamics.params.rtol),
                    num(m.dynamics.params.end_time)
                )
            } else {
                "off".into()
            },
        ),
        (
            "FE disc (quasi-static)".into(),
            if m.fem.enabled {
                format!(
                    "on: flank elements {} mm, largest {} mm, {} stations per flank, {} crank angles",
                    mm(m.fem.params.flank_size),
                    mm(m.fem.params.max_size),
                    m.fem.params.stations_per_flank,
                    m.fem.params.crank_angles
                )
            } else {
                "off".into()
            },
        ),
    ];
    if let Some(l) = &summary.validity_limit {
        opts.push((
            "validity limit".into(),
            format!(
                "{} h ({} um of wear): {}",
                num(l.hours),
                num(l.max_wear_um),
                l.reason
            ),
        ));
    }
    key_value_table(&mut h, &opts);

    h.push_str(
        "<h2>Stages</h2>\n<p>One column per stage; every quantity of <code>stages.csv</code>, in \
         its order (the column names there in the last column).</p>\n<table>\n\
         <tr><th>quantity</th>",
    );
    for s in &summary.stages {
        let _ = write!(h, "<th>{} h</th>", num(s.hours));
    }
    h.push_str("<th>column</th></tr>\n");
    // Every quantity of the table but the hours, in the declaration's order.
    let quantities: Vec<&Quantity> = STAGE
        .iter()
        .copied()
        .filter(|q| q.name != "hours")
        .collect();
    for q in quantities {
        let cells: Vec<String> = summary
            .stages
            .iter()
            .map(|s| match s.value(q) {
                Value::Number(v) => rounded(q.unit, v),
                Value::Count(n) => n.to_string(),
                Value::Pair(p) => p.map(|v| rounded(q.unit, v)).join(" to "),
                Value::Absent => "-".to_string(),
            })
            .collect();
        if cells.iter().all(|c| c == "-") {
            continue;
        }
        let label = if q.unit.is_empty() {
            q.label.to_string()
        } else {
            format!("{} ({})", q.label, q.unit)
        };
        let _ = write!(h, "<tr><th>{}</th>", esc(&label));
        for c in cells {
            let _ = write!(h, "<td>{}</td>", esc(&c));
        }
        let _ = writeln!(h, "<td><code>{}</code></td></tr>", esc(q.name));
    }
    h.push_str("</table>\n");

    if let Some(life) = &summary.accuracy_life {
        h.push_str("<h2>Accuracy life</h2>\n");
        let mut rows = vec![(
            "accuracy life".to_string(),
            life.accuracy_life_h.map_or(
                format!("beyond {} h (within spec throughout)", num(life.horizon_h)),
                |v| format!("{} h", num(v.round())),
            ),
        )];
        if let Some(k) = life.limited_by {
            let label = LIFE
                .iter()
                .find(|l| l.key == k)
                .map_or(k, |l| l.quantity.label);
            rows.push(("limited by".into(), label.to_string()));
        }
        for l in &LIFE {
            if let Some(v) = m.life.threshold(l.key) {
                let bound = if l.sense == Sense::AtLeast {
                    "at least"
                } else {
                    "at most"
                };
                rows.push((
                    format!("spec: {}", l.quantity.label),
                    format!("{bound} {} {}", num(v), l.quantity.unit),
                ));
            }
        }
        rows.push(("hours studied".into(), format!("{} h", num(life.horizon_h))));
        key_value_table(&mut h, &rows);
    }

    if let Some(p) = &summary.paper_comparison {
        h.push_str("<h2>Comparison with the paper</h2>\n");
        let mut rows = Vec::new();
        fields(&serde_json::to_value(p).unwrap_or_default(), "", &mut rows);
        key_value_table(&mut h, &rows);
    }

    h.push_str("<h2>Detailed plots</h2>\n");
    let mut svgs: Vec<_> = std::fs::read_dir(&plots)
        .map_err(|e| Error::io(&plots, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .filter(|p| {
            !HOURS_PLOTS
                .iter()
                .chain(&["stage"])
                .any(|s| p.file_stem().is_some_and(|f| f == *s))
        })
        .collect();
    // The order of the study's narrative, then any other plot by name.
    let order = [
        "wear",
        "profile_wear",
        "load",
        "te",
        "te_hours",
        "lost_motion_sources",
        "angular_te_sources",
        "hysteresis",
        "flexible_te_hours",
        "von_mises",
    ];
    let rank = |p: &std::path::PathBuf| {
        let stem = p.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        (
            order.iter().position(|o| *o == stem).unwrap_or(order.len()),
            stem.to_string(),
        )
    };
    svgs.sort_by_key(rank);
    for p in &svgs {
        inline_svg(&mut h, p, "")?;
    }
    h.push_str("</body>\n</html>\n");
    let path = dir.join("report.html");
    std::fs::write(&path, h).map_err(|e| Error::io(&path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_escapes() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1.25), "1.25");
        assert_eq!(num(412.0), "412");
        assert_eq!(num(0.035612345), "0.0356123");
        assert_eq!(num(1.5e-7), "1.5000e-7");
        assert_eq!(esc("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
    }
}
