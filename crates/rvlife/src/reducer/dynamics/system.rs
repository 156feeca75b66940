//! Equations of motion of the planar rigid multibody RV reducer.
//!
//! Bodies and coordinates (all in the fixed pin-ring frame, SI):
//! - input shaft with sun gear: angle `theta_s` (prescribed, or driven by a motor torque);
//! - output carrier (rigid disk + output shaft): angle `theta_o`;
//! - crankshaft `k` with its planet gear: centre `X_k` (2) and angle `vartheta_k` (absolute);
//! - cycloid disc `d` (two, eccentrics 180 degrees apart): centre `c_d` (2) and angle `psi_d`.
//!
//! The mass matrix is diagonal (each body's mass and centroidal inertia), so the equations are
//! `M qdd = Q(t, q, qd)` with every coupling in the generalised forces `Q`, each derived from a
//! potential (or a dissipation) so that without damping and friction the total energy
//! [`System::energy`] is conserved exactly by the continuous equations:
//! - sun-planet mesh (per planet): deflection along the line of action in the carrier frame
//!   `delta = r_bs (theta_s - theta_o) + r_bp (vartheta_k - theta_o) - u_k . (X_k - S_k)`
//!   (lumped-parameter planetary model of Lin and Parker, J. Vib. Acoust. 121, 1999), spring and
//!   damper with backlash;
//! - crank-carrier bearings: isotropic spring-damper between `X_k` and its seat `S_k` on the
//!   carrier, with optional radial clearance;
//! - crank-disc bearings: the same between the eccentric centre of crank `k` for disc `d` and the
//!   bore centre of disc `d`;
//! - disc-pin contacts: the gap from the actual profile ([`GapField`]) and the MSC Adams IMPACT
//!   force `F = k d^e + STEP(d, 0, 0, d_max, c_max) dd/dt` (clamped at zero: a contact never
//!   pulls), optional smoothed Coulomb friction `mu F tanh(v_t / v_ref)` (physics-notes 6);
//! - the output torque on the carrier (positive counter-clockwise: a load resisting forward
//!   rotation is negative) and the motor torque on the input.

use std::cell::RefCell;
use std::f64::consts::PI;

use crate::geometry::{cross, rotate, Vec2};

use super::gap::GapField;
use super::params::{Drive, DynamicsParams, LoadProfile};
use crate::reducer::perp;
pub use crate::reducer::{Layout, MAX_DOFS};

/// Adams `STEP(x, x0, h0, x1, h1)`: cubic blend from `h0` at `x0` to `h1` at `x1`, constant
/// outside (MSC Adams function reference).
#[inline]
pub fn step(x: f64, x0: f64, h0: f64, x1: f64, h1: f64) -> f64 {
    if x <= x0 {
        h0
    } else if x >= x1 {
        h1
    } else {
        let u = (x - x0) / (x1 - x0);
        h0 + (h1 - h0) * u * u * (3.0 - 2.0 * u)
    }
}

/// Integral of `STEP(tau, t0, 0, t1, 1)` from `t0` to `t` (s): the angle of a shaft whose speed
/// is ramped by `STEP`, per unit final speed.
#[inline]
fn step_integral(t: f64, t0: f64, t1: f64) -> f64 {
    if t <= t0 {
        0.0
    } else if t >= t1 {
        0.5 * (t1 - t0) + (t - t1)
    } else {
        let d = t1 - t0;
        let u = (t - t0) / d;
        d * (u * u * u - 0.5 * u * u * u * u)
    }
}

/// Positions, speeds and nominal accelerations of one state (see `System::absolute`).
#[derive(Default)]
struct Kinematics {
    q0: [f64; MAX_DOFS],
    dq: [f64; MAX_DOFS],
    q: [f64; MAX_DOFS],
    qd: [f64; MAX_DOFS],
    qdd: [f64; MAX_DOFS],
}

/// Contact force of one pin on one disc at one instant.
#[derive(Debug, Clone, Copy, Default)]
pub struct PinForce {
    /// Magnitude of the contact force, N (>= 0): the law's force times the length of the gap
    /// field's gradient (the force vector is `F grad(gap)`, as in the static analysis).
    pub normal: f64,
    /// Penetration, m (>= 0).
    pub penetration: f64,
}

