//! The reducer's power losses and efficiency (docs/model.md section 18.4): Coulomb friction at
//! the disc-pin contacts and in the pins' grooves with the coefficient of the contact's oil
//! film, Palmgren's friction moments of the crank bearings, and ISO/TR 14179-2's loss of the
//! sun-planet meshes, each on the loads of the frictionless static analysis over a mesh cycle.
//!
//! The friction forces do not change the normal loads they are computed from (the loads are
//! the frictionless equilibrium's): the usual approach of cycloid-drive efficiency models
//! (e.g. J. W. Sensinger, "Efficiency of high-sensitivity gear trains, such as cycloid
//! drives", J. Mech. Des. 135(7), 2013), first order in the friction coefficient.

use std::f64::consts::TAU;

use serde::Serialize;

use crate::error::Result;
use crate::geometry::Profile;
use crate::reducer::{BearingLaw, Drive, Reducer};
use crate::statics::{StaticAnalysis, StaticSolution};
use crate::tribology::{palmgren_moment, pin_dissipation, Lubrication, SpurMesh};
use crate::wear::{contact_kinematics, entrainment_speed, WearParams};

/// The frictionless loads of one output torque over a mesh cycle, from which the losses at
/// any speed and oil follow ([`mesh_cycle_loads`]).
#[derive(Debug, Clone)]
pub struct MeshCycleLoads {
    /// Output torque, N m.
    pub torque: f64,
    /// The static solutions at the crank angles of a mesh cycle.
    pub solutions: Vec<StaticSolution>,
    /// Per solution, the crank bearings' radial forces (N, in the order of
    /// `StaticAnalysis::bearing_forces`: per crank its crank-carrier pair, then its crank-disc
    /// bearing of each disc; empty with rigid support).
    pub bearing_forces: Vec<Vec<f64>>,
}

/// The static solutions of the reducer `red` on `profile` under the output torque `torque`
/// (N m) at `samples` crank angles of a mesh cycle, with the bearing forces.
///
/// # Errors
/// The static analysis's.
pub fn mesh_cycle_loads(
    red: &Reducer,
    profile: &Profile,
    torque: f64,
    samples: usize,
) -> Result<MeshCycleLoads> {
    let sa = StaticAnalysis::new(red, profile)?;
    let phis = crate::te::mesh_cycle_angles(red.geometry.pins, samples);
    let solutions = sa.solve_sequence(&phis, torque)?;
    let bearing_forces = solutions.iter().map(|s| sa.bearing_forces(s)).collect();
    Ok(MeshCycleLoads {
        torque,
        solutions,
        bearing_forces,
    })
}

/// The power balance of the reducer at one operating point, mean over a mesh cycle (powers W).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OperatingPoint {
    /// Output speed, rpm.
    pub output_speed_rpm: f64,
    /// Output torque, N m.
    pub torque_nm: f64,
    /// Oil temperature, deg C.
    pub temperature_c: f64,
    /// Output power `T omega_out`, W.
    pub output_power_w: f64,
    /// Input power: the output's plus every loss, W.
    pub input_power_w: f64,
    /// Efficiency, output over input power.
    pub efficiency: f64,
    /// Loss of the sliding disc-pin contacts, W.
    pub loss_disc_pins_w: f64,
    /// Loss of the pins turning in their grooves, W.
    pub loss_pin_grooves_w: f64,
    /// Loss of the crank bearings (crank-disc and crank-carrier), W.
    pub loss_crank_bearings_w: f64,
    /// Loss of the sun-planet meshes, W.
    pub loss_gear_meshes_w: f64,
    /// Smallest lambda ratio (minimum film over composite roughness) of a loaded disc-pin
    /// contact.
    pub lambda_min: f64,
    /// Load-weighted mean lambda ratio of the loaded disc-pin contacts.
    pub lambda_mean: f64,
    /// Thinnest minimum film of a loaded disc-pin contact, um.
    pub film_min_um: f64,
    /// Load-weighted mean friction coefficient of the disc-pin contacts.
    pub pin_friction_coefficient: f64,
}

impl OperatingPoint {
    /// The sum of the losses, W.
    pub fn loss_w(&self) -> f64 {
        self.loss_disc_pins_w
            + self.loss_pin_grooves_w
            + self.loss_crank_bearings_w
            + self.loss_gear_meshes_w
    }
}

