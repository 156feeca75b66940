//! Life statistics of a Monte Carlo run with right-censored samples (docs/model.md section
//! 12.3): the Kaplan-Meier estimate of the survival and its quantiles, and the two-parameter
//! Weibull distribution fitted by maximum likelihood with the censored samples, its `B_p` lives
//! with two-sided likelihood-ratio confidence bounds (IEC 61649:2008, Weibull analysis,
//! sections 10-11; Lawless, *Statistical Models and Methods for Lifetime Data*, 2nd ed., 2003,
//! sections 5.2 and 3.2 for the Kaplan-Meier estimate).
//!
//! A sample that leaves the spec gives a failure time; one that does not within the life
//! search gives a censoring time (it is known to last longer). Times are in any one unit (h);
//! every computation is made on times divided by the largest, which moves the log-likelihood
//! by a constant and so changes neither the estimates nor the likelihood-ratio bounds.

use argmin::core::{CostFunction, Executor, State, TerminationReason, TerminationStatus};
use argmin::solver::brent::BrentRoot;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Fewest failures for a Weibull fit: with one failure the shape is not determined by the
/// data (IEC 61649 section 10 asks for several failures).
pub const MIN_FAILURES: usize = 2;

/// Shapes searched, `[1/SHAPE_RANGE, SHAPE_RANGE]`: wear-out lives of a tolerance population
/// lie well inside (shapes of 1 to 20 are typical of mechanical wear-out).
const SHAPE_RANGE: f64 = 1e3;

/// The Kaplan-Meier estimate of the survival of `failures` and `censored` times (Lawless eq.
/// 3.2.2): `S(t) = prod over failure times t_j <= t of (1 - d_j / n_j)`, `d_j` failures at
/// `t_j` and `n_j` samples still at risk just before it (a censoring time equal to a failure
/// time counts as at risk, the usual convention). Returns the steps `(t_j, S(t_j))` in
/// ascending time; empty without failures.
pub fn kaplan_meier(failures: &[f64], censored: &[f64]) -> Vec<(f64, f64)> {
    let mut times: Vec<f64> = failures.to_vec();
    times.sort_by(f64::total_cmp);
    times.dedup();
    let mut s = 1.0;
    times
        .into_iter()
        .map(|t| {
            let d = failures.iter().filter(|&&x| x == t).count();
            let at_risk = failures.iter().filter(|&&x| x >= t).count()
                + censored.iter().filter(|&&x| x >= t).count();
            s *= 1.0 - d as f64 / at_risk as f64;
            (t, s)
        })
        .collect()
}

/// The Kaplan-Meier `p`-quantile: the first failure time by which the estimated fraction
/// failed, `1 - S`, reaches `p` (0 < p < 1). `None` where it never does: the `p`-quantile then
/// lies beyond the last failure time, and with every censoring time after it, beyond the
/// censoring.
pub fn kaplan_meier_quantile(steps: &[(f64, f64)], p: f64) -> Option<f64> {
    steps
        .iter()
        .find(|(_, s)| 1.0 - s >= p - 1e-12)
        .map(|&(t, _)| t)
}

/// A two-parameter Weibull fit: `F(t) = 1 - exp(-(t / scale)^shape)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weibull {
    /// Shape `beta` (dimensionless).
    pub shape: f64,
    /// Scale `eta`, in the unit of the times (h).
    pub scale: f64,
}

impl Weibull {
    /// The `p`-quantile (`B_p` life for `p` = 0.1: `B10`), `eta (-ln(1 - p))^(1/beta)`.
    pub fn quantile(&self, p: f64) -> f64 {
        self.scale * (-(-p).ln_1p()).powf(1.0 / self.shape)
    }
}

/// A `B_p` life with its two-sided likelihood-ratio confidence bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundedQuantile {
    /// The maximum-likelihood estimate, in the unit of the times.
    pub estimate: f64,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound; `None` where the likelihood does not fall enough at any time below 1000
    /// times the longest time given (the data cannot bound it from above).
    pub upper: Option<f64>,
}

/// The samples' times divided by the largest: failures, censored, and the scale (the largest
/// time).
struct Scaled {
    failures: Vec<f64>,
    all: Vec<f64>,
    unit: f64,
    /// Sum of the logs of the scaled failure times.
    log_failures: f64,
}

impl Scaled {
    fn new(failures: &[f64], censored: &[f64]) -> Scaled {
        let unit = failures.iter().chain(censored).copied().fold(0.0, f64::max);
        let failures: Vec<f64> = failures.iter().map(|t| t / unit).collect();
        let all: Vec<f64> = failures
            .iter()
            .copied()
            .chain(censored.iter().map(|t| t / unit))
            .collect();
        let log_failures = failures.iter().map(|t| t.ln()).sum();
        Scaled {
            failures,
            all,
            unit,
            log_failures,
        }
    }

