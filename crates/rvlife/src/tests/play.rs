//! The no-load limits of the contact problem (docs/model.md section 5.10) against loaded solves
//! at falling torque on modified and worn discs, with part errors, and over the bearing
//! clearances of every preset.

use rayon::prelude::*;

use crate::config::{preset_text, Config, Model, PRESETS};
use crate::geometry::{Profile, Vec2, WearMap};
use crate::statics::StaticAnalysis;
use crate::te::{
    hysteresis_and_rated, hysteresis_cold, hysteresis_with_from, mesh_cycle_angles,
    revolution_angles, torque_fractions, zero_torque, zero_torque_twist_from, ZeroTorqueStart,
    HYSTERESIS_LEVELS,
};
use crate::units::ARCMIN_PER_RAD;

fn example() -> Model {
    Config::from_toml_str(&preset_text("rv-40e").unwrap(), "test")
        .unwrap()
        .validate()
        .unwrap()
}

/// The preset `name` validated, with the radial clearance `c` (m) in its crank-disc bearings
/// (`kind` 0), its crank-carrier bearings (1) or both (2).
fn preset_with_clearance(name: &str, kind: usize, c: f64) -> Model {
    let mut m = Config::from_toml_str(&preset_text(name).unwrap(), "test")
        .unwrap()
        .validate()
        .unwrap();
    if kind != 1 {
        m.reducer.bearings.disc.clearance = c;
    }
    if kind != 0 {
        m.reducer.bearings.carrier.clearance = c;
    }
    m
}

/// The example's disc new and at four stages of its own wear (1 250 to 7 500 h).
fn stages(m: &Model) -> Vec<(f64, Profile)> {
    let mut m = m.clone();
    m.wear.stage_hours = vec![1250.0, 2500.0, 5000.0, 7500.0];
    let hist = crate::wear::integrate(&m.wear_inputs(), &|_, _| {}).unwrap();
    let mut out = vec![(0.0, m.profile().unwrap())];
    for (h, map) in hist.hours.iter().zip(&hist.maps) {
        let p = m
            .cycloid
            .profile(Some(WearMap::new(map.clone()).unwrap()))
            .unwrap();
        out.push((*h, p));
    }
    out
}

/// The example (2 um in its needle bearings, 10 / 10 um of modification), new and at four
/// worn stages, 24 crank angles, both directions: the loaded twist at `1e-2`, `1e-3` and
/// `1e-4` of the rated torque never lies behind the no-load limit (to 1e-9 rad, the twist
/// tables' round-off) and comes down towards it as the torque falls (each lighter solve
/// between the limit and the heavier one). The loaded twists converge slowly where a disc rests
/// on a pin near the line of centres (the line contact's approach goes as `F ln(1/F)`, and the
/// pin's groove contact adds another); the lightest stays within 0.08 arcmin of the limit
/// everywhere (0.063 seen).
#[test]
fn loaded_twists_come_down_to_the_no_load_limit() {
    let m = example();
    let rated = m.rating.rated_torque;
    let phis = mesh_cycle_angles(m.reducer.geometry.pins, 24);
    let mut worst: f64 = 0.0;
    for (hours, profile) in stages(&m) {
        let sa = StaticAnalysis::new(&m.reducer, &profile).unwrap();
        let rows: Vec<[f64; 4]> = phis
            .par_iter()
            .flat_map_iter(|&phi| {
                let sa = &sa;
                [1.0, -1.0].into_iter().map(move |s| {
                    let limit = sa.no_load_twist(phi, s).unwrap();
                    let psi0 = sa.first_contact(phi, s).unwrap();
                    let mut d = [0.0; 4];
                    for (k, f) in [1e-2, 1e-3, 1e-4].into_iter().enumerate() {
                        let sol = sa.solve_near(phi, s * f * rated, psi0, None).unwrap();
                        d[k] = s * (sol.twist - limit);
                    }
                    d[3] = phi;
                    d
                })
            })
            .collect();
        for d in &rows {
            let at = format!("{hours} h, crank {:.3} deg", d[3].to_degrees());
            assert!(d[2] >= -1e-9, "{at}: behind the limit by {:e} rad", d[2]);
            assert!(d[1] >= d[2] - 1e-9 && d[0] >= d[1] - 1e-9, "{at}: {d:?}");
            worst = worst.max(d[2]);
        }
    }
    println!(
        "lightest loaded twist beyond the limit: at most {:.4} arcmin",
        worst * ARCMIN_PER_RAD
    );
    assert!(worst * ARCMIN_PER_RAD < 0.08);
}

