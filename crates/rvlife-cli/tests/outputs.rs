//! The outputs of the `rvlife` binary: results directories written all-or-nothing (never a user
//! file lost, interrupted and concurrent runs, identical bytes), and `calibrate --measured`.

mod common;

use common::*;

/// `--force` replaces only a results directory rvlife wrote: a folder of user files is refused
/// with exit 2 and left intact; `.`, `..` and the current folder are refused before any work;
/// an unwritable `--out` is found before the study.
#[test]
fn run_out_never_deletes_user_files() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &fast_text());
    let user = dir.path().join("thesis");
    std::fs::create_dir(&user).unwrap();
    std::fs::write(user.join("chapter1.tex"), "years of work").unwrap();
    let o = rvlife([
        "run".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        user.as_os_str(),
        "--force".as_ref(),
    ]);
    assert_input_error(&o, "user folder", &["--out", ".rvlife-results"]);
    assert_eq!(
        std::fs::read_to_string(user.join("chapter1.tex")).unwrap(),
        "years of work"
    );
    for bad in [".", ".."] {
        let o = Command::new(env!("CARGO_BIN_EXE_rvlife"))
            .current_dir(&user)
            .args([
                "run".as_ref(),
                cfg.as_os_str(),
                "--out".as_ref(),
                bad.as_ref(),
                "--force".as_ref(),
            ])
            .output()
            .unwrap();
        assert_input_error(&o, bad, &["--out", "current"]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .current_dir(&user)
        .args([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            user.as_os_str(),
            "--force".as_ref(),
        ])
        .output()
        .unwrap();
    assert_input_error(&o, "cwd", &["--out"]);
    assert_eq!(leftover_tmp_dirs(&user), Vec::<String>::new());
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
    #[cfg(target_os = "linux")]
    {
        let o = rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            "/proc/rvlife-results".as_ref(),
        ]);
        assert_input_error(&o, "/proc", &["--out", "cannot be written"]);
        assert!(!stdout(&o).contains("rvlife study"), "{}", stdout(&o));
    }
    // A results directory of rvlife is replaced with --force.
    let out = dir.path().join("r");
    ok(
        &rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ]),
        "first run",
    );
    assert!(out.join(".rvlife-results").is_file());
    ok(
        &rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
            "--force".as_ref(),
        ]),
        "replace",
    );
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
}

/// Interrupted runs leave nothing behind: SIGINT at random moments of the compute and write
/// phases removes the temporary directory; the temporary directory of a killed run (SIGKILL)
/// is removed by the next run in the same folder.
#[test]
#[cfg(unix)]
fn interrupted_runs_leave_no_temporary_directory() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &fast_text());
    for (i, delay_ms) in [300u64, 600, 800, 900, 1000, 1100, 1200, 1400]
        .iter()
        .enumerate()
    {
        let out = dir.path().join(format!("r{i}"));
        let child = spawn_run(&cfg, &out);
        std::thread::sleep(std::time::Duration::from_millis(*delay_ms));
        // SAFETY: sends SIGINT to our own child process.
        unsafe {
            libc::kill(child.id() as libc::pid_t, libc::SIGINT);
        }
        let mut child = child;
        let status = child.wait().unwrap();
        assert!(
            matches!(status.code(), Some(0) | Some(130)),
            "interrupted run: {status:?}"
        );
        assert_eq!(
            leftover_tmp_dirs(dir.path()),
            Vec::<String>::new(),
            "after {delay_ms} ms"
        );
        if out.exists() {
            assert!(
                out.join(".rvlife-results").is_file(),
                "partial results in {}",
                out.display()
            );
        }
    }
    // A temporary directory of a dead run (a process that has exited) is removed.
    let dead = Command::new("true").spawn().unwrap();
    let pid = dead.id();
    let mut dead = dead;
    dead.wait().unwrap();
    let stale = dir.path().join(format!(".rvlife-tmp-{pid}-abcdef"));
    std::fs::create_dir(&stale).unwrap();
    std::fs::write(stale.join("summary.json"), "{").unwrap();
    ok(
        &rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            dir.path().join("after").as_os_str(),
        ]),
        "run after a killed one",
    );
    assert!(
        !stale.exists(),
        "the stale temporary directory is still there"
    );
}

/// Two runs to the same new `--out`: one writes it, the other exits 2 and replaces nothing
/// (the later one used to replace the earlier silently).
#[test]
fn concurrent_runs_do_not_replace_each_other() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &fast_text());
    let out = dir.path().join("r");
    let (a, b) = (spawn_run(&cfg, &out), spawn_run(&cfg, &out));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    let mut codes = [a.status.code(), b.status.code()];
    codes.sort();
    assert_eq!(codes, [Some(0), Some(2)], "{}\n{}", stderr(&a), stderr(&b));
    let loser = if a.status.code() == Some(2) { &a } else { &b };
    assert!(stderr(loser).contains("--out"), "{}", stderr(loser));
    assert!(out.join(".rvlife-results").is_file());
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
}

