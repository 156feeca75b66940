//! The accuracy-life study: wear over working hours, and at every stage the worn profile, the
//! static TE and lost motion, the loaded TE at the rated torque, and the contact loads.
//!
//! Pipeline: [`crate::wear::integrate`] gives the wear map at each stage; each stage's
//! profile is the modified profile with that map (or, in the paper's model, with a uniform
//! equidistant offset equal to the maximum wear, paper section 3.1); [`crate::te`] gives STE,
//! lost motion and loaded TE on it; with `[dynamics] enabled`, [`crate::dynamics::simulate`]
//! gives the dynamic TE of the whole reducer with it; with `[fem] enabled`,
//! [`crate::fem::flex::analyse_stage`] gives the flexible-disc TE, torsional stiffness and disc
//! stress on a plane-stress FE model of the worn disc.

use std::sync::atomic::{AtomicUsize, Ordering};

use serde::Serialize;

use crate::budget;
use crate::config::Model;
use crate::dynamics::{simulate_discs, DynamicsSummary};
use crate::error::Error;
use crate::error::Result;
use crate::fem::flex::{analyse_stage, FlexibleStage};
use crate::fem::mesh::Mesh;
use crate::fem::DiscSet;
use crate::geometry::{Profile, WearMap};
use crate::quantities::{AccuracyPoint, StageSummary, ACCURACY, ANGULAR_TE, STAGE};
use crate::statics::StaticAnalysis;
use crate::te::{
    angular_te_of, hysteresis_and_rated, hysteresis_with, loaded_te_with, mesh_cycle_angles,
    revolution, revolution_no_load, static_te_with, torque_fractions, CurveStats, LoadedTe,
    RevolutionTe, StaticTe, TwistTable, HYSTERESIS_LEVELS, PLAY_ROUND_OFF,
};
use crate::units::ARCMIN_PER_RAD;
use crate::wear::BearingWearRates;
use crate::wear::{integrate, ValidityLimit, WearHistory, WearInputs, WearModelKind};

pub mod parts;

/// Full results of one stage.
#[derive(Debug, Clone)]
pub struct Stage {
    /// Working hours, h.
    pub hours: f64,
    /// Wear map at this stage (None when unworn).
    pub wear: Option<WearMap>,
    /// Profile used for TE (worn; uniform-max in the paper's model).
    pub profile: Profile,
    /// Static TE over a mesh cycle.
    pub ste: StaticTe,
    /// Loaded TE over a mesh cycle.
    pub loaded: LoadedTe,
    /// Hysteresis twist table averaged over a mesh cycle.
    pub hysteresis: TwistTable,
    /// Static TE over an output revolution (with part errors; without, every mesh cycle of
    /// the revolution is [`Stage::ste`]).
    pub revolution: Option<RevolutionTe>,
    /// Summary numbers.
    pub summary: StageSummary,
    /// Summary of the multibody simulation with this stage's profile (when dynamics are on).
    pub dynamics: Option<DynamicsSummary>,
    /// Flexible-disc analysis and the disc mesh (when the flexible disc is on).
    pub flexible: Option<(FlexibleStage, Mesh)>,
}

/// Everything `analyse_profile` finds for one profile.
#[derive(Debug, Clone)]
pub struct ProfileAnalysis {
    /// Static TE over a mesh cycle.
    pub ste: StaticTe,
    /// Loaded TE over a mesh cycle.
    pub loaded: LoadedTe,
    /// Hysteresis twist table averaged over a mesh cycle.
    pub hysteresis: TwistTable,
    /// Static TE over an output revolution (with part errors only).
    pub revolution: Option<RevolutionTe>,
    /// Summary numbers.
    pub summary: StageSummary,
}

/// Results of the whole study.
#[derive(Debug, Clone)]
pub struct Study {
    /// The model it ran.
    pub model: Model,
    /// The wear history.
    pub wear: WearHistory,
    /// Stages.
    pub stages: Vec<Stage>,
    /// The accuracy life against `[life]` (when thresholds are set).
    pub life: Option<crate::life::AccuracyLife>,
}

/// Comparison with the paper's headline numbers (docs/model.md section 16).
#[derive(Debug, Clone, Serialize)]
pub struct PaperComparison {
    /// Slope of the mean STE against the maximum wear, arcmin per 10 um (least squares through
    /// the origin over the stages).
    pub ste_per_10um_arcmin: f64,
    /// Mean STE at the last stage, arcmin.
    pub ste_last_stage_arcmin: f64,
    /// Paper: rigid-body STE mean at 10 um wear (Adams), arcmin.
    pub paper_ste_at_10um_arcmin: f64,
    /// Paper: largest rigid STE over the study (6450 h), arcmin.
    pub paper_ste_max_arcmin: f64,
    /// Uniform-offset estimate per side, `10 um / (a (Zp + Z1/Z2))`, arcmin
    /// (docs/model.md section 6).
    pub uniform_offset_per_10um_arcmin: f64,
    /// Paper: rigid-body DTE mean at 10 um wear under the sinusoidal load (Adams), arcmin.
    pub paper_dte_at_10um_arcmin: f64,
    /// Paper: largest rigid DTE over the study (6450 h), arcmin.
    pub paper_dte_max_arcmin: f64,
    /// Paper: rigid-flexible STE mean at 10 um wear (Adams, disc as a modal FE body), arcmin.
    pub paper_flexible_ste_at_10um_arcmin: f64,
    /// Paper: largest rigid-flexible STE over the study (7500 h), arcmin.
    pub paper_flexible_ste_max_arcmin: f64,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// rvlife version.
    pub rvlife_version: &'static str,
    /// Overall ratio `i_H`.
    pub ratio: f64,
    /// Wear model.
    pub wear_model: WearModelKind,
    /// Archard coefficient, mm^3/(N m).
    pub archard_coefficient_mm3_per_n_m: f64,
    /// Rated torque, N m.
    pub rated_torque_nm: f64,
    /// Torque of the loaded TE, N m.
    pub loaded_te_torque_nm: f64,
    /// Mesh cycles per working hour of each tooth at the nominal input speed.
    pub mesh_cycles_per_hour: f64,
    /// Wear-rate evaluations (profile updates + 1).
    pub wear_rate_evaluations: usize,
    /// Stages (up to the validity limit).
    pub stages: Vec<StageSummary>,
    /// Where the model leaves its validity, when it does before the last stage: the stages
    /// from there on are not reported.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub validity_limit: Option<ValidityLimit>,
    /// The accuracy life against `[life]` (when thresholds are set).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy_life: Option<crate::life::AccuracyLife>,
    /// The measured profile's fit (when `cycloid.measured_profile` is set): file, points, RMS
    /// and largest residual, um.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured_profile_fit: Option<serde_json::Value>,
    /// Against the paper: only for the paper's reducer as printed (its stage, unmodified, no
    /// measured profile), like for like.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paper_comparison: Option<PaperComparison>,
}

