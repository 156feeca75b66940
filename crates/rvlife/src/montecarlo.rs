//! Monte Carlo over the part tolerances: a batch of sampled reducers through the accuracy-life
//! study, with percentiles of the accuracy quantities and the accuracy life's distribution.
//!
//! Sample `i` of seed `s` draws its part errors and modification errors
//! ([`crate::config::Tolerances::sample`]) from its own ChaCha8 stream (seed `s`, stream `i`),
//! so a sample's numbers do not depend on how many samples run, on which shard, or on the
//! thread count: shards merged give the unsharded run's files byte for byte.
//!
//! **Shared wear** (the default): the wear maps are those of the nominal reducer, integrated
//! once at the study's stages and at the points that split each interval between two into
//! `SUBDIVISIONS` parts; every sample is
//! analysed with its own errors on those maps. A sample's errors change its load sharing and so
//! its wear a little; `full_wear` integrates every sample's own wear instead (the cost and the
//! difference are measured in the README).
//!
//! Each sampled reducer at each working-hour point: backlash, lost motion and torsional
//! stiffness from the hysteresis curve averaged over one mesh cycle
//! (`crate::te::hysteresis_with`, the measuring torque and the rated torque), the angular TE
//! over an output revolution (`crate::te::revolution_perturbed`); the accuracy life by
//! bisection over the shared maps between the stages, then linear interpolation.

use std::ops::Range;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::budget;
use crate::config::Model;
use crate::error::{Error, Result};
use crate::geometry::WearMap;
use crate::life::accuracy_life;
use crate::quantities::{AccuracyPoint, ACCURACY};
use crate::statics::StaticAnalysis;
use crate::te::{
    angular_te_from, has_play, hysteresis_with_from, mesh_cycle_angles, revolution_perturbed,
    zero_torque_over_revolution_from, Starts,
};
use crate::units::ARCMIN_PER_RAD;

mod assembly;
mod lives;
pub mod weibull;

pub use assembly::REJECTED;

pub use lives::{
    life_distribution, life_text, lives_and_censored, reliability, weibull_sample,
    LifeDistribution, WeibullLife, LIFE_CONFIDENCE,
};

/// Wear maps between two stages of the shared wear history (the accuracy life is located to
/// an eighth of a stage interval by bisection, then interpolated).
pub(crate) const SUBDIVISIONS: usize = 8;

/// Crank angles per mesh cycle of a Monte Carlo's hysteresis curves and revolution TE unless
/// the user sets them (`rvlife montecarlo --samples-per-mesh-cycle`, the design search's B10
/// goal): the lost motion and backlash of the example differ from 24 angles' by under 1 % (an
/// estimate from the example's runs), at a sixth of the solves.
pub const DEFAULT_SAMPLES_PER_MESH_CYCLE: usize = 4;

/// The points of one sample's accuracy at which a Monte Carlo of `model` counts its work
/// ([`check_work`]): the stages and half the points beyond them where the life is looked for
/// (the bracket's steps of 1.5x to `life.max_hours`, else ten times the last stage), and that
/// horizon over the last stage's hours (1 without life thresholds).
pub(crate) fn life_points(model: &Model) -> (usize, f64) {
    let last = model.wear.stage_hours.last().copied().unwrap_or(0.0);
    let (beyond, horizon) = if model.life.any() && last > 0.0 {
        let max_h = model.life.max_hours.unwrap_or(10.0 * last);
        (
            ((max_h / last).ln() / 1.5f64.ln()).ceil().max(0.0) as usize,
            max_h / last,
        )
    } else {
        (0, 1.0)
    };
    (model.wear.stage_hours.len() + beyond / 2, horizon)
}

/// What to run: `samples` reducers of seed `seed`, the part `shard = (I, N)` (1-based) of them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Number of sampled reducers of the whole run.
    pub samples: usize,
    /// Seed.
    pub seed: u64,
    /// `(I, N)`: this run is the `I`-th of `N` disjoint contiguous parts; `(1, 1)`: all.
    pub shard: (usize, usize),
    /// Integrate every sample's own wear instead of sharing the nominal reducer's.
    pub full_wear: bool,
    /// Crank angles per mesh cycle of the hysteresis curves and the revolution TE.
    pub samples_per_mesh_cycle: usize,
}

impl Plan {
    /// The sample indices of this shard: `[floor((I-1) S/N), floor(I S/N))`.
    pub fn indices(&self) -> Range<usize> {
        let (i, n) = self.shard;
        (i - 1) * self.samples / n..i * self.samples / n
    }
}

/// Checks the work of a Monte Carlo run of `samples` samples (this shard's) before it starts
/// ([`crate::budget`]): `samples x points x per_cycle x`
/// [`budget::MONTE_CARLO_SOLVES_PER_ANGLE`], `points` the stages and half the points beyond
/// them where the life is looked for; with `full_wear` each sample also integrates its own wear
/// (the study's wear work, times the 8 mesh cycles of a reducer with errors, times `horizon`,
/// the hours integrated over the last stage's).
///
/// # Errors
/// [`Error::Invalid`] naming `--samples` with the estimate and the budget.
pub(crate) fn check_work(
    model: &Model,
    samples: usize,
    points: usize,
    per_cycle: usize,
    full_wear: bool,
    horizon: f64,
) -> Result<()> {
    let grades = model
        .tolerances
        .selective
        .as_ref()
        .map_or(0, |s| s.pin_grades.len());
    let mut per_sample =
        (points + grades) as f64 * per_cycle as f64 * budget::MONTE_CARLO_SOLVES_PER_ANGLE;
    if full_wear {
        let w = &model.wear;
        per_sample += 8.0
            * horizon.max(1.0)
            * w.scheduled_updates()
            * w.rate_evaluation_solves(model.load.levels.len(), 1);
    }
    let total = samples as f64 * per_sample;
    if total <= model.work_budget {
        return Ok(());
    }
    Err(Error::invalid(
        "--samples",
        samples,
        format!(
            "the estimated work, {:.1} min ({} samples x {:.0} solves), exceeds the work \
             budget of {:.1} min: fewer samples, --shard I/N across machines, or a larger \
             --work-budget-min",
            budget::minutes(total),
            samples,
            per_sample,
            budget::minutes(model.work_budget)
        ),
    ))
}

