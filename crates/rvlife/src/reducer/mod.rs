//! The mechanical model of the RV reducer, and its two analyses.
//!
//! One model ([`Reducer`]): the input shaft with the sun, 2 or 3 crankshafts with their planets
//! on crank-carrier bearings, the output carrier, two cycloid discs on the cranks' eccentrics
//! (crank-disc bearings), 180 degrees apart, the sun-planet meshes, and the disc-pin contacts
//! with the line-contact law of [`crate::contact::ContactModel`] on gaps measured from the
//! actual (modified, worn) profile. docs/model.md sections 1, 5 and 8.
//!
//! - `statics`: static equilibrium of the model under an output torque with the input locked
//!   (the catalogue measuring set-up): loaded TE, load sharing between pins and between the two
//!   discs, disc translations on their bearings, hysteresis curves. It serves `contact`, `te`,
//!   `hysteresis` and the wear integration.
//! - `dynamics`: the same bodies, bearings, meshes and contact law in time, with inertia,
//!   damping, a drive and a load history: the dynamic TE.
//!
//! Coordinates (fixed pin-ring frame, SI), laid out by [`Layout`]: the input (sun) angle
//! `theta_s`, the output carrier angle `theta_o`, crank `k`'s centre `X_k` and absolute angle
//! `vartheta_k`, disc `d`'s centre `c_d` and angle `psi_d`. The nominal (rigid) kinematics of
//! input angle `theta_s` are [`Reducer::nominal`]; both analyses work with deviations from it.
//!
//! `support = Rigid` is the paper's and Li Lixing's assumption: one disc with its centre on the
//! eccentric (no bearing compliance) carrying a fixed share of the output torque; the first-stage
//! kinematics still apply (turning the carrier with the input locked turns the cranks too).

mod bearing;
mod bearing_eval;
mod bearing_table;
pub mod errors;
pub(crate) mod estimates;
mod pin_wear;
mod play;
pub mod structure;

pub use bearing::{BearingLaw, RadialBearing, DEAD_BAND_STIFFNESS, TAKE_UP_WIDTH};
pub(crate) use bearing_eval::{BearingEval, Frozen};
#[cfg(test)]
pub(crate) use bearing_table::BearingTable;
pub use pin_wear::{angle_on_pin, contact_direction, PinWear, PIN_MAP_POINTS};
pub(crate) use play::{Element, ElementLaw, MeshElement};

use std::f64::consts::PI;

use nalgebra::UnitComplex;

use crate::contact::ContactModel;
use crate::geometry::{cross, rotate, rotate_by, CycloidGeometry, Vec2};
use errors::at;

/// `J v`: `v` turned by +90 degrees.
#[inline]
pub(crate) fn perp(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// How the discs are held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Support {
    /// Both discs on their crank-disc bearings, the cranks on their crank-carrier bearings and
    /// the sun-planet meshes: the discs translate and turn under load, and the torque share of
    /// each disc comes out of the equilibrium (docs/model.md section 5). The default.
    Bearings,
    /// The paper's and Li's model: one disc, its centre fixed on the eccentric, carrying
    /// `load_share` of the output torque (paper eqs 8-9: 0.55).
    Rigid {
        /// Share of the output torque on the disc, (0, 1].
        load_share: f64,
    },
}

/// Sun-planet mesh (SI): a spring and damper along the line of action with backlash
/// (lumped-parameter planetary model of Lin and Parker, J. Vib. Acoust. 121, 1999).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mesh {
    /// Pressure angle, rad.
    pub pressure_angle: f64,
    /// Sun pitch radius, m.
    pub sun_pitch_radius: f64,
    /// Planet pitch radius, m.
    pub planet_pitch_radius: f64,
    /// Face width of sun and planets, m.
    pub face_width: f64,
    /// Sun base radius, m.
    pub sun_base_radius: f64,
    /// Planet base radius, m.
    pub planet_base_radius: f64,
    /// `Z1 / Z2`.
    pub sun_planet_ratio: f64,
    /// Stiffness along the line of action, N/m: the mesh's with the parts in series with it
    /// (the crank's and the input shaft's torsion, [`structure::SeriesCompliances`]).
    pub stiffness: f64,
    /// Damping, N s/m (dynamics only).
    pub damping: f64,
    /// Total backlash along the line of action, m.
    pub backlash: f64,
}

/// The crank bearings ([`RadialBearing`]: rollers or linear springs, with clearance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bearings {
    /// One crank's crank-carrier bearings (a tapered roller pair: two rows), between the
    /// crank's centre and its seat in the carrier.
    pub carrier: RadialBearing,
    /// One crank-disc (eccentric needle) bearing, between an eccentric's centre and its bore
    /// in the disc; in a single-stage drive the eccentric bearing of each disc.
    pub disc: RadialBearing,
}

/// Indices of the generalised coordinates.
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    /// Number of cranks (planets; 0 for a single-stage drive).
    pub cranks: usize,
    /// Number of discs.
    pub discs: usize,
}

impl Layout {
    /// Input (sun) angle.
    pub(crate) const SUN: usize = 0;
    /// Output (carrier) angle.
    pub const OUT: usize = 1;
    /// First coordinate of crank `k` (`x`, `y`, angle).
    pub fn crank(&self, k: usize) -> usize {
        2 + 3 * k
    }
    /// First coordinate of disc `d` (`x`, `y`, angle).
    pub fn disc(&self, d: usize) -> usize {
        2 + 3 * self.cranks + 3 * d
    }
    /// Number of generalised coordinates.
    pub(crate) fn dofs(&self) -> usize {
        2 + 3 * self.cranks + 3 * self.discs
    }
}

