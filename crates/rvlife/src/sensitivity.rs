//! How the new reducer's torsional stiffness `b/a` and lost motion move when each estimated
//! dimension or count of its structure changes by a fraction (`rvlife hysteresis
//! --sensitivity`; docs/model.md section 5.9): the user sees which estimates matter.
//!
//! Each input is set to `(1 -+ f)` times the value the config resolves it to (its own or the
//! estimate it defaults to; counts rounded to whole numbers), the config validated again, and
//! the hysteresis curve of the new reducer solved at the measuring and the rated torque, mean
//! over the crank angles of a mesh cycle (`te.samples_per_mesh_cycle`).

use rayon::prelude::*;
use serde::Serialize;

use crate::config::{Config, Model};
use crate::error::{Error, Result};
use crate::units::ARCMIN_PER_RAD;

/// One input's effect.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Sensitivity {
    /// The dotted config key.
    pub key: &'static str,
    /// What it stands for.
    pub what: &'static str,
    /// Its value in the config (its own or its estimate), in the key's unit.
    pub value: f64,
    /// The values tried below and above it, in the key's unit.
    pub tried: [f64; 2],
    /// `b/a` at the value below and above, relative change from the config's (-0.05: 5 % less).
    pub stiffness_change: [f64; 2],
    /// Lost motion at the value below and above, relative change from the config's.
    pub lost_motion_change: [f64; 2],
}

/// The config's own `b/a` (N m/arcmin) and lost motion (arcmin) beside the rows.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SensitivityTable {
    /// The fraction each input was moved by (0.2: +-20 %).
    pub fraction: f64,
    /// `b/a` of the config, N m/arcmin.
    pub stiffness_nm_per_arcmin: f64,
    /// Lost motion of the config, arcmin.
    pub lost_motion_arcmin: f64,
    /// One row per input, in the order of [`INPUTS`].
    pub rows: Vec<Sensitivity>,
}

/// An estimated input: its key, what it stands for, whether it is a count, how to read its
/// value off the model and how to set it in a config.
struct Input {
    key: &'static str,
    what: &'static str,
    count: bool,
    value: fn(&Model, &Config) -> Option<f64>,
    set: fn(&mut Config, f64),
}

