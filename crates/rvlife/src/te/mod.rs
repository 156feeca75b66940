//! Transmission error and the catalogue accuracy quantities of the reducer, from the static
//! analysis of its mechanical model ([`crate::statics`]; paper eqs 21-23,
//! docs/model.md section 6).
//!
//! Every angle here is the **output (carrier) rotation** beyond its nominal position with the
//! input locked at the crank angle of the sample: `TE = theta_out - theta_in / i_H` (paper
//! eq 21), positive counter-clockwise.
//!
//! - **STE** (static TE): for each crank angle, the twist at which the unloaded mechanism first
//!   touches a pin when the output is turned forward (counter-clockwise, the sense of a positive
//!   output torque), over every pin of every disc: the `T -> 0+` limit of the loaded twist
//!   (`crate::statics::StaticAnalysis::first_contact`). `reverse` is the same turning
//!   the other way, as a positive angle.
//! - **Loaded TE**: the twist of the static equilibrium under an output torque, in the sense of
//!   the torque.
//! - **Hysteresis curve** (Nabtesco's measuring set-up): the output torque swept
//!   `0 -> +T_r -> -T_r -> +T_r` with the input locked, twist against torque. The model is
//!   frictionless, so the curve is single-valued for `T != 0` and jumps at `T = 0` across the
//!   play. From it: **backlash** (the width at zero torque), **lost motion** (the twist between
//!   the curve's midpoints at `+-` the measuring torque, 3 % of rated by default),
//!   **hysteresis loss** (the width of the loop at zero torque after loading to `+-T_r`; equal
//!   to the backlash without friction) and **torsional stiffness** `b/a` (here: the secant of
//!   the loading branches between the measuring torque and the rated torque,
//!   `b = T_r - T_m`, `a` the mean of the two sides' twists over that span).
//!
//! All pins and teeth are identical, so the cycloid stage repeats every mesh cycle (`2 pi / Zp`
//! of crank angle); curves are computed over one mesh cycle at the start of an output
//! revolution and repeated over the revolution. (With bearings, the crank seats' directions
//! turn slowly with the carrier; that dependence within a revolution is not sampled here.)

use std::f64::consts::TAU;

use rayon::prelude::*;
use serde::Serialize;

use nalgebra::Rotation2;

use crate::error::{Error, Result};
use crate::geometry::{cross, Profile, Vec2};
use crate::reducer::{Reducer, Support};
use crate::statics::{StaticAnalysis, StaticSolution, TouchingPin};
use crate::units::ARCMIN_PER_RAD;

mod catalogue;
mod friction;
mod zero_torque;

pub use catalogue::CataloguePoints;
pub use friction::FrictionTorques;
#[cfg(test)]
pub(crate) use friction::{friction_branch, friction_torques};

use zero_torque::zero_twist_and_start;
pub(crate) use zero_torque::{
    at_round_off_floor, zero_torque, zero_torque_twist_from, ZeroTorque, ZeroTorqueStart,
    PLAY_ROUND_OFF,
};

/// Torque levels per side of the study's hysteresis curves beyond the measuring torque (every
/// 12.5 % of the rated torque; with the knee's torques, [`KNEE`]).
pub(crate) const HYSTERESIS_LEVELS: usize = 8;

/// `[te]` checked (docs/model.md section 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TeParams {
    /// Crank angles per mesh cycle of the TE curves.
    pub samples: usize,
    /// Output torque of the loaded TE, N m.
    pub loaded_torque: f64,
    /// Measuring torque of lost motion, as a fraction of the rated torque (catalogue: 0.03).
    pub measuring_torque_fraction: f64,
}

/// Crank angles (rad) of `samples` points over one mesh cycle `[0, 2 pi / Zp)`.
pub(crate) fn mesh_cycle_angles(pins: usize, samples: usize) -> Vec<f64> {
    (0..samples)
        .map(|k| TAU * k as f64 / (pins as f64 * samples as f64))
        .collect()
}

/// Static transmission error over one mesh cycle.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct StaticTe {
    /// Crank angles, rad.
    pub crank_angle: Vec<f64>,
    /// Forward STE: output twist at first contact turning counter-clockwise, rad.
    pub forward: Vec<f64>,
    /// Reverse STE: output twist at first contact turning clockwise, as a positive angle, rad.
    pub reverse: Vec<f64>,
}

/// Summary statistics of a curve, rad.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CurveStats {
    /// Mean, rad.
    pub mean: f64,
    /// Peak-to-peak, rad.
    pub peak_to_peak: f64,
    /// Maximum, rad.
    pub max: f64,
    /// Minimum, rad.
    pub min: f64,
}

impl CurveStats {
    /// Statistics of `v` (non-empty).
    pub fn of(v: &[f64]) -> CurveStats {
        let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        CurveStats {
            mean: v.iter().sum::<f64>() / v.len() as f64,
            peak_to_peak: max - min,
            max,
            min,
        }
    }
}

impl StaticTe {
    /// Statistics of the forward STE.
    pub(crate) fn stats(&self) -> CurveStats {
        CurveStats::of(&self.forward)
    }
    /// Geometric play (the backlash at each crank angle: the width of the hysteresis curve at
    /// zero torque), rad, at its round-off floor (`at_round_off_floor`: never
    /// negative by round-off).
    pub fn backlash(&self) -> Vec<f64> {
        self.forward
            .iter()
            .zip(&self.reverse)
            .map(|(f, r)| at_round_off_floor(f + r))
            .collect()
    }
    /// Statistics of the backlash over the mesh cycle.
    pub(crate) fn backlash_stats(&self) -> CurveStats {
        CurveStats::of(&self.backlash())
    }
}

