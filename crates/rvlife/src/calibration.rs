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
//! of an assembled reducer that the model, with its zero-clearance pins, does not have.
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
//! The reference runs are [`crate::study::run`] with dynamics and the flexible disc off (none
//! of the fitted quantities needs them) and stages spread evenly over the equivalent hours:
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

use std::path::{Path, PathBuf};

use argmin::core::{CostFunction, Executor};
use argmin::solver::brent::BrentOpt;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::config::Model;
use crate::error::{Error, Result};
use crate::quantities::{self, Quantity, StageSummary};

/// The option that names the measurements in messages.
const OPTION: &str = "--measured";

/// One measurable quantity: a quantity of the stage table ([`crate::quantities`]) that a
/// measurements file may hold as a column (its name, with the unit), and whether the running-in
/// play adds to it.
#[derive(Debug, Clone, Copy)]
pub struct Measurable {
    /// The quantity: its name is the column, its unit the column's.
    pub quantity: &'static Quantity,
    /// True if the running-in play `b0` adds to it (backlash, lost motion).
    pub running_in: bool,
}

impl Measurable {
    /// Column name in the measurements file.
    pub fn column(&self) -> &'static str {
        self.quantity.name
    }

    /// Unit of the column (as in its name).
    pub fn unit(&self) -> &'static str {
        self.quantity.unit
    }

    /// The stage's value.
    fn value(&self, s: &StageSummary) -> f64 {
        s.value(self.quantity).number().unwrap_or(f64::NAN)
    }
}

/// The columns a measurements file may have besides `hours`: quantities of the stage table.
/// A quantity the study gains can be measured by adding it here.
pub(crate) const QUANTITIES: &[Measurable] = &[
    Measurable {
        quantity: &quantities::LOST_MOTION,
        running_in: true,
    },
    Measurable {
        quantity: &quantities::BACKLASH,
        running_in: true,
    },
    Measurable {
        quantity: &quantities::ANGULAR_TE,
        running_in: false,
    },
    Measurable {
        quantity: &quantities::MAX_WEAR,
        running_in: false,
    },
];

/// Largest working hours accepted in a measurements file, h (the range of `wear.stage_hours`).
pub(crate) const MAX_HOURS: f64 = 1e7;
/// Largest measured value accepted (arcmin or um).
pub(crate) const MAX_VALUE: f64 = 1e4;
/// Reference horizon of the first pass, in multiples of the largest measured hours.
const FIRST_HORIZON: f64 = 4.0;
/// Stages of the first pass.
const FIRST_STAGES: usize = 24;
/// Reference horizon of the refining passes, in multiples of the largest measured hours.
const REFINE_HORIZON: f64 = 2.0;
/// Stages of the refining passes.
const REFINE_STAGES: usize = 32;
/// Most reference passes.
const MAX_PASSES: usize = 5;
/// Confidence level of the reported interval.
pub(crate) const CONFIDENCE: f64 = 0.95;

/// Measured values of one quantity.
#[derive(Debug, Clone, Serialize)]
pub struct Series {
    /// Column name (an entry of `QUANTITIES`).
    pub column: &'static str,
    /// Index into `QUANTITIES`.
    #[serde(skip)]
    pub quantity: usize,
    /// Working hours of each value, h.
    pub hours: Vec<f64>,
    /// Measured values, in the column's unit.
    pub values: Vec<f64>,
}

/// A measurements file: one series per quantity column (an empty cell is a value not
/// measured at that row's hours).
#[derive(Debug, Clone, Serialize)]
pub struct Measurements {
    /// The file.
    pub path: PathBuf,
    /// The quantity columns in file order.
    pub series: Vec<Series>,
}

fn bad(path: &Path, what: impl Into<String>) -> Error {
    Error::invalid(OPTION, path.display(), what)
}

impl Measurements {
    /// Reads and checks a CSV file with a header: a column `hours` (h, in `[0, 1e7]`) and one
    /// or more of the `QUANTITIES` columns (values finite, in `[0, 1e4]` of their unit; an
    /// empty cell is no value). `#` starts a comment line.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--measured` and the file: it cannot be read; no `hours`
    /// column; unknown or repeated columns (listing the allowed ones); a column of a quantity
    /// the study does not compute yet; a cell that is not a number or out of range (with its
    /// row and column); no quantity column or no value at all.
    pub fn read(path: &Path) -> Result<Measurements> {
        let text =
            std::fs::read_to_string(path).map_err(|e| bad(path, format!("cannot be read: {e}")))?;
        Self::parse(path, &text)
    }

