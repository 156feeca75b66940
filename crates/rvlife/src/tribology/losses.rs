//! Friction of the crank bearings (Palmgren) and of the sun-planet meshes (ISO/TR 14179-2 with
//! Ohlendorf's gear loss factor), docs/model.md sections 18.4 and 18.5.

/// Palmgren's friction moment of a rolling bearing (N m): the load term `M1 = f1 P dm` and the
/// viscous term `M0 = 1e-7 f0 (nu n)^(2/3) dm^3` (N mm, `nu` in mm^2/s, `n` in rpm, `dm` in mm)
/// for `nu n >= 2000`, else `160e-7 f0 dm^3` (A. Palmgren, *Ball and Roller Bearing
/// Engineering*, 3rd ed., 1959; T. A. Harris and M. N. Kotzalas, *Essential Concepts of
/// Bearing Technology*, 5th ed., 2007, section 11.2). `load` the radial load (N),
/// `pitch_diameter` `dm` (m), `speed_rpm` the inner ring's speed relative to the outer
/// (rpm, its magnitude), `viscosity` the oil's kinematic viscosity (m^2/s).
pub fn palmgren_moment(
    load: f64,
    pitch_diameter: f64,
    speed_rpm: f64,
    viscosity: f64,
    f0: f64,
    f1: f64,
) -> f64 {
    let dm_mm = pitch_diameter * 1e3;
    let nu_n = viscosity * 1e6 * speed_rpm.abs();
    let m0_nmm = if nu_n >= 2000.0 {
        1e-7 * f0 * nu_n.powf(2.0 / 3.0) * dm_mm.powi(3)
    } else {
        160e-7 * f0 * dm_mm.powi(3)
    };
    m0_nmm * 1e-3 + f1 * load.abs() * pitch_diameter
}

/// One external spur mesh for [`mesh_loss_fraction`] (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpurMesh {
    /// Pinion (sun) and wheel (planet) pitch radii, m (standard centre distance).
    pub pitch_radii: [f64; 2],
    /// Module, m (addendum = module).
    pub module: f64,
    /// Pressure angle, rad.
    pub pressure_angle: f64,
    /// Face width, m.
    pub face_width: f64,
    /// Arithmetic mean roughness of the flanks `Ra`, m.
    pub roughness_ra: f64,
}

impl SpurMesh {
    /// Ohlendorf's gear loss factor `H_V = pi (u + 1)/(z1 u) (1 - eps_a + eps_1^2 + eps_2^2)`
    /// for a spur mesh (`eps_i` the addendum contact ratios; H. Ohlendorf, *Verlustleistung
    /// und Erwärmung von Stirnrädern*, TU München, 1958; ISO/TR 14179-2:2001, eq. 7).
    pub fn loss_factor(&self) -> f64 {
        let [r1, r2] = self.pitch_radii;
        let (z1, z2) = (2.0 * r1 / self.module, 2.0 * r2 / self.module);
        let u = z2 / z1;
        let a = self.pressure_angle;
        let eps = |r: f64, z: f64| {
            let rb = r * a.cos();
            let ra = r + self.module;
            z / std::f64::consts::TAU * ((ra * ra - rb * rb).sqrt() / rb - a.tan())
        };
        let (e1, e2) = (eps(r1, z1), eps(r2, z2));
        std::f64::consts::PI * (u + 1.0) / (z1 * u) * (1.0 - (e1 + e2) + e1 * e1 + e2 * e2)
    }

