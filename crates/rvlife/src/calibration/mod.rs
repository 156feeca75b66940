//! Calibration of the Archard coefficient from measurements of a worn reducer
//! (`rvlife calibrate --measured FILE.csv`).
//!
//! # Model of the fit
//!
//! A measured quantity `y` (lost motion, backlash, maximum wear depth) at working hours `h` is
//! modelled as
//!
//! `y = Q(h k / k_ref; k_ref) + b0 [backlash, lost motion only] + noise`,
//!
//! `Q(H; k_ref)` the study's stage value after `H` hours at the reference coefficient `k_ref`,
//! `k` the fitted Archard coefficient (m^2/N) and `b0` (arcmin, optional) the running-in play
//! of an assembled reducer beyond the model's own. With a running-in in the config
//! (`wear.running_in_factor` > 1) the hours `h` become the equivalent steady hours
//! `H(h) = h + (r - 1) tau (1 - exp(-h/tau))` (docs/model.md section 7.10) and the factor `r` is
//! fitted too (`ln r` by Brent's method on the profile likelihood, `ln k` and `b0` fitted at
//! each `r`), its time constant `tau` kept (docs/model.md section 13.2).
//!
//! The k-h scaling is exact in the code, not an approximation: the wear rate
//! (`crate::wear::wear_rate`) is `k` times a function of the worn profile only, so the depth
//! integrated with profile updates at hours `t_u` for coefficient `k` equals the one integrated
//! with updates at `t_u k / k_ref` for `k_ref` (checked to round-off in the tests). One
//! reference study over "equivalent hours" `H` therefore gives the model for every `k` by
//! interpolation (monotone cubic, Fritsch-Carlson PCHIP, in `H`). What is not scale-free is
//! the update schedule that `rvlife run` picks: `wear.profile_update_hours` counts real hours,
//! so a run at `2 k` updates the profile half as often per micrometre as the reference run; the
//! difference is the discretisation error of the explicit wear integration, small because the
//! `wear.max_wear_step_um` rule (depth, scale-free) sets most updates: 0.012 % or less of the
//! lost motion, backlash and maximum wear of the example at 2 k (test
//! `direct_run_at_twice_k_matches_the_reference_at_twice_the_hours`).
//!
//! The reference runs are the study ([`crate::study::run`], without the twist shares) with
//! dynamics and the flexible disc off (none of the fitted quantities needs them) and stages
//! spread evenly over the equivalent hours:
//! a first pass at the config's coefficient over `4 h_max` (24 stages) locates `k`, and passes
//! at the last estimate over `2 h_max` (32 stages) refine it until two agree within 25 %.
//!
//! # Least squares and confidence interval
//!
//! The columns of one unit share one noise level `sigma_u` (lost motion and backlash are read
//! off one hysteresis measurement with one encoder; wear depth is another instrument),
//! estimated from the data when both units are present (iteratively reweighted:
//! `sigma_u^2 = RSS_u / n_u x N / (N - p)`; with one unit the weights cancel and the fit is
//! ordinary least squares). Per-column levels were tried and rejected: estimated from 8 values
//! each they scatter by +-25 %, and the interval, which ignores that, covered the true `k`
//! too rarely in repeated trials. The fit minimises `sum ((y - model) / sigma_u)^2` over `ln k` (Brent's method, argmin, after a
//! scan of the bracket); `b0` enters linearly and is eliminated in closed form for every `k`
//! (variable projection). `k` is fitted as `ln k` because it acts as a scale of the hours: the
//! model is a shift along `ln h`, which keeps the linearisation good and the interval positive.
//!
//! The 95 % confidence interval is the Gauss-Newton (Wald) one: covariance
//! `s^2 (J^T W J)^-1` at the optimum, `J` the Jacobian of the model in `(ln k, b0)` (analytic
//! derivative of the interpolant), `W = diag(1/sigma_u^2)`, `s^2 = weighted RSS / (N - p)` the
//! residual variance from the data, and the Student-t quantile with `N - p` degrees of freedom
//! (`N` measured values, `p` = 1 or 2 parameters): `ln k +- t sd(ln k)`, mapped to `k`. It
//! assumes independent Gaussian errors and a model that is nearly linear in `ln k` over the
//! interval; it does not include the model's own error (its discretisation, its physics).

mod measurements;
mod pchip;
pub mod structure;

use std::path::Path;

use argmin::core::Executor;
use argmin::solver::brent::BrentOpt;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::config::Model;
use crate::error::{Error, Result};
use crate::montecarlo::weibull::Scalar;
use crate::quantities::StageSummary;
use crate::wear::RunningIn;

use measurements::bad;
pub(crate) use measurements::QUANTITIES;
pub use measurements::{Measurable, Measurements, Series};
use pchip::Pchip;

/// Reference horizon of the first pass, in multiples of the largest measured hours.
const FIRST_HORIZON: f64 = 4.0;
/// Stages of the first pass.
const FIRST_STAGES: usize = 24;
/// Reference horizon of the refining passes, in multiples of the largest measured hours.
const REFINE_HORIZON: f64 = 2.0;
/// Stages of the refining passes.
const REFINE_STAGES: usize = 32;
/// Most reference studies of one calibration; each must fit this fraction of the work budget.
pub const MAX_PASSES: usize = 5;
/// Confidence level of the reported interval.
pub(crate) const CONFIDENCE: f64 = 0.95;
/// Largest running-in factor `r` the fit searches.
const MAX_RUNNING_IN_FACTOR: f64 = 1000.0;

