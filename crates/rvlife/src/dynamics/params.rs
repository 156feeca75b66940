//! `[dynamics]` configuration (engineering units) and the checked SI parameters of the
//! multibody model.
//!
//! Defaults: the paper's section 4.2 set-up (input ramped by `STEP(time, 0, 0, 0.1, 9000 deg/s)`,
//! sinusoidal output load of 412 N m amplitude and 0.3 s period, TE over 0.1-0.8 s), material
//! densities of the paper's Table 2, the gear data of its Table 1 (planet pitch radius 27 mm,
//! pressure angle 30 degrees), and stiffnesses of typical RV-40E-class components (stated with
//! each key).

use crate::contact::gap::GapField;
use crate::contact::ContactModel;
use crate::geometry::{Profile, Vec2};
use crate::reducer::Reducer;
pub use crate::reducer::{Bearings, Mesh};

/// Input drive (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drive {
    /// Prescribed speed `speed STEP(t, t0, 0, t1, 1)`, rad/s.
    Speed {
        /// Final speed, rad/s.
        speed: f64,
        /// Ramp start, s.
        t0: f64,
        /// Ramp end, s.
        t1: f64,
    },
    /// Motor torque `torque STEP(t, 0, 0, ramp, 1)` on a free input shaft.
    Torque {
        /// Torque, N m.
        torque: f64,
        /// Ramp time, s (0: a step).
        ramp: f64,
        /// Initial input speed, rad/s (the whole reducer spins rigidly).
        initial_speed: f64,
    },
}

/// Torque on the output carrier (SI; positive counter-clockwise, in the sense of positive output
/// rotation: it presses the flank `0 < mesh angle < pi` and makes the TE positive; a load that
/// resists a reducer driven forward is negative).
#[derive(Debug, Clone, PartialEq)]
pub enum LoadProfile {
    /// No load.
    None,
    /// `torque STEP(t, 0, 0, ramp, 1)`, N m.
    Constant {
        /// Torque, N m.
        torque: f64,
        /// Ramp time, s (0: applied at once).
        ramp: f64,
    },
    /// `offset + amplitude sin(2 pi t / period + phase)`, N m.
    Sinusoidal {
        /// Amplitude, N m.
        amplitude: f64,
        /// Period, s.
        period: f64,
        /// Mean, N m.
        offset: f64,
        /// Phase, rad.
        phase: f64,
    },
    /// Linear interpolation in a time table (s, N m), strictly increasing times.
    Table {
        /// Times, s.
        time: Vec<f64>,
        /// Torques, N m.
        torque: Vec<f64>,
    },
}

/// Body inertias (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertias {
    /// Input shaft + sun, kg m^2.
    pub input: f64,
    /// Carrier + output shaft + load, kg m^2.
    pub output: f64,
    /// Crankshaft + planet mass, kg.
    pub crank_mass: f64,
    /// Crankshaft + planet inertia, kg m^2.
    pub crank: f64,
    /// Disc mass, kg.
    pub disc_mass: f64,
    /// Disc inertia about its centre, kg m^2.
    pub disc: f64,
}

/// The elastic part of the disc-pin contact force in the dynamics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ImpactLaw {
    /// The stage's line-contact law itself ([`ContactModel::force`]) with the flank curvature of
    /// each contact point (from the gap table): the same law as the static analysis, at every
    /// mesh angle. The default.
    Hertz,
    /// MSC Adams IMPACT's `F = k d^e` with one stiffness `k` (N/m^e) and exponent `e` for every
    /// contact (given by the user).
    Power {
        /// `k`, N/m^e.
        stiffness: f64,
        /// `e`.
        exponent: f64,
    },
}

impl ImpactLaw {
    /// Elastic force (N) at penetration `pen` (m) on a flank of curvature `curvature` (1/m);
    /// `warm` is the last force of this contact (N, a warm start of the Hertz law's inversion).
    /// NaN where the Hertz law leaves its range (the simulation then stops with an error).
    #[inline]
    pub fn force(&self, contact: &ContactModel, pen: f64, curvature: f64, warm: f64) -> f64 {
        self.force_with(&contact.prepared(), pen, curvature, warm)
    }

    /// [`ImpactLaw::force`] with the contact's law already prepared (`law`:
    /// [`ContactModel::prepared`] of the contact).
    #[inline]
    pub(crate) fn force_with(
        &self,
        law: &crate::contact::PreparedLaw,
        pen: f64,
        curvature: f64,
        warm: f64,
    ) -> f64 {
        match *self {
            ImpactLaw::Hertz => law
                .force_from(pen, curvature, warm)
                .map_or(f64::NAN, |(f, _)| f),
            ImpactLaw::Power {
                stiffness,
                exponent,
            } => stiffness * pen.powf(exponent),
        }
    }

    /// Elastic energy (J) at penetration `pen` (m): the integral of [`ImpactLaw::force`] (at
    /// fixed curvature).
    #[cfg(test)]
    pub(crate) fn potential(&self, contact: &ContactModel, pen: f64, curvature: f64) -> f64 {
        match *self {
            ImpactLaw::Hertz => contact.potential(pen, curvature).unwrap_or(f64::NAN),
            ImpactLaw::Power {
                stiffness,
                exponent,
            } => stiffness * pen.powf(exponent + 1.0) / (exponent + 1.0),
        }
    }

