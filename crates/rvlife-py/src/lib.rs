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
use pyo3_stub_gen::derive::{gen_stub_pyclass, gen_stub_pyfunction, gen_stub_pymethods};
use rvlife::api::{Spelling, Wear};
use rvlife::config::{Config, Model};
use serde_json::Value;

/// A Rust error as the Python exception of its kind, its message in Python's spelling
/// ([`pythonic`]).
fn py_err(e: rvlife::Error) -> PyErr {
    let text = pythonic(&e.to_string());
    match e {
        rvlife::Error::Invalid { .. } | rvlife::Error::Config { .. } => PyValueError::new_err(text),
        rvlife::Error::Io { .. } => PyOSError::new_err(text),
        rvlife::Error::Numerical { .. } => PyRuntimeError::new_err(text),
    }
}

/// The command line's switches, which Python passes as `name=True`.
const SWITCHES: &[&str] = &[
    "force",
    "keep-going",
    "full-wear",
    "fit-running-in",
    "nominal",
    "pin-forces",
];

/// A message of the library as a Python user reads it: every command-line option
/// (`--work-budget-min`) as its keyword argument (`work_budget_min`), a switch as
/// `force=True`.
fn pythonic(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find("--") {
        let before = &rest[..i];
        let after = &rest[i + 2..];
        let n = after
            .find(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'))
            .unwrap_or(after.len());
        let name = &after[..n];
        let starts_word = before.chars().last().is_none_or(|c| !c.is_alphanumeric());
        out.push_str(before);
        if starts_word && name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
            out.push_str(&name.replace('-', "_"));
            if SWITCHES.contains(&name) {
                out.push_str("=True");
            }
        } else {
            out.push_str("--");
            out.push_str(name);
        }
        rest = &after[n..];
    }
    out.push_str(rest);
    out
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
///
/// Calls are monotone: parallel work reports its counts out of order (30 after 31), and a
/// count not above the last one reported is dropped. The check and the call hold one lock
/// (taken before the GIL, so no thread waits for it while holding the GIL), so a smaller count
/// cannot overtake a larger one between them.
fn progress_fn(cb: Option<Py<PyAny>>) -> impl Fn(usize, usize) + Sync {
    let last = std::sync::Mutex::new(0usize);
    move |done, total| {
        if let Some(cb) = &cb {
            let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
            if done <= *last && done != 0 {
                return;
            }
            *last = done;
            Python::attach(|py| {
                if let Err(e) = cb.bind(py).call1((done, total)) {
                    e.print(py);
                }
            });
        }
    }
}

/// The text of a built-in config (`rvlife example --preset NAME`).
#[gen_stub_pyfunction]
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
#[gen_stub_pyfunction]
#[pyfunction]
fn presets() -> Vec<(&'static str, &'static str)> {
    rvlife::config::PRESETS
        .iter()
        .map(|p| (p.name, p.summary))
        .collect()
}

/// A validated config: the parsed TOML ([`Config`], for the commands that override keys) and
/// its model ([`Model`]), built once and shared by every call.
#[gen_stub_pyclass]
#[pyclass(frozen, module = "rvlife._rvlife")]
struct Loaded {
    text: String,
    config: Config,
    model: Model,
}

/// Parses and validates a config (raises `ValueError` naming the key).
#[gen_stub_pyfunction]
#[pyfunction]
#[pyo3(signature = (text, origin, base_dir = None, work_budget_min = rvlife::budget::DEFAULT_MINUTES))]
fn load(
    py: Python<'_>,
    text: &str,
    origin: &str,
    base_dir: Option<PathBuf>,
    work_budget_min: f64,
) -> PyResult<Loaded> {
    py.detach(|| {
        let mut config = config(text, origin, base_dir)?;
        config.work_budget_minutes = work_budget_min;
        let model = rvlife::api::validated(&config).map_err(py_err)?;
        Ok(Loaded {
            text: text.to_string(),
            config,
            model,
        })
    })
}

/// TOML text of a JSON object (a config given as a Python dict).
#[gen_stub_pyfunction]
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

/// The results directory `out` prepared before the work (`None`: none written).
fn staging(
    out: Option<&std::path::Path>,
    force: bool,
) -> PyResult<Option<rvlife::output::Staging>> {
    out.map(|dir| rvlife::output::Staging::prepare(dir, force).map_err(py_err))
        .transpose()
}

/// `rvlife profile`: the profile's points (`x_mm`, `y_mm`, `mesh_angle_deg`, `wear_um`).
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, wear_um, hours, nominal, points_per_tooth, progress = None))]
#[allow(clippy::too_many_arguments)]
fn profile(
    py: Python<'_>,
    cfg: &Loaded,
    wear_um: Option<f64>,
    hours: Option<f64>,
    nominal: bool,
    points_per_tooth: usize,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
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
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, crank_deg, torque_nm, wear_um, hours, progress = None))]
fn contact(
    py: Python<'_>,
    cfg: &Loaded,
    crank_deg: f64,
    torque_nm: f64,
    wear_um: Option<f64>,
    hours: Option<f64>,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::contact(&cfg.model, wear, crank_deg, torque_nm, Spelling::Python, p)
    })
}

