//! Golden outputs: what the commands write and print is compared with what this release recorded
//! in `tests/golden/`, so that a change meant to leave the results alone (a restructuring, a
//! speed-up) shows that it does, byte for byte.
//!
//! Recorded, per case (`tests/golden/<case>.sha256`: the SHA-256 of every file and of the
//! console output):
//! - `run`: every file of `rvlife run` on the built-in example (results, plots, profiles,
//!   `report.html`) and its console table;
//! - `montecarlo`: every file of `rvlife montecarlo` (8 samples, the tolerance table and life
//!   spec of `tests/montecarlo.rs`);
//! - `calibrate`: `rvlife calibrate --measured` with the running-in play, and `--target-wear-um`;
//! - `dynamics`: `rvlife dynamics --out` with pin forces, and `--json`;
//! - `commands`: the `--json` and console output of `contact`, `te` (also with part errors, a
//!   single-stage drive and a rigid support), `hysteresis`, the `profile` exports, `example`, and
//!   the messages of bad inputs.
//!
//! Console times (`2.56 s`) and `wall_time_s` are masked. A `stages.csv` is compared column by
//! column (`tests/golden/<case>/stages.csv` holds the recorded file): every recorded column must
//! be there with the same values; a column the output table adds is allowed.
//!
//! A change meant to move results records them anew:
//! `RVLIFE_GOLDEN_WRITE=1 cargo test --release -p rvlife-cli --test golden`
//! (`RVLIFE_GOLDEN_BIN=PATH` records the outputs of another build of `rvlife`).

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use sha2::{Digest, Sha256};

/// The folder of the recorded outputs.
fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn writing() -> bool {
    std::env::var_os("RVLIFE_GOLDEN_WRITE").is_some()
}

/// The binary under test (or, when recording, the one named by `RVLIFE_GOLDEN_BIN`).
fn binary() -> PathBuf {
    match std::env::var_os("RVLIFE_GOLDEN_BIN") {
        Some(p) if writing() => PathBuf::from(p),
        _ => PathBuf::from(env!("CARGO_BIN_EXE_rvlife")),
    }
}