    /// [`Measurements::read`] on the text of the file.
    ///
    /// # Errors
    /// As [`Measurements::read`].
    pub fn parse(path: &Path, text: &str) -> Result<Measurements> {
        let allowed: Vec<&str> = std::iter::once("hours")
            .chain(QUANTITIES.iter().map(Measurable::column))
            .collect();
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .flexible(false)
            .from_reader(text.as_bytes());
        let header: Vec<String> = rdr
            .headers()
            .map_err(|e| bad(path, format!("is not a CSV file with a header: {e}")))?
            .iter()
            .map(str::to_string)
            .collect();
        let unknown: Vec<&str> = header
            .iter()
            .map(String::as_str)
            .filter(|c| !allowed.contains(c))
            .collect();
        if !unknown.is_empty() {
            return Err(bad(
                path,
                format!(
                    "unknown column(s) {}; allowed: {}",
                    unknown.join(", "),
                    allowed.join(", ")
                ),
            ));
        }
        for (i, c) in header.iter().enumerate() {
            if header[..i].contains(c) {
                return Err(bad(path, format!("column {c} is given twice")));
            }
        }
        let Some(hours_col) = header.iter().position(|c| c == "hours") else {
            return Err(bad(
                path,
                format!(
                    "has no `hours` column (working hours, h); columns: {}",
                    header.join(", ")
                ),
            ));
        };
        let mut series = Vec::new();
        let mut cols = Vec::new();
        for (i, c) in header.iter().enumerate() {
            if i == hours_col {
                continue;
            }
            let q = QUANTITIES
                .iter()
                .position(|q| q.column() == c)
                .expect("checked against the allowed columns");
            series.push(Series {
                column: QUANTITIES[q].column(),
                quantity: q,
                hours: Vec::new(),
                values: Vec::new(),
            });
            cols.push(i);
        }
        if series.is_empty() {
            return Err(bad(
                path,
                format!(
                    "has no measured quantity; give one or more of the columns {}",
                    allowed[1..].join(", ")
                ),
            ));
        }
        for (r, rec) in rdr.records().enumerate() {
            let row = r + 2; // 1-based, after the header
            let rec = rec.map_err(|e| bad(path, format!("row {row}: {e}")))?;
            let cell = |i: usize| -> Result<Option<f64>> {
                let s = rec.get(i).unwrap_or("");
                if s.is_empty() {
                    return Ok(None);
                }
                s.parse::<f64>().map(Some).map_err(|_| {
                    bad(
                        path,
                        format!("row {row}, column {}: {s:?} is not a number", header[i]),
                    )
                })
            };
            let Some(h) = cell(hours_col)? else {
                return Err(bad(path, format!("row {row}: the hours cell is empty")));
            };
            if !(h.is_finite() && (0.0..=MAX_HOURS).contains(&h)) {
                return Err(bad(
                    path,
                    format!("row {row}, column hours = {h}: must be a finite number in [0, 1e7] h"),
                ));
            }
            for (s, &i) in series.iter_mut().zip(&cols) {
                if let Some(v) = cell(i)? {
                    if !(v.is_finite() && (0.0..=MAX_VALUE).contains(&v)) {
                        return Err(bad(
                            path,
                            format!(
                                "row {row}, column {} = {v}: must be a finite number in \
                                 [0, 1e4] {}",
                                header[i],
                                QUANTITIES[s.quantity].unit()
                            ),
                        ));
                    }
                    s.hours.push(h);
                    s.values.push(v);
                }
            }
        }
        series.retain(|s| !s.values.is_empty());
        if series.is_empty() {
            return Err(bad(path, "has no measured values (no data rows)"));
        }
        Ok(Measurements {
            path: path.to_path_buf(),
            series,
        })
    }

    /// Number of measured values over all series.
    pub fn len(&self) -> usize {
        self.series.iter().map(|s| s.values.len()).sum()
    }

    /// True if there are no measured values (never after [`Measurements::read`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Largest measured working hours, h.
    pub fn max_hours(&self) -> f64 {
        self.series
            .iter()
            .flat_map(|s| s.hours.iter().copied())
            .fold(0.0, f64::max)
    }

