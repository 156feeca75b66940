//! `[tolerances]`: the distributions of the part errors of a batch of reducers, sampled by
//! `rvlife montecarlo` (docs/model.md section 12), with ISO 286-1 grades.

use rand::Rng;
use rand_distr::{Distribution, Normal, Uniform};
use serde::{Deserialize, Serialize};

use super::range::{check, Range};
use crate::error::{Error, Result};
use crate::geometry::{CycloidGeometry, Modification, Vec2};
use crate::reducer::errors::PartErrors;

/// One tolerance: a distribution of an error about zero.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToleranceConfig {
    /// Normal distribution with this standard deviation (the key's unit). Range: [0, 1000] um
    /// or [0, 600] arcmin.
    #[serde(default)]
    pub normal: Option<f64>,
    /// Uniform distribution within `+-` this limit (the key's unit). Range: as `normal`.
    #[serde(default)]
    pub uniform: Option<f64>,
    /// ISO 286-1 standard tolerance grade (5 to 11) of the feature's size: normal with
    /// `sigma = IT/12` (the tolerance zone of the diameter is `+-3 sigma` of the process, and
    /// the error is a radius or a position: half the diameter's deviation). Lengths only.
    /// Range: whole number, 5 to 11, sizes up to 3150 mm.
    #[serde(default)]
    pub iso_grade: Option<i64>,
}

/// `[tolerances]`: the distributions of the part errors of a batch of reducers, sampled
/// independently for every pin and crank by `rvlife montecarlo`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TolerancesConfig {
    /// Radial position of each pin centre, um (ISO grade of the pin circle diameter).
    #[serde(default)]
    pub pin_radial_um: Option<ToleranceConfig>,
    /// Tangential position of each pin centre, um (ISO grade of the pin circle diameter).
    #[serde(default)]
    pub pin_tangential_um: Option<ToleranceConfig>,
    /// Radius of each pin, um (ISO grade of the pin diameter).
    #[serde(default)]
    pub pin_radius_um: Option<ToleranceConfig>,
    /// Pin circle radial run-out (TIR), um: its magnitude is the absolute value of a draw, its
    /// direction uniform (ISO grade of the pin circle diameter).
    #[serde(default)]
    pub pin_circle_runout_um: Option<ToleranceConfig>,
    /// Eccentricity of each crank, um (ISO grade of the eccentric's throw, `2 a`).
    #[serde(default)]
    pub crank_eccentricity_um: Option<ToleranceConfig>,
    /// Phase of each crank's eccentrics, arcmin.
    #[serde(default)]
    pub crank_phase_arcmin: Option<ToleranceConfig>,
    /// Equidistant modification error, um (ISO grade of the pin circle diameter).
    #[serde(default)]
    pub equidistant_um: Option<ToleranceConfig>,
    /// Offset modification error, um (ISO grade of the pin circle diameter).
    #[serde(default)]
    pub offset_um: Option<ToleranceConfig>,
    /// Rotation modification error, arcmin.
    #[serde(default)]
    pub rotation_arcmin: Option<ToleranceConfig>,
    /// Selective assembly: the pin grade chosen for each unit to bring its backlash into a
    /// band (`[tolerances.selective_assembly]`; none: every unit is built as drawn).
    #[serde(default)]
    pub selective_assembly: Option<SelectiveAssemblyConfig>,
}

/// `[tolerances.selective_assembly]`: RV reducers are built by choosing, for each unit, one
/// grade of pins (a set whose radius differs from nominal by the grade's offset) that brings
/// the new unit's backlash into the factory's band; a unit that no grade brings into the band
/// is rejected at assembly (docs/model.md section 12.4).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SelectiveAssemblyConfig {
    /// Radius offsets of the pin grades on hand, um (each added to every pin's radius).
    /// Range: 1 to 21 distinct values, each within [-20, 20] um.
    pub pin_grades_um: Vec<f64>,
    /// The band the new unit's backlash must fall in, `[low, high]`, arcmin. Range: `0 <= low
    /// < high <= 60` arcmin.
    pub backlash_arcmin: [f64; 2],
}

/// The validated `[tolerances.selective_assembly]` (SI).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SelectiveAssembly {
    /// Radius offsets of the pin grades, m, ascending.
    pub pin_grades: Vec<f64>,
    /// The backlash band `[low, high]`, rad.
    pub backlash: [f64; 2],
}