/// The power balance at the output speed `output_speed_rpm` (rpm, > 0) of the loads `loads`
/// on `profile` with the oil and friction of `lub`, the pins held or turning as `wear` says
/// (docs/model.md section 18.4).
pub fn operating_point(
    red: &Reducer,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    loads: &MeshCycleLoads,
    output_speed_rpm: f64,
) -> OperatingPoint {
    let geo = profile.geometry();
    let zc = geo.disc_teeth() as f64;
    let omega_out = output_speed_rpm.abs() * TAU / 60.0;
    // Crank angle in the pins' frame per second: the disc turns by `-1/Zc` of it.
    let crank_speed = omega_out * zc;
    let omega_in = omega_out * red.ratio.abs();
    let e_star = red.contact.materials.contact_modulus();
    let n = loads.solutions.len().max(1) as f64;
    let (mut pins, mut grooves, mut bearings) = (0.0, 0.0, 0.0);
    let (mut lambda_min, mut film_min) = (f64::INFINITY, f64::INFINITY);
    let (mut lambda_sum, mut mu_sum, mut force_sum) = (0.0, 0.0, 0.0);
    for (sol, forces) in loads.solutions.iter().zip(&loads.bearing_forces) {
        let kinematics: Vec<Vec<(f64, f64)>> = sol
            .discs
            .iter()
            .map(|d| contact_kinematics(profile, d))
            .collect();
        // Each contact's film and friction coefficient.
        let film: Vec<Vec<(f64, f64)>> = sol
            .discs
            .iter()
            .zip(&kinematics)
            .map(|(disc, kin)| {
                disc.pins
                    .iter()
                    .zip(kin)
                    .map(|(p, &(w, v_d))| {
                        if p.force <= 0.0 {
                            return (0.0, 0.0);
                        }
                        let u = entrainment_speed(geo, p.pin, disc.pose.crank_angle, w, v_d)
                            * crank_speed;
                        let (f, lambda) = lub.contact_film(p.half_width, p.max_pressure, e_star, u);
                        lambda_min = lambda_min.min(lambda);
                        film_min = film_min.min(f.minimum);
                        let mu = lub.friction_coefficient(lambda);
                        lambda_sum += p.force * lambda;
                        mu_sum += p.force * mu;
                        force_sum += p.force;
                        (mu, lambda)
                    })
                    .collect()
            })
            .collect();
        let speeds: Vec<Vec<(f64, f64)>> = kinematics
            .iter()
            .map(|k| {
                k.iter()
                    .map(|&(w, v)| (w * crank_speed, v * crank_speed))
                    .collect()
            })
            .collect();
        let mu: Vec<Vec<f64>> = film
            .iter()
            .map(|d| d.iter().map(|x| x.0).collect())
            .collect();
        let (p, g) = pin_dissipation(
            sol,
            &speeds,
            &mu,
            &wear.pin_turning,
            wear.pin_rolling_fraction,
            e_star,
        );
        pins += p;
        grooves += g;
        bearings += bearing_loss(red, lub, forces, omega_in);
    }
    let (pins, grooves, bearings) = (pins / n, grooves / n, bearings / n);
    let output_power = loads.torque.abs() * omega_out;
    let meshes = mesh_loss(red, lub, output_power + pins + grooves + bearings, omega_in);
    let input_power = output_power + pins + grooves + bearings + meshes;
    let loaded = force_sum > 0.0;
    OperatingPoint {
        output_speed_rpm,
        torque_nm: loads.torque,
        temperature_c: lub.temperature_c,
        output_power_w: output_power,
        input_power_w: input_power,
        efficiency: if input_power > 0.0 {
            output_power / input_power
        } else {
            0.0
        },
        loss_disc_pins_w: pins,
        loss_pin_grooves_w: grooves,
        loss_crank_bearings_w: bearings,
        loss_gear_meshes_w: meshes,
        lambda_min: if loaded { lambda_min } else { 0.0 },
        lambda_mean: if loaded { lambda_sum / force_sum } else { 0.0 },
        film_min_um: if loaded { film_min * 1e6 } else { 0.0 },
        pin_friction_coefficient: if loaded { mu_sum / force_sum } else { 0.0 },
    }
}

