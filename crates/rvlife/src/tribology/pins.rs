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
                let loaded: Vec<usize> = (0..sol.discs.len())
                    .filter(|&d| sol.discs[d].pins[j].force > 0.0)
                    .collect();
                let contacts: Vec<pin_turning::PinContact> = loaded
                    .iter()
                    .map(|&d| pin_turning::PinContact {
                        force: sol.discs[d].pins[j].force,
                        surface_speed: speeds[d][j].0,
                    })
                    .collect();
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
