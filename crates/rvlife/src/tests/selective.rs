//! Selective assembly of Monte Carlo's units (docs/model.md section 12.4).

use crate::config::{preset_text, Config, Model, SelectiveAssembly, SelectiveAssemblyConfig};
use crate::montecarlo::{new_backlash, run, sample_model, unusable, Plan, REJECTED};

fn example() -> Model {
    Config::from_toml_str(&preset_text("rv-40e").unwrap(), "test")
        .unwrap()
        .validate()
        .unwrap()
}

fn selection(grades: &[f64], band: [f64; 2]) -> SelectiveAssembly {
    SelectiveAssemblyConfig {
        pin_grades_um: grades.to_vec(),
        backlash_arcmin: band,
    }
    .validate()
    .unwrap()
}

/// Larger pins take play: over 7 grades of 0.5 um each way of nominal, the new unit's
/// backlash never rises with the grade, on 6 sampled reducers of the example.
#[test]
fn backlash_falls_as_the_pins_grow() {
    let m = example();
    for index in 0..6 {
        let s = sample_model(&m, 1, index);
        let backlash: Vec<f64> = [-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5]
            .iter()
            .map(|g| {
                let mut u = s.clone();
                for r in &mut u.reducer.errors.pin_radius {
                    *r += g * 1e-6;
                }
                new_backlash(&u, 4).unwrap()
            })
            .collect();
        println!("sample {index}: {backlash:?}");
        assert!(
            backlash.windows(2).all(|w| w[1] <= w[0] + 1e-9),
            "sample {index}: {backlash:?}"
        );
    }
}

/// Monte Carlo of the example with its pins graded into a backlash band: every unit built
/// starts within the band (its 0 h stage is the check's own analysis), the others are
/// rejected at assembly naming the band, and a band no grade reaches rejects every unit,
/// which makes the run unusable.
#[test]
fn units_built_start_within_the_band() {
    let mut m = example();
    m.tolerances.selective = Some(selection(
        &[-2.0, -1.5, -1.0, -0.5, 0.0, 0.5, 1.0],
        [0.05, 0.5],
    ));
    m.wear.stage_hours = vec![0.0, 2500.0];
    let plan = Plan {
        samples: 8,
        seed: 1,
        shard: (1, 1),
        full_wear: false,
        samples_per_mesh_cycle: 4,
    };
    let records = run(&m, &plan, &|_, _| {}).unwrap();
    let mut built = 0;
    for r in &records {
        if r.status == "ok" {
            built += 1;
            let b = r.points[0].backlash_arcmin;
            assert!((0.05..=0.5).contains(&b), "sample {}: {b}", r.sample);
        } else {
            assert!(
                r.status.starts_with(REJECTED) && r.status.contains("[0.05, 0.5]"),
                "{}",
                r.status
            );
        }
    }
    println!("{built} of 8 built");
    assert!(built > 0);
    m.tolerances.selective = Some(selection(&[0.0], [40.0, 50.0]));
    let records = run(&m, &plan, &|_, _| {}).unwrap();
    assert!(records.iter().all(|r| r.status.starts_with(REJECTED)));
    assert!(unusable(&records).unwrap().contains("rejected at assembly"));
}

/// The band and the grades are checked by key.
#[test]
fn bad_grades_and_bands_are_named() {
    let bad = |grades: &[f64], band: [f64; 2]| {
        SelectiveAssemblyConfig {
            pin_grades_um: grades.to_vec(),
            backlash_arcmin: band,
        }
        .validate()
        .unwrap_err()
        .to_string()
    };
    assert!(bad(&[], [0.0, 1.0]).contains("tolerances.selective_assembly.pin_grades_um"));
    assert!(bad(&[1.0, 1.0], [0.0, 1.0]).contains("distinct"));
    assert!(bad(&[25.0], [0.0, 1.0]).contains("pin_grades_um[0]"));
    assert!(bad(&[0.0], [0.5, 0.5]).contains("backlash_arcmin"));
    assert!(bad(&[0.0], [f64::NAN, 0.5]).contains("backlash_arcmin[0]"));
}
