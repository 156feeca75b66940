//! The analyses of one stage beyond its static part: its outcome, its dynamics and flexible
//! analysis, and how their results are recorded in the stage; the flexible disc's pass over a
//! study in parts. The schedule over the stages is [`super::executor`]'s, the study's state
//! [`super::state`]'s.

use super::stage::arcmin;
use super::stage::{Failure, UnwornPlay};
use super::Stage;
use crate::config::Model;
use crate::dynamics::{simulate_discs, DynamicsSummary};
use crate::error::Result;
use crate::fem::flex::{analyse_stage, FlexibleStage};
use crate::fem::mesh::Mesh;
use crate::fem::DiscSet;
use crate::geometry::Profile;
use crate::te::CurveStats;
use crate::units::ARCMIN_PER_RAD;

/// A stage's dynamics and flexible analysis: the DTE summary and the flexible results.
pub(super) type StageRow = (Option<DynamicsSummary>, Option<(FlexibleStage, Mesh)>);

/// What one stage's analyses made of it (`StageRunner::run` in [`super::executor`]).
pub(super) enum Outcome {
    /// No static results.
    Failed(Failure),
    /// Not analysed: an earlier stage's static analysis failed.
    Skipped,
    /// Analysed, with the unworn disc's play on its parts (its play not yet split against
    /// the new reducer's) and its dynamics and flexible analysis (or their error).
    Done(Box<(Stage, UnwornPlay, Result<StageRow>)>),
}

/// The multibody simulation and the flexible analysis of the stage of `profile`, side by side
/// (each if enabled), on the FE disc (the unworn `base` moved onto a worn profile's outline);
/// `tick` after each.
///
/// # Errors
/// Failures of either analysis or of the FE disc.
pub(super) fn dynamics_and_flexible(
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
                &model.reducer,
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

/// Writes a stage's dynamics and flexible results `row` into the stage and its summary (the
/// DTE statistics; the flexible TE, stiffness, play and stresses in the summary's units).
pub(super) fn record_row(st: &mut Stage, row: StageRow) {
    let (dynamics, flexible) = row;
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

/// The flexible disc's analysis of every stage of `study` (docs/model.md section 9), after its
/// static stages: the FE disc built on the unworn profile, moved onto each stage's outline
/// and analysed on the stage's worn parts, as [`super::run`] does with `[fem] enabled` and
/// the dynamics off; the same numbers recorded in each stage and its summary. `progress(done,
/// total)` after the FE disc and after each stage. `study.model` then has `[fem] enabled`.
///
/// # Errors
/// The FE disc's failures and the flexible analysis's, as [`super::run`] reports them.
pub(super) fn flexible_pass(
    study: &mut super::Study,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<()> {
    let mut model = study.model.clone();
    model.fem.enabled = true;
    model.dynamics.enabled = false;
    let total = study.stages.len() + 1;
    let base_profile = model.profile()?;
    let base = DiscSet::build(&base_profile, &model.fem.params, &model.reducer)?;
    progress(1, total);
    let wear = &study.wear;
    for (i, st) in study.stages.iter_mut().enumerate() {
        let worn = crate::wear::WornState::new(
            model.wear.model,
            wear.bearing_rates,
            st.hours,
            &wear.maps[i],
            &wear.pin_maps[i],
        )?;
        let staged = model.worn(&worn);
        let row = dynamics_and_flexible(&staged, &st.profile, Some(&base), &base_profile, &|| {})?;
        record_row(st, row);
        progress(i + 2, total);
    }
    study.model = model;
    Ok(())
}
