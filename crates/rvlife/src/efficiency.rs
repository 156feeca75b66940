//! The reducer's power losses and efficiency (docs/model.md section 18.4): Coulomb friction at
//! the disc-pin contacts and in the pins' grooves with the coefficient of the contact's oil
//! film, Palmgren's friction moments of the crank bearings, and ISO/TR 14179-2's loss of the
//! sun-planet meshes, each on the loads of the frictionless static analysis over a mesh cycle.
//!
//! Two ways: to first order ([`operating_point`]), the friction forces on the frictionless
//! equilibrium's loads (the usual approach of cycloid-drive efficiency models, e.g. J. W.
//! Sensinger, "Efficiency of high-sensitivity gear trains, such as cycloid drives", J. Mech.
//! Des. 135(7), 2013), what the heat balance iterates; and with the friction in the
//! equilibrium ([`running_point`], docs/model.md section 18.8), the input torque from the
//! running reducer's equilibrium with the friction forces of its own loads, what every output
//! reports.

use std::f64::consts::TAU;

use serde::Serialize;

use crate::error::Result;
use crate::geometry::Profile;
use crate::reducer::{BearingLaw, Drive, RadialBearing, Reducer, Support};
use crate::statics::{ContactFriction, StaticAnalysis, StaticSolution};
use crate::tribology::{palmgren_moment, pin_friction_forces, Lubrication, SpurMesh};
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

/// The static solutions of the analysis `sa` under the output torque `torque` (N m) at
/// `samples` crank angles of a mesh cycle, with the bearing forces.
///
/// # Errors
/// The static analysis's.
pub fn mesh_cycle_loads(
    sa: &StaticAnalysis,
    torque: f64,
    samples: usize,
) -> Result<MeshCycleLoads> {
    let phis = crate::te::mesh_cycle_angles(sa.reducer().geometry.pins, samples);
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
    /// Input power, W: with the friction in the equilibrium ([`running_point`]) the input
    /// torque that holds it times the input speed, mean over the mesh cycle; to first order
    /// ([`operating_point`]) the output's plus every loss.
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

/// The losses of one configuration of the running reducer and the friction forces that make
/// them ([`friction_at`]): powers W, the film's statistics as sums over the loaded contacts.
#[derive(Debug, Clone, Default)]
struct Losses {
    pins: f64,
    grooves: f64,
    bearings: f64,
    meshes: f64,
    lambda_min: f64,
    film_min: f64,
    lambda_sum: f64,
    mu_sum: f64,
    force_sum: f64,
}

/// The running conditions of an operating point: the output speed (rpm, > 0) and the signed
/// speeds of the forward drive (the input driving the output against its torque).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Running {
    output_speed_rpm: f64,
    /// Input speed, rad/s, signed: the output turns against its torque, `-sgn(T) |omega_out|`.
    pub(crate) omega_in: f64,
    /// Crank angle per second in the pins' frame, `|omega_out| Zc`, rad/s.
    crank_speed: f64,
}

impl Running {
    pub(crate) fn new(
        red: &Reducer,
        profile: &Profile,
        torque: f64,
        output_speed_rpm: f64,
    ) -> Self {
        let omega_out = output_speed_rpm.abs() * TAU / 60.0;
        let zc = profile.geometry().disc_teeth() as f64;
        Running {
            output_speed_rpm,
            omega_in: -torque.signum() * omega_out * red.ratio,
            crank_speed: omega_out * zc,
        }
    }
}