/// Whether `m`'s disc is the paper's as printed (its stage, no modification, no measured
/// profile; docs/model.md section 16): the only reducer compared with the paper's numbers.
pub(crate) fn is_papers_reducer(m: &crate::config::Model) -> bool {
    crate::config::Config::paper()
        .cycloid
        .validate()
        .is_ok_and(|(geometry, modification)| {
            m.cycloid.geometry == geometry
                && m.cycloid.modification == modification
                && m.cycloid.measured.is_none()
        })
}

/// Radians to arcminutes, with values below 1e-6 arcmin reported as zero rather than as a
/// signed `-0.0000` or a `3.87e-8`: 1.5e-11 m at the example's pitch radius, the resolution of
/// the contact geometry (its gap field is interpolated to about 1e-11 m; the first contact is
/// solved to 1e-14 m of gap), and a thousandth of the twist a 0.01 um modification gives.
fn arcmin(rad: f64) -> f64 {
    let v = rad * ARCMIN_PER_RAD;
    if v.abs() < 1e-6 {
        0.0
    } else {
        v
    }
}

/// Fails loudly, naming the quantity, if a stage summary holds a NaN or an infinity (JSON has
/// neither: they would be written as `null`, and as `NaN`/`inf` in CSV).
fn check_finite(summary: &StageSummary) -> Result<()> {
    match STAGE.iter().find(|q| !summary.value(q).is_finite()) {
        Some(q) => Err(Error::numerical(
            "stage summary",
            format!("{} is not a finite number at {} h", q.name, summary.hours),
        )),
        None => Ok(()),
    }
}

/// The validated model of `cfg` ([`crate::config::Config::validate`]) whose study fits the
/// work budget ([`check_work`]): what every command and every design of a sweep runs on.
///
/// # Errors
/// [`Error::Invalid`] naming the key, the value and the allowed range, or the key that drives
/// the work beyond the budget (a key the file does not set named as a default).
pub(crate) fn validated(cfg: &crate::config::Config) -> Result<Model> {
    let model = cfg.validate()?;
    check_work(&model).map_err(|e| cfg.explain_default(e))?;
    Ok(model)
}

/// The estimated work of a study of `model`, in static solves ([`crate::budget`]): `(wear
/// integration, stages' analyses)` ([`check_work`]).
pub(crate) fn study_work(model: &Model) -> (f64, f64) {
    let w = &model.wear;
    let positions = crate::wear::revolution_positions(&model.reducer);
    let wear = w.scheduled_updates() * w.rate_evaluation_solves(model.load.levels.len(), positions);
    let stages = w.stage_hours.len() as f64 * model.budget().per_stage;
    (wear, stages)
}

/// Checks the work of a study of `model` against its budget before it starts
/// ([`crate::budget`]): wear-rate evaluations (`last stage / wear.profile_update_hours`) x
/// (load levels x (`wear.crank_steps_per_mesh_cycle` + set-up) + the rest of an evaluation),
/// plus stages x (`te.samples_per_mesh_cycle` x the hysteresis and loaded-TE torques +
/// set-up). The profile updates that `wear.max_wear_step_um` asks for are checked by the wear
/// integration once the first wear rate is known.
///
/// # Errors
/// [`Error::Invalid`] naming the key whose value is furthest above the example's (the key that
/// sets the load levels for them: `load.levels`, `load.file`), with the estimate and the
/// budget.
pub(crate) fn check_work(model: &Model) -> Result<()> {
    let w = &model.wear;
    let updates = w.scheduled_updates();
    let (wear, stages) = study_work(model);
    let total = wear + stages;
    if total <= model.work_budget {
        return Ok(());
    }
    // The factor furthest above the example's value drives it.
    let levels = model.load.levels.len() as f64;
    let candidates = [
        (
            model.load.levels_key.to_string(),
            format!("{levels} levels"),
            levels / 24.0,
        ),
        (
            "wear.profile_update_hours".to_string(),
            format!("{}", w.update_hours),
            updates / 30.0,
        ),
        (
            "wear.crank_steps_per_mesh_cycle".to_string(),
            w.crank_steps.to_string(),
            w.crank_steps as f64 / 18.0,
        ),
        (
            "wear.stage_hours".to_string(),
            format!("{} stages", w.stage_hours.len()),
            w.stage_hours.len() as f64 / 7.0,
        ),
        (
            "te.samples_per_mesh_cycle".to_string(),
            model.te.samples.to_string(),
            model.te.samples as f64 / 24.0,
        ),
    ];
    let (key, value, _) = candidates
        .iter()
        .fold(&candidates[0], |a, b| if b.2 > a.2 { b } else { a });
    Err(Error::invalid(
        key.as_str(),
        value,
        format!(
            "the study would need about {total:.2e} contact solves (~{:.1} min: {updates} \
             wear-rate evaluations x {levels} load levels x {} crank steps, {} stages x {} TE \
             samples), more than the work budget of {:.1} min (--work-budget-min); lower it",
            budget::minutes(total),
            w.crank_steps,
            w.stage_hours.len(),
            model.te.samples,
            budget::minutes(model.work_budget),
        ),
    ))
}

