//! Physics checks that can fail: closed forms, limits, conservation (issue 2 "Must show").

use std::f64::consts::TAU;

use rvlife::config::{Config, Model, WearModelKind};
use rvlife::contact::{
    first_contact, li_load_distribution, pin_geometries, solve, ApproachLaw, ContactModel,
    Materials,
};
use rvlife::geometry::{CycloidGeometry, Modification, Profile, WearMap};
use rvlife::te::{static_te, ARCMIN_PER_RAD};

fn model() -> Model {
    Config::example().validate().unwrap()
}

fn paper_geometry() -> CycloidGeometry {
    model().geometry
}

fn steel() -> Materials {
    Materials {
        disc_youngs_modulus: 219e9,
        disc_poisson_ratio: 0.3,
        pin_youngs_modulus: 219e9,
        pin_poisson_ratio: 0.3,
    }
}

/// Physics-notes section 2: the unmodified profile touches every pin at every crank angle.
#[test]
fn unmodified_profile_touches_every_pin() {
    let profile = Profile::new(paper_geometry(), Modification::default(), None).unwrap();
    let mut worst: f64 = 0.0;
    for k in 0..97 {
        let phi = k as f64 * 0.1371; // many crank angles, not commensurate with the pin pitch
        for g in pin_geometries(&profile, phi, 0.0).unwrap() {
            worst = worst.max(g.gap.abs());
        }
    }
    // 1e-9 mm = 1e-12 m.
    assert!(worst < 1e-12, "largest |gap| = {worst:e} m");
}

/// Li's lever arms: l_j = a Zc sin(t_j) / S(t_j) from the exact geometry.
#[test]
fn lever_arms_match_li() {
    let geo = paper_geometry();
    let profile = Profile::new(geo.clone(), Modification::default(), None).unwrap();
    let k1 = geo.k1();
    for phi in [0.0, 0.05, 0.1] {
        for g in pin_geometries(&profile, phi, 0.0).unwrap() {
            let t = TAU * g.pin as f64 / 40.0 - phi;
            let li =
                geo.disc_pitch_radius() * t.sin() / (1.0 + k1 * k1 - 2.0 * k1 * t.cos()).sqrt();
            assert!(
                (g.lever_arm - li).abs() < 1e-12,
                "pin {}: {} vs {}",
                g.pin,
                g.lever_arm,
                li
            );
        }
    }
}

/// With a linear contact law the load distribution equals Li's closed form within 0.5 % of the
/// peak force. Li's form is the small-rotation limit: the exact geometry adds a second-order
/// closing of the pin sitting in the near-conformal root (gap ~ -(beta R)^2 / (2 rho_c)), so the
/// springs are stiff enough (5 kN/um) to keep the rotation, and that term, small.
#[test]
fn linear_law_reproduces_li_distribution() {
    let geo = paper_geometry();
    let profile = Profile::new(geo.clone(), Modification::default(), None).unwrap();
    let model = ContactModel {
        law: ApproachLaw::Linear { stiffness: 5e9 },
        materials: steel(),
        width: geo.width,
        pin_radius: geo.pin_radius,
        max_radius: geo.pin_circle_radius,
    };
    let t_disc = 0.55 * 412.0;
    for phi in [0.0, 0.031, 0.077, 0.12] {
        let sol = solve(&profile, &model, phi, t_disc).unwrap();
        let li = li_load_distribution(&geo, phi, t_disc);
        let fmax = li.iter().copied().fold(0.0, f64::max);
        for (p, f) in sol.pins.iter().zip(&li) {
            assert!(
                (p.force - f).abs() <= 0.005 * fmax,
                "phi {phi}, pin {}: {} N vs Li {} N",
                p.pin,
                p.force,
                f
            );
        }
        // Li's approximation F_max ~ 4 T_disc / (a Zc Zp) = 447 N.
        assert!((fmax - 447.0).abs() < 0.02 * 447.0, "{fmax}");
    }
}

