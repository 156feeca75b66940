//! Refusals that name the key or option the user wrote, before the work: physical ranges,
//! part errors, negative numbers on the command line, fits and merges that cannot stand
//! behind their numbers, output paths that are links or cannot be replaced, inputs that are
//! not regular files or are too large, and the console's zeros.

mod common;

use std::path::Path;
use std::process::Command;

use common::*;

fn example() -> String {
    ok(&rvlife(["example"]), "example")
}

/// Values that pass a bare `> 0` but are not physical are refused by their own key at once
/// (they used to pass the ranges and end, 15-30 s later, naming `reducer.rated_torque_nm`).
#[test]
fn ranges_admit_physical_values_only() {
    let ex = example();
    for (table, key, value) in [
        ("reducer.gears", "mesh_stiffness_n_per_um", "4.4e-10"),
        ("reducer.gears", "face_width_mm", "1e-300"),
        ("materials.disc", "youngs_modulus_gpa", "1e-300"),
        ("materials.pin", "youngs_modulus_gpa", "0.01"),
    ] {
        let (_d, o) = run_config(&set_key(&ex, table, key, value), &["te"]);
        assert_input_error(&o, key, &[&format!("{table}.{key}"), "must be"]);
    }
    let linear = set_key(&ex, "reducer.bearings", "model", "\"linear\"");
    let t = add_line(
        &linear,
        "reducer.bearings",
        "crank_carrier_stiffness_n_per_um = 1e-300",
    );
    let (_d, o) = run_config(&t, &["te"]);
    assert_input_error(
        &o,
        "crank-carrier stiffness",
        &[
            "reducer.bearings.crank_carrier_stiffness_n_per_um",
            "[1, 1e6]",
        ],
    );
}

/// Part errors the stage cannot take are refused naming the `[errors]` entry that moves a
/// flank most; errors of a precision reducer's size (all pins 1 um oversize, 0.5 um of
/// pin-circle run-out) are assembled with preload and analysed, with an angular TE of the
/// errors' size.
#[test]
fn part_errors_are_named_by_their_key() {
    let ex = example();
    let zeros = |n: usize| vec!["0.0"; n].join(", ");
    let with = |line: &str| format!("{ex}\n[errors]\n{line}\n");
    let (_d, o) = run_config(
        &with(&format!("pin_radius_um = [500.0, {}]", zeros(39))),
        &["te"],
    );
    assert_input_error(&o, "pin +500 um", &["errors.pin_radius_um[0] = 500"]);
    let (_d, o) = run_config(&with("crank_phase_arcmin = [600.0, -600.0]"), &["te"]);
    assert_input_error(&o, "crank phase", &["errors.crank_phase_arcmin[0] = 600"]);
    for line in [
        format!("pin_radius_um = [{}]", vec!["1.0"; 40].join(", ")),
        "pin_circle_runout_um = 0.5".to_string(),
    ] {
        let (_d, o) = run_config(&with(&line), &["te", "--json"]);
        let v = json_ok(&o, &line);
        let angular = num(&v, "angular_te_arcmin");
        assert!(
            angular.is_finite() && (0.0..1.0).contains(&angular),
            "{line}: angular TE {angular} arcmin"
        );
        assert!(num(&v, "backlash_max_arcmin") >= 0.0, "{line}: {v}");
    }
}