/// Static TE of the reducer `red` with disc profile `profile` at `samples` crank angles over one
/// mesh cycle.
///
/// # Errors
/// [`Error::Invalid`] if the modifications interfere (negative play: the disc cannot be
/// assembled without preload); solver failures.
pub fn static_te(red: &Reducer, profile: &Profile, samples: usize) -> Result<StaticTe> {
    let phis = mesh_cycle_angles(red.geometry.pins, samples);
    let sa = StaticAnalysis::new(red, profile)?;
    let StaticTe {
        forward, reverse, ..
    } = static_te_with(&sa, &phis)?;
    if let Some(k) = (0..samples).find(|&k| forward[k] + reverse[k] < -PLAY_ROUND_OFF) {
        return Err(Error::invalid(
            "cycloid.modification",
            format!(
                "play {:.4} arcmin at crank angle {:.3} deg",
                (forward[k] + reverse[k]) * ARCMIN_PER_RAD,
                phis[k].to_degrees()
            ),
            "the modified disc interferes with the pins (negative clearance); \
             thin the teeth (equidistant > 0 or offset < 0)",
        ));
    }
    Ok(StaticTe {
        crank_angle: phis,
        forward,
        reverse,
    })
}

/// Loaded TE over one mesh cycle.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct LoadedTe {
    /// Output torque, N m.
    pub torque: f64,
    /// Crank angles, rad.
    pub crank_angle: Vec<f64>,
    /// Output twist in the sense of the torque, rad.
    pub te: Vec<f64>,
    /// Static solutions at each crank angle.
    pub solutions: Vec<StaticSolution>,
}

impl LoadedTe {
    /// The loaded TE of the equilibria `solutions` under `torque` (N m) at the crank angles
    /// `crank_angle` (rad), one each.
    pub(crate) fn from_solutions(
        torque: f64,
        crank_angle: Vec<f64>,
        solutions: Vec<StaticSolution>,
    ) -> LoadedTe {
        let s = crate::statics::sense(torque);
        LoadedTe {
            torque,
            crank_angle,
            te: solutions.iter().map(|x| s * x.twist).collect(),
            solutions,
        }
    }
    /// Statistics of the loaded TE.
    pub(crate) fn stats(&self) -> CurveStats {
        CurveStats::of(&self.te)
    }
    /// Largest pin force over the cycle, N.
    pub(crate) fn max_force(&self) -> f64 {
        self.solutions
            .iter()
            .map(|s| s.max_force())
            .fold(0.0, f64::max)
    }
    /// Largest Hertz pressure over the cycle, Pa.
    pub(crate) fn max_pressure(&self) -> f64 {
        self.solutions
            .iter()
            .map(|s| s.max_pressure())
            .fold(0.0, f64::max)
    }
    /// Fewest and most pins in contact on one disc over the cycle.
    pub fn pins_in_contact(&self) -> (usize, usize) {
        let it = self.solutions.iter().map(|s| s.pins_in_contact());
        (it.clone().min().unwrap_or(0), it.max().unwrap_or(0))
    }
    /// Mean tangent torsional stiffness over the cycle, N m/rad.
    pub(crate) fn mean_stiffness(&self) -> f64 {
        self.solutions.iter().map(|s| s.stiffness).sum::<f64>() / self.solutions.len() as f64
    }
    /// The solution with the largest pin force.
    pub(crate) fn worst(&self) -> &StaticSolution {
        self.solutions
            .iter()
            .max_by(|a, b| a.max_force().total_cmp(&b.max_force()))
            .expect("at least two samples")
    }
}

/// Loaded TE of `red` with `profile` at output torque `torque` (N m) over one mesh cycle.
///
/// # Errors
/// Solver failures (each names its crank angle and torque).
#[cfg(test)]
pub(crate) fn loaded_te(
    red: &Reducer,
    profile: &Profile,
    torque: f64,
    samples: usize,
) -> Result<LoadedTe> {
    loaded_te_with(&StaticAnalysis::new(red, profile)?, torque, samples)
}

/// [`loaded_te`] on an analysis already built (its contact geometry reused).
///
/// # Errors
/// As [`loaded_te`].
pub(crate) fn loaded_te_with(sa: &StaticAnalysis, torque: f64, samples: usize) -> Result<LoadedTe> {
    let phis = mesh_cycle_angles(sa.reducer().geometry.pins, samples);
    let solutions = sa.solve_sequence(&phis, torque)?;
    Ok(LoadedTe::from_solutions(torque, phis, solutions))
}

/// The catalogue accuracy quantities of one hysteresis curve (rad, N m/rad).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Accuracy {
    /// Width of the curve at zero torque, rad.
    pub backlash: f64,
    /// Twist between the curve's midpoints at `+-` the measuring torque, rad.
    pub lost_motion: f64,
    /// Width of the loop at zero torque after loading to `+-` rated torque, rad (equal to the
    /// backlash in this frictionless model).
    pub hysteresis_loss: f64,
    /// `b/a`: `(T_r - T_m)` over the mean twist of the two loading branches between the
    /// measuring torque `T_m` and the rated torque `T_r`, N m/rad.
    pub torsional_stiffness: f64,
}

/// A hysteresis curve: the sweep `0 -> +T_r -> -T_r -> +T_r` with the input locked.
#[derive(Debug, Clone, Serialize)]
pub struct HysteresisCurve {
    /// Output torque along the sweep, N m (zero appears twice where the twist jumps).
    pub torque: Vec<f64>,
    /// Output twist along the sweep, rad.
    pub twist: Vec<f64>,
}

/// Twist (rad) at each torque of a grid, from which the sweep and the accuracy follow.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct TwistTable {
    /// Torque fractions of the rated torque on each side, increasing from 0 to 1 (0 first: the
    /// `0+` / `0-` limits), with the measuring fraction among them.
    pub fractions: Vec<f64>,
    /// Rated torque, N m.
    pub rated_torque: f64,
    /// Measuring torque fraction.
    pub measuring_fraction: f64,
    /// Twist at `+fraction T_r` (the first entry: `0+`), rad.
    pub positive: Vec<f64>,
    /// Twist at `-fraction T_r` (the first entry: `0-`), rad.
    pub negative: Vec<f64>,
    /// The friction torque at each torque of the grid (`[lubrication] enabled`; `None`:
    /// frictionless), from which the curve's two branches follow (docs/model.md section
    /// 18.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionTorques>,
}

/// Where the hysteresis search of one crank angle starts ([`TwistTable`]'s grid at that
/// crank angle): what the search found there in a neighbouring state. The default is empty.
#[derive(Debug, Clone, Default)]
pub(crate) struct CrankStart {
    /// The zero-torque search's.
    zero: ZeroTorqueStart,
    /// The first loaded level of the grid each way (positive torque first; one solution
    /// each): where the next search's first loaded level starts.
    loaded: Option<Box<[Vec<StaticSolution>; 2]>>,
}

