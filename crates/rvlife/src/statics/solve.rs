//! Solutions under an output torque: the potential's minimum (torque control) from a neighbour
//! or cold, load steps where it does not converge from there, sequences of crank angles, and
//! the checked solution (docs/model.md section 5.3).

use super::*;

impl<'a> StaticAnalysis<'a> {
    /// Static equilibrium at crank angle `phi` (rad) under output torque `torque` (N m; zero
    /// gives the `T -> 0+` pose of the forward direction with zero forces).
    ///
    /// # Errors
    /// [`Error::Invalid`] for a non-finite input; [`Error::Numerical`] naming the crank angle,
    /// torque and wear if the equilibrium is not reached to `RESIDUAL_TOLERANCE`, or if the
    /// contact law leaves its range.
    pub fn solve(&self, phi: f64, torque: f64) -> Result<StaticSolution> {
        check_input(phi, torque)?;
        let s = sense(torque);
        let psi0 = self.first_contact(phi, s)?;
        self.solve_from(phi, torque, psi0)
    }

    /// [`StaticAnalysis::solve`] with the first-contact twist `psi0` (rad) of the torque's
    /// direction already known.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`].
    pub(crate) fn solve_from(&self, phi: f64, torque: f64, psi0: f64) -> Result<StaticSolution> {
        self.solve_near(phi, torque, psi0, None)
    }