/// Largest number of generalised coordinates (3 cranks and 2 discs; a single-stage drive
/// with 3 discs has 11).
pub(crate) const MAX_DOFS: usize = 2 + 3 * 3 + 6;

/// What drives the discs and takes their torque out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drive {
    /// RV reducer: a planetary first stage (sun on the input, planets on 2 or 3 crankshafts),
    /// the cranks on the output carrier, two discs on the cranks' eccentrics.
    Rv,
    /// Single-stage cycloid drive: the input shaft is the eccentric (1 to 3 discs on it), the
    /// output flange takes the discs' rotation through pins in holes.
    SingleStage(OutputPins),
}

/// The pins-in-holes output mechanism of a single-stage drive (SI): `count` pins on the
/// output flange at radius `circle_radius`, each in a hole of the disc whose radius exceeds
/// the pin's by the eccentricity plus `hole_clearance`; a pin pushes on its hole's wall
/// (frictionless, unilateral) with `stiffness` per unit of approach, so about half the pins
/// carry the torque (the parallel-crank equivalence of the W mechanism: Blagojevic et al.,
/// Strojniski vestnik 57, 2011; Gorla et al., Proc. IMechE C 222, 2008).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputPins {
    /// Number of output pins (holes per disc).
    pub count: usize,
    /// Radius of their circle, m.
    pub circle_radius: f64,
    /// Radial clearance of a pin in its hole beyond the eccentricity, m.
    pub hole_clearance: f64,
    /// Contact stiffness of one pin on one disc, N/m.
    pub stiffness: f64,
}

/// Coulomb friction of the quasi-static hysteresis curve (docs/model.md section 18.3): the
/// contacts creep at no speed, so no film forms and each slides at its boundary coefficient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuasiStaticFriction {
    /// Friction coefficient of the disc-pin contacts at a standstill (lambda 0).
    pub pin: f64,
    /// Palmgren's load factor `f1` of the crank bearings.
    pub bearing_f1: f64,
    /// How the pins sit in their grooves (`[wear] pin_turning`).
    pub pin_turning: crate::contact::PinTurning,
    /// `[wear] pin_rolling_fraction`.
    pub pin_rolling_fraction: f64,
}

/// The reducer's mechanical model (SI): what the static and the dynamic analysis share.
#[derive(Debug, Clone, PartialEq)]
pub struct Reducer {
    /// Cycloid stage geometry.
    pub geometry: CycloidGeometry,
    /// Overall ratio `i_H = 1 + (Z2/Z1) Zp` (docs/model.md section 1).
    pub ratio: f64,
    /// Number of cranks (= planets), 1 to 12.
    pub cranks: usize,
    /// Crank circle radius (sun-planet centre distance), m.
    pub crank_circle_radius: f64,
    /// Sun-planet mesh.
    pub mesh: Mesh,
    /// Crank bearings.
    pub bearings: Bearings,
    /// Disc-pin line-contact law.
    pub contact: ContactModel,
    /// How the discs are held in the static analysis.
    pub support: Support,
    /// Force (N) whose Hertz half-width sets the band over which the contact geometry is
    /// averaged ([`crate::contact::gap::GapField::new`]): `[contact] band_force_n`, by default Li's
    /// largest pin force at the rated torque.
    pub contact_band_force: f64,
    /// `[contact] band = "envelope"` (default): the contact geometry is the upper envelope of
    /// the flank averaged over a narrow and the wide band ([`crate::contact::gap::Band`]); `false`
    /// (`"single"`): the flank averaged over the band.
    pub contact_envelope: bool,
    /// Mesh angles per tooth of the contact geometry's gap table.
    pub gap_points: usize,
    /// Part errors (pins, pin circle, cranks) seen by the static analysis; zero for the
    /// nominal reducer. The multibody model uses the nominal parts.
    pub errors: errors::PartErrors,
    /// The drive: RV (first stage, cranks) or single-stage (eccentric input shaft, pins in
    /// holes).
    pub drive: Drive,
    /// Eccentric phase of each disc, rad (RV: 0 and pi; single-stage: 1 to 3 discs).
    pub disc_phases: Vec<f64>,
    /// The pins' wear (docs/model.md section 7.11), seen by the static analysis; empty for
    /// unworn pins. The multibody model and the flexible disc use unworn pins.
    pub pin_wear: PinWear,
    /// The parts in series with the crank bearings and the meshes, each on its own: what
    /// [`RadialBearing::series_stiffness`] and [`Mesh::stiffness`] hold summed (the share of
    /// the twist each part takes is found by taking it out).
    pub series: structure::SeriesCompliances,
    /// Coulomb friction of the quasi-static hysteresis curve (docs/model.md section 18.3;
    /// `None`: frictionless, `[lubrication] enabled = false`).
    pub friction: Option<QuasiStaticFriction>,
}

impl Reducer {
    /// Replaces the parts in series ([`Reducer::series`]) by `series`, taking the old parts
    /// out of the sums in the bearings' and the mesh's stiffness and the new ones in
    /// (`1/k' = 1/k - c_old + c_new` on each side; docs/model.md section 5.9).
    pub fn set_series(&mut self, series: structure::SeriesCompliances) {
        let swap = |k: f64, before: f64, after: f64| 1.0 / (1.0 / k - before + after);
        let old = self.series;
        let b = &mut self.bearings;
        b.disc.series_stiffness =
            swap(b.disc.series_stiffness, old.disc_side(), series.disc_side());
        b.carrier.series_stiffness = swap(
            b.carrier.series_stiffness,
            old.carrier_side(),
            series.carrier_side(),
        );
        self.mesh.stiffness = swap(self.mesh.stiffness, old.mesh_side(), series.mesh_side());
        self.series = series;
    }

