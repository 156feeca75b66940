//! The accuracy-life distribution of a Monte Carlo run (docs/model.md section 12.3): the
//! empirical quantiles of the lives, the Kaplan-Meier quantiles and the Weibull fit with its
//! likelihood-ratio bounds ([`super::weibull`]), and their sentences.

use serde::Serialize;

use super::weibull;
use super::SampleRecord;

/// The accuracy-life distribution over the records with status `ok`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct LifeDistribution {
    /// Samples counted.
    pub n: usize,
    /// Fraction whose life exceeds the horizon (censored: the last stage, or `life.max_hours`
    /// beyond it, or where the wear model leaves its validity).
    pub censored_fraction: f64,
    /// B10 life: the hours by which 10 % have left the spec, h, interpolated between the
    /// sorted lives (absent: the interpolation reaches a censored sample; see `km_b10_h`).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub b10_h: Option<f64>,
    /// B50 (median) life, h (absent: the interpolation reaches a censored sample).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub b50_h: Option<f64>,
    /// 5th percentile of the life, h (absent: fewer than 5 % within the horizon).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub p5_h: Option<f64>,
    /// 95th percentile of the life, h (absent: fewer than 95 % within the horizon).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub p95_h: Option<f64>,
    /// How many samples each threshold limited.
    pub limited_by: std::collections::BTreeMap<String, usize>,
    /// Samples that left the spec within the horizon (the failures of the life statistics;
    /// the others are censored where their life search ended, `SampleRecord::censored_h`).
    pub failures: usize,
    /// How far the samples were followed, h: the latest of their lives and censoring times
    /// (the life search's horizon, unless every sample's search ended sooner); a B10 or B50
    /// that the samples do not reach lies beyond it.
    pub horizon_h: f64,
    /// Kaplan-Meier B10, h: the first life by which 10 % of the samples had left the spec, so
    /// that B10 is at most this (absent: fewer than 10 % by the horizon, B10 beyond it).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub km_b10_h: Option<f64>,
    /// Kaplan-Meier B50, h (absent: fewer than half by the horizon, B50 beyond it).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub km_b50_h: Option<f64>,
    /// The Weibull fit with its B10 and B50 and their bounds (absent: fewer than
    /// [`weibull::MIN_FAILURES`] failures, or no maximum of the likelihood).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub weibull: Option<WeibullLife>,
}

/// The two-parameter Weibull distribution of the samples' lives by maximum likelihood with the
/// censored samples, and its B10 and B50 with two-sided likelihood-ratio bounds
/// ([`weibull::quantile_with_bounds`]; IEC 61649:2008; docs/model.md section 12.3).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct WeibullLife {
    /// Shape `beta`.
    pub shape: f64,
    /// Scale `eta` (the life by which 63.2 % leave the spec), h.
    pub scale_h: f64,
    /// Confidence of the two-sided bounds (0.9: the 5 % and 95 % bounds).
    pub confidence: f64,
    /// B10 of the fit, h.
    pub b10_h: f64,
    /// Lower bound of B10, h.
    pub b10_lower_h: f64,
    /// Upper bound of B10, h (absent: the samples do not bound it from above).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub b10_upper_h: Option<f64>,
    /// B50 of the fit, h.
    pub b50_h: f64,
    /// Lower bound of B50, h.
    pub b50_lower_h: f64,
    /// Upper bound of B50, h (absent: the samples do not bound it from above).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub b50_upper_h: Option<f64>,
}

/// Confidence of the Weibull bounds the runs report (two-sided: 5 % and 95 %).
pub const LIFE_CONFIDENCE: f64 = 0.9;

/// The accuracy lives (h, ascending) of the `ok` records of `records` that left the spec, and
/// the censoring times of those that did not (in the records' order): where each one's life
/// search ended within spec (`censored_h`: the horizon, or sooner where its analysis or the
/// shared wear history ended), or, for records without one (shards of earlier versions), the
/// run's horizon `horizon` (h), or the longest life where that lies beyond it.
pub fn lives_and_censored(records: &[SampleRecord], horizon: f64) -> (Vec<f64>, Vec<f64>) {
    let ok: Vec<&SampleRecord> = records.iter().filter(|r| r.status == "ok").collect();
    let mut lives: Vec<f64> = ok.iter().filter_map(|r| r.accuracy_life_h).collect();
    lives.sort_by(f64::total_cmp);
    let fallback = horizon.max(lives.last().copied().unwrap_or(0.0));
    let censored = ok
        .iter()
        .filter(|r| r.accuracy_life_h.is_none())
        .map(|r| r.censored_h.unwrap_or(fallback))
        .collect();
    (lives, censored)
}

