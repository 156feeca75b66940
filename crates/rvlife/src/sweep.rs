//! A design sweep: the product of values of config keys, one accuracy-life study per design
//! (docs/config.md, "Design sweeps"; `rvlife sweep`, the Python package's `grid` and `sweep`).
//!
//! Each design is the base config with the varied keys set ([`crate::config::edit::set`],
//! comments kept) and validated before any study starts, so a design out of range is refused
//! naming its key and the other keys' values; the whole sweep's estimated work is checked
//! against the work budget. Each study is the one `rvlife run` runs on that config; a study
//! that fails is kept as a row with its reason, and the sweep goes on.

use serde_json::Value as Json;

use crate::config::{edit, Config, Model};
use crate::error::{Error, Result};
use crate::study::Study;

/// Largest number of designs of one sweep.
pub const MAX_DESIGNS: usize = 10_000;

/// One varied key and its values (`--vary KEY=LO:HI:N` or `KEY=A,B,C`).
#[derive(Debug, Clone, PartialEq)]
pub struct Vary {
    /// The dotted key (`cycloid.eccentricity_mm`).
    pub key: String,
    /// Its values, in order.
    pub values: Vec<Json>,
}

/// `v` rounded to 12 significant digits: the grid's `lo + k (hi - lo)/(n - 1)` written as
/// the user would (1.3, not 1.2999999999999998).
fn tidy(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// A value as written on the command line for `option` (`--vary`, `--set`) in the argument
/// `spec`: a TOML value (`1.2`, `40`, `true`, `"rollers"`, `[1.0, 2.0]`), else the text as a
/// string (`rollers`).
///
/// # Errors
/// [`Error::Invalid`] naming `option` and `spec` for a number that is not finite (`nan`,
/// `inf`, anywhere in an array), named as written: JSON, in which the designs are recorded,
/// has no such numbers.
pub fn parse_value(option: &str, spec: &str, text: &str) -> Result<Json> {
    let t = text.trim();
    let v = match format!("v = {t}").parse::<toml::Table>() {
        Ok(mut table) => table.remove("v"),
        Err(_) => None,
    };
    fn finite(v: &toml::Value) -> bool {
        match v {
            toml::Value::Float(x) => x.is_finite(),
            toml::Value::Array(a) => a.iter().all(finite),
            toml::Value::Table(m) => m.values().all(finite),
            _ => true,
        }
    }
    match v {
        Some(v) if !finite(&v) => Err(Error::invalid(
            option,
            spec,
            format!("the value `{t}` is not a finite number"),
        )),
        Some(v) => Ok(serde_json::to_value(v).unwrap_or_else(|_| Json::String(t.to_string()))),
        None => Ok(Json::String(t.to_string())),
    }
}

impl Vary {
    /// Parses `KEY=LO:HI:N` (N values evenly spaced from LO to HI, N >= 1; N = 1 is LO) or
    /// `KEY=A,B,...` (the values, each as [`parse_value`] reads it).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `option` (`--vary`) with the text and the allowed forms.
    pub fn parse(option: &str, spec: &str) -> Result<Vary> {
        let bad = |why: &str| {
            Error::invalid(
                option,
                spec,
                format!("{why}; write KEY=LO:HI:N (N values from LO to HI) or KEY=A,B,C"),
            )
        };
        let (key, rest) = spec.split_once('=').ok_or_else(|| bad("no `=`"))?;
        let key = key.trim().to_string();
        if key.is_empty() || rest.trim().is_empty() {
            return Err(bad("a key and its values are needed"));
        }
        let parts: Vec<&str> = rest.split(':').collect();
        let values = if parts.len() == 3 {
            let num = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
            let (Some(lo), Some(hi)) = (num(parts[0]), num(parts[1])) else {
                return Err(bad("LO and HI must be finite numbers"));
            };
            let n: usize = parts[2]
                .trim()
                .parse()
                .ok()
                .filter(|&n| (1..=MAX_DESIGNS).contains(&n))
                .ok_or_else(|| bad(&format!("N must be a whole number in [1, {MAX_DESIGNS}]")))?;
            (0..n)
                .map(|k| {
                    let v = if n == 1 {
                        lo
                    } else {
                        tidy(lo + (hi - lo) * k as f64 / (n - 1) as f64)
                    };
                    serde_json::json!(v)
                })
                .collect()
        } else if parts.len() == 1 {
            rest.split(',')
                .map(|t| parse_value(option, spec, t))
                .collect::<Result<Vec<_>>>()?
        } else {
            return Err(bad("LO:HI:N takes three parts"));
        };
        Ok(Vary { key, values })
    }
}

/// One design of a sweep.
#[derive(Debug, Clone)]
pub struct Design {
    /// Its index in the sweep (0-based, the product's order: the last varied key fastest).
    pub index: usize,
    /// The varied keys' values.
    pub values: Vec<(String, Json)>,
    /// Its config text (the base with the keys set).
    pub text: String,
    /// Its validated model.
    pub model: Model,
}

/// The designs of `varies` over the base config `text` (with the fixed `sets` applied
/// first), each validated as `rvlife run` validates a file, with the work budget of the
/// whole sweep (`budget_min`, minutes): first every design's sections and work (no static
/// analysis; the sum against the budget as it grows, so a sweep too large is refused after
/// the designs that exceed it), then each design's physical checks and assembly
/// (`study::admitted`).
///
/// # Errors
/// [`Error::Invalid`] naming a key that is not a config key or a value out of its range (with
/// the design's other values), a key varied twice, more than [`MAX_DESIGNS`] designs, or the
/// whole sweep's work beyond the budget (naming `--vary`).
pub fn designs(
    text: &str,
    origin: &str,
    base_dir: Option<&std::path::Path>,
    sets: &[(String, Json)],
    varies: &[Vary],
    budget_min: f64,
) -> Result<Vec<Design>> {
    for (i, v) in varies.iter().enumerate() {
        if varies[..i].iter().any(|w| w.key == v.key) || sets.iter().any(|s| s.0 == v.key) {
            return Err(Error::invalid(
                "--vary",
                &v.key,
                "each key varied once, and not also set",
            ));
        }
    }
    let count = varies
        .iter()
        .try_fold(1usize, |n, v| n.checked_mul(v.values.len()))
        .filter(|&n| n <= MAX_DESIGNS)
        .ok_or_else(|| {
            Error::invalid(
                "--vary",
                varies
                    .iter()
                    .map(|v| v.values.len().to_string())
                    .collect::<Vec<_>>()
                    .join(" x "),
                format!("at most {MAX_DESIGNS} designs in one sweep"),
            )
        })?;
    let fixed: Vec<(String, Option<Json>)> = sets
        .iter()
        .map(|(k, v)| (k.clone(), Some(v.clone())))
        .collect();
    let base = edit::set(text, origin, &fixed)?;
    // Every design's sections and work first (no static analysis), the sum against the budget
    // as it grows: a sweep too large is refused after the designs that exceed the budget,
    // before any design's physical checks or FE disc.
    let budget = crate::budget::solves_in_minutes(budget_min);
    let mut work = 0.0;
    let mut checked = Vec::with_capacity(count);
    for index in 0..count {
        // Mixed radix, the last key fastest.
        let mut rest = index;
        let mut values = vec![(String::new(), Json::Null); varies.len()];
        for (j, v) in varies.iter().enumerate().rev() {
            values[j] = (v.key.clone(), v.values[rest % v.values.len()].clone());
            rest /= v.values.len();
        }
        let edits: Vec<(String, Option<Json>)> = values
            .iter()
            .map(|(k, v)| (k.clone(), Some(v.clone())))
            .collect();
        let t = edit::set(&base, origin, &edits).map_err(|e| in_design(e, index, &values))?;
        let mut cfg = Config::from_toml_in(&t, origin, base_dir)?;
        cfg.work_budget_minutes = budget_min;
        let model = crate::study::budgeted(&cfg).map_err(|e| in_design(e, index, &values))?;
        let (w, s) = crate::study::study_work(&model);
        work += w + s;
        if work > budget {
            return Err(Error::invalid(
                "--vary",
                format!("{count} designs"),
                format!(
                    "the sweep's estimated work, at least {:.1} min (the first {} of {count} \
                     designs), exceeds the work budget of {:.1} min (--work-budget-min): fewer \
                     designs, or a larger budget",
                    crate::budget::minutes(work),
                    index + 1,
                    budget_min
                ),
            ));
        }
        checked.push((index, values, t, cfg, model));
    }
    let mut out = Vec::with_capacity(count);
    for (index, values, text, cfg, model) in checked {
        let model =
            crate::study::admitted(&cfg, model).map_err(|e| in_design(e, index, &values))?;
        out.push(Design {
            index,
            values,
            text,
            model,
        });
    }
    Ok(out)
}

/// `e` in the context of the design `index` with its varied `values`.
fn in_design(e: Error, index: usize, values: &[(String, Json)]) -> Error {
    let others: Vec<String> = values.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    e.in_context(format!("(design {index}: {})", others.join(", ")))
}

/// One design's study.
#[derive(Debug)]
pub struct Outcome {
    /// The design.
    pub design: Design,
    /// Its study (`Err`: why it failed; the sweep went on).
    pub study: std::result::Result<Study, String>,
}

impl Outcome {
    /// `ok` or `failed: <reason>`.
    pub fn status(&self) -> String {
        match &self.study {
            Ok(_) => "ok".into(),
            Err(e) => format!("failed: {e}"),
        }
    }
}

/// Runs every design's study in turn (each study is parallel inside); `progress(done,
/// total)` after each design.
pub fn run(designs: Vec<Design>, progress: &(dyn Fn(usize, usize) + Sync)) -> Vec<Outcome> {
    let total = designs.len();
    designs
        .into_iter()
        .enumerate()
        .map(|(k, design)| {
            let study = crate::study::run(&design.model, &|_, _| {}).map_err(|e| e.to_string());
            progress(k + 1, total);
            Outcome { design, study }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vary_specs_give_the_values_a_user_wrote() {
        let v = Vary::parse("--vary", "cycloid.eccentricity_mm=1.2:1.4:3").unwrap();
        assert_eq!(v.key, "cycloid.eccentricity_mm");
        assert_eq!(
            v.values,
            vec![
                serde_json::json!(1.2),
                serde_json::json!(1.3),
                serde_json::json!(1.4)
            ]
        );
        let v = Vary::parse("--vary", "contact.law=paper,johnson").unwrap();
        assert_eq!(v.values, vec![Json::from("paper"), Json::from("johnson")]);
        let v = Vary::parse("--vary", "cycloid.pins=38,40").unwrap();
        assert_eq!(v.values, vec![Json::from(38), Json::from(40)]);
        for bad in [
            "x",
            "k=",
            "k=1:2",
            "k=1:2:0",
            "k=a:2:3",
            "k=1:inf:2",
            "=1,2",
        ] {
            let e = Vary::parse("--vary", bad).unwrap_err().to_string();
            assert!(e.contains("--vary") && e.contains(bad), "{bad}: {e}");
        }
        // A number that is not finite is refused as written, never recorded as `null`.
        for (bad, written) in [("k=nan,1", "nan"), ("k=1,-inf", "-inf")] {
            let e = Vary::parse("--vary", bad).unwrap_err().to_string();
            assert!(
                e.contains(bad) && e.contains(&format!("`{written}` is not a finite number")),
                "{bad}: {e}"
            );
            assert!(!e.contains("null"), "{bad}: {e}");
        }
        let e = parse_value("--set", "k=[1.0, nan]", "[1.0, nan]").unwrap_err();
        assert!(
            e.to_string()
                .contains("`[1.0, nan]` is not a finite number"),
            "{e}"
        );
    }

    /// A sweep whose work exceeds the budget is refused by its size (naming `--vary`) before
    /// any design's physical checks: here every design's torque is more than the stage
    /// carries, which the physical checks would refuse (by `reducer.rated_torque_nm`) first if
    /// they ran before the budget.
    #[test]
    fn a_sweep_too_large_is_refused_before_any_physical_check() {
        let text = crate::config::EXAMPLE_TOML;
        let sets = [("reducer.rated_torque_nm".to_string(), Json::from(1e6))];
        let one = [Vary::parse("--vary", "cycloid.eccentricity_mm=1.3").unwrap()];
        let e = designs(text, "<ex>", None, &sets, &one, 1e6)
            .unwrap_err()
            .to_string();
        assert!(e.contains("reducer.rated_torque_nm"), "{e}");
        let many = [Vary::parse("--vary", "cycloid.eccentricity_mm=1.25:1.35:200").unwrap()];
        let e = designs(text, "<ex>", None, &sets, &many, 0.5)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--vary = 200 designs") && e.contains("exceeds the work budget"),
            "{e}"
        );
    }

    #[test]
    fn designs_are_the_product_last_key_fastest_and_refused_by_key() {
        let text = crate::config::EXAMPLE_TOML;
        let varies = [
            Vary::parse("--vary", "cycloid.eccentricity_mm=1.25:1.35:2").unwrap(),
            Vary::parse("--vary", "cycloid.modification.equidistant_mm=0.01,0.012").unwrap(),
        ];
        let sets = [("dynamics.enabled".to_string(), Json::from(false))];
        let d = designs(text, "<ex>", None, &sets, &varies, 1e6).unwrap();
        assert_eq!(d.len(), 4);
        assert_eq!(d[1].values[0].1, serde_json::json!(1.25));
        assert_eq!(d[1].values[1].1, serde_json::json!(0.012));
        assert!((d[2].model.cycloid.geometry.eccentricity - 1.35e-3).abs() < 1e-15);
        assert!(!d[3].model.dynamics.enabled);
        // A design out of range names its key and its design.
        let bad = [Vary::parse("--vary", "cycloid.eccentricity_mm=1.3,-1").unwrap()];
        let e = designs(text, "<ex>", None, &[], &bad, 1e6)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cycloid.eccentricity_mm") && e.contains("design 1"),
            "{e}"
        );
        // The budget counts every design.
        let e = designs(text, "<ex>", None, &sets, &varies, 0.1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--vary") || e.contains("budget"), "{e}");
    }
}
