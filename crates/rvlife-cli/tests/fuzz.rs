//! Config and duty-cycle fuzzing of the `rvlife` binary (proptest).
//!
//! Each case is a mutated copy of the built-in example (dynamics and flexible disc off, a
//! 1000 h study): one or two keys get an extreme, zero, negative, scaled, non-finite or
//! wrongly typed value, or are removed; one case in four also swaps the load for a generated
//! duty cycle (durations from 1e-300 to 1e308 s, zero and negative ones, NaN; torques beyond
//! the stage; speeds from 0 to 1e300 rpm). `rvlife run` must end with exit 0 or 2, never a
//! panic, a hang past the work budget (`--work-budget-min 1`, killed at 240 s), or a NaN or
//! infinity in any output; an exit 2 must print one `error: invalid ...`/`error: config ...`
//! line naming a key.
//!
//! The base config carries part errors of a precision reducer's size (`[errors]`), so that the
//! gear, bearing and part-error keys are mutated with the rest. A second test fuzzes the
//! newer commands: `montecarlo` on a mutated config (its `[tolerances]` and `[life]` keys
//! among the rest), `merge` of shards with one mutated cell, and `calibrate --measured` with a
//! generated measurements file. Each prints its cases, outcomes and slowest refusal.
//!
//! A third test fuzzes the keys of the bearings, meshes, parts in series, contact law and wear
//! model on every preset through `te` and `hysteresis`; a fourth runs `montecarlo` on every
//! preset and fails on any sample that does not run.
//!
//! `RVLIFE_FUZZ_CASES` sets the number of cases (default 60, the CI run; the seed is fixed, so
//! CI runs the same cases every time, and `RVLIFE_FUZZ_SEED` picks others);
//! `RVLIFE_FUZZ_COMMAND_CASES` those of the newer commands (default 12),
//! `RVLIFE_FUZZ_PART_CASES` those of the part keys (default 40) and `RVLIFE_FUZZ_MC_CASES` the
//! Monte Carlo runs (default 5).

use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use proptest::prelude::*;
use proptest::test_runner::{Config as RunnerConfig, RngAlgorithm, TestRng, TestRunner};
use serde_json::Value;

mod common;
use common::{assert_all_finite, rvlife_within};

/// Part errors of a precision reducer's size (a few micrometres and arcminutes).
const ERRORS: &str =
    "\n[errors]\npin_radial_um = [1.0, -1.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, \
0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, \
0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -0.5]\npin_circle_runout_um = 0.5\n\
pin_circle_runout_deg = 30.0\ncrank_eccentricity_um = [1.0, -1.0]\n\
crank_phase_arcmin = [0.5, 0.0]\n";

/// The slowest refusal (exit 2) so far of each test: seconds and the case.
static SLOWEST_RUN: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));
static SLOWEST_COMMAND: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));

fn note_refusal(slowest: &Mutex<(f64, String)>, secs: f64, case: &str) {
    let mut s = slowest.lock().unwrap_or_else(|e| e.into_inner());
    if secs > s.0 {
        *s = (secs, case.to_string());
    }
}

fn slowest_refusal(slowest: &Mutex<(f64, String)>) -> String {
    let s = slowest.lock().unwrap_or_else(|e| e.into_inner());
    let first =
        s.1.lines()
            .rev()
            .find(|l| l.starts_with("error"))
            .unwrap_or("");
    format!("{:.2} s ({first})", s.0)
}

/// The example, fast: no dynamics, no flexible disc, stages at 0, 500 and 1000 h.
fn base_config() -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .arg("example")
        .output()
        .expect("rvlife example");
    let text = String::from_utf8(o.stdout).expect("utf-8");
    text.lines()
        .map(|l| {
            let key = l.split('=').next().unwrap_or("").trim();
            match key {
                "enabled" => "enabled = false".to_string(),
                "stage_hours" => "stage_hours = [0.0, 500.0, 1000.0]".to_string(),
                _ => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
        + ERRORS
}

/// Indices of the `key = value` lines of `text`.
fn key_lines(text: &str) -> Vec<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| {
            let t = l.trim_start();
            !t.starts_with('#') && !t.starts_with('[') && t.contains('=')
        })
        .map(|(i, _)| i)
        .collect()
}

