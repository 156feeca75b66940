//! What a design search reads off a candidate's study: its goals (`--objective`) and
//! constraints (`--constraint`), each a quantity of the quantity table at a stage, or the
//! accuracy life (docs/model.md section 19).

use crate::config::Model;
use crate::error::{Error, Result};
use crate::quantities::{Models, Quantity, STAGE};

/// The B10 goal's default samples per candidate.
pub const B10_SAMPLES: usize = 30;

/// A stage of the study, as `@STAGE` names it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StageAt {
    /// The new reducer (the first stage, `@new` or no `@`).
    New,
    /// The last stage (`@last`).
    Last,
    /// The stage at these working hours (`@7500`), h.
    Hours(f64),
}

impl StageAt {
    /// Parses the text after `@` (`new`, `last`, or hours).
    fn parse(option: &str, whole: &str, s: &str) -> Result<StageAt> {
        match s.trim() {
            "new" | "0" => Ok(StageAt::New),
            "last" => Ok(StageAt::Last),
            h => h
                .parse::<f64>()
                .ok()
                .filter(|h| h.is_finite() && *h >= 0.0)
                .map(StageAt::Hours)
                .ok_or_else(|| {
                    Error::invalid(
                        option,
                        whole,
                        "a stage after `@`: new, last, or the hours of one of the study's \
                         stages (wear.stage_hours)",
                    )
                }),
        }
    }

    /// The index of the stage among `hours` (the study's stage hours).
    pub fn index(&self, hours: &[f64]) -> Option<usize> {
        match *self {
            StageAt::New => (!hours.is_empty()).then_some(0),
            StageAt::Last => hours.len().checked_sub(1),
            StageAt::Hours(h) => hours
                .iter()
                .position(|&x| (x - h).abs() <= 1e-9 * h.max(1.0)),
        }
    }

    /// Checks that the study of `model` has this stage.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `option` with `whole` and the stages there are.
    pub(crate) fn check(&self, model: &Model, option: &str, whole: &str) -> Result<()> {
        let hours = &model.wear.stage_hours;
        match self.index(hours) {
            Some(_) => Ok(()),
            None => Err(Error::invalid(
                option,
                whole,
                format!("a stage of the study: new, last or one of {hours:?} h"),
            )),
        }
    }

    /// `@new`, `@last`, `@7500h`, as the outputs name it.
    pub fn suffix(&self) -> String {
        match self {
            StageAt::New => String::new(),
            StageAt::Last => "@last".into(),
            StageAt::Hours(h) => format!("@{h}h"),
        }
    }
}

/// A quantity of the quantity table by its name (`lost_motion_arcmin`).
///
/// # Errors
/// [`Error::Invalid`] naming `option` with the text and a few names that exist.
fn quantity(option: &str, whole: &str, name: &str) -> Result<&'static Quantity> {
    STAGE
        .iter()
        .copied()
        .find(|q| q.name == name.trim())
        .ok_or_else(|| {
            Error::invalid(
                option,
                whole,
                "life, b10[:SAMPLES] or a quantity of stages.csv (docs/config.md: lost_motion_arcmin, \
                 backlash_arcmin, angular_te_arcmin, torsional_stiffness_nm_per_arcmin, \
                 max_pressure_mpa, ...), optionally @new, @last or @HOURS",
            )
        })
}

/// A goal of the search.
#[derive(Debug, Clone)]
pub enum Goal {
    /// The accuracy life, as its score (docs/model.md section 19): maximised.
    Life,
    /// The B10 life of a Monte Carlo of `samples` reducers per candidate (`[tolerances]`,
    /// the same seed for every candidate: common random numbers), as its score: maximised.
    B10 {
        /// Samples per candidate.
        samples: usize,
    },
    /// A quantity at a stage, minimised (or maximised with `max:`).
    Quantity {
        /// The quantity.
        quantity: &'static Quantity,
        /// Its stage.
        at: StageAt,
        /// Maximise instead of minimise.
        maximise: bool,
    },
}

impl Goal {
    /// Parses `--objective`'s comma-separated goals: `life`, `b10` or `b10:N`, `QUANTITY`,
    /// `max:QUANTITY`, each quantity optionally `@new`, `@last` or `@HOURS`.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--objective` with the text and the allowed forms.
    pub fn parse_list(text: &str) -> Result<Vec<Goal>> {
        let goals = text
            .split(',')
            .map(|g| Goal::parse(text, g.trim()))
            .collect::<Result<Vec<_>>>()?;
        if goals.is_empty() || goals.len() > 4 {
            return Err(Error::invalid("--objective", text, "one to four goals"));
        }
        Ok(goals)
    }

