//! Integration tests of the `rvlife` command-line binary: every command on the built-in example
//! or an edited copy of it (written to a temporary directory), each run as a separate process of
//! the release binary.

mod common;

use common::*;

// ---------------------------------------------------------------------------------------------
// 1. The example config parses back; the contact JSON.

#[test]
fn example_parses_back_and_contact_json_has_the_documented_keys() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "example.toml", &paper_text());
    let v = contact_json(&cfg, "0", "412");
    for key in [
        "twist_arcmin",
        "first_contact_arcmin",
        "max_force_n",
        "pins_in_contact",
        "max_pressure_mpa",
        "residual",
        "discs",
    ] {
        assert!(v.get(key).is_some(), "contact JSON lacks {key:?}: {v}");
    }
    let discs = v["discs"].as_array().expect("discs array");
    assert_eq!(discs.len(), 2, "both discs on their bearings");
    let mut all_max: f64 = 0.0;
    for d in discs {
        let forces = num_array(d, "pin_forces_n");
        assert_eq!(forces.len(), PINS);
        assert!(
            forces.iter().all(|f| f.is_finite() && *f >= 0.0),
            "{forces:?}"
        );
        let max = forces.iter().copied().fold(0.0, f64::max);
        all_max = all_max.max(max);
        assert_rel(num(d, "max_force_n"), max, 1e-12, "max_force_n of a disc");
        let in_contact = forces.iter().filter(|f| **f > 0.0).count();
        assert_eq!(d["pins_in_contact"].as_u64(), Some(in_contact as u64));
        // About half the pins carry load on one flank (Li: Zp/2 for an unmodified disc).
        assert!(
            (10..=PINS / 2 + 1).contains(&in_contact),
            "pins in contact: {in_contact}"
        );
        let pins = d["pins"].as_array().expect("pins array");
        assert_eq!(pins.len(), PINS);
        for (j, p) in pins.iter().enumerate() {
            assert_eq!(p["pin"].as_u64(), Some(j as u64), "pins[] in pin order");
            assert_eq!(num(p, "force_n"), forces[j], "pins[{j}].force_n");
        }
    }
    assert_rel(num(&v, "max_force_n"), all_max, 1e-12, "max_force_n");
    assert!(num(&v, "twist_arcmin") > 0.0);
    assert!(num(&v, "residual") <= 1e-9);
    assert!(num(&v, "max_pressure_mpa") > 0.0);
    // The built-in config (no CONFIG argument) is the same as the printed example.
    let printed = ok(&rvlife(["example"]), "rvlife example");
    let printed = write_config(dir.path(), "printed.toml", &printed);
    let v = contact_json(&printed, "0", "412");
    let builtin = json_ok(
        &rvlife([
            "contact",
            "--crank-deg",
            "0",
            "--torque-nm",
            "412",
            "--json",
        ]),
        "contact on the built-in example",
    );
    assert_eq!(builtin["discs"], v["discs"]);
}

