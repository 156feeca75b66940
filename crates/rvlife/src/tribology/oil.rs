//! The oil: kinematic viscosity against temperature (ASTM D341's Walther equation through the
//! viscosities at 40 and 100 deg C), density, and the pressure-viscosity coefficient
//! (docs/model.md section 18.1).

/// The kinematic viscosity at 100 deg C (mm^2/s) of a mineral oil of ISO VG grade `grade`
/// (ISO 3448: the grade is the viscosity at 40 deg C, mm^2/s), for a viscosity index of about
/// 95: interpolated on the viscosity-index table of ASTM D2270 (as printed in gear-oil data
/// sheets: VG 32 5.4, VG 46 6.8, VG 68 8.7, VG 100 11.1, VG 150 14.6, VG 220 18.7, VG 320
/// 23.9, VG 460 30.4, VG 680 38.9 mm^2/s), log-log between grades. Estimate: a real oil's data
/// sheet replaces it (`[lubrication] oil_viscosity_100_mm2_per_s`).
pub fn viscosity_100_of_grade(grade: f64) -> f64 {
    const TABLE: [(f64, f64); 9] = [
        (32.0, 5.4),
        (46.0, 6.8),
        (68.0, 8.7),
        (100.0, 11.1),
        (150.0, 14.6),
        (220.0, 18.7),
        (320.0, 23.9),
        (460.0, 30.4),
        (680.0, 38.9),
    ];
    let g = grade.clamp(TABLE[0].0, TABLE[TABLE.len() - 1].0);
    let i = TABLE
        .windows(2)
        .position(|w| g <= w[1].0)
        .unwrap_or(TABLE.len() - 2);
    let ((x0, y0), (x1, y1)) = (TABLE[i], TABLE[i + 1]);
    let t = (g.ln() - x0.ln()) / (x1.ln() - x0.ln());
    (y0.ln() + t * (y1.ln() - y0.ln())).exp()
}

/// A lubricating oil (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oil {
    /// Kinematic viscosity at 40 deg C, m^2/s.
    pub viscosity_40: f64,
    /// Kinematic viscosity at 100 deg C, m^2/s (below `viscosity_40`).
    pub viscosity_100: f64,
    /// Density at 15 deg C, kg/m^3.
    pub density_15: f64,
    /// Pressure-viscosity coefficient `alpha` of Barus' law `eta = eta_0 exp(alpha p)`, 1/Pa.
    pub pressure_viscosity: f64,
}

impl Oil {
    /// Walther's constants `(A, B)` of `log10 log10 (nu + 0.7) = A - B log10 T` (ASTM D341;
    /// `nu` in mm^2/s, `T` in K) through the viscosities at 40 and 100 deg C.
    fn walther(&self) -> (f64, f64) {
        let z = |nu_m2: f64| (nu_m2 * 1e6 + 0.7).log10().log10();
        let (t40, t100) = (313.15_f64.log10(), 373.15_f64.log10());
        let b = (z(self.viscosity_40) - z(self.viscosity_100)) / (t100 - t40);
        (z(self.viscosity_40) + b * t40, b)
    }

    /// Kinematic viscosity at `temperature_c` (deg C), m^2/s (ASTM D341; exact at 40 and 100
    /// deg C, for oils within its range of about 0.2 to 1e6 mm^2/s).
    pub fn kinematic_viscosity(&self, temperature_c: f64) -> f64 {
        let (a, b) = self.walther();
        let z = a - b * (temperature_c + 273.15).log10();
        (10f64.powf(10f64.powf(z)) - 0.7) * 1e-6
    }

    /// Density at `temperature_c` (deg C), kg/m^3: `rho_15 (1 - 6.5e-4 (T - 15))`, the thermal
    /// expansion of mineral oils (ASTM D1250's coefficient for their densities, about 6.5e-4
    /// per K).
    pub fn density(&self, temperature_c: f64) -> f64 {
        self.density_15 * (1.0 - 6.5e-4 * (temperature_c - 15.0))
    }

    /// Dynamic viscosity at atmospheric pressure and `temperature_c` (deg C), Pa s.
    pub fn dynamic_viscosity(&self, temperature_c: f64) -> f64 {
        self.kinematic_viscosity(temperature_c) * self.density(temperature_c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walther_goes_through_both_points_and_falls_with_temperature() {
        let oil = Oil {
            viscosity_40: 68e-6,
            viscosity_100: viscosity_100_of_grade(68.0) * 1e-6,
            density_15: 880.0,
            pressure_viscosity: 2e-8,
        };
        assert!((oil.kinematic_viscosity(40.0) / 68e-6 - 1.0).abs() < 1e-12);
        assert!((oil.kinematic_viscosity(100.0) / 8.7e-6 - 1.0).abs() < 1e-12);
        // Hand calculation of ASTM D341 through 68 and 8.7 mm^2/s: B = (log log 68.7 - log log
        // 9.4)/(log 373.15 - log 313.15) = 3.62440, A = log log 68.7 + B log 313.15 = 9.30969,
        // and at 60 deg C nu = 10^10^(A - B log 333.15) - 0.7 = 28.6587 mm^2/s.
        let (a, b) = oil.walther();
        assert!(
            (a - 9.30969).abs() < 1e-5 && (b - 3.62440).abs() < 1e-5,
            "{a} {b}"
        );
        assert!((oil.kinematic_viscosity(60.0) * 1e6 - 28.6587).abs() < 1e-3);
        let mut last = f64::INFINITY;
        for t in 0..=120 {
            let nu = oil.kinematic_viscosity(t as f64);
            assert!(nu < last && nu > 0.0);
            last = nu;
        }
        assert!((viscosity_100_of_grade(68.0) - 8.7).abs() < 1e-12);
        assert!((viscosity_100_of_grade(320.0) - 23.9).abs() < 1e-12);
    }
}
