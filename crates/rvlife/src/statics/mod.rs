//! Static equilibrium of the reducer model under an output torque, with the input locked: the
//! catalogue's measuring set-up for torsional stiffness, lost motion and backlash
//! (docs/model.md sections 5 and 6), and the loaded TE.
//!
//! **Set-up.** The input (sun) is locked at the angle that puts disc 1's eccentric at crank
//! angle `phi`; a torque `T` (N m) acts on the output carrier, positive counter-clockwise (the
//! sense of positive output rotation: it presses the flank `0 < mesh angle < pi`). The unknowns
//! are the deviations of every other coordinate from the nominal kinematics
//! ([`Reducer::nominal`]): the carrier twist `psi` (the output's TE under load), each crank's
//! centre and angle, each disc's centre and angle. The forces are those of the dynamic model:
//! meshes and bearings (`Reducer::structural_forces`) and the disc-pin contacts with the
//! line-contact law on the contact geometry both analyses share, the gap field of the actual
//! profile ([`GapField`]: exact global closest points at touching, averaged over the Hertz
//! band).
//!
//! **Solution.** One method for every loaded state: the equilibrium under `T` is the minimum
//! of the potential energy `U - T psi` over every coordinate but the input (torque control),
//! found by Newton's method with the tangent made positive definite, a backtracking line search
//! and Levenberg-Marquardt's trust region, started from the neighbouring crank angle, torque
//! level or stage with an Euler predictor, or cold from the locked-input mode at a twist that
//! carries the torque (where Newton does not converge from it, the same mode with the other
//! coordinates settled at that twist). Where a solve does not converge from its start, the
//! torque is applied in load steps from it, each solved the same way (path following). Every
//! solution is returned only with its residual (every generalised force, moments over the pin
//! circle radius) below `RESIDUAL_TOLERANCE` of the force scale; otherwise an error names the
//! crank angle, the torque and the wear. The no-load limits come from the same constraints
//! (`NoLoad`). docs/model.md section 5.3.
//!
//! **`T -> 0+` (STE).** With no load the bearings are undeformed and the mechanism moves as one
//! rigid body along its locked-input mode: carrier `+psi`, cranks `+(1 + Z1/Z2) psi` about their
//! axes, discs turning with the carrier. The first contact along that mode, over every pin of
//! both discs (no lever-arm cut-off), is the limit of the loaded twist as the torque tends to
//! zero (`StaticAnalysis::first_contact`): the static TE.
//!
//! **Rigid support** ([`Support::Rigid`], the paper's and Li's model): one disc with its centre
//! on the eccentric carries `load_share T`; the only unknown is the twist along the same mode,
//! and `load_share T = sum F_j m_j` with the mode lever `m_j = -d gap_j / d psi`
//! (about `l_j (Zp + Z1/Z2)/Zc`, docs/model.md section 6).

use std::borrow::Cow;

use nalgebra::{DMatrix, DVector, Matrix2x3, Rotation2, Vector3};
use rayon::prelude::*;
use serde::Serialize;

mod first_contact;
mod forces;
mod newton;
mod play;
mod running;
mod shares;
mod solve;

pub(crate) use play::NoLoad;
pub use running::{ContactFriction, RunningRates};
pub use shares::{twist_shares, TwistShare};

use crate::contact::gap::GapField;
use crate::contact::DiscPose;
use crate::error::{Error, Result};
use crate::geometry::{cross, mesh_angle, Profile, Vec2};
use crate::reducer::{
    perp, rotation_difference, BearingEval, Drive, Frozen, Layout, Reducer, StructureRotations,
    Support, MAX_DOFS,
};
use crate::units::ARCMIN_PER_RAD;

/// Relative residual every static solution is checked against: every generalised force of the
/// equilibrium (moments divided by the pin circle radius) below this times the force scale, the
/// sum of the pin forces (what the bearings carry), and at least the output torque over the
/// pin circle radius; or below the round-off floor of the contact forces where that is larger
/// ([`ROUNDOFF_GAP_ULPS`]).
pub(crate) const RESIDUAL_TOLERANCE: f64 = 1e-9;