/// One sampled reducer's results.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleRecord {
    /// Sample index.
    pub sample: usize,
    /// `ok` or `failed: <reason>` (the analysis failed at some working hours; the points
    /// before are kept); parts that interfere are assembled with preload (docs/model.md
    /// section 5.12). Shards of earlier versions may hold `interference`.
    pub status: String,
    /// The accuracy quantities at each stage.
    pub points: Vec<AccuracyPoint>,
    /// Accuracy life, h (`None`: beyond the last stage, or no thresholds).
    pub accuracy_life_h: Option<f64>,
    /// The threshold crossed first.
    pub limited_by: Option<String>,
    /// Where a sample that did not leave the spec was censored, h: the last working hours its
    /// life search analysed within spec (the horizon, or sooner where its analysis or the
    /// shared wear history ended there); `None` for a sample that left the spec, was not
    /// analysed, or under no thresholds (Lawless, *Statistical Models and Methods for Lifetime
    /// Data*, 2003, section 1.2: right-censoring times).
    pub censored_h: Option<f64>,
}

/// The nominal reducer's wear maps at the stages and between them.
pub struct SharedWear {
    /// Working hours of every map, h (stages and subdivisions).
    pub hours: Vec<f64>,
    /// Wear maps (None: unworn).
    pub maps: Vec<Option<WearMap>>,
    /// The pins' wear maps at the same hours, m (empty: unworn; docs/model.md section 7.11).
    pub pin_maps: Vec<Vec<f64>>,
    /// Clearance growth of the crank bearings (docs/model.md section 7.9).
    pub bearing_rates: crate::wear::BearingWearRates,
    /// Index in `hours` of each stage.
    pub stage_index: Vec<usize>,
    /// Index in `hours` of each point beyond the last stage where the accuracy life is looked
    /// for.
    pub extension_index: Vec<usize>,
    /// The history's early part only ([`NominalWear::partial`]).
    pub partial: bool,
}

/// Stages and their subdivisions, then (with life thresholds) the points beyond the last
/// stage where the accuracy life is looked for (x 1.5 in hours up to `life.max_hours`, default
/// 10 x the last stage) with their subdivisions: `(hours, index of each stage, index of each
/// point beyond)`.
fn dense_hours(model: &Model) -> (Vec<f64>, Vec<usize>, Vec<usize>) {
    let mut hours = Vec::new();
    let mut idx = Vec::new();
    let mut prev: Option<f64> = None;
    let push = |hours: &mut Vec<f64>, prev: &mut Option<f64>, h: f64| {
        if let Some(p) = *prev {
            for k in 1..SUBDIVISIONS {
                hours.push(p + (h - p) * k as f64 / SUBDIVISIONS as f64);
            }
        }
        hours.push(h);
        *prev = Some(h);
        hours.len() - 1
    };
    for &h in &model.wear.stage_hours {
        idx.push(push(&mut hours, &mut prev, h));
    }
    let mut ext = Vec::new();
    let last = model.wear.stage_hours.last().copied().unwrap_or(0.0);
    if model.life.any() && last > 0.0 {
        let max_h = model.life.max_hours.unwrap_or(10.0 * last);
        let mut h = last;
        while h < max_h {
            h = (1.5 * h).min(max_h);
            ext.push(push(&mut hours, &mut prev, h));
        }
    }
    (hours, idx, ext)
}

/// The nominal reducer's wear history as plain data ([`nominal_wear`]): what a Monte Carlo
/// shard needs besides the config, computed once and sent to every shard (a distributed run
/// sends it to its workers as JSON). Rebuilt into the maps by [`SharedWear::of`] exactly as
/// the serial run builds them, so a shard given it writes the serial run's bytes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NominalWear {
    /// Working hours of every map, h (stages and subdivisions).
    pub hours: Vec<f64>,
    /// The disc's wear depth at each of those hours on the wear model's mesh-angle grid, m.
    pub maps: Vec<Vec<f64>>,
    /// The pins' wear maps at the same hours, m (empty: unworn).
    pub pin_maps: Vec<Vec<f64>>,
    /// Clearance growth of each crank-disc bearing, m/h.
    pub bearing_rate_disc: f64,
    /// Clearance growth of each crank-carrier bearing, m/h.
    pub bearing_rate_carrier: f64,
    /// Index in `hours` of each stage.
    pub stage_index: Vec<usize>,
    /// Index in `hours` of each point beyond the last stage where the life is looked for.
    pub extension_index: Vec<usize>,
    /// Whether this is the history's early part, up to the last stage, handed on while the
    /// points beyond it are integrated ([`nominal_wear_reporting`]): a sample whose accuracy
    /// life lies beyond its stages waits for the whole ([`SampleStep::Beyond`]). Absent in
    /// JSON: false.
    #[serde(default)]
    pub partial: bool,
}

