//! The points of a hysteresis curve the catalogue quantities are read between (docs/model.md
//! section 6.3): the midpoints of the lost motion and the secant of the torsional stiffness
//! `b/a`, for drawing them on the curve.

use serde::Serialize;

use super::TwistTable;

/// The points a hysteresis curve's lost motion and torsional stiffness are read between
/// ([`TwistTable::catalogue_points`]), each `[torque N m, twist rad]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CataloguePoints {
    /// The curve's midpoints at `-T_m` and at `+T_m` (the measuring torque).
    pub lost_motion: [[f64; 2]; 2],
    /// The ends of the secant `b/a`: at `+T_m` on the loading branch and at `+T_r`.
    pub torsional_stiffness: [[f64; 2]; 2],
}

impl TwistTable {
    /// The points of the curve the catalogue quantities are read between (docs/model.md
    /// section 6.3; Nabtesco's catalogue: lost motion is the twist between the hysteresis
    /// curve's midpoints within `+-3 %` of rated torque, torsional stiffness `b/a` the secant
    /// above it), as [`TwistTable::accuracy`] reads them: torque in N m, twist in rad.
    ///
    /// - `lost_motion`: the midpoints `[torque, twist]` at `-T_m` and at `+T_m` (`T_m` the
    ///   measuring torque); their twists differ by [`super::Accuracy::lost_motion`].
    ///   Frictionless the curve is single-valued there; with friction each is the mean of its
    ///   two branches.
    /// - `torsional_stiffness`: the secant of `b/a` from the loading branch's point at `+T_m`
    ///   to the rated torque, `[T_m, psi]` and `[T_r, psi + a]` with `b = T_r - T_m` and `a`
    ///   the mean twist of both senses' loading branches over that span; the torque over the
    ///   twist between them is [`super::Accuracy::torsional_stiffness`]. Where both senses
    ///   are alike the second point is the curve's at `+T_r`.
    pub fn catalogue_points(&self) -> CataloguePoints {
        let (m, r) = (self.level(self.measuring_fraction), self.level(1.0));
        // The midpoints at +-T_m, the loading branch at +T_m, and `a`.
        let (mid_p, mid_n, load_m, a) = match self.branches() {
            Some(b) => {
                let mid = |side: usize| 0.5 * (b.rising(side, m) + b.falling(side, m));
                let a =
                    0.5 * ((b.rising(0, r) - b.rising(0, m)) + (b.falling(1, m) - b.falling(1, r)));
                (mid(0), mid(1), b.rising(0, m), a)
            }
            None => {
                let a = 0.5
                    * ((self.positive[r] - self.positive[m])
                        + (self.negative[m] - self.negative[r]));
                (self.positive[m], self.negative[m], self.positive[m], a)
            }
        };
        let t_m = self.measuring_fraction * self.rated_torque;
        CataloguePoints {
            lost_motion: [[-t_m, mid_n], [t_m, mid_p]],
            torsional_stiffness: [[t_m, load_m], [self.rated_torque, load_m + a]],
        }
    }
}