    /// This reducer without its disc body's compliance in series
    /// ([`structure::SeriesCompliances::disc_body`]): for the analyses that model the disc
    /// body as a finite-element model themselves (its bores' part stays).
    pub fn without_disc_body(&self) -> Reducer {
        let mut r = self.clone();
        r.set_series(structure::SeriesCompliances {
            disc_body: 0.0,
            ..self.series
        });
        r
    }

    /// Whether the meshes and bearings are linear springs (no clearance, backlash, rollers or
    /// parts in series), so that their stiffness matrix is the same at every configuration.
    pub(crate) fn structure_is_linear(&self) -> bool {
        let linear = |b: &RadialBearing| {
            matches!(b.law, BearingLaw::Linear { .. })
                && b.clearance <= 0.0
                && b.series_stiffness.is_infinite()
        };
        self.mesh.backlash <= 0.0 && linear(&self.bearings.carrier) && linear(&self.bearings.disc)
    }

    /// Speed of a crank bearing's inner ring relative to its outer ring per unit input speed
    /// (rad/s per rad/s): RV, the crank relative to the carrier and the discs, `kappa - 1/i_H`
    /// (both crank bearings; section 1.1 of docs/model.md); single-stage, the eccentric
    /// relative to its disc, `1 - 1/i_H` (`i_H = -Zc`).
    pub(crate) fn bearing_speed_ratio(&self) -> f64 {
        match self.drive {
            Drive::Rv => self.kappa() - 1.0 / self.ratio,
            Drive::SingleStage(_) => 1.0 - 1.0 / self.ratio,
        }
    }

    /// The bearing whose radial force is entry `i` of `StaticAnalysis::bearing_forces`: per
    /// crank its crank-carrier pair, then its crank-disc bearing of each disc (a single-stage
    /// drive: each disc's eccentric bearing).
    pub(crate) fn bearing_of_force(&self, i: usize) -> &RadialBearing {
        if self.cranks > 0 && i % (1 + self.discs()) == 0 {
            &self.bearings.carrier
        } else {
            &self.bearings.disc
        }
    }

    /// The largest half play of the bearings and meshes, m: half a bearing's radial clearance,
    /// half the meshes' backlash along the line of action (0: no play).
    pub(crate) fn max_half_play(&self) -> f64 {
        0.5 * self
            .bearings
            .carrier
            .clearance
            .max(self.bearings.disc.clearance)
            .max(if self.cranks > 0 {
                self.mesh.backlash
            } else {
                0.0
            })
    }