/// `rvlife te --json`.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, torque_nm, wear_um, hours, progress = None))]
fn te(
    py: Python<'_>,
    cfg: &Loaded,
    torque_nm: Option<f64>,
    wear_um: Option<f64>,
    hours: Option<f64>,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::te(&cfg.model, wear, torque_nm, Spelling::Python, p)
    })
}

/// `rvlife hysteresis --json`.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, crank_deg, levels, wear_um, hours, progress = None))]
fn hysteresis(
    py: Python<'_>,
    cfg: &Loaded,
    crank_deg: f64,
    levels: usize,
    wear_um: Option<f64>,
    hours: Option<f64>,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::hysteresis_curve(&cfg.model, wear, crank_deg, levels, Spelling::Python, p)
    })
}

/// `rvlife efficiency --json`: the losses and efficiency over output speed, torque and oil
/// temperature.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, speeds_rpm, torques_nm, temperatures_c, wear_um, hours, progress = None))]
#[allow(clippy::too_many_arguments)]
fn efficiency(
    py: Python<'_>,
    cfg: &Loaded,
    speeds_rpm: Option<Vec<f64>>,
    torques_nm: Option<Vec<f64>>,
    temperatures_c: Option<Vec<f64>>,
    wear_um: Option<f64>,
    hours: Option<f64>,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let wear = Wear { wear_um, hours };
    command(py, progress, |p| {
        rvlife::api::efficiency(
            &cfg.model,
            wear,
            speeds_rpm.as_deref(),
            torques_nm.as_deref(),
            temperatures_c.as_deref(),
            Spelling::Python,
            p,
        )
    })
}

/// `rvlife dynamics --json` (without `wall_time_s`) with the time series as `samples`
/// (`time_s`, `te_arcmin`, ... arrays) and, when asked, `pin_forces_n` (samples x pins of
/// both discs); `out` also writes the results directory.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
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
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
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
        let staging = staging(out.as_deref(), force)?;
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

/// The accuracy-life study (`rvlife run`): its `summary.json` object with the study's
/// `verdict` added; `out` also writes the results directory (atomically; `force` replaces an
/// existing one).
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, out, force, progress = None))]
fn run_study(
    py: Python<'_>,
    cfg: &Loaded,
    out: Option<PathBuf>,
    force: bool,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let p = progress_fn(progress);
    let v = py.detach(|| -> PyResult<Value> {
        let m = &cfg.model;
        let staging = staging(out.as_deref(), force)?;
        let study = rvlife::study::run(m, &p).map_err(py_err)?;
        if let Some(staging) = staging {
            staging
                .commit(|dir| rvlife::output::write_files(&study, dir))
                .map_err(py_err)?;
        }
        let mut v = serde_json::to_value(study.summary())
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        v["verdict"] = Value::String(study.verdict());
        Ok(v)
    })?;
    Ok(to_py(py, &v)?.unbind())
}