/// The assembled reducer: parameters, gap fields and the constant kinematic data.
pub struct System<'a> {
    p: &'a DynamicsParams,
    gaps: [&'a GapField; 2],
    layout: Layout,
    /// Inverse masses per coordinate.
    inv_mass: Vec<f64>,
    /// Masses per coordinate (for the kinetic energy).
    mass: Vec<f64>,
    pins: Vec<Vec2>,
    /// Profile angle offset of each disc (0, -pi/Zc): the profile of disc 2 sits half a tooth
    /// turned, as its crank angle is `phi + pi`.
    chi: [f64; 2],
    zc: f64,
    zp: usize,
    /// Offset of the path parameter of every pin found at the last evaluation from its
    /// kinematic guess (disc-major): the next Newton search starts from the kinematic guess plus
    /// this offset (when below 0.3 rad). The offset follows the small deviations from the
    /// nominal motion, so one Newton step usually suffices.
    t_cache: RefCell<Vec<f64>>,
    /// Last contact force of every pin (disc-major), N: the warm start of the contact law's
    /// inversion.
    f_cache: RefCell<Vec<f64>>,
}

impl<'a> System<'a> {
    /// Assembles the system for `params` with the gap fields of the two discs.
    pub fn new(p: &'a DynamicsParams, gaps: [&'a GapField; 2]) -> Self {
        let red = &p.reducer;
        let layout = red.layout();
        let n = layout.dofs();
        let mut mass = vec![0.0; n];
        mass[Layout::SUN] = p.inertia.input;
        mass[Layout::OUT] = p.inertia.output;
        for k in 0..red.cranks {
            let i = layout.crank(k);
            mass[i] = p.inertia.crank_mass;
            mass[i + 1] = p.inertia.crank_mass;
            mass[i + 2] = p.inertia.crank;
        }
        for d in 0..2 {
            let i = layout.disc(d);
            mass[i] = p.inertia.disc_mass;
            mass[i + 1] = p.inertia.disc_mass;
            mass[i + 2] = p.inertia.disc;
        }
        let geo = &red.geometry;
        let zc = geo.disc_teeth() as f64;
        System {
            p,
            gaps,
            layout,
            inv_mass: mass.iter().map(|m| 1.0 / m).collect(),
            mass,
            pins: (0..geo.pins).map(|j| geo.pin_centre(j)).collect(),
            chi: [red.profile_turn(0), red.profile_turn(1)],
            zc,
            zp: geo.pins,
            t_cache: RefCell::new(vec![f64::NAN; 2 * geo.pins]),
            f_cache: RefCell::new(vec![0.0; 2 * geo.pins]),
        }
    }

    /// The coordinate layout.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// Number of states (`2 x dofs`).
    pub fn states(&self) -> usize {
        2 * self.layout.dofs()
    }

    /// Prescribed input angle (rad) and speed (rad/s) at time `t` for a speed drive.
    pub fn input_motion(&self, t: f64) -> Option<(f64, f64, f64)> {
        match self.p.drive {
            Drive::Speed { speed, t0, t1 } => {
                let w = speed * step(t, t0, 0.0, t1, 1.0);
                let acc = if t > t0 && t < t1 {
                    let u = (t - t0) / (t1 - t0);
                    speed * 6.0 * u * (1.0 - u) / (t1 - t0)
                } else {
                    0.0
                };
                Some((speed * step_integral(t, t0, t1), w, acc))
            }
            Drive::Torque { .. } => None,
        }
    }

    /// Initial state `z = [theta_s, e, omega_s, de/dt]`: the input angle and speed, and the
    /// deviations `e` of every other coordinate from its nominal motion (see the module docs of
    /// [`super`]), all zero: every body at its nominal position, at rest (speed drive) or
    /// spinning rigidly at the drive's initial speed (torque drive). An unmodified disc then
    /// touches every pin with zero force.
    pub fn initial_state(&self) -> Vec<f64> {
        let n = self.layout.dofs();
        let mut z = vec![0.0; 2 * n];
        if let Drive::Torque { initial_speed, .. } = self.p.drive {
            z[n + Layout::SUN] = initial_speed;
        }
        z
    }

    /// Absolute positions and speeds of state `z` at time `t`, and the input acceleration if it
    /// is prescribed.
    /// Nominal positions `q0`, deviations `dq` (zero for the input), absolute speeds `qd` and
    /// nominal accelerations `qdd` of state `z` at time `t`, and the input acceleration if it is
    /// prescribed.
    fn absolute(&self, t: f64, z: &[f64], st: &mut Kinematics) -> Option<f64> {
        let n = self.layout.dofs();
        let motion = self.input_motion(t);
        let (th_s, w_s, a_s) = motion.unwrap_or((z[Layout::SUN], z[n + Layout::SUN], 0.0));
        self.p.reducer.nominal(
            th_s,
            w_s,
            a_s,
            &mut st.q0[..n],
            &mut st.qd[..n],
            &mut st.qdd[..n],
        );
        st.dq[Layout::SUN] = 0.0;
        st.dq[1..n].copy_from_slice(&z[1..n]);
        for i in 1..n {
            st.qd[i] += z[n + i];
        }
        for i in 0..n {
            st.q[i] = st.q0[i] + st.dq[i];
        }
        motion.map(|m| m.2)
    }

    /// Right-hand side `dz/dt` of the first-order system for state `z` (see
    /// [`System::initial_state`]) at time `t`; with `forces`, also the pin forces of both discs
    /// (`2 x Zp`, disc-major).
    pub fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64], forces: Option<&mut [PinForce]>) {
        let n = self.layout.dofs();
        let mut k = Kinematics::default();
        let prescribed = self.absolute(t, z, &mut k);
        let (q, qd, mut qdd) = (k.q, k.qd, k.qdd);
        let mut g = [0.0; MAX_DOFS];
        self.forces(t, &k, &mut g[..n], forces);
        let a_s = match prescribed {
            Some(a) => a,
            None => {
                // Torque drive: the nominal accelerations again, with the input acceleration
                // that the forces give.
                let a = g[Layout::SUN] * self.inv_mass[Layout::SUN];
                let (mut q2, mut qd2) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
                let (th_s, w_s) = (q[Layout::SUN], qd[Layout::SUN]);
                self.p
                    .reducer
                    .nominal(th_s, w_s, a, &mut q2[..n], &mut qd2[..n], &mut qdd[..n]);
                a
            }
        };
        dz[Layout::SUN] = qd[Layout::SUN];
        dz[n + Layout::SUN] = a_s;
        for i in 1..n {
            dz[i] = z[n + i];
            dz[n + i] = g[i] * self.inv_mass[i] - qdd[i];
        }
    }

    /// Generalised forces `Q` (N or N m per coordinate) at the positions and speeds `k`.
    fn forces(&self, t: f64, k: &Kinematics, g: &mut [f64], mut pin_out: Option<&mut [PinForce]>) {
        let p = self.p;
        let lay = self.layout;
        let n = lay.dofs();
        let (q, qd) = (&k.q[..n], &k.qd[..n]);
        g[Layout::OUT] += p.load.torque(t);
        if let Drive::Torque { .. } = p.drive {
            g[Layout::SUN] += p.drive.torque(t);
        }
        p.reducer.structural_forces(&k.q0[..n], &k.dq[..n], qd, g);
        // Disc-pin contacts.
        let ct = &p.contact;
        let mut cache = self.t_cache.borrow_mut();
        let mut fcache = self.f_cache.borrow_mut();
        for d in 0..2 {
            let id = lay.disc(d);
            let c = Vec2::new(q[id], q[id + 1]);
            let cd = Vec2::new(qd[id], qd[id + 1]);
            let (psi, wpsi) = (q[id + 2], qd[id + 2]);
            let ang = psi + self.chi[d];
            // Kinematic crank angle of this disc and the contact-parameter guess of pin j:
            // t_j = -phi - 2 pi j Zc / Zp + Zc (psi + phi / Zc) (geometry::contact_parameter_guess).
            let phi = c.y.atan2(c.x);
            let base = -phi + self.zc * (ang + phi / self.zc);
            let (sa, ca) = ang.sin_cos();
            for j in 0..self.zp {
                let pj = self.pins[j];
                let rel = pj - c;
                let ql = Vec2::new(ca * rel.x + sa * rel.y, -sa * rel.x + ca * rel.y);
                let tg = base - 2.0 * PI * j as f64 * self.zc / self.zp as f64;
                let slot = &mut cache[d * self.zp + j];
                let start = if slot.abs() < 0.3 { tg + *slot } else { tg };
                let (ge, t_found) = self.gaps[d].eval(&ql, start);
                *slot = t_found - tg;
                if ge.gap >= 0.0 {
                    fcache[d * self.zp + j] = 0.0;
                    continue;
                }
                let w = Vec2::new(
                    ca * ge.grad.x - sa * ge.grad.y,
                    sa * ge.grad.x + ca * ge.grad.y,
                );
                let pen = -ge.gap;
                // d(gap)/dt = w . (-c' - psi' J (p - c)).
                let gap_dot = -w.dot(&(cd + perp(rel) * wpsi));
                let f_cached = &mut fcache[d * self.zp + j];
                let elastic = ct
                    .law
                    .force(&p.reducer.contact, pen, ge.curvature, *f_cached);
                *f_cached = elastic;
                let fnorm = (elastic
                    - step(pen, 0.0, 0.0, ct.penetration, ct.max_damping) * gap_dot)
                    .max(0.0);
                // Q = F d(gap)/dx: d gap/dc = -w, d gap/dpsi = -(p - c) x w.
                g[id] -= fnorm * w.x;
                g[id + 1] -= fnorm * w.y;
                g[id + 2] -= fnorm * cross(&rel, &w);
                if ct.friction > 0.0 {
                    let wn = w / w.norm();
                    let tau = perp(wn);
                    let xc = rel - wn * p.reducer.geometry.pin_radius;
                    let v = cd + perp(xc) * wpsi;
                    let vt = v.dot(&tau);
                    let ff = tau * (-ct.friction * fnorm * (vt / ct.friction_velocity).tanh());
                    g[id] += ff.x;
                    g[id + 1] += ff.y;
                    g[id + 2] += cross(&xc, &ff);
                }
                if let Some(out) = pin_out.as_deref_mut() {
                    // The force vector is `F w`; `|w|` (the gap field's gradient) departs
                    // from 1 by up to a few per cent where the band-averaged field meets a
                    // steep wear scar.
                    out[d * self.zp + j] = PinForce {
                        normal: fnorm * w.norm(),
                        penetration: pen,
                    };
                }
            }
        }
    }

    /// Total mechanical energy (J): kinetic energy of all bodies plus the elastic energy of
    /// the mesh, bearing and contact springs. Conserved when damping, friction, load and drive
    /// torque are zero (torque drive).
    pub fn energy(&self, t: f64, z: &[f64]) -> f64 {
        let p = self.p;
        let lay = self.layout;
        let n = lay.dofs();
        let mut k = Kinematics::default();
        self.absolute(t, z, &mut k);
        let (q, qd) = (&k.q[..n], &k.qd[..n]);
        let mut e = 0.0;
        for ((m, v), _) in self.mass.iter().zip(qd).zip(0..n) {
            e += 0.5 * m * v * v;
        }
        e += p.reducer.structural_energy(&k.q0[..n], &k.dq[..n]);
        let ct = &p.contact;
        for d in 0..2 {
            let id = lay.disc(d);
            let c = Vec2::new(q[id], q[id + 1]);
            let ang = q[id + 2] + self.chi[d];
            let phi = c.y.atan2(c.x);
            let base = -phi + self.zc * (ang + phi / self.zc);
            for j in 0..self.zp {
                let ql = rotate(&(self.pins[j] - c), -ang);
                let tg = base - 2.0 * PI * j as f64 * self.zc / self.zp as f64;
                let ge = self.gaps[d].eval(&ql, tg).0;
                if ge.gap < 0.0 {
                    e += ct.law.potential(&p.reducer.contact, -ge.gap, ge.curvature);
                }
            }
        }
        e
    }

    /// Transmission error `theta_o - theta_s / i_H` (rad, paper eq 21) of state `y`.
    pub fn transmission_error(&self, z: &[f64]) -> f64 {
        z[Layout::OUT]
    }

    /// Input and output angles (rad) and speeds (rad/s) of state `z` at time `t`.
    pub fn shafts(&self, t: f64, z: &[f64]) -> [f64; 4] {
        let n = self.layout.dofs();
        let (th_s, w_s, _) =
            self.input_motion(t)
                .unwrap_or((z[Layout::SUN], z[n + Layout::SUN], 0.0));
        [
            th_s,
            th_s / self.p.reducer.ratio + z[Layout::OUT],
            w_s,
            w_s / self.p.reducer.ratio + z[n + Layout::OUT],
        ]
    }
}

