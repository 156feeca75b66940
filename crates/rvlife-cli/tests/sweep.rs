//! `rvlife sweep`: the design grid's order and files, each design's study equal to `rvlife run`
//! of its config, refusals before any work.

mod common;

use common::{assert_input_error, ok, rvlife, short_study_text, write_config};

/// The short study without dynamics, with a lost-motion spec.
fn base(dir: &std::path::Path) -> std::path::PathBuf {
    let text = common::set_key(&short_study_text(), "dynamics", "enabled", "false");
    let text = format!("{text}\n[life]\nlost_motion_arcmin = 0.8\n");
    write_config(dir, "base.toml", &text)
}

#[test]
fn a_sweep_runs_every_design_in_order_and_each_is_its_configs_study() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = base(dir.path());
    let out = dir.path().join("sweep");
    let o = rvlife([
        "sweep".as_ref(),
        cfg.as_os_str(),
        "--vary".as_ref(),
        "cycloid.eccentricity_mm=1.25:1.35:3".as_ref(),
        "--vary".as_ref(),
        "cycloid.modification.equidistant_mm=0.0,0.004".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let text = ok(&o, "sweep");
    assert!(text.contains("6 designs (0 failed)"), "{text}");
    let mut r = csv::Reader::from_path(out.join("sweep.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(str::to_string).collect();
    assert_eq!(
        &header[..6],
        [
            "design",
            "cycloid.eccentricity_mm",
            "cycloid.modification.equidistant_mm",
            "status",
            "accuracy_life_h",
            "limited_by"
        ]
    );
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    // Six designs of three stages each, the last key fastest.
    assert_eq!(rows.len(), 18);
    let designs: Vec<(&str, &str, &str)> = rows
        .iter()
        .step_by(3)
        .map(|r| (&r[0], &r[1], &r[2]))
        .collect();
    assert_eq!(
        designs,
        [
            ("0", "1.25", "0.0"),
            ("1", "1.25", "0.004"),
            ("2", "1.3", "0.0"),
            ("3", "1.3", "0.004"),
            ("4", "1.35", "0.0"),
            ("5", "1.35", "0.004")
        ]
    );
    // Design 5's rows are `rvlife run` of its config, column for column.
    let run = dir.path().join("run5");
    ok(
        &rvlife([
            "run".as_ref(),
            out.join("designs/design_5.toml").as_os_str(),
            "--out".as_ref(),
            run.as_os_str(),
        ]),
        "run design 5",
    );
    let stages = std::fs::read_to_string(run.join("stages.csv")).unwrap();
    let mine: Vec<String> = rows[15..18]
        .iter()
        .map(|r| r.iter().skip(6).collect::<Vec<_>>().join(","))
        .collect();
    let theirs: Vec<&str> = stages.lines().skip(1).collect();
    assert_eq!(mine, theirs);
    for f in [
        "designs.csv",
        "summary.json",
        "report.html",
        "plots/accuracy_life.svg",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["designs"].as_array().unwrap().len(), 6);
    common::assert_all_finite(&summary, "summary.json");
}

#[test]
fn bad_sweeps_are_refused_naming_the_key_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = base(dir.path());
    let out = dir.path().join("never");
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["--vary", "cycloid.eccentricty_mm=1.2,1.3"],
            &["cycloid.eccentricty_mm", "unknown field"],
        ),
        (
            &["--vary", "cycloid.eccentricity_mm=1.3,-1"],
            &["cycloid.eccentricity_mm", "design 1"],
        ),
        (
            &["--vary", "cycloid.eccentricity_mm=1.2:1.3"],
            &["--vary", "KEY=LO:HI:N"],
        ),
        (
            &["--vary", "cycloid.eccentricity_mm=1.2:1.3:0"],
            &["--vary", "N must be"],
        ),
        (
            &["--vary", "cycloid.pins=38,40", "--vary", "cycloid.pins=36"],
            &["--vary", "cycloid.pins", "once"],
        ),
        (
            &["--vary", "cycloid.pins=40", "--set", "nokey"],
            &["--set", "KEY=VALUE"],
        ),
        (
            &[
                "--vary",
                "wear.profile_update_hours=250:1:4",
                "--work-budget-min",
                "0.1",
            ],
            &["budget"],
        ),
    ];
    for (args, needles) in cases {
        let mut a: Vec<std::ffi::OsString> = vec!["sweep".into(), cfg.clone().into()];
        a.extend(args.iter().map(Into::into));
        a.extend(["--out".into(), out.clone().into_os_string()]);
        let t = std::time::Instant::now();
        let o = rvlife(&a);
        assert_input_error(&o, &format!("{args:?}"), needles);
        assert!(
            t.elapsed().as_secs_f64() < 5.0,
            "{args:?} took {:?}",
            t.elapsed()
        );
        assert!(!out.exists(), "{args:?} wrote its output");
    }
}
