//! The reducer running quasi-statically with friction in its equilibrium (docs/model.md
//! section 18.8): the contacts' friction forces as generalised forces of the static analysis,
//! the input torque that drives the output against its torque, the elastic energy and the
//! kinematic rates along which the friction forces work.
//!
//! The friction law is not the statics' (it is the lubrication's, `crate::efficiency`): a
//! [`ContactFriction`] holds the forces a law gives at one configuration, and
//! [`StaticAnalysis::solve_with_friction`] solves the equilibrium with them held. Iterated to a
//! fixed point, the normal loads and the friction forces are each other's, and by virtual work
//! the input's work equals the output's, the change of the elastic energy and the friction
//! forces' work along the path, to the solver's tolerance.

use super::*;
use crate::geometry::rotate;

/// The friction forces of one configuration on the moving bodies (a friction law's output):
/// each disc-pin contact's tangential force on the disc, each crank bearing's friction moment,
/// the meshes' moment on the input. Their generalised forces are
/// [`StaticAnalysis::applied_forces`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactFriction {
    /// Per disc and pin (`discs x Zp`), the tangential force on the disc at the pin's contact
    /// along the pin's counter-clockwise tangent, N (0 for an unloaded pin).
    pub pins: Vec<Vec<f64>>,
    /// Per crank bearing, in the order of [`StaticAnalysis::bearing_forces`], the friction
    /// moment on its inner body (the crank; in a single-stage drive the input's eccentric)
    /// about `+z`, N m; its outer body (the carrier or the disc) takes the opposite.
    pub bearings: Vec<f64>,
    /// Moment on the input shaft about `+z`, N m (the sun-planet meshes' friction).
    pub input: f64,
}

/// The nominal (kinematic) rates of one configuration per unit input rotation, along which the
/// friction forces of a running reducer act ([`StaticAnalysis::running_rates`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RunningRates {
    /// Per disc and pin, the speed of the disc's material at the contact along the pin's
    /// counter-clockwise tangent, m/rad (0 for an unloaded pin).
    pub contacts: Vec<Vec<f64>>,
    /// Per crank bearing (order of [`StaticAnalysis::bearing_forces`]), the inner body's turn
    /// relative to the outer's, rad/rad.
    pub bearings: Vec<f64>,
    /// The output's turn, rad/rad (`1/i_H`).
    pub output: f64,
}

impl ContactFriction {
    /// The power of these forces along `rates` per unit input speed (W per rad/s; negative
    /// where they resist the motion): `sum F w + sum M r + M_in`.
    pub fn power(&self, rates: &RunningRates) -> f64 {
        let pins: f64 = self
            .pins
            .iter()
            .zip(&rates.contacts)
            .flat_map(|(f, w)| f.iter().zip(w).map(|(f, w)| f * w))
            .sum();
        let bearings: f64 = self
            .bearings
            .iter()
            .zip(&rates.bearings)
            .map(|(m, r)| m * r)
            .sum();
        pins + bearings + self.input
    }
}

impl<'a> StaticAnalysis<'a> {
    /// The frame of the analysed reducer in which `sol` was solved (its crank angle with the
    /// meshes' play taken up in its torque's sense).
    fn frame_of(&self, sol: &StaticSolution) -> Frame {
        self.frame(
            self.play_taken_up(sol.crank_angle, sense(sol.output_torque))
                .0,
        )
    }

    /// The inner and outer body (coordinate indices of their angles) of each crank bearing in
    /// the order of [`StaticAnalysis::bearing_forces`].
    fn bearing_bodies(&self) -> Vec<(usize, usize)> {
        let red = &*self.red;
        let lay = red.layout();
        let mut out = Vec::new();
        if red.cranks == 0 {
            for d in 0..red.discs() {
                out.push((Layout::SUN, lay.disc(d) + 2));
            }
        } else {
            for k in 0..red.cranks {
                let c = lay.crank(k) + 2;
                out.push((c, Layout::OUT));
                for d in 0..red.discs() {
                    out.push((c, lay.disc(d) + 2));
                }
            }
        }
        out
    }

    /// Each loaded contact of `sol`: `(disc, pin, contact point relative to the disc centre,
    /// pin's counter-clockwise tangent)`, fixed frame.
    fn contact_frames(&self, sol: &StaticSolution, fr: &Frame) -> Vec<(usize, usize, Vec2, Vec2)> {
        let mut out = Vec::new();
        for (d, disc) in sol.discs.iter().enumerate() {
            let pose = self.pose_from(fr, &sol.deviations, d);
            for p in disc.pins.iter().filter(|p| p.force > 0.0) {
                let r = rotate(&p.point, pose.angle);
                let outward = -rotate(&p.normal, pose.angle);
                out.push((d, p.pin, r, Vec2::new(-outward.y, outward.x)));
            }
        }
        out
    }

