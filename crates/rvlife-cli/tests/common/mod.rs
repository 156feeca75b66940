//! Helpers shared by the command-line test binaries (each uses some of them).

#![allow(dead_code, unused_imports)]

pub use std::collections::BTreeMap;
pub use std::f64::consts::PI;
pub use std::path::{Path, PathBuf};
pub use std::process::{Command, Output};

pub use serde_json::Value;

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs rvlife, killing it after `secs` seconds (a watchdog thread; the output is read as it
/// comes, so a large output cannot block the child): a hang fails the test instead of
/// stalling it.
pub fn rvlife_within<I, S>(secs: u64, args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    use std::process::Stdio;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let child = Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot start the rvlife binary");
    let pid = child.id();
    let done = Arc::new(AtomicBool::new(false));
    let killed = Arc::new(AtomicBool::new(false));
    let (d, k) = (done.clone(), killed.clone());
    std::thread::spawn(move || {
        let start = std::time::Instant::now();
        while !d.load(Ordering::SeqCst) {
            if start.elapsed().as_secs() >= secs {
                k.store(true, Ordering::SeqCst);
                #[cfg(unix)]
                // SAFETY: kills our own child process, still unreaped (done is false).
                unsafe {
                    libc::kill(pid as libc::pid_t, libc::SIGKILL);
                }
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    });
    let o = child.wait_with_output().expect("output");
    done.store(true, Ordering::SeqCst);
    assert!(
        !killed.load(Ordering::SeqCst),
        "rvlife did not finish within {secs} s (hang)\nstderr:\n{}",
        stderr(&o)
    );
    o
}

/// Walks a JSON tree and fails on any null (serde_json writes non-finite floats as null) or
/// non-finite number.
pub fn assert_all_finite(v: &Value, path: &str) {
    match v {
        Value::Null => panic!("null (NaN or infinity?) at {path}"),
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            assert!(x.is_finite(), "non-finite number at {path}: {n}");
        }
        Value::String(s) => {
            let l = s.to_ascii_lowercase();
            assert!(
                l != "nan" && !l.contains("inf"),
                "non-finite string at {path}: {s}"
            );
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                assert_all_finite(x, &format!("{path}[{i}]"));
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                assert_all_finite(x, &format!("{path}.{k}"));
            }
        }
        Value::Bool(_) => {}
    }
}

/// Arc minutes per radian.
pub const ARCMIN_PER_RAD: f64 = 180.0 * 60.0 / PI;

/// Example reducer: eccentricity (m), disc teeth, pins, overall ratio, load share, rated torque.
pub const ECCENTRICITY_M: f64 = 1.3e-3;

pub const DISC_TEETH: f64 = 39.0;

pub const PINS: usize = 40;

pub const RATIO: f64 = 81.0;

pub const RATED_TORQUE_NM: f64 = 412.0;

pub fn rvlife<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args(args)
        .output()
        .expect("cannot start the rvlife binary")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Asserts success and returns stdout.
pub fn ok(o: &Output, what: &str) -> String {
    assert!(
        o.status.success(),
        "{what}: expected success, got {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        stdout(o),
        stderr(o)
    );
    stdout(o)
}

pub fn json_ok(o: &Output, what: &str) -> Value {
    let out = ok(o, what);
    serde_json::from_str(&out)
        .unwrap_or_else(|e| panic!("{what}: stdout is not JSON ({e}):\n{out}"))
}

/// Asserts exit code 2 and that stderr contains every needle.
pub fn assert_input_error(o: &Output, what: &str, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{what}: expected exit code 2\nstdout:\n{}\nstderr:\n{err}",
        stdout(o)
    );
    assert!(
        err.contains("error"),
        "{what}: stderr has no error message:\n{err}"
    );
    for n in needles {
        assert!(
            err.contains(n),
            "{what}: stderr does not mention {n:?}:\n{err}"
        );
    }
}

pub fn paper_text() -> String {
    let out = ok(
        &rvlife(["example", "--preset", "paper"]),
        "rvlife example --preset paper",
    );
    assert!(
        out.contains("[cycloid]"),
        "example has no [cycloid] table:\n{out}"
    );
    without_spec(&out)
}