/// Clearances of the scans below, um: none, the presets' 2 um, the crank bearings' radial
/// internal clearance groups (ISO 5753-1) up to where a robot reducer is no longer built.
const CLEARANCES_UM: [f64; 7] = [0.0, 1.0, 2.0, 5.0, 9.85, 15.0, 20.0];

/// `rvlife te` on `m` new, its quantities in arcmin.
fn te_of(m: &Model) -> crate::api::TeResult {
    let new = crate::api::Wear {
        wear_um: None,
        hours: None,
    };
    crate::api::te(m, new, None, crate::api::Spelling::Cli, &|_, _| {}).unwrap()
}

/// Part errors far below the play do not take it away (docs/model.md section 5.12): `rvlife
/// te` with 0.01 um of pin-circle run-out gives a backlash within 0.01 arcmin of the one
/// without it, on every preset with 0 to 20 um in its crank-disc bearings and, apart, in its
/// crank-carrier bearings, and the largest backlash over the revolution is never below the
/// mean. Before the contact problem any crossing of the rigid first contacts counted as
/// preload and halved the example's backlash; until the preload was told from an interference
/// that holds no torque, the paper's reducer with play only in its crank-carrier bearings lost
/// 96 % of it (0.4244 to 0.0177 arcmin at 5 um), and the largest backlash of `te` with part
/// errors was the rigid first contacts' (0.037 arcmin against a backlash of 0.279). A reducer
/// with no play anywhere is left out: its modifications' rigid play (0.3 um at the pin circle
/// on the RV presets) is closed by 0.005 um at a pin near the line of centres, whose small
/// lever turns that into 0.03 arcmin of rigid twist, and the crank angles where it is closed
/// are preloaded.
#[test]
fn a_tiny_part_error_keeps_the_bearings_play() {
    let cases: Vec<(&str, usize, f64)> = PRESETS
        .iter()
        .flat_map(|p| (0..2).flat_map(move |kind| CLEARANCES_UM.map(|c| (p.name, kind, c))))
        .collect();
    let rows: Vec<(String, f64, f64, f64, f64)> = cases
        .par_iter()
        .filter_map(|&(name, kind, c)| {
            let m = preset_with_clearance(name, kind, c * 1e-6);
            if m.reducer.max_half_play() <= 0.0 {
                return None;
            }
            let plain = te_of(&m);
            let mut errs = m.clone();
            errs.reducer.errors.pin_circle_offset = Vec2::new(0.005e-6, 0.0);
            let with = te_of(&errs);
            let at = format!("{name}, {} bearings {c} um", ["disc", "carrier"][kind]);
            Some((
                at,
                plain.backlash_arcmin,
                with.backlash_arcmin,
                plain.backlash_max_arcmin,
                with.backlash_max_arcmin,
            ))
        })
        .collect();
    for (at, plain, with, plain_max, with_max) in &rows {
        println!("{at}: backlash {plain:.5} arcmin, with 0.01 um of run-out {with:.5}");
        assert!((with - plain).abs() < 0.01, "{at}: {plain} then {with}");
        assert!(plain_max >= plain && with_max >= with, "{at}: {rows:?}");
    }
    assert!(rows.len() >= 60, "{} cases with play", rows.len());
}

/// `rvlife hysteresis` as the command runs it ([`crate::api::hysteresis_curve`]) over the
/// clearance scan, 0 to 20 um in the crank-disc bearings, the crank-carrier bearings and both,
/// on every preset: every curve is solved, its backlash is not negative and grows with the
/// clearance.
#[test]
fn hysteresis_over_clearances_on_every_preset() {
    let cases: Vec<(&str, usize, f64)> = PRESETS
        .iter()
        .flat_map(|p| (0..3).flat_map(move |kind| CLEARANCES_UM.map(|c| (p.name, kind, c))))
        .collect();
    let results: Vec<(String, usize, f64, f64)> = cases
        .par_iter()
        .map(|&(name, kind, c)| {
            let m = preset_with_clearance(name, kind, c * 1e-6);
            let new = crate::api::Wear {
                wear_um: None,
                hours: None,
            };
            let r = crate::api::hysteresis_curve(
                &m,
                new,
                0.0,
                10,
                crate::api::Spelling::Cli,
                &|_, _| {},
            )
            .unwrap_or_else(|e| panic!("{name}, bearings {kind}, clearance {c} um: {e}"));
            (name.to_string(), kind, c, r.backlash_arcmin)
        })
        .collect();
    for w in results.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        assert!(a.3 >= 0.0, "{a:?}");
        if a.0 == b.0 && a.1 == b.1 {
            assert!(b.3 >= a.3 - 1e-9, "{a:?} then {b:?}");
        }
    }
    for r in &results {
        println!(
            "{} bearings {} clearance {} um: backlash {:.4} arcmin",
            r.0,
            ["disc", "carrier", "both"][r.1],
            r.2,
            r.3
        );
    }
}