/// The Monte Carlo run (`rvlife montecarlo`) or its shard `"I/N"`: runs the samples and, with
/// `out`, writes the command line's files (the whole run's, or the shard's for merging).
/// Returns `{"samples_csv", "stages_csv", "shard_json"}`: the records in the files' form and
/// the shard's meta-data (for [`merge`]).
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, builtins.str]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, samples, seed, shard, full_wear, samples_per_mesh_cycle, out, force, progress = None, shared_wear = None, threads = None))]
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
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
    shared_wear: Option<String>,
    threads: Option<usize>,
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
        let staging = staging(out.as_deref(), force)?;
        let nominal = shared_wear
            .as_deref()
            .map(serde_json::from_str::<rvlife::montecarlo::NominalWear>)
            .transpose()
            .map_err(|e| PyValueError::new_err(format!("invalid shared_wear: {e}")))?;
        let work = || -> PyResult<Vec<rvlife::montecarlo::SampleRecord>> {
            match (&nominal, full_wear) {
                (None, false) => rvlife::montecarlo::run(m, &plan, &p),
                (n, _) => rvlife::montecarlo::run_on(m, &plan, n.as_ref(), &p),
            }
            .map_err(py_err)
        };
        let records = in_threads(threads, work)?;
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

/// Runs `f` on a pool of `threads` threads (`None`: rayon's global pool, one per core): a
/// task of a distributed run takes the one core its worker gives it.
fn in_threads<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    match threads {
        None => f(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?
            .install(f),
    }
}

/// The nominal reducer's wear history of a Monte Carlo run as JSON
/// ([`rvlife::montecarlo::nominal_wear`]): computed once and given to every shard
/// (`montecarlo(..., shared_wear=...)`), the shards write the serial run's bytes.
#[gen_stub_pyfunction]
#[pyfunction]
#[pyo3(signature = (cfg, threads = None))]
fn nominal_wear(py: Python<'_>, cfg: &Loaded, threads: Option<usize>) -> PyResult<String> {
    py.detach(|| {
        in_threads(threads, || {
            let w = rvlife::montecarlo::nominal_wear(&cfg.model).map_err(py_err)?;
            serde_json::to_string(&w).map_err(|e| PyRuntimeError::new_err(e.to_string()))
        })
    })
}

/// A JSON text from Python, for the config edits.
fn json_arg(what: &str, text: &str) -> PyResult<Value> {
    serde_json::from_str(text).map_err(|e| PyValueError::new_err(format!("invalid {what}: {e}")))
}

/// `text` with the dotted keys of the JSON object `edits` set (`null`: removed), comments kept
/// ([`rvlife::config::edit::set`]).
#[gen_stub_pyfunction]
#[pyfunction]
fn config_set(text: &str, origin: &str, edits: &str) -> PyResult<String> {
    let Value::Object(m) = json_arg("replace", edits)? else {
        return Err(PyValueError::new_err("replace takes a dict of dotted keys"));
    };
    let edits: Vec<(String, Option<Value>)> = m
        .into_iter()
        .map(|(k, v)| (k, (!v.is_null()).then_some(v)))
        .collect();
    rvlife::config::edit::set(text, origin, &edits).map_err(py_err)
}

/// `text` with the nested JSON object `patch` merged over it ([`rvlife::config::edit::merge`]).
#[gen_stub_pyfunction]
#[pyfunction]
fn config_merge(text: &str, origin: &str, patch: &str) -> PyResult<String> {
    rvlife::config::edit::merge(text, origin, &json_arg("config", patch)?).map_err(py_err)
}

