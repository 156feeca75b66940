//! Accuracy life: the working hours at which a reducer first leaves its accuracy spec
//! (`[life]`: lost motion, backlash, angular TE above, torsional stiffness below a
//! threshold).
//!
//! The quantities are found at the study's stages; where a threshold is crossed between two
//! stages the crossing is located by Brent's root finder on the working hours, each trial the
//! wear at those hours and an analysis of the worn reducer (not an interpolation between the
//! stages: lost motion and backlash grow unevenly as the worn band spreads over the flank),
//! down to `LIFE_TOLERANCE`; the last bracket is interpolated linearly.

use serde::Serialize;

use crate::config::LifeThresholds;
use crate::error::Result;
use crate::quantities::{AccuracyPoint, Sense, LIFE};

/// Relative width of the last bracket of the crossing's search (of the hours at its upper end): 0.5 %.
pub(crate) const LIFE_TOLERANCE: f64 = 0.005;

/// The accuracy life found.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct AccuracyLife {
    /// Working hours at which the first threshold is crossed, h; `None` when none is crossed
    /// within the horizon (the life exceeds `horizon_h`; absent from JSON).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub accuracy_life_h: Option<f64>,
    /// The threshold crossed first (its `[life]` key).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub limited_by: Option<&'static str>,
    /// The last working hours studied, h: the last stage, or beyond it as far as the
    /// integration was stepped to find the crossing (`life.max_hours`).
    pub horizon_h: f64,
}

/// Margins of `p` against every threshold set ([`LIFE`]), relative to the threshold: positive
/// inside the spec, `(limit - value)/limit` (`(value - limit)/limit` for a smallest value, the
/// stiffness), with the key.
pub(crate) fn margins(th: &LifeThresholds, p: &AccuracyPoint) -> Vec<(&'static str, f64)> {
    LIFE.iter()
        .filter_map(|l| {
            let limit = th.threshold(l.key)?;
            let value = (l.quantity.accuracy?)(p);
            Some(match l.sense {
                Sense::AtMost => (l.key, (limit - value) / limit),
                Sense::AtLeast => (l.key, (value - limit) / limit),
            })
        })
        .collect()
}

