//! The friction of the disc-pin contacts and of the pins in their grooves (docs/model.md
//! sections 7.12 and 18.4): what the efficiency and the hysteresis curve's friction share.

use crate::contact::pin_turning::{self, PinTurning};
use crate::statics::StaticSolution;

/// The friction power (W, or work per unit of the speeds' parameter) of the disc-pin contacts
/// of `sol` and of the pins in their grooves (docs/model.md sections 7.12 and 18.4):
/// `speeds[d][j] = (w, v_d)`, the disc material's speed along pin `j`'s counter-clockwise
/// tangent at disc `d`'s contact and the contact's speed along the flank (m/s, or m per unit
/// of any parameter), `mu[d][j]` the contact's friction coefficient. Fixed pins slide by
/// `1 - f` of `|w|` at the contact and `f` in the groove at the contact's coefficient (`f` the
/// `rolling_fraction`); turning pins as the balance of the friction moments says
/// ([`pin_turning::balance`] with `turning`'s coefficients): a sliding contact loses
/// `mu Q |w - u|`, a rolling one its creep work (Carter), the groove `mu_g Q |u|`. Returns
/// `(contacts, grooves)`.
pub fn pin_dissipation(
    sol: &StaticSolution,
    speeds: &[Vec<(f64, f64)>],
    mu: &[Vec<f64>],
    turning: &PinTurning,
    rolling_fraction: f64,
    e_star: f64,
) -> (f64, f64) {
    let (mut pins, mut grooves) = (0.0, 0.0);
    match *turning {
        PinTurning::Fixed => {
            let f = rolling_fraction;
            for ((disc, kin), mu) in sol.discs.iter().zip(speeds).zip(mu) {
                for ((p, &(w, _)), &mu) in disc.pins.iter().zip(kin).zip(mu) {
                    if p.force > 0.0 {
                        pins += mu * p.force * (1.0 - f) * w.abs();
                        grooves += mu * p.force * f * w.abs();
                    }
                }
            }
        }
        PinTurning::Balance {
            pin_friction,
            groove_friction,
        } => {
            let n_pins = sol.discs.first().map_or(0, |d| d.pins.len());
            for j in 0..n_pins {
                let (loaded, contacts) = pin_contacts(sol, j, |d| speeds[d][j].0);
                let b = pin_turning::balance(&contacts, pin_friction, groove_friction);
                for (k, &d) in loaded.iter().enumerate() {
                    let p = &sol.discs[d].pins[j];
                    let (w, v_d) = speeds[d][j];
                    pins += match b.rolling_traction[k] {
                        Some(t) => {
                            pin_friction
                                * p.force
                                * pin_turning::micro_slip_speed(
                                    t,
                                    p.force,
                                    pin_friction,
                                    p.max_pressure,
                                    e_star,
                                    v_d,
                                )
                        }
                        None => mu[d][j] * p.force * (w - b.surface_speed).abs(),
                    };
                    grooves += groove_friction * p.force * b.surface_speed.abs();
                }
            }
        }
    }
    (pins, grooves)
}

/// The Coulomb forces of the disc-pin contacts of `sol` on the discs when the disc material
/// moves past its pins at `speeds[d][j]` (any unit of speed, along pin `j`'s counter-clockwise
/// tangent at disc `d`'s contact), with the contact coefficients `mu[d][j]` (docs/model.md
/// sections 7.12 and 18.8): per disc and pin the tangential force on the disc (N, along the
/// same tangent; 0 for an unloaded pin), and the power they lose at those speeds, split
/// `(contacts, grooves)`. A held pin takes `-mu Q sgn(w)` (lost `1 - f` at the contact and
/// `f`, the `rolling_fraction`, in the groove); a turning pin turns as the balance of the
/// friction moments says ([`pin_turning::balance`] with `turning`'s coefficients): a sliding
/// contact takes `-mu Q sgn(w - u)`, the contacts on which the pin rolls share by their loads
/// what the groove's `mu_g G sgn(u)` leaves (so the pin's moments balance), and the loss is
/// the power of these forces, the groove's `mu_g G |u|` of it (a rolling contact's creep is
/// left out: it sticks).
pub fn pin_friction_forces(
    sol: &StaticSolution,
    speeds: &[Vec<f64>],
    mu: &[Vec<f64>],
    turning: &PinTurning,
    rolling_fraction: f64,
) -> (Vec<Vec<f64>>, f64, f64) {
    let mut forces: Vec<Vec<f64>> = sol.discs.iter().map(|d| vec![0.0; d.pins.len()]).collect();
    let (mut pins, mut grooves) = (0.0, 0.0);
    match *turning {
        PinTurning::Fixed => {
            let f = rolling_fraction;
            for (d, disc) in sol.discs.iter().enumerate() {
                for p in disc.pins.iter().filter(|p| p.force > 0.0) {
                    let (j, w) = (p.pin, speeds[d][p.pin]);
                    let q = mu[d][j] * p.force;
                    forces[d][j] = if w == 0.0 { 0.0 } else { -q * w.signum() };
                    pins += (1.0 - f) * q * w.abs();
                    grooves += f * q * w.abs();
                }
            }
        }
        PinTurning::Balance {
            pin_friction,
            groove_friction,
        } => {
            let n_pins = sol.discs.first().map_or(0, |d| d.pins.len());
            for j in 0..n_pins {
                let (loaded, contacts) = pin_contacts(sol, j, |d| speeds[d][j]);
                if loaded.is_empty() {
                    continue;
                }
                let b = pin_turning::balance(&contacts, pin_friction, groove_friction);
                let u = b.surface_speed;
                let groove = groove_friction * contacts.iter().map(|c| c.force).sum::<f64>();
                // The sliding contacts' forces on the pin, and the load of the rolling ones.
                let (mut sliding, mut rolling_load) = (0.0, 0.0);
                for (k, &d) in loaded.iter().enumerate() {
                    let c = contacts[k];
                    if b.rolling_traction[k].is_none() {
                        let f = mu[d][j] * c.force * (c.surface_speed - u).signum();
                        sliding += f;
                        forces[d][j] = -f;
                    } else {
                        rolling_load += c.force;
                    }
                }
                let carried = groove * u.signum() - sliding;
                for (k, &d) in loaded.iter().enumerate() {
                    if b.rolling_traction[k].is_some() {
                        forces[d][j] = -carried * contacts[k].force / rolling_load;
                    }
                }
                let lost: f64 = loaded
                    .iter()
                    .zip(&contacts)
                    .map(|(&d, c)| -forces[d][j] * c.surface_speed)
                    .sum();
                let in_groove = groove * u.abs();
                grooves += in_groove;
                pins += lost - in_groove;
            }
        }
    }
    (forces, pins, grooves)
}

/// The discs whose contact on pin `j` of `sol` is loaded, and those contacts with the disc
/// material's speed `speed(d)` along the pin's tangent.
fn pin_contacts(
    sol: &StaticSolution,
    j: usize,
    speed: impl Fn(usize) -> f64,
) -> (Vec<usize>, Vec<pin_turning::PinContact>) {
    let loaded: Vec<usize> = (0..sol.discs.len())
        .filter(|&d| sol.discs[d].pins[j].force > 0.0)
        .collect();
    let contacts = loaded
        .iter()
        .map(|&d| pin_turning::PinContact {
            force: sol.discs[d].pins[j].force,
            surface_speed: speed(d),
        })
        .collect();
    (loaded, contacts)
}
