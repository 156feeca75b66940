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