impl SelectiveAssemblyConfig {
    /// Checks the grades and the band and converts them to SI.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `tolerances.selective_assembly.pin_grades_um` or
    /// `.backlash_arcmin` with the allowed range.
    pub fn validate(&self) -> Result<SelectiveAssembly> {
        let key = "tolerances.selective_assembly";
        let grades = &self.pin_grades_um;
        if grades.is_empty() || grades.len() > 21 {
            return Err(Error::invalid(
                format!("{key}.pin_grades_um"),
                format!("{} grades", grades.len()),
                "must list 1 to 21 grades",
            ));
        }
        let mut pin_grades = Vec::with_capacity(grades.len());
        for (i, &g) in grades.iter().enumerate() {
            pin_grades.push(
                check(
                    &format!("{key}.pin_grades_um[{i}]"),
                    g,
                    Range::closed(-20.0, 20.0, "um"),
                )? * 1e-6,
            );
        }
        pin_grades.sort_by(f64::total_cmp);
        if pin_grades.windows(2).any(|w| w[0] == w[1]) {
            return Err(Error::invalid(
                format!("{key}.pin_grades_um"),
                format!("{grades:?}"),
                "must list distinct grades",
            ));
        }
        let [lo, hi] = self.backlash_arcmin;
        let band_key = format!("{key}.backlash_arcmin");
        let lo = check(
            &format!("{band_key}[0]"),
            lo,
            Range::closed(0.0, 60.0, "arcmin"),
        )?;
        let hi = check(
            &format!("{band_key}[1]"),
            hi,
            Range::closed(0.0, 60.0, "arcmin"),
        )?;
        if lo >= hi {
            return Err(Error::invalid(
                band_key,
                format!("[{lo}, {hi}]"),
                "must be [low, high] with low < high",
            ));
        }
        let arcmin = (1.0_f64 / 60.0).to_radians();
        Ok(SelectiveAssembly {
            pin_grades,
            backlash: [lo * arcmin, hi * arcmin],
        })
    }
}

/// A validated distribution of one error about zero (SI: m or rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Tolerance {
    /// Normal, standard deviation.
    Normal(f64),
    /// Uniform within `+-` the limit.
    Uniform(f64),
}

impl Tolerance {
    /// One draw.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match *self {
            Tolerance::Normal(s) if s > 0.0 => Normal::new(0.0, s)
                .expect("validated: finite positive sigma")
                .sample(rng),
            Tolerance::Uniform(l) if l > 0.0 => Uniform::new_inclusive(-l, l)
                .expect("validated: finite positive limit")
                .sample(rng),
            _ => {
                // Zero width: one draw, like a tolerance left out.
                let _: f64 = rng.random();
                0.0
            }
        }
    }
}

/// The validated `[tolerances]` (SI), `None` where not given.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Tolerances {
    /// Pin radial position, m.
    pub pin_radial: Option<Tolerance>,
    /// Pin tangential position, m.
    pub pin_tangential: Option<Tolerance>,
    /// Pin radius, m.
    pub pin_radius: Option<Tolerance>,
    /// Pin circle run-out (TIR), m.
    pub pin_circle_runout: Option<Tolerance>,
    /// Crank eccentricity, m.
    pub crank_eccentricity: Option<Tolerance>,
    /// Crank phase, rad.
    pub crank_phase: Option<Tolerance>,
    /// Equidistant modification, m.
    pub equidistant: Option<Tolerance>,
    /// Offset modification, m.
    pub offset: Option<Tolerance>,
    /// Rotation modification, rad.
    pub rotation: Option<Tolerance>,
    /// Selective assembly of the pins' grade (none: units built as drawn).
    pub selective: Option<SelectiveAssembly>,
}

impl Tolerances {
    /// Whether no tolerance is given.
    pub fn is_empty(&self) -> bool {
        *self == Tolerances::default()
    }