/// The wear history of `model` at its stages and the points that split each interval between
/// two into [`SUBDIVISIONS`] parts,
/// and beyond the last stage where the accuracy life is looked for ([`dense_hours`]; up to
/// where the wear model leaves its validity).
///
/// # Errors
/// Wear integration failures; [`Error::Invalid`] naming `wear.stage_hours` if the wear
/// model's validity ends before the last stage.
pub fn nominal_wear(model: &Model) -> Result<NominalWear> {
    nominal_wear_reporting(model, &|_, _| {}, &|_| {})
}

/// [`nominal_wear`], `progress(done, total)` hearing the wear integration's steps
/// ([`crate::wear::integrate`]'s) and `early` the history's early part as soon as the
/// integration has passed the last stage, when points beyond it follow
/// ([`NominalWear::partial`]; the same maps as the whole history's at those hours): the
/// samples' stages can be analysed while the rest is integrated.
///
/// # Errors
/// As [`nominal_wear`].
pub fn nominal_wear_reporting(
    model: &Model,
    progress: &(dyn Fn(usize, usize) + Sync),
    early: &dyn Fn(NominalWear),
) -> Result<NominalWear> {
    let (mut hours, stage_index, mut extension_index) = dense_hours(model);
    let mut m = model.clone();
    m.wear.stage_hours = hours.clone();
    let bearing_rates = crate::config::bearing_rates(model)?;
    let inputs = crate::wear::WearInputs {
        bearing_rates,
        ..m.wear_inputs()
    };
    let last_stage = stage_index.last().copied().unwrap_or(0);
    let seen = std::sync::Mutex::new((Vec::new(), Vec::new()));
    let hist = crate::wear::integrate_with_stages(&inputs, progress, &|sw| {
        if extension_index.is_empty() || sw.index > last_stage {
            return;
        }
        let Ok(mut seen) = seen.lock() else {
            return;
        };
        seen.0.push(sw.map.to_vec());
        seen.1.push(sw.pin_map.to_vec());
        if sw.index == last_stage && seen.0.len() == last_stage + 1 {
            let (maps, pin_maps) = std::mem::take(&mut *seen);
            early(NominalWear {
                hours: hours[..=last_stage].to_vec(),
                maps,
                pin_maps,
                bearing_rate_disc: bearing_rates.disc,
                bearing_rate_carrier: bearing_rates.carrier,
                stage_index: stage_index.clone(),
                extension_index: Vec::new(),
                partial: true,
            });
        }
    })?;
    if let Some(l) = &hist.limit {
        if hist.maps.len() <= last_stage {
            return Err(Error::invalid(
                "wear.stage_hours",
                format!("{:?}", model.wear.stage_hours),
                format!(
                    "the nominal reducer leaves the wear model's validity at {:.0} h ({}); \
                     end the stages before",
                    l.hours, l.reason
                ),
            ));
        }
    }
    // Beyond the validity limit there is no extension.
    hours.truncate(hist.maps.len());
    extension_index.retain(|&i| i < hours.len());
    Ok(NominalWear {
        hours,
        maps: hist.maps.clone(),
        pin_maps: hist.pin_maps.clone(),
        bearing_rate_disc: bearing_rates.disc,
        bearing_rate_carrier: bearing_rates.carrier,
        stage_index,
        extension_index,
        partial: false,
    })
}

impl SharedWear {
    /// The maps of a nominal history of `model` ([`nominal_wear`]).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `shared_wear` if the history does not fit `model` (another
    /// config's: other stages or another grid); a map that is not a wear map.
    pub fn of(model: &Model, w: &NominalWear) -> Result<SharedWear> {
        let (hours, stage_index, _) = dense_hours(model);
        let fits = w.maps.len() == w.hours.len()
            && w.hours.iter().zip(&hours).all(|(a, b)| a == b)
            && w.stage_index == stage_index
            && w.stage_index.iter().all(|&i| i < w.hours.len());
        if !fits {
            return Err(Error::invalid(
                "shared_wear",
                "(a nominal wear history)",
                "the history of this config's nominal reducer (same stages and life search)",
            ));
        }
        let maps = w
            .maps
            .iter()
            .map(|map| Ok(crate::wear::profile_maps(model.wear.model, map)?.1))
            .collect::<Result<_>>()?;
        Ok(SharedWear {
            hours: w.hours.clone(),
            maps,
            pin_maps: w.pin_maps.clone(),
            bearing_rates: crate::wear::BearingWearRates {
                disc: w.bearing_rate_disc,
                carrier: w.bearing_rate_carrier,
            },
            stage_index: w.stage_index.clone(),
            extension_index: w.extension_index.clone(),
            partial: w.partial,
        })
    }
}

/// [`nominal_wear`] as the maps every sample is analysed on.
///
/// # Errors
/// As [`nominal_wear`].
pub(crate) fn shared_wear(model: &Model) -> Result<SharedWear> {
    SharedWear::of(model, &nominal_wear(model)?)
}

