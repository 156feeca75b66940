//! Speed: one static solve of the reducer model at the rated torque (new and 7500 h disc, with
//! the contact geometry built once), the power balance at the rated point (first order and with
//! the friction in the equilibrium), the contact geometry of one profile, the static TE of one
//! stage, 0.8 s multibody simulations (rigid discs at 10 um and 7500 h, flexible discs at 10 um), the
//! flexible disc, and the built-in study. Run with
//! `cargo bench -p rvlife`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use rvlife::config::Config;
use rvlife::geometry::WearMap;
use rvlife::statics::StaticAnalysis;

fn benches(c: &mut Criterion) {
    let model = Config::example().validate().expect("example validates");
    let new = model.profile().expect("profile");
    let mut worn_model = model.clone();
    worn_model.wear.stage_hours = vec![7500.0];
    let hist = rvlife::wear::integrate(&worn_model.wear_inputs(), &|_, _| {}).expect("wear");
    let worn = model
        .cycloid
        .profile(Some(WearMap::new(hist.maps[0].clone()).expect("map")))
        .expect("worn profile");
    let red = &model.reducer;
    let sa_new = StaticAnalysis::new(red, &new).expect("gap field");
    let sa_worn = StaticAnalysis::new(red, &worn).expect("gap field");
    c.bench_function("static_solve_new_disc", |b| {
        b.iter(|| {
            sa_new
                .solve(black_box(0.05), model.rating.rated_torque)
                .unwrap()
        })
    });
    c.bench_function("static_solve_worn_7500h", |b| {
        b.iter(|| {
            sa_worn
                .solve(black_box(0.05), model.rating.rated_torque)
                .unwrap()
        })
    });
    // The power balance at the rated point (412 N m, 15 rpm output) over a mesh cycle of 24
    // crank angles from its frictionless loads: to first order, and with the friction in the
    // equilibrium (the sweeps of the running equilibrium at every crank angle).
    let loads = rvlife::efficiency::mesh_cycle_loads(&sa_new, model.rating.rated_torque, 24)
        .expect("loads");
    c.bench_function("efficiency_rated_point_first_order", |b| {
        b.iter(|| {
            rvlife::efficiency::operating_point(
                &sa_new,
                &new,
                &model.lubrication,
                &model.wear,
                black_box(&loads),
                15.0,
            )
        })
    });
    c.bench_function("efficiency_rated_point_in_equilibrium", |b| {
        b.iter(|| {
            rvlife::efficiency::running_point(
                &sa_new,
                &new,
                &model.lubrication,
                &model.wear,
                black_box(&loads),
                15.0,
            )
            .unwrap()
        })
    });
    c.bench_function("contact_geometry_worn_7500h", |b| {
        b.iter(|| StaticAnalysis::new(red, black_box(&worn)).unwrap())
    });
    // The `te` command as a library call (what the Python package's `te` runs): 10 um uniform
    // wear, loaded TE at 412 N m.
    c.bench_function("api_te_10um_412nm", |b| {
        let wear = rvlife::api::Wear {
            wear_um: Some(10.0),
            hours: None,
        };
        b.iter(|| {
            rvlife::api::te(
                &model,
                black_box(wear),
                Some(412.0),
                rvlife::api::Spelling::Python,
                &|_, _| {},
            )
            .unwrap()
        })
    });
    c.bench_function("static_te_worn_7500h", |b| {
        b.iter(|| rvlife::te::static_te(red, black_box(&worn), model.te.samples).unwrap())
    });
    // The paper's section 4.2 run: 0.8 s, 10 um uniform wear, sinusoidal 412 N m (gap table
    // included).
    let worn10 = model
        .cycloid
        .profile(Some(WearMap::uniform(720, 10e-6).expect("map")))
        .expect("profile");
    let mut group = c.benchmark_group("dynamics");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(40));
    group.bench_function("simulate_0p8s_10um_sinusoidal", |b| {
        b.iter(|| {
            rvlife::dynamics::simulate(
                black_box(&worn10),
                &model.reducer,
                &model.dynamics.params,
                false,
            )
            .unwrap()
        })
    });
    group.bench_function("simulate_0p8s_7500h_sinusoidal", |b| {
        b.iter(|| {
            rvlife::dynamics::simulate(
                black_box(&worn),
                &model.reducer,
                &model.dynamics.params,
                false,
            )
            .unwrap()
        })
    });
    // Flexible discs: the FE disc, its modal reduction and the 0.8 s run.
    let flexible = {
        let mut c = Config::example();
        c.dynamics.disc = "flexible".into();
        c.validate()
            .expect("flexible example validates")
            .dynamics
            .params
    };
    group.measurement_time(Duration::from_secs(80));
    group.bench_function("simulate_flexible_0p8s_10um_sinusoidal", |b| {
        b.iter(|| {
            rvlife::dynamics::simulate_discs(
                black_box(&worn10),
                &model.reducer,
                &flexible,
                &model.fem.params,
                None,
                false,
            )
            .unwrap()
        })
    });
    group.finish();
    let mut group = c.benchmark_group("fem");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(30));
    group.bench_function("disc_mesh_assembly_reduction_10um", |b| {
        b.iter(|| rvlife::fem::DiscModel::build(black_box(&worn10), &model.fem.params).unwrap())
    });
    let disc =
        rvlife::fem::DiscSet::build(&worn10, &model.fem.params, &model.reducer).expect("disc");
    group.bench_function("flexible_stage_72_crank_angles_10um", |b| {
        b.iter(|| {
            rvlife::fem::flex::analyse_stage(
                black_box(&worn10),
                &model.reducer,
                &disc,
                model.rating.rated_torque,
            )
            .unwrap()
        })
    });
    group.finish();
    let mut group = c.benchmark_group("study");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(40));
    let mut no_dynamics = model.clone();
    no_dynamics.dynamics.enabled = false;
    no_dynamics.fem.enabled = false;
    group.bench_function("builtin_study_without_dynamics", |b| {
        b.iter(|| rvlife::study::run(black_box(&no_dynamics), &|_, _| {}).unwrap())
    });
    group.measurement_time(Duration::from_secs(60));
    group.bench_function("builtin_study_with_dte_and_fem", |b| {
        b.iter(|| rvlife::study::run(black_box(&model), &|_, _| {}).unwrap())
    });
    group.finish();
}

criterion_group!(study, benches);
criterion_main!(study);