    /// [`StaticAnalysis::solve_from`] started from `near`, the solution at a nearby crank angle
    /// or torque of the same direction (a continuation: fewer Newton steps than the cold start;
    /// the solution is the same to the convergence tolerance). A `near` of the other direction
    /// is ignored.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`].
    pub(crate) fn solve_near(
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
    pub(crate) fn solve_with_offsets(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        offsets: &[f64],
    ) -> Result<StaticSolution> {
        self.solve_loaded(phi, torque, psi0, near, offsets, &[])
    }

    /// [`StaticAnalysis::solve_with_offsets`] with the constant generalised forces `applied`
    /// (N on lengths, N m on angles, in the layout of [`Layout`], or empty) acting besides the
    /// output torque: forces that a model outside this one supplies, such as the contacts'
    /// friction at the configuration before (docs/model.md section 18.8). Bearing support only.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve_with_offsets`]; [`Error::Invalid`] if `applied` is neither
    /// empty nor one finite value per coordinate, or is given with rigid support.
    pub(crate) fn solve_loaded(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        offsets: &[f64],
        applied: &[f64],
    ) -> Result<StaticSolution> {
        let n = self.red.layout().dofs();
        if !(applied.is_empty() || (applied.len() == n && self.red.support == Support::Bearings))
            || applied.iter().any(|a| !a.is_finite())
        {
            return Err(Error::invalid(
                "static analysis applied forces",
                format!("{} values", applied.len()),
                format!("must be empty or {n} finite values, with bearing support"),
            ));
        }
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
        let s = sense(torque);
        let (phi_free, shift) = self.play_taken_up(phi, s);
        if shift == 0.0 {
            return self.solve_free(phi, torque, psi0, near, &Extra { offsets, applied });
        }
        // The backlash-free copy at its crank angle, from `near` taken there too.
        let near = near.map(|x| {
            let sx = sense(x.output_torque);
            let (phi_x, shift_x) = self.play_taken_up(x.crank_angle, sx);
            StaticSolution {
                crank_angle: phi_x,
                twist: x.twist - shift_x,
                first_contact_twist: x.first_contact_twist - shift_x,
                ..x.clone()
            }
        });
        let extra = Extra { offsets, applied };
        let mut sol = self.solve_free(phi_free, torque, psi0 - shift, near.as_ref(), &extra)?;
        if torque != 0.0 {
            self.check_meshes_engaged(&sol, s)?;
        }
        sol.crank_angle = phi;
        sol.twist += shift;
        sol.first_contact_twist += shift;
        Ok(sol)
    }

    /// Every sun-planet mesh of the backlash-free copy at the solution `sol` (its crank angle)
    /// deflected in the sense that a torque of sense `s` loads it, `-s sgn(i_H)` (the locked
    /// sun reacts `-T/i_H`, so the meshes' forces sum to `-T/(i_H r_bs)`): the condition under
    /// which the play of every mesh is taken up (see `StaticAnalysis::mesh_play`).
    ///
    /// # Errors
    /// [`Error::Numerical`] naming the crank angle if a mesh is unloaded or loaded the other
    /// way (its play is not taken up: the reducer would rest inside it).
    fn check_meshes_engaged(&self, sol: &StaticSolution, s: f64) -> Result<()> {
        let red = &*self.red;
        let n = red.layout().dofs();
        if sol.deviations.len() != n {
            return Ok(());
        }
        let fr = self.frame(sol.crank_angle);
        let sense = -s * red.ratio.signum();
        for k in 0..red.cranks {
            let delta = red.mesh_deflection(k, &fr.q0[..n], &sol.deviations);
            if sense * delta <= 0.0 || delta.is_nan() {
                return Err(self.fail(
                    sol.crank_angle,
                    &format!(
                        "the sun-planet mesh of crank {} is not loaded in the sense of the \
                         output torque {:.6e} N m (deflection {delta:.3e} m): the meshes' \
                         backlash cannot be taken up",
                        k + 1,
                        sol.output_torque
                    ),
                ));
            }
        }
        Ok(())
    }

    /// [`StaticAnalysis::solve_with_offsets`] of the analysed reducer at its crank angle
    /// `phi` (no play to take up).
    fn solve_free(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        extra: &Extra,
    ) -> Result<StaticSolution> {
        match self.solve_direct(phi, torque, psi0, near, extra) {
            Err(Error::Numerical { .. }) if torque != 0.0 => {
                self.loaded_solves[1].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                self.solve_in_load_steps(phi, torque, psi0, near, extra)
            }
            result => result,
        }
    }

    /// [`StaticAnalysis::solve_with_offsets`] where the solve from its start does not converge
    /// (path following with step control): the torque applied in steps
    /// from `near` (loaded in the same sense, below or above the torque by more than a
    /// thousandth of it; else from zero), each
    /// solve started from the one before, a step halved where it fails and doubled again (up to
    /// an eighth of the way) where it succeeds (a disc that moves onto other pins part of the
    /// way, as on a ridge of a worn flank, is followed along the loading path). The error of the last step tried when
    /// the step falls below 1e-6 of the torque, or after [`MAX_LOAD_STEPS`] solves (a path that
    /// advances by ever smaller steps would otherwise run for hours).
    pub(super) fn solve_in_load_steps(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        extra: &Extra,
    ) -> Result<StaticSolution> {
        let mut prev = near
            .filter(|x| {
                x.output_torque * torque > 0.0
                    && (x.output_torque - torque).abs() > 1e-3 * torque.abs()
            })
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
            match self.solve_direct(phi, next, psi0, prev.as_ref(), extra) {
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
    pub(super) fn solve_direct(
        &self,
        phi: f64,
        torque: f64,
        psi0: f64,
        near: Option<&StaticSolution>,
        extra: &Extra,
    ) -> Result<StaticSolution> {
        let s = sense(torque);
        let n = self.red.layout().dofs();
        let near = near.filter(|x| {
            let beyond = s * (x.twist - x.first_contact_twist);
            (x.output_torque == 0.0 || x.output_torque * s > 0.0) && beyond.is_finite()
        });
        let start = Start {
            psi0,
            near: near.filter(|x| x.deviations.len() == n).map(|x| Near {
                deviations: &x.deviations,
                first_contact_twist: x.first_contact_twist,
                torque: x.output_torque,
                stiffness: x.stiffness,
                direction: &x.twist_direction,
            }),
            beyond: near.map(|x| s * (x.twist - x.first_contact_twist)),
            extra: *extra,
            settle: false,
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
    /// of consecutive angles ([`sequence_run`]), each solve of a run started from its
    /// predecessor's solution. The runs do not depend on the number of threads, so neither do
    /// the results.
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`], for the first crank angle that fails.
    pub(crate) fn solve_sequence(&self, phis: &[f64], torque: f64) -> Result<Vec<StaticSolution>> {
        let s = sense(torque);
        let runs: Vec<Vec<StaticSolution>> = phis
            .par_chunks(sequence_run(phis.len()))
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

    /// The rigid support's twist (its only unknown): safeguarded Newton on the monotone
    /// `f(x) = s T(psi0 + s x) - |T|` with `eval(psi) -> (T, dT/dpsi)`. Returns the converged
    /// twist. The root lies at `x >= 0`
    /// unless the reducer already carries more than `|T|` at its rigid first contact (part
    /// errors or a modification that interfere: preload, docs/model.md section 5.12): where
    /// every twist tried carries too much down to [`BEHIND_FIRST_CONTACT`] of the twist
    /// estimate, the search continues behind first contact.
    pub(super) fn outer<F>(&self, phi: f64, torque: f64, start: &Start, mut eval: F) -> Result<f64>
    where
        F: FnMut(f64) -> Result<(f64, f64)>,
    {
        let psi0 = start.psi0;
        let s = sense(torque);
        let target = torque.abs();
        let tol = 1e-11 * target;
        let guess = self.twist_guess(torque);
        let (mut lo, mut hi) = (0.0_f64, f64::INFINITY);
        // Whether the bracket is open below first contact (preload).
        let mut behind = false;
        let mut x = match start.beyond {
            Some(b) if b > 0.0 => b,
            _ => guess,
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
            if !behind && lo == 0.0 && hi < BEHIND_FIRST_CONTACT * guess {
                behind = true;
                lo = f64::NEG_INFINITY;
            }
            // Newton inside the bracket; while the bracket is open above, at most four times
            // the current twist (the stiffness grows as pins engage, so a step from a soft
            // start overshoots); while it is open below, at most four twist estimates behind.
            let newton = if k > 0.0 { x - f / k } else { f64::NAN };
            let floor = if lo.is_finite() {
                lo
            } else {
                hi - 4.0 * hi.abs().max(guess)
            };
            let ceiling = if x > 0.0 { hi.min(4.0 * x) } else { hi };
            // (Bisection only after 40 steps: where round-off makes T(psi) jitter at the
            // tolerance, Newton can wander inside the bracket.)
            let next = if step < 40 && newton > floor && newton < ceiling {
                newton
            } else if !lo.is_finite() {
                floor
            } else if hi.is_finite() {
                0.5 * (lo + hi)
            } else {
                4.0 * x.max(lo)
            };
            if next.abs() > MAX_TWIST {
                return Err(self.fail(
                    phi,
                    &format!(
                        "the output torque {torque:.6e} N m needs a twist beyond {:.0} arcmin: \
                         more than the contact model can describe",
                        MAX_TWIST * ARCMIN_PER_RAD
                    ),
                ));
            }
            if hi.is_finite()
                && lo.is_finite()
                && hi - lo <= 1e-15 * hi.abs().max(lo.abs()).max(1e-12)
            {
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
    pub(super) fn twist_guess(&self, t: f64) -> f64 {
        let geo = &self.red.geometry;
        let rc = geo.disc_pitch_radius();
        let f = 4.0 * 0.5 * t.abs() * self.red.twist_factor() / (rc * geo.pins as f64);
        let delta = self.red.contact.approach(f.max(1e-6), 0.0);
        (3.0 * delta / rc).max(1e-12)
    }

    pub(super) fn solve_rigid(
        &self,
        phi: f64,
        torque: f64,
        start: &Start,
    ) -> Result<StaticSolution> {
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
            twist_direction: Vec::new(),
        })
    }

    pub(super) fn solve_bearings(
        &self,
        phi: f64,
        torque: f64,
        start: &Start,
    ) -> Result<StaticSolution> {
        let psi0 = start.psi0;
        let red = &*self.red;
        let n = red.layout().dofs();
        let zp = red.geometry.pins;
        let mut fr = self.frame(phi);
        fr.offsets = start.extra.offsets.to_vec();
        fr.applied[..start.extra.applied.len()].copy_from_slice(start.extra.applied);
        let mut memory = vec![vec![PinMemory::NONE; zp]; self.red.discs()];
        let mut z = [0.0; MAX_DOFS];
        self.mode_deviation(&fr, psi0, &mut z[..n]);
        let k_struct = self.structural_stiffness(&fr, &z[..n]);
        if torque == 0.0 {
            let ev = self.eval_bearings(&fr, &z, &mut memory, false)?;
            let kt = self.tangent(&k_struct, &ev, &fr, &z);
            return self.check(self.assemble(&fr, &z, ev, &kt, 0.0, psi0));
        }
        self.loaded_solves[0].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        // Cold, from the locked-input mode and, where Newton does not converge from there,
        // from the mode with the other coordinates settled at its twist.
        let mut solved =
            self.torque_controlled(&fr, torque, start, &mut z[..n], &k_struct, &mut memory)?;
        if solved.is_none() && start.near.is_none() {
            for m in memory.iter_mut() {
                m.fill(PinMemory::NONE);
            }
            let settled = Start {
                settle: true,
                ..*start
            };
            solved =
                self.torque_controlled(&fr, torque, &settled, &mut z[..n], &k_struct, &mut memory)?;
        }
        let Some((_, kt)) = solved else {
            return Err(self.fail(
                phi,
                &format!(
                    "the potential's minimum under the output torque was not reached from the \
                     {} start in {} steps",
                    if start.near.is_some() {
                        "neighbour's"
                    } else {
                        "cold"
                    },
                    newton::TORQUE_CONTROL_STEPS
                ),
            ));
        };
        // Every pin at the solution (the solve skipped pins known to be open).
        let ev = self.eval_bearings(&fr, &z, &mut memory, false)?;
        self.check(self.assemble(&fr, &z, ev, &kt, torque, psi0))
    }

    /// The solution at deviations `z` from the full evaluation `ev` there and the tangent `kt`.
    pub(super) fn assemble(
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
        let mut direction = self.condensation_direction(kt);
        direction[Layout::OUT] = 1.0;
        StaticSolution {
            crank_angle: fr.phi,
            output_torque: torque,
            twist: z[Layout::OUT],
            first_contact_twist: psi0,
            stiffness: self.condensed_along(kt, &direction),
            discs,
            residual: if unloaded { 0.0 } else { residual },
            roundoff_floor: if unloaded { 0.0 } else { ev.roundoff / scale },
            deviations: z[..n].to_vec(),
            twist_direction: direction,
        }
    }

    pub(super) fn disc_load(
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
    pub(super) fn check(&self, sol: StaticSolution) -> Result<StaticSolution> {
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