/// The static analysis of `model`'s reducer with `profile`, the mesh cycle's crank angles
/// (`te.samples`) and the hysteresis over them at the rated torque with the equilibria at
/// `+rated` ([`hysteresis_and_rated`]): what [`analyse_profile`] and the accuracy life's
/// trials share.
///
/// # Errors
/// Solver failures.
#[allow(clippy::type_complexity)]
fn stage_hysteresis<'a>(
    model: &'a Model,
    profile: &'a Profile,
) -> Result<(
    StaticAnalysis<'a>,
    Vec<f64>,
    (
        Vec<TwistTable>,
        TwistTable,
        Vec<crate::statics::StaticSolution>,
    ),
)> {
    let phis = mesh_cycle_angles(model.reducer.geometry.pins, model.te.samples);
    let sa = StaticAnalysis::new(&model.reducer, profile)?;
    let h = hysteresis_and_rated(
        &sa,
        &phis,
        model.rating.rated_torque,
        model.te.measuring_torque_fraction,
        &torque_fractions(model.te.measuring_torque_fraction, HYSTERESIS_LEVELS, true),
    )?;
    Ok((sa, phis, h))
}

/// Analyses one profile: static TE, the hysteresis curve averaged over a mesh cycle (backlash,
/// lost motion, hysteresis loss, torsional stiffness) and the loaded TE at the model's
/// loaded-TE torque, all from the static analysis of the reducer model.
///
/// # Errors
/// Solver failures; interference of the modifications.
pub(crate) fn analyse_profile(
    model: &Model,
    profile: &Profile,
    hours: f64,
) -> Result<ProfileAnalysis> {
    let red = &model.reducer;
    let (sa, phis, (tables, mean, rated)) = stage_hysteresis(model, profile)?;
    let ste = StaticTe {
        crank_angle: phis.clone(),
        forward: tables.iter().map(|t| t.positive[0]).collect(),
        reverse: tables.iter().map(|t| -t.negative[0]).collect(),
    };
    if let Some(k) = ste.backlash().iter().position(|&b| b < -PLAY_ROUND_OFF) {
        return Err(Error::invalid(
            "cycloid.modification",
            format!(
                "play {:.4} arcmin at crank angle {:.3} deg",
                ste.backlash()[k] * ARCMIN_PER_RAD,
                ste.crank_angle[k].to_degrees()
            ),
            "the modified disc interferes with the pins (negative clearance); \
             thin the teeth (equidistant > 0 or offset < 0)",
        ));
    }
    // At the rated torque (the default) the loaded TE is the hysteresis' top level.
    let loaded = if model.te.loaded_torque == model.rating.rated_torque {
        LoadedTe::from_solutions(model.te.loaded_torque, phis, rated)
    } else {
        loaded_te_with(&sa, model.te.loaded_torque, model.te.samples)?
    };
    let acc = mean.accuracy();
    let s = ste.stats();
    let play = ste.backlash_stats();
    let l = loaded.stats();
    let (pmin, pmax) = loaded.pins_in_contact();
    let share = match red.support {
        crate::reducer::Support::Rigid { load_share } => load_share,
        crate::reducer::Support::Bearings => {
            loaded
                .solutions
                .iter()
                .map(|x| {
                    let total: f64 = x.discs.iter().map(|d| d.torque).sum();
                    if total != 0.0 {
                        x.discs[0].torque / total
                    } else {
                        0.5
                    }
                })
                .sum::<f64>()
                / loaded.solutions.len() as f64
        }
    };
    let max_wear_um = model.cycloid.wear_depth(profile) * 1e6;
    let rev = if red.errors.is_zero() {
        None
    } else {
        Some(revolution(&sa, model.te.samples)?)
    };
    let (angular_te, play_max) = match &rev {
        None => (s.peak_to_peak, play.max),
        Some(rev) => {
            let (angular_te, play_max) =
                revolution_no_load(&sa, rev, model.te.samples, model.rating.rated_torque)?;
            (angular_te, play_max.max(0.0))
        }
    };
    let summary = StageSummary {
        hours,
        max_wear_um,
        ste_mean_arcmin: arcmin(s.mean),
        ste_peak_to_peak_arcmin: arcmin(s.peak_to_peak),
        ste_reverse_mean_arcmin: arcmin(CurveStats::of(&ste.reverse).mean),
        backlash_arcmin: arcmin(acc.backlash),
        backlash_max_arcmin: arcmin(play_max),
        angular_te_arcmin: arcmin(angular_te),
        lost_motion_arcmin: arcmin(acc.lost_motion),
        hysteresis_loss_arcmin: arcmin(acc.hysteresis_loss),
        loaded_te_mean_arcmin: arcmin(l.mean),
        loaded_te_peak_to_peak_arcmin: arcmin(l.peak_to_peak),
        max_force_n: loaded.max_force(),
        max_pressure_mpa: loaded.max_pressure() * 1e-6,
        pins_in_contact: pmin,
        pins_in_contact_max: pmax,
        disc_load_share: share,
        // The split of the lost motion as if the whole play were the assembly's; the study
        // splits the play between assembly, bearing wear and disc wear (`split_play`).
        lost_motion_elastic_arcmin: arcmin(acc.lost_motion - acc.backlash),
        lost_motion_assembly_arcmin: arcmin(acc.backlash),
        angular_te_assembly_arcmin: arcmin(angular_te),
        pin_max_wear_um: red.pin_wear.max_depth() * 1e6,
        crank_disc_clearance_um: red.bearings.disc.clearance * 1e6,
        crank_carrier_clearance_um: red.bearings.carrier.clearance * 1e6,
        torsional_stiffness_nm_per_arcmin: acc.torsional_stiffness / ARCMIN_PER_RAD,
        tangent_stiffness_nm_per_arcmin: loaded.mean_stiffness() / ARCMIN_PER_RAD,
        // The dynamics' and the flexible disc's quantities are added by the study.
        ..Default::default()
    };
    check_finite(&summary)?;
    Ok(ProfileAnalysis {
        ste,
        loaded,
        hysteresis: mean,
        revolution: rev,
        summary,
    })
}

