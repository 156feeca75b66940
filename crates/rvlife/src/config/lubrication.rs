//! `[lubrication]`: the oil, its temperature, the surfaces and the friction models of the
//! losses and efficiency, and whether the wear follows the oil film (docs/model.md section 18).

use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::error::{Error, Result};
use crate::tribology::{oil, FrictionModel, HeatBalance, Lubrication, Oil, WearFilm};

/// `[lubrication]`. Every default is an **estimate** for the grease-lubricated RV class
/// (docs/model.md section 18.7 gives their sources).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricationConfig {
    /// Whether the study uses the section: Coulomb friction in the hysteresis curve (its two
    /// branches, the catalogue quantities with friction) and the efficiency at every stage.
    /// `false` (default): the frictionless analyses; `rvlife efficiency` reads the section
    /// either way.
    #[serde(default)]
    pub enabled: bool,
    /// ISO 3448 viscosity grade of the oil (of a grease, its base oil): its kinematic
    /// viscosity at 40 deg C, mm^2/s; the viscosity at 100 deg C follows for a mineral oil of
    /// viscosity index about 95 unless given. Range: [2, 3200].
    #[serde(default = "d_grade")]
    pub oil_iso_vg: f64,
    /// Kinematic viscosity at 40 deg C, mm^2/s (default: the grade). Range: [2, 1e5] mm^2/s.
    #[serde(default)]
    pub oil_viscosity_40_mm2_per_s: Option<f64>,
    /// Kinematic viscosity at 100 deg C, mm^2/s (default: a mineral oil's of the grade).
    /// Range: [0.5, 1e4] mm^2/s, below the viscosity at 40 deg C.
    #[serde(default)]
    pub oil_viscosity_100_mm2_per_s: Option<f64>,
    /// Density at 15 deg C, kg/m^3. Range: [600, 1500] kg/m^3.
    #[serde(default = "d_density")]
    pub oil_density_kg_per_m3: f64,
    /// Pressure-viscosity coefficient `alpha` of Barus' law, 1/GPa (mineral oils 15-25,
    /// synthetic hydrocarbons 10-15). Range: [1, 60] 1/GPa.
    #[serde(default = "d_alpha")]
    pub pressure_viscosity_per_gpa: f64,
    /// Operating temperature of the oil, deg C (the catalogue's efficiency charts: the case
    /// at 40 deg C). Range: [-40, 150] deg C.
    #[serde(default = "d_temperature")]
    pub temperature_c: f64,
    /// RMS roughness `Rq` of the disc flanks, um (ground). Range: [0.005, 10] um.
    #[serde(default = "d_disc_rq")]
    pub disc_roughness_um: f64,
    /// RMS roughness `Rq` of the pins, um (ground and superfinished). Range: [0.005, 10] um.
    #[serde(default = "d_pin_rq")]
    pub pin_roughness_um: f64,
    /// Arithmetic mean roughness `Ra` of the sun and planet flanks, um. Range: [0.01, 10] um.
    #[serde(default = "d_gear_ra")]
    pub gear_roughness_ra_um: f64,
    /// Module of the sun and planets, mm (their teeth follow from the pitch radii). Range:
    /// [0.1, 20] mm.
    #[serde(default = "d_module")]
    pub gear_module_mm: f64,
    /// The disc-pin friction: `"lambda"` (default: mixed lubrication, the boundary and the
    /// film's coefficients weighted by the asperities' share of the load at the contact's
    /// lambda ratio) or `"constant"` (`friction_coefficient` everywhere).
    #[serde(default = "d_friction")]
    pub friction: String,
    /// The constant model's friction coefficient. Range: [0, 1].
    #[serde(default = "d_mu")]
    pub friction_coefficient: f64,
    /// Boundary friction coefficient of the disc-pin contacts (`"lambda"`). Range: [0, 1].
    #[serde(default = "d_mu_b")]
    pub boundary_friction_coefficient: f64,
    /// Friction (traction) coefficient of a full elastohydrodynamic film (`"lambda"`). Range:
    /// [0, 1], at most the boundary coefficient.
    #[serde(default = "d_mu_f")]
    pub film_friction_coefficient: f64,
    /// Whether the wear follows the film: `"constant"` (default: `[wear]`'s coefficients as
    /// they are) or `"lambda"` (`[wear]`'s coefficients are boundary values, scaled at each
    /// contact by the asperities' share of its load; disc and pins, `flodin` model).
    #[serde(default = "d_wear")]
    pub wear: String,
    /// Whether the oil's temperature is the steady one of the losses' heat balance (the
    /// efficiency's operating points; `temperature_c` then sets only the wear's film).
    #[serde(default)]
    pub heat_balance: bool,
    /// Ambient temperature of the heat balance, deg C. Range: [-40, 100] deg C.
    #[serde(default = "d_ambient")]
    pub ambient_c: f64,
    /// Heat transfer coefficient of the housing (free convection and radiation in still air),
    /// W/(m^2 K). Range: [1, 1000] W/(m^2 K).
    #[serde(default = "d_k_heat")]
    pub heat_transfer_w_per_m2_k: f64,
    /// Housing surface giving off the heat, m^2 (default `0.75 pi D^2` of the housing's outer
    /// diameter `D`). Range: [1e-4, 100] m^2.
    #[serde(default)]
    pub housing_area_m2: Option<f64>,
    /// Palmgren's viscous factor `f0` of the crank bearings. Range: [0, 100].
    #[serde(default = "d_f0")]
    pub bearing_f0: f64,
    /// Palmgren's load factor `f1` of the crank bearings. Range: [0, 0.01].
    #[serde(default = "d_f1")]
    pub bearing_f1: f64,
}