/// Round-off of a computed gap, in units of the last place of the pin circle radius: a gap is
/// the difference of two lengths of the size of the pin circle radius (pin centre and pin path
/// in the disc frame) after a rotation, so it carries a few ulps of `Rp` (about 1e-17 m for a
/// 64 mm pin circle) whatever its size. The contact forces then carry `k_j` times that, and the
/// residual of an equilibrium cannot be driven below `4 eps Rp sum k_j`: for the example at
/// 0.1 % of its rated torque that is about 1e-8 of the force scale, above
/// [`RESIDUAL_TOLERANCE`]. Such a solution is accepted at that floor, which it reports
/// ([`StaticSolution::roundoff_floor`]).
pub(crate) const ROUNDOFF_GAP_ULPS: f64 = 4.0;

/// Largest elastic twist beyond first contact the static analysis follows, rad (about 34
/// arcmin: 30 times the twist of the example at its rated torque).
pub(crate) const MAX_TWIST: f64 = 0.01;

/// Fraction of the twist estimate ([`StaticAnalysis::twist_guess`]) beyond first contact below
/// which the rigid support's search for the twist (`StaticAnalysis::outer`) that still finds
/// more than the torque concludes that the reducer is preloaded at first contact and continues
/// behind it (docs/model.md section 5.3).
pub(crate) const BEHIND_FIRST_CONTACT: f64 = 1e-3;

/// Most solves of one loading path in `StaticAnalysis::solve_in_load_steps`.
pub(crate) const MAX_LOAD_STEPS: usize = 96;

/// Longest run of consecutive crank angles solved in `StaticAnalysis::solve_sequence`, each
/// started from the previous one; a sequence is cut into equal runs no longer than this.
pub(crate) const SEQUENCE_RUN: usize = 16;

/// Runs of `n` crank angles in `StaticAnalysis::solve_sequence`: the fewest of at most
/// [`SEQUENCE_RUN`] angles, but at least two for `n >= 4` so that two cores share every
/// sequence, of equal length (the last one shorter by the remainder). Fixed by `n` alone: the
/// results do not depend on the number of threads.
pub(crate) fn sequence_run(n: usize) -> usize {
    let runs = n.div_ceil(SEQUENCE_RUN).max(if n >= 4 { 2 } else { 1 });
    n.div_ceil(runs).max(1)
}

/// One pin's share of a static solution.
#[derive(Debug, Clone, Copy, Serialize, serde::Deserialize)]
pub struct PinLoad {
    /// Pin index `j`.
    pub pin: usize,
    /// Profile parameter of the contact (global, rad): the pin centre's path parameter in the
    /// gap field, which is the contact point's on the unworn flank and close to it on a worn
    /// one.
    pub profile_parameter: f64,
    /// Mesh angle of the contact, rad.
    pub mesh_angle: f64,
    /// Gap at the solved pose, m (negative: the contact's approach).
    pub gap: f64,
    /// Normal force, N.
    pub force: f64,
    /// Lever arm of the force about the disc centre, m.
    pub lever_arm: f64,
    /// Contact half-width, m.
    pub half_width: f64,
    /// Maximum Hertz pressure, Pa.
    pub max_pressure: f64,
    /// Flank curvature of the contact law, 1/m.
    pub curvature: f64,
    /// Contact stiffness `dF/ddelta`, N/m (0 when open).
    pub stiffness: f64,
    /// Contact point in the disc's profile frame, m.
    #[serde(skip)]
    pub point: Vec2,
    /// Outward flank normal at the contact, profile frame.
    #[serde(skip)]
    pub normal: Vec2,
}

/// One disc of a static solution.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct DiscLoad {
    /// Pose of the disc.
    #[serde(skip)]
    pub pose: DiscPose,
    /// Translation of the disc centre from its nominal position on the eccentric, m (zero with
    /// rigid support).
    #[serde(skip)]
    pub translation: Vec2,
    /// Disc rotation beyond its nominal angle, rad.
    pub rotation: f64,
    /// Moment of the pin forces about the disc centre, `sum F_j l_j`, N m.
    pub torque: f64,
    /// Every pin (`Zp` entries, in pin order).
    pub pins: Vec<PinLoad>,
}

impl DiscLoad {
    /// Largest pin force, N.
    pub(crate) fn max_force(&self) -> f64 {
        self.pins.iter().map(|p| p.force).fold(0.0, f64::max)
    }
    /// Number of pins carrying a force.
    pub fn pins_in_contact(&self) -> usize {
        self.pins.iter().filter(|p| p.force > 0.0).count()
    }
}