/// `rvlife hysteresis` as the command runs it ([`crate::api::hysteresis_curve`]: the preset's
/// crank angles per mesh cycle, 10 torque levels per side, the twist shares) where the inner
/// solve crawled and failed after 100 steps (a disc held only by its pins, its crank bearings
/// open in their clearance, docs/model.md section 5.3): the RV presets with 9.85-20 um in both
/// bearing kinds, the single-stage preset with 20 um in its eccentric bearings. Every curve is
/// solved, every twist is finite and its backlash is positive (the bearings' play).
#[test]
fn hysteresis_where_the_inner_solve_crawled() {
    let cases = [
        ("rv-40e", 2, 9.85e-6),
        ("rv-40e", 2, 20e-6),
        ("rv-20e", 2, 13e-6),
        ("single-stage", 0, 20e-6),
        ("single-stage", 2, 20e-6),
    ];
    for &(name, kind, c) in &cases {
        let m = preset_with_clearance(name, kind, c);
        let new = crate::api::Wear {
            wear_um: None,
            hours: None,
        };
        let r =
            crate::api::hysteresis_curve(&m, new, 0.0, 10, crate::api::Spelling::Cli, &|_, _| {})
                .unwrap_or_else(|e| panic!("{name}, bearings {kind}, clearance {c:e}: {e}"));
        println!(
            "{name} bearings {kind} clearance {c:e}: backlash {:.4} arcmin",
            r.backlash_arcmin
        );
        assert!(
            r.twist_arcmin.iter().all(|x| x.is_finite()) && r.backlash_arcmin > 0.0,
            "{name}, bearings {kind}, clearance {c:e}: {:?}",
            r.twist_arcmin
        );
    }
}

/// The unworn disc (`None`) and `model`'s wear maps at each of `hours` (its own wear
/// integration).
fn new_and_worn(model: &Model, hours: &[f64]) -> Vec<Option<WearMap>> {
    let mut m = model.clone();
    m.wear.stage_hours = hours.to_vec();
    let hist = crate::wear::integrate(&m.wear_inputs(), &|_, _| {}).unwrap();
    std::iter::once(None)
        .chain(
            hist.maps
                .iter()
                .map(|w| Some(WearMap::new(w.clone()).unwrap())),
        )
        .collect()
}

