//! Physical checks of a validated model (docs/model.md section 15.2), made by the gate every
//! command passes (`study::validated`, after the work budget) before any analysis starts, so
//! that a non-physical input is refused by the key the user wrote (exit 2) instead of ending as
//! a solver failure half-way through a study. On the model the analyses run on.
//!
//! - **Mesh:** with the modifications, the unworn disc must stay in mesh: turning it either way
//!   from its nominal pose, a pin must stop it within the static analysis' twist range, and the
//!   play between the two directions must not be negative (interference). Probed at the
//!   crank angles of a mesh cycle that the study solves, and `PROBES_PER_MESH_CYCLE` more.
//! - **Torque:** every torque the study applies (rated torque both ways, loaded-TE torque, the
//!   largest wear load in each direction, the peak of the dynamic load) must be carried by the
//!   unworn stage at the same crank angles: the static analysis converges, the twist beyond
//!   first contact stays within half the range it follows (`MAX_TWIST`), and the largest Hertz
//!   pressure stays within `materials.max_contact_pressure_mpa` (ISO 76:2006 static capacity of
//!   hardened steel in line contact, 4000 MPa, by default). A torque beyond is refused with the
//!   torque the stage does carry in that direction.

use std::f64::consts::TAU;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use crate::config::{load_peaks, Model, ModificationConfig};
use crate::error::{Error, Result};
use crate::geometry::Profile;
use crate::reducer::Reducer;
use crate::statics::{StaticAnalysis, MAX_TWIST};
use crate::units::ARCMIN_PER_RAD;

/// Crank angles per mesh cycle at which the unworn stage is probed besides the study's own.
pub(crate) const PROBES_PER_MESH_CYCLE: usize = 4;

/// Play below which the modified disc interferes with the pins, rad (the study's own test of
/// the worn stages uses the same bound).
const INTERFERENCE: f64 = 1e-9;

/// The crank angles (rad, one mesh cycle, ascending, without repeats) at which the unworn
/// stage is probed: the study's TE samples (`te.samples_per_mesh_cycle`), its wear steps
/// (`wear.crank_steps_per_mesh_cycle`) and [`PROBES_PER_MESH_CYCLE`] more, so that a torque
/// the check passes is solved at every crank angle the study solves it at.
fn probe_angles(model: &Model) -> Vec<f64> {
    let pins = model.cycloid.geometry.pins;
    let mut k: Vec<(usize, usize)> = [
        PROBES_PER_MESH_CYCLE,
        model.te.samples,
        model.wear.crank_steps,
    ]
    .iter()
    .flat_map(|&n| (0..n).map(move |i| (i, n)))
    .collect();
    // Exact fractions i/n, sorted and deduplicated by cross-multiplication.
    k.sort_by(|a, b| (a.0 * b.1).cmp(&(b.0 * a.1)));
    k.dedup_by(|a, b| a.0 * b.1 == b.0 * a.1);
    k.iter()
        .map(|&(i, n)| TAU * i as f64 / (pins * n) as f64)
        .collect()
}

/// A bound in a message: `412`, `1.5e12`.
fn show(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-3) {
        format!("{v:.4e}")
    } else {
        format!("{}", (v * 1e4).round() / 1e4)
    }
}

