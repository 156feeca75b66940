//! Coulomb friction in the quasi-static hysteresis curve (docs/model.md section 18.3).
//!
//! With the input locked, the output's twist makes the contacts creep: the disc-pin contacts
//! slide (or the pins turn in their grooves) and the crank bearings turn a little. Coulomb
//! friction resists each of these motions with `mu N` (a bearing with Palmgren's load moment
//! `f1 F dm`), so the twist costs the friction torque
//!
//! ```text
//! T_f(psi) = sum_k mu_k N_k |ds_k/dpsi| + sum_b f1 F_b dm_b |dtheta_b/dpsi|
//! ```
//!
//! on top of the elastic torque `T_e(psi)` of the frictionless curve, with the normal loads and
//! the creep rates of the frictionless equilibrium (first order in `mu`). Rigid-plastic
//! contacts stick until the friction has turned round, so the curve has two branches: rising
//! `T = T_e(psi) + T_f(psi)` while the twist grows, falling `T = T_e(psi) - T_f(psi)` while it
//! shrinks, a vertical step between them at each turning point; the loop's area is the work
//! of the friction over the cycle. At a torque `T` of the grid the branches lie the
//! friction's twist `T_f / k` below and above the frictionless twist (`k` the tangent
//! stiffness there; first order again), so the midpoints are the frictionless curve's.

use serde::{Deserialize, Serialize};

use super::{Accuracy, HysteresisCurve, TwistTable, PLAY_ROUND_OFF};
use crate::geometry::{rotate, Vec2};
use crate::reducer::BearingLaw;
use crate::reducer::QuasiStaticFriction;
#[cfg(test)]
use crate::statics::ContactFriction;
use crate::statics::{StaticAnalysis, StaticSolution};
use crate::tribology::pin_dissipation;
#[cfg(test)]
use crate::tribology::pin_friction_forces;

/// The friction of a twist table's grid, each side in the order of its torque fractions (the
/// first entry at zero torque): the friction torque `T_f` (N m, `>= 0`) and the twist it
/// moves the branches by, `T_f / k` (rad, `k` the tangent stiffness).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrictionTorques {
    /// At `+fraction T_r`, N m.
    pub positive: Vec<f64>,
    /// At `-fraction T_r`, N m.
    pub negative: Vec<f64>,
    /// `T_f / k` at `+fraction T_r`, rad.
    pub positive_twist: Vec<f64>,
    /// `T_f / k` at `-fraction T_r`, rad.
    pub negative_twist: Vec<f64>,
}

/// The friction torque `T_f` (N m) at each of the loaded solutions `side` of one crank angle,
/// in the order of increasing torque magnitude (one side of a twist table's grid): the creep
/// rates along each solution's twist direction ([`StaticAnalysis::creep_rates`]; without one,
/// rigid support, by differences of the neighbouring solutions, central inside and one-sided
/// at the ends), the contacts' friction as [`pin_dissipation`] with the coefficient `f.pin`,
/// the bearings' with Palmgren's load term (module docs).
pub(crate) fn friction_torques(
    sa: &StaticAnalysis,
    f: &QuasiStaticFriction,
    side: &[StaticSolution],
) -> Vec<f64> {
    (0..side.len())
        .map(|j| {
            let sol = &side[j];
            let creep = sa.creep_rates(sol).or_else(|| differences(side, j));
            match creep {
                Some((contacts, bearings)) => friction_torque(sa, f, sol, &contacts, &bearings),
                None => 0.0,
            }
        })
        .collect()
}