/// Moment balance of the reducer: the two discs' pin moments add up to the equivalent disc
/// torque `T Zc/(Zp + Z1/Z2)` (the first stage turns the cranks as the output twists), the
/// residual is below 1e-9, and each disc's `pin_moment_nm` is the sum over its `pins`.
#[test]
fn contact_pin_moments_balance_the_output_torque() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "example.toml", &paper_text());
    let factor = DISC_TEETH / (PINS as f64 + 0.5);
    for (crank, torque) in [
        ("0", RATED_TORQUE_NM),
        ("0", -RATED_TORQUE_NM),
        ("0.75", RATED_TORQUE_NM),
        ("4.5", 50.0),
    ] {
        let v = contact_json(&cfg, crank, &torque.to_string());
        let what = format!("crank {crank} deg, {torque} N m");
        assert!(num(&v, "residual") <= 1e-9, "{what}: residual");
        let mut total = 0.0;
        for d in v["discs"].as_array().unwrap() {
            let moment: f64 = d["pins"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| num(p, "force_n") * num(p, "lever_arm_mm") / 1000.0)
                .sum();
            assert_rel(moment, num(d, "pin_moment_nm"), 1e-9, &what);
            total += moment;
        }
        // The bearings and meshes carry a little of the moment as the discs translate.
        assert_rel(
            total,
            torque * factor,
            0.02,
            &format!("sum of pin moments, {what}"),
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Negative torque loads the other flank.

#[test]
fn contact_negative_torque_mirrors_the_forces() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "example.toml", &paper_text());
    let pos = contact_json(&cfg, "0", "412");
    let neg = contact_json(&cfg, "0", "-412");
    let rp = num(&pos, "twist_arcmin");
    let rn = num(&neg, "twist_arcmin");
    assert!(rp > 0.0, "positive torque: twist {rp}");
    assert!(rn < 0.0, "negative torque: twist {rn}");
    // The first stage's lines of action are not mirror-symmetric: a few parts per million.
    assert_rel(rn, -rp, 1e-4, "mirrored twist");
    let fp = num_array(&pos["discs"][0], "pin_forces_n");
    let fn_ = num_array(&neg["discs"][0], "pin_forces_n");
    assert_eq!(fp.len(), PINS);
    assert_eq!(fn_.len(), PINS);
    let fmax = fp.iter().copied().fold(0.0, f64::max);
    assert!(fmax > 0.0);
    for j in 0..PINS {
        let a = fp[j];
        let b = fn_[(PINS - j) % PINS];
        // The roller bearings' stiffness follows their load, which the first stage's
        // asymmetric lines of action make differ slightly between the senses (3.1e-3 of the
        // largest force measured with the structure in series; 1e-3 with linear bearings).
        assert!(
            (a - b).abs() <= 4e-3 * fmax,
            "pin {j} at +412 N m: {a} N; pin {} at -412 N m: {b} N",
            (PINS - j) % PINS
        );
    }
    // The largest force is one of the pins above, under the same bound (1.2e-3 measured with
    // the cranks' torsion in series with the meshes, which softens the first stage).
    assert_rel(
        num(&neg, "max_force_n"),
        num(&pos, "max_force_n"),
        3e-3,
        "max force",
    );
}

#[test]
fn te_json_unworn_is_zero() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "paper.toml", &paper_text());
    let v = json_ok(
        &rvlife(["te".as_ref(), cfg.as_os_str(), "--json".as_ref()]),
        "rvlife te --json (paper)",
    );
    let te = num(&v, "te_mean_arcmin");
    let b = num(&v, "backlash_arcmin");
    let lm = num(&v, "lost_motion_arcmin");
    assert!(te.abs() < 1e-6, "unworn STE mean {te} arcmin");
    assert!(b.abs() < 1e-6, "unworn backlash {b} arcmin");
    // Lost motion of an unworn reducer: the elastic twist between -3 % and +3 % of rated.
    let k = num(&v, "torsional_stiffness_nm_per_arcmin");
    assert!(
        lm > 0.0 && lm < 2.0 * 0.06 * RATED_TORQUE_NM / k,
        "lost motion {lm}"
    );
    check_te_arrays(&v);
}

#[test]
fn te_json_uniform_wear_offsets_by_w_over_a_zc() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "paper.toml", &paper_text());
    let v = json_ok(
        &rvlife([
            "te".as_ref(),
            cfg.as_os_str(),
            "--json".as_ref(),
            "--wear-um".as_ref(),
            "10".as_ref(),
        ]),
        "rvlife te --json --wear-um 10 (paper)",
    );
    let expected = uniform_offset_arcmin(10e-6);
    assert!((expected - 0.6529).abs() < 1e-3, "{expected}");
    assert_rel(
        num(&v, "te_mean_arcmin"),
        expected,
        0.01,
        "STE mean at 10 um",
    );
    assert_rel(
        num(&v, "backlash_arcmin"),
        2.0 * expected,
        0.01,
        "backlash at 10 um",
    );
    assert!(num(&v, "lost_motion_arcmin") > num(&v, "backlash_arcmin"));
    assert_rel(num(&v, "max_wear_um"), 10.0, 1e-9, "max_wear_um");
    check_te_arrays(&v);
}

#[test]
fn te_json_with_torque_reports_loaded_te() {
    let v = json_ok(
        &rvlife(["te", "--json", "--torque-nm", "412"]),
        "rvlife te --json --torque-nm 412",
    );
    let lte = num(&v, "loaded_te_mean_arcmin");
    // Contacts, crank bearings and meshes: about 1.2 arcmin at the rated torque.
    assert!(lte > 0.5 && lte < 3.0, "loaded TE mean {lte} arcmin");
    let arr = num_array(&v, "loaded_te_arcmin");
    assert_eq!(arr.len(), num_array(&v, "te_arcmin").len());
    assert!(num(&v, "max_force_n") > 0.0);
}

// ---------------------------------------------------------------------------------------------
// 4. Equidistant modification: backlash.