/// The friction of the running reducer at the solution `sol` (bearing forces `forces`, N, in
/// the order of [`StaticAnalysis::bearing_forces`]) with the oil and friction of `lub`, the pins
/// held or turning as `wear` says (docs/model.md sections 18.4 and 18.8): the forces opposing
/// the nominal motion and the losses they make along it.
///
/// Each disc-pin contact's coefficient is its film's ([`Lubrication::contact_film`] at its
/// entrainment speed), its force as [`pin_friction_forces`] says at the disc material's
/// speed along the nominal motion ([`StaticAnalysis::running_rates`]). A crank bearing's
/// moment is Palmgren's at its relative speed, against it; the meshes' ISO/TR 14179-2 loss
/// acts as a moment on the input.
#[allow(clippy::too_many_arguments)]
fn friction_at(
    sa: &StaticAnalysis,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    sol: &StaticSolution,
    forces: &[f64],
    run: Running,
) -> (ContactFriction, Losses) {
    let red = sa.reducer();
    let geo = profile.geometry();
    let e_star = red.contact.materials.contact_modulus();
    let rates = sa.running_rates(sol);
    let omega_in = run.omega_in;
    let mut loss = Losses {
        lambda_min: f64::INFINITY,
        film_min: f64::INFINITY,
        ..Default::default()
    };
    let kinematics: Vec<Vec<(f64, f64)>> = sol
        .discs
        .iter()
        .map(|disc| contact_kinematics(profile, disc))
        .collect();
    // Each loaded contact's friction coefficient.
    let mu: Vec<Vec<f64>> = sol
        .discs
        .iter()
        .zip(&kinematics)
        .map(|(disc, kin)| {
            disc.pins
                .iter()
                .zip(kin)
                .map(|(p, &(w, v_d))| {
                    if p.force <= 0.0 {
                        return 0.0;
                    }
                    let u = entrainment_speed(geo, p.pin, disc.pose.crank_angle, w, v_d)
                        * run.crank_speed;
                    let (f, lambda) = lub.contact_film(p.half_width, p.max_pressure, e_star, u);
                    let mu = lub.friction_coefficient(lambda);
                    loss.lambda_min = loss.lambda_min.min(lambda);
                    loss.film_min = loss.film_min.min(f.minimum);
                    loss.lambda_sum += p.force * lambda;
                    loss.mu_sum += p.force * mu;
                    loss.force_sum += p.force;
                    mu
                })
                .collect()
        })
        .collect();
    // The disc material's speeds along the nominal motion; with rigid support (no coordinates
    // to take the rates from) those of the contact's kinematics, whose sense the losses do not
    // need.
    let speeds: Vec<Vec<f64>> = if sol.deviations.is_empty() {
        kinematics
            .iter()
            .map(|d| d.iter().map(|&(w, _)| w * run.crank_speed).collect())
            .collect()
    } else {
        rates
            .contacts
            .iter()
            .map(|d| d.iter().map(|w| w * omega_in).collect())
            .collect()
    };
    let (pins, pin_loss, groove_loss) = pin_friction_forces(
        sol,
        &speeds,
        &mu,
        &wear.pin_turning,
        wear.pin_rolling_fraction,
    );
    loss.pins = pin_loss;
    loss.grooves = groove_loss;
    let bearings: Vec<f64> = forces
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            let r = rates.bearings.get(i).copied().unwrap_or(0.0) * omega_in;
            let m = bearing_moment(red.bearing_of_force(i), lub, f, r.abs());
            loss.bearings += m * r.abs();
            if r == 0.0 {
                0.0
            } else {
                -m * r.signum()
            }
        })
        .collect();
    let output_power = sol.output_torque.abs() * (rates.output * omega_in).abs();
    let passing = output_power + loss.pins + loss.grooves + loss.bearings;
    loss.meshes = mesh_loss(red, lub, passing, omega_in.abs());
    let input = if omega_in != 0.0 {
        -loss.meshes / omega_in
    } else {
        0.0
    };
    (
        ContactFriction {
            pins,
            bearings,
            input,
        },
        loss,
    )
}

/// The power balance at the output speed `output_speed_rpm` (rpm, > 0) of the loads `loads`
/// on the analysis `sa` of `profile` with the oil and friction of `lub`, the pins held or
/// turning as `wear` says, to first order (docs/model.md section 18.4): the losses of the
/// frictionless equilibria ([`friction_at`]), the input power the output's plus them. What
/// the heat balance iterates; [`running_point`] has the friction in the equilibrium.
pub fn operating_point(
    sa: &StaticAnalysis,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    loads: &MeshCycleLoads,
    output_speed_rpm: f64,
) -> OperatingPoint {
    let run = Running::new(sa.reducer(), profile, loads.torque, output_speed_rpm);
    let losses: Vec<Losses> = loads
        .solutions
        .iter()
        .zip(&loads.bearing_forces)
        .map(|(sol, forces)| friction_at(sa, profile, lub, wear, sol, forces, run).1)
        .collect();
    let output_power = loads.torque.abs() * output_speed_rpm.abs() * TAU / 60.0;
    let lost: f64 = losses
        .iter()
        .map(|l| l.pins + l.grooves + l.bearings + l.meshes)
        .sum::<f64>()
        / losses.len().max(1) as f64;
    summarise(loads.torque, lub, run, &losses, output_power + lost)
}