/// One reference study: the quantities against equivalent hours at one coefficient.
#[derive(Debug, Clone)]
struct Reference {
    /// Coefficient of the run, m^2/N.
    archard: f64,
    /// Last equivalent hours within the model's validity, h.
    last_hours: f64,
    /// Interpolant of every entry of [`QUANTITIES`].
    curves: Vec<Pchip>,
}

impl Reference {
    /// Model value of quantity `q` at `h` working hours for the coefficient `k` (m^2/N) with
    /// the running-in `run_in`, and its derivatives with respect to `ln k` and `ln r`: the
    /// reference's value at the equivalent hours `H(h) k / k_ref` (docs/model.md section 7.10).
    fn model(&self, q: usize, h: f64, k: f64, run_in: RunningIn) -> (f64, f64, f64) {
        let c = &self.curves[q];
        let big_h = run_in.equivalent_hours(h) * k / self.archard;
        let (v, dv) = c.eval(big_h);
        // dH/d ln r = r tau (1 - exp(-h/tau)).
        let dh_dlnr = if run_in.factor > 1.0 {
            run_in.factor * run_in.hours * -(-h / run_in.hours).exp_m1()
        } else {
            0.0
        };
        (v, dv * big_h, dv * dh_dlnr * k / self.archard)
    }
}

/// The model of one reference pass: stages over `[0, horizon]` equivalent hours at `archard`,
/// dynamics and the flexible disc off, within a `MAX_PASSES`-th of the work budget (so that
/// the whole calibration stays within it).
fn reference_model(model: &Model, archard: f64, horizon: f64, stages: usize) -> Model {
    let mut m = model.clone().static_only();
    m.work_budget = model.work_budget / MAX_PASSES as f64;
    m.wear.archard = archard;
    // Steady: the fit applies the running-in as a warp of the hours.
    m.wear.running_in.factor = 1.0;
    m.wear.stage_hours = (0..=stages)
        .map(|i| horizon * i as f64 / stages as f64)
        .collect();
    // The reference study's work is named by its hours, whatever sets the load levels.
    m.load.levels_key = "load.kind";
    m
}

/// Rewords a budget refusal of a reference run as one of the measured hours.
fn budget_error(path: &Path, h_max: f64, horizon: f64, e: Error) -> Error {
    match e {
        Error::Invalid { allowed, .. } if allowed.contains("budget") => bad(
            path,
            format!(
                "the largest measured hours, {h_max} h, need a reference study over {horizon:.4e} \
                 equivalent hours that exceeds its share of the work budget (a calibration \
                 runs up to {MAX_PASSES} reference studies, each within 1/{MAX_PASSES} of \
                 --work-budget-min: {allowed}); give fewer hours or raise --work-budget-min"
            ),
        ),
        other => other,
    }
}

/// The fit's k-h scaling holds for the disc's wear alone: a config with wearing crank bearings
/// (their clearance grows with real hours, whatever the disc's coefficient) is refused by its
/// key.
fn disc_wear_only(model: &Model) -> Result<()> {
    let kb = model.wear.bearings.archard;
    if kb > 0.0 {
        return Err(Error::invalid(
            "wear.bearing_archard_coefficient_mm3_per_n_m",
            kb * 1e9,
            "must be 0 for calibrate --measured: the fit of the disc's coefficient scales the \
             hours, which the bearings' wear, counted in real hours, does not follow (fitting \
             both coefficients is not built yet)",
        ));
    }
    let kp = model.wear.pin_archard;
    if kp > 0.0 {
        return Err(Error::invalid(
            "wear.pin_archard_coefficient_mm3_per_n_m",
            kp * 1e9,
            "must be 0 for calibrate --measured: the fit is of the disc's coefficient alone \
             (fitting the pins' with it is not built yet)",
        ));
    }
    Ok(())
}

/// Checks, before any work, that the first reference study of the calibration fits the work
/// budget ([`crate::budget`]): the stage analyses and profile updates over `4 x` the
/// equivalent hours of the largest measured hours at the config's coefficient and running-in, including the updates that
/// `wear.max_wear_step_um` asks for at the unworn disc's wear rate (one wear-rate evaluation).
///
/// # Errors
/// [`Error::Invalid`] naming `--measured`, the hours and the estimate.
pub fn check_budget(model: &Model, data: &Measurements) -> Result<()> {
    disc_wear_only(model)?;
    let h_max = data.max_hours();
    let horizon = FIRST_HORIZON * model.wear.running_in.equivalent_hours(h_max);
    let m = reference_model(model, model.wear.archard, horizon, FIRST_STAGES);
    let check = || -> Result<()> {
        crate::study::check_work(&m)?;
        let inputs = m.wear_inputs();
        let rate = crate::wear::wear_rate(&m.profile()?, &inputs)?;
        let max_rate = rate.disc.iter().copied().fold(0.0, f64::max);
        crate::wear::check_updates(&inputs, horizon, max_rate)
    };
    check().map_err(|e| budget_error(&data.path, h_max, horizon, e))
}

/// A fitted parameter with its confidence interval.
#[derive(Debug, Clone, Serialize)]
pub struct Estimate {
    /// Best estimate.
    pub value: f64,
    /// Lower end of the `CONFIDENCE` interval.
    pub lower: f64,
    /// Upper end of the interval.
    pub upper: f64,
}

/// Fit statistics of one measured quantity.
#[derive(Debug, Clone, Serialize)]
pub struct QuantityFit {
    /// Column name.
    pub column: &'static str,
    /// Unit of the values and residuals.
    pub unit: &'static str,
    /// Number of measured values.
    pub points: usize,
    /// Root mean square of the residuals (measured - model), in the unit.
    pub rms_residual: f64,
    /// Noise level used as its weight, in the unit (one per unit, estimated from the
    /// residuals when the file has two units).
    pub sigma: f64,
}

