//! The k-h scaling that `rvlife calibrate --measured` rests on ([`crate::calibration`]).

use crate::config::{Config, Model};
use crate::quantities::StageSummary;
use crate::wear::{integrate, integrate_on_schedule};

/// One number of a stage summary.
type StageValue = fn(&StageSummary) -> f64;

/// The example without dynamics and the flexible disc, stages at `hours`.
fn fast_model(hours: &[f64]) -> Model {
    let mut cfg = Config::paper();
    cfg.dynamics.enabled = false;
    cfg.fem.enabled = false;
    let mut m = cfg.validate().expect("example validates");
    m.wear.stage_hours = hours.to_vec();
    m
}

/// The wear rate is `k` times a function of the worn profile, so the wear after `h` hours at
/// `2 k` with the profile updates at half the hours equals the wear after `2 h` at `k`: exact to
/// round-off (1e-9 relative), on the schedule of a run at `k`.
#[test]
fn wear_depends_on_k_and_hours_only_through_their_product() {
    let hours = [0.0, 1500.0, 3000.0, 4500.0];
    let m = fast_model(&hours);
    let reference = integrate(&m.wear_inputs(), &|_, _| {}).unwrap();
    let mut m2 = m.clone();
    m2.wear.archard *= 2.0;
    m2.wear.stage_hours = hours.iter().map(|h| h / 2.0).collect();
    let half: Vec<f64> = reference.update_hours.iter().map(|t| t / 2.0).collect();
    let scaled = integrate_on_schedule(&m2.wear_inputs(), &half, &|_, _| {}).unwrap();
    assert_eq!(reference.maps.len(), scaled.maps.len());
    let max = reference.max_depths().last().copied().unwrap();
    assert!(max > 20e-6, "the example wears {max} m");
    for (a, b) in reference.maps.iter().zip(&scaled.maps) {
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 1e-9 * max, "{x} {y}");
        }
    }
}

/// What the scaling leaves out: `rvlife run` at `2 k` chooses its own profile updates
/// (`wear.profile_update_hours` counts real hours), so it differs from the reference at `k`
/// read at twice the hours by the discretisation error of the wear integration. For the
/// example at 1500-4500 h (2 k: 26-73 um of wear) it was measured at 0.012 % or less of the
/// lost motion, backlash and maximum wear (printed): the `wear.max_wear_step_um` rule, which
/// counts depth and so scales, sets most updates. Asserted below 0.1 %.
#[test]
fn direct_run_at_twice_k_matches_the_reference_at_twice_the_hours() {
    let hours = [0.0, 1500.0, 3000.0, 4500.0];
    let mut m2 = fast_model(&hours);
    m2.wear.archard *= 2.0;
    let t = std::time::Instant::now();
    let direct = crate::study::run(&m2, &|_, _| {}).unwrap();
    let wall = t.elapsed().as_secs_f64();
    let m = fast_model(&hours.iter().map(|h| 2.0 * h).collect::<Vec<_>>());
    let reference = crate::study::run(&m, &|_, _| {}).unwrap();
    let quantities: [(&str, StageValue); 3] = [
        ("lost_motion_arcmin", |s| s.lost_motion_arcmin),
        ("backlash_arcmin", |s| s.backlash_arcmin),
        ("max_wear_um", |s| s.max_wear_um),
    ];
    for (a, b) in direct.stages.iter().zip(&reference.stages).skip(1) {
        for (name, f) in quantities {
            let rel = (f(&a.summary) - f(&b.summary)) / f(&b.summary);
            eprintln!(
                "{} h at 2k vs {} h at k: {name} {:.5} vs {:.5} ({:+.3} %)",
                a.hours,
                b.hours,
                f(&a.summary),
                f(&b.summary),
                rel * 100.0
            );
            assert!(rel.abs() < 1e-3, "{name} at {} h: {rel}", a.hours);
        }
    }
    eprintln!(
        "study at 2k: {wall:.2} s, {} wear-rate evaluations (reference: {})",
        direct.wear.rate_evaluations(),
        reference.wear.rate_evaluations()
    );
}