    fn parse(whole: &str, g: &str) -> Result<Goal> {
        let o = "--objective";
        if g == "life" {
            return Ok(Goal::Life);
        }
        if let Some(rest) = g.strip_prefix("b10") {
            let samples = match rest.strip_prefix(':') {
                None if rest.is_empty() => B10_SAMPLES,
                Some(n) => n
                    .trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|n| (10..=10_000).contains(n))
                    .ok_or_else(|| {
                        Error::invalid(o, whole, "b10:SAMPLES with SAMPLES in [10, 10000]")
                    })?,
                None => return Err(Error::invalid(o, whole, "b10 or b10:SAMPLES")),
            };
            return Ok(Goal::B10 { samples });
        }
        let (maximise, rest) = match g.strip_prefix("max:") {
            Some(r) => (true, r),
            None => (false, g.strip_prefix("min:").unwrap_or(g)),
        };
        let (name, at) = match rest.split_once('@') {
            Some((n, s)) => (n, StageAt::parse(o, whole, s)?),
            None => (rest, StageAt::New),
        };
        Ok(Goal::Quantity {
            quantity: quantity(o, whole, name)?,
            at,
            maximise,
        })
    }

    /// Whether the goal reads a quantity of the models `m`.
    pub(crate) fn uses(&self, m: Models) -> bool {
        matches!(self, Goal::Quantity { quantity, .. } if quantity.models == m)
    }

    /// Checks that the study of `model` gives the goal.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--objective`: the life without `[life]` thresholds, B10
    /// without `[tolerances]`, a stage the study does not have.
    pub(crate) fn check(&self, model: &Model) -> Result<()> {
        match self {
            Goal::Life | Goal::B10 { .. } if !model.life.any() => Err(Error::invalid(
                "--objective",
                self.name(),
                "a spec to leave: set a threshold in [life] (lost_motion_arcmin, ...)",
            )),
            Goal::B10 { .. } if model.tolerances.is_empty() => Err(Error::invalid(
                "--objective",
                self.name(),
                "tolerances to sample: a [tolerances] section with at least one part error",
            )),
            Goal::Quantity { at, .. } => at.check(model, "--objective", &self.name()),
            _ => Ok(()),
        }
    }

    /// The goal's name in the outputs (`life`, `b10`, `lost_motion_arcmin`,
    /// `max:torsional_stiffness_nm_per_arcmin@last`).
    pub fn name(&self) -> String {
        match self {
            Goal::Life => "life".into(),
            Goal::B10 { .. } => "b10".into(),
            Goal::Quantity {
                quantity,
                at,
                maximise,
            } => format!(
                "{}{}{}",
                if *maximise { "max:" } else { "" },
                quantity.name,
                at.suffix()
            ),
        }
    }
}

/// Which side of its limit a constraint keeps a quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    /// `Q <= V`.
    AtMost,
    /// `Q >= V`.
    AtLeast,
}

/// A constraint on a quantity at a stage (`--constraint lost_motion_arcmin<=0.8`,
/// `max_pressure_mpa@last<=1500`).
#[derive(Debug, Clone)]
pub struct Constraint {
    /// As the user wrote it.
    pub text: String,
    /// The quantity.
    pub quantity: &'static Quantity,
    /// Its stage (default the new reducer).
    pub at: StageAt,
    /// Its side of the limit.
    pub sense: Sense,
    /// The limit, in the quantity's unit.
    pub limit: f64,
}

impl Constraint {
    /// Parses `Q[@STAGE]<=V` or `Q[@STAGE]>=V`.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `--constraint` with the text and the allowed form.
    pub fn parse(text: &str) -> Result<Constraint> {
        let o = "--constraint";
        let (lhs, sense, rhs) = if let Some((l, r)) = text.split_once("<=") {
            (l, Sense::AtMost, r)
        } else if let Some((l, r)) = text.split_once(">=") {
            (l, Sense::AtLeast, r)
        } else {
            return Err(Error::invalid(
                o,
                text,
                "QUANTITY<=VALUE or QUANTITY>=VALUE, the quantity optionally @new, @last or \
                 @HOURS (lost_motion_arcmin<=0.8)",
            ));
        };
        let limit = rhs
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| Error::invalid(o, text, "a finite number after <= or >="))?;
        let (name, at) = match lhs.split_once('@') {
            Some((n, s)) => (n, StageAt::parse(o, text, s)?),
            None => (lhs, StageAt::New),
        };
        Ok(Constraint {
            text: text.trim().to_string(),
            quantity: quantity(o, text, name)?,
            at,
            sense,
            limit,
        })
    }

    /// The violation of `value` relative to the limit's size (`<= 0`: satisfied); an absent
    /// value violates by 1.
    pub fn violation(&self, value: Option<f64>) -> f64 {
        let Some(v) = value.filter(|v| v.is_finite()) else {
            return 1.0;
        };
        let scale = self.limit.abs().max(1e-12);
        match self.sense {
            Sense::AtMost => (v - self.limit) / scale,
            Sense::AtLeast => (self.limit - v) / scale,
        }
    }
}