/// A static equilibrium of the reducer.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct StaticSolution {
    /// Crank angle of disc 1, rad.
    pub crank_angle: f64,
    /// Output torque on the carrier, N m.
    pub output_torque: f64,
    /// Carrier (output) rotation beyond nominal, rad: the loaded TE.
    pub twist: f64,
    /// Twist at first contact in the direction of the torque (the `T -> 0+` limit), rad.
    pub first_contact_twist: f64,
    /// Tangent torsional stiffness `dT/dpsi` at the solution, N m/rad.
    pub stiffness: f64,
    /// The discs (two with bearings, one with rigid support).
    pub discs: Vec<DiscLoad>,
    /// Relative residual of the equilibrium (see `RESIDUAL_TOLERANCE`).
    pub residual: f64,
    /// Round-off floor of the residual, relative like it: `4 eps Rp sum k_j` over the loaded
    /// pins over the force scale (`ROUNDOFF_GAP_ULPS`). The solution is accepted when its
    /// residual is below the larger of this and `RESIDUAL_TOLERANCE`.
    pub roundoff_floor: f64,
    /// Coordinate deviations from the nominal kinematics (bearing support; empty with rigid
    /// support), in the layout of [`Layout`], SI.
    #[serde(skip)]
    pub deviations: Vec<f64>,
    /// `dz/dpsi` of every coordinate at the solution with the inner coordinates kept in
    /// equilibrium (the condensation direction `-K_ii^-1 K_io`, its output entry 1; empty
    /// where not known): with [`StaticSolution::stiffness`] the first-order change of the
    /// configuration with the output torque, `dz/dT = twist_direction / stiffness`, from which
    /// a solve at another torque starts (docs/model.md section 5.3).
    #[serde(skip)]
    pub(crate) twist_direction: Vec<f64>,
}

impl StaticSolution {
    /// Largest pin force over the discs, N.
    pub(crate) fn max_force(&self) -> f64 {
        self.discs.iter().map(|d| d.max_force()).fold(0.0, f64::max)
    }
    /// Largest Hertz pressure over the discs, Pa.
    pub(crate) fn max_pressure(&self) -> f64 {
        self.discs
            .iter()
            .flat_map(|d| d.pins.iter().map(|p| p.max_pressure))
            .fold(0.0, f64::max)
    }
    /// Fewest pins in contact on one disc.
    pub fn pins_in_contact(&self) -> usize {
        self.discs
            .iter()
            .map(|d| d.pins_in_contact())
            .min()
            .unwrap_or(0)
    }
}

/// One pin at the pose where it first touches (see `StaticAnalysis::touching_pins`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TouchingPin {
    /// Disc index (from 0).
    pub disc: usize,
    /// Pin index.
    pub pin: usize,
    /// Carrier twist at which the pin touches, rad.
    pub twist: f64,
    /// Mode lever `m = -d gap / d psi` there, m/rad (positive turning counter-clockwise).
    pub lever: f64,
    /// Gradient of the gap with respect to the pin centre there, fixed frame (unit length to
    /// 1e-3: the flank's outward normal).
    pub gradient: Vec2,
    /// Pin centre relative to the disc centre there, fixed frame, m.
    pub position: Vec2,
    /// `d lever / d psi` there, m/rad^2.
    pub lever_rate: f64,
    /// `d gradient / d psi` there, 1/rad.
    pub gradient_rate: Vec2,
    /// `d (position x gradient) / d psi` there, m/rad.
    pub arm_rate: f64,
}

/// A pin that can stop the unloaded mechanism: `(disc, pin, linear estimate gap/m of its
/// touching twist (rad), path parameter, mode lever m (m/rad))`.
type Stopping = (usize, usize, f64, f64, f64);

/// One pin at one pose.
#[derive(Debug, Clone, Copy)]
struct PinEval {
    pin: usize,
    /// Path parameter found in the gap field, rad.
    t: f64,
    gap: f64,
    curvature: f64,
    /// Gradient of the gap with respect to the pin centre, pin-ring frame (about the flank's
    /// outward normal).
    w: Vec2,
    /// Pin centre relative to the disc centre, pin-ring frame, m.
    rel: Vec2,
    /// Pin centre in the profile frame, m.
    q: Vec2,
    /// Gradient in the profile frame.
    grad: Vec2,
    force: f64,
    stiffness: f64,
    /// Gradient of the law's flank curvature with respect to the pin centre, profile frame,
    /// 1/m^2.
    curvature_grad: Vec2,
}