/// Checks that the modified, unworn disc of `profile` stays in mesh on the reducer `nominal`
/// (the model's without part errors: parts that close the play are assembled with preload,
/// docs/model.md section 5.12, and their errors are checked by the torques they carry, see
/// [`check_stage`]); `mods` and the pin circle radius `rp` (m) name the modification that is
/// to blame.
///
/// Returns the static analysis of the unworn stage on `nominal`, which the torque checks use
/// too.
///
/// # Errors
/// [`Error::Invalid`] naming the modification key that contributes most (its effect on the
/// flank in mm: `|equidistant|`, `|offset|`, `|rotation| Rp`), its value and the play found.
fn check_mesh<'a>(
    model: &Model,
    nominal: &'a Reducer,
    profile: &'a Profile,
    mods: &ModificationConfig,
    rp: f64,
) -> Result<StaticAnalysis<'a>> {
    let blame = |why: String| {
        let parts = [
            (
                "equidistant_mm",
                mods.equidistant_mm,
                mods.equidistant_mm.abs(),
            ),
            ("offset_mm", mods.offset_mm, mods.offset_mm.abs()),
            (
                "rotation_deg",
                mods.rotation_deg,
                mods.rotation_deg.to_radians().abs() * rp * 1e3,
            ),
        ];
        let (key, value, effect) =
            parts
                .iter()
                .copied()
                .fold(parts[0], |a, b| if b.2 > a.2 { b } else { a });
        if effect == 0.0 {
            Error::invalid(
                "cycloid",
                "the nominal stage",
                format!("{why}: check eccentricity_mm, pin_circle_radius_mm and pin_radius_mm"),
            )
        } else {
            Error::invalid(
                format!("cycloid.modification.{key}"),
                show(value),
                format!(
                    "{why} (modifications: equidistant_mm = {}, offset_mm = {}, rotation_deg = \
                     {}; real ones move the flank by micrometres to a few tens of micrometres)",
                    show(mods.equidistant_mm),
                    show(mods.offset_mm),
                    show(mods.rotation_deg)
                ),
            )
        }
    };
    let sa = StaticAnalysis::new(nominal, profile).map_err(|e| {
        blame(format!(
            "the contact geometry of the modified disc cannot be built ({e})"
        ))
    })?;
    for phi in probe_angles(model) {
        let forward = sa.first_contact(phi, 1.0);
        let reverse = sa.first_contact(phi, -1.0);
        let (fw, rv) = match (forward, reverse) {
            (Ok(f), Ok(r)) => (f, r),
            _ => {
                return Err(blame(format!(
                    "at crank angle {:.2} deg no pin stops the unworn disc when it turns (the \
                     modifications take the flank out of reach of the pins)",
                    phi.to_degrees()
                )))
            }
        };
        if fw - rv < -INTERFERENCE {
            return Err(blame(format!(
                "the unworn disc interferes with the pins: play {:.4} arcmin at crank angle \
                 {:.2} deg; thin the teeth (equidistant_mm > 0 or offset_mm < 0)",
                (fw - rv) * ARCMIN_PER_RAD,
                phi.to_degrees()
            )));
        }
    }
    Ok(sa)
}

/// Largest Hertz pressure (Pa) of the static solutions at the probe angles under `torque`, or
/// why the stage does not carry it (at the first probe angle, in order, that does not). The
/// angles are solved in parallel; those after a failure are left unsolved.
fn carried(sa: &StaticAnalysis, model: &Model, torque: f64) -> std::result::Result<f64, String> {
    let angles = probe_angles(model);
    let failed = AtomicUsize::new(usize::MAX);
    let at = |phi: f64| -> std::result::Result<f64, String> {
        let s = sa
            .solve(phi, torque)
            .map_err(|e| format!("the static analysis cannot carry it ({e})"))?;
        // Half the twist range of the static analysis: the loading paths of the study (warm
        // starts, load steps, the hysteresis sweep) stay inside the range.
        let beyond = (s.twist - s.first_contact_twist).abs();
        if beyond > 0.5 * MAX_TWIST {
            return Err(format!(
                "the twist beyond first contact would be {:.1} arcmin at crank angle {:.2} deg, \
                 more than half the {:.0} arcmin the static analysis follows",
                beyond * ARCMIN_PER_RAD,
                phi.to_degrees(),
                MAX_TWIST * ARCMIN_PER_RAD
            ));
        }
        Ok(s.max_pressure())
    };
    let results: Vec<Option<std::result::Result<f64, String>>> = angles
        .par_iter()
        .enumerate()
        .map(|(i, &phi)| {
            if i > failed.load(Ordering::Relaxed) {
                return None;
            }
            let r = at(phi);
            if r.is_err() {
                failed.fetch_min(i, Ordering::Relaxed);
            }
            Some(r)
        })
        .collect();
    let mut pmax: f64 = 0.0;
    // Every angle before the first failure was solved.
    for r in results.into_iter().map_while(|r| r) {
        pmax = pmax.max(r?);
    }
    if pmax > model.materials.max_contact_pressure {
        Err(format!(
            "the largest Hertz pressure would be {:.0} MPa, above \
             materials.max_contact_pressure_mpa = {:.0} MPa",
            pmax * 1e-6,
            model.materials.max_contact_pressure * 1e-6
        ))
    } else {
        Ok(pmax)
    }
}