    /// One sampled reducer: its part errors and its modification (the nominal `modification`
    /// plus the sampled modification errors), for `pins` pins and `cranks` cranks. The draws
    /// are made in a fixed order (pins radial, tangential, radius; run-out magnitude and
    /// direction; crank eccentricities, phases; equidistant, offset, rotation), each list
    /// drawn whether or not its tolerance is given (zero then, from one uniform draw). A
    /// normal draw may take more than one number from the stream (rand_distr's ziggurat
    /// rejects a few per cent), so adding or changing a tolerance does change the later draws:
    /// compare batches by their statistics, not sample by sample.
    pub fn sample<R: Rng + ?Sized>(
        &self,
        rng: &mut R,
        pins: usize,
        cranks: usize,
        modification: Modification,
    ) -> (PartErrors, Modification) {
        fn draw<R: Rng + ?Sized>(rng: &mut R, t: &Option<Tolerance>) -> f64 {
            match t {
                Some(t) => t.sample(rng),
                None => {
                    // Keep the stream's position independent of which tolerances are given.
                    let _: f64 = rng.random();
                    0.0
                }
            }
        }
        let pin_radial: Vec<f64> = (0..pins).map(|_| draw(rng, &self.pin_radial)).collect();
        let pin_tangential: Vec<f64> = (0..pins).map(|_| draw(rng, &self.pin_tangential)).collect();
        let pin_radius: Vec<f64> = (0..pins).map(|_| draw(rng, &self.pin_radius)).collect();
        let runout = draw(rng, &self.pin_circle_runout).abs();
        let dir = rng.random::<f64>() * std::f64::consts::TAU;
        let crank_eccentricity: Vec<f64> = (0..cranks)
            .map(|_| draw(rng, &self.crank_eccentricity))
            .collect();
        let crank_phase: Vec<f64> = (0..cranks).map(|_| draw(rng, &self.crank_phase)).collect();
        let m = Modification {
            equidistant: modification.equidistant + draw(rng, &self.equidistant),
            offset: modification.offset + draw(rng, &self.offset),
            rotation: modification.rotation + draw(rng, &self.rotation),
        };
        (
            PartErrors {
                pin_radial,
                pin_tangential,
                pin_radius,
                pin_circle_offset: Vec2::new(dir.cos(), dir.sin()) * (0.5 * runout),
                crank_eccentricity,
                crank_phase,
            },
            m,
        )
    }
}

/// ISO 286-1:2010 standard tolerance `IT` (m) of grade `grade` (5 to 11) for the nominal size
/// `size` (m, up to 3150 mm): `IT = k i`, `k` = 7, 10, 16, 25, 40, 64, 100 for IT5-IT11, with
/// the tolerance factor `i = 0.45 D^(1/3) + 0.001 D` um up to 500 mm and `I = 0.004 D + 2.1` um
/// above, `D` (mm) the geometric mean of the size step that holds `size` (the standard's
/// table values are these, rounded).
pub(crate) fn iso_it(grade: i64, size: f64) -> Option<f64> {
    const STEPS: [f64; 23] = [
        0.0,
        3.0,
        6.0,
        10.0,
        18.0,
        30.0,
        50.0,
        80.0,
        120.0,
        180.0,
        250.0,
        315.0,
        400.0,
        500.0,
        630.0,
        800.0,
        1000.0,
        1250.0,
        1600.0,
        2000.0,
        2500.0,
        3150.0,
        f64::INFINITY,
    ];
    let k = match grade {
        5 => 7.0,
        6 => 10.0,
        7 => 16.0,
        8 => 25.0,
        9 => 40.0,
        10 => 64.0,
        11 => 100.0,
        _ => return None,
    };
    let mm = size * 1e3;
    if !(mm > 0.0 && mm <= 3150.0) {
        return None;
    }
    let i = STEPS.windows(2).position(|w| mm > w[0] && mm <= w[1])?;
    let (lo, hi) = (STEPS[i].max(1.0), STEPS[i + 1]);
    let d = (lo * hi).sqrt();
    let factor = if hi <= 500.0 {
        0.45 * d.cbrt() + 0.001 * d
    } else {
        0.004 * d + 2.1
    };
    Some(k * factor * 1e-6)
}