/// Where a sampled reducer's searches start at its next state: the revolution's zero-torque
/// searches ([`zero_torque_over_revolution_from`]) and the hysteresis curve's crank angles
/// ([`hysteresis_with_from`]). The default is empty.
#[derive(Debug, Clone, Default)]
pub(crate) struct Starts {
    /// One per crank angle of the revolution.
    pub revolution: Vec<ZeroTorqueStart>,
    /// One per crank angle of the hysteresis curve.
    pub cranks: Vec<CrankStart>,
}

impl CrankStart {
    /// Whether it holds nothing to start from (a search solved cold).
    fn is_empty(&self) -> bool {
        self.loaded.is_none() && self.zero.is_empty()
    }

    /// What the neighbouring crank angle starts from: the first loaded level of this grid
    /// each way, and nothing else. The levels above it are solved each from the one below, as
    /// cold: a worn reducer can hold more than one equilibrium under the same torque (a disc
    /// that rolls over a ridge of its worn flank onto other pins), and the curve is the one
    /// reached by loading at a fixed crank angle, not by turning the crank under load
    /// (docs/model.md section 6.3: every level started from the neighbour's, 10 of 3 456
    /// loaded twists of the worn example reached other equilibria, up to 9e-5 rad away). A
    /// sampled reducer's next stage keeps the same rule. The zero-torque searches start cold:
    /// the contact problem from the neighbour's configuration takes more programmes than from
    /// the rigid first contact, and a light solve from the neighbour's may settle on another
    /// of the equilibria that the curve's kink near zero torque allows.
    fn neighbour(&self) -> CrankStart {
        CrankStart {
            zero: ZeroTorqueStart::default(),
            loaded: self.loaded.clone(),
        }
    }
}

impl TwistTable {
    /// The twists of the static solutions of one crank angle, `solve(torque)` for every torque
    /// of the grid `fractions` of `rated` (both signs) and the zero-torque limits
    /// ([`zero_torque`]) at zero, and the solution at `+rated`, started from what `warm` holds
    /// (the same crank angle's search in a neighbouring state, a sampled reducer's last stage,
    /// or the neighbouring crank angle's first loaded level: [`CrankStart::neighbour`]), which
    /// it then holds for the next: the zero-torque twists by [`zero_torque_twist_from`] and the
    /// first loaded level each way from that level there, each level above from the one below,
    /// where every solve converges; else cold (the first loaded level from the zero-torque
    /// state, where the mechanism mode has no stiffness yet). The same equilibria, to the
    /// solvers' tolerances.
    ///
    /// # Errors
    /// Those of the solver; [`Error::Numerical`] if the twists do not rise with the torque
    /// (a solve that settled on another branch).
    fn at_crank_from(
        sa: &StaticAnalysis,
        phi: f64,
        fractions: &[f64],
        rated: f64,
        measuring_fraction: f64,
        warm: &mut CrankStart,
    ) -> Result<(TwistTable, StaticSolution)> {
        let last = warm
            .loaded
            .take()
            .filter(|l| l.iter().all(|side| side.len() == 1));
        // The twist rises with the torque through the whole grid, both sides.
        let tol = PLAY_ROUND_OFF;
        let rising = |positive: &[f64], negative: &[f64]| {
            positive.windows(2).all(|w| w[1] >= w[0] - tol)
                && negative.windows(2).all(|w| w[1] <= w[0] + tol)
                && positive[0] >= negative[0] - tol
        };
        // A warm grid that does not rise (a solve that followed its start onto another
        // branch) is solved again cold.
        let warm_grid = last
            .map(|last| Self::grid_from(sa, phi, fractions, rated, &mut warm.zero, &last))
            .transpose()?
            .filter(|(p, n, _)| rising(p, n));
        let (positive, negative, solutions) = match warm_grid {
            Some(grid) => grid,
            None => Self::grid_cold(sa, phi, fractions, rated)?,
        };
        let heaviest = solutions[0].last().cloned();
        // Friction: the torque at each level each way, zero at zero torque where the discs
        // float in their play (nothing presses the contacts), the lightest level's where they
        // are preloaded.
        let friction = sa
            .reducer()
            .friction
            .map(|f| friction::table_friction(sa, &f, &solutions, &positive, &negative));
        // The first loaded level each way, where the next state's grid starts.
        let [mut up, mut down] = solutions;
        up.truncate(1);
        down.truncate(1);
        warm.loaded = Some(Box::new([up, down]));
        if !rising(&positive, &negative) {
            return Err(Error::numerical(
                "hysteresis",
                format!(
                    "the twist does not rise with the torque at crank angle {:.3} deg \
                     (a solve settled on another branch): {:?} arcmin at +{:?} of the rated \
                     torque, {:?} at -",
                    phi.to_degrees(),
                    positive
                        .iter()
                        .map(|p| p * ARCMIN_PER_RAD)
                        .collect::<Vec<_>>(),
                    fractions,
                    negative
                        .iter()
                        .map(|p| p * ARCMIN_PER_RAD)
                        .collect::<Vec<_>>(),
                ),
            ));
        }
        let table = TwistTable {
            fractions: fractions.to_vec(),
            rated_torque: rated,
            measuring_fraction,
            positive,
            negative,
            friction,
        };
        let rated_solution = heaviest.ok_or_else(|| {
            Error::numerical("hysteresis", "the torque grid holds no loaded level")
        })?;
        Ok((table, rated_solution))
    }