/// Running-in is a warp of the hours: with the rate from the new profile (no profile updates)
/// the wear after `t` hours with `k(t) = k_ss (1 + (r - 1) exp(-t/tau))` is the steady wear
/// times `H(t)/t`, `H(t) = t + (r - 1) tau (1 - exp(-t/tau))`, to round-off (1e-12); with
/// profile updates it is the steady wear after `H(t)` hours within 1 % (the update schedules
/// differ). `r` = 3, `tau` = 300 h.
#[test]
fn running_in_warps_the_hours() {
    let hours = [0.0, 300.0, 1000.0, 3000.0];
    let mut m = fast_model(&hours);
    m.wear.update_hours = 0.0;
    let steady = integrate(&m.wear_inputs(), &|_, _| {}).unwrap();
    let mut r = m.clone();
    r.wear.running_in = crate::wear::RunningIn {
        factor: 3.0,
        hours: 300.0,
    };
    let warped = integrate(&r.wear_inputs(), &|_, _| {}).unwrap();
    let depth =
        |h: &crate::wear::WearHistory, i: usize| h.maps[i].iter().copied().fold(0.0, f64::max);
    for (i, &t) in hours.iter().enumerate().skip(1) {
        let big_h = r.wear.running_in.equivalent_hours(t);
        let ratio = depth(&warped, i) / depth(&steady, i);
        println!("{t} h: ratio {ratio:.6}, H/t {:.6}", big_h / t);
        assert!((ratio / (big_h / t) - 1.0).abs() < 1e-12);
    }
    // With updates: at t against the steady run at H(t).
    let mut m = fast_model(&hours);
    let mut r = m.clone();
    r.wear.running_in = crate::wear::RunningIn {
        factor: 3.0,
        hours: 300.0,
    };
    let warped = integrate(&r.wear_inputs(), &|_, _| {}).unwrap();
    let equivalent: Vec<f64> = hours
        .iter()
        .map(|&t| r.wear.running_in.equivalent_hours(t))
        .collect();
    m.wear.stage_hours = equivalent;
    let steady = integrate(&m.wear_inputs(), &|_, _| {}).unwrap();
    for (i, t) in hours.iter().enumerate().skip(1) {
        let ratio = depth(&warped, i) / depth(&steady, i);
        println!("with updates, {t} h: {ratio:.5}");
        assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
    }
}

/// The fit of a running-in factor (`calibrate --measured` on a config with
/// `wear.running_in_factor` > 1): lost motion generated by a direct study with running-in
/// (`r` = 4, `tau` = 300 h, `k` = 1.7 times the example's, a play `b0` = 0.1 arcmin, Gaussian
/// noise of 0.005 arcmin, seed fixed, not chosen), fitted from the start `r` = 2 with `tau`
/// kept: `k`, `r` and `b0` each within their 95 % intervals, `k` within 10 % and `r` within
/// 30 % of the truth, the RMS residual within 0.5-1.5 times the noise.
#[test]
#[cfg_attr(
    target_family = "wasm",
    ignore = "calibration is not in the web build's page: run natively"
)]
fn calibration_fits_the_running_in_factor() {
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let hours = [
        0.0, 50.0, 100.0, 200.0, 300.0, 450.0, 600.0, 800.0, 1000.0, 1250.0, 1500.0, 2000.0,
    ];
    let mut truth = fast_model(&hours);
    let k_true = 1.7 * truth.wear.archard;
    truth.wear.archard = k_true;
    let (r_true, tau, b0_true, sigma) = (4.0, 300.0, 0.1, 0.005);
    truth.wear.running_in = crate::wear::RunningIn {
        factor: r_true,
        hours: tau,
    };
    let study = crate::study::run(&truth, &|_, _| {}).unwrap();
    assert_eq!(study.stages.len(), hours.len());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2025);
    let noise = Normal::new(0.0, sigma).unwrap();
    let mut csv = String::from("hours,lost_motion_arcmin\n");
    for s in &study.stages {
        let y = s.summary.lost_motion_arcmin + b0_true + noise.sample(&mut rng);
        csv.push_str(&format!("{},{y}\n", s.hours));
    }
    let data = crate::calibration::Measurements::parse(std::path::Path::new("m.csv"), &csv)
        .expect("generated data parse");
    let mut start = fast_model(&hours);
    start.wear.running_in = crate::wear::RunningIn {
        factor: 2.0,
        hours: tau,
    };
    let options = crate::calibration::Options {
        fit_running_in: true,
    };
    options.check(&start, &data).unwrap();
    let cal = crate::calibration::calibrate(&start, &data, options, &|_| {}).unwrap();
    let k = &cal.archard_coefficient_m2_per_n;
    let r = cal.running_in_factor.as_ref().expect("r fitted");
    let b0 = cal.running_in_backlash_arcmin.as_ref().expect("b0 fitted");
    let rms = cal.quantities[0].rms_residual;
    eprintln!(
        "k {:.4e} [{:.4e}, {:.4e}] (true {k_true:.4e}); r {:.3} [{:.3}, {:.3}] (true {r_true}); \
         b0 {:.4} [{:.4}, {:.4}] (true {b0_true}); RMS {rms:.5}; {} dof",
        k.value,
        k.lower,
        k.upper,
        r.value,
        r.lower,
        r.upper,
        b0.value,
        b0.lower,
        b0.upper,
        cal.degrees_of_freedom
    );
    assert_eq!(cal.parameters, 3);
    assert_eq!(cal.running_in_hours, Some(tau));
    for (name, e, t) in [("k", k, k_true), ("r", r, r_true), ("b0", b0, b0_true)] {
        assert!(
            e.lower <= t && t <= e.upper,
            "{name}: {t} not in [{}, {}]",
            e.lower,
            e.upper
        );
    }
    assert!((k.value / k_true - 1.0).abs() < 0.10, "k {}", k.value);
    assert!((r.value / r_true - 1.0).abs() < 0.30, "r {}", r.value);
    assert!(rms > 0.5 * sigma && rms < 1.5 * sigma, "RMS {rms}");
}