/// The sampled reducer `index` of `seed`: `model` with its part errors and modification drawn
/// from `model.tolerances`.
pub(crate) fn sample_model(model: &Model, seed: u64, index: usize) -> Model {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index as u64);
    let (errors, modification) = model.tolerances.sample(
        &mut rng,
        model.cycloid.geometry.pins,
        model.reducer.cranks,
        model.cycloid.modification,
    );
    let mut m = model.clone();
    m.reducer.errors = errors;
    m.cycloid.modification = modification;
    m
}

/// The accuracy quantities of `model` (a sampled reducer) with wear `wear` at `hours`. Without
/// `with_angular_te` (a trial of the life search whose spec does not bound the angular TE) the
/// revolution is not solved and the point's angular TE is NaN: such a point never leaves the
/// life search, which reads only the quantities the spec bounds ([`crate::life::margins`]).
/// The revolution's zero-torque searches and the hysteresis curve's crank angles start from
/// `warm`, the same sample's last state ([`zero_torque_over_revolution_from`],
/// [`hysteresis_with_from`]), and leave this one's there.
fn accuracy_at(
    model: &Model,
    wear: Option<WearMap>,
    hours: f64,
    per_cycle: usize,
    with_angular_te: bool,
    warm: &mut Starts,
) -> Result<AccuracyPoint> {
    let profile = model.cycloid.profile(wear)?;
    let sa = StaticAnalysis::new(&model.reducer, &profile)?;
    let rated = model.rating.rated_torque;
    // With play the no-load limits are the contact problem's; parts whose rigid kinematics
    // interfere assemble through the bearings' play or with preload (docs/model.md sections
    // 5.10 and 5.12).
    let angular_te = if !with_angular_te {
        f64::NAN
    } else if has_play(&sa) {
        zero_torque_over_revolution_from(&sa, per_cycle, rated, &mut warm.revolution)?.0
    } else {
        let rev = revolution_perturbed(&sa, per_cycle)?;
        angular_te_from(&sa, &rev, per_cycle, rated, &mut warm.revolution)?
    };
    let phis = mesh_cycle_angles(model.cycloid.geometry.pins, per_cycle);
    let (_, mean) = hysteresis_with_from(
        &sa,
        &phis,
        rated,
        model.te.measuring_torque_fraction,
        1,
        &mut warm.cranks,
    )?;
    let acc = mean.accuracy();
    let values = [
        acc.backlash,
        acc.lost_motion,
        acc.torsional_stiffness,
        angular_te,
    ];
    let needed = if with_angular_te {
        &values[..]
    } else {
        &values[..3]
    };
    if needed.iter().any(|v| !v.is_finite()) {
        return Err(Error::numerical(
            "accuracy",
            format!(
                "a non-finite accuracy quantity at {hours} h (backlash, lost motion, stiffness, \
                 angular TE: {values:?})"
            ),
        ));
    }
    Ok(AccuracyPoint {
        hours,
        max_wear_um: model.cycloid.wear_depth(&profile) * 1e6,
        backlash_arcmin: acc.backlash * ARCMIN_PER_RAD,
        lost_motion_arcmin: acc.lost_motion * ARCMIN_PER_RAD,
        angular_te_arcmin: angular_te * ARCMIN_PER_RAD,
        torsional_stiffness_nm_per_arcmin: acc.torsional_stiffness / ARCMIN_PER_RAD,
    })
}

/// Runs one sampled reducer through the study (module documentation). `shared`: the nominal
/// wear history (whole), or `None` to integrate the sample's own.
pub(crate) fn run_sample(
    model: &Model,
    plan: &Plan,
    shared: Option<&SharedWear>,
    index: usize,
) -> SampleRecord {
    let m = match assembled(model, plan, index) {
        Ok(m) => m,
        Err(rejected) => return rejected,
    };
    let own;
    let wear = match shared {
        Some(s) => s,
        None => match shared_wear(&m) {
            Ok(w) => {
                own = w;
                &own
            }
            Err(e) => {
                return SampleRecord {
                    sample: index,
                    status: format!("failed: {e}"),
                    points: Vec::new(),
                    accuracy_life_h: None,
                    limited_by: None,
                    censored_h: None,
                }
            }
        },
    };
    match stages_of(model, plan, wear, m, index) {
        SampleStep::Done(r) => r,
        SampleStep::Beyond(s) => beyond_stages(model, plan, wear, *s),
    }
}

/// A sampled reducer analysed at its stages, all within the spec, waiting for the nominal
/// wear history beyond the last stage to find its accuracy life ([`sample_beyond`]): its
/// model, its stages' points and where its next analysis starts.
#[derive(Debug, Clone)]
pub struct SampleStages {
    index: usize,
    model: Model,
    points: Vec<AccuracyPoint>,
    warm: Starts,
}

impl SampleStages {
    /// The sample's index.
    pub fn index(&self) -> usize {
        self.index
    }
}

/// One sample on a nominal history that may be partial ([`sample_on`]).
#[derive(Debug, Clone)]
pub enum SampleStep {
    /// Its record.
    Done(SampleRecord),
    /// Its stages analysed, its life beyond them: it needs the whole history.
    Beyond(Box<SampleStages>),
}

/// Sample `index` of `plan` on the nominal history `shared`: what [`run_on`] gives for it
/// when `shared` is whole; on an early part ([`NominalWear::partial`]) a sample whose stages
/// all lie within the spec waits ([`SampleStep::Beyond`]) for [`sample_beyond`] on the whole,
/// which then gives the same record as [`run_on`].
pub fn sample_on(model: &Model, plan: &Plan, shared: &SharedWear, index: usize) -> SampleStep {
    match assembled(model, plan, index) {
        Ok(m) => stages_of(model, plan, shared, m, index),
        Err(rejected) => SampleStep::Done(rejected),
    }
}