    /// How the contact geometry sees the worn flank ([`crate::contact::gap::GapField::new`]).
    pub(crate) fn contact_band(&self) -> crate::contact::gap::Band<'_> {
        crate::contact::gap::Band {
            contact: &self.contact,
            force: self.contact_band_force,
            envelope: self.contact_envelope,
        }
    }

    /// The coordinate layout.
    pub(crate) fn layout(&self) -> Layout {
        Layout {
            cranks: self.cranks,
            discs: self.disc_phases.len(),
        }
    }

    /// Number of discs.
    pub fn discs(&self) -> usize {
        self.disc_phases.len()
    }

    /// Absolute angle of the eccentric (crank angle, rad) at positions `q0 + dq`: crank 1's
    /// angle in an RV reducer, the input angle of a single-stage drive.
    pub(crate) fn eccentric_angle(&self, q0: &[f64], dq: &[f64]) -> f64 {
        match self.drive {
            Drive::Rv => {
                let k = self.layout().crank(0) + 2;
                q0[k] + dq[k]
            }
            Drive::SingleStage(_) => q0[Layout::SUN] + dq[Layout::SUN],
        }
    }

    /// Output twist per unit of disc rotation at a fixed crank angle, `Zc / (Zp + Z1/Z2)`:
    /// with the input locked, turning the carrier by `psi` turns the cranks relative to it by
    /// `(Z1/Z2) psi`, so the disc turns by `psi (Zp + Z1/Z2) / Zc` relative to its position at a
    /// fixed crank (docs/model.md section 6; 0.963 for the paper's reducer).
    pub(crate) fn twist_factor(&self) -> f64 {
        let zp = self.geometry.pins as f64;
        (zp - 1.0) / (zp + self.mesh.sun_planet_ratio)
    }

    /// Mesh cycles per hour of every disc tooth at input speed `speed_rpm` (rpm):
    /// `60 n_in Zp / |i_H|` (docs/model.md section 1: one mesh cycle per crank revolution
    /// relative to the carrier; the paper counts input revolutions instead, see
    /// [`crate::wear`]).
    pub(crate) fn mesh_cycles_per_hour(&self, speed_rpm: f64) -> f64 {
        60.0 * speed_rpm * self.geometry.pins as f64 / self.ratio.abs()
    }

    /// Share of the output torque on one disc for the closed-form estimates (Li's
    /// distribution, the paper's wear model, reference forces): `load_share` with rigid
    /// support, 1/2 with bearings (two discs).
    pub(crate) fn disc_share(&self) -> f64 {
        match self.support {
            Support::Rigid { load_share } => load_share,
            Support::Bearings => 0.5,
        }
    }

    /// Torque (N m) on one disc at a fixed crank angle equivalent to the output torque
    /// `torque` (N m): `share T Zc/(Zp + Z1/Z2)` (docs/model.md section 6: the first stage
    /// turns the cranks when the output twists with the input locked).
    pub(crate) fn equivalent_disc_torque(&self, torque: f64) -> f64 {
        self.disc_share() * torque * self.twist_factor()
    }

    /// Displacement of pin `j`'s centre from its nominal position by the part errors, fixed
    /// frame, m: radial and tangential errors along the pin's own directions plus the pin
    /// circle's offset (docs/model.md section 10).
    pub(crate) fn pin_displacement(&self, j: usize) -> Vec2 {
        let g = std::f64::consts::TAU * j as f64 / self.geometry.pins as f64;
        let (er, et) = (Vec2::new(g.cos(), g.sin()), Vec2::new(-g.sin(), g.cos()));
        let err = &self.errors;
        er * at(&err.pin_radial, j) + et * at(&err.pin_tangential, j) + err.pin_circle_offset
    }

    /// Rigid-body correction of a disc's pose from the crank errors (docs/model.md section 10): translation (m, fixed
    /// frame) and rotation (rad), for the disc's eccentric direction `alpha` (rad, fixed frame)
    /// and the carrier angle `carrier` (rad). Least-squares fit of the bores' displacements
    /// (module documentation). Zero without crank errors.
    pub(crate) fn disc_correction(&self, alpha: f64, carrier: f64) -> (Vec2, f64) {
        let err = &self.errors;
        if !err.has_crank_errors() || self.cranks == 0 {
            return (Vec2::zeros(), 0.0);
        }
        let e = self.geometry.eccentricity;
        let n = self.cranks;
        let v: Vec<Vec2> = (0..n)
            .map(|k| {
                let (de, dp) = (at(&err.crank_eccentricity, k), at(&err.crank_phase, k));
                let a1 = alpha + dp;
                // (e + de) u(alpha + dp) - e u(alpha), without cancellation for small dp.
                let half = 0.5 * dp;
                let chord = Vec2::new(
                    -(alpha + half).sin() * 2.0 * half.sin(),
                    (alpha + half).cos() * 2.0 * half.sin(),
                );
                chord * e + Vec2::new(a1.cos(), a1.sin()) * de
            })
            .collect();
        let mean = v.iter().fold(Vec2::zeros(), |s, x| s + x) / n as f64;
        let bores: Vec<Vec2> = (0..n).map(|k| rotate(&self.seat(k), carrier)).collect();
        let centroid = bores.iter().fold(Vec2::zeros(), |s, b| s + b) / n as f64;
        let (mut num, mut den) = (0.0, 0.0);
        for (b, vk) in bores.iter().zip(&v) {
            let r = b - centroid;
            num += cross(&r, &(vk - mean));
            den += r.norm_squared();
        }
        let rot = if den > 0.0 { num / den } else { 0.0 };
        (mean, rot)
    }

    /// An upper bound (m) of how much the part errors change any pin's gap at any pose, to first
    /// order: the largest pin displacement and radius error, plus the largest disc translation
    /// and the rotation's effect at the pin circle (`|v_k| <= |de_k| + e |dphi_k|`; the fitted
    /// rotation is at most `2 max |v_k| / R_c`), with a factor 1.5 of margin.
    pub(crate) fn error_gap_bound(&self) -> f64 {
        let err = &self.errors;
        let amax = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let pins = (0..self.geometry.pins)
            .map(|j| self.pin_displacement(j).norm())
            .fold(0.0_f64, f64::max);
        let e = self.geometry.eccentricity;
        let v = (0..self.cranks)
            .map(|k| at(&err.crank_eccentricity, k).abs() + e * at(&err.crank_phase, k).abs())
            .fold(0.0_f64, f64::max);
        let rc = self.crank_circle_radius.max(1e-12);
        let rp = self.geometry.pin_circle_radius + self.geometry.pin_radius;
        1.5 * (pins + amax(&err.pin_radius) + v * (1.0 + 2.0 * rp / rc))
    }

    /// Crank angle speed ratio of the locked-input mode: `d vartheta / d theta_o = 1 + Z1/Z2`.
    pub(crate) fn crank_mode_ratio(&self) -> f64 {
        1.0 + self.mesh.sun_planet_ratio
    }

    /// Seat of crank `k` on the carrier at `theta_o = 0` (= its bore centre in the disc frame),
    /// m: on the crank circle at `2 pi k / cranks`.
    pub(crate) fn seat(&self, k: usize) -> Vec2 {
        let al = 2.0 * PI * k as f64 / self.cranks as f64;
        Vec2::new(al.cos(), al.sin()) * self.crank_circle_radius
    }

    /// Line of action of crank `k`'s mesh at `theta_o = 0` (unit vector).
    pub(crate) fn line_of_action(&self, k: usize) -> Vec2 {
        let (sin, cos) = self.mesh.pressure_angle.sin_cos();
        line_of_action(self.seat(k), sin, cos)
    }

    /// Eccentric phase of disc `d`, rad (RV: 0 and pi).
    pub(crate) fn phase(&self, d: usize) -> f64 {
        self.disc_phases[d]
    }

    /// Angle (rad) by which the profile of disc `d` is turned in its own frame,
    /// `-phase / Zc`: a disc whose eccentric leads by `phase` sits that much of a tooth
    /// turned (RV: 0 and `-pi/Zc`, half a tooth).
    pub(crate) fn profile_turn(&self, d: usize) -> f64 {
        -self.phase(d) / self.geometry.disc_teeth() as f64
    }

    /// Input angle (rad) at which disc 1's eccentric points at crank angle `phi` (rad):
    /// `vartheta = kappa theta_s` with `kappa = (1 + Z1/Z2)/i_H - Z1/Z2 = -Zc/i_H`.
    pub(crate) fn input_angle_for_crank(&self, phi: f64) -> f64 {
        phi / self.kappa()
    }

    /// `kappa = d vartheta / d theta_s` of the nominal kinematics.
    pub(crate) fn kappa(&self) -> f64 {
        let r = self.mesh.sun_planet_ratio;
        (1.0 + r) / self.ratio - r
    }

    /// Nominal (kinematic, rigid) positions, speeds and accelerations of every coordinate for
    /// input angle `th_s`, speed `w_s` and acceleration `a_s`: `theta_o = theta_s / i_H`,
    /// crank `vartheta = theta_o - (Z1/Z2)(theta_s - theta_o)`, crank centres on the carrier,
    /// disc centres on the eccentrics, discs turning with the carrier (docs/model.md section 1).
    pub fn nominal(
        &self,
        th_s: f64,
        w_s: f64,
        a_s: f64,
        q: &mut [f64],
        qd: &mut [f64],
        qdd: &mut [f64],
    ) {
        let lay = self.layout();
        let i_h = self.ratio;
        let kappa = self.kappa();
        let (th_o, w_o, a_o) = (th_s / i_h, w_s / i_h, a_s / i_h);
        let (th_k, w_k, a_k) = (kappa * th_s, kappa * w_s, kappa * a_s);
        q[Layout::SUN] = th_s;
        qd[Layout::SUN] = w_s;
        qdd[Layout::SUN] = a_s;
        q[Layout::OUT] = th_o;
        qd[Layout::OUT] = w_o;
        qdd[Layout::OUT] = a_o;
        let mut put = |i: usize, x: Vec2, w: f64, a: f64| {
            let v = perp(x) * w;
            let acc = perp(x) * a - x * (w * w);
            q[i] = x.x;
            q[i + 1] = x.y;
            qd[i] = v.x;
            qd[i + 1] = v.y;
            qdd[i] = acc.x;
            qdd[i + 1] = acc.y;
        };
        for k in 0..self.cranks {
            put(lay.crank(k), rotate(&self.seat(k), th_o), w_o, a_o);
        }
        let e = self.geometry.eccentricity;
        for d in 0..self.discs() {
            let ang = th_k + self.phase(d);
            put(lay.disc(d), Vec2::new(ang.cos(), ang.sin()) * e, w_k, a_k);
        }
        for k in 0..self.cranks {
            let i = lay.crank(k) + 2;
            q[i] = th_k;
            qd[i] = w_k;
            qdd[i] = a_k;
        }
        for d in 0..self.discs() {
            let i = lay.disc(d) + 2;
            q[i] = th_o;
            qd[i] = w_o;
            qdd[i] = a_o;
        }
    }

    /// Generalised forces of the sun-planet meshes and the crank bearings (N or N m per
    /// coordinate), added to `g`, at positions `q0 + dq` (`q0`: a nominal configuration of
    /// [`Reducer::nominal`], `dq`: deviations from it) and speeds `qd` (zero speeds: the static
    /// forces). Every spring deflection is formed from the deviations (rotation differences by
    /// half-angle sines), not as a difference of absolute positions, so it keeps full relative
    /// precision down to the smallest loads. Every force derives from
    /// [`Reducer::structural_energy`] (plus damping).
    pub(crate) fn structural_forces(&self, q0: &[f64], dq: &[f64], qd: &[f64], g: &mut [f64]) {
        self.structural_forces_with(q0, dq, qd, g, &mut BearingEval::Exact);
    }

    /// [`Reducer::structural_forces`] with the bearings evaluated as `eval` says.
    pub(crate) fn structural_forces_with(
        &self,
        q0: &[f64],
        dq: &[f64],
        qd: &[f64],
        g: &mut [f64],
        eval: &mut BearingEval,
    ) {
        let rot = StructureRotations::new(self, q0, dq);
        self.structural_forces_at(&rot, q0, dq, qd, g, eval, None);
    }

    /// [`Reducer::structural_forces_with`] with the rotations at `q0 + dq` already formed
    /// (`rot`, [`StructureRotations::new`] or [`StructureRotations::moved`]), and with
    /// `only = Some(c)` only the terms of the elements whose deflection depends on coordinate
    /// `c` (a mesh on the sun, the output and its crank; a crank-carrier bearing on its
    /// crank's centre and the output; a crank-disc bearing on its crank and disc; a
    /// single-stage drive's eccentric bearing on the input and its disc's centre, its pins in
    /// holes on the output and the disc): what a difference of the forces over `c` sees, at a
    /// fraction of the work. The skipped bearings still take their place in `eval`'s call
    /// order.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn structural_forces_at(
        &self,
        rot: &StructureRotations,
        q0: &[f64],
        dq: &[f64],
        qd: &[f64],
        g: &mut [f64],
        eval: &mut BearingEval,
        only: Option<usize>,
    ) {
        let touches = |set: &[usize]| moved_by(only, set);
        let lay = self.layout();
        let (w_s, w_o) = (qd[Layout::SUN], qd[Layout::OUT]);
        let m = &self.mesh;
        let b = &self.bearings;
        let d_o = dq[Layout::OUT];
        let (carrier, carrier_step) = (rot.carrier, rot.carrier_step);
        let n_discs = rot.n_discs;
        for k in 0..self.cranks {
            let ic = lay.crank(k);
            let dx = Vec2::new(dq[ic], dq[ic + 1]);
            let xd = Vec2::new(qd[ic], qd[ic + 1]);
            let w_k = qd[ic + 2];
            let seat0 = rot.seats[k];
            let seat = carrier * seat0;
            let dseat = perp(seat);
            // Crank centre relative to its seat: the nominal crank sits on its seat.
            let rel = dx - carrier_step.apply(&seat0);
            // Sun-planet mesh: deflection along the line of action in the carrier frame (zero
            // in the nominal kinematics: r_bs (th_s - th_o) + r_bp (th_k - th_o) = 0 there).
            if touches(&[Layout::SUN, Layout::OUT, ic, ic + 1, ic + 2]) {
                let u = carrier * rot.lines[k];
                let delta = m.sun_base_radius * (dq[Layout::SUN] - d_o)
                    + m.planet_base_radius * (dq[ic + 2] - d_o)
                    - u.dot(&rel);
                let d_th_o =
                    -(m.sun_base_radius + m.planet_base_radius) - perp(u).dot(&rel) + u.dot(&dseat);
                let delta_dot = m.sun_base_radius * w_s + m.planet_base_radius * w_k - u.dot(&xd)
                    + d_th_o * w_o;
                let half = 0.5 * m.backlash;
                let f = if half <= 0.0 {
                    m.stiffness * delta + m.damping * delta_dot
                } else {
                    let (fe, _, _) = bearing::take_up(delta.abs() - half, m.stiffness);
                    let fe = fe.copysign(delta);
                    let damped = if fe != 0.0 {
                        let v = fe + m.damping * delta_dot;
                        if v * fe > 0.0 {
                            v
                        } else {
                            0.0
                        }
                    } else {
                        0.0
                    };
                    damped + DEAD_BAND_STIFFNESS * delta
                };
                g[Layout::SUN] -= f * m.sun_base_radius;
                g[ic + 2] -= f * m.planet_base_radius;
                g[Layout::OUT] -= f * d_th_o;
                g[ic] += f * u.x;
                g[ic + 1] += f * u.y;
            }
            // Crank-carrier bearing.
            if touches(&[Layout::OUT, ic, ic + 1]) {
                let rd = xd - dseat * w_o;
                let fb = eval.force(&b.carrier, rel, rd);
                g[ic] -= fb.x;
                g[ic + 1] -= fb.y;
                g[Layout::OUT] += fb.dot(&dseat);
            } else {
                eval.skip();
            }
            // Crank-disc bearings: eccentric centre minus bore centre, zero nominally.
            for (d, (disc, disc_step)) in rot.discs.iter().enumerate().take(n_discs) {
                let id = lay.disc(d);
                if !touches(&[ic, ic + 1, ic + 2, id, id + 1, id + 2]) {
                    eval.skip();
                    continue;
                }
                let (ecc, decc) = rot.eccentrics[k][d];
                let de_dth = perp(ecc);
                let dc = Vec2::new(dq[id], dq[id + 1]);
                let cd = Vec2::new(qd[id], qd[id + 1]);
                let arm = disc * seat0;
                let darm = disc_step.apply(&seat0);
                let r = dx + decc - dc - darm;
                let rdot = xd + de_dth * w_k - cd - perp(arm) * qd[id + 2];
                let fe = eval.force(&b.disc, r, rdot);
                g[ic] -= fe.x;
                g[ic + 1] -= fe.y;
                g[ic + 2] -= fe.dot(&de_dth);
                g[id] += fe.x;
                g[id + 1] += fe.y;
                g[id + 2] += fe.dot(&perp(arm));
            }
        }
        if let Drive::SingleStage(w) = self.drive {
            self.single_stage_forces(&w, q0, dq, qd, g, eval, only);
        }
    }

    /// Generalised forces of a single-stage drive's eccentric bearings (input shaft to each
    /// disc) and pins in holes (each disc to the output flange), added to `g`
    /// ([`Reducer::structural_forces`]; every force derives from
    /// [`Reducer::structural_energy`], plus the bearings' damping); `only` as in
    /// [`Reducer::structural_forces_at`].
    #[allow(clippy::too_many_arguments)]
    fn single_stage_forces(
        &self,
        w: &OutputPins,
        q0: &[f64],
        dq: &[f64],
        qd: &[f64],
        g: &mut [f64],
        eval: &mut BearingEval,
        only: Option<usize>,
    ) {
        let touches = |set: &[usize]| moved_by(only, set);
        let lay = self.layout();
        let a = self.geometry.eccentricity;
        let b = &self.bearings;
        let w_s = qd[Layout::SUN];
        let th_o = q0[Layout::OUT] + dq[Layout::OUT];
        for d in 0..self.discs() {
            let id = lay.disc(d);
            let ang0 = q0[Layout::SUN] + self.phase(d);
            let ecc = Vec2::new(
                (ang0 + dq[Layout::SUN]).cos(),
                (ang0 + dq[Layout::SUN]).sin(),
            ) * a;
            let decc = rotation_difference(&Vec2::new(a, 0.0), ang0, dq[Layout::SUN]);
            let dc = Vec2::new(dq[id], dq[id + 1]);
            let cd = Vec2::new(qd[id], qd[id + 1]);
            // Eccentric bearing: eccentric centre minus disc centre, zero nominally.
            if touches(&[Layout::SUN, id, id + 1]) {
                let r = decc - dc;
                let rdot = perp(ecc) * w_s - cd;
                let fe = eval.force(&b.disc, r, rdot);
                g[Layout::SUN] -= fe.dot(&perp(ecc));
                g[id] += fe.x;
                g[id + 1] += fe.y;
            } else {
                eval.skip();
            }
            // Pins in holes: pin centre minus hole centre, of length `a` nominally.
            if !touches(&[Layout::OUT, id, id + 1, id + 2]) {
                continue;
            }
            let c0 = Vec2::new(q0[id], q0[id + 1]);
            let psi = q0[id + 2] + dq[id + 2];
            // The rotations shared by the disc's pins, each formed once.
            let steps = HoleSteps::new(q0, dq, id);
            let (rot_o, rot_d) = (th_o.sin_cos(), psi.sin_cos());
            for k in 0..w.count {
                let wk = output_pin(w, k);
                let dvec = steps.pin_in_hole(&wk, c0 + dc);
                let len = dvec.norm();
                let pen = len - (a + w.hole_clearance);
                if pen <= 0.0 || len == 0.0 {
                    continue;
                }
                let f = dvec * (bearing::take_up(pen, w.stiffness).0 / len);
                g[Layout::OUT] -= f.dot(&perp(rotate_by(&wk, rot_o)));
                g[id] += f.x;
                g[id + 1] += f.y;
                g[id + 2] += f.dot(&perp(rotate_by(&wk, rot_d)));
            }
        }
    }

    /// Deflection (m) of crank `k`'s sun-planet mesh along its line of action at positions
    /// `q0 + dq` (see [`Reducer::structural_forces`]): `r_bs (d theta_s - d theta_o) + r_bp
    /// (d theta_k - d theta_o) - u . (crank centre - seat)`, zero in the nominal kinematics;
    /// the mesh pushes the crank when it is positive (docs/model.md section 5.1).
    pub(crate) fn mesh_deflection(&self, k: usize, q0: &[f64], dq: &[f64]) -> f64 {
        let ic = self.layout().crank(k);
        let m = &self.mesh;
        let d_o = dq[Layout::OUT];
        let th_o = q0[Layout::OUT] + d_o;
        let dx = Vec2::new(dq[ic], dq[ic + 1]);
        let rel = dx - rotation_difference(&self.seat(k), q0[Layout::OUT], d_o);
        let u = rotate(&self.line_of_action(k), th_o);
        m.sun_base_radius * (dq[Layout::SUN] - d_o) + m.planet_base_radius * (dq[ic + 2] - d_o)
            - u.dot(&rel)
    }

    /// Elastic energy of the meshes and the crank bearings (J) at positions `q0 + dq` (see
    /// [`Reducer::structural_forces`], whose static forces are minus its gradient), summed
    /// over the elements of [`Reducer::elements`].
    pub(crate) fn structural_energy(&self, q0: &[f64], dq: &[f64]) -> f64 {
        let (mut radial, mut meshes) = (Vec::new(), Vec::new());
        self.elements(q0, dq, &mut radial, &mut meshes);
        let stiffness = self.mesh.stiffness;
        let mesh_energy = |m: &MeshElement| {
            let delta = m.deflection;
            if m.half_play > 0.0 {
                bearing::take_up(delta.abs() - m.half_play, stiffness).2
                    + 0.5 * DEAD_BAND_STIFFNESS * delta * delta
            } else {
                0.5 * stiffness * delta * delta
            }
        };
        meshes.iter().map(mesh_energy).sum::<f64>()
            + radial.iter().map(Element::energy).sum::<f64>()
    }
}