/// Replacement values: extremes, zero, negatives, non-finite, wrong types, garbage strings.
const VALUES: &[&str] = &[
    "0",
    "-1",
    "1e300",
    "-1e300",
    "nan",
    "inf",
    "-inf",
    "1e-300",
    "1e-12",
    "1e12",
    "2.75",
    "-2e8",
    "0.5",
    "1e6",
    "10000",
    "\"bogus\"",
    "[]",
    "true",
    "[0.0]",
    "[1e308]",
    "-0.0",
    "{ normal = -1.0 }",
    "{ uniform = 1e300 }",
    "{ iso_grade = 99 }",
    "{ }",
];

#[derive(Debug, Clone)]
enum Mutation {
    /// Line index among the key lines, value index in [`VALUES`].
    Set(usize, usize),
    /// Line index, power of ten, negate.
    Scale(usize, i32, bool),
    /// Line index: the key is removed (its default applies).
    Remove(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<usize>(), 0..VALUES.len()).prop_map(|(l, v)| Mutation::Set(l, v)),
        4 => (
            any::<usize>(),
            prop_oneof![3 => -1..=1i32, 1 => -8..=8i32],
            prop::bool::weighted(0.2)
        )
            .prop_map(|(l, p, n)| Mutation::Scale(l, p, n)),
        1 => any::<usize>().prop_map(Mutation::Remove),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let keys = key_lines(text);
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let pick = |l: usize| keys[l % keys.len()];
    match *m {
        Mutation::Set(l, v) => {
            let i = pick(l);
            let key = lines[i].split('=').next().unwrap_or("").trim().to_string();
            lines[i] = format!("{key} = {}", VALUES[v]);
        }
        Mutation::Scale(l, p, negate) => {
            let i = pick(l);
            let (key, rest) = lines[i].split_once('=').expect("a key line");
            let value = rest.split('#').next().unwrap_or("").trim();
            if let Ok(x) = value.parse::<f64>() {
                let y = x * 10f64.powi(p) * if negate { -1.0 } else { 1.0 };
                lines[i] = format!("{} = {y:e}", key.trim());
            }
        }
        Mutation::Remove(l) => {
            let i = pick(l);
            lines[i] = format!("# {}", lines[i]);
        }
    }
    lines.join("\n") + "\n"
}

const DURATIONS: &[&str] = &["1e-300", "1", "3600", "1e12", "1e308", "0", "-1", "nan"];
const TORQUES: &[&str] = &["0", "412", "-412", "1000", "-3000", "12700", "1e300", "nan"];
const SPEEDS: &[&str] = &["0", "1", "1500", "1e6", "1e300", "-5"];

/// A duty cycle of 1 to 12 rows drawn from the lists above (mostly plausible rows).
fn duty_cycle() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            prop_oneof![4 => Just(2usize), 1 => 0..DURATIONS.len()],
            prop_oneof![4 => 0..3usize, 1 => 0..TORQUES.len()],
            prop_oneof![4 => Just(2usize), 1 => 0..SPEEDS.len()],
        ),
        1..12,
    )
    .prop_map(|rows| {
        let mut s = String::from("duration_s,torque_nm,speed_rpm\n");
        for (d, t, n) in rows {
            s.push_str(&format!("{},{},{}\n", DURATIONS[d], TORQUES[t], SPEEDS[n]));
        }
        s
    })
}

/// Scans every CSV, JSON and SVG file under `dir` for a non-finite number.
fn assert_outputs_finite(dir: &std::path::Path, case: &str) {
    for e in std::fs::read_dir(dir).expect("read_dir").flatten() {
        let p = e.path();
        if p.is_dir() {
            assert_outputs_finite(&p, case);
            continue;
        }
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext == "json" {
            let v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap())
                .unwrap_or_else(|e| panic!("{}: not JSON ({e})\n{case}", p.display()));
            assert_all_finite(&v, &p.display().to_string());
        } else if ext == "csv" {
            let text = std::fs::read_to_string(&p).unwrap();
            for cell in text.split([',', '\n']) {
                let c = cell.trim().to_ascii_lowercase();
                assert!(
                    c != "nan" && c != "inf" && c != "-inf",
                    "{}: non-finite cell {cell:?}\n{case}",
                    p.display()
                );
            }
        }
    }
}

static EXIT_0: AtomicUsize = AtomicUsize::new(0);
static EXIT_2: AtomicUsize = AtomicUsize::new(0);