/// The power balance at the output speed `output_speed_rpm` (rpm, > 0) with the friction in
/// the equilibrium (docs/model.md section 18.8): at each crank angle of `loads` the running
/// reducer's equilibrium with the friction forces of its own loads
/// ([`StaticAnalysis::solve_running`] with [`friction_at`]), the input power the mean of the
/// input torque that holds it times the input speed, the losses those of its forces along the
/// nominal motion. The input power exceeds the output's by the losses to within the elastic
/// energy's change over the cycle and the contact law's own work (docs/model.md section 18.8:
/// 5e-4 of the input on the example).
///
/// # Errors
/// The static analysis's. With rigid support (one disc on a fixed centre, no coordinates for the
/// forces) it is the first-order point ([`operating_point`]).
pub fn running_point(
    sa: &StaticAnalysis,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    loads: &MeshCycleLoads,
    output_speed_rpm: f64,
) -> Result<OperatingPoint> {
    if matches!(sa.reducer().support, Support::Rigid { .. }) {
        // One disc on a fixed centre: no coordinates for the friction forces to act on.
        return Ok(operating_point(
            sa,
            profile,
            lub,
            wear,
            loads,
            output_speed_rpm,
        ));
    }
    let run = Running::new(sa.reducer(), profile, loads.torque, output_speed_rpm);
    let mut losses = Vec::with_capacity(loads.solutions.len());
    let mut input = 0.0;
    for sol in &loads.solutions {
        let (solved, held) = running_equilibrium(sa, profile, lub, wear, sol, run)?;
        input += sa.input_torque(&solved, &held) * run.omega_in;
        let forces = sa.bearing_forces(&solved);
        losses.push(friction_at(sa, profile, lub, wear, &solved, &forces, run).1);
    }
    let input_power = input / loads.solutions.len().max(1) as f64;
    summarise(loads.torque, lub, run, &losses, input_power).checked(loads.torque, output_speed_rpm)
}

/// The running equilibrium at the configuration of `sol` ([`StaticAnalysis::solve_running`]
/// with [`friction_at`] at the running conditions `run`): the solution and the friction forces
/// it holds.
///
/// # Errors
/// As [`StaticAnalysis::solve_running`].
pub(crate) fn running_equilibrium(
    sa: &StaticAnalysis,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    sol: &StaticSolution,
    run: Running,
) -> Result<(StaticSolution, ContactFriction)> {
    sa.solve_running(sol, |s| {
        let forces = sa.bearing_forces(s);
        Ok(friction_at(sa, profile, lub, wear, s, &forces, run).0)
    })
}

/// The operating point of the losses `losses` (one per crank angle) and the input power
/// `input_power` (W) at the output torque `torque` (N m).
fn summarise(
    torque: f64,
    lub: &Lubrication,
    run: Running,
    losses: &[Losses],
    input_power: f64,
) -> OperatingPoint {
    let n = losses.len().max(1) as f64;
    let sum = |f: fn(&Losses) -> f64| losses.iter().map(f).sum::<f64>();
    let least = |f: fn(&Losses) -> f64| losses.iter().map(f).fold(f64::INFINITY, f64::min);
    let force_sum = sum(|l| l.force_sum);
    // The film's statistics of the loaded contacts (none: 0).
    let over = |x: f64| if force_sum > 0.0 { x } else { 0.0 };
    let output_power = torque.abs() * run.output_speed_rpm.abs() * TAU / 60.0;
    OperatingPoint {
        output_speed_rpm: run.output_speed_rpm,
        torque_nm: torque,
        temperature_c: lub.temperature_c,
        output_power_w: output_power,
        input_power_w: input_power,
        efficiency: if input_power > 0.0 {
            output_power / input_power
        } else {
            0.0
        },
        loss_disc_pins_w: sum(|l| l.pins) / n,
        loss_pin_grooves_w: sum(|l| l.grooves) / n,
        loss_crank_bearings_w: sum(|l| l.bearings) / n,
        loss_gear_meshes_w: sum(|l| l.meshes) / n,
        lambda_min: over(least(|l| l.lambda_min)),
        lambda_mean: over(sum(|l| l.lambda_sum) / force_sum),
        film_min_um: over(least(|l| l.film_min) * 1e6),
        pin_friction_coefficient: over(sum(|l| l.mu_sum) / force_sum),
    }
}

