//! `rvlife._rvlife`: the native half of the Python package. A config is loaded once ([`load`]:
//! TOML text, the name it came from and the folder relative paths start in), validated exactly
//! as the command line validates a file; every function takes it, runs the command's library call
//! ([`rvlife::api`], [`rvlife::study`], [`rvlife::montecarlo`]) with the GIL released, and
//! returns the JSON object the command line prints as Python objects (lists of floats as numpy
//! `float64` arrays). Bad input raises `ValueError` with the command line's message (naming the
//! key); a file that cannot be read or written `OSError`; a solver failure `RuntimeError`.
//! The typed results, `Config` and the Dask sweep are the Python half (`python/rvlife`).

use std::path::PathBuf;

use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rvlife::api::{Spelling, Wear};
use rvlife::config::{Config, Model};
use serde_json::Value;

/// A Rust error as the Python exception of its kind.
fn py_err(e: rvlife::Error) -> PyErr {
    match e {
        rvlife::Error::Invalid { .. } | rvlife::Error::Config { .. } => {
            PyValueError::new_err(e.to_string())
        }
        rvlife::Error::Io { .. } => PyOSError::new_err(e.to_string()),
        rvlife::Error::Numerical { .. } => PyRuntimeError::new_err(e.to_string()),
    }
}

/// The JSON value `v` as Python objects: objects as dicts, arrays of numbers with a fraction
/// anywhere as numpy `float64` arrays, other arrays as lists.
fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match n.as_i64() {
            Some(i) if !n.is_f64() => i.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            if !a.is_empty() && a.iter().all(Value::is_number) && a.iter().any(Value::is_f64) {
                let x: Vec<f64> = a.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect();
                PyArray1::from_vec(py, x).into_any()
            } else {
                let items = a
                    .iter()
                    .map(|x| to_py(py, x))
                    .collect::<PyResult<Vec<_>>>()?;
                PyList::new(py, items)?.into_any()
            }
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// The parsed, not yet validated config.
fn config(text: &str, origin: &str, base_dir: Option<PathBuf>) -> PyResult<Config> {
    Config::from_toml_in(text, origin, base_dir.as_deref()).map_err(py_err)
}

/// A progress callback `(done, total)` calling the Python callable `cb` (with the GIL) from
/// any thread; an exception it raises is printed and ignored.
fn progress_fn(cb: Option<Py<PyAny>>) -> impl Fn(usize, usize) + Sync {
    move |done, total| {
        if let Some(cb) = &cb {
            Python::attach(|py| {
                if let Err(e) = cb.bind(py).call1((done, total)) {
                    e.print(py);
                }
            });
        }
    }
}

/// The text of a built-in config (`rvlife example --preset NAME`).
#[pyfunction]
#[pyo3(signature = (preset = "rv-40e"))]
fn example_toml(preset: &str) -> PyResult<String> {
    rvlife::config::preset_text(preset).map_err(|e| match e {
        rvlife::Error::Invalid { value, allowed, .. } => {
            PyValueError::new_err(format!("invalid preset = {value}: {allowed}"))
        }
        other => py_err(other),
    })
}

/// `(name, summary)` of every built-in config.
#[pyfunction]
fn presets() -> Vec<(&'static str, &'static str)> {
    rvlife::config::PRESETS
        .iter()
        .map(|p| (p.name, p.summary))
        .collect()
}

/// A validated config: the parsed TOML ([`Config`], for the commands that override keys) and
/// its model ([`Model`]), built once and shared by every call.
#[pyclass(frozen, module = "rvlife._rvlife")]
struct Loaded {
    text: String,
    config: Config,
    model: Model,
}

/// Parses and validates a config (raises `ValueError` naming the key).
#[pyfunction]
#[pyo3(signature = (text, origin, base_dir = None))]
fn load(py: Python<'_>, text: &str, origin: &str, base_dir: Option<PathBuf>) -> PyResult<Loaded> {
    py.detach(|| {
        let config = config(text, origin, base_dir)?;
        let model = rvlife::api::validated(&config).map_err(py_err)?;
        Ok(Loaded {
            text: text.to_string(),
            config,
            model,
        })
    })
}

/// TOML text of a JSON object (a config given as a Python dict).
#[pyfunction]
fn toml_from_json(json: &str) -> PyResult<String> {
    let v: Value = serde_json::from_str(json).map_err(|e| PyValueError::new_err(e.to_string()))?;
    if !v.is_object() {
        return Err(PyValueError::new_err(
            "invalid config: must be a dict of sections",
        ));
    }
    toml::to_string(&v).map_err(|e| PyValueError::new_err(format!("invalid config: {e}")))
}

/// Runs `f` (a command on the validated model, with the progress callback) without the GIL
/// and returns its JSON result as Python objects ([`to_py`]).
fn command<F, T>(py: Python<'_>, progress: Option<Py<PyAny>>, f: F) -> PyResult<Py<PyAny>>
where
    F: FnOnce(&(dyn Fn(usize, usize) + Sync)) -> rvlife::Result<T> + Send,
    T: serde::Serialize,
{
    let p = progress_fn(progress);
    let v = py.detach(|| {
        let r = f(&p).map_err(py_err)?;
        serde_json::to_value(&r).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })?;
    Ok(to_py(py, &v)?.unbind())
}

/// `rvlife profile`: the profile's points (`x_mm`, `y_mm`, `mesh_angle_deg`, `wear_um`).
#[pyfunction]
#[pyo3(signature = (cfg, wear_um, hours, nominal, points_per_tooth, progress = None))]
#[allow(clippy::too_many_arguments)]
fn profile(
    py: Python<'_>,
    cfg: &Loaded,
    wear_um: Option<f64>,
    hours: Option<f64>,
    nominal: bool,
    points_per_tooth: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::profile_points(
            &cfg.model,
            wear,
            nominal,
            points_per_tooth,
            Spelling::Python,
            p,
        )
    })
}