    fn r(&self) -> f64 {
        self.failures.len() as f64
    }

    /// Log-likelihood at `(shape, scale)` (scaled times).
    fn log_likelihood(&self, shape: f64, scale: f64) -> f64 {
        let r = self.r();
        r * shape.ln() - r * shape * scale.ln() + (shape - 1.0) * self.log_failures
            - self
                .all
                .iter()
                .map(|t| (t / scale).powf(shape))
                .sum::<f64>()
    }

    /// The scale that maximises the likelihood at `shape`: `(sum t^beta / r)^(1/beta)`.
    fn scale_at(&self, shape: f64) -> f64 {
        (self.all.iter().map(|t| t.powf(shape)).sum::<f64>() / self.r()).powf(1.0 / shape)
    }

    /// The profile score in the shape (decreasing from +inf): zero at the MLE.
    fn shape_score(&self, shape: f64) -> f64 {
        let (mut s, mut sl) = (0.0, 0.0);
        for t in &self.all {
            let w = t.powf(shape);
            s += w;
            sl += w * t.ln();
        }
        1.0 / shape + self.log_failures / self.r() - sl / s
    }

    /// With the `p`-quantile held at `tau` (scaled), the derivative of the log-likelihood in
    /// the shape (decreasing: the likelihood is concave in the shape there).
    fn score_at_quantile(&self, shape: f64, tau: f64, k: f64) -> f64 {
        let r = self.r();
        let tail: f64 = self
            .all
            .iter()
            .map(|t| {
                let x = t / tau;
                x.powf(shape) * x.ln()
            })
            .sum();
        r / shape - r * tau.ln() + self.log_failures - k * tail
    }

    /// The largest log-likelihood with the `p`-quantile held at `tau` (scaled), over the
    /// shape.
    fn profile_at_quantile(&self, tau: f64, k: f64) -> Option<f64> {
        let shape = decreasing_root(|b| self.score_at_quantile(b, tau, k))?;
        let scale = tau / k.powf(1.0 / shape);
        Some(self.log_likelihood(shape, scale))
    }
}

/// A function of one variable as argmin's cost function (the function itself): the root
/// searches here, the Brent minimisations of [`crate::calibration`].
pub(crate) struct Scalar<'a>(pub(crate) &'a dyn Fn(f64) -> f64);

impl CostFunction for Scalar<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, x: &f64) -> std::result::Result<f64, argmin::core::Error> {
        Ok((self.0)(*x))
    }
}

/// The root of `f` between `lo` and `hi` (opposite signs) by Brent's method (argmin's
/// `BrentRoot`), to a relative tolerance of 1e-12 of the bracket's end; `None` if it does not
/// converge in 200 steps.
fn root(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64) -> Option<f64> {
    let run = Executor::new(
        Scalar(f),
        BrentRoot::new(lo, hi, 1e-12 * hi.abs().max(1e-300)),
    )
    .configure(|s| s.max_iters(200))
    .timer(false)
    .run()
    .ok()?;
    let state = run.state();
    matches!(
        state.get_termination_status(),
        TerminationStatus::Terminated(TerminationReason::SolverConverged)
    )
    .then(|| state.get_best_param().copied())
    .flatten()
}

/// The root of a function of the shape that decreases from positive to negative, searched in
/// `[1/SHAPE_RANGE, SHAPE_RANGE]` (bracket widened by factors of 2 from 1); `None` where it
/// keeps its sign over the range.
fn decreasing_root(f: impl Fn(f64) -> f64) -> Option<f64> {
    let (mut lo, mut hi) = (1.0, 1.0);
    while f(lo) <= 0.0 {
        lo *= 0.5;
        if lo < 1.0 / SHAPE_RANGE {
            return None;
        }
    }
    while f(hi) >= 0.0 {
        hi *= 2.0;
        if hi > SHAPE_RANGE {
            return None;
        }
    }
    root(&f, lo, hi)
}

/// The Weibull distribution of `failures` with the `censored` times, by maximum likelihood
/// (IEC 61649 section 10.3; Lawless section 5.2.2): the shape solves the profile score
/// `1/beta + mean(ln t_f) - sum(t^beta ln t) / sum(t^beta) = 0`, the scale follows. `None`
/// with fewer than [`MIN_FAILURES`] failures, a time that is not positive and finite, or data
/// whose likelihood has no maximum at a finite shape (every failure at the longest time).
pub fn fit(failures: &[f64], censored: &[f64]) -> Option<Weibull> {
    if failures.len() < MIN_FAILURES
        || failures
            .iter()
            .chain(censored)
            .any(|t| !(t.is_finite() && *t > 0.0))
    {
        return None;
    }
    let d = Scaled::new(failures, censored);
    let shape = decreasing_root(|b| d.shape_score(b))?;
    Some(Weibull {
        shape,
        scale: d.scale_at(shape) * d.unit,
    })
}

