//! Lubrication, friction and losses (docs/model.md section 18): the oil's viscosity against
//! temperature ([`oil`]), the elastohydrodynamic film of a line contact and its lambda ratio
//! ([`film`]), the friction and wear coefficients in mixed lubrication ([`Lubrication`]), and
//! the friction of the crank bearings and the sun-planet meshes ([`losses`]). The reducer's
//! power losses and efficiency built from them are [`crate::efficiency`].

pub mod film;
pub mod losses;
pub mod oil;
mod pins;

pub use film::{composite_roughness, line_contact_film, Film};
pub use losses::{palmgren_moment, SpurMesh};
pub use oil::Oil;
pub use pins::{pin_dissipation, pin_friction_forces};

/// How the disc-pin contacts' friction coefficient is found (`[lubrication] friction`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionModel {
    /// One coefficient for every contact, whatever the film.
    Constant(f64),
    /// The load-sharing model of mixed lubrication ([`Lubrication::asperity_share`]): the
    /// boundary coefficient where the asperities carry the load, the film's where the oil
    /// does.
    Lambda {
        /// Boundary friction coefficient `mu_b` (asperity contact).
        boundary: f64,
        /// Friction coefficient of the elastohydrodynamic film `mu_f` (its traction).
        film: f64,
    },
}

/// How the Archard coefficients depend on the film (`[lubrication] wear`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WearFilm {
    /// The coefficients of `[wear]` whatever the film (the wear models of docs/model.md
    /// section 7 as they stand).
    Constant,
    /// `[wear]`'s coefficients are the boundary values, scaled at each contact by the share of
    /// its load the asperities carry ([`Lubrication::asperity_share`]).
    Lambda,
}

/// The heat balance of a reducer in still air (docs/model.md section 18.5): the losses leave
/// through the housing's surface, `P = k A (T - T_amb)` (ISO/TR 14179-2's housing term: free
/// convection and radiation in one coefficient).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeatBalance {
    /// Ambient temperature, deg C.
    pub ambient_c: f64,
    /// Heat transfer coefficient `k` of the housing, W/(m^2 K).
    pub coefficient: f64,
    /// Housing surface `A` that gives off the heat, m^2 (`None`: `0.75 pi D^2`, a cylinder of
    /// the housing's outer diameter `D` and length `D/2` with one free end face).
    pub area: Option<f64>,
}

impl HeatBalance {
    /// The steady temperature (deg C) where the losses `loss(T)` (W at the oil temperature
    /// `T`) leave through the surface `area` (m^2): the fixed point of
    /// `T = T_amb + loss(T)/(k A)`, iterated with half steps to 0.01 K.
    ///
    /// # Errors
    /// [`crate::Error::Numerical`] if it passes 150 deg C (the losses outgrow what the housing
    /// gives off) or takes more than 200 iterations.
    pub fn steady_temperature(&self, area: f64, loss: impl Fn(f64) -> f64) -> crate::Result<f64> {
        let mut t = self.ambient_c;
        for _ in 0..200 {
            let next = self.ambient_c + loss(t) / (self.coefficient * area);
            if next.is_nan() || next > 150.0 {
                return Err(crate::Error::numerical(
                    "heat balance",
                    format!(
                        "the oil passes 150 deg C ({next:.1} deg C at {t:.1} deg C): the losses \
                         outgrow what {area:.4} m^2 at {} W/(m^2 K) give off",
                        self.coefficient
                    ),
                ));
            }
            if (next - t).abs() < 0.01 {
                return Ok(next);
            }
            t += 0.5 * (next - t);
        }
        Err(crate::Error::numerical(
            "heat balance",
            "the oil temperature does not settle in 200 steps",
        ))
    }
}

/// `[lubrication]` checked, SI: the oil, its temperature, the surfaces and the friction
/// models (docs/model.md section 18).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lubrication {
    /// The oil (a grease's base oil).
    pub oil: Oil,
    /// Operating temperature of the oil at the contacts, deg C.
    pub temperature_c: f64,
    /// RMS roughness `Rq` of the disc flanks, m.
    pub disc_roughness: f64,
    /// RMS roughness `Rq` of the pins, m.
    pub pin_roughness: f64,
    /// Arithmetic mean roughness `Ra` of the sun and planet flanks, m.
    pub gear_roughness_ra: f64,
    /// Module of the sun and planets, m (their addendum; the teeth from the pitch radii).
    pub gear_module: f64,
    /// The disc-pin contacts' friction.
    pub friction: FrictionModel,
    /// Whether the wear coefficients follow the film.
    pub wear: WearFilm,
    /// Palmgren's viscous factor `f0` of the crank bearings.
    pub bearing_f0: f64,
    /// Palmgren's load factor `f1` of the crank bearings.
    pub bearing_f1: f64,
    /// The steady oil temperature from the heat balance of the losses (`None`: the oil at
    /// [`Lubrication::temperature_c`]).
    pub heat: Option<HeatBalance>,
    /// Whether the study's analyses use it (`[lubrication] enabled`): friction in the
    /// hysteresis curve and the efficiency at every stage. `rvlife efficiency` reads the
    /// section either way.
    pub enabled: bool,
}

