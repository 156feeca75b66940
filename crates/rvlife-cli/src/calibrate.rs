//! `rvlife calibrate`: the Archard coefficient for a target wear, its fit to measurements
//! against hours, or the structure compliance from a measured hysteresis curve or a catalogue
//! stiffness; every calibration writes `calibrated.toml` (docs/model.md section 13).

use std::path::{Path, PathBuf};

use rvlife::config::Model;
use rvlife::Result;

use crate::{busy, load_config_text, validated};

/// `rvlife calibrate` with its options (the command line's, checked by clap).
#[allow(clippy::too_many_arguments)]
pub(crate) fn run(
    config: Option<&Path>,
    budget: f64,
    target_wear_um: f64,
    measured: Option<&Path>,
    catalogue_stiffness_nm_per_arcmin: Option<f64>,
    fit_running_in: bool,
    out: Option<&Path>,
    force: bool,
) -> Result<()> {
    let calibrated = calibrated_path(out, force)?;
    let structure = match (&measured, catalogue_stiffness_nm_per_arcmin) {
        (_, Some(s)) => Some(StructureTarget::Catalogue(s)),
        (Some(path), None) => {
            let text = rvlife::input::read_text(path).map_err(|e| {
                rvlife::Error::invalid("--measured", path.display(), format!("cannot be read: {e}"))
            })?;
            rvlife::calibration::structure::MeasuredCurve::is_curve(&text)
                .then(|| {
                    rvlife::calibration::structure::MeasuredCurve::parse(path, &text)
                        .map(StructureTarget::Curve)
                })
                .transpose()?
        }
        (None, None) => None,
    };
    match (structure, measured) {
        (Some(target), _) => {
            if fit_running_in {
                return Err(rvlife::Error::invalid(
                    "--fit-running-in",
                    "given",
                    "applies to measurements against hours, not to a hysteresis curve \
                             or a catalogue stiffness",
                ));
            }
            calibrate_structure(config, budget, target, out, force, &calibrated)?;
        }
        (None, Some(path)) => {
            calibrate_measured(
                config,
                budget,
                path,
                fit_running_in,
                out,
                force,
                &calibrated,
            )?;
        }
        (None, None) => {
            if fit_running_in {
                return Err(rvlife::Error::invalid(
                    "--fit-running-in",
                    "given",
                    "needs --measured (a fit to measurements against hours)",
                ));
            }
            let (cfg, text) = load_config_text(config, budget)?;
            let model = validated(&cfg)?;
            let staging = out
                .map(|dir| rvlife::output::Staging::prepare(dir, force))
                .transpose()?;
            let pb = busy("calibrating");
            let fitted = rvlife::wear::calibrate(&model.wear_inputs(), target_wear_um * 1e-6);
            pb.finish_and_clear();
            let (k, achieved) = fitted?;
            let last = model.wear.stage_hours.last().copied().unwrap_or(0.0);
            let (value, _) = archard_in_key_unit(&model, k);
            say!(
                "archard_coefficient_mm3_per_n_m = {:.6e}   # max wear {:.4} um at {} h",
                k * 1e9,
                achieved * 1e6,
                last
            );
            let what = format!(
                "rvlife calibrate --target-wear-um {target_wear_um}: max wear {:.4} um \
                         at {last} h",
                achieved * 1e6
            );
            let edits = [(model.wear.archard_key.to_string(), value)];
            let origin = config_origin(config);
            match staging {
                Some(staging) => {
                    staging.commit(|dir| {
                        write_calibrated(
                            &text,
                            &origin,
                            &edits,
                            &what,
                            &dir.join("calibrated.toml"),
                        )
                    })?;
                }
                None => write_calibrated(&text, &origin, &edits, &what, &calibrated)?,
            }
        }
    }
    say!("calibrated config: {}", calibrated.display());
    Ok(())
}

/// What a structure calibration fits to.
enum StructureTarget {
    /// A measured hysteresis curve.
    Curve(rvlife::calibration::structure::MeasuredCurve),
    /// A catalogue `b/a`, N m/arcmin.
    Catalogue(f64),
}

/// Where `calibrated.toml` goes: inside `out`, else the current directory, where it must not
/// exist (refused before any work: a calibration never overwrites a file it did not make).
fn calibrated_path(out: Option<&Path>, force: bool) -> Result<PathBuf> {
    match out {
        Some(dir) => {
            rvlife::output::check_output_dir(dir, force)?;
            Ok(dir.join("calibrated.toml"))
        }
        None => {
            let p = PathBuf::from("calibrated.toml");
            if p.exists() {
                return Err(rvlife::Error::invalid(
                    "calibrated.toml",
                    "exists in the current directory",
                    "give --out DIR for the calibration's files, or move it: a calibration \
                     does not overwrite it",
                ));
            }
            Ok(p)
        }
    }
}

