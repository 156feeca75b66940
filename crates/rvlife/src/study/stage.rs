//! One stage of the study: its worn profile's static analysis (static TE, the hysteresis curve
//! and its catalogue quantities, the loaded TE), the no-load play it is split against, and the
//! accuracy point of the life search's trials.

use crate::config::Model;
use crate::dynamics::DynamicsSummary;
use crate::error::{Error, Result};
use crate::fem::flex::FlexibleStage;
use crate::fem::mesh::Mesh;
use crate::geometry::{Profile, WearMap};
use crate::quantities::{AccuracyPoint, StageSummary, ACCURACY, ANGULAR_TE, STAGE};
use crate::statics::StaticAnalysis;
use crate::te::{
    angular_te_of, hysteresis_and_rated, hysteresis_with_from, loaded_te_with, mesh_cycle_angles,
    revolution, revolution_no_load, static_te_with, torque_fractions, CrankStart, CurveStats,
    LoadedTe, RevolutionTe, StaticTe, TwistTable, HYSTERESIS_LEVELS, PLAY_ROUND_OFF,
};
use crate::units::ARCMIN_PER_RAD;
use crate::wear::BearingWearRates;

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

/// Radians to arcminutes, with values below 1e-6 arcmin reported as zero rather than as a
/// signed `-0.0000` or a `3.87e-8`: 1.5e-11 m at the example's pitch radius, the resolution of
/// the contact geometry (its gap field is interpolated to about 1e-11 m; the first contact is
/// solved to 1e-14 m of gap), and a thousandth of the twist a 0.01 um modification gives.
pub(super) fn arcmin(rad: f64) -> f64 {
    let v = rad * ARCMIN_PER_RAD;
    if v.abs() < 1e-6 {
        0.0
    } else {
        v
    }
}

/// Fails loudly, naming the quantity, if a stage summary holds a NaN or an infinity (JSON has
/// neither: they would be written as `null`, and as `NaN`/`inf` in CSV).
pub(super) fn check_finite(summary: &StageSummary) -> Result<()> {
    match STAGE.iter().find(|q| !summary.value(q).is_finite()) {
        Some(q) => Err(Error::numerical(
            "stage summary",
            format!("{} is not a finite number at {} h", q.name, summary.hours),
        )),
        None => Ok(()),
    }
}

/// The static analysis of `model`'s reducer with `profile`, the mesh cycle's crank angles
/// (`te.samples`) and the hysteresis over them at the rated torque with the equilibria at
/// `+rated` ([`hysteresis_and_rated`]): what [`analyse_profile`] and the accuracy life's
/// trials share.
///
/// # Errors
/// Solver failures.
#[allow(clippy::type_complexity)]
pub(super) fn stage_hysteresis<'a>(
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
    // The losses and efficiency at the rated torque and speed, on the hysteresis' top level.
    let efficiency = model
        .lubrication
        .enabled
        .then(|| stage_efficiency(model, &sa, profile, &rated))
        .transpose()?;
    let friction_torque = mean
        .friction
        .as_ref()
        .and_then(|f| f.positive.last().copied());
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
            (angular_te, play_max)
        }
    };
    let play_max = crate::te::largest_play(play_max, acc.backlash);
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
        friction_torque_nm: friction_torque,
        efficiency: efficiency.map(|e| e.efficiency),
        loss_disc_pins_w: efficiency.map(|e| e.loss_disc_pins_w),
        loss_pin_grooves_w: efficiency.map(|e| e.loss_pin_grooves_w),
        loss_crank_bearings_w: efficiency.map(|e| e.loss_crank_bearings_w),
        loss_gear_meshes_w: efficiency.map(|e| e.loss_gear_meshes_w),
        lambda_mean: efficiency.map(|e| e.lambda_mean),
        oil_temperature_c: efficiency.map(|e| e.temperature_c),
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

/// The power balance of `profile` at the rated torque and the rated input speed
/// ([`crate::efficiency::balanced_point`]) on the equilibria `rated` at the rated torque over
/// the mesh cycle.
fn stage_efficiency(
    model: &Model,
    sa: &StaticAnalysis,
    profile: &Profile,
    rated: &[crate::statics::StaticSolution],
) -> Result<crate::efficiency::OperatingPoint> {
    let loads = crate::efficiency::MeshCycleLoads {
        torque: model.rating.rated_torque,
        solutions: rated.to_vec(),
        bearing_forces: rated.iter().map(|s| sa.bearing_forces(s)).collect(),
    };
    crate::efficiency::balanced_point(
        sa,
        profile,
        &model.lubrication,
        &model.wear,
        &loads,
        model.rating.input_speed_rpm / model.reducer.ratio.abs(),
    )
}