/// The branch of the hysteresis curve through the crank angle and torque of the frictionless
/// solution `sol` with the friction in the equilibrium (docs/model.md section 18.3): the
/// equilibrium with every contact slipping against its creep ([`StaticAnalysis::solve_running`]
/// with the forces of the creep rates along the solution's own twist direction,
/// [`StaticAnalysis::creep_rates`]: the disc-pin contacts as [`pin_friction_forces`] with the
/// coefficient `f.pin`, the bearings with Palmgren's load moment `f1 F dm`); `loading`: the
/// twist growing in the torque's sense, else shrinking. What the first-order branches
/// (`T_f / k` either side of `sol`) stand for, and what `tests::friction` checks them against
/// (the curve's grid stays first order: these sweeps cost several solves per point).
///
/// # Errors
/// The solver's; [`crate::Error::Invalid`] with rigid support (no twist direction).
#[cfg(test)]
pub(crate) fn friction_branch(
    sa: &StaticAnalysis,
    f: &QuasiStaticFriction,
    sol: &StaticSolution,
    loading: bool,
) -> crate::error::Result<StaticSolution> {
    let red = sa.reducer();
    let sense = if sol.output_torque < 0.0 { -1.0 } else { 1.0 };
    let sigma = if loading { sense } else { -sense };
    let law = |s: &StaticSolution| -> crate::error::Result<ContactFriction> {
        let (contacts, rates) = sa.creep_rates(s).ok_or_else(|| {
            crate::Error::invalid(
                "friction in the equilibrium",
                "rigid support",
                "needs bearing support",
            )
        })?;
        let speeds: Vec<Vec<f64>> = contacts
            .iter()
            .map(|d| d.iter().map(|c| sigma * c).collect())
            .collect();
        let mu: Vec<Vec<f64>> = s.discs.iter().map(|d| vec![f.pin; d.pins.len()]).collect();
        let (pins, _, _) =
            pin_friction_forces(s, &speeds, &mu, &f.pin_turning, f.pin_rolling_fraction);
        let bearings = sa
            .bearing_forces(s)
            .iter()
            .zip(&rates)
            .enumerate()
            .map(|(i, (&force, &rate))| match red.bearing_of_force(i).law {
                BearingLaw::Rollers { pitch_diameter, .. } => {
                    -f.bearing_f1 * force * pitch_diameter * sign(sigma * rate)
                }
                BearingLaw::Linear { .. } => 0.0,
            })
            .collect();
        Ok(ContactFriction {
            pins,
            bearings,
            input: 0.0,
        })
    };
    Ok(sa.solve_running(sol, law)?.0)
}

/// The sign of `x`, 0 at 0.
#[cfg(test)]
fn sign(x: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x.signum()
    }
}

/// The friction torque (N m) at `sol` with the creep rates `contacts` (per disc and pin, m/rad)
/// and `bearings` (per bearing, rad/rad).
fn friction_torque(
    sa: &StaticAnalysis,
    f: &QuasiStaticFriction,
    sol: &StaticSolution,
    contacts: &[Vec<f64>],
    bearings: &[f64],
) -> f64 {
    let red = sa.reducer();
    let e_star = red.contact.materials.contact_modulus();
    let speeds: Vec<Vec<(f64, f64)>> = contacts
        .iter()
        .map(|d| d.iter().map(|&w| (w, 0.0)).collect())
        .collect();
    let mu: Vec<Vec<f64>> = sol
        .discs
        .iter()
        .map(|d| vec![f.pin; d.pins.len()])
        .collect();
    let (pins, grooves) = pin_dissipation(
        sol,
        &speeds,
        &mu,
        &f.pin_turning,
        f.pin_rolling_fraction,
        e_star,
    );
    let forces = sa.bearing_forces(sol);
    let moment = |law: &BearingLaw, force: f64| match *law {
        BearingLaw::Rollers { pitch_diameter, .. } => f.bearing_f1 * force * pitch_diameter,
        BearingLaw::Linear { .. } => 0.0,
    };
    let bearing: f64 = forces
        .iter()
        .zip(bearings)
        .enumerate()
        .map(|(i, (&force, &rate))| moment(&red.bearing_of_force(i).law, force) * rate.abs())
        .sum();
    pins + grooves + bearing
}