/// `rvlife contact --json`.
#[pyfunction]
#[pyo3(signature = (cfg, crank_deg, torque_nm, wear_um, hours, progress = None))]
fn contact(
    py: Python<'_>,
    cfg: &Loaded,
    crank_deg: f64,
    torque_nm: f64,
    wear_um: Option<f64>,
    hours: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::contact(&cfg.model, wear, crank_deg, torque_nm, Spelling::Python, p)
    })
}

/// `rvlife te --json`.
#[pyfunction]
#[pyo3(signature = (cfg, torque_nm, wear_um, hours, progress = None))]
fn te(
    py: Python<'_>,
    cfg: &Loaded,
    torque_nm: Option<f64>,
    wear_um: Option<f64>,
    hours: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::te(&cfg.model, wear, torque_nm, Spelling::Python, p)
    })
}

/// `rvlife hysteresis --json`.
#[pyfunction]
#[pyo3(signature = (cfg, crank_deg, levels, wear_um, hours, progress = None))]
fn hysteresis(
    py: Python<'_>,
    cfg: &Loaded,
    crank_deg: f64,
    levels: usize,
    wear_um: Option<f64>,
    hours: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::hysteresis_curve(&cfg.model, wear, crank_deg, levels, Spelling::Python, p)
    })
}

/// `rvlife dynamics --json` (without `wall_time_s`) with the time series as `samples`
/// (`time_s`, `te_arcmin`, ... arrays) and, when asked, `pin_forces_n` (samples x pins of
/// both discs); `out` also writes the results directory.
#[pyfunction]
#[pyo3(signature = (cfg, load, torque_nm, disc, wear_um, hours, pin_forces, out, force, progress = None))]
#[allow(clippy::too_many_arguments)]
fn dynamics(
    py: Python<'_>,
    cfg: &Loaded,
    load: Option<String>,
    torque_nm: Option<f64>,
    disc: Option<String>,
    wear_um: Option<f64>,
    hours: Option<f64>,
    pin_forces: bool,
    out: Option<PathBuf>,
    force: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let p = progress_fn(progress);
    let v = py.detach(|| -> PyResult<Value> {
        let opts = rvlife::api::DynamicsOptions {
            load,
            torque_nm,
            disc,
        };
        let m =
            rvlife::api::dynamics_model(&cfg.config, &opts, Spelling::Python).map_err(py_err)?;
        let staging = match &out {
            Some(dir) => Some(rvlife::output::Staging::prepare(dir, force).map_err(py_err)?),
            None => None,
        };
        let res = rvlife::api::dynamics(
            &m,
            Wear { wear_um, hours },
            pin_forces,
            Spelling::Python,
            &p,
        )
        .map_err(py_err)?;
        let mut v = serde_json::to_value(&res.summary)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        if let Some(staging) = staging {
            staging
                .commit(|dir| rvlife::output::write_dynamics_files(&res, dir))
                .map_err(py_err)?;
        }
        let samples = serde_json::to_value(&res.samples)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        // Columns of the time series.
        let mut cols = serde_json::Map::new();
        if let Some(Value::Object(first)) = samples.get(0) {
            for key in first.keys() {
                let col: Vec<Value> = samples
                    .as_array()
                    .into_iter()
                    .flatten()
                    .map(|s| s[key.as_str()].clone())
                    .collect();
                cols.insert(key.clone(), Value::Array(col));
            }
        }
        v["samples"] = Value::Object(cols);
        if let Some(f) = &res.pin_forces {
            v["pin_forces_n"] = serde_json::json!(f);
        }
        Ok(v)
    })?;
    Ok(to_py(py, &v)?.unbind())
}

