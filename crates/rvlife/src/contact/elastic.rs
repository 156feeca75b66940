//! Non-Hertzian elastic line contact: the pressure and the approach of a pin pressed with a given
//! force on a flank of *any* shape, from the half-plane's surface displacement (Johnson,
//! *Contact Mechanics*, 1985, eq 2.25b, both bodies as elastic half-planes) and the contact
//! complementarity, solved by an active set on piecewise-constant pressure panels (Kalker's
//! discretisation, *Three-Dimensional Elastic Bodies in Rolling Contact*, 1990, section 5.1).
//!
//! The closed-form laws of [`super::ContactModel`] assume a circular flank over the contact band.
//! On a worn flank whose wear map bends within the band (the edge of a wear scar), this solver
//! tells how far that assumption moves a pin: [`approach_excess`] is the approach on the circle
//! the law assumes minus the approach that carries the same force on the actual flank, the
//! error of the contact geometry in the elastic sense (a rigid comparison of
//! closest points overstates it: features narrower than the band are flattened elastically).
//!
//! Model: initial separation `h(x)` of pin and flank along the flank normal at tangential
//! coordinate `x`; pressure `p(x) >= 0` on panels of width `dx`; separation under load
//! `h(x) - delta + (2 c / pi) sum_j p_j K(x, j)` with `K(x, j) = -int_{panel j} ln|x - s| ds`
//! (the surface displacement relative to a reference at 1 m, where `c = (1 - nu1^2)/E1 +
//! (1 - nu2^2)/E2`); it is zero where `p > 0` and non-negative elsewhere, and
//! `sum_j p_j dx = F / B`. The reference depth only shifts `delta` by `(2 c / pi) ln(d) F / B`,
//! the same for every flank shape at the same force, so differences of approaches at equal force
//! do not depend on it.

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};
use crate::geometry::{Profile, Vec2};

/// Solution of one line contact.
#[derive(Debug, Clone)]
pub struct LineContact {
    /// Approach `delta` (m) that carries the force, relative to the separation `h(x)` given
    /// and to a displacement reference at 1 m depth (see the module docs).
    pub approach: f64,
    /// Pressure on each panel, Pa.
    pub pressure: Vec<f64>,
    /// Half the extent of the loaded panels, m.
    pub half_width: f64,
}

/// `int ln|u| du = u ln|u| - u`.
fn log_primitive(u: f64) -> f64 {
    if u == 0.0 {
        0.0
    } else {
        u * u.abs().ln() - u
    }
}