    /// The twists of the grid each way (positive torques, then negative, each with the
    /// zero-torque limit at zero) and the loaded solutions each way, up the torque grid from
    /// the zero-torque state of [`zero_torque`].
    ///
    /// # Errors
    /// Those of the solver.
    #[allow(clippy::type_complexity)]
    fn grid_cold(
        sa: &StaticAnalysis,
        phi: f64,
        fractions: &[f64],
        rated: f64,
    ) -> Result<(Vec<f64>, Vec<f64>, [Vec<StaticSolution>; 2])> {
        let mut positive = Vec::with_capacity(fractions.len());
        let mut negative = Vec::with_capacity(fractions.len());
        let mut solutions = [Vec::new(), Vec::new()];
        let ZeroTorque {
            twist,
            start,
            light,
            ..
        } = zero_torque(sa, phi, rated)?;
        let sides = [(1.0, &mut positive), (-1.0, &mut negative)];
        for ((k, (side, out)), light) in sides.into_iter().enumerate().zip(light) {
            // Up the torque grid, each solve started from the one below (the first from the
            // zero-torque configuration of the no-load limit, with play, or the heaviest solve of
            // the descent, with preload).
            for &f in fractions {
                out.push(if f == 0.0 {
                    twist[k]
                } else {
                    let torque = side * f * rated;
                    let below = solutions[k].last().or(light.as_ref());
                    let sol = sa.solve_near(phi, torque, start[k], below)?;
                    let twist = sol.twist;
                    solutions[k].push(sol);
                    twist
                });
            }
        }
        Ok((positive, negative, solutions))
    }

    /// [`TwistTable::grid_cold`] with the zero-torque twists from `zero`
    /// ([`zero_twist_and_start`]) and the first loaded level each way from `last` (that
    /// level's solution each way in a neighbouring state), the levels above it each from the
    /// one below, as cold.
    ///
    /// # Errors
    /// Those of the solver, at the first solve that fails.
    #[allow(clippy::type_complexity)]
    fn grid_from(
        sa: &StaticAnalysis,
        phi: f64,
        fractions: &[f64],
        rated: f64,
        zero: &mut ZeroTorqueStart,
        last: &[Vec<StaticSolution>; 2],
    ) -> Result<(Vec<f64>, Vec<f64>, [Vec<StaticSolution>; 2])> {
        let (twist, start) = zero_twist_and_start(sa, phi, rated, zero)?;
        let mut twists = [Vec::new(), Vec::new()];
        let mut solutions = [Vec::new(), Vec::new()];
        for (k, side) in [1.0, -1.0].into_iter().enumerate() {
            let mut level = 0;
            for &f in fractions {
                if f == 0.0 {
                    twists[k].push(twist[k]);
                    continue;
                }
                let near = last[k].get(level).or(solutions[k].last());
                let sol = sa.solve_near(phi, side * f * rated, start[k], near)?;
                level += 1;
                twists[k].push(sol.twist);
                solutions[k].push(sol);
            }
        }
        let [positive, negative] = twists;
        Ok((positive, negative, solutions))
    }

    /// The mean of several tables of the same grid (non-empty).
    pub(crate) fn mean_of(tables: &[TwistTable]) -> TwistTable {
        let n = tables.len() as f64;
        let avg = |f: fn(&TwistTable) -> &Vec<f64>| -> Vec<f64> {
            (0..f(&tables[0]).len())
                .map(|i| tables.iter().map(|t| f(t)[i]).sum::<f64>() / n)
                .collect()
        };
        TwistTable {
            fractions: tables[0].fractions.clone(),
            rated_torque: tables[0].rated_torque,
            measuring_fraction: tables[0].measuring_fraction,
            positive: avg(|t| &t.positive),
            negative: avg(|t| &t.negative),
            friction: tables
                .iter()
                .all(|t| t.friction.is_some())
                .then(|| FrictionTorques {
                    positive: avg(|t| &t.friction.as_ref().expect("checked").positive),
                    negative: avg(|t| &t.friction.as_ref().expect("checked").negative),
                    positive_twist: avg(|t| &t.friction.as_ref().expect("checked").positive_twist),
                    negative_twist: avg(|t| &t.friction.as_ref().expect("checked").negative_twist),
                }),
        }
    }

    pub(crate) fn at(&self, fraction: f64) -> (f64, f64) {
        let i = self.level(fraction);
        (self.positive[i], self.negative[i])
    }

    /// The index of the torque fraction `fraction` in the grid.
    pub(crate) fn level(&self, fraction: f64) -> usize {
        self.fractions
            .iter()
            .position(|&f| (f - fraction).abs() < 1e-12)
            .expect("the grid holds the measuring and the rated torque")
    }

    /// The catalogue quantities of this table.
    pub fn accuracy(&self) -> Accuracy {
        if let Some(b) = self.branches() {
            return self.accuracy_with_friction(&b);
        }
        let (zp, zn) = self.at(0.0);
        let (mp, mn) = self.at(self.measuring_fraction);
        let (rp, rn) = self.at(1.0);
        let b = self.rated_torque * (1.0 - self.measuring_fraction);
        let a = 0.5 * ((rp - mp) + (mn - rn));
        let play = at_round_off_floor(zp - zn);
        Accuracy {
            backlash: play,
            lost_motion: mp - mn,
            // Loaded to +T_r and back to 0+, then to -T_r and back to 0-: frictionless, the
            // branches retrace, so the width at zero is the play.
            hysteresis_loss: play,
            torsional_stiffness: if a > 0.0 { b / a } else { f64::INFINITY },
        }
    }

    /// The sweep `0 -> +T_r -> -T_r -> +T_r` as one polyline.
    pub fn curve(&self) -> HysteresisCurve {
        if let Some(b) = self.branches() {
            return self.curve_with_friction(&b);
        }
        let t = |f: f64, s: f64| s * f * self.rated_torque;
        let mut torque = Vec::new();
        let mut twist = Vec::new();
        let n = self.fractions.len();
        // 0+ -> +T_r
        for i in 0..n {
            torque.push(t(self.fractions[i], 1.0));
            twist.push(self.positive[i]);
        }
        // +T_r -> 0+, jump to 0-, -> -T_r
        for i in (0..n - 1).rev() {
            torque.push(t(self.fractions[i], 1.0));
            twist.push(self.positive[i]);
        }
        for i in 0..n {
            torque.push(-t(self.fractions[i], 1.0));
            twist.push(self.negative[i]);
        }
        // -T_r -> 0-, jump to 0+, -> +T_r
        for i in (0..n - 1).rev() {
            torque.push(-t(self.fractions[i], 1.0));
            twist.push(self.negative[i]);
        }
        for i in 0..n {
            torque.push(t(self.fractions[i], 1.0));
            twist.push(self.positive[i]);
        }
        HysteresisCurve { torque, twist }
    }
}