/// The sampled reducer `index` of `plan` as built: with `[tolerances.selective_assembly]`,
/// the pin grade chosen ([`assembly::select_grade`]), or the record of a unit rejected at
/// assembly.
fn assembled(model: &Model, plan: &Plan, index: usize) -> std::result::Result<Model, SampleRecord> {
    let m = sample_model(model, plan.seed, index);
    let Some(sel) = &model.tolerances.selective else {
        return Ok(m);
    };
    assembly::select_grade(m, sel, |unit| {
        new_backlash(unit, plan.samples_per_mesh_cycle)
    })
    .map_err(|status| SampleRecord {
        sample: index,
        status,
        points: Vec::new(),
        accuracy_life_h: None,
        limited_by: None,
        censored_h: None,
    })
}

/// The catalogue backlash (arcmin) of the unworn reducer `unit` over `per_cycle` crank angles
/// a mesh cycle, as a sample's 0 h stage is analysed.
///
/// # Errors
/// Those of the analysis.
pub(crate) fn new_backlash(unit: &Model, per_cycle: usize) -> Result<f64> {
    Ok(accuracy_at(unit, None, 0.0, per_cycle, false, &mut Starts::default())?.backlash_arcmin)
}

/// The record of a sample that waited ([`SampleStep::Beyond`]), on the whole nominal history
/// `shared`.
///
/// # Errors
/// [`Error::Invalid`] naming `shared_wear` if `shared` is an early part again.
pub fn sample_beyond(
    model: &Model,
    plan: &Plan,
    shared: &SharedWear,
    waiting: SampleStages,
) -> Result<SampleRecord> {
    if shared.partial {
        return Err(Error::invalid(
            "shared_wear",
            "an early part",
            "the whole nominal wear history, with its points beyond the last stage",
        ));
    }
    Ok(beyond_stages(model, plan, shared, waiting))
}

/// The accuracy point of the sampled reducer `m` at map `i` of `wear`, its analyses started
/// from `warm` (the sample's last state) and leaving theirs there.
fn point_at(
    m: &Model,
    wear: &SharedWear,
    i: usize,
    per_cycle: usize,
    angular_te: bool,
    warm: &mut Starts,
) -> Result<AccuracyPoint> {
    let pins = wear.pin_maps.get(i).map_or(&[][..], |p| &p[..]);
    let parts = crate::wear::WornState::parts(wear.bearing_rates, wear.hours[i], pins);
    accuracy_at(
        &m.worn(&parts),
        wear.maps[i].clone(),
        wear.hours[i],
        per_cycle,
        angular_te,
        warm,
    )
}

/// The sampled reducer `m` (sample `index`) at its stages, then its accuracy life, unless
/// that lies beyond the stages and `wear` is an early part.
fn stages_of(model: &Model, plan: &Plan, wear: &SharedWear, m: Model, index: usize) -> SampleStep {
    // A stage reports every quantity; a trial of the life search solves the angular TE only
    // where the spec bounds it. The stages and trials are solved in order, each revolution
    // started from the last one's.
    let mut warm = Starts::default();
    let mut points = Vec::new();
    let mut status = "ok".to_string();
    for &i in &wear.stage_index {
        match point_at(&m, wear, i, plan.samples_per_mesh_cycle, true, &mut warm) {
            Ok(p) => points.push(p),
            Err(e) => {
                status = format!("failed: {e}");
                break;
            }
        }
    }
    let waiting = SampleStages {
        index,
        model: m,
        points,
        warm,
    };
    if waiting.points.is_empty() || status != "ok" {
        return SampleStep::Done(SampleRecord {
            sample: index,
            status,
            points: waiting.points,
            accuracy_life_h: None,
            limited_by: None,
            censored_h: None,
        });
    }
    if wear.partial && first_outside(&model.life, &waiting.points).is_none() {
        return SampleStep::Beyond(Box::new(waiting));
    }
    SampleStep::Done(beyond_stages(model, plan, wear, waiting))
}

/// The record of a sample analysed at its stages (`waiting`, every stage analysed): its
/// accuracy life by bisection over the shared maps between the stages, or at the points
/// beyond them.
fn beyond_stages(
    model: &Model,
    plan: &Plan,
    wear: &SharedWear,
    waiting: SampleStages,
) -> SampleRecord {
    let SampleStages {
        index,
        model: m,
        points,
        mut warm,
    } = waiting;
    // `at` by hours maps to the nearest map (the bisection's trial hours are the maps' own:
    // the bracket halves over indices).
    let mut lookup = |h: f64| -> Result<AccuracyPoint> {
        let i = wear
            .hours
            .iter()
            .position(|&x| (x - h).abs() <= 1e-9 * h.max(1.0))
            .ok_or_else(|| Error::numerical("accuracy life", "no wear map at those hours"))?;
        point_at(
            &m,
            wear,
            i,
            plan.samples_per_mesh_cycle,
            model.life.angular_te_arcmin.is_some(),
            &mut warm,
        )
    };
    let ext: Vec<f64> = wear
        .extension_index
        .iter()
        .map(|&i| wear.hours[i])
        .collect();
    let life = bracket_life(&model.life, &points, &wear.hours, &ext, &mut lookup)
        .ok()
        .flatten();
    SampleRecord {
        sample: index,
        status: "ok".to_string(),
        points,
        accuracy_life_h: life.as_ref().and_then(|l| l.accuracy_life_h),
        censored_h: life
            .as_ref()
            .and_then(|l| l.accuracy_life_h.is_none().then_some(l.horizon_h)),
        limited_by: life.and_then(|l| l.limited_by.map(str::to_string)),
    }
}