    /// ISO/TR 14179-2's mean coefficient of friction of the mesh,
    /// `mu_mZ = 0.048 (F_bt/b / (v_sum rho_red))^0.2 eta^-0.05 Ra^0.25 X_L` (`F_bt/b` in N/mm,
    /// `v_sum = 2 v_t sin alpha` in m/s, `rho_red` the flanks' reduced radius at the pitch
    /// point in mm, `eta` the dynamic viscosity in mPa s, `Ra` in um, `X_L = 1` for mineral oil;
    /// ISO/TR 14179-2:2001, eq. 9), for the base-circle force `force` (N), the pitch-line speed
    /// `pitch_speed` (m/s) and the viscosity `viscosity` (Pa s); bounded to [0.01, 0.2] (the
    /// fit's data: at a standstill it would grow without bound).
    pub fn friction_coefficient(&self, force: f64, pitch_speed: f64, viscosity: f64) -> f64 {
        let a = self.pressure_angle;
        let [r1, r2] = self.pitch_radii;
        let rho = r1 * r2 * a.sin() / (r1 + r2) * 1e3;
        let v_sum = 2.0 * pitch_speed.abs() * a.sin();
        let line_load = force.abs() / (self.face_width * 1e3);
        if v_sum <= 0.0 || line_load <= 0.0 {
            return 0.2;
        }
        let mu = 0.048
            * (line_load / (v_sum * rho)).powf(0.2)
            * (viscosity * 1e3).powf(-0.05)
            * (self.roughness_ra * 1e6).powf(0.25);
        mu.clamp(0.01, 0.2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palmgren_moment_against_a_hand_calculation() {
        // dm = 30 mm, P = 2 kN, n = 1000 rpm, nu = 20 mm^2/s (nu n = 20 000), f0 = 3, f1 = 5e-4:
        // M0 = 1e-7 * 3 * 20000^(2/3) * 27000 N mm = 0.005968 N m (20000^(2/3) = 736.806);
        // M1 = 5e-4 * 2000 * 0.03 = 0.03 N m.
        let m = palmgren_moment(2000.0, 0.03, 1000.0, 20e-6, 3.0, 5e-4);
        assert!(
            (m - (1e-7 * 3.0 * 736.806 * 27000.0 * 1e-3 + 0.03)).abs() < 1e-8,
            "{m}"
        );
        // Below nu n = 2000 the viscous term is constant: 160e-7 * 3 * 27000 N mm.
        let slow = palmgren_moment(0.0, 0.03, 50.0, 20e-6, 3.0, 5e-4);
        assert!((slow - 160e-7 * 3.0 * 27000.0 * 1e-3).abs() < 1e-12);
    }

    #[test]
    fn ohlendorf_loss_factor_of_a_standard_pair() {
        // z1 = 20, z2 = 40, m = 1 mm, 20 deg: eps_1 = 20/(2 pi) (sqrt(11^2 - 9.3969^2)/9.3969
        // - tan 20); by hand: ra1 = 11, rb1 = 9.39693, sqrt(121 - 88.3022) = 5.71820,
        // 5.71820/9.39693 = 0.60852, minus 0.36397 = 0.24455, times 3.18310 = 0.77842;
        // eps_2: ra2 = 21, rb2 = 18.79385, sqrt(441 - 353.2089) = 9.36970, / 18.79385 = 0.49855,
        // minus 0.36397 = 0.13458, times 6.36620 = 0.85677. eps_a = 1.63519.
        // H_V = pi * 3/(20 * 2) * (1 - 1.63519 + 0.60593 + 0.73405) = 0.16606.
        let mesh = SpurMesh {
            pitch_radii: [0.010, 0.020],
            module: 0.001,
            pressure_angle: 20f64.to_radians(),
            face_width: 0.01,
            roughness_ra: 0.4e-6,
        };
        assert!(
            (mesh.loss_factor() - 0.16606).abs() < 1e-5,
            "{}",
            mesh.loss_factor()
        );
        let mu = mesh.friction_coefficient(1000.0, 2.0, 0.05);
        assert!((0.01..=0.2).contains(&mu));
        // Hand: F/b = 100 N/mm, v_sum = 1.36808, rho = 10 * 20 * 0.34202/30 = 2.28013 mm;
        // (100/(1.36808 * 2.28013))^0.2 = 2.00072; 50^-0.05 = 0.82234; 0.4^0.25 = 0.79527:
        // mu = 0.048 * 2.00072 * 0.82234 * 0.79527 = 0.062805.
        assert!((mu - 0.062805).abs() < 2e-6, "{mu}");
    }
}