/// The config text as a dict of sections.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
fn config_to_dict(py: Python<'_>, text: &str, origin: &str) -> PyResult<Py<PyAny>> {
    let v = rvlife::config::edit::to_json(text, origin).map_err(py_err)?;
    Ok(to_py(py, &v)?.unbind())
}

/// The accuracy life of the config (`accuracy_life` of `rvlife run`'s `summary.json`, the
/// verdict, the last stage's accuracy quantities), from the study without the dynamic and FE
/// analyses (they do not enter the life).
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, progress = None))]
fn accuracy_life(
    py: Python<'_>,
    cfg: &Loaded,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    command(py, progress, |p| {
        let study = rvlife::study::run(&cfg.model.clone().static_only(), p)?;
        let s = study.summary();
        let last = s.stages.last();
        Ok(serde_json::json!({
            "accuracy_life_h": s.accuracy_life.as_ref().and_then(|l| l.accuracy_life_h),
            "limited_by": s.accuracy_life.as_ref().and_then(|l| l.limited_by),
            "horizon_h": s.accuracy_life.as_ref().map(|l| l.horizon_h),
            "verdict": study.verdict(),
            "hours": s.stages.iter().map(|x| x.hours).collect::<Vec<_>>(),
            "lost_motion_arcmin": s.stages.iter().map(|x| x.lost_motion_arcmin).collect::<Vec<_>>(),
            "backlash_arcmin": s.stages.iter().map(|x| x.backlash_arcmin).collect::<Vec<_>>(),
            "angular_te_arcmin": s.stages.iter().map(|x| x.angular_te_arcmin).collect::<Vec<_>>(),
            "torsional_stiffness_nm_per_arcmin": s.stages.iter().map(|x| x.torsional_stiffness_nm_per_arcmin).collect::<Vec<_>>(),
            "max_wear_um": last.map(|x| x.max_wear_um),
        }))
    })
}

/// `rvlife calibrate`: the Archard coefficient giving `target_wear_um` of largest wear at the
/// last stage; `{archard_coefficient_mm3_per_n_m, max_wear_um, hours}`.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, target_wear_um))]
fn calibrate_target(py: Python<'_>, cfg: &Loaded, target_wear_um: f64) -> PyResult<Py<PyAny>> {
    command(py, None, |_| {
        let (k, achieved) =
            rvlife::wear::calibrate(&cfg.model.wear_inputs(), target_wear_um * 1e-6)?;
        Ok(serde_json::json!({
            "archard_coefficient_mm3_per_n_m": k * 1e9,
            "archard_coefficient_m2_per_n": k,
            "max_wear_um": achieved * 1e6,
            "hours": cfg.model.wear.stage_hours.last().copied().unwrap_or(0.0),
        }))
    })
}

/// `rvlife calibrate --measured`: the fit of the Archard coefficient to the measurements CSV
/// `csv` (its text; `name` in messages), `calibration.json` as a dict; `out` also writes the
/// results directory.
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, csv, name, fit_running_in, out, force, progress = None))]
#[allow(clippy::too_many_arguments)]
fn calibrate_measured(
    py: Python<'_>,
    cfg: &Loaded,
    csv: &str,
    name: &str,
    fit_running_in: bool,
    out: Option<PathBuf>,
    force: bool,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    use rvlife::calibration::{Measurements, Options};
    command(py, progress, |p| {
        let data = Measurements::parse(std::path::Path::new(name), csv)?;
        data.check_for_fit(fit_running_in, false)?;
        rvlife::api::calibrate_measured(
            &cfg.model,
            &data,
            Options { fit_running_in },
            out.as_deref(),
            force,
            &|pass| p(pass, rvlife::calibration::MAX_PASSES),
        )
    })
}