impl PinEval {
    /// A pin known to be open (see [`StaticAnalysis::eval_bearings`]): no force, its last
    /// path parameter and gap.
    fn open(pin: usize, t: f64, gap: f64, rel: Vec2) -> Self {
        PinEval {
            pin,
            t,
            gap,
            curvature: 0.0,
            w: Vec2::zeros(),
            rel,
            q: Vec2::zeros(),
            grad: Vec2::zeros(),
            force: 0.0,
            stiffness: 0.0,
            curvature_grad: Vec2::zeros(),
        }
    }
}

/// A pin's last evaluation in the bearing-supported solve: path parameter, gap (m) and force
/// (N) at disc centre `centre` and angle `angle`.
#[derive(Debug, Clone, Copy)]
struct PinMemory {
    t: f64,
    gap: f64,
    force: f64,
    centre: Vec2,
    angle: f64,
}

impl PinMemory {
    const NONE: PinMemory = PinMemory {
        t: f64::NAN,
        gap: f64::NAN,
        force: f64::NAN,
        centre: Vec2::new(f64::NAN, f64::NAN),
        angle: f64::NAN,
    };
}

/// The nominal positions of the locked-input configuration at one crank angle.
struct Frame {
    phi: f64,
    q0: [f64; MAX_DOFS],
    /// Gap offsets per pin of each disc (`2 x Zp`, disc-major, m; empty: none): see
    /// [`StaticAnalysis::solve_with_offsets`].
    offsets: Vec<f64>,
    /// Constant generalised forces acting besides the output torque (N, N m; zero: none): see
    /// [`StaticAnalysis::solve_loaded`].
    applied: [f64; MAX_DOFS],
}

/// What a loaded solve adds to the model: the gap offsets of
/// [`StaticAnalysis::solve_with_offsets`] and the generalised forces of
/// [`StaticAnalysis::solve_loaded`] (each empty: none).
#[derive(Clone, Copy, Default)]
pub(crate) struct Extra<'s> {
    offsets: &'s [f64],
    applied: &'s [f64],
}

/// Everything evaluated at one configuration of the bearing-supported model.
struct Eval {
    /// Generalised forces of every coordinate (without the output torque).
    g: [f64; MAX_DOFS],
    /// Pins per disc.
    pins: Vec<Vec<PinEval>>,
    /// Poses per disc.
    poses: Vec<DiscPose>,
    /// Force scale of the residual: the sum of the pin forces on both discs, N.
    scale: f64,
    /// Round-off floor of every generalised force, N: `4 eps Rp sum k_j` over the loaded pins.
    roundoff: f64,
}

/// Where a solve starts: the first-contact twist of its direction (rad), and optionally a
/// neighbouring solution (its deviations and first-contact twist, and its twist beyond first
/// contact in the solve's direction, rad); `settle`: a cold start with the coordinates other
/// than the twist settled at it (docs/model.md section 5.3).
#[derive(Clone, Copy)]
struct Start<'s> {
    psi0: f64,
    near: Option<Near<'s>>,
    beyond: Option<f64>,
    extra: Extra<'s>,
    settle: bool,
}

/// A neighbouring solution a solve starts from: its deviations, first-contact twist (rad),
/// output torque (N m), tangent torsional stiffness (N m/rad) and twist direction
/// ([`StaticSolution::twist_direction`], empty where not known).
#[derive(Clone, Copy)]
struct Near<'s> {
    deviations: &'s [f64],
    first_contact_twist: f64,
    torque: f64,
    stiffness: f64,
    direction: &'s [f64],
}

/// Static analysis of one reducer with one disc profile (both discs alike).
pub struct StaticAnalysis<'a> {
    /// The reducer as given.
    given: &'a Reducer,
    /// The reducer analysed: the one given, or, when its sun-planet meshes have backlash, its
    /// copy with backlash-free meshes whose sun is turned by the play (see `mesh_play`).
    red: Cow<'a, Reducer>,
    /// Half the meshes' backlash along the line of action `h` (m) when the analysis carries
    /// it, else 0. Under a static torque of sense `s` every mesh carries load in one sense
    /// (the locked sun reacts `-T/i_H`), so a mesh whose play is taken up is a backlash-free
    /// mesh with the sun turned by `s sgn(i_H) h / r_bs`: the analysis solves the
    /// backlash-free copy at the crank angle the turned sun gives and adds the output's
    /// kinematic share of the turn, `s h / (r_bs |i_H|)`, to every twist it returns
    /// (docs/model.md section 5.11). The solver then never crosses the meshes' dead band.
    mesh_play: f64,
    profile: &'a Profile,
    field: GapField,
    /// The contact's law, prepared ([`crate::contact::ContactModel::prepared`]).
    contact_law: crate::contact::PreparedLaw,
    /// Pin centres, ground frame, m (with the reducer's part errors).
    pin_centres: Vec<Vec2>,
    /// Added to each pin's gap, m: minus the pin's radius error.
    pin_gap: Vec<f64>,
    /// Loaded solves of bearing support so far (each load step counted), and the solves that
    /// did not converge from their start and applied the torque in load steps (docs/model.md
    /// section 5.3): the solver's own diagnostic.
    loaded_solves: [std::sync::atomic::AtomicUsize; 2],
}

