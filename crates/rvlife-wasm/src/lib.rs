//! rvlife in the browser: the commands of [`rvlife::api`] for JavaScript, built for
//! `wasm32-unknown-unknown` with wasm-bindgen and run in a Web Worker by the page of `web/`.
//!
//! Plain data in, plain data out: a config is its TOML text (validated on every call exactly
//! as the command line validates a file, with the same messages); every result is a JSON
//! string whose keys are those of the command line's `--json` output or results files
//! (`summary.json` of `rvlife run`, the CSV tables as text); progress goes to an optional
//! JavaScript callback `(done, total)`. An error is thrown as a JavaScript `Error` whose
//! message is the command line's message (without its `error: ` prefix). Nothing touches a
//! file system: the results' files come back as text, for the page to offer as downloads.
//!
//! Units are those of the command line: engineering units at this edge, in the names.

#![warn(missing_docs)]

mod answers;
#[cfg(test)]
mod typescript;

use rvlife::api::{self, Spelling, Wear};
use rvlife::config::{Config, Model};
use rvlife::units::ARCMIN_PER_RAD;
use serde::Serialize;
use serde_json::{json, Value};
use wasm_bindgen::prelude::*;

/// Where errors say the config came from.
const ORIGIN: &str = "config.toml";

/// A progress callback usable where the library asks for `Fn(usize, usize) + Sync`.
///
/// `wasm32-unknown-unknown` has one thread (rayon runs its loops on the calling thread), so
/// the JavaScript function is only ever called from the thread that made it.
struct Progress(Option<js_sys::Function>);

// SAFETY: the wasm32-unknown-unknown build this crate is for has no threads; the callback is
// never shared with another thread.
unsafe impl Sync for Progress {}

impl Progress {
    fn call(&self, done: usize, total: usize) {
        if let Some(f) = &self.0 {
            // A callback that throws does not stop the analysis.
            let _ = f.call2(
                &JsValue::NULL,
                &JsValue::from_f64(done as f64),
                &JsValue::from_f64(total as f64),
            );
        }
    }
}

