//! The study in parts (`study::parts`, what the web page runs on separate workers) against the
//! study on one machine's threads: the same results files byte for byte, through the bytes
//! that cross between workers; and the validity limit taken from a failed stage as the study
//! takes it.

use crate::config::{Config, Model};
use crate::study::parts::{self, StageOutcome};
use crate::study::Study;

/// The example without dynamics and FE; with `worn_parts`, also part errors, running-in and
/// crank bearings and pins that wear (the stages' own bearings, pins and revolution TE).
fn model(worn_parts: bool) -> Model {
    let mut cfg = Config::example();
    cfg.dynamics.enabled = false;
    cfg.fem.enabled = false;
    if worn_parts {
        cfg.wear.bearing_archard_coefficient_mm3_per_n_m = 1e-9;
        cfg.wear.pin_archard_coefficient_mm3_per_n_m = 6.844807e-9;
        cfg.wear.running_in_factor = 3.0;
        cfg.errors.pin_circle_runout_um = 2.0;
        cfg.wear.stage_hours = vec![0.0, 2000.0, 4000.0];
        // Pins held rigidly: with them in grooves, this much wear and the run-out, the
        // WebAssembly build's static solve at 4e-4 N m fails at 327 h (the potential's minimum
        // not reached in 100 steps; natively it converges): a robustness defect of its own, not
        // what this test is about.
        cfg.contact.pin_support = Some("rigid".into());
        // And the disc body rigid: with it elastic the native static solve at 4e-4 N m fails
        // the same way at 223 h (the discs float in their bearings' grown clearance), the
        // same defect.
        cfg.reducer.structure.disc_body = Some("rigid".into());
    }
    cfg.validate().unwrap()
}

/// `x` through the bytes a worker sends (CBOR, as the WebAssembly binding sends them).
fn crossed<T: serde::Serialize + serde::de::DeserializeOwned>(x: &T) -> T {
    let mut bytes = Vec::new();
    ciborium::into_writer(x, &mut bytes).unwrap();
    ciborium::from_reader(bytes.as_slice()).unwrap()
}

/// The study of `m` in parts, as the page runs it: the unworn first stage beside the wear, the
/// others as the wear hands them on, the accuracy life's crossing made ahead, every piece
/// through bytes.
fn in_parts(m: &Model) -> Study {
    let ground = crossed(&parts::ground(m).unwrap());
    let first = parts::unworn_first(m).map(|s| crossed(&parts::static_stage(m, &ground, &s)));
    // The stages as the integration hands them on, each analysed at once (the first unless
    // it was analysed beside the wear): those of the finished history.
    let handed = std::cell::RefCell::new(Vec::new());
    let wear = parts::wear_history(m, &ground, &|_, _| {}, &|s| {
        handed.borrow_mut().push(crossed(&s));
    })
    .unwrap();
    let handed = handed.into_inner();
    let whole = parts::stage_wears(&wear);
    assert_eq!(handed.len(), whole.len());
    for (a, b) in handed.iter().zip(&whole) {
        assert_eq!(crossed(a), crossed(b));
    }
    // In the order handed on, the accuracy life's trials between two stages offered after
    // each (as the page makes them on the worker that holds the wear, while the others go on).
    let mut outcomes: Vec<StageOutcome> = first.into_iter().collect();
    let mut ahead = None;
    let mut settled_with = None;
    for s in &handed {
        if outcomes.iter().all(|o| o.index() != s.index) {
            outcomes.push(crossed(&parts::static_stage(m, &ground, s)));
        }
        if ahead.is_none() {
            ahead = parts::crossing_ahead(m, &wear, &outcomes);
            settled_with = ahead.is_some().then_some(outcomes.len());
        }
    }
    // The example's life lies between two of its early stages: settled before the last is in.
    if m.life.any() {
        assert!(
            settled_with.is_some_and(|k| k < handed.len()),
            "the crossing ahead settled with {settled_with:?} of {} stages",
            handed.len()
        );
    }
    parts::assemble_ahead(m, wear, outcomes, ahead, &|_| {}).unwrap()
}