/// `text` with its `[tolerances]` and `[life]` tables commented out: the tests' base, to which
/// each test adds the spec and tolerances it needs (the presets ship both).
pub fn without_spec(text: &str) -> String {
    let mut skipping = false;
    text.lines()
        .map(|l| {
            let t = l.trim();
            if t.starts_with('[') {
                skipping = t.starts_with("[tolerances]") || t.starts_with("[life]");
            }
            if skipping && !t.is_empty() && !t.starts_with('#') {
                format!("# {l}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect()
}

pub fn write_config(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("cannot write config");
    p
}

/// Name of the TOML table a line opens (`[cycloid]` -> `cycloid`), if it is a header.
pub fn table_header(line: &str) -> Option<&str> {
    let code = line.split('#').next().unwrap_or("").trim();
    code.strip_prefix('[')
        .and_then(|s| s.strip_suffix(']'))
        .map(str::trim)
}

/// Replaces the value of `key` in table `table` (the first `key = ...` line there), keeping
/// the rest of the text. Panics if the key is not found, so that a changed example cannot make
/// a test silently check nothing.
pub fn set_key(text: &str, table: &str, key: &str, value: &str) -> String {
    let mut current = String::new();
    let mut done = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if let Some(t) = table_header(line) {
            current = t.to_string();
        }
        let is_key = line
            .split_once('=')
            .is_some_and(|(k, _)| k.trim() == key && !line.trim_start().starts_with('#'));
        if !done && current == table && is_key {
            out.push(format!("{key} = {value}"));
            done = true;
        } else {
            out.push(line.to_string());
        }
    }
    assert!(done, "key {table}.{key} not found in the example config");
    out.join("\n") + "\n"
}

/// Replaces the body of table `table` (everything up to the next header) by `body`.
pub fn replace_table(text: &str, table: &str, body: &str) -> String {
    let mut current = String::new();
    let mut found = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if let Some(t) = table_header(line) {
            current = t.to_string();
            out.push(line.to_string());
            if t == table {
                found = true;
                out.push(body.to_string());
            }
            continue;
        }
        if current != table {
            out.push(line.to_string());
        }
    }
    assert!(found, "table [{table}] not found in the example config");
    out.join("\n") + "\n"
}

/// Inserts `line` right after the header of table `table`.
pub fn add_line(text: &str, table: &str, line: &str) -> String {
    let mut found = false;
    let mut out = Vec::new();
    for l in text.lines() {
        out.push(l.to_string());
        if table_header(l) == Some(table) {
            out.push(line.to_string());
            found = true;
        }
    }
    assert!(found, "table [{table}] not found in the example config");
    out.join("\n") + "\n"
}

/// The example with a short wear study: 500 h in two stages, and dynamics over 0.15 s (a few
/// seconds in all).
pub fn short_study_text() -> String {
    let t = set_key(&paper_text(), "wear", "stage_hours", "[0.0, 250.0, 500.0]");
    let t = set_key(&t, "wear", "profile_update_hours", "250.0");
    short_dynamics(&t)
}

/// Shortens the simulated time of the dynamics to 0.15 s (TE window 0.1-0.15 s).
pub fn short_dynamics(text: &str) -> String {
    let t = set_key(text, "dynamics", "end_time_s", "0.15");
    set_key(&t, "dynamics", "window_s", "[0.1, 0.15]")
}

pub fn num(v: &Value, key: &str) -> f64 {
    v.get(key)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("missing or non-numeric key {key:?} in {v}"))
}

pub fn num_array(v: &Value, key: &str) -> Vec<f64> {
    v.get(key)
        .and_then(Value::as_array)
        .unwrap_or_else(|| panic!("missing array {key:?}"))
        .iter()
        .map(|x| {
            x.as_f64()
                .unwrap_or_else(|| panic!("non-numeric entry in {key:?}: {x}"))
        })
        .collect()
}

pub fn assert_rel(actual: f64, expected: f64, rel: f64, what: &str) {
    let err = (actual - expected).abs();
    assert!(
        err <= rel * expected.abs(),
        "{what}: {actual} vs expected {expected} (relative error {:.3e} > {rel:e})",
        err / expected.abs()
    );
}

pub fn contact_json(config: &Path, crank_deg: &str, torque_nm: &str) -> Value {
    json_ok(
        &rvlife([
            "contact".as_ref(),
            config.as_os_str(),
            "--crank-deg".as_ref(),
            crank_deg.as_ref(),
            "--torque-nm".as_ref(),
            torque_nm.as_ref(),
            "--json".as_ref(),
        ]),
        "rvlife contact --json",
    )
}

/// Every file under `dir` (relative path -> contents).
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).expect("read_dir") {
            let p = e.expect("dir entry").path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).expect("prefix").to_path_buf();
                out.insert(rel, std::fs::read(&p).expect("read"));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// Entries of `dir` whose name starts with `.rvlife-tmp-`.