/// Most cranks, and most discs, of an RV reducer's layout (`2 + 3 (cranks + discs) <=
/// MAX_DOFS`).
const MAX_BODIES: usize = 3;

/// The rotations of an RV reducer's structure at positions `q0 + dq`
/// ([`Reducer::structural_forces_at`]): the carrier's and each disc's (absolute and as a step
/// from `q0`), each crank's eccentric for each disc (`a (cos, sin)(theta_k + phase)` and its
/// step), and the cranks' seats and mesh lines of action at `theta_o = 0`. Formed once per
/// configuration; a difference over one coordinate re-forms only the rotations that
/// coordinate turns ([`StructureRotations::moved`]), from the same expressions, so the forces
/// are those of [`Reducer::structural_forces_at`] bit for bit.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StructureRotations {
    carrier: UnitComplex<f64>,
    carrier_step: RotationStep,
    /// Discs that the cranks carry (none without cranks: a single-stage drive).
    n_discs: usize,
    discs: [(UnitComplex<f64>, RotationStep); MAX_BODIES],
    /// `[crank][disc]`: the eccentric (m) and its change from `q0` (m).
    eccentrics: [[(Vec2, Vec2); MAX_BODIES]; MAX_BODIES],
    seats: [Vec2; MAX_BODIES],
    lines: [Vec2; MAX_BODIES],
}

