//! Static equilibrium of the reducer model under an output torque, with the input locked: the
//! catalogue's measuring set-up for torsional stiffness, lost motion and backlash
//! (physics-notes sections 8-9), and the loaded TE.
//!
//! **Set-up.** The input (sun) is locked at the angle that puts disc 1's eccentric at crank
//! angle `phi`; a torque `T` (N m) acts on the output carrier, positive counter-clockwise (the
//! sense of positive output rotation: it presses the flank `0 < mesh angle < pi`). The unknowns
//! are the deviations of every other coordinate from the nominal kinematics
//! ([`Reducer::nominal`]): the carrier twist `psi` (the output's TE under load), each crank's
//! centre and angle, each disc's centre and angle. The forces are those of the dynamic model:
//! meshes and bearings ([`Reducer::structural_forces`]) and the disc-pin contacts with the
//! line-contact law on the contact geometry both analyses share, the gap field of the actual
//! profile ([`GapField`]: exact global closest points at touching, averaged over the Hertz
//! band).
//!
//! **Solution.** Twist control: for a given carrier twist `psi` the other coordinates are in
//! equilibrium (a strongly convex problem: Newton's method with the exact tangent of the
//! contacts and backtracking on the residual norm), and the torque the carrier needs, `T(psi)`,
//! is monotone; the outer loop finds `T(psi) = T` by safeguarded Newton with the condensed
//! stiffness `dT/dpsi = K_oo - K_oi K_ii^-1 K_io` and an Euler predictor of the inner
//! coordinates. Every solution is returned only with its residual (every generalised force,
//! moments over the pin circle radius) below [`RESIDUAL_TOLERANCE`] of the force scale;
//! otherwise an error names the crank angle, the torque and the wear.
//!
//! **`T -> 0+` (STE).** With no load the bearings are undeformed and the mechanism moves as one
//! rigid body along its locked-input mode: carrier `+psi`, cranks `+(1 + Z1/Z2) psi` about their
//! axes, discs turning with the carrier. The first contact along that mode, over every pin of
//! both discs (no lever-arm cut-off), is the limit of the loaded twist as the torque tends to
//! zero ([`StaticAnalysis::first_contact`]): the static TE.
//!
//! **Rigid support** ([`Support::Rigid`], the paper's and Li's model): one disc with its centre
//! on the eccentric carries `load_share T`; the only unknown is the twist along the same mode,
//! and `load_share T = sum F_j m_j` with the mode lever `m_j = -d gap_j / d psi`
//! (about `l_j (Zp + Z1/Z2)/Zc`, physics-notes section 6).

use nalgebra::{DMatrix, DVector, Matrix2x3, Rotation2, Vector3};
use rayon::prelude::*;
use serde::Serialize;

use super::dynamics::GapField;
use super::{perp, rotation_difference, Drive, Layout, Reducer, Support, MAX_DOFS};
use crate::contact::DiscPose;
use crate::error::{Error, Result};
use crate::geometry::{cross, mesh_angle, Profile, Vec2};
use crate::te::ARCMIN_PER_RAD;

/// Relative residual every static solution is checked against: every generalised force of the
/// equilibrium (moments divided by the pin circle radius) below this times the force scale, the
/// sum of the pin forces (what the bearings carry), and at least the output torque over the
/// pin circle radius; or below the round-off floor of the contact forces where that is larger
/// ([`ROUNDOFF_GAP_ULPS`]).
pub const RESIDUAL_TOLERANCE: f64 = 1e-9;

/// Round-off of a computed gap, in units of the last place of the pin circle radius: a gap is
/// the difference of two lengths of the size of the pin circle radius (pin centre and pin path
/// in the disc frame) after a rotation, so it carries a few ulps of `Rp` (about 1e-17 m for a
/// 64 mm pin circle) whatever its size. The contact forces then carry `k_j` times that, and the
/// residual of an equilibrium cannot be driven below `4 eps Rp sum k_j`: for the example at
/// 0.1 % of its rated torque that is about 1e-8 of the force scale, above
/// [`RESIDUAL_TOLERANCE`]. Such a solution is accepted at that floor, which it reports
/// ([`StaticSolution::roundoff_floor`]).
pub const ROUNDOFF_GAP_ULPS: f64 = 4.0;

/// Largest elastic twist beyond first contact the static analysis follows, rad (about 34
/// arcmin: 30 times the twist of the example at its rated torque).
pub const MAX_TWIST: f64 = 0.01;

/// Most solves of one loading path in [`StaticAnalysis::solve_in_load_steps`].
pub const MAX_LOAD_STEPS: usize = 96;

/// Consecutive crank angles solved in one run of [`StaticAnalysis::solve_sequence`], each
/// started from the previous one.
pub const SEQUENCE_RUN: usize = 16;

/// One pin's share of a static solution (also of [`crate::contact::solve`]).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PinLoad {
    /// Pin index `j`.
    pub pin: usize,
    /// Profile parameter of the contact (global, rad): in the static analysis the pin centre's
    /// path parameter in the gap field, which is the contact point's on the unworn flank and
    /// close to it on a worn one; the closest point's in [`crate::contact::solve`].
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
#[derive(Debug, Clone, Serialize)]
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
    pub fn max_force(&self) -> f64 {
        self.pins.iter().map(|p| p.force).fold(0.0, f64::max)
    }
    /// Number of pins carrying a force.
    pub fn pins_in_contact(&self) -> usize {
        self.pins.iter().filter(|p| p.force > 0.0).count()
    }
}

/// A static equilibrium of the reducer.
#[derive(Debug, Clone, Serialize)]
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
    /// Relative residual of the equilibrium (see [`RESIDUAL_TOLERANCE`]).
    pub residual: f64,
    /// Round-off floor of the residual, relative like it: `4 eps Rp sum k_j` over the loaded
    /// pins over the force scale ([`ROUNDOFF_GAP_ULPS`]). The solution is accepted when its
    /// residual is below the larger of this and [`RESIDUAL_TOLERANCE`].
    pub roundoff_floor: f64,
    /// Coordinate deviations from the nominal kinematics (bearing support; empty with rigid
    /// support), in the layout of [`Layout`], SI.
    #[serde(skip)]
    pub deviations: Vec<f64>,
}

impl StaticSolution {
    /// Largest pin force over the discs, N.
    pub fn max_force(&self) -> f64 {
        self.discs.iter().map(|d| d.max_force()).fold(0.0, f64::max)
    }
    /// Largest Hertz pressure over the discs, Pa.
    pub fn max_pressure(&self) -> f64 {
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

/// One pin at the pose where it first touches (see [`StaticAnalysis::touching_pins`]).
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
/// contact in the solve's direction, rad).
struct Start<'s> {
    psi0: f64,
    near: Option<(&'s [f64], f64)>,
    beyond: Option<f64>,
    offsets: &'s [f64],
}

/// Static analysis of one reducer with one disc profile (both discs alike).
pub struct StaticAnalysis<'a> {
    red: &'a Reducer,
    profile: &'a Profile,
    field: GapField,
    /// Pin centres, ground frame, m (with the reducer's part errors).
    pin_centres: Vec<Vec2>,
    /// Added to each pin's gap, m: minus the pin's radius error.
    pin_gap: Vec<f64>,
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
        let (pin_centres, pin_gap) = pins_of(red);
        Ok(StaticAnalysis {
            red,
            profile,
            field,
            pin_centres,
            pin_gap,
        })
    }