/// Masks console times: a decimal number followed by ` s` and then `;`, `,` or the line's end.
fn mask_times(text: &str) -> String {
    text.lines()
        .map(|line| {
            let words: Vec<&str> = line.split(' ').collect();
            let mut out = Vec::with_capacity(words.len());
            for (i, w) in words.iter().enumerate() {
                let next = words.get(i + 1).copied().unwrap_or("");
                let unit = next == "s" || next.starts_with("s;") || next.starts_with("s,");
                let number = w.contains('.') && w.chars().all(|c| c.is_ascii_digit() || c == '.');
                out.push(if unit && number { "<time>" } else { w });
            }
            out.join(" ")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Removes `"wall_time_s":<number>` from a compact JSON object.
fn mask_wall_time(json: &str) -> String {
    let key = "\"wall_time_s\":";
    let Some(start) = json.find(key) else {
        return json.to_string();
    };
    let rest = &json[start + key.len()..];
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    let mut tail = &rest[end..];
    let mut head = &json[..start];
    if let Some(t) = tail.strip_prefix(',') {
        tail = t;
    } else if let Some(h) = head.strip_suffix(',') {
        head = h;
    }
    format!("{head}{tail}")
}

/// One case: runs commands in a fresh folder and collects what they write and print.
struct Case {
    name: &'static str,
    dir: tempfile::TempDir,
    outputs: BTreeMap<String, Vec<u8>>,
}

impl Case {
    fn new(name: &'static str) -> Case {
        Case {
            name,
            dir: tempfile::tempdir().unwrap(),
            outputs: BTreeMap::new(),
        }
    }

    /// Writes an input file into the case's folder.
    fn input(&self, name: &str, text: &str) {
        std::fs::write(self.dir.path().join(name), text).unwrap();
    }

    /// Runs `rvlife args` in the case's folder; keeps its masked stdout (and stderr when it
    /// fails) under `label`, and checks its exit code.
    fn run(&mut self, label: &str, args: &[&str], code: i32) {
        let o = Command::new(binary())
            .args(args)
            .current_dir(self.dir.path())
            .output()
            .expect("cannot start rvlife");
        let stdout = String::from_utf8_lossy(&o.stdout);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(
            o.status.code(),
            Some(code),
            "rvlife {args:?}\nstdout:\n{stdout}\nstderr:\n{stderr}"
        );
        let shown = if args.contains(&"--json") {
            mask_wall_time(stdout.trim_end())
        } else {
            mask_times(&stdout)
        };
        self.outputs
            .insert(format!("{label}.stdout"), shown.into_bytes());
        if code != 0 {
            self.outputs.insert(
                format!("{label}.stderr"),
                stderr.trim_end().as_bytes().to_vec(),
            );
        }
    }

    /// Keeps every file under `folder` of the case's folder (or the one file `folder`).
    fn files(&mut self, folder: &str) {
        let root = self.dir.path().join(folder);
        if root.is_file() {
            self.outputs
                .insert(folder.to_string(), std::fs::read(&root).unwrap());
            return;
        }
        let mut stack = vec![root.clone()];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                } else {
                    let rel = p.strip_prefix(self.dir.path()).unwrap();
                    self.outputs
                        .insert(rel.display().to_string(), std::fs::read(&p).unwrap());
                }
            }
        }
    }

    /// Records the outputs (`RVLIFE_GOLDEN_WRITE`) or compares them with the record.
    fn check(self) {
        let manifest = golden_dir().join(format!("{}.sha256", self.name));
        let digest = |b: &[u8]| format!("{:x}", Sha256::digest(b));
        if writing() {
            let mut text = String::new();
            for (k, v) in &self.outputs {
                text.push_str(&format!("{}  {k}\n", digest(v)));
                if k.ends_with("stages.csv") {
                    let copy = golden_dir().join(self.name).join(k);
                    std::fs::create_dir_all(copy.parent().unwrap()).unwrap();
                    std::fs::write(copy, v).unwrap();
                }
            }
            std::fs::write(&manifest, text).unwrap();
            return;
        }
        let recorded = std::fs::read_to_string(&manifest)
            .unwrap_or_else(|e| panic!("{}: {e}", manifest.display()));
        let mut problems = Vec::new();
        let mut seen = Vec::new();
        for line in recorded.lines() {
            let (sum, name) = line.split_once("  ").expect("`<sha256>  <file>`");
            seen.push(name.to_string());
            let Some(now) = self.outputs.get(name) else {
                problems.push(format!("{name}: not written any more"));
                continue;
            };
            if name.ends_with("stages.csv") {
                let copy = golden_dir().join(self.name).join(name);
                let was = std::fs::read_to_string(&copy).unwrap();
                if let Err(e) = same_columns(&was, &String::from_utf8_lossy(now)) {
                    problems.push(format!("{name}: {e}"));
                }
            } else if digest(now) != sum {
                problems.push(format!("{name}: differs from the record"));
            }
        }
        for name in self.outputs.keys() {
            if !seen.contains(name) {
                problems.push(format!("{name}: new output, not in the record"));
            }
        }
        assert!(
            problems.is_empty(),
            "case {}: outputs differ from tests/golden ({} problems):\n{}",
            self.name,
            problems.len(),
            problems.join("\n")
        );
    }
}

/// Every column of the CSV text `was` is in `now` with the same values, row by row.
fn same_columns(was: &str, now: &str) -> Result<(), String> {
    let table = |t: &str| -> (Vec<String>, Vec<Vec<String>>) {
        let mut lines = t.lines();
        let head = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect();
        (head, rows)
    };
    let (h0, r0) = table(was);
    let (h1, r1) = table(now);
    if r0.len() != r1.len() {
        return Err(format!("{} rows, recorded {}", r1.len(), r0.len()));
    }
    for (c, name) in h0.iter().enumerate() {
        let k = h1
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("column {name} is missing"))?;
        for (i, (a, b)) in r0.iter().zip(&r1).enumerate() {
            if a.get(c) != b.get(k) {
                return Err(format!(
                    "column {name}, row {}: {:?}, recorded {:?}",
                    i + 1,
                    b.get(k),
                    a.get(c)
                ));
            }
        }
    }
    Ok(())
}

/// The paper's reducer (`rvlife example --preset paper`, without its spec and tolerances) with
/// `from -> to` replaced (each must be found).
fn paper_with(edits: &[(&str, &str)]) -> String {
    let mut t =
        common::without_spec(&rvlife::config::preset_text("paper").expect("the paper preset"));
    for (from, to) in edits {
        assert!(t.contains(from), "the paper preset has no `{from}`");
        t = t.replacen(from, to, 1);
    }
    t
}

