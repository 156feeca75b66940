//! Single-stage cycloid drives: input on the eccentric shaft, output by pins in holes.

use crate::config::{preset_text, Config, Model};
use crate::statics::StaticAnalysis;
use crate::te::mesh_cycle_angles;
use crate::units::ARCMIN_PER_RAD;

fn config_text(discs: usize, equidistant_mm: f64) -> String {
    preset_text("single-stage")
        .unwrap()
        .replace("discs = 2 ", &format!("discs = {discs} "))
        .replace(
            "equidistant_mm = 0.008  # (preset)",
            &format!("equidistant_mm = {equidistant_mm}"),
        )
        .replace("offset_mm = -0.005  # (preset)", "offset_mm = 0.0")
}

fn model(discs: usize, equidistant_mm: f64) -> Model {
    Config::from_toml_str(&config_text(discs, equidistant_mm), "test")
        .unwrap()
        .validate()
        .unwrap()
}

/// Kinematics: the ratio is `-Zc`, the locked-input mode turns the discs with the output and
/// leaves the eccentric still, so the unmodified stage touches at zero twist at every crank
/// angle, and an equidistant modification `D` gives a first-contact twist of at least
/// `D / (a Zc)`: the largest lever of a pin is the disc's pitch radius `a Zc` (where
/// `cos x = K1`), reached to 1e-3 by the nearest pin; RV's `a (Zp + Z1/Z2)` becomes `a Zc`
/// without a first stage. Within 0.2 %: the contact geometry is the flank averaged over the
/// Hertz band, 0.085 % below the exact equidistant curve's twist here. Scanned over 90 crank
/// angles of a mesh cycle, 1, 2 and 3 discs.
#[test]
fn single_stage_kinematics_and_uniform_play() {
    for discs in 1..=3 {
        let m = model(discs, 0.0);
        assert_eq!(m.reducer.ratio, -(m.cycloid.geometry.disc_teeth() as f64));
        let p = m.profile().unwrap();
        let sa = StaticAnalysis::new(&m.reducer, &p).unwrap();
        for phi in mesh_cycle_angles(m.cycloid.geometry.pins, 90) {
            for s in [1.0, -1.0] {
                let t = sa.first_contact(phi, s).unwrap();
                assert!(t.abs() * ARCMIN_PER_RAD < 1e-6, "{discs} discs: {t:e} rad");
            }
        }
        let d = 0.01e-3;
        let m = model(discs, 0.01);
        let p = m.profile().unwrap();
        let sa = StaticAnalysis::new(&m.reducer, &p).unwrap();
        let closed = d / (m.cycloid.geometry.eccentricity * m.cycloid.geometry.disc_teeth() as f64);
        let mut lo = f64::INFINITY;
        for phi in mesh_cycle_angles(m.cycloid.geometry.pins, 90) {
            let t = sa.first_contact(phi, 1.0).unwrap();
            assert!(t >= closed * (1.0 - 2e-3), "{discs} discs: {t} < {closed}");
            lo = lo.min(t);
        }
        assert!(
            lo <= closed * 1.002,
            "{discs} discs: smallest {lo}, closed form {closed}"
        );
    }
}

/// Equilibrium and load sharing from the model: the discs' pin moments sum to the output
/// torque (no first stage: twist factor 1) to 3e-5 at 24 crank angles and three torques
/// (1.0e-5 measured with roller eccentric bearings, 1.1e-6 with linear ones: the pins-in-holes
/// forces act on the deflected discs);
/// three discs 120 deg apart share it within 5 % of a third each on the mesh-cycle mean, two
/// discs 180 deg apart equally to 1e-6.
#[test]
fn single_stage_discs_share_the_output_torque() {
    for discs in [2, 3] {
        let m = model(discs, 0.008);
        let p = m.profile().unwrap();
        let sa = StaticAnalysis::new(&m.reducer, &p).unwrap();
        let mut share = vec![0.0; discs];
        let phis = mesh_cycle_angles(m.cycloid.geometry.pins, 24);
        for t in [-412.0, 41.2, 412.0] {
            for &phi in &phis {
                let sol = sa.solve(phi, t).unwrap();
                assert_eq!(sol.discs.len(), discs);
                let sum: f64 = sol.discs.iter().map(|d| d.torque).sum();
                assert!(
                    (sum - t).abs() < 3e-5 * t.abs(),
                    "{discs} discs: {sum} vs {t}"
                );
                if t == 412.0 {
                    for (s, d) in share.iter_mut().zip(&sol.discs) {
                        *s += d.torque / sum / phis.len() as f64;
                    }
                }
            }
        }
        for s in &share {
            let tol = if discs == 2 { 1e-6 } else { 0.05 };
            assert!(
                (s * discs as f64 - 1.0).abs() < tol,
                "{discs} discs: shares {share:?}"
            );
        }
    }
}