/// The first of `points` outside the spec `th` (a margin that is not at least zero).
fn first_outside(th: &crate::config::LifeThresholds, points: &[AccuracyPoint]) -> Option<usize> {
    points
        .iter()
        .position(|p| !crate::life::margins(th, p).iter().all(|m| m.1 >= 0.0))
}

/// The accuracy life from the stage points, the crossing bracket narrowed by bisection over
/// the hours of `grid` (`at` evaluates a grid point) and the last grid interval interpolated.
fn bracket_life(
    th: &crate::config::LifeThresholds,
    points: &[AccuracyPoint],
    grid: &[f64],
    extension: &[f64],
    at: &mut dyn FnMut(f64) -> Result<AccuracyPoint>,
) -> Result<Option<crate::life::AccuracyLife>> {
    if !th.any() || points.is_empty() {
        return Ok(None);
    }
    let inside = |p: &AccuracyPoint| crate::life::margins(th, p).iter().all(|m| m.1 >= 0.0);
    let mut horizon_h = points.last().map_or(0.0, |p| p.hours);
    let (pa, pb) = match first_outside(th, points) {
        Some(0) => {
            return accuracy_life(
                th,
                &points[..1],
                |_| unreachable!("crossed at the start"),
                &|_, _| {},
            );
        }
        Some(i) => (points[i - 1], points[i]),
        None => {
            // Beyond the stages, at the shared maps' points there.
            let mut lo = *points.last().expect("points is not empty");
            let mut found = None;
            for &h in extension {
                let Ok(p) = at(h) else {
                    break;
                };
                horizon_h = h;
                if !inside(&p) {
                    found = Some((lo, p));
                    break;
                }
                lo = p;
            }
            match found {
                Some(pair) => pair,
                None => {
                    return Ok(Some(crate::life::AccuracyLife {
                        accuracy_life_h: None,
                        limited_by: None,
                        horizon_h,
                    }))
                }
            }
        }
    };
    let idx = |h: f64| grid.iter().position(|&x| x == h).unwrap_or(0);
    let (mut a, mut b) = (idx(pa.hours), idx(pb.hours));
    let (mut pa, mut pb) = (pa, pb);
    while b > a + 1 {
        let mid = (a + b) / 2;
        // A map between that cannot be analysed: the crossing is interpolated on the bracket
        // known so far.
        let Ok(pm) = at(grid[mid]) else {
            break;
        };
        if inside(&pm) {
            a = mid;
            pa = pm;
        } else {
            b = mid;
            pb = pm;
        }
    }
    let life = crate::life::crossing(th, &pa, &pb);
    Ok(Some(crate::life::AccuracyLife {
        accuracy_life_h: Some(life.0),
        limited_by: Some(life.1),
        horizon_h,
    }))
}