impl StructureRotations {
    /// The rotations of `red` at `q0 + dq` (rad; lengths `red.layout().dofs()`).
    pub(crate) fn new(red: &Reducer, q0: &[f64], dq: &[f64]) -> Self {
        let lay = red.layout();
        let cranks = red.cranks.min(MAX_BODIES);
        let n_discs = if red.cranks > 0 {
            red.discs().min(MAX_BODIES)
        } else {
            0
        };
        let (pa_sin, pa_cos) = red.mesh.pressure_angle.sin_cos();
        let mut seats = [Vec2::zeros(); MAX_BODIES];
        let mut lines = [Vec2::zeros(); MAX_BODIES];
        for k in 0..cranks {
            seats[k] = red.seat(k);
            lines[k] = line_of_action(seats[k], pa_sin, pa_cos);
        }
        let mut rot = StructureRotations {
            carrier: UnitComplex::identity(),
            carrier_step: RotationStep::new(0.0, 0.0),
            n_discs,
            discs: [(UnitComplex::identity(), RotationStep::new(0.0, 0.0)); MAX_BODIES],
            eccentrics: [[(Vec2::zeros(), Vec2::zeros()); MAX_BODIES]; MAX_BODIES],
            seats,
            lines,
        };
        rot.turn_carrier(q0, dq);
        for d in 0..n_discs {
            rot.turn_disc(&lay, q0, dq, d);
        }
        for k in 0..cranks {
            rot.turn_crank(red, &lay, q0, dq, k);
        }
        rot
    }