/// Palmgren's loss (W) of the crank bearings under the radial forces `forces` (N, in the order
/// of [`MeshCycleLoads::bearing_forces`]) at the input speed `omega_in` (rad/s): each bearing's
/// moment at its speed relative to its outer ring, every row of a pair with its share of the
/// load. Bearings of the linear law (no rollers, no pitch diameter) lose nothing.
fn bearing_loss(red: &Reducer, lub: &Lubrication, forces: &[f64], omega_in: f64) -> f64 {
    let omega = omega_in * red.bearing_speed_ratio().abs();
    let rpm = omega * 60.0 / TAU;
    let nu = lub.oil.kinematic_viscosity(lub.temperature_c);
    let moment = |b: &crate::reducer::RadialBearing, f: f64| -> f64 {
        match b.law {
            BearingLaw::Rollers {
                rows,
                pitch_diameter,
                ..
            } => {
                let rows = rows.max(1) as f64;
                rows * palmgren_moment(
                    f / rows,
                    pitch_diameter,
                    rpm,
                    nu,
                    lub.bearing_f0,
                    lub.bearing_f1,
                )
            }
            BearingLaw::Linear { .. } => 0.0,
        }
    };
    let total: f64 = forces
        .iter()
        .enumerate()
        .map(|(i, &f)| moment(red.bearing_of_force(i), f))
        .sum();
    total * omega
}

/// ISO/TR 14179-2's load-dependent loss (W) of the sun-planet meshes passing the power `power`
/// (W) at the input speed `omega_in` (rad/s): `mu_mZ H_V P` with the base-circle force of each
/// of the cranks' meshes; none in a single-stage drive.
fn mesh_loss(red: &Reducer, lub: &Lubrication, power: f64, omega_in: f64) -> f64 {
    if red.cranks == 0 || matches!(red.drive, Drive::SingleStage(_)) || omega_in <= 0.0 {
        return 0.0;
    }
    let m = &red.mesh;
    let mesh = SpurMesh {
        pitch_radii: [m.sun_pitch_radius, m.planet_pitch_radius],
        module: lub.gear_module,
        pressure_angle: m.pressure_angle,
        face_width: m.face_width,
        roughness_ra: lub.gear_roughness_ra,
    };
    let force = power / omega_in / (m.sun_base_radius * red.cranks as f64);
    let mu = mesh.friction_coefficient(force, m.sun_pitch_radius * omega_in, lub.viscosity());
    mu * mesh.loss_factor() * power
}

/// [`operating_point`] at the oil's steady temperature when `lub` holds a heat balance (the
/// temperature where the losses leave through the housing, iterated with the viscosity;
/// docs/model.md section 18.5), else at its temperature.
///
/// # Errors
/// [`crate::Error::Numerical`] if the heat balance does not settle below 150 deg C.
pub fn balanced_point(
    red: &Reducer,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    loads: &MeshCycleLoads,
    output_speed_rpm: f64,
) -> Result<OperatingPoint> {
    let at = |t: f64| {
        operating_point(
            red,
            profile,
            &lub.at_temperature(t),
            wear,
            loads,
            output_speed_rpm,
        )
    };
    match lub.heat {
        None => Ok(at(lub.temperature_c)),
        Some(h) => {
            let area = h.area.unwrap_or(f64::NAN);
            let t = h
                .steady_temperature(area, |t| at(t).loss_w())
                .map_err(|e| {
                    crate::Error::numerical(
                        "heat balance",
                        format!(
                            "at {} N m and {output_speed_rpm} rpm output: {e}",
                            loads.torque
                        ),
                    )
                })?;
            Ok(at(t))
        }
    }
}

/// The efficiency map: the power balance at every output speed of `speeds_rpm` (rpm) and
/// torque of `torques` (N m) at every oil temperature of `temperatures_c` (deg C), torque-major
/// then temperature then speed; with a heat balance in `lub`, at its steady temperature
/// instead ([`balanced_point`], `temperatures_c` unread). The static loads of each torque are
/// solved once ([`mesh_cycle_loads`], `samples` crank angles per mesh cycle).
///
/// # Errors
/// The static analysis's.
#[allow(clippy::too_many_arguments)]
pub fn efficiency_map(
    red: &Reducer,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    torques: &[f64],
    speeds_rpm: &[f64],
    temperatures_c: &[f64],
    samples: usize,
) -> Result<Vec<OperatingPoint>> {
    let mut out = Vec::with_capacity(torques.len() * speeds_rpm.len() * temperatures_c.len());
    for &t in torques {
        let loads = mesh_cycle_loads(red, profile, t, samples)?;
        if lub.heat.is_some() {
            for &s in speeds_rpm {
                out.push(balanced_point(red, profile, lub, wear, &loads, s)?);
            }
            continue;
        }
        for &temp in temperatures_c {
            let lub = lub.at_temperature(temp);
            for &s in speeds_rpm {
                out.push(operating_point(red, profile, &lub, wear, &loads, s));
            }
        }
    }
    Ok(out)
}