/// The smallest margin and its key (`None` without thresholds).
fn worst(th: &LifeThresholds, p: &AccuracyPoint) -> Option<(&'static str, f64)> {
    margins(th, p)
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The accuracy life from the quantities at increasing working hours `points`, refining a
/// crossing between two of them with `at(hours)` (the quantities after that many hours of
/// wear), by Brent's root finder down to [`LIFE_TOLERANCE`] and linear interpolation of the crossing
/// margin in the last bracket. Without a crossing among `points`, `at` steps on beyond the last
/// one (x 1.5 in hours) up to `th.max_hours` (default 10 x the last point's hours), calling
/// `beyond(hours, max_hours)` before each such step (the search's notice to the user). `None`
/// without thresholds.
///
/// # Errors
/// Those of `at`.
pub(crate) fn accuracy_life(
    th: &LifeThresholds,
    points: &[AccuracyPoint],
    mut at: impl FnMut(f64) -> Result<AccuracyPoint>,
    beyond: &dyn Fn(f64, f64),
) -> Result<Option<AccuracyLife>> {
    if !th.any() || points.is_empty() {
        return Ok(None);
    }
    let horizon_h = points.last().map_or(0.0, |p| p.hours);
    let Some(i) = points.iter().position(|p| outside(th, p)) else {
        let last = points.last().copied().expect("points is not empty");
        let (bracket, horizon_h) = beyond_stages(th, last, &mut at, beyond);
        let Some((lo, hi)) = bracket else {
            return Ok(Some(AccuracyLife {
                accuracy_life_h: None,
                limited_by: None,
                horizon_h,
            }));
        };
        let (h, key) = locate_crossing(th, lo, hi, &mut at)?;
        return Ok(Some(AccuracyLife {
            accuracy_life_h: Some(h),
            limited_by: Some(key),
            horizon_h,
        }));
    };
    if i == 0 {
        return Ok(Some(AccuracyLife {
            accuracy_life_h: Some(points[0].hours),
            limited_by: worst(th, &points[0]).map(|w| w.0),
            horizon_h,
        }));
    }
    let (h, key) = locate_crossing(th, points[i - 1], points[i], &mut at)?;
    Ok(Some(AccuracyLife {
        accuracy_life_h: Some(h),
        limited_by: Some(key),
        horizon_h,
    }))
}

/// The search of [`accuracy_life`] beyond the stages, from the last stage's point `last`
/// (inside the spec): the wear integration stepped on (x 1.5 in hours, each trial `at`, each
/// announced first by `beyond(trial hours, horizon)`) up to the horizon `max_hours` (default
/// 10 x the last stage), or until a trial fails (the wear model leaves its validity). Returns
/// the bracket of the crossing (the last trial inside the spec and the first outside), if a
/// trial left the spec, and the hours reached (h).
pub(crate) fn beyond_stages(
    th: &LifeThresholds,
    last: AccuracyPoint,
    at: &mut dyn FnMut(f64) -> Result<AccuracyPoint>,
    beyond: &dyn Fn(f64, f64),
) -> (Option<(AccuracyPoint, AccuracyPoint)>, f64) {
    let max_h = th.max_hours.unwrap_or(10.0 * last.hours);
    let mut horizon_h = last.hours;
    let mut lo = last;
    while lo.hours < max_h && lo.hours > 0.0 {
        let next = (1.5 * lo.hours).min(max_h);
        beyond(next, max_h);
        let Ok(p) = at(next) else {
            break;
        };
        horizon_h = next;
        if outside(th, &p) {
            return (Some((lo, p)), horizon_h);
        }
        lo = p;
    }
    (None, horizon_h)
}

/// Whether the point `p` lies outside the spec `th` (a margin below zero).
pub(crate) fn outside(th: &LifeThresholds, p: &AccuracyPoint) -> bool {
    worst(th, p).is_some_and(|w| w.1 < 0.0)
}

/// The crossing in the bracket `lo` (inside the spec) .. `hi` (outside): Brent's root
/// finder (argmin's `BrentRoot`: inverse quadratic interpolation safeguarded by bisection) on
/// the smallest margin against the hours, down to a bracket of [`LIFE_TOLERANCE`] of `hi`'s
/// hours, then [`crossing`] in the tightest bracket evaluated. `lo` and `hi` are not
/// evaluated again.
///
/// # Errors
/// Those of `at`; a root finder that has not converged in 100 steps (it cannot happen with a
/// valid bracket: the bisection safeguard halves it at least every other step).
fn locate_crossing(
    th: &LifeThresholds,
    lo: AccuracyPoint,
    hi: AccuracyPoint,
    at: &mut dyn FnMut(f64) -> Result<AccuracyPoint>,
) -> Result<(f64, &'static str)> {
    use argmin::core::{CostFunction, Executor, State, TerminationReason, TerminationStatus};
    use argmin::solver::brent::BrentRoot;
    use std::cell::RefCell;

    /// The smallest margin at the trial hours; every point evaluated is kept.
    struct Margin<'a> {
        th: &'a LifeThresholds,
        at: RefCell<&'a mut dyn FnMut(f64) -> Result<AccuracyPoint>>,
        seen: &'a RefCell<Vec<AccuracyPoint>>,
        failure: &'a RefCell<Option<crate::error::Error>>,
    }
    impl CostFunction for Margin<'_> {
        type Param = f64;
        type Output = f64;
        fn cost(&self, h: &f64) -> std::result::Result<f64, argmin::core::Error> {
            let known = self.seen.borrow().iter().find(|p| p.hours == *h).copied();
            let p = match known {
                Some(p) => p,
                None => match (self.at.borrow_mut())(*h) {
                    Ok(p) => {
                        self.seen.borrow_mut().push(p);
                        p
                    }
                    Err(e) => {
                        *self.failure.borrow_mut() = Some(e);
                        return Err(argmin::core::Error::msg("trial failed"));
                    }
                },
            };
            Ok(worst(self.th, &p).map_or(0.0, |w| w.1))
        }
    }
    let seen = RefCell::new(vec![lo, hi]);
    let failure = RefCell::new(None);
    let margin = Margin {
        th,
        at: RefCell::new(at),
        seen: &seen,
        failure: &failure,
    };
    let tol = LIFE_TOLERANCE * hi.hours;
    let run = Executor::new(margin, BrentRoot::new(lo.hours, hi.hours, tol))
        .configure(|s| s.max_iters(100))
        .run();
    if let Some(e) = failure.borrow_mut().take() {
        return Err(e);
    }
    let converged = match &run {
        Ok(r) => matches!(
            r.state().get_termination_status(),
            TerminationStatus::Terminated(TerminationReason::SolverConverged)
        ),
        Err(_) => false,
    };
    if !converged {
        return Err(crate::error::Error::numerical(
            "accuracy life",
            format!(
                "the crossing between {:.0} h and {:.0} h was not located to {tol:.1} h in 100 \
                 steps",
                lo.hours, hi.hours
            ),
        ));
    }
    // The tightest bracket evaluated: the last point inside the spec before the first one
    // outside.
    let out = |p: &AccuracyPoint| worst(th, p).is_some_and(|w| w.1 < 0.0);
    let seen = seen.into_inner();
    let first_out = seen
        .iter()
        .filter(|p| out(p))
        .min_by(|a, b| a.hours.total_cmp(&b.hours))
        .copied()
        .unwrap_or(hi);
    let last_in = seen
        .iter()
        .filter(|p| !out(p) && p.hours < first_out.hours)
        .max_by(|a, b| a.hours.total_cmp(&b.hours))
        .copied()
        .unwrap_or(lo);
    Ok(crossing(th, &last_in, &first_out))
}

