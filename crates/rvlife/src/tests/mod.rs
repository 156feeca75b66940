//! The library's tests of physics that can fail (closed forms, conservation, invariants
//! scanned over crank angles and torques, limits, published numbers), inside the crate so that
//! they reach the analyses' internals; each file's own documentation says what it checks.

mod calibration;
mod clearance;
mod compliance;
mod disc_body;
mod dynamics;
mod errors;
mod fem;
mod flexible_dynamics;
mod friction;
mod life;
mod measured;
mod optimize;
mod parts;
mod physics;
mod pin_wear;
mod play;
mod selective;
mod single_stage;

/// The built-in example with `[reducer.structure] compliance_arcmin_per_knm = c`, validated.
pub(crate) fn example_with_structure_compliance(c: f64) -> crate::config::Model {
    crate::config::Config::from_toml_str(
        &crate::config::EXAMPLE_TOML.replace(
            "compliance_arcmin_per_knm = 0.0",
            &format!("compliance_arcmin_per_knm = {c}"),
        ),
        "test",
    )
    .unwrap()
    .validate()
    .unwrap()
}
