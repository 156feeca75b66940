//! Unit conversions at the edges: every computation is in SI (m, rad, N, N m, Pa, s); inputs
//! and outputs carry engineering units in their names (`pin_radius_mm`, `te_arcmin`) and are
//! converted with these factors only where they enter or leave.

/// Arcminutes per radian, `180 * 60 / pi` (output angles: `te_arcmin = te_rad * ARCMIN_PER_RAD`).
pub const ARCMIN_PER_RAD: f64 = 180.0 * 60.0 / std::f64::consts::PI;
