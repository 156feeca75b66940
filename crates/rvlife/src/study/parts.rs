//! The accuracy-life study in parts, for a front end that runs its stages on workers that share
//! no memory (the web page's Web Workers, each with its own WebAssembly instance): what
//! [`super::run`] does on one machine's threads, without the dynamics and the flexible disc.
//!
//! 1. [`ground`]: the crank bearings' wear rates, which every other part needs;
//! 2. [`wear_history`]: the wear integration to the stages (one worker), while
//!    [`unworn_first`], the 0 h stage, needs none and can be analysed beside it;
//! 3. [`static_stage`] for every stage of [`stage_wears`], on any worker, in any order;
//! 4. [`assemble`]: the study from the wear history and the stages' outcomes, with its
//!    accuracy life, on the worker that integrated the wear;
//! 5. with `[fem] enabled`, [`flexible`] on that worker: the flexible disc's analysis of
//!    every stage.
//!
//! What crosses between workers ([`Ground`], [`StageWear`], [`StageOutcome`]) is plain data
//! (serde). A study assembled from parts equals [`super::run`]'s with dynamics and FE off: the
//! same functions on the same numbers, so the same results files byte for byte (tested). The
//! loaded solutions' geometry that no results file holds (contact points and normals, disc
//! poses, the solver's coordinates) does not cross and is zero in the assembled study.

use serde::{Deserialize, Serialize};

use super::results::Study;
use super::stage::{no_load, static_part, Failure, NoLoad, Stage, UnwornPlay};
use super::trials::{study_life, LifeTrials};
use crate::config::Model;
use crate::error::{Error, Result};
use crate::quantities::StageSummary;
use crate::te::{LoadedTe, RevolutionTe, StaticTe, TwistTable};
use crate::wear::{BearingWearRates, ValidityLimit, WearHistory, WearInputs, WearModelKind};

/// What every part of a study starts from: the crank bearings' clearance growth from the new
/// reducer's loads (docs/model.md section 7.9).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Ground {
    rates: BearingWearRates,
}

/// The [`Ground`] of a study of `model` (nothing to solve where the bearings do not wear).
///
/// # Errors
/// Solver failures on the new reducer.
pub fn ground(model: &Model) -> Result<Ground> {
    Ok(Ground {
        rates: crate::config::bearing_rates(model)?,
    })
}

/// The steps of [`wear_history`]'s progress for `model`: its wear-rate evaluations as
/// scheduled (`last stage / wear.profile_update_hours`, at least 1; 1 in the paper's model).
pub fn wear_steps(model: &Model) -> usize {
    let w = &model.wear;
    if w.model == WearModelKind::Paper || w.update_hours <= 0.0 {
        1
    } else {
        (w.stage_hours.last().copied().unwrap_or(0.0) / w.update_hours)
            .ceil()
            .max(1.0) as usize
    }
}

/// The wear integration of a study of `model` to its stages ([`crate::wear::integrate`]);
/// `progress(done, total)` after each wear-rate evaluation, `on_stage` with each stage's wear
/// as soon as it is known (what [`stage_wears`] gives of the history), so that it can be
/// analysed while the integration goes on.
///
/// # Errors
/// Those of [`crate::wear::integrate`].
pub fn wear_history(
    model: &Model,
    ground: &Ground,
    progress: &(dyn Fn(usize, usize) + Sync),
    on_stage: &dyn Fn(StageWear),
) -> Result<WearHistory> {
    wear_history_with(model, ground.rates, progress, on_stage)
}

/// [`wear_history`] with the crank bearings' clearance growth `rates` (m/h), what it takes of
/// the [`Ground`].
///
/// # Errors
/// As [`wear_history`].
pub(super) fn wear_history_with(
    model: &Model,
    rates: BearingWearRates,
    progress: &(dyn Fn(usize, usize) + Sync),
    on_stage: &dyn Fn(StageWear),
) -> Result<WearHistory> {
    let inputs = WearInputs {
        bearing_rates: rates,
        ..model.wear_inputs()
    };
    crate::wear::integrate_with_stages(&inputs, progress, &|s| {
        on_stage(StageWear {
            index: s.index,
            hours: s.hours,
            map: s.map.to_vec(),
            pin_map: s.pin_map.to_vec(),
        })
    })
}