#[test]
fn te_equidistant_modification_gives_lost_motion() {
    let dir = tempfile::tempdir().unwrap();
    let text = set_key(
        &paper_text(),
        "cycloid.modification",
        "equidistant_mm",
        "0.01",
    );
    let cfg = write_config(dir.path(), "equidistant.toml", &text);
    let v = json_ok(
        &rvlife(["te".as_ref(), cfg.as_os_str(), "--json".as_ref()]),
        "rvlife te (equidistant 0.01 mm)",
    );
    let expected = 2.0 * uniform_offset_arcmin(0.01e-3);
    assert_rel(
        num(&v, "backlash_arcmin"),
        expected,
        0.01,
        "backlash with equidistant_mm = 0.01",
    );
}

#[test]
fn run_writes_the_results_directory() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "short.toml", &short_study_text());
    let out = dir.path().join("results");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ];
        args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
        rvlife(args)
    };

    let text = ok(&run(&[]), "rvlife run (short study)");
    assert!(text.contains("3 stages"), "stdout:\n{text}");
    // The verdict is the first line after the header, and the report's first section.
    let verdict = text.lines().nth(1).unwrap_or_default();
    assert!(
        verdict.starts_with("no accuracy spec: set [life]") && verdict.contains("duty: 412 N m"),
        "stdout:\n{text}"
    );
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());

    // summary.json
    let raw = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    assert!(!raw.contains("NaN"), "summary.json contains NaN");
    let summary: Value = serde_json::from_str(&raw).expect("summary.json is JSON");
    assert_all_finite(&summary, "summary");
    let stages = summary["stages"].as_array().expect("stages array");
    assert_eq!(stages.len(), 3);
    for (i, st) in stages.iter().enumerate() {
        for key in STAGE_KEYS {
            assert!(
                st.get(key).is_some_and(Value::is_number),
                "stage {i} lacks numeric {key:?}: {st}"
            );
        }
    }
    let hours: Vec<f64> = stages.iter().map(|s| num(s, "hours")).collect();
    assert_eq!(hours, vec![0.0, 250.0, 500.0]);
    let wear: Vec<f64> = stages.iter().map(|s| num(s, "max_wear_um")).collect();
    assert_eq!(wear[0], 0.0, "wear at 0 h");
    assert!(
        wear.windows(2).all(|w| w[1] > w[0]),
        "max_wear_um does not grow with hours: {wear:?}"
    );
    // Wear opens backlash: backlash and lost motion grow too.
    let b: Vec<f64> = stages.iter().map(|s| num(s, "backlash_arcmin")).collect();
    assert!(b[0].abs() < 1e-6 && b[2] > b[0], "backlash {b:?}");
    let lm: Vec<f64> = stages
        .iter()
        .map(|s| num(s, "lost_motion_arcmin"))
        .collect();
    assert!(lm[0] > 0.0 && lm[2] > lm[0], "lost motion {lm:?}");

    // Files.
    for f in [
        "summary.json",
        "stages.csv",
        "wear.csv",
        "te_revolution.csv",
        "load.csv",
        "hysteresis.csv",
        "plots/hysteresis.png",
        "plots/wear.svg",
        "plots/wear.png",
        "plots/te_hours.png",
    ] {
        let p = out.join(f);
        let len = std::fs::metadata(&p)
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
            .len();
        assert!(len > 0, "{f} is empty");
    }
    let dxf: Vec<_> = std::fs::read_dir(out.join("profiles"))
        .expect("profiles/")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "dxf"))
        .collect();
    assert!(!dxf.is_empty(), "no profiles/*.dxf");
    let png = std::fs::read(out.join("plots/wear.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "plots/wear.png is not a PNG");
    let svg = std::fs::read_to_string(out.join("plots/wear.svg")).unwrap();
    assert!(svg.contains("<svg"), "plots/wear.svg is not an SVG");
    assert_report(&out);
    let stages_csv = std::fs::read_to_string(out.join("stages.csv")).unwrap();
    assert!(stages_csv.starts_with("hours,"), "stages.csv header");
    assert_eq!(
        stages_csv.lines().count(),
        4,
        "stages.csv: header + 3 stages"
    );

    // Second run into the non-empty directory without --force: refused, nothing touched.
    let before = snapshot(&out);
    let o = run(&[]);
    assert_input_error(&o, "second run without --force", &["--force"]);
    assert_eq!(
        snapshot(&out),
        before,
        "refused run changed the results directory"
    );
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());

    // With --force: replaced; but not once it holds a file the run did not write (the user's
    // file is kept, with the results).
    ok(&run(&["--force"]), "rvlife run --force");
    assert!(out.join("summary.json").is_file());
    std::fs::write(out.join("stray.txt"), "x").unwrap();
    let before = snapshot(&out);
    let o = run(&["--force"]);
    assert_input_error(&o, "--force over a user's file", &["stray.txt"]);
    assert_eq!(snapshot(&out), before);
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
}