/// How far the samples of a run were followed, h: the latest of their lives and censoring
/// times (`lives`, `censored`), or, with no sample censored (all out of spec), the latest life
/// or the horizon `horizon` (h), whichever is later. A quantile the Kaplan-Meier estimate does
/// not reach lies beyond it; it is the run's horizon unless every life search ended sooner.
pub(crate) fn followed_to(lives: &[f64], censored: &[f64], horizon: f64) -> f64 {
    let latest = lives.iter().chain(censored).copied().reduce(f64::max);
    match latest {
        Some(t) if !censored.is_empty() => t,
        _ => horizon.max(latest.unwrap_or(0.0)),
    }
}

/// The reliability curve of the records with status `ok`: `(hours, fraction within spec)` at
/// 0 h and at every observed accuracy life (a step down there, both ends of each step given),
/// ending where the samples were followed to ([`followed_to`]: the horizon `horizon`,
/// h, unless every search ended sooner). It is the Kaplan-Meier estimate of the survival
/// with each sample that never left the spec censored where its search ended
/// (`SampleRecord::censored_h`); with every censoring time after the last life, the usual
/// case, that is exactly `R(t) = 1 - #{life <= t}/n`, computed so (docs/model.md section 12).
/// Empty without `ok` records.
pub fn reliability(records: &[SampleRecord], horizon: f64) -> Vec<(f64, f64)> {
    let n = records.iter().filter(|r| r.status == "ok").count();
    if n == 0 {
        return Vec::new();
    }
    let (lives, censored) = lives_and_censored(records, horizon);
    let last_life = lives.last().copied().unwrap_or(0.0);
    let km = censored
        .iter()
        .any(|&c| c < last_life)
        .then(|| weibull::kaplan_meier(&lives, &censored));
    // The Kaplan-Meier steps are at the distinct lives, ascending: the loop's own order.
    let mut steps = km.iter().flatten();
    let mut out = vec![(0.0, 1.0)];
    let mut gone = 0;
    for (i, &t) in lives.iter().enumerate() {
        gone += 1;
        if lives.get(i + 1) == Some(&t) {
            continue;
        }
        let before = out.last().map_or(1.0, |p| p.1);
        let after = match steps.next() {
            Some(&(_, s)) => s,
            None => 1.0 - gone as f64 / n as f64,
        };
        out.push((t, before));
        out.push((t, after));
    }
    let last = out.last().map_or(1.0, |p| p.1);
    out.push((followed_to(&lives, &censored, horizon), last));
    out
}

/// The sample the Weibull law is fitted to ([`lives_and_censored`]): the positive lives (a life
/// of 0 h, out of spec when new, is a failure before any time the Weibull law can hold) and
/// the censoring times.
pub fn weibull_sample(records: &[SampleRecord], horizon: f64) -> (Vec<f64>, Vec<f64>) {
    let (lives, censored) = lives_and_censored(records, horizon);
    (positive(&lives), censored)
}

/// The positive ones of `lives` (h): those the Weibull law is fitted to.
fn positive(lives: &[f64]) -> Vec<f64> {
    lives.iter().copied().filter(|&t| t > 0.0).collect()
}

