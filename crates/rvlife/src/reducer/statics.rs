//! Static equilibrium of the reducer model under an output torque, with the input locked: the
//! catalogue's measuring set-up for torsional stiffness, lost motion and backlash
//! (physics-notes sections 8-9), and the loaded TE.
//!
//! **Set-up.** The input (sun) is locked at the angle that puts disc 1's eccentric at crank
//! angle `phi`; a torque `T` (N m) acts on the output carrier, positive counter-clockwise (the
//! sense of positive output rotation: it presses the flank `0 < mesh angle < pi`). The unknowns
//! are the deviations of every other coordinate from the nominal kinematics
//! ([`Reducer::nominal`]): the carrier twist `psi` (the output's TE under load), each crank's
//! centre and angle, each disc's centre and angle. The forces are those of the dynamic model
//! ([`Reducer::structural_forces`]: meshes and bearings) and the disc-pin contacts with the
//! line-contact law on exact gaps of the actual profile ([`crate::contact::pin_at_pose`], global
//! closest points).
//!
//! **Solution.** Twist control: for a given carrier twist `psi` the other coordinates are in
//! equilibrium (a strongly convex problem: Newton's method with the Gauss-Newton tangent of the
//! contacts and a backtracking line search on the elastic energy), and the torque the carrier
//! needs, `T(psi)`, is monotone; the outer loop finds `T(psi) = T` by safeguarded Newton with
//! the condensed stiffness `dT/dpsi = K_oo - K_oi K_ii^-1 K_io`. Every converged pose is checked
//! with global closest points of every pin, and every solution is returned only with its
//! residual (every generalised force, moments over the pin circle radius) below 1e-9 of the
//! largest force acting; otherwise an error names the crank angle, the torque and the wear.
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

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::{rotation_difference, Layout, Reducer, Support, MAX_DOFS};
use crate::contact::{pin_at_pose, DiscPose, PinGeometry};
use crate::error::{Error, Result};
use crate::geometry::{cross, mesh_angle, rotate, Profile, Vec2};
use crate::te::ARCMIN_PER_RAD;

/// Relative residual every static solution is checked against: every generalised force of the
/// equilibrium (moments divided by the pin circle radius) below this times the force scale, the
/// sum of the pin forces on the more loaded disc (what the disc's bearings carry).
pub const RESIDUAL_TOLERANCE: f64 = 1e-9;

/// One pin's share of a static solution.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PinLoad {
    /// Pin index `j`.
    pub pin: usize,
    /// Profile parameter of the contact point (global, rad).
    pub profile_parameter: f64,
    /// Mesh angle of the contact point on the disc, rad.
    pub mesh_angle: f64,
    /// Gap at the solved pose, m (negative: the contact's approach).
    pub gap: f64,
    /// Normal force, N.
    pub force: f64,
    /// Lever arm about the disc centre, m.
    pub lever_arm: f64,
    /// Contact half-width, m.
    pub half_width: f64,
    /// Maximum Hertz pressure, Pa.
    pub max_pressure: f64,
    /// Flank curvature at the contact for the contact law, 1/m.
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
    /// Full coordinate deviations from the nominal kinematics (bearing support), SI.
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

/// The nominal positions of the locked-input configuration at one crank angle.
struct Frame {
    phi: f64,
    q0: [f64; MAX_DOFS],
}

/// Pin state during the iterations.
#[derive(Debug, Clone, Copy)]
struct PinEval {
    geo: PinGeometry,
    /// Flank normal in the pin-ring frame.
    w: Vec2,
    /// Pin centre relative to the disc centre, pin-ring frame, m.
    rel: Vec2,
    force: f64,
    stiffness: f64,
}

/// Static analysis of one reducer with one disc profile (both discs alike).
pub struct StaticAnalysis<'a> {
    red: &'a Reducer,
    profile: &'a Profile,
}

/// Everything evaluated at one configuration.
struct Eval {
    /// Generalised forces (bearing support: every coordinate; rigid: `[T(psi)]` in slot OUT).
    g: [f64; MAX_DOFS],
    /// Elastic energy, J.
    energy: f64,
    /// Pins per disc.
    pins: Vec<Vec<PinEval>>,
    /// Poses per disc.
    poses: Vec<DiscPose>,
    /// Force scale of the residual: the sum of the pin forces on the more loaded disc (what
    /// its bearings carry), N.
    scale: f64,
}