pub fn leftover_tmp_dirs(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read_dir")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".rvlife-tmp-"))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// 3. Static transmission error and lost motion.

/// Uniform wear `w` (m) lets the output turn by `w / (a (Zp + Z1/Z2))` (docs/model.md
/// section 6); in arcmin.
pub fn uniform_offset_arcmin(w: f64) -> f64 {
    w / (ECCENTRICITY_M * (PINS as f64 + 0.5)) * ARCMIN_PER_RAD
}

pub fn check_te_arrays(v: &Value) {
    let input = num_array(v, "input_deg");
    let te = num_array(v, "te_arcmin");
    assert_eq!(input.len(), te.len(), "input_deg and te_arcmin lengths");
    let n = input.len();
    assert!(n >= 39 * 40, "only {n} samples over a revolution");
    assert!(te.iter().all(|x| x.is_finite()));
    assert!(input[0].abs() < 1e-9, "input_deg starts at {}", input[0]);
    let end = 360.0 * RATIO * (1.0 - 1.0 / n as f64);
    assert!(
        input[n - 1] >= end - 1e-6,
        "input_deg ends at {} < {end}",
        input[n - 1]
    );
    assert!(
        input.windows(2).all(|w| w[1] > w[0]),
        "input_deg is not increasing"
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Bad input: exit code 2, a message naming the key, no results directory.

/// Writes `text` as a config and checks that `run`, `contact` and `te` all reject it with exit
/// code 2 and a message containing every needle, and that `run` leaves nothing behind.
pub fn check_bad_config(text: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "bad.toml", text);
    let out = dir.path().join("results");
    let o = rvlife([
        "run".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_input_error(&o, "run", needles);
    assert!(!out.exists(), "run left {} behind", out.display());
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
    let o = rvlife([
        "contact".as_ref(),
        cfg.as_os_str(),
        "--crank-deg".as_ref(),
        "0".as_ref(),
        "--torque-nm".as_ref(),
        "412".as_ref(),
    ]);
    assert_input_error(&o, "contact", needles);
    let o = rvlife(["te".as_ref(), cfg.as_os_str()]);
    assert_input_error(&o, "te", needles);
}

pub fn bad_key(table: &str, key: &str, value: &str, needles: &[&str]) {
    check_bad_config(&set_key(&paper_text(), table, key, value), needles);
}

// ---------------------------------------------------------------------------------------------
// 6. The study: results directory.

pub const STAGE_KEYS: [&str; 17] = [
    "backlash_arcmin",
    "hysteresis_loss_arcmin",
    "disc_load_share",
    "flexible_ste_mean_arcmin",
    "flexible_loaded_te_mean_arcmin",
    "torsional_stiffness_nm_per_arcmin",
    "max_von_mises_mpa",
    "dte_mean_arcmin",
    "dte_peak_to_peak_arcmin",
    "hours",
    "max_wear_um",
    "ste_mean_arcmin",
    "ste_peak_to_peak_arcmin",
    "lost_motion_arcmin",
    "loaded_te_mean_arcmin",
    "max_force_n",
    "pins_in_contact",
];

// ---------------------------------------------------------------------------------------------
// 7. Profile export.

pub fn profile(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["profile".as_ref(), "--out".as_ref(), out.as_os_str()];
    args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
    ok(&rvlife(args), &format!("rvlife profile --out {name}"));
    out
}

/// Reads a profile CSV: (x, y, mesh angle, wear) per point.
pub fn read_profile_csv(path: &Path) -> Vec<[f64; 4]> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().map(str::trim),
        Some("x_mm,y_mm,mesh_angle_deg,wear_um"),
        "CSV header"
    );
    lines
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| {
                    x.trim()
                        .parse()
                        .unwrap_or_else(|_| panic!("bad CSV line {l:?}"))
                })
                .collect();
            assert_eq!(v.len(), 4, "CSV line {l:?}");
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}

pub fn check_bad_dynamics(text: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "bad.toml", text);
    let out = dir.path().join("out");
    let o = rvlife([
        "dynamics".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_input_error(&o, "dynamics", needles);
    assert!(!out.exists(), "dynamics left {} behind", out.display());
}

pub fn table_config(dir: &Path, table: &str) -> PathBuf {
    std::fs::write(dir.join("load.csv"), table).unwrap();
    let t = set_key(&paper_text(), "dynamics.load", "kind", "\"table\"");
    let t = replace_table(&t, "dynamics.load", "kind = \"table\"\nfile = \"load.csv\"");
    write_config(dir, "table.toml", &short_dynamics(&t))
}

// ---------------------------------------------------------------------------------------------
// Reliability: no hang, no lost data, every bad input refused by the key the user wrote.

/// The example without the dynamics and the flexible disc (a study of about a second).
pub fn fast_text() -> String {
    let t = set_key(&paper_text(), "dynamics", "enabled", "false");
    set_key(&t, "fem", "enabled", "false")
}

/// Writes `text` as a config in a fresh folder and runs `args` (the config path first) with a
/// time limit of 120 s.
pub fn run_config(text: &str, args: &[&str]) -> (tempfile::TempDir, Output) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", text);
    let mut all: Vec<std::ffi::OsString> = vec![args[0].into(), cfg.into_os_string()];
    all.extend(args[1..].iter().map(|a| std::ffi::OsString::from(*a)));
    let o = rvlife_within(120, all);
    (dir, o)
}

/// `rvlife run CFG --out DIR/r` with a time limit of 120 s: the results folder and the output.
pub fn run_study(dir: &Path, cfg: &Path) -> (PathBuf, Output) {
    let out = dir.join("r");
    let o = rvlife_within(
        120,
        [
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
    );
    (out, o)
}

/// Starts `rvlife run CFG --out OUT` in the background, its output piped.
pub fn spawn_run(cfg: &Path, out: &Path) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args([
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// The example with only `[cycloid]` changed to another stage.
pub fn stage_text(pins: u32, e_mm: f64, rp_mm: f64, rrp_mm: f64, width_mm: f64) -> String {
    let t = set_key(&paper_text(), "cycloid", "pins", &pins.to_string());
    let t = set_key(&t, "cycloid", "eccentricity_mm", &format!("{e_mm:?}"));
    let t = set_key(&t, "cycloid", "pin_circle_radius_mm", &format!("{rp_mm:?}"));
    let t = set_key(&t, "cycloid", "pin_radius_mm", &format!("{rrp_mm:?}"));
    set_key(&t, "cycloid", "width_mm", &format!("{width_mm:?}"))
}

// ---------------------------------------------------------------------------------------------
// Calibration from measurements.

/// The example's Archard coefficient, mm^3/(N m).
pub const EXAMPLE_ARCHARD_MM3: f64 = 6.844807e-9;

/// Hours of the generated measurements.
pub const MEASURED_HOURS: [f64; 8] = [250.0, 500.0, 750.0, 1000.0, 1250.0, 1500.0, 1750.0, 2000.0];

/// Lost motion and backlash (arcmin) that rvlife itself predicts at [`MEASURED_HOURS`] with
/// the Archard coefficient `k_mm3` (fast example, `rvlife run`).
pub fn model_lost_motion_and_backlash(k_mm3: f64) -> Vec<(f64, f64, f64)> {
    let hours = MEASURED_HOURS.map(|h| format!("{h:.1}")).join(", ");
    let t = set_key(&fast_text(), "wear", "stage_hours", &format!("[{hours}]"));
    let t = set_key(
        &t,
        "wear",
        "archard_coefficient_mm3_per_n_m",
        &format!("{k_mm3:e}"),
    );
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "truth.toml", &t);
    let (out, o) = run_study(dir.path(), &cfg);
    ok(&o, "run at k_true");
    let text = std::fs::read_to_string(out.join("stages.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let (h, lm, bl) = (
        col("hours"),
        col("lost_motion_arcmin"),
        col("backlash_arcmin"),
    );
    lines
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            (f[h], f[lm], f[bl])
        })
        .collect()
}

/// Gaussian noise of standard deviation 1, 2 per point, from a fixed seed.
pub fn unit_noise(n: usize, seed: u64) -> Vec<(f64, f64)> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let a: f64 = StandardNormal.sample(&mut rng);
            let b: f64 = StandardNormal.sample(&mut rng);
            (a, b)
        })
        .collect()
}

