//! Elastohydrodynamic film of a line contact and the lambda ratio (docs/model.md section 18.2).
//!
//! Pan and Hamrock's curve fits of their numerical solutions for a rectangular (line) contact
//! (P. Pan and B. J. Hamrock, "Simple formulas for performance parameters used in
//! elastohydrodynamically lubricated line contacts", J. Tribol. 111, 1989, 246-251; also B. J.
//! Hamrock, S. R. Schmid and B. O. Jacobson, *Fundamentals of Fluid Film Lubrication*, 2nd
//! ed., 2004, section 21.6):
//!
//! ```text
//! h_min / R = 1.714 U^0.694 G^0.568 W'^-0.128
//! h_c   / R = 2.922 U^0.692 G^0.470 W'^-0.166
//! U = eta_0 u / (E' R),  G = alpha E',  W' = w' / (E' R),  E' = 2 E*
//! ```
//!
//! with `u` the entrainment (mean rolling) speed, `R` the reduced radius, `w'` the load per unit
//! length and `E*` the contact modulus `1/((1-nu1^2)/E1 + (1-nu2^2)/E2)`.

/// One line contact's film (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Film {
    /// Central film thickness, m.
    pub central: f64,
    /// Minimum film thickness, m.
    pub minimum: f64,
}

/// Pan and Hamrock's film of a line contact (module docs): entrainment speed `u` (m/s, its
/// magnitude is used; 0 gives no film), reduced radius `radius` (m), load per unit length
/// `load_per_length` (N/m, > 0), contact modulus `contact_modulus` (`E*`, Pa), oil viscosity
/// `viscosity` (Pa s) and pressure-viscosity coefficient `alpha` (1/Pa).
pub fn line_contact_film(
    u: f64,
    radius: f64,
    load_per_length: f64,
    contact_modulus: f64,
    viscosity: f64,
    alpha: f64,
) -> Film {
    let e = 2.0 * contact_modulus;
    let speed = viscosity * u.abs() / (e * radius);
    if speed <= 0.0 || load_per_length <= 0.0 {
        return Film {
            central: 0.0,
            minimum: 0.0,
        };
    }
    let g = alpha * e;
    let w = load_per_length / (e * radius);
    Film {
        central: radius * 2.922 * speed.powf(0.692) * g.powf(0.470) * w.powf(-0.166),
        minimum: radius * 1.714 * speed.powf(0.694) * g.powf(0.568) * w.powf(-0.128),
    }
}

/// The reduced radius `R` (m) and load per unit length `w'` (N/m) of a Hertz line contact from
/// its half-width `b` (m) and peak pressure `p0` (Pa) under the contact modulus `E*`:
/// `b/R = 2 p0/E*` and `w' = pi b p0 / 2` (Johnson, *Contact Mechanics*, 1985, section 4.2).
pub fn hertz_radius_and_load(
    half_width: f64,
    max_pressure: f64,
    contact_modulus: f64,
) -> (f64, f64) {
    (
        half_width * contact_modulus / (2.0 * max_pressure),
        std::f64::consts::PI * half_width * max_pressure / 2.0,
    )
}

/// The composite roughness `sqrt(Rq1^2 + Rq2^2)` (m) of two surfaces of RMS roughness `rq1`
/// and `rq2` (m).
pub fn composite_roughness(rq1: f64, rq2: f64) -> f64 {
    rq1.hypot(rq2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand calculation of Pan and Hamrock's formulas for a steel roller pair.
    #[test]
    fn film_against_a_hand_calculation() {
        // R = 10 mm, w' = 1e5 N/m (1 kN on 10 mm), u = 1 m/s, eta_0 = 0.05 Pa s,
        // alpha = 2e-8 1/Pa, E* = 115.4 GPa (E' = 230.8 GPa).
        // U = 0.05 * 1 / (2.308e11 * 0.01) = 2.1664e-11; G = 4616; W' = 1e5/(2.308e9) = 4.3328e-5.
        // h_min = 0.01 * 1.714 * U^0.694 * G^0.568 * W'^-0.128
        //       = 0.01 * 1.714 * 3.9719e-8 * 120.588 * 3.6182 = 2.9703e-7 m;
        // h_c   = 0.01 * 2.922 * U^0.692 * G^0.470 * W'^-0.166
        //       = 0.01 * 2.922 * 4.1718e-8 * 52.748 * 5.3003 = 3.4081e-7 m.
        // Dowson and Higginson's h_min/R = 2.65 U^0.70 G^0.54 W'^-0.13 gives 3.1929e-7 m: the
        // two fits of the same solutions agree within 7 %.
        let f = line_contact_film(1.0, 0.01, 1e5, 115.4e9, 0.05, 2e-8);
        assert!(
            (f.minimum / 2.9703e-7 - 1.0).abs() < 1e-4,
            "{:e}",
            f.minimum
        );
        assert!(
            (f.central / 3.4081e-7 - 1.0).abs() < 1e-4,
            "{:e}",
            f.central
        );
        assert!(f.minimum < f.central);
        assert!((f.minimum / 3.1929e-7 - 1.0).abs() < 0.08);
        assert_eq!(
            line_contact_film(0.0, 0.01, 1e5, 115.4e9, 0.05, 2e-8).minimum,
            0.0
        );
        // Hertz: b = sqrt(4 w' R/(pi E*)), p0 = 2 w'/(pi b) give back R and w'.
        let (r, w) = (0.01, 1e5);
        let b = (4.0 * w * r / (std::f64::consts::PI * 115.4e9)).sqrt();
        let p0 = 2.0 * w / (std::f64::consts::PI * b);
        let (r2, w2) = hertz_radius_and_load(b, p0, 115.4e9);
        assert!((r2 / r - 1.0).abs() < 1e-12 && (w2 / w - 1.0).abs() < 1e-12);
    }
}