    /// The reducer analysed.
    pub fn reducer(&self) -> &'a Reducer {
        self.red
    }

    /// The contact geometry.
    pub fn gap_field(&self) -> &GapField {
        &self.field
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

    /// Nominal positions at crank angle `phi` (input locked there).
    fn frame(&self, phi: f64) -> Frame {
        let red = self.red;
        let n = red.layout().dofs();
        let (mut q0, mut qd, mut qdd) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS], [0.0; MAX_DOFS]);
        red.nominal(
            red.input_angle_for_crank(phi),
            0.0,
            0.0,
            &mut q0[..n],
            &mut qd[..n],
            &mut qdd[..n],
        );
        Frame {
            phi,
            q0,
            offsets: Vec::new(),
        }
    }

    /// Deviations `z` of the locked-input rigid-body mode at carrier twist `psi` from the
    /// nominal positions of `fr` (bearings and meshes undeformed): carrier `+psi`, crank seats
    /// turned with it, cranks `+(1 + Z1/Z2) psi` about their axes, disc centres on the
    /// eccentrics, discs `+psi`.
    fn mode_deviation(&self, fr: &Frame, psi: f64, z: &mut [f64]) {
        let red = self.red;
        let lay = red.layout();
        let dk = red.crank_mode_ratio() * psi;
        let q0 = &fr.q0;
        z[Layout::SUN] = 0.0;
        z[Layout::OUT] = psi;
        for k in 0..red.cranks {
            let i = lay.crank(k);
            let dx = rotation_difference(&red.seat(k), q0[Layout::OUT], psi);
            z[i] = dx.x;
            z[i + 1] = dx.y;
            z[i + 2] = dk;
        }
        let a = red.geometry.eccentricity;
        for d in 0..red.discs() {
            let i = lay.disc(d);
            let ang0 = red.eccentric_angle(q0, &[0.0; MAX_DOFS]) + red.phase(d);
            let dc = rotation_difference(&Vec2::new(a, 0.0), ang0, dk);
            z[i] = dc.x;
            z[i + 1] = dc.y;
            z[i + 2] = psi;
        }
    }

    /// Pose of disc `d` at deviations `z` (bearing support).
    fn pose_from(&self, fr: &Frame, z: &[f64], d: usize) -> DiscPose {
        let lay = self.red.layout();
        let i = lay.disc(d);
        let q0 = &fr.q0;
        let (dc, dpsi) = if self.red.errors.has_crank_errors() {
            self.red.errors.disc_correction(
                self.red,
                self.red.eccentric_angle(q0, z) + self.red.phase(d),
                q0[Layout::OUT] + z[Layout::OUT],
            )
        } else {
            (Vec2::zeros(), 0.0)
        };
        DiscPose {
            crank_angle: fr.phi + self.red.phase(d),
            centre: Vec2::new(q0[i] + z[i], q0[i + 1] + z[i + 1]) + dc,
            angle: q0[i + 2] + z[i + 2] + self.red.profile_turn(d) + dpsi,
        }
    }

    /// Pose of disc `d` along the locked-input mode at twist `psi`, and `dc/dpsi`.
    fn mode_pose(&self, phi: f64, d: usize, psi: f64) -> (DiscPose, Vec2) {
        let ratio = self.red.crank_mode_ratio();
        match self.red.support {
            Support::Rigid { .. } => {
                let geo = &self.red.geometry;
                let zc = geo.disc_teeth() as f64;
                let ang = phi + ratio * psi;
                let c = Vec2::new(ang.cos(), ang.sin()) * geo.eccentricity;
                let carrier = self.red.input_angle_for_crank(phi) / self.red.ratio + psi;
                let (dc, dpsi) = self.red.errors.disc_correction(self.red, ang, carrier);
                (
                    DiscPose {
                        crank_angle: phi,
                        centre: c + dc,
                        angle: -phi / zc + psi + dpsi,
                    },
                    Vec2::new(-c.y, c.x) * ratio,
                )
            }
            Support::Bearings => {
                let fr = self.frame(phi);
                let mut z = [0.0; MAX_DOFS];
                let n = self.red.layout().dofs();
                self.mode_deviation(&fr, psi, &mut z[..n]);
                let pose = self.pose_from(&fr, &z, d);
                let c = pose.centre;
                (pose, Vec2::new(-c.y, c.x) * ratio)
            }
        }
    }

    /// Pin `j` at `pose` from the gap field; `hint` is its path parameter at a nearby pose
    /// (NaN: none, the kinematic guess is used).
    fn eval_pin(&self, pose: &DiscPose, j: usize, hint: f64) -> Result<PinEval> {
        self.eval_pin_from(pose, &Rotation2::new(pose.angle), j, hint, f64::NAN, 0.0)
    }

    /// [`StaticAnalysis::eval_pin`] with the pin's force at a nearby pose (N) as the contact
    /// law's starting guess; `rot` is the rotation of the disc by `pose.angle`; `offset` (m) is
    /// added to the gap.
    fn eval_pin_from(
        &self,
        pose: &DiscPose,
        rot: &Rotation2<f64>,
        j: usize,
        hint: f64,
        force: f64,
        offset: f64,
    ) -> Result<PinEval> {
        let rel = self.pin_centres[j] - pose.centre;
        let q = rot.inverse_transform_vector(&rel);
        let guess = self
            .profile
            .contact_parameter_guess(j, pose.crank_angle, pose.angle);
        // The cached parameter, unless it drifted a quarter tooth from the kinematics.
        let start = if hint.is_finite() && (hint - guess).abs() < 1.5 {
            hint
        } else {
            guess
        };
        let (ge, t) = self.field.eval(&q, start);
        let gap = ge.gap + offset + self.pin_gap[j];
        let (force, stiffness) = if gap < 0.0 {
            self.red
                .contact
                .force_from(-gap, ge.curvature, force)
                .map_err(|e| self.law_error(e, pose))?
        } else {
            (0.0, 0.0)
        };
        Ok(PinEval {
            pin: j,
            t,
            gap,
            curvature: ge.curvature,
            w: rot * ge.grad,
            rel,
            q,
            grad: ge.grad,
            force,
            stiffness,
            curvature_grad: ge.curvature_grad,
        })
    }

    /// Every pin of one disc at `pose`; `cache` holds the pins' path parameters (updated).
    fn eval_pins(&self, pose: &DiscPose, cache: &mut [f64]) -> Result<Vec<PinEval>> {
        let rot = Rotation2::new(pose.angle);
        cache
            .iter_mut()
            .enumerate()
            .map(|(j, hint)| {
                let p = self.eval_pin_from(pose, &rot, j, *hint, f64::NAN, 0.0)?;
                *hint = p.t;
                Ok(p)
            })
            .collect()
    }

    fn law_error(&self, e: Error, pose: &DiscPose) -> Error {
        match e {
            Error::Numerical { message, .. } => Error::numerical(
                "static equilibrium",
                format!(
                    "{message} at crank angle {:.4} deg (max wear {:.2} um)",
                    pose.crank_angle.to_degrees(),
                    self.wear_um()
                ),
            ),
            other => other,
        }
    }

    /// Forces of the bearing-supported model at deviations `z`. `memory` holds every pin's
    /// last evaluation (updated). With `lazy`, a pin whose remembered gap exceeds twice the
    /// largest displacement of its centre in the disc frame since then (`|dc| + |p - c|
    /// |dpsi|`; the field's gradient is within 1.1 of unit length where gaps are below a
    /// millimetre) is known to be open and is not evaluated again: its entry carries no force
    /// and its remembered gap. Every solution is returned from a full evaluation.
    fn eval_bearings(
        &self,
        fr: &Frame,
        z: &[f64],
        memory: &mut [Vec<PinMemory>],
        lazy: bool,
    ) -> Result<Eval> {
        let red = self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let mut g = [0.0; MAX_DOFS];
        let zero = [0.0; MAX_DOFS];
        red.structural_forces(&fr.q0[..n], &z[..n], &zero[..n], &mut g[..n]);
        let mut scale: f64 = 0.0;
        let mut stiffness: f64 = 0.0;
        let mut pins = Vec::with_capacity(2);
        let mut poses = Vec::with_capacity(2);
        for (d, mem) in memory.iter_mut().enumerate() {
            let pose = self.pose_from(fr, z, d);
            let id = lay.disc(d);
            let rot = Rotation2::new(pose.angle);
            let zp = mem.len();
            let mut ev = Vec::with_capacity(zp);
            for (j, m) in mem.iter_mut().enumerate() {
                let rel = self.pin_centres[j] - pose.centre;
                if lazy && m.gap.is_finite() {
                    let moved =
                        (pose.centre - m.centre).norm() + rel.norm() * (pose.angle - m.angle).abs();
                    if m.gap > 2.0 * moved {
                        ev.push(PinEval::open(j, m.t, m.gap, rel));
                        continue;
                    }
                }
                let offset = fr.offsets.get(d * zp + j).copied().unwrap_or(0.0);
                let p = self.eval_pin_from(&pose, &rot, j, m.t, m.force, offset)?;
                *m = PinMemory {
                    t: p.t,
                    gap: p.gap,
                    force: p.force,
                    centre: pose.centre,
                    angle: pose.angle,
                };
                ev.push(p);
            }
            scale += ev.iter().map(|p| p.force).sum::<f64>();
            stiffness += ev.iter().map(|p| p.stiffness).sum::<f64>();
            for p in ev.iter().filter(|p| p.force > 0.0) {
                // Q = F d(gap)/dq: d gap/dc = -w, d gap/dpsi = -(p - c) x w.
                g[id] -= p.force * p.w.x;
                g[id + 1] -= p.force * p.w.y;
                g[id + 2] -= p.force * cross(&p.rel, &p.w);
            }
            pins.push(ev);
            poses.push(pose);
        }
        Ok(Eval {
            g,
            pins,
            poses,
            scale,
            roundoff: self.roundoff(stiffness),
        })
    }

    /// Round-off floor (N) of the forces of contacts with total stiffness `stiffness` (N/m)
    /// ([`ROUNDOFF_GAP_ULPS`]).
    fn roundoff(&self, stiffness: f64) -> f64 {
        ROUNDOFF_GAP_ULPS * f64::EPSILON * self.red.geometry.pin_circle_radius * stiffness
    }

    /// Structural tangent stiffness `-dQ/dq` (meshes and bearings) by central differences of
    /// [`Reducer::structural_forces`] at deviations `z` (linear springs on exact rigid-body
    /// kinematics: the differences are exact to round-off).
    fn structural_stiffness(&self, fr: &Frame, z: &[f64]) -> DMatrix<f64> {
        let red = self.red;
        let n = red.layout().dofs();
        let rp = red.geometry.pin_circle_radius;
        let mut k = DMatrix::zeros(n, n);
        let zero = [0.0; MAX_DOFS];
        let mut zz = [0.0; MAX_DOFS];
        zz[..n].copy_from_slice(&z[..n]);
        // The pins in holes of a single-stage drive touch at zero load: steps well below their
        // approach at the smallest loads solved (1e-8 m at 1 N m) keep the tangent of each
        // contact on its own side of the kink.
        let step = match red.drive {
            Drive::Rv => 1e-8,
            Drive::SingleStage(_) => 1e-12,
        };
        for c in 0..n {
            let h = if is_angle(c) { step / rp } else { step };
            let (mut gp, mut gm) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
            zz[c] = z[c] + h;
            red.structural_forces(&fr.q0[..n], &zz[..n], &zero[..n], &mut gp[..n]);
            zz[c] = z[c] - h;
            red.structural_forces(&fr.q0[..n], &zz[..n], &zero[..n], &mut gm[..n]);
            zz[c] = z[c];
            for r in 0..n {
                k[(r, c)] = -(gp[r] - gm[r]) / (2.0 * h);
            }
        }
        k
    }

    /// Tangent stiffness of the bearing-supported model: structural plus, for each disc, the
    /// 3 x 3 stiffness of its pin forces on its centre `c` and angle `psi`. A pin's gap is
    /// `g(q)`, `q = R(-psi)(p - c)`, its generalised force `Q = F grad_z g` with
    /// `F = F(-g)` the contact law, so `-dQ/dz = k a a^T - F d2g/dz2` with `a = grad_z g =
    /// (-w, -(p - c) x w)`, `w = R(psi) grad_q g`: the contact stiffness and the geometric
    /// stiffness of the turning normals (large on a near-conformal worn flank). `d2g/dz2 =
    /// B^T H B` plus the rotation's own second derivatives, with `H` the gap Hessian in the
    /// fixed frame ([`GapField::hessian`]) and `B = dq/dz = [-I, -J (p - c)]` in the
    /// fixed frame. The law's flank curvature follows the contact along the flank, so
    /// `dF/dz` also has `dF/dkappa B^T grad kappa` (about 5e-4 of the contact term at the
    /// rated torque, and not symmetric).
    ///
    /// `k_struct` is the structural stiffness of the frame, kept over the solve (the bearings
    /// and meshes are linear springs); the pins in holes of a single-stage drive engage and
    /// release with the load, so there it is rebuilt at `z`.
    fn tangent(&self, k_struct: &DMatrix<f64>, ev: &Eval, fr: &Frame, z: &[f64]) -> DMatrix<f64> {
        if let Drive::SingleStage(_) = self.red.drive {
            let ks = self.structural_stiffness(fr, z);
            return self.tangent_with(&ks, ev);
        }
        self.tangent_with(k_struct, ev)
    }

    fn tangent_with(&self, k_struct: &DMatrix<f64>, ev: &Eval) -> DMatrix<f64> {
        let lay = self.red.layout();
        let mut k = k_struct.clone();
        let law = &self.red.contact;
        for (d, pose) in ev.poses.iter().enumerate() {
            let id = lay.disc(d);
            let rot = Rotation2::new(pose.angle);
            for p in ev.pins[d].iter().filter(|p| p.force > 0.0) {
                let jr = -perp(p.rel);
                let b = Matrix2x3::from_columns(&[Vec2::new(-1.0, 0.0), Vec2::new(0.0, -1.0), jr]);
                let hf = rot * self.field.hessian(&p.q, p.t) * rot.inverse();
                let mut hess = b.transpose() * hf * b;
                let jw = perp(p.w);
                hess[(0, 2)] -= jw.x;
                hess[(2, 0)] -= jw.x;
                hess[(1, 2)] -= jw.y;
                hess[(2, 1)] -= jw.y;
                hess[(2, 2)] -= p.w.dot(&p.rel);
                let a = Vector3::new(-p.w.x, -p.w.y, -cross(&p.rel, &p.w));
                let kappa = rot * p.curvature_grad;
                let dk = Vector3::new(-kappa.x, -kappa.y, jr.dot(&kappa));
                let force_kappa = law.force_curvature_derivative(p.force, p.stiffness, p.curvature);
                let kd = a * a.transpose() * p.stiffness
                    - a * dk.transpose() * force_kappa
                    - hess * p.force;
                let mut block = k.view_mut((id, id), (3, 3));
                block += kd;
            }
        }
        k
    }

    /// Largest scaled residual of the inner coordinates (every one but input and output):
    /// forces in N, moments divided by the pin circle radius.
    fn inner_residual(&self, g: &[f64]) -> f64 {
        let n = self.red.layout().dofs();
        let rp = self.red.geometry.pin_circle_radius;
        (2..n)
            .map(|i| g[i].abs() / if is_angle(i) { rp } else { 1.0 })
            .fold(0.0, f64::max)
    }

    /// Equilibrium of every coordinate but input and output at the carrier twist fixed in `z`
    /// (deviations, updated in place): Newton's method with backtracking on the residual norm.
    /// Returns the converged evaluation and the tangent. `force_floor` (N) is the least force
    /// scale of the convergence test.
    fn inner_solve(
        &self,
        fr: &Frame,
        z: &mut [f64],
        k_struct: &DMatrix<f64>,
        memory: &mut [Vec<PinMemory>],
        force_floor: f64,
    ) -> Result<(Eval, DMatrix<f64>)> {
        let n = self.red.layout().dofs();
        let m = n - 2;
        let rp = self.red.geometry.pin_circle_radius;
        let merit = |e: &Eval| -> f64 {
            (2..n)
                .map(|i| {
                    let x = e.g[i] / if is_angle(i) { rp } else { 1.0 };
                    x * x
                })
                .sum()
        };
        let mut ev = self.eval_bearings(fr, z, memory, true)?;
        let mut stalled = 0;
        // The tangent is kept while the residual falls at least fourfold per step (a modified
        // Newton method), and rebuilt otherwise.
        let mut kt: Option<DMatrix<f64>> = None;
        let mut last_res = f64::INFINITY;
        // Levenberg-Marquardt damping of the Newton step (relative to the diagonal), raised
        // when a step of the exact tangent finds no descent away from the round-off floor (a
        // disc on a ridge of a worn flank, where the tangent is indefinite), reset after a
        // descent.
        let mut damping = 0.0;
        for _ in 0..100 {
            let res = self.inner_residual(&ev.g);
            let scale = ev.scale.max(force_floor).max(1e-300);
            // Whether `kt` is the tangent at the current state `ev`.
            let fresh = kt.is_none() || res > 0.25 * last_res;
            if fresh {
                kt = Some(self.tangent(k_struct, &ev, fr, z));
            }
            last_res = res;
            // Converged to a hundredth of the acceptance tolerance, or at the round-off floor of
            // the forces (the residual stopped falling): return the tangent at the solution.
            if res <= 0.01 * RESIDUAL_TOLERANCE * scale || stalled >= 2 {
                let kt = match kt {
                    Some(kt) if fresh => kt,
                    _ => self.tangent(k_struct, &ev, fr, z),
                };
                return Ok((ev, kt));
            }
            let kt = kt.as_ref().expect("tangent built above");
            let mut kii = kt.view((2, 2), (m, m)).into_owned();
            if damping > 0.0 {
                for i in 0..m {
                    kii[(i, i)] += damping * kii[(i, i)].abs();
                }
            }
            let rhs = DVector::from_iterator(m, (2..n).map(|i| ev.g[i]));
            let step = kii
                .lu()
                .solve(&rhs)
                .ok_or_else(|| self.fail(fr.phi, "the inner stiffness matrix is singular"))?;
            let m0 = merit(&ev);
            let base: Vec<f64> = z[..n].to_vec();
            let mut alpha = 1.0;
            loop {
                for i in 0..m {
                    z[2 + i] = base[2 + i] + alpha * step[i];
                }
                // A trial step long enough to take a contact out of the law's validity (a
                // Newton step across a sharp feature of a worn flank) is shortened like one
                // that raises the residual.
                let trial = match self.eval_bearings(fr, z, memory, true) {
                    Ok(trial) => trial,
                    Err(_) if alpha >= 1e-4 => {
                        alpha *= 0.5;
                        continue;
                    }
                    Err(e) => return Err(e),
                };
                let mt = merit(&trial);
                if mt <= m0 * (1.0 - 1e-4 * alpha) {
                    stalled = 0;
                    damping = 0.0;
                    ev = trial;
                    break;
                }
                if alpha < 1e-4 && res > 1e-6 * scale && damping < 1e8 {
                    // No descent along this step: damp it and try again from the same state.
                    damping = if damping == 0.0 { 1e-3 } else { 10.0 * damping };
                    z[..n].copy_from_slice(&base);
                    break;
                }
                if res <= 1e-6 * scale || alpha < 1e-4 {
                    // At the round-off floor (or lost): keep the better of the two states.
                    stalled += 1;
                    if mt < m0 {
                        ev = trial;
                    } else {
                        z[..n].copy_from_slice(&base);
                    }
                    break;
                }
                alpha *= 0.5;
            }
        }
        Err(self.fail(
            fr.phi,
            "the bearing equilibrium did not converge in 100 Newton steps",
        ))
    }

    /// Equilibrium under the output torque `torque` with every coordinate but the input free
    /// (torque control), by Newton's method on all of them at once from the locked-input mode
    /// at `psi0` plus the twist estimate, with backtracking on the scaled residual norm: the
    /// fast path of [`StaticAnalysis::solve`]. `None` when a step fails to reduce the residual
    /// or the tangent is singular (near first contact, where the torque-twist curve has its
    /// kink); the caller then takes the twist-controlled path, which always converges.
    fn torque_controlled(
        &self,
        fr: &Frame,
        torque: f64,
        start: &Start,
        z: &mut [f64],
        k_struct: &DMatrix<f64>,
        memory: &mut [Vec<PinMemory>],
    ) -> Result<Option<(Eval, DMatrix<f64>)>> {
        let n = self.red.layout().dofs();
        let m = n - 1;
        let rp = self.red.geometry.pin_circle_radius;
        let force_floor = torque.abs() / rp;
        let s = if torque < 0.0 { -1.0 } else { 1.0 };
        match start.near {
            // The neighbour's deviations, moved along the mode by the change of first contact.
            Some((near, near_psi0)) => {
                let (mut a, mut b) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
                self.mode_deviation(fr, near_psi0, &mut a[..n]);
                self.mode_deviation(fr, start.psi0, &mut b[..n]);
                for i in 0..n {
                    z[i] = near[i] + b[i] - a[i];
                }
                z[Layout::SUN] = 0.0;
            }
            None => self.mode_deviation(fr, start.psi0 + s * self.twist_guess(torque), z),
        }
        // Residual of coordinate i (output torque included), and scaled: moments over the pin
        // circle radius.
        let residual = |g: &[f64; MAX_DOFS], i: usize| -> f64 {
            if i == Layout::OUT {
                g[i] + torque
            } else {
                g[i]
            }
        };
        let scaled = |g: &[f64; MAX_DOFS], i: usize| -> f64 {
            residual(g, i) / if is_angle(i) { rp } else { 1.0 }
        };
        let merit = |e: &Eval| -> f64 { (1..n).map(|i| scaled(&e.g, i).powi(2)).sum() };
        let mut ev = self.eval_bearings(fr, z, memory, true)?;
        if start.near.is_none() {
            // Cold: along the mode until its torque reaches the target (Newton then starts
            // from the stiff side, where its steps do not overshoot into new contacts).
            let mut x = self.twist_guess(torque);
            for _ in 0..20 {
                let mode_torque = self.mode_torque(fr, start.psi0 + s * x, &ev.g);
                if s * mode_torque >= torque.abs() || x > 0.5 * MAX_TWIST {
                    break;
                }
                x *= 2.0;
                self.mode_deviation(fr, start.psi0 + s * x, z);
                // A failed evaluation sends the solve to the twist-controlled path.
                let Ok(next) = self.eval_bearings(fr, z, memory, true) else {
                    return Ok(None);
                };
                ev = next;
            }
        }
        let mut kt: Option<DMatrix<f64>> = None;
        let mut last_res = f64::INFINITY;
        for _ in 0..30 {
            let res = (1..n).map(|i| scaled(&ev.g, i).abs()).fold(0.0, f64::max);
            let scale = ev.scale.max(force_floor).max(1e-300);
            // A tangent is closed form per loaded pin, cheaper than an evaluation: it is rebuilt
            // at every step unless the residual fell a thousandfold.
            let fresh = kt.is_none() || res > 1e-3 * last_res;
            if fresh {
                kt = Some(self.tangent(k_struct, &ev, fr, z));
            }
            last_res = res;
            if res <= 0.01 * RESIDUAL_TOLERANCE * scale {
                let kt = match kt {
                    Some(kt) if fresh => kt,
                    _ => self.tangent(k_struct, &ev, fr, z),
                };
                return Ok(Some((ev, kt)));
            }
            let kt = kt.as_ref().expect("tangent built above");
            let k = kt.view((1, 1), (m, m)).into_owned();
            let rhs = DVector::from_iterator(m, (1..n).map(|i| residual(&ev.g, i)));
            let Some(step) = k.lu().solve(&rhs) else {
                return Ok(None);
            };
            let m0 = merit(&ev);
            let base: Vec<f64> = z[..n].to_vec();
            let mut alpha = 1.0;
            loop {
                for i in 0..m {
                    z[1 + i] = base[1 + i] + alpha * step[i];
                }
                let Ok(trial) = self.eval_bearings(fr, z, memory, true) else {
                    return Ok(None);
                };
                let mt = merit(&trial);
                if mt <= m0 * (1.0 - 1e-4 * alpha) {
                    ev = trial;
                    // At the round-off floor a step barely reduces the residual: accept there.
                    if mt > 0.25 * m0 && res <= 0.5 * ev.roundoff {
                        let kt = self.tangent(k_struct, &ev, fr, z);
                        return Ok(Some((ev, kt)));
                    }
                    break;
                }
                if alpha < 1e-3 {
                    // At the round-off floor of the contact forces the residual no longer
                    // falls: accept there (the caller's check applies the floor).
                    if res <= 0.5 * ev.roundoff {
                        let kt = self.tangent(k_struct, &ev, fr, z);
                        return Ok(Some((ev, kt)));
                    }
                    return Ok(None);
                }
                alpha *= 0.5;
            }
        }
        Ok(None)
    }

    /// Output torque (N m) that balances the generalised forces `g` along the locked-input mode
    /// at twist `psi`: `-sum_i g_i dz_i/dpsi` (the mode's virtual work; its tangent by a
    /// central difference of [`StaticAnalysis::mode_deviation`]).
    fn mode_torque(&self, fr: &Frame, psi: f64, g: &[f64; MAX_DOFS]) -> f64 {
        let n = self.red.layout().dofs();
        let h = 1e-6;
        let (mut a, mut b) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
        self.mode_deviation(fr, psi - h, &mut a[..n]);
        self.mode_deviation(fr, psi + h, &mut b[..n]);
        -(0..n)
            .map(|i| g[i] * (b[i] - a[i]) / (2.0 * h))
            .sum::<f64>()
    }

    /// `dz/dpsi` of the inner coordinates at fixed inner forces: `-K_ii^-1 K_io` (zero for the
    /// input and output entries).
    fn condensation_direction(&self, kt: &DMatrix<f64>) -> Vec<f64> {
        let n = self.red.layout().dofs();
        let m = n - 2;
        let o = Layout::OUT;
        let kii = kt.view((2, 2), (m, m)).into_owned();
        let kio = DVector::from_iterator(m, (2..n).map(|i| kt[(i, o)]));
        let mut out = vec![0.0; n];
        if let Some(x) = kii.lu().solve(&kio) {
            for i in 0..m {
                out[2 + i] = -x[i];
            }
        }
        out
    }

    /// Condensed torsional stiffness `K_oo - K_oi K_ii^-1 K_io` (N m/rad).
    fn condensed(&self, kt: &DMatrix<f64>) -> f64 {
        let n = self.red.layout().dofs();
        let o = Layout::OUT;
        let dz = self.condensation_direction(kt);
        kt[(o, o)] + (2..n).map(|i| kt[(o, i)] * dz[i]).sum::<f64>()
    }

    /// Mode lever `m_j = -d gap_j / d psi` of a pin along the locked-input mode with
    /// `dc/dpsi` = `dc`.
    fn mode_lever(p: &PinEval, dc: Vec2) -> f64 {
        p.w.dot(&dc) + cross(&p.rel, &p.w)
    }

    /// Rigid support: pins of the disc at twist `psi`, the torque `T(psi) = sum F_j m_j /
    /// share` and its derivative.
    fn eval_rigid(
        &self,
        phi: f64,
        psi: f64,
        cache: &mut [f64],
    ) -> Result<(Vec<PinEval>, DiscPose, f64, f64)> {
        let Support::Rigid { load_share } = self.red.support else {
            unreachable!("rigid evaluation of a bearing-supported reducer")
        };
        let (pose, dc) = self.mode_pose(phi, 0, psi);
        let pins = self.eval_pins(&pose, cache)?;
        let (mut t, mut k) = (0.0, 0.0);
        for p in &pins {
            let lever = Self::mode_lever(p, dc);
            t += p.force * lever;
            k += p.stiffness * lever * lever;
        }
        Ok((pins, pose, t / load_share, k / load_share))
    }

    /// Gap of pin `j` of disc `d` along the mode at twist `psi`, and its mode lever; `hint` is
    /// the pin's path parameter (updated).
    fn mode_gap(
        &self,
        phi: f64,
        d: usize,
        j: usize,
        psi: f64,
        hint: &mut f64,
    ) -> Result<(f64, f64)> {
        let (pose, dc) = self.mode_pose(phi, d, psi);
        let p = self.eval_pin(&pose, j, *hint)?;
        *hint = p.t;
        Ok((p.gap, Self::mode_lever(&p, dc)))
    }

    /// Carrier twist (rad) at which the unloaded mechanism first touches a pin when the carrier
    /// is turned, input locked, in direction `direction` (+1 counter-clockwise, -1 clockwise),
    /// at crank angle `phi`: the `T -> 0+` limit of the loaded twist (the static TE in that
    /// direction), over every pin of every disc. Zero for an unmodified, unworn disc.
    ///
    /// Each pin's touching twist along the mode is solved (Newton on `gap_j(psi) = 0`,
    /// `d gap_j/d psi = -m_j`, bisection where Newton does not settle) for the candidates whose
    /// linear estimate `gap_j / m_j` is near the smallest, then every pin is checked at the
    /// result (a pin that closes faster than linearly can touch first).
    ///
    /// # Errors
    /// [`Error::Numerical`] if no pin can stop the mechanism.
    pub fn first_contact(&self, phi: f64, direction: f64) -> Result<f64> {
        let s = if direction < 0.0 { -1.0 } else { 1.0 };
        let zp = self.red.geometry.pins;
        let est = self.stopping_pins(phi, s)?;
        let lin_min = est.iter().map(|e| s * e.2).fold(f64::INFINITY, f64::min);
        if !lin_min.is_finite() {
            return Err(self.fail(phi, "no pin can stop the mechanism"));
        }
        let mut best = f64::INFINITY;
        for margin in [0.25 * lin_min.abs() + 1e-6, f64::INFINITY] {
            for &(d, j, e, t, _) in &est {
                if s * e - lin_min > margin {
                    continue;
                }
                if let Some(b) = self.touching_twist(phi, d, j, e, s, t)? {
                    best = best.min(s * b);
                }
            }
            if best.is_finite() {
                break;
            }
        }
        if !best.is_finite() {
            return Err(self.fail(phi, "no pin stops the mechanism"));
        }
        for _ in 0..10 {
            let psi = s * best;
            let mut improved = false;
            for d in 0..self.discs() {
                let (pose, _) = self.mode_pose(phi, d, psi);
                for j in 0..zp {
                    let p = self.eval_pin(&pose, j, f64::NAN)?;
                    if p.gap < -1e-13 {
                        if let Some(b) = self.touching_twist(phi, d, j, psi, s, p.t)? {
                            if s * b < best {
                                best = s * b;
                                improved = true;
                            }
                        }
                    }
                }
            }
            if !improved {
                break;
            }
        }
        Ok(s * best)
    }

    /// Every pin that can stop the unloaded mechanism turned in direction `direction` at crank
    /// angle `phi`, with its own touching twist: the pins whose linear estimate `gap_j / m_j`
    /// could fall below the smallest if every gap changed by up to `gap_reach` (m), each
    /// solved as in
    /// [`StaticAnalysis::first_contact`] (which is the extreme of these twists over every
    /// pin). Each entry carries what a small error needs to move that twist to first order
    /// (the gap's gradient and the pin's position at the touching pose):
    /// [`crate::te::revolution`] builds the transmission error of a reducer with part errors
    /// from these entries.
    ///
    /// # Errors
    /// [`Error::Numerical`] if no pin can stop the mechanism.
    pub fn touching_pins(
        &self,
        phi: f64,
        direction: f64,
        gap_reach: f64,
    ) -> Result<Vec<TouchingPin>> {
        let s = if direction < 0.0 { -1.0 } else { 1.0 };
        let est = self.stopping_pins(phi, s)?;
        let Some(&(_, _, e_best, _, m_best)) =
            est.iter().min_by(|a, b| (s * a.2).total_cmp(&(s * b.2)))
        else {
            return Err(self.fail(phi, "no pin can stop the mechanism"));
        };
        let lin_min = s * e_best;
        let mut out = Vec::new();
        for &(d, j, e, t, m) in &est {
            let reach = gap_reach * (1.0 / m.abs() + 1.0 / m_best.abs());
            if s * e - lin_min > reach + 0.25 * lin_min.abs() + 1e-6 {
                continue;
            }
            let Some(b) = self.touching_twist(phi, d, j, e, s, t)? else {
                continue;
            };
            let at = |psi: f64| -> Result<(f64, Vec2, f64, Vec2)> {
                let (pose, dc) = self.mode_pose(phi, d, psi);
                let p = self.eval_pin(&pose, j, t)?;
                Ok((Self::mode_lever(&p, dc), p.w, cross(&p.rel, &p.w), p.rel))
            };
            let (m, w, arm, rel) = at(b)?;
            // Rates along the mode by central differences over 1e-6 rad (2 arcsec, a hundredth
            // of the twists they extrapolate over).
            let h = 1e-6;
            let (hi, lo) = (at(b + h)?, at(b - h)?);
            out.push(TouchingPin {
                disc: d,
                pin: j,
                twist: b,
                lever: m,
                gradient: w,
                position: rel,
                lever_rate: (hi.0 - lo.0) / (2.0 * h),
                gradient_rate: (hi.1 - lo.1) / (2.0 * h),
                arm_rate: (hi.2 - lo.2) / (2.0 * h),
            });
            let _ = arm;
        }
        if out.is_empty() {
            return Err(self.fail(phi, "no pin stops the mechanism"));
        }
        Ok(out)
    }

    /// Twist (rad) at which pin `pin` of disc `disc` touches when the unloaded mechanism is
    /// turned in direction `direction` at crank angle `phi`, solved from the estimate
    /// `estimate` (rad) as in [`StaticAnalysis::first_contact`]; `None` if the pin moves away.
    ///
    /// # Errors
    /// [`Error::Numerical`] if the contact geometry cannot be evaluated.
    pub fn pin_touching_twist(
        &self,
        phi: f64,
        disc: usize,
        pin: usize,
        estimate: f64,
        direction: f64,
    ) -> Result<Option<f64>> {
        let s = if direction < 0.0 { -1.0 } else { 1.0 };
        self.touching_twist(phi, disc, pin, estimate, s, f64::NAN)
    }

    /// The same analysis for the reducer `red` (same profile and contact geometry, e.g. the
    /// reducer without its part errors), without rebuilding the contact geometry.
    ///
    /// # Errors
    /// [`Error::Invalid`] if `red` has another gap table or band than this analysis's reducer.
    pub fn for_reducer<'b>(&self, red: &'b Reducer) -> Result<StaticAnalysis<'b>>
    where
        'a: 'b,
    {
        if red.geometry != self.red.geometry
            || red.gap_points != self.red.gap_points
            || red.contact_band_force != self.red.contact_band_force
            || red.contact_envelope != self.red.contact_envelope
            || red.contact != self.red.contact
        {
            return Err(Error::invalid(
                "static analysis reducer",
                "another stage or contact geometry",
                "must share the stage and the contact geometry of the analysis",
            ));
        }
        let (pin_centres, pin_gap) = pins_of(red);
        Ok(StaticAnalysis {
            red,
            profile: self.profile,
            field: self.field.clone(),
            pin_centres,
            pin_gap,
        })
    }

    /// The pins of every disc that can stop the unloaded mechanism turned in direction `s`
    /// (+-1) at crank angle `phi` ([`Stopping`]).
    fn stopping_pins(&self, phi: f64, s: f64) -> Result<Vec<Stopping>> {
        let zp = self.red.geometry.pins;
        let mut est = Vec::with_capacity(2 * zp);
        for d in 0..self.discs() {
            let (pose, dc) = self.mode_pose(phi, d, 0.0);
            for j in 0..zp {
                let p = self.eval_pin(&pose, j, f64::NAN)?;
                let m = Self::mode_lever(&p, dc);
                if s * m > self.lever_floor() {
                    est.push((d, j, p.gap / m, p.t, m));
                }
            }
        }
        Ok(est)
    }

    /// Smallest mode lever (m/rad) of a pin that can stop the mechanism: `1e-9 Rp` (64 pm for
    /// the example). A pin at the exact tip or root of a tooth has no lever; its computed lever
    /// is round-off (measured 2e-14 to 1.6e-13 m/rad at crank angle 0), and with a gap at
    /// round-off too (1e-17 m) it would put a first contact anywhere within 3e-4 rad. A pin
    /// with a lever of `1e-9 Rp` would need a billion times the force of one at the pin circle
    /// to hold a torque: this is a floor of the arithmetic, not a cut-off of the physics.
    fn lever_floor(&self) -> f64 {
        1e-9 * self.red.geometry.pin_circle_radius
    }

    /// Twist (rad) at which pin `j` of disc `d` touches, near the estimate `est`, turning in
    /// direction `s`; `None` if it moves away.
    fn touching_twist(
        &self,
        phi: f64,
        d: usize,
        j: usize,
        est: f64,
        s: f64,
        t_hint: f64,
    ) -> Result<Option<f64>> {
        let mut hint = t_hint;
        let mut b = est;
        for _ in 0..12 {
            let (g, m) = self.mode_gap(phi, d, j, b, &mut hint)?;
            if s * m <= self.lever_floor() {
                return Ok(None);
            }
            if g.abs() < 1e-14 {
                return Ok(Some(b));
            }
            b += g / m;
        }
        // Bracket the sign change of the gap (it decreases with s psi) and bisect.
        let mut w = 1e-7 + 0.1 * est.abs();
        while w <= MAX_TWIST {
            let (lo, hi) = (est - w, est + w);
            let glo = self.mode_gap(phi, d, j, lo, &mut hint)?.0;
            let ghi = self.mode_gap(phi, d, j, hi, &mut hint)?.0;
            if glo * ghi < 0.0 {
                let (mut a, mut fa, mut c) = (lo, glo, hi);
                for _ in 0..200 {
                    let mid = 0.5 * (a + c);
                    let fm = self.mode_gap(phi, d, j, mid, &mut hint)?.0;
                    if fm.abs() < 1e-15 || (c - a).abs() < 1e-16 {
                        return Ok(Some(mid));
                    }
                    if (fm < 0.0) == (fa < 0.0) {
                        a = mid;
                        fa = fm;
                    } else {
                        c = mid;
                    }
                }
                return Ok(Some(0.5 * (a + c)));
            }
            w *= 2.0;
        }
        Ok(None)
    }

    /// Static equilibrium at crank angle `phi` (rad) under output torque `torque` (N m; zero
    /// gives the `T -> 0+` pose of the forward direction with zero forces).
    ///
    /// # Errors
    /// [`Error::Invalid`] for a non-finite input; [`Error::Numerical`] naming the crank angle,
    /// torque and wear if the equilibrium is not reached to [`RESIDUAL_TOLERANCE`], or if the
    /// contact law leaves its range.
    pub fn solve(&self, phi: f64, torque: f64) -> Result<StaticSolution> {
        check_input(phi, torque)?;
        let s = if torque < 0.0 { -1.0 } else { 1.0 };
        let psi0 = self.first_contact(phi, s)?;
        self.solve_from(phi, torque, psi0)
    }

    /// [`StaticAnalysis::solve`] with the first-contact twist `psi0` (rad) of the torque's
    /// direction already known.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`].
    pub fn solve_from(&self, phi: f64, torque: f64, psi0: f64) -> Result<StaticSolution> {
        self.solve_near(phi, torque, psi0, None)
    }

    /// [`StaticAnalysis::solve_from`] started from `near`, the solution at a nearby crank angle
    /// or torque of the same direction (a continuation: fewer Newton steps than the cold start;
    /// the solution is the same to the convergence tolerance). A `near` of the other direction
    /// is ignored.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`].
    pub fn solve_near(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
    ) -> Result<StaticSolution> {
        self.solve_with_offsets(phi, torque, psi0, near, &[])
    }

    /// [`StaticAnalysis::solve_near`] with `offsets` (m, `2 x Zp` disc-major, or empty) added
    /// to the pins' gaps: an extra approach that a model outside this one supplies, such as the
    /// body deflection of a flexible disc ([`crate::fem::flex`]). Bearing support only (the
    /// rigid support ignores them). The first-contact twist `psi0` is that of the unloaded
    /// mechanism (the offsets vanish with the load).
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`]; [`Error::Invalid`] if `offsets` is neither empty nor
    /// `2 x Zp` long or holds a non-finite value.
    pub fn solve_with_offsets(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        offsets: &[f64],
    ) -> Result<StaticSolution> {
        let zp = self.red.geometry.pins;
        if !(offsets.is_empty() || offsets.len() == 2 * zp)
            || offsets.iter().any(|o| !o.is_finite())
        {
            return Err(Error::invalid(
                "static analysis gap offsets",
                format!("{} values", offsets.len()),
                format!("must be empty or {} finite values", 2 * zp),
            ));
        }
        match self.solve_direct(phi, torque, psi0, near, offsets) {
            Err(Error::Numerical { .. }) if torque != 0.0 => {
                self.solve_in_load_steps(phi, torque, psi0, near, offsets)
            }
            result => result,
        }
    }

    /// The last resort of [`StaticAnalysis::solve_with_offsets`]: the torque applied in steps
    /// from `near` (when it lies on the way, else from zero), each solve started from the one
    /// before, a step halved where it fails and doubled again (up to an eighth of the way)
    /// where it succeeds (a disc that moves onto other pins part of the way up, as on a ridge of
    /// a worn flank, is followed along the loading path). The error of the last step tried when
    /// the step falls below 1e-6 of the torque, or after [`MAX_LOAD_STEPS`] solves (a path that
    /// advances by ever smaller steps would otherwise run for hours).
    fn solve_in_load_steps(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        offsets: &[f64],
    ) -> Result<StaticSolution> {
        let mut prev = near
            .filter(|x| x.output_torque * torque > 0.0 && x.output_torque.abs() < torque.abs())
            .cloned();
        let mut reached = prev.as_ref().map_or(0.0, |x| x.output_torque);
        let first_step = (torque - reached) / 8.0;
        let mut step = first_step;
        let mut attempt = 0;
        loop {
            attempt += 1;
            let next = if (torque - reached).abs() <= 1.000001 * step.abs() {
                torque
            } else {
                reached + step
            };
            match self.solve_direct(phi, next, psi0, prev.as_ref(), offsets) {
                Ok(sol) if next == torque => return Ok(sol),
                Ok(sol) => {
                    reached = next;
                    prev = Some(sol);
                    // Back towards the first step after a success.
                    if step.abs() < first_step.abs() {
                        step *= 2.0;
                    }
                }
                Err(e) if step.abs() < 1e-6 * torque.abs() => return Err(e),
                Err(e) if attempt >= MAX_LOAD_STEPS => {
                    return Err(Error::numerical(
                        "static equilibrium",
                        format!(
                            "the load steps reached {reached:.6e} of {torque:.6e} N m in \
                             {MAX_LOAD_STEPS} solves at crank angle {:.4} deg (last: {e})",
                            phi.to_degrees()
                        ),
                    ))
                }
                Err(_) => step *= 0.5,
            }
        }
    }

    /// One attempt of [`StaticAnalysis::solve_with_offsets`]: from `near`, or cold.
    fn solve_direct(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        offsets: &[f64],
    ) -> Result<StaticSolution> {
        let s = if torque < 0.0 { -1.0 } else { 1.0 };
        let n = self.red.layout().dofs();
        let near = near.filter(|x| {
            let beyond = s * (x.twist - x.first_contact_twist);
            (x.output_torque == 0.0 || x.output_torque * s > 0.0)
                && beyond.is_finite()
                && beyond >= 0.0
        });
        let start = Start {
            psi0,
            near: near
                .filter(|x| x.deviations.len() == n)
                .map(|x| (&x.deviations[..], x.first_contact_twist)),
            beyond: near.map(|x| s * (x.twist - x.first_contact_twist)),
            offsets,
        };
        let result = match self.red.support {
            Support::Bearings => self.solve_bearings(phi, torque, &start),
            Support::Rigid { .. } => self.solve_rigid(phi, torque, &start),
        };
        result.map_err(|e| match e {
            Error::Numerical { context, message } => Error::Numerical {
                context,
                message: format!("{message} (output torque {torque:.6e} N m)"),
            },
            other => other,
        })
    }

    /// Static equilibria at the crank angles `phis` (rad, in order, neighbours close) under one
    /// output torque `torque` (N m): [`StaticAnalysis::solve`] at each, in parallel over runs
    /// of [`SEQUENCE_RUN`] consecutive angles, each solve of a run started from its
    /// predecessor's solution. The runs do not depend on the number of threads, so neither do
    /// the results.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`], for the first crank angle that fails.
    pub fn solve_sequence(&self, phis: &[f64], torque: f64) -> Result<Vec<StaticSolution>> {
        let s = if torque < 0.0 { -1.0 } else { 1.0 };
        let runs: Vec<Vec<StaticSolution>> = phis
            .par_chunks(SEQUENCE_RUN)
            .map(|run| -> Result<Vec<StaticSolution>> {
                let mut out: Vec<StaticSolution> = Vec::with_capacity(run.len());
                for &phi in run {
                    check_input(phi, torque)?;
                    let psi0 = self.first_contact(phi, s)?;
                    let sol = self.solve_near(phi, torque, psi0, out.last())?;
                    out.push(sol);
                }
                Ok(out)
            })
            .collect::<Result<_>>()?;
        Ok(runs.into_iter().flatten().collect())
    }

    /// Safeguarded Newton on the monotone `f(x) = s T(psi0 + s x) - |T|`, `x >= 0`, with
    /// `eval(psi) -> (T, dT/dpsi)`. Returns the converged twist.
    fn outer<F>(&self, phi: f64, torque: f64, start: &Start, mut eval: F) -> Result<f64>
    where
        F: FnMut(f64) -> Result<(f64, f64)>,
    {
        let psi0 = start.psi0;
        let s = if torque < 0.0 { -1.0 } else { 1.0 };
        let target = torque.abs();
        let tol = 1e-11 * target;
        let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
        let mut x = match start.beyond {
            Some(b) if b > 0.0 => b,
            _ => self.twist_guess(torque),
        };
        for step in 0..200 {
            let (t, k) = eval(psi0 + s * x)?;
            let f = s * t - target;
            if f.abs() <= tol {
                return Ok(psi0 + s * x);
            }
            if f > 0.0 {
                hi = x;
            } else {
                lo = x;
            }
            // Newton inside the bracket; while the bracket is open above, at most four times
            // the current twist (the stiffness grows as pins engage, so a step from a soft
            // start overshoots).
            let newton = if k > 0.0 { x - f / k } else { f64::NAN };
            // (Bisection only after 40 steps: where round-off makes T(psi) jitter at the
            // tolerance, Newton can wander inside the bracket.)
            let next = if step < 40 && newton > lo && newton < hi.min(4.0 * x) {
                newton
            } else if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                4.0 * x.max(lo)
            };
            if next > MAX_TWIST {
                return Err(self.fail(
                    phi,
                    &format!(
                        "the output torque {torque:.6e} N m needs a twist beyond {:.0} arcmin: \
                         more than the contact model can describe",
                        MAX_TWIST * ARCMIN_PER_RAD
                    ),
                ));
            }
            if hi.is_finite() && hi - lo <= 1e-15 * hi.max(1e-12) {
                return Ok(psi0 + s * 0.5 * (lo + hi));
            }
            x = next;
        }
        Err(self.fail(
            phi,
            "the twist for the output torque was not found in 200 steps",
        ))
    }

    /// Initial guess of the elastic twist beyond first contact (rad) for output torque `t`:
    /// Li's largest force at the equivalent disc torque compressing one contact over the pitch
    /// radius, three times for the bearings.
    fn twist_guess(&self, t: f64) -> f64 {
        let geo = &self.red.geometry;
        let rc = geo.disc_pitch_radius();
        let f = 4.0 * 0.5 * t.abs() * self.red.twist_factor() / (rc * geo.pins as f64);
        let delta = self.red.contact.approach(f.max(1e-6), 0.0);
        (3.0 * delta / rc).max(1e-12)
    }

    fn solve_rigid(&self, phi: f64, torque: f64, start: &Start) -> Result<StaticSolution> {
        let psi0 = start.psi0;
        let zp = self.red.geometry.pins;
        let mut cache = vec![f64::NAN; zp];
        let psi = if torque == 0.0 {
            psi0
        } else {
            self.outer(phi, torque, start, |p| {
                let (_, _, t, k) = self.eval_rigid(phi, p, &mut cache)?;
                Ok((t, k))
            })?
        };
        let (pins, pose, t, k) = self.eval_rigid(phi, psi, &mut cache)?;
        let Support::Rigid { load_share } = self.red.support else {
            unreachable!()
        };
        let scale = pins.iter().map(|p| p.force).sum::<f64>().max(1e-300);
        let roundoff = self.roundoff(pins.iter().map(|p| p.stiffness).sum::<f64>()) / scale;
        let rp = self.red.geometry.pin_circle_radius;
        let residual = if torque == 0.0 {
            0.0
        } else {
            (t - torque).abs() * load_share / rp / scale
        };
        let zc = self.red.geometry.disc_teeth() as f64;
        let disc = self.disc_load(
            &pins,
            pose,
            Vec2::zeros(),
            pose.angle + phi / zc,
            torque == 0.0,
        );
        self.check(StaticSolution {
            crank_angle: phi,
            output_torque: torque,
            twist: psi,
            first_contact_twist: psi0,
            stiffness: k,
            discs: vec![disc],
            residual,
            roundoff_floor: if torque == 0.0 { 0.0 } else { roundoff },
            deviations: Vec::new(),
        })
    }

    fn solve_bearings(&self, phi: f64, torque: f64, start: &Start) -> Result<StaticSolution> {
        let psi0 = start.psi0;
        let red = self.red;
        let n = red.layout().dofs();
        let zp = red.geometry.pins;
        let rp = red.geometry.pin_circle_radius;
        let mut fr = self.frame(phi);
        fr.offsets = start.offsets.to_vec();
        let mut memory = vec![vec![PinMemory::NONE; zp]; self.red.discs()];
        let mut z = [0.0; MAX_DOFS];
        self.mode_deviation(&fr, psi0, &mut z[..n]);
        let k_struct = self.structural_stiffness(&fr, &z[..n]);
        if torque == 0.0 {
            let ev = self.eval_bearings(&fr, &z, &mut memory, false)?;
            let kt = self.tangent(&k_struct, &ev, &fr, &z);
            return self.check(self.assemble(&fr, &z, ev, &kt, 0.0, psi0));
        }
        let mut zt = z;
        if let Some((_, kt)) =
            self.torque_controlled(&fr, torque, start, &mut zt[..n], &k_struct, &mut memory)?
        {
            // Every pin at the solution (the solve skipped pins known to be open).
            let ev = self.eval_bearings(&fr, &zt, &mut memory, false)?;
            let sol = self.assemble(&fr, &zt, ev, &kt, torque, psi0);
            if sol.residual <= RESIDUAL_TOLERANCE.max(sol.roundoff_floor) {
                return Ok(sol);
            }
        }
        // The twist-controlled path. Cold: it trusts neither the neighbour nor the pins' memory
        // of the fast path (whose rejected trial steps can take a disc far outside the gap
        // field's range, where a remembered gap is no bound).
        for m in memory.iter_mut() {
            m.fill(PinMemory::NONE);
        }
        let cold = Start {
            psi0,
            near: None,
            beyond: None,
            offsets: start.offsets,
        };
        let floor = torque.abs() / rp;
        // Predictor of the inner coordinates per unit twist: the rigid mode at first, then the
        // condensation direction `-K_ii^-1 K_io` of the last tangent.
        let mut current = psi0;
        let mut slope: Option<Vec<f64>> = None;
        let mut last: Option<DMatrix<f64>> = None;
        let psi = self.outer(phi, torque, &cold, |p| {
            match &slope {
                Some(dz) => {
                    for i in 2..n {
                        z[i] += dz[i] * (p - current);
                    }
                    z[Layout::OUT] = p;
                }
                None => {
                    let (mut a, mut b) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
                    self.mode_deviation(&fr, current, &mut a[..n]);
                    self.mode_deviation(&fr, p, &mut b[..n]);
                    for i in 0..n {
                        z[i] += b[i] - a[i];
                    }
                }
            }
            current = p;
            let (ev, kt) = self.inner_solve(&fr, &mut z[..n], &k_struct, &mut memory, floor)?;
            slope = Some(self.condensation_direction(&kt));
            let out = (-ev.g[Layout::OUT], self.condensed(&kt));
            last = Some(kt);
            Ok(out)
        })?;
        let kt = match last {
            Some(kt) if current == psi => kt,
            _ => {
                if let Some(dz) = &slope {
                    for i in 2..n {
                        z[i] += dz[i] * (psi - current);
                    }
                }
                z[Layout::OUT] = psi;
                self.inner_solve(&fr, &mut z[..n], &k_struct, &mut memory, floor)?
                    .1
            }
        };
        let ev = self.eval_bearings(&fr, &z, &mut memory, false)?;
        self.check(self.assemble(&fr, &z, ev, &kt, torque, psi0))
    }

    /// The solution at deviations `z` from the full evaluation `ev` there and the tangent `kt`.
    fn assemble(
        &self,
        fr: &Frame,
        z: &[f64; MAX_DOFS],
        ev: Eval,
        kt: &DMatrix<f64>,
        torque: f64,
        psi0: f64,
    ) -> StaticSolution {
        let lay = self.red.layout();
        let n = lay.dofs();
        let rp = self.red.geometry.pin_circle_radius;
        let scale = ev.scale.max(torque.abs() / rp).max(1e-300);
        let out_res = (ev.g[Layout::OUT] + torque).abs() / rp;
        let residual = self.inner_residual(&ev.g).max(out_res) / scale;
        let unloaded = torque == 0.0;
        let discs = (0..self.red.discs())
            .map(|d| {
                let id = lay.disc(d);
                self.disc_load(
                    &ev.pins[d],
                    ev.poses[d],
                    Vec2::new(z[id], z[id + 1]),
                    z[id + 2],
                    unloaded,
                )
            })
            .collect();
        StaticSolution {
            crank_angle: fr.phi,
            output_torque: torque,
            twist: z[Layout::OUT],
            first_contact_twist: psi0,
            stiffness: self.condensed(kt),
            discs,
            residual: if unloaded { 0.0 } else { residual },
            roundoff_floor: if unloaded { 0.0 } else { ev.roundoff / scale },
            deviations: z[..n].to_vec(),
        }
    }

    fn disc_load(
        &self,
        pins: &[PinEval],
        pose: DiscPose,
        translation: Vec2,
        rotation: f64,
        unloaded: bool,
    ) -> DiscLoad {
        let law = &self.red.contact;
        let r = self.red.geometry.pin_radius;
        let out: Vec<PinLoad> = pins
            .iter()
            .map(|p| {
                // The force acts as F grad(gap) (|grad| = 1 for an exact distance, within about
                // 1e-3 for the band-averaged field): its magnitude and lever arm.
                let norm = p.w.norm();
                let (f, k) = if unloaded {
                    (0.0, 0.0)
                } else {
                    (p.force * norm, p.stiffness * norm)
                };
                let h = law.hertz(f, p.curvature);
                let normal = p.grad / p.grad.norm();
                let point = p.q - normal * (r + p.gap);
                PinLoad {
                    pin: p.pin,
                    profile_parameter: p.t,
                    mesh_angle: mesh_angle(p.t),
                    gap: p.gap,
                    force: f,
                    lever_arm: cross(&p.rel, &p.w) / norm,
                    half_width: h.half_width,
                    max_pressure: h.max_pressure,
                    curvature: p.curvature,
                    stiffness: k,
                    point,
                    normal,
                }
            })
            .collect();
        DiscLoad {
            pose,
            translation,
            rotation,
            torque: pins.iter().map(|p| p.force * cross(&p.rel, &p.w)).sum(),
            pins: out,
        }
    }

    /// Returns the solution if its residual is within [`RESIDUAL_TOLERANCE`], an error naming
    /// the crank angle, torque and wear otherwise.
    fn check(&self, sol: StaticSolution) -> Result<StaticSolution> {
        let allowed = RESIDUAL_TOLERANCE.max(sol.roundoff_floor);
        if sol.residual.is_finite() && sol.residual <= allowed && sol.twist.is_finite() {
            Ok(sol)
        } else {
            Err(self.fail(
                sol.crank_angle,
                &format!(
                    "the equilibrium residual is {:.3e} of the force scale (allowed \
                     {allowed:.3e}; twist {:.6} arcmin)",
                    sol.residual,
                    sol.twist * ARCMIN_PER_RAD
                ),
            ))
        }
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
            .map(|j| red.geometry.pin_centre(j) + red.errors.pin_displacement(red, j))
            .collect(),
        (0..zp).map(|j| -red.errors.pin_radius_error(j)).collect(),
    )
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
        let model = Config::example().validate().unwrap();
        let n_map = 720;
        // A wear scar like the late stage's: 40 um deep, centred on the flank.
        let depth: Vec<f64> = (0..n_map)
            .map(|i| {
                let x = std::f64::consts::TAU * i as f64 / n_map as f64;
                40e-6 * (0.5 - 0.5 * (x - 0.8).cos()).powi(2)
            })
            .collect();
        for wear in [None, Some(WearMap::new(depth).unwrap())] {
            let profile = model.profile(wear).unwrap();
            let sa = StaticAnalysis::new(&model.reducer, &profile).unwrap();
            let red = &model.reducer;
            let n = red.layout().dofs();
            let rp = red.geometry.pin_circle_radius;
            for &phi in &[0.05, 0.7] {
                let sol = sa.solve(phi, model.rated_torque).unwrap();
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
