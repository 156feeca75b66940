//! A Monte Carlo run's verdict in one sentence (B10 and B50 lives against the spec, the
//! fraction within spec at the horizon, the samples analysed; docs/model.md section 12.3), for
//! `report.html`, the console and the page alike.

use std::collections::BTreeMap;

use super::num;
use crate::config::LifeThresholds;
use crate::montecarlo::{life_distribution, life_text, LifeDistribution, SampleRecord};
use crate::quantities::{Sense, LIFE};

/// The verdict line of a whole Monte Carlo run of `records` over the stages `stage_hours`
/// (h) against the spec `spec` (the report's first section).
pub fn verdict(
    records: &[SampleRecord],
    stage_hours: &[f64],
    spec: &crate::config::LifeThresholds,
) -> String {
    let mut status_counts = std::collections::BTreeMap::new();
    for r in records {
        *status_counts.entry(status_key(&r.status)).or_insert(0) += 1;
    }
    verdict_of(
        &life_distribution(records, spec.horizon_h(stage_hours)),
        &status_counts,
        spec,
    )
}

/// A record's status as counted: `ok`, `interference` or `failed`.
pub(crate) fn status_key(status: &str) -> String {
    if status.starts_with("failed") {
        "failed".to_string()
    } else if status.starts_with(crate::montecarlo::REJECTED) {
        crate::montecarlo::REJECTED.to_string()
    } else {
        status.to_string()
    }
}

/// The spec as text: `lost motion 1 arcmin, backlash 1 arcmin` (empty without thresholds).
pub(crate) fn spec_text(spec: &LifeThresholds) -> String {
    LIFE.iter()
        .filter_map(|l| {
            spec.threshold(l.key).map(|v| {
                let bound = if l.sense == Sense::AtLeast {
                    "at least "
                } else {
                    ""
                };
                format!("{} {bound}{} {}", l.quantity.label, num(v), l.quantity.unit)
            })
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The run's verdict in one sentence, from its life distribution `l` (a life beyond what the
/// samples show is said to lie beyond `l.horizon_h`, how far they were followed), its samples'
/// status counts and the spec.
pub(crate) fn verdict_of(
    l: &LifeDistribution,
    status_counts: &BTreeMap<String, usize>,
    spec: &LifeThresholds,
) -> String {
    let horizon = l.horizon_h;
    let total: usize = status_counts.values().sum();
    if l.n == 0 {
        let counts: Vec<String> = status_counts
            .iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        return format!(
            "no sampled reducer could be analysed ({total} samples: {})",
            counts.join(", ")
        );
    }
    let spec_line = spec_text(spec);
    if spec_line.is_empty() {
        return format!(
            "{} of {total} sampled reducers analysed; no accuracy spec ([life]) to judge them by",
            l.n
        );
    }
    let rejected = status_counts
        .get(crate::montecarlo::REJECTED)
        .copied()
        .unwrap_or(0);
    let assembly = if rejected > 0 {
        format!(
            "; {rejected} of {total} rejected at assembly ({:.1} %: no pin grade brings their \
             backlash into the band)",
            100.0 * rejected as f64 / total as f64
        )
    } else {
        String::new()
    };
    format!(
        "B10 accuracy life {} (10 % of the reducers leave the spec by then), B50 {}; {:.0} % \
         within spec at {horizon:.0} h; spec: {spec_line}; {} of {total} samples analysed{assembly}",
        life_text(l.b10_h, l.km_b10_h, horizon),
        life_text(l.b50_h, l.km_b50_h, horizon),
        100.0 * l.censored_fraction,
        l.n
    )
}