/// The name of the config for messages and headers.
fn config_origin(config: Option<&Path>) -> String {
    config.map_or("the built-in example".into(), |p| p.display().to_string())
}

/// A fitted Archard coefficient `k` (m^2/N) in the unit of the config's key.
fn archard_in_key_unit(model: &Model, k: f64) -> (serde_json::Value, &'static str) {
    if model.wear.archard_key.ends_with("m2_per_n") {
        (serde_json::json!(k), "m^2/N")
    } else {
        (serde_json::json!(k * 1e9), "mm^3/(N m)")
    }
}

/// Writes `calibrated.toml` at `path` (a new file, written atomically): the config `text` with
/// each fitted key of `edits` set (comments and layout kept), under a header naming the
/// calibration `what`.
fn write_calibrated(
    text: &str,
    origin: &str,
    edits: &[(String, serde_json::Value)],
    what: &str,
    path: &Path,
) -> Result<()> {
    let edits: Vec<(String, Option<serde_json::Value>)> = edits
        .iter()
        .map(|(k, v)| (k.clone(), Some(v.clone())))
        .collect();
    let body = rvlife::config::edit::set(text, origin, &edits)?;
    let keys: Vec<String> = edits
        .iter()
        .map(|(k, v)| format!("{k} = {}", v.as_ref().map_or("".into(), |v| v.to_string())))
        .collect();
    let out = format!(
        "# calibrated from {origin} by {what}\n# fitted: {}\n{body}",
        keys.join(", ")
    );
    rvlife::output::write_file_atomically(path, false, |tmp| {
        std::fs::write(tmp, &out).map_err(|e| rvlife::Error::Io {
            path: path.to_path_buf(),
            source: e,
        })
    })?;
    Ok(())
}

/// `rvlife calibrate` of the structure compliance on a measured hysteresis curve or a
/// catalogue `b/a`: the fit, `calibration.json` in `out`, and `calibrated.toml`.
fn calibrate_structure(
    config: Option<&Path>,
    budget: f64,
    target: StructureTarget,
    out: Option<&Path>,
    force: bool,
    calibrated: &Path,
) -> Result<()> {
    use rvlife::calibration::structure::{fit_catalogue, fit_curve};
    let (cfg, text) = load_config_text(config, budget)?;
    let model = validated(&cfg)?;
    let staging = out
        .map(|dir| rvlife::output::Staging::prepare(dir, force))
        .transpose()?;
    let pb = busy("calibrating the structure compliance");
    let fit = match &target {
        StructureTarget::Curve(c) => fit_curve(&model, c),
        StructureTarget::Catalogue(s) => fit_catalogue(&model, *s),
    };
    pb.finish_and_clear();
    let fit = fit?;
    let c = &fit.compliance_arcmin_per_knm;
    match fit.rms_residual_arcmin {
        Some(rms) => say!(
            "compliance_arcmin_per_knm = {:.4}   # 95 % CI [{:.4}, {:.4}] (Student-t, {} degrees \
             of freedom, {} rows at or beyond the measuring torque); RMS residual {rms:.5} \
             arcmin; bench zero {:.5} arcmin, the loading sides {:.5} arcmin further apart \
             than modelled (play, not fitted here)",
            c.value,
            c.lower,
            c.upper,
            fit.degrees_of_freedom,
            fit.points,
            fit.offset_arcmin.unwrap_or(0.0),
            fit.extra_play_arcmin.unwrap_or(0.0)
        ),
        None => say!(
            "compliance_arcmin_per_knm = {:.4}   # from one catalogue value: no interval",
            c.value
        ),
    }
    say!(
        "torsional stiffness b/a: {:.1} N m/arcmin as modelled, {:.1} with the fitted compliance",
        fit.model_stiffness_nm_per_arcmin,
        fit.fitted_stiffness_nm_per_arcmin
    );
    let what = match &target {
        StructureTarget::Curve(curve) => format!(
            "rvlife calibrate --measured {} (a hysteresis curve; 95 % CI [{:.4}, {:.4}] \
             arcmin/(kN m))",
            curve.path.display(),
            c.lower,
            c.upper
        ),
        StructureTarget::Catalogue(s) => {
            format!("rvlife calibrate --catalogue-stiffness-nm-per-arcmin {s}")
        }
    };
    let edits = [(
        "reducer.structure.compliance_arcmin_per_knm".to_string(),
        serde_json::json!((c.value * 1e4).round() / 1e4),
    )];
    let origin = config_origin(config);
    match staging {
        Some(staging) => {
            staging.commit(|dir| {
                let json = serde_json::to_string_pretty(&fit).map_err(|e| {
                    rvlife::Error::invalid("calibration.json", e.to_string(), "must serialise")
                })?;
                std::fs::write(dir.join("calibration.json"), json + "\n").map_err(|e| {
                    rvlife::Error::Io {
                        path: dir.join("calibration.json"),
                        source: e,
                    }
                })?;
                write_calibrated(&text, &origin, &edits, &what, &dir.join("calibrated.toml"))
            })?;
            Ok(())
        }
        None => write_calibrated(&text, &origin, &edits, &what, calibrated),
    }
}