/// Solves the line contact of a force per unit length `force_per_length` (N/m, > 0) on the
/// initial separation `separation` (m) sampled at the centres of equal panels of width `dx` (m),
/// with the combined compliance `compliance` (`(1-nu1^2)/E1 + (1-nu2^2)/E2`, 1/Pa).
///
/// The active set starts at the panel of smallest separation, drops panels with negative pressure and adds panels whose separation
/// under load is negative, until neither happens (at most `4 n` passes). The contact must stay
/// clear of the ends of the sampled window.
///
/// # Errors
/// [`Error::Numerical`] if the active set does not settle, the loaded zone reaches an end of
/// the window (widen it), or the solution leaves a separation below `-1e-12` m or a residual
/// force above `1e-9` of the load.
pub fn solve(
    separation: &[f64],
    dx: f64,
    force_per_length: f64,
    compliance: f64,
) -> Result<LineContact> {
    let n = separation.len();
    if n < 8 || !(dx > 0.0 && force_per_length > 0.0 && compliance > 0.0) {
        return Err(Error::numerical(
            "line contact",
            format!("needs at least 8 panels and positive widths, force and compliance (n = {n})"),
        ));
    }
    let scale = 2.0 * compliance / std::f64::consts::PI;
    // Influence matrix: displacement at centre i per unit pressure on panel j.
    let infl = DMatrix::from_fn(n, n, |i, j| {
        let u = (j as f64 - i as f64) * dx;
        -scale * (log_primitive(u + 0.5 * dx) - log_primitive(u - 0.5 * dx))
    });
    let hmin = separation.iter().copied().fold(f64::INFINITY, f64::min);
    let mut active: Vec<bool> = separation.iter().map(|&h| h <= hmin + 1e-12).collect();
    let mut pressure = vec![0.0; n];
    for _ in 0..4 * n {
        let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
        let m = idx.len();
        let mut a = DMatrix::zeros(m + 1, m + 1);
        let mut rhs = DVector::zeros(m + 1);
        for (r, &i) in idx.iter().enumerate() {
            for (c, &j) in idx.iter().enumerate() {
                a[(r, c)] = infl[(i, j)];
            }
            a[(r, m)] = -1.0;
            a[(m, r)] = dx;
            rhs[r] = -separation[i];
        }
        rhs[m] = force_per_length;
        let x = a.lu().solve(&rhs).ok_or_else(|| {
            Error::numerical("line contact", "singular active-set system".to_string())
        })?;
        let approach = x[m];
        pressure.iter_mut().for_each(|p| *p = 0.0);
        for (r, &i) in idx.iter().enumerate() {
            pressure[i] = x[r];
        }
        // Drop the panels pulled into tension.
        let negative: Vec<usize> = idx.iter().copied().filter(|&i| pressure[i] < 0.0).collect();
        if !negative.is_empty() {
            for i in negative {
                active[i] = false;
                pressure[i] = 0.0;
            }
            if active.iter().all(|a| !a) {
                return Err(Error::numerical(
                    "line contact",
                    "every panel went into tension".to_string(),
                ));
            }
            continue;
        }
        // Add the panels that the deformed pin penetrates.
        let gap = |i: usize| -> f64 {
            separation[i] - approach + idx.iter().map(|&j| infl[(i, j)] * pressure[j]).sum::<f64>()
        };
        let tol = 1e-12;
        let entering: Vec<usize> = (0..n).filter(|&i| !active[i] && gap(i) < -tol).collect();
        if entering.is_empty() {
            if active[0] || active[n - 1] {
                return Err(Error::numerical(
                    "line contact",
                    "the loaded zone reaches the end of the sampled window".to_string(),
                ));
            }
            let carried: f64 = pressure.iter().sum::<f64>() * dx;
            if (carried / force_per_length - 1.0).abs() > 1e-9 {
                return Err(Error::numerical(
                    "line contact",
                    format!("carried {carried:e} N/m of {force_per_length:e}"),
                ));
            }
            let lo = active.iter().position(|&a| a).unwrap_or(0);
            let hi = active.iter().rposition(|&a| a).unwrap_or(0);
            return Ok(LineContact {
                approach,
                pressure,
                half_width: 0.5 * (hi - lo + 1) as f64 * dx,
            });
        }
        for i in entering {
            active[i] = true;
        }
    }
    Err(Error::numerical(
        "line contact",
        "the active set did not settle".to_string(),
    ))
}

/// Separation between a pin of radius `pin_radius` (m) centred at `q` (disc frame, m) and the
/// actual flank of `profile`, along the flank normal at the pin's closest point (parameter
/// `t_foot`, from [`Profile::project`]), at `panels` equal panel centres over `+-half_length`
/// (m) of the tangent there. Returns the panel width and the separations (m; negative where
/// the undeformed pin overlaps the flank).
///
/// # Errors
/// [`Error::Numerical`] if the flank cannot be followed over the window (it folds, or the
/// window is wider than the pin).
#[cfg(test)]
pub(crate) fn flank_separation(
    profile: &Profile,
    q: &Vec2,
    pin_radius: f64,
    t_foot: f64,
    half_length: f64,
    panels: usize,
) -> Result<(f64, Vec<f64>)> {
    let foot = profile.point(t_foot);
    let n = foot.normal;
    let tau = Vec2::new(n.y, -n.x);
    let rel = q - foot.p;
    let (xc, zc) = (rel.dot(&tau), rel.dot(&n));
    let dx = 2.0 * half_length / panels as f64;
    let fail = |what: String| Error::numerical("flank separation", what);
    let mut t = t_foot;
    let mut out = Vec::with_capacity(panels);
    for k in 0..panels {
        let x = -half_length + (k as f64 + 0.5) * dx;
        let u = x - xc;
        if u.abs() >= pin_radius {
            return Err(fail(format!(
                "window {half_length:e} m reaches past the pin radius"
            )));
        }
        // The flank point whose tangential coordinate is x: Newton in t from the last one.
        let mut found = false;
        for _ in 0..50 {
            let pt = profile.point(t);
            let xt = (pt.p - foot.p).dot(&tau);
            if (xt - x).abs() < 1e-12 {
                found = true;
                break;
            }
            let dxt = pt.dp.dot(&tau);
            if dxt.abs() < 1e-12 {
                break;
            }
            t -= (xt - x) / dxt;
        }
        if !found {
            return Err(fail(format!("flank not followed at x = {x:e} m")));
        }
        let zf = (profile.point(t).p - foot.p).dot(&n);
        let zp = zc - (pin_radius * pin_radius - u * u).sqrt();
        out.push(zp - zf);
    }
    Ok((dx, out))
}