/// The sum of pin moments equals the disc torque (equilibrium), for both load directions and
/// for worn and modified discs.
#[test]
fn pin_moments_balance_the_disc_torque() {
    let m = model();
    let wear: Vec<f64> = (0..720)
        .map(|i| {
            let t = TAU * i as f64 / 720.0;
            if t < std::f64::consts::PI {
                20e-6 * t.sin().powi(2)
            } else {
                0.0
            }
        })
        .collect();
    let profiles = [
        m.profile(None).unwrap(),
        m.profile(Some(WearMap::new(wear).unwrap())).unwrap(),
        Profile::new(
            m.geometry.clone(),
            Modification {
                equidistant: 10e-6,
                offset: -5e-6,
                rotation: 0.0,
            },
            None,
        )
        .unwrap(),
    ];
    for profile in &profiles {
        for torque in [226.6, -226.6, 50.0] {
            for phi in [0.0, 0.05, 0.11] {
                let sol = solve(profile, &m.contact, phi, torque).unwrap();
                let rel = (sol.pin_moment() - torque).abs() / torque.abs();
                assert!(
                    rel < 1e-9,
                    "torque {torque}, phi {phi}: moment {}",
                    sol.pin_moment()
                );
                assert!(sol
                    .pins
                    .iter()
                    .all(|p| p.force >= 0.0 && p.force.is_finite()));
            }
        }
    }
}

/// A uniform equidistant modification drrp gives lost motion 2 drrp / (a Zc) within 1 %
/// (physics-notes section 6).
#[test]
fn equidistant_modification_lost_motion() {
    let geo = paper_geometry();
    for drrp in [5e-6, 10e-6, 30e-6] {
        let profile = Profile::new(
            geo.clone(),
            Modification {
                equidistant: drrp,
                ..Default::default()
            },
            None,
        )
        .unwrap();
        let ste = static_te(&profile, 24).unwrap();
        let expected = 2.0 * drrp / geo.disc_pitch_radius();
        let lm = ste.lost_motion_stats();
        for v in [lm.mean, lm.max, lm.min] {
            assert!(
                (v / expected - 1.0).abs() < 0.01,
                "drrp {drrp}: {v} vs {expected}"
            );
        }
        // Each side alone: drrp / (a Zc) within 1 % (0.678 arcmin per 10 um).
        let fwd = ste.stats().mean;
        assert!((fwd / (0.5 * expected) - 1.0).abs() < 0.01);
    }
    let per_10um = 10e-6 / geo.disc_pitch_radius() * ARCMIN_PER_RAD;
    assert!((per_10um - 0.678).abs() < 0.001, "{per_10um}");
}

/// Uniform wear through the wear map equals the equidistant modification.
#[test]
fn uniform_wear_map_equals_equidistant() {
    let geo = paper_geometry();
    let worn = Profile::new(
        geo.clone(),
        Modification::default(),
        Some(WearMap::uniform(720, 10e-6).unwrap()),
    )
    .unwrap();
    let eq = Profile::new(
        geo,
        Modification {
            equidistant: 10e-6,
            ..Default::default()
        },
        None,
    )
    .unwrap();
    for phi in [0.0, 0.07] {
        let a = first_contact(&worn, phi, 1.0).unwrap();
        let b = first_contact(&eq, phi, 1.0).unwrap();
        assert!((a - b).abs() < 1e-12 * b.abs().max(1e-9), "{a} {b}");
    }
}

/// Hertz half-width, pressure and both approach laws against a hand calculation
/// (F = 447 N, B = 8.75 mm, steel, pin 3 mm on a convex 5 mm flank).
#[test]
fn hertz_against_hand_calculation() {
    let mut m = ContactModel {
        law: ApproachLaw::Paper,
        materials: steel(),
        width: 8.75e-3,
        pin_radius: 3e-3,
        max_radius: 64e-3,
    };
    let h = m.hertz(447.0, 1.0 / 5e-3);
    // b = sqrt(4 F R* / (pi B E*)), R* = 1.875 mm, E* = 120.33 GPa.
    assert!((h.half_width / 3.183604185328929e-05 - 1.0).abs() < 1e-12);
    assert!((h.max_pressure / 1021552112.2154368 - 1.0).abs() < 1e-12);
    assert!((h.mean_pressure / h.max_pressure - std::f64::consts::PI / 4.0).abs() < 1e-12);
    let d = m.approach(447.0, 1.0 / 5e-3);
    assert!((d / 1.7624156801261954e-06 - 1.0).abs() < 1e-12, "{d}");
    // The inverse law returns the force.
    let (f, k) = m.force(d, 1.0 / 5e-3).unwrap();
    assert!((f / 447.0 - 1.0).abs() < 1e-10, "{f}");
    let e = 1e-9;
    let fd = (m.force(d + e, 0.2e3).unwrap().0 - m.force(d - e, 0.2e3).unwrap().0) / (2.0 * e);
    assert!((k / fd - 1.0).abs() < 1e-5, "{k} {fd}");
    m.law = ApproachLaw::Johnson;
    let dj = m.approach(447.0, 1.0 / 5e-3);
    assert!((dj / 1.537185999929665e-06 - 1.0).abs() < 1e-12, "{dj}");
    // The notes: the two forms differ by roughly 11 % (15 % here).
    assert!(d / dj > 1.05 && d / dj < 1.2);
}