/// Torque fractions of a hysteresis grid: 0, the measuring fraction, then `levels` equal steps
/// up to 1; with `knee`, also [`KNEE`] times the measuring fraction (where the play closes and
/// the stiffness sets in: the curve's knee, which the hysteresis plot zooms on).
pub(crate) fn torque_fractions(measuring_fraction: f64, levels: usize, knee: bool) -> Vec<f64> {
    let mut f = vec![0.0, measuring_fraction];
    // The levels start above the grid's largest torque near the measuring one.
    let mut above = measuring_fraction;
    if knee {
        f.extend(KNEE.iter().map(|k| k * measuring_fraction));
        above *= KNEE[2];
    }
    for i in 1..=levels.max(1) {
        let x = i as f64 / levels.max(1) as f64;
        if x > above + 1e-12 {
            f.push(x);
        }
    }
    f.sort_by(f64::total_cmp);
    f
}

/// Extra torques of a study's hysteresis grid near the measuring torque, as multiples of it:
/// a third, two thirds and five thirds (1 %, 2 % and 5 % of the rated torque at the
/// catalogue's 3 %).
pub(crate) const KNEE: [f64; 3] = [1.0 / 3.0, 2.0 / 3.0, 5.0 / 3.0];

/// Hysteresis of `red` with `profile`: the twist table at each crank angle of `crank_angles`
/// (rad) on the grid `torque_fractions``(measuring_fraction, levels, false)` of `rated` (N m),
/// in parallel, and their mean (the curve averaged over the crank angles, as a measurement over
/// a mesh cycle averages it).
///
/// # Errors
/// Solver failures.
pub fn hysteresis(
    red: &Reducer,
    profile: &Profile,
    crank_angles: &[f64],
    rated: f64,
    measuring_fraction: f64,
    levels: usize,
) -> Result<(Vec<TwistTable>, TwistTable)> {
    hysteresis_with(
        &StaticAnalysis::new(red, profile)?,
        crank_angles,
        rated,
        measuring_fraction,
        levels,
    )
}

/// [`hysteresis`] on an analysis already built (its contact geometry reused).
///
/// # Errors
/// As [`hysteresis`].
pub(crate) fn hysteresis_with(
    sa: &StaticAnalysis,
    crank_angles: &[f64],
    rated: f64,
    measuring_fraction: f64,
    levels: usize,
) -> Result<(Vec<TwistTable>, TwistTable)> {
    let fractions = torque_fractions(measuring_fraction, levels, false);
    let (tables, mean, _) =
        hysteresis_and_rated(sa, crank_angles, rated, measuring_fraction, &fractions)?;
    Ok((tables, mean))
}

/// [`hysteresis_with`] with each crank angle's search started from its entry of `warm`
/// ([`TwistTable::at_crank_from`]; a `warm` of another length is reset), which then holds this
/// curve's ends: a sampled reducer's stages, solved in order, start each from the one before.
/// An empty entry starts from its neighbour's, as [`hysteresis_and_rated`] does.
///
/// # Errors
/// As [`hysteresis`].
pub(crate) fn hysteresis_with_from(
    sa: &StaticAnalysis,
    crank_angles: &[f64],
    rated: f64,
    measuring_fraction: f64,
    levels: usize,
    warm: &mut Vec<CrankStart>,
) -> Result<(Vec<TwistTable>, TwistTable)> {
    let fractions = torque_fractions(measuring_fraction, levels, false);
    if warm.len() != crank_angles.len() {
        *warm = vec![CrankStart::default(); crank_angles.len()];
    }
    let tables: Vec<TwistTable> = tables_from(
        sa,
        crank_angles,
        &fractions,
        rated,
        measuring_fraction,
        warm,
    )?
    .into_iter()
    .map(|t| t.0)
    .collect();
    let mean = TwistTable::mean_of(&tables);
    Ok((tables, mean))
}

/// The twist table and the solution at `+rated` of each crank angle of `crank_angles`
/// ([`TwistTable::at_crank_from`]), each started from its entry of `warm` (as long as
/// `crank_angles`), or, where that entry is empty, from its neighbour's just solved: the
/// first loaded level each way from that level at the crank angle before (a start whose pins
/// carry load, where the first level up from a zero-torque state starts from no stiffness
/// along the mechanism mode), the levels above each from the one below, the zero-torque
/// searches cold ([`CrankStart::neighbour`], docs/model.md section 6.3). In parallel over
/// runs of consecutive crank angles ([`crate::statics::sequence_run`]: fixed by their number,
/// so the results do not depend on the number of threads). The same equilibria as every crank
/// angle solved cold, to the solvers' tolerances (a warm grid that does not rise is solved
/// again cold).
///
/// # Errors
/// As [`TwistTable::at_crank_from`].
fn tables_from(
    sa: &StaticAnalysis,
    crank_angles: &[f64],
    fractions: &[f64],
    rated: f64,
    measuring_fraction: f64,
    warm: &mut [CrankStart],
) -> Result<Vec<(TwistTable, StaticSolution)>> {
    let run = crate::statics::sequence_run(crank_angles.len());
    Ok(crank_angles
        .par_chunks(run)
        .zip(warm.par_chunks_mut(run))
        .map(|(phis, starts)| {
            let mut out = Vec::with_capacity(phis.len());
            for (i, &phi) in phis.iter().enumerate() {
                if i > 0 && starts[i].is_empty() {
                    starts[i] = starts[i - 1].neighbour();
                }
                out.push(TwistTable::at_crank_from(
                    sa,
                    phi,
                    fractions,
                    rated,
                    measuring_fraction,
                    &mut starts[i],
                )?);
            }
            Ok(out)
        })
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .collect())
}

/// [`hysteresis_and_rated`] with every crank angle solved cold (from the rigid first contacts,
/// each level from the one below): the reference of the warm starts' tests.
#[cfg(test)]
pub(crate) fn hysteresis_cold(
    sa: &StaticAnalysis,
    crank_angles: &[f64],
    rated: f64,
    measuring_fraction: f64,
    fractions: &[f64],
) -> Result<(Vec<TwistTable>, Vec<StaticSolution>)> {
    Ok(crank_angles
        .par_iter()
        .map(|&phi| {
            let mut cold = CrankStart::default();
            TwistTable::at_crank_from(sa, phi, fractions, rated, measuring_fraction, &mut cold)
        })
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .unzip())
}