#[test]
fn run_outputs_are_unchanged() {
    let mut c = Case::new("run");
    c.run("run", &["run", "--out", "run"], 0);
    c.files("run");
    c.check();
}

/// With friction off (`[lubrication] enabled = false`), the built-in example writes what it
/// wrote before friction existed, byte for byte: `run_frictionless.sha256` is the last
/// frictionless release's record of the `run` case, kept as it was.
#[test]
fn frictionless_run_equals_the_release_before_friction() {
    let mut c = Case::new("run_frictionless");
    let example = rvlife::config::EXAMPLE_TOML;
    let on = "[lubrication]\nenabled = true";
    assert!(example.contains(on), "the example enables [lubrication]");
    c.input(
        "frictionless.toml",
        &example.replacen(on, "[lubrication]\nenabled = false", 1),
    );
    c.run("run", &["run", "frictionless.toml", "--out", "run"], 0);
    c.files("run");
    c.check();
}

#[test]
fn montecarlo_outputs_are_unchanged() {
    let mut c = Case::new("montecarlo");
    let mut cfg = paper_with(&[
        ("equidistant_mm = 0.0 ", "equidistant_mm = 0.008 "),
        ("offset_mm = 0.0 ", "offset_mm = -0.005 "),
        ("enabled = true ", "enabled = false "),
    ]);
    cfg.push_str(common::MONTE_CARLO_SPEC);
    c.input("mc.toml", &cfg);
    c.run(
        "montecarlo",
        &[
            "montecarlo",
            "mc.toml",
            "--samples",
            "8",
            "--seed",
            "7",
            "--out",
            "mc",
        ],
        0,
    );
    c.files("mc");
    c.check();
}

#[test]
fn calibrate_outputs_are_unchanged() {
    let mut c = Case::new("calibrate");
    c.input(
        "measured.csv",
        "# bench data of one reducer (test input)\n\
         hours,lost_motion_arcmin,max_wear_um\n\
         0,0.08,\n600,0.36,\n1200,0.45,15\n2400,0.55,\n3600,0.62,33\n",
    );
    // The paper's reducer: the fit of the disc's coefficient needs a config whose bearings and
    // pins keep their size (the example's wear too).
    let paper = Command::new(binary())
        .args(["example", "--preset", "paper"])
        .output()
        .expect("cannot start rvlife");
    c.input("paper.toml", &String::from_utf8_lossy(&paper.stdout));
    c.run(
        "measured",
        &[
            "calibrate",
            "paper.toml",
            "--measured",
            "measured.csv",
            "--fit-running-in",
            "--out",
            "cal",
        ],
        0,
    );
    c.files("cal");
    c.run("target", &["calibrate", "--target-wear-um", "60"], 0);
    c.files("calibrated.toml");
    // A hysteresis curve: the structure compliance, into the folder of its own.
    c.input(
        "curve.csv",
        "torque_nm,twist_arcmin\n0,0\n12.36,0.5\n103,1.5\n206,2.5\n309,3.5\n412,4.5\n\
         206,2.5\n0,0.2\n-12.36,-0.5\n-103,-1.5\n-206,-2.5\n-309,-3.5\n-412,-4.5\n\
         -206,-2.5\n0,-0.2\n12.36,0.5\n206,2.5\n412,4.5\n",
    );
    c.run(
        "structure",
        &["calibrate", "--measured", "curve.csv", "--out", "structure"],
        0,
    );
    c.files("structure");
    c.check();
}

#[test]
fn dynamics_outputs_are_unchanged() {
    let mut c = Case::new("dynamics");
    c.run(
        "out",
        &[
            "dynamics",
            "--wear-um",
            "10",
            "--out",
            "dyn",
            "--pin-forces",
        ],
        0,
    );
    c.files("dyn");
    c.run("json", &["dynamics", "--wear-um", "10", "--json"], 0);
    c.run(
        "constant",
        &[
            "dynamics",
            "--hours",
            "1250",
            "--load",
            "constant",
            "--torque-nm",
            "-300",
            "--json",
        ],
        0,
    );
    c.check();
}

