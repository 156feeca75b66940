//! Every quantity of the table ([`rvlife::quantities::STAGE`]) appears in every output that
//! promises the full set: `stages.csv` (its columns, in the table's order), `summary.json` (every
//! stage's keys), `report.html` (the stage table) and the console of `rvlife run --all`; the
//! Python package's study is checked by its own tests. The built-in example runs the multibody
//! model and the flexible disc, so every quantity has a value.

mod common;

use common::*;
use rvlife::quantities::STAGE;

#[test]
fn every_quantity_appears_in_every_full_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = rvlife_within(
        300,
        [
            "run".as_ref(),
            "--all".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
    );
    let console = ok(&o, "run --all");
    let csv = std::fs::read_to_string(out.join("stages.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    let stages = summary["stages"].as_array().unwrap();
    assert_eq!(stages.len(), 7);
    let expected: Vec<&str> = STAGE.iter().flat_map(|q| q.columns()).collect();
    assert_eq!(header, expected, "stages.csv columns are the table's");
    for s in stages {
        let keys: Vec<&str> = s.as_object().unwrap().keys().map(String::as_str).collect();
        let mut names: Vec<&str> = STAGE.iter().map(|q| q.name).collect();
        names.sort_unstable();
        assert_eq!(
            keys, names,
            "summary.json holds every quantity of the table"
        );
    }
    // The stage table of the report and the console, one row per quantity.
    let console_rows: Vec<&str> = console
        .lines()
        .skip_while(|l| !l.starts_with("every quantity of the stages"))
        .skip(1)
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    for q in STAGE {
        if q.name != "hours" {
            assert!(
                report.contains(&format!("<td><code>{}</code></td></tr>", q.name)),
                "report.html lacks {}",
                q.name
            );
        }
        assert!(
            console_rows.contains(&q.name),
            "rvlife run --all lacks {}",
            q.name
        );
    }
    // The values agree between the outputs: stages.csv's columns are summary.json's numbers.
    for (row, s) in csv.lines().skip(1).zip(stages) {
        let cells: Vec<&str> = row.split(',').collect();
        for q in STAGE {
            let v = &s[q.name];
            let nums: Vec<f64> = match v {
                Value::Array(a) => a.iter().filter_map(Value::as_f64).collect(),
                other => other.as_f64().into_iter().collect(),
            };
            for (col, x) in q.columns().iter().zip(nums) {
                let k = header.iter().position(|h| h == col).unwrap();
                let c: f64 = cells[k].parse().unwrap();
                assert!(
                    (c - x).abs() <= 5e-7 * (1.0 + x.abs()),
                    "{col}: {c} in stages.csv, {x} in summary.json"
                );
            }
        }
    }
}