/// Writes a measurements file from model values plus `sigma` times the noise plus `b0`.
pub fn measured_csv(
    dir: &Path,
    name: &str,
    truth: &[(f64, f64, f64)],
    noise: &[(f64, f64)],
    sigma: f64,
    b0: f64,
) -> PathBuf {
    let mut s = String::from("hours,lost_motion_arcmin,backlash_arcmin\n");
    for ((h, lm, bl), (a, b)) in truth.iter().zip(noise) {
        s.push_str(&format!(
            "{h},{:.6},{:.6}\n",
            (lm + b0 + sigma * a).max(0.0),
            (bl + b0 + sigma * b).max(0.0)
        ));
    }
    let p = dir.join(name);
    std::fs::write(&p, s).unwrap();
    p
}

/// Runs `rvlife calibrate CFG --measured FILE --out DIR [extra]` and reads calibration.json.
pub fn calibrate_json(cfg: &Path, measured: &Path, out: &Path, extra: &[&str]) -> (Value, String) {
    let mut args: Vec<std::ffi::OsString> = vec![
        "calibrate".into(),
        cfg.into(),
        "--measured".into(),
        measured.into(),
        "--out".into(),
        out.into(),
    ];
    args.extend(extra.iter().map(std::ffi::OsString::from));
    let t = std::time::Instant::now();
    let o = rvlife_within(300, args);
    let text = ok(&o, "calibrate --measured");
    eprintln!("calibrate: {:.2} s\n{text}", t.elapsed().as_secs_f64());
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("calibration.json")).unwrap())
            .unwrap();
    assert_all_finite(&v, "calibration.json");
    for f in ["residuals.csv", "calibration.svg", "calibration.png"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    (v, text)
}