#[test]
fn run_refuses_an_existing_file_as_output() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "short.toml", &short_study_text());
    let out = dir.path().join("file");
    std::fs::write(&out, "keep me").unwrap();
    let o = rvlife([
        "run".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_input_error(&o, "run --out FILE", &[]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me");
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
}

#[test]
fn profile_dxf_is_r2000_polyline() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile(dir.path(), "disc.dxf", &[]);
    let text = std::fs::read_to_string(&p).unwrap();
    assert!(text.contains("LWPOLYLINE"), "no LWPOLYLINE in the DXF");
    assert!(text.contains("AC1015"), "DXF is not R2000 (AC1015)");
    assert!(
        text.trim_end().ends_with("EOF"),
        "DXF does not end with EOF"
    );
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        names,
        vec![std::ffi::OsString::from("disc.dxf")],
        "temporary file left"
    );
}

#[test]
fn profile_csv_nominal_radii_between_root_and_tip() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile(dir.path(), "disc.csv", &["--nominal"]);
    let pts = read_profile_csv(&p);
    assert!(pts.len() >= 39 * 10, "only {} points", pts.len());
    // Root Rp - rrp - a = 59.7 mm, tip Rp - rrp + a = 62.3 mm.
    let (lo, hi) = (59.7 - 1e-6, 62.3 + 1e-6);
    let mut rmin = f64::INFINITY;
    let mut rmax = 0.0_f64;
    for [x, y, _, w] in &pts {
        let r = x.hypot(*y);
        assert!((lo..=hi).contains(&r), "point ({x}, {y}) at radius {r} mm");
        assert_eq!(*w, 0.0, "nominal profile has wear");
        rmin = rmin.min(r);
        rmax = rmax.max(r);
    }
    // The profile reaches (close to) both the root and the tip circles.
    assert!(
        rmin < 59.7 + 1e-3 && rmax > 62.3 - 1e-3,
        "radii {rmin}..{rmax}"
    );
}

#[test]
fn profile_csv_uniform_wear_moves_the_flank_in() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile(dir.path(), "worn.csv", &["--wear-um", "5"]);
    let pts = read_profile_csv(&p);
    for [x, y, _, w] in &pts {
        assert!((w - 5.0).abs() < 1e-6, "wear column {w}");
        let r = x.hypot(*y);
        assert!(
            (59.7 - 5e-3 - 1e-6..=62.3 - 5e-3 + 1e-6).contains(&r),
            "worn point at radius {r} mm"
        );
    }
}

#[test]
fn profile_svg() {
    let dir = tempfile::tempdir().unwrap();
    let p = profile(dir.path(), "disc.svg", &[]);
    let text = std::fs::read_to_string(&p).unwrap();
    assert!(text.contains("<svg"), "no <svg> element");
    assert!(text.trim_end().ends_with("</svg>"), "SVG not closed");
}

// ---------------------------------------------------------------------------------------------
// Dynamics