/// Four sampled reducers of the example (Monte Carlo samples 0-3 of seed 1: part errors and
/// modification from its tolerances), on the nominal wear maps new and at four stages (1 250 to
/// 7 500 h), at 24 crank angles spread over the output revolution: the zero-torque twists
/// started from the last stage's ends ([`zero_torque_twist_from`], as Monte Carlo solves a
/// sample's stages) equal the cold search's ([`zero_torque`], from the rigid first contacts)
/// to 1e-11 rad (2e-8 arcmin; the contact problem stops at 1.6e-12 rad, the solves at a
/// residual of 1e-9 of their forces), both where the stage has play and where it is preloaded
/// (the last stage's lightest solves as starts, in place of the descent from 2.56 % of the
/// rated torque); and so do the hysteresis curves at
/// the 4 crank angles of a mesh cycle, every level of the grid of [`hysteresis_with_from`]
/// (each loaded level from the last stage's) against every crank angle solved cold.
#[test]
fn warm_started_searches_equal_the_cold_ones() {
    let nominal = example();
    let rated = nominal.rating.rated_torque;
    let maps = new_and_worn(&nominal, &[1250.0, 2500.0, 5000.0, 7500.0]);
    let all = revolution_angles(nominal.reducer.geometry.pins, 4);
    let phis: Vec<f64> = all.iter().copied().step_by(all.len() / 24 + 1).collect();
    let (mut preloaded, mut play, mut worst, mut worst_curve) = (0, 0, 0.0_f64, 0.0_f64);
    for index in 0..4 {
        let sample = crate::montecarlo::sample_model(&nominal, 1, index);
        let mut warm = vec![ZeroTorqueStart::default(); phis.len()];
        let mut cranks = Vec::new();
        for map in &maps {
            let profile = sample.cycloid.profile(map.clone()).unwrap();
            let sa = StaticAnalysis::new(&sample.reducer, &profile).unwrap();
            let cycle = mesh_cycle_angles(sample.reducer.geometry.pins, 4);
            let grid = torque_fractions(0.03, 1, false);
            let (cold, _) = hysteresis_cold(&sa, &cycle, rated, 0.03, &grid).unwrap();
            let (hot, _) = hysteresis_with_from(&sa, &cycle, rated, 0.03, 1, &mut cranks).unwrap();
            for (c, h) in cold.iter().zip(&hot) {
                for (a, b) in c.positive.iter().zip(&h.positive) {
                    worst_curve = worst_curve.max((a - b).abs());
                }
                for (a, b) in c.negative.iter().zip(&h.negative) {
                    worst_curve = worst_curve.max((a - b).abs());
                }
            }
            let rows: Vec<(bool, [f64; 2], [f64; 2])> = phis
                .par_iter()
                .zip(warm.par_iter_mut())
                .map(|(&phi, w)| {
                    let cold = zero_torque(&sa, phi, rated).unwrap();
                    let hot = zero_torque_twist_from(&sa, phi, rated, w).unwrap();
                    (cold.preloaded, cold.twist, hot)
                })
                .collect();
            for (pre, cold, hot) in rows {
                if pre {
                    preloaded += 1;
                } else {
                    play += 1;
                }
                for k in 0..2 {
                    worst = worst.max((cold[k] - hot[k]).abs());
                }
            }
        }
    }
    println!(
        "{preloaded} preloaded and {play} free crank angles; largest difference {worst:.3e} rad, \
         of the hysteresis curves {worst_curve:.3e} rad"
    );
    assert!(preloaded > 0 && play > 0);
    assert!(
        worst < 1e-11,
        "warm and cold twists differ by {worst:e} rad"
    );
    assert!(
        worst_curve < 1e-11,
        "warm and cold hysteresis curves differ by {worst_curve:e} rad"
    );
}

/// The study's hysteresis curves with each crank angle's loaded levels started from the
/// neighbouring crank angle's ([`hysteresis_and_rated`], in runs of consecutive crank angles)
/// equal every crank angle solved cold (each level from the one below, the first from the
/// zero-torque state) to 1e-11 rad: the example and a sampled reducer of it (part errors that
/// preload some crank angles), new and at three stages of wear (1 250 to 7 500 h), the 24
/// crank angles of a mesh cycle, every level of the study's grid (0 to the rated torque, both
/// ways: 22 loaded solves per crank angle) and the solutions at the rated torque.
#[test]
fn neighbour_started_hysteresis_equals_the_cold_one() {
    let nominal = example();
    let rated = nominal.rating.rated_torque;
    let maps = new_and_worn(&nominal, &[1250.0, 3750.0, 7500.0]);
    let grid = torque_fractions(0.03, HYSTERESIS_LEVELS, true);
    let (mut worst, mut solves) = (0.0_f64, 0);
    for model in [
        nominal.clone(),
        crate::montecarlo::sample_model(&nominal, 1, 0),
    ] {
        let cycle = mesh_cycle_angles(model.reducer.geometry.pins, 24);
        for map in &maps {
            let profile = model.cycloid.profile(map.clone()).unwrap();
            let sa = StaticAnalysis::new(&model.reducer, &profile).unwrap();
            let (chained, _, rated_chained) =
                hysteresis_and_rated(&sa, &cycle, rated, 0.03, &grid).unwrap();
            let (cold, rated_cold) = hysteresis_cold(&sa, &cycle, rated, 0.03, &grid).unwrap();
            for (c, h) in cold.iter().zip(&chained) {
                for (a, b) in c
                    .positive
                    .iter()
                    .zip(&h.positive)
                    .chain(c.negative.iter().zip(&h.negative))
                {
                    worst = worst.max((a - b).abs());
                    solves += 1;
                }
            }
            for (c, h) in rated_cold.iter().zip(&rated_chained) {
                worst = worst.max((c.twist - h.twist).abs());
            }
        }
    }
    println!("{solves} twists; largest difference {worst:.3e} rad");
    assert_eq!(solves, 2 * 4 * 24 * 2 * grid.len());
    assert!(
        worst < 1e-11,
        "neighbour-started and cold hysteresis differ by {worst:e} rad"
    );
}

