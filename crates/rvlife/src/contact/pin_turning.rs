//! Pins that turn in their housing grooves: the pin's rotation from the balance of the friction
//! moments on it, and the micro-slip of the disc contact on which it rolls (docs/model.md
//! section 7.12), shared by the wear integration and the friction losses.
//!
//! A pin touched by the discs at contacts `i` (normal force `Q_i`, N; `w_i` the speed of the
//! disc material along the pin's counter-clockwise tangent at the contact) turns with the
//! surface speed `u` that balances the moments about its axis (all at the pin radius): Coulomb
//! friction `mu_d Q_i sgn(w_i - u)` from each sliding disc contact, and the groove's
//! `-mu_g G sgn(u)` (`G = sum Q_i`: the groove reacts each disc's load beneath it; anything in
//! `[-mu_g G, mu_g G]` while the pin stands still). The net moment is non-increasing in `u`,
//! so the balance has one solution at `u = 0` or at a contact's `w_i`: there the pin rolls on
//! that contact, which carries the traction the balance leaves, within `mu_d Q_i`. With one
//! contact the answer is binary: the pin rolls when `mu_d > mu_g`, and stands still otherwise.
//!
//! A contact that rolls under a traction `F < mu_d Q` slips only over the trailing part of its
//! band: Carter's creep of two elastic cylinders (Johnson, *Contact Mechanics*, 1985, section
//! 8.2) is `xi = (mu_d b/R)(1 - sqrt(1 - F/(mu_d Q)))` with `b/R = 2 p0/E*` (Hertz), and the
//! traction works at `F xi V` (`V` the rolling speed). In the slip zone the traction is
//! `mu_d p`, so Archard's `integral p s` is that work over `mu_d`: the contact wears as a
//! sliding one would with the sliding speed `(F/(mu_d Q)) xi V`.

/// How the pins sit in their grooves (`[wear] pin_turning`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PinTurning {
    /// Held in their grooves (or turning by a given fraction, `pin_rolling_fraction`).
    Fixed,
    /// Turning as the balance of the friction moments says.
    Balance {
        /// Friction coefficient of the disc-pin contacts `mu_d` (0-1].
        pin_friction: f64,
        /// Friction coefficient of the pin in its groove `mu_g` (0-1].
        groove_friction: f64,
    },
}

/// One disc contact on a pin, for [`balance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PinContact {
    /// Normal force `Q`, N (> 0).
    pub force: f64,
    /// Speed of the disc material along the pin's counter-clockwise tangent at the contact,
    /// `w`, any unit of speed (m per radian of crank angle in the wear integration).
    pub surface_speed: f64,
}

/// The pin's state from [`balance`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PinBalance {
    /// The pin's surface speed `u` (the unit of [`PinContact::surface_speed`]; 0: it stands
    /// still).
    pub surface_speed: f64,
    /// Per contact: `Some(F)`, the traction (N, magnitude) of a contact on which the pin rolls;
    /// `None` for a contact that slides at `|w - u|`.
    pub rolling_traction: Vec<Option<f64>>,
}

/// The surface speed of a pin under the disc contacts `contacts` with the friction
/// coefficients `pin_friction` (`mu_d`, disc-pin) and `groove_friction` (`mu_g`), from the
/// balance of the friction moments (module docs). An empty `contacts` gives a pin at rest.
pub(crate) fn balance(
    contacts: &[PinContact],
    pin_friction: f64,
    groove_friction: f64,
) -> PinBalance {
    let groove: f64 = groove_friction * contacts.iter().map(|c| c.force).sum::<f64>();
    // The sign of `x` (`tie` where it is zero).
    let sgn = |x: f64, tie: f64| if x != 0.0 { x.signum() } else { tie };
    // Net moment (over the radius) on the pin turning just below (`side` -1) or just above
    // (+1) the surface speed `u`: `sum mu_d Q_i sgn(w_i - u) - mu_g G sgn(u)`.
    let net = |u: f64, side: f64| -> f64 {
        contacts
            .iter()
            .map(|c| pin_friction * c.force * sgn(c.surface_speed - u, -side))
            .sum::<f64>()
            - groove * sgn(u, side)
    };
    let mut candidates: Vec<f64> = contacts.iter().map(|c| c.surface_speed).collect();
    candidates.push(0.0);
    candidates.sort_by(f64::total_cmp);
    // The net moment falls from `mu_d sum Q + mu_g G` to its negative: the first candidate
    // across which it changes sign (standing still preferred on a tie).
    let u = if net(0.0, -1.0) >= 0.0 && net(0.0, 1.0) <= 0.0 {
        0.0
    } else {
        candidates
            .iter()
            .copied()
            .find(|&c| net(c, -1.0) >= 0.0 && net(c, 1.0) <= 0.0)
            .unwrap_or(0.0)
    };
    let sticking: Vec<bool> = contacts
        .iter()
        .map(|c| u != 0.0 && c.surface_speed == u)
        .collect();
    let stuck_force: f64 = contacts
        .iter()
        .zip(&sticking)
        .filter(|(_, s)| **s)
        .map(|(c, _)| c.force)
        .sum();
    // What the rolling contacts carry: the groove's friction less the sliding contacts'.
    let sliding: f64 = contacts
        .iter()
        .zip(&sticking)
        .filter(|(_, s)| !**s)
        .map(|(c, _)| pin_friction * c.force * (c.surface_speed - u).signum())
        .sum();
    let carried = (groove * u.signum() - sliding).abs();
    let rolling_traction = contacts
        .iter()
        .zip(&sticking)
        .map(|(c, s)| s.then(|| (carried * c.force / stuck_force).min(pin_friction * c.force)))
        .collect();
    PinBalance {
        surface_speed: u,
        rolling_traction,
    }
}