/// What belongs to the other drive is refused, naming the key.
#[test]
fn single_stage_input_errors_name_their_key() {
    let err = |text: String| {
        Config::from_toml_str(&text, "test")
            .unwrap()
            .validate()
            .unwrap_err()
            .to_string()
    };
    let base = config_text(2, 0.0);
    for (text, key) in [
        (
            base.replace("discs = 2 ", "discs = 2\nplanets = 2\n"),
            "reducer.planets",
        ),
        (base.replace("discs = 2 ", "discs = 4 "), "reducer.discs"),
        (
            base.replace("discs = 2 ", "discs = 2\ndisc_phases_deg = [0.0]\n"),
            "reducer.disc_phases_deg",
        ),
        (
            base.replace("circle_radius_mm = 40.5", "circle_radius_mm = 55.0"),
            "reducer.output_pins.circle_radius_mm",
        ),
        (
            base.replace("count = 8", "count = 2"),
            "reducer.output_pins.count",
        ),
        (
            base.replace("drive = \"single_stage\"", "drive = \"planetary\""),
            "reducer.drive",
        ),
    ] {
        let e = err(text);
        assert!(e.contains(key), "{key}: {e}");
    }
    // Dynamics and the flexible disc are refused for a single-stage drive.
    let t = base.replacen(
        "[dynamics]\nenabled = false",
        "[dynamics]\nenabled = true",
        1,
    );
    if t != base {
        assert!(err(t).contains("dynamics.enabled"));
    }
    // RV keys of the single stage are refused for an RV reducer.
    let rv = crate::config::preset_text("paper")
        .unwrap()
        .replace("planets = 2 ", "planets = 2\ndiscs = 3\n");
    assert!(err(rv).contains("reducer.discs"));
}

/// The hysteresis curve of a single-stage drive with play in its eccentric bearings
/// (clearances of 0.5-9.85 um, every crank angle of the study's mesh cycle, ten levels per
/// quarter): every solve converges (the eccentric free inside its clearance while no pin
/// holds it made the inner tangent singular, and the analysis failed). On the unmodified disc
/// the play grows by the pitch-point closed form `c/(a Zc)` (docs/model.md section 5.10: the
/// centre play `c/2` adds `c/(2 a Zc)` per side) within 1 % of that rise; on the preset's
/// modified disc, which touches the pins on one flank each way and can also shift along the
/// line of centres, by more than that and increasingly with the clearance.
#[test]
fn single_stage_hysteresis_with_play_in_the_eccentric_bearings() {
    let backlash = |text: &str, c: f64| -> (f64, f64) {
        let with = text.replace(
            "crank_disc_clearance_um = 0.0",
            &format!("crank_disc_clearance_um = {c}"),
        );
        assert_ne!(with, text, "the preset names the clearance");
        let m = Config::from_toml_str(&with, "test")
            .unwrap()
            .validate()
            .unwrap();
        let profile = m.cycloid.profile(None).unwrap();
        let phis = mesh_cycle_angles(m.reducer.geometry.pins, m.te.samples);
        let (_, mean) = crate::te::hysteresis(
            &m.reducer,
            &profile,
            &phis,
            m.rating.rated_torque,
            m.te.measuring_torque_fraction,
            10,
        )
        .unwrap_or_else(|e| panic!("clearance {c} um: {e}"));
        let geo = &m.reducer.geometry;
        let rise = c * 1e-6 / (geo.eccentricity * geo.disc_teeth() as f64);
        (mean.accuracy().backlash, rise)
    };
    let arcmin = |x: f64| x * ARCMIN_PER_RAD;
    for (name, text, unmodified) in [
        ("unmodified", config_text(2, 0.0), true),
        ("preset", preset_text("single-stage").unwrap(), false),
    ] {
        let (b0, _) = backlash(&text, 0.0);
        let mut last = 0.0;
        for c in [0.5, 1.0, 2.07, 5.0, 9.85] {
            let (b, rise) = backlash(&text, c);
            let got = b - b0;
            let ok = if unmodified {
                (got - rise).abs() < 0.01 * rise
            } else {
                got > rise && got > last
            };
            assert!(
                ok,
                "{name}, clearance {c} um: the backlash rose {:.5} arcmin against {:.5}",
                arcmin(got),
                arcmin(rise)
            );
            last = got;
        }
    }
}
