//! Integration tests of the `rvlife` command-line binary.
//!
//! Every test runs the release binary as a separate process, on the built-in example config
//! (`rvlife example`) or an edited copy of it written to a temporary directory.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

mod common;
use common::{assert_all_finite, rvlife_within};

/// Arc minutes per radian.
const ARCMIN_PER_RAD: f64 = 180.0 * 60.0 / PI;
/// Example reducer: eccentricity (m), disc teeth, pins, overall ratio, load share, rated torque.
const ECCENTRICITY_M: f64 = 1.3e-3;
const DISC_TEETH: f64 = 39.0;
const PINS: usize = 40;
const RATIO: f64 = 81.0;
const RATED_TORQUE_NM: f64 = 412.0;

fn rvlife<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args(args)
        .output()
        .expect("cannot start the rvlife binary")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts success and returns stdout.
fn ok(o: &Output, what: &str) -> String {
    assert!(
        o.status.success(),
        "{what}: expected success, got {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        stdout(o),
        stderr(o)
    );
    stdout(o)
}

fn json_ok(o: &Output, what: &str) -> Value {
    let out = ok(o, what);
    serde_json::from_str(&out)
        .unwrap_or_else(|e| panic!("{what}: stdout is not JSON ({e}):\n{out}"))
}

/// Asserts exit code 2 and that stderr contains every needle.
fn assert_input_error(o: &Output, what: &str, needles: &[&str]) {
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

fn example_text() -> String {
    let out = ok(&rvlife(["example"]), "rvlife example");
    assert!(
        out.contains("[cycloid]"),
        "example has no [cycloid] table:\n{out}"
    );
    out
}

fn write_config(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("cannot write config");
    p
}

/// Name of the TOML table a line opens (`[cycloid]` -> `cycloid`), if it is a header.
fn table_header(line: &str) -> Option<&str> {
    let code = line.split('#').next().unwrap_or("").trim();
    code.strip_prefix('[')
        .and_then(|s| s.strip_suffix(']'))
        .map(str::trim)
}

/// Replaces the value of `key` in table `table` (the first `key = ...` line there), keeping
/// the rest of the text. Panics if the key is not found, so that a changed example cannot make
/// a test silently check nothing.
fn set_key(text: &str, table: &str, key: &str, value: &str) -> String {
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
fn replace_table(text: &str, table: &str, body: &str) -> String {
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
fn add_line(text: &str, table: &str, line: &str) -> String {
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
fn short_study_text() -> String {
    let t = set_key(
        &example_text(),
        "wear",
        "stage_hours",
        "[0.0, 250.0, 500.0]",
    );
    let t = set_key(&t, "wear", "profile_update_hours", "250.0");
    short_dynamics(&t)
}

/// Shortens the simulated time of the dynamics to 0.15 s (TE window 0.1-0.15 s).
fn short_dynamics(text: &str) -> String {
    let t = set_key(text, "dynamics", "end_time_s", "0.15");
    set_key(&t, "dynamics", "window_s", "[0.1, 0.15]")
}

fn num(v: &Value, key: &str) -> f64 {
    v.get(key)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("missing or non-numeric key {key:?} in {v}"))
}

fn num_array(v: &Value, key: &str) -> Vec<f64> {
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

fn assert_rel(actual: f64, expected: f64, rel: f64, what: &str) {
    let err = (actual - expected).abs();
    assert!(
        err <= rel * expected.abs(),
        "{what}: {actual} vs expected {expected} (relative error {:.3e} > {rel:e})",
        err / expected.abs()
    );
}

fn contact_json(config: &Path, crank_deg: &str, torque_nm: &str) -> Value {
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
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
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
fn leftover_tmp_dirs(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read_dir")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".rvlife-tmp-"))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// 1. The example config parses back; the contact JSON.

#[test]
fn example_parses_back_and_contact_json_has_the_documented_keys() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "example.toml", &example_text());
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
    let cfg = write_config(dir.path(), "example.toml", &example_text());
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
    let cfg = write_config(dir.path(), "example.toml", &example_text());
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
        assert!(
            (a - b).abs() <= 1e-3 * fmax,
            "pin {j} at +412 N m: {a} N; pin {} at -412 N m: {b} N",
            (PINS - j) % PINS
        );
    }
    assert_rel(
        num(&neg, "max_force_n"),
        num(&pos, "max_force_n"),
        1e-3,
        "max force",
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Static transmission error and lost motion.

/// Uniform wear `w` (m) lets the output turn by `w / (a (Zp + Z1/Z2))` (docs/model.md
/// section 6); in arcmin.
fn uniform_offset_arcmin(w: f64) -> f64 {
    w / (ECCENTRICITY_M * (PINS as f64 + 0.5)) * ARCMIN_PER_RAD
}

fn check_te_arrays(v: &Value) {
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

#[test]
fn te_json_unworn_is_zero() {
    let v = json_ok(&rvlife(["te", "--json"]), "rvlife te --json");
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
    let v = json_ok(
        &rvlife(["te", "--json", "--wear-um", "10"]),
        "rvlife te --json --wear-um 10",
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
        &example_text(),
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

// ---------------------------------------------------------------------------------------------
// 5. Bad input: exit code 2, a message naming the key, no results directory.

/// Writes `text` as a config and checks that `run`, `contact` and `te` all reject it with exit
/// code 2 and a message containing every needle, and that `run` leaves nothing behind.
fn check_bad_config(text: &str, needles: &[&str]) {
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

fn bad_key(table: &str, key: &str, value: &str, needles: &[&str]) {
    check_bad_config(&set_key(&example_text(), table, key, value), needles);
}

#[test]
fn bad_fem_bore_cuts_the_teeth() {
    let t = format!("{}\ncrank_bore_diameter_mm = 40.0\n", example_text());
    check_bad_config(&t, &["fem.crank_bore_diameter_mm", "cuts the teeth"]);
}

#[test]
fn bad_fem_holes_cut_each_other() {
    check_bad_config(
        &add_line(&example_text(), "fem", "centre_hole_diameter_mm = 60.0"),
        &["fem.", "cut each other"],
    );
}

#[test]
fn bad_fem_mesh_beyond_memory() {
    let t = set_key(&example_text(), "fem", "flank_element_size_mm", "0.01");
    let t = set_key(&t, "fem", "load_patch_half_width_mm", "0.02");
    check_bad_config(&t, &["fem.flank_element_size_mm", "GB"]);
}

#[test]
fn bad_eccentricity_k1_above_one() {
    bad_key("cycloid", "eccentricity_mm", "1.7", &["eccentricity_mm"]);
}

#[test]
fn bad_too_few_pins() {
    bad_key("cycloid", "pins", "2", &["pins"]);
}

#[test]
fn bad_negative_pin_radius() {
    bad_key("cycloid", "pin_radius_mm", "-3.0", &["pin_radius_mm"]);
}

#[test]
fn bad_zero_width() {
    bad_key("cycloid", "width_mm", "0.0", &["width_mm"]);
}

#[test]
fn bad_undercut_profile() {
    bad_key(
        "cycloid",
        "pin_radius_mm",
        "5.0",
        &["pin_radius_mm", "undercut"],
    );
}

#[test]
fn bad_nan_pin_radius() {
    bad_key("cycloid", "pin_radius_mm", "nan", &["pin_radius_mm"]);
}

#[test]
fn bad_infinite_eccentricity() {
    bad_key("cycloid", "eccentricity_mm", "inf", &["eccentricity_mm"]);
}

#[test]
fn bad_unknown_key() {
    check_bad_config(
        &add_line(&example_text(), "cycloid", "bogus = 1"),
        &["bogus"],
    );
}

#[test]
fn bad_negative_sinusoidal_amplitude() {
    let text = replace_table(
        &example_text(),
        "load",
        "kind = \"sinusoidal\"\namplitude_nm = -5.0",
    );
    check_bad_config(&text, &["amplitude_nm"]);
}

#[test]
fn bad_stage_hours_not_increasing() {
    bad_key(
        "wear",
        "stage_hours",
        "[0.0, 2500.0, 1250.0]",
        &["stage_hours"],
    );
}

#[test]
fn bad_load_share_above_one() {
    let text = set_key(&example_text(), "contact", "support", "\"rigid\"");
    check_bad_config(
        &add_line(&text, "contact", "load_share = 1.5"),
        &["contact.load_share"],
    );
}

#[test]
fn bad_contact_band_force() {
    for v in ["0.0", "-5.0", "1e300"] {
        check_bad_config(
            &add_line(&example_text(), "contact", &format!("band_force_n = {v}")),
            &["contact.band_force_n"],
        );
    }
}

#[test]
fn bad_contact_band() {
    check_bad_config(
        &set_key(&example_text(), "contact", "band", "\"widest\""),
        &["contact.band"],
    );
}

#[test]
fn bad_poisson_ratio() {
    bad_key("materials.disc", "poisson_ratio", "0.6", &["poisson_ratio"]);
}

#[test]
fn bad_unparsable_toml() {
    check_bad_config("[cycloid\npins = 40\n", &[]);
}

#[test]
fn bad_missing_config_file() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("no-such-config.toml");
    let out = dir.path().join("results");
    let o = rvlife([
        "run".as_ref(),
        cfg.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_input_error(&o, "run with a missing config", &["no-such-config.toml"]);
    assert!(!out.exists(), "run left {} behind", out.display());
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
    let o = rvlife(["te".as_ref(), cfg.as_os_str()]);
    assert_input_error(&o, "te with a missing config", &["no-such-config.toml"]);
}

#[test]
fn bad_contact_arguments() {
    let o = rvlife(["contact", "--crank-deg", "nan", "--torque-nm", "412"]);
    assert_input_error(&o, "contact --crank-deg nan", &["--crank-deg"]);
    let o = rvlife(["contact", "--crank-deg", "0", "--torque-nm", "inf"]);
    assert_input_error(&o, "contact --torque-nm inf", &["--torque-nm"]);
    let o = rvlife([
        "contact",
        "--crank-deg",
        "0",
        "--torque-nm",
        "412",
        "--wear-um",
        "-1",
    ]);
    assert_input_error(&o, "contact --wear-um -1", &["--wear-um"]);
    // Missing required argument and conflicting wear options: clap's usage errors, also code 2.
    let o = rvlife(["contact", "--crank-deg", "0"]);
    assert_input_error(&o, "contact without --torque-nm", &["--torque-nm"]);
    let o = rvlife(["te", "--wear-um", "5", "--hours", "100"]);
    assert_input_error(&o, "te --wear-um with --hours", &[]);
    let o = rvlife(["te", "--torque-nm", "nan"]);
    assert_input_error(&o, "te --torque-nm nan", &["--torque-nm"]);
    let o = rvlife(["no-such-subcommand"]);
    assert_input_error(&o, "unknown subcommand", &[]);
}

#[test]
fn bad_profile_extension() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.txt");
    let o = rvlife(["profile".as_ref(), "--out".as_ref(), out.as_os_str()]);
    assert_input_error(&o, "profile --out x.txt", &["--out"]);
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(
        left.is_empty(),
        "profile with a bad extension wrote {left:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// 6. The study: results directory.

const STAGE_KEYS: [&str; 17] = [
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

    // With --force: replaced (a stray file disappears).
    std::fs::write(out.join("stray.txt"), "x").unwrap();
    ok(&run(&["--force"]), "rvlife run --force");
    assert!(out.join("summary.json").is_file());
    assert!(!out.join("stray.txt").exists(), "--force kept an old file");
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

// ---------------------------------------------------------------------------------------------
// 7. Profile export.

fn profile(dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["profile".as_ref(), "--out".as_ref(), out.as_os_str()];
    args.extend(extra.iter().map(|s| std::ffi::OsStr::new(*s)));
    ok(&rvlife(args), &format!("rvlife profile --out {name}"));
    out
}

/// Reads a profile CSV: (x, y, mesh angle, wear) per point.
fn read_profile_csv(path: &Path) -> Vec<[f64; 4]> {
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
    let cfg = write_config(dir.path(), "dyn.toml", &short_dynamics(&example_text()));
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
    let cfg = write_config(dir.path(), "dyn.toml", &short_dynamics(&example_text()));
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

fn check_bad_dynamics(text: &str, needles: &[&str]) {
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

#[test]
fn bad_dynamics_stiffness_damping_and_times() {
    let ex = example_text();
    check_bad_dynamics(
        &set_key(
            &ex,
            "reducer.bearings",
            "crank_disc_stiffness_n_per_um",
            "-5.0",
        ),
        &["reducer.bearings.crank_disc_stiffness_n_per_um", "-5"],
    );
    check_bad_dynamics(
        &set_key(&ex, "reducer.gears", "mesh_stiffness_n_per_um", "1e12"),
        &["reducer.gears.mesh_stiffness_n_per_um"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics.impact", "damping_ratio", "-0.1"),
        &["dynamics.impact.damping_ratio"],
    );
    check_bad_dynamics(
        &add_line(
            &ex,
            "dynamics.impact",
            "stiffness_n_per_m_e = 1e30\nexponent = 1.5",
        ),
        &["dynamics.impact.stiffness_n_per_m_e"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics", "window_s", "[0.5, 0.9]"),
        &["dynamics.window_s", "end_time_s"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics", "end_time_s", "0.0"),
        &["dynamics.end_time_s"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics.drive", "ramp_end_s", "2.0"),
        &["dynamics.drive.ramp_end_s"],
    );
    check_bad_dynamics(
        &set_key(&ex, "dynamics", "relative_tolerance", "0.5"),
        &["dynamics.relative_tolerance"],
    );
}

fn table_config(dir: &Path, table: &str) -> PathBuf {
    std::fs::write(dir.join("load.csv"), table).unwrap();
    let t = set_key(&example_text(), "dynamics.load", "kind", "\"table\"");
    let t = replace_table(&t, "dynamics.load", "kind = \"table\"\nfile = \"load.csv\"");
    write_config(dir, "table.toml", &short_dynamics(&t))
}

#[test]
fn bad_load_tables_unsorted_gaps_nan() {
    for (table, needles) in [
        (
            "time_s,torque_nm\n0,0\n0.5,100\n0.3,200\n1.0,0\n",
            &["load.csv row 3 column time_s", "increase"][..],
        ),
        (
            "time_s,torque_nm\n0,0\n0.5,\n1.0,0\n",
            &["load.csv row 2 column torque_nm", "gap"][..],
        ),
        (
            "time_s,torque_nm\n0,0\n0.5,NaN\n1.0,0\n",
            &["load.csv row 2 column torque_nm", "finite"][..],
        ),
        (
            "time_s,torque_nm\n0,0\n0.1,10\n",
            &["load.csv column time_s", "cover"][..],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let cfg = table_config(dir.path(), table);
        let o = rvlife(["dynamics".as_ref(), cfg.as_os_str(), "--json".as_ref()]);
        assert_input_error(&o, "load table", needles);
    }
    // A good table runs.
    let dir = tempfile::tempdir().unwrap();
    let cfg = table_config(dir.path(), "time_s,torque_nm\n0,0\n0.05,200\n1.0,200\n");
    let v = json_ok(
        &rvlife(["dynamics".as_ref(), cfg.as_os_str(), "--json".as_ref()]),
        "good load table",
    );
    assert!(num(&v, "te_mean_arcmin") > 0.0, "{v}");
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

// ---------------------------------------------------------------------------------------------
// Reliability: no hang, no lost data, every bad input refused by the key the user wrote.

/// The example without the dynamics and the flexible disc (a study of about a second).
fn fast_text() -> String {
    let t = set_key(&example_text(), "dynamics", "enabled", "false");
    set_key(&t, "fem", "enabled", "false")
}

/// Writes `text` as a config in a fresh folder and runs `args` (the config path first) with a
/// time limit of 120 s.
fn run_config(text: &str, args: &[&str]) -> (tempfile::TempDir, Output) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", text);
    let mut all: Vec<std::ffi::OsString> = vec![args[0].into(), cfg.into_os_string()];
    all.extend(args[1..].iter().map(|a| std::ffi::OsString::from(*a)));
    let o = rvlife_within(120, all);
    (dir, o)
}

/// `rvlife run CFG --out DIR/r` with a time limit of 120 s: the results folder and the output.
fn run_study(dir: &Path, cfg: &Path) -> (PathBuf, Output) {
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

/// The wear integration always advances: with an update step below the old 1e-9 h round-off
/// margin (a huge Archard coefficient over 2e-9 h) it used to loop for ever.
#[test]
fn wear_integration_advances_below_the_old_hour_margin() {
    let t = set_key(
        &fast_text(),
        "wear",
        "archard_coefficient_mm3_per_n_m",
        "1e3",
    );
    let (_d, o) = run_config(&t, &["te", "--hours", "2e-9", "--json"]);
    let v: Value = serde_json::from_str(&ok(&o, "te --hours 2e-9")).unwrap();
    assert!(num(&v, "max_wear_um") > 0.0, "{v}");
    assert_all_finite(&v, "te");
}

/// Configs whose work exceeds the budget are refused before the work, naming the key that
/// drives it and the estimate: 10 000 load levels; a wear step of 0.01 um at ten times the
/// example's wear rate; a duty cycle of 200 000 distinct rows.
#[test]
fn work_beyond_the_budget_is_refused_by_its_key() {
    let t = replace_table(
        &fast_text(),
        "load",
        "kind = \"sinusoidal\"\namplitude_nm = 412.0\nlevels = 10000",
    );
    let (_d, o) = run_config(&t, &["te"]);
    assert_input_error(
        &o,
        "load.levels",
        &["load.levels", "contact solves", "budget"],
    );
    let t = set_key(&fast_text(), "wear", "max_wear_step_um", "0.01");
    let t = set_key(&t, "wear", "archard_coefficient_mm3_per_n_m", "6.8e-8");
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &t);
    let (out, o) = run_study(dir.path(), &cfg);
    assert_input_error(
        &o,
        "max_wear_step_um",
        &["wear.max_wear_step_um", "profile updates", "budget"],
    );
    assert!(!out.exists());
    assert_eq!(leftover_tmp_dirs(dir.path()), Vec::<String>::new());
    let mut csv = String::from("duration_s,torque_nm,speed_rpm\n");
    for i in 0..200_000 {
        csv.push_str(&format!("1,{},1500\n", 100.0 + i as f64 * 1e-3));
    }
    std::fs::write(dir.path().join("dc.csv"), csv).unwrap();
    let t = replace_table(
        &fast_text(),
        "load",
        "kind = \"duty_cycle\"\nfile = \"dc.csv\"",
    );
    let cfg = write_config(dir.path(), "dc.toml", &t);
    let o = rvlife_within(120, ["te".as_ref(), cfg.as_os_str()]);
    assert_input_error(
        &o,
        "duty cycle rows",
        &["load.file", "200000 levels", "budget"],
    );
}

/// Torques the unworn stage cannot carry are refused before any analysis (exit 2, not a
/// solver failure), naming the key and the torque the stage does carry: a wear load of 1e12
/// and of 12 700 N m, a dynamic amplitude of 5e5 N m, `--torque-nm 1e30`, and an eccentricity
/// so small (0.014-0.033 mm) that the rated torque is beyond the stage.
#[test]
fn torques_beyond_the_stage_are_refused_by_their_key() {
    for (torque, why) in [
        ("1e12", "static analysis"),
        ("12700", "twist beyond first contact"),
    ] {
        let t = set_key(&fast_text(), "load", "torque_nm", torque);
        let (_d, o) = run_config(&t, &["te", "--hours", "100"]);
        assert_input_error(&o, torque, &["load.torque_nm", why, "carries at most"]);
    }
    let t = set_key(&fast_text(), "dynamics.load", "amplitude_nm", "5e5");
    let (_d, o) = run_config(&t, &["dynamics"]);
    assert_input_error(
        &o,
        "amplitude",
        &["dynamics.load.amplitude_nm", "carries at most"],
    );
    let o = rvlife_within(60, ["te", "--torque-nm", "1e30"]);
    assert_input_error(&o, "--torque-nm", &["--torque-nm", "carries at most"]);
    let o = rvlife_within(60, ["contact", "--crank-deg", "0", "--torque-nm", "-1e30"]);
    assert_input_error(&o, "contact --torque-nm", &["--torque-nm", "clockwise"]);
    // Disc bearings a hundred times softer: the disc would move by most of the eccentricity
    // under the rated torque (the load steps ran for hours, advancing by ever smaller steps).
    let t = set_key(
        &fast_text(),
        "reducer.bearings",
        "crank_disc_stiffness_n_per_um",
        "5",
    );
    let (_d, o) = run_config(&t, &["contact", "--crank-deg", "0", "--torque-nm", "100"]);
    assert_input_error(
        &o,
        "soft bearings",
        &["reducer.rated_torque_nm", "carries at most"],
    );
    for e in ["0.014", "0.033", "0.13"] {
        let t = set_key(&fast_text(), "cycloid", "eccentricity_mm", e);
        let (_d, o) = run_config(&t, &["te"]);
        assert_input_error(
            &o,
            e,
            &["reducer.rated_torque_nm", "carries at most", "[cycloid]"],
        );
    }
}

/// Modifications that take the flank out of mesh or into the pins are refused by their key.
#[test]
fn non_physical_modifications_are_refused_by_their_key() {
    for (key, value, words) in [
        ("offset_mm", "2.75", "no pin stops"),
        ("equidistant_mm", "-1", "interferes"),
        ("offset_mm", "-2.75", "contact geometry"),
        ("rotation_deg", "-2e8", "30 arcmin"),
        ("rotation_deg", "1e300", "30 arcmin"),
    ] {
        let t = set_key(&fast_text(), "cycloid.modification", key, value);
        let (_d, o) = run_config(&t, &["te"]);
        assert_input_error(&o, key, &[&format!("cycloid.modification.{key}"), words]);
    }
}

/// Long horizons, deep targets and options that set keys: `--hours 1e12`, `calibrate
/// --target-wear-um 1e9`, `--wear-um 1e9` and `dynamics --torque-nm 1e5` are refused by their
/// option (exit 2), not by a solver after minutes or by the key the option sets.
#[test]
fn horizons_and_targets_beyond_the_model_are_refused() {
    let o = rvlife_within(60, ["te", "--hours", "1e12"]);
    assert_input_error(&o, "--hours", &["--hours", "1e7"]);
    let o = rvlife_within(60, ["calibrate", "--target-wear-um", "1e9"]);
    assert_input_error(&o, "target", &["--target-wear-um", "tooth height"]);
    let o = rvlife_within(60, ["te", "--wear-um", "1e9"]);
    assert_input_error(&o, "--wear-um", &["invalid --wear-um", "folds"]);
    // An option that sets a key is named as the option.
    let o = rvlife_within(60, ["dynamics", "--load", "constant", "--torque-nm", "1e5"]);
    assert_input_error(
        &o,
        "dynamics --torque-nm",
        &["invalid --torque-nm", "carries at most"],
    );
}

/// Errors blame the key the user wrote: lengths out of the physical range name themselves
/// (not the contact stiffness of the dynamics); `calibrate` over a zero-hour study names
/// `wear.stage_hours`; a default the file does not set is named as a default, with the key it
/// depends on.
#[test]
fn errors_blame_the_key_the_user_wrote() {
    for (table, key, value) in [
        ("cycloid", "pin_circle_radius_mm", "1e308"),
        ("cycloid", "width_mm", "1e-12"),
        ("reducer", "rated_torque_nm", "1e300"),
        ("reducer", "rated_torque_nm", "1e-12"),
    ] {
        let t = set_key(&fast_text(), table, key, value);
        let (_d, o) = run_config(&t, &["te"]);
        let what = format!("{table}.{key}");
        assert_input_error(&o, &what, &[&format!("invalid {what} = ")]);
        assert!(!stderr(&o).contains("dynamics.impact"), "{}", stderr(&o));
        assert!(stderr(&o).len() < 400, "{}", stderr(&o));
    }
    let t = set_key(&fast_text(), "wear", "stage_hours", "[0.0]");
    let (_d, o) = run_config(&t, &["calibrate"]);
    assert_input_error(&o, "stage_hours", &["wear.stage_hours", "0 h"]);
    // The bore default (2 x dynamics.inertia.crank_bore_radius_mm) cuts the teeth.
    let t = add_line(
        &example_text(),
        "dynamics.inertia",
        "crank_bore_radius_mm = 19.0",
    );
    let (_d, o) = run_config(&t, &["te"]);
    assert_input_error(
        &o,
        "default bore",
        &[
            "fem.crank_bore_diameter_mm (not in your file",
            "dynamics.inertia.crank_bore_radius_mm",
        ],
    );
}

/// Duty-cycle durations that would overflow their sum are refused by row; long but finite ones
/// keep their shares (the old sum became infinite, every weight 0, and the study reported no
/// wear with exit 0).
#[test]
fn duty_cycle_durations_cannot_overflow() {
    let dir = tempfile::tempdir().unwrap();
    let t = replace_table(
        &fast_text(),
        "load",
        "kind = \"duty_cycle\"\nfile = \"dc.csv\"",
    );
    let t = set_key(&t, "wear", "stage_hours", "[0.0, 500.0]");
    let cfg = write_config(dir.path(), "c.toml", &t);
    std::fs::write(
        dir.path().join("dc.csv"),
        "duration_s,torque_nm,speed_rpm\n1e308,412,1500\n1e308,-412,1500\n",
    )
    .unwrap();
    let o = rvlife_within(60, ["te".as_ref(), cfg.as_os_str()]);
    assert_input_error(&o, "1e308", &["row 1 column duration_s", "1e12"]);
    std::fs::write(
        dir.path().join("dc.csv"),
        "duration_s,torque_nm,speed_rpm\n1e12,412,1500\n1e12,412,1500\n1e12,-412,1500\n",
    )
    .unwrap();
    let (out, o) = run_study(dir.path(), &cfg);
    ok(&o, "run with 1e12 s rows");
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let wear = num(&s["stages"][1], "max_wear_um");
    assert!(wear > 1.0, "no wear from a finite duty cycle: {wear}");
}

/// A study past the model's validity reports the stages before it, says where and why it
/// stopped, and exits 0 (it exited 1 with no result).
#[test]
fn study_stops_at_the_validity_limit_with_the_stages_before_it() {
    let t = set_key(
        &fast_text(),
        "wear",
        "archard_coefficient_mm3_per_n_m",
        "3.4e-7",
    );
    let t = set_key(&t, "wear", "max_wear_step_um", "20.0");
    let t = set_key(
        &t,
        "wear",
        "stage_hours",
        "[0.0, 2000.0, 4000.0, 6000.0, 8000.0, 10000.0]",
    );
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &t);
    let (out, o) = run_study(dir.path(), &cfg);
    let text = ok(&o, "run past validity");
    assert!(text.contains("leaves its validity at"), "{text}");
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let lim = &s["validity_limit"];
    let stages = s["stages"].as_array().unwrap();
    assert!(!stages.is_empty() && stages.len() < 6, "{}", stages.len());
    let last = num(stages.last().unwrap(), "hours");
    let at = num(lim, "hours");
    assert!(
        at > last && at <= 10000.0,
        "limit {at} h, last stage {last} h"
    );
    assert!(
        num(lim, "max_wear_um") > 0.0 && lim["reason"].is_string(),
        "{lim}"
    );
    assert_all_finite(&s["stages"], "stages");
    // The wear-only command says the same by its option.
    let o = rvlife_within(
        120,
        [
            "te".as_ref(),
            cfg.as_os_str(),
            "--hours".as_ref(),
            "9000".as_ref(),
        ],
    );
    assert_input_error(&o, "--hours past validity", &["--hours", "validity"]);
}

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

/// Starts `rvlife run CFG --out OUT` in the background, its output piped.
fn spawn_run(cfg: &Path, out: &Path) -> std::process::Child {
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

/// The example with only `[cycloid]` changed to another stage.
fn stage_text(pins: u32, e_mm: f64, rp_mm: f64, rrp_mm: f64, width_mm: f64) -> String {
    let t = set_key(&example_text(), "cycloid", "pins", &pins.to_string());
    let t = set_key(&t, "cycloid", "eccentricity_mm", &format!("{e_mm:?}"));
    let t = set_key(&t, "cycloid", "pin_circle_radius_mm", &format!("{rp_mm:?}"));
    let t = set_key(&t, "cycloid", "pin_radius_mm", &format!("{rrp_mm:?}"));
    set_key(&t, "cycloid", "width_mm", &format!("{width_mm:?}"))
}

/// A user's own reducer: with only `[cycloid]` of the example edited (a Zp 30 stage, and Zp
/// 20 and 60 stages), the sizes outside it (crank circle, crank bores, pillar and centre
/// holes) default from the stage, and `te`, `contact` and `hysteresis` run; the Zp 30 stage
/// runs the whole study, dynamics and flexible disc included. Before, `te` failed on the crank
/// bores of the disabled-or-not `[dynamics]` section.
#[test]
fn a_reducer_with_only_cycloid_edited_runs() {
    let stages = [
        stage_text(30, 1.2, 50.0, 4.0, 10.0),
        stage_text(20, 1.5, 50.0, 5.0, 10.0),
        stage_text(60, 0.6, 60.0, 2.5, 10.0),
    ];
    for (i, t) in stages.iter().enumerate() {
        for args in [
            &["te", "--json"][..],
            &[
                "contact",
                "--crank-deg",
                "3",
                "--torque-nm",
                "200",
                "--json",
            ][..],
            &["hysteresis", "--json"][..],
        ] {
            let (_d, o) = run_config(t, args);
            let v: Value = serde_json::from_str(&ok(&o, &format!("stage {i}: {args:?}"))).unwrap();
            assert_all_finite(&v, args[0]);
        }
    }
    let t = short_dynamics(&set_key(&stages[0], "wear", "stage_hours", "[0.0, 1250.0]"));
    let dir = tempfile::tempdir().unwrap();
    let cfg = write_config(dir.path(), "c.toml", &t);
    let (out, o) = run_study(dir.path(), &cfg);
    ok(&o, "Zp 30 study");
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_all_finite(&s, "summary");
    let last = &s["stages"][1];
    assert!(num(last, "max_wear_um") > 0.0 && last.get("dte_mean_arcmin").is_some());
    assert!(last.get("flexible_ste_mean_arcmin").is_some(), "{last}");
}

/// A command checks only what it uses: a bad value in a disabled `[dynamics]` does not stop
/// `te`, and the `dynamics` command, which uses the section, names it.
#[test]
fn commands_check_only_the_sections_they_use() {
    let t = set_key(&fast_text(), "dynamics", "end_time_s", "-1.0");
    let (_d, o) = run_config(&t, &["te"]);
    ok(&o, "te with a bad, disabled [dynamics]");
    let (_d, o) = run_config(&t, &["dynamics"]);
    assert_input_error(&o, "dynamics command", &["dynamics.end_time_s"]);
    let t = set_key(&fast_text(), "fem", "flank_element_size_mm", "0.001");
    let (_d, o) = run_config(&t, &["contact", "--crank-deg", "0", "--torque-nm", "100"]);
    ok(&o, "contact with a bad, disabled [fem]");
}

/// Every built-in reducer (`rvlife example --list`) prints a config that runs `te` and
/// `hysteresis`; the classes rank by stiffness as by size (RV-20E < RV-40E < RV-80E).
#[test]
fn every_preset_runs_te_and_hysteresis() {
    let list = ok(&rvlife(["example", "--list"]), "example --list");
    let names: Vec<&str> = list
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert_eq!(
        names,
        ["paper", "rv-20e", "rv-40e", "rv-80e", "single-stage"],
        "{list}"
    );
    let mut stiffness = BTreeMap::new();
    for name in &names {
        let text = ok(&rvlife(["example", "--preset", name]), name);
        let (_d, o) = run_config(&text, &["te", "--json"]);
        let v: Value = serde_json::from_str(&ok(&o, &format!("{name} te"))).unwrap();
        assert_all_finite(&v, name);
        let (_d, o) = run_config(&text, &["hysteresis", "--json"]);
        let v: Value = serde_json::from_str(&ok(&o, &format!("{name} hysteresis"))).unwrap();
        assert_all_finite(&v, name);
        stiffness.insert(
            name.to_string(),
            num(&v, "torsional_stiffness_nm_per_arcmin"),
        );
    }
    assert!(stiffness["rv-20e"] < stiffness["rv-40e"] && stiffness["rv-40e"] < stiffness["rv-80e"]);
    assert_eq!(stiffness["paper"], stiffness["rv-40e"]);
    let o = rvlife(["example", "--preset", "rv-1000e"]);
    assert_input_error(&o, "unknown preset", &["--preset", "rv-20e"]);
}

// ---------------------------------------------------------------------------------------------
// Calibration from measurements.

/// The example's Archard coefficient, mm^3/(N m).
const EXAMPLE_ARCHARD_MM3: f64 = 6.844807e-9;
/// Hours of the generated measurements.
const MEASURED_HOURS: [f64; 8] = [250.0, 500.0, 750.0, 1000.0, 1250.0, 1500.0, 1750.0, 2000.0];

/// Lost motion and backlash (arcmin) that rvlife itself predicts at [`MEASURED_HOURS`] with
/// the Archard coefficient `k_mm3` (fast example, `rvlife run`).
fn model_lost_motion_and_backlash(k_mm3: f64) -> Vec<(f64, f64, f64)> {
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
fn unit_noise(n: usize, seed: u64) -> Vec<(f64, f64)> {
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
fn measured_csv(
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
fn calibrate_json(cfg: &Path, measured: &Path, out: &Path, extra: &[&str]) -> (Value, String) {
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
fn k_interval(v: &Value) -> (f64, f64, f64) {
    let k = &v["archard_coefficient_mm3_per_n_m"];
    (num(k, "value"), num(k, "lower"), num(k, "upper"))
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
            let (v0, _) = calibrate_json(&cfg, &m, &dir.path().join("fit0"), &[]);
            let (k0, lo0, hi0) = k_interval(&v0);
            eprintln!("without b0: {k0:.5e} [{lo0:.5e}, {hi0:.5e}]");
            assert!(
                !(lo0 <= k_true && k_true <= hi0),
                "without b0 the play should bias k: {k0} [{lo0}, {hi0}]"
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
    for (name, text, needles) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let t = std::time::Instant::now();
        let o = rvlife_within(
            60,
            [
                "calibrate".as_ref(),
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
        "--measured".as_ref(),
        p.as_os_str(),
        "--fit-running-in".as_ref(),
    ]);
    assert_input_error(
        &o,
        "running-in, 2 values",
        &["2 measured value(s)", "at least 3"],
    );
    // --fit-running-in and --out need --measured (clap: exit 2).
    let o = rvlife(["calibrate", "--fit-running-in"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// `report.html` of a results directory `out`: self-contained (every plot inline, no address,
/// no script, no external resource), under 5 MB, and rendered by headless Chromium without a
/// console message into a screenshot that is not blank. Chromium is required when
/// `RVLIFE_REQUIRE_BROWSER` is set (CI sets it); otherwise a machine without it skips the
/// rendering with a note on stderr.
fn assert_report(out: &Path) {
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
    for needle in [
        "Reducer",
        "Model options",
        "Stages",
        "Comparison with the paper",
        "lost_motion_arcmin",
        env!("CARGO_PKG_VERSION"),
    ] {
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
            "--window-size=1200,2400",
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
