//! `[wear]`: the Archard wear model, its coefficient, the working-hour stages and the
//! profile-update schedule (docs/model.md section 7).

use serde::{Deserialize, Serialize};

use super::range::{check, whole, Range};
use crate::error::{Error, Result};
use crate::wear::{BearingWearParams, PinTurning, RunningIn, WearModelKind, WearParams};

/// `[wear]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearConfig {
    /// `"flodin"` (default: sliding from the real kinematics, profile updates) or `"paper"`
    /// (eqs 11-20 as printed, Li's forces, no updates, TE from the uniform maximum wear).
    #[serde(default = "default_wear_model")]
    pub model: String,
    /// Dimensional Archard coefficient `k = K/H`, mm^3/(N m). Range: (0, 1e6] mm^3/(N m).
    #[serde(default)]
    pub archard_coefficient_mm3_per_n_m: Option<f64>,
    /// The same coefficient in m^2/N (= 1/Pa); give exactly one of the two. Range: (0, 1e-3]
    /// m^2/N.
    #[serde(default)]
    pub archard_coefficient_m2_per_n: Option<f64>,
    /// Working-hour stages at which results are reported, h. Range: 1 to 1000 stages, each in
    /// [0, 1e7] h, strictly increasing.
    pub stage_hours: Vec<f64>,
    /// Profile update step, h (0, the default: wear rate from the new profile only). Range:
    /// [0, 1e7] h, at most 100 000 updates to the last stage.
    #[serde(default)]
    pub profile_update_hours: f64,
    /// Largest wear increment between profile updates, um: the update step is shortened so that
    /// no point wears more than this between two rebuilds of the load sharing. Range: [0.01,
    /// 1000] um.
    #[serde(default = "default_max_step")]
    pub max_wear_step_um: f64,
    /// Crank angles solved per mesh cycle (wear map resolution = pins x this). Range: whole
    /// number, 2 to 1000.
    #[serde(default = "default_steps")]
    pub crank_steps_per_mesh_cycle: i64,
    /// Fraction of the disc-pin sliding taken up by pins turning in their grooves, 0..1
    /// (0: pins do not turn, the conservative default). Range: [0, 1].
    #[serde(default)]
    pub pin_rolling_fraction: f64,
    /// How the pins turn in their grooves: `"fixed"` (default: held, or turning by
    /// `pin_rolling_fraction`) or `"balance"` (the rotation from the balance of the disc's and
    /// the groove's friction moments, with Carter's micro-slip where a pin rolls;
    /// docs/model.md section 7.12; `flodin` model only).
    #[serde(default = "default_pin_turning")]
    pub pin_turning: String,
    /// Friction coefficient of the disc-pin contacts, read with `pin_turning = "balance"`
    /// (default 0.1: an **estimate** for boundary-lubricated hardened steel). Range: (0, 1].
    #[serde(default = "default_pin_friction")]
    pub pin_friction_coefficient: f64,
    /// Friction coefficient of a pin in its housing groove, read with `pin_turning =
    /// "balance"` (default 0.05: an **estimate** for a greased conformal contact). Range:
    /// (0, 1].
    #[serde(default = "default_groove_friction")]
    pub groove_friction_coefficient: f64,
    /// Overlap ratio `eps_a` of the paper's sliding distance (`paper` model only). Range:
    /// (0, 100].
    #[serde(default = "default_overlap")]
    pub overlap_ratio: f64,
    /// Archard coefficient of the crank bearings' roller-raceway contacts, mm^3/(N m) (default
    /// 0: the bearings keep their clearance; docs/model.md section 7.9). Range: [0, 1e6]
    /// mm^3/(N m).
    #[serde(default)]
    pub bearing_archard_coefficient_mm3_per_n_m: f64,
    /// Archard coefficient of the pins' side of the disc-pin contacts, mm^3/(N m) (default 0:
    /// the pins do not wear; docs/model.md section 7.11; `flodin` model only). Range:
    /// [0, 1e6] mm^3/(N m).
    #[serde(default)]
    pub pin_archard_coefficient_mm3_per_n_m: f64,
    /// Slip ratio of the bearings' rolling contacts, sliding per rolled distance (default
    /// 0.02: an **estimate** for lightly loaded roller bearings). Range: [0, 1].
    #[serde(default = "default_slip")]
    pub bearing_slip_ratio: f64,
    /// Running-in: the disc's Archard coefficient when new over its steady value (default 1:
    /// no running-in; docs/model.md section 7.10). Range: [1, 1000].
    #[serde(default = "default_running_in_factor")]
    pub running_in_factor: f64,
    /// Running-in: the time constant over which the coefficient falls to its steady value, h
    /// (read when `running_in_factor` > 1). Range: (0, 1e6] h.
    #[serde(default = "default_running_in_hours")]
    pub running_in_hours: f64,
}