/// [`hysteresis_with`] on the grid `fractions` ([`torque_fractions`]) and the equilibria at
/// `+rated` at each crank angle on the way (the loaded TE at the rated torque,
/// [`LoadedTe::from_solutions`]), each crank angle's first loaded level started from its
/// neighbour's ([`tables_from`]).
///
/// # Errors
/// As [`hysteresis`].
pub(crate) fn hysteresis_and_rated(
    sa: &StaticAnalysis,
    crank_angles: &[f64],
    rated: f64,
    measuring_fraction: f64,
    fractions: &[f64],
) -> Result<(Vec<TwistTable>, TwistTable, Vec<StaticSolution>)> {
    let mut warm = vec![CrankStart::default(); crank_angles.len()];
    let (tables, solutions): (Vec<TwistTable>, Vec<StaticSolution>) = tables_from(
        sa,
        crank_angles,
        fractions,
        rated,
        measuring_fraction,
        &mut warm,
    )?
    .into_iter()
    .unzip();
    let mean = TwistTable::mean_of(&tables);
    Ok((tables, mean, solutions))
}

/// The input angle (deg) of crank angle `phi` (rad) as the outputs give it, `i_H phi / Zc`
/// (`ratio` = `i_H`, `Zc` = `pins - 1`).
pub(crate) fn input_deg(phi: f64, pins: usize, ratio: f64) -> f64 {
    (ratio * phi / (pins - 1) as f64).to_degrees()
}

/// Repeats a mesh-cycle curve over one output revolution (`Zc Zp` mesh cycles) and returns
/// `(input angle in degrees, value)` pairs, the input angle being [`input_deg`].
pub(crate) fn over_revolution(
    crank_angle: &[f64],
    values: &[f64],
    pins: usize,
    ratio: f64,
) -> (Vec<f64>, Vec<f64>) {
    let period = TAU / pins as f64;
    let cycles = (pins - 1) * pins;
    let mut x = Vec::with_capacity(cycles * values.len());
    let mut y = Vec::with_capacity(cycles * values.len());
    for c in 0..cycles {
        for (phi, v) in crank_angle.iter().zip(values) {
            x.push(input_deg(phi + c as f64 * period, pins, ratio));
            y.push(*v);
        }
    }
    (x, y)
}

/// Crank angles (rad) of one output revolution at `samples` points per mesh cycle:
/// `i 2 pi / (Zp samples)` for `i` in `0..Zc Zp samples` (the crank turns `Zc` times relative
/// to the pin ring while the output turns once, docs/model.md section 1). Point `c samples + k`
/// is point `k` of [`mesh_cycle_angles`] in mesh cycle `c`.
pub(crate) fn revolution_angles(pins: usize, samples: usize) -> Vec<f64> {
    let n = (pins - 1) * pins * samples;
    (0..n)
        .map(|i| TAU * i as f64 / (pins as f64 * samples as f64))
        .collect()
}

/// Static transmission error over one output revolution (the reducer with part errors has no
/// symmetry left: every mesh cycle differs).
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct RevolutionTe {
    /// Crank angles, rad (`revolution_angles`).
    pub crank_angle: Vec<f64>,
    /// Forward STE (first contact turning counter-clockwise), rad.
    pub forward: Vec<f64>,
    /// Reverse STE (first contact turning clockwise), as a positive angle, rad.
    pub reverse: Vec<f64>,
}

impl RevolutionTe {
    /// Angular transmission error (catalogue): peak-to-peak of the forward output error over
    /// one output revolution, rad.
    pub(crate) fn angular_te(&self) -> f64 {
        CurveStats::of(&self.forward).peak_to_peak
    }
    /// Play between the two directions at each crank angle (the width of the hysteresis curve
    /// at zero torque there), rad.
    pub fn play(&self) -> Vec<f64> {
        self.forward
            .iter()
            .zip(&self.reverse)
            .map(|(f, r)| f + r)
            .collect()
    }
    /// Statistics of the play over the revolution.
    pub(crate) fn play_stats(&self) -> CurveStats {
        CurveStats::of(&self.play())
    }
}

/// Crank angles spread over the output revolution at which the angular TE and the largest play
/// of a reducer with play or whose rigid kinematics interfere are taken from its zero-torque
/// twists (docs/model.md section 5.12).
const ANGULAR_TE_SPREAD: usize = 24;

/// Whether the reducer of `sa` turns through play before its pins stop it (bearings with
/// clearance or meshes with backlash, on bearing support): its no-load limits then come from
/// the contact problem ([`StaticAnalysis::no_load`]), not from the rigid first contacts.
pub(crate) fn has_play(sa: &StaticAnalysis) -> bool {
    let red = sa.reducer();
    red.max_half_play() > 0.0 && red.support == Support::Bearings
}

/// Angular TE and largest play (rad) of the reducer of `sa` over its output revolution, from
/// its revolution STE `rev` (at `samples` crank angles per mesh cycle; `rated`: the rated
/// torque, N m). Without play, the peak-to-peak of the rigid forward twists
/// ([`RevolutionTe::angular_te`]) and the largest gap between the two ways; where the part
/// errors close the rigid play (the rigid first contacts cross: preload, docs/model.md section
/// 5.12), or where the reducer has play (its no-load limits are the contact problem's, which
/// the rigid revolution does not see), the zero-torque twists with the play and any preload
/// carried ([`zero_torque`] at [`ANGULAR_TE_SPREAD`] crank angles spread over the revolution:
/// the peak-to-peak of the forward twists and the largest gap between the two ways).
///
/// # Errors
/// Those of the solver.
pub(crate) fn revolution_no_load(
    sa: &StaticAnalysis,
    rev: &RevolutionTe,
    samples: usize,
    rated: f64,
) -> Result<(f64, f64)> {
    revolution_no_load_from(sa, rev, samples, rated, &mut Vec::new())
}