    /// These rotations (formed at `q0 + dq'`) at `q0 + dq` where `dq` differs from `dq'` in
    /// coordinate `c` only: the rotations that `c` turns formed again.
    pub(crate) fn moved(&self, red: &Reducer, q0: &[f64], dq: &[f64], c: usize) -> Self {
        let lay = red.layout();
        let mut rot = *self;
        if c == Layout::OUT {
            rot.turn_carrier(q0, dq);
        }
        for d in 0..rot.n_discs {
            if lay.disc(d) + 2 == c {
                rot.turn_disc(&lay, q0, dq, d);
            }
        }
        for k in 0..red.cranks.min(MAX_BODIES) {
            if lay.crank(k) + 2 == c {
                rot.turn_crank(red, &lay, q0, dq, k);
            }
        }
        rot
    }

    fn turn_carrier(&mut self, q0: &[f64], dq: &[f64]) {
        self.carrier = UnitComplex::new(q0[Layout::OUT] + dq[Layout::OUT]);
        self.carrier_step = RotationStep::new(q0[Layout::OUT], dq[Layout::OUT]);
    }

    fn turn_disc(&mut self, lay: &Layout, q0: &[f64], dq: &[f64], d: usize) {
        let id = lay.disc(d);
        self.discs[d] = (
            UnitComplex::new(q0[id + 2] + dq[id + 2]),
            RotationStep::new(q0[id + 2], dq[id + 2]),
        );
    }