/// The wear of one stage: what [`static_stage`] needs of the wear history.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageWear {
    /// The stage's index in the study (from 0, in the order of `wear.stage_hours`).
    pub index: usize,
    /// Working hours, h.
    pub hours: f64,
    /// The disc's wear depth on the wear grid, m ([`WearHistory::maps`]); empty: unworn.
    pub(crate) map: Vec<f64>,
    /// The pins' wear round the pin, m ([`WearHistory::pin_maps`]); empty: unworn.
    pub(crate) pin_map: Vec<f64>,
}

impl StageWear {
    /// Whether neither the disc nor the pins have worn.
    pub(crate) fn is_unworn(&self) -> bool {
        unworn(&self.map, &self.pin_map)
    }
}

/// Whether a stage's disc wear `map` and pins' wear `pin_map` (m; empty: unworn) are nil.
pub(crate) fn unworn(map: &[f64], pin_map: &[f64]) -> bool {
    map.iter().chain(pin_map).all(|w| *w == 0.0)
}

/// The stages of the wear history `wear`, in order: what [`static_stage`] analyses.
pub fn stage_wears(wear: &WearHistory) -> Vec<StageWear> {
    (0..wear.hours.len())
        .map(|i| StageWear {
            index: i,
            hours: wear.hours[i],
            map: wear.maps[i].clone(),
            pin_map: wear.pin_maps.get(i).cloned().unwrap_or_default(),
        })
        .collect()
}

/// The study's first stage when it lies at 0 h (`wear.stage_hours` starts with 0): unworn, so
/// it can be analysed beside the wear integration ([`assemble`] takes its outcome in place of
/// the wear history's first stage, which is unworn too).
pub fn unworn_first(model: &Model) -> Option<StageWear> {
    (model.wear.stage_hours.first() == Some(&0.0)).then(|| StageWear {
        index: 0,
        hours: 0.0,
        map: Vec::new(),
        pin_map: Vec::new(),
    })
}

/// A stage's static results without its profile (which [`assemble`] makes again from the
/// wear history) and without dynamics or flexible results; its play not yet split against the
/// new reducer's (the unworn disc's play on its parts kept for that), which the first stage
/// finds when it lies at 0 h (beside the wear integration, as [`super::run`] does).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct StageRecord {
    ste: StaticTe,
    loaded: LoadedTe,
    hysteresis: TwistTable,
    revolution: Option<RevolutionTe>,
    summary: StageSummary,
    play: UnwornPlay,
    new: Option<NoLoad>,
}

/// A failure as it crosses between workers: the error's kind and words, so that
/// [`assemble`] reports it exactly as [`super::run`] would.
#[derive(Debug, Clone, Serialize, Deserialize)]
enum ErrorRecord {
    Invalid {
        field: String,
        value: String,
        allowed: String,
    },
    Config {
        path: String,
        message: String,
    },
    Io {
        path: std::path::PathBuf,
        message: String,
    },
    Numerical {
        context: String,
        message: String,
    },
}

impl From<&Error> for ErrorRecord {
    fn from(e: &Error) -> Self {
        match e {
            Error::Invalid {
                field,
                value,
                allowed,
            } => ErrorRecord::Invalid {
                field: field.clone(),
                value: value.clone(),
                allowed: allowed.clone(),
            },
            Error::Config { path, message } => ErrorRecord::Config {
                path: path.clone(),
                message: message.clone(),
            },
            Error::Io { path, source } => ErrorRecord::Io {
                path: path.clone(),
                message: source.to_string(),
            },
            Error::Numerical { context, message } => ErrorRecord::Numerical {
                context: context.to_string(),
                message: message.clone(),
            },
        }
    }
}