    /// Linearised stiffness `dF/dd` (N/m) at force `force` (N) on a flank of curvature
    /// `curvature`.
    pub(crate) fn stiffness_at(&self, contact: &ContactModel, force: f64, curvature: f64) -> f64 {
        match *self {
            ImpactLaw::Hertz => {
                let d = contact.approach(force, curvature);
                contact.force(d, curvature).map_or(f64::NAN, |(_, k)| k)
            }
            ImpactLaw::Power {
                stiffness,
                exponent,
            } => {
                let d = (force / stiffness).powf(1.0 / exponent);
                exponent * force / d
            }
        }
    }
}

/// Impact contact (SI): MSC Adams IMPACT semantics, `F = F_e(d) + STEP(d, 0, 0, d_max, c_max)
/// dd/dt` with `d` the penetration (the damping resists its growth), clamped at zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Elastic part.
    pub law: ImpactLaw,
    /// `c_max`, N s/m.
    pub max_damping: f64,
    /// `d_max`, m.
    pub penetration: f64,
    /// Coulomb coefficient.
    pub friction: f64,
    /// Smoothing speed, m/s.
    pub friction_velocity: f64,
}

/// The damping of the reducer's meshes and crank bearings in the multibody model, N s/m: what
/// the dynamics add to the model's reducer (one reducer for every analysis; the static ones
/// are undamped).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damping {
    /// Each sun-planet mesh, along its line of action.
    pub mesh: f64,
    /// Each crank-carrier bearing.
    pub carrier: f64,
    /// Each crank-disc bearing.
    pub disc: f64,
}

impl Damping {
    /// `reducer` with this damping in its meshes and bearings.
    pub fn on(&self, reducer: &Reducer) -> Reducer {
        let mut red = reducer.clone();
        red.mesh.damping = self.mesh;
        red.bearings.carrier.damping = self.carrier;
        red.bearings.disc.damping = self.disc;
        red
    }
}

/// Checked SI parameters of one dynamic simulation of a reducer (the model's,
/// [`crate::config::Model::reducer`], which every simulation is given).
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicsParams {
    /// The damping of the reducer's meshes and bearings.
    pub damping: Damping,
    /// Disc-pin impact contact.
    pub contact: Impact,
    /// Inertias.
    pub inertia: Inertias,
    /// Drive.
    pub drive: Drive,
    /// Load: output torque on the carrier.
    pub load: LoadProfile,
    /// Simulated time, s.
    pub end_time: f64,
    /// TE statistics window, s.
    pub window: (f64, f64),
    /// Sampling interval, s.
    pub output_interval: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// Time integrator.
    pub integrator: Method,
    /// Gap-table resolution per tooth.
    pub gap_points: usize,
    /// Reference pin force (Li's largest force at the rated torque), N.
    pub reference_force: f64,
    /// Flexible discs: the modal reduction of the FE disc (`None`: rigid discs).
    pub flexible: Option<crate::fem::modal::ModalSettings>,
}

impl DynamicsParams {
    /// The gap field of `profile` for these parameters: `gap_points` mesh angles per tooth,
    /// averaged over the Hertz band of the reducer's contact ([`GapField::new`]).
    ///
    /// # Errors
    /// As [`GapField::new`].
    pub(crate) fn gap_field(
        &self,
        profile: &Profile,
        reducer: &Reducer,
    ) -> crate::error::Result<GapField> {
        GapField::new(profile, self.gap_points, Some(reducer.contact_band()))
    }
}

/// Time integrator of the multibody model ([`super::ode`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Explicit Tsitouras 5(4) ([`super::ode::Tsit45`]).
    Tsit45,
    /// Implicit ESDIRK 3(4) ([`super::ode::Esdirk34`]).
    Esdirk34,
}

/// Mass (kg) and polar inertia about the centre (kg m^2) of the disc: the profile polygon
/// (shoelace formulas) minus the crank bores, times density and width.
pub(crate) fn disc_inertia(
    profile: &Profile,
    bores: usize,
    bore_r: f64,
    bore_circle: f64,
    rho: f64,
) -> (f64, f64) {
    let pts: Vec<Vec2> = profile.sample(64);
    let (mut area, mut ip) = (0.0, 0.0);
    for i in 0..pts.len() {
        let (p, q) = (pts[i], pts[(i + 1) % pts.len()]);
        let cr = p.x * q.y - q.x * p.y;
        area += 0.5 * cr;
        ip += cr * (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y) / 12.0;
    }
    let (area, ip) = (area.abs(), ip.abs());
    let hole = std::f64::consts::PI * bore_r * bore_r;
    let b = profile.geometry().width;
    let a_net = area - bores as f64 * hole;
    let ip_net =
        ip - bores as f64 * (0.5 * hole * bore_r * bore_r + hole * bore_circle * bore_circle);
    (rho * b * a_net, rho * b * ip_net)
}