/// `rvlife calibrate --measured CURVE` or `--catalogue-stiffness-nm-per-arcmin`: the
/// structure compliance fitted to a measured hysteresis curve (`csv`, its text, columns
/// `torque_nm,twist_arcmin`; `name` in messages) or to a catalogue `b/a` (`catalogue`,
/// N m/arcmin), `calibration.json` as a dict (`rvlife::calibration::structure::StructureFit`).
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (cfg, csv, name, catalogue))]
fn calibrate_structure(
    py: Python<'_>,
    cfg: &Loaded,
    csv: Option<&str>,
    name: &str,
    catalogue: Option<f64>,
) -> PyResult<Py<PyAny>> {
    use rvlife::calibration::structure::{fit_catalogue, fit_curve, MeasuredCurve};
    command(py, None, |_| match (csv, catalogue) {
        (_, Some(s)) => fit_catalogue(&cfg.model, s),
        (Some(text), None) => {
            let curve = MeasuredCurve::parse(std::path::Path::new(name), text)?;
            fit_curve(&cfg.model, &curve)
        }
        (None, None) => Err(rvlife::Error::invalid(
            "measured",
            "missing",
            "a hysteresis curve or a catalogue stiffness",
        )),
    })
}

/// Whether the CSV text `csv` is a hysteresis curve (`torque_nm,twist_arcmin`) rather than
/// measurements against hours.
#[gen_stub_pyfunction]
#[pyfunction]
fn is_hysteresis_curve(csv: &str) -> bool {
    rvlife::calibration::structure::MeasuredCurve::is_curve(csv)
}

/// The design search (`rvlife optimize`) of `problem` ([`OptimizeProblem`]: the ranges, goals,
/// constraints and settings, validated); with `out`, also the command line's files (after the
/// follow-up studies of the report); with `batch`, a callable given the jobs the search asks
/// for together (`[(unit point, index, phase)]`) that returns their candidates as JSON texts
/// in that order ([`OptimizeProblem::evaluate`]'s, on a cluster's workers). Returns
/// `{"candidates_csv", "pareto_csv", "optimum_toml", "best", "start", "stopped"}` (`best`,
/// `start`: row indices).
#[gen_stub_pyfunction]
#[pyfunction]
#[gen_stub(override_return_type(type_repr = "dict[builtins.str, typing.Any]", imports = ("builtins", "typing")))]
#[pyo3(signature = (problem, out, force, progress = None, batch = None))]
fn optimize(
    py: Python<'_>,
    problem: &OptimizeProblem,
    out: Option<PathBuf>,
    force: bool,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.int, builtins.int], None]]", imports = ("typing", "collections.abc", "builtins")))]
    progress: Option<Py<PyAny>>,
    #[gen_stub(override_type(type_repr = "typing.Optional[collections.abc.Callable[[builtins.list[builtins.tuple[builtins.list[builtins.float], builtins.int, builtins.str]]], builtins.list[builtins.str]]]", imports = ("typing", "collections.abc", "builtins")))]
    batch: Option<Py<PyAny>>,
) -> PyResult<Py<PyAny>> {
    let p = progress_fn(progress);
    let on_cluster =
        |jobs: &[rvlife::optimize::Job]| -> rvlife::Result<Vec<rvlife::optimize::Candidate>> {
            let failed = |e: String| rvlife::Error::numerical("optimize (batch)", e);
            let texts: Vec<String> = Python::attach(|py| {
                let cb = batch.as_ref().expect("called only with a batch");
                cb.bind(py)
                    .call1((jobs.to_vec(),))
                    .and_then(|r| r.extract())
                    .map_err(|e| failed(e.to_string()))
            })?;
            texts
                .iter()
                .map(|t| serde_json::from_str(t).map_err(|e| failed(e.to_string())))
                .collect()
        };
    let problem = &problem.0;
    let v = py.detach(|| -> PyResult<Value> {
        let staging = staging(out.as_deref(), force)?;
        let outcome = rvlife::optimize::run_batched(
            problem,
            batch
                .is_some()
                .then_some(&on_cluster as &rvlife::optimize::Batch),
            &|d, t, _| p(d, t),
            &|| false,
        )
        .map_err(py_err)?;
        if let Some(staging) = staging {
            let follow =
                rvlife::optimize::follow_up(problem, &outcome, &|_, _| {}).map_err(py_err)?;
            staging
                .commit(|dir| {
                    rvlife::output::optimize::write_files(dir, problem, &outcome, &follow)
                })
                .map_err(py_err)?;
        }
        let (candidates, front) =
            rvlife::output::candidates::tables_csv(problem, &outcome).map_err(py_err)?;
        let optimum = outcome
            .best
            .map(|i| problem.text_of(&outcome.candidates[i].values, false))
            .transpose()
            .map_err(py_err)?;
        Ok(serde_json::json!({
            "candidates_csv": candidates,
            "pareto_csv": front,
            "optimum_toml": optimum,
            "best": outcome.best,
            "start": outcome.start,
            "stopped": outcome.stopped,
        }))
    })?;
    Ok(to_py(py, &v)?.unbind())
}