/// The running-in model follows a measured reducer's lost motion (Lubricants 2025, 13(8), 362:
/// 0.712 arcmin new, about 0.888 at 600 h, 0.927 at 1550 h, and about 0.0024 arcsec/h after
/// 600 h, whence the point 0.904 at 1000 h, read off that slope rather than measured). The
/// bench's reducer is not the preset's, so the point is the shape: the RV-40E-class preset (its
/// 2 um crank-bearing clearance; its bearings and pins kept from wearing, which the fit does
/// not scale), running-in from `r` = 5 with `tau` = 200 h kept, `k`, `r`
/// and the play `b0` fitted: RMS residual below 0.01 arcmin, every coefficient plausible (`k`
/// within 0.01-10 times the example's, `r` above 1, `b0` between -0.03 arcmin and the new
/// lost motion),
/// and 1 degree of freedom left for the intervals.
#[test]
#[cfg_attr(
    target_family = "wasm",
    ignore = "calibration is not in the web build's page: run natively"
)]
fn calibration_follows_the_2025_bench_lost_motion() {
    let text = crate::config::preset_text("rv-40e").unwrap();
    let mut cfg = crate::config::Config::from_toml_str(&text, "rv-40e").unwrap();
    // The disc alone wears: the fit of its coefficient scales the hours.
    cfg.wear.bearing_archard_coefficient_mm3_per_n_m = 0.0;
    cfg.wear.pin_archard_coefficient_mm3_per_n_m = 0.0;
    cfg.dynamics.enabled = false;
    cfg.fem.enabled = false;
    let mut m = cfg.validate().unwrap();
    let k_example = m.wear.archard;
    m.wear.running_in = crate::wear::RunningIn {
        factor: 5.0,
        hours: 200.0,
    };
    let data = crate::calibration::Measurements::parse(
        std::path::Path::new("bench2025.csv"),
        "hours,lost_motion_arcmin\n0,0.712\n600,0.888\n1000,0.904\n1550,0.927\n",
    )
    .unwrap();
    let options = crate::calibration::Options {
        fit_running_in: true,
    };
    let cal = crate::calibration::calibrate(&m, &data, options, &|_| {}).unwrap();
    let k = &cal.archard_coefficient_mm3_per_n_m;
    let r = cal.running_in_factor.as_ref().unwrap();
    let b0 = cal.running_in_backlash_arcmin.as_ref().unwrap();
    let rms = cal.quantities[0].rms_residual;
    eprintln!(
        "k {:.4e} mm^3/(N m) [{:.4e}, {:.4e}]; r {:.2} [{:.2}, {:.2}]; b0 {:.4} [{:.4}, {:.4}] \
         arcmin; RMS {rms:.5} arcmin",
        k.value, k.lower, k.upper, r.value, r.lower, r.upper, b0.value, b0.lower, b0.upper
    );
    for res in &cal.residuals {
        eprintln!(
            "{} h: {:.4} measured, {:.4} model",
            res.hours, res.measured, res.model
        );
    }
    assert_eq!(cal.degrees_of_freedom, 1);
    assert!(rms < 0.01, "RMS {rms}");
    let ratio = k.value * 1e-9 / k_example;
    assert!((0.01..=10.0).contains(&ratio), "k {ratio} x the example's");
    assert!(r.value > 1.0, "r {}", r.value);
    // The model's own new lost motion (0.720 arcmin) is above the bench's: a play a little
    // below 0 is what the bench's zero asks for.
    assert!(b0.value > -0.03 && b0.value < 0.712, "b0 {}", b0.value);
}