/// The crossing between `lo` (inside the spec) and `hi` (outside): the threshold crossed at
/// `hi` (the smallest margin there) and the hours at which its margin, interpolated linearly,
/// is zero.
pub(crate) fn crossing(
    th: &LifeThresholds,
    lo: &AccuracyPoint,
    hi: &AccuracyPoint,
) -> (f64, &'static str) {
    let (key, m_hi) = worst(th, hi).unwrap_or(("", 0.0));
    let m_lo = margins(th, lo)
        .into_iter()
        .find(|m| m.0 == key)
        .map_or(0.0, |m| m.1);
    let f = if m_lo > m_hi {
        m_lo / (m_lo - m_hi)
    } else {
        1.0
    };
    (lo.hours + f.clamp(0.0, 1.0) * (hi.hours - lo.hours), key)
}

/// The verdict of a study in one line, for the console and the report: the accuracy life and
/// the threshold that sets it with its spec ("accuracy life 1858 h, limited by lost motion
/// (spec 1 arcmin)"), or the hours within spec with the smallest margin at the last point
/// studied, or what is missing; followed by the duty it assumes (`levels`, the `[load]`
/// spectrum: one level's torque and input speed, or the number of levels and the largest
/// torque).
///
/// `th`: the `[life]` thresholds; `life`: the study's accuracy life (`None` without
/// thresholds); `last`: the quantities at the last stage. Source: docs/model.md section 11.
pub fn verdict(
    th: &LifeThresholds,
    life: Option<&AccuracyLife>,
    last: Option<&AccuracyPoint>,
    levels: &[crate::wear::LoadLevel],
) -> String {
    let label = |key: &'static str| -> (&'static str, &'static str) {
        LIFE.iter()
            .find(|l| l.key == key)
            .map_or((key, ""), |l| (l.quantity.label, l.quantity.unit))
    };
    // The threshold as written (every key reaching here has one).
    let limit = |key: &str| {
        th.threshold(key)
            .map_or(String::from("?"), |v| v.to_string())
    };
    let spec = |key: &'static str| {
        let (name, unit) = label(key);
        format!("{name} (spec {} {unit})", limit(key))
    };
    let duty = match levels {
        [one] => format!(
            "duty: {:.0} N m at {:.0} rpm input",
            one.torque.abs(),
            one.speed_rpm
        ),
        many => format!(
            "duty: {} load levels up to {:.0} N m",
            many.len(),
            many.iter().map(|l| l.torque.abs()).fold(0.0, f64::max)
        ),
    };
    let head = match life {
        None => "no accuracy spec: set [life] (lost_motion_arcmin, backlash_arcmin, \
                 angular_te_arcmin or torsional_stiffness_min_nm_per_arcmin) for an accuracy \
                 life"
            .to_string(),
        Some(AccuracyLife {
            accuracy_life_h: Some(h),
            limited_by: Some(key),
            ..
        }) if *h <= 0.0 => format!("out of spec when new: {}", spec(key)),
        Some(AccuracyLife {
            accuracy_life_h: Some(h),
            limited_by: Some(key),
            ..
        }) => format!("accuracy life {h:.0} h, limited by {}", spec(key)),
        Some(l) => {
            let margin = last.and_then(|p| {
                let (key, m) = worst(th, p)?;
                let value = LIFE.iter().find(|x| x.key == key)?.quantity.accuracy?(p);
                Some((key, value, p.hours, m))
            });
            match margin {
                Some((key, value, hours, m)) => {
                    let (name, unit) = label(key);
                    format!(
                        "within spec up to {:.0} h (smallest margin: {name} {value:.3} {unit} \
                         at {hours:.0} h against {} {unit}, {:.0} % to go)",
                        l.horizon_h,
                        limit(key),
                        100.0 * m
                    )
                }
                None => format!("within spec up to {:.0} h", l.horizon_h),
            }
        }
    };
    format!("{head}; {duty}")
}