impl From<ErrorRecord> for Error {
    fn from(e: ErrorRecord) -> Self {
        match e {
            ErrorRecord::Invalid {
                field,
                value,
                allowed,
            } => Error::Invalid {
                field,
                value,
                allowed,
            },
            ErrorRecord::Config { path, message } => Error::Config { path, message },
            ErrorRecord::Io { path, message } => Error::Io {
                path,
                source: std::io::Error::other(message),
            },
            ErrorRecord::Numerical { context, message } => Error::Numerical {
                context: context.into(),
                message,
            },
        }
    }
}

/// What [`static_stage`] made of one stage: its static results, or why it has none.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StageOutcome {
    index: usize,
    hours: f64,
    result: std::result::Result<Box<StageRecord>, (ErrorRecord, Option<f64>)>,
}

impl StageOutcome {
    /// The stage's index in the study.
    pub fn index(&self) -> usize {
        self.index
    }

    /// Whether the stage has no static results (its failure is reported by [`assemble`]).
    pub fn failed(&self) -> bool {
        self.result.is_err()
    }

    /// The outcome of `stage` whose static analysis failed with `e` (for tests of the
    /// assembly).
    #[cfg(test)]
    pub(crate) fn static_failure(stage: &StageWear, e: &Error) -> Self {
        let max = stage.map.iter().copied().fold(0.0, f64::max);
        StageOutcome {
            index: stage.index,
            hours: stage.hours,
            result: Err((e.into(), Some(max))),
        }
    }
}

/// The static analysis of one stage of a study of `model` (what [`super::run`] does for each
/// stage before the dynamics and the flexible disc): the worn profile, the static TE,
/// hysteresis curve, loaded TE and the unworn disc's play on the parts as worn by then (the
/// play is split by source in [`assemble`]); the first stage, at 0 h, also finds the new
/// reducer's play.
pub fn static_stage(model: &Model, ground: &Ground, stage: &StageWear) -> StageOutcome {
    let result = model
        .profile()
        .map_err(|e| Failure::Static(e, 0.0))
        .and_then(|base| {
            let (s, _, play) = static_part(
                model,
                ground.rates,
                stage.hours,
                &stage.map,
                &stage.pin_map,
                &base,
            )?;
            let new = (stage.index == 0 && stage.hours == 0.0)
                .then(|| no_load(model, &base))
                .transpose()
                .map_err(|e| Failure::Static(e, 0.0))?;
            Ok((s, play, new))
        })
        .map(|(s, play, new)| {
            Box::new(StageRecord {
                ste: s.ste,
                loaded: s.loaded,
                hysteresis: s.hysteresis,
                revolution: s.revolution,
                summary: s.summary,
                play,
                new,
            })
        })
        .map_err(|f| match f {
            Failure::Prepare(e) => ((&e).into(), None),
            Failure::Static(e, max) => ((&e).into(), Some(max)),
        });
    StageOutcome {
        index: stage.index,
        hours: stage.hours,
        result,
    }
}

/// The study of `model` from its wear history `wear` ([`wear_history`]) and the outcomes of
/// its stages ([`static_stage`] of every one of [`stage_wears`], in any order; the first may
/// be [`unworn_first`]'s): the stages up to the validity limit, and the accuracy life
/// (`notice` told when its search goes on beyond the last stage).
///
/// # Errors
/// [`Error::Invalid`] naming the stage when an outcome does not belong to `wear` (another
/// stage's hours, a stage missing or given twice); the stages' failures as [`super::run`]
/// reports them; those of the accuracy life's search.
pub fn assemble(
    model: &Model,
    wear: WearHistory,
    outcomes: Vec<StageOutcome>,
    notice: &dyn Fn(&str),
) -> Result<Study> {
    assemble_ahead(model, wear, outcomes, None, notice)
}

