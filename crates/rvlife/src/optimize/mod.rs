//! The design search for accuracy life (docs/model.md section 19; `rvlife optimize`): the
//! config keys to vary within ranges, the goal (the accuracy life, the B10 life of a Monte
//! Carlo, or several quantities for a Pareto front), constraints on any quantity of the
//! quantity table at any stage, and the search that evaluates one study per candidate.
//!
//! - [`Problem`]: the base config, the [`Variable`]s, the [`Goal`]s and the [`Constraint`]s,
//!   parsed from the command line's words and validated before any study: each key's range is
//!   checked by building the designs at its ends (a value out of the key's range is refused
//!   naming the key), and the whole search's estimated work against the work budget.
//! - [`evaluate`]: one candidate's study and what the goals and constraints read off it
//!   ([`Candidate`]).
//! - [`search`]: the single-goal search (a Latin hypercube, then Nelder-Mead, argmin's);
//!   `pareto`: NSGA-II (the moors crate) for several goals.
//!
//! The search works in the unit box `[0, 1]^d` of the varied keys, each mapped linearly onto
//! its range (an integer key rounded). Every search minimises; a goal to maximise is negated.

mod evaluate;
mod follow;
mod goal;
pub mod pareto;
mod point;
mod run;
pub mod search;

pub use evaluate::{evaluate, life_score, Candidate, Status};
pub use follow::{follow_up, FollowUp, Sensitivity, SENSITIVITY_STEP};
pub use goal::{Constraint, Goal, Sense, StageAt};
pub use point::{pareto_front, Point, Settings, PENALTY};
pub use run::{run, run_batched, Batch, Job, Outcome};

use serde_json::Value as Json;

use crate::config::{edit, Config, Model};
use crate::error::{Error, Result};

/// Most evaluations of one search.
pub const MAX_EVALUATIONS: usize = 5_000;

/// Most varied keys of one search.
pub const MAX_VARIABLES: usize = 12;

/// One varied key and its range (`--vary KEY=LO:HI`).
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// The dotted config key (`cycloid.modification.equidistant_mm`).
    pub key: String,
    /// Lower end of the range, in the key's unit.
    pub lo: f64,
    /// Upper end of the range, in the key's unit.
    pub hi: f64,
    /// Whether the key takes whole numbers (pins, rollers): the value is rounded.
    pub integer: bool,
}

impl Variable {
    /// Parses `KEY=LO:HI` (`LO < HI`, finite); whole-number ends (`38:42`) make an integer key
    /// when the base config's value of the key is a whole number too (`integer`).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `option` with the text and the allowed form.
    pub fn parse(option: &str, spec: &str, integer: impl Fn(&str) -> bool) -> Result<Variable> {
        let bad = |why: &str| {
            Error::invalid(
                option,
                spec,
                format!("{why}; write KEY=LO:HI (LO < HI, the key dotted as in the config)"),
            )
        };
        let (key, rest) = spec.split_once('=').ok_or_else(|| bad("no `=`"))?;
        let key = key.trim().to_string();
        let parts: Vec<&str> = rest.split(':').collect();
        if key.is_empty() || parts.len() != 2 {
            return Err(bad("a key and a range LO:HI are needed"));
        }
        let num = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let (Some(lo), Some(hi)) = (num(parts[0]), num(parts[1])) else {
            return Err(bad("LO and HI must be finite numbers"));
        };
        if lo >= hi {
            return Err(bad("LO must be below HI"));
        }
        let whole = |s: &str| !s.contains(['.', 'e', 'E']);
        let integer = whole(parts[0]) && whole(parts[1]) && integer(&key);
        Ok(Variable {
            key,
            lo,
            hi,
            integer,
        })
    }

    /// The key's value at `u` in `[0, 1]` (clamped), in the key's unit.
    pub fn value(&self, u: f64) -> f64 {
        let v = self.lo + u.clamp(0.0, 1.0) * (self.hi - self.lo);
        if self.integer {
            v.round()
        } else {
            v
        }
    }

    /// Where `value` lies in the range, `(value - lo)/(hi - lo)`.
    pub fn unit(&self, value: f64) -> f64 {
        (value - self.lo) / (self.hi - self.lo)
    }

    /// The value as JSON for the config edit (an integer key as a whole number).
    pub(crate) fn json(&self, v: f64) -> Json {
        if self.integer {
            Json::from(v as i64)
        } else {
            serde_json::json!(format!("{v:.9e}").parse::<f64>().unwrap_or(v))
        }
    }
}