/// The accuracy-spec quantities of one profile only ([`AccuracyPoint`]: backlash, lost motion
/// and stiffness from the hysteresis curve averaged over a mesh cycle, the angular TE from its
/// zero-torque row or, with part errors, over an output revolution), as
/// [`analyse_profile`] finds them, without the loaded TE: the accuracy life's trials.
///
/// A trial reads the curve at the three torques the quantities are defined at (zero, the
/// measuring and the rated torque: [`hysteresis_with`] with one level), not on the stage's
/// plotted grid: each loaded twist is the equilibrium at its torque whatever the levels solved
/// before it, so the quantities are the stage analysis's to the solver's tolerance. With part
/// errors and no angular TE in `[life]`, the revolution is not solved and the point's angular
/// TE is NaN: a trial's point never leaves the life search, which reads only the quantities the
/// spec bounds ([`crate::life::margins`]).
///
/// # Errors
/// Solver failures; a quantity the spec needs that is not finite.
fn accuracy_point(model: &Model, profile: &Profile, hours: f64) -> Result<AccuracyPoint> {
    let red = &model.reducer;
    let sa = StaticAnalysis::new(red, profile)?;
    let phis = mesh_cycle_angles(red.geometry.pins, model.te.samples);
    let (tables, mean) = hysteresis_with(
        &sa,
        &phis,
        model.rating.rated_torque,
        model.te.measuring_torque_fraction,
        1,
    )?;
    let acc = mean.accuracy();
    let angular_te = if red.errors.is_zero() {
        let forward: Vec<f64> = tables.iter().map(|t| t.positive[0]).collect();
        CurveStats::of(&forward).peak_to_peak
    } else if model.life.angular_te_arcmin.is_some() {
        let rev = revolution(&sa, model.te.samples)?;
        angular_te_of(&sa, &rev, model.te.samples, model.rating.rated_torque)?
    } else {
        f64::NAN
    };
    let p = AccuracyPoint {
        hours,
        max_wear_um: model.cycloid.wear_depth(profile) * 1e6,
        backlash_arcmin: arcmin(acc.backlash),
        lost_motion_arcmin: arcmin(acc.lost_motion),
        angular_te_arcmin: arcmin(angular_te),
        torsional_stiffness_nm_per_arcmin: acc.torsional_stiffness / ARCMIN_PER_RAD,
    };
    let skipped = |name: &str| name == ANGULAR_TE.name && angular_te.is_nan();
    match ACCURACY
        .iter()
        .find(|q| !skipped(q.name) && q.accuracy.is_some_and(|value| !value(&p).is_finite()))
    {
        Some(q) => Err(Error::numerical(
            "accuracy life",
            format!("{} is not a finite number at {hours} h", q.name),
        )),
        None => Ok(p),
    }
}

/// A stage's dynamics and flexible analysis: the DTE summary and the flexible results.
type StageRow = (Option<DynamicsSummary>, Option<(FlexibleStage, Mesh)>);

/// What [`run`] made of one stage.
enum Outcome {
    /// No static results.
    Failed(Failure),
    /// Not analysed: an earlier stage's static analysis failed.
    Skipped,
    /// Analysed, with its dynamics and flexible analysis (or their error).
    Done(Box<(Stage, Result<StageRow>)>),
}

/// The no-load accuracy of a reducer with a given disc: what the stages' lost motion and
/// angular TE are split against (docs/model.md section 6.5).
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(crate) struct NoLoad {
    /// Mean backlash over a mesh cycle, rad.
    play: f64,
    /// Angular TE (over an output revolution with part errors, a mesh cycle without), rad.
    angular_te: f64,
}

/// [`NoLoad`] of `model`'s reducer with the disc `profile`, from the rigid first contacts:
/// where part errors make them cross (preload, docs/model.md section 5.12) the play is zero,
/// and the angular TE is [`angular_te_of`]'s.
fn no_load(model: &Model, profile: &Profile) -> Result<NoLoad> {
    let red = &model.reducer;
    let samples = model.te.samples;
    let sa = StaticAnalysis::new(red, profile)?;
    let ste = static_te_with(&sa, &mesh_cycle_angles(red.geometry.pins, samples))?;
    let play = ste.backlash().iter().map(|b| b.max(0.0)).sum::<f64>() / samples as f64;
    let angular_te = if red.errors.is_zero() {
        ste.stats().peak_to_peak
    } else {
        let rev = revolution(&sa, samples)?;
        angular_te_of(&sa, &rev, samples, model.rating.rated_torque)?
    };
    Ok(NoLoad { play, angular_te })
}

/// Splits the play of `s` (its backlash) into the new reducer's (`new`), the bearings' wear
/// (the unworn disc's on the stage's bearings and unworn pins, `bearings`, beyond `new`), the
/// pins' wear (the unworn disc's on the stage's bearings and pins, `parts`, beyond
/// `bearings`) and the disc's wear (the rest), the elastic part being the lost motion beyond
/// the backlash; and its angular TE the same way (docs/model.md section 6.5).
fn split_play(s: &mut StageSummary, new: NoLoad, bearings: NoLoad, parts: NoLoad) {
    s.lost_motion_assembly_arcmin = arcmin(new.play);
    s.lost_motion_bearing_wear_arcmin = arcmin(bearings.play - new.play);
    s.lost_motion_pin_wear_arcmin = arcmin(parts.play - bearings.play);
    s.lost_motion_elastic_arcmin = s.lost_motion_arcmin - s.backlash_arcmin;
    // The disc's parts are the rest of the totals as reported, so the parts add up to them
    // exactly whatever [`arcmin`] rounds to zero.
    s.lost_motion_disc_wear_arcmin = s.lost_motion_arcmin
        - (s.lost_motion_elastic_arcmin
            + s.lost_motion_assembly_arcmin
            + s.lost_motion_bearing_wear_arcmin
            + s.lost_motion_pin_wear_arcmin);
    s.angular_te_assembly_arcmin = arcmin(new.angular_te);
    s.angular_te_bearing_wear_arcmin = arcmin(bearings.angular_te - new.angular_te);
    s.angular_te_pin_wear_arcmin = arcmin(parts.angular_te - bearings.angular_te);
    s.angular_te_disc_wear_arcmin = s.angular_te_arcmin
        - (s.angular_te_assembly_arcmin
            + s.angular_te_bearing_wear_arcmin
            + s.angular_te_pin_wear_arcmin);
}

