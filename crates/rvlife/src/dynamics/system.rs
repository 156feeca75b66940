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
//! `System::energy` is conserved exactly by the continuous equations:
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
//!   pulls), optional smoothed Coulomb friction `mu F tanh(v_t / v_ref)` (docs/model.md section 8);
//! - the output torque on the carrier (positive counter-clockwise: a load resisting forward
//!   rotation is negative) and the motor torque on the input.

use std::cell::{Cell, RefCell};
use std::f64::consts::{PI, TAU};

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use crate::fem::flex::FlexibleLaw;
use crate::fem::modal::ModalDisc;
use crate::geometry::{cross, rotate, Vec2};

use super::params::{Drive, DynamicsParams, LoadProfile};
use crate::contact::gap::{GapEval, GapField};
pub use crate::reducer::Layout;
pub(crate) use crate::reducer::MAX_DOFS;
use crate::reducer::{perp, BearingEval, Reducer};

/// A disc's pose for its pin contacts: centre `c` (m) and its speed
/// `cd` (m/s), angular speed `wpsi` (rad/s), the base of the pins' contact-parameter guesses
/// (rad), and the sine and cosine of the profile's angle.
struct DiscFrame {
    c: Vec2,
    cd: Vec2,
    wpsi: f64,
    base: f64,
    sa: f64,
    ca: f64,
}

impl DiscFrame {
    /// A pin centre `p` (fixed frame, m) relative to the disc centre, in the fixed frame and in
    /// the disc's profile frame.
    #[inline]
    fn pin(&self, p: Vec2) -> (Vec2, Vec2) {
        let rel = p - self.c;
        let ql = Vec2::new(
            self.ca * rel.x + self.sa * rel.y,
            -self.sa * rel.x + self.ca * rel.y,
        );
        (rel, ql)
    }

    /// A profile-frame vector in the fixed frame.
    #[inline]
    fn to_fixed(&self, v: Vec2) -> Vec2 {
        Vec2::new(self.ca * v.x - self.sa * v.y, self.sa * v.x + self.ca * v.y)
    }
}

/// Gap margin of the open-pin skip, m: a pin is evaluated again once its last gap minus the
/// largest change its move since then can make falls below this.
const SKIP_MARGIN: f64 = 1e-6;

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

/// How [`System::forces`] treats the pin contacts (the costly part of a right-hand side).
enum Contacts {
    /// Computed.
    Compute,
    /// Computed and kept in [`System::kept`].
    Store,
    /// Computed for the discs marked, the others' taken from [`System::kept`].
    Reuse([bool; 2]),
}

/// Pin-contact forces of each disc at the last `Contacts::Store` evaluation.
#[derive(Default)]
struct KeptContacts {
    /// Generalised forces on each disc's `x, y, psi` (N, N, N m).
    disc: [[f64; 3]; 2],
    /// Modal forces of disc 1, then disc 2 (`modes` each; flexible discs).
    modal: Vec<f64>,
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
    /// The model's reducer with the damping of `p` ([`super::Damping::on`]).
    reducer: Reducer,
    gaps: [&'a GapField; 2],
    layout: Layout,
    /// Inverse masses per coordinate.
    inv_mass: Vec<f64>,
    /// Masses per coordinate (for the kinetic energy).
    // Read by the tests only (energy, assembly checks).
    #[cfg_attr(not(test), allow(dead_code))]
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
    /// Gap (m) of every pin at its last evaluation and the pin centre in the disc's profile
    /// frame then (disc-major), to skip pins that cannot have closed since (rigid discs).
    open_cache: RefCell<Vec<(f64, Vec2)>>,
    /// Largest gap gradient `|grad g|` met so far (at least 1).
    max_gradient: Cell<f64>,
    /// The contact's law, prepared ([`crate::contact::ContactModel::prepared`]).
    contact_law: crate::contact::PreparedLaw,
    /// The flexible discs (the modal FE disc, each disc on it by its mount), if any.
    flex: Option<Flexible<'a>>,
    /// The pin contacts of the last Jacobian's base point, reused by its columns.
    kept: RefCell<KeptContacts>,
}

/// The flexible-disc data of a [`System`]: the modal disc, its contact law and the inverse of
/// each disc's rigid mass less the modes' effective mass.
struct Flexible<'a> {
    modal: &'a ModalDisc<'a>,
    law: FlexibleLaw,
    /// Per disc: whole teeth from its contact parameters to the model's.
    shift: [f64; 2],
    /// Per disc: the modes' participation factors in its profile frame (the model's turned
    /// back by the mount's rotation).
    participation: [Vec<[f64; 3]>; 2],
    /// Per disc: `(M_r - L^T L)^-1` in its profile frame (`x, y, rotation`).
    schur_inv: [Matrix3<f64>; 2],
    /// Largest station compliance, m/N (bounds the body deflection at open pins).
    max_compliance: f64,
    /// Largest station amplitude of every mode, m kg^-1/2 (bounds the modal displacement).
    max_amplitude: Vec<f64>,
}