/// Negative and fractional numbers given to whole-number options are refused naming the
/// option (they used to be read as options: "unexpected argument '-1' found"); a work budget
/// below 6 s is refused by its own option instead of blaming a config key.
#[test]
fn command_line_numbers_name_their_option() {
    for (args, needle) in [
        (vec!["montecarlo", "--samples", "-1"], "--samples"),
        (vec!["montecarlo", "--samples", "1.5"], "--samples"),
        (vec!["montecarlo", "--seed", "-1"], "--seed"),
        (vec!["montecarlo", "--shard", "-1/3"], "--shard"),
        (vec!["hysteresis", "--levels", "-3"], "--levels"),
        (vec!["--work-budget-min", "-1", "te"], "--work-budget-min"),
        (vec!["--work-budget-min", "1e-9", "te"], "--work-budget-min"),
    ] {
        let o = rvlife(&args);
        assert_input_error(&o, &args.join(" "), &[needle]);
        assert!(
            !stderr(&o).contains("unexpected argument"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// A table the user wrote, even empty, is the user's: the message does not call it a default.
#[test]
fn an_empty_table_the_user_wrote_is_not_a_default() {
    let t = set_key(&example(), "tolerances", "pin_radial_um", "{ }");
    let (_d, o) = run_config(&t, &["montecarlo", "--samples", "2"]);
    assert_input_error(&o, "empty distribution", &["tolerances.pin_radial_um ="]);
    assert!(!stderr(&o).contains("not in your file"), "{}", stderr(&o));
}

/// A fit that stops at the bound of its search says so and exits 2 (lost motion rising from
/// 0.08 to 0.9 arcmin within 0.002 h used to print an interval [0, inf] and exit 0).
#[test]
fn a_fit_at_its_bound_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let m = dir.path().join("m.csv");
    std::fs::write(
        &m,
        "hours,lost_motion_arcmin\n0,0.08\n0.001,0.5\n0.002,0.9\n",
    )
    .unwrap();
    let cfg = write_config(dir.path(), "c.toml", &fast_text());
    let o = calibrate_measured(&cfg, &m);
    assert_input_error(&o, "fit at its bound", &["--measured", "search range"]);
    assert!(!stdout(&o).contains("inf"), "{}", stdout(&o));
}

/// Long numbers in messages are written in exponent notation (1e300 used to be 301 digits).
#[test]
fn messages_write_huge_values_readably() {
    let o = rvlife(["calibrate", "--target-wear-um", "1e300"]);
    assert_input_error(&o, "1e300", &["--target-wear-um = 1e300"]);
    assert!(!stderr(&o).contains("0000000000"), "{}", stderr(&o));
}

/// `merge` checks the shards' numbers like computed ones: a `nan` is refused naming the file.
#[test]
fn merge_refuses_non_finite_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &example());
    let shard = |i: usize| {
        let out = dir.path().join(format!("s{i}"));
        montecarlo_shard(&cfg, i, &out);
        out
    };
    let (s1, s2) = (shard(1), shard(2));
    let stages = s1.join("stages.csv");
    let text = std::fs::read_to_string(&stages).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let cut = lines[1].rfind(',').unwrap();
    lines[1] = format!("{},nan", &lines[1][..cut]);
    std::fs::write(&stages, lines.join("\n") + "\n").unwrap();
    let out = dir.path().join("m");
    let o = rvlife([
        "merge".as_ref(),
        s1.as_os_str(),
        s2.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_input_error(
        &o,
        "merge nan",
        &["stages.csv", "nan", "not a finite number"],
    );
    assert!(!out.exists());
}

/// A symbolic link as `--out` (a loop, a self-link, a link to nothing) is refused before the
/// work, saying what it is (it used to compute the whole run, then claim another run had
/// written the folder).
#[test]
fn links_as_output_are_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::os::unix::fs::symlink(d.join("loopb"), d.join("loopa")).unwrap();
    std::os::unix::fs::symlink(d.join("loopa"), d.join("loopb")).unwrap();
    std::os::unix::fs::symlink(d.join("self"), d.join("self")).unwrap();
    std::os::unix::fs::symlink(d.join("nowhere"), d.join("dangling")).unwrap();
    std::os::unix::fs::symlink(d.join("nowhere.csv"), d.join("dangling.csv")).unwrap();
    let cfg = write_config(d, "c.toml", &example());
    for (name, what) in [
        ("loopa", "loops"),
        ("self", "loops"),
        ("dangling", "does not exist"),
    ] {
        let out = d.join(name);
        for args in [
            vec!["run", "--force"],
            vec!["run"],
            vec!["montecarlo", "--samples", "2"],
        ] {
            let mut all: Vec<std::ffi::OsString> =
                vec![args[0].into(), cfg.clone().into_os_string()];
            all.extend(args[1..].iter().map(std::ffi::OsString::from));
            all.extend(["--out".into(), out.clone().into_os_string()]);
            let o = rvlife_within(30, all);
            assert_input_error(&o, name, &["--out", "symbolic link", what]);
        }
    }
    let o = rvlife([
        "profile".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        d.join("dangling.csv").as_os_str(),
    ]);
    assert_input_error(&o, "profile to a link", &["--out", "symbolic link"]);
}

/// A results marker the user made (empty), or a results folder the user added a file to, is
/// not replaced by `--force`: the marker lists the files of the run that wrote it.
#[test]
fn force_replaces_only_what_rvlife_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cfg = write_config(d, "c.toml", &fast_text());
    let out = d.join("res");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join(".rvlife-results"), "").unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let run = |out: &Path| {
        rvlife_within(
            120,
            [
                "run".as_ref(),
                cfg.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
                "--force".as_ref(),
            ],
        )
    };
    assert_input_error(
        &run(&out),
        "user marker",
        &["--out", "not written by rvlife"],
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    let res = d.join("r2");
    ok(&run(&res), "first run");
    let marker = std::fs::read_to_string(res.join(".rvlife-results")).unwrap();
    assert!(marker.lines().any(|l| l == "summary.json"), "{marker}");
    ok(&run(&res), "replacing its own results");
    std::fs::write(res.join("plots").join("mine.svg"), "<svg/>").unwrap();
    assert_input_error(&run(&res), "added file", &["--out", "plots/mine.svg"]);
    assert!(res.join("plots").join("mine.svg").is_file());
}

/// Runs the binary as an unprivileged user (`setpriv` to `nobody`) when the tests run as root,
/// else as is; `None` where neither can show the case (root without `setpriv`, or a binary
/// `nobody` cannot reach).
fn unprivileged(args: &[&std::ffi::OsStr]) -> Option<std::process::Output> {
    // SAFETY: geteuid has no preconditions.
    let root = unsafe { libc::geteuid() } == 0;
    let command = || {
        if root {
            let mut c = Command::new("setpriv");
            c.args(["--reuid=65534", "--regid=65534", "--clear-groups"])
                .arg(env!("CARGO_BIN_EXE_rvlife"));
            c
        } else {
            Command::new(env!("CARGO_BIN_EXE_rvlife"))
        }
    };
    let runs = command()
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !runs {
        return None;
    }
    Some(command().args(args).output().expect("rvlife"))
}

/// A results folder the user cannot empty (owned by root, in a folder the user may write), and
/// a profile into a folder the user cannot write, are refused before the work, naming `--out`
/// (the first used to exit 0 and leave the old results in a hidden folder).
#[test]
fn outputs_that_cannot_be_replaced_are_refused_before_the_work() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::set_permissions(d, std::fs::Permissions::from_mode(0o755)).unwrap();
    let cfg = write_config(d, "c.toml", &fast_text());
    std::fs::set_permissions(&cfg, std::fs::Permissions::from_mode(0o644)).unwrap();
    let parent = d.join("nbdir");
    std::fs::create_dir(&parent).unwrap();
    let res = parent.join("res");
    ok(
        &rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            res.as_os_str(),
        ]),
        "results to protect",
    );
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } == 0 {
        let c = std::ffi::CString::new(parent.to_str().unwrap()).unwrap();
        // SAFETY: a valid path; nobody:nogroup.
        assert_eq!(unsafe { libc::chown(c.as_ptr(), 65534, 65534) }, 0);
    } else {
        std::fs::set_permissions(&res, std::fs::Permissions::from_mode(0o555)).unwrap();
    }
    let before = snapshot(&res);
    let Some(o) = unprivileged(&[
        "run".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        res.as_os_str(),
        "--force".as_ref(),
    ]) else {
        eprintln!("skipped: no unprivileged user can run the binary here (root without setpriv?)");
        return;
    };
    assert_input_error(&o, "root-owned results", &["--out", "cannot remove"]);
    assert_eq!(snapshot(&res), before);
    assert_eq!(leftover_tmp_dirs(&parent), Vec::<String>::new());
    let ro = d.join("ro");
    std::fs::create_dir(&ro).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
    let p = ro.join("p.csv");
    let o = unprivileged(&[
        "profile".as_ref(),
        cfg.as_os_str(),
        "--hours".as_ref(),
        "5000".as_ref(),
        "--out".as_ref(),
        p.as_os_str(),
    ])
    .expect("checked above");
    assert_input_error(&o, "read-only folder", &["--out", "cannot be written"]);
    std::fs::set_permissions(&res, std::fs::Permissions::from_mode(0o755)).ok();
}

