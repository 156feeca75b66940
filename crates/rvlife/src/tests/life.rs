//! Accuracy life: the hours at which the first `[life]` threshold is crossed.

use crate::config::{Config, Model};
use crate::geometry::WearMap;
use crate::study::study_life;

/// The paper's reducer with 8 / -5 um of modification, without dynamics or the FE disc, and
/// without the preset's spec (each test sets its own).
fn model() -> Model {
    let text = crate::config::preset_text("paper")
        .unwrap()
        .replace("equidistant_mm = 0.0 ", "equidistant_mm = 0.008 ")
        .replace("offset_mm = 0.0 ", "offset_mm = -0.005 ")
        .replace("enabled = true ", "enabled = false ");
    let mut m = Config::from_toml_str(&text, "test")
        .unwrap()
        .validate()
        .unwrap();
    m.life = Default::default();
    m
}

/// A lost-motion threshold halfway between two stages' values: the life lies between those
/// stages, is limited by lost motion, and the lost motion of the reducer worn for exactly
/// that many hours (its own wear integration and analysis) equals the threshold to 1 % of the
/// rise between the stages (the root finder stops at 0.5 % of the hours, the last bracket is
/// interpolated linearly); the study's wear replayed to those hours (no wear rate evaluated
/// again) is that integration's, within 1e-12 of the deepest wear. A threshold above the last
/// stage's value is found beyond it, the integration stepped on (to 2 % of the last rise: the
/// wear there is integrated on the model's own update rule), the same to the bit whether its
/// trials are made ahead, beside the stages' analyses, or after them; one never reached gives no life within the horizon
/// (`life.max_hours`); one below the unworn value a life of zero.
#[test]
fn accuracy_life_is_where_the_worn_reducer_reaches_the_threshold() {
    let mut m = model();
    let study = crate::study::run(&m, &|_, _| {}).unwrap();
    let s: Vec<_> = study.stages.iter().map(|s| s.summary.clone()).collect();
    let (a, b) = (&s[2], &s[3]);
    assert!(b.lost_motion_arcmin > a.lost_motion_arcmin);
    let limit = 0.5 * (a.lost_motion_arcmin + b.lost_motion_arcmin);
    m.life.lost_motion_arcmin = Some(limit);
    let life = study_life(&m, &s, &study.wear, None, &|_| {})
        .unwrap()
        .unwrap();
    let h = life.accuracy_life_h.unwrap();
    assert_eq!(life.limited_by, Some("lost_motion_arcmin"));
    assert!(
        h > a.hours && h < b.hours,
        "life {h} h outside [{}, {}]",
        a.hours,
        b.hours
    );
    let mut at = m.clone();
    at.wear.stage_hours = vec![h];
    let hist =
        crate::wear::integrate_on_schedule(&at.wear_inputs(), &study.wear.update_hours, &|_, _| {})
            .unwrap();
    let inputs = crate::wear::WearInputs {
        bearing_rates: crate::config::bearing_rates(&m).unwrap(),
        ..m.wear_inputs()
    };
    let (replayed, _) = study.wear.replay(&inputs, h).unwrap().unwrap();
    let deepest = hist.maps[0].iter().copied().fold(0.0, f64::max);
    for (r, x) in replayed.iter().zip(&hist.maps[0]) {
        assert!((r - x).abs() < 1e-12 * deepest, "{r:e} {x:e}");
    }
    let p = m
        .cycloid
        .profile(Some(WearMap::new(hist.maps[0].clone()).unwrap()))
        .unwrap();
    let lm = crate::study::analyse_profile(&m, &p, h)
        .unwrap()
        .summary
        .lost_motion_arcmin;
    let rise = b.lost_motion_arcmin - a.lost_motion_arcmin;
    assert!(
        (lm - limit).abs() < 0.01 * rise,
        "lost motion at the life ({h:.1} h): {lm} against the threshold {limit}"
    );
    // Beyond the last stage the integration steps on (x 1.5): a threshold a little above the
    // last stage's lost motion is crossed there, and the reducer worn that long has it.
    let (p, q) = (&s[s.len() - 2], &s[s.len() - 1]);
    let beyond = q.lost_motion_arcmin + 0.5 * (q.lost_motion_arcmin - p.lost_motion_arcmin);
    m.life.lost_motion_arcmin = Some(beyond);
    m.life.max_hours = Some(2.0 * q.hours);
    let later = study_life(&m, &s, &study.wear, None, &|_| {})
        .unwrap()
        .unwrap();
    let h = later
        .accuracy_life_h
        .expect("crossed beyond the last stage");
    // The trials beyond the stages made ahead (beside the stages' analyses, from the last
    // stage's point) give the same life to the bit, and so does the study itself, which makes
    // them so when its last stage is within the spec.
    let start = crate::quantities::AccuracyPoint::of(q);
    let ahead = crate::study::LifeTrials::ahead(&m, &study.wear, start);
    assert!(ahead.is_some());
    let with_ahead = study_life(&m, &s, &study.wear, ahead, &|_| {})
        .unwrap()
        .unwrap();
    assert_eq!(with_ahead, later);
    let rerun = crate::study::run(&m, &|_, _| {}).unwrap();
    assert_eq!(rerun.life.as_ref(), Some(&later));
    assert!(h > q.hours && h <= 2.0 * q.hours, "life {h} h");
    let mut at = m.clone();
    at.wear.stage_hours = vec![h];
    let hist = crate::wear::integrate(&at.wear_inputs(), &|_, _| {}).unwrap();
    let pr = m
        .cycloid
        .profile(Some(WearMap::new(hist.maps[0].clone()).unwrap()))
        .unwrap();
    let lm = crate::study::analyse_profile(&m, &pr, h)
        .unwrap()
        .summary
        .lost_motion_arcmin;
    let rise = q.lost_motion_arcmin - p.lost_motion_arcmin;
    assert!(
        (lm - beyond).abs() < 0.02 * rise,
        "beyond: {lm} against {beyond} at {h:.0} h"
    );
    // Not crossed within the horizon.
    m.life.lost_motion_arcmin = Some(q.lost_motion_arcmin * 1.1);
    m.life.max_hours = Some(1.2 * q.hours);
    let none = study_life(&m, &s, &study.wear, None, &|_| {})
        .unwrap()
        .unwrap();
    assert_eq!(none.accuracy_life_h, None);
    assert_eq!(none.horizon_h, 1.2 * q.hours);
    m.life.lost_motion_arcmin = Some(s[0].lost_motion_arcmin * 0.9);
    let zero = study_life(&m, &s, &study.wear, None, &|_| {})
        .unwrap()
        .unwrap();
    assert_eq!(zero.accuracy_life_h, Some(0.0));
}