impl<'a> StaticAnalysis<'a> {
    /// The analysis of `red` with the disc profile `profile`: builds the contact geometry (the
    /// gap field of the profile, `red.gap_points` mesh angles per tooth, averaged over the
    /// Hertz band of `red.contact_band_force`).
    ///
    /// # Errors
    /// [`Error::Numerical`] if a projection of the gap field fails.
    pub fn new(red: &'a Reducer, profile: &'a Profile) -> Result<Self> {
        let field = GapField::new(profile, red.gap_points, Some(red.contact_band()))?;
        Ok(Self::with_field(red, profile, field))
    }

    /// [`StaticAnalysis::new`] that solves `red` as it is, its meshes' backlash as the dead
    /// band of their force law (the dynamics' model), without taking up the play exactly:
    /// converges only where every mesh is well engaged (tests).
    #[cfg(test)]
    pub(crate) fn with_mesh_dead_band(red: &'a Reducer, profile: &'a Profile) -> Result<Self> {
        let mut sa = Self::new(red, profile)?;
        sa.red = Cow::Borrowed(red);
        sa.mesh_play = 0.0;
        Ok(sa)
    }

    /// The analysis of `red` on the contact geometry `field` of `profile`.
    pub(crate) fn with_field(red: &'a Reducer, profile: &'a Profile, field: GapField) -> Self {
        let (pin_centres, pin_gap) = pins_of(red);
        let carried = red.mesh.backlash > 0.0 && red.cranks > 0 && red.support == Support::Bearings;
        let (analysed, mesh_play) = if carried {
            let mut free = red.clone();
            free.mesh.backlash = 0.0;
            (Cow::Owned(free), 0.5 * red.mesh.backlash)
        } else {
            (Cow::Borrowed(red), 0.0)
        };
        StaticAnalysis {
            given: red,
            contact_law: red.contact.prepared(),
            red: analysed,
            mesh_play,
            profile,
            field,
            pin_centres,
            pin_gap,
            loaded_solves: Default::default(),
        }
    }

    /// The loaded solves of bearing support this analysis has made so far (each load step
    /// counted), and how many solves did not converge from their start and applied the torque
    /// in load steps (docs/model.md section 5.3).
    #[cfg(test)]
    pub(crate) fn loaded_solves(&self) -> [usize; 2] {
        self.loaded_solves
            .each_ref()
            .map(|c| c.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// The reducer analysed (as given).
    pub fn reducer(&self) -> &'a Reducer {
        self.given
    }

    /// The meshes' play taken up in direction `s` (+-1) at crank angle `phi` (rad, the locked
    /// input's position): the crank angle of the backlash-free copy (rad) and the twist to
    /// add to its solutions (rad); `(phi, 0)` without backlash (see `mesh_play`).
    fn play_taken_up(&self, phi: f64, s: f64) -> (f64, f64) {
        if self.mesh_play <= 0.0 {
            return (phi, 0.0);
        }
        let red = &*self.red;
        let sun_turn = s * red.ratio.signum() * self.mesh_play / red.mesh.sun_base_radius;
        (phi + red.kappa() * sun_turn, sun_turn / red.ratio)
    }

    /// The disc profile analysed.
    pub fn profile(&self) -> &'a Profile {
        self.profile
    }

    fn discs(&self) -> usize {
        match self.red.support {
            Support::Bearings => self.red.discs(),
            Support::Rigid { .. } => 1,
        }
    }

    fn wear_um(&self) -> f64 {
        self.profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6
    }

