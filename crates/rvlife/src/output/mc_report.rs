//! A Monte Carlo run's plots and `report.html`: the verdict (B10 and B50 lives against the
//! spec, the fraction within spec at the horizon), the samples' status, the reliability curve
//! (survivors included), the accuracy life's table and histogram, each accuracy quantity's fan
//! chart against hours with its spec line, and the last stage's histograms where the samples
//! differ (docs/model.md section 12.3).

use std::fmt::Write as _;
use std::path::Path;

use super::html::{esc, inline_svg, key_value_table, num, page_head};
pub use super::mc_shards::ShardMeta;
pub use super::mc_verdict::verdict;
pub(crate) use super::mc_verdict::{spec_text, status_key, verdict_of};
use crate::config::LifeThresholds;
use crate::error::{Error, Result};
use crate::montecarlo::{
    life_text, reliability, weibull, weibull_sample, LifeDistribution, Percentiles, Plan,
    SampleRecord,
};

/// Fractions out of spec at which the Weibull plot's confidence band is drawn.
const WEIBULL_BAND_FRACTIONS: [f64; 11] =
    [0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.632, 0.8, 0.9, 0.99];
use crate::quantities::{Quantity, ACCURACY, LIFE};
use serde::Serialize;

/// `summary.json` of a Monte Carlo run.
#[derive(Debug, Clone, Serialize)]
pub struct McSummary {
    /// rvlife version.
    pub rvlife_version: &'static str,
    /// Samples, seed and options.
    pub plan: Plan,
    /// Samples by status: ok, interference, failed.
    pub status_counts: std::collections::BTreeMap<String, usize>,
    /// The accuracy life's distribution (with `[life]` thresholds).
    pub life: LifeDistribution,
    /// Percentiles of every quantity at every stage.
    pub percentiles: Vec<Percentiles>,
    /// Standard error of a percentile `p` estimated from `n` samples, relative to the
    /// quantity's spread: `sqrt(p (1-p) / n) / f(x_p)`; for a normal quantity this is
    /// `1.25 sigma / sqrt(n)` at the median and `2.11 sigma / sqrt(n)` at 5 and 95 %.
    pub percentile_standard_error_note: &'static str,
}

/// The `[life]` spec of a config's text, read from its `[life]` table alone (so that a config
/// whose other tables name files elsewhere still gives its spec); empty without one, or where
/// the table does not parse (the run itself validated it).
pub(crate) fn spec_of(config_toml: &str) -> LifeThresholds {
    let Ok(table) = config_toml.parse::<toml::Table>() else {
        return LifeThresholds::default();
    };
    table
        .get("life")
        .cloned()
        .and_then(|v| v.try_into::<crate::config::LifeConfig>().ok())
        .and_then(|c| c.validate().ok())
        .unwrap_or_default()
}

/// The `[life]` threshold on quantity `q`, if the spec sets one.
fn limit_on(spec: &LifeThresholds, q: &Quantity) -> Option<f64> {
    LIFE.iter()
        .find(|l| l.quantity.name == q.name)
        .and_then(|l| spec.threshold(l.key))
}

/// Whether the samples' values spread (a histogram of identical values is one bar).
fn spreads(values: &[f64]) -> bool {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    hi - lo > 1e-9 * hi.abs().max(lo.abs()).max(1e-12)
}