fn check_case(text: &str, duty: Option<&str>) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("c.toml");
    let mut text = text.to_string();
    if let Some(csv) = duty {
        std::fs::write(dir.path().join("dc.csv"), csv).unwrap();
        text = text.replace(
            "kind = \"constant\"",
            "kind = \"duty_cycle\"\nfile = \"dc.csv\"",
        );
        text = text
            .lines()
            .filter(|l| !l.trim_start().starts_with("torque_nm = 412.0"))
            .collect::<Vec<_>>()
            .join("\n");
    }
    std::fs::write(&cfg, &text).unwrap();
    let out = dir.path().join("results");
    eprintln!("case:\n{text}\nduty cycle:\n{}", duty.unwrap_or("-"));
    let start = Instant::now();
    let o = rvlife_within(
        240,
        [
            "--work-budget-min".as_ref(),
            "1".as_ref(),
            "run".as_ref(),
            cfg.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    let case = format!(
        "config:\n{text}\nduty cycle:\n{}\nstderr:\n{err}",
        duty.unwrap_or("-")
    );
    assert!(!err.contains("panicked"), "panic\n{case}");
    match o.status.code() {
        Some(0) => {
            EXIT_0.fetch_add(1, Ordering::Relaxed);
            assert_outputs_finite(&out, &case);
        }
        Some(2) => {
            EXIT_2.fetch_add(1, Ordering::Relaxed);
            note_refusal(&SLOWEST_RUN, start.elapsed().as_secs_f64(), &case);
            assert!(
                err.lines().any(|l| l.starts_with("error: ")),
                "exit 2 without an error line\n{case}"
            );
            assert!(!out.exists(), "exit 2 left results behind\n{case}");
        }
        other => panic!("exit {other:?}\n{case}"),
    }
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(".rvlife-tmp-"))
        .collect();
    assert!(left.is_empty(), "temporary directory left\n{case}");
}

/// A proptest runner of `RVLIFE_FUZZ_SEED` (default `seed`) for the number of cases in the
/// environment variable `cases_var` (default `cases`), shrinking up to `shrink` times; with the
/// cases and the seed.
fn runner(cases_var: &str, cases: u32, seed: u64, shrink: u32) -> (TestRunner, u32, u64) {
    let cases: u32 = std::env::var(cases_var)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(cases);
    let seed: u64 = std::env::var("RVLIFE_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(seed);
    let mut seed_bytes = [0u8; 32];
    seed_bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let config = RunnerConfig {
        cases,
        max_shrink_iters: shrink,
        failure_persistence: None,
        ..RunnerConfig::default()
    };
    let runner = TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed_bytes),
    );
    (runner, cases, seed)
}

#[test]
fn fuzzed_configs_end_with_exit_0_or_2_and_finite_outputs() {
    let (mut runner, cases, seed) = runner("RVLIFE_FUZZ_CASES", 60, 20261122, 32);
    let base = base_config();
    let strategy = (
        prop::collection::vec(mutation(), 1..=2),
        prop::option::weighted(0.25, duty_cycle()),
    );
    let result = runner.run(&strategy, |(mutations, duty)| {
        let text = mutations.iter().fold(base.clone(), |t, m| apply(&t, m));
        check_case(&text, duty.as_deref());
        Ok(())
    });
    eprintln!(
        "fuzz: {cases} cases (seed {seed}): {} exit 0, {} exit 2; slowest refusal {}",
        EXIT_0.load(Ordering::Relaxed),
        EXIT_2.load(Ordering::Relaxed),
        slowest_refusal(&SLOWEST_RUN)
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// A case of the newer commands.
#[derive(Debug, Clone)]
enum CommandCase {
    /// `montecarlo --samples 2` on the base config with these mutations.
    MonteCarlo(Vec<Mutation>),
    /// `merge` of two shards with one cell changed: file (samples.csv, stages.csv,
    /// shard.json), row, column, value index in [`CELLS`].
    Merge(usize, usize, usize, usize),
    /// `calibrate --measured`: column index in [`COLUMNS`], rows of (hours, value) indices in
    /// [`HOURS`] and [`CELLS`].
    Calibrate(usize, Vec<(usize, usize)>),
}

const CELLS: &[&str] = &[
    "nan", "inf", "-1", "1e300", "", "abc", "0", "-0", "1e-300", "0.9", "0.7",
];
const HOURS: &[&str] = &[
    "0", "100", "600", "1550", "-5", "nan", "1e300", "1e-300", "",
];
const COLUMNS: &[&str] = &[
    "lost_motion_arcmin",
    "backlash_arcmin",
    "max_wear_um",
    "angular_te_arcmin",
    "bogus",
];

fn command_case() -> impl Strategy<Value = CommandCase> {
    prop_oneof![
        2 => prop::collection::vec(mutation(), 1..=2).prop_map(CommandCase::MonteCarlo),
        2 => (0..3usize, any::<usize>(), any::<usize>(), 0..CELLS.len())
            .prop_map(|(f, r, c, v)| CommandCase::Merge(f, r, c, v)),
        1 => (
            0..COLUMNS.len(),
            prop::collection::vec(
                (
                    prop_oneof![4 => 0..4usize, 1 => 0..HOURS.len()],
                    prop_oneof![4 => 9..11usize, 1 => 0..CELLS.len()],
                ),
                0..6
            )
        )
            .prop_map(|(c, rows)| CommandCase::Calibrate(c, rows)),
    ]
}

/// Two shards of a two-sample Monte Carlo run of the base config, computed once.
fn shards() -> &'static (tempfile::TempDir, [std::path::PathBuf; 2]) {
    static SHARDS: std::sync::OnceLock<(tempfile::TempDir, [std::path::PathBuf; 2])> =
        std::sync::OnceLock::new();
    SHARDS.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let cfg = dir.path().join("c.toml");
        std::fs::write(&cfg, base_config()).unwrap();
        let out = |i: usize| {
            let o = dir.path().join(format!("s{i}"));
            common::montecarlo_shard(&cfg, i, &o);
            o
        };
        let s = [out(1), out(2)];
        (dir, s)
    })
}

fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

/// Replaces one cell of a CSV text (row 1.. after the header, column modulo the row's).
fn set_cell(text: &str, row: usize, col: usize, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.len() > 1 {
        let r = 1 + row % (lines.len() - 1);
        let mut cells: Vec<String> = lines[r].split(',').map(str::to_string).collect();
        let c = col % cells.len();
        cells[c] = value.to_string();
        lines[r] = cells.join(",");
    }
    lines.join("\n") + "\n"
}

/// Replaces the `n`-th number of a JSON text by `value` (as written, quoted if not a number).
fn set_json_number(text: &str, n: usize, value: &str) -> String {
    let b = text.as_bytes();
    let mut starts = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let number_start = (b[i].is_ascii_digit() || b[i] == b'-')
            && (i == 0 || matches!(b[i - 1], b':' | b'[' | b',' | b' '));
        if number_start {
            let j = i + text[i..]
                .find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c)))
                .unwrap_or(text.len() - i);
            starts.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    if starts.is_empty() {
        return text.to_string();
    }
    let (a, z) = starts[n % starts.len()];
    let v = if value.parse::<f64>().is_ok_and(f64::is_finite) {
        value.to_string()
    } else {
        format!("\"{value}\"")
    };
    format!("{}{v}{}", &text[..a], &text[z..])
}

static CMD_EXIT_0: AtomicUsize = AtomicUsize::new(0);
static CMD_EXIT_2: AtomicUsize = AtomicUsize::new(0);