/// Without profile updates the wear map is the rate times the hours: linear in hours.
#[test]
fn wear_is_linear_in_hours_without_updates() {
    let mut m = model();
    m.update_hours = 0.0;
    m.stage_hours = vec![0.0, 1000.0, 2000.0, 4000.0];
    let hist = rvlife::wear::integrate(&m, &|_, _| {}).unwrap();
    assert_eq!(hist.rate_evaluations, 1);
    let base = &hist.maps[1];
    assert!(base.iter().copied().fold(0.0, f64::max) > 0.0);
    for (s, factor) in [(2, 2.0), (3, 4.0)] {
        for (a, b) in hist.maps[s].iter().zip(base) {
            assert!((a - factor * b).abs() <= 1e-12 * a.abs().max(1e-18));
        }
    }
    assert!(hist.maps[0].iter().all(|&x| x == 0.0));
}

/// Wear with profile updates stays on the loaded flank, grows monotonically with hours, and
/// feeds back: the worn disc carries the rated torque on larger pin forces (paper Fig. 8 trend).
#[test]
fn wear_with_updates_grows_and_concentrates_load() {
    let mut m = model();
    m.stage_hours = vec![0.0, 1000.0, 2000.0];
    let hist = rvlife::wear::integrate(&m, &|_, _| {}).unwrap();
    let n = hist.maps[0].len();
    let max = hist.max_depths();
    assert!(max[1] > 0.0 && max[2] > max[1]);
    for map in &hist.maps {
        // No wear on the unloaded flank (mesh angles 181..359 deg).
        // (The Hertz-band filter spreads a trace of the tip and root wear over a few degrees.)
        let peak = map.iter().copied().fold(0.0, f64::max);
        for (i, h) in map.iter().enumerate() {
            let deg = 360.0 * i as f64 / n as f64;
            if deg > 190.0 && deg < 350.0 {
                assert_eq!(*h, 0.0, "wear on the unloaded flank at {deg} deg");
            } else if deg > 181.0 {
                assert!(*h <= 1e-3 * peak, "wear on the unloaded flank at {deg} deg");
            }
        }
    }
    let new = m.profile(None).unwrap();
    let worn = m
        .profile(Some(WearMap::new(hist.maps[2].clone()).unwrap()))
        .unwrap();
    let f_new = solve(&new, &m.contact, 0.0, 226.6).unwrap();
    let f_worn = solve(&worn, &m.contact, 0.0, 226.6).unwrap();
    assert!(f_worn.max_force() > f_new.max_force());
    assert!(f_worn.disc_rotation > f_new.disc_rotation);
}

/// Kinematics (physics-notes section 1): i_H = 1 + (Z2/Z1) Zp, mesh cycles per hour.
#[test]
fn reducer_kinematics() {
    let m = model();
    assert_eq!(m.ratio, 81.0);
    let c = m.mesh_cycles_per_hour(1500.0);
    assert!((c - 60.0 * 1500.0 * 40.0 / 81.0).abs() < 1e-9);
}

/// The paper's wear model (eqs 11-20 as printed) is linear in hours and its TE uses a uniform
/// offset equal to the maximum wear.
#[test]
fn paper_wear_model() {
    let mut m = model();
    m.wear_model = WearModelKind::Paper;
    m.stage_hours = vec![0.0, 1000.0, 2000.0];
    let study = rvlife::study::run(&m, &|_, _| {}).unwrap();
    let max = study.wear.max_depths();
    assert!((max[2] / max[1] - 2.0).abs() < 1e-9);
    let s = &study.stages[2];
    let expected = max[2] / m.geometry.disc_pitch_radius() * ARCMIN_PER_RAD;
    assert!((s.summary.ste_mean_arcmin / expected - 1.0).abs() < 0.01);
}

/// The built-in example is calibrated to the paper's 60 um of maximum wear at 7500 h.
#[test]
fn example_is_calibrated_to_sixty_microns() {
    let m = model();
    let hist = rvlife::wear::integrate(&m, &|_, _| {}).unwrap();
    let last = *hist.max_depths().last().unwrap();
    assert!((last * 1e6 - 60.0).abs() < 1.5, "{} um", last * 1e6);
}