/// The largest torque (N m, magnitude) in the direction of `sign` that the stage carries,
/// below `above` which it does not: halving from `min(above, 64 x rated)`, then 12 steps of
/// geometric bisection (within 2^-12 of an octave, 0.02 %). A failing solve costs up to
/// 0.2 s, so the search starts near the rating rather than at an absurd torque.
fn capacity(sa: &StaticAnalysis, model: &Model, sign: f64, above: f64) -> f64 {
    let floor = 1e-9 * model.rating.rated_torque;
    let (mut lo, mut hi) = (above.min(64.0 * model.rating.rated_torque), above);
    while carried(sa, model, sign * lo).is_err() {
        hi = lo;
        lo *= 0.5;
        if lo < floor {
            return 0.0;
        }
    }
    for _ in 0..12 {
        let mid = (lo * hi).sqrt();
        if carried(sa, model, sign * mid).is_ok() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// A torque of the config that the unworn stage does not carry: its key, the torque (N m) and
/// why.
struct NotCarried {
    key: String,
    torque: f64,
    reason: String,
}

impl NotCarried {
    /// "it carries at most 206 N m counter-clockwise (probed at the 36 crank angles ...)": the
    /// capacity of the stage of `sa` that way ([`capacity`], a search of up to a second or two).
    fn at_most(&self, sa: &StaticAnalysis, model: &Model) -> String {
        let max = crate::config::MAX_TORQUE_NM;
        format!(
            "it carries at most {} N m {} (probed at the {} crank angles of a mesh cycle the \
             study solves)",
            show(capacity(
                sa,
                model,
                self.torque.signum(),
                self.torque.abs().min(max)
            )),
            if self.torque > 0.0 {
                "counter-clockwise"
            } else {
                "clockwise"
            },
            probe_angles(model).len()
        )
    }
}

/// The first of the torques `uses` (key as the user wrote it, output torque in N m) that the
/// unworn stage of `profile` on the reducer `red` does not carry (see the module docs), if
/// any; a torque beyond [`crate::config::MAX_TORQUE_NM`] is not solved at all.
///
/// # Errors
/// Those of building the static analysis.
fn not_carried(
    model: &Model,
    sa: &StaticAnalysis,
    uses: &[(String, f64)],
) -> Result<Option<NotCarried>> {
    let max = crate::config::MAX_TORQUE_NM;
    let mut checked: Vec<f64> = Vec::new();
    for (key, torque) in uses {
        let t = *torque;
        if t == 0.0 || checked.contains(&t) {
            continue;
        }
        let refused = if t.is_nan() || t.abs() > max {
            Err(format!(
                "it is beyond {max:e} N m, the largest torque rvlife takes"
            ))
        } else {
            carried(sa, model, t)
        };
        if let Err(reason) = refused {
            return Ok(Some(NotCarried {
                key: key.clone(),
                torque: t,
                reason,
            }));
        }
        checked.push(t);
    }
    Ok(None)
}

/// Checks the torques `uses` (key as the user wrote it, output torque in N m) against what the
/// unworn stage of the static analysis `sa` carries (see the module docs).
///
/// # Errors
/// [`Error::Invalid`] naming the first key whose torque is not carried, with the reason (the
/// pressure above the limit, or the static analysis failing) and the largest torque the stage
/// carries in that direction.
fn check_torques(model: &Model, sa: &StaticAnalysis, uses: &[(String, f64)]) -> Result<()> {
    match not_carried(model, sa, uses)? {
        None => Ok(()),
        Some(n) => Err(torque_error(model, sa, &n)),
    }
}

/// The refusal of a torque the unworn stage of `sa` does not carry, by its own key.
fn torque_error(model: &Model, sa: &StaticAnalysis, n: &NotCarried) -> Error {
    Error::invalid(
        n.key.as_str(),
        show(n.torque),
        format!(
            "{NOT_CARRIED}: {}; {}; check the torque, or the stage \
             dimensions in [cycloid] and [materials]",
            n.reason,
            n.at_most(sa, model)
        ),
    )
}

/// The keys that set a part in series with the crank bearings or the meshes (docs/model.md
/// section 5.9: the structure compliance, the carrier's pillars, the cranks' bending and
/// torsion, the input shaft, the housing ring), in the order [`blame_written`] looks at them.
pub const SERIES_KEYS: &[&str] = &[
    "reducer.structure.compliance_arcmin_per_knm",
    "reducer.bearings.carrier_stiffness_n_per_um",
    "reducer.bearings.crank_bending_stiffness_n_per_um",
    "reducer.bearings.crank_torsion_stiffness_nm_per_rad",
    "reducer.structure.crank_diameter_mm",
    "reducer.structure.crank_span_mm",
    "reducer.structure.eccentric_spacing_mm",
    "reducer.structure.crank_torsion_length_mm",
    "reducer.structure.input_shaft_diameter_mm",
    "reducer.structure.input_shaft_length_mm",
    "reducer.structure.housing_outer_diameter_mm",
    "reducer.structure.housing_width_mm",
];

/// The refusal of a torque the unworn stage does not carry ([`torque_error`]), its start.
const NOT_CARRIED: &str = "is more than the unworn stage carries";

/// The refusal of the torque `n` that the unworn stage of the config `cfg` does not carry,
/// blamed on the key that makes it so where that is a part in series the user wrote
/// ([`SERIES_KEYS`]): where the torque fails on the stage's compliance (not on the contact
/// pressure), the first such key at whose default (the key left out: its estimate from the
/// stage's dimensions) the stage passes every check. `None` where there is none. Costs a
/// validation and a check of the stage per such key the config writes.
fn blame_written(cfg: &crate::config::Config, n: &NotCarried) -> Option<Error> {
    if n.reason.contains("Hertz pressure") || n.reason.contains("the largest torque rvlife") {
        return None;
    }
    let json = serde_json::to_value(cfg).ok()?;
    let written = |key: &str| cfg.written.as_ref().is_none_or(|w| w.contains(key));
    SERIES_KEYS
        .iter()
        .copied()
        .filter(|k| written(k))
        .find_map(|key| {
            let pointer = format!("/{}", key.replace('.', "/"));
            let value = json.pointer(&pointer)?.as_f64()?;
            let default = without_key(cfg, &json, key)?;
            let passes = default
                .validate_unassembled()
                .and_then(|m| check_stage(&m, &default.cycloid.modification, Blame::Nobody))
                .is_ok();
            passes.then(|| {
                Error::invalid(
                    key,
                    show(value),
                    format!(
                    "leaves the stage too compliant: the unworn stage does not carry {} = {} N m \
                     ({}); with this key at its default (left out) it does; check this value",
                    n.key,
                    show(n.torque),
                    n.reason
                ),
                )
            })
        })
}

/// `cfg` (as JSON: `json`) with `key` left out, so that it takes its default.
fn without_key(
    cfg: &crate::config::Config,
    json: &serde_json::Value,
    key: &str,
) -> Option<crate::config::Config> {
    let (parent, name) = key.rsplit_once('.')?;
    let mut v = json.clone();
    v.pointer_mut(&format!("/{}", parent.replace('.', "/")))?
        .as_object_mut()?
        .remove(name)?;
    let mut c: crate::config::Config = serde_json::from_value(v).ok()?;
    c.base_dir.clone_from(&cfg.base_dir);
    c.work_budget_minutes = cfg.work_budget_minutes;
    c.written = cfg.written.as_ref().map(|w| {
        let mut w = w.clone();
        w.remove(key);
        w
    });
    Some(c)
}

/// The physical checks of the unworn stage of `model` (its nominal profile: modified, without
/// a measured profile): the modifications `mods` (as written) keep the disc in mesh
/// ([`check_mesh`]), and every torque the config applies is carried ([`check_torques`]): the
/// rated torque both ways, the loaded-TE torque, the largest wear load each way (named by
/// `model.load.level_keys`) and, with
/// `[dynamics]` enabled, the peaks of the dynamic load. Both on the nominal parts; with part
/// errors the torques are then checked with the errors in place ([`blame_errors`]).
///
/// # Errors
/// [`Error::Invalid`] naming the key to blame.
pub(crate) fn check_stage(model: &Model, mods: &ModificationConfig, blame: Blame) -> Result<()> {
    let c = &model.cycloid;
    let profile = &Profile::new(c.geometry.clone(), c.modification, None)?;
    let level_keys = &model.load.level_keys;
    let nominal = Reducer {
        errors: Default::default(),
        ..model.reducer.clone()
    };
    let sa = check_mesh(
        model,
        &nominal,
        profile,
        mods,
        model.cycloid.geometry.pin_circle_radius,
    )?;
    let rated = model.rating.rated_torque;
    let mut uses = vec![
        ("reducer.rated_torque_nm".to_string(), rated),
        ("reducer.rated_torque_nm".to_string(), -rated),
        ("te.loaded_torque_nm".to_string(), model.te.loaded_torque),
    ];
    for dir in [1.0, -1.0] {
        let peak = model
            .load
            .levels
            .iter()
            .zip(level_keys)
            .filter(|(l, _)| l.torque * dir > 0.0)
            .max_by(|a, b| (a.0.torque * dir).total_cmp(&(b.0.torque * dir)));
        if let Some((l, key)) = peak {
            uses.push((key.clone(), l.torque));
        }
    }
    if model.dynamics.enabled {
        uses.extend(load_peaks(&model.dynamics.params.load));
    }
    // With part errors: the nominal stage first, so that a torque it does not carry is blamed
    // on the key that makes it so (`blame`), else on the torque (or the stage), and one that
    // only the errors make too much on the errors.
    if let Some(n) = not_carried(model, &sa, &uses)? {
        return Err(match blame {
            Blame::Written(cfg) => {
                blame_written(cfg, &n).unwrap_or_else(|| torque_error(model, &sa, &n))
            }
            Blame::Nobody => Error::invalid(n.key.as_str(), show(n.torque), NOT_CARRIED),
        });
    }
    if model.reducer.errors.is_zero() {
        return Ok(());
    }
    let with_errors = StaticAnalysis::new(&model.reducer, profile)?;
    match not_carried(model, &with_errors, &uses)? {
        None => Ok(()),
        Some(n) => Err(blame_errors(model, &with_errors, &n)),
    }
}

/// Whom [`check_stage`] refuses a torque the unworn nominal stage does not carry by.
#[derive(Clone, Copy)]
pub(crate) enum Blame<'a> {
    /// The key of the config that makes it so where [`blame_written`] finds one, else the
    /// torque's key.
    Written(&'a crate::config::Config),
    /// The torque's key without the capacity search: for a check whose message nobody reads.
    Nobody,
}

/// The error to report when the stage with its part errors does not carry a torque that the
/// nominal stage carries: the `[errors]` entry that moves a flank most (lengths as they are,
/// a crank's phase error times the eccentricity, the run-out as its total indicator reading),
/// with what is not carried and why.
fn blame_errors(model: &Model, sa: &StaticAnalysis, n: &NotCarried) -> Error {
    let err = &model.reducer.errors;
    let a = model.cycloid.geometry.eccentricity;
    let um = 1e6;
    let arcmin = 60.0 * 180.0 / std::f64::consts::PI;
    // (key, index, value as written, flank effect in m)
    let mut parts: Vec<(&str, Option<usize>, f64, f64)> = Vec::new();
    for (key, list) in [
        ("pin_radial_um", &err.pin_radial),
        ("pin_tangential_um", &err.pin_tangential),
        ("pin_radius_um", &err.pin_radius),
        ("crank_eccentricity_um", &err.crank_eccentricity),
    ] {
        for (i, &x) in list.iter().enumerate() {
            parts.push((key, Some(i), x * um, x.abs()));
        }
    }
    for (i, &x) in err.crank_phase.iter().enumerate() {
        parts.push(("crank_phase_arcmin", Some(i), x * arcmin, x.abs() * a));
    }
    let runout = 2.0 * err.pin_circle_offset.norm();
    parts.push(("pin_circle_runout_um", None, runout * um, runout));
    let (key, index, value, _) =
        parts
            .iter()
            .copied()
            .fold(parts[0], |m, p| if p.3 > m.3 { p } else { m });
    let key = match index {
        Some(i) => format!("errors.{key}[{i}]"),
        None => format!("errors.{key}"),
    };
    Error::invalid(
        key,
        show(value),
        format!(
            "with the part errors of [errors] (this one moves a flank most) the unworn stage \
             does not carry {} = {} N m, which the nominal stage carries: {}; {}; real part \
             errors of a precision reducer are a few micrometres and arcminutes",
            n.key,
            show(n.torque),
            n.reason,
            n.at_most(sa, model)
        ),
    )
}

impl Model {
    /// Checks that the unworn stage carries the output torque `torque` (N m), as every torque
    /// of the config is checked by [`crate::config::Config::validate`]; `key` names the torque
    /// in the message (a command-line flag such as `--torque-nm`).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `key`, with the largest torque the stage carries that way.
    pub(crate) fn check_torque(&self, key: &str, torque: f64) -> Result<()> {
        if !torque.is_finite() {
            return Err(Error::invalid(key, torque, "must be a finite number"));
        }
        let profile = self.profile()?;
        let sa = StaticAnalysis::new(&self.reducer, &profile)?;
        check_torques(self, &sa, &[(key.to_string(), torque)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    /// The capacity of the paper's reducer is where its largest Hertz pressure reaches the limit
    /// or its twist leaves the range the static analysis follows, whichever comes first: carried
    /// at 0.99 of it, not at 1.01, both ways, above the catalogue's momentary maximum torque (5
    /// times the rated for the RV-E series); where the pressure sets it, the pressure there
    /// within 1 % of 4000 MPa (Hertz pressure grows as the square root of the force, so 2 % of
    /// torque is 1 % of pressure), and the refusal names the limit that set it.
    #[test]
    fn capacity_is_where_the_pressure_reaches_the_limit() {
        let m = Config::paper().validate().unwrap();
        let p = m.profile().unwrap();
        let sa = StaticAnalysis::new(&m.reducer, &p).unwrap();
        for sign in [1.0, -1.0] {
            let cap = capacity(&sa, &m, sign, 1e6);
            assert!(cap > 5.0 * m.rating.rated_torque, "{cap}");
            let p_at = carried(&sa, &m, sign * 0.99 * cap).unwrap();
            let beyond = carried(&sa, &m, sign * 1.01 * cap).unwrap_err();
            let rel = p_at / m.materials.max_contact_pressure - 1.0;
            assert!(m.check_torque("t", sign * 0.99 * cap).is_ok());
            let e = m
                .check_torque("t", sign * 1.01 * cap)
                .unwrap_err()
                .to_string();
            assert!(e.contains("carries at most"), "{e}");
            if beyond.contains("twist beyond first contact") {
                assert!(rel < 0.0, "pressure {p_at} at 0.99 x {cap} N m");
                assert!(e.contains("twist beyond first contact"), "{e}");
                continue;
            }
            assert!(rel.abs() < 0.01, "pressure {p_at} at 0.99 x {cap} N m");
            assert!(e.contains("carries at most") && e.contains("MPa"), "{e}");
        }
    }
}