fn err(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

fn to_json(v: &impl Serialize) -> Result<String, JsError> {
    serde_json::to_string(v).map_err(err)
}

/// The parsed config of `text` (not validated): syntax, types and unknown keys checked.
fn parsed(text: &str) -> Result<Config, JsError> {
    Config::from_toml_in(text, ORIGIN, None).map_err(err)
}

/// The validated model of `text`, as the command line's commands validate a file (ranges,
/// cross-section rules, the physical checks, the work budget).
fn model(text: &str) -> Result<Model, JsError> {
    api::validated(&parsed(text)?).map_err(err)
}

/// The model of `text` for the static accuracy-life study: dynamics and the FE disc off.
fn static_model(text: &str) -> Result<Model, JsError> {
    Ok(model(text)?.static_only())
}

fn wear(hours: Option<f64>, wear_um: Option<f64>) -> Wear {
    Wear { wear_um, hours }
}

/// Runs the command `f` on the validated model of `text` with the progress callback, and
/// returns its result as JSON.
fn command<T: Serialize>(
    text: &str,
    progress: Option<js_sys::Function>,
    f: impl FnOnce(&Model, &(dyn Fn(usize, usize) + Sync)) -> rvlife::Result<T>,
) -> Result<String, JsError> {
    let m = model(text)?;
    let p = Progress(progress);
    to_json(&f(&m, &|d, t| p.call(d, t)).map_err(err)?)
}

/// The built-in reducers: JSON `[{name, summary}]` (`rvlife example --list`).
#[wasm_bindgen]
pub fn presets() -> Result<String, JsError> {
    let list: Vec<answers::Preset> = rvlife::config::PRESETS
        .iter()
        .map(|p| answers::Preset {
            name: p.name,
            summary: p.summary,
        })
        .collect();
    to_json(&list)
}

/// The table of stage quantities (`rvlife.quantities()` in Python): JSON
/// `[{name, unit, label, description, models, columns}]` ([`api::quantity_table`]), in the order
/// of `summary.json`.
///
/// # Errors
/// None in practice (the JSON of static text).
#[wasm_bindgen]
pub fn quantities() -> Result<String, JsError> {
    to_json(&api::quantity_table())
}

/// The TOML text of the built-in reducer `name` (`rvlife example --preset NAME`).
///
/// # Errors
/// An unknown name, naming the known ones.
#[wasm_bindgen(js_name = presetText)]
pub fn preset_text(name: &str) -> Result<String, JsError> {
    rvlife::config::preset_text(name).map_err(err)
}

/// The editor's view of the config `text`: JSON `{message, keys}`, where `message` is `null`
/// if `text` is a valid config, else the command line's message for it (the first bad key,
/// its value and its allowed range; or the parse error), and `keys` is
/// `[{section, key, value, commented, comment, unit, allowed}]`
/// ([`rvlife::config::schema::keys`], the ranges recorded by this same validation), or `null`
/// if the text does not parse.
#[wasm_bindgen]
pub fn inspect(text: &str) -> Result<String, JsError> {
    let (keys, message) = match rvlife::config::schema::keys(text, ORIGIN, api::validated) {
        Ok((keys, validated)) => (Some(keys), validated.err().map(|e| e.to_string())),
        Err(e) => (None, Some(e.to_string())),
    };
    to_json(&answers::Inspection { message, keys })
}

/// `text` with the dotted `key` set to the JSON `value_json` (`null` removes the key),
/// comments and layout kept ([`rvlife::config::edit::set`]).
///
/// # Errors
/// An unknown key or a value of the wrong type, naming the key.
#[wasm_bindgen(js_name = setKey)]
pub fn set_key(text: &str, key: &str, value_json: &str) -> Result<String, JsError> {
    let v: Value = serde_json::from_str(value_json).map_err(err)?;
    let v = (!v.is_null()).then_some(v);
    rvlife::config::edit::set(text, ORIGIN, &[(key.to_string(), v)]).map_err(err)
}

/// The disc profile's points (`rvlife profile --json`): nominal (`nominal`: no modification),
/// modified, or worn after `hours` (h) or uniformly by `wear_um` (um); `per_tooth` points per
/// tooth (0: the export's). JSON [`rvlife::api::ProfilePoints`] (mm, deg, um).
///
/// # Errors
/// The config's message, or the argument's (named as in Python: `hours`, `wear_um`).
#[wasm_bindgen]
pub fn profile(
    text: &str,
    hours: Option<f64>,
    wear_um: Option<f64>,
    nominal: bool,
    per_tooth: usize,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    command(text, progress, |m, p| {
        api::profile_points(
            m,
            wear(hours, wear_um),
            nominal,
            per_tooth,
            Spelling::Python,
            p,
        )
    })
}

/// The loaded contact at `crank_deg` under `torque_nm` (`rvlife contact --json`), worn after
/// `hours` or by `wear_um`. JSON [`rvlife::api::ContactResult`].
///
/// # Errors
/// The config's message, or the argument's.
#[wasm_bindgen]
pub fn contact(
    text: &str,
    crank_deg: f64,
    torque_nm: f64,
    hours: Option<f64>,
    wear_um: Option<f64>,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    command(text, progress, |m, p| {
        api::contact(
            m,
            wear(hours, wear_um),
            crank_deg,
            torque_nm,
            Spelling::Python,
            p,
        )
    })
}

/// The static transmission error over a mesh cycle (`rvlife te --json`), worn after `hours`
/// or by `wear_um`, loaded by `torque_nm` if given. JSON [`rvlife::api::TeResult`].
///
/// # Errors
/// The config's message, or the argument's.
#[wasm_bindgen]
pub fn te(
    text: &str,
    hours: Option<f64>,
    wear_um: Option<f64>,
    torque_nm: Option<f64>,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    command(text, progress, |m, p| {
        api::te(m, wear(hours, wear_um), torque_nm, Spelling::Python, p)
    })
}

/// The hysteresis curve at `crank_deg` with `levels` torque levels (`rvlife hysteresis
/// --json`), worn after `hours` or by `wear_um`. JSON [`rvlife::api::HysteresisResult`] with
/// `catalogue_points`: where the mean curve's lost motion and torsional stiffness are read
/// (`lost_motion` and `torsional_stiffness`, each two `[torque N m, twist arcmin]` points),
/// for the page to mark them on the curve.
///
/// # Errors
/// The config's message, or the argument's.
#[wasm_bindgen]
pub fn hysteresis(
    text: &str,
    crank_deg: f64,
    levels: usize,
    hours: Option<f64>,
    wear_um: Option<f64>,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    command(text, progress, |m, p| {
        let (result, mean) = api::hysteresis_curve_and_table(
            m,
            wear(hours, wear_um),
            crank_deg,
            levels,
            Spelling::Python,
            p,
        )?;
        let points = mean.catalogue_points();
        let arcmin = |[[t0, psi0], [t1, psi1]]: [[f64; 2]; 2]| {
            [[t0, psi0 * ARCMIN_PER_RAD], [t1, psi1 * ARCMIN_PER_RAD]]
        };
        Ok(answers::HysteresisView {
            result,
            catalogue_points: answers::CataloguePoints {
                lost_motion: arcmin(points.lost_motion),
                torsional_stiffness: arcmin(points.torsional_stiffness),
            },
        })
    })
}

/// A study's results, kept in the module for the page to read: its summary at once, the
/// tables when the first is asked for, each stage profile's file (DXF, CSV) when asked for.
#[wasm_bindgen]
pub struct StudyResults {
    study: rvlife::study::Study,
    tables: std::cell::OnceCell<Vec<(String, Vec<u8>)>>,
}

impl StudyResults {
    fn new(study: rvlife::study::Study) -> Self {
        StudyResults {
            study,
            tables: std::cell::OnceCell::new(),
        }
    }
}

#[wasm_bindgen]
impl StudyResults {
    /// JSON `{summary, verdict, files}`: `summary` is `summary.json`'s object, `verdict` the
    /// one-line verdict against `[life]`, `files` the names of every data file of the results
    /// directory (`summary.json`, `stages.csv`, ..., `profiles/worn_<H>h.dxf`), in order.
    pub fn overview(&self) -> Result<String, JsError> {
        let mut files = rvlife::output::study::table_names(&self.study);
        files.extend(rvlife::output::study::profile_files(&self.study));
        to_json(&answers::StudyOverview {
            summary: self.study.summary(),
            verdict: self.study.verdict(),
            files,
        })
    }

    /// The flexible disc's analysis of every stage of this study (`rvlife::study::parts::
    /// flexible`: the FE disc of `[fem]` moved onto each stage's worn outline, as `rvlife run`
    /// with `[fem] enabled` and the dynamics off), then [`StudyResults::overview`] with the
    /// `flexible_*` quantities in every stage. `progress(done, total)` hears the FE disc's
    /// build and each stage.
    ///
    /// # Errors
    /// The FE disc's failures and the flexible analysis's.
    pub fn flexible(&mut self, progress: Option<js_sys::Function>) -> Result<String, JsError> {
        let p = Progress(progress);
        rvlife::study::parts::flexible(&mut self.study, &|d, t| p.call(d, t)).map_err(err)?;
        self.tables = std::cell::OnceCell::new();
        self.overview()
    }

    /// The text of the data file `name` (one of `overview`'s `files`), byte for byte what
    /// `rvlife run` writes.
    ///
    /// # Errors
    /// An unknown name.
    pub fn file(&self, name: &str) -> Result<String, JsError> {
        if self.tables.get().is_none() {
            let tables = rvlife::output::study::tables(&self.study).map_err(err)?;
            let _ = self.tables.set(tables);
        }
        let tables = self.tables.get().map_or(&[][..], |t| t.as_slice());
        let bytes = match tables.iter().find(|(n, _)| n == name) {
            Some((_, b)) => b.clone(),
            None => rvlife::output::study::profile_file(&self.study, name)
                .map_err(err)?
                .ok_or_else(|| JsError::new(&format!("no results file {name:?}")))?,
        };
        String::from_utf8(bytes).map_err(err)
    }
}

/// The accuracy-life study without dynamics and the FE disc (`rvlife run` with both off),
/// its results kept as [`StudyResults`].
///
/// # Errors
/// The config's message; the study's failures.
#[wasm_bindgen]
pub fn study(text: &str, progress: Option<js_sys::Function>) -> Result<StudyResults, JsError> {
    let m = static_model(text)?;
    let p = Progress(progress);
    let study = rvlife::study::run(&m, &|d, t| p.call(d, t)).map_err(err)?;
    Ok(StudyResults::new(study))
}

// The study of `study` in parts, for the page to run its stages on several Web Workers
// (each with its own module): `studyPlan`, then `studyWear` on one worker beside the
// unworn first stage's `studyStage` on another, then `studyStage` for every stage
// `studyWear` hands on, on any worker, as soon as it is handed on, then `StudyWear.assemble`
// on the worker that integrated the wear (`rvlife::study::parts`). What crosses between
// workers is bytes (CBOR); the results equal `study`'s.

/// `v` as CBOR bytes: what crosses between the page's workers.
fn cbor(v: &impl Serialize) -> Result<Vec<u8>, JsError> {
    let mut bytes = Vec::new();
    ciborium::into_writer(v, &mut bytes).map_err(err)?;
    Ok(bytes)
}

/// The value of the CBOR `bytes` ([`cbor`]); `what` names them in the error.
fn from_cbor<T: serde::de::DeserializeOwned>(bytes: &[u8], what: &str) -> Result<T, JsError> {
    ciborium::from_reader(bytes).map_err(|e| JsError::new(&format!("{what}: {e}")))
}

thread_local! {
    /// The last config text a study part validated, and its model: the parts of one study
    /// validate it once per worker.
    static STATIC_MODEL: std::cell::RefCell<Option<(String, Model)>> =
        const { std::cell::RefCell::new(None) };
}

/// [`static_model`] of `text`, validated once for the calls on the same text.
fn static_model_kept(text: &str) -> Result<Model, JsError> {
    if let Some(m) =
        STATIC_MODEL.with_borrow(|k| k.as_ref().and_then(|(t, m)| (t == text).then(|| m.clone())))
    {
        return Ok(m);
    }
    let m = static_model(text)?;
    STATIC_MODEL.with_borrow_mut(|k| *k = Some((text.to_string(), m.clone())));
    Ok(m)
}

/// The plan of [`study`] in parts for the config `text`: a JavaScript object `{ground,
/// first, wearSteps, stages}` with the bytes every part needs (`ground`), the unworn first
/// stage's bytes for [`study_stage`] when the first stage lies at 0 h (else `undefined`), the
/// wear integration's progress steps and the number of stages.
///
/// # Errors
/// The config's message; solver failures on the new reducer.
#[wasm_bindgen(js_name = studyPlan)]
pub fn study_plan(text: &str) -> Result<js_sys::Object, JsError> {
    use rvlife::study::parts;
    let m = static_model_kept(text)?;
    let ground = parts::ground(&m).map_err(err)?;
    let plan = js_sys::Object::new();
    let set = |k: &str, v: JsValue| js_sys::Reflect::set(&plan, &k.into(), &v).map(|_| ());
    let bytes = |b: Vec<u8>| JsValue::from(js_sys::Uint8Array::from(b.as_slice()));
    let first = match parts::unworn_first(&m) {
        Some(s) => bytes(cbor(&s)?),
        None => JsValue::UNDEFINED,
    };
    set("ground", bytes(cbor(&ground)?))
        .and_then(|_| set("first", first))
        .and_then(|_| set("wearSteps", (parts::wear_steps(&m) as f64).into()))
        .and_then(|_| set("stages", (m.wear.stage_hours.len() as f64).into()))
        .map_err(|_| JsError::new("the study plan could not be made"))?;
    Ok(plan)
}

/// The static analysis of one stage of the study of `text` (`ground` and `stage`: bytes from
/// [`study_plan`] or handed on by [`study_wear`]): the bytes of its outcome, for
/// [`StudyWear::assemble`]. A stage whose analysis fails still has an outcome (its failure,
/// reported by the assembly as the study would).
///
/// # Errors
/// The config's message; bytes that are not a study part's.
#[wasm_bindgen(js_name = studyStage)]
pub fn study_stage(text: &str, ground: &[u8], stage: &[u8]) -> Result<Vec<u8>, JsError> {
    use rvlife::study::parts;
    let m = static_model_kept(text)?;
    let ground: parts::Ground = from_cbor(ground, "study ground")?;
    let stage: parts::StageWear = from_cbor(stage, "study stage")?;
    cbor(&parts::static_stage(&m, &ground, &stage))
}

/// Runs a small analysis of the built-in example: its validation, the ground of its study (the
/// new reducer's loads and play) and its unworn stage's static analysis; keeps nothing. A
/// WebAssembly engine compiles a function when it is first called and optimises it once it
/// has run a while (V8: Liftoff, then TurboFan), and the workers of one page share that code,
/// so the page's first analysis runs at full speed once one worker has run this.
///
/// # Errors
/// None in practice: the built-in example is valid.
#[wasm_bindgen]
pub fn warm() -> Result<(), JsError> {
    use rvlife::study::parts;
    let text = rvlife::config::preset_text("rv-40e").map_err(err)?;
    let m = static_model(&text)?;
    let ground = parts::ground(&m).map_err(err)?;
    if let Some(first) = parts::unworn_first(&m) {
        parts::static_stage(&m, &ground, &first);
    }
    Ok(())
}

/// The wear integration of the study of `text`, kept in the module for the stages and the
/// assembly.
#[wasm_bindgen]
pub struct StudyWear {
    model: Model,
    wear: rvlife::wear::WearHistory,
    /// The accuracy life's trials between two stages, once made ([`StudyWear::offer`]).
    ahead: Option<rvlife::study::parts::LifeAhead>,
}

/// The wear integration of the study of `text` (`ground`: [`study_plan`]'s bytes), with
/// progress `(done, total)` in wear-rate evaluations; `on_stage` is called with each stage's
/// bytes for [`study_stage`] as soon as the integration has passed it (in the stages' order),
/// so that the stages can be analysed on other workers while it goes on.
///
/// # Errors
/// The config's message; the wear integration's failures.
#[wasm_bindgen(js_name = studyWear)]
pub fn study_wear(
    text: &str,
    ground: &[u8],
    progress: Option<js_sys::Function>,
    on_stage: Option<js_sys::Function>,
) -> Result<StudyWear, JsError> {
    use rvlife::study::parts;
    let m = static_model_kept(text)?;
    let ground: parts::Ground = from_cbor(ground, "study ground")?;
    let p = Progress(progress);
    let wear = parts::wear_history(&m, &ground, &|d, t| p.call(d, t), &|s| {
        if let (Some(f), Ok(bytes)) = (&on_stage, cbor(&s)) {
            // A callback that throws does not stop the integration.
            let _ = f.call1(&JsValue::NULL, &js_sys::Uint8Array::from(bytes.as_slice()));
        }
    })
    .map_err(err)?;
    Ok(StudyWear {
        model: m,
        wear,
        ahead: None,
    })
}

#[wasm_bindgen]
impl StudyWear {
    /// The stages' outcomes known so far ([`study_stage`]'s bytes, any order): once every
    /// stage up to the first outside the spec is among them, the accuracy life's trials
    /// between two stages are made here, for [`StudyWear::assemble`] (while the other workers
    /// analyse the later stages). Returns whether that is settled (made, or not needed); the
    /// page offers the outcomes again after each stage until it is.
    ///
    /// # Errors
    /// Outcomes that cannot be read.
    pub fn offer(&mut self, outcomes: Vec<js_sys::Uint8Array>) -> Result<bool, JsError> {
        if self.ahead.is_some() {
            return Ok(true);
        }
        let outcomes = outcomes
            .iter()
            .map(|o| from_cbor(&o.to_vec(), "study stage outcome"))
            .collect::<Result<Vec<_>, _>>()?;
        self.ahead = rvlife::study::parts::crossing_ahead(&self.model, &self.wear, &outcomes);
        Ok(self.ahead.is_some())
    }

    /// The study from this wear and the stages' outcomes ([`study_stage`]'s bytes, one for
    /// each stage, in any order): the results of [`study`]. `notice(text)` hears each step of
    /// the accuracy life's search beyond the last stage (a wear integration each, which can
    /// take as long as the study: `rvlife run` prints the same lines).
    ///
    /// # Errors
    /// Outcomes that are not this study's; the stages' failures and the accuracy life's, as
    /// [`study`] reports them.
    pub fn assemble(
        &mut self,
        outcomes: Vec<js_sys::Uint8Array>,
        notice: Option<js_sys::Function>,
    ) -> Result<StudyResults, JsError> {
        let outcomes = outcomes
            .iter()
            .map(|o| from_cbor(&o.to_vec(), "study stage outcome"))
            .collect::<Result<Vec<_>, _>>()?;
        let study = rvlife::study::parts::assemble_ahead(
            &self.model,
            self.wear.clone(),
            outcomes,
            self.ahead.take(),
            &|text| {
                if let Some(f) = &notice {
                    // A callback that throws does not stop the search.
                    let _ = f.call1(&JsValue::NULL, &JsValue::from_str(text));
                }
            },
        )
        .map_err(err)?;
        Ok(StudyResults::new(study))
    }
}

/// The multibody simulation (`rvlife dynamics --disc DISC --json`) with `disc` `"rigid"` or
/// `"flexible"` discs (the FE disc's modes, docs/model.md section 9; `None`: the config's
/// `[fem]` choice), worn after `hours` or by `wear_um`, under a constant output torque
/// `torque_nm` if given (else the config's `[dynamics.load]`): JSON `{summary, time_s,
/// te_arcmin, output_speed_deg_s}` with the command line's summary and the time series at the
/// output interval.
///
/// # Errors
/// The config's message (`[dynamics]` checked as if enabled), or the argument's (`--disc`
/// not rigid or flexible); the simulation's failures.
#[wasm_bindgen]
pub fn dynamics(
    text: &str,
    hours: Option<f64>,
    wear_um: Option<f64>,
    torque_nm: Option<f64>,
    disc: Option<String>,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    let opts = api::DynamicsOptions {
        load: torque_nm.map(|_| "constant".to_string()),
        torque_nm,
        disc,
    };
    let m = api::dynamics_model(&parsed(text)?, &opts, Spelling::Python).map_err(err)?;
    let p = Progress(progress);
    let r = api::dynamics(
        &m,
        wear(hours, wear_um),
        false,
        Spelling::Python,
        &|d, t| p.call(d, t),
    )
    .map_err(err)?;
    let series =
        |f: fn(&rvlife::dynamics::Sample) -> f64| -> Vec<f64> { r.samples.iter().map(f).collect() };
    to_json(&answers::DynamicsView {
        time_s: series(|s| s.time_s),
        te_arcmin: series(|s| s.te_arcmin),
        output_speed_deg_s: series(|s| s.output_speed_deg_s),
        summary: r.summary,
    })
}

/// The Monte Carlo accuracy life of `samples` reducers drawn from `[tolerances]` with `seed`
/// (`rvlife montecarlo --samples N --seed S`; dynamics and the FE disc off): JSON `{samples_csv,
/// stages_csv, life, percentiles, records, horizon_h, verdict, reliability}` with the command
/// line's `samples.csv` and `stages.csv` texts, the life distribution and percentiles of its
/// `summary.json`, every sample's `{sample, status, accuracy_life_h, limited_by}`, the horizon
/// beyond which a life is censored (h), the report's verdict sentence (B10, B50, the fraction
/// within spec, the samples analysed: `rvlife::output::mc_verdict::verdict`) and the
/// reliability curve `[[hours, fraction within spec]]` (`rvlife::montecarlo::reliability`).
///
/// # Errors
/// The config's message; `samples` out of range (named `samples`).
#[wasm_bindgen]
pub fn montecarlo(
    text: &str,
    samples: usize,
    seed: u64,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    let m = static_model(text)?;
    let plan = montecarlo_plan(&m, samples, seed, None)?;
    let p = Progress(progress);
    let records = rvlife::montecarlo::run(&m, &plan, &|d, t| p.call(d, t)).map_err(err)?;
    montecarlo_json(&m, &records)
}

/// The JSON of [`montecarlo`] from the records of a whole run.
fn montecarlo_json(
    m: &Model,
    records: &[rvlife::montecarlo::SampleRecord],
) -> Result<String, JsError> {
    let (samples_csv, stages_csv) = rvlife::montecarlo::records_csv(records);
    let life =
        rvlife::montecarlo::life_distribution(records, m.life.horizon_h(&m.wear.stage_hours));
    let percentiles = rvlife::montecarlo::percentiles(records, &m.wear.stage_hours);
    let horizon = m.life.horizon_h(&m.wear.stage_hours);
    let list = records
        .iter()
        .map(|r| answers::SampleLife {
            sample: r.sample,
            status: r.status.clone(),
            accuracy_life_h: r.accuracy_life_h,
            limited_by: r.limited_by.clone(),
        })
        .collect();
    to_json(&answers::MonteCarloView {
        samples_csv,
        stages_csv,
        life,
        percentiles,
        records: list,
        horizon_h: horizon,
        verdict: rvlife::output::mc_verdict::verdict(records, &m.wear.stage_hours, &m.life),
        reliability: rvlife::montecarlo::reliability(records, horizon),
    })
}

/// The plan of [`montecarlo`]'s run of `samples` with `seed`, or of its part `shard` (`I/N`):
/// the whole run's work checked against the config's budget.
fn montecarlo_plan(
    m: &Model,
    samples: usize,
    seed: u64,
    shard: Option<&str>,
) -> Result<rvlife::montecarlo::Plan, JsError> {
    api::montecarlo_plan(
        m,
        samples,
        seed,
        shard,
        false,
        rvlife::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE,
        Spelling::Python,
    )
    .map_err(err)
}

/// Validates the config `text` and keeps its model in this worker for the parts of a run that
/// follow (a study's stages, a Monte Carlo run's samples): a worker waiting for its first
/// part validates meanwhile.
///
/// # Errors
/// The config's message.
#[wasm_bindgen]
pub fn prepare(text: &str) -> Result<(), JsError> {
    static_model_kept(text).map(|_| ())
}

/// The first part of [`montecarlo`] run on several workers: the nominal reducer's wear history
/// of the config `text` (`rvlife::montecarlo::nominal_wear`), which every sample is analysed
/// on, as bytes for [`montecarlo_shard`]. Checks the whole run of `samples` with `seed` first.
/// `progress(done, total)` hears the wear integration's steps, and `early(bytes)` the
/// history's early part up to the last stage as soon as it is integrated, when points beyond
/// it follow (`rvlife::montecarlo::NominalWear::partial`): the samples' stages can be analysed
/// on it meanwhile.
///
/// # Errors
/// The config's message; `samples` out of range or beyond the work budget (named
/// `samples`); the wear integration's failure.
#[wasm_bindgen(js_name = montecarloWear)]
pub fn montecarlo_wear(
    text: &str,
    samples: usize,
    seed: u64,
    progress: Option<js_sys::Function>,
    early: Option<js_sys::Function>,
) -> Result<Vec<u8>, JsError> {
    let m = static_model_kept(text)?;
    montecarlo_plan(&m, samples, seed, None)?;
    let p = Progress(progress);
    let whole = rvlife::montecarlo::nominal_wear_reporting(&m, &|d, t| p.call(d, t), &|w| {
        if let (Some(f), Ok(bytes)) = (&early, cbor(&w)) {
            // A callback that throws does not stop the integration.
            let _ = f.call1(&JsValue::NULL, &js_sys::Uint8Array::from(bytes.as_slice()));
        }
    })
    .map_err(err)?;
    cbor(&whole)
}

/// A part of a Monte Carlo run whose samples wait for the whole nominal history
/// ([`montecarlo_shard`]), kept in the worker that analysed their stages.
struct KeptPart {
    /// The run and the part: config text, samples, seed, index, count.
    key: (String, usize, u64, usize, usize),
    /// The part's samples done.
    done: Vec<rvlife::montecarlo::SampleRecord>,
    /// Those waiting.
    waiting: Vec<rvlife::montecarlo::SampleStages>,
}

thread_local! {
    /// The parts of the current Monte Carlo run whose samples wait in this worker.
    static KEPT_PARTS: std::cell::RefCell<Vec<KeptPart>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The part `index` of `count` (1-based: the samples `[(index-1) S/count, index S/count)`) of
/// [`montecarlo`]'s run of `samples` reducers with `seed`, on the nominal wear history `wear`
/// ([`montecarlo_wear`]'s bytes, its early part or the whole): JSON `{meta, samples_csv,
/// stages_csv}`, the shard's meta-data (`rvlife::output::mc_shards::ShardMeta`) and its
/// records as the command line's tables, for [`montecarlo_merge`]. On the early part, a
/// sample whose life lies beyond its stages waits in this worker, and the answer is
/// `{"waiting": N}`: the same call on the same worker with the whole history then finishes the
/// part. `progress(done, total)` counts this part's samples analysed.
///
/// # Errors
/// The config's message; `samples` or the part out of range; bytes that are not this
/// config's nominal wear history.
#[wasm_bindgen(js_name = montecarloShard)]
pub fn montecarlo_shard(
    text: &str,
    samples: usize,
    seed: u64,
    wear: &[u8],
    index: usize,
    count: usize,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    use rvlife::montecarlo::{sample_beyond, sample_on, SampleStep, SharedWear};
    let m = static_model_kept(text)?;
    let plan = montecarlo_plan(&m, samples, seed, Some(&format!("{index}/{count}")))?;
    let wear: rvlife::montecarlo::NominalWear = from_cbor(wear, "nominal wear history")?;
    let shared = SharedWear::of(&m, &wear).map_err(err)?;
    let key = (text.to_string(), samples, seed, index, count);
    // Only this run's parts are kept: a new run drops the others.
    let kept = KEPT_PARTS.with_borrow_mut(|k| {
        k.retain(|p| (&p.key.0, p.key.1, p.key.2) == (&key.0, key.1, key.2));
        k.iter()
            .position(|p| p.key == key)
            .map(|i| k.swap_remove(i))
    });
    let p = Progress(progress);
    let (mut done, waiting) = match kept {
        Some(part) => (part.done, part.waiting),
        None => {
            let mut done = Vec::new();
            let mut waiting = Vec::new();
            let idx = plan.indices();
            let total = idx.len();
            for (k, i) in idx.enumerate() {
                match sample_on(&m, &plan, &shared, i) {
                    SampleStep::Done(r) => done.push(r),
                    SampleStep::Beyond(w) => waiting.push(*w),
                }
                p.call(k + 1, total);
            }
            (done, waiting)
        }
    };
    if !waiting.is_empty() && shared.partial {
        let n = waiting.len();
        KEPT_PARTS.with_borrow_mut(|k| k.push(KeptPart { key, done, waiting }));
        return to_json(&json!({ "waiting": n }));
    }
    for w in waiting {
        done.push(sample_beyond(&m, &plan, &shared, w).map_err(err)?);
    }
    done.sort_by_key(|r| r.sample);
    let (samples_csv, stages_csv) = rvlife::montecarlo::records_csv(&done);
    let meta = rvlife::output::mc_shards::ShardMeta {
        rvlife_version: env!("CARGO_PKG_VERSION").into(),
        plan,
        stage_hours: m.wear.stage_hours.clone(),
        config_toml: text.to_string(),
    };
    to_json(&json!({"meta": meta, "samples_csv": samples_csv, "stages_csv": stages_csv}))
}

/// The parts of [`montecarlo`]'s run of the config `text` ([`montecarlo_shard`]'s JSON, one
/// per part) merged by the library's merge (`rvlife::output::mc_shards::merge_parts`, as
/// `rvlife merge` does): [`montecarlo`]'s JSON, the same bytes as the run in one part.
///
/// # Errors
/// The config's message; parts that are not one run's (another config, seed or count, a
/// missing or repeated part; named `shards`) or not [`montecarlo_shard`]'s JSON.
#[wasm_bindgen(js_name = montecarloMerge)]
pub fn montecarlo_merge(text: &str, shards: Vec<String>) -> Result<String, JsError> {
    use rvlife::output::mc_shards::{merge_parts, parse_records, Part, ShardMeta};
    #[derive(serde::Deserialize)]
    struct Shard {
        meta: ShardMeta,
        samples_csv: String,
        stages_csv: String,
    }
    let m = static_model_kept(text)?;
    let parts = shards
        .iter()
        .enumerate()
        .map(|(k, json)| {
            let origin = format!("part {}", k + 1);
            let s: Shard =
                serde_json::from_str(json).map_err(|e| JsError::new(&format!("{origin}: {e}")))?;
            let records = parse_records(
                (&format!("{origin} samples.csv"), &s.samples_csv),
                (&format!("{origin} stages.csv"), &s.stages_csv),
            )
            .map_err(err)?;
            Ok(Part {
                origin,
                meta: s.meta,
                records,
            })
        })
        .collect::<Result<Vec<_>, JsError>>()?;
    let (meta, records) = merge_parts(parts).map_err(err)?;
    if meta.config_toml != text {
        return Err(JsError::new("the parts are another config's run"));
    }
    montecarlo_json(&m, &records)
}

/// The design search (`rvlife optimize`: one goal by the Latin hypercube, CMA-ES, the compass
/// search and Nelder-Mead; several by NSGA-II; docs/model.md section 19) of the config
/// `text`, then its follow-up (the best and base designs' studies and the sensitivity at the
/// best): `vary` a JSON list of `"KEY=LO:HI"` texts, `objective` the goals (`life`,
/// `b10[:N]`, `[max:]QUANTITY[@STAGE]`, comma-separated), `constraints` a JSON list of
/// `"Q<=V"` texts, at most `evaluations` candidates with `seed`, the config's own work budget.
/// `progress(done, total)` counts the candidates, then the follow-up's steps.
/// JSON `{candidates_csv, pareto_csv, optimum_toml, best, start, front, plots}`: the command
/// line's tables, the best design's config (`null`: none feasible), the best and base
/// candidates (`{candidate, values, goals, scores, ...}` or `null`), the front's candidate
/// numbers and the report's plots (`[{stem, title, x_label, y_label, against_hours, caption,
/// curves: [{name, points: [[x, y]], joined}]}]`, `rvlife::output::candidates::plots`).
///
/// # Errors
/// The config's message; a range, goal, constraint or the search's work refused by name
/// (`--vary`, `--objective`, `--constraint`, `--evaluations` or the key); a follow-up study's
/// failure.
#[wasm_bindgen]
pub fn optimize(
    text: &str,
    vary: &str,
    objective: &str,
    constraints: &str,
    evaluations: usize,
    seed: u64,
    progress: Option<js_sys::Function>,
) -> Result<String, JsError> {
    let list = |name: &str, json: &str| -> Result<Vec<String>, JsError> {
        serde_json::from_str(json).map_err(|e| {
            err(rvlife::Error::invalid(
                name,
                json,
                format!("a JSON list of texts ({e})"),
            ))
        })
    };
    let budget = rvlife::config::Config::from_toml_in(text, "page", None)
        .map_err(err)?
        .work_budget_minutes;
    let problem = rvlife::optimize::Problem::new(
        text,
        "page",
        None,
        budget,
        &list("--vary", vary)?,
        objective,
        &list("--constraint", constraints)?,
        rvlife::optimize::Settings { evaluations, seed },
    )
    .map_err(err)?;
    let p = Progress(progress);
    let outcome =
        rvlife::optimize::run(&problem, &|d, t, _| p.call(d, t), &|| false).map_err(err)?;
    let n = outcome.candidates.len();
    let follow = rvlife::optimize::follow_up(&problem, &outcome, &|d, t| p.call(n + d, n + t))
        .map_err(err)?;
    let (candidates_csv, pareto_csv) =
        rvlife::output::candidates::tables_csv(&problem, &outcome).map_err(err)?;
    let optimum = outcome
        .best
        .map(|i| problem.text_of(&outcome.candidates[i].values, false))
        .transpose()
        .map_err(err)?;
    let of = |i: Option<usize>| {
        i.map(|i| rvlife::output::candidates::candidate_json(&problem, &outcome.candidates[i]))
    };
    to_json(&answers::OptimizeView {
        candidates_csv,
        pareto_csv,
        optimum_toml: optimum,
        best: of(outcome.best),
        start: of(outcome.start),
        plots: rvlife::output::candidates::plots(&problem, &outcome, &follow),
        front: outcome.front,
    })
}