fn check_command_case(case: &CommandCase) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out");
    let budget = ["--work-budget-min", "1"];
    let (args, shown): (Vec<std::ffi::OsString>, String) = match case {
        CommandCase::MonteCarlo(ms) => {
            let text = ms.iter().fold(base_config(), |t, m| apply(&t, m));
            let cfg = d.join("c.toml");
            std::fs::write(&cfg, &text).unwrap();
            let a = [
                "montecarlo",
                cfg.to_str().unwrap(),
                "--samples",
                "2",
                "--samples-per-mesh-cycle",
                "2",
                "--keep-going",
            ];
            (
                budget.iter().chain(a.iter()).map(Into::into).collect(),
                format!("montecarlo, config:\n{text}"),
            )
        }
        CommandCase::Merge(f, r, c, v) => {
            let (_, src) = shards();
            let s1 = d.join("s1");
            let s2 = d.join("s2");
            copy_dir(&src[0], &s1);
            copy_dir(&src[1], &s2);
            let name = ["samples.csv", "stages.csv", "shard.json"][*f];
            let p = s1.join(name);
            let text = std::fs::read_to_string(&p).unwrap();
            let changed = if *f == 2 {
                set_json_number(&text, *r, CELLS[*v])
            } else {
                set_cell(&text, *r, *c, CELLS[*v])
            };
            std::fs::write(&p, &changed).unwrap();
            (
                vec!["merge".into(), s1.into_os_string(), s2.into_os_string()],
                format!("merge, {name}:\n{changed}"),
            )
        }
        CommandCase::Calibrate(c, rows) => {
            let mut csv = format!("hours,{}\n", COLUMNS[*c]);
            for (h, v) in rows {
                csv.push_str(&format!("{},{}\n", HOURS[*h], CELLS[*v]));
            }
            let m = d.join("m.csv");
            std::fs::write(&m, &csv).unwrap();
            let cfg = d.join("c.toml");
            std::fs::write(&cfg, base_config()).unwrap();
            let a = [
                "calibrate",
                cfg.to_str().unwrap(),
                "--measured",
                m.to_str().unwrap(),
            ];
            (
                budget.iter().chain(a.iter()).map(Into::into).collect(),
                format!("calibrate --measured:\n{csv}"),
            )
        }
    };
    let mut args = args;
    args.extend(["--out".into(), out.clone().into_os_string()]);
    // Shown with a failure (the test's output is captured), also one inside rvlife_within.
    eprintln!("case: {shown}");
    let start = Instant::now();
    let o = rvlife_within(240, &args);
    let err = String::from_utf8_lossy(&o.stderr);
    let shown = format!("{shown}\nstderr:\n{err}");
    assert!(!err.contains("panicked"), "panic\n{shown}");
    match o.status.code() {
        Some(0) => {
            CMD_EXIT_0.fetch_add(1, Ordering::Relaxed);
            if out.exists() {
                assert_outputs_finite(&out, &shown);
            }
            let text = String::from_utf8_lossy(&o.stdout).to_ascii_lowercase();
            assert!(
                !text.contains("nan") && !text.contains(" inf"),
                "non-finite number printed\n{shown}"
            );
        }
        Some(2) => {
            CMD_EXIT_2.fetch_add(1, Ordering::Relaxed);
            note_refusal(&SLOWEST_COMMAND, start.elapsed().as_secs_f64(), &shown);
            assert!(
                err.lines().any(|l| l.starts_with("error: ")),
                "exit 2 without an error line\n{shown}"
            );
        }
        other => panic!("exit {other:?}\n{shown}"),
    }
}