    /// Checks that the measurements can determine the parameters: `N >= p + 1` values
    /// (`p` = 1, or 2 with `fit_running_in`), some hours above 0, and with `fit_running_in` a
    /// backlash or lost-motion column.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--measured` (or `--fit-running-in`).
    pub fn check_for_fit(&self, fit_running_in: bool) -> Result<()> {
        let p = 1 + usize::from(fit_running_in);
        if self.len() < p + 1 {
            return Err(bad(
                &self.path,
                format!(
                    "has {} measured value(s); fitting {} parameter(s) ({}) needs at least {} \
                     (parameters + 1, for the residual variance)",
                    self.len(),
                    p,
                    if fit_running_in { "k and b0" } else { "k" },
                    p + 1
                ),
            ));
        }
        if self.max_hours() <= 0.0 {
            return Err(bad(
                &self.path,
                "all measurements are at 0 h, where there is no wear: the Archard coefficient \
                 cannot be found; give measurements after some working hours",
            ));
        }
        if fit_running_in
            && !self
                .series
                .iter()
                .any(|s| QUANTITIES[s.quantity].running_in)
        {
            return Err(Error::invalid(
                "--fit-running-in",
                "set",
                format!(
                    "the running-in play adds to backlash and lost motion, and {} has neither \
                     column (backlash_arcmin, lost_motion_arcmin)",
                    self.path.display()
                ),
            ));
        }
        Ok(())
    }
}

/// Monotone piecewise-cubic Hermite interpolation (Fritsch and Carlson, SIAM J. Numer. Anal.
/// 17, 1980; end slopes as in Moler, Numerical Computing with MATLAB, `pchip`), linear beyond
/// the ends. Keeps a monotone series monotone and is continuously differentiable.
#[derive(Debug, Clone)]
struct Pchip {
    x: Vec<f64>,
    y: Vec<f64>,
    d: Vec<f64>,
}

impl Pchip {
    /// `x` strictly increasing, at least 2 points.
    fn new(x: Vec<f64>, y: Vec<f64>) -> Pchip {
        let n = x.len();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let del: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        let mut d = vec![0.0; n];
        if n == 2 {
            d = vec![del[0]; 2];
        } else {
            for i in 1..n - 1 {
                if del[i - 1] * del[i] > 0.0 {
                    let w1 = 2.0 * h[i] + h[i - 1];
                    let w2 = h[i] + 2.0 * h[i - 1];
                    d[i] = (w1 + w2) / (w1 / del[i - 1] + w2 / del[i]);
                }
            }
            let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
                let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
                if s * d0 <= 0.0 {
                    0.0
                } else if d0 * d1 < 0.0 && s.abs() > 3.0 * d0.abs() {
                    3.0 * d0
                } else {
                    s
                }
            };
            d[0] = end(h[0], h[1], del[0], del[1]);
            d[n - 1] = end(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
        }
        Pchip { x, y, d }
    }

    /// Value and derivative at `t`.
    fn eval(&self, t: f64) -> (f64, f64) {
        let n = self.x.len();
        if t <= self.x[0] {
            return (self.y[0] + self.d[0] * (t - self.x[0]), self.d[0]);
        }
        if t >= self.x[n - 1] {
            return (
                self.y[n - 1] + self.d[n - 1] * (t - self.x[n - 1]),
                self.d[n - 1],
            );
        }
        let i = self.x.partition_point(|&v| v <= t).clamp(1, n - 1) - 1;
        let h = self.x[i + 1] - self.x[i];
        let s = (t - self.x[i]) / h;
        let (y0, y1, d0, d1) = (self.y[i], self.y[i + 1], self.d[i], self.d[i + 1]);
        let v = (2.0 * s.powi(3) - 3.0 * s * s + 1.0) * y0
            + (s.powi(3) - 2.0 * s * s + s) * h * d0
            + (-2.0 * s.powi(3) + 3.0 * s * s) * y1
            + (s.powi(3) - s * s) * h * d1;
        let dv = (6.0 * s * s - 6.0 * s) / h * y0
            + (3.0 * s * s - 4.0 * s + 1.0) * d0
            + (-6.0 * s * s + 6.0 * s) / h * y1
            + (3.0 * s * s - 2.0 * s) * d1;
        (v, dv)
    }
}

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
    /// Model value and its derivative with respect to `ln k` of quantity `q` at hours `h`.
    fn model(&self, q: usize, h: f64, k: f64) -> (f64, f64) {
        let c = &self.curves[q];
        let big_h = h * k / self.archard;
        let (v, dv) = c.eval(big_h);
        (v, dv * big_h)
    }
}