impl Lubrication {
    /// The friction of the quasi-static hysteresis curve: the contacts' coefficient at lambda
    /// 0, the pins held or turning as `[wear]` says (`pin_turning`, `pin_rolling_fraction`).
    pub fn quasi_static(
        &self,
        pin_turning: crate::contact::PinTurning,
        pin_rolling_fraction: f64,
    ) -> crate::reducer::QuasiStaticFriction {
        crate::reducer::QuasiStaticFriction {
            pin: self.friction_coefficient(0.0),
            bearing_f1: self.bearing_f1,
            pin_turning,
            pin_rolling_fraction,
        }
    }

    /// The share of a contact's load carried by the asperities at the lambda ratio `lambda`
    /// (minimum film over composite roughness, `>= 0`): `phi = exp(-B lambda^C)` with `B =
    /// 2.32`, `C = 0.97` (X. Zhou and M. Hoeprich, "Torque of tapered roller bearings", J.
    /// Tribol. 113, 1991, eq. 29, the load-sharing concept of K. L. Johnson, J. A. Greenwood
    /// and S. Y. Poon, Wear 19, 1972; `B`, `C` of the raceway contact in M. Wingertszahn et al.,
    /// Lubricants 11, 2023, 369). 1 at `lambda = 0`, 0.10 at 1, 0.001 at 3.
    pub fn asperity_share(lambda: f64) -> f64 {
        (-2.32 * lambda.max(0.0).powf(0.97)).exp()
    }

    /// The disc-pin contacts' friction coefficient at the lambda ratio `lambda`:
    /// `mu = mu_b phi + mu_f (1 - phi)`, `phi` the [`Lubrication::asperity_share`] (the
    /// asperities' and the film's shares of the traction; Wingertszahn et al. 2023, eq. 36;
    /// the constant model's coefficient whatever `lambda`).
    pub fn friction_coefficient(&self, lambda: f64) -> f64 {
        match self.friction {
            FrictionModel::Constant(mu) => mu,
            FrictionModel::Lambda { boundary, film } => {
                let s = Self::asperity_share(lambda);
                boundary * s + film * (1.0 - s)
            }
        }
    }

    /// The factor on `[wear]`'s Archard coefficients at the lambda ratio `lambda`: the
    /// asperities' share of the load where the wear follows the film
    /// ([`Lubrication::wear_follows_film`]; Archard's law acting on the load the asperities
    /// carry, the film's share wearing nothing), 1 otherwise.
    pub fn wear_factor(&self, lambda: f64) -> f64 {
        if self.wear_follows_film() {
            Self::asperity_share(lambda)
        } else {
            1.0
        }
    }

    /// Whether the wear coefficients follow the film: [`WearFilm::Lambda`] in an enabled
    /// section.
    pub fn wear_follows_film(&self) -> bool {
        self.enabled && self.wear == WearFilm::Lambda
    }

    /// The oil's dynamic viscosity at the operating temperature, Pa s.
    pub fn viscosity(&self) -> f64 {
        self.oil.dynamic_viscosity(self.temperature_c)
    }

    /// The composite RMS roughness of the disc-pin contacts, m.
    pub fn contact_roughness(&self) -> f64 {
        composite_roughness(self.disc_roughness, self.pin_roughness)
    }

    /// The film and lambda ratio of a disc-pin contact of Hertz half-width `half_width` (m)
    /// and peak pressure `max_pressure` (Pa) under the contact modulus `contact_modulus` (Pa),
    /// entrained at `entrainment` (m/s): `(film, lambda)` with `lambda = h_min / sigma`.
    pub fn contact_film(
        &self,
        half_width: f64,
        max_pressure: f64,
        contact_modulus: f64,
        entrainment: f64,
    ) -> (Film, f64) {
        let (radius, load) = film::hertz_radius_and_load(half_width, max_pressure, contact_modulus);
        let f = line_contact_film(
            entrainment,
            radius,
            load,
            contact_modulus,
            self.viscosity(),
            self.oil.pressure_viscosity,
        );
        (f, f.minimum / self.contact_roughness())
    }

    /// This lubrication at another temperature (deg C).
    pub fn at_temperature(&self, temperature_c: f64) -> Lubrication {
        Lubrication {
            temperature_c,
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn asperity_share_is_zhou_and_hoeprich() {
        assert!((Lubrication::asperity_share(0.0) - 1.0).abs() < 1e-15);
        // exp(-2.32) = 0.098274; exp(-2.32 * 3^0.97) = exp(-6.73435) = 0.0011893.
        assert!((Lubrication::asperity_share(1.0) - 0.098274).abs() < 1e-6);
        assert!((Lubrication::asperity_share(3.0) - 0.0011893).abs() < 1e-7);
        let mut last = 1.0;
        for k in 1..=100 {
            let s = Lubrication::asperity_share(0.1 * k as f64);
            assert!(s < last && s > 0.0);
            last = s;
        }
    }
}