#[test]
fn fuzzed_newer_commands_end_with_exit_0_or_2_and_finite_outputs() {
    // No shrinking: a case can take minutes, and each prints itself.
    let (mut runner, cases, seed) = runner("RVLIFE_FUZZ_COMMAND_CASES", 12, 20261125, 0);
    let result = runner.run(&command_case(), |case| {
        check_command_case(&case);
        Ok(())
    });
    eprintln!(
        "fuzz of the newer commands: {cases} cases (seed {seed}): {} exit 0, {} exit 2; \
         slowest refusal {}",
        CMD_EXIT_0.load(Ordering::Relaxed),
        CMD_EXIT_2.load(Ordering::Relaxed),
        slowest_refusal(&SLOWEST_COMMAND)
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// The built-in reducers the parts fuzz and the Monte Carlo fuzz run on.
const PRESETS: [&str; 5] = ["rv-40e", "paper", "rv-20e", "rv-80e", "single-stage"];

/// The sections whose keys the parts fuzz mutates: the bearings, the meshes, the parts in
/// series, the contact law and the wear model.
const PART_SECTIONS: [&str; 5] = [
    "[reducer.gears]",
    "[reducer.bearings]",
    "[reducer.structure]",
    "[contact]",
    "[wear]",
];

/// Preset `name` as `rvlife example --preset` prints it, its dynamics, flexible disc and
/// friction off (`enabled = false`).
fn preset_config(name: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_rvlife"))
        .args(["example", "--preset", name])
        .output()
        .expect("rvlife example --preset");
    String::from_utf8(o.stdout)
        .expect("utf-8")
        .lines()
        .map(|l| {
            if l.split('=').next().unwrap_or("").trim() == "enabled" {
                "enabled = false".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// The key lines of [`PART_SECTIONS`] in `text`, set (`key = value`) or left at their default
/// (`# key = value`).
fn part_key_lines(text: &str) -> Vec<usize> {
    let mut section = "";
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let t = l.trim_start();
        if t.starts_with('[') {
            section = t.split_whitespace().next().unwrap_or("");
            continue;
        }
        if !PART_SECTIONS.contains(&section) {
            continue;
        }
        let body = t.strip_prefix('#').map_or(t, str::trim_start);
        let Some((key, _)) = body.split_once('=') else {
            continue;
        };
        let key = key.trim();
        if !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            out.push(i);
        }
    }
    out
}

/// A mutation of one part key: line (among [`part_key_lines`]), then either a value of
/// [`VALUES`] or the key's value scaled by a power of ten (negated with the flag).
#[derive(Debug, Clone)]
enum PartMutation {
    Set(usize, usize),
    Scale(usize, i32, bool),
}

fn part_mutation() -> impl Strategy<Value = PartMutation> {
    prop_oneof![
        1 => (any::<usize>(), 0..VALUES.len()).prop_map(|(l, v)| PartMutation::Set(l, v)),
        3 => (
            any::<usize>(),
            prop_oneof![3 => -1..=1i32, 1 => -6..=6i32],
            prop::bool::weighted(0.15)
        )
            .prop_map(|(l, p, n)| PartMutation::Scale(l, p, n)),
    ]
}

/// `text` with `m` applied (a key left at its default is written first), and the key's name.
fn apply_part(text: &str, m: &PartMutation) -> (String, String) {
    let keys = part_key_lines(text);
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let (PartMutation::Set(l, _) | PartMutation::Scale(l, _, _)) = *m;
    let i = keys[l % keys.len()];
    let t = lines[i].trim_start();
    let body = t.strip_prefix('#').map_or(t, str::trim_start).to_string();
    let (key, rest) = body.split_once('=').expect("a key line");
    let key = key.trim();
    let value = rest.split('#').next().unwrap_or("").trim();
    lines[i] = match *m {
        PartMutation::Set(_, v) => format!("{key} = {}", VALUES[v]),
        PartMutation::Scale(_, p, negate) => match value.parse::<f64>() {
            Ok(x) => format!(
                "{key} = {:e}",
                x * 10f64.powi(p) * if negate { -1.0 } else { 1.0 }
            ),
            Err(_) => format!("{key} = {value}"),
        },
    };
    (lines.join("\n") + "\n", key.to_string())
}

static PART_EXIT_0: AtomicUsize = AtomicUsize::new(0);
static PART_EXIT_2: AtomicUsize = AtomicUsize::new(0);
static SLOWEST_PART: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));

/// The key an `error: invalid KEY = ...` line names, if any.
fn named_key(err: &str) -> Option<String> {
    let line = err.lines().find(|l| l.starts_with("error: invalid "))?;
    let rest = line.trim_start_matches("error: invalid ");
    Some(rest.split(" = ").next().unwrap_or(rest).trim().to_string())
}

/// `te --json` and `hysteresis --json` on the config `text`, whose keys `mutated` the fuzz
/// set: exit 0 with finite numbers, or exit 2 with an error line that names a key the config
/// writes (its last part, indices stripped) or a command-line flag, and not the preset's
/// torque where the fuzz changed only parts in series (`rvlife::study::SERIES_KEYS`) and the torque
/// fails on the stage's compliance: that refusal names the part; never a panic or another exit.
fn check_part_case(text: &str, mutated: &[String]) {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("c.toml");
    std::fs::write(&cfg, text).unwrap();
    for command in ["te", "hysteresis"] {
        let start = Instant::now();
        let o = rvlife_within(
            240,
            [
                "--work-budget-min".as_ref(),
                "1".as_ref(),
                command.as_ref(),
                cfg.as_os_str(),
                "--json".as_ref(),
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        let case = format!("rvlife {command} on:\n{text}\nstderr:\n{err}");
        assert!(!err.contains("panicked"), "panic\n{case}");
        match o.status.code() {
            Some(0) => {
                PART_EXIT_0.fetch_add(1, Ordering::Relaxed);
                let v: Value = serde_json::from_slice(&o.stdout)
                    .unwrap_or_else(|e| panic!("{e}: not JSON\n{case}"));
                assert_all_finite(&v, command);
            }
            Some(2) => {
                PART_EXIT_2.fetch_add(1, Ordering::Relaxed);
                note_refusal(&SLOWEST_PART, start.elapsed().as_secs_f64(), &case);
                assert!(
                    err.lines().any(|l| l.starts_with("error: ")),
                    "exit 2 without an error line\n{case}"
                );
                if let Some(key) = named_key(&err) {
                    let last = key.rsplit('.').next().unwrap_or(&key);
                    let last = last.split('[').next().unwrap_or(last);
                    assert!(
                        key.starts_with("--") || text.contains(last),
                        "the refusal names {key}, which the config does not write\n{case}"
                    );
                    let only_series = mutated.iter().all(|m| {
                        rvlife::study::SERIES_KEYS
                            .iter()
                            .any(|k| k.rsplit('.').next() == Some(m.as_str()))
                    });
                    assert!(
                        !(only_series
                            && last.ends_with("torque_nm")
                            && err.contains("is more than the unworn stage carries")
                            && !err.contains("Hertz pressure")),
                        "the refusal names the torque {key}, which the fuzz left as the preset \
                         has it; it changed {mutated:?}\n{case}"
                    );
                }
                // A config refused by one command is refused by the other.
                break;
            }
            other => panic!("exit {other:?}\n{case}"),
        }
    }
}

/// The keys of the bearings, meshes, parts in series, contact and wear on every preset, one
/// or two at a time (values of [`VALUES`] or scaled by powers of ten), through `te` and
/// `hysteresis` (docs/model.md section 15). `RVLIFE_FUZZ_PART_CASES` sets the number of cases
/// (default 40, the CI run).
#[test]
fn fuzzed_part_keys_end_with_exit_0_or_2_in_te_and_hysteresis() {
    let (mut runner, cases, seed) = runner("RVLIFE_FUZZ_PART_CASES", 40, 20261129, 16);
    let bases: Vec<String> = PRESETS.iter().map(|p| preset_config(p)).collect();
    let strategy = (
        0..PRESETS.len(),
        prop::collection::vec(part_mutation(), 1..=2),
    );
    let result = runner.run(&strategy, |(preset, mutations)| {
        let mut keys = Vec::new();
        let text = mutations.iter().fold(bases[preset].clone(), |t, m| {
            let (t, key) = apply_part(&t, m);
            keys.push(key);
            t
        });
        check_part_case(&format!("# preset {}\n{text}", PRESETS[preset]), &keys);
        Ok(())
    });
    eprintln!(
        "fuzz of the part keys: {cases} cases (seed {seed}): {} commands exit 0, {} exit 2; \
         slowest refusal {}",
        PART_EXIT_0.load(Ordering::Relaxed),
        PART_EXIT_2.load(Ordering::Relaxed),
        slowest_refusal(&SLOWEST_PART)
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// `montecarlo --samples 4` on every preset at seeds drawn by the fuzz's generator: every
/// sample is analysed (status `ok`: none fails) and the lives are finite.
/// `RVLIFE_FUZZ_MC_CASES` sets the number of runs (default 5, one a preset in CI).
#[test]
fn monte_carlo_on_every_preset_fails_no_sample() {
    let (mut runner, cases, seed) = runner("RVLIFE_FUZZ_MC_CASES", 5, 20261130, 0);
    let done = AtomicUsize::new(0);
    let result = runner.run(&(any::<u32>(), 1..=1000u64), |(_, mc_seed)| {
        let preset = PRESETS[done.fetch_add(1, Ordering::Relaxed) % PRESETS.len()];
        let dir = tempfile::tempdir().unwrap();
        let cfg = dir.path().join("c.toml");
        std::fs::write(&cfg, preset_config(preset)).unwrap();
        let out = dir.path().join("mc");
        let o = rvlife_within(
            600,
            [
                "montecarlo".as_ref(),
                cfg.as_os_str(),
                "--samples".as_ref(),
                "4".as_ref(),
                "--seed".as_ref(),
                mc_seed.to_string().as_ref(),
                "--keep-going".as_ref(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{preset} seed {mc_seed}\n{err}");
        let samples = std::fs::read_to_string(out.join("samples.csv")).unwrap();
        for row in samples.lines().skip(1) {
            assert!(
                row.split(',').nth(1) == Some("ok"),
                "{preset} seed {mc_seed}: a sample did not run\n{row}"
            );
        }
        let summary: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        assert_all_finite(&summary, "summary.json");
        Ok(())
    });
    eprintln!("Monte Carlo on every preset: {cases} runs (seed {seed})");
    if let Err(e) = result {
        panic!("{e}");
    }
}