    fn turn_crank(&mut self, red: &Reducer, lay: &Layout, q0: &[f64], dq: &[f64], k: usize) {
        let ic = lay.crank(k);
        let a = red.geometry.eccentricity;
        for d in 0..self.n_discs {
            let ang0 = q0[ic + 2] + red.phase(d);
            let ecc = Vec2::new((ang0 + dq[ic + 2]).cos(), (ang0 + dq[ic + 2]).sin()) * a;
            let decc = rotation_difference(&Vec2::new(a, 0.0), ang0, dq[ic + 2]);
            self.eccentrics[k][d] = (ecc, decc);
        }
    }
}

/// Whether an element whose deflection depends on the coordinates `set` is evaluated when only
/// those moved by coordinate `only` are ([`Reducer::structural_forces_at`]; `None`:
/// every element).
#[inline]
fn moved_by(only: Option<usize>, set: &[usize]) -> bool {
    only.is_none_or(|c| set.contains(&c))
}

/// Output pin `k` of `w` at carrier angle 0 (m).
#[inline]
fn output_pin(w: &OutputPins, k: usize) -> Vec2 {
    let beta = std::f64::consts::TAU * k as f64 / w.count as f64;
    Vec2::new(beta.cos(), beta.sin()) * w.circle_radius
}

/// The output's and one disc's rotation steps at positions `q0 + dq` ([`RotationStep`]),
/// formed once for all of that disc's pins in holes ([`HoleSteps::pin_in_hole`]).
struct HoleSteps {
    out: RotationStep,
    disc: RotationStep,
}

impl HoleSteps {
    #[inline]
    fn new(q0: &[f64], dq: &[f64], id: usize) -> Self {
        HoleSteps {
            out: RotationStep::new(q0[Layout::OUT], dq[Layout::OUT]),
            disc: RotationStep::new(q0[id + 2], dq[id + 2]),
        }
    }

    /// The centre of the pin at `wk` (m, [`output_pin`]) minus its hole's centre (m) for the
    /// disc whose centre is at `centre`: of length `a` in the nominal kinematics (the disc
    /// turns with the output), formed from the deviations so that it keeps full precision.
    #[inline]
    fn pin_in_hole(&self, wk: &Vec2, centre: Vec2) -> Vec2 {
        self.out.apply(wk) - self.disc.apply(wk) - centre
    }
}

/// Line of action (unit vector) of the mesh of the crank seated at `seat` (m, carrier frame at
/// `theta_o = 0`) for the pressure angle of sine `sin` and cosine `cos`.
#[inline]
fn line_of_action(seat: Vec2, sin: f64, cos: f64) -> Vec2 {
    let e = seat / seat.norm();
    e * sin + perp(e) * cos
}

/// `R(a0 + da) v - R(a0) v`, accurate for small `da`: `R(a0) ((cos da - 1) v + sin da J v)`
/// with `cos da - 1 = -2 sin^2(da/2)`.
#[inline]
pub(crate) fn rotation_difference(v: &Vec2, a0: f64, da: f64) -> Vec2 {
    RotationStep::new(a0, da).apply(v)
}

/// The map `v -> R(a0 + da) v - R(a0) v` of [`rotation_difference`] for one pair of angles
/// (rad), its sines formed once for many vectors.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RotationStep {
    /// `cos da - 1 = -2 sin^2(da/2)`.
    cos_minus_one: f64,
    sin: f64,
    at: UnitComplex<f64>,
}

impl RotationStep {
    #[inline]
    pub(crate) fn new(a0: f64, da: f64) -> Self {
        let h = (0.5 * da).sin();
        RotationStep {
            cos_minus_one: -2.0 * h * h,
            sin: da.sin(),
            at: UnitComplex::new(a0),
        }
    }

    #[inline]
    pub(crate) fn apply(&self, v: &Vec2) -> Vec2 {
        self.at * (*v * self.cos_minus_one + perp(*v) * self.sin)
    }
}
