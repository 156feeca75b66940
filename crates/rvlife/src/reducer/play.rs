//! The structure's elements as the no-load contact problem sees them (docs/model.md section
//! 5.10): each crank bearing, each output pin in its hole and each sun-planet mesh as a
//! relative displacement of two bodies and the room it has.
//!
//! Under no load an elastic part carries nothing, so it is undeformed: a bearing's centres stay
//! within half its radial clearance of each other, an output pin within its hole, a mesh
//! within half its backlash of its nominal contact. The same kinematics give the elastic
//! energy of [`Reducer::structural_energy`], so the constraints and the loaded analysis see one
//! structure.

use super::*;

/// The law an [`Element`] carries under load.
#[derive(Debug, Clone, Copy)]
pub(crate) enum ElementLaw<'a> {
    /// A crank bearing (or a single-stage drive's eccentric bearing).
    Bearing(&'a RadialBearing),
    /// An output pin in its disc hole (single-stage): stiffness beyond contact, N/m.
    PinInHole(f64),
}

/// One radial element at a configuration: the relative position `r` (m) of its two centres
/// (zero in the nominal kinematics for a bearing, of length `a` for an output pin in its hole)
/// and the largest length `room` (m) that `r` can reach without loading it (half a bearing's
/// radial clearance; the hole's radius less the pin's, `a` plus the hole's clearance).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Element<'a> {
    pub(crate) r: Vec2,
    pub(crate) room: f64,
    pub(crate) law: ElementLaw<'a>,
}

impl Element<'_> {
    /// Elastic energy (J) of the element at its relative position.
    pub(crate) fn energy(&self) -> f64 {
        match self.law {
            ElementLaw::Bearing(b) => b.energy(self.r),
            ElementLaw::PinInHole(k) => bearing::take_up(self.r.norm() - self.room, k).2,
        }
    }
}

/// A sun-planet mesh at a configuration: its deflection along the line of action (m, zero in
/// the nominal kinematics) and half its backlash (m).
#[derive(Debug, Clone, Copy)]
pub(crate) struct MeshElement {
    pub(crate) deflection: f64,
    pub(crate) half_play: f64,
}

impl Reducer {
    /// Every radial element and every mesh of the structure at positions `q0 + dq` (`q0`: a
    /// nominal configuration of [`Reducer::nominal`], `dq`: deviations from it), appended to
    /// `radial` and `meshes` in a fixed order: for each crank its crank-carrier bearing, then
    /// its crank-disc bearing of each disc; for a single-stage drive, for each disc its
    /// eccentric bearing, then its output pins. Formed from the deviations (rotation
    /// differences) so that every length keeps full relative precision.
    pub(crate) fn elements<'a>(
        &'a self,
        q0: &[f64],
        dq: &[f64],
        radial: &mut Vec<Element<'a>>,
        meshes: &mut Vec<MeshElement>,
    ) {
        let lay = self.layout();
        let d_o = dq[Layout::OUT];
        let a = self.geometry.eccentricity;
        let b = &self.bearings;
        for k in 0..self.cranks {
            let ic = lay.crank(k);
            let dx = Vec2::new(dq[ic], dq[ic + 1]);
            let seat0 = self.seat(k);
            meshes.push(MeshElement {
                deflection: self.mesh_deflection(k, q0, dq),
                half_play: 0.5 * self.mesh.backlash,
            });
            radial.push(Element {
                r: dx - rotation_difference(&seat0, q0[Layout::OUT], d_o),
                room: 0.5 * b.carrier.clearance,
                law: ElementLaw::Bearing(&b.carrier),
            });
            for d in 0..self.discs() {
                let id = lay.disc(d);
                let ang0 = q0[ic + 2] + self.phase(d);
                let decc = rotation_difference(&Vec2::new(a, 0.0), ang0, dq[ic + 2]);
                let dc = Vec2::new(dq[id], dq[id + 1]);
                let darm = rotation_difference(&seat0, q0[id + 2], dq[id + 2]);
                radial.push(Element {
                    r: dx + decc - dc - darm,
                    room: 0.5 * b.disc.clearance,
                    law: ElementLaw::Bearing(&b.disc),
                });
            }
        }
        if let Drive::SingleStage(w) = self.drive {
            for d in 0..self.discs() {
                let id = lay.disc(d);
                let ang0 = q0[Layout::SUN] + self.phase(d);
                let decc = rotation_difference(&Vec2::new(a, 0.0), ang0, dq[Layout::SUN]);
                let dc = Vec2::new(dq[id], dq[id + 1]);
                radial.push(Element {
                    r: decc - dc,
                    room: 0.5 * b.disc.clearance,
                    law: ElementLaw::Bearing(&b.disc),
                });
                let c0 = Vec2::new(q0[id], q0[id + 1]);
                let steps = HoleSteps::new(q0, dq, id);
                for k in 0..w.count {
                    radial.push(Element {
                        r: steps.pin_in_hole(&output_pin(&w, k), c0 + dc),
                        room: a + w.hole_clearance,
                        law: ElementLaw::PinInHole(w.stiffness),
                    });
                }
            }
        }
    }
}
