//! The flexible disc in the multibody model (fixed-interface modes and residual flexibility of
//! the FE disc, `fem::modal`): its quasi-static limit, its stiff limit and its modal convergence.

use rvlife::config::{Config, Model};
use rvlife::fem::flex::solve_flexible_bearings;
use rvlife::fem::modal::{ModalDisc, ModalSettings};
use rvlife::fem::DiscModel;
use rvlife::geometry::{Profile, WearMap};
use rvlife::reducer::dynamics::{simulate_with, DynamicsParams};
use rvlife::reducer::statics::StaticAnalysis;
use rvlife::te::ARCMIN_PER_RAD;

fn model_with(edit: impl FnOnce(&mut Config)) -> Model {
    let mut c = Config::example();
    edit(&mut c);
    c.validate().unwrap()
}

/// The slow set-up of `tests/dynamics.rs`: 412 N m applied over 1 s at 90 deg/s input, window
/// 1.2-1.45 s, contacts critically damped, bearings at 0.8 of critical.
fn slow_model() -> Model {
    model_with(|c| {
        c.reducer.bearings.damping_ratio = 0.8;
        let d = &mut c.dynamics;
        d.end_time_s = 1.45;
        d.window_s = [1.2, 1.45];
        d.drive.speed_deg_s = 90.0;
        d.drive.ramp_end_s = 0.5;
        d.load.kind = "constant".into();
        d.load.torque_nm = Some(412.0);
        d.load.ramp_s = 1.0;
        d.impact.damping_ratio = 1.0;
    })
}

/// Every body 100 times heavier, the disc's density too (modal frequencies / 10), so the
/// integrator's step is ten times longer and inertia forces stay negligible.
fn heavy(p: &DynamicsParams) -> DynamicsParams {
    let mut p = p.clone();
    let i = &mut p.inertia;
    for v in [
        &mut i.disc_mass,
        &mut i.disc,
        &mut i.crank_mass,
        &mut i.crank,
        &mut i.output,
    ] {
        *v *= 100.0;
    }
    p
}

/// Modal settings at the example's disc density times `density_scale`, heavily damped modes
/// (quasi-static runs).
fn settings(density_scale: f64, cutoff_hz: f64) -> ModalSettings {
    ModalSettings {
        cutoff_hz,
        damping_ratio: 0.5,
        max_modes: 200,
        density: Config::example().dynamics.inertia.disc_density_kg_m3 * density_scale,
    }
}

fn stage(m: &Model, hours: f64) -> Profile {
    if hours == 0.0 {
        return m.profile(None).unwrap();
    }
    let mut m = m.clone();
    m.stage_hours = vec![hours];
    let hist = rvlife::wear::integrate(&m, &|_, _| {}).unwrap();
    m.profile(Some(WearMap::new(hist.maps[0].clone()).unwrap()))
        .unwrap()
}

/// Slowly ramped 412 N m: the flexible DTE equals the static flexible analysis of the same
/// reducer (both discs on their bearings, the FE body's deflection at the pins) at the same
/// crank angles within 1 %, on the new disc and the disc worn for 7500 h.
#[test]
fn slow_flexible_dte_equals_the_static_flexible_analysis() {
    let m = slow_model();
    for hours in [0.0, 7500.0] {
        let profile = stage(&m, hours);
        let disc = DiscModel::build(&profile, &m.fem).unwrap();
        let p = heavy(&m.dynamics);
        let modal = ModalDisc::build(&disc, &settings(100.0, 6e3)).unwrap();
        let t0 = std::time::Instant::now();
        let r = simulate_with(&profile, &p, Some(&modal), false).unwrap();
        eprintln!(
            "{hours} h: {} modes ({:.0}..{:.0} Hz at density x 100), {} steps, {:.1} s",
            modal.modes(),
            modal.omega[0] / std::f64::consts::TAU,
            modal.omega.last().unwrap() / std::f64::consts::TAU,
            r.summary.steps,
            t0.elapsed().as_secs_f64()
        );
        let sa = StaticAnalysis::new(&m.reducer, &profile).unwrap();
        let kappa = m.reducer.kappa();
        let window: Vec<&rvlife::reducer::dynamics::Sample> = r
            .samples
            .iter()
            .filter(|s| s.time_s >= p.window.0 && s.time_s <= p.window.1)
            .collect();
        let (mut worst, mut sum_dyn, mut sum_st) = (0.0_f64, 0.0, 0.0);
        for k in 0..24 {
            let s = window[k * (window.len() - 1) / 23];
            let phi = kappa * s.input_angle_deg.to_radians();
            let rigid = sa.solve(phi, 412.0).unwrap();
            let (flex, _) = solve_flexible_bearings(&sa, &m.reducer, &disc, rigid).unwrap();
            let te_static = flex.twist * ARCMIN_PER_RAD;
            worst = worst.max((s.te_arcmin - te_static).abs() / te_static);
            sum_dyn += s.te_arcmin;
            sum_st += te_static;
        }
        eprintln!(
            "{hours} h: mean flexible DTE {:.5} arcmin, static flexible {:.5}; largest \
             difference at a crank angle {worst:.2e}",
            sum_dyn / 24.0,
            sum_st / 24.0
        );
        assert!(
            worst < 0.01,
            "{hours} h: flexible DTE differs by {worst:.3e}"
        );
    }
}