/// One measured value against the fitted model.
#[derive(Debug, Clone, Serialize)]
pub struct Residual {
    /// Working hours, h.
    pub hours: f64,
    /// Column name.
    pub column: &'static str,
    /// Measured value, in the column's unit.
    pub measured: f64,
    /// Fitted model, in the column's unit.
    pub model: f64,
    /// Measured - model.
    pub residual: f64,
}

/// The fitted model curve of one quantity, for plots.
#[derive(Debug, Clone, Serialize)]
pub struct FitCurve {
    /// Column name.
    pub column: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// Working hours, h (0 to 1.05 x the largest measured).
    pub hours: Vec<f64>,
    /// Model values.
    pub values: Vec<f64>,
}

/// The result of [`calibrate`] (`calibration.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Calibration {
    /// Archard coefficient, m^2/N, with its interval.
    pub archard_coefficient_m2_per_n: Estimate,
    /// The same in mm^3/(N m) (the config key `wear.archard_coefficient_mm3_per_n_m`).
    pub archard_coefficient_mm3_per_n_m: Estimate,
    /// The config's coefficient, m^2/N.
    pub config_archard_coefficient_m2_per_n: f64,
    /// Standard error of `ln k`.
    pub ln_k_standard_error: f64,
    /// Running-in play added to backlash and lost motion, arcmin (with `--fit-running-in`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub running_in_backlash_arcmin: Option<Estimate>,
    /// Running-in factor `r = k(0)/k_ss` of the disc's coefficient, fitted when the config
    /// has one (`wear.running_in_factor` > 1), its interval from that of `ln r`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub running_in_factor: Option<Estimate>,
    /// Its time constant `tau`, h: the config's `wear.running_in_hours`, not fitted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub running_in_hours: Option<f64>,
    /// Confidence level of the intervals.
    pub confidence: f64,
    /// How the interval is found.
    pub interval_method: &'static str,
    /// Measured values `N`.
    pub points: usize,
    /// Fitted parameters `p`.
    pub parameters: usize,
    /// Degrees of freedom `N - p`.
    pub degrees_of_freedom: usize,
    /// Student-t quantile used.
    pub t_quantile: f64,
    /// Residual variance of the weighted fit, `weighted RSS / (N - p)` (1 when the weights
    /// match the scatter).
    pub residual_variance: f64,
    /// Per quantity.
    pub quantities: Vec<QuantityFit>,
    /// Every measured value against the model.
    pub residuals: Vec<Residual>,
    /// Model curves.
    pub curves: Vec<FitCurve>,
    /// Coefficient of the last reference study, m^2/N.
    pub reference_archard_coefficient_m2_per_n: f64,
    /// Equivalent hours covered by the last reference study, h.
    pub reference_hours: f64,
    /// Reference studies run.
    pub reference_runs: usize,
    /// Stages analysed over all reference studies.
    pub reference_stages: usize,
}

/// Options of [`calibrate`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Options {
    /// Fit the running-in play `b0` too.
    pub fit_running_in: bool,
}

impl Options {
    /// The parameters fitted for `model`: `ln k` always, `b0` with
    /// [`Options::fit_running_in`], the running-in factor `r` when the config has a running-in
    /// (`wear.running_in_factor` > 1, the fit's start; its time constant is kept).
    fn fitted(self, model: &Model) -> Fitted {
        Fitted {
            b0: self.fit_running_in,
            factor: model.wear.running_in.factor > 1.0,
        }
    }

    /// Checks, before any work, that `data` can determine the parameters fitted for `model`
    /// ([`Measurements::check_for_fit`]).
    ///
    /// # Errors
    /// As [`Measurements::check_for_fit`].
    pub fn check(self, model: &Model, data: &Measurements) -> Result<()> {
        let f = self.fitted(model);
        data.check_for_fit(f.b0, f.factor)
    }
}

/// Least-squares fit on one reference.
struct Fit {
    ln_k: f64,
    b0: f64,
    /// The running-in with its fitted factor (factor 1: none).
    run_in: RunningIn,
    sigma: Vec<f64>,
}

/// Which parameters a fit determines.
#[derive(Debug, Clone, Copy)]
struct Fitted {
    /// The running-in play `b0`.
    b0: bool,
    /// The running-in factor `r`.
    factor: bool,
}

impl Fitted {
    /// Number of parameters `p`.
    fn count(self) -> usize {
        1 + usize::from(self.b0) + usize::from(self.factor)
    }
}

/// All measured points as (series index, hours, value).
fn points(data: &Measurements) -> Vec<(usize, f64, f64)> {
    data.series
        .iter()
        .enumerate()
        .flat_map(|(j, s)| s.hours.iter().zip(&s.values).map(move |(h, v)| (j, *h, *v)))
        .collect()
}

/// The best `b0` for `k` (weighted mean of the running-in residuals) and the weighted RSS.
fn profile_cost(
    reference: &Reference,
    data: &Measurements,
    sigma: &[f64],
    fit_b0: bool,
    run_in: RunningIn,
    ln_k: f64,
) -> (f64, f64) {
    let k = ln_k.exp();
    let pts = points(data);
    let model: Vec<f64> = pts
        .iter()
        .map(|&(j, h, _)| reference.model(data.series[j].quantity, h, k, run_in).0)
        .collect();
    let ri = |j: usize| QUANTITIES[data.series[j].quantity].running_in;
    let b0 = if fit_b0 {
        let (num, den) = pts.iter().zip(&model).filter(|((j, _, _), _)| ri(*j)).fold(
            (0.0, 0.0),
            |(a, b), ((j, _, y), m)| {
                let w = sigma[*j].powi(-2);
                (a + w * (y - m), b + w)
            },
        );
        num / den
    } else {
        0.0
    };
    let rss = pts
        .iter()
        .zip(&model)
        .map(|((j, _, y), m)| {
            let r = y - m - if ri(*j) { b0 } else { 0.0 };
            (r / sigma[*j]).powi(2)
        })
        .sum();
    (b0, rss)
}