/// The fitted coefficient and its interval, mm^3/(N m).
pub fn k_interval(v: &Value) -> (f64, f64, f64) {
    let k = &v["archard_coefficient_mm3_per_n_m"];
    (num(k, "value"), num(k, "lower"), num(k, "upper"))
}

/// `report.html` of a results directory `out`: self-contained (every plot inline, no address,
/// no script, no external resource), under 5 MB, and rendered by headless Chromium without a
/// console message into a screenshot that is not blank. Chromium is required when
/// `RVLIFE_REQUIRE_BROWSER` is set (CI sets it); otherwise a machine without it skips the
/// rendering with a note on stderr.
pub fn assert_report(out: &Path) {
    assert_page(
        out,
        &[
            "Reducer",
            "Model options",
            "Stages",
            "Comparison with the paper",
            "lost_motion_arcmin",
            env!("CARGO_PKG_VERSION"),
        ],
    );
}

/// [`assert_report`] for any of rvlife's report pages (a study's or a Monte Carlo run's): the
/// page checks, the verdict first, every needle present, and the rendering.
pub fn assert_page(out: &Path, needles: &[&str]) {
    let path = out.join("report.html");
    let html = std::fs::read_to_string(&path).expect("report.html");
    assert!(html.len() < 5 << 20, "report.html is {} bytes", html.len());
    let svg_files = std::fs::read_dir(out.join("plots"))
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "svg"))
        .count();
    assert!(svg_files >= 6, "{svg_files} SVG plots");
    assert_eq!(html.matches("<svg").count(), svg_files, "plots inline");
    for needle in [
        "http:", "https:", "<script", "<link", "src=", "@import", "url(",
    ] {
        assert!(!html.contains(needle), "report.html contains {needle:?}");
    }
    // The answer first: the verdict is the report's first section.
    let first = html.find("<h2>").expect("report.html has sections");
    assert!(
        html[first..].starts_with("<h2>Verdict</h2>\n<p class=\"verdict\"><strong>"),
        "report.html's first section is not the verdict"
    );
    for needle in needles {
        assert!(html.contains(needle), "report.html lacks {needle:?}");
    }
    let browser = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|b| {
            Command::new(b)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        });
    let Some(browser) = browser else {
        assert!(
            std::env::var_os("RVLIFE_REQUIRE_BROWSER").is_none(),
            "RVLIFE_REQUIRE_BROWSER is set but no chromium is on the PATH"
        );
        eprintln!("report.html: no chromium on the PATH, rendering not checked");
        return;
    };
    let shot = out.join("report_screenshot.png");
    let o = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1200,4000",
        ])
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", path.canonicalize().unwrap().display()))
        .output()
        .expect("chromium runs");
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "chromium failed:\n{log}");
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(console.is_empty(), "console messages: {console:?}");
    // The screenshot: decoded, and far from one colour (tables, text and plots on white).
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&shot).expect("screenshot written"),
    ));
    let mut reader = decoder.read_info().expect("screenshot is a PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG frame");
    let px = &buf[..info.buffer_size()];
    let step = info.color_type.samples();
    let dark = px
        .chunks(step)
        .filter(|p| p[..3].iter().all(|c| *c < 128))
        .count();
    let colour = px
        .chunks(step)
        .filter(|p| p[..3].iter().max().unwrap() - p[..3].iter().min().unwrap() > 60)
        .count();
    let n = px.len() / step;
    assert!(
        dark > n / 1000 && colour > n / 1000,
        "screenshot looks blank: {dark} dark and {colour} coloured of {n} pixels"
    );
    std::fs::remove_file(&shot).unwrap();
}