/// The life distribution of `records` whose life search ran to `horizon` (h): empirical
/// quantiles with the censored lives counted as longer than every observed one (a quantile
/// only where every censored sample was followed beyond it), the Kaplan-Meier B10 and B50, and
/// the Weibull fit with its bounds ([`WeibullLife`]), each sample censored where its search
/// ended ([`lives_and_censored`]).
pub fn life_distribution(records: &[SampleRecord], horizon: f64) -> LifeDistribution {
    let ok: Vec<&SampleRecord> = records.iter().filter(|r| r.status == "ok").collect();
    let (lives, censored) = lives_and_censored(records, horizon);
    let n = ok.len();
    let q = |p: f64| {
        // Position of the p-quantile among all n (censored at the top: valid where every
        // censored sample was followed at least that far).
        let h = (n.saturating_sub(1)) as f64 * p;
        if n == 0 || h.ceil() as usize >= lives.len() {
            None
        } else {
            let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
            let v = lives[lo] + (h - lo as f64) * (lives[hi] - lives[lo]);
            censored.iter().all(|&c| c >= v).then_some(v)
        }
    };
    let mut limited_by = std::collections::BTreeMap::new();
    for r in &ok {
        if let Some(k) = &r.limited_by {
            *limited_by.entry(k.clone()).or_insert(0) += 1;
        }
    }
    let km = weibull::kaplan_meier(&lives, &censored);
    let positive = positive(&lives);
    let bounded = |p: f64| weibull::quantile_with_bounds(&positive, &censored, p, LIFE_CONFIDENCE);
    let weibull = weibull::fit(&positive, &censored).and_then(|w| {
        let (b10, b50) = (bounded(0.1)?, bounded(0.5)?);
        Some(WeibullLife {
            shape: w.shape,
            scale_h: w.scale,
            confidence: LIFE_CONFIDENCE,
            b10_h: b10.estimate,
            b10_lower_h: b10.lower,
            b10_upper_h: b10.upper,
            b50_h: b50.estimate,
            b50_lower_h: b50.lower,
            b50_upper_h: b50.upper,
        })
    });
    LifeDistribution {
        n,
        censored_fraction: if n > 0 {
            (n - lives.len()) as f64 / n as f64
        } else {
            0.0
        },
        b10_h: q(0.1),
        b50_h: q(0.5),
        p5_h: q(0.05),
        p95_h: q(0.95),
        limited_by,
        failures: lives.len(),
        horizon_h: followed_to(&lives, &censored, horizon),
        km_b10_h: weibull::kaplan_meier_quantile(&km, 0.1),
        km_b50_h: weibull::kaplan_meier_quantile(&km, 0.5),
        weibull,
    }
}

/// A life for a sentence: the estimate where there is one (`x h`), else at most the
/// Kaplan-Meier quantile (`at most x h`: that many samples had left the spec by then), else
/// beyond the horizon.
pub fn life_text(estimate: Option<f64>, km: Option<f64>, horizon: f64) -> String {
    match (estimate, km) {
        (Some(x), _) => format!("{x:.0} h"),
        (None, Some(k)) => format!("at most {k:.0} h"),
        (None, None) => format!("beyond {horizon:.0} h"),
    }
}

impl LifeDistribution {
    /// The Weibull fit in a sentence: shape, scale, B10 and B50 with their bounds, or why
    /// there is none.
    pub fn weibull_text(&self) -> String {
        let bound = |u: Option<f64>| u.map_or("unbounded".to_string(), |u| format!("{u:.0}"));
        match &self.weibull {
            Some(w) => {
                format!(
                "Weibull fit (maximum likelihood, {}): shape {:.2}, scale {:.0} h; B10 {:.0} h \
                 [{:.0}, {}], B50 {:.0} h [{:.0}, {}] ({:.0} % two-sided likelihood-ratio \
                 bounds, IEC 61649)",
                if self.failures == self.n {
                    format!("all {} samples out of spec within {:.0} h", self.n, self.horizon_h)
                } else {
                    format!(
                        "{} of {} samples out of spec within {:.0} h, the others censored there",
                        self.failures, self.n, self.horizon_h
                    )
                },
                w.shape,
                w.scale_h,
                w.b10_h,
                w.b10_lower_h,
                bound(w.b10_upper_h),
                w.b50_h,
                w.b50_lower_h,
                bound(w.b50_upper_h),
                100.0 * w.confidence
            )
            }
            None => format!(
                "no Weibull fit: {} of {} samples out of spec within {:.0} h (at least {} with \
                 a positive life are needed)",
                self.failures,
                self.n,
                self.horizon_h,
                weibull::MIN_FAILURES
            ),
        }
    }
}
