//! Measured profiles: points fitted as a normal deviation map over the described profile.

use std::path::Path;

use crate::config::{Config, Model};
use crate::geometry::{Profile, WearMap};
use crate::output::export::{write_profile, ProfileFormat};
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};

fn text(measured: Option<&Path>) -> String {
    let t = crate::config::preset_text("paper")
        .unwrap()
        .replace("equidistant_mm = 0.0 ", "equidistant_mm = 0.008 ")
        .replace("offset_mm = 0.0 ", "offset_mm = -0.005 ");
    match measured {
        None => t,
        Some(p) => t.replace(
            "width_mm = 8.75 ",
            &format!("measured_profile = \"{}\"\nwidth_mm = 8.75 ", p.display()),
        ),
    }
}

fn model(measured: Option<&Path>) -> Model {
    Config::from_toml_str(&text(measured), "test")
        .unwrap()
        .validate()
        .unwrap()
}

/// Largest normal distance (m) between two profiles of the same stage and modification, on
/// 4 000 points per tooth: the difference of their deviation maps.
fn max_gap(a: &Profile, b: &Profile) -> f64 {
    let depth = |p: &Profile, t: f64| p.wear().map_or(0.0, |w| w.eval(t).0);
    (0..4000)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 4000.0;
            (depth(a, t) - depth(b, t)).abs()
        })
        .fold(0.0, f64::max)
}

/// `rvlife profile --out` files (CSV and DXF) of the modified profile, a uniformly worn one and
/// the one worn for 7 500 h, read back as `measured_profile`, give the same profile to 0.1 um
/// on 4 000 points per tooth (1e-6 um measured: the files' rounding); the STE of the measured
/// worn profile equals that of the worn model to 1e-6 (3e-9 measured).
#[test]
#[cfg_attr(
    target_family = "wasm",
    ignore = "reads files the config names: the wasm build has no file system"
)]
fn exported_profiles_round_trip_through_measured_profile() {
    let dir = tempfile::tempdir().unwrap();
    let m = model(None);
    let mut worn = m.clone();
    worn.wear.stage_hours = vec![7500.0];
    let hist = crate::wear::integrate(&worn.wear_inputs(), &|_, _| {}).unwrap();
    let n = hist.maps[0].len();
    let cases = [
        ("modified", m.profile().unwrap()),
        (
            "uniform",
            m.cycloid
                .profile(Some(WearMap::uniform(n, 20e-6).unwrap()))
                .unwrap(),
        ),
        (
            "7500h",
            m.cycloid
                .profile(Some(WearMap::new(hist.maps[0].clone()).unwrap()))
                .unwrap(),
        ),
    ];
    for (name, original) in &cases {
        for (ext, fmt) in [("csv", ProfileFormat::Csv), ("dxf", ProfileFormat::Dxf)] {
            let path = dir.path().join(format!("{name}.{ext}"));
            write_profile(original, &path, fmt).unwrap();
            let mm = model(Some(&path));
            let fit = mm.cycloid.measured.as_ref().unwrap();
            let back = mm.profile().unwrap();
            let gap = max_gap(original, &back);
            assert!(gap < 0.1e-6, "{name}.{ext}: {:e} um", gap * 1e6);
            assert!(
                fit.fit_max < 0.1e-6,
                "{name}.{ext}: residual {:e}",
                fit.fit_max
            );
            // The measured deviation is not wear.
            assert!(
                mm.cycloid.wear_depth(&back) < 1e-9,
                "{name}: wear {}",
                mm.cycloid.wear_depth(&back)
            );
        }
    }
    let path = dir.path().join("7500h.csv");
    let mm = model(Some(&path));
    let a = crate::te::static_te(&mm.reducer, &mm.profile().unwrap(), 12).unwrap();
    let b = crate::te::static_te(&m.reducer, &cases[2].1, 12).unwrap();
    for (x, y) in a.forward.iter().zip(&b.forward) {
        assert!((x - y).abs() < 1e-6 * y.abs().max(1e-6), "{x} vs {y}");
    }
}