/// The wear map of a stage from the wear integration's depths `map` (m per grid point; empty
/// or zero: unworn), and the map its profile is made with (the uniform one at the map's
/// largest depth in the paper's wear model, section 3.1 of the paper); `None` when unworn.
///
/// # Errors
/// [`Error::Invalid`] for a map [`WearMap::new`] refuses.
fn stage_maps(model: &Model, map: &[f64]) -> Result<(Option<WearMap>, Option<WearMap>)> {
    let max = map.iter().copied().fold(0.0, f64::max);
    let wear_map = if max > 0.0 {
        Some(WearMap::new(map.to_vec())?)
    } else {
        None
    };
    let te_map = match (&wear_map, model.wear.model) {
        (Some(_), WearModelKind::Paper) => Some(WearMap::uniform(map.len(), max)?),
        (w, _) => w.clone(),
    };
    Ok((wear_map, te_map))
}

/// Why a stage of a study has no static results.
#[derive(Debug)]
enum Failure {
    /// Its wear map could not be made: an error of the study.
    Prepare(Error),
    /// Its static analysis failed (with the stage's largest wear depth, m).
    Static(Error, f64),
}

/// The static part of the stage at `hours` with the wear depth `map` (m per grid point; empty
/// or zero: unworn) and the pins' wear `pin_map` (m round the pin; empty or zero: unworn):
/// the worn profile, its static analysis on the parts as worn by then (the crank bearings'
/// clearance grown by `rates`, the pins by `pin_map`), and its play split against the new
/// reducer's (`new`) and the unworn disc's on those parts (docs/model.md section 6.5). Also
/// returns the model with the worn parts. The stage has no dynamics or flexible results yet.
fn static_part<'a>(
    model: &'a Model,
    rates: BearingWearRates,
    new: NoLoad,
    hours: f64,
    map: &[f64],
    pin_map: &[f64],
    base_profile: &Profile,
) -> std::result::Result<(Stage, std::borrow::Cow<'a, Model>), Failure> {
    // The crank bearings as worn by this stage's hours (their rates are constant in time),
    // and the pins as worn by then.
    let base_model = model;
    let staged = crate::config::worn_parts(model, rates, hours, pin_map);
    let model: &Model = &staged;
    let max = map.iter().copied().fold(0.0, f64::max);
    let (wear_map, te_map) = stage_maps(model, map).map_err(Failure::Prepare)?;
    let (profile, mut a) = model
        .cycloid
        .profile(te_map)
        .and_then(|p| analyse_profile(model, &p, hours).map(|a| (p, a)))
        .map_err(|e| Failure::Static(e, max))?;
    // The unworn disc's play on this stage's bearings, then on its bearings and pins (the new
    // reducer's unless they wear).
    let unworn = || -> Result<(NoLoad, NoLoad)> {
        if std::ptr::eq(model, base_model) {
            return Ok((new, new));
        }
        let bearings_only = crate::config::worn_parts(base_model, rates, hours, &[]);
        let bearings = if std::ptr::eq(&*bearings_only, base_model) {
            new
        } else {
            no_load(&bearings_only, base_profile)?
        };
        let parts = if model.reducer.pin_wear.is_zero() {
            bearings
        } else {
            no_load(model, base_profile)?
        };
        Ok((bearings, parts))
    };
    let (b, p) = unworn().map_err(|e| Failure::Static(e, max))?;
    split_play(&mut a.summary, new, b, p);
    let stage = Stage {
        hours,
        wear: wear_map,
        profile,
        ste: a.ste,
        loaded: a.loaded,
        hysteresis: a.hysteresis,
        revolution: a.revolution,
        summary: a.summary,
        dynamics: None,
        flexible: None,
    };
    Ok((stage, staged))
}