/// The Monte Carlo tests' tolerances of every kind (pins 1 um, IT5 radii, 4 um run-out, cranks
/// 1 um and 0.5 arcmin, modifications 0.5 um) and life spec (lost motion 2.3 arcmin, angular
/// TE 1.5 arcmin), appended to a config.
pub const MONTE_CARLO_SPEC: &str = "\n[tolerances]\n\
         pin_radial_um = { normal = 1.0 }\n\
         pin_tangential_um = { normal = 1.0 }\n\
         pin_radius_um = { iso_grade = 5 }\n\
         pin_circle_runout_um = { uniform = 4.0 }\n\
         crank_eccentricity_um = { normal = 1.0 }\n\
         crank_phase_arcmin = { normal = 0.5 }\n\
         equidistant_um = { normal = 0.5 }\n\
         offset_um = { normal = 0.5 }\n\
         \n[life]\nlost_motion_arcmin = 2.3\nangular_te_arcmin = 1.5\n";

/// `rvlife calibrate CFG --measured M` (no `--out`) with a time limit of 300 s.
pub fn calibrate_measured(cfg: &Path, measured: &Path) -> Output {
    rvlife_within(
        300,
        [
            "calibrate".as_ref(),
            cfg.as_os_str(),
            "--measured".as_ref(),
            measured.as_os_str(),
        ],
    )
}

/// Shard `i` of 2 of a two-sample Monte Carlo run of `cfg` (2 crank angles per mesh cycle,
/// `--keep-going`) into `out`, which must succeed.
pub fn montecarlo_shard(cfg: &Path, i: usize, out: &Path) {
    let o = rvlife_within(
        300,
        [
            "montecarlo".as_ref(),
            cfg.as_os_str(),
            "--samples".as_ref(),
            "2".as_ref(),
            "--samples-per-mesh-cycle".as_ref(),
            "2".as_ref(),
            "--keep-going".as_ref(),
            "--shard".as_ref(),
            format!("{i}/2").as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
    );
    ok(&o, &format!("montecarlo shard {i}/2"));
}
