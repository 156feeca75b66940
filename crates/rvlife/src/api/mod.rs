//! The commands of rvlife as library calls: each takes a validated [`Model`] and the command's
//! arguments and returns a typed, serialisable result (`results`), which the command line
//! prints with `--json` (its JSON object, keys sorted) and the Python package returns as the
//! same object. Arguments are checked here, and an error names the argument as the caller
//! spells it ([`Spelling`]: `--crank-deg` on the command line, `crank_deg` in Python).

pub mod commands;
mod efficiency;
mod results;

pub use efficiency::{efficiency, EfficiencyResult, DEFAULT_SPEEDS_RPM, DEFAULT_TORQUE_FRACTIONS};

pub use results::{
    quantity_table, ContactDisc, ContactPin, ContactResult, HysteresisResult, LoadedTeResult,
    ProfilePoints, QuantityDoc, TeResult, TwistCurve, TwistShareResult,
};

use crate::config::Model;
use crate::error::{Error, Result};
use crate::geometry::{Profile, WearMap};
use crate::statics::{twist_shares, StaticAnalysis};
use crate::te::{
    hysteresis, hysteresis_with, loaded_te_with, mesh_cycle_angles, over_revolution, CurveStats,
    StaticTe, TwistTable,
};
use crate::units::ARCMIN_PER_RAD;

/// How a caller writes argument names in error messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spelling {
    /// Command-line options: `crank_deg` is `--crank-deg`.
    Cli,
    /// Keyword arguments: `crank_deg` as is.
    Python,
}

impl Spelling {
    /// The argument `key` (snake case) as this caller writes it.
    pub fn name(self, key: &str) -> String {
        match self {
            Spelling::Cli => format!("--{}", key.replace('_', "-")),
            Spelling::Python => key.to_string(),
        }
    }
}

/// Which worn profile a command analyses: at most one of a uniform depth (um) and working
/// hours (h) of the config's wear model; neither is the unworn profile.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Wear {
    /// Uniform wear depth along the whole profile, um.
    pub wear_um: Option<f64>,
    /// Working hours of the config's wear model, h.
    pub hours: Option<f64>,
}

/// A finite-number check naming the argument.
fn finite(spelling: Spelling, key: &str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Error::invalid(
            spelling.name(key),
            v,
            "must be a finite number",
        ))
    }
}

/// The validated model of `cfg` ([`crate::config::Config::validate`]) whose study fits the
/// work budget (`crate::study::check_work`): what every command runs on.
///
/// # Errors
/// [`Error::Invalid`] naming the key, the value and the allowed range, or the key that drives
/// the work beyond the budget (a key the file does not set named as a default).
pub fn validated(cfg: &crate::config::Config) -> Result<Model> {
    crate::study::validated(cfg)
}

/// `"bearings"` or `"rigid"`: how the model supports the discs.
pub(crate) fn support_name(model: &Model) -> &'static str {
    match model.reducer.support {
        crate::reducer::Support::Bearings => "bearings",
        crate::reducer::Support::Rigid { .. } => "rigid",
    }
}