/// The estimated dimensions and counts of an RV reducer's structure and bearings.
const INPUTS: &[Input] = &[
    Input {
        key: "reducer.structure.crank_diameter_mm",
        what: "crankshaft diameter",
        count: false,
        value: |m, _| m.structure.crank.map(|c| c.diameter * 1e3),
        set: |c, v| c.reducer.structure.crank_diameter_mm = Some(v),
    },
    Input {
        key: "reducer.structure.crank_span_mm",
        what: "crank's span between its bearings",
        count: false,
        value: |m, _| m.structure.crank.map(|c| c.span * 1e3),
        set: |c, v| c.reducer.structure.crank_span_mm = Some(v),
    },
    Input {
        key: "reducer.structure.eccentric_spacing_mm",
        what: "spacing of a crank's eccentrics",
        count: false,
        value: |m, _| m.structure.crank.map(|c| c.eccentric_spacing * 1e3),
        set: |c, v| c.reducer.structure.eccentric_spacing_mm = Some(v),
    },
    Input {
        key: "reducer.structure.crank_torsion_length_mm",
        what: "crank's twisted length",
        count: false,
        value: |m, _| {
            m.structure
                .crank
                .map(|_| m.structure.crank_torsion_length * 1e3)
        },
        set: |c, v| c.reducer.structure.crank_torsion_length_mm = Some(v),
    },
    Input {
        key: "reducer.structure.input_shaft_diameter_mm",
        what: "input shaft diameter",
        count: false,
        value: |m, _| m.structure.crank.map(|_| m.structure.input_shaft.0 * 1e3),
        set: |c, v| c.reducer.structure.input_shaft_diameter_mm = Some(v),
    },
    Input {
        key: "reducer.structure.input_shaft_length_mm",
        what: "input shaft length",
        count: false,
        value: |m, _| m.structure.crank.map(|_| m.structure.input_shaft.1 * 1e3),
        set: |c, v| c.reducer.structure.input_shaft_length_mm = Some(v),
    },
    Input {
        key: "reducer.structure.housing_outer_diameter_mm",
        what: "case diameter round the pins",
        count: false,
        value: |m, _| m.structure.housing.map(|h| 2.0 * h.outer_radius * 1e3),
        set: |c, v| c.reducer.structure.housing_outer_diameter_mm = Some(v),
    },
    Input {
        key: "reducer.structure.housing_width_mm",
        what: "housing ring's width",
        count: false,
        value: |m, _| m.structure.housing.map(|h| h.width * 1e3),
        set: |c, v| c.reducer.structure.housing_width_mm = Some(v),
    },
    Input {
        key: "reducer.bearings.carrier_stiffness_n_per_um",
        what: "carrier's pillars at a crank seat",
        count: false,
        value: |m, _| (m.reducer.series.carrier > 0.0).then(|| 1e-6 / m.reducer.series.carrier),
        set: |c, v| c.reducer.bearings.carrier_stiffness_n_per_um = Some(v),
    },
    Input {
        key: "reducer.bearings.crank_disc_rollers",
        what: "needles on an eccentric",
        count: true,
        value: |_, c| Some(c.reducer.bearings.crank_disc_rollers as f64),
        set: |c, v| c.reducer.bearings.crank_disc_rollers = v as i64,
    },
    Input {
        key: "reducer.bearings.crank_carrier_rollers",
        what: "rollers per row of a crank-carrier pair",
        count: true,
        value: |_, c| Some(c.reducer.bearings.crank_carrier_rollers as f64),
        set: |c, v| c.reducer.bearings.crank_carrier_rollers = v as i64,
    },
    Input {
        key: "reducer.bearings.crank_disc_roller_length_mm",
        what: "needle length",
        count: false,
        value: |m, _| roller_length(&m.reducer.bearings.disc.law),
        set: |c, v| c.reducer.bearings.crank_disc_roller_length_mm = Some(v),
    },
    Input {
        key: "reducer.bearings.crank_carrier_roller_length_mm",
        what: "crank-carrier roller length",
        count: false,
        value: |m, _| roller_length(&m.reducer.bearings.carrier.law),
        set: |c, v| c.reducer.bearings.crank_carrier_roller_length_mm = Some(v),
    },
    Input {
        key: "reducer.bearings.crank_carrier_contact_angle_deg",
        what: "tapered rollers' contact angle",
        count: false,
        value: |_, c| Some(c.reducer.bearings.crank_carrier_contact_angle_deg),
        set: |c, v| c.reducer.bearings.crank_carrier_contact_angle_deg = v,
    },
    Input {
        key: "reducer.bearings.crank_disc_clearance_um",
        what: "needle bearings' assembly clearance",
        count: false,
        value: |m, _| Some(m.reducer.bearings.disc.clearance * 1e6),
        set: |c, v| c.reducer.bearings.crank_disc_clearance_um = Some(v),
    },
    Input {
        key: "reducer.gears.mesh_stiffness_n_per_um",
        what: "sun-planet mesh stiffness",
        count: false,
        value: |_, c| Some(c.reducer.gears.mesh_stiffness_n_per_um),
        set: |c, v| c.reducer.gears.mesh_stiffness_n_per_um = v,
    },
    Input {
        key: "contact.groove_clearance_um",
        what: "pin's clearance in its groove",
        count: false,
        value: |m, c| {
            m.reducer
                .contact
                .groove
                .map(|_| c.contact.groove_clearance_um.unwrap_or(10.0))
        },
        set: |c, v| c.contact.groove_clearance_um = Some(v),
    },
];

/// A roller set's length, mm (`None` for a linear law).
fn roller_length(law: &crate::reducer::BearingLaw) -> Option<f64> {
    match law {
        crate::reducer::BearingLaw::Rollers { length, .. } => Some(length * 1e3),
        _ => None,
    }
}

/// `b/a` (N m/arcmin) and lost motion (arcmin) of `model`'s new reducer.
fn accuracy(model: &Model) -> Result<(f64, f64)> {
    let a = crate::study::new_reducer_curve(model, 1)?.accuracy();
    Ok((
        a.torsional_stiffness / ARCMIN_PER_RAD,
        a.lost_motion * ARCMIN_PER_RAD,
    ))
}

/// Checks a sensitivity's `fraction` for `model` before any work ([`sensitivity`]).
///
/// # Errors
/// [`Error::Invalid`] naming `--sensitivity` for a fraction outside (0, 0.5] or a drive without
/// cranks.
pub fn check_fraction(fraction: f64, model: &Model) -> Result<()> {
    if !(fraction > 0.0 && fraction <= 0.5) {
        return Err(Error::invalid(
            "--sensitivity",
            fraction,
            "must be a fraction in (0, 0.5]",
        ));
    }
    if model.structure.crank.is_none() {
        return Err(Error::invalid(
            "--sensitivity",
            "a single-stage drive",
            "applies to an RV reducer (its cranks, carrier and housing)",
        ));
    }
    Ok(())
}

