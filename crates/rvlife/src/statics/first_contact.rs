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
    /// is the largest twist the constraints allow ([`StaticAnalysis::no_load`], docs/model.md
    /// section 5.10). Where the parts interfere (preload, docs/model.md section 5.12) there is
    /// no such limit, and the rigid first contact is returned: the two directions' values then
    /// cross, which the callers report.
    ///
    /// # Errors
    /// Those of [`StaticAnalysis::first_contact`] and [`StaticAnalysis::no_load`].
    pub(crate) fn no_load_twist(&self, phi: f64, direction: f64) -> Result<f64> {
        let psi0 = self.first_contact(phi, direction)?;
        Ok(match self.no_load(phi, direction, psi0)? {
            NoLoad::Limit { twist, .. } => twist,
            NoLoad::Preloaded { .. } => psi0,
        })
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