/// The sliding speed (the unit of `rolling_speed`) with which a contact that rolls under the
/// traction `traction` (N) wears: `(F/(mu_d Q)) xi V`, Carter's creep `xi = (2 mu_d p0/E*)
/// (1 - sqrt(1 - F/(mu_d Q)))` (module docs), for the normal force `force` (N), the Hertz
/// pressure `max_pressure` (Pa), the contact modulus `contact_modulus` (Pa) and the rolling
/// speed `rolling_speed`.
pub(crate) fn micro_slip_speed(
    traction: f64,
    force: f64,
    pin_friction: f64,
    max_pressure: f64,
    contact_modulus: f64,
    rolling_speed: f64,
) -> f64 {
    let ratio = (traction / (pin_friction * force)).clamp(0.0, 1.0);
    let creep = 2.0 * pin_friction * max_pressure / contact_modulus * (1.0 - (1.0 - ratio).sqrt());
    ratio * creep * rolling_speed.abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(force: f64, surface_speed: f64) -> PinContact {
        PinContact {
            force,
            surface_speed,
        }
    }

    /// One contact: the pin rolls with the disc when `mu_d > mu_g` and carries the groove's
    /// friction `mu_g Q`; it stands still otherwise.
    #[test]
    fn one_contact_is_binary() {
        for w in [-0.3, 0.2] {
            let b = balance(&[c(100.0, w)], 0.1, 0.05);
            assert_eq!(b.surface_speed, w);
            assert!((b.rolling_traction[0].unwrap() - 5.0).abs() < 1e-12);
            let b = balance(&[c(100.0, w)], 0.05, 0.1);
            assert_eq!(b.surface_speed, 0.0);
            assert_eq!(b.rolling_traction[0], None);
        }
    }

    /// Two discs on one pin dragging it opposite ways with equal forces: their frictions cancel
    /// and the pin stands still; with one force three times the other, the stronger contact
    /// turns the pin (`mu_d (3 - 1) Q > mu_g 4 Q` for `mu_d` 0.1, `mu_g` 0.04) and carries
    /// `mu_g 4 Q + mu_d Q`.
    #[test]
    fn opposed_contacts_balance() {
        let b = balance(&[c(100.0, 0.2), c(100.0, -0.2)], 0.1, 0.04);
        assert_eq!(b.surface_speed, 0.0);
        let b = balance(&[c(300.0, 0.2), c(100.0, -0.2)], 0.1, 0.04);
        assert_eq!(b.surface_speed, 0.2);
        let f = b.rolling_traction[0].unwrap();
        assert!((f - (0.04 * 400.0 + 0.1 * 100.0)).abs() < 1e-9, "{f}");
        assert_eq!(b.rolling_traction[1], None);
    }

    /// Carter's creep: zero without traction, `mu_d b/R` at the onset of sliding.
    #[test]
    fn micro_slip_limits() {
        assert_eq!(micro_slip_speed(0.0, 100.0, 0.1, 1e9, 1e11, 1.0), 0.0);
        let full = micro_slip_speed(10.0, 100.0, 0.1, 1e9, 1e11, 1.0);
        assert!((full - 2.0 * 0.1 * 1e-2).abs() < 1e-15, "{full}");
    }
}