    /// The generalised forces (N, N m; layout of [`Layout`]) of the friction `friction` at the
    /// solution `sol`: each pin's tangential force on its disc's centre and, about it, on its
    /// angle; each bearing's moment on its inner and (opposite) outer body; the input's moment.
    /// Empty with rigid support.
    pub fn applied_forces(&self, sol: &StaticSolution, friction: &ContactFriction) -> Vec<f64> {
        let lay = self.red.layout();
        let n = lay.dofs();
        if sol.deviations.len() != n {
            return Vec::new();
        }
        let fr = self.frame_of(sol);
        let mut q = vec![0.0; n];
        for (d, j, r, t) in self.contact_frames(sol, &fr) {
            let f = friction
                .pins
                .get(d)
                .and_then(|p| p.get(j))
                .copied()
                .unwrap_or(0.0);
            let i = lay.disc(d);
            q[i] += f * t.x;
            q[i + 1] += f * t.y;
            q[i + 2] += f * cross(&r, &t);
        }
        for ((inner, outer), m) in self.bearing_bodies().into_iter().zip(&friction.bearings) {
            q[inner] += m;
            q[outer] -= m;
        }
        q[Layout::SUN] += friction.input;
        q
    }

    /// The equilibrium at the crank angle and torque of `near` (a solution there, from which it
    /// starts) with the friction forces `friction` held ([`StaticAnalysis::applied_forces`] at
    /// `near`'s configuration; [`StaticAnalysis::solve_loaded`]).
    ///
    /// # Errors
    /// As [`StaticAnalysis::solve`]; [`Error::Invalid`] with rigid support.
    pub fn solve_with_friction(
        &self,
        near: &StaticSolution,
        friction: &ContactFriction,
    ) -> Result<StaticSolution> {
        let applied = self.applied_forces(near, friction);
        if applied.is_empty() {
            return Err(Error::invalid(
                "static analysis with friction",
                "rigid support",
                "needs bearing support (every coordinate of the reducer)",
            ));
        }
        self.solve_loaded(
            near.crank_angle,
            near.output_torque,
            near.first_contact_twist,
            Some(near),
            &[],
            &applied,
        )
    }

    /// The torque on the input (N m, about `+z`) that holds the solution `sol` of the forces
    /// `friction` in equilibrium: minus the generalised force of the meshes (or the
    /// eccentric bearings) and of the friction on the input coordinate. NaN with rigid support.
    pub fn input_torque(&self, sol: &StaticSolution, friction: &ContactFriction) -> f64 {
        let n = self.red.layout().dofs();
        if sol.deviations.len() != n {
            return f64::NAN;
        }
        let fr = self.frame_of(sol);
        let (zero, mut g) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
        self.red
            .structural_forces(&fr.q0[..n], &sol.deviations, &zero[..n], &mut g[..n]);
        let applied = self.applied_forces(sol, friction);
        -(g[Layout::SUN] + applied[Layout::SUN])
    }

    /// The elastic energy of the solution `sol`, J: the meshes', the bearings' and the
    /// contacts'.
    ///
    /// # Errors
    /// [`Error::Invalid`] with rigid support; the contact law's.
    pub fn elastic_energy_of(&self, sol: &StaticSolution) -> Result<f64> {
        let n = self.red.layout().dofs();
        if sol.deviations.len() != n {
            return Err(Error::invalid(
                "elastic energy",
                "rigid support",
                "needs bearing support",
            ));
        }
        let fr = self.frame_of(sol);
        let mut z = [0.0; MAX_DOFS];
        z[..n].copy_from_slice(&sol.deviations);
        let mut memory = vec![vec![PinMemory::NONE; self.red.geometry.pins]; self.red.discs()];
        let ev = self.eval_bearings(&fr, &z, &mut memory, false)?;
        Ok(self.elastic_energy(&fr, &z, &ev))
    }

    /// The positions of every coordinate of `sol` (nominal plus deviations, the analysed
    /// reducer's frame), m and rad: the path whose differences the friction forces work along.
    pub fn positions_of(&self, sol: &StaticSolution) -> Vec<f64> {
        let n = self.red.layout().dofs();
        let fr = self.frame_of(sol);
        (0..n)
            .map(|i| fr.q0[i] + sol.deviations.get(i).copied().unwrap_or(0.0))
            .collect()
    }