fn tolerance(
    key: &str,
    t: &ToleranceConfig,
    unit: &'static str,
    to_si: f64,
    size: Option<f64>,
) -> Result<Tolerance> {
    let given = [
        t.normal.is_some(),
        t.uniform.is_some(),
        t.iso_grade.is_some(),
    ]
    .iter()
    .filter(|&&b| b)
    .count();
    if given != 1 {
        return Err(Error::invalid(
            key,
            format!("{given} distributions"),
            "give exactly one of normal = sigma, uniform = limit, iso_grade = 5..11",
        ));
    }
    // Part errors beyond a millimetre (or 10 degrees) are not tolerances.
    let hi = if unit == "um" { 1000.0 } else { 600.0 };
    if let Some(s) = t.normal {
        return Ok(Tolerance::Normal(
            check(&format!("{key}.normal"), s, Range::non_negative(hi, unit))? * to_si,
        ));
    }
    if let Some(l) = t.uniform {
        return Ok(Tolerance::Uniform(
            check(&format!("{key}.uniform"), l, Range::non_negative(hi, unit))? * to_si,
        ));
    }
    let grade = t.iso_grade.unwrap_or(0);
    let Some(size) = size else {
        return Err(Error::invalid(
            format!("{key}.iso_grade"),
            grade,
            "ISO grades apply to lengths; give normal = sigma or uniform = limit",
        ));
    };
    let it = iso_it(grade, size).ok_or_else(|| {
        Error::invalid(
            format!("{key}.iso_grade"),
            grade,
            format!(
                "must be a whole number from 5 to 11 (ISO 286-1, sizes up to 3150 mm; this \
                 feature is {:.3} mm)",
                size * 1e3
            ),
        )
    })?;
    Ok(Tolerance::Normal(it / 12.0))
}

impl TolerancesConfig {
    /// Checks every distribution and converts to SI; ISO grades take the feature sizes from
    /// `geometry` (pin diameter, pin circle diameter, the eccentric's throw `2 a`).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key (`tolerances.pin_radial_um.normal`), the value and
    /// the allowed range.
    pub fn validate(&self, geometry: &CycloidGeometry) -> Result<Tolerances> {
        let um = 1e-6;
        let arcmin = (1.0_f64 / 60.0).to_radians();
        let circle = 2.0 * geometry.pin_circle_radius;
        let t = |key: &str, v: &Option<ToleranceConfig>, unit, si, size| -> Result<_> {
            v.as_ref()
                .map(|v| tolerance(&format!("tolerances.{key}"), v, unit, si, size))
                .transpose()
        };
        Ok(Tolerances {
            pin_radial: t("pin_radial_um", &self.pin_radial_um, "um", um, Some(circle))?,
            pin_tangential: t(
                "pin_tangential_um",
                &self.pin_tangential_um,
                "um",
                um,
                Some(circle),
            )?,
            pin_radius: t(
                "pin_radius_um",
                &self.pin_radius_um,
                "um",
                um,
                Some(2.0 * geometry.pin_radius),
            )?,
            pin_circle_runout: t(
                "pin_circle_runout_um",
                &self.pin_circle_runout_um,
                "um",
                um,
                Some(circle),
            )?,
            crank_eccentricity: t(
                "crank_eccentricity_um",
                &self.crank_eccentricity_um,
                "um",
                um,
                Some(2.0 * geometry.eccentricity),
            )?,
            crank_phase: t(
                "crank_phase_arcmin",
                &self.crank_phase_arcmin,
                "arcmin",
                arcmin,
                None,
            )?,
            equidistant: t(
                "equidistant_um",
                &self.equidistant_um,
                "um",
                um,
                Some(circle),
            )?,
            offset: t("offset_um", &self.offset_um, "um", um, Some(circle))?,
            rotation: t(
                "rotation_arcmin",
                &self.rotation_arcmin,
                "arcmin",
                arcmin,
                None,
            )?,
            selective: self
                .selective_assembly
                .as_ref()
                .map(SelectiveAssemblyConfig::validate)
                .transpose()?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ISO 286-1 Table 1 values (um): IT5 and IT7 at 18-30 mm are 9 and 21, IT6 at 80-120
    /// mm is 22, IT11 at 3-6 mm is 75; the formula gives them to the standard's rounding.
    #[test]
    fn iso_tolerances_match_the_standard_table() {
        for (grade, size_mm, table_um) in [
            (5, 25.0, 9.0),
            (7, 25.0, 21.0),
            (6, 100.0, 22.0),
            (11, 5.0, 75.0),
        ] {
            let it = iso_it(grade, size_mm * 1e-3).unwrap() * 1e6;
            assert!(
                (it - table_um).abs() / table_um < 0.06,
                "IT{grade} {size_mm} mm: {it}"
            );
        }
        assert!(iso_it(4, 0.01).is_none() && iso_it(12, 0.01).is_none());
    }
}