/// Same input, same bytes: two runs write byte-identical results directories (DXF headers
/// included).
#[test]
fn two_runs_write_identical_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let t = set_key(&fast_text(), "wear", "stage_hours", "[0.0, 500.0]");
    let cfg = write_config(dir.path(), "c.toml", &t);
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    ok(
        &rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            a.as_os_str(),
        ]),
        "run a",
    );
    std::thread::sleep(std::time::Duration::from_millis(1100));
    ok(
        &rvlife([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            b.as_os_str(),
        ]),
        "run b",
    );
    let (sa, sb) = (snapshot(&a), snapshot(&b));
    assert_eq!(sa.keys().collect::<Vec<_>>(), sb.keys().collect::<Vec<_>>());
    for (k, v) in &sa {
        assert!(v == &sb[k], "{} differs between two runs", k.display());
    }
    assert!(sa.keys().any(|k| k.extension().is_some_and(|e| e == "dxf")));
}

/// Calibration recovers the coefficient rvlife generated its data with: lost motion
/// (0.19-0.58 arcmin) and backlash (0.02-0.15 arcmin) at 8 hour points, 250-2000 h, with
/// k_true = 1.7 x the example's, plus Gaussian noise of sigma = 0.01 arcmin (seed 7), fitted
/// starting from the example's coefficient. k_true lies in the 95 % interval (a 1-in-20 miss is
/// what the interval allows; the seed was not chosen) and the estimate within 5 % of it (the
/// interval is about +-3 %). With the same noise draws scaled to sigma / 4 the interval shrinks
/// with the noise: its width in ln k is 1/4 of the first within 0.19-0.32 (the fit is nearly
/// linear in ln k over the interval; noise-free data give k_true to 1e-5).
#[test]
fn calibrate_measured_recovers_a_known_coefficient() {
    let k_true = 1.7 * EXAMPLE_ARCHARD_MM3;
    let truth = model_lost_motion_and_backlash(k_true);
    assert_eq!(truth.len(), MEASURED_HOURS.len());
    let noise = unit_noise(truth.len(), 7);
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &fast_text());
    let sigma = 0.01;
    let m = measured_csv(dir.path(), "m.csv", &truth, &noise, sigma, 0.0);
    let (v, text) = calibrate_json(&cfg, &m, &dir.path().join("fit"), &[]);
    assert!(
        text.contains("archard_coefficient_mm3_per_n_m = "),
        "{text}"
    );
    assert!(text.contains("RMS residual"), "{text}");
    let (k, lo, hi) = k_interval(&v);
    eprintln!("k_true {k_true:.5e}: fitted {k:.5e} [{lo:.5e}, {hi:.5e}]");
    assert!(lo <= k_true && k_true <= hi, "{k_true} not in [{lo}, {hi}]");
    assert_rel(k, k_true, 0.05, "fitted k");
    assert!(hi / lo < 1.15, "interval too wide: [{lo}, {hi}]");
    assert_eq!(num(&v, "degrees_of_freedom"), 15.0);
    for q in v["quantities"].as_array().unwrap() {
        let rms = num(q, "rms_residual");
        assert!(rms > 0.3 * sigma && rms < 2.0 * sigma, "{q}");
    }
    let m4 = measured_csv(dir.path(), "m4.csv", &truth, &noise, sigma / 4.0, 0.0);
    let (v4, _) = calibrate_json(&cfg, &m4, &dir.path().join("fit4"), &[]);
    let (k4, lo4, hi4) = k_interval(&v4);
    eprintln!("sigma/4: fitted {k4:.5e} [{lo4:.5e}, {hi4:.5e}]");
    assert!(
        lo4 <= k_true && k_true <= hi4,
        "{k_true} not in [{lo4}, {hi4}]"
    );
    let ratio = (hi4.ln() - lo4.ln()) / (hi.ln() - lo.ln());
    eprintln!("interval width ratio at sigma/4: {ratio:.3}");
    assert!((0.19..=0.32).contains(&ratio), "{ratio}");
}