fn d_grade() -> f64 {
    68.0
}
fn d_density() -> f64 {
    880.0
}
fn d_alpha() -> f64 {
    20.0
}
fn d_temperature() -> f64 {
    40.0
}
fn d_disc_rq() -> f64 {
    0.25
}
fn d_pin_rq() -> f64 {
    0.1
}
fn d_gear_ra() -> f64 {
    0.4
}
fn d_module() -> f64 {
    1.0
}
fn d_friction() -> String {
    "lambda".into()
}
fn d_mu() -> f64 {
    0.05
}
fn d_mu_b() -> f64 {
    0.1
}
fn d_mu_f() -> f64 {
    0.05
}
fn d_wear() -> String {
    "constant".into()
}
fn d_ambient() -> f64 {
    20.0
}
fn d_k_heat() -> f64 {
    15.0
}
fn d_f0() -> f64 {
    6.0
}
fn d_f1() -> f64 {
    0.0005
}

impl Default for LubricationConfig {
    fn default() -> Self {
        LubricationConfig {
            enabled: false,
            oil_iso_vg: d_grade(),
            oil_viscosity_40_mm2_per_s: None,
            oil_viscosity_100_mm2_per_s: None,
            oil_density_kg_per_m3: d_density(),
            pressure_viscosity_per_gpa: d_alpha(),
            temperature_c: d_temperature(),
            disc_roughness_um: d_disc_rq(),
            pin_roughness_um: d_pin_rq(),
            gear_roughness_ra_um: d_gear_ra(),
            gear_module_mm: d_module(),
            friction: d_friction(),
            friction_coefficient: d_mu(),
            boundary_friction_coefficient: d_mu_b(),
            film_friction_coefficient: d_mu_f(),
            wear: d_wear(),
            heat_balance: false,
            ambient_c: d_ambient(),
            heat_transfer_w_per_m2_k: d_k_heat(),
            housing_area_m2: None,
            bearing_f0: d_f0(),
            bearing_f1: d_f1(),
        }
    }
}