/// A known deviation (a 5 um bump of material missing and a 2 um ridge of excess material
/// elsewhere on the flank) is recovered to 1e-3 um from exact points; with Gaussian noise of
/// 0.3 um on every coordinate the map is within 0.15 um of it (each of the 720 nodes is fitted
/// from about 78 points: a standard error near 0.04 um) and the reported RMS residual is the
/// noise's normal component, 0.3 um, within 10 %.
#[test]
#[cfg_attr(
    target_family = "wasm",
    ignore = "reads files the config names: the wasm build has no file system"
)]
fn a_known_deviation_is_recovered_from_measured_points() {
    let dir = tempfile::tempdir().unwrap();
    let m = model(None);
    let n = m.cycloid.geometry.pins * m.wear.crank_steps;
    let bump: Vec<f64> = (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            let g = |c: f64, w: f64| (-0.5 * ((t - c) / w).powi(2)).exp();
            5e-6 * g(1.6, 0.2) - 2e-6 * g(4.4, 0.15)
        })
        .collect();
    let truth = m
        .cycloid
        .profile(Some(WearMap::deviation(bump).unwrap()))
        .unwrap();
    let path = dir.path().join("bump.csv");
    write_profile(&truth, &path, ProfileFormat::Csv).unwrap();
    let exact = model(Some(&path));
    let gap = max_gap(&truth, &exact.profile().unwrap());
    assert!(gap < 1e-9, "exact points: {:e} um", gap * 1e6);
    // Noisy points.
    let text = std::fs::read_to_string(&path).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let noise = Normal::new(0.0, 0.3e-3).unwrap();
    let mut out = String::from("x_mm,y_mm\n");
    for line in text.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        out.push_str(&format!(
            "{},{}\n",
            f[0] + noise.sample(&mut rng),
            f[1] + noise.sample(&mut rng)
        ));
    }
    let noisy = dir.path().join("noisy.csv");
    std::fs::write(&noisy, out).unwrap();
    let mm = model(Some(&noisy));
    let gap = max_gap(&truth, &mm.profile().unwrap());
    assert!(gap < 0.15e-6, "noisy points: {:e} um", gap * 1e6);
    let rms = mm.cycloid.measured.as_ref().unwrap().fit_rms;
    assert!(
        (rms / 0.3e-6 - 1.0).abs() < 0.1,
        "RMS residual {:e} um",
        rms * 1e6
    );
}

/// Bad files exit 2 (`Error::Invalid`) naming `cycloid.measured_profile`, before any work.
#[test]
#[cfg_attr(
    target_family = "wasm",
    ignore = "reads files the config names: the wasm build has no file system"
)]
fn bad_measured_profiles_are_refused_with_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.csv");
    write_profile(&model(None).profile().unwrap(), &good, ProfileFormat::Csv).unwrap();
    let lines: Vec<String> = std::fs::read_to_string(&good)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    let write = |name: &str, body: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, body).unwrap();
        p
    };
    let metres: String = std::iter::once("x_mm,y_mm".to_string())
        .chain(lines[1..].iter().map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            format!("{},{}", f[0] * 1e-3, f[1] * 1e-3)
        }))
        .collect::<Vec<_>>()
        .join("\n");
    let half = lines.len() / 80; // a fraction of the first tooth only
    let cases = [
        dir.path().join("missing.csv"),
        write("few.csv", &lines[..10].join("\n")),
        write("metres.csv", &metres),
        write("columns.csv", &lines.join("\n").replace("x_mm", "x")),
        write(
            "nan.csv",
            &format!("{}\nNaN,1.0\n", lines[..100].join("\n")),
        ),
        write("partial.csv", &lines[..half].join("\n")),
    ];
    for p in &cases {
        let e = Config::from_toml_str(&text(Some(p)), "test")
            .unwrap()
            .validate()
            .unwrap_err();
        assert!(
            matches!(e, crate::Error::Invalid { .. })
                && e.to_string().contains("cycloid.measured_profile"),
            "{}: {e}",
            p.display()
        );
    }
}
