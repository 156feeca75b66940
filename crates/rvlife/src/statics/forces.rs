//! The forces of one configuration: pin contacts on the gap field, bearings and meshes, and
//! their tangent stiffness (docs/model.md section 5).

use super::*;
use crate::geometry::rotate;

impl<'a> StaticAnalysis<'a> {
    /// Nominal positions at crank angle `phi` (input locked there).
    pub(super) fn frame(&self, phi: f64) -> Frame {
        let red = &*self.red;
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
            applied: [0.0; MAX_DOFS],
        }
    }

    /// Radial forces (N) of the crank bearings at the solution `sol`, in the order of
    /// [`Reducer::structural_forces`]: for each crank its crank-carrier pair, then its
    /// crank-disc bearing of each disc (single-stage: each disc's eccentric bearing). Empty
    /// with rigid support.
    pub(crate) fn bearing_forces(&self, sol: &StaticSolution) -> Vec<f64> {
        let n = self.red.layout().dofs();
        if sol.deviations.len() != n {
            return Vec::new();
        }
        let s = sense(sol.output_torque);
        let fr = self.frame(self.play_taken_up(sol.crank_angle, s).0);
        let mut recorded: Vec<Frozen> = Vec::with_capacity(12);
        let (zero, mut g) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
        self.red.structural_forces_with(
            &fr.q0[..n],
            &sol.deviations,
            &zero[..n],
            &mut g[..n],
            &mut BearingEval::Record(&mut recorded, false),
        );
        recorded.iter().map(|b| b.force().norm()).collect()
    }

    /// The creep of the contacts and bearings of `sol` per unit output twist, along its twist
    /// direction (`dz/dpsi` with the inner coordinates in equilibrium; docs/model.md section
    /// 18.3): per disc and pin, the displacement of the disc's material point at the contact
    /// along the pin's counter-clockwise tangent (m/rad; 0 for an unloaded pin), by central
    /// differences of the poses `1e-7` rad either side; per bearing, in the order of
    /// [`StaticAnalysis::bearing_forces`], its rings' relative turn (rad/rad). `None` where
    /// the solution holds no twist direction (rigid support).
    #[allow(clippy::type_complexity)]
    pub(crate) fn creep_rates(&self, sol: &StaticSolution) -> Option<(Vec<Vec<f64>>, Vec<f64>)> {
        let red = &*self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let t = &sol.twist_direction;
        if t.len() != n || sol.deviations.len() != n {
            return None;
        }
        let s = sense(sol.output_torque);
        let fr = self.frame(self.play_taken_up(sol.crank_angle, s).0);
        const H: f64 = 1e-7;
        let shifted = |h: f64| -> Vec<f64> {
            sol.deviations
                .iter()
                .zip(t)
                .map(|(z, d)| z + h * d)
                .collect()
        };
        let (zp, zm) = (shifted(H), shifted(-H));
        let contacts = sol
            .discs
            .iter()
            .enumerate()
            .map(|(d, disc)| {
                let (a, b) = (self.pose_from(&fr, &zm, d), self.pose_from(&fr, &zp, d));
                disc.pins
                    .iter()
                    .map(|p| {
                        if p.force <= 0.0 {
                            return 0.0;
                        }
                        let moved = (b.centre + rotate(&p.point, b.angle))
                            - (a.centre + rotate(&p.point, a.angle));
                        let out = -rotate(&p.normal, disc.pose.angle);
                        moved.dot(&Vec2::new(-out.y, out.x)) / (2.0 * H)
                    })
                    .collect()
            })
            .collect();
        let mut bearings = Vec::new();
        if red.cranks == 0 {
            for d in 0..red.discs() {
                bearings.push(t[Layout::SUN] - t[lay.disc(d) + 2]);
            }
        } else {
            for k in 0..red.cranks {
                let c = lay.crank(k) + 2;
                bearings.push(t[c] - t[Layout::OUT]);
                for d in 0..red.discs() {
                    bearings.push(t[c] - t[lay.disc(d) + 2]);
                }
            }
        }
        Some((contacts, bearings))
    }

    /// Deviations `z` of the locked-input rigid-body mode at carrier twist `psi` from the
    /// nominal positions of `fr` (bearings and meshes undeformed): carrier `+psi`, crank seats
    /// turned with it, cranks `+(1 + Z1/Z2) psi` about their axes, disc centres on the
    /// eccentrics, discs `+psi`.
    pub(super) fn mode_deviation(&self, fr: &Frame, psi: f64, z: &mut [f64]) {
        let red = &*self.red;
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
    pub(super) fn pose_from(&self, fr: &Frame, z: &[f64], d: usize) -> DiscPose {
        let lay = self.red.layout();
        let i = lay.disc(d);
        let q0 = &fr.q0;
        let (dc, dpsi) = if self.red.errors.has_crank_errors() {
            self.red.disc_correction(
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
    pub(super) fn mode_pose(&self, phi: f64, d: usize, psi: f64) -> (DiscPose, Vec2) {
        let ratio = self.red.crank_mode_ratio();
        match self.red.support {
            Support::Rigid { .. } => {
                let geo = &self.red.geometry;
                let zc = geo.disc_teeth() as f64;
                let ang = phi + ratio * psi;
                let c = Vec2::new(ang.cos(), ang.sin()) * geo.eccentricity;
                let carrier = self.red.input_angle_for_crank(phi) / self.red.ratio + psi;
                let (dc, dpsi) = self.red.disc_correction(ang, carrier);
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
    pub(super) fn eval_pin(&self, pose: &DiscPose, j: usize, hint: f64) -> Result<PinEval> {
        self.eval_pin_from(pose, &Rotation2::new(pose.angle), j, hint, f64::NAN, 0.0)
    }

    /// [`StaticAnalysis::eval_pin`] with the pin's force at a nearby pose (N) as the contact
    /// law's starting guess; `rot` is the rotation of the disc by `pose.angle`; `offset` (m) is
    /// added to the gap.
    pub(super) fn eval_pin_from(
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
        // The pin's wear where the disc meets it, at the kinematic contact (a constant of the
        // solve: the tangent stays exact).
        let worn = self
            .red
            .pin_wear
            .gap_at(&self.red.geometry, j, pose.crank_angle);
        let gap = ge.gap + offset + self.pin_gap[j] + worn;
        let (force, stiffness) = if gap < 0.0 {
            self.contact_law
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
    pub(super) fn eval_pins(&self, pose: &DiscPose, cache: &mut [f64]) -> Result<Vec<PinEval>> {
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

    pub(super) fn law_error(&self, e: Error, pose: &DiscPose) -> Error {
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
    pub(super) fn eval_bearings(
        &self,
        fr: &Frame,
        z: &[f64],
        memory: &mut [Vec<PinMemory>],
        lazy: bool,
    ) -> Result<Eval> {
        let red = &*self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let mut g = [0.0; MAX_DOFS];
        let zero = [0.0; MAX_DOFS];
        red.structural_forces(&fr.q0[..n], &z[..n], &zero[..n], &mut g[..n]);
        for (gi, ai) in g[..n].iter_mut().zip(&fr.applied[..n]) {
            *gi += ai;
        }
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
    pub(super) fn roundoff(&self, stiffness: f64) -> f64 {
        ROUNDOFF_GAP_ULPS * f64::EPSILON * self.red.geometry.pin_circle_radius * stiffness
    }

    /// Structural tangent stiffness `-dQ/dq` (meshes and bearings) by central differences of
    /// [`Reducer::structural_forces`] at deviations `z` (linear springs on exact rigid-body
    /// kinematics: the differences are exact to round-off).
    pub(super) fn structural_stiffness(&self, fr: &Frame, z: &[f64]) -> DMatrix<f64> {
        self.structural_stiffness_with(fr, z, false)
    }

    /// [`StaticAnalysis::structural_stiffness`], with the bearings' stiffness floored when
    /// `floored` ([`crate::reducer::RadialBearing::stiffness_matrix_floored`]).
    pub(super) fn structural_stiffness_with(
        &self,
        fr: &Frame,
        z: &[f64],
        floored: bool,
    ) -> DMatrix<f64> {
        let red = &*self.red;
        let n = red.layout().dofs();
        let rp = red.geometry.pin_circle_radius;
        let mut k = DMatrix::zeros(n, n);
        let zero = [0.0; MAX_DOFS];
        let mut zz = [0.0; MAX_DOFS];
        zz[..n].copy_from_slice(&z[..n]);
        // The bearings' laws linearised here: differences of exact kinematics with no roller
        // sums, exact to round-off for the linear part and the geometric terms alike.
        let mut frozen: Vec<Frozen> = Vec::with_capacity(12);
        let mut g0 = [0.0; MAX_DOFS];
        // The rotations at `z`, each difference re-forming only those its coordinate turns.
        let base = StructureRotations::new(red, &fr.q0[..n], &z[..n]);
        red.structural_forces_at(
            &base,
            &fr.q0[..n],
            &z[..n],
            &zero[..n],
            &mut g0[..n],
            &mut BearingEval::Record(&mut frozen, floored),
            None,
        );
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
            // Only the elements that coordinate `c` moves: the others' forces cancel in the
            // difference.
            zz[c] = z[c] + h;
            red.structural_forces_at(
                &base.moved(red, &fr.q0[..n], &zz[..n], c),
                &fr.q0[..n],
                &zz[..n],
                &zero[..n],
                &mut gp[..n],
                &mut BearingEval::Frozen(&frozen, 0),
                Some(c),
            );
            zz[c] = z[c] - h;
            red.structural_forces_at(
                &base.moved(red, &fr.q0[..n], &zz[..n], c),
                &fr.q0[..n],
                &zz[..n],
                &zero[..n],
                &mut gm[..n],
                &mut BearingEval::Frozen(&frozen, 0),
                Some(c),
            );
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
    pub(super) fn tangent(
        &self,
        k_struct: &DMatrix<f64>,
        ev: &Eval,
        fr: &Frame,
        z: &[f64],
    ) -> DMatrix<f64> {
        if matches!(self.red.drive, Drive::SingleStage(_)) || !self.red.structure_is_linear() {
            let ks = self.structural_stiffness(fr, z);
            return self.tangent_with(&ks, ev);
        }
        self.tangent_with(k_struct, ev)
    }

    /// [`StaticAnalysis::tangent`] with the bearings' stiffness floored (a stiffer stand-in for
    /// the first Newton steps from unloaded bearings; never returned with a solution).
    pub(super) fn tangent_floored(
        &self,
        k_struct: &DMatrix<f64>,
        ev: &Eval,
        fr: &Frame,
        z: &[f64],
    ) -> DMatrix<f64> {
        if self.red.structure_is_linear() {
            return self.tangent(k_struct, ev, fr, z);
        }
        let ks = self.structural_stiffness_with(fr, z, true);
        self.tangent_with(&ks, ev)
    }

    pub(super) fn tangent_with(&self, k_struct: &DMatrix<f64>, ev: &Eval) -> DMatrix<f64> {
        let lay = self.red.layout();
        let mut k = k_struct.clone();
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
                let force_kappa =
                    self.contact_law
                        .force_curvature_derivative(p.force, p.stiffness, p.curvature);
                let kd = a * a.transpose() * p.stiffness
                    - a * dk.transpose() * force_kappa
                    - hess * p.force;
                let mut block = k.view_mut((id, id), (3, 3));
                block += kd;
            }
        }
        k
    }
}