impl LoadProfile {
    /// Torque on the output carrier (N m) at time `t`: positive counter-clockwise, the sense of
    /// positive output rotation (it presses the flank `0 < mesh angle < pi` and gives a positive
    /// TE). A load resisting a reducer driven forward is negative.
    pub fn torque(&self, t: f64) -> f64 {
        match self {
            LoadProfile::None => 0.0,
            LoadProfile::Constant { torque, ramp } => {
                if *ramp > 0.0 {
                    torque * step(t, 0.0, 0.0, *ramp, 1.0)
                } else {
                    *torque
                }
            }
            LoadProfile::Sinusoidal {
                amplitude,
                period,
                offset,
                phase,
            } => offset + amplitude * (2.0 * PI * t / period + phase).sin(),
            LoadProfile::Table { time, torque } => {
                let i = time.partition_point(|&x| x <= t);
                if i == 0 {
                    torque[0]
                } else if i == time.len() {
                    torque[time.len() - 1]
                } else {
                    let u = (t - time[i - 1]) / (time[i] - time[i - 1]);
                    torque[i - 1] + u * (torque[i] - torque[i - 1])
                }
            }
        }
    }
}

impl Drive {
    /// Motor torque on the input (N m) at time `t` (zero for a speed drive).
    pub fn torque(&self, t: f64) -> f64 {
        match self {
            Drive::Speed { .. } => 0.0,
            Drive::Torque { torque, ramp, .. } => {
                if *ramp > 0.0 {
                    torque * step(t, 0.0, 0.0, *ramp, 1.0)
                } else {
                    *torque
                }
            }
        }
    }
}