/// The verdict line names the life with the threshold and its spec, or the hours within spec
/// with the smallest margin at the last stage (the quantity, its value, the spec and the
/// share left), or the missing spec; and the duty.
#[test]
fn the_verdict_names_the_life_its_limit_and_the_duty() {
    use crate::life::{verdict, AccuracyLife};
    use crate::quantities::AccuracyPoint;
    let m = model();
    let mut th = m.life.clone();
    th.lost_motion_arcmin = Some(1.0);
    th.backlash_arcmin = Some(2.0);
    let last = AccuracyPoint {
        hours: 7500.0,
        max_wear_um: 60.0,
        backlash_arcmin: 0.5,
        lost_motion_arcmin: 0.8,
        angular_te_arcmin: 0.1,
        torsional_stiffness_nm_per_arcmin: 150.0,
    };
    let levels = &m.load.levels;
    let life = AccuracyLife {
        accuracy_life_h: Some(1857.6),
        limited_by: Some("lost_motion_arcmin"),
        horizon_h: 7500.0,
    };
    assert_eq!(
        verdict(&th, Some(&life), Some(&last), levels),
        "accuracy life 1858 h, limited by lost motion (spec 1 arcmin); duty: 412 N m at 1500 \
         rpm input"
    );
    let within = AccuracyLife {
        accuracy_life_h: None,
        limited_by: None,
        horizon_h: 75000.0,
    };
    // Lost motion 0.8 of 1.0 (20 % to go) is closer than backlash 0.5 of 2.0 (75 %).
    assert_eq!(
        verdict(&th, Some(&within), Some(&last), levels),
        "within spec up to 75000 h (smallest margin: lost motion 0.800 arcmin at 7500 h against \
         1 arcmin, 20 % to go); duty: 412 N m at 1500 rpm input"
    );
    let new = AccuracyLife {
        accuracy_life_h: Some(0.0),
        limited_by: Some("backlash_arcmin"),
        horizon_h: 7500.0,
    };
    assert!(verdict(&th, Some(&new), Some(&last), levels)
        .starts_with("out of spec when new: backlash (spec 2 arcmin)"));
    assert!(verdict(&th, None, Some(&last), levels).starts_with("no accuracy spec: set [life]"));
}

