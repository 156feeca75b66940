//! The study's results: its stages, wear history and accuracy life, the verdict and
//! `summary.json`.

use serde::Serialize;

use super::stage::Stage;
use crate::config::Model;
use crate::quantities::{AccuracyPoint, StageSummary};
use crate::units::ARCMIN_PER_RAD;
use crate::wear::{ValidityLimit, WearHistory, WearModelKind};

/// Results of the whole study.
#[derive(Debug, Clone)]
pub struct Study {
    /// The model it ran.
    pub model: Model,
    /// The wear history.
    pub wear: WearHistory,
    /// Stages.
    pub stages: Vec<Stage>,
    /// The accuracy life against `[life]` (when thresholds are set).
    pub life: Option<crate::life::AccuracyLife>,
    /// Each part's share of the new reducer's elastic twist at the rated torque, mean over a
    /// mesh cycle (docs/model.md section 5.9; empty for the paper's rigid support).
    pub twist_shares: Vec<crate::statics::TwistShare>,
}

/// Comparison with the paper's headline numbers (docs/model.md section 16).
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct PaperComparison {
    /// Slope of the mean STE against the maximum wear, arcmin per 10 um (least squares through
    /// the origin over the stages).
    pub ste_per_10um_arcmin: f64,
    /// Mean STE at the last stage, arcmin.
    pub ste_last_stage_arcmin: f64,
    /// Paper: rigid-body STE mean at 10 um wear (Adams), arcmin.
    pub paper_ste_at_10um_arcmin: f64,
    /// Paper: largest rigid STE over the study (6450 h), arcmin.
    pub paper_ste_max_arcmin: f64,
    /// Uniform-offset estimate per side, `10 um / (a (Zp + Z1/Z2))`, arcmin
    /// (docs/model.md section 6).
    pub uniform_offset_per_10um_arcmin: f64,
    /// Paper: rigid-body DTE mean at 10 um wear under the sinusoidal load (Adams), arcmin.
    pub paper_dte_at_10um_arcmin: f64,
    /// Paper: largest rigid DTE over the study (6450 h), arcmin.
    pub paper_dte_max_arcmin: f64,
    /// Paper: rigid-flexible STE mean at 10 um wear (Adams, disc as a modal FE body), arcmin.
    pub paper_flexible_ste_at_10um_arcmin: f64,
    /// Paper: largest rigid-flexible STE over the study (7500 h), arcmin.
    pub paper_flexible_ste_max_arcmin: f64,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS), ts(rename = "StudySummary"))]
pub struct Summary {
    /// rvlife version.
    pub rvlife_version: &'static str,
    /// Overall ratio `i_H`.
    pub ratio: f64,
    /// Wear model.
    pub wear_model: WearModelKind,
    /// Archard coefficient, mm^3/(N m).
    pub archard_coefficient_mm3_per_n_m: f64,
    /// Rated torque, N m.
    pub rated_torque_nm: f64,
    /// Torque of the loaded TE, N m.
    pub loaded_te_torque_nm: f64,
    /// Mesh cycles per working hour of each tooth at the nominal input speed.
    pub mesh_cycles_per_hour: f64,
    /// Wear-rate evaluations (profile updates + 1).
    pub wear_rate_evaluations: usize,
    /// Stages (up to the validity limit).
    pub stages: Vec<StageSummary>,
    /// Where the model leaves its validity, when it does before the last stage: the stages
    /// from there on are not reported.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub validity_limit: Option<ValidityLimit>,
    /// The accuracy life against `[life]` (when thresholds are set).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub accuracy_life: Option<crate::life::AccuracyLife>,
    /// Each part's share of the new reducer's elastic twist at the rated torque
    /// (docs/model.md section 5.9): part, share (0..1), twist (arcmin).
    pub twist_shares: Vec<serde_json::Value>,
    /// The measured profile's fit (when `cycloid.measured_profile` is set): file, points, RMS
    /// and largest residual, um.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub measured_profile_fit: Option<serde_json::Value>,
    /// Against the paper: only for the paper's reducer as printed (its stage, unmodified, no
    /// measured profile), like for like.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub paper_comparison: Option<PaperComparison>,
}

/// Whether `m`'s disc is the paper's as printed (its stage, no modification, no measured
/// profile; docs/model.md section 16): the only reducer compared with the paper's numbers.
pub(crate) fn is_papers_reducer(m: &crate::config::Model) -> bool {
    crate::config::Config::paper()
        .cycloid
        .validate()
        .is_ok_and(|(geometry, modification)| {
            m.cycloid.geometry == geometry
                && m.cycloid.modification == modification
                && m.cycloid.measured.is_none()
        })
}

impl Study {
    /// The study's verdict in one line ([`crate::life::verdict`]: the accuracy life and what
    /// limits it against its spec, or the hours within spec, with the duty), as the console and
    /// the report give it first.
    pub fn verdict(&self) -> String {
        crate::life::verdict(
            &self.model.life,
            self.life.as_ref(),
            self.stages
                .last()
                .map(|s| AccuracyPoint::of(&s.summary))
                .as_ref(),
            &self.model.load.levels,
        )
    }

    /// The `summary.json` content.
    pub fn summary(&self) -> Summary {
        let m = &self.model;
        let stages: Vec<StageSummary> = self.stages.iter().map(|s| s.summary.clone()).collect();
        let (sxy, sxx) = stages.iter().fold((0.0, 0.0), |(a, b), s| {
            (
                a + s.max_wear_um * s.ste_mean_arcmin,
                b + s.max_wear_um.powi(2),
            )
        });
        let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
        Summary {
            rvlife_version: env!("CARGO_PKG_VERSION"),
            ratio: m.reducer.ratio,
            wear_model: m.wear.model,
            archard_coefficient_mm3_per_n_m: m.wear.archard * 1e9,
            rated_torque_nm: m.rating.rated_torque,
            loaded_te_torque_nm: m.te.loaded_torque,
            mesh_cycles_per_hour: m.reducer.mesh_cycles_per_hour(m.rating.input_speed_rpm),
            wear_rate_evaluations: self.wear.rate_evaluations(),
            validity_limit: self.wear.limit.clone(),
            accuracy_life: self.life.clone(),
            twist_shares: self
                .twist_shares
                .iter()
                .map(|s| {
                    serde_json::json!({
                        "part": s.part,
                        "share": s.share,
                        "twist_arcmin": s.twist * ARCMIN_PER_RAD,
                    })
                })
                .collect(),
            measured_profile_fit: m.cycloid.measured.as_ref().map(|x| {
                serde_json::json!({
                    "source": x.source.display().to_string(),
                    "points": x.points,
                    "fit_rms_um": x.fit_rms * 1e6,
                    "fit_max_um": x.fit_max * 1e6,
                })
            }),
            paper_comparison: is_papers_reducer(m).then(|| PaperComparison {
                ste_per_10um_arcmin: slope * 10.0,
                ste_last_stage_arcmin: stages.last().map_or(0.0, |s| s.ste_mean_arcmin),
                paper_ste_at_10um_arcmin: 0.5351,
                paper_ste_max_arcmin: 4.11,
                uniform_offset_per_10um_arcmin: 10e-6 / m.cycloid.geometry.disc_pitch_radius()
                    * m.reducer.twist_factor()
                    * ARCMIN_PER_RAD,
                paper_dte_at_10um_arcmin: 0.2278,
                paper_dte_max_arcmin: 3.51,
                paper_flexible_ste_at_10um_arcmin: 1.7342,
                paper_flexible_ste_max_arcmin: 6.77,
            }),
            stages,
        }
    }
}
