//! `rvlife efficiency`: the console's table of the efficiency map.

use rvlife::api::EfficiencyResult;

/// Refuses an `--out` file that exists unless `force`, before any work.
///
/// # Errors
/// [`rvlife::Error::Invalid`] naming `--out`.
pub(crate) fn check_out(out: Option<&std::path::Path>, force: bool) -> rvlife::Result<()> {
    match out {
        Some(path) if path.exists() && !force => Err(rvlife::Error::invalid(
            "--out",
            path.display(),
            "exists; give --force to replace it",
        )),
        _ => Ok(()),
    }
}

/// Prints the rated point's balance, then one row per operating point.
pub(crate) fn print(r: &EfficiencyResult) {
    let a = &r.at_rated;
    say!(
        "at the rated point ({:.0} N m, {:.1} rpm output, oil at {:.0} deg C): efficiency {:.1} %, losses {:.1} W of {:.1} W in (disc-pin {:.1}, grooves {:.1}, crank bearings {:.1}, gear meshes {:.1}); disc-pin lambda {:.2} (least {:.2}), friction coefficient {:.3}",
        a.torque_nm,
        a.output_speed_rpm,
        a.temperature_c,
        100.0 * a.efficiency,
        a.loss_w(),
        a.input_power_w,
        a.loss_disc_pins_w,
        a.loss_pin_grooves_w,
        a.loss_crank_bearings_w,
        a.loss_gear_meshes_w,
        a.lambda_mean,
        a.lambda_min,
        a.pin_friction_coefficient
    );
    say!(
        "{:>10} {:>9} {:>7} {:>12} {:>10} {:>9} {:>9} {:>9} {:>9} {:>8}",
        "torque_Nm",
        "speed_rpm",
        "oil_C",
        "efficiency_%",
        "loss_W",
        "pins_W",
        "grooves_W",
        "bearing_W",
        "meshes_W",
        "lambda"
    );
    for p in &r.points {
        say!(
            "{:>10.1} {:>9.1} {:>7.1} {:>12.2} {:>10.2} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>8.3}",
            p.torque_nm,
            p.output_speed_rpm,
            p.temperature_c,
            100.0 * p.efficiency,
            p.loss_w(),
            p.loss_disc_pins_w,
            p.loss_pin_grooves_w,
            p.loss_crank_bearings_w,
            p.loss_gear_meshes_w,
            p.lambda_mean
        );
    }
}