/// [`revolution_no_load`] with the zero-torque searches started from `warm`
/// ([`zero_torque_over_revolution_from`]).
///
/// # Errors
/// Those of the solver.
pub(crate) fn revolution_no_load_from(
    sa: &StaticAnalysis,
    rev: &RevolutionTe,
    samples: usize,
    rated: f64,
    warm: &mut Vec<ZeroTorqueStart>,
) -> Result<(f64, f64)> {
    if rev.play_stats().min >= -PLAY_ROUND_OFF && !has_play(sa) {
        return Ok((rev.angular_te(), rev.play_stats().max));
    }
    zero_torque_over_revolution_from(sa, samples, rated, warm)
}

/// Angular TE and largest play (rad) from the zero-torque twists ([`zero_torque`]) at
/// [`ANGULAR_TE_SPREAD`] crank angles spread over one output revolution (every
/// `len/ANGULAR_TE_SPREAD + 1`-th of [`revolution_angles`] at `samples` per mesh cycle, so that
/// successive ones fall at different points of the mesh cycle): the peak-to-peak of the
/// forward twists and the largest gap between the two ways, with the play and any preload
/// carried. A sampled estimate, below the exact one by the peaks it misses. Each crank angle's
/// search starts from its entry of `warm` ([`zero_torque_twist_from`]; a `warm` of another
/// length is reset, an empty one starts every search from the rigid first contacts), which
/// then holds this revolution's ends: a sampled reducer's stages, solved in order, start each
/// from the one before.
///
/// # Errors
/// Those of the solver.
pub(crate) fn zero_torque_over_revolution_from(
    sa: &StaticAnalysis,
    samples: usize,
    rated: f64,
    warm: &mut Vec<ZeroTorqueStart>,
) -> Result<(f64, f64)> {
    let all = revolution_angles(sa.reducer().geometry.pins, samples);
    let stride = all.len() / ANGULAR_TE_SPREAD + 1;
    let picked: Vec<f64> = all.into_iter().step_by(stride).collect();
    if warm.len() != picked.len() {
        *warm = vec![ZeroTorqueStart::default(); picked.len()];
    }
    let twists = picked
        .par_iter()
        .zip(warm.par_iter_mut())
        .map(|(&phi, w)| zero_torque_twist_from(sa, phi, rated, w))
        .collect::<Result<Vec<[f64; 2]>>>()?;
    let forward: Vec<f64> = twists.iter().map(|t| t[0]).collect();
    let play = twists.iter().map(|t| t[0] - t[1]).fold(0.0, f64::max);
    Ok((CurveStats::of(&forward).peak_to_peak, play))
}

/// The largest play over the output revolution (rad) reported beside the catalogue backlash
/// `backlash` (rad): `sampled`, the largest play found at the crank angles searched, not
/// below `backlash` nor zero. The catalogue backlash is the mean of the plays at a mesh
/// cycle's crank angles (the mean curve's width at zero torque, docs/model.md section 6), so
/// the largest play over the revolution is at least it; a sampled search
/// ([`zero_torque_over_revolution_from`]) can miss the peak.
pub(crate) fn largest_play(sampled: f64, backlash: f64) -> f64 {
    sampled.max(backlash).max(0.0)
}

/// Angular TE (rad) of the reducer of `sa` over its output revolution: the first of
/// [`revolution_no_load`].
///
/// # Errors
/// Those of the solver.
pub(crate) fn angular_te_of(
    sa: &StaticAnalysis,
    rev: &RevolutionTe,
    samples: usize,
    rated: f64,
) -> Result<f64> {
    angular_te_from(sa, rev, samples, rated, &mut Vec::new())
}

/// [`angular_te_of`] with the zero-torque searches started from `warm`
/// ([`revolution_no_load_from`]).
///
/// # Errors
/// Those of the solver.
pub(crate) fn angular_te_from(
    sa: &StaticAnalysis,
    rev: &RevolutionTe,
    samples: usize,
    rated: f64,
    warm: &mut Vec<ZeroTorqueStart>,
) -> Result<f64> {
    Ok(revolution_no_load_from(sa, rev, samples, rated, warm)?.0)
}

/// Static TE over one output revolution, each crank angle solved on its own
/// ([`StaticAnalysis::first_contact`] in both directions at every one of the `Zc Zp samples`
/// crank angles of [`revolution_angles`]): the reference that [`revolution`] is checked
/// against, `Zc Zp` times the work of [`static_te`].
///
/// # Errors
/// Solver failures.
#[cfg(test)]
pub(crate) fn revolution_exact(sa: &StaticAnalysis, samples: usize) -> Result<RevolutionTe> {
    let phis = revolution_angles(sa.reducer().geometry.pins, samples);
    let pairs: Vec<(f64, f64)> = phis
        .par_iter()
        .map(|&phi| Ok((sa.first_contact(phi, 1.0)?, -sa.first_contact(phi, -1.0)?)))
        .collect::<Result<_>>()?;
    Ok(RevolutionTe {
        crank_angle: phis,
        forward: pairs.iter().map(|p| p.0).collect(),
        reverse: pairs.iter().map(|p| p.1).collect(),
    })
}

/// Static TE over one output revolution at `samples` crank angles per mesh cycle.
///
/// Without part errors the stage repeats every mesh cycle and the curve is the mesh-cycle
/// STE tiled. With part errors ([`crate::reducer::errors::PartErrors`]), first-order
/// perturbation of the nominal reducer's touching twists: at each crank angle of one mesh
/// cycle, every pin that could touch first is solved once without errors
/// (`StaticAnalysis::touching_pins`: its touching twist `psi_j`, lever `m_j`, gap gradient
/// `w_j` and position `r_j`); at crank angle `phi + c 2 pi/Zp` the same contact is made by pin
/// `j + c` turned by `c 2 pi/Zp`, and the errors move its touching twist to
/// `psi_j + (w . (dp - dc) - dr - dpsi (r x w)) / m_j` (`dp`: pin displacement, `dr`: radius
/// error, `dc`, `dpsi`: the disc's pose correction from the cranks); the STE is the extreme
/// over the pins. The shift is taken to second order (the lever's and the normal's change
/// along the mode over the shift), and the pins it puts first (within a tenth of the shift) are
/// then solved exactly with the errors in place: the result equals `revolution_exact` to
/// 1e-8 arcmin (tests), at a tenth of its work.
///
/// # Errors
/// Solver failures.
pub fn revolution(sa: &StaticAnalysis, samples: usize) -> Result<RevolutionTe> {
    revolution_with(sa, samples, true)
}