/// The creep rates at `side[j]` by differences of its neighbours (rigid support: one disc on a
/// fixed centre, no bearings): `None` with fewer than two solutions.
#[allow(clippy::type_complexity)]
fn differences(side: &[StaticSolution], j: usize) -> Option<(Vec<Vec<f64>>, Vec<f64>)> {
    let n = side.len();
    if n < 2 {
        return None;
    }
    let (a, b) = (&side[j.saturating_sub(1)], &side[(j + 1).min(n - 1)]);
    let dpsi = b.twist - a.twist;
    if dpsi.abs() <= f64::EPSILON * b.twist.abs().max(1e-12) {
        return None;
    }
    let contacts = side[j]
        .discs
        .iter()
        .enumerate()
        .map(|(d, disc)| {
            disc.pins
                .iter()
                .map(|p| {
                    if p.force <= 0.0 {
                        return 0.0;
                    }
                    let at = |s: &StaticSolution| {
                        let pose = &s.discs[d].pose;
                        pose.centre + rotate(&p.point, pose.angle)
                    };
                    let moved: Vec2 = at(b) - at(a);
                    let out = -rotate(&p.normal, disc.pose.angle);
                    moved.dot(&Vec2::new(-out.y, out.x)) / dpsi
                })
                .collect()
        })
        .collect();
    Some((contacts, Vec::new()))
}

/// The two branches of a twist table with friction at the grid's torques (module docs): at each
/// level the frictionless twist `psi` moved by the friction's twist `delta = T_f / k` (`k` the
/// tangent stiffness there), down on the rising branch (the torque carries the friction too)
/// and up on the falling one, each held at the sweep's turning point while the friction turns
/// round (rigid-plastic contacts stick).
#[derive(Debug, Clone)]
pub(crate) struct Branches {
    /// Per side (positive, negative) and level: `(psi, delta)`, rad.
    sides: [Vec<(f64, f64)>; 2],
    /// The twist where the rising branch reaches `+T_r`, and the falling one `-T_r`.
    top: f64,
    bottom: f64,
}

impl Branches {
    /// The branches of the twists `positive` and `negative` (rad) with the friction's twists
    /// `friction` (rad) at the same levels.
    pub(crate) fn new(positive: &[f64], negative: &[f64], friction: &FrictionTorques) -> Branches {
        let zip = |p: &[f64], d: &[f64]| p.iter().copied().zip(d.iter().copied()).collect();
        let sides: [Vec<(f64, f64)>; 2] = [
            zip(positive, &friction.positive_twist),
            zip(negative, &friction.negative_twist),
        ];
        let (rp, dp) = *sides[0].last().expect("a loaded level");
        let (rn, dn) = *sides[1].last().expect("a loaded level");
        Branches {
            sides,
            top: rp - dp,
            bottom: rn + dn,
        }
    }

    /// The twist where the rising branch reaches `+T_r` (the top turning point).
    pub(crate) fn top(&self) -> f64 {
        self.top
    }

    /// The twist where the falling branch reaches `-T_r` (the bottom turning point).
    pub(crate) fn bottom(&self) -> f64 {
        self.bottom
    }

    /// The rising branch's twist at level `i` of side `side` (0 positive, 1 negative).
    pub(crate) fn rising(&self, side: usize, i: usize) -> f64 {
        let (psi, delta) = self.sides[side][i];
        (psi - delta).max(self.bottom)
    }

    /// The falling branch's twist at level `i` of side `side`.
    pub(crate) fn falling(&self, side: usize, i: usize) -> f64 {
        let (psi, delta) = self.sides[side][i];
        (psi + delta).min(self.top)
    }
}