impl<'a> StaticAnalysis<'a> {
    /// The analysis of `red` with the disc profile `profile`.
    pub fn new(red: &'a Reducer, profile: &'a Profile) -> Self {
        StaticAnalysis { red, profile }
    }

    fn discs(&self) -> usize {
        match self.red.support {
            Support::Bearings => 2,
            Support::Rigid { .. } => 1,
        }
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
        Frame { phi, q0 }
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
        for d in 0..2 {
            let i = lay.disc(d);
            let ang0 = q0[lay.crank(0) + 2] + Reducer::phase(d);
            let dc = rotation_difference(&Vec2::new(a, 0.0), ang0, dk);
            z[i] = dc.x;
            z[i + 1] = dc.y;
            z[i + 2] = psi;
        }
    }

    /// Pose of disc `d` at deviations `z` (bearing support).
    fn pose_from(&self, fr: &Frame, z: &[f64], d: usize) -> DiscPose {
        let i = self.red.layout().disc(d);
        let q0 = &fr.q0;
        DiscPose {
            crank_angle: fr.phi + Reducer::phase(d),
            centre: Vec2::new(q0[i] + z[i], q0[i + 1] + z[i + 1]),
            angle: q0[i + 2] + z[i + 2] + self.red.profile_turn(d),
        }
    }

    /// Pose of the single disc of the rigid support along the mode, and `dc/dpsi`.
    fn rigid_pose(&self, phi: f64, psi: f64) -> (DiscPose, Vec2) {
        let geo = &self.red.geometry;
        let zc = geo.disc_teeth() as f64;
        let ang = phi + self.red.crank_mode_ratio() * psi;
        let c = Vec2::new(ang.cos(), ang.sin()) * geo.eccentricity;
        (
            DiscPose {
                crank_angle: phi,
                centre: c,
                angle: -phi / zc + psi,
            },
            Vec2::new(-c.y, c.x) * self.red.crank_mode_ratio(),
        )
    }

    /// Every pin of one disc at `pose`: gaps, forces and stiffnesses. `hints` holds the contact
    /// parameters of the last evaluation (NaN: none), updated in place; `global` forces global
    /// closest-point searches.
    fn eval_pins(
        &self,
        pose: &DiscPose,
        hints: &mut [f64],
        global: bool,
    ) -> Result<Vec<PinEval>> {
        let geo = &self.red.geometry;
        let law = &self.red.contact;
        let (sa, ca) = pose.angle.sin_cos();
        let mut out = Vec::with_capacity(geo.pins);
        for (j, hint) in hints.iter_mut().enumerate() {
            let h = (!global && hint.is_finite()).then_some(*hint);
            let pg = pin_at_pose(self.profile, j, pose, h)?;
            *hint = pg.t;
            let w = Vec2::new(ca * pg.normal.x - sa * pg.normal.y, sa * pg.normal.x + ca * pg.normal.y);
            let (force, stiffness) = if pg.gap < 0.0 {
                law.force(-pg.gap, pg.curvature).map_err(|e| self.law_error(e, pose))?
            } else {
                (0.0, 0.0)
            };
            out.push(PinEval {
                geo: pg,
                w,
                rel: geo.pin_centre(j) - pose.centre,
                force,
                stiffness,
            });
        }
        Ok(out)
    }

    fn law_error(&self, e: Error, pose: &DiscPose) -> Error {
        match e {
            Error::Numerical { message, .. } => Error::numerical(
                "static equilibrium",
                format!(
                    "{message} at crank angle {:.4} deg (max wear {:.2} um)",
                    pose.crank_angle.to_degrees(),
                    self.profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6
                ),
            ),
            other => other,
        }
    }