#[test]
fn command_outputs_are_unchanged() {
    let mut c = Case::new("commands");
    let contact = ["contact", "--crank-deg", "3", "--torque-nm", "412"];
    c.run(
        "contact_json",
        &[&contact[..], &["--hours", "2500", "--json"]].concat(),
        0,
    );
    c.run("contact", &[&contact[..], &["--wear-um", "10"]].concat(), 0);
    c.run(
        "te_json",
        &["te", "--torque-nm", "412", "--wear-um", "10", "--json"],
        0,
    );
    c.run("te", &["te", "--torque-nm", "-200", "--hours", "1250"], 0);
    c.run(
        "hysteresis_json",
        &[
            "hysteresis",
            "--crank-deg",
            "5",
            "--levels",
            "4",
            "--hours",
            "1250",
            "--json",
        ],
        0,
    );
    c.run("hysteresis", &["hysteresis", "--wear-um", "20"], 0);
    // Part errors: the revolution is solved mesh cycle by mesh cycle.
    let pins: Vec<String> = (0..40)
        .map(|j| format!("{:.2}", ((j * 7) % 11) as f64 * 0.3 - 1.5))
        .collect();
    c.input(
        "errors.toml",
        &format!(
            "{}\n[errors]\npin_radial_um = [{}]\npin_circle_runout_um = 3.0\n\
             pin_circle_runout_deg = 40.0\ncrank_eccentricity_um = [1.0, -0.5]\n\
             crank_phase_arcmin = [0.3, -0.2]\n",
            paper_with(&[
                ("equidistant_mm = 0.0 ", "equidistant_mm = 0.008 "),
                ("offset_mm = 0.0 ", "offset_mm = -0.005 "),
            ]),
            pins.join(", ")
        ),
    );
    c.run(
        "te_errors_json",
        &["te", "errors.toml", "--torque-nm", "412", "--json"],
        0,
    );
    c.input(
        "rigid.toml",
        &paper_with(&[
            ("support = \"bearings\"", "support = \"rigid\""),
            ("# load_share = 0.55", "load_share = 0.55"),
        ]),
    );
    c.run(
        "contact_rigid_json",
        &[&["contact", "rigid.toml"][..], &contact[1..], &["--json"]].concat(),
        0,
    );
    c.run("te_rigid_json", &["te", "rigid.toml", "--json"], 0);
    c.run("example", &["example"], 0);
    c.run("example_list", &["example", "--list"], 0);
    let single = Command::new(binary())
        .args(["example", "--preset", "single-stage"])
        .output()
        .unwrap();
    c.input("single.toml", &String::from_utf8_lossy(&single.stdout));
    c.run(
        "te_single_json",
        &["te", "single.toml", "--torque-nm", "100", "--json"],
        0,
    );
    c.run(
        "contact_single_json",
        &[
            "contact",
            "single.toml",
            "--crank-deg",
            "10",
            "--torque-nm",
            "-150",
            "--json",
        ],
        0,
    );
    c.run(
        "profile_csv",
        &["profile", "--out", "p.csv", "--hours", "1250"],
        0,
    );
    c.run(
        "profile_dxf",
        &["profile", "--out", "p.dxf", "--wear-um", "5"],
        0,
    );
    c.run(
        "profile_svg",
        &["profile", "--out", "p.svg", "--nominal"],
        0,
    );
    for f in ["p.csv", "p.dxf", "p.svg"] {
        c.files(f);
    }
    // Bad inputs: the message names the key, the value and the range (exit 2).
    let bad: [(&str, &[(&str, &str)]); 6] = [
        ("range", &[("pin_radius_mm = 3.0", "pin_radius_mm = -3.0")]),
        ("mesh", &[("offset_mm = 0.0 ", "offset_mm = 2.75 ")]),
        (
            "unknown",
            &[(
                "[cycloid.modification]",
                "[cycloid.modification]\nbogus = 1",
            )],
        ),
        (
            "torque",
            &[("\ntorque_nm = 412.0 ", "\ntorque_nm = 12700.0 ")],
        ),
        (
            "levels",
            &[
                ("kind = \"constant\"", "kind = \"sinusoidal\""),
                ("\ntorque_nm = 412.0 ", "\nlevels = 10000 "),
            ],
        ),
        (
            "default",
            &[(
                "# crank_bore_radius_mm = 13.0",
                "crank_bore_radius_mm = 25.0",
            )],
        ),
    ];
    for (label, edits) in bad {
        let name = format!("bad_{label}.toml");
        c.input(&name, &paper_with(edits));
        c.run(&format!("bad_{label}"), &["te", &name], 2);
    }
    c.run("bad_flag", &["te", "--wear-um", "-1"], 2);
    c.check();
}
