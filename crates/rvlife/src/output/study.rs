//! A study's results directory (`rvlife run`) and a dynamic simulation's (`rvlife dynamics
//! --out`), written all-or-nothing ([`super::staging`]).
//!
//! Contents:
//! - `summary.json`: [`crate::study::Summary`] (a `stages` array and the paper comparison);
//! - `stages.csv`: one row per stage with the summary numbers (the `dte_*` columns empty when
//!   dynamics are off);
//! - `wear.csv`: `mesh_angle_deg` and `wear_um_<H>h` for every stage;
//! - `te_mesh_cycle.csv`: per stage and crank angle, forward and reverse STE, lost motion and
//!   loaded TE (arcmin) over one mesh cycle;
//! - `te_revolution.csv`: `input_deg` and `ste_arcmin_<H>h` for every stage over one output
//!   revolution;
//! - `load.csv`: per stage, the pin forces, pressures and half-widths at the crank angle of the
//!   largest force;
//! - `profiles/worn_<H>h.dxf` (and `.csv`): the profile used for TE at every stage;
//! - `plots/*.svg`, `plots/*.png`: see [`crate::output::plot`].

use std::path::Path;

use rayon::prelude::*;

use super::export::{write_profile_sampled, ProfileFormat, EXPORT_POINTS_PER_TOOTH};
use super::{f, hours_tag, write_json, write_rows};
use crate::error::{Error, Result};
use crate::study::Study;
use crate::te::{input_deg, over_revolution};
use crate::units::ARCMIN_PER_RAD;