/// The accuracy-life study (`rvlife run`): its `summary.json` object; `out` also writes the
/// results directory (atomically; `force` replaces an existing one).
#[pyfunction]
#[pyo3(signature = (cfg, out, force, progress = None))]
fn run_study(
    py: Python<'_>,
    cfg: &Loaded,
    out: Option<PathBuf>,
    force: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let p = progress_fn(progress);
    let v = py.detach(|| -> PyResult<Value> {
        let m = &cfg.model;
        let staging = match &out {
            Some(dir) => Some(rvlife::output::Staging::prepare(dir, force).map_err(py_err)?),
            None => None,
        };
        let study = rvlife::study::run(m, &p).map_err(py_err)?;
        if let Some(staging) = staging {
            staging
                .commit(|dir| rvlife::output::write_files(&study, dir))
                .map_err(py_err)?;
        }
        serde_json::to_value(study.summary()).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })?;
    Ok(to_py(py, &v)?.unbind())
}

/// The Monte Carlo run (`rvlife montecarlo`) or its shard `"I/N"`: runs the samples and, with
/// `out`, writes the command line's files (the whole run's, or the shard's for merging).
/// Returns `{"samples_csv", "stages_csv", "shard_json"}`: the records in the files' form and
/// the shard's meta-data (for [`merge`]).
#[pyfunction]
#[pyo3(signature = (cfg, samples, seed, shard, full_wear, samples_per_mesh_cycle, out, force, progress = None))]
#[allow(clippy::too_many_arguments)]
fn montecarlo(
    py: Python<'_>,
    cfg: &Loaded,
    samples: usize,
    seed: u64,
    shard: Option<String>,
    full_wear: bool,
    samples_per_mesh_cycle: usize,
    out: Option<PathBuf>,
    force: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let p = progress_fn(progress);
    let v = py.detach(|| -> PyResult<Value> {
        let m = &cfg.model;
        let plan = rvlife::api::montecarlo_plan(
            m,
            samples,
            seed,
            shard.as_deref(),
            full_wear,
            samples_per_mesh_cycle,
            Spelling::Python,
        )
        .map_err(py_err)?;
        let staging = match &out {
            Some(dir) => Some(rvlife::output::Staging::prepare(dir, force).map_err(py_err)?),
            None => None,
        };
        let records = rvlife::montecarlo::run(m, &plan, &p).map_err(py_err)?;
        let meta = rvlife::output::montecarlo::ShardMeta {
            rvlife_version: env!("CARGO_PKG_VERSION").into(),
            plan,
            stage_hours: m.wear.stage_hours.clone(),
            config_toml: cfg.text.clone(),
        };
        let whole = plan.shard == (1, 1);
        if let Some(staging) = staging {
            staging
                .commit(|dir| {
                    if whole {
                        rvlife::output::montecarlo::write_results(dir, &meta, &records)
                    } else {
                        rvlife::output::montecarlo::write_shard(dir, &meta, &records)
                    }
                })
                .map_err(py_err)?;
        }
        let (samples_csv, stages_csv) = rvlife::output::montecarlo::records_csv(&records);
        Ok(serde_json::json!({
            "samples_csv": samples_csv,
            "stages_csv": stages_csv,
            "shard_json": serde_json::to_string_pretty(&meta)
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))? + "\n",
        }))
    })?;
    Ok(to_py(py, &v)?.unbind())
}

/// Merges shard directories (`rvlife merge`) into the whole run's files in `out`.
#[pyfunction]
#[pyo3(signature = (dirs, out, force))]
fn merge(py: Python<'_>, dirs: Vec<PathBuf>, out: PathBuf, force: bool) -> PyResult<()> {
    py.detach(|| -> PyResult<()> {
        let (meta, records) = rvlife::output::montecarlo::merge(&dirs).map_err(py_err)?;
        let staging = rvlife::output::Staging::prepare(&out, force).map_err(py_err)?;
        staging
            .commit(|dir| rvlife::output::montecarlo::write_results(dir, &meta, &records))
            .map_err(py_err)?;
        Ok(())
    })
}

/// The rvlife version.
/// The table of stage quantities (`rvlife::quantities::STAGE`, the order of `summary.json` and
/// `stages.csv`): per quantity its name (with its unit), unit, label, description, the models
/// that produce it (`static`, `dynamics`, `flexible`) and its CSV columns.
/// One quantity for Python: name, unit, label, description, models, CSV columns.
type QuantityRow = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    Vec<&'static str>,
);

#[pyfunction]
fn quantities() -> Vec<QuantityRow> {
    rvlife::quantities::STAGE
        .iter()
        .map(|q| {
            let models = match q.models {
                rvlife::quantities::Models::Static => "static",
                rvlife::quantities::Models::Dynamics => "dynamics",
                rvlife::quantities::Models::Flexible => "flexible",
            };
            (q.name, q.unit, q.label, q.description, models, q.columns())
        })
        .collect()
}

#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _rvlife(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(example_toml, m)?)?;
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_class::<Loaded>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(toml_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(profile, m)?)?;
    m.add_function(wrap_pyfunction!(contact, m)?)?;
    m.add_function(wrap_pyfunction!(te, m)?)?;
    m.add_function(wrap_pyfunction!(hysteresis, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics, m)?)?;
    m.add_function(wrap_pyfunction!(run_study, m)?)?;
    m.add_function(wrap_pyfunction!(montecarlo, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(quantities, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