    fn fail(&self, phi: f64, what: &str) -> Error {
        Error::numerical(
            "static equilibrium",
            format!(
                "{what} at crank angle {:.4} deg (max wear {:.2} um)",
                phi.to_degrees(),
                self.wear_um()
            ),
        )
    }
}

/// True for the angle coordinates of [`Layout`] (input, output, and the third of every body).
/// A finite crank angle (rad) and torque (N m).
/// The pins of `red` with its part errors: centres (fixed frame, m) and the gap offsets of
/// their radius errors (m).
fn pins_of(red: &Reducer) -> (Vec<Vec2>, Vec<f64>) {
    let zp = red.geometry.pins;
    (
        (0..zp)
            .map(|j| red.geometry.pin_centre(j) + red.pin_displacement(j))
            .collect(),
        (0..zp).map(|j| -red.errors.pin_radius_error(j)).collect(),
    )
}

/// The sense of a torque or direction `x`: -1 below zero, +1 otherwise (zero loads forward).
pub(crate) fn sense(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

fn check_input(phi: f64, torque: f64) -> Result<()> {
    if phi.is_finite() && torque.is_finite() {
        Ok(())
    } else {
        Err(Error::invalid(
            "static analysis input",
            format!("crank angle {phi} rad, torque {torque} N m"),
            "must be finite",
        ))
    }
}

fn is_angle(i: usize) -> bool {
    i < 2 || (i - 2) % 3 == 2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use crate::geometry::WearMap;

    /// The analytic tangent equals central differences of the generalised forces (contacts,
    /// bearings and meshes) at loaded equilibria of a new and a worn disc, to the part left out
    /// to the difference error (steps of 1e-11 m: a pin within a step of touching would
    /// otherwise blur the kink of its law).
    #[test]
    fn tangent_equals_difference_of_forces() {
        let model = Config::paper().validate().unwrap();
        let n_map = 720;
        // A wear scar like the late stage's: 40 um deep, centred on the flank.
        let depth: Vec<f64> = (0..n_map)
            .map(|i| {
                let x = std::f64::consts::TAU * i as f64 / n_map as f64;
                40e-6 * (0.5 - 0.5 * (x - 0.8).cos()).powi(2)
            })
            .collect();
        for wear in [None, Some(WearMap::new(depth).unwrap())] {
            let profile = model.cycloid.profile(wear).unwrap();
            let sa = StaticAnalysis::new(&model.reducer, &profile).unwrap();
            let red = &model.reducer;
            let n = red.layout().dofs();
            let rp = red.geometry.pin_circle_radius;
            for &phi in &[0.05, 0.7] {
                let sol = sa.solve(phi, model.rating.rated_torque).unwrap();
                let fr = sa.frame(phi);
                let z = sol.deviations.clone();
                let mut memory = vec![vec![PinMemory::NONE; red.geometry.pins]; 2];
                let ev = sa.eval_bearings(&fr, &z, &mut memory, false).unwrap();
                let ks = sa.structural_stiffness(&fr, &z);
                let kt = sa.tangent_with(&ks, &ev);
                let mut worst: f64 = 0.0;
                for c in 0..n {
                    let h = if is_angle(c) { 1e-11 / rp } else { 1e-11 };
                    let mut zp = z.clone();
                    zp[c] += h;
                    let mut zm = z.clone();
                    zm[c] -= h;
                    let gp = sa
                        .eval_bearings(&fr, &zp, &mut memory.clone(), false)
                        .unwrap()
                        .g;
                    let gm = sa
                        .eval_bearings(&fr, &zm, &mut memory.clone(), false)
                        .unwrap()
                        .g;
                    for r in 0..n {
                        let sr = if is_angle(r) { rp } else { 1.0 };
                        let sc = if is_angle(c) { 1.0 / rp } else { 1.0 };
                        let fd = -(gp[r] - gm[r]) / (2.0 * h);
                        worst = worst.max(((fd - kt[(r, c)]) / sr * sc).abs());
                    }
                }
                // Scale: the stiffest entry (a bearing or contact, N/m).
                let kmax = (0..n)
                    .map(|i| {
                        let s = if is_angle(i) { rp * rp } else { 1.0 };
                        kt[(i, i)].abs() / s
                    })
                    .fold(0.0, f64::max);
                println!("phi {phi}: worst {worst:.3e} N/m of {kmax:.3e}");
                assert!(worst < 2e-5 * kmax, "{worst} vs {kmax}");
            }
        }
    }
}
