//! The pins' wear map and where a disc meets a pin (docs/model.md section 7.11).
//!
//! The pins sit fixed in their housing grooves, so a pin is worn where the disc meets it, an
//! arc of its surface that the contact sweeps back and forth once per revolution of the
//! eccentric. The contact normal of a cycloid mesh passes through the pitch point `P = Zp e u`
//! (`u` the eccentric's direction, at `Zp e` from the housing centre on the line of centres:
//! the pitch circles of the pin ring, radius `Zp e`, and of the disc, `Zc e`, roll on each other),
//! so pin `j` (centre `X_j`) is touched on its surface point in the direction of `P - X_j`.
//! Every pin of the nominal reducer sees the same history one mesh cycle after its neighbour,
//! so one map, on the angle around the pin measured from its inward radial direction, serves
//! every pin.

use std::f64::consts::TAU;

use crate::geometry::{cross, CycloidGeometry, Vec2};

/// Points of the pin wear map around the pin (0.5 deg apart).
pub const PIN_MAP_POINTS: usize = 720;

/// Wear depth of the pins around their circumference (docs/model.md section 7.11).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PinWear {
    /// Depth, m: `depth[m]` at the angle `beta = 2 pi m / n` around the pin, counter-clockwise
    /// from the pin's inward radial direction (towards the housing centre). Empty: unworn.
    pub depth: Vec<f64>,
}

impl PinWear {
    /// A map of `n` points around the pin (`depth` in m, see [`PinWear::depth`]).
    pub fn new(depth: Vec<f64>) -> Self {
        PinWear { depth }
    }

    /// Whether the pins are unworn.
    pub fn is_zero(&self) -> bool {
        self.depth.iter().all(|&d| d == 0.0)
    }

    /// Largest depth, m.
    pub fn max_depth(&self) -> f64 {
        self.depth.iter().copied().fold(0.0, f64::max)
    }

    /// Depth (m) at the angle `beta` (rad) around the pin, linear between the map's points
    /// (periodic); 0 for an unworn pin.
    pub fn depth_at_angle(&self, beta: f64) -> f64 {
        let n = self.depth.len();
        if n == 0 {
            return 0.0;
        }
        let x = beta.rem_euclid(TAU) / TAU * n as f64;
        let i = (x.floor() as usize).min(n - 1);
        let w = x - i as f64;
        self.depth[i] * (1.0 - w) + self.depth[(i + 1) % n] * w
    }

    /// The gap that pin `j`'s wear adds where the disc of crank angle `crank` (rad, the
    /// eccentric's direction) meets it, m: the depth at the kinematic contact
    /// ([`contact_direction`]). The map is written ([`crate::wear`]) and read at the same
    /// kinematic coordinate, so the loaded contact, which sits up to about 3 deg round the pin
    /// from it at the rated torque (the disc turned by the twist), reads the wear it wrote; and
    /// the gap does not depend on the solution's deviations (the static analysis' tangent
    /// stays exact).
    pub fn gap_at(&self, geo: &CycloidGeometry, j: usize, crank: f64) -> f64 {
        if self.depth.is_empty() {
            return 0.0;
        }
        self.depth_at_angle(contact_direction(geo, j, crank).0)
    }
}

/// The angle (rad, in `[0, 2 pi)`) of the direction `towards` around a pin centred at
/// `centre`, counter-clockwise from the pin's inward radial direction.
pub fn angle_on_pin(centre: &Vec2, towards: &Vec2) -> f64 {
    let inward = -centre / centre.norm();
    cross(&inward, towards)
        .atan2(inward.dot(towards))
        .rem_euclid(TAU)
}

/// Where the disc meets pin `j` at crank angle `crank` (rad): the angle `beta` (rad, in
/// `[0, 2 pi)`) of the contact point around the pin, counter-clockwise from its inward radial
/// direction, and `d beta / d crank` (the contact's angular speed on the pin per unit crank
/// angle), from the pitch point `P = Zp e (cos crank, sin crank)`: `beta` is the direction of
/// `P - X_j`, and `d beta/d crank = (P - X_j) x P' / |P - X_j|^2`.
pub fn contact_direction(geo: &CycloidGeometry, j: usize, crank: f64) -> (f64, f64) {
    let zp = geo.pins as f64;
    let (s, c) = crank.sin_cos();
    let p = Vec2::new(c, s) * (zp * geo.eccentricity);
    let dp = Vec2::new(-s, c) * (zp * geo.eccentricity);
    let x = geo.pin_centre(j);
    let d = p - x;
    (angle_on_pin(&x, &d), cross(&d, &dp) / d.norm_squared())
}