/// The profile of a command: nominal (`nominal`: no modification, no measured profile), worn
/// uniformly by `wear.wear_um` (um, the paper's conservative model), or by the config's wear
/// model after `wear.hours` (h; `progress(done, total)` reports the wear integration), or the
/// config's unworn profile.
///
/// # Errors
/// [`Error::Invalid`] naming the argument as `spelling` writes it (a negative or non-finite
/// depth, both a depth and hours, a depth that folds the flank, hours out of `[0, 1e7]`, too many profile updates, or
/// hours beyond the wear model's validity); the wear integration's failures.
pub fn profile_for(
    model: &Model,
    wear: Wear,
    nominal: bool,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Profile> {
    worn_for(model, wear, nominal, spelling, progress).map(|w| w.1)
}

/// The reducer and profile of a command at `wear` ([`profile_for`]'s profile): after
/// `wear.hours` the model has its crank bearings worn when
/// `wear.bearing_archard_coefficient_mm3_per_n_m` is set (docs/model.md section 7.9) and its
/// pins worn when `wear.pin_archard_coefficient_mm3_per_n_m` is (section 7.11); otherwise it is
/// `model` itself.
///
/// # Errors
/// As [`profile_for`]; those of the bearings' wear rates (a static analysis of the new
/// reducer).
pub fn worn_for<'a>(
    model: &'a Model,
    wear: Wear,
    nominal: bool,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(std::borrow::Cow<'a, Model>, Profile)> {
    let base = model;
    let mut model = model.clone();
    if nominal {
        model.cycloid = model.cycloid.nominal();
    }
    let n = model.wear_inputs().grid_points();
    if let (Some(w), Some(_)) = (wear.wear_um, wear.hours) {
        return Err(Error::invalid(
            spelling.name("wear_um"),
            w,
            format!(
                "give either {} or {}, not both",
                spelling.name("wear_um"),
                spelling.name("hours")
            ),
        ));
    }
    let map = match (wear.wear_um, wear.hours) {
        (Some(w), _) => {
            if !w.is_finite() || w < 0.0 {
                return Err(Error::invalid(
                    spelling.name("wear_um"),
                    w,
                    "must be a finite number >= 0",
                ));
            }
            // A worn profile must stay a profile: a wear deeper than the local convex radius
            // of the flank folds it over itself (the profile's error, named by the argument).
            return (w > 0.0)
                .then(|| WearMap::uniform(n, w * 1e-6))
                .transpose()
                .and_then(|m| model.cycloid.profile(m))
                .map(|p| (std::borrow::Cow::Borrowed(base), p))
                .map_err(|e| match e {
                    Error::Invalid { allowed, .. } => {
                        Error::invalid(spelling.name("wear_um"), w, allowed)
                    }
                    other => other,
                });
        }
        (None, Some(h)) => {
            if !(h.is_finite() && (0.0..=1e7).contains(&h)) {
                return Err(Error::invalid(
                    spelling.name("hours"),
                    h,
                    "must be a finite number in [0, 1e7] h",
                ));
            }
            if model.wear.update_hours > 0.0 && h / model.wear.update_hours > 100_000.0 {
                return Err(Error::invalid(
                    spelling.name("hours"),
                    h,
                    format!(
                        "would need more than 100000 profile updates of \
                         wear.profile_update_hours = {} h",
                        model.wear.update_hours
                    ),
                ));
            }
            let mut w = model.wear.clone();
            w.stage_hours = vec![h];
            let rates = crate::config::bearing_rates(&model)?;
            let inputs = crate::wear::WearInputs {
                wear: &w,
                bearing_rates: rates,
                ..model.wear_inputs()
            };
            if let Some((depth, rate)) = crate::wear::far_beyond_validity(&inputs, h)? {
                return Err(Error::invalid(
                    spelling.name("hours"),
                    h,
                    format!(
                        "is far beyond the validity of the wear model: at the unworn disc's \
                         mean wear rate, {:.3e} um/h, the flank would lose {:.0} um by then, \
                         {:.1} times the eccentricity {:.0} um where the model ends (half the \
                         teeth's height); give fewer hours",
                        rate * 1e6,
                        depth * 1e6,
                        depth / model.cycloid.geometry.eccentricity,
                        model.cycloid.geometry.eccentricity * 1e6
                    ),
                ));
            }
            // The config's own stages passed the work budget when it was validated: work
            // beyond it now is the hours asked for.
            let hist = crate::wear::integrate(&inputs, progress).map_err(|e| match e {
                Error::Invalid { allowed, .. } if allowed.contains("work budget") => {
                    Error::invalid(
                        spelling.name("hours"),
                        h,
                        format!("is more wear than the work budget allows: {allowed}"),
                    )
                }
                other => other,
            })?;
            if let Some(l) = &hist.limit {
                return Err(Error::invalid(
                    spelling.name("hours"),
                    h,
                    format!(
                        "is beyond the validity of the wear model, which it leaves at {:.0} h \
                         with {:.2} um of wear: {}; give fewer hours",
                        l.hours, l.max_wear_um, l.reason
                    ),
                ));
            }
            let worn = crate::wear::WornState::new(
                model.wear.model,
                rates,
                h,
                hist.maps.first().map_or(&[][..], |m| &m[..]),
                hist.pin_maps.first().map_or(&[][..], |m| &m[..]),
            )?;
            let profile = model.cycloid.profile(worn.disc_profile.clone())?;
            return Ok((base.worn(&worn), profile));
        }
        (None, None) => None,
    };
    Ok((
        std::borrow::Cow::Borrowed(base),
        model.cycloid.profile(map)?,
    ))
}

/// Static equilibrium of the reducer at crank angle `crank_deg` (deg) under output torque
/// `torque_nm` (N m), input locked (`rvlife contact --json`): twist, first-contact twist,
/// largest force and pressure, stiffness, residual, and per disc its translation, rotation and
/// pins (mesh angle, gap, force, lever arm, Hertz half-width and pressure).
///
/// `progress(done, total)` reports the wear integration of `wear.hours`.
///
/// # Errors
/// [`Error::Invalid`] for a non-finite argument or a torque the unworn stage cannot carry;
/// solver failures.
pub fn contact(
    model: &Model,
    wear: Wear,
    crank_deg: f64,
    torque_nm: f64,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<ContactResult> {
    finite(spelling, "crank_deg", crank_deg)?;
    finite(spelling, "torque_nm", torque_nm)?;
    model.check_torque(&spelling.name("torque_nm"), torque_nm)?;
    let (staged, profile) = worn_for(model, wear, false, spelling, progress)?;
    let model: &Model = &staged;
    let sa = StaticAnalysis::new(&model.reducer, &profile)?;
    let sol = sa.solve(crank_deg.to_radians(), torque_nm)?;
    let discs = sol
        .discs
        .iter()
        .map(|d| ContactDisc {
            translation_um: [d.translation.x * 1e6, d.translation.y * 1e6],
            rotation_arcmin: d.rotation * ARCMIN_PER_RAD,
            pin_moment_nm: d.torque,
            max_force_n: d.max_force(),
            pins_in_contact: d.pins_in_contact(),
            pin_forces_n: d.pins.iter().map(|p| p.force).collect(),
            pins: d
                .pins
                .iter()
                .map(|p| ContactPin {
                    pin: p.pin,
                    mesh_angle_deg: p.mesh_angle.to_degrees(),
                    gap_um: p.gap * 1e6,
                    force_n: p.force,
                    lever_arm_mm: p.lever_arm * 1e3,
                    half_width_um: p.half_width * 1e6,
                    max_pressure_mpa: p.max_pressure * 1e-6,
                })
                .collect(),
        })
        .collect();
    Ok(ContactResult {
        crank_deg,
        torque_nm,
        support: support_name(model),
        twist_arcmin: sol.twist * ARCMIN_PER_RAD,
        first_contact_arcmin: sol.first_contact_twist * ARCMIN_PER_RAD,
        max_force_n: sol.max_force(),
        pins_in_contact: sol.pins_in_contact(),
        max_pressure_mpa: sol.max_pressure() * 1e-6,
        torsional_stiffness_nm_per_arcmin: sol.stiffness / ARCMIN_PER_RAD,
        residual: sol.residual,
        residual_roundoff_floor: sol.roundoff_floor,
        max_wear_um: profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6,
        discs,
    })
}

/// STE over a mesh cycle and an output revolution, backlash, lost motion and torsional
/// stiffness (`rvlife te --json`), with the loaded TE at `torque_nm` (N m) when given.
/// Arrays: `input_deg` and `te_arcmin` over the output revolution, `loaded_te_arcmin` likewise.
///
/// # Errors
/// [`Error::Invalid`] for a non-finite torque or one the unworn stage cannot carry; solver
/// failures.
pub fn te(
    model: &Model,
    wear: Wear,
    torque_nm: Option<f64>,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<TeResult> {
    if let Some(t) = torque_nm {
        finite(spelling, "torque_nm", t)?;
        model.check_torque(&spelling.name("torque_nm"), t)?;
    }
    let (staged, profile) = worn_for(model, wear, false, spelling, progress)?;
    let model: &Model = &staged;
    let red = &model.reducer;
    let phis = mesh_cycle_angles(red.geometry.pins, model.te.samples);
    let sa = StaticAnalysis::new(red, &profile)?;
    let curves = hysteresis_with(
        &sa,
        &phis,
        model.rating.rated_torque,
        model.te.measuring_torque_fraction,
        1,
    );
    let (tables, mean) = curves?;
    let ste = StaticTe {
        crank_angle: phis,
        forward: tables.iter().map(|t| t.positive[0]).collect(),
        reverse: tables.iter().map(|t| -t.negative[0]).collect(),
    };
    let st = ste.stats();
    let play = ste.backlash_stats();
    let acc = mean.accuracy();
    // Over the output revolution: the mesh cycle tiled, or with part errors every mesh
    // cycle of the revolution.
    let rev = crate::te::revolution(&sa, model.te.samples)?;
    let (angular_te, rev_play_max) =
        crate::te::revolution_no_load(&sa, &rev, model.te.samples, model.rating.rated_torque)?;
    let input_deg: Vec<f64> = rev
        .crank_angle
        .iter()
        .map(|p| crate::te::input_deg(*p, model.cycloid.geometry.pins, model.reducer.ratio))
        .collect();
    let te_arcmin: Vec<f64> = rev.forward.iter().map(|v| v * ARCMIN_PER_RAD).collect();
    let play_max = crate::te::largest_play(
        if red.errors.is_zero() {
            play.max
        } else {
            rev_play_max
        },
        acc.backlash,
    );
    let loaded = match torque_nm {
        Some(t) => {
            let l = loaded_te_with(&sa, t, model.te.samples)?;
            let ls = l.stats();
            let (_, lte) = over_revolution(
                &l.crank_angle,
                &l.te,
                model.cycloid.geometry.pins,
                model.reducer.ratio,
            );
            Some(LoadedTeResult {
                torque_nm: t,
                loaded_te_mean_arcmin: ls.mean * ARCMIN_PER_RAD,
                loaded_te_peak_to_peak_arcmin: ls.peak_to_peak * ARCMIN_PER_RAD,
                max_force_n: l.max_force(),
                pins_in_contact: l.pins_in_contact().0,
                loaded_te_arcmin: lte.iter().map(|x| x * ARCMIN_PER_RAD).collect(),
            })
        }
        None => None,
    };
    Ok(TeResult {
        max_wear_um: model.cycloid.wear_depth(&profile) * 1e6,
        angular_te_arcmin: angular_te * ARCMIN_PER_RAD,
        support: support_name(model),
        te_mean_arcmin: st.mean * ARCMIN_PER_RAD,
        te_peak_to_peak_arcmin: st.peak_to_peak * ARCMIN_PER_RAD,
        te_reverse_mean_arcmin: CurveStats::of(&ste.reverse).mean * ARCMIN_PER_RAD,
        backlash_arcmin: acc.backlash * ARCMIN_PER_RAD,
        backlash_max_arcmin: play_max * ARCMIN_PER_RAD,
        lost_motion_arcmin: acc.lost_motion * ARCMIN_PER_RAD,
        measuring_torque_nm: model.te.measuring_torque_fraction * model.rating.rated_torque,
        torsional_stiffness_nm_per_arcmin: acc.torsional_stiffness / ARCMIN_PER_RAD,
        samples_per_mesh_cycle: model.te.samples,
        loaded,
        input_deg,
        te_arcmin,
    })
}

/// The hysteresis curve (output torque 0 -> +rated -> -rated -> +rated in `levels` steps per
/// quarter, input locked) averaged over a mesh cycle and at crank angle `crank_deg` (deg), with
/// backlash, lost motion, hysteresis loss and torsional stiffness (`rvlife hysteresis --json`).
///
/// # Errors
/// [`Error::Invalid`] for a non-finite crank angle or `levels` outside 1-1000; solver failures.
pub fn hysteresis_curve(
    model: &Model,
    wear: Wear,
    crank_deg: f64,
    levels: usize,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<HysteresisResult> {
    hysteresis_curve_and_table(model, wear, crank_deg, levels, spelling, progress).map(|(r, _)| r)
}

/// [`hysteresis_curve`] with the twist table averaged over the mesh cycle that its mean curve
/// and catalogue quantities come from (rad; [`TwistTable::catalogue_points`] gives the points
/// they are read between).
///
/// # Errors
/// As [`hysteresis_curve`].
pub fn hysteresis_curve_and_table(
    model: &Model,
    wear: Wear,
    crank_deg: f64,
    levels: usize,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(HysteresisResult, TwistTable)> {
    finite(spelling, "crank_deg", crank_deg)?;
    if !(1..=1000).contains(&levels) {
        return Err(Error::invalid(
            spelling.name("levels"),
            levels,
            "must be a whole number from 1 to 1000",
        ));
    }
    let (staged, profile) = worn_for(model, wear, false, spelling, progress)?;
    let model: &Model = &staged;
    let red = &model.reducer;
    let mut phis = mesh_cycle_angles(red.geometry.pins, model.te.samples);
    phis.push(crank_deg.to_radians());
    let curves = hysteresis(
        red,
        &profile,
        &phis,
        model.rating.rated_torque,
        model.te.measuring_torque_fraction,
        levels,
    );
    let (mut tables, _) = curves?;
    let at_crank = tables.pop().expect("the crank angle's table");
    phis.pop();
    let rated = model.rating.rated_torque;
    let twist_shares = twist_shares(red, &profile, &phis, rated)?
        .into_iter()
        .map(|s| TwistShareResult {
            part: s.part,
            share: s.share,
            twist_arcmin: s.twist * ARCMIN_PER_RAD,
        })
        .collect();
    // The mean over the mesh cycle only (not the extra crank angle).
    let mean_table = TwistTable::mean_of(&tables);
    let mean = describe_twist(&mean_table);
    let result = HysteresisResult {
        max_wear_um: profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6,
        support: support_name(model),
        rated_torque_nm: model.rating.rated_torque,
        measuring_torque_fraction: model.te.measuring_torque_fraction,
        torsional_stiffness_definition: "b/a: (rated - measuring torque) over the mean twist of \
                                         the two loading branches between them",
        crank_deg,
        at_crank_angle: describe_twist(&at_crank),
        samples_per_mesh_cycle: model.te.samples,
        torque_nm: mean.torque_nm.clone(),
        twist_arcmin: mean.twist_arcmin.clone(),
        backlash_arcmin: mean.backlash_arcmin,
        lost_motion_arcmin: mean.lost_motion_arcmin,
        hysteresis_loss_arcmin: mean.hysteresis_loss_arcmin,
        torsional_stiffness_nm_per_arcmin: mean.torsional_stiffness_nm_per_arcmin,
        mesh_cycle_mean: mean,
        twist_shares,
    };
    Ok((result, mean_table))
}

/// A hysteresis curve and its catalogue quantities (torque N m, twist and the accuracy
/// quantities arcmin, stiffness N m/arcmin).
fn describe_twist(t: &TwistTable) -> TwistCurve {
    let a = t.accuracy();
    let c = t.curve();
    TwistCurve {
        torque_nm: c.torque,
        twist_arcmin: c.twist.iter().map(|x| x * ARCMIN_PER_RAD).collect(),
        backlash_arcmin: a.backlash * ARCMIN_PER_RAD,
        lost_motion_arcmin: a.lost_motion * ARCMIN_PER_RAD,
        hysteresis_loss_arcmin: a.hysteresis_loss * ARCMIN_PER_RAD,
        torsional_stiffness_nm_per_arcmin: a.torsional_stiffness / ARCMIN_PER_RAD,
    }
}

/// The profile's points (`rvlife profile` writes them as CSV): `x_mm`, `y_mm`,
/// `mesh_angle_deg`, `wear_um`, each `Zc per_tooth` long, and `points_per_tooth`.
/// `per_tooth` 0 takes the export's default ([`crate::output::export::points_per_tooth`]).
///
/// # Errors
/// As [`profile_for`]; [`Error::Invalid`] for `per_tooth` above 100000.
pub fn profile_points(
    model: &Model,
    wear: Wear,
    nominal: bool,
    per_tooth: usize,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<ProfilePoints> {
    if per_tooth > 100_000 {
        return Err(Error::invalid(
            spelling.name("points_per_tooth"),
            per_tooth,
            "must be 0 (the export's default) to 100000",
        ));
    }
    let profile = profile_for(model, wear, nominal, spelling, progress)?;
    let n = if per_tooth == 0 {
        crate::output::export::points_per_tooth(&profile)
    } else {
        per_tooth
    };
    let pts = crate::output::export::profile_points(&profile, n);
    let col = |f: fn(&(f64, f64, f64, f64)) -> f64| pts.iter().map(f).collect::<Vec<f64>>();
    Ok(ProfilePoints {
        points_per_tooth: n,
        max_wear_um: profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6,
        x_mm: col(|p| p.0),
        y_mm: col(|p| p.1),
        mesh_angle_deg: col(|p| p.2),
        wear_um: col(|p| p.3),
    })
}

/// Overrides of `rvlife dynamics` on the config: the dynamic model is checked as enabled,
/// and `load` (`[dynamics.load] kind`), `torque_nm` (a constant load's torque, N m) and `disc`
/// (`"rigid"` or `"flexible"`) replace the config's values when given.
#[derive(Debug, Clone, Default)]
pub struct DynamicsOptions {
    /// Load kind: `none`, `constant`, `sinusoidal` or `table`.
    pub load: Option<String>,
    /// Constant output torque, N m (only with a constant load).
    pub torque_nm: Option<f64>,
    /// Disc model: `rigid` or `flexible`.
    pub disc: Option<String>,
}

/// The validated model of `cfg` for a dynamic simulation with the overrides `opts`.
///
/// # Errors
/// [`Error::Invalid`] as [`crate::config::Config::validate`], naming `torque_nm` as `spelling`
/// writes it when the torque override is what is out of range.
pub fn dynamics_model(
    cfg: &crate::config::Config,
    opts: &DynamicsOptions,
    spelling: Spelling,
) -> Result<Model> {
    let mut cfg = cfg.clone();
    // The dynamic model is checked (and its load) as if enabled.
    cfg.dynamics.enabled = true;
    if let Some(d) = &opts.disc {
        cfg.dynamics.disc = d.clone();
    }
    if let Some(kind) = &opts.load {
        cfg.dynamics.load.kind = kind.clone();
    }
    if let Some(t) = opts.torque_nm {
        if cfg.dynamics.load.kind != "constant" {
            return Err(Error::invalid(
                spelling.name("torque_nm"),
                t,
                format!(
                    "applies only to a constant load ({})",
                    match spelling {
                        Spelling::Cli => "--load constant",
                        Spelling::Python => "load=\"constant\"",
                    }
                ),
            ));
        }
        cfg.dynamics.load.torque_nm = Some(t);
    }
    validated(&cfg).map_err(|e| match e {
        Error::Invalid {
            field,
            value,
            allowed,
        } if opts.torque_nm.is_some() && field.starts_with("dynamics.load.torque_nm") => {
            Error::Invalid {
                field: spelling.name("torque_nm"),
                value,
                allowed,
            }
        }
        Error::Invalid {
            field,
            value,
            allowed,
        } if opts.disc.is_some() && field.starts_with("dynamics.disc") => Error::Invalid {
            field: spelling.name("disc"),
            value,
            allowed,
        },
        other => other,
    })
}

/// The multibody simulation of `rvlife dynamics` on the profile `wear` selects (its summary is
/// what `rvlife dynamics --json` prints, with `wall_time_s`).
///
/// # Errors
/// As [`profile_for`]; the simulation's failures.
pub fn dynamics(
    model: &Model,
    wear: Wear,
    pin_forces: bool,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<crate::dynamics::DynamicsResult> {
    let (staged, profile) = worn_for(model, wear, false, spelling, progress)?;
    let model: &Model = &staged;
    crate::dynamics::simulate_discs(
        &profile,
        &model.reducer,
        &model.dynamics.params,
        &model.fem.params,
        None,
        pin_forces,
    )
}

/// The Monte Carlo plan of `rvlife montecarlo`, checked before any work: `samples` (1 to
/// 1e6) reducers of seed `seed`, the shard `"I/N"` of them (`"/N"`: `I` from
/// `SLURM_ARRAY_TASK_ID`), each sample's own wear (`full_wear`), `per_cycle` (1-64) crank angles
/// per mesh cycle; the work is checked against the model's budget
/// (`crate::montecarlo::check_work`).
///
/// # Errors
/// [`Error::Invalid`] naming the argument as `spelling` writes it; no `[tolerances]`; the
/// budget.
pub fn montecarlo_plan(
    model: &Model,
    samples: usize,
    seed: u64,
    shard: Option<&str>,
    full_wear: bool,
    per_cycle: usize,
    spelling: Spelling,
) -> Result<crate::montecarlo::Plan> {
    if !(1..=1_000_000).contains(&samples) {
        return Err(Error::invalid(
            spelling.name("samples"),
            samples,
            "must be 1 to 1000000",
        ));
    }
    if !(1..=64).contains(&per_cycle) {
        return Err(Error::invalid(
            spelling.name("samples_per_mesh_cycle"),
            per_cycle,
            "must be 1 to 64",
        ));
    }
    let shard = match shard {
        None => (1, 1),
        Some(text) => {
            // `/N`: the index from the job array (SLURM numbers tasks as `--array` says).
            let owned;
            let text = if let Some(n) = text.strip_prefix('/') {
                let id = std::env::var("SLURM_ARRAY_TASK_ID").map_err(|_| {
                    Error::invalid(
                        spelling.name("shard"),
                        format!("\"{text}\""),
                        "takes its index from SLURM_ARRAY_TASK_ID, which is not set; give I/N",
                    )
                })?;
                owned = format!("{}/{n}", id.trim());
                owned.as_str()
            } else {
                text
            };
            let parsed = text.split_once('/').and_then(|(i, n)| {
                Some((
                    i.trim().parse::<usize>().ok()?,
                    n.trim().parse::<usize>().ok()?,
                ))
            });
            match parsed {
                Some((i, n)) if n >= 1 && (1..=n).contains(&i) && n <= samples => (i, n),
                _ => {
                    return Err(Error::invalid(
                        spelling.name("shard"),
                        format!("\"{text}\""),
                        format!(
                            "must be I/N with 1 <= I <= N <= {} ({samples})",
                            spelling.name("samples")
                        ),
                    ))
                }
            }
        }
    };
    if model.tolerances.is_empty() {
        return Err(Error::invalid(
            "tolerances",
            "no tolerance given",
            "give at least one distribution in [tolerances] (e.g. pin_radial_um = { normal = 1.0 })",
        ));
    }
    let plan = crate::montecarlo::Plan {
        samples,
        seed,
        shard,
        full_wear,
        samples_per_mesh_cycle: per_cycle,
    };
    let (points, horizon) = crate::montecarlo::life_points(model);
    crate::montecarlo::check_work(
        model,
        plan.indices().len(),
        points,
        plan.samples_per_mesh_cycle,
        plan.full_wear,
        horizon,
    )?;
    Ok(plan)
}

/// `rvlife calibrate --measured` on the validated `model` and the measurements `data`: the
/// options and the work are checked and the results directory `out` (when given; `force`
/// replaces one rvlife wrote) prepared before the reference studies run
/// ([`crate::calibration::calibrate`]; `progress(pass)` before each), then written with the
/// fit.
///
/// # Errors
/// [`Error::Invalid`] naming `--measured` or `--fit-running-in` (the options against the
/// model and data), the work beyond the budget, or `--out`; the fit's own refusals and
/// failures ([`crate::calibration::calibrate`]); [`Error::Io`] writing the results.
#[cfg(feature = "files")]
pub fn calibrate_measured(
    model: &Model,
    data: &crate::calibration::Measurements,
    options: crate::calibration::Options,
    out: Option<&std::path::Path>,
    force: bool,
    progress: &dyn Fn(usize),
) -> Result<crate::calibration::Calibration> {
    options.check(model, data)?;
    crate::calibration::check_budget(model, data)?;
    let staging = out
        .map(|dir| crate::output::Staging::prepare(dir, force))
        .transpose()?;
    let cal = crate::calibration::calibrate(model, data, options, progress)?;
    if let Some(staging) = staging {
        staging.commit(|dir| crate::output::calibration::write_files(&cal, dir))?;
    }
    Ok(cal)
}