/// The loaded solve (the potential's minimum by torque control, docs/model.md section 5.3)
/// converges from its start (the neighbour's solution, or cold), without load steps, at all but
/// 1 in 400 of the loaded solves of the study's hysteresis grid (24 crank angles, both ways,
/// every level from the measuring torque to the rated torque) of the example and of a sampled
/// reducer of it (part errors that preload some crank angles), new and at three stages of wear
/// (1 250 to 7 500 h), and of the sampled reducer's zero-torque states at 24 crank angles over
/// the output revolution (its preloaded crank angles' descents and probes). The example's grid
/// takes load steps nowhere.
#[test]
fn loaded_solves_converge_from_their_start() {
    let nominal = example();
    let rated = nominal.rating.rated_torque;
    let maps = new_and_worn(&nominal, &[1250.0, 3750.0, 7500.0]);
    let grid = torque_fractions(0.03, HYSTERESIS_LEVELS, true);
    let sampled = crate::montecarlo::sample_model(&nominal, 1, 0);
    let all = revolution_angles(nominal.reducer.geometry.pins, 4);
    let spread: Vec<f64> = all.iter().copied().step_by(all.len() / 24 + 1).collect();
    let (mut solves, mut fallbacks) = (0, 0);
    for model in [&nominal, &sampled] {
        let cycle = mesh_cycle_angles(model.reducer.geometry.pins, 24);
        for map in &maps {
            let profile = model.cycloid.profile(map.clone()).unwrap();
            let sa = StaticAnalysis::new(&model.reducer, &profile).unwrap();
            hysteresis_and_rated(&sa, &cycle, rated, 0.03, &grid).unwrap();
            if std::ptr::eq(model, &nominal) {
                assert_eq!(
                    sa.loaded_solves()[1],
                    0,
                    "the example's grid took load steps"
                );
            } else {
                for &phi in &spread {
                    zero_torque(&sa, phi, rated).unwrap();
                }
            }
            let [n, f] = sa.loaded_solves();
            solves += n;
            fallbacks += f;
        }
    }
    println!("{fallbacks} of {solves} loaded solves took load steps");
    assert!(solves > 3000);
    assert!(
        400 * fallbacks <= solves,
        "{fallbacks} of {solves} loaded solves took load steps"
    );
}

/// An unmodified, unworn disc on bearings without clearance touches the pins both ways at the
/// same twist: its backlash, peak backlash and hysteresis loss are zero or positive (the two
/// twists' round-off, -7e-9 arcmin before, is floored at zero, `te::at_round_off_floor`), with
/// and without friction, and the peak backlash is never below the mean.
#[test]
fn play_and_loss_without_play_are_never_negative() {
    use crate::api::{Spelling, Wear};
    let text = preset_text("rv-40e").unwrap();
    for lubrication in [true, false] {
        let edits: Vec<(String, Option<serde_json::Value>)> = [
            (
                "cycloid.modification.equidistant_mm",
                serde_json::json!(0.0),
            ),
            ("cycloid.modification.offset_mm", serde_json::json!(0.0)),
            (
                "reducer.bearings.crank_disc_clearance_um",
                serde_json::json!(0.0),
            ),
            ("lubrication.enabled", serde_json::json!(lubrication)),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), Some(v)))
        .collect();
        let t = crate::config::edit::set(&text, "test", &edits).unwrap();
        let m = crate::api::validated(&Config::from_toml_str(&t, "test").unwrap()).unwrap();
        let te = crate::api::te(&m, Wear::default(), None, Spelling::Cli, &|_, _| {}).unwrap();
        assert!(te.backlash_arcmin >= 0.0, "{}", te.backlash_arcmin);
        assert!(te.backlash_arcmin < 1e-6, "{}", te.backlash_arcmin);
        assert!(te.backlash_max_arcmin >= te.backlash_arcmin);
        for crank_deg in [0.0, 2.25, 4.5, 6.75] {
            let h = crate::api::hysteresis_curve(
                &m,
                Wear::default(),
                crank_deg,
                HYSTERESIS_LEVELS,
                Spelling::Cli,
                &|_, _| {},
            )
            .unwrap();
            assert!(
                h.backlash_arcmin >= 0.0,
                "{crank_deg}: {}",
                h.backlash_arcmin
            );
            assert!(
                h.hysteresis_loss_arcmin >= 0.0,
                "{crank_deg} deg, lubrication {lubrication}: {}",
                h.hysteresis_loss_arcmin
            );
        }
    }
}