/// A design search's problem: `vary` the `KEY=LO:HI` ranges, `objective` the goals,
/// `constraints` the `Q<=V` texts, validated with the whole search's work before any study
/// (`ValueError` naming the key or argument); [`optimize`] runs it, and a cluster's worker
/// builds it once and evaluates its candidates.
#[gen_stub_pyclass]
#[pyclass(frozen, module = "rvlife._rvlife")]
struct OptimizeProblem(rvlife::optimize::Problem);

#[gen_stub_pymethods]
#[pymethods]
impl OptimizeProblem {
    /// The problem of these arguments (`rvlife optimize`'s options).
    #[new]
    #[pyo3(signature = (text, origin, base_dir, work_budget_min, vary, objective, constraints, evaluations, seed))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        text: &str,
        origin: &str,
        base_dir: Option<PathBuf>,
        work_budget_min: f64,
        vary: Vec<String>,
        objective: &str,
        constraints: Vec<String>,
        evaluations: usize,
        seed: u64,
    ) -> PyResult<Self> {
        py.detach(|| {
            rvlife::optimize::Problem::new(
                text,
                origin,
                base_dir.as_deref(),
                work_budget_min,
                &vary,
                objective,
                &constraints,
                rvlife::optimize::Settings { evaluations, seed },
            )
        })
        .map(OptimizeProblem)
        .map_err(py_err)
    }

    /// The candidate at `unit` (the unit box) as the search evaluates it: its JSON text, which
    /// [`optimize`]'s `batch` returns.
    fn evaluate(
        &self,
        py: Python<'_>,
        unit: Vec<f64>,
        index: usize,
        phase: &str,
    ) -> PyResult<String> {
        if unit.len() != self.0.variables.len() || unit.iter().any(|u| !(0.0..=1.0).contains(u)) {
            return Err(PyValueError::new_err(format!(
                "invalid unit = {unit:?}: {} numbers in [0, 1]",
                self.0.variables.len()
            )));
        }
        let c = py.detach(|| rvlife::optimize::evaluate(&self.0, &unit, index, phase));
        serde_json::to_string(&c).map_err(|e| PyValueError::new_err(e.to_string()))
    }
}

/// The designs of a sweep as config texts (`rvlife sweep`'s `--vary`, validated with the
/// sweep's work budget): `vary` a JSON list of `[key, [values]]`.
#[gen_stub_pyfunction]
#[pyfunction]
fn sweep_designs(
    text: &str,
    origin: &str,
    base_dir: Option<PathBuf>,
    vary: &str,
    work_budget_min: f64,
) -> PyResult<Vec<String>> {
    let v = json_arg("grid", vary)?;
    let varies: Vec<rvlife::sweep::Vary> = v
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|x| {
            Some(rvlife::sweep::Vary {
                key: x.get(0)?.as_str()?.to_string(),
                values: x.get(1)?.as_array()?.clone(),
            })
        })
        .collect();
    let d = rvlife::sweep::designs(
        text,
        origin,
        base_dir.as_deref(),
        &[],
        &varies,
        work_budget_min,
    )
    .map_err(py_err)?;
    Ok(d.into_iter().map(|d| d.text).collect())
}