#[test]
fn study_in_parts_is_the_study() {
    for worn_parts in [false, true] {
        let m = model(worn_parts);
        let whole = crate::study::run(&m, &|_, _| {}).unwrap();
        let parted = in_parts(&m);
        let (a, b) = (
            crate::output::study::data_files(&whole).unwrap(),
            crate::output::study::data_files(&parted).unwrap(),
        );
        assert_eq!(a.len(), b.len());
        for ((name, x), (other, y)) in a.iter().zip(&b) {
            assert_eq!(name, other);
            assert!(x == y, "{name} differs (worn parts: {worn_parts})");
        }
        assert_eq!(whole.verdict(), parted.verdict());
        let names: Vec<String> = crate::output::study::tables(&whole)
            .unwrap()
            .into_iter()
            .map(|(n, _)| n)
            .collect();
        assert_eq!(crate::output::study::table_names(&whole), names);
    }
}

/// The flexible disc after the static stages in parts (`parts::flexible`, what the page runs
/// with `[fem] enabled`) against the study with it on one machine: the same files, the
/// flexible quantities among them.
#[test]
fn flexible_disc_in_parts_is_the_studys() {
    let mut cfg = Config::example();
    cfg.dynamics.enabled = false;
    let fem = cfg.validate().unwrap();
    let whole = crate::study::run(&fem, &|_, _| {}).unwrap();
    let mut parted = in_parts(&fem.clone().static_only());
    let steps = std::sync::Mutex::new(Vec::new());
    parts::flexible(&mut parted, &|d, t| steps.lock().unwrap().push((d, t))).unwrap();
    let n = parted.stages.len() + 1;
    assert_eq!(
        steps.into_inner().unwrap(),
        (1..=n).map(|d| (d, n)).collect::<Vec<_>>()
    );
    let (a, b) = (
        crate::output::study::data_files(&whole).unwrap(),
        crate::output::study::data_files(&parted).unwrap(),
    );
    assert_eq!(
        a.iter().map(|f| &f.0).collect::<Vec<_>>(),
        b.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name} differs");
    }
    let last = &parted.stages.last().unwrap().summary;
    assert!(last
        .flexible_ste_peak_to_peak_arcmin
        .is_some_and(|v| v > 0.0));
    assert!(last.max_von_mises_mpa.is_some_and(|v| v > 0.0));
}

#[test]
fn stage_failure_in_parts_is_the_validity_limit() {
    let m = model(false);
    let ground = parts::ground(&m).unwrap();
    let wear = parts::wear_history(&m, &ground, &|_, _| {}, &|_| {}).unwrap();
    let stages = parts::stage_wears(&wear);
    // A worn stage whose static analysis fails (a solver's failure, through the bytes a
    // worker sends) is the validity limit: the stages from it on are dropped.
    let k = 3;
    let failure = crate::Error::numerical("static equilibrium", "did not converge");
    let mut outcomes: Vec<StageOutcome> = stages
        .iter()
        .map(|s| match s.index {
            i if i == k => crossed(&StageOutcome::static_failure(s, &failure)),
            _ => parts::static_stage(&m, &ground, s),
        })
        .collect();
    outcomes.reverse();
    assert!(outcomes.iter().any(|o| o.index() == k && o.failed()));
    let study = parts::assemble(&m, wear.clone(), outcomes, &|_| {}).unwrap();
    assert_eq!(study.stages.len(), k);
    let limit = study.wear.limit.as_ref().expect("the validity limit");
    assert_eq!(limit.hours, wear.hours[k]);
    assert_eq!(limit.reason, failure.to_string());
    assert_eq!(study.wear.hours.len(), k);
    // On the unworn first stage the same failure is the study's error, word for word.
    let mut outcomes: Vec<StageOutcome> = stages[1..]
        .iter()
        .map(|s| parts::static_stage(&m, &ground, s))
        .collect();
    outcomes.push(crossed(&StageOutcome::static_failure(&stages[0], &failure)));
    let e = parts::assemble(&m, wear.clone(), outcomes, &|_| {}).unwrap_err();
    assert_eq!(e.to_string(), failure.to_string());
    // Outcomes that do not belong: a stage missing, or twice.
    let again = |drop: usize, twice: bool| {
        let mut o: Vec<StageOutcome> = stages
            .iter()
            .filter(|s| s.index != drop)
            .map(|s| parts::static_stage(&m, &ground, s))
            .collect();
        if twice {
            o.push(o[0].clone());
        }
        parts::assemble(&m, wear.clone(), o, &|_| {})
    };
    assert!(again(usize::MAX, true)
        .unwrap_err()
        .to_string()
        .contains("stage outcome"));
    assert!(again(2, false)
        .unwrap_err()
        .to_string()
        .contains("stage 2 was not analysed"));
}