/// Writes all result files of `study` into the existing, empty directory `dir`, ending with
/// `report.html` (`crate::output::html::write_report`).
///
/// # Errors
/// [`Error::Io`] on any write failure.
pub fn write_files(study: &Study, dir: &Path) -> Result<()> {
    let summary = study.summary();
    write_json(&dir.join("summary.json"), &summary)?;

    // stages.csv: every quantity of the table.
    let (header, rows) = crate::quantities::stages_csv(&summary.stages);
    write_rows(&dir.join("stages.csv"), &header, &rows)?;

    // wear.csv
    let tags: Vec<String> = study.stages.iter().map(|s| hours_tag(s.hours)).collect();
    let mut header = vec!["mesh_angle_deg".to_string()];
    header.extend(tags.iter().map(|t| format!("wear_um_{t}")));
    let angles = study.wear.angles();
    let rows: Vec<Vec<String>> = angles
        .iter()
        .enumerate()
        .map(|(m, a)| {
            let mut r = vec![f(a.to_degrees())];
            r.extend(study.wear.maps.iter().map(|map| f(map[m] * 1e6)));
            r
        })
        .collect();
    write_rows(&dir.join("wear.csv"), &header, &rows)?;

    // te_mesh_cycle.csv
    let header: Vec<String> = [
        "hours",
        "crank_deg",
        "input_deg",
        "ste_forward_arcmin",
        "ste_reverse_arcmin",
        "backlash_arcmin",
        "loaded_te_arcmin",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let ratio = study.model.reducer.ratio;
    let pins = study.model.cycloid.geometry.pins;
    let mut rows = Vec::new();
    for s in &study.stages {
        for k in 0..s.ste.crank_angle.len() {
            let phi = s.ste.crank_angle[k];
            rows.push(vec![
                f(s.hours),
                f(phi.to_degrees()),
                f(input_deg(phi, pins, ratio)),
                f(s.ste.forward[k] * ARCMIN_PER_RAD),
                f(s.ste.reverse[k] * ARCMIN_PER_RAD),
                f((s.ste.forward[k] + s.ste.reverse[k]) * ARCMIN_PER_RAD),
                f(s.loaded.te[k] * ARCMIN_PER_RAD),
            ]);
        }
    }
    write_rows(&dir.join("te_mesh_cycle.csv"), &header, &rows)?;

    // te_revolution.csv
    let curves: Vec<(Vec<f64>, Vec<f64>)> = study
        .stages
        .iter()
        .map(|s| match &s.revolution {
            // With part errors, the revolution solved; without, the mesh cycle repeated.
            Some(rev) => (
                rev.crank_angle
                    .iter()
                    .map(|phi| input_deg(*phi, pins, ratio))
                    .collect(),
                rev.forward.clone(),
            ),
            None => over_revolution(&s.ste.crank_angle, &s.ste.forward, pins, ratio),
        })
        .collect();
    let mut header = vec!["input_deg".to_string()];
    header.extend(tags.iter().map(|t| format!("ste_arcmin_{t}")));
    let rows: Vec<Vec<String>> = (0..curves[0].0.len())
        .map(|i| {
            let mut r = vec![format!("{:.4}", curves[0].0[i])];
            r.extend(
                curves
                    .iter()
                    .map(|c| format!("{:.5}", c.1[i] * ARCMIN_PER_RAD)),
            );
            r
        })
        .collect();
    write_rows(&dir.join("te_revolution.csv"), &header, &rows)?;

    // hysteresis.csv: the curve of every stage, averaged over a mesh cycle.
    let header: Vec<String> = ["hours", "torque_nm", "twist_arcmin"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut rows = Vec::new();
    for s in &study.stages {
        let c = s.hysteresis.curve();
        for (t, x) in c.torque.iter().zip(&c.twist) {
            rows.push(vec![f(s.hours), f(*t), f(x * ARCMIN_PER_RAD)]);
        }
    }
    write_rows(&dir.join("hysteresis.csv"), &header, &rows)?;

    // load.csv
    let header: Vec<String> = [
        "hours",
        "crank_deg",
        "disc",
        "pin",
        "mesh_angle_deg",
        "gap_um",
        "force_n",
        "lever_arm_mm",
        "half_width_um",
        "max_pressure_mpa",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut rows = Vec::new();
    for s in &study.stages {
        let w = s.loaded.worst();
        for (d, p) in w
            .discs
            .iter()
            .enumerate()
            .flat_map(|(d, disc)| disc.pins.iter().map(move |p| (d, p)))
        {
            rows.push(vec![
                f(s.hours),
                f(w.crank_angle.to_degrees()),
                (d + 1).to_string(),
                p.pin.to_string(),
                f(p.mesh_angle.to_degrees()),
                f(p.gap * 1e6),
                f(p.force),
                f(p.lever_arm * 1e3),
                f(p.half_width * 1e6),
                f(p.max_pressure * 1e-6),
            ]);
        }
    }
    write_rows(&dir.join("load.csv"), &header, &rows)?;

    // te_flexible.csv (flexible disc on)
    if study.stages.iter().any(|s| s.flexible.is_some()) {
        let header: Vec<String> = [
            "hours",
            "crank_deg",
            "rigid_ste_arcmin",
            "rigid_loaded_te_arcmin",
            "flexible_ste_arcmin",
            "flexible_loaded_te_arcmin",
            "max_force_n",
            "rigid_ste_reverse_arcmin",
            "flexible_ste_reverse_arcmin",
            "flexible_loaded_te_reverse_arcmin",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let mut rows = Vec::new();
        for s in &study.stages {
            if let Some((fl, _)) = &s.flexible {
                for k in 0..fl.crank_angle.len() {
                    rows.push(vec![
                        f(s.hours),
                        f(fl.crank_angle[k].to_degrees()),
                        f(fl.rigid_ste[k] * ARCMIN_PER_RAD),
                        f(fl.rigid_loaded_te[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_ste[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_loaded_te[k] * ARCMIN_PER_RAD),
                        f(fl.max_force[k]),
                        f(fl.rigid_ste_reverse[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_ste_reverse[k] * ARCMIN_PER_RAD),
                        f(fl.flexible_loaded_te_reverse[k] * ARCMIN_PER_RAD),
                    ]);
                }
            }
        }
        write_rows(&dir.join("te_flexible.csv"), &header, &rows)?;
        // hysteresis_flexible.csv: the flexible hysteresis curve of every stage.
        let header: Vec<String> = ["hours", "torque_nm", "twist_arcmin"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let mut rows = Vec::new();
        for s in &study.stages {
            if let Some((fl, _)) = &s.flexible {
                for (t, w) in fl.hysteresis_torque.iter().zip(&fl.hysteresis_twist) {
                    rows.push(vec![f(s.hours), f(*t), f(w * ARCMIN_PER_RAD)]);
                }
            }
        }
        write_rows(&dir.join("hysteresis_flexible.csv"), &header, &rows)?;
    }

    // Profiles and plots are independent: write them side by side.
    let pdir = dir.join("profiles");
    std::fs::create_dir(&pdir).map_err(|e| Error::io(&pdir, e))?;
    let plots = dir.join("plots");
    std::fs::create_dir(&plots).map_err(|e| Error::io(&plots, e))?;
    let (profiles, figures) = rayon::join(
        || -> Result<()> {
            study
                .stages
                .par_iter()
                .zip(tags.par_iter())
                .try_for_each(|(s, tag)| {
                    for (ext, format) in [("dxf", ProfileFormat::Dxf), ("csv", ProfileFormat::Csv)]
                    {
                        write_profile_sampled(
                            &s.profile,
                            &pdir.join(format!("worn_{tag}.{ext}")),
                            format,
                            EXPORT_POINTS_PER_TOOTH,
                        )?;
                    }
                    Ok(())
                })
        },
        || crate::output::plot::write_all(study, &plots),
    );
    profiles?;
    figures?;
    crate::output::html::write_report(study, &summary, dir)
}

/// Writes a dynamic simulation's results into the existing directory `dir` (written
/// all-or-nothing through [`super::Staging`]): `summary.json`
/// ([`crate::dynamics::DynamicsSummary`]), `dynamics.csv` (the time series), `pin_forces.csv`
/// (if computed: `time_s`, `disc<d>_pin<j>_n`), and `plots/speeds` and `plots/te` (SVG and PNG).
///
/// # Errors
/// [`Error::Io`] on write failures.
pub fn write_dynamics_files(res: &crate::dynamics::DynamicsResult, dir: &Path) -> Result<()> {
    {
        write_json(&dir.join("summary.json"), &res.summary)?;
        let p = dir.join("dynamics.csv");
        let header: Vec<String> = [
            "time_s",
            "input_angle_deg",
            "output_angle_deg",
            "input_speed_deg_s",
            "output_speed_deg_s",
            "te_arcmin",
            "load_nm",
            "pins_in_contact_disc1",
            "pins_in_contact_disc2",
            "max_pin_force_n",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let rows: Vec<Vec<String>> = res
            .samples
            .iter()
            .map(|s| {
                vec![
                    format!("{:.7}", s.time_s),
                    format!("{:.9}", s.input_angle_deg),
                    format!("{:.9}", s.output_angle_deg),
                    f(s.input_speed_deg_s),
                    f(s.output_speed_deg_s),
                    f(s.te_arcmin),
                    f(s.load_nm),
                    s.pins_in_contact[0].to_string(),
                    s.pins_in_contact[1].to_string(),
                    f(s.max_pin_force_n),
                ]
            })
            .collect();
        write_rows(&p, &header, &rows)?;
        if let Some(forces) = &res.pin_forces {
            let zp = forces.first().map_or(0, |r| r.len() / 2);
            let p = dir.join("pin_forces.csv");
            let mut header = vec!["time_s".to_string()];
            for d in 1..=2 {
                header.extend((0..zp).map(|j| format!("disc{d}_pin{j}_n")));
            }
            let rows: Vec<Vec<String>> = res
                .samples
                .iter()
                .zip(forces)
                .map(|(s, r)| {
                    std::iter::once(format!("{:.7}", s.time_s))
                        .chain(r.iter().map(|v| format!("{v:.3}")))
                        .collect()
                })
                .collect();
            write_rows(&p, &header, &rows)?;
        }
        let plots = dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(|e| Error::io(&plots, e))?;
        crate::output::plot::dynamics(res, &plots)
    }
}