    /// Forces and energy of the bearing-supported model at deviations `z`.
    fn eval_bearings(
        &self,
        fr: &Frame,
        z: &[f64],
        hints: &mut [Vec<f64>],
        global: bool,
    ) -> Result<Eval> {
        let red = self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let mut g = [0.0; MAX_DOFS];
        let zero = [0.0; MAX_DOFS];
        red.structural_forces(&fr.q0[..n], &z[..n], &zero[..n], &mut g[..n]);
        let mut energy = red.structural_energy(&fr.q0[..n], &z[..n]);
        let mut scale: f64 = 0.0;
        let mut pins = Vec::with_capacity(2);
        let mut poses = Vec::with_capacity(2);
        for (d, h) in hints.iter_mut().enumerate() {
            let pose = self.pose_from(fr, z, d);
            let ev = self.eval_pins(&pose, h, global)?;
            let id = lay.disc(d);
            scale = scale.max(ev.iter().map(|p| p.force).sum::<f64>());
            for p in &ev {
                if p.force > 0.0 {
                    g[id] -= p.force * p.w.x;
                    g[id + 1] -= p.force * p.w.y;
                    g[id + 2] -= p.force * cross(&p.rel, &p.w);
                    energy += red
                        .contact
                        .potential(-p.geo.gap, p.geo.curvature)
                        .map_err(|e| self.law_error(e, &pose))?;
                }
            }
            pins.push(ev);
            poses.push(pose);
        }
        Ok(Eval {
            g,
            energy,
            pins,
            poses,
            scale,
        })
    }