/// The model of one reference pass: stages over `[0, horizon]` equivalent hours at `archard`,
/// dynamics and the flexible disc off.
fn reference_model(model: &Model, archard: f64, horizon: f64, stages: usize) -> Model {
    let mut m = model.clone();
    m.wear.archard = archard;
    m.dynamics.enabled = false;
    m.fem.enabled = false;
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
                 equivalent hours that exceeds the work budget ({allowed}); give fewer hours \
                 or raise --work-budget-min"
            ),
        ),
        other => other,
    }
}

/// The fit's k-h scaling holds for a steady coefficient of the disc alone: a config with
/// running-in (`wear.running_in_factor` > 1, whose time constant is in real hours) or with
/// wearing crank bearings (their clearance grows with real hours, whatever the disc's
/// coefficient) is refused by its key.
fn steady_only(model: &Model) -> Result<()> {
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
    let r = model.wear.running_in.factor;
    if r > 1.0 {
        return Err(Error::invalid(
            "wear.running_in_factor",
            r,
            "must be 1 for calibrate --measured: the fit of the steady coefficient scales the \
             hours, which a running-in time constant does not allow (fitting the running-in \
             is not built yet)",
        ));
    }
    Ok(())
}

/// Checks, before any work, that the first reference study of the calibration fits the work
/// budget ([`crate::budget`]): the stage analyses and profile updates over
/// `4 x` the largest measured hours at the config's coefficient, including the updates that
/// `wear.max_wear_step_um` asks for at the unworn disc's wear rate (one wear-rate evaluation).
///
/// # Errors
/// [`Error::Invalid`] naming `--measured`, the hours and the estimate.
pub fn check_budget(model: &Model, data: &Measurements) -> Result<()> {
    steady_only(model)?;
    let h_max = data.max_hours();
    let horizon = FIRST_HORIZON * h_max;
    let m = reference_model(model, model.wear.archard, horizon, FIRST_STAGES);
    let check = || -> Result<()> {
        crate::study::check_work(&m)?;
        let inputs = m.wear_inputs();
        let rate = crate::wear::wear_rate(&m.profile()?, &inputs)?;
        let max_rate = rate.iter().copied().fold(0.0, f64::max);
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

/// Least-squares fit on one reference.
struct Fit {
    ln_k: f64,
    b0: f64,
    sigma: Vec<f64>,
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
    ln_k: f64,
) -> (f64, f64) {
    let k = ln_k.exp();
    let pts = points(data);
    let model: Vec<f64> = pts
        .iter()
        .map(|&(j, h, _)| reference.model(data.series[j].quantity, h, k).0)
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
    lo: f64,
    hi: f64,
) -> Result<f64> {
    const SCAN: usize = 60;
    let cost = |x: f64| profile_cost(reference, data, sigma, fit_b0, x).1;
    let xs: Vec<f64> = (0..=SCAN)
        .map(|i| lo + (hi - lo) * i as f64 / SCAN as f64)
        .collect();
    let best = (0..=SCAN)
        .min_by(|&a, &b| cost(xs[a]).total_cmp(&cost(xs[b])))
        .expect("a scan");
    let (a, b) = (xs[best.saturating_sub(1)], xs[(best + 1).min(SCAN)]);
    struct Cost<'a>(&'a dyn Fn(f64) -> f64);
    impl CostFunction for Cost<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, x: &f64) -> std::result::Result<f64, argmin::core::Error> {
            Ok((self.0)(*x))
        }
    }
    let res = Executor::new(Cost(&cost), BrentOpt::new(a, b).set_tolerance(1e-8, 1e-10))
        .configure(|st| st.max_iters(200))
        .timer(false)
        .run()
        .map_err(|e| Error::numerical("calibration", e.to_string()))?;
    let x = res.state.best_param.unwrap_or(xs[best]);
    Ok(if cost(x) <= cost(xs[best]) {
        x
    } else {
        xs[best]
    })
}