/// The sensitivity of `config`'s new reducer to each estimated input of an RV reducer's
/// structure ([module documentation](self)), each moved by `fraction` both ways (inputs the
/// config's model does not use, such as a linear bearing's roller count, are left out).
///
/// # Errors
/// [`Error::Invalid`] naming `--sensitivity` for a fraction outside (0, 0.5] or a drive without
/// cranks; naming the input's key where a moved value is refused by the validation; solver
/// failures.
pub fn sensitivity(config: &Config, fraction: f64) -> Result<SensitivityTable> {
    let model = crate::study::validated(config)?;
    check_fraction(fraction, &model)?;
    let (k0, lm0) = accuracy(&model)?;
    let rows = INPUTS
        .par_iter()
        .filter_map(|input| (input.value)(&model, config).map(|v| (input, v)))
        .map(|(input, v)| {
            let moved = |s: f64| -> Result<(f64, f64, f64)> {
                let mut x = v * (1.0 + s * fraction);
                if input.count {
                    x = x.round();
                }
                let mut c = config.clone();
                (input.set)(&mut c, x);
                let m = crate::study::validated(&c).map_err(|e| {
                    Error::invalid(
                        input.key,
                        x,
                        format!("moved by {s:+}{fraction} of its value for the sensitivity: {e}"),
                    )
                })?;
                let (k, lm) = accuracy(&m)?;
                Ok((x, k / k0 - 1.0, lm / lm0 - 1.0))
            };
            let (lo, hi) = (moved(-1.0)?, moved(1.0)?);
            Ok(Sensitivity {
                key: input.key,
                what: input.what,
                value: v,
                tried: [lo.0, hi.0],
                stiffness_change: [lo.1, hi.1],
                lost_motion_change: [lo.2, hi.2],
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(SensitivityTable {
        fraction,
        stiffness_nm_per_arcmin: k0,
        lost_motion_arcmin: lm0,
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On the example, each estimate moves `b/a` and the lost motion the way its physics says:
    /// a thicker crank, more or longer rollers, a wider case stiffen the reducer and take lost
    /// motion away; a longer crank span softens it; a larger needle clearance adds lost motion
    /// (by about its own play, `b/a` within 0.5 %). Every row moves both ways and the table's
    /// own values are the study's (`b/a` 157.1 with friction, lost motion 0.720). A fraction outside (0, 0.5]
    /// and a single-stage drive are refused by name.
    #[test]
    #[cfg_attr(
        target_family = "wasm",
        ignore = "the sensitivity is not in the web build's page: run natively"
    )]
    fn each_estimate_moves_the_reducer_the_way_its_physics_says() {
        let cfg = Config::example();
        let t = sensitivity(&cfg, 0.2).unwrap();
        assert!((t.stiffness_nm_per_arcmin - 157.1).abs() < 0.1);
        assert!((t.lost_motion_arcmin - 0.720).abs() < 0.001);
        assert_eq!(t.rows.len(), INPUTS.len());
        let row = |k: &str| t.rows.iter().find(|r| r.key.ends_with(k)).unwrap();
        for k in [
            "crank_diameter_mm",
            "housing_outer_diameter_mm",
            "crank_disc_rollers",
            "crank_carrier_rollers",
            "crank_disc_roller_length_mm",
        ] {
            let r = row(k);
            assert!(
                r.stiffness_change[0] < 0.0 && r.stiffness_change[1] > 0.0,
                "{r:?}"
            );
            assert!(
                r.lost_motion_change[0] > 0.0 && r.lost_motion_change[1] < 0.0,
                "{r:?}"
            );
        }
        let span = row("crank_span_mm");
        assert!(span.stiffness_change[0] > 0.0 && span.stiffness_change[1] < 0.0);
        let c = row("crank_disc_clearance_um");
        assert!(c.lost_motion_change[0] < 0.0 && c.lost_motion_change[1] > 0.0);
        assert!(c.stiffness_change.iter().all(|x| x.abs() < 0.005), "{c:?}");
        let e = sensitivity(&cfg, 0.7).unwrap_err().to_string();
        assert!(e.contains("--sensitivity"), "{e}");
        let single = Config::from_toml_str(
            &crate::config::preset_text("single-stage").unwrap(),
            "single",
        )
        .unwrap();
        let e = sensitivity(&single, 0.2).unwrap_err().to_string();
        assert!(
            e.contains("--sensitivity") && e.contains("single-stage"),
            "{e}"
        );
    }
}