/// A validated search: the base config text and the keys set in every candidate, the
/// varied keys, the goals and the constraints, and the settings.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The base config's text (comments kept: the optimum's config is this text edited).
    pub text: String,
    /// Where the text came from (its path, or `<built-in>`).
    pub origin: String,
    /// The directory the config's relative paths start from.
    pub base_dir: Option<std::path::PathBuf>,
    /// The work budget of each candidate's study and of the whole search, minutes.
    pub budget_min: f64,
    /// The varied keys.
    pub variables: Vec<Variable>,
    /// The goals: one for a single-goal search, two or more for a Pareto front.
    pub goals: Vec<Goal>,
    /// The constraints.
    pub constraints: Vec<Constraint>,
    /// Evaluations and seed.
    pub settings: Settings,
    /// The base design's model (its values of the varied keys are the start).
    pub base: Model,
    /// The base design's values of the varied keys (`None`: outside the range given).
    pub start: Option<Vec<f64>>,
    /// The keys set in every candidate so that its study runs only the models the goals
    /// and constraints read (`dynamics.enabled`, `fem.enabled` off unless asked for).
    pub fixed: Vec<(String, Option<Json>)>,
}

impl Problem {
    /// The search of `variables` (`--vary KEY=LO:HI` each), `goals` (`--objective`, comma
    /// separated) and `constraints` (`--constraint Q<=V` each) over the config `text`.
    /// Validates before any study: every key is a config key and both ends of its range
    /// give a valid design (with the others at their base values), the goals and
    /// constraints name quantities of the quantity table at stages the study has, and the
    /// whole search's estimated work fits the work budget.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the option (`--vary`, `--objective`, `--constraint`,
    /// `--evaluations`) or the key with the value and the allowed range.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        text: &str,
        origin: &str,
        base_dir: Option<&std::path::Path>,
        budget_min: f64,
        variables: &[String],
        goals: &str,
        constraints: &[String],
        settings: Settings,
    ) -> Result<Problem> {
        if !(2..=MAX_EVALUATIONS).contains(&settings.evaluations) {
            return Err(Error::invalid(
                "--evaluations",
                settings.evaluations.to_string(),
                format!("a whole number in [2, {MAX_EVALUATIONS}]"),
            ));
        }
        let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| Error::Config {
            path: origin.to_string(),
            message: e.to_string(),
        })?;
        let base_value = |key: &str| -> Option<toml::Value> {
            let mut v: &toml::Value = doc.get(key.split('.').next()?)?;
            for part in key.split('.').skip(1) {
                v = v.get(part)?;
            }
            Some(v.clone())
        };
        let integer = |key: &str| matches!(base_value(key), Some(toml::Value::Integer(_)));
        let variables = variables
            .iter()
            .map(|v| Variable::parse("--vary", v, integer))
            .collect::<Result<Vec<_>>>()?;
        if variables.is_empty() || variables.len() > MAX_VARIABLES {
            return Err(Error::invalid(
                "--vary",
                variables.len().to_string(),
                format!("1 to {MAX_VARIABLES} varied keys"),
            ));
        }
        for (i, v) in variables.iter().enumerate() {
            if variables[..i].iter().any(|w| w.key == v.key) {
                return Err(Error::invalid("--vary", &v.key, "each key varied once"));
            }
        }
        let goals = Goal::parse_list(goals)?;
        let constraints = constraints
            .iter()
            .map(|c| Constraint::parse(c))
            .collect::<Result<Vec<_>>>()?;
        let uses = |m: crate::quantities::Models| {
            goals.iter().any(|g| g.uses(m)) || constraints.iter().any(|c| c.quantity.models == m)
        };
        let mut fixed = Vec::new();
        if !uses(crate::quantities::Models::Dynamics) {
            fixed.push(("dynamics.enabled".to_string(), Some(Json::from(false))));
        }
        if !uses(crate::quantities::Models::Flexible) {
            fixed.push(("fem.enabled".to_string(), Some(Json::from(false))));
        }
        let mut cfg = Config::from_toml_in(text, origin, base_dir)?;
        cfg.work_budget_minutes = budget_min;
        let base_model = crate::study::validated(&cfg)?;
        let mut p = Problem {
            text: text.to_string(),
            origin: origin.to_string(),
            base_dir: base_dir.map(std::path::Path::to_path_buf),
            budget_min,
            variables,
            goals,
            constraints,
            settings,
            base: base_model,
            start: None,
            fixed,
        };
        p.start = p
            .variables
            .iter()
            .map(|v| {
                let x = base_value(&v.key)?.as_float().or_else(|| {
                    base_value(&v.key)
                        .and_then(|t| t.as_integer())
                        .map(|i| i as f64)
                })?;
                (v.lo..=v.hi).contains(&x).then_some(x)
            })
            .collect();
        for g in &p.goals {
            g.check(&p.base)?;
        }
        for c in &p.constraints {
            c.at.check(&p.base, "--constraint", &c.text)?;
        }
        // Both ends of each range, the other keys at their base values, then at the middle,
        // the low and the high ends of theirs: an end that no such design accepts (a value
        // outside the key's own range) is refused naming the key before any study; one that
        // only some combinations refuse (modifications that make the disc interfere with the
        // pins) leaves those candidates infeasible.
        let base_u: Vec<f64> = p
            .variables
            .iter()
            .enumerate()
            .map(|(i, v)| p.start.as_ref().map_or(0.5, |s| v.unit(s[i])))
            .collect();
        let mut work: f64 = 0.0;
        for (i, v) in p.variables.iter().enumerate() {
            for end in [0.0, 1.0] {
                let mut first = None;
                for others in [None, Some(0.5), Some(0.0), Some(1.0)] {
                    let mut u = match others {
                        None => base_u.clone(),
                        Some(x) => vec![x; p.variables.len()],
                    };
                    u[i] = end;
                    match p.model(&u) {
                        Ok(model) => {
                            work = work.max(p.candidate_work(&model));
                            first = None;
                            break;
                        }
                        Err(e) => {
                            first.get_or_insert(e);
                        }
                    }
                }
                if let Some(e) = first {
                    return Err(e.in_context(format!("(--vary {}={}:{})", v.key, v.lo, v.hi)));
                }
            }
        }
        // The candidates, then the follow-up (docs/model.md section 19.5): the sensitivity's
        // two candidates per key and the best and base designs' studies.
        let (base_wear, base_stages) = crate::study::study_work(&p.base);
        let follow = 2.0 * p.variables.len() as f64 * work + 2.0 * (base_wear + base_stages);
        let total = work * p.settings.evaluations as f64 + follow;
        let budget = crate::budget::solves_in_minutes(budget_min);
        if total > budget {
            return Err(Error::invalid(
                "--evaluations",
                p.settings.evaluations.to_string(),
                format!(
                    "the search's estimated work, {:.1} min ({:.2} min a candidate, and the \
                     follow-up's {:.1} min), exceeds the work budget of {budget_min:.1} min \
                     (--work-budget-min): at most {} evaluations fit, or a larger budget",
                    crate::budget::minutes(total),
                    crate::budget::minutes(work),
                    crate::budget::minutes(follow),
                    ((budget - follow) / work).floor().max(0.0),
                ),
            ));
        }
        Ok(p)
    }

    /// Whether a candidate needs its study: a goal other than B10, or a constraint, reads
    /// its stages (a B10 goal alone reads only its Monte Carlo).
    pub fn needs_study(&self) -> bool {
        !self.constraints.is_empty() || self.goals.iter().any(|g| !matches!(g, Goal::B10 { .. }))
    }

    /// The estimated work of one candidate (static solves, [`crate::budget`]): its study's
    /// when it needs one ([`Self::needs_study`]), and with a B10 goal its Monte Carlo's (the
    /// nominal wear, then per sample its points at the Monte Carlo's crank angles, as
    /// `rvlife montecarlo` counts them).
    fn candidate_work(&self, model: &Model) -> f64 {
        let (wear, stages) = crate::study::study_work(model);
        let (points, _) = crate::montecarlo::life_points(model);
        let per_sample = points as f64
            * crate::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE as f64
            * crate::budget::MONTE_CARLO_SOLVES_PER_ANGLE;
        let monte_carlo: f64 = self
            .goals
            .iter()
            .map(|g| match g {
                Goal::B10 { samples } => wear + *samples as f64 * per_sample,
                _ => 0.0,
            })
            .sum();
        let study = if self.needs_study() {
            wear + stages
        } else {
            0.0
        };
        study + monte_carlo
    }

    /// The values of the varied keys at `u` (unit box).
    pub fn values(&self, u: &[f64]) -> Vec<f64> {
        self.variables
            .iter()
            .zip(u)
            .map(|(v, &x)| v.value(x))
            .collect()
    }

    /// The config text of the design with the varied keys at `values` (their units), with
    /// the fixed keys set too when `fixed` (the candidate's study) or not (the optimum's
    /// config, as the user's own runs it).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming a key that is not a config key.
    pub fn text_of(&self, values: &[f64], fixed: bool) -> Result<String> {
        let mut edits: Vec<(String, Option<Json>)> = if fixed {
            self.fixed.clone()
        } else {
            Vec::new()
        };
        edits.extend(
            self.variables
                .iter()
                .zip(values)
                .map(|(v, &x)| (v.key.clone(), Some(v.json(x)))),
        );
        edit::set(&self.text, &self.origin, &edits)
    }

    /// The validated model of the candidate at `u` (unit box), as its study runs it.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key and value out of range, with the candidate's
    /// values.
    pub fn model(&self, u: &[f64]) -> Result<Model> {
        let values = self.values(u);
        let text = self.text_of(&values, true)?;
        let in_candidate = |e: Error| -> Error {
            let all: Vec<String> = self
                .variables
                .iter()
                .zip(&values)
                .map(|(v, x)| format!("{} = {x}", v.key))
                .collect();
            e.in_context(format!("(candidate {})", all.join(", ")))
        };
        let mut cfg = Config::from_toml_in(&text, &self.origin, self.base_dir.as_deref())
            .map_err(in_candidate)?;
        cfg.work_budget_minutes = self.budget_min;
        crate::study::validated(&cfg).map_err(in_candidate)
    }
}