/// The paper's numbers are compared only with the paper's reducer as printed: the `paper`
/// preset is, the built-in example (the paper's stage with 10 / 10 um of modification) and
/// the other presets are not.
#[test]
fn only_the_papers_reducer_is_compared_with_the_paper() {
    use crate::config::{preset_text, Config};
    let model = |name: &str| {
        Config::from_toml_in(&preset_text(name).unwrap(), name, None)
            .unwrap()
            .validate()
            .unwrap()
    };
    assert!(crate::study::is_papers_reducer(&model("paper")));
    for name in ["rv-40e", "rv-20e", "rv-80e"] {
        assert!(!crate::study::is_papers_reducer(&model(name)), "{name}");
    }
    assert!(!crate::study::is_papers_reducer(
        &Config::example().validate().unwrap()
    ));
}

/// The wear integration continued from its last stage (`WearHistory::continued`, the life
/// search's step beyond the stages) keeps the history's stages, maps and profile updates, and
/// its wear at the new last stage is an integration's from zero to the same hours: exactly
/// (to 1e-12 of the deepest wear, round-off of the same sums) with profile updates where the
/// old last stage is a multiple of `wear.profile_update_hours` (every update schedule passes
/// through those multiples, so the two schedules are the same), and with the paper's model
/// (one rate held throughout). Continuing again from the continued history is the same as
/// continuing once. The trials of the life search between replay it (`replay`).
#[test]
fn wear_continued_from_the_last_stage_is_the_integration_from_zero() {
    let example = Config::example().validate().unwrap();
    let mut paper = model();
    paper.wear.model = crate::wear::WearModelKind::Paper;
    for (name, mut m) in [("example", example), ("paper model", paper)] {
        m.wear.stage_hours = vec![0.0, 500.0];
        let inputs = crate::wear::WearInputs {
            bearing_rates: crate::config::bearing_rates(&m).unwrap(),
            ..m.wear_inputs()
        };
        let short = crate::wear::integrate(&inputs, &|_, _| {}).unwrap();
        let once = short.continued(&inputs, 1000.0).unwrap();
        let twice = short
            .continued(&inputs, 750.0)
            .unwrap()
            .continued(&inputs, 1000.0)
            .unwrap();
        // An integration from zero with these stages.
        let from_zero = |stages: Vec<f64>| {
            let mut w = m.wear.clone();
            w.stage_hours = stages;
            crate::wear::integrate(&crate::wear::WearInputs { wear: &w, ..inputs }, &|_, _| {})
                .unwrap()
        };
        let long = from_zero(vec![0.0, 500.0, 1000.0]);
        assert_eq!(once.hours, vec![0.0, 500.0, 1000.0], "{name}");
        assert_eq!(once.maps[..2], short.maps[..], "{name}");
        assert_eq!(once.update_hours, long.update_hours, "{name}");
        let deepest = long.maps[2].iter().copied().fold(0.0, f64::max);
        assert!(deepest > 0.0, "{name}");
        assert_eq!(twice.update_hours, long.update_hours, "{name}");
        for (got, x) in [(&once, "once"), (&twice, "twice")] {
            let last = got.maps.last().unwrap();
            for (a, b) in last.iter().zip(&long.maps[2]) {
                assert!((a - b).abs() < 1e-12 * deepest, "{name} {x}: {a:e} {b:e}");
            }
        }
        let (between, _) = once.replay(&inputs, 750.0).unwrap().unwrap();
        let mid = from_zero(vec![0.0, 500.0, 750.0, 1000.0]);
        for (a, b) in between.iter().zip(&mid.maps[2]) {
            assert!(
                (a - b).abs() < 1e-12 * deepest,
                "{name} replayed: {a:e} {b:e}"
            );
        }
        assert!(short.continued(&inputs, 400.0).is_err(), "{name}");
    }
}
