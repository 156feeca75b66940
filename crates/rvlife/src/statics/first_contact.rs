//! First contact along the locked-input mode: the `T -> 0+` limit of the loaded twist (the
//! static TE) and the pins that touch first (docs/model.md sections 5 and 6).

use super::*;

impl<'a> StaticAnalysis<'a> {
    /// Mode lever `m_j = -d gap_j / d psi` of a pin along the locked-input mode with
    /// `dc/dpsi` = `dc`.
    pub(super) fn mode_lever(p: &PinEval, dc: Vec2) -> f64 {
        p.w.dot(&dc) + cross(&p.rel, &p.w)
    }

    /// Rigid support: pins of the disc at twist `psi`, the torque `T(psi) = sum F_j m_j /
    /// share` and its derivative.
    pub(super) fn eval_rigid(
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
    pub(super) fn mode_gap(
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
    pub(crate) fn first_contact(&self, phi: f64, direction: f64) -> Result<f64> {
        let s = sense(direction);
        let (phi_free, shift) = self.play_taken_up(phi, s);
        Ok(self.first_contact_free(phi_free, s)? + shift)
    }

    /// [`StaticAnalysis::first_contact`] of the analysed reducer (the backlash-free copy of a
    /// reducer with backlash in its meshes) at its crank angle `phi`, direction `s` (+-1).
    fn first_contact_free(&self, phi: f64, s: f64) -> Result<f64> {
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

    /// The `T -> 0+` limit of the loaded twist (rad) in direction `direction` at crank angle
    /// `phi`: [`StaticAnalysis::first_contact`] when the reducer has no play in its bearings
    /// and meshes; otherwise the mechanism first turns through its play (the bearings' centres
    /// and the meshes move within their clearances until pins stop the discs), and the limit
    /// is extrapolated from loaded solutions at `T_1`, `2 T_1` and `4 T_1` (the fit
    /// `psi = psi_0 + a T^0.9 + b T`: the rollers' approach goes as `F^0.9`, the contacts'
    /// nearly as `F`), `T_1` the torque at which a bearing force `10^3 k_0 c/2` balances it
    /// at the crank circle (`k_0` = [`crate::reducer::DEAD_BAND_STIFFNESS`], `c/2` the largest
    /// half play): loads far above the dead-band springs and far below the rated ones; `10 T_1`
    /// where a solve at `T_1` does not converge, `100 T_1` where neither does, then halving down
    /// from `10^3 T_1` or `10^4 T_1` (docs/model.md section 5.10).
    ///
    /// # Errors
    /// Those of [`StaticAnalysis::first_contact`] and [`StaticAnalysis::solve`].
    pub(crate) fn no_load_twist(&self, phi: f64, direction: f64) -> Result<f64> {
        let psi0 = self.first_contact(phi, direction)?;
        Ok(self.no_load_from(phi, direction, psi0)?.0)
    }

    /// [`StaticAnalysis::no_load_twist`] from the first contact `psi0` already found
    /// ([`StaticAnalysis::first_contact`] in the same direction), with the heaviest of the
    /// light solves it was extrapolated from (`None` without play), from which solves at
    /// higher torques can start.
    ///
    /// # Errors
    /// As [`StaticAnalysis::no_load_twist`].
    pub(crate) fn no_load_from(
        &self,
        phi: f64,
        direction: f64,
        psi0: f64,
    ) -> Result<(f64, Option<StaticSolution>)> {
        let s = sense(direction);
        let play = self.red.max_half_play();
        if play <= 0.0 || self.red.support != Support::Bearings {
            return Ok((psi0, None));
        }
        let arm = match self.red.drive {
            Drive::Rv => self.red.crank_circle_radius,
            Drive::SingleStage(_) => {
                self.red.geometry.eccentricity * self.red.geometry.disc_teeth() as f64
            }
        };
        let t1 = 1e3 * crate::reducer::DEAD_BAND_STIFFNESS * play * arm;
        // The three light solves; should one fail to converge (a disc nearly unloaded between
        // both flanks, its contacts switching within Newton's steps; a disc on one pin of a
        // modified profile with its bearing at the edge of its clearance), all three again at
        // ten, then a hundred times the torques.
        let solves = |t1: f64| -> Result<([f64; 3], Option<StaticSolution>)> {
            let mut psi = [0.0; 3];
            let mut below: Option<StaticSolution> = None;
            for (i, f) in [1.0, 2.0, 4.0].iter().enumerate() {
                let sol = self.solve_near(phi, s * f * t1, psi0, below.as_ref())?;
                psi[i] = sol.twist;
                below = Some(sol);
            }
            Ok((psi, below))
        };
        // Last resort: down from a loaded state, where the contacts are settled, halving the
        // torque from `10^3 T_1` (then `10^4 T_1`) with each solve started from the one above,
        // until a solve fails or `T_1` is reached: the three lightest converged, `L, 2 L, 4 L`,
        // then take the place of `T_1, 2 T_1, 4 T_1`.
        let descending = |top: f64| -> Result<([f64; 3], Option<StaticSolution>)> {
            let mut done: Vec<StaticSolution> = Vec::new();
            let mut t = top;
            let mut last_error = None;
            while t >= 0.99 * t1 {
                match self.solve_near(phi, s * t, psi0, done.last()) {
                    Ok(sol) => done.push(sol),
                    Err(e) => {
                        last_error = Some(e);
                        break;
                    }
                }
                t *= 0.5;
            }
            let n = done.len();
            if n < 3 {
                return Err(last_error.unwrap_or_else(|| {
                    self.fail(phi, "no light solve converged on the way down")
                }));
            }
            let psi = [done[n - 1].twist, done[n - 2].twist, done[n - 3].twist];
            Ok((psi, Some(done.swap_remove(n - 3))))
        };
        // Each attempt in turn while the one before fails to converge; the last one's error.
        type Light = Result<([f64; 3], Option<StaticSolution>)>;
        let later: [&dyn Fn() -> Light; 4] = [
            &|| solves(10.0 * t1),
            &|| solves(100.0 * t1),
            &|| descending(1e3 * t1),
            &|| descending(1e4 * t1),
        ];
        let mut light = solves(t1);
        for attempt in later {
            match light {
                Err(Error::Numerical { .. }) => light = attempt(),
                _ => break,
            }
        }
        let (psi, heaviest) = light?;
        // psi_i = psi_0 + a x_i^0.9 + b x_i at x = 1, 2, 4 (units of T_1).
        let m = nalgebra::Matrix3::from_fn(|r, c| {
            let x = [1.0_f64, 2.0, 4.0][r];
            [1.0, x.powf(0.9), x][c]
        });
        let sol = m
            .lu()
            .solve(&nalgebra::Vector3::new(psi[0], psi[1], psi[2]))
            .ok_or_else(|| self.fail(phi, "the no-load extrapolation is singular"))?;
        // The limit lies between the rigid first contact and the lightest loaded solution.
        let lo = psi0.min(psi[0]);
        let hi = psi0.max(psi[0]);
        Ok((sol[0].clamp(lo, hi), heaviest))
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
    pub(crate) fn touching_pins(
        &self,
        phi: f64,
        direction: f64,
        gap_reach: f64,
    ) -> Result<Vec<TouchingPin>> {
        let s = sense(direction);
        let (phi, shift) = self.play_taken_up(phi, s);
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
                twist: b + shift,
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
    pub(crate) fn pin_touching_twist(
        &self,
        phi: f64,
        disc: usize,
        pin: usize,
        estimate: f64,
        direction: f64,
    ) -> Result<Option<f64>> {
        let s = sense(direction);
        let (phi, shift) = self.play_taken_up(phi, s);
        Ok(self
            .touching_twist(phi, disc, pin, estimate - shift, s, f64::NAN)?
            .map(|b| b + shift))
    }

    /// The same analysis for the reducer `red` (same profile and contact geometry, e.g. the
    /// reducer without its part errors), without rebuilding the contact geometry.
    ///
    /// # Errors
    /// [`Error::Invalid`] if `red` has another gap table or band than this analysis's reducer.
    pub(crate) fn for_reducer<'b>(&self, red: &'b Reducer) -> Result<StaticAnalysis<'b>>
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
        Ok(StaticAnalysis::with_field(
            red,
            self.profile,
            self.field.clone(),
        ))
    }

    /// The pins of every disc that can stop the unloaded mechanism turned in direction `s`
    /// (+-1) at crank angle `phi` ([`Stopping`]).
    pub(super) fn stopping_pins(&self, phi: f64, s: f64) -> Result<Vec<Stopping>> {
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
    pub(super) fn lever_floor(&self) -> f64 {
        1e-9 * self.red.geometry.pin_circle_radius
    }

    /// Twist (rad) at which pin `j` of disc `d` touches, near the estimate `est`, turning in
    /// direction `s`; `None` if it moves away.
    pub(super) fn touching_twist(
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
}