impl LubricationConfig {
    /// The lubrication, SI.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key, the value and its range.
    pub fn validate(&self) -> Result<Lubrication> {
        let k = |name: &str| format!("lubrication.{name}");
        let grade = check(
            &k("oil_iso_vg"),
            self.oil_iso_vg,
            Range::closed(2.0, 3200.0, ""),
        )?;
        let nu40 = match self.oil_viscosity_40_mm2_per_s {
            Some(v) => check(
                &k("oil_viscosity_40_mm2_per_s"),
                v,
                Range::closed(2.0, 1e5, "mm^2/s"),
            )?,
            None => grade,
        };
        let nu100 = match self.oil_viscosity_100_mm2_per_s {
            Some(v) => {
                let v = check(
                    &k("oil_viscosity_100_mm2_per_s"),
                    v,
                    Range::closed(0.5, 1e4, "mm^2/s"),
                )?;
                if v >= nu40 {
                    return Err(Error::invalid(
                        k("oil_viscosity_100_mm2_per_s"),
                        v,
                        format!("must be below the viscosity at 40 deg C ({nu40} mm^2/s)"),
                    ));
                }
                v
            }
            None => oil::viscosity_100_of_grade(nu40),
        };
        let oil = Oil {
            viscosity_40: nu40 * 1e-6,
            viscosity_100: nu100 * 1e-6,
            density_15: check(
                &k("oil_density_kg_per_m3"),
                self.oil_density_kg_per_m3,
                Range::closed(600.0, 1500.0, "kg/m^3"),
            )?,
            pressure_viscosity: check(
                &k("pressure_viscosity_per_gpa"),
                self.pressure_viscosity_per_gpa,
                Range::closed(1.0, 60.0, "1/GPa"),
            )? * 1e-9,
        };
        let um = |name: &str, v: f64, lo: f64| -> Result<f64> {
            Ok(check(&k(name), v, Range::closed(lo, 10.0, "um"))? * 1e-6)
        };
        let coefficient = |name: &str, v: f64| check(&k(name), v, Range::closed(0.0, 1.0, ""));
        let friction = match self.friction.as_str() {
            "constant" => FrictionModel::Constant(coefficient(
                "friction_coefficient",
                self.friction_coefficient,
            )?),
            "lambda" => {
                let boundary = coefficient(
                    "boundary_friction_coefficient",
                    self.boundary_friction_coefficient,
                )?;
                let film =
                    coefficient("film_friction_coefficient", self.film_friction_coefficient)?;
                if film > boundary {
                    return Err(Error::invalid(
                        k("film_friction_coefficient"),
                        film,
                        format!(
                            "must be at most lubrication.boundary_friction_coefficient ({boundary})"
                        ),
                    ));
                }
                FrictionModel::Lambda { boundary, film }
            }
            other => {
                return Err(Error::invalid(
                    k("friction"),
                    format!("\"{other}\""),
                    "must be \"lambda\" or \"constant\"",
                ))
            }
        };
        let wear = match self.wear.as_str() {
            "constant" => WearFilm::Constant,
            "lambda" => WearFilm::Lambda,
            other => {
                return Err(Error::invalid(
                    k("wear"),
                    format!("\"{other}\""),
                    "must be \"constant\" or \"lambda\"",
                ))
            }
        };
        let temperature_c = check(
            &k("temperature_c"),
            self.temperature_c,
            Range::closed(-40.0, 150.0, "deg C"),
        )?;
        // The oil must stay liquid and within ASTM D341's range at the temperature.
        let nu = oil.kinematic_viscosity(temperature_c) * 1e6;
        if !(0.2..=1e6).contains(&nu) {
            return Err(Error::invalid(
                k("temperature_c"),
                temperature_c,
                format!("gives the oil {nu:.3e} mm^2/s, outside ASTM D341's 0.2 to 1e6 mm^2/s"),
            ));
        }
        Ok(Lubrication {
            oil,
            temperature_c,
            disc_roughness: um("disc_roughness_um", self.disc_roughness_um, 0.005)?,
            pin_roughness: um("pin_roughness_um", self.pin_roughness_um, 0.005)?,
            gear_roughness_ra: um("gear_roughness_ra_um", self.gear_roughness_ra_um, 0.01)?,
            gear_module: check(
                &k("gear_module_mm"),
                self.gear_module_mm,
                Range::closed(0.1, 20.0, "mm"),
            )? * 1e-3,
            friction,
            wear,
            bearing_f0: check(
                &k("bearing_f0"),
                self.bearing_f0,
                Range::closed(0.0, 100.0, ""),
            )?,
            bearing_f1: check(
                &k("bearing_f1"),
                self.bearing_f1,
                Range::closed(0.0, 0.01, ""),
            )?,
            heat: if self.heat_balance {
                Some(HeatBalance {
                    ambient_c: check(
                        &k("ambient_c"),
                        self.ambient_c,
                        Range::closed(-40.0, 100.0, "deg C"),
                    )?,
                    coefficient: check(
                        &k("heat_transfer_w_per_m2_k"),
                        self.heat_transfer_w_per_m2_k,
                        Range::closed(1.0, 1000.0, "W/(m^2 K)"),
                    )?,
                    area: self
                        .housing_area_m2
                        .map(|a| check(&k("housing_area_m2"), a, Range::closed(1e-4, 100.0, "m^2")))
                        .transpose()?,
                })
            } else {
                None
            },
            enabled: self.enabled,
        })
    }
}