/// Minimises the weighted RSS over `ln k` in `[lo, hi]`: a scan of 61 points, then Brent's
/// method (argmin) between the neighbours of the best.
fn minimise(
    reference: &Reference,
    data: &Measurements,
    sigma: &[f64],
    fit_b0: bool,
    run_in: RunningIn,
    lo: f64,
    hi: f64,
) -> Result<f64> {
    let cost = |x: f64| profile_cost(reference, data, sigma, fit_b0, run_in, x).1;
    Ok(scan_then_brent(&cost, lo, hi, 60)?.0)
}

/// Minimises `cost` over `[lo, hi]`: a scan of `n + 1` evenly spaced points, then Brent's
/// method between the neighbours of the best ([`brent`]); the better of the two and its cost
/// (the scan's best when no point has a finite cost).
fn scan_then_brent(cost: &dyn Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> Result<(f64, f64)> {
    let xs: Vec<f64> = (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect();
    let costs: Vec<f64> = xs.iter().map(|&x| cost(x)).collect();
    let best = (0..=n)
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .expect("a scan");
    if !costs[best].is_finite() {
        return Ok((xs[best], costs[best]));
    }
    let (a, b) = (xs[best.saturating_sub(1)], xs[(best + 1).min(n)]);
    let x = brent(cost, a, b)?.unwrap_or(xs[best]);
    let c = cost(x);
    Ok(if c <= costs[best] {
        (x, c)
    } else {
        (xs[best], costs[best])
    })
}

/// Brent's method (argmin) on `cost` between `a` and `b`: its best point, if any.
fn brent(cost: &dyn Fn(f64) -> f64, a: f64, b: f64) -> Result<Option<f64>> {
    let res = Executor::new(Scalar(cost), BrentOpt::new(a, b).set_tolerance(1e-8, 1e-10))
        .configure(|st| st.max_iters(200))
        .timer(false)
        .run()
        .map_err(|e| Error::numerical("calibration", e.to_string()))?;
    Ok(res.state.best_param)
}

/// Iteratively reweighted fit on one reference at the running-in `run_in`, `ln k` in
/// `[lo, hi]`; `p` parameters in all (for the residual variance).
fn fit_on(
    reference: &Reference,
    data: &Measurements,
    fit_b0: bool,
    run_in: RunningIn,
    p: usize,
    (lo, hi): (f64, f64),
) -> Result<Fit> {
    let n_total = data.len() as f64;
    let p = p as f64;
    // Start: every unit scaled by the size of its values.
    let size = |u: &str| {
        let (ss, n) = data
            .series
            .iter()
            .filter(|s| QUANTITIES[s.quantity].unit() == u)
            .flat_map(|s| s.values.iter())
            .fold((0.0, 0), |(a, b), v| (a + v * v, b + 1));
        (ss / n as f64).sqrt().max(1e-9)
    };
    let mut sigma: Vec<f64> = data
        .series
        .iter()
        .map(|s| size(QUANTITIES[s.quantity].unit()))
        .collect();
    // Series of one unit share one noise level (lost motion and backlash are read off one
    // hysteresis measurement).
    let unit = |j: usize| QUANTITIES[data.series[j].quantity].unit();
    let groups = {
        let mut u: Vec<&str> = (0..data.series.len()).map(unit).collect();
        u.dedup();
        u.sort_unstable();
        u.dedup();
        u.len()
    };
    let mut ln_k = f64::NAN;
    for _ in 0..8 {
        let x = minimise(reference, data, &sigma, fit_b0, run_in, lo, hi)?;
        let converged = (x - ln_k).abs() < 1e-7;
        ln_k = x;
        if groups == 1 || converged {
            break;
        }
        let (b0, _) = profile_cost(reference, data, &sigma, fit_b0, run_in, ln_k);
        let k = ln_k.exp();
        // Sum of squared residuals and count of each series.
        let per_series: Vec<(f64, usize)> = data
            .series
            .iter()
            .map(|s| {
                let q = QUANTITIES[s.quantity];
                let rss = s
                    .hours
                    .iter()
                    .zip(&s.values)
                    .map(|(h, y)| {
                        let m = reference.model(s.quantity, *h, k, run_in).0
                            + if q.running_in { b0 } else { 0.0 };
                        (y - m).powi(2)
                    })
                    .sum();
                (rss, s.values.len())
            })
            .collect();
        sigma = (0..data.series.len())
            .map(|j| {
                let (rss, n) = (0..data.series.len())
                    .filter(|&i| unit(i) == unit(j))
                    .fold((0.0, 0), |(a, b), i| {
                        (a + per_series[i].0, b + per_series[i].1)
                    });
                (rss / n as f64 * n_total / (n_total - p)).sqrt().max(1e-9)
            })
            .collect();
    }
    let (b0, _) = profile_cost(reference, data, &sigma, fit_b0, run_in, ln_k);
    Ok(Fit {
        ln_k,
        b0,
        run_in,
        sigma,
    })
}

/// `sum_u n_u ln(RSS_u / n_u)` over the units `u` of the data: twice the negative Gaussian log
/// likelihood with each unit's noise level at its estimate, up to a constant (with one unit,
/// `n ln(RSS/n)`, monotone in the residual sum of squares).
fn profile_likelihood(reference: &Reference, data: &Measurements, fit: &Fit) -> f64 {
    let k = fit.ln_k.exp();
    let mut units: Vec<(&str, f64, usize)> = Vec::new();
    for s in &data.series {
        let q = QUANTITIES[s.quantity];
        let rss: f64 = s
            .hours
            .iter()
            .zip(&s.values)
            .map(|(h, y)| {
                let m = reference.model(s.quantity, *h, k, fit.run_in).0
                    + if q.running_in { fit.b0 } else { 0.0 };
                (y - m).powi(2)
            })
            .sum();
        match units.iter_mut().find(|u| u.0 == q.unit()) {
            Some(u) => {
                u.1 += rss;
                u.2 += s.values.len();
            }
            None => units.push((q.unit(), rss, s.values.len())),
        }
    }
    units
        .iter()
        .map(|&(_, rss, n)| n as f64 * (rss / n as f64).max(1e-300).ln())
        .sum()
}

/// The fit with the running-in factor `r` too (time constant `tau` h): Brent's method (argmin)
/// on the profile likelihood over `ln r` in `[0, ln MAX_RUNNING_IN_FACTOR]` after a scan of 41
/// points, `ln k` (and `b0`) fitted at each `r` by [`fit_on`], `ln k` bounded by `bracket(r)`.
fn fit_with_running_in(
    reference: &Reference,
    data: &Measurements,
    fit_b0: bool,
    tau: f64,
    p: usize,
    bracket: &dyn Fn(f64) -> (f64, f64),
) -> Result<Fit> {
    let at = |ln_r: f64| -> Option<Fit> {
        let run_in = RunningIn {
            factor: ln_r.exp(),
            hours: tau,
        };
        let (lo, hi) = bracket(run_in.factor);
        if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        fit_on(reference, data, fit_b0, run_in, p, (lo, hi)).ok()
    };
    let cost =
        |ln_r: f64| at(ln_r).map_or(f64::INFINITY, |f| profile_likelihood(reference, data, &f));
    let (x, c) = scan_then_brent(&cost, 0.0, MAX_RUNNING_IN_FACTOR.ln(), 40)?;
    if !c.is_finite() {
        return Err(bad(
            &data.path,
            "no running-in factor in [1, 1000] gives a fit within the reference study's \
             validity: the data do not follow the model",
        ));
    }
    at(x).ok_or_else(|| Error::numerical("calibration", "the running-in fit lost its optimum"))
}

/// Runs one reference study and builds its interpolants.
fn run_reference(
    model: &Model,
    data: &Measurements,
    archard: f64,
    horizon: f64,
    stages: usize,
) -> Result<Reference> {
    let m = reference_model(model, archard, horizon, stages);
    let h_max = data.max_hours();
    crate::study::check_work(&m).map_err(|e| budget_error(&data.path, h_max, horizon, e))?;
    let study =
        crate::study::run_stages(&m).map_err(|e| budget_error(&data.path, h_max, horizon, e))?;
    let sums: Vec<StageSummary> = study.stages.iter().map(|s| s.summary.clone()).collect();
    if sums.len() < 3 {
        let why = study
            .wear
            .limit
            .as_ref()
            .map_or(String::new(), |l| format!(": {}", l.reason));
        return Err(bad(
            &data.path,
            format!(
                "the wear model leaves its validity at {:.4e} equivalent hours of the \
                 reference study{why}, too early to fit the measurements (the model cannot \
                 follow this much wear)",
                sums.last().map_or(0.0, |s| s.hours)
            ),
        ));
    }
    let hours: Vec<f64> = sums.iter().map(|s| s.hours).collect();
    let curves = QUANTITIES
        .iter()
        .map(|q| Pchip::new(hours.clone(), sums.iter().map(|s| q.value(s)).collect()))
        .collect();
    Ok(Reference {
        archard,
        last_hours: *hours.last().expect("stages"),
        curves,
    })
}

/// Fits the Archard coefficient (and with [`Options::fit_running_in`] the running-in play) to
/// measured lost motion, backlash or maximum wear against working hours (see the module docs
/// for the model, the reference studies and the interval). `progress(pass)` is called before
/// each reference study.
///
/// Cost: 2 to `MAX_PASSES` reference studies without dynamics and FE (24 + 32 stages each
/// time, about a second each for the example); the least squares on the interpolants is
/// negligible. Each study must fit a `MAX_PASSES`-th of the work budget.
///
/// # Errors
/// [`Error::Invalid`] naming `--measured` for too few values, no hours above 0, work beyond the
/// budget, wear the model cannot follow, data that do not determine `k` (flat model), a
/// coefficient beyond `1e6` times the config's either way, a fit that stops at a bound of its
/// search range, an interval the data cannot bound, or a model that follows a measured series
/// worse than the series' mean ([`Calibration::check_standing`]); solver failures of the
/// studies.
pub fn calibrate(
    model: &Model,
    data: &Measurements,
    options: Options,
    progress: &dyn Fn(usize),
) -> Result<Calibration> {
    let fitted = options.fitted(model);
    data.check_for_fit(fitted.b0, fitted.factor)?;
    disc_wear_only(model)?;
    let h_max = data.max_hours();
    let fit_b0 = fitted.b0;
    let k_cfg = model.wear.archard;
    let mut archard = k_cfg;
    // The running-in of the current estimate (the config's to start).
    let mut run_in = model.wear.running_in;
    let mut runs = 0;
    let mut stages_total = 0;
    let mut last_fit: Option<(Reference, Fit)> = None;
    // Where the last pass' optimum lay in its bracket: -1 at the bottom, +1 at the top.
    let mut at_bound = 0;
    for pass in 0..MAX_PASSES {
        let (factor, stages) = if pass == 0 {
            (FIRST_HORIZON, FIRST_STAGES)
        } else {
            (REFINE_HORIZON, REFINE_STAGES)
        };
        progress(pass + 1);
        let horizon = factor * run_in.equivalent_hours(h_max);
        let reference = run_reference(model, data, archard, horizon, stages)?;
        runs += 1;
        stages_total += stages + 1;
        // ln k bracket: up to the validity of the reference at the running-in factor `r`;
        // down to a thousandth of the first pass' horizon, a quarter of the refining passes'.
        let last = reference.last_hours;
        let hi_at = |r: f64| {
            let h_eq = RunningIn {
                factor: r,
                ..run_in
            }
            .equivalent_hours(h_max);
            (archard * last / h_eq).ln()
        };
        let lo = if pass == 0 {
            (archard / 1000.0).ln()
        } else {
            (archard / 4.0).ln()
        };
        let fit = if fitted.factor {
            let bracket = |r: f64| (lo, hi_at(r));
            fit_with_running_in(
                &reference,
                data,
                fit_b0,
                run_in.hours,
                fitted.count(),
                &bracket,
            )?
        } else {
            fit_on(
                &reference,
                data,
                fit_b0,
                run_in,
                fitted.count(),
                (lo, hi_at(run_in.factor)),
            )?
        };
        let hi = hi_at(fit.run_in.factor);
        let k = fit.ln_k.exp();
        let at_top = hi - fit.ln_k < 1e-3;
        at_bound = if at_top {
            1
        } else if fit.ln_k - lo < 1e-3 {
            -1
        } else {
            0
        };
        let settled = pass > 0 && (fit.ln_k - archard.ln()).abs() < 1.25f64.ln() && !at_top;
        if at_top && reference.last_hours < 0.999 * horizon {
            return Err(bad(
                &data.path,
                format!(
                    "the measurements ask for more wear than the model follows: its validity \
                     ends at {:.4e} equivalent hours of the reference study, and the best fit \
                     lies at that end (k >= {k:.4e} m^2/N)",
                    reference.last_hours
                ),
            ));
        }
        if !(1e-6..=1e6).contains(&(k / k_cfg)) {
            return Err(bad(
                &data.path,
                format!(
                    "the fit moves the Archard coefficient to {k:.4e} m^2/N, more than 1e6 \
                     times from the config's {k_cfg:.4e}: the data do not follow the model"
                ),
            ));
        }
        archard = k;
        run_in = fit.run_in;
        last_fit = Some((reference, fit));
        if settled {
            break;
        }
    }
    let (reference, fit) = last_fit.expect("at least one pass");
    if at_bound != 0 {
        return Err(bad(
            &data.path,
            format!(
                "the fit stopped at the {} of the Archard coefficient's search range after \
                 {runs} reference studies (k {} {:.4e} m^2/N, {:.4} x the config's): no \
                 coefficient in the range follows the measurements, which change {} than the \
                 model does (if the config's wear.archard is far off, start nearer the data)",
                if at_bound > 0 { "top" } else { "bottom" },
                if at_bound > 0 { ">=" } else { "<=" },
                fit.ln_k.exp(),
                fit.ln_k.exp() / k_cfg,
                if at_bound > 0 { "faster" } else { "slower" },
            ),
        ));
    }
    let c = summarise(model, data, &reference, &fit, fitted, runs, stages_total)?;
    c.check_standing(data)?;
    Ok(c)
}

impl Calibration {
    /// [`standing`] of this fit.
    ///
    /// # Errors
    /// As [`standing`].
    fn check_standing(&self, data: &Measurements) -> Result<()> {
        standing(
            &self.archard_coefficient_m2_per_n,
            self.running_in_factor.as_ref(),
            self.running_in_backlash_arcmin.as_ref(),
            &self.residuals,
            data,
        )
    }
}

/// Refuses a fit nobody can stand behind: an interval the data cannot bound (an end that is
/// not finite, or a positive parameter's lower end at zero: the coefficient `k` (m^2/N), the
/// running-in factor; the running-in play `b0` (arcmin) needs finite ends), or a model that
/// follows a measured series of 3 values or more worse than the series' own mean does (its
/// residuals' sum of squares above the values' about their mean).
///
/// # Errors
/// [`Error::Invalid`] naming `--measured`, with the estimate and its interval, or the series
/// with its RMS residual and spread.
fn standing(
    k: &Estimate,
    factor: Option<&Estimate>,
    b0: Option<&Estimate>,
    residuals: &[Residual],
    data: &Measurements,
) -> Result<()> {
    let positive = |e: &Estimate| e.lower > 0.0 && e.upper.is_finite();
    let finite = |e: &Estimate| e.lower.is_finite() && e.upper.is_finite();
    let unbounded = |what: &str, e: &Estimate| {
        bad(
            &data.path,
            format!(
                "the data cannot bound the {:.0} % interval of {what} (best fit {:.4e}, \
                 interval [{:.4e}, {:.4e}]): more measurements, or measurements over more \
                 hours, are needed",
                100.0 * CONFIDENCE,
                e.value,
                e.lower,
                e.upper
            ),
        )
    };
    if !positive(k) {
        return Err(unbounded("the Archard coefficient (m^2/N)", k));
    }
    if let Some(e) = factor.filter(|e| !positive(e)) {
        return Err(unbounded("the running-in factor", e));
    }
    if let Some(e) = b0.filter(|e| !finite(e)) {
        return Err(unbounded("the running-in play (arcmin)", e));
    }
    for s in &data.series {
        let n = s.values.len();
        if n < 3 {
            continue;
        }
        let mean = s.values.iter().sum::<f64>() / n as f64;
        let spread = s.values.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
        let rss: f64 = residuals
            .iter()
            .filter(|r| r.column == s.column)
            .map(|r| r.residual.powi(2))
            .sum();
        if spread > 0.0 && rss > spread {
            let unit = QUANTITIES[s.quantity].unit();
            return Err(bad(
                &data.path,
                format!(
                    "the fitted model follows {} worse than the measurements' own mean does \
                     (RMS residual {:.4} {unit}, spread about the mean {:.4} {unit}): the data \
                     do not follow the model",
                    s.column,
                    (rss / n as f64).sqrt(),
                    (spread / n as f64).sqrt()
                ),
            ));
        }
    }
    Ok(())
}

/// Interval, residuals and curves of the final fit.
fn summarise(
    model: &Model,
    data: &Measurements,
    reference: &Reference,
    fit: &Fit,
    fitted: Fitted,
    runs: usize,
    stages: usize,
) -> Result<Calibration> {
    let pts = points(data);
    let n = pts.len();
    let p = fitted.count();
    let fit_b0 = fitted.b0;
    // Columns of the Jacobian: ln k, then ln r and b0 when fitted.
    let col_r = fitted.factor.then_some(1);
    let col_b0 = fit_b0.then_some(1 + usize::from(fitted.factor));
    let k = fit.ln_k.exp();
    let ri = |j: usize| QUANTITIES[data.series[j].quantity].running_in;
    // Weighted Jacobian and residuals.
    let mut jac = DMatrix::<f64>::zeros(n, p);
    let mut res = DVector::<f64>::zeros(n);
    let mut residuals = Vec::with_capacity(n);
    for (i, &(j, h, y)) in pts.iter().enumerate() {
        let q = data.series[j].quantity;
        let (m, dm, dm_dlnr) = reference.model(q, h, k, fit.run_in);
        let m = m + if ri(j) { fit.b0 } else { 0.0 };
        let w = 1.0 / fit.sigma[j];
        jac[(i, 0)] = dm * w;
        if let Some(c) = col_r {
            jac[(i, c)] = dm_dlnr * w;
        }
        if let (Some(c), true) = (col_b0, ri(j)) {
            jac[(i, c)] = w;
        }
        res[i] = (y - m) * w;
        residuals.push(Residual {
            hours: h,
            column: data.series[j].column,
            measured: y,
            model: m,
            residual: y - m,
        });
    }
    let dof = n - p;
    let s2 = res.norm_squared() / dof as f64;
    let jtj = jac.transpose() * &jac;
    let flat = || {
        bad(
            &data.path,
            "the model does not change with the Archard coefficient at the measured hours \
             (zero Jacobian): the data cannot determine it",
        )
    };
    let inv = jtj.try_inverse().ok_or_else(flat)?;
    let cov = inv * s2;
    if !(cov[(0, 0)].is_finite() && cov[(0, 0)] >= 0.0) {
        return Err(flat());
    }
    let t = StudentsT::new(0.0, 1.0, dof as f64)
        .map_err(|e| Error::numerical("calibration", e.to_string()))?
        .inverse_cdf(0.5 + 0.5 * CONFIDENCE);
    let se = cov[(0, 0)].sqrt();
    let kest = Estimate {
        value: k,
        lower: (fit.ln_k - t * se).exp(),
        upper: (fit.ln_k + t * se).exp(),
    };
    let running_in = col_b0.map(|c| {
        let sb = cov[(c, c)].max(0.0).sqrt();
        Estimate {
            value: fit.b0,
            lower: fit.b0 - t * sb,
            upper: fit.b0 + t * sb,
        }
    });
    let running_in_factor = col_r.map(|c| {
        let sr = cov[(c, c)].max(0.0).sqrt();
        let ln_r = fit.run_in.factor.ln();
        Estimate {
            value: fit.run_in.factor,
            lower: (ln_r - t * sr).exp(),
            upper: (ln_r + t * sr).exp(),
        }
    });
    let quantities = data
        .series
        .iter()
        .enumerate()
        .map(|(j, s)| {
            let rs: Vec<f64> = residuals
                .iter()
                .zip(&pts)
                .filter(|(_, pt)| pt.0 == j)
                .map(|(r, _)| r.residual)
                .collect();
            QuantityFit {
                column: s.column,
                unit: QUANTITIES[s.quantity].unit(),
                points: rs.len(),
                rms_residual: (rs.iter().map(|r| r * r).sum::<f64>() / rs.len() as f64).sqrt(),
                sigma: fit.sigma[j],
            }
        })
        .collect();
    let h_max = data.max_hours();
    let grid: Vec<f64> = (0..=200).map(|i| 1.05 * h_max * i as f64 / 200.0).collect();
    let curves = data
        .series
        .iter()
        .map(|s| FitCurve {
            column: s.column,
            unit: QUANTITIES[s.quantity].unit(),
            hours: grid.clone(),
            values: grid
                .iter()
                .map(|&h| {
                    reference.model(s.quantity, h, k, fit.run_in).0
                        + if QUANTITIES[s.quantity].running_in {
                            fit.b0
                        } else {
                            0.0
                        }
                })
                .collect(),
        })
        .collect();
    let mm3 = |e: &Estimate| Estimate {
        value: e.value * 1e9,
        lower: e.lower * 1e9,
        upper: e.upper * 1e9,
    };
    Ok(Calibration {
        archard_coefficient_mm3_per_n_m: mm3(&kest),
        archard_coefficient_m2_per_n: kest,
        config_archard_coefficient_m2_per_n: model.wear.archard,
        ln_k_standard_error: se,
        running_in_backlash_arcmin: running_in,
        running_in_factor,
        running_in_hours: fitted.factor.then_some(fit.run_in.hours),
        confidence: CONFIDENCE,
        interval_method: if fitted.factor {
            "Gauss-Newton (Wald) covariance s^2 (J^T W J)^-1 in (ln k, ln r, b0), residual \
             variance from the data, Student-t with N - p degrees of freedom; weights 1/sigma^2 \
             per unit, estimated from the residuals"
        } else {
            "Gauss-Newton (Wald) covariance s^2 (J^T W J)^-1 in (ln k, b0), residual variance \
             from the data, Student-t with N - p degrees of freedom; weights 1/sigma^2 per \
             unit, estimated from the residuals"
        },
        points: n,
        parameters: p,
        degrees_of_freedom: dof,
        t_quantile: t,
        residual_variance: s2,
        quantities,
        residuals,
        curves,
        reference_archard_coefficient_m2_per_n: reference.archard,
        reference_hours: reference.last_hours,
        reference_runs: runs,
        reference_stages: stages,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pchip_interpolates_and_keeps_monotone_data_monotone() {
        let x: Vec<f64> = (0..8).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| v * v).collect();
        let c = Pchip::new(x.clone(), y.clone());
        for (a, b) in x.iter().zip(&y) {
            assert!((c.eval(*a).0 - b).abs() < 1e-12);
        }
        let mut prev = -1.0;
        for i in 0..=700 {
            let t = i as f64 * 0.01;
            let (v, d) = c.eval(t);
            assert!(v >= prev && d >= 0.0, "{t} {v} {d}");
            prev = v;
            // Derivative against a central difference.
            let fd = (c.eval(t + 1e-6).0 - c.eval(t - 1e-6).0) / 2e-6;
            assert!((fd - d).abs() < 1e-4 * (1.0 + d.abs()), "{t} {fd} {d}");
        }
        // x^2 between the nodes within 3 % of the node spacing squared.
        assert!((c.eval(3.5).0 - 12.25).abs() < 0.03);
    }

    #[test]
    fn measurements_columns_are_checked() {
        let p = Path::new("m.csv");
        let m = Measurements::parse(p, "hours,backlash_arcmin,max_wear_um\n0,0.1,\n100,0.5,3\n")
            .unwrap();
        assert_eq!(m.series.len(), 2);
        assert_eq!(m.series[1].values, vec![3.0]);
        assert_eq!(m.len(), 3);
        let e = Measurements::parse(p, "hours,torque\n1,2\n").unwrap_err();
        assert!(e.to_string().contains("unknown column(s) torque"), "{e}");
        let e = Measurements::parse(p, "h,backlash_arcmin\n1,2\n").unwrap_err();
        assert!(e.to_string().contains("unknown"), "{e}");
        let e = Measurements::parse(p, "backlash_arcmin\n1\n").unwrap_err();
        assert!(e.to_string().contains("no `hours` column"), "{e}");
        assert!(Measurements::parse(p, "hours,angular_te_arcmin\n1,2\n").is_ok());
        let e = Measurements::parse(p, "hours,backlash_arcmin\n-1,2\n").unwrap_err();
        assert!(e.to_string().contains("hours = -1"), "{e}");
        let e = Measurements::parse(p, "hours,backlash_arcmin\n1,NaN\n").unwrap_err();
        assert!(e.to_string().contains("backlash_arcmin = NaN"), "{e}");
        let e = Measurements::parse(p, "hours,backlash_arcmin\n1,x\n").unwrap_err();
        assert!(e.to_string().contains("not a number"), "{e}");
        let m = Measurements::parse(p, "hours,backlash_arcmin\n1,2\n").unwrap();
        let e = m.check_for_fit(false, false).unwrap_err();
        assert!(e.to_string().contains("at least 2"), "{e}");
    }

    #[test]
    fn fits_nobody_can_stand_behind_are_refused() {
        let p = Path::new("m.csv");
        let m =
            Measurements::parse(p, "hours,lost_motion_arcmin\n0,0.1\n100,0.2\n200,0.3\n").unwrap();
        let est = |value: f64, lower: f64, upper: f64| Estimate {
            value,
            lower,
            upper,
        };
        let res = |r: [f64; 3]| -> Vec<Residual> {
            r.iter()
                .zip([0.0, 100.0, 200.0])
                .map(|(&residual, hours)| Residual {
                    hours,
                    column: "lost_motion_arcmin",
                    measured: 0.0,
                    model: 0.0,
                    residual,
                })
                .collect()
        };
        let good = est(1e-17, 0.9e-17, 1.1e-17);
        let small = res([0.01, -0.01, 0.01]);
        assert!(standing(&good, None, None, &small, &m).is_ok());
        for k in [
            est(1e-17, 0.0, f64::INFINITY),
            est(1e-17, 1e-18, f64::INFINITY),
        ] {
            let e = standing(&k, None, None, &small, &m)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("cannot bound") && e.contains("--measured"),
                "{e}"
            );
        }
        let e = standing(&good, Some(&est(2.0, 0.0, 5.0)), None, &small, &m).unwrap_err();
        assert!(e.to_string().contains("running-in factor"), "{e}");
        let e = standing(
            &good,
            None,
            Some(&est(0.1, f64::NEG_INFINITY, 1.0)),
            &small,
            &m,
        )
        .unwrap_err();
        assert!(e.to_string().contains("running-in play"), "{e}");
        // Spread about the mean: 0.02 arcmin^2; residuals of 0.1: 0.03.
        let e = standing(&good, None, None, &res([0.1, -0.1, 0.1]), &m).unwrap_err();
        assert!(
            e.to_string()
                .contains("worse than the measurements' own mean"),
            "{e}"
        );
    }
}