impl super::ode::OdeSystem for System<'_> {
    fn states(&self) -> usize {
        System::states(self)
    }

    fn initial(&self) -> Vec<f64> {
        self.initial_state()
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        System::rhs(self, t, y, dy, None);
    }

    /// Lengths to `1e-4 rtol` m, angles to that over the pin circle radius, speeds to those
    /// times 1e4 1/s (the order of the contact frequencies); the input angle and speed, which
    /// only carry the rigid-body motion, to `1e-2 rtol` rad and `rtol` rad/s.
    fn absolute_tolerances(&self, rtol: f64) -> Vec<f64> {
        let n = self.layout.dofs();
        let len = 1e-4 * rtol;
        let ang = len / self.p.reducer.geometry.pin_circle_radius;
        let mut a = vec![0.0; 2 * n];
        for k in 0..self.p.reducer.cranks {
            let i = self.layout.crank(k);
            a[i..i + 3].copy_from_slice(&[len, len, ang]);
        }
        for d in 0..2 {
            let i = self.layout.disc(d);
            a[i..i + 3].copy_from_slice(&[len, len, ang]);
        }
        a[Layout::OUT] = ang;
        for i in 0..n {
            a[n + i] = a[i] * 1e4;
        }
        a[Layout::SUN] = 1e-2 * rtol;
        a[n + Layout::SUN] = rtol;
        a
    }
}