/// The accuracy-spec quantities of one profile only ([`AccuracyPoint`]: backlash, lost motion
/// and stiffness from the hysteresis curve averaged over a mesh cycle, the angular TE from its
/// zero-torque row or, with part errors, over an output revolution), as
/// [`analyse_profile`] finds them, without the loaded TE: the accuracy life's trials.
///
/// A trial reads the curve at the three torques the quantities are defined at (zero, the
/// measuring and the rated torque: [`hysteresis_with_from`] with one level), not on the
/// stage's plotted grid: each loaded twist is the equilibrium at its torque whatever the
/// levels solved before it, so the quantities are the stage analysis's to the solver's
/// tolerance. Each crank angle's search starts from its entry of `warm` (the same crank angle
/// at the trial before, which the search then holds for the next: the contact problems from
/// that trial's configurations, the first loaded levels from its solutions; empty: as cold),
/// as a sampled reducer's stages do; the same equilibria to the solvers' tolerances. With part
/// errors and no angular TE in `[life]`, the revolution is not solved and the point's angular
/// TE is NaN: a trial's point never leaves the life search, which reads only the quantities the
/// spec bounds ([`crate::life::margins`]).
///
/// # Errors
/// Solver failures; a quantity the spec needs that is not finite.
pub(super) fn accuracy_point(
    model: &Model,
    profile: &Profile,
    hours: f64,
    warm: &mut Vec<CrankStart>,
) -> Result<AccuracyPoint> {
    let red = &model.reducer;
    let sa = StaticAnalysis::new(red, profile)?;
    let phis = mesh_cycle_angles(red.geometry.pins, model.te.samples);
    let (tables, mean) = hysteresis_with_from(
        &sa,
        &phis,
        model.rating.rated_torque,
        model.te.measuring_torque_fraction,
        1,
        warm,
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
pub(super) fn no_load(model: &Model, profile: &Profile) -> Result<NoLoad> {
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

/// Why a stage of a study has no static results.
#[derive(Debug)]
pub(super) enum Failure {
    /// Its wear map could not be made: an error of the study.
    Prepare(Error),
    /// Its static analysis failed (with the stage's largest wear depth, m).
    Static(Error, f64),
}

/// The unworn disc's play on the parts of one stage (docs/model.md section 6.5), against
/// which [`split_play`] splits the stage's play: on the stage's bearings, then on its bearings
/// and pins. `None` where those parts have not worn by then: `bearings` the new reducer's,
/// `parts` the same as `bearings`.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(super) struct UnwornPlay {
    bearings: Option<NoLoad>,
    parts: Option<NoLoad>,
}

impl UnwornPlay {
    /// [`split_play`] of `s` against the new reducer's play `new` and these.
    pub(super) fn split(self, s: &mut StageSummary, new: NoLoad) {
        let bearings = self.bearings.unwrap_or(new);
        split_play(s, new, bearings, self.parts.unwrap_or(bearings));
    }
}

/// The static part of the stage at `hours` with the wear depth `map` (m per grid point; empty
/// or zero: unworn) and the pins' wear `pin_map` (m round the pin; empty or zero: unworn):
/// the worn profile, its static analysis on the parts as worn by then (the crank bearings'
/// clearance grown by `rates`, the pins by `pin_map`), and the unworn disc's play on those
/// parts, against which its play is split once the new reducer's is known
/// ([`UnwornPlay::split`]; the summary's split fields are zero until then). Also returns the
/// model with the worn parts. The stage has no dynamics or flexible results yet.
pub(super) fn static_part<'a>(
    model: &'a Model,
    rates: BearingWearRates,
    hours: f64,
    map: &[f64],
    pin_map: &[f64],
    base_profile: &Profile,
) -> std::result::Result<(Stage, std::borrow::Cow<'a, Model>, UnwornPlay), Failure> {
    // The crank bearings as worn by this stage's hours (their rates are constant in time),
    // and the pins as worn by then.
    let base_model = model;
    let worn = crate::wear::WornState::new(model.wear.model, rates, hours, map, pin_map)
        .map_err(Failure::Prepare)?;
    let staged = model.worn(&worn);
    let model: &Model = &staged;
    let max = map.iter().copied().fold(0.0, f64::max);
    let (profile, a) = model
        .cycloid
        .profile(worn.disc_profile.clone())
        .and_then(|p| analyse_profile(model, &p, hours).map(|a| (p, a)))
        .map_err(|e| Failure::Static(e, max))?;
    // The unworn disc's play on this stage's bearings, then on its bearings and pins (the new
    // reducer's unless they wear).
    let unworn = || -> Result<UnwornPlay> {
        if std::ptr::eq(model, base_model) {
            return Ok(UnwornPlay {
                bearings: None,
                parts: None,
            });
        }
        let bearings_only = base_model.worn(&worn.bearings_only());
        let bearings = if std::ptr::eq(&*bearings_only, base_model) {
            None
        } else {
            Some(no_load(&bearings_only, base_profile)?)
        };
        let parts = if model.reducer.pin_wear.is_zero() {
            None
        } else {
            Some(no_load(model, base_profile)?)
        };
        Ok(UnwornPlay { bearings, parts })
    };
    let play = unworn().map_err(|e| Failure::Static(e, max))?;
    let stage = Stage {
        hours,
        wear: worn.disc.clone(),
        profile,
        ste: a.ste,
        loaded: a.loaded,
        hysteresis: a.hysteresis,
        revolution: a.revolution,
        summary: a.summary,
        dynamics: None,
        flexible: None,
    };
    Ok((stage, staged, play))
}