/// With `--fit-running-in` the fit recovers a running-in play b0 = 0.1 arcmin added to the
/// generated backlash and lost motion (sigma = 0.01 arcmin) and still k_true: over 5 noise
/// draws (seeds 11-15, not chosen) at least 3 have both within their 95 % intervals (the joint
/// coverage of two 95 % intervals is about 90 %: 3 of 5 or more with probability 0.99). Seeds
/// 11 and 12 miss (b0 2.3 and 2.5 standard errors off); 20 draws of another generator all
/// covered both. Fitted without b0 (first draw), the play is read as wear and the interval of
/// k misses k_true.
#[test]
fn calibrate_measured_fits_the_running_in_play() {
    let k_true = 1.7 * EXAMPLE_ARCHARD_MM3;
    let truth = model_lost_motion_and_backlash(k_true);
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &fast_text());
    let b0_true = 0.1;
    let mut covered = 0;
    for seed in 11..=15 {
        let noise = unit_noise(truth.len(), seed);
        let name = format!("m{seed}.csv");
        let m = measured_csv(dir.path(), &name, &truth, &noise, 0.01, b0_true);
        let out = dir.path().join(format!("fit{seed}"));
        let (v, text) = calibrate_json(&cfg, &m, &out, &["--fit-running-in"]);
        assert!(text.contains("running-in play b0 = "), "{text}");
        assert_eq!(num(&v, "degrees_of_freedom"), 14.0);
        let (k, lo, hi) = k_interval(&v);
        let b = &v["running_in_backlash_arcmin"];
        let (b0, blo, bhi) = (num(b, "value"), num(b, "lower"), num(b, "upper"));
        let hit = lo <= k_true && k_true <= hi && blo <= b0_true && b0_true <= bhi;
        eprintln!(
            "seed {seed}: k {k:.5e} [{lo:.5e}, {hi:.5e}] (true {k_true:.5e}), b0 {b0:.4} \
             [{blo:.4}, {bhi:.4}]: {}",
            if hit { "covered" } else { "missed" }
        );
        assert_rel(k, k_true, 0.15, "fitted k with b0");
        covered += usize::from(hit);
        if seed == 11 {
            // Without b0 the model cannot follow the play: the fit is refused, not reported.
            let o = calibrate_measured(&cfg, &m);
            assert_input_error(
                &o,
                "fit without b0",
                &["--measured", "worse than the measurements' own mean"],
            );
        }
    }
    assert!(
        covered >= 3,
        "only {covered} of 5 draws covered k_true and b0"
    );
}