/// Stage `i` of a study at `hours` with the wear depth `map` and the pins' wear `pin_map`: its
/// static part ([`static_part`]), then its dynamics and flexible analysis
/// ([`dynamics_and_flexible`]). Skipped when a stage before it has failed its static analysis
/// (`failed`: the lowest such index, which a failure here lowers); `tick` after each
/// analysis, `on_static` with the static part's summary.
#[allow(clippy::too_many_arguments)]
fn run_stage(
    model: &Model,
    rates: BearingWearRates,
    new: NoLoad,
    i: usize,
    hours: f64,
    map: &[f64],
    pin_map: &[f64],
    base: Option<&DiscSet>,
    base_profile: &Profile,
    failed: &AtomicUsize,
    tick: &(dyn Fn() + Sync),
    on_static: &dyn Fn(&StageSummary),
) -> Outcome {
    if i > failed.load(Ordering::Relaxed) {
        return Outcome::Skipped;
    }
    let (stage, staged) = match static_part(model, rates, new, hours, map, pin_map, base_profile) {
        Ok(x) => x,
        Err(f) => {
            if matches!(f, Failure::Static(..)) {
                failed.fetch_min(i, Ordering::Relaxed);
            }
            return Outcome::Failed(f);
        }
    };
    on_static(&stage.summary);
    tick();
    let rest = if i > failed.load(Ordering::Relaxed) {
        Ok((None, None))
    } else {
        dynamics_and_flexible(&staged, &stage.profile, base, base_profile, tick)
    };
    Outcome::Done(Box::new((stage, rest)))
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
fn until_limit<T>(
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
/// beyond them).
///
/// # Errors
/// Those of [`study_life`].
fn finish(
    model: &Model,
    wear: WearHistory,
    stages: Vec<Stage>,
    ahead: Option<LifeTrials>,
    notice: &dyn Fn(&str),
) -> Result<Study> {
    let summaries: Vec<StageSummary> = stages.iter().map(|s| s.summary.clone()).collect();
    let life = study_life(model, &summaries, &wear, ahead, notice)?;
    Ok(Study {
        model: model.clone(),
        wear,
        stages,
        life,
    })
}

/// The multibody simulation and the flexible analysis of the stage of `profile`, side by side
/// (each if enabled), on the FE disc (the unworn `base` moved onto a worn profile's outline);
/// `tick` after each.
///
/// # Errors
/// Failures of either analysis or of the FE disc.
fn dynamics_and_flexible(
    model: &Model,
    profile: &Profile,
    base: Option<&DiscSet>,
    base_profile: &Profile,
    tick: &(dyn Fn() + Sync),
) -> Result<StageRow> {
    if !(model.dynamics.enabled || model.fem.enabled) {
        return Ok((None, None));
    }
    let own = match base {
        Some(b) if profile.wear().is_some() => Some(DiscSet::build_morphed(
            profile,
            &model.fem.params,
            &model.reducer,
            b,
            base_profile,
        )?),
        _ => None,
    };
    let disc = own.as_ref().or(base);
    let (dynamics, flexible) = rayon::join(
        || -> Result<Option<DynamicsSummary>> {
            if !model.dynamics.enabled {
                return Ok(None);
            }
            let r = simulate_discs(
                profile,
                &model.dynamics.params,
                &model.fem.params,
                disc,
                false,
            )?;
            tick();
            Ok(Some(r.summary))
        },
        || -> Result<Option<FlexibleStage>> {
            let (true, Some(disc)) = (model.fem.enabled, disc) else {
                return Ok(None);
            };
            let fl = analyse_stage(profile, &model.reducer, disc, model.rating.rated_torque)?;
            tick();
            Ok(Some(fl))
        },
    );
    let flexible = flexible?;
    let mesh = disc.map(|d| d.models[0].fe.mesh.clone());
    Ok((dynamics?, flexible.zip(mesh)))
}

/// Runs the study. `progress(done, total)` reports the work in steps (wear-rate evaluations,
/// then stages, then, when dynamics are on, one multibody simulation per stage, run in
/// parallel).
///
/// Stops at the working hours where the worn profile leaves the model's validity (see
/// [`crate::wear::integrate`]; also when a worn stage's analysis fails) and reports the stages
/// before it, with [`crate::wear::WearHistory::limit`] set.
///
/// # Errors
/// Solver failures on the unworn profile; interfering modifications; [`Error::Invalid`] naming
/// `wear.stage_hours` when no stage lies within the validity; the work budget.
pub fn run(model: &Model, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<Study> {
    run_with_notices(model, progress, &|_| {})
}

/// [`run`], telling `notice` (one line of text each) when the accuracy life's search goes on
/// beyond the last stage (a wear integration per step: it can take as long as the study).
///
/// # Errors
/// As [`run`].
pub fn run_with_notices(
    model: &Model,
    progress: &(dyn Fn(usize, usize) + Sync),
    notice: &dyn Fn(&str),
) -> Result<Study> {
    let w = &model.wear;
    let n_stages = w.stage_hours.len();
    let wear_total = parts::wear_steps(model);
    let dyn_total = if model.dynamics.enabled { n_stages } else { 0 };
    let fem_total = if model.fem.enabled { n_stages } else { 0 };
    let total = wear_total + n_stages + dyn_total + fem_total;
    // The unworn disc's FE models are built beside the wear integration (they need the
    // unworn profile only); every worn stage's are then the same meshes moved onto its
    // outline (one topology and symbolic factorisation for the study; results smooth in the
    // wear).
    let flexible_dynamics = model.dynamics.enabled && model.dynamics.params.flexible.is_some();
    let base_profile = model.profile()?;
    let ground = parts::ground(model)?;
    let (rates, new) = (ground.rates(), ground.new_play());
    // Progress: the wear-rate evaluations so far plus the stage analyses done.
    let (wear_done, done) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let report = || {
        progress(
            wear_done.load(Ordering::Relaxed) + done.load(Ordering::Relaxed),
            total,
        )
    };
    let tick = || {
        done.fetch_add(1, Ordering::Relaxed);
        report();
    };
    let failed = AtomicUsize::new(usize::MAX);
    // A first stage at 0 h needs no wear: it is analysed beside the wear integration, on the
    // unworn disc's FE models.
    let unworn_first = w.stage_hours.first() == Some(&0.0);
    let (wear, base) = rayon::join(
        || {
            parts::wear_history(model, &ground, &|d, _| {
                wear_done.fetch_max(d, Ordering::Relaxed);
                report();
            })
        },
        || -> Result<(Option<DiscSet>, Option<Outcome>)> {
            let base = if model.fem.enabled || flexible_dynamics {
                Some(DiscSet::build(
                    &base_profile,
                    &model.fem.params,
                    &model.reducer,
                )?)
            } else {
                None
            };
            let first = unworn_first.then(|| {
                run_stage(
                    model,
                    rates,
                    new,
                    0,
                    0.0,
                    &[],
                    &[],
                    base.as_ref(),
                    &base_profile,
                    &failed,
                    &tick,
                    &|_| {},
                )
            });
            Ok((base, first))
        },
    );
    let mut wear = wear?;
    let (base, first) = base?;
    // Per stage, in parallel, the most worn first (they take longest, so the cores finish
    // together): the static analysis, then the FE disc moved onto the worn outline (when the
    // flexible disc or flexible dynamics need it), and the multibody simulation and the
    // flexible analysis side by side. The stages are then taken in order: the first whose
    // static analysis fails on a worn profile is the validity limit, and the stages after it
    // are dropped (skipped once it is known).
    let n = wear.hours.len();
    let slots: Vec<std::sync::OnceLock<Outcome>> =
        (0..n).map(|_| std::sync::OnceLock::new()).collect();
    // The 0 h stage analysed beside the wear (the wear history then starts at 0 h unworn).
    if let Some(f) = first {
        if n > 0 && wear.hours[0] == 0.0 && wear.maps[0].iter().all(|w| *w == 0.0) {
            let _ = slots[0].set(f);
        }
    }
    let mut order: Vec<usize> = (0..n).filter(|&i| slots[i].get().is_none()).collect();
    order.sort_by(|&a, &b| wear.hours[b].total_cmp(&wear.hours[a]));
    let next = AtomicUsize::new(0);
    // The accuracy life's trials beyond the stages, taken up by the next worker free (before
    // any further stage) once the last stage's static analysis finds it within the spec: the
    // search beyond the stages then likely follows, and its wear integration runs beside the
    // other stages' analyses.
    let ahead: std::sync::Mutex<Option<LifeTrials>> = std::sync::Mutex::new(None);
    let ahead_start: std::sync::Mutex<Option<AccuracyPoint>> = std::sync::Mutex::new(None);
    let take_ahead = || {
        let start = ahead_start.lock().ok().and_then(|mut s| s.take());
        if let Some(start) = start {
            let trials = LifeTrials::ahead(model, &wear, start);
            if let Ok(mut slot) = ahead.lock() {
                *slot = trials;
            }
        }
    };
    rayon::scope(|s| {
        for _ in 0..rayon::current_num_threads().min(n) {
            s.spawn(|_| loop {
                take_ahead();
                let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
                    break;
                };
                let on_static = |summary: &StageSummary| {
                    let start = AccuracyPoint::of(summary);
                    let last = i + 1 == n && w.stage_hours.len() == n;
                    if last && model.life.any() && !crate::life::outside(&model.life, &start) {
                        if let Ok(mut slot) = ahead_start.lock() {
                            *slot = Some(start);
                        }
                    }
                };
                let _ = slots[i].set(run_stage(
                    model,
                    rates,
                    new,
                    i,
                    wear.hours[i],
                    &wear.maps[i],
                    &wear.pin_maps[i],
                    base.as_ref(),
                    &base_profile,
                    &failed,
                    &tick,
                    &on_static,
                ));
            });
        }
    });
    // A worker that finished its last stage before the trials were asked for.
    take_ahead();
    let outcomes = slots.into_iter().map(|slot| match slot.into_inner() {
        Some(Outcome::Done(b)) => Some(Ok(*b)),
        Some(Outcome::Failed(f)) => Some(Err(f)),
        Some(Outcome::Skipped) | None => None,
    });
    let mut stages = Vec::with_capacity(n_stages);
    let mut rows = Vec::with_capacity(n_stages);
    for (stage, rest) in until_limit(model, &mut wear, outcomes)? {
        rows.push(rest?);
        stages.push(stage);
    }
    for (st, (dynamics, flexible)) in stages.iter_mut().zip(rows) {
        if let Some(d) = dynamics {
            st.summary.dte_mean_arcmin = Some(d.te_mean_arcmin);
            st.summary.dte_peak_to_peak_arcmin = Some(d.te_peak_to_peak_arcmin);
            st.summary.dte_rms_arcmin = Some(d.te_rms_arcmin);
            st.summary.dte_range_arcmin = Some([d.te_min_arcmin, d.te_max_arcmin]);
            st.dynamics = Some(d);
        }
        if let Some((fl, mesh)) = flexible {
            let ste = CurveStats::of(&fl.flexible_ste);
            let loaded = CurveStats::of(&fl.flexible_loaded_te);
            let rigid = CurveStats::of(&fl.rigid_loaded_te);
            let s = &mut st.summary;
            s.flexible_ste_mean_arcmin = Some(arcmin(ste.mean));
            s.flexible_ste_peak_to_peak_arcmin = Some(arcmin(ste.peak_to_peak));
            s.flexible_loaded_te_mean_arcmin = Some(arcmin(loaded.mean));
            s.flexible_loaded_te_peak_to_peak_arcmin = Some(arcmin(loaded.peak_to_peak));
            s.rigid_loaded_te_revolution_mean_arcmin = Some(arcmin(rigid.mean));
            s.flexible_torsional_stiffness_nm_per_arcmin =
                Some(fl.torsional_stiffness / ARCMIN_PER_RAD);
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
            let gap = |a: &[f64], b: &[f64]| {
                let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
                arcmin(mean(&d))
            };
            s.flexible_ste_reverse_mean_arcmin = Some(arcmin(mean(&fl.flexible_ste_reverse)));
            s.flexible_loaded_te_reverse_mean_arcmin =
                Some(arcmin(mean(&fl.flexible_loaded_te_reverse)));
            s.flexible_backlash_arcmin = Some(gap(&fl.rigid_ste, &fl.rigid_ste_reverse));
            s.flexible_lost_motion_arcmin = Some(gap(&fl.flexible_ste, &fl.flexible_ste_reverse));
            s.max_von_mises_mpa = Some(fl.stress.max_von_mises * 1e-6);
            s.max_root_stress_mpa = Some(fl.stress.max_root_stress * 1e-6);
            st.flexible = Some((fl, mesh));
        }
    }
    let ahead = ahead.into_inner().ok().flatten();
    finish(model, wear, stages, ahead, notice)
}

impl Study {
    /// The study's verdict in one line ([`crate::life::verdict`]: the accuracy life and what
    /// limits it against its spec, or the hours within spec, with the duty), as the console and
    /// the report give it first.
    pub fn verdict(&self) -> String {
        crate::life::verdict(
            &self.model.life,
            self.life.as_ref(),
            self.stages
                .last()
                .map(|s| AccuracyPoint::of(&s.summary))
                .as_ref(),
            &self.model.load.levels,
        )
    }

    /// The `summary.json` content.
    pub fn summary(&self) -> Summary {
        let m = &self.model;
        let stages: Vec<StageSummary> = self.stages.iter().map(|s| s.summary.clone()).collect();
        let (sxy, sxx) = stages.iter().fold((0.0, 0.0), |(a, b), s| {
            (
                a + s.max_wear_um * s.ste_mean_arcmin,
                b + s.max_wear_um.powi(2),
            )
        });
        let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        Summary {
            rvlife_version: env!("CARGO_PKG_VERSION"),
            ratio: m.reducer.ratio,
            wear_model: m.wear.model,
            archard_coefficient_mm3_per_n_m: m.wear.archard * 1e9,
            rated_torque_nm: m.rating.rated_torque,
            loaded_te_torque_nm: m.te.loaded_torque,
            mesh_cycles_per_hour: m.reducer.mesh_cycles_per_hour(m.rating.input_speed_rpm),
            wear_rate_evaluations: self.wear.rate_evaluations(),
            validity_limit: self.wear.limit.clone(),
            accuracy_life: self.life.clone(),
            measured_profile_fit: m.cycloid.measured.as_ref().map(|x| {
                serde_json::json!({
                    "source": x.source.display().to_string(),
                    "points": x.points,
                    "fit_rms_um": x.fit_rms * 1e6,
                    "fit_max_um": x.fit_max * 1e6,
                })
            }),
            paper_comparison: is_papers_reducer(m).then(|| PaperComparison {
                ste_per_10um_arcmin: slope * 10.0,
                ste_last_stage_arcmin: stages.last().map_or(0.0, |s| s.ste_mean_arcmin),
                paper_ste_at_10um_arcmin: 0.5351,
                paper_ste_max_arcmin: 4.11,
                uniform_offset_per_10um_arcmin: 10e-6 / m.cycloid.geometry.disc_pitch_radius()
                    * m.reducer.twist_factor()
                    * ARCMIN_PER_RAD,
                paper_dte_at_10um_arcmin: 0.2278,
                paper_dte_max_arcmin: 3.51,
                paper_flexible_ste_at_10um_arcmin: 1.7342,
                paper_flexible_ste_max_arcmin: 6.77,
            }),
            stages,
        }
    }
}

/// [`crate::life::accuracy_life`] of a study of `model`: the stages' summaries, each trial
/// the study's own wear integration `wear` replayed to the trial hours
/// ([`WearHistory::replay`]: no wear rate is evaluated again) and the worn profile's accuracy
/// quantities ([`accuracy_point`]); beyond the last stage a wear
/// integration by the model's rule, each step announced by `notice` (one line of text: the
/// search can take as long as the study). `ahead`: the trials beyond the stages already made
/// from the last stage while the stages were analysed ([`LifeTrials::ahead`]), used when they
/// start from the same point.
///
/// # Errors
/// Wear integration and analysis failures.
pub(crate) fn study_life(
    model: &Model,
    stages: &[StageSummary],
    wear: &WearHistory,
    ahead: Option<LifeTrials>,
    notice: &dyn Fn(&str),
) -> Result<Option<crate::life::AccuracyLife>> {
    let points: Vec<AccuracyPoint> = stages.iter().map(AccuracyPoint::of).collect();
    let last = points.last().map_or(0.0, |p| p.hours);
    let beyond = |h: f64, max_h: f64| {
        notice(&format!(
            "within spec at the last stage ({last:.0} h): wear integrated on to {h:.0} h to find \
             the accuracy life (search horizon {max_h:.0} h, life.max_hours)"
        ))
    };
    let Some(&start) = points.last() else {
        return Ok(None);
    };
    let mut trials = match ahead {
        Some(t) if wear.limit.is_none() && t.start == start => t,
        _ => LifeTrials::new(model, wear, start)?,
    };
    crate::life::accuracy_life(&model.life, &points, |h| trials.at(model, h), &beyond)
}

/// The accuracy life's trials of a study ([`study_life`]): its wear integration, continued
/// as the trials go beyond its last stage, and the points evaluated so far.
pub(crate) struct LifeTrials {
    /// The last stage's point, where the trials beyond the stages start.
    start: AccuracyPoint,
    rates: BearingWearRates,
    history: WearHistory,
    seen: Vec<AccuracyPoint>,
}

impl LifeTrials {
    /// No trials yet, on the study's wear integration `wear` whose last stage's point is
    /// `start`.
    ///
    /// # Errors
    /// Those of [`crate::config::bearing_rates`].
    fn new(model: &Model, wear: &WearHistory, start: AccuracyPoint) -> Result<Self> {
        Ok(LifeTrials {
            start,
            rates: crate::config::bearing_rates(model)?,
            history: wear.clone(),
            seen: Vec::new(),
        })
    }

    /// The trials beyond the stages ([`crate::life::beyond_stages`]) from the last stage's
    /// point `start`, made while the other stages are analysed when that point lies within
    /// the spec (the search beyond the stages then likely follows; the study waits for them).
    /// Their failures are left to the search itself, which meets them again.
    pub(crate) fn ahead(model: &Model, wear: &WearHistory, start: AccuracyPoint) -> Option<Self> {
        let mut trials = LifeTrials::new(model, wear, start).ok()?;
        crate::life::beyond_stages(&model.life, start, &mut |h| trials.at(model, h), &|_, _| {});
        Some(trials)
    }

    /// The accuracy point after `h` working hours: one evaluated before, or the wear replayed
    /// to `h` from the integration, continued beyond its last stage when `h` lies beyond it.
    ///
    /// # Errors
    /// Wear integration (the validity limit met on the way included) and analysis failures.
    fn at(&mut self, model: &Model, h: f64) -> Result<AccuracyPoint> {
        if let Some(p) = self.seen.iter().find(|p| p.hours == h) {
            return Ok(*p);
        }
        let rates = self.rates;
        let base = WearInputs {
            bearing_rates: rates,
            ..model.wear_inputs()
        };
        let (map, pins) = match self.history.replay(&base, h)? {
            Some(state) => state,
            None => {
                // Beyond the hours integrated so far: the integration continued there,
                // and the trials between replayed from it.
                let next = if self.history.limit.is_none() && h > 0.0 {
                    self.history.continued(&base, h)?
                } else {
                    let mut w = model.wear.clone();
                    w.stage_hours = vec![h];
                    integrate(&WearInputs { wear: &w, ..base }, &|_, _| {})?
                };
                if let Some(l) = &next.limit {
                    return Err(crate::error::Error::numerical(
                        "accuracy life",
                        l.reason.clone(),
                    ));
                }
                let state = (
                    next.maps.last().cloned().unwrap_or_default(),
                    next.pin_maps.last().cloned().unwrap_or_default(),
                );
                self.history = next;
                state
            }
        };
        let max = map.iter().copied().fold(0.0, f64::max);
        let wear = match model.wear.model {
            _ if max <= 0.0 => None,
            WearModelKind::Paper => Some(WearMap::uniform(map.len(), max)?),
            WearModelKind::Flodin => Some(WearMap::new(map.clone())?),
        };
        let profile = model.cycloid.profile(wear)?;
        let p = accuracy_point(
            &crate::config::worn_parts(model, rates, h, &pins),
            &profile,
            h,
        )?;
        self.seen.push(p);
        Ok(p)
    }
}