/// Inputs that are not regular files (a FIFO, a device) or beyond 16 MiB are refused at once
/// naming the path (a FIFO used to block for ever, `/dev/zero` to read until memory ran out).
#[test]
fn inputs_must_be_regular_files_within_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo.toml");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let big = dir.path().join("big.toml");
    std::fs::write(&big, "#".repeat(17 << 20)).unwrap();
    for (path, needle) in [
        (fifo.as_path(), "not a regular file"),
        (Path::new("/dev/zero"), "not a regular file"),
        (dir.path(), "a directory"),
        (big.as_path(), "MiB"),
    ] {
        let o = rvlife_within(20, ["te".as_ref(), path.as_os_str()]);
        assert_input_error(
            &o,
            &path.display().to_string(),
            &[&path.display().to_string(), needle],
        );
    }
    let m = rvlife_within(
        20,
        [
            "calibrate".as_ref(),
            "--measured".as_ref(),
            fifo.as_os_str(),
        ],
    );
    assert_input_error(&m, "measured FIFO", &["not a regular file"]);
}

/// Round-off signs on exact zeros are not printed: the paper's reducer with a tiny run-out
/// has an STE mean of -1e-9 arcmin, printed `0.00000`.
#[test]
fn the_console_prints_no_negative_zeros() {
    let t = format!("{}\n[errors]\npin_circle_runout_um = 0.01\n", paper_text());
    let (_d, o) = run_config(&t, &["te"]);
    let out = ok(&o, "te");
    assert!(!out.contains("-0.00000"), "{out}");
    assert!(out.contains("STE mean"), "{out}");
}

/// Backlash in the sun-planet meshes (`[reducer.gears] backlash_um`) is carried, not refused:
/// `te` and `contact` run with 0.1 to 5 um (they used to end after 19-32 s naming
/// `reducer.rated_torque_nm`).
#[test]
fn sun_planet_backlash_is_carried() {
    let ex = example();
    for b in ["0.1", "1.0", "2.07", "5.0"] {
        let t = set_key(&ex, "reducer.gears", "backlash_um", b);
        let (_d, o) = run_config(&t, &["te", "--torque-nm", "412", "--json"]);
        assert_all_finite(&json_ok(&o, &format!("te, backlash {b} um")), "te");
        let (_d, o) = run_config(
            &t,
            &[
                "contact",
                "--crank-deg",
                "3",
                "--torque-nm",
                "412",
                "--json",
            ],
        );
        assert_all_finite(
            &json_ok(&o, &format!("contact, backlash {b} um")),
            "contact",
        );
    }
}
