//! Wear of the crank bearings as growth of their radial clearance (docs/model.md section 7.9).
//!
//! **Model.** Archard on the roller-raceway contacts of the load distribution (the approach of
//! Lubricants 2025, 13(8), 362, section 3.2). Each roller passing a point of a raceway slides
//! `xi 2 b` over it (`xi`: the slip ratio of the rolling contact, `2 b` the Hertz contact
//! width) under the mean pressure `Q/(2 b l)`, so the point loses `k xi Q / l` per passage,
//! whatever the width; a point of a roller's surface loses the same per passage through a
//! contact. With the rings turning at `omega` relative to each other and `gamma = D cos(alpha)
//! / d_m` (roller diameter `D`, pitch diameter `d_m`; Harris and Kotzalas, *Rolling Bearing
//! Analysis*, 5th ed., vol. 1, ch. 8):
//!
//! - a point of the outer and of the inner raceway on the load line is overrolled
//!   `Z |omega| (1 -+ gamma) / (4 pi)` times per second (the cage at `(1 - gamma)/2` of
//!   `omega` from the outer ring): together `Z |omega| / (2 pi)` passages of the most loaded
//!   roller `Q_max`, whatever the diameter;
//! - each roller spins at `(d_m / 2 D) (1 - gamma^2) |omega|` relative to the cage and meets
//!   both raceways once a turn, so its diameter shrinks by `4 k xi Q_mean / l` per turn, evenly
//!   round it (`Q_mean = sum Q_i / Z`, the rollers' time-mean load as they orbit). Small
//!   rollers spin faster and shrink faster.
//!
//! The clearance along the load grows by both raceways' depth and the rollers' diameter loss:
//!
//! ```text
//! dc/dt = k xi |omega| / (2 pi l) [Z Q_max + 2 (d_m/D) (1 - gamma^2) sum Q_i / Z]
//! ```
//!
//! with `Q_max` the most loaded roller (the roller under the load, [`RadialBearing::most_loaded_roller`]),
//! averaged over the mesh cycle and over the load spectrum (time fractions, each level at its
//! speed). Each bearing kind takes its most loaded bearing's rate. The rates come from the new
//! reducer's loads and are constant in time: under a constant load the clearance grows
//! linearly.

use crate::error::{Error, Result};
use crate::reducer::{BearingLaw, RadialBearing, Reducer};
use crate::statics::StaticAnalysis;

use super::WearInputs;

/// `[wear]`'s crank-bearing keys, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BearingWearParams {
    /// Archard coefficient of the roller-raceway contacts, m^2/N (0: the bearings do not
    /// wear).
    pub archard: f64,
    /// Slip ratio of the rolling contacts, the sliding distance per rolled distance.
    pub slip: f64,
}

/// Clearance growth of the crank bearings, m/h.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BearingWearRates {
    /// Each crank-disc bearing (single-stage: each eccentric bearing).
    pub disc: f64,
    /// Each crank-carrier bearing.
    pub carrier: f64,
}

/// Clearance growth (m/s) of `bearing` carrying the radial load `force` (N) per row at the
/// relative ring speed `omega` (rad/s), Archard coefficient `archard` (m^2/N) and slip
/// `slip`: the raceways' `k xi Q_max Z |omega| / (2 pi l)` plus the rollers'
/// `k xi |omega| / (2 pi l) 2 (d_m/D) (1 - gamma^2) sum Q_i / Z` (module docs). Zero for a
/// linear bearing.
pub fn clearance_growth(
    bearing: &RadialBearing,
    force: f64,
    omega: f64,
    archard: f64,
    slip: f64,
) -> f64 {
    let BearingLaw::Rollers {
        count,
        length,
        diameter,
        pitch_diameter,
        contact_angle,
        ..
    } = bearing.law
    else {
        return 0.0;
    };
    let q = bearing.roller_loads_for(force).unwrap_or_default();
    let (q_max, q_sum) = (q.first().copied().unwrap_or(0.0), q.iter().sum::<f64>());
    let z = count as f64;
    let gamma = diameter * contact_angle.cos() / pitch_diameter;
    let rollers = 2.0 * pitch_diameter / diameter * (1.0 - gamma * gamma) * q_sum / z;
    archard * slip * (z * q_max + rollers) * omega.abs() / (std::f64::consts::TAU * length)
}

