//! `rvlife efficiency`: the power losses and efficiency over output speed, torque and oil
//! temperature (docs/model.md section 18.4).

use serde::Serialize;

use super::{finite, worn_for, Spelling, Wear};
use crate::config::Model;
use crate::efficiency::{efficiency_map, OperatingPoint};
use crate::error::{Error, Result};

/// The default output speeds of the map, rpm (the catalogue's efficiency charts span about
/// 5-60 rpm at the output).
pub const DEFAULT_SPEEDS_RPM: [f64; 7] = [5.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0];

/// The default torques of the map, fractions of the rated torque.
pub const DEFAULT_TORQUE_FRACTIONS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

/// Most values of each of the map's axes.
const MAX_AXIS: usize = 100;

/// The efficiency map (`rvlife efficiency --json`).
#[derive(Debug, Clone, Serialize)]
pub struct EfficiencyResult {
    /// Rated output torque, N m.
    pub rated_torque_nm: f64,
    /// Output speed at the rated input speed, rpm.
    pub rated_output_speed_rpm: f64,
    /// Largest wear depth of the analysed profile, um.
    pub max_wear_um: f64,
    /// Crank angles per mesh cycle whose losses are averaged.
    pub samples_per_mesh_cycle: usize,
    /// The lubrication's friction model (`lambda` or `constant`).
    pub friction_model: &'static str,
    /// The oil's kinematic viscosity at 40 deg C, mm^2/s.
    pub oil_viscosity_40_mm2_per_s: f64,
    /// Every operating point, torque-major, then temperature, then speed.
    pub points: Vec<OperatingPoint>,
    /// At the rated torque and the rated output speed, at the config's oil temperature.
    pub at_rated: OperatingPoint,
}

/// Checks one axis of the map: 1 to 100 values, each finite and in `ok` (`what` says the
/// range in words).
fn axis(
    spelling: Spelling,
    key: &str,
    values: &[f64],
    ok: impl Fn(f64) -> bool,
    what: &str,
) -> Result<()> {
    if values.is_empty() || values.len() > MAX_AXIS {
        return Err(Error::invalid(
            spelling.name(key),
            values.len(),
            format!("must give 1 to {MAX_AXIS} values"),
        ));
    }
    for &v in values {
        finite(spelling, key, v)?;
        if !ok(v) {
            return Err(Error::invalid(spelling.name(key), v, what));
        }
    }
    Ok(())
}

/// The power losses and efficiency of `model` (on the profile `wear` says) at every output
/// speed of `speeds_rpm` (rpm; default [`DEFAULT_SPEEDS_RPM`]), output torque of `torques_nm`
/// (N m; default [`DEFAULT_TORQUE_FRACTIONS`] of the rated torque) and oil temperature of
/// `temperatures_c` (deg C; default the config's; with `[lubrication] heat_balance` each point
/// at its steady temperature instead), and at the rated point.
///
/// # Errors
/// [`Error::Invalid`] naming the argument for an empty or too long list, a speed outside
/// (0, 1e4] rpm, a torque of 0 or one the unworn stage cannot carry, a temperature outside
/// [-40, 150] deg C or given with the heat balance; solver failures; a heat balance that does
/// not settle.
pub fn efficiency(
    model: &Model,
    wear: Wear,
    speeds_rpm: Option<&[f64]>,
    torques_nm: Option<&[f64]>,
    temperatures_c: Option<&[f64]>,
    spelling: Spelling,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<EfficiencyResult> {
    let rated = model.rating.rated_torque;
    let speeds = speeds_rpm.map_or(DEFAULT_SPEEDS_RPM.to_vec(), <[f64]>::to_vec);
    let torques = torques_nm.map_or(
        DEFAULT_TORQUE_FRACTIONS.iter().map(|f| f * rated).collect(),
        <[f64]>::to_vec,
    );
    let lub = model.lubrication;
    if let (Some(t), Some(_)) = (temperatures_c, lub.heat) {
        return Err(Error::invalid(
            spelling.name("temperatures_c"),
            format!("{t:?}"),
            "cannot be given with [lubrication] heat_balance = true (the heat balance sets the \
             oil's temperature)",
        ));
    }
    let temperatures = temperatures_c.map_or(vec![lub.temperature_c], <[f64]>::to_vec);
    axis(
        spelling,
        "speeds_rpm",
        &speeds,
        |v| v > 0.0 && v <= 1e4,
        "must be an output speed in (0, 1e4] rpm",
    )?;
    axis(
        spelling,
        "torques_nm",
        &torques,
        |v| v != 0.0,
        "must not be 0 N m",
    )?;
    for &t in &torques {
        model.check_torque(&spelling.name("torques_nm"), t)?;
    }
    axis(
        spelling,
        "temperatures_c",
        &temperatures,
        |v| {
            let nu = lub.oil.kinematic_viscosity(v) * 1e6;
            (-40.0..=150.0).contains(&v) && (0.2..=1e6).contains(&nu)
        },
        "must be in [-40, 150] deg C, where the oil's viscosity is within ASTM D341's 0.2 to \
         1e6 mm^2/s",
    )?;
    let (staged, profile) = worn_for(model, wear, false, spelling, progress)?;
    let model: &Model = &staged;
    let red = &model.reducer;
    let samples = model.te.samples;
    let points = efficiency_map(
        red,
        &profile,
        &lub,
        &model.wear,
        &torques,
        &speeds,
        &temperatures,
        samples,
    )?;
    let rated_speed = model.rating.input_speed_rpm / red.ratio.abs();
    let at_rated = efficiency_map(
        red,
        &profile,
        &lub,
        &model.wear,
        &[rated],
        &[rated_speed],
        &[lub.temperature_c],
        samples,
    )?[0];
    Ok(EfficiencyResult {
        rated_torque_nm: rated,
        rated_output_speed_rpm: rated_speed,
        max_wear_um: profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6,
        samples_per_mesh_cycle: samples,
        friction_model: match lub.friction {
            crate::tribology::FrictionModel::Constant(_) => "constant",
            crate::tribology::FrictionModel::Lambda { .. } => "lambda",
        },
        oil_viscosity_40_mm2_per_s: lub.oil.viscosity_40 * 1e6,
        points,
        at_rated,
    })
}