    /// The nominal rates of the configuration `sol` per unit input rotation (docs/model.md
    /// section 1): the disc material's speed at each loaded contact along the pin's tangent,
    /// each bearing's relative turn, the output's turn.
    pub fn running_rates(&self, sol: &StaticSolution) -> RunningRates {
        let red = &*self.red;
        let lay = red.layout();
        let n = lay.dofs();
        let fr = self.frame_of(sol);
        let (mut q, mut qd, mut qdd) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS], [0.0; MAX_DOFS]);
        red.nominal(
            fr.q0[Layout::SUN],
            1.0,
            0.0,
            &mut q[..n],
            &mut qd[..n],
            &mut qdd[..n],
        );
        let mut contacts: Vec<Vec<f64>> =
            sol.discs.iter().map(|d| vec![0.0; d.pins.len()]).collect();
        if sol.deviations.len() == n {
            for (d, j, r, t) in self.contact_frames(sol, &fr) {
                let i = lay.disc(d);
                let v = Vec2::new(qd[i], qd[i + 1]) + perp(r) * qd[i + 2];
                contacts[d][j] = v.dot(&t);
            }
        }
        let bearings = self
            .bearing_bodies()
            .into_iter()
            .map(|(a, b)| qd[a] - qd[b])
            .collect();
        RunningRates {
            contacts,
            bearings,
            output: qd[Layout::OUT],
        }
    }
}

/// Relative change of the friction forces' generalised forces between two sweeps at which
/// [`StaticAnalysis::solve_running`] stops (forces over the sum of the pin forces, moments over
/// the pin circle radius too): the equilibrium's own tolerance.
pub(crate) const FRICTION_TOLERANCE: f64 = RESIDUAL_TOLERANCE;

/// Most sweeps of [`StaticAnalysis::solve_running`].
const FRICTION_SWEEPS: usize = 60;

impl<'a> StaticAnalysis<'a> {
    /// The equilibrium of the running reducer at the crank angle and torque of `start` (a
    /// solution there, frictionless or not) with the friction forces of the law `law` at its
    /// own configuration: sweeps of [`StaticAnalysis::solve_with_friction`], each holding the
    /// law's forces at the solution before, until they change by less than
    /// [`FRICTION_TOLERANCE`] of the force scale (the friction couples into the normal loads
    /// by the coefficient, so each sweep cuts the change about tenfold; where the sweeps
    /// alternate, as a pin switching between rolling and sliding can make them, the forces are
    /// relaxed, by halves down to 1/64). Returns the solution and the forces it holds.
    ///
    /// # Errors
    /// The law's and the solves'; [`Error::Numerical`] naming the crank angle and torque if the
    /// forces do not settle in 60 sweeps.
    pub fn solve_running(
        &self,
        start: &StaticSolution,
        law: impl Fn(&StaticSolution) -> Result<ContactFriction>,
    ) -> Result<(StaticSolution, ContactFriction)> {
        let n = self.red.layout().dofs();
        let rp = self.red.geometry.pin_circle_radius;
        let scaled = |q: &[f64], i: usize| q[i] / if is_angle(i) { rp } else { 1.0 };
        let mut held = law(start)?;
        let mut sol = self.solve_with_friction(start, &held)?;
        let (mut omega, mut last_change) = (1.0_f64, f64::INFINITY);
        for _ in 0..FRICTION_SWEEPS {
            let target = law(&sol)?;
            let (a, b) = (
                self.applied_forces(&sol, &held),
                self.applied_forces(&sol, &target),
            );
            let scale: f64 = sol
                .discs
                .iter()
                .flat_map(|d| d.pins.iter().map(|p| p.force))
                .sum::<f64>()
                .max(sol.output_torque.abs() / rp)
                .max(1e-300);
            let change = (0..n.min(a.len()).min(b.len()))
                .map(|i| (scaled(&a, i) - scaled(&b, i)).abs())
                .fold(0.0, f64::max);
            if change <= FRICTION_TOLERANCE * scale {
                return Ok((sol, held));
            }
            if change > 0.9 * last_change {
                omega = (0.5 * omega).max(1.0 / 64.0);
            }
            last_change = change;
            held = if omega < 1.0 {
                held.mixed(&target, omega)
            } else {
                target
            };
            sol = self.solve_with_friction(&sol, &held)?;
        }
        Err(self.fail(
            sol.crank_angle,
            &format!(
                "the friction forces did not settle in {FRICTION_SWEEPS} sweeps (output torque \
                 {:.6e} N m)",
                sol.output_torque
            ),
        ))
    }
}

impl ContactFriction {
    /// `(1 - w) self + w other`, entry by entry.
    fn mixed(&self, other: &ContactFriction, w: f64) -> ContactFriction {
        let mix = |a: f64, b: f64| (1.0 - w) * a + w * b;
        ContactFriction {
            pins: self
                .pins
                .iter()
                .zip(&other.pins)
                .map(|(a, b)| a.iter().zip(b).map(|(a, b)| mix(*a, *b)).collect())
                .collect(),
            bearings: self
                .bearings
                .iter()
                .zip(&other.bearings)
                .map(|(a, b)| mix(*a, *b))
                .collect(),
            input: mix(self.input, other.input),
        }
    }
}
