//! The paper's dynamic runs (Tao et al. 2024, sections 4.2-4.3) with rigid and flexible discs:
//! the built-in example's reducer, input ramped to 9000 deg/s over 0.1 s, TE over 0.1-0.8 s,
//! without load and under the sinusoidal 412 N m of period 0.3 s, on the disc worn uniformly by
//! 10 um and at every stage of the built-in study.
//!
//! `cargo run --release --example paper_dynamics -- OUT_DIR` writes `OUT_DIR/paper_dynamics.csv`
//! (one row per wear state, load and disc model: DTE mean, peak-to-peak, RMS, largest pin
//! force, the largest inertia torque on the output, steps, wall time), the TE time histories of
//! the 10 um runs (`OUT_DIR/10um_<load>_<disc>/te.{svg,png}`; the flexible run without load is the
//! paper's Fig. 17), and `OUT_DIR/te_hours.{svg,png}` (mean TE over hours, rigid against
//! flexible, without load and under load: the paper's Fig. 19b).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use rvlife::config::{Config, Model};
use rvlife::dynamics::params::LoadProfile;
use rvlife::dynamics::{simulate_with, DynamicsResult, FlexibleDiscs};
use rvlife::fem::modal::ModalDisc;
use rvlife::fem::DiscSet;
use rvlife::geometry::{Profile, WearMap};
use rvlife::wear::WearModelKind;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or("usage: paper_dynamics OUT_DIR")?,
    );
    std::fs::create_dir_all(&out)?;
    let mut c = Config::paper();
    c.dynamics.disc = "flexible".into();
    let m = c.validate()?;
    let sinusoidal = m.dynamics.params.load.clone();
    // The wear states: 10 um uniform, then the study's stages as the study analyses them.
    let mut states: Vec<(String, f64, Profile)> = vec![(
        "10um".into(),
        f64::NAN,
        m.cycloid.profile(Some(WearMap::uniform(720, 10e-6)?))?,
    )];
    let hist = rvlife::wear::integrate(&m.wear_inputs(), &|_, _| {})?;
    for (h, map) in hist.hours.iter().zip(&hist.maps) {
        let max = map.iter().copied().fold(0.0, f64::max);
        let wear = match m.wear.model {
            WearModelKind::Paper => WearMap::uniform(map.len(), max)?,
            _ => WearMap::new(map.clone())?,
        };
        states.push((
            format!("{h:.0}h"),
            *h,
            m.cycloid.profile((max > 0.0).then_some(wear))?,
        ));
    }
    let mut csv = String::from(
        "case,hours,max_wear_um,load,disc,modes,dte_mean_arcmin,dte_peak_to_peak_arcmin,\
         dte_rms_arcmin,max_pin_force_n,max_output_inertia_torque_nm,steps,wall_s\n",
    );
    let mut curves: Vec<(String, Vec<(f64, f64)>)> = [
        "rigid, no load",
        "flexible, no load",
        "rigid, sinusoidal 412 N m",
        "flexible, sinusoidal 412 N m",
    ]
    .iter()
    .map(|l| (l.to_string(), Vec::new()))
    .collect();
    for (name, hours, profile) in &states {
        let t0 = Instant::now();
        let discs = DiscSet::build(profile, &m.fem.params, &m.reducer)?;
        let modal = ModalDisc::build(
            &discs.models[0],
            &m.dynamics.params.flexible.expect("flexible"),
        )?;
        let fd = FlexibleDiscs::new(&modal, &discs)?;
        let build_s = t0.elapsed().as_secs_f64();
        for (k, (load_name, load)) in [
            ("none", LoadProfile::None),
            ("sinusoidal", sinusoidal.clone()),
        ]
        .into_iter()
        .enumerate()
        {
            let mut p = m.dynamics.params.clone();
            p.load = load;
            for (f, flexible) in [None, Some(fd)].into_iter().enumerate() {
                let t = Instant::now();
                let r = simulate_with(profile, &m.reducer, &p, flexible, false)?;
                let wall = t.elapsed().as_secs_f64() + if f == 1 { build_s } else { 0.0 };
                let s = &r.summary;
                let disc_name = if f == 0 { "rigid" } else { "flexible" };
                writeln!(
                    csv,
                    "{name},{},{:.2},{load_name},{disc_name},{},{:.5},{:.5},{:.5},{:.1},{:.2},{},{:.2}",
                    if hours.is_nan() { String::new() } else { format!("{hours:.0}") },
                    s.max_wear_um,
                    s.disc_modes,
                    s.te_mean_arcmin,
                    s.te_peak_to_peak_arcmin,
                    s.te_rms_arcmin,
                    s.max_pin_force_n,
                    output_inertia_torque(&r, &m),
                    s.steps,
                    wall
                )?;
                eprintln!(
                    "{name:>6} {load_name:>10} {disc_name:>8}: mean {:.4}, p-p {:.4}, RMS {:.4} arcmin, \
                     {:.0} N, {:.1} s",
                    s.te_mean_arcmin, s.te_peak_to_peak_arcmin, s.te_rms_arcmin, s.max_pin_force_n, wall
                );
                if hours.is_nan() {
                    let dir = out.join(format!("10um_{load_name}_{disc_name}"));
                    std::fs::create_dir_all(&dir)?;
                    rvlife::output::plot::dynamics(&r, &dir)?;
                } else {
                    curves[2 * k + f].1.push((*hours, s.te_mean_arcmin));
                }
            }
        }
    }
    std::fs::write(out.join("paper_dynamics.csv"), csv)?;
    rvlife::output::plot::curves_against_hours(
        &out,
        "te_hours",
        "Mean TE over 0.1-0.8 s: rigid against flexible discs",
        "TE mean (arcmin)",
        &curves,
    )?;
    eprintln!("results in {}", out.display());
    Ok(())
}

/// Largest inertia torque on the output over the window, N m: the carrier's inertia times its
/// angular acceleration (differences of the sampled output speed).
fn output_inertia_torque(r: &DynamicsResult, m: &Model) -> f64 {
    let (w0, w1) = m.dynamics.params.window;
    let j = m.dynamics.params.inertia.output;
    r.samples
        .windows(2)
        .filter(|w| w[0].time_s >= w0 && w[1].time_s <= w1)
        .map(|w| {
            let acc = (w[1].output_speed_deg_s - w[0].output_speed_deg_s).to_radians()
                / (w[1].time_s - w[0].time_s);
            (j * acc).abs()
        })
        .fold(0.0, f64::max)
}
