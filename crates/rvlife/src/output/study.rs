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

#[cfg(feature = "files")]
use std::path::Path;

use rayon::prelude::*;

use super::export::{profile_bytes, ProfileFormat, EXPORT_POINTS_PER_TOOTH};
use super::{f, hours_tag, json_bytes, numbers_bytes, rows_bytes};
#[cfg(feature = "files")]
use super::{write_json, write_rows};
#[cfg(feature = "files")]
use crate::error::Error;
use crate::error::Result;
use crate::study::Study;
use crate::te::{input_deg, over_revolution};
use crate::units::ARCMIN_PER_RAD;

/// Writes all result files of `study` into the existing, empty directory `dir`: its
/// [`data_files`], the plots, and last `report.html` (`crate::output::html::write_report`).
///
/// # Errors
/// [`Error::Io`] on any write failure.
#[cfg(feature = "files")]
pub fn write_files(study: &Study, dir: &Path) -> Result<()> {
    let summary = study.summary();
    for sub in ["profiles", "plots"] {
        let d = dir.join(sub);
        std::fs::create_dir(&d).map_err(|e| Error::io(&d, e))?;
    }
    // Data files, plots and the report are independent: made side by side.
    let (written, figures) = rayon::join(
        || {
            data_files(study)?.par_iter().try_for_each(|(name, bytes)| {
                let p = dir.join(name);
                std::fs::write(&p, bytes).map_err(|e| Error::io(&p, e))
            })
        },
        || {
            crate::output::plot::write_all(study, &dir.join("plots"))?;
            crate::output::html::write_report(study, &summary, dir)
        },
    );
    written?;
    figures
}

/// The data files of a study's results directory, in memory: `(path relative to the
/// directory, bytes)` for `summary.json`, the CSV tables ([`tables`]) and
/// `profiles/worn_<H>h.dxf` and `.csv` of every stage ([`profile_files`]), byte for byte what
/// [`write_files`] writes; the plots and the report are not among them.
///
/// # Errors
/// [`crate::Error::Numerical`] if a table or a profile cannot be serialised.
pub fn data_files(study: &Study) -> Result<Vec<(String, Vec<u8>)>> {
    let (files, profiles) = rayon::join(
        || tables(study),
        || {
            profile_entries(study)
                .collect::<Vec<_>>()
                .into_par_iter()
                .map(|(name, profile, format)| {
                    Ok((
                        name,
                        profile_bytes(profile, format, EXPORT_POINTS_PER_TOOTH)?,
                    ))
                })
                .collect::<Result<Vec<_>>>()
        },
    );
    let mut files = files?;
    files.extend(profiles?);
    Ok(files)
}

/// Every stage profile file of the results directory: its name (`profiles/worn_<H>h.dxf` and
/// `.csv`, in the stages' order), the profile and the format.
fn profile_entries(
    study: &Study,
) -> impl Iterator<Item = (String, &crate::geometry::Profile, ProfileFormat)> {
    study.stages.iter().flat_map(|s| {
        let tag = hours_tag(s.hours);
        [("dxf", ProfileFormat::Dxf), ("csv", ProfileFormat::Csv)]
            .map(|(ext, format)| (format!("profiles/worn_{tag}.{ext}"), &s.profile, format))
    })
}

/// The stage profiles' file names of the results directory, `profiles/worn_<H>h.dxf` and
/// `.csv` for every stage, in the stages' order: what [`profile_file`] makes.
pub fn profile_files(study: &Study) -> Vec<String> {
    profile_entries(study).map(|(name, _, _)| name).collect()
}

/// The bytes of the stage profile file `name` (one of [`profile_files`]; `None` for another
/// name): the profile used for TE at that stage, with the export's points per tooth.
///
/// # Errors
/// [`crate::Error::Numerical`] if the file cannot be serialised.
pub fn profile_file(study: &Study, name: &str) -> Result<Option<Vec<u8>>> {
    profile_entries(study)
        .find(|(n, _, _)| n == name)
        .map(|(_, profile, format)| profile_bytes(profile, format, EXPORT_POINTS_PER_TOOTH))
        .transpose()
}

/// The study's `summary.json` and CSV tables (the module's list), in memory: `(file name,
/// bytes)`, byte for byte what [`write_files`] writes.
///
/// # Errors
/// [`crate::Error::Numerical`] if a table cannot be serialised.
pub fn tables(study: &Study) -> Result<Vec<(String, Vec<u8>)>> {
    let summary = study.summary();
    // The files' contents in the order of `table_names`, which names them.
    let mut files = vec![json_bytes(&summary)?];

    // stages.csv: every quantity of the table.
    let (header, rows) = crate::quantities::stages_csv(&summary.stages);
    files.push(rows_bytes(&header, &rows)?);

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
    files.push(rows_bytes(&header, &rows)?);

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
    files.push(rows_bytes(&header, &rows)?);

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
    files.push(numbers_bytes(
        &header,
        curves[0].0.len(),
        1 + curves.len(),
        |i, j| match j {
            0 => (curves[0].0[i], 4),
            _ => (curves[j - 1].1[i] * ARCMIN_PER_RAD, 5),
        },
    ));

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
    files.push(rows_bytes(&header, &rows)?);

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
    files.push(rows_bytes(&header, &rows)?);

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
        files.push(rows_bytes(&header, &rows)?);
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
        files.push(rows_bytes(&header, &rows)?);
    }

    let names = table_names(study);
    assert_eq!(names.len(), files.len(), "a table without its name");
    Ok(names.into_iter().zip(files).collect())
}

/// The names of [`tables`]' files for `study`, in its order, without making them (the page
/// lists the results before any is asked for): the one list of the tables' names.
pub fn table_names(study: &Study) -> Vec<String> {
    let mut names: Vec<String> = [
        "summary.json",
        "stages.csv",
        "wear.csv",
        "te_mesh_cycle.csv",
        "te_revolution.csv",
        "hysteresis.csv",
        "load.csv",
    ]
    .map(String::from)
    .to_vec();
    if study.stages.iter().any(|s| s.flexible.is_some()) {
        names.extend(["te_flexible.csv", "hysteresis_flexible.csv"].map(String::from));
    }
    names
}

/// Writes a dynamic simulation's results into the existing directory `dir` (written
/// all-or-nothing through [`super::Staging`]): `summary.json`
/// ([`crate::dynamics::DynamicsSummary`]), `dynamics.csv` (the time series), `pin_forces.csv`
/// (if computed: `time_s`, `disc<d>_pin<j>_n`), and `plots/speeds` and `plots/te` (SVG and PNG).
///
/// # Errors
/// [`Error::Io`] on write failures.
#[cfg(feature = "files")]
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
                    super::fixed(s.time_s, 7),
                    super::fixed(s.input_angle_deg, 9),
                    super::fixed(s.output_angle_deg, 9),
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
                    std::iter::once(super::fixed(s.time_s, 7))
                        .chain(r.iter().map(|v| super::fixed(*v, 3)))
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