/// Monte Carlo in parts as the web page runs it: the samples' stages analysed on the nominal
/// history's early part (handed on once the integration passes the last stage), the samples
/// whose life lies beyond finished on the whole history, both through the bytes a worker
/// sends: the same records, bit for bit, as the run on one machine.
#[test]
fn monte_carlo_on_the_early_history_equals_the_run_on_the_whole() {
    use crate::montecarlo::{self, NominalWear, Plan, SampleStep, SharedWear};
    // The example: of six samples of seed 1, three outlast the last stage (7 500 h).
    let m = model(false);
    let plan = Plan {
        samples: 6,
        seed: 1,
        shard: (1, 1),
        full_wear: false,
        samples_per_mesh_cycle: 4,
    };
    let whole_run = montecarlo::run(&m, &plan, &|_, _| {}).unwrap();
    let early = std::sync::Mutex::new(None);
    let whole = montecarlo::nominal_wear_reporting(&m, &|_, _| {}, &|w: NominalWear| {
        *early.lock().unwrap() = Some(crossed(&w));
    })
    .unwrap();
    let early = early
        .into_inner()
        .unwrap()
        .expect("the early part is handed on");
    assert!(early.partial && !whole.partial);
    assert_eq!(early.maps[..], whole.maps[..early.maps.len()]);
    let (early, whole) = (
        SharedWear::of(&m, &early).unwrap(),
        SharedWear::of(&m, &crossed(&whole)).unwrap(),
    );
    let mut waited = 0;
    for (i, want) in whole_run.iter().enumerate() {
        let got = match montecarlo::sample_on(&m, &plan, &early, i) {
            SampleStep::Done(r) => r,
            SampleStep::Beyond(s) => {
                waited += 1;
                assert_eq!(s.index(), i);
                montecarlo::sample_beyond(&m, &plan, &whole, *s).unwrap()
            }
        };
        assert!(&got == want, "sample {i}: {got:?} against {want:?}");
    }
    assert!(
        (1..whole_run.len()).contains(&waited),
        "{waited} of {} samples waited for the whole history: both ways are checked",
        whole_run.len()
    );
}

/// Records what a study's observers hear.
#[derive(Default)]
struct Heard {
    progress: std::sync::Mutex<Vec<(usize, usize)>>,
    stages: std::sync::Mutex<Vec<(usize, f64)>>,
}

impl crate::study::Observer for Heard {
    fn progress(&self, done: usize, total: usize) {
        self.progress.lock().unwrap().push((done, total));
    }

    fn stage(&self, index: usize, summary: &crate::quantities::StageSummary) {
        self.stages.lock().unwrap().push((index, summary.hours));
    }
}

/// The study's executor with observers (`study::Executor`) against the easy call
/// (`study::run`): the same results files byte for byte, with two observers each hearing every
/// stage's static results exactly once at the stage's hours, and the progress with one fixed
/// total (the wear-rate evaluations as scheduled and one step a stage), never beyond it, its
/// last report the whole (the worn parts' study stopped at 18 of 19 before that report: the
/// scheduled count of wear-rate evaluations is an estimate).
#[test]
fn executor_observers_hear_every_stage_and_the_progress() {
    for worn_parts in [false, true] {
        let m = model(worn_parts);
        let (first, second) = (Heard::default(), Heard::default());
        let study = crate::study::Executor::new(&m)
            .observe(&first)
            .observe(&second)
            .run()
            .unwrap();
        let easy = crate::study::run(&m, &|_, _| {}).unwrap();
        let (a, b) = (
            crate::output::study::data_files(&study).unwrap(),
            crate::output::study::data_files(&easy).unwrap(),
        );
        assert!(a == b, "the files differ (worn parts: {worn_parts})");
        let total = parts::wear_steps(&m) + m.wear.stage_hours.len();
        for heard in [first, second] {
            let mut stages = heard.stages.into_inner().unwrap();
            stages.sort_by_key(|s| s.0);
            let hours: Vec<(usize, f64)> = study
                .stages
                .iter()
                .enumerate()
                .map(|(i, s)| (i, s.hours))
                .collect();
            assert_eq!(stages, hours, "worn parts: {worn_parts}");
            let progress = heard.progress.into_inner().unwrap();
            assert!(progress.iter().all(|&(d, t)| t == total && d <= total));
            assert_eq!(progress.last(), Some(&(total, total)), "{progress:?}");
        }
    }
}