/// Separation (m) between a pin of radius `pin_radius` and a circular flank of curvature
/// `curvature` (1/m, positive convex) at the panel centres of [`flank_separation`], the two
/// surfaces `min_gap` (m) apart at `x = 0`: the geometry the closed-form laws assume.
#[cfg(test)]
pub(crate) fn circle_separation(
    min_gap: f64,
    pin_radius: f64,
    curvature: f64,
    half_length: f64,
    panels: usize,
) -> (f64, Vec<f64>) {
    let dx = 2.0 * half_length / panels as f64;
    // Sagitta of a circle of curvature k over x: k x^2 / (1 + sqrt(1 - k^2 x^2)).
    let sag = |k: f64, x: f64| k * x * x / (1.0 + (1.0 - (k * x).powi(2)).max(0.0).sqrt());
    let h = (0..panels)
        .map(|k| {
            let x = -half_length + (k as f64 + 0.5) * dx;
            min_gap + sag(1.0 / pin_radius, x) + sag(curvature, x)
        })
        .collect();
    (dx, h)
}

/// The approach of the pin centred at `q` (disc frame, m) with force `force` (N) on the actual
/// flank of `profile` (foot parameter `t_foot`) minus its approach on the circular flank the
/// closed-form law assumes (curvature `curvature`, 1/m, surfaces `law_gap` apart at the pin's
/// pose, m), both by [`solve`] with 160 panels over `+-4` Hertz half-widths `half_width` (m),
/// or twice, four times, ... that while the loaded zone reaches the window's ends (up to half
/// the pin radius).
/// Positive: the actual flank needs less approach than the law's geometry, so the pin at its
/// solved pose reaches that much further into the actual flank than the law allows.
///
/// `width` is the contact length `B` (m), `compliance` as in [`solve`].
///
/// # Errors
/// As [`solve`] and [`flank_separation`].
#[allow(clippy::too_many_arguments)]
#[cfg(test)]
pub(crate) fn approach_excess(
    profile: &Profile,
    q: &Vec2,
    pin_radius: f64,
    t_foot: f64,
    force: f64,
    half_width: f64,
    law_gap: f64,
    curvature: f64,
    width: f64,
    compliance: f64,
) -> Result<f64> {
    const PANELS: usize = 160;
    // A conformal worn flank spreads the contact far beyond the Hertz half-width of the law's
    // circle: widen the window until the loaded zone stays inside it.
    let mut half_length = 4.0 * half_width;
    loop {
        let (dx, actual) = flank_separation(profile, q, pin_radius, t_foot, half_length, PANELS)?;
        let (_, circle) = circle_separation(law_gap, pin_radius, curvature, half_length, PANELS);
        let on_actual = solve(&actual, dx, force / width, compliance);
        let on_circle = solve(&circle, dx, force / width, compliance);
        match (on_actual, on_circle) {
            (Ok(a), Ok(c)) => return Ok(c.approach - a.approach),
            (Err(e), _) | (_, Err(e)) => {
                if half_length * 2.0 > 0.5 * pin_radius {
                    return Err(e);
                }
                half_length *= 2.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Hertz line contact (Johnson eq 4.43-4.45 for cylinders): half-width
    /// `b = sqrt(4 P R c / pi)`, peak pressure `2P/(pi b)`; and at equal load the approach on
    /// two radii differs by `-(P c / pi) ln(R2 / R1)` (the flatter contact needs less) whatever
    /// the displacement reference.
    #[test]
    fn reproduces_hertz() {
        let c = 2.0 * (1.0 - 0.09) / 219e9;
        let p = 4000.0 / 8.75e-3;
        let solve_r = |r: f64| {
            let b = (4.0 * p * r * c / PI).sqrt();
            let half = 3.0 * b;
            let n = 300;
            let (dx, h) = circle_separation(0.0, 1e9, 1.0 / r, half, n);
            let s = solve(&h, dx, p, c).unwrap();
            (s, b, dx)
        };
        let (s1, b1, dx) = solve_r(3e-3);
        let peak = s1.pressure.iter().copied().fold(0.0, f64::max);
        assert!(
            (s1.half_width / b1 - 1.0).abs() < dx / b1,
            "{} {b1}",
            s1.half_width
        );
        assert!((peak / (2.0 * p / (PI * b1)) - 1.0).abs() < 5e-3, "{peak}");
        let (s2, _, _) = solve_r(6e-3);
        let expected = -p * c / PI * (2.0_f64).ln();
        let got = s2.approach - s1.approach;
        assert!((got / expected - 1.0).abs() < 1e-3, "{got:e} {expected:e}");
    }
}