fn default_pin_turning() -> String {
    "fixed".into()
}
fn default_pin_friction() -> f64 {
    0.1
}
fn default_groove_friction() -> f64 {
    0.05
}

fn default_running_in_factor() -> f64 {
    1.0
}
fn default_running_in_hours() -> f64 {
    200.0
}

fn default_slip() -> f64 {
    0.02
}

fn default_wear_model() -> String {
    "flodin".into()
}
fn default_max_step() -> f64 {
    1.0
}
fn default_steps() -> i64 {
    18
}
fn default_overlap() -> f64 {
    1.3
}

impl WearConfig {
    /// The wear model's parameters, SI.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and its range.
    pub fn validate(&self) -> Result<WearParams> {
        let w = self;
        let wear_model = match w.model.as_str() {
            "flodin" => WearModelKind::Flodin,
            "paper" => WearModelKind::Paper,
            other => {
                return Err(Error::invalid(
                    "wear.model",
                    format!("\"{other}\""),
                    "must be \"flodin\" or \"paper\"",
                ))
            }
        };
        let archard_key = if w.archard_coefficient_m2_per_n.is_some() {
            "wear.archard_coefficient_m2_per_n"
        } else {
            "wear.archard_coefficient_mm3_per_n_m"
        };
        let archard = match (
            w.archard_coefficient_mm3_per_n_m,
            w.archard_coefficient_m2_per_n,
        ) {
            (Some(k), None) => {
                check(
                    "wear.archard_coefficient_mm3_per_n_m",
                    k,
                    Range::positive(1e6, "mm^3/(N m)"),
                )? * 1e-9
            }
            (None, Some(k)) => check(
                "wear.archard_coefficient_m2_per_n",
                k,
                Range::positive(1e-3, "m^2/N"),
            )?,
            _ => {
                return Err(Error::invalid(
                    "wear.archard_coefficient_mm3_per_n_m",
                    "missing or given twice",
                    "give exactly one of archard_coefficient_mm3_per_n_m and \
                     archard_coefficient_m2_per_n",
                ))
            }
        };
        if w.stage_hours.is_empty() || w.stage_hours.len() > 1000 {
            return Err(Error::invalid(
                "wear.stage_hours",
                format!("{} entries", w.stage_hours.len()),
                "must list 1 to 1000 stages",
            ));
        }
        let mut prev = -1.0;
        for (i, &h) in w.stage_hours.iter().enumerate() {
            let field = format!("wear.stage_hours[{i}]");
            check(&field, h, Range::closed(0.0, 1e7, "h"))?;
            if h <= prev {
                return Err(Error::invalid(field, h, "stages must increase strictly"));
            }
            prev = h;
        }
        let update_hours = check(
            "wear.profile_update_hours",
            w.profile_update_hours,
            Range::closed(0.0, 1e7, "h (0: no profile updates)"),
        )?;
        if update_hours > 0.0 && prev / update_hours > 100_000.0 {
            return Err(Error::invalid(
                "wear.profile_update_hours",
                update_hours,
                "would need more than 100000 profile updates; use a larger step",
            ));
        }
        let max_wear_step = check(
            "wear.max_wear_step_um",
            w.max_wear_step_um,
            Range::closed(0.01, 1000.0, "um"),
        )? * 1e-6;
        let wear_steps = whole(
            "wear.crank_steps_per_mesh_cycle",
            w.crank_steps_per_mesh_cycle,
            2,
            1000,
        )?;
        let pin_rolling_fraction = check(
            "wear.pin_rolling_fraction",
            w.pin_rolling_fraction,
            Range::closed(0.0, 1.0, ""),
        )?;
        let pin_turning = match w.pin_turning.as_str() {
            "fixed" => PinTurning::Fixed,
            "balance" => PinTurning::Balance {
                pin_friction: check(
                    "wear.pin_friction_coefficient",
                    w.pin_friction_coefficient,
                    Range::positive(1.0, ""),
                )?,
                groove_friction: check(
                    "wear.groove_friction_coefficient",
                    w.groove_friction_coefficient,
                    Range::positive(1.0, ""),
                )?,
            },
            other => {
                return Err(Error::invalid(
                    "wear.pin_turning",
                    format!("\"{other}\""),
                    "must be \"fixed\" or \"balance\"",
                ))
            }
        };
        if pin_turning != PinTurning::Fixed {
            if pin_rolling_fraction > 0.0 {
                return Err(Error::invalid(
                    "wear.pin_rolling_fraction",
                    pin_rolling_fraction,
                    "must be 0 with wear.pin_turning = \"balance\" (the balance sets how the \
                     pins turn)",
                ));
            }
            if wear_model == WearModelKind::Paper {
                return Err(Error::invalid(
                    "wear.pin_turning",
                    "\"balance\"",
                    "must be \"fixed\" with wear.model = \"paper\" (the paper's sliding is \
                     that of fixed pins)",
                ));
            }
        }
        let overlap_ratio = check(
            "wear.overlap_ratio",
            w.overlap_ratio,
            Range::positive(100.0, ""),
        )?;
        let bearings = BearingWearParams {
            archard: check(
                "wear.bearing_archard_coefficient_mm3_per_n_m",
                w.bearing_archard_coefficient_mm3_per_n_m,
                Range::non_negative(1e6, "mm^3/(N m)"),
            )? * 1e-9,
            slip: check(
                "wear.bearing_slip_ratio",
                w.bearing_slip_ratio,
                Range::closed(0.0, 1.0, ""),
            )?,
        };
        let pin_archard = check(
            "wear.pin_archard_coefficient_mm3_per_n_m",
            w.pin_archard_coefficient_mm3_per_n_m,
            Range::non_negative(1e6, "mm^3/(N m)"),
        )? * 1e-9;
        if pin_archard > 0.0 && wear_model == WearModelKind::Paper {
            return Err(Error::invalid(
                "wear.pin_archard_coefficient_mm3_per_n_m",
                w.pin_archard_coefficient_mm3_per_n_m,
                "must be 0 with wear.model = \"paper\" (the paper's model wears the disc only)",
            ));
        }
        let running_in = RunningIn {
            factor: check(
                "wear.running_in_factor",
                w.running_in_factor,
                Range::closed(1.0, 1e3, ""),
            )?,
            hours: check(
                "wear.running_in_hours",
                w.running_in_hours,
                Range::positive(1e6, "h"),
            )?,
        };
        Ok(WearParams {
            running_in,
            bearings,
            model: wear_model,
            archard,
            archard_key,
            stage_hours: w.stage_hours.clone(),
            update_hours,
            max_wear_step,
            crank_steps: wear_steps,
            pin_rolling_fraction,
            pin_turning,
            pin_archard,
            overlap_ratio,
        })
    }
}