/// Writes the plots of a whole Monte Carlo run into `dir/plots` and its `report.html`.
///
/// # Errors
/// [`Error::Io`] if a file cannot be written.
pub(crate) fn write(
    dir: &Path,
    meta: &ShardMeta,
    records: &[SampleRecord],
    summary: &McSummary,
) -> Result<()> {
    let spec = spec_of(&meta.config_toml);
    let horizon = spec.horizon_h(&meta.stage_hours);
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| Error::io(&plots, e))?;
    let life = &summary.life;
    // How far the samples were followed: the horizon unless every life search ended sooner.
    let followed = life.horizon_h;
    let mut figures: Vec<(String, String, String)> = Vec::new();
    let mut figure = |section: &str, stem: &str, caption: String| {
        figures.push((section.to_string(), stem.to_string(), caption));
    };
    let has_spec = !spec_text(&spec).is_empty();
    if has_spec && life.n > 0 {
        let curve = reliability(records, horizon);
        crate::output::plot::reliability_curve(
            &plots,
            "reliability",
            &curve,
            &[("B10", life.b10_h), ("B50", life.b50_h)],
        )?;
        figure(
            "reliability",
            "reliability",
            format!(
                "fraction of the {} analysed reducers within spec against working hours; the {:.0} \
                 % still within spec at {followed:.0} h are counted throughout",
                life.n,
                100.0 * life.censored_fraction
            ),
        );
    }
    if let Some(w) = &life.weibull {
        let (positive, censored) = weibull_sample(records, horizon);
        let fit = weibull::Weibull {
            shape: w.shape,
            scale: w.scale_h,
        };
        let bands: Vec<(f64, weibull::BoundedQuantile)> = WEIBULL_BAND_FRACTIONS
            .iter()
            .filter_map(|&p| {
                weibull::quantile_with_bounds(&positive, &censored, p, w.confidence).map(|q| (p, q))
            })
            .collect();
        crate::output::plot::weibull_plot(
            &plots,
            "weibull",
            &weibull::kaplan_meier(&positive, &censored),
            &fit,
            &bands,
            w.confidence,
        )?;
        let upper =
            |u: Option<f64>| u.map_or("not bounded above".to_string(), |u| format!("{u:.0} h"));
        let first = censored
            .iter()
            .copied()
            .reduce(f64::min)
            .unwrap_or(followed);
        let censored_at = if first < followed {
            format!("where their life searches ended ({first:.0} to {followed:.0} h)")
        } else {
            format!("at {followed:.0} h")
        };
        figure(
            "life",
            "weibull",
            format!(
                "Weibull plot (IEC 61649): the {} positive lives by Kaplan-Meier with the {} \
                 censored {censored_at}, the maximum-likelihood line (shape {:.2}, scale {:.0} \
                 h) and its {:.0} % likelihood-ratio bounds; B10 {:.0} h [{:.0} h, {}], B50 {:.0} \
                 h [{:.0} h, {}]",
                positive.len(),
                censored.len(),
                w.shape,
                w.scale_h,
                100.0 * w.confidence,
                w.b10_h,
                w.b10_lower_h,
                upper(w.b10_upper_h),
                w.b50_h,
                w.b50_lower_h,
                upper(w.b50_upper_h),
            ),
        );
    }
    let lives: Vec<f64> = records
        .iter()
        .filter(|r| r.status == "ok")
        .filter_map(|r| r.accuracy_life_h)
        .collect();
    if !lives.is_empty() {
        let survivors = life.n - lives.len();
        let marks: Vec<(String, f64)> = [("B10", life.b10_h), ("B50", life.b50_h)]
            .iter()
            .filter_map(|(n, v)| v.map(|x| (n.to_string(), x)))
            .collect();
        let named: Vec<String> = marks
            .iter()
            .zip(["red", "magenta"])
            .map(|((n, x), c)| format!("{n} {x:.0} h {c}"))
            .collect();
        crate::output::plot::histogram(
            &plots,
            "life_histogram",
            &format!(
                "Accuracy life: {} of {} reducers left the spec{}",
                lives.len(),
                life.n,
                if named.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", named.join(", "))
                }
            ),
            "accuracy life (h)",
            &lives,
            30,
            &marks,
        )?;
        figure(
            "life",
            "life_histogram",
            format!(
                "the lives of the {} reducers that left the spec within {followed:.0} h; {survivors} \
                 more stayed within it (not drawn)",
                lives.len()
            ),
        );
    }
    for q in ACCURACY {
        let Some(f) = q.accuracy else {
            continue;
        };
        let rows: Vec<_> = summary
            .percentiles
            .iter()
            .filter(|x| x.quantity == q.name)
            .collect();
        let col = |g: fn(&crate::montecarlo::Percentiles) -> f64| {
            rows.iter().map(|x| g(x)).collect::<Vec<f64>>()
        };
        let unit = if q.unit.is_empty() {
            String::new()
        } else {
            format!(" ({})", q.unit)
        };
        let limit = limit_on(&spec, q);
        if !rows.is_empty() && rows.iter().all(|x| x.n > 0) {
            let stem = format!("fan_{}", q.name);
            crate::output::plot::fan_chart(
                &plots,
                &stem,
                &format!("{}: median and 5-95 % of the sampled reducers", q.label),
                &format!("{}{unit}", q.label),
                &col(|x| x.hours),
                [&col(|x| x.p5), &col(|x| x.p50), &col(|x| x.p95)],
                limit,
            )?;
            figure(
                "fans",
                &stem,
                limit.map_or(String::new(), |v| {
                    format!("dashed: the spec, {} {}", num(v), q.unit)
                }),
            );
        }
        let last: Vec<f64> = records
            .iter()
            .filter(|r| r.status == "ok")
            .filter_map(|r| {
                r.points
                    .get(meta.stage_hours.len().saturating_sub(1))
                    .map(f)
            })
            .collect();
        if !last.is_empty() && spreads(&last) {
            let stem = format!("hist_{}", q.name);
            let marks: Vec<(String, f64)> = limit.iter().map(|v| ("spec".into(), *v)).collect();
            crate::output::plot::histogram(
                &plots,
                &stem,
                &format!(
                    "{} at {:.0} h{}",
                    q.label,
                    meta.stage_hours.last().copied().unwrap_or(0.0),
                    if marks.is_empty() { "" } else { " (spec: red)" }
                ),
                &format!("{}{unit}", q.label),
                &last,
                30,
                &marks,
            )?;
            figure("last", &stem, String::new());
        }
    }
    // The page.
    let mut h = String::with_capacity(1 << 20);
    page_head(&mut h, "rvlife Monte Carlo report");
    let _ = writeln!(
        h,
        "<h2>Verdict</h2>\n<p class=\"verdict\"><strong>{}</strong></p>",
        esc(&verdict_of(&summary.life, &summary.status_counts, &spec))
    );
    h.push_str("<h2>Spec and samples</h2>\n");
    let mut rows = vec![(
        "accuracy spec ([life])".to_string(),
        if has_spec {
            spec_text(&spec)
        } else {
            "none".into()
        },
    )];
    rows.push(("life search horizon".into(), format!("{horizon:.0} h")));
    let total: usize = summary.status_counts.values().sum();
    rows.push(("samples".into(), total.to_string()));
    for (status, n) in &summary.status_counts {
        let what = match status.as_str() {
            "ok" => "analysed",
            "interference" => "interference (cannot be assembled without preload)",
            "failed" => "failed (the analysis stopped; points before it kept)",
            other => other,
        };
        rows.push((format!("  {what}"), n.to_string()));
    }
    rows.push(("seed".into(), summary.plan.seed.to_string()));
    rows.push((
        "wear".into(),
        if summary.plan.full_wear {
            "each sample's own".into()
        } else {
            "the nominal reducer's, shared".into()
        },
    ));
    key_value_table(&mut h, &rows);
    let figures_of = |h: &mut String, section: &str| -> Result<()> {
        for (s, stem, caption) in &figures {
            if s == section {
                inline_svg(h, &plots.join(format!("{stem}.svg")), caption)?;
            }
        }
        Ok(())
    };
    if has_spec && life.n > 0 {
        h.push_str("<h2>Reliability</h2>\n");
        figures_of(&mut h, "reliability")?;
        h.push_str("<h2>Accuracy life</h2>\n");
        let hh =
            |v: Option<f64>| v.map_or(format!("beyond {followed:.0} h"), |x| format!("{x:.0} h"));
        let mut rows = vec![
            (
                "5 % of the reducers out of spec by".to_string(),
                hh(life.p5_h),
            ),
            (
                "B10 (10 %)".into(),
                life_text(life.b10_h, life.km_b10_h, followed),
            ),
            (
                "B50 (median)".into(),
                life_text(life.b50_h, life.km_b50_h, followed),
            ),
            ("95 %".into(), hh(life.p95_h)),
            (
                format!("within spec at {followed:.0} h"),
                format!("{:.1} %", 100.0 * life.censored_fraction),
            ),
        ];
        for (k, n) in &life.limited_by {
            let label = LIFE
                .iter()
                .find(|l| l.key == k)
                .map_or(k.as_str(), |l| l.quantity.label);
            rows.push((format!("limited by {label}"), format!("{n} reducers")));
        }
        key_value_table(&mut h, &rows);
        h.push_str(&format!("<p>{}.</p>\n", esc(&life.weibull_text())));
        figures_of(&mut h, "life")?;
    }
    h.push_str("<h2>Accuracy against hours</h2>\n");
    figures_of(&mut h, "fans")?;
    let last_h = meta.stage_hours.last().copied().unwrap_or(0.0);
    let _ = writeln!(h, "<h2>At the last stage, {last_h:.0} h</h2>");
    h.push_str(
        "<table>\n<tr><th>quantity</th><th>p5</th><th>p50</th><th>p95</th><th>mean</th></tr>\n",
    );
    for q in ACCURACY {
        if let Some(p) = summary
            .percentiles
            .iter()
            .find(|x| x.quantity == q.name && x.hours == last_h)
        {
            let _ = writeln!(
                h,
                "<tr><th>{} ({})</th><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(q.label),
                esc(q.unit),
                num(p.p5),
                num(p.p50),
                num(p.p95),
                num(p.mean)
            );
        }
    }
    h.push_str("</table>\n");
    figures_of(&mut h, "last")?;
    h.push_str(
        "<p>Files: <code>samples.csv</code>, <code>stages.csv</code>, \
         <code>percentiles.csv</code>, <code>summary.json</code>, <code>config.toml</code>, \
         <code>plots/</code>.</p>\n</body>\n</html>\n",
    );
    let path = dir.join("report.html");
    std::fs::write(&path, h).map_err(|e| Error::io(&path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spec comes from the `[life]` table alone; a text without one gives none.
    #[test]
    fn spec_from_the_life_table() {
        let s = spec_of("[life]\nlost_motion_arcmin = 1.0\nmax_hours = 9000.0\n[wear]\nx = 1\n");
        assert_eq!(s.lost_motion_arcmin, Some(1.0));
        assert_eq!(s.horizon_h(&[0.0, 7500.0]), 9000.0);
        assert_eq!(spec_text(&s), "lost motion 1 arcmin");
        let none = spec_of("[wear]\nx = 1\n");
        assert!(spec_text(&none).is_empty());
        assert_eq!(none.horizon_h(&[0.0, 7500.0]), 75000.0);
    }
}