/// [`revolution`] without the exact solve at the end: the second-order perturbation alone,
/// within about 1 % of the errors' effect on the twist (1.1 % measured for errors of 2-4 um
/// that move the twist by 0.5 arcmin, less for smaller ones: the remainder is of third
/// order), at a fraction of the work. For Monte Carlo sampling.
///
/// # Errors
/// Solver failures.
pub(crate) fn revolution_perturbed(sa: &StaticAnalysis, samples: usize) -> Result<RevolutionTe> {
    revolution_with(sa, samples, false)
}

fn revolution_with(sa: &StaticAnalysis, samples: usize, polish: bool) -> Result<RevolutionTe> {
    let red = sa.reducer();
    let zp = red.geometry.pins;
    let period = TAU / zp as f64;
    let phis = mesh_cycle_angles(zp, samples);
    let all = revolution_angles(zp, samples);
    if red.errors.is_zero() {
        let ste = static_te_with(sa, &phis)?;
        let n = all.len();
        return Ok(RevolutionTe {
            crank_angle: all,
            forward: (0..n).map(|i| ste.forward[i % samples]).collect(),
            reverse: (0..n).map(|i| ste.reverse[i % samples]).collect(),
        });
    }
    let errors = &red.errors;
    let nominal = Reducer {
        errors: Default::default(),
        ..red.clone()
    };
    let sa0 = sa.for_reducer(&nominal)?;
    let reach = red.error_gap_bound();
    let tables: Vec<[Vec<TouchingPin>; 2]> = phis
        .par_iter()
        .map(|&phi| {
            Ok([
                sa0.touching_pins(phi, 1.0, reach)?,
                sa0.touching_pins(phi, -1.0, reach)?,
            ])
        })
        .collect::<Result<_>>()?;
    let dp: Vec<Vec2> = (0..zp).map(|j| red.pin_displacement(j)).collect();
    let dr: Vec<f64> = (0..zp).map(|j| errors.pin_radius_error(j)).collect();
    let discs = match red.support {
        Support::Bearings => red.discs(),
        Support::Rigid { .. } => 1,
    };
    let pairs: Vec<(f64, f64)> = all
        .par_iter()
        .enumerate()
        .map(|(i, &phi)| {
            let (c, k) = (i / samples, i % samples);
            let rot = Rotation2::new(c as f64 * period);
            let carrier = red.input_angle_for_crank(phi) / red.ratio;
            let corr: Vec<(Vec2, f64)> = (0..discs)
                .map(|d| red.disc_correction(phi + red.phase(d), carrier))
                .collect();
            // The touching twist of `t` with the errors in place, `None` when its gap does not
            // close within the expansion (no real root).
            let twist = |t: &TouchingPin| -> Option<f64> {
                let j = (t.pin + c) % zp;
                let w = rot * t.gradient;
                let r = rot * t.position;
                let (dc, dpsi) = corr[t.disc];
                let shift = dp[j] - dc;
                // Gap change at the touching pose, and its rate along the mode.
                let a = w.dot(&shift) - dr[j] - dpsi * cross(&r, &w);
                let b = (rot * t.gradient_rate).dot(&shift) - dpsi * t.arm_rate;
                // Solve a + b x - m x - m' x^2 / 2 = 0 for the twist change x (the nominal
                // gap closes as m x + m' x^2 / 2 beyond its touching twist): the root nearest
                // zero, in the form that stays accurate as m' -> 0.
                let (q2, q1) = (0.5 * t.lever_rate, t.lever - b);
                let disc = q1 * q1 + 4.0 * q2 * a;
                if disc < 0.0 {
                    return None;
                }
                let den = q1 + q1.signum() * disc.sqrt();
                (den != 0.0).then(|| t.twist + 2.0 * a / den)
            };
            // The pins the perturbation puts first (within a tenth of the error's effect, or
            // 0.1 arcsec), each solved exactly with the errors in place; the exact first
            // contact when none of them touches.
            let first = |s: f64, table: &[TouchingPin]| -> Result<f64> {
                let est: Vec<(f64, &TouchingPin)> = table
                    .iter()
                    .map(|t| (twist(t).map_or(f64::INFINITY, |x| s * x), t))
                    .collect();
                let (best, best_pin) = est
                    .iter()
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|&(x, t)| (x, t))
                    .expect("touching_pins returns at least one pin");
                if !best.is_finite() {
                    return sa.first_contact(phi, s);
                }
                if !polish {
                    return Ok(s * best);
                }
                let margin = 0.1 * (best - s * best_pin.twist).abs() + 5e-7;
                let mut exact = f64::INFINITY;
                for &(x, t) in est.iter().filter(|e| e.0 <= best + margin) {
                    let j = (t.pin + c) % zp;
                    if let Some(b) = sa.pin_touching_twist(phi, t.disc, j, s * x, s)? {
                        exact = exact.min(s * b);
                    }
                }
                if exact.is_finite() {
                    Ok(s * exact)
                } else {
                    sa.first_contact(phi, s)
                }
            };
            Ok((first(1.0, &tables[k][0])?, -first(-1.0, &tables[k][1])?))
        })
        .collect::<Result<_>>()?;
    Ok(RevolutionTe {
        crank_angle: all,
        forward: pairs.iter().map(|p| p.0).collect(),
        reverse: pairs.iter().map(|p| p.1).collect(),
    })
}

/// [`static_te`] at the crank angles `phis` with the analysis built.
pub(crate) fn static_te_with(sa: &StaticAnalysis, phis: &[f64]) -> Result<StaticTe> {
    let pairs: Vec<(f64, f64)> = phis
        .par_iter()
        .map(|&phi| Ok((sa.no_load_twist(phi, 1.0)?, -sa.no_load_twist(phi, -1.0)?)))
        .collect::<Result<_>>()?;
    Ok(StaticTe {
        crank_angle: phis.to_vec(),
        forward: pairs.iter().map(|p| p.0).collect(),
        reverse: pairs.iter().map(|p| p.1).collect(),
    })
}