/// Runs the plan's samples in parallel (rayon); `progress(done, total)` after each.
///
/// # Errors
/// The shared wear integration's failures.
pub fn run(
    model: &Model,
    plan: &Plan,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<SampleRecord>> {
    let shared = if plan.full_wear {
        None
    } else {
        Some(nominal_wear(model)?)
    };
    run_on(model, plan, shared.as_ref(), progress)
}

/// [`run`] on a nominal wear history computed before ([`nominal_wear`], `None` with
/// `plan.full_wear`): the shards of a distributed run share one.
///
/// # Errors
/// [`SharedWear::of`]'s for a history of another config; [`Error::Invalid`] naming
/// `shared_wear` if one is given with `plan.full_wear` or none without it.
pub fn run_on(
    model: &Model,
    plan: &Plan,
    nominal: Option<&NominalWear>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<SampleRecord>> {
    if nominal.is_some() == plan.full_wear {
        return Err(Error::invalid(
            "shared_wear",
            if plan.full_wear { "given" } else { "none" },
            "the nominal wear history without full_wear, none with it",
        ));
    }
    let shared = nominal.map(|w| SharedWear::of(model, w)).transpose()?;
    let idx: Vec<usize> = plan.indices().collect();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let total = idx.len();
    Ok(idx
        .par_iter()
        .map(|&i| {
            let r = run_sample(model, plan, shared.as_ref(), i);
            progress(
                done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
                total,
            );
            r
        })
        .collect())
}

/// Percentiles of one quantity at one stage over the samples that reached it.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct Percentiles {
    /// Working hours, h.
    pub hours: f64,
    /// Quantity (column name of `stages.csv`).
    pub quantity: &'static str,
    /// Samples with a value.
    pub n: usize,
    /// 5th percentile.
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Mean.
    pub mean: f64,
}

/// The `q`-quantile (0..1) of sorted `v` by linear interpolation between order statistics
/// (Hyndman and Fan 1996, definition 7; NumPy's default).
pub(crate) fn quantile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let h = (v.len() - 1) as f64 * q;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    if lo == hi {
        return v[lo];
    }
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// The quantities of `stages.csv` and `percentiles.csv` ([`ACCURACY`]), each with its name
/// and its accessor of an accuracy point.
pub(crate) fn quantities() -> impl Iterator<Item = (&'static str, fn(&AccuracyPoint) -> f64)> {
    ACCURACY.iter().filter_map(|q| Some((q.name, q.accuracy?)))
}

/// Percentiles (5/50/95) of every quantity at every stage over the records with status `ok`
/// (a stage no sample reached has no row).
pub fn percentiles(records: &[SampleRecord], stage_hours: &[f64]) -> Vec<Percentiles> {
    let mut out = Vec::new();
    for (s, &h) in stage_hours.iter().enumerate() {
        for (name, f) in quantities() {
            let mut v: Vec<f64> = records
                .iter()
                .filter(|r| r.status == "ok")
                .filter_map(|r| r.points.get(s).map(f))
                .collect();
            v.sort_by(f64::total_cmp);
            if v.is_empty() {
                continue;
            }
            out.push(Percentiles {
                hours: h,
                quantity: name,
                n: v.len(),
                p5: quantile(&v, 0.05),
                p50: quantile(&v, 0.5),
                p95: quantile(&v, 0.95),
                mean: v.iter().sum::<f64>() / v.len().max(1) as f64,
            });
        }
    }
    out
}

/// Why a Monte Carlo run cannot stand for the design, if it cannot: fewer than half of the
/// samples analysed (the others cannot be assembled without preload, or failed), or half or
/// more of the analysed ones out of spec when new (an accuracy life of 0 h). `None` for a
/// usable run.
pub fn unusable(records: &[SampleRecord]) -> Option<String> {
    let rejected = records
        .iter()
        .filter(|r| r.status.starts_with(REJECTED))
        .count();
    if !records.is_empty() && rejected == records.len() {
        return Some(format!(
            "every one of the {rejected} samples was rejected at assembly \
             ([tolerances.selective_assembly])"
        ));
    }
    // Units rejected at assembly are not built: the run stands for those that were.
    let total = records.len() - rejected;
    let ok = records.iter().filter(|r| r.status == "ok").count();
    let interfering = records
        .iter()
        .filter(|r| r.status == "interference")
        .count();
    if total > 0 && 2 * ok < total {
        let failed = total - ok - interfering;
        return Some(if interfering > 0 {
            format!(
                "{ok} of {total} samples analysed ({interfering} marked interference by an \
                 earlier version, {failed} failed)"
            )
        } else {
            format!("{ok} of {total} samples analysed ({failed} failed)")
        });
    }
    let dead = records
        .iter()
        .filter(|r| r.status == "ok" && r.accuracy_life_h == Some(0.0))
        .count();
    if ok > 0 && 2 * dead >= ok {
        return Some(format!(
            "{dead} of {ok} analysed samples are out of spec when new (accuracy life 0 h)"
        ));
    }
    None
}

fn fmt_opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x}"))
}