/// The friction of one crank angle's grid: the friction torque at each loaded level each way
/// ([`friction_torques`], `solutions` per side) and its twist `T_f / k`; at zero torque none
/// where the discs float in their play (nothing presses the contacts: `positive[0] -
/// negative[0]` beyond the round-off), the lightest level's where they are preloaded.
pub(crate) fn table_friction(
    sa: &StaticAnalysis,
    f: &QuasiStaticFriction,
    solutions: &[Vec<StaticSolution>; 2],
    positive: &[f64],
    negative: &[f64],
) -> FrictionTorques {
    let side = |k: usize| {
        let loaded = friction_torques(sa, f, &solutions[k]);
        let twist: Vec<f64> = loaded
            .iter()
            .zip(&solutions[k])
            .map(|(t, s)| {
                if s.stiffness > 0.0 {
                    t / s.stiffness
                } else {
                    0.0
                }
            })
            .collect();
        let played = positive[0] - negative[0] > PLAY_ROUND_OFF;
        let first = |v: &[f64]| {
            if played {
                0.0
            } else {
                v.first().copied().unwrap_or(0.0)
            }
        };
        (
            std::iter::once(first(&loaded))
                .chain(loaded.iter().copied())
                .collect::<Vec<f64>>(),
            std::iter::once(first(&twist))
                .chain(twist.iter().copied())
                .collect::<Vec<f64>>(),
        )
    };
    let ((positive, positive_twist), (negative, negative_twist)) = (side(0), side(1));
    FrictionTorques {
        positive,
        negative,
        positive_twist,
        negative_twist,
    }
}

impl TwistTable {
    /// The two branches of the curve with friction (`None` frictionless).
    pub(crate) fn branches(&self) -> Option<Branches> {
        self.friction
            .as_ref()
            .map(|f| Branches::new(&self.positive, &self.negative, f))
    }

    /// The friction's work over the closed sweep `+T_r -> -T_r -> +T_r`, J: the area of the
    /// loop of [`TwistTable::curve`] (0 frictionless).
    pub fn friction_work(&self) -> f64 {
        if self.friction.is_none() {
            return 0.0;
        }
        let c = self.curve();
        // The loop: the sweep from its first return to +T_r (the first loading left out).
        let n = self.fractions.len();
        let (t, x) = (&c.torque[n - 1..], &c.twist[n - 1..]);
        // Shoelace: the area the sweep encloses, counter-clockwise in (twist, torque).
        let area: f64 = (1..t.len())
            .map(|i| 0.5 * (x[i - 1] * t[i] - x[i] * t[i - 1]))
            .sum();
        area.abs()
    }

    /// [`TwistTable::accuracy`] with friction (docs/model.md section 18.3): the midpoints of
    /// the two branches, the loop's width at zero torque, the loading branches for the
    /// stiffness.
    pub(crate) fn accuracy_with_friction(&self, b: &Branches) -> Accuracy {
        let (zp, zn) = self.at(0.0);
        let level = |f: f64| self.level(f);
        let (m, r) = (level(self.measuring_fraction), level(1.0));
        let mid = |side: usize, i: usize| 0.5 * (b.rising(side, i) + b.falling(side, i));
        let a = 0.5 * ((b.rising(0, r) - b.rising(0, m)) + (b.falling(1, m) - b.falling(1, r)));
        Accuracy {
            backlash: super::at_round_off_floor(zp - zn),
            lost_motion: mid(0, m) - mid(1, m),
            hysteresis_loss: super::at_round_off_floor(b.falling(0, 0) - b.rising(1, 0)),
            torsional_stiffness: if a > 0.0 {
                self.rated_torque * (1.0 - self.measuring_fraction) / a
            } else {
                f64::INFINITY
            },
        }
    }

    /// [`TwistTable::curve`] with friction: the first loading up the rising branch from zero,
    /// then down the falling branch to `-T_r` and up the rising one to `+T_r`, at the grid's
    /// torques.
    pub(crate) fn curve_with_friction(&self, b: &Branches) -> HysteresisCurve {
        let r = self.rated_torque;
        let f = &self.fractions;
        let n = f.len();
        let mut points: Vec<(f64, f64)> = Vec::with_capacity(4 * n);
        // The first loading from the state at rest at `0+`: the rising branch.
        points.extend((0..n).map(|i| (f[i] * r, b.rising(0, i).max(self.positive[0]))));
        points.extend((0..n).rev().map(|i| (f[i] * r, b.falling(0, i))));
        points.extend((0..n).map(|i| (-f[i] * r, b.falling(1, i))));
        points.extend((0..n).rev().map(|i| (-f[i] * r, b.rising(1, i))));
        points.extend((0..n).map(|i| (f[i] * r, b.rising(0, i))));
        let (torque, twist) = points.into_iter().unzip();
        HysteresisCurve { torque, twist }
    }
}