/// One pin that may touch a flexible disc.
struct FlexPin {
    j: usize,
    t: f64,
    gap: f64,
    modal: f64,
    modal_rate: f64,
    rel: Vec2,
    w: Vec2,
    curvature: f64,
    gap_dot: f64,
}

impl<'a> System<'a> {
    /// Assembles the system of the model's reducer `reducer` for `params` (its damping
    /// added) with the gap fields of the two discs.
    pub fn new(p: &'a DynamicsParams, reducer: &Reducer, gaps: [&'a GapField; 2]) -> Self {
        let reducer = p.damping.on(reducer);
        let red = &reducer;
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
            open_cache: RefCell::new(vec![(f64::NAN, Vec2::zeros()); 2 * geo.pins]),
            max_gradient: Cell::new(1.0),
            contact_law: red.contact.prepared(),
            flex: None,
            kept: RefCell::new(KeptContacts::default()),
            reducer,
        }
    }

    /// Assembles the system with flexible discs: both discs are `modal` (the fixed-interface
    /// modes and residual flexibility of the FE disc, [`crate::fem::modal`]) at their own
    /// contact parameters, the contact's local approach from [`FlexibleLaw`] (the Hertz law
    /// with its disc term cut at the load patch, the FE body supplying the rest), as in the
    /// quasi-static flexible analysis (`crate::fem::flex::solve_flexible_bearings`).
    ///
    /// # Errors
    /// [`crate::error::Error::Invalid`] if the disc mass and inertia of `p.inertia` are below
    /// the modes' effective mass (the rigid-body mass of the flexible disc must stay positive
    /// definite).
    pub fn flexible(
        p: &'a DynamicsParams,
        reducer: &Reducer,
        gaps: [&'a GapField; 2],
        discs: super::FlexibleDiscs<'a>,
    ) -> crate::error::Result<Self> {
        let modal = discs.modal;
        let mut sys = System::new(p, reducer, gaps);
        let m = modal.modes();
        let mr = Matrix3::from_diagonal(&Vector3::new(
            p.inertia.disc_mass,
            p.inertia.disc_mass,
            p.inertia.disc,
        ));
        let mut participation: [Vec<[f64; 3]>; 2] = [Vec::new(), Vec::new()];
        let mut schur_inv = [Matrix3::zeros(); 2];
        for d in 0..2 {
            // A model-frame vector v is R(rotation) of the disc-frame one: L . A_model =
            // (R(-rotation) L) . A_disc.
            let rot = discs.mounts[d].rotation;
            participation[d] = modal
                .participation
                .iter()
                .map(|l| {
                    let v = rotate(&Vec2::new(l[0], l[1]), -rot);
                    [v.x, v.y, l[2]]
                })
                .collect();
            let mut ll = Matrix3::zeros();
            for l in &participation[d] {
                let v = Vector3::from(*l);
                ll += v * v.transpose();
            }
            schur_inv[d] = (mr - ll).cholesky().map(|c| c.inverse()).ok_or_else(|| {
                crate::error::Error::invalid(
                    "dynamics.inertia.disc_density_kg_m3",
                    p.inertia.disc_mass,
                    format!(
                        "the disc mass (kg) and inertia must exceed the effective mass of its \
                         {m} elastic modes"
                    ),
                )
            })?;
        }
        let ns = modal.disc.stations();
        let max_compliance = (0..ns)
            .map(|g| modal.disc.compliance[g * ns + g])
            .fold(0.0, f64::max);
        sys.flex = Some(Flexible {
            modal,
            shift: [0, 1].map(|d| TAU * discs.mounts[d].teeth as f64),
            participation,
            law: FlexibleLaw {
                model: sys.reducer.contact,
                patch: modal.disc.params.patch,
            },
            schur_inv,
            max_compliance,
            max_amplitude: (0..m)
                .map(|i| {
                    (0..ns)
                        .map(|g| modal.station_modes[g * m + i].abs())
                        .fold(0.0, f64::max)
                })
                .collect(),
        });
        Ok(sys)
    }

    /// Pins of the ring (the pin forces of `System::rhs` are `2 x pins`, disc-major).
    pub fn pins(&self) -> usize {
        self.zp
    }

    /// Modes per disc (0 for rigid discs).
    pub fn modes(&self) -> usize {
        self.flex.as_ref().map_or(0, |f| f.modal.modes())
    }

    /// The coordinate layout.
    pub(crate) fn layout(&self) -> Layout {
        self.layout
    }

    /// Number of states: `2 x dofs`, then for flexible discs the modal coordinates of disc 1
    /// and 2 (`modes` each), then their rates.
    pub fn states(&self) -> usize {
        2 * self.layout.dofs() + 4 * self.modes()
    }

    /// Prescribed input angle (rad) and speed (rad/s) at time `t` for a speed drive.
    pub(crate) fn input_motion(&self, t: f64) -> Option<(f64, f64, f64)> {
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
    pub(crate) fn initial_state(&self) -> Vec<f64> {
        let n = self.layout.dofs();
        let mut z = vec![0.0; self.states()];
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
        self.reducer.nominal(
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
    pub(crate) fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64], forces: Option<&mut [PinForce]>) {
        self.evaluate(t, z, dz, forces, Contacts::Compute);
    }

    /// The discs whose pin contacts depend on state `j` (see [`System::states`]): a disc's
    /// own position, speed and modal states, and the input's angle and speed (which carry
    /// every body's nominal motion under a torque drive).
    pub(crate) fn column_discs(&self, j: usize) -> [bool; 2] {
        let n = self.layout.dofs();
        let m = self.modes();
        if j >= 2 * n {
            let d = ((j - 2 * n) % (2 * m.max(1))) / m.max(1);
            return [d == 0, d == 1];
        }
        let i = j % n;
        if i == Layout::SUN {
            return [true, true];
        }
        [0, 1].map(|d| {
            let id = self.layout.disc(d);
            (id..id + 3).contains(&i)
        })
    }

    /// The right-hand side as [`System::rhs`], with the pin contacts computed (`Compute`),
    /// computed and kept (`Store`), or recomputed for the marked discs only and taken from the
    /// last `Store` for the others (`Reuse`).
    fn evaluate(
        &self,
        t: f64,
        z: &[f64],
        dz: &mut [f64],
        forces: Option<&mut [PinForce]>,
        contacts: Contacts,
    ) {
        let n = self.layout.dofs();
        let mut k = Kinematics::default();
        let prescribed = self.absolute(t, z, &mut k);
        let (q, qd, mut qdd) = (k.q, k.qd, k.qdd);
        let mut g = [0.0; MAX_DOFS];
        let m = self.modes();
        let mut modal_force = vec![0.0; 2 * m];
        self.forces(t, z, &k, &mut g[..n], &mut modal_force, forces, contacts);
        let a_s = match prescribed {
            Some(a) => a,
            None => {
                // Torque drive: the nominal accelerations again, with the input acceleration
                // that the forces give.
                let a = g[Layout::SUN] * self.inv_mass[Layout::SUN];
                let (mut q2, mut qd2) = ([0.0; MAX_DOFS], [0.0; MAX_DOFS]);
                let (th_s, w_s) = (q[Layout::SUN], qd[Layout::SUN]);
                self.reducer
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
        if let Some(fl) = &self.flex {
            let om = &fl.modal.omega;
            let zeta = fl.modal.damping_ratio;
            let (eta0, rate0) = (2 * n, 2 * n + 2 * m);
            for d in 0..2 {
                let id = self.layout.disc(d);
                let ang = q[id + 2] + self.chi[d];
                // Disc-frame generalised forces on the rigid body.
                let fb = rotate(&Vec2::new(g[id], g[id + 1]), -ang);
                let qb = Vector3::new(fb.x, fb.y, g[id + 2]);
                // Modal forces less the modal stiffness and damping.
                let f_eta: Vec<f64> = (0..m)
                    .map(|i| {
                        let (eta, rate) = (z[eta0 + d * m + i], z[rate0 + d * m + i]);
                        modal_force[d * m + i] - 2.0 * zeta * om[i] * rate - om[i] * om[i] * eta
                    })
                    .collect();
                let mut rhs = qb;
                for (l, f) in fl.participation[d].iter().zip(&f_eta) {
                    rhs -= Vector3::from(*l) * *f;
                }
                let acc = fl.schur_inv[d] * rhs;
                for i in 0..m {
                    let l = Vector3::from(fl.participation[d][i]);
                    dz[eta0 + d * m + i] = z[rate0 + d * m + i];
                    dz[rate0 + d * m + i] = f_eta[i] - l.dot(&acc);
                }
                let a_abs = rotate(&Vec2::new(acc.x, acc.y), ang);
                dz[n + id] = a_abs.x - qdd[id];
                dz[n + id + 1] = a_abs.y - qdd[id + 1];
                dz[n + id + 2] = acc.z - qdd[id + 2];
            }
        }
    }

    /// Generalised forces `Q` (N or N m per coordinate) at the positions and speeds `k`: the
    /// load, drive and structural forces, then each disc's pin contacts (computed on their
    /// own and added, so that a contact kept by `Store` and one recomputed add alike).
    #[allow(clippy::too_many_arguments)]
    fn forces(
        &self,
        t: f64,
        z: &[f64],
        k: &Kinematics,
        g: &mut [f64],
        modal_force: &mut [f64],
        mut pin_out: Option<&mut [PinForce]>,
        contacts: Contacts,
    ) {
        let p = self.p;
        let n = self.layout.dofs();
        let m = self.modes();
        g[Layout::OUT] += p.load.torque(t);
        if let Drive::Torque { .. } = p.drive {
            g[Layout::SUN] += p.drive.torque(t);
        }
        self.reducer.structural_forces_with(
            &k.q0[..n],
            &k.dq[..n],
            &k.qd[..n],
            g,
            &mut BearingEval::Exact,
        );
        let mut kept = match contacts {
            Contacts::Compute => None,
            _ => Some(self.kept.borrow_mut()),
        };
        for d in 0..2 {
            let id = self.layout.disc(d);
            let modal = &mut modal_force[d * m..(d + 1) * m];
            let mut gd = [0.0; 3];
            match (&contacts, kept.as_deref_mut()) {
                (Contacts::Reuse(mark), Some(kept)) if !mark[d] => {
                    gd = kept.disc[d];
                    modal.copy_from_slice(&kept.modal[d * m..(d + 1) * m]);
                }
                _ => {
                    match &self.flex {
                        Some(fl) => self.flexible_contacts(
                            fl,
                            d,
                            z,
                            k,
                            &mut gd,
                            modal,
                            pin_out.as_deref_mut(),
                        ),
                        None => self.rigid_contacts(d, k, &mut gd, pin_out.as_deref_mut()),
                    }
                    if let (Contacts::Store, Some(kept)) = (&contacts, kept.as_deref_mut()) {
                        kept.disc[d] = gd;
                        kept.modal.resize(2 * m, 0.0);
                        kept.modal[d * m..(d + 1) * m].copy_from_slice(modal);
                    }
                }
            }
            for (gi, v) in g[id..id + 3].iter_mut().zip(gd) {
                *gi += v;
            }
        }
    }

    /// Pin contacts of rigid disc `d`: generalised forces on its coordinates (`x, y, psi`)
    /// added to `g`, and each pin's force to `pin_out`.
    fn rigid_contacts(
        &self,
        d: usize,
        k: &Kinematics,
        g: &mut [f64; 3],
        mut pin_out: Option<&mut [PinForce]>,
    ) {
        let p = self.p;
        let n = self.layout.dofs();
        let (q, qd) = (&k.q[..n], &k.qd[..n]);
        let ct = &p.contact;
        let mut cache = self.t_cache.borrow_mut();
        let mut fcache = self.f_cache.borrow_mut();
        let mut open_cache = self.open_cache.borrow_mut();
        let fr = self.disc_frame(d, q, qd);
        let (cd, wpsi) = (fr.cd, fr.wpsi);
        for j in 0..self.zp {
            let (rel, ql) = fr.pin(self.pins[j]);
            // A pin whose last gap exceeds what its move since then can close stays open:
            // the gap changes by at most |grad g| |dq| (with twice the steepest gradient
            // met, and 1 um to spare).
            let open = &mut open_cache[d * self.zp + j];
            if open.0 > SKIP_MARGIN
                && open.0 > SKIP_MARGIN + 2.0 * self.max_gradient.get() * (ql - open.1).norm()
            {
                fcache[d * self.zp + j] = 0.0;
                continue;
            }
            let (ge, _) = self.pin_gap(&fr, d, j, &ql, &mut cache[d * self.zp + j]);
            *open = (ge.gap, ql);
            let gn = ge.grad.norm();
            if gn > self.max_gradient.get() {
                self.max_gradient.set(gn);
            }
            if ge.gap >= 0.0 {
                fcache[d * self.zp + j] = 0.0;
                continue;
            }
            let w = fr.to_fixed(ge.grad);
            let pen = -ge.gap;
            // d(gap)/dt = w . (-c' - psi' J (p - c)).
            let gap_dot = -w.dot(&(cd + perp(rel) * wpsi));
            let f_cached = &mut fcache[d * self.zp + j];
            let elastic = ct
                .law
                .force_with(&self.contact_law, pen, ge.curvature, *f_cached);
            *f_cached = elastic;
            let fnorm =
                (elastic - step(pen, 0.0, 0.0, ct.penetration, ct.max_damping) * gap_dot).max(0.0);
            self.apply_pin_force(g, fnorm, rel, w, cd, wpsi);
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

    /// The pose of disc `d` at the coordinates `q` and speeds `qd` (deviations included).
    #[inline]
    fn disc_frame(&self, d: usize, q: &[f64], qd: &[f64]) -> DiscFrame {
        let id = self.layout.disc(d);
        let c = Vec2::new(q[id], q[id + 1]);
        let ang = q[id + 2] + self.chi[d];
        // Kinematic crank angle of this disc and the contact-parameter guess of pin j:
        // t_j = -phi - 2 pi j Zc / Zp + Zc (psi + phi / Zc) (geometry::contact_parameter_guess).
        let phi = c.y.atan2(c.x);
        let (sa, ca) = ang.sin_cos();
        DiscFrame {
            c,
            cd: Vec2::new(qd[id], qd[id + 1]),
            wpsi: qd[id + 2],
            base: -phi + self.zc * (ang + phi / self.zc),
            sa,
            ca,
        }
    }

    /// Gap of pin `j` (disc-frame centre `ql`) against disc `d` and its contact parameter, the
    /// search started from the kinematic guess plus the offset in `slot` (when below 0.3 rad),
    /// which it updates.
    #[inline]
    fn pin_gap(
        &self,
        fr: &DiscFrame,
        d: usize,
        j: usize,
        ql: &Vec2,
        slot: &mut f64,
    ) -> (GapEval, f64) {
        let tg = fr.base - 2.0 * PI * j as f64 * self.zc / self.zp as f64;
        let start = if slot.abs() < 0.3 { tg + *slot } else { tg };
        let (ge, t_found) = self.gaps[d].eval(ql, start);
        *slot = t_found - tg;
        (ge, t_found)
    }

    /// Adds the generalised forces of a pin force `fnorm w` (N; `w` the gap's gradient in the
    /// fixed frame, `rel` the pin centre relative to the disc centre, m) to the generalised
    /// forces `g` of its disc (`x, y, psi`; speed `cd`, m/s, and `wpsi`, rad/s), with the
    /// smoothed Coulomb friction of the contact.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn apply_pin_force(
        &self,
        g: &mut [f64; 3],
        fnorm: f64,
        rel: Vec2,
        w: Vec2,
        cd: Vec2,
        wpsi: f64,
    ) {
        let ct = &self.p.contact;
        // Q = F d(gap)/dx: d gap/dc = -w, d gap/dpsi = -(p - c) x w.
        g[0] -= fnorm * w.x;
        g[1] -= fnorm * w.y;
        g[2] -= fnorm * cross(&rel, &w);
        if ct.friction > 0.0 {
            let wn = w / w.norm();
            let tau = perp(wn);
            let xc = rel - wn * self.reducer.geometry.pin_radius;
            let v = cd + perp(xc) * wpsi;
            let vt = v.dot(&tau);
            let ff = tau * (-ct.friction * fnorm * (vt / ct.friction_velocity).tanh());
            g[0] += ff.x;
            g[1] += ff.y;
            g[2] += cross(&xc, &ff);
        }
    }

    /// Pin contacts of flexible disc `d`: the rigid gaps from the gap field, the modal
    /// displacement `sum_i b_i(t_j) eta_i` of the flank under each pin, and the elastic forces
    /// from the contact problem `w_flex(F_j) + g_j + sum_i b_i(t_j) eta_i + sum_k R_jk F_k = 0`
    /// on the loaded pins (`>= 0` gaps on the others; [`crate::fem::modal`]), solved by Newton
    /// on the active set with a ratio test (warm-started from the last forces), to 1e-13 m.
    /// The IMPACT damping is added on the local approach with the rigid and modal gap rates
    /// (the residual flexibility's rate is left out). Adds the rigid-body forces to `g` (`x, y,
    /// psi`) and the modal forces `sum_j b_i(t_j) F_j` to `modal_force` (this disc's `m`). A contact problem that fails to
    /// converge makes the modal forces NaN (the simulation then stops with an error).
    #[allow(clippy::too_many_arguments)]
    fn flexible_contacts(
        &self,
        fl: &Flexible,
        d: usize,
        z: &[f64],
        k: &Kinematics,
        g: &mut [f64; 3],
        modal_force: &mut [f64],
        mut pin_out: Option<&mut [PinForce]>,
    ) {
        let p = self.p;
        let ct = &p.contact;
        let n = self.layout.dofs();
        let m = fl.modal.modes();
        let zp = self.zp;
        let eta = &z[2 * n + d * m..2 * n + (d + 1) * m];
        let rate = &z[2 * n + 2 * m + d * m..2 * n + 2 * m + (d + 1) * m];
        let (q, qd) = (&k.q[..n], &k.qd[..n]);
        let fr = self.disc_frame(d, q, qd);
        let (cd, wpsi) = (fr.cd, fr.wpsi);
        let mut cache = self.t_cache.borrow_mut();
        let mut fcache = self.f_cache.borrow_mut();
        let last_total: f64 = fcache[d * zp..(d + 1) * zp].iter().sum();
        // A pin open by more than the body deflection the forces can cause cannot touch.
        let reach = 5e-6 + 2.0 * fl.max_compliance * last_total;
        let modal_bound: f64 = fl
            .max_amplitude
            .iter()
            .zip(eta)
            .map(|(b, e)| b * e.abs())
            .sum();
        let mut pins: Vec<FlexPin> = Vec::new();
        let mut amps: Vec<f64> = Vec::new();
        let mut b = vec![0.0; m];
        for j in 0..zp {
            let (rel, ql) = fr.pin(self.pins[j]);
            let (ge, t_found) = self.pin_gap(&fr, d, j, &ql, &mut cache[d * zp + j]);
            if ge.gap >= reach + modal_bound {
                fcache[d * zp + j] = 0.0;
                continue;
            }
            fl.modal.amplitudes(t_found + fl.shift[d], &mut b);
            let modal: f64 = b.iter().zip(eta).map(|(b, e)| b * e).sum();
            if ge.gap + modal >= reach {
                fcache[d * zp + j] = 0.0;
                continue;
            }
            let modal_rate: f64 = b.iter().zip(rate).map(|(b, e)| b * e).sum();
            let w = fr.to_fixed(ge.grad);
            pins.push(FlexPin {
                j,
                t: t_found,
                gap: ge.gap,
                modal,
                modal_rate,
                rel,
                w,
                curvature: ge.curvature,
                gap_dot: -w.dot(&(cd + perp(rel) * wpsi)),
            });
            amps.extend_from_slice(&b);
        }
        let nc = pins.len();
        if nc == 0 {
            return;
        }
        let ts: Vec<f64> = pins.iter().map(|p| p.t + fl.shift[d]).collect();
        let r = fl.modal.residual_compliance(&ts, &amps);
        let mut f: Vec<f64> = pins.iter().map(|p| fcache[d * zp + p.j]).collect();
        let free_gap = |a: usize, f: &[f64]| -> f64 {
            pins[a].gap + pins[a].modal + (0..nc).map(|k| r[a * nc + k] * f[k]).sum::<f64>()
        };
        let mut active: Vec<bool> = (0..nc)
            .map(|a| f[a] > 0.0 || free_gap(a, &f) < 0.0)
            .collect();
        let tol = 1e-13;
        let mut converged = false;
        for _ in 0..200 {
            let idx: Vec<usize> = (0..nc).filter(|&a| active[a]).collect();
            let na = idx.len();
            let mut res = DVector::<f64>::zeros(na);
            let mut jac = DMatrix::<f64>::zeros(na, na);
            for (x, &a) in idx.iter().enumerate() {
                let (w, dw) = fl.law.approach(f[a], pins[a].curvature);
                res[x] = w + free_gap(a, &f);
                for (y, &bb) in idx.iter().enumerate() {
                    jac[(x, y)] = r[a * nc + bb];
                }
                jac[(x, x)] += dw;
            }
            if res.iter().all(|v| v.abs() < tol) {
                let worst = (0..nc)
                    .filter(|&a| !active[a])
                    .map(|a| (a, free_gap(a, &f)))
                    .filter(|(_, gp)| *gp < -tol)
                    .min_by(|x, y| x.1.total_cmp(&y.1));
                match worst {
                    Some((a, _)) => {
                        active[a] = true;
                        f[a] = 0.0;
                        continue;
                    }
                    None => {
                        converged = true;
                        break;
                    }
                }
            }
            let Some(delta) = jac.lu().solve(&(-res)) else {
                break;
            };
            let mut alpha = 1.0;
            let mut blocking = None;
            for (x, &a) in idx.iter().enumerate() {
                if f[a] + delta[x] < 0.0 {
                    let al = f[a] / (-delta[x]);
                    if al < alpha {
                        alpha = al;
                        blocking = Some(a);
                    }
                }
            }
            for (x, &a) in idx.iter().enumerate() {
                f[a] = (f[a] + alpha * delta[x]).max(0.0);
            }
            if let Some(a) = blocking {
                active[a] = false;
                f[a] = 0.0;
            }
        }
        if !converged {
            modal_force.iter_mut().for_each(|v| *v = f64::NAN);
            return;
        }
        for (a, pin) in pins.iter().enumerate() {
            fcache[d * zp + pin.j] = f[a];
            if f[a] <= 0.0 {
                continue;
            }
            let pen = fl.law.approach(f[a], pin.curvature).0;
            let gap_dot = pin.gap_dot + pin.modal_rate;
            let fnorm =
                (f[a] - step(pen, 0.0, 0.0, ct.penetration, ct.max_damping) * gap_dot).max(0.0);
            self.apply_pin_force(g, fnorm, pin.rel, pin.w, cd, wpsi);
            for i in 0..m {
                modal_force[i] += amps[a * m + i] * fnorm;
            }
            if let Some(out) = pin_out.as_deref_mut() {
                out[d * zp + pin.j] = PinForce {
                    normal: fnorm * pin.w.norm(),
                    penetration: pen,
                };
            }
        }
    }

    /// Forgets the warm starts of the contact solves (closest-point parameters, last pin
    /// forces), so that a new integration starts as from [`System::new`].
    pub(crate) fn reset_caches(&self) {
        self.t_cache.borrow_mut().fill(f64::NAN);
        self.f_cache.borrow_mut().fill(0.0);
        self.open_cache.borrow_mut().fill((f64::NAN, Vec2::zeros()));
        self.max_gradient.set(1.0);
    }

    /// Total mechanical energy (J): kinetic energy of all bodies plus the elastic energy of
    /// the mesh, bearing and contact springs. Conserved when damping, friction, load and drive
    /// torque are zero (torque drive). Rigid discs only (the modal coordinates of flexible discs
    /// are not counted).
    #[cfg(test)]
    pub(crate) fn energy(&self, t: f64, z: &[f64]) -> f64 {
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
        e += self.reducer.structural_energy(&k.q0[..n], &k.dq[..n]);
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
                    e += ct
                        .law
                        .potential(&self.reducer.contact, -ge.gap, ge.curvature);
                }
            }
        }
        e
    }

    /// Transmission error `theta_o - theta_s / i_H` (rad, paper eq 21) of state `y`.
    pub(crate) fn transmission_error(&self, z: &[f64]) -> f64 {
        z[Layout::OUT]
    }

    /// Input and output angles (rad) and speeds (rad/s) of state `z` at time `t`.
    pub(crate) fn shafts(&self, t: f64, z: &[f64]) -> [f64; 4] {
        let n = self.layout.dofs();
        let (th_s, w_s, _) =
            self.input_motion(t)
                .unwrap_or((z[Layout::SUN], z[n + Layout::SUN], 0.0));
        [
            th_s,
            th_s / self.reducer.ratio + z[Layout::OUT],
            w_s,
            w_s / self.reducer.ratio + z[n + Layout::OUT],
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

    /// Keeps each disc's pin contacts.
    fn rhs_base(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.evaluate(t, y, dy, None, Contacts::Store);
    }

    /// Recomputes the pin contacts of the discs that state `j` moves
    /// (`System::column_discs`) and reuses the others' from the base point: a state of
    /// a crank, the output or the other disc leaves a disc's contacts unchanged.
    fn rhs_column(&self, t: f64, y: &[f64], j: usize, dy: &mut [f64]) {
        self.evaluate(t, y, dy, None, Contacts::Reuse(self.column_discs(j)));
    }

    /// Lengths to `1e-4 rtol` m, angles to that over the pin circle radius, speeds to those
    /// times 1e4 1/s (the order of the contact frequencies); the input angle and speed, which
    /// only carry the rigid-body motion, to `1e-2 rtol` rad and `rtol` rad/s.
    fn absolute_tolerances(&self, rtol: f64) -> Vec<f64> {
        let n = self.layout.dofs();
        let len = 1e-4 * rtol;
        let ang = len / self.reducer.geometry.pin_circle_radius;
        let mut a = vec![0.0; self.states()];
        for k in 0..self.reducer.cranks {
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
        if let Some(fl) = &self.flex {
            // Modal coordinates to the station displacement `len`, their rates to that times
            // the mode's frequency.
            let m = fl.modal.modes();
            for d in 0..2 {
                for i in 0..m {
                    let e = len / fl.max_amplitude[i].max(1e-30);
                    a[2 * n + d * m + i] = e;
                    a[2 * n + 2 * m + d * m + i] = e * fl.modal.omega[i];
                }
            }
        }
        a
    }
}