/// The flexible disc's analysis of every stage of the assembled `study` (docs/model.md section
/// 9), as [`super::run`] makes it with `[fem] enabled` and the dynamics off: the same
/// `flexible_*` quantities in every stage. `progress(done, total)` hears the FE disc's build
/// and each stage.
///
/// # Errors
/// The FE disc's failures and the flexible analysis's.
pub fn flexible(study: &mut Study, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<()> {
    super::analyses::flexible_pass(study, progress)
}

/// The accuracy life's trials between two stages, made before the assembly
/// ([`crossing_ahead`]).
pub struct LifeAhead(Option<LifeTrials>);

/// The accuracy life's trials between two stages (docs/model.md section 11), made from the
/// stages' outcomes known so far (any order) while the others are analysed, on the worker that
/// holds the wear history `wear`: `None` while the stages up to the first outside the spec are
/// not all known; otherwise what [`assemble_ahead`] takes (trials, or none where the search
/// needs none there). The assembly then finds them done: the same study as [`assemble`]'s.
pub fn crossing_ahead(
    model: &Model,
    wear: &WearHistory,
    outcomes: &[StageOutcome],
) -> Option<LifeAhead> {
    let mut points: Vec<Option<Option<crate::quantities::AccuracyPoint>>> =
        vec![None; wear.hours.len()];
    for o in outcomes {
        if let Some(slot) = points.get_mut(o.index) {
            *slot = Some(match &o.result {
                Ok(r) => Some(crate::quantities::AccuracyPoint::of(&r.summary)),
                Err(_) => None,
            });
        }
    }
    LifeTrials::crossing_ahead(model, wear, points, || true).map(LifeAhead)
}

/// [`assemble`] with the accuracy life's trials made ahead ([`crossing_ahead`]).
///
/// # Errors
/// As [`assemble`].
pub fn assemble_ahead(
    model: &Model,
    mut wear: WearHistory,
    outcomes: Vec<StageOutcome>,
    ahead: Option<LifeAhead>,
    notice: &dyn Fn(&str),
) -> Result<Study> {
    let n = wear.hours.len();
    let mut slots: Vec<Option<StageOutcome>> = (0..n).map(|_| None).collect();
    for o in outcomes {
        let i = o.index;
        let belongs = i < n && wear.hours[i] == o.hours && slots[i].is_none();
        if !belongs {
            return Err(Error::invalid(
                format!("stage outcome {i}"),
                format!("{} h", o.hours),
                format!("one outcome for each of the wear history's {n} stages, at its hours"),
            ));
        }
        slots[i] = Some(o);
    }
    // The new reducer's play: the first stage's, else found here when a stage needs it.
    let mut new = slots
        .first()
        .and_then(|o| o.as_ref())
        .and_then(|o| o.result.as_ref().ok())
        .and_then(|r| r.new);
    let mut new_play = || -> Result<NoLoad> {
        if let Some(n) = new {
            return Ok(n);
        }
        let n = no_load(model, &model.profile()?)?;
        new = Some(n);
        Ok(n)
    };
    let outcomes: Vec<_> = slots
        .into_iter()
        .zip(&wear.maps)
        .map(|(slot, map)| {
            slot.map(|o| match o.result {
                Ok(mut r) => crate::wear::profile_maps(model.wear.model, map)
                    .and_then(|(wear_map, te_map)| {
                        r.play.split(&mut r.summary, new_play()?);
                        Ok(Stage {
                            hours: o.hours,
                            wear: wear_map,
                            profile: model.cycloid.profile(te_map)?,
                            ste: r.ste,
                            loaded: r.loaded,
                            hysteresis: r.hysteresis,
                            revolution: r.revolution,
                            summary: r.summary,
                            dynamics: None,
                            flexible: None,
                        })
                    })
                    .map(|s| (s, ()))
                    .map_err(Failure::Prepare),
                Err((e, None)) => Err(Failure::Prepare(e.into())),
                Err((e, Some(max))) => Err(Failure::Static(e.into(), max)),
            })
        })
        .collect();
    let stages = until_limit(model, &mut wear, outcomes)?
        .into_iter()
        .map(|(s, ())| s)
        .collect();
    finish(model, wear, stages, ahead.and_then(|a| a.0), notice, true)
}

/// The stages of a study in order, each with its extra results (`T`), up to the validity
/// limit: the first stage whose static analysis fails on a worn profile is where the wear
/// model leaves its validity (set in `wear`, whose stages are cut there), and the stages after
/// it are dropped. `None`: a stage not analysed.
///
/// # Errors
/// A stage's failure that is not the validity limit (on the unworn profile, a bad input, a
/// wear map that cannot be made); a stage not analysed before the limit; [`Error::Invalid`]
/// naming `wear.stage_hours` when no stage lies within the validity.
pub(super) fn until_limit<T>(
    model: &Model,
    wear: &mut WearHistory,
    outcomes: impl IntoIterator<Item = Option<std::result::Result<(Stage, T), Failure>>>,
) -> Result<Vec<(Stage, T)>> {
    let mut stages = Vec::new();
    for (i, outcome) in outcomes.into_iter().enumerate() {
        match outcome {
            Some(Ok(done)) => stages.push(done),
            Some(Err(Failure::Prepare(e))) => return Err(e),
            Some(Err(Failure::Static(e, max))) => {
                if max > 0.0 && !matches!(e, Error::Invalid { .. } | Error::Io { .. }) {
                    // A worn stage the static analysis cannot follow: the validity limit.
                    wear.limit = Some(ValidityLimit {
                        hours: wear.hours[i],
                        max_wear_um: max * 1e6,
                        reason: e.to_string(),
                    });
                    break;
                }
                return Err(e);
            }
            None => {
                return Err(Error::numerical(
                    "study",
                    format!("stage {i} was not analysed (an earlier stage's failure was lost)"),
                ))
            }
        }
    }
    wear.hours.truncate(stages.len());
    wear.maps.truncate(stages.len());
    if stages.is_empty() {
        let l = wear.limit.as_ref();
        let w = &model.wear;
        return Err(Error::invalid(
            "wear.stage_hours",
            format!("{:?}", w.stage_hours),
            format!(
                "no stage lies within the validity of the wear model: it leaves it at {:.0} h \
                 ({:.2} um of wear: {}); list earlier stages",
                l.map_or(0.0, |l| l.hours),
                l.map_or(0.0, |l| l.max_wear_um),
                l.map_or("", |l| l.reason.as_str())
            ),
        ));
    }
    Ok(stages)
}

/// The study of `model` from its wear history `wear` and its stages: the accuracy life
/// ([`study_life`], with the trials beyond the stages made `ahead`, `notice` told of the search
/// beyond them) and, with `shares`, each part's share of the new reducer's twist.
///
/// # Errors
/// Those of [`study_life`] and of the shares' static solves.
pub(super) fn finish(
    model: &Model,
    wear: WearHistory,
    stages: Vec<Stage>,
    ahead: Option<LifeTrials>,
    notice: &dyn Fn(&str),
    shares: bool,
) -> Result<Study> {
    let summaries: Vec<StageSummary> = stages.iter().map(|s| s.summary.clone()).collect();
    let life = study_life(model, &summaries, &wear, ahead, notice)?;
    // Where the new reducer's twist goes at the rated torque (docs/model.md section 5.9).
    let twist_shares = if shares {
        crate::statics::twist_shares(
            &model.reducer,
            &model.profile()?,
            &crate::te::mesh_cycle_angles(model.reducer.geometry.pins, model.te.samples),
            model.rating.rated_torque,
        )?
    } else {
        Vec::new()
    };
    Ok(Study {
        model: model.clone(),
        wear,
        stages,
        life,
        twist_shares,
    })
}