/// Bad measurement files and options are refused with exit 2 naming `--measured` (or the
/// option), the file and what is allowed, before any work: no results directory appears.
#[test]
fn calibrate_measured_bad_inputs_exit_2_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fit");
    let cases: [(&str, &str, &[&str]); 8] = [
        (
            "no_hours.csv",
            "h,backlash_arcmin\n100,1\n200,2\n",
            &["unknown column(s) h", "allowed: hours"],
        ),
        (
            "no_hours2.csv",
            "backlash_arcmin\n1\n2\n",
            &["no `hours` column"],
        ),
        (
            "negative.csv",
            "hours,backlash_arcmin\n-100,1\n200,2\n",
            &["row 2, column hours = -100", "[0, 1e7] h"],
        ),
        (
            "nan.csv",
            "hours,lost_motion_arcmin\n100,NaN\n200,2\n",
            &["lost_motion_arcmin = NaN", "[0, 1e4] arcmin"],
        ),
        (
            "negative_value.csv",
            "hours,max_wear_um\n100,-3\n200,2\n",
            &["max_wear_um = -3", "[0, 1e4] um"],
        ),
        (
            "few.csv",
            "hours,backlash_arcmin\n100,1\n",
            &["1 measured value(s)", "at least 2"],
        ),
        (
            "unknown.csv",
            "hours,backlash_arcmin,temperature_c\n100,1,20\n200,2,20\n",
            &["unknown column(s) temperature_c", "lost_motion_arcmin"],
        ),
        (
            "budget.csv",
            "hours,backlash_arcmin\n100,1\n1e7,2\n",
            &["largest measured hours", "work budget"],
        ),
    ];
    // The paper's reducer: its disc alone wears, without running-in (the example's bearings and
    // pins wear too, which the fit refuses, and its running-in factor is fitted as well).
    let paper = write_config(dir.path(), "paper.toml", &paper_text());
    for (name, text, needles) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let t = std::time::Instant::now();
        let o = rvlife_within(
            60,
            [
                "calibrate".as_ref(),
                paper.as_os_str(),
                "--measured".as_ref(),
                p.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
        );
        let mut all = vec!["invalid --measured", name];
        all.extend_from_slice(needles);
        assert_input_error(&o, name, &all);
        assert!(
            t.elapsed().as_secs_f64() < 5.0,
            "{name}: not refused at once"
        );
        assert!(!out.exists(), "{name}: results directory created");
    }
    let missing = dir.path().join("missing.csv");
    let o = rvlife([
        "calibrate".as_ref(),
        "--measured".as_ref(),
        missing.as_os_str(),
    ]);
    assert_input_error(&o, "missing", &["invalid --measured", "cannot be read"]);
    // The running-in play needs a backlash or lost-motion column, and 3 values.
    let p = dir.path().join("wear.csv");
    std::fs::write(&p, "hours,max_wear_um\n100,1\n200,2\n300,3\n").unwrap();
    let o = rvlife([
        "calibrate".as_ref(),
        paper.as_os_str(),
        "--measured".as_ref(),
        p.as_os_str(),
        "--fit-running-in".as_ref(),
    ]);
    assert_input_error(
        &o,
        "running-in without play",
        &["--fit-running-in", "backlash_arcmin"],
    );
    let p = dir.path().join("two.csv");
    std::fs::write(&p, "hours,backlash_arcmin\n100,1\n200,2\n").unwrap();
    let o = rvlife([
        "calibrate".as_ref(),
        paper.as_os_str(),
        "--measured".as_ref(),
        p.as_os_str(),
        "--fit-running-in".as_ref(),
    ]);
    assert_input_error(
        &o,
        "running-in, 2 values",
        &["2 measured value(s)", "at least 3"],
    );
    // The fit scales the hours by the disc's coefficient: bearing wear (in real hours) is
    // refused by its key; a running-in factor is fitted, which needs one more value.
    let three = dir.path().join("three.csv");
    std::fs::write(&three, "hours,backlash_arcmin\n100,1\n200,2\n300,3\n").unwrap();
    for (line, file, needles) in [
        (
            "bearing_archard_coefficient_mm3_per_n_m = 1e-9",
            &three,
            &["wear.bearing_archard_coefficient_mm3_per_n_m", "must be 0"][..],
        ),
        (
            "running_in_factor = 3.0",
            &p,
            &["2 measured value(s)", "running-in factor r", "at least 3"][..],
        ),
    ] {
        let (key, value) = line.split_once(" = ").unwrap();
        let cfg = write_config(
            dir.path(),
            "c.toml",
            &set_key(&paper_text(), "wear", key, value),
        );
        let o = rvlife([
            "calibrate".as_ref(),
            cfg.as_os_str(),
            "--measured".as_ref(),
            file.as_os_str(),
        ]);
        assert_input_error(&o, line, needles);
    }
    // --fit-running-in and --out need --measured (clap: exit 2).
    let o = rvlife(["calibrate", "--fit-running-in"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// Every plot against hours of a quantity with a `[life]` threshold draws the threshold and
/// marks the accuracy life when there is one: `te_hours` (lost motion, backlash, angular TE),
/// `lost_motion_sources` and `angular_te_sources`; without `[life]` none draws a spec. The DTE
/// has its own plot (`dte_hours`), so its range does not set the TE plot's scale.
#[test]
fn plots_against_hours_draw_the_spec_and_the_life() {
    let base = set_key(&fast_text(), "wear", "stage_hours", "[0.0, 1250.0, 2500.0]");
    let with_spec = format!(
        "{base}\n[life]\nlost_motion_arcmin = 0.2\nbacklash_arcmin = 0.9\nangular_te_arcmin = 0.5\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let study = |text: &str, name: &str| {
        let d = dir.path().join(name);
        std::fs::create_dir_all(&d).unwrap();
        let (out, o) = run_study(&d, &write_config(&d, "c.toml", text));
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out.join("plots")
    };
    let plots = study(&with_spec, "spec");
    let plot = |name: &str| std::fs::read_to_string(plots.join(format!("{name}.svg"))).unwrap();
    for (name, needles) in [
        (
            "te_hours",
            &[
                "spec: lost motion 0.2",
                "spec: backlash 0.9",
                "spec: angular TE 0.5",
                "accuracy life",
            ][..],
        ),
        (
            "lost_motion_sources",
            &["spec: lost motion 0.2", "accuracy life"][..],
        ),
        (
            "angular_te_sources",
            &["spec: angular TE 0.5", "accuracy life"][..],
        ),
    ] {
        let svg = plot(name);
        for n in needles {
            assert!(svg.contains(n), "{name}.svg lacks {n:?}");
        }
    }
    let plain = study(&base, "plain");
    for name in ["te_hours", "lost_motion_sources", "angular_te_sources"] {
        let svg = std::fs::read_to_string(plain.join(format!("{name}.svg"))).unwrap();
        assert!(
            !svg.contains("spec:"),
            "{name}.svg draws a spec without [life]"
        );
    }
    assert!(!plain.join("dte_hours.svg").exists());
}