/// On a disc worn by the wear model (with its wear ripple at the pin pitch and an unworn root
/// that closes on its pin as the disc turns), the solved pose still balances the torque at every
/// crank angle of a mesh cycle, and no driving pin penetrates at first contact by more than
/// 0.2 um (pins at the root and tip, whose lever arm at the nominal pose is below 2 % of `a Zc`,
/// close only to second order and are left out of the geometric first contact by definition).
/// The 0.2 um bound is a regression guard, not a physical tolerance: near a worn, near-conformal
/// root the closest point can switch between two local feet as the disc turns, so the gap of a
/// pin there jumps by up to ~0.1 um (a known limitation of the projection).
#[test]
fn worn_disc_contact_balances_over_a_mesh_cycle() {
    let mut m = model();
    m.stage_hours = vec![4000.0];
    let hist = rvlife::wear::integrate(&m, &|_, _| {}).unwrap();
    let worn = m
        .profile(Some(WearMap::new(hist.maps[0].clone()).unwrap()))
        .unwrap();
    for k in 0..18 {
        let phi = TAU * k as f64 / (40.0 * 18.0);
        let sol = solve(&worn, &m.contact, phi, 226.6).unwrap();
        let rel = (sol.pin_moment() - 226.6).abs() / 226.6;
        assert!(rel < 1e-8, "phi {phi}: moment {}", sol.pin_moment());
        let b0 = first_contact(&worn, phi, 1.0).unwrap();
        let lmin = 0.02 * m.geometry.disc_pitch_radius();
        let nominal = pin_geometries(&worn, phi, 0.0).unwrap();
        for g in pin_geometries(&worn, phi, b0).unwrap() {
            if nominal[g.pin].lever_arm > lmin {
                assert!(g.gap > -2e-7, "phi {phi}: pin {} gap {:e}", g.pin, g.gap);
            }
        }
    }
}

/// Load spectra: a duty cycle that runs at rated torque half of the time and idles the other
/// half wears at half the constant-torque rate; a sinusoid about zero wears both flanks alike.
#[test]
fn load_spectra_scale_the_wear() {
    let dir = tempfile::tempdir().unwrap();
    let duty = dir.path().join("duty.csv");
    std::fs::write(
        &duty,
        "duration_s,torque_nm,speed_rpm\n2.0,412.0,1500.0\n2.0,0.0,1500.0\n",
    )
    .unwrap();
    let base = rvlife::config::EXAMPLE_TOML
        .replace("profile_update_hours = 250.0", "profile_update_hours = 0.0");
    let text = base.replace(
        "kind = \"constant\"              # \"constant\", \"sinusoidal\" or \"duty_cycle\"\ntorque_nm = 412.0",
        &format!("kind = \"duty_cycle\"\nfile = \"{}\"", duty.display()),
    );
    assert!(text.contains("duty_cycle"));
    let constant = Config::from_toml_str(&base, "x")
        .unwrap()
        .validate()
        .unwrap();
    let halved = Config::from_toml_str(&text, "x")
        .unwrap()
        .validate()
        .unwrap();
    let a = rvlife::wear::integrate(&constant, &|_, _| {}).unwrap();
    let b = rvlife::wear::integrate(&halved, &|_, _| {}).unwrap();
    let (ma, mb) = (a.max_depths()[6], b.max_depths()[6]);
    assert!((mb / ma - 0.5).abs() < 1e-9, "{ma} {mb}");

    let sine = base.replace(
        "kind = \"constant\"              # \"constant\", \"sinusoidal\" or \"duty_cycle\"\ntorque_nm = 412.0",
        "kind = \"sinusoidal\"\namplitude_nm = 412.0\noffset_nm = 0.0\nperiod_s = 0.3\nlevels = 24",
    );
    let m = Config::from_toml_str(&sine, "x")
        .unwrap()
        .validate()
        .unwrap();
    let h = rvlife::wear::integrate(&m, &|_, _| {}).unwrap();
    let map = &h.maps[6];
    let n = map.len();
    // Mirror symmetry of the tooth: mesh angle t on one flank pairs with 2 pi - t on the other.
    let peak = map.iter().copied().fold(0.0, f64::max);
    for i in 1..n / 2 {
        assert!(
            (map[i] - map[n - i]).abs() < 0.02 * peak,
            "{i}: {} {}",
            map[i],
            map[n - i]
        );
    }
}
