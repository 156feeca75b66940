//! Estimates of the reducer's parts where the config leaves them out (**estimates** for the
//! RV-E class, scaled with the stage; docs/model.md section 5): the rollers of a crank
//! bearing, the journals they run on, the carrier's seats. The config's validation
//! ([`crate::config`]) checks the ranges of what the user wrote and takes these for what they
//! did not.

use super::structure::{carrier_seat_stiffness, CrankBeam};
use crate::geometry::CycloidGeometry;

/// Fill of a roller set's pitch circle by its rollers, `Z D / (pi d_m)`, for the default roller
/// diameter: 0.75, a caged set (**estimate**; a full complement fills about 0.95, Harris and
/// Kotzalas, vol. 1, ch. 2).
pub(crate) const ROLLER_FILL: f64 = 0.75;

/// Diameter `D` (m) of `count` rollers round a journal of diameter `journal` (m) filling
/// [`ROLLER_FILL`] of their pitch circle `d_m = journal + D`: `D = f pi journal / (Z - f pi)`
/// (**estimate**).
pub(crate) fn roller_diameter_estimate(count: usize, journal: f64) -> f64 {
    let f = ROLLER_FILL * std::f64::consts::PI;
    f * journal / (count as f64 - f)
}

/// Journal diameters (m) of the crank-carrier and crank-disc roller sets: the crank's diameter
/// (`reducer.structure.crank_diameter_mm`) and the eccentric's, that plus twice the
/// eccentricity (the eccentric carries the crank's section off its axis; **estimates**). A
/// stage without cranks (single-stage) takes its eccentric journal as a fifth of the pin
/// circle radius.
pub(crate) fn journal_estimates(
    geometry: &CycloidGeometry,
    crank: Option<&CrankBeam>,
) -> (f64, f64) {
    let crank = match crank {
        Some(c) => c.diameter,
        None => 0.2 * geometry.pin_circle_radius,
    };
    (crank, crank + 2.0 * geometry.eccentricity)
}

/// The carrier's pillars at the crank seats (**estimates**, RV-E class, scaled with the
/// stage): round bars filling the discs' pillar holes (22 mm diameter scaled,
/// [`CycloidGeometry::scaled_from_root`]) less twice the eccentricity and 0.5 mm of running
/// clearance, as long as 2.5 disc widths (two discs and their spacers between the plates):
/// the seat stiffness of [`carrier_seat_stiffness`], N/m. The plates themselves, the output
/// flange's bolts and the main bearings (which carry no load under a pure torque) are taken
/// as rigid. `None` where the pillars would be under 1 mm thick (an eccentricity too large for
/// the scaled holes).
pub(crate) fn carrier_seat_estimate(geometry: &CycloidGeometry) -> Option<f64> {
    let d = (geometry.scaled_from_root(22.0) - 0.5) * 1e-3 - 2.0 * geometry.eccentricity;
    (d >= 1e-3).then(|| carrier_seat_stiffness(d, 2.5 * geometry.width))
}