/// Iteratively reweighted fit on one reference, `ln k` in `[lo, hi]`.
fn fit_on(
    reference: &Reference,
    data: &Measurements,
    fit_b0: bool,
    lo: f64,
    hi: f64,
) -> Result<Fit> {
    let n_total = data.len() as f64;
    let p = 1.0 + f64::from(u8::from(fit_b0));
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
        let x = minimise(reference, data, &sigma, fit_b0, lo, hi)?;
        let converged = (x - ln_k).abs() < 1e-7;
        ln_k = x;
        if groups == 1 || converged {
            break;
        }
        let (b0, _) = profile_cost(reference, data, &sigma, fit_b0, ln_k);
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
                        let m = reference.model(s.quantity, *h, k).0
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
    let (b0, _) = profile_cost(reference, data, &sigma, fit_b0, ln_k);
    Ok(Fit { ln_k, b0, sigma })
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
    let study = crate::study::run(&m, &|_, _| {})
        .map_err(|e| budget_error(&data.path, h_max, horizon, e))?;
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
/// negligible.
///
/// # Errors
/// [`Error::Invalid`] naming `--measured` for too few values, no hours above 0, work beyond the
/// budget, wear the model cannot follow, data that do not determine `k` (flat model), or a
/// coefficient beyond `1e6` times the config's either way; solver failures of the studies.
pub fn calibrate(
    model: &Model,
    data: &Measurements,
    options: Options,
    progress: &dyn Fn(usize),
) -> Result<Calibration> {
    data.check_for_fit(options.fit_running_in)?;
    steady_only(model)?;
    let h_max = data.max_hours();
    let fit_b0 = options.fit_running_in;
    let k_cfg = model.wear.archard;
    let mut archard = k_cfg;
    let mut runs = 0;
    let mut stages_total = 0;
    let mut last_fit: Option<(Reference, Fit)> = None;
    for pass in 0..MAX_PASSES {
        let (factor, stages) = if pass == 0 {
            (FIRST_HORIZON, FIRST_STAGES)
        } else {
            (REFINE_HORIZON, REFINE_STAGES)
        };
        progress(pass + 1);
        let reference = run_reference(model, data, archard, factor * h_max, stages)?;
        runs += 1;
        stages_total += stages + 1;
        // ln k bracket: up to the validity of the reference; down to a thousandth of the
        // first pass' horizon, a quarter of the refining passes'.
        let hi = (archard * reference.last_hours / h_max).ln();
        let lo = if pass == 0 {
            (archard / 1000.0).ln()
        } else {
            (archard / 4.0).ln()
        };
        let fit = fit_on(&reference, data, fit_b0, lo, hi)?;
        let k = fit.ln_k.exp();
        let at_top = hi - fit.ln_k < 1e-3;
        let settled = pass > 0 && (fit.ln_k - archard.ln()).abs() < 1.25f64.ln() && !at_top;
        if at_top && reference.last_hours < 0.999 * factor * h_max {
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
        last_fit = Some((reference, fit));
        if settled {
            break;
        }
    }
    let (reference, fit) = last_fit.expect("at least one pass");
    summarise(model, data, &reference, &fit, fit_b0, runs, stages_total)
}

/// Interval, residuals and curves of the final fit.
fn summarise(
    model: &Model,
    data: &Measurements,
    reference: &Reference,
    fit: &Fit,
    fit_b0: bool,
    runs: usize,
    stages: usize,
) -> Result<Calibration> {
    let pts = points(data);
    let n = pts.len();
    let p = 1 + usize::from(fit_b0);
    let k = fit.ln_k.exp();
    let ri = |j: usize| QUANTITIES[data.series[j].quantity].running_in;
    // Weighted Jacobian and residuals.
    let mut jac = DMatrix::<f64>::zeros(n, p);
    let mut res = DVector::<f64>::zeros(n);
    let mut residuals = Vec::with_capacity(n);
    for (i, &(j, h, y)) in pts.iter().enumerate() {
        let q = data.series[j].quantity;
        let (m, dm) = reference.model(q, h, k);
        let m = m + if ri(j) { fit.b0 } else { 0.0 };
        let w = 1.0 / fit.sigma[j];
        jac[(i, 0)] = dm * w;
        if fit_b0 && ri(j) {
            jac[(i, 1)] = w;
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
    let running_in = fit_b0.then(|| {
        let sb = cov[(1, 1)].max(0.0).sqrt();
        Estimate {
            value: fit.b0,
            lower: fit.b0 - t * sb,
            upper: fit.b0 + t * sb,
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
                    reference.model(s.quantity, h, k).0
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
        confidence: CONFIDENCE,
        interval_method: "Gauss-Newton (Wald) covariance s^2 (J^T W J)^-1 in (ln k, b0), \
                          residual variance from the data, Student-t with N - p degrees of \
                          freedom; weights 1/sigma^2 per unit, estimated from the residuals",
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
        let e = m.check_for_fit(false).unwrap_err();
        assert!(e.to_string().contains("at least 2"), "{e}");
    }
}
