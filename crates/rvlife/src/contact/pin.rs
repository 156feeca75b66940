//! One pin measured against the actual profile at a disc pose: closest point, gap, lever arm,
//! normal and curvature (docs/model.md section 4).

use crate::error::Result;
use crate::geometry::{cross, rotate, CycloidGeometry, Profile, Vec2};

/// Geometry of one pin against the actual profile at one disc pose.
#[derive(Debug, Clone, Copy)]
pub struct PinGeometry {
    /// Pin index `j`.
    pub pin: usize,
    /// Profile parameter of the closest profile point, rad.
    pub t: f64,
    /// Gap between pin and flank along the normal, m (negative: penetration).
    pub gap: f64,
    /// Lever arm `l = (p_c x n)_z` about the disc centre, m.
    pub lever_arm: f64,
    /// Contact point in the disc frame, m.
    pub point: Vec2,
    /// Outward unit normal of the flank at the contact point (disc frame).
    pub normal: Vec2,
    /// Flank curvature at the contact point for the contact law, 1/m (negative: concave): that
    /// of the modified profile (`Profile::macro_curvature`).
    pub curvature: f64,
}

/// Disc pose for crank angle `phi` and extra rotation `beta` (rad): the disc centre
/// `a (cos phi, sin phi)` (m, pin-ring frame) and the disc rotation `psi = -phi/Zc + beta` (rad)
/// (docs/model.md section 1).
pub(crate) fn disc_pose(geo: &CycloidGeometry, phi: f64, beta: f64) -> (Vec2, f64) {
    let zc = geo.disc_teeth() as f64;
    let centre = Vec2::new(geo.eccentricity * phi.cos(), geo.eccentricity * phi.sin());
    (centre, -phi / zc + beta)
}

/// Pose of a disc in the pin-ring frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DiscPose {
    /// Crank angle `phi` whose kinematics the pose is near (rad): it gives the kinematic guess
    /// of every contact parameter (`Profile::contact_parameter_guess`).
    pub crank_angle: f64,
    /// Disc centre, m.
    pub centre: Vec2,
    /// Angle of the profile frame, rad (counter-clockwise).
    pub angle: f64,
}

impl DiscPose {
    /// The pose of crank angle `phi` turned by `beta` beyond nominal (`disc_pose`).
    pub fn at(geo: &CycloidGeometry, phi: f64, beta: f64) -> Self {
        let (centre, angle) = disc_pose(geo, phi, beta);
        DiscPose {
            crank_angle: phi,
            centre,
            angle,
        }
    }

    /// Centre of pin `j` in the profile frame, m.
    pub(crate) fn pin_in_disc(&self, geo: &CycloidGeometry, j: usize) -> Vec2 {
        rotate(&(geo.pin_centre(j) - self.centre), -self.angle)
    }
}

/// Measures pin `j` against the actual profile at disc pose `pose`: the global closest point
/// within the search window ([`Profile::project`]), or, with `hint = Some(t)` (the contact
/// parameter found at a nearby pose, rad), a warm-started local search that falls back to the
/// global one when the foot leaves its bracket.
///
/// # Errors
/// [`Error::Numerical`] if the projection fails.
pub(crate) fn pin_at_pose(
    profile: &Profile,
    j: usize,
    pose: &DiscPose,
    hint: Option<f64>,
) -> Result<PinGeometry> {
    let geo = profile.geometry();
    let q = pose.pin_in_disc(geo, j);
    let proj = match hint.and_then(|t| profile.project_near(&q, t)) {
        Some(p) => p,
        None => {
            let t0 = profile.contact_parameter_guess(j, pose.crank_angle, pose.angle);
            profile.project(&q, t0)?
        }
    };
    Ok(pin_geometry_of(profile, j, proj))
}

fn pin_geometry_of(profile: &Profile, j: usize, proj: crate::geometry::Projection) -> PinGeometry {
    let pt = proj.point;
    PinGeometry {
        pin: j,
        t: pt.t,
        gap: proj.distance - profile.geometry().pin_radius,
        lever_arm: cross(&pt.p, &pt.normal),
        point: pt.p,
        normal: pt.normal,
        curvature: profile.macro_curvature(pt.t),
    }
}

/// Measures pin `j` against the actual profile for crank angle `phi` (rad, direction of the
/// eccentric in the pin-ring frame) and extra disc rotation `beta` (rad), the disc centre on the
/// eccentric: [`pin_at_pose`] with the global search.
///
/// # Errors
/// [`Error::Numerical`] if the projection fails.
pub(crate) fn pin_geometry(
    profile: &Profile,
    j: usize,
    phi: f64,
    beta: f64,
) -> Result<PinGeometry> {
    pin_at_pose(
        profile,
        j,
        &DiscPose::at(profile.geometry(), phi, beta),
        None,
    )
}

/// Geometry of every pin at one pose (see [`pin_geometry`]), in pin order.
#[cfg(test)]
pub(crate) fn pin_geometries(profile: &Profile, phi: f64, beta: f64) -> Result<Vec<PinGeometry>> {
    (0..profile.geometry().pins)
        .map(|j| pin_geometry(profile, j, phi, beta))
        .collect()
}