/// The texts of Monte Carlo's `samples.csv` (one row per sample) and `stages.csv` (one row per
/// sample and stage); floats in Rust's shortest round-trip form, so reading them back gives
/// the same bits.
pub fn records_csv(records: &[SampleRecord]) -> (String, String) {
    let mut s = String::from("sample,status,accuracy_life_h,limited_by,censored_h\n");
    let mut t = String::from("sample,hours");
    for (q, _) in quantities() {
        t.push(',');
        t.push_str(q);
    }
    t.push('\n');
    for r in records {
        s.push_str(&format!(
            "{},{},{},{},{}\n",
            r.sample,
            csv_field(&r.status),
            fmt_opt(r.accuracy_life_h),
            r.limited_by.clone().unwrap_or_default(),
            fmt_opt(r.censored_h)
        ));
        for p in &r.points {
            t.push_str(&format!("{},{}", r.sample, p.hours));
            for (_, f) in quantities() {
                t.push_str(&format!(",{}", f(p)));
            }
            t.push('\n');
        }
    }
    (s, t)
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\"").replace('\n', " "))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(status: &str, life: Option<f64>) -> SampleRecord {
        SampleRecord {
            sample: 0,
            status: status.into(),
            points: Vec::new(),
            accuracy_life_h: life,
            limited_by: None,
            censored_h: None,
        }
    }

    /// The reliability curve counts the samples still within spec at the horizon throughout
    /// (the empirical survival function of censored lives) and leaves out the ones that could
    /// not be analysed: of 4 analysed reducers, lives 100 and 200 h and two survivors, it
    /// steps from 1 to 0.75 at 100 h and to 0.5 at 200 h and stays at 0.5 to the horizon; the
    /// B10 and B50 of the life distribution lie on it.
    #[test]
    fn reliability_counts_the_survivors() {
        let records = [
            record("ok", Some(200.0)),
            record("interference", None),
            record("ok", None),
            record("ok", Some(100.0)),
            record("ok", None),
        ];
        let curve = reliability(&records, 1000.0);
        assert_eq!(
            curve,
            vec![
                (0.0, 1.0),
                (100.0, 1.0),
                (100.0, 0.75),
                (200.0, 0.75),
                (200.0, 0.5),
                (1000.0, 0.5)
            ]
        );
        let l = life_distribution(&records, 1000.0);
        assert_eq!(l.n, 4);
        assert_eq!(l.censored_fraction, 0.5);
        assert!(l.b10_h.is_some_and(|b| b <= 200.0), "{:?}", l.b10_h);
        assert_eq!(
            (l.failures, l.km_b10_h, l.km_b50_h),
            (2, Some(100.0), Some(200.0))
        );
        assert_eq!(unusable(&records), None);
        // Tied lives step once.
        let tied = [record("ok", Some(50.0)), record("ok", Some(50.0))];
        assert_eq!(
            reliability(&tied, 60.0),
            vec![(0.0, 1.0), (50.0, 1.0), (50.0, 0.0), (60.0, 0.0)]
        );
    }

    /// A run is unusable when fewer than half of its samples could be analysed, or when half
    /// or more of the analysed ones are out of spec new.
    #[test]
    fn unusable_runs_are_named() {
        let most_interfere = [
            record("interference", None),
            record("interference", None),
            record("ok", Some(10.0)),
        ];
        assert!(unusable(&most_interfere).is_some_and(|w| w.contains("1 of 3")));
        let dead = [record("ok", Some(0.0)), record("ok", Some(5.0))];
        assert!(unusable(&dead).is_some_and(|w| w.contains("out of spec when new")));
        assert_eq!(unusable(&[record("ok", Some(5.0))]), None);
    }

    /// A sample whose life search ended before the horizon (its analysis, or the shared wear
    /// history, ended there) is censored there, not at the horizon. One of four samples out of
    /// spec at 3 477 h and three followed within spec to 5 000 h only, horizon 75 000 h: B50
    /// lies beyond 5 000 h (not "beyond 75 000 h"), the Weibull fit's sample carries 5 000 h,
    /// the reliability curve ends there. One of them followed only to 2 000 h, before the
    /// failure: the failure's step is the Kaplan-Meier one, 1 - 1/3 of the three at risk (not
    /// 1 - 1/4), and the interpolated B10 is not given (that sample's life may lie below it).
    #[test]
    fn samples_are_censored_where_their_search_ended() {
        let at = |h: f64| SampleRecord {
            censored_h: Some(h),
            ..record("ok", None)
        };
        let records = [record("ok", Some(3477.0)), at(5e3), at(5e3), at(5e3)];
        let l = life_distribution(&records, 75e3);
        assert_eq!(l.horizon_h, 5e3);
        assert_eq!(life_text(l.b50_h, l.km_b50_h, l.horizon_h), "beyond 5000 h");
        assert_eq!(weibull_sample(&records, 75e3).1, vec![5e3; 3]);
        assert_eq!(reliability(&records, 75e3).last(), Some(&(5e3, 0.75)));
        let early = [record("ok", Some(3477.0)), at(2e3), at(5e3), at(5e3)];
        let r = reliability(&early, 75e3);
        assert_eq!(r[1..3], [(3477.0, 1.0), (3477.0, 1.0 - 1.0 / 3.0)], "{r:?}");
        let l = life_distribution(&early, 75e3);
        assert_eq!((l.b10_h, l.km_b10_h), (None, Some(3477.0)));
        // Followed to the horizon, as before: the same figures as censoring at the horizon.
        let full = [record("ok", Some(3477.0)), at(75e3), at(75e3), at(75e3)];
        let old = [
            record("ok", Some(3477.0)),
            record("ok", None),
            record("ok", None),
            record("ok", None),
        ];
        assert_eq!(
            life_distribution(&full, 75e3),
            life_distribution(&old, 75e3)
        );
        assert_eq!(reliability(&full, 75e3), reliability(&old, 75e3));
    }

    /// One of four samples out of spec at 3 477 h, three within spec at the 75 000 h horizon:
    /// the interpolated B10 is not defined, and the run says B10 is at most 3 477 h (a quarter
    /// of the samples had left the spec by then), never "beyond 75 000 h"; one failure fits no
    /// Weibull law and the run says so.
    #[test]
    fn b10_is_bounded_by_the_samples_that_left_the_spec() {
        let records = [
            record("ok", Some(3477.0)),
            record("ok", None),
            record("ok", None),
            record("ok", None),
        ];
        let l = life_distribution(&records, 75e3);
        assert_eq!(l.b10_h, None);
        assert_eq!(l.km_b10_h, Some(3477.0));
        assert_eq!(l.km_b50_h, None);
        assert!(l.weibull.is_none());
        assert_eq!(life_text(l.b10_h, l.km_b10_h, 75e3), "at most 3477 h");
        assert_eq!(life_text(l.b50_h, l.km_b50_h, 75e3), "beyond 75000 h");
        assert!(
            l.weibull_text().starts_with("no Weibull fit: 1 of 4"),
            "{}",
            l.weibull_text()
        );
        // Twelve lives from a Weibull law of shape 4 and scale 5 000 h, eight more within spec
        // at 7 500 h: a fit with B10 and B50 inside their bounds.
        let mut more: Vec<SampleRecord> = [
            2200.0, 2900.0, 3300.0, 3650.0, 3900.0, 4200.0, 4500.0, 4800.0, 5200.0, 5600.0, 6100.0,
            6900.0,
        ]
        .iter()
        .map(|&t| record("ok", Some(t)))
        .collect();
        more.extend((0..8).map(|_| record("ok", None)));
        let l = life_distribution(&more, 7500.0);
        let w = l.weibull.as_ref().unwrap();
        assert!(w.b10_lower_h < w.b10_h && w.b10_upper_h.is_some_and(|u| w.b10_h < u));
        assert!(w.b50_lower_h < w.b50_h && w.b50_upper_h.is_some_and(|u| w.b50_h < u));
        assert!(w.shape > 2.0 && w.shape < 8.0, "{w:?}");
        assert!(l.weibull_text().contains("likelihood-ratio"));
    }
}
