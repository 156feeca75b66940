//! The JSON the module's commands answer with, where it is more than one library result: each
//! a type, so that the page's TypeScript types are generated from it with the library's
//! result types (the test `generated_typescript_is_current`, ts-rs). Keys and units are the
//! command line's.

use rvlife::api::HysteresisResult;
use rvlife::config::schema::KeyDoc;
use rvlife::dynamics::DynamicsSummary;
use rvlife::montecarlo::{LifeDistribution, Percentiles};
use rvlife::output::candidates::{CandidateSummary, Plot};
use rvlife::study::Summary;
use serde::Serialize;

/// A built-in reducer (`rvlife example --list`).
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct Preset {
    /// Its name (`rv-40e`).
    pub name: &'static str,
    /// One line on what it is and where its data come from.
    pub summary: &'static str,
}

/// `inspect`: the command line's message for the text (`null` if valid) and its keys
/// (`null` if the text does not parse).
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct Inspection {
    /// The first bad key, its value and its allowed range; or the parse error.
    pub message: Option<String>,
    /// Every key of the config with its value, comment, unit and range.
    pub keys: Option<Vec<KeyDoc>>,
}

/// The mean hysteresis curve's points the catalogue quantities are read between
/// (`rvlife::te::TwistTable::catalogue_points`, docs/model.md section 6.3), each `[torque
/// N m, twist arcmin]`.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct CataloguePoints {
    /// The midpoints at `-T_m` and at `+T_m`, the measuring torque: their twists differ by
    /// the lost motion.
    pub lost_motion: [[f64; 2]; 2],
    /// The secant `b/a` from the loading branch at `+T_m` to `+T_r`: torque over twist
    /// between them is the torsional stiffness.
    pub torsional_stiffness: [[f64; 2]; 2],
}

/// `hysteresis`: the command line's JSON (`rvlife hysteresis --json`) and the catalogue's
/// points, for the page to mark them on the curve.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct HysteresisView {
    /// The command line's result.
    #[serde(flatten)]
    pub result: HysteresisResult,
    /// Where the mean curve's lost motion and torsional stiffness are read.
    pub catalogue_points: CataloguePoints,
}

/// `study` and `studyAssemble`: the study's overview.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct StudyOverview {
    /// `summary.json` of `rvlife run`.
    pub summary: Summary,
    /// The one-line verdict against `[life]`.
    pub verdict: String,
    /// The names of the results' data files, in order (`summary.json`, `stages.csv`, ...,
    /// `profiles/worn_<H>h.dxf`).
    pub files: Vec<String>,
}

/// `dynamics`: the command line's summary (`rvlife dynamics --json`) and the time series at
/// the output interval.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct DynamicsView {
    /// The summary over the TE window.
    pub summary: DynamicsSummary,
    /// Time, s.
    pub time_s: Vec<f64>,
    /// Dynamic transmission error, arcmin.
    pub te_arcmin: Vec<f64>,
    /// Output speed, deg/s.
    pub output_speed_deg_s: Vec<f64>,
}

/// One Monte Carlo sample's life.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct SampleLife {
    /// Sample index, from 0.
    pub sample: usize,
    /// `ok`, or `failed: <reason>`.
    pub status: String,
    /// Accuracy life, h (`null`: beyond the horizon, or no thresholds).
    pub accuracy_life_h: Option<f64>,
    /// The `[life]` key of the threshold crossed first.
    pub limited_by: Option<String>,
}

/// `montecarlo` and `montecarloMerge` (`rvlife montecarlo`): its tables as text, the life
/// distribution and percentiles of its `summary.json`, every sample's life, the horizon, the
/// report's verdict and the reliability curve.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct MonteCarloView {
    /// `samples.csv`.
    pub samples_csv: String,
    /// `stages.csv`.
    pub stages_csv: String,
    /// The accuracy-life distribution over the samples analysed.
    pub life: LifeDistribution,
    /// Each accuracy quantity's percentiles at each stage.
    pub percentiles: Vec<Percentiles>,
    /// Every sample's life, in sample order.
    pub records: Vec<SampleLife>,
    /// Beyond it a life is censored, h.
    pub horizon_h: f64,
    /// B10, B50, the fraction within spec and the samples analysed, one sentence.
    pub verdict: String,
    /// `[working hours, fraction within spec]`, a step curve from `(0, 1)`
    /// (`rvlife::montecarlo::reliability`).
    pub reliability: Vec<(f64, f64)>,
}

/// `optimize` (`rvlife optimize`): its tables as text, the best design's config (`null`: none
/// feasible), the best and base candidates, the Pareto front's candidate numbers and the
/// report's plots.
#[derive(Serialize)]
#[cfg_attr(test, derive(ts_rs::TS))]
pub struct OptimizeView {
    /// `candidates.csv`.
    pub candidates_csv: String,
    /// `pareto.csv`.
    pub pareto_csv: String,
    /// `optimum.toml`.
    pub optimum_toml: Option<String>,
    /// The best feasible candidate.
    pub best: Option<CandidateSummary>,
    /// The base design's candidate.
    pub start: Option<CandidateSummary>,
    /// The front's candidate numbers.
    pub front: Vec<usize>,
    /// The report's plots.
    pub plots: Vec<Plot>,
}