#[test]
fn dynamics_json_and_results_directory() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "dyn.toml", &short_dynamics(&paper_text()));
    let out = dir.path().join("dyn");
    let v = json_ok(
        &rvlife([
            "dynamics".as_ref(),
            cfg.as_os_str(),
            "--wear-um".as_ref(),
            "10".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
            "--pin-forces".as_ref(),
            "--json".as_ref(),
        ]),
        "rvlife dynamics --json",
    );
    assert_all_finite(&v, "dynamics");
    for key in [
        "te_mean_arcmin",
        "te_peak_to_peak_arcmin",
        "te_rms_arcmin",
        "output_speed_deg_s",
    ] {
        assert!(v.get(key).is_some_and(Value::is_number), "no {key}: {v}");
    }
    // Over this 50 ms window the output crosses the backlash as the load reverses (about
    // 1 arcmin), a 0.3 % speed change; the 0.1 % check over 0.3 s is in the library tests.
    assert_rel(
        num(&v, "output_speed_deg_s"),
        9000.0 / RATIO,
        1e-2,
        "output speed",
    );
    assert_rel(num(&v, "max_wear_um"), 10.0, 1e-9, "wear");
    for f in [
        "summary.json",
        "dynamics.csv",
        "pin_forces.csv",
        "plots/speeds.svg",
        "plots/speeds.png",
        "plots/te.svg",
        "plots/te.png",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let csv = std::fs::read_to_string(out.join("dynamics.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "time_s",
        "input_speed_deg_s",
        "output_speed_deg_s",
        "te_arcmin",
        "load_nm",
    ] {
        assert!(
            header.split(',').any(|c| c == col),
            "no column {col}: {header}"
        );
    }
    assert_eq!(csv.lines().count(), 1 + 751, "0.15 s at 0.2 ms plus t = 0");
    assert!(!csv.contains("NaN"));
    let forces = std::fs::read_to_string(out.join("pin_forces.csv")).unwrap();
    assert_eq!(
        forces.lines().next().unwrap().split(',').count(),
        1 + 2 * PINS,
        "time plus one column per pin and disc"
    );
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
}

#[test]
fn dynamics_no_load_on_a_perfect_reducer_has_no_te() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "dyn.toml", &short_dynamics(&paper_text()));
    let v = json_ok(
        &rvlife([
            "dynamics".as_ref(),
            cfg.as_os_str(),
            "--load".as_ref(),
            "none".as_ref(),
            "--json".as_ref(),
        ]),
        "rvlife dynamics --load none",
    );
    assert!(num(&v, "te_peak_to_peak_arcmin") < 0.01, "{v}");
    assert!(num(&v, "te_mean_arcmin").abs() < 0.01, "{v}");
}

/// A reader that closes the pipe before rvlife prints (`rvlife te --json | head -c 0`) ends it
/// quietly by SIGPIPE, as it ends `cat`: no panic (it exited 101 with "failed printing to
/// stdout" before).
#[test]
#[cfg(unix)]
fn closed_stdout_pipe_ends_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args(["te", "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.signal(), Some(13), "{:?}", out.status);
}

/// A negative target wear reaches the range check (exit 2 naming the option), not the argument
/// parser.
#[test]
fn calibrate_negative_target_is_refused_by_the_range_check() {
    let o = rvlife(["calibrate", "--target-wear-um", "-1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("invalid --target-wear-um = -1"),
        "{}",
        stderr(&o)
    );
}

/// `profile --json` prints the points the web page draws (its `profile`): `--points-per-tooth`
/// a tooth, each column that many a tooth; uniform wear is the same depth at every point.
#[test]
fn profile_json_prints_the_points() {
    let o = rvlife([
        "profile",
        "--json",
        "--points-per-tooth",
        "12",
        "--wear-um",
        "5",
    ]);
    ok(&o, "profile --json");
    let v: Value = serde_json::from_slice(&o.stdout).expect("profile --json is JSON");
    assert_eq!(v["points_per_tooth"], 12);
    let wear = v["wear_um"].as_array().unwrap();
    assert_eq!(wear.len() % 12, 0);
    assert_eq!(v["x_mm"].as_array().unwrap().len(), wear.len());
    assert!(
        wear.iter()
            .all(|w| (w.as_f64().unwrap() - 5.0).abs() < 1e-9),
        "{wear:?}"
    );
    // A file or the JSON, not both.
    let o = rvlife(["profile", "--json", "--out", "p.csv"]);
    assert!(!o.status.success());
}

/// `profile --out FILE` follows the rules of `run --out`, checked before any work: an existing
/// file is kept (exit 2) unless `--force`; a directory or a missing folder is refused (exit 2)
/// and nothing is left behind.
#[test]
fn profile_out_is_checked_before_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("disc.csv");
    std::fs::write(&out, "user data").unwrap();
    let o = rvlife(["profile".as_ref(), "--out".as_ref(), out.as_os_str()]);
    assert_input_error(&o, "profile --out existing", &["--out", "--force"]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "user data");
    let o = rvlife([
        "profile".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--force".as_ref(),
    ]);
    ok(&o, "profile --out existing --force");
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("x_mm"));
    let sub = dir.path().join("folder.csv");
    std::fs::create_dir(&sub).unwrap();
    let o = rvlife([
        "profile".as_ref(),
        "--out".as_ref(),
        sub.as_os_str(),
        "--force".as_ref(),
    ]);
    assert_input_error(&o, "profile --out directory", &["--out", "directory"]);
    let missing = dir.path().join("no/such/folder/disc.csv");
    let o = rvlife(["profile".as_ref(), "--out".as_ref(), missing.as_os_str()]);
    assert_input_error(&o, "profile --out missing folder", &["--out", "folder"]);
    let mut left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    left.sort();
    assert_eq!(left, ["disc.csv", "folder.csv"], "left behind: {left:?}");
}