/// `rvlife calibrate --measured`: every input is checked (the file, the config, the work
/// budget, the results directory) before the reference studies run.
fn calibrate_measured(
    config: Option<&Path>,
    budget: f64,
    path: &Path,
    fit_running_in: bool,
    out: Option<&Path>,
    force: bool,
    calibrated: &Path,
) -> Result<()> {
    use rvlife::calibration::{Measurements, Options};
    let data = Measurements::read(path)?;
    data.check_for_fit(fit_running_in, false)?;
    let (cfg, text) = load_config_text(config, budget)?;
    let model = rvlife::api::validated(&cfg)?;
    let start = std::time::Instant::now();
    let pb = busy("calibrating");
    let cal = rvlife::api::calibrate_measured(
        &model,
        &data,
        Options { fit_running_in },
        out,
        force,
        &|pass| pb.set_message(format!("calibrating: reference study {pass}")),
    );
    pb.finish_and_clear();
    let cal = cal?;
    let wall = start.elapsed().as_secs_f64();
    let pct = cal.confidence * 100.0;
    let (k, unit) = if model.wear.archard_key.ends_with("m2_per_n") {
        (&cal.archard_coefficient_m2_per_n, "m^2/N")
    } else {
        (&cal.archard_coefficient_mm3_per_n_m, "mm^3/(N m)")
    };
    say!(
        "{} = {:.6e}   # {unit}; {pct:.0} % CI [{:.6e}, {:.6e}]; {:.4} x the config's",
        model.wear.archard_key.trim_start_matches("wear."),
        k.value,
        k.lower,
        k.upper,
        cal.archard_coefficient_m2_per_n.value / cal.config_archard_coefficient_m2_per_n
    );
    say!(
        "k = {:.6e} m^2/N, {pct:.0} % CI [{:.6e}, {:.6e}] (Gauss-Newton covariance, Student-t \
         with {} degrees of freedom, {} values, residual variance from the data)",
        cal.archard_coefficient_m2_per_n.value,
        cal.archard_coefficient_m2_per_n.lower,
        cal.archard_coefficient_m2_per_n.upper,
        cal.degrees_of_freedom,
        cal.points
    );
    if let Some(b) = &cal.running_in_backlash_arcmin {
        say!(
            "running-in play b0 = {:.5} arcmin, {pct:.0} % CI [{:.5}, {:.5}]",
            b.value,
            b.lower,
            b.upper
        );
    }
    if let (Some(r), Some(tau)) = (&cal.running_in_factor, cal.running_in_hours) {
        say!(
            "running_in_factor = {:.5}   # {pct:.0} % CI [{:.5}, {:.5}]; running_in_hours = {tau} \
             (the config's, not fitted)",
            r.value,
            r.lower,
            r.upper
        );
    }
    for q in &cal.quantities {
        say!(
            "{}: RMS residual {:.5} {} over {} values",
            q.column,
            q.rms_residual,
            q.unit,
            q.points
        );
    }
    say!(
        "{} reference studies ({} stages), {:.2} s{}",
        cal.reference_runs,
        cal.reference_stages,
        wall,
        out.map_or(String::new(), |d| format!("; results in {}", d.display()))
    );
    let (value, _) = archard_in_key_unit(&model, cal.archard_coefficient_m2_per_n.value);
    let mut edits = vec![(model.wear.archard_key.to_string(), value)];
    if let Some(r) = &cal.running_in_factor {
        edits.push(("wear.running_in_factor".into(), serde_json::json!(r.value)));
    }
    let b0 = cal
        .running_in_backlash_arcmin
        .as_ref()
        .map_or(String::new(), |b| {
            format!(
                "; the running-in play b0 = {:.5} arcmin has no key: it is not in the config",
                b.value
            )
        });
    write_calibrated(
        &text,
        &config_origin(config),
        &edits,
        &format!(
            "rvlife calibrate --measured {} ({pct:.0} % CI of k [{:.6e}, {:.6e}] m^2/N){b0}",
            path.display(),
            cal.archard_coefficient_m2_per_n.lower,
            cal.archard_coefficient_m2_per_n.upper
        ),
        calibrated,
    )
}