    /// Structural tangent stiffness `-dQ/dq` (meshes and bearings) by central differences of
    /// [`Reducer::structural_forces`] at deviations `z` (linear springs on exact rigid-body
    /// kinematics: the differences are exact to round-off).
    fn structural_stiffness(&self, fr: &Frame, z: &[f64]) -> DMatrix<f64> {
        let red = self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let rp = red.geometry.pin_circle_radius;
        let mut k = DMatrix::zeros(n, n);
        let zero = [0.0; MAX_DOFS];
        let mut zz = [0.0; MAX_DOFS];
        zz[..n].copy_from_slice(&z[..n]);
        for c in 0..n {
            let is_angle = c < 2 || (c - 2) % 3 == 2;
            let h = if is_angle { 1e-8 / rp } else { 1e-8 };
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

    /// Tangent stiffness of the bearing-supported model: structural plus the Gauss-Newton
    /// contact part `k_j grad g_j grad g_j^T` of every loaded pin.
    fn tangent(&self, k_struct: &DMatrix<f64>, ev: &Eval) -> DMatrix<f64> {
        let lay = self.red.layout();
        let mut k = k_struct.clone();
        for (d, pins) in ev.pins.iter().enumerate() {
            let id = lay.disc(d);
            for p in pins.iter().filter(|p| p.stiffness > 0.0) {
                let gr = [-p.w.x, -p.w.y, -cross(&p.rel, &p.w)];
                for a in 0..3 {
                    for b in 0..3 {
                        k[(id + a, id + b)] += p.stiffness * gr[a] * gr[b];
                    }
                }
            }
        }
        k
    }

    /// Scaled residual of the inner coordinates (every one but input and output): forces in N,
    /// moments divided by the pin circle radius.
    fn inner_residual(&self, g: &[f64]) -> f64 {
        let lay = self.red.layout();
        let rp = self.red.geometry.pin_circle_radius;
        (2..lay.dofs())
            .map(|i| {
                let is_angle = (i - 2) % 3 == 2;
                g[i].abs() / if is_angle { rp } else { 1.0 }
            })
            .fold(0.0, f64::max)
    }

    /// Equilibrium of every coordinate but input and output at carrier twist fixed in `q`
    /// (absolute positions, updated in place). Returns the converged evaluation and the
    /// tangent.
    fn inner_solve(
        &self,
        fr: &Frame,
        q: &mut [f64],
        k_struct: &DMatrix<f64>,
        hints: &mut [Vec<f64>],
        global: bool,
    ) -> Result<(Eval, DMatrix<f64>)> {
        let lay = self.red.layout();
        let n = lay.dofs();
        let m = n - 2;
        let phi = fr.phi;
        let rp = self.red.geometry.pin_circle_radius;
        let mut ev = self.eval_bearings(fr, q, hints, global)?;
        let (mut best, mut stalled) = (f64::INFINITY, 0);
        for _ in 0..100 {
            let res = self.inner_residual(&ev.g);
            if std::env::var("RVLIFE_DEBUG").is_ok() {
                let imax = (2..n).max_by(|a, b| ev.g[*a].abs().total_cmp(&ev.g[*b].abs())).unwrap();
                eprintln!("inner: res {res:.3e} scale {:.3e} energy {:.6e} out {:.6e} worst dof {imax} g {:.3e}", ev.scale, ev.energy, ev.g[Layout::OUT], ev.g[imax]);
                if std::env::var("RVLIFE_DEBUG").unwrap() == "2" {
                    for (d, pins) in ev.pins.iter().enumerate() {
                        for p in pins.iter().filter(|p| p.geo.gap < 1e-7) {
                            eprintln!("   d{d} j{} gap {:.4e} F {:.4e} k {:.3e} t {:.6} lever {:.3e}", p.geo.pin, p.geo.gap, p.force, p.stiffness, p.geo.t, p.geo.lever_arm);
                        }
                    }
                }
            }
            let kt = self.tangent(k_struct, &ev);
            // Converged, or at the round-off floor of the gaps (about 1e-17 m on a 64 mm
            // geometry): the residual stopped falling for three Newton steps.
            if res < 0.5 * best {
                best = res;
                stalled = 0;
            } else {
                stalled += 1;
            }
            if res <= 1e-12 * ev.scale.max(1e-9) || stalled >= 3 {
                return Ok((ev, kt));
            }
            let kii = kt.view((2, 2), (m, m)).into_owned();
            let rhs = DVector::from_iterator(m, (2..n).map(|i| ev.g[i]));
            let step = kii
                .cholesky()
                .map(|c| c.solve(&rhs))
                .ok_or_else(|| self.fail(phi, "the inner stiffness matrix is not positive definite"))?;
            // Backtracking on the residual norm (the contact law depends on the flank curvature
            // at the moving contact point, so the forces have no exact potential to descend).
            let merit = |e: &Eval| -> f64 {
                (2..n)
                    .map(|i| {
                        let x = e.g[i] / if (i - 2) % 3 == 2 { rp } else { 1.0 };
                        x * x
                    })
                    .sum()
            };
            let m0 = merit(&ev);
            let base: Vec<f64> = q[..n].to_vec();
            let mut alpha = 1.0;
            loop {
                for i in 0..m {
                    q[2 + i] = base[2 + i] + alpha * step[i];
                }
                let trial = self.eval_bearings(fr, q, hints, global)?;
                let mt = merit(&trial);
                if mt <= m0 * (1.0 - 1e-4 * alpha) || mt.sqrt() <= 1e-12 * ev.scale || alpha < 1e-4 {
                    ev = trial;
                    break;
                }
                alpha *= 0.5;
            }
        }
        Err(self.fail(phi, "the bearing equilibrium did not converge in 100 Newton steps"))
    }

    fn fail(&self, phi: f64, what: &str) -> Error {
        Error::numerical(
            "static equilibrium",
            format!(
                "{what} at crank angle {:.4} deg (max wear {:.2} um)",
                phi.to_degrees(),
                self.profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6
            ),
        )
    }

    /// Condensed torsional stiffness `K_oo - K_oi K_ii^-1 K_io` (N m/rad).
    fn condensed(&self, kt: &DMatrix<f64>) -> f64 {
        let n = self.red.layout().dofs();
        let m = n - 2;
        let o = Layout::OUT;
        let kii = kt.view((2, 2), (m, m)).into_owned();
        let kio = DVector::from_iterator(m, (2..n).map(|i| kt[(i, o)]));
        match kii.cholesky() {
            Some(c) => kt[(o, o)] - kio.dot(&c.solve(&kio)),
            None => kt[(o, o)],
        }
    }

    /// Rigid support: pins of the disc at twist `psi`, the torque `T(psi) = sum F_j m_j /
    /// share` and its derivative.
    fn eval_rigid(
        &self,
        phi: f64,
        psi: f64,
        hints: &mut [f64],
        global: bool,
    ) -> Result<(Vec<PinEval>, DiscPose, f64, f64)> {
        let Support::Rigid { load_share } = self.red.support else {
            unreachable!("rigid evaluation of a bearing-supported reducer")
        };
        let (pose, dc) = self.rigid_pose(phi, psi);
        let pins = self.eval_pins(&pose, hints, global)?;
        let (mut t, mut k) = (0.0, 0.0);
        for p in &pins {
            let lever = p.w.dot(&dc) + p.geo.lever_arm;
            t += p.force * lever;
            k += p.stiffness * lever * lever;
        }
        Ok((pins, pose, t / load_share, k / load_share))
    }

    /// Mode lever `m_j = -d gap_j / d psi` of a pin along the locked-input mode.
    fn mode_lever(p: &PinEval, dc: Vec2) -> f64 {
        p.w.dot(&dc) + p.geo.lever_arm
    }

    /// Gap of pin `j` of disc `d` along the mode at twist `psi`, and its mode lever.
    fn mode_gap(&self, phi: f64, d: usize, j: usize, psi: f64) -> Result<(f64, f64)> {
        let (pose, dc) = self.mode_pose(phi, d, psi);
        let p = self.eval_one(&pose, j)?;
        Ok((p.geo.gap, Self::mode_lever(&p, dc)))
    }

    /// Pose of disc `d` along the locked-input mode at twist `psi` and its `dc/dpsi`.
    fn mode_pose(&self, phi: f64, d: usize, psi: f64) -> (DiscPose, Vec2) {
        match self.red.support {
            Support::Rigid { .. } => self.rigid_pose(phi, psi),
            Support::Bearings => {
                let fr = self.frame(phi);
                let mut z = [0.0; MAX_DOFS];
                let n = self.red.layout().dofs();
                self.mode_deviation(&fr, psi, &mut z[..n]);
                let pose = self.pose_from(&fr, &z, d);
                let c = pose.centre;
                (pose, Vec2::new(-c.y, c.x) * self.red.crank_mode_ratio())
            }
        }
    }

    fn eval_one(&self, pose: &DiscPose, j: usize) -> Result<PinEval> {
        let pg = pin_at_pose(self.profile, j, pose, None)?;
        let w = rotate(&pg.normal, pose.angle);
        Ok(PinEval {
            geo: pg,
            w,
            rel: self.red.geometry.pin_centre(j) - pose.centre,
            force: 0.0,
            stiffness: 0.0,
        })
    }

    /// Carrier twist (rad) at which the unloaded mechanism first touches a pin when the carrier
    /// is turned, input locked, in direction `direction` (+1 counter-clockwise, -1 clockwise),
    /// at crank angle `phi`: the `T -> 0+` limit of the loaded twist (the static TE in that
    /// direction), over every pin of every disc. Zero for an unmodified, unworn disc.
    ///
    /// Each pin's touching twist along the mode is solved exactly (Newton on `gap_j(psi) = 0`,
    /// `d gap_j/d psi = -m_j`, Brent's method where the gap has a kink) for the candidates whose
    /// linear estimate `gap_j / m_j` is near the smallest, then every pin is checked at the
    /// result (a pin that closes faster than linearly can touch first).
    ///
    /// # Errors
    /// [`Error::Numerical`] if no pin can stop the mechanism or a projection fails.
    pub fn first_contact(&self, phi: f64, direction: f64) -> Result<f64> {
        let s = if direction < 0.0 { -1.0 } else { 1.0 };
        let zp = self.red.geometry.pins;
        let mut est: Vec<(usize, usize, f64)> = Vec::with_capacity(2 * zp);
        for d in 0..self.discs() {
            let (pose, dc) = self.mode_pose(phi, d, 0.0);
            for j in 0..zp {
                let p = self.eval_one(&pose, j)?;
                let m = Self::mode_lever(&p, dc);
                if s * m > 0.0 {
                    est.push((d, j, p.geo.gap / m));
                }
            }
        }
        let lin_min = est
            .iter()
            .map(|e| s * e.2)
            .fold(f64::INFINITY, f64::min);
        if !lin_min.is_finite() {
            return Err(self.fail(phi, "no pin can stop the mechanism"));
        }
        let mut best = f64::INFINITY;
        for margin in [0.25 * lin_min.abs() + 1e-6, f64::INFINITY] {
            for &(d, j, e) in &est {
                if s * e - lin_min > margin {
                    continue;
                }
                if let Some(b) = self.touching_twist(phi, d, j, e, s)? {
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
                    let g = self.eval_one(&pose, j)?.geo.gap;
                    if g < -1e-13 {
                        if let Some(b) = self.touching_twist(phi, d, j, psi, s)? {
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

    /// Twist (rad) at which pin `j` of disc `d` touches, near the estimate `est`, turning in
    /// direction `s`; `None` if it moves away.
    fn touching_twist(&self, phi: f64, d: usize, j: usize, est: f64, s: f64) -> Result<Option<f64>> {
        let mut b = est;
        for _ in 0..12 {
            let (g, m) = self.mode_gap(phi, d, j, b)?;
            if s * m <= 0.0 {
                return Ok(None);
            }
            if g.abs() < 1e-14 {
                return Ok(Some(b));
            }
            b += g / m;
        }
        // Bracket the sign change of the gap (it decreases with s psi) and bisect.
        let mut w = 1e-7 + 0.1 * est.abs();
        for _ in 0..40 {
            let (lo, hi) = (est - w, est + w);
            let (glo, ghi) = (self.mode_gap(phi, d, j, lo)?.0, self.mode_gap(phi, d, j, hi)?.0);
            if glo * ghi < 0.0 {
                let (mut a, mut fa, mut c) = (lo, glo, hi);
                for _ in 0..200 {
                    let mid = 0.5 * (a + c);
                    let fm = self.mode_gap(phi, d, j, mid)?.0;
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
        if !phi.is_finite() || !torque.is_finite() {
            return Err(Error::invalid(
                "static analysis input",
                format!("crank angle {phi} rad, torque {torque} N m"),
                "must be finite",
            ));
        }
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
        let result = match self.red.support {
            Support::Bearings => self.solve_bearings(phi, torque, psi0),
            Support::Rigid { .. } => self.solve_rigid(phi, torque, psi0),
        };
        result.map_err(|e| match e {
            Error::Numerical { context, message } => Error::Numerical {
                context,
                message: format!("{message} (output torque {torque:.6e} N m)"),
            },
            other => other,
        })
    }

    /// Safeguarded Newton on the monotone `f(x) = s T(psi0 + s x) - |T|`, `x >= 0`, with
    /// `eval(psi) -> (T, dT/dpsi)`. Returns the converged twist.
    fn outer<F>(&self, phi: f64, torque: f64, psi0: f64, x_guess: f64, mut eval: F) -> Result<f64>
    where
        F: FnMut(f64) -> Result<(f64, f64)>,
    {
        let s = if torque < 0.0 { -1.0 } else { 1.0 };
        let target = torque.abs();
        let tol = 1e-11 * target;
        let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
        let mut x = x_guess.max(1e-9);
        for _ in 0..200 {
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
            let newton = if k > 0.0 { x - f / k } else { f64::NAN };
            let next = if newton > lo && newton < hi {
                newton
            } else if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                2.0 * x.max(lo)
            };
            if hi.is_finite() && hi - lo <= 1e-15 * hi.max(1e-12) {
                return Ok(psi0 + s * 0.5 * (lo + hi));
            }
            x = next;
        }
        Err(self.fail(phi, "the twist for the output torque was not found in 200 steps"))
    }

    /// Initial guess of the elastic twist beyond first contact (rad) for output torque `t`:
    /// Li's largest force at the equivalent disc torque compressing one contact over the pitch
    /// radius, plus twice that for the bearings.
    fn twist_guess(&self, t: f64) -> f64 {
        let geo = &self.red.geometry;
        let rc = geo.disc_pitch_radius();
        let f = 4.0 * 0.5 * t.abs() * self.red.twist_factor() / (rc * geo.pins as f64);
        let delta = self
            .red
            .contact
            .approach(f.max(1e-6), 0.0);
        3.0 * delta / rc
    }

    fn solve_rigid(&self, phi: f64, torque: f64, psi0: f64) -> Result<StaticSolution> {
        let zp = self.red.geometry.pins;
        let mut hints = vec![f64::NAN; zp];
        let psi = if torque == 0.0 {
            psi0
        } else {
            let mut psi = psi0;
            for _round in 0..5 {
                psi = self.outer(phi, torque, psi0, self.twist_guess(torque), |p| {
                    let (_, _, t, k) = self.eval_rigid(phi, p, &mut hints, false)?;
                    Ok((t, k))
                })?;
                // Confirm with global closest points: a foot that jumped means another round.
                let local = self.eval_rigid(phi, psi, &mut hints, false)?.2;
                let global = self.eval_rigid(phi, psi, &mut hints, true)?.2;
                if (local - global).abs() <= 1e-11 * torque.abs() {
                    break;
                }
            }
            psi
        };
        let (pins, pose, t, k) = self.eval_rigid(phi, psi, &mut hints, true)?;
        let Support::Rigid { load_share } = self.red.support else {
            unreachable!()
        };
        let scale = pins.iter().map(|p| p.force).sum::<f64>().max(1e-300);
        let rp = self.red.geometry.pin_circle_radius;
        let residual = if torque == 0.0 {
            0.0
        } else {
            (t - torque).abs() * load_share / rp / scale
        };
        let zc = self.red.geometry.disc_teeth() as f64;
        let disc = self.disc_load(&pins, pose, Vec2::zeros(), pose.angle + phi / zc, torque == 0.0);
        let sol = StaticSolution {
            crank_angle: phi,
            output_torque: torque,
            twist: psi,
            first_contact_twist: psi0,
            stiffness: k,
            discs: vec![disc],
            residual,
            deviations: Vec::new(),
        };
        self.check(sol)
    }

    fn solve_bearings(&self, phi: f64, torque: f64, psi0: f64) -> Result<StaticSolution> {
        let red = self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let zp = red.geometry.pins;
        let fr = self.frame(phi);
        let mut hints = vec![vec![f64::NAN; zp]; 2];
        let mut q = [0.0; MAX_DOFS];
        self.mode_deviation(&fr, psi0, &mut q[..n]);
        let k_struct = self.structural_stiffness(&fr, &q[..n]);
        let mut current_psi = psi0;
        let mut global = false;
        if torque != 0.0 {
            for round in 0..5 {
                // Moves the warm start along the rigid mode to a new twist.
                let shift = |q: &mut [f64], from: f64, to: f64| {
                    let (mut a, mut b) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
                    self.mode_deviation(&fr, from, &mut a[..n]);
                    self.mode_deviation(&fr, to, &mut b[..n]);
                    for i in 0..n {
                        q[i] += b[i] - a[i];
                    }
                };
                let psi = self.outer(phi, torque, psi0, self.twist_guess(torque), |p| {
                    shift(&mut q[..n], current_psi, p);
                    current_psi = p;
                    let (ev, kt) = self.inner_solve(&fr, &mut q[..n], &k_struct, &mut hints, global)?;
                    Ok((-ev.g[Layout::OUT], self.condensed(&kt)))
                })?;
                shift(&mut q[..n], current_psi, psi);
                current_psi = psi;
                // Confirm with global closest points; a foot that jumped means another round
                // with global searches.
                let local = self.eval_bearings(&fr, &q, &mut hints, false)?;
                let glob = self.eval_bearings(&fr, &q, &mut hints, true)?;
                let same = local
                    .pins
                    .iter()
                    .flatten()
                    .zip(glob.pins.iter().flatten())
                    .all(|(a, b)| (a.geo.gap - b.geo.gap).abs() <= 1e-13);
                if same {
                    break;
                }
                global = round >= 1;
            }
        }
        let (ev, kt) = if torque == 0.0 {
            let ev = self.eval_bearings(&fr, &q, &mut hints, true)?;
            let kt = self.tangent(&k_struct, &ev);
            (ev, kt)
        } else {
            self.inner_solve(&fr, &mut q[..n], &k_struct, &mut hints, true)?
        };
        let rp = red.geometry.pin_circle_radius;
        let scale = ev.scale.max(torque.abs() / rp).max(1e-300);
        let out_res = (ev.g[Layout::OUT] + torque).abs() / rp;
        let residual = self.inner_residual(&ev.g).max(out_res) / scale;
        let mut discs = Vec::with_capacity(2);
        for d in 0..2 {
            let id = lay.disc(d);
            let translation = Vec2::new(q[id], q[id + 1]);
            discs.push(self.disc_load(&ev.pins[d], ev.poses[d], translation, q[id + 2], torque == 0.0));
        }
        let sol = StaticSolution {
            crank_angle: phi,
            output_torque: torque,
            twist: q[Layout::OUT],
            first_contact_twist: psi0,
            stiffness: self.condensed(&kt),
            discs,
            residual: if torque == 0.0 { 0.0 } else { residual },
            deviations: q[..n].to_vec(),
        };
        self.check(sol)
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
        let out: Vec<PinLoad> = pins
            .iter()
            .map(|p| {
                let (f, k) = if unloaded { (0.0, 0.0) } else { (p.force, p.stiffness) };
                let h = law.hertz(f, p.geo.curvature);
                PinLoad {
                    pin: p.geo.pin,
                    profile_parameter: p.geo.t,
                    mesh_angle: mesh_angle(p.geo.t),
                    gap: p.geo.gap,
                    force: f,
                    lever_arm: p.geo.lever_arm,
                    half_width: h.half_width,
                    max_pressure: h.max_pressure,
                    curvature: p.geo.curvature,
                    stiffness: k,
                    point: p.geo.point,
                    normal: p.geo.normal,
                }
            })
            .collect();
        DiscLoad {
            pose,
            translation,
            rotation,
            torque: out.iter().map(|p| p.force * p.lever_arm).sum(),
            pins: out,
        }
    }

    /// Returns the solution if its residual is within [`RESIDUAL_TOLERANCE`], an error naming
    /// the crank angle, torque and wear otherwise.
    fn check(&self, sol: StaticSolution) -> Result<StaticSolution> {
        if sol.residual.is_finite() && sol.residual <= RESIDUAL_TOLERANCE && sol.twist.is_finite() {
            Ok(sol)
        } else {
            Err(self.fail(
                sol.crank_angle,
                &format!(
                    "the equilibrium residual is {:.3e} of the largest force (allowed {RESIDUAL_TOLERANCE:e}; twist {:.6} arcmin)",
                    sol.residual,
                    sol.twist * ARCMIN_PER_RAD
                ),
            ))
        }
    }
}

#[cfg(test)]
mod debug_tests {
    use super::*;
    use crate::contact::{pin_at_pose, DiscPose};

    #[test]
    fn root_pin_gap_gradient() {
        let m = crate::config::Config::example().validate().unwrap();
        let prof = m.profile(None).unwrap();
        let geo = prof.geometry().clone();
        let phi = 0.5f64.to_radians();
        let base = DiscPose::at(&geo, phi, 0.0);
        for j in [0usize, 1, 20] {
            let mut pose = base;
            pose.centre.x += 0.3e-6;
            pose.centre.y -= 0.2e-6;
            pose.angle += 2e-6;
            let g0 = pin_at_pose(&prof, j, &pose, None).unwrap();
            let w = rotate(&g0.normal, pose.angle);
            let h = 1e-9;
            for (k, d) in [Vec2::new(h, 0.0), Vec2::new(0.0, h)].iter().enumerate() {
                let mut pp = pose;
                pp.centre += d;
                let mut pm = pose;
                pm.centre -= d;
                let gp = pin_at_pose(&prof, j, &pp, None).unwrap().gap;
                let gm = pin_at_pose(&prof, j, &pm, None).unwrap().gap;
                eprintln!("pin {j} dir {k}: fd {:.9} analytic {:.9} (t {:.6})", (gp - gm) / (2.0 * h), -w[k], g0.t);
            }
            let mut pp = pose;
            pp.angle += 1e-9;
            let mut pm = pose;
            pm.angle -= 1e-9;
            let gp = pin_at_pose(&prof, j, &pp, None).unwrap().gap;
            let gm = pin_at_pose(&prof, j, &pm, None).unwrap().gap;
            let rel = geo.pin_centre(j) - pose.centre;
            eprintln!("pin {j} angle: fd {:.9e} analytic {:.9e}", (gp - gm) / 2e-9, -cross(&rel, &w));
        }
    }
}

#[cfg(test)]
mod debug_tests2 {
    use super::*;

    #[test]
    fn structural_energy_matches_forces() {
        let m = crate::config::Config::example().validate().unwrap();
        let prof = m.profile(None).unwrap();
        let red = &m.reducer;
        let sa = StaticAnalysis::new(red, &prof);
        let fr = sa.frame(0.3);
        let n = red.layout().dofs();
        let mut z = [0.0; MAX_DOFS];
        for i in 1..n {
            z[i] = 1e-6 * ((i as f64) * 0.7).sin();
        }
        let zero = [0.0; MAX_DOFS];
        let mut g = [0.0; MAX_DOFS];
        red.structural_forces(&fr.q0[..n], &z[..n], &zero[..n], &mut g[..n]);
        for c in 0..n {
            let h = 1e-10;
            let mut zp = z;
            zp[c] += h;
            let mut zm = z;
            zm[c] -= h;
            let fd = -(red.structural_energy(&fr.q0[..n], &zp[..n])
                - red.structural_energy(&fr.q0[..n], &zm[..n]))
                / (2.0 * h);
            eprintln!("dof {c}: fd {fd:.6e} force {:.6e}", g[c]);
        }
    }
}