impl OperatingPoint {
    /// `self` if its input power is finite and at least its output power.
    ///
    /// # Errors
    /// [`crate::Error::Numerical`] naming the torque and speed otherwise.
    fn checked(self, torque: f64, speed_rpm: f64) -> Result<Self> {
        if self.input_power_w.is_finite() && self.input_power_w >= self.output_power_w {
            Ok(self)
        } else {
            Err(crate::Error::numerical(
                "efficiency",
                format!(
                    "the running equilibrium at {torque} N m and {speed_rpm} rpm output needs an \
                     input power of {:.6e} W for an output power of {:.6e} W",
                    self.input_power_w, self.output_power_w
                ),
            ))
        }
    }
}

/// Palmgren's friction moment (N m) of the bearing `b` under the radial force `force` (N) at
/// the speed `omega` (rad/s) relative to its outer ring, every row of a pair with its share of
/// the load; none for the linear law (no rollers, no pitch diameter).
fn bearing_moment(b: &RadialBearing, lub: &Lubrication, force: f64, omega: f64) -> f64 {
    match b.law {
        BearingLaw::Rollers {
            rows,
            pitch_diameter,
            ..
        } => {
            let rows = rows.max(1) as f64;
            rows * palmgren_moment(
                force / rows,
                pitch_diameter,
                omega * 60.0 / TAU,
                lub.oil.kinematic_viscosity(lub.temperature_c),
                lub.bearing_f0,
                lub.bearing_f1,
            )
        }
        BearingLaw::Linear { .. } => 0.0,
    }
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

/// The power balance with the friction in the equilibrium ([`running_point`]) at the oil's
/// steady temperature when `lub` holds a heat balance (the temperature where the first-order
/// losses ([`operating_point`]) leave through the housing, iterated with the viscosity;
/// docs/model.md section 18.5), else at its temperature.
///
/// # Errors
/// As [`running_point`]; [`crate::Error::Numerical`] if the heat balance does not settle below
/// 150 deg C.
pub fn balanced_point(
    sa: &StaticAnalysis,
    profile: &Profile,
    lub: &Lubrication,
    wear: &WearParams,
    loads: &MeshCycleLoads,
    output_speed_rpm: f64,
) -> Result<OperatingPoint> {
    let temperature = match lub.heat {
        None => lub.temperature_c,
        Some(h) => {
            let area = h.area.unwrap_or(f64::NAN);
            let first_order = |t: f64| {
                let lub = lub.at_temperature(t);
                operating_point(sa, profile, &lub, wear, loads, output_speed_rpm).loss_w()
            };
            h.steady_temperature(area, first_order).map_err(|e| {
                crate::Error::numerical(
                    "heat balance",
                    format!(
                        "at {} N m and {output_speed_rpm} rpm output: {e}",
                        loads.torque
                    ),
                )
            })?
        }
    };
    let lub = lub.at_temperature(temperature);
    running_point(sa, profile, &lub, wear, loads, output_speed_rpm)
}

/// The efficiency map: the power balance with the friction in the equilibrium
/// ([`running_point`]) at every output speed of `speeds_rpm` (rpm) and torque of `torques`
/// (N m) at every oil temperature of `temperatures_c` (deg C), torque-major then temperature
/// then speed; with a heat balance in `lub`, at its steady temperature instead
/// ([`balanced_point`], `temperatures_c` unread). The frictionless loads of each torque, from
/// which each point's equilibria start, are solved once ([`mesh_cycle_loads`], `samples` crank
/// angles per mesh cycle).
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
    let sa = StaticAnalysis::new(red, profile)?;
    let mut out = Vec::with_capacity(torques.len() * speeds_rpm.len() * temperatures_c.len());
    for &t in torques {
        let loads = mesh_cycle_loads(&sa, t, samples)?;
        if lub.heat.is_some() {
            for &s in speeds_rpm {
                out.push(balanced_point(&sa, profile, lub, wear, &loads, s)?);
            }
            continue;
        }
        for &temp in temperatures_c {
            let lub = lub.at_temperature(temp);
            for &s in speeds_rpm {
                out.push(running_point(&sa, profile, &lub, wear, &loads, s)?);
            }
        }
    }
    Ok(out)
}