/// Clearance growth rates (m/h) of the crank bearings of `inputs.reducer` with the unworn disc
/// `profile`, under `inputs.load` (each level's torque solved at `samples` crank angles of a
/// mesh cycle), with the coefficients of `inputs.wear.bearings`.
///
/// # Errors
/// [`Error::Invalid`] naming the key if the bearings wear but are linear or the discs are held
/// rigidly (no bearing loads); the solver's errors.
pub fn bearing_wear_rates(
    inputs: &WearInputs,
    profile: &crate::geometry::Profile,
    samples: usize,
) -> Result<BearingWearRates> {
    let p = inputs.wear.bearings;
    if p.archard <= 0.0 {
        return Ok(BearingWearRates::default());
    }
    let red: &Reducer = inputs.reducer;
    let rollers = |b: &RadialBearing| matches!(b.law, BearingLaw::Rollers { .. });
    if !rollers(&red.bearings.disc) || !rollers(&red.bearings.carrier) {
        return Err(Error::invalid(
            "wear.bearing_archard_coefficient_mm3_per_n_m",
            format!("{:e}", p.archard * 1e9),
            "needs reducer.bearings.model = \"rollers\" (the wear acts on the rollers' contacts)",
        ));
    }
    if red.support != crate::reducer::Support::Bearings {
        return Err(Error::invalid(
            "wear.bearing_archard_coefficient_mm3_per_n_m",
            format!("{:e}", p.archard * 1e9),
            "needs contact.support = \"bearings\" (rigid support has no bearing loads)",
        ));
    }
    let sa = StaticAnalysis::new(red, profile)?;
    let phis = crate::te::mesh_cycle_angles(red.geometry.pins, samples);
    let discs = red.discs();
    let per_crank = 1 + discs;
    let mut rates = BearingWearRates::default();
    for level in inputs.load {
        if level.torque == 0.0 || level.fraction <= 0.0 {
            continue;
        }
        let omega = level.speed_rpm * std::f64::consts::TAU / 60.0 * red.bearing_speed_ratio();
        let sols = sa.solve_sequence(&phis, level.torque)?;
        let (mut disc, mut carrier) = (vec![0.0; red.cranks.max(1) * discs], vec![0.0; red.cranks]);
        for sol in &sols {
            let f = sa.bearing_forces(sol);
            if red.cranks == 0 {
                for (d, fd) in f.iter().enumerate().take(discs) {
                    disc[d] += clearance_growth(&red.bearings.disc, *fd, omega, p.archard, p.slip);
                }
                continue;
            }
            for k in 0..red.cranks {
                let rows = match red.bearings.carrier.law {
                    BearingLaw::Rollers { rows, .. } => rows as f64,
                    BearingLaw::Linear { .. } => 1.0,
                };
                carrier[k] += clearance_growth(
                    &red.bearings.carrier,
                    f[k * per_crank] / rows,
                    omega,
                    p.archard,
                    p.slip,
                );
                for d in 0..discs {
                    disc[k * discs + d] += clearance_growth(
                        &red.bearings.disc,
                        f[k * per_crank + 1 + d],
                        omega,
                        p.archard,
                        p.slip,
                    );
                }
            }
        }
        let mean = |v: &[f64]| v.iter().copied().fold(0.0, f64::max) / sols.len() as f64;
        rates.disc += level.fraction * mean(&disc) * 3600.0;
        rates.carrier += level.fraction * mean(&carrier) * 3600.0;
    }
    Ok(rates)
}