/// Merges shard directories (`rvlife merge`) into the whole run's files in `out`.
#[gen_stub_pyfunction]
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

/// One quantity for Python: name, unit, label, description, models, CSV columns.
type QuantityRow = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    Vec<&'static str>,
);

/// The table of stage quantities ([`rvlife::api::quantity_table`], the order of
/// `summary.json` and `stages.csv`): per quantity its name (with its unit), unit, label,
/// description, the models that produce it (`static`, `dynamics`, `flexible`, `lubrication`)
/// and its CSV columns.
#[gen_stub_pyfunction]
#[pyfunction]
fn quantities() -> Vec<QuantityRow> {
    rvlife::api::quantity_table()
        .into_iter()
        .map(|q| (q.name, q.unit, q.label, q.description, q.models, q.columns))
        .collect()
}

/// Every command as the library declares it ([`rvlife::api::commands::COMMANDS`]), JSON:
/// what the package's test checks its functions' signatures against.
#[gen_stub_pyfunction]
#[pyfunction]
fn commands() -> String {
    rvlife::api::commands::commands_json()
}

/// The rvlife version.
#[gen_stub_pyfunction]
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

pyo3_stub_gen::define_stub_info_gatherer!(stub_info);

pyo3_stub_gen::module_doc!(
    "rvlife._rvlife",
    "The native module of rvlife (PyO3), generated from its functions' signatures. A config is\n\
     loaded once (`load`: TOML text, origin, base folder) and passed to every command; results\n\
     are the command line's JSON objects as dicts, lists of floats as numpy float64 arrays. Bad\n\
     input raises ValueError naming the key."
);

/// The native module's stub (`python/rvlife/_rvlife.pyi`) as pyo3-stub-gen writes it from the
/// functions' and classes' own signatures and doc comments; `tests/stub.rs` fails while the
/// file in the tree is not this text. Errors: the crate's `pyproject.toml` unreadable, or no
/// module `rvlife._rvlife` gathered (message).
pub fn stub_text() -> Result<String, String> {
    let info = stub_info().map_err(|e| e.to_string())?;
    info.modules
        .get("rvlife._rvlife")
        .map(|m| m.to_string())
        .ok_or_else(|| format!("no module rvlife._rvlife among {:?}", info.modules.keys()))
}

#[pymodule]
fn _rvlife(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(example_toml, m)?)?;
    m.add_function(wrap_pyfunction!(presets, m)?)?;
    m.add_class::<Loaded>()?;
    m.add_class::<OptimizeProblem>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(toml_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(profile, m)?)?;
    m.add_function(wrap_pyfunction!(contact, m)?)?;
    m.add_function(wrap_pyfunction!(te, m)?)?;
    m.add_function(wrap_pyfunction!(hysteresis, m)?)?;
    m.add_function(wrap_pyfunction!(efficiency, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics, m)?)?;
    m.add_function(wrap_pyfunction!(run_study, m)?)?;
    m.add_function(wrap_pyfunction!(montecarlo, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(nominal_wear, m)?)?;
    m.add_function(wrap_pyfunction!(config_set, m)?)?;
    m.add_function(wrap_pyfunction!(config_merge, m)?)?;
    m.add_function(wrap_pyfunction!(config_to_dict, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy_life, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_target, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_measured, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate_structure, m)?)?;
    m.add_function(wrap_pyfunction!(is_hysteresis_curve, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_designs, m)?)?;
    m.add_function(wrap_pyfunction!(optimize, m)?)?;
    m.add_function(wrap_pyfunction!(quantities, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(commands, m)?)?;
    Ok(())
}