/// The `p`-quantile of the Weibull fit of `failures` and `censored` with its two-sided
/// likelihood-ratio bounds at `confidence` (0.9: the 5 % and 95 % bounds; IEC 61649 section
/// 11.2): the quantiles `tau` where twice the drop of the profile log-likelihood (the shape
/// re-fitted with the quantile held at `tau`) reaches the chi-squared quantile of one degree
/// of freedom at `confidence` (2.706 at 0.9). `None` where [`fit`] gives no fit, or the
/// lower bound cannot be located.
pub fn quantile_with_bounds(
    failures: &[f64],
    censored: &[f64],
    p: f64,
    confidence: f64,
) -> Option<BoundedQuantile> {
    let w = fit(failures, censored)?;
    let d = Scaled::new(failures, censored);
    let k = -(-p).ln_1p();
    let best = d.log_likelihood(w.shape, w.scale / d.unit);
    let tau_hat = w.quantile(p) / d.unit;
    let level = ChiSquared::new(1.0).ok()?.inverse_cdf(confidence);
    // Twice the likelihood's drop, less the level: negative inside the interval.
    let excess = |tau: f64| -> f64 {
        d.profile_at_quantile(tau, k)
            .map_or(f64::INFINITY, |l| 2.0 * (best - l) - level)
    };
    let outside = |from: f64, factor: f64, limit: f64| -> Option<f64> {
        let mut t = from;
        loop {
            t *= factor;
            if (factor > 1.0 && t > limit) || (factor < 1.0 && t < limit) {
                return None;
            }
            if excess(t) > 0.0 {
                return Some(t);
            }
        }
    };
    let lower = {
        let below = outside(tau_hat, 0.5, 1e-12)?;
        root(&|ln_t: f64| excess(ln_t.exp()), below.ln(), tau_hat.ln())?.exp()
    };
    let upper = outside(tau_hat, 2.0, 1e3).and_then(|above| {
        root(&|ln_t: f64| excess(ln_t.exp()), tau_hat.ln(), above.ln()).map(f64::exp)
    });
    Some(BoundedQuantile {
        estimate: tau_hat * d.unit,
        lower: lower * d.unit,
        upper: upper.map(|u| u * d.unit),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::Distribution;

    /// The ball-bearing fatigue lives of Lieblein and Zelen (1956), 23 failures in millions of
    /// revolutions, the textbook Weibull data set (Lawless 2003, example 5.2.2).
    const BALL_BEARINGS: [f64; 23] = [
        17.88, 28.92, 33.00, 41.52, 42.12, 45.60, 48.48, 51.84, 51.96, 54.12, 55.56, 67.80, 68.64,
        68.64, 68.88, 84.12, 93.12, 98.64, 105.12, 105.84, 127.92, 128.04, 173.40,
    ];

    /// Lawless's maximum-likelihood estimates for the ball bearings: shape 2.102, scale 81.88
    /// (to the four figures he gives), and the fit's score zero.
    #[test]
    fn ball_bearing_fit_is_the_published_one() {
        let w = fit(&BALL_BEARINGS, &[]).unwrap();
        assert!((w.shape - 2.102).abs() < 5e-4, "{w:?}");
        assert!((w.scale - 81.88).abs() < 5e-3, "{w:?}");
        let d = Scaled::new(&BALL_BEARINGS, &[]);
        assert!(d.shape_score(w.shape).abs() < 1e-9);
    }

    /// At both bounds twice the likelihood's drop is the chi-squared level (2.706 at 90 %),
    /// the bounds straddle the estimate, and censoring the longest lives keeps the estimate
    /// near and widens the interval. The ball bearings' B10 is 28.07 with bounds 18.11 and
    /// 38.66 million revolutions by an independent grid search of the profile likelihood
    /// (numpy; grid steps of 0.23 % in the quantile, so agreement within 0.5 %).
    #[test]
    fn bounds_are_where_the_likelihood_falls_by_the_level() {
        let b = quantile_with_bounds(&BALL_BEARINGS, &[], 0.1, 0.9).unwrap();
        let upper = b.upper.unwrap();
        assert!(b.lower < b.estimate && b.estimate < upper, "{b:?}");
        for (got, grid) in [(b.estimate, 28.07), (b.lower, 18.11), (upper, 38.66)] {
            assert!(
                (got / grid - 1.0).abs() < 5e-3,
                "{got} against {grid}: {b:?}"
            );
        }
        let d = Scaled::new(&BALL_BEARINGS, &[]);
        let w = fit(&BALL_BEARINGS, &[]).unwrap();
        let best = d.log_likelihood(w.shape, w.scale / d.unit);
        let k = -(-0.1f64).ln_1p();
        for t in [b.lower, upper] {
            let drop = 2.0 * (best - d.profile_at_quantile(t / d.unit, k).unwrap());
            assert!((drop - 2.7055).abs() < 1e-3, "{t}: {drop}");
        }
        // The 10 longest lives censored at 90 (type I censoring at 90 million revolutions).
        let failed: Vec<f64> = BALL_BEARINGS
            .iter()
            .copied()
            .filter(|&t| t <= 90.0)
            .collect();
        let censored = vec![90.0; BALL_BEARINGS.len() - failed.len()];
        let c = quantile_with_bounds(&failed, &censored, 0.1, 0.9).unwrap();
        assert!((c.estimate / b.estimate - 1.0).abs() < 0.15, "{c:?} {b:?}");
        // The same grid search censored: 29.47 [18.13, 40.31].
        for (got, grid) in [
            (c.estimate, 29.47),
            (c.lower, 18.13),
            (c.upper.unwrap(), 40.31),
        ] {
            assert!(
                (got / grid - 1.0).abs() < 5e-3,
                "{got} against {grid}: {c:?}"
            );
        }
        assert!(c.upper.unwrap() - c.lower > upper - b.lower, "{c:?} {b:?}");
    }

    /// Coverage: of 400 censored samples of 30 from a known Weibull (shape 3, scale 1000 h,
    /// censored at 900 h: about half fail), the 90 % likelihood-ratio interval holds the true
    /// B10 in 0.90 of them within 0.05 (3.3 binomial standard errors of 0.015; the LR interval
    /// is exact only asymptotically, so a few percent off is expected at 15 failures).
    #[test]
    fn ninety_percent_intervals_cover_the_true_b10_nine_times_in_ten() {
        let truth = Weibull {
            shape: 3.0,
            scale: 1000.0,
        };
        let b10 = truth.quantile(0.1);
        let law = rand_distr::Weibull::new(truth.scale, truth.shape).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(61649);
        let trials = 400;
        let mut covered = 0;
        for _ in 0..trials {
            let lives: Vec<f64> = (0..30).map(|_| law.sample(&mut rng)).collect();
            let failed: Vec<f64> = lives.iter().copied().filter(|&t| t <= 900.0).collect();
            let censored = vec![900.0; lives.len() - failed.len()];
            let b = quantile_with_bounds(&failed, &censored, 0.1, 0.9).unwrap();
            if b.lower <= b10 && b.upper.is_none_or(|u| b10 <= u) {
                covered += 1;
            }
        }
        let rate = covered as f64 / trials as f64;
        assert!((rate - 0.9).abs() < 0.05, "coverage {rate}");
    }

    /// Kaplan-Meier without censoring is the empirical survival; a sample censored before a
    /// failure leaves the risk set (worked by hand: failures at 1, 3, 3 and 6, censored at 2
    /// and 5: 6 at risk at 1, 4 at 3, 1 at 6, so S = 5/6, 5/6 x 2/4, 0).
    #[test]
    fn kaplan_meier_is_the_product_limit() {
        let s = kaplan_meier(&[1.0, 2.0, 3.0, 4.0], &[]);
        assert_eq!(s, vec![(1.0, 0.75), (2.0, 0.5), (3.0, 0.25), (4.0, 0.0)]);
        // Six samples: failures at 1, 3, 3 and 6; censored at 2 and 5.
        let s = kaplan_meier(&[1.0, 3.0, 3.0, 6.0], &[2.0, 5.0]);
        let expect = [
            (1.0, 5.0 / 6.0),
            (3.0, 5.0 / 6.0 * (1.0 - 2.0 / 4.0)),
            (6.0, 5.0 / 6.0 * 0.5 * 0.0),
        ];
        for ((t, v), (te, ve)) in s.iter().zip(expect) {
            assert_eq!(*t, te);
            assert!((v - ve).abs() < 1e-15, "{t}: {v} against {ve}");
        }
        // One of four samples out of spec at 3 477 h, three still in at 75 000 h: B10 (and
        // B25) at most 3 477 h; B50 beyond the censoring.
        let s = kaplan_meier(&[3477.0], &[75e3, 75e3, 75e3]);
        assert_eq!(kaplan_meier_quantile(&s, 0.1), Some(3477.0));
        assert_eq!(kaplan_meier_quantile(&s, 0.25), Some(3477.0));
        assert_eq!(kaplan_meier_quantile(&s, 0.5), None);
        assert!(fit(&[3477.0], &[75e3, 75e3, 75e3]).is_none());
    }
}
