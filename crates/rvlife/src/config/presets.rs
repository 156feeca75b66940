//! Built-in reducers (`rvlife example --preset NAME`): the paper's reducer, RV-20E-, RV-40E-
//! and RV-80E-class reducers and a single-stage cycloid drive, each the built-in example with
//! the values that differ.
//!
//! Catalogue values (Nabtesco RV-E series catalogue: rated output torque 167, 412 and 784 N m;
//! ratio 81 offered for each) are marked as such. The internal dimensions of the RV-20E and
//! RV-80E classes are **estimates**: the paper's RV-40E-class stage (Tables 1-2) scaled by the
//! cube root of the rated-torque ratio (geometric similarity at equal contact stress: torque
//! goes as length cubed), with the mesh stiffness scaled linearly (the crank bearings' rollers
//! follow the disc width and the crank circle); sizes outside `[cycloid]` then default from
//! the stage ([`crate::geometry::CycloidGeometry::scaled_from_root`]).
//!
//! The example and the RV-E presets carry 2 um of radial internal clearance in the crank-disc
//! needle bearings, an **estimate** of the assembly play of fine-fit needles (ISO 5753-1 group
//! C2 starts at 0), a preloaded crank-carrier pair, and 10 / 10 um of equidistant / offset
//! modification (**estimate**), which give the RV-40E class about 0.6 arcmin of lost motion new
//! (catalogue: up to 1 arcmin). The `paper` preset is the paper's reducer as printed.

use crate::config::{Config, EXAMPLE_TOML};
use crate::error::{Error, Result};

impl Config {
    /// The paper's reducer as printed (Tao et al. 2024, Tables 1-2; `rvlife example --preset
    /// paper`): the example without play in its bearings, without profile modification and
    /// without an accuracy spec.
    pub fn paper() -> Config {
        let text = preset_text("paper").expect("the paper preset exists");
        Config::from_toml_str(&text, "<paper>").expect("the paper preset parses")
    }
}

/// One built-in reducer.
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    /// Name given to `--preset`.
    pub name: &'static str,
    /// One line: what it is and where its numbers come from.
    pub summary: &'static str,
    /// `(table, key, value)` replacing the example's value.
    edits: &'static [(&'static str, &'static str, &'static str)],
}

/// Length scale of an estimated class against the paper's RV-40E: `(T / 412 N m)^(1/3)`.
/// RV-20E: (167/412)^(1/3) = 0.7400; RV-80E: (784/412)^(1/3) = 1.2391.
const RV20E: &[(&str, &str, &str)] = &[
    ("reducer", "rated_torque_nm", "167.0"),
    ("reducer.gears", "face_width_mm", "7.4"),
    ("reducer.gears", "mesh_stiffness_n_per_um", "148.0"),
    ("cycloid", "eccentricity_mm", "0.96"),
    ("cycloid", "pin_circle_radius_mm", "47.4"),
    ("cycloid", "pin_radius_mm", "2.2"),
    ("cycloid", "width_mm", "6.5"),
    ("load", "torque_nm", "167.0"),
    ("dynamics.load", "amplitude_nm", "167.0"),
];

const RV80E: &[(&str, &str, &str)] = &[
    ("reducer", "rated_torque_nm", "784.0"),
    ("reducer.gears", "face_width_mm", "12.4"),
    ("reducer.gears", "mesh_stiffness_n_per_um", "248.0"),
    ("cycloid", "eccentricity_mm", "1.61"),
    ("cycloid", "pin_circle_radius_mm", "79.3"),
    ("cycloid", "pin_radius_mm", "3.72"),
    ("cycloid", "width_mm", "10.84"),
    ("load", "torque_nm", "784.0"),
    ("dynamics.load", "amplitude_nm", "784.0"),
];

/// The built-in reducers; the first is the default of `rvlife example`.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "rv-40e",
        summary: "RV-40E class: catalogue rated torque 412 N m, ratio 81; internal dimensions \
                  of the paper's reducer, with the play and modifications of its class: the \
                  built-in example, the default",
        edits: &[],
    },
    Preset {
        name: "paper",
        summary: "the paper's RV-40E-class reducer as printed (Tao et al. 2024, Tables 1-2): no \
                  play in the crank bearings, no profile modification, pins held rigidly, a \
                  rigid disc body, the disc the only part that wears, at the paper's \
                  coefficient, without running-in, frictionless",
        edits: &[
            ("reducer.bearings", "crank_disc_clearance_um", "0.0"),
            ("cycloid.modification", "equidistant_mm", "0.0"),
            ("cycloid.modification", "offset_mm", "0.0"),
            ("contact", "pin_support", "\"rigid\""),
            ("reducer.structure", "disc_body", "\"rigid\""),
            ("wear", "archard_coefficient_mm3_per_n_m", "6.844807e-9"),
            ("wear", "bearing_archard_coefficient_mm3_per_n_m", "0.0"),
            ("wear", "pin_archard_coefficient_mm3_per_n_m", "0.0"),
            ("wear", "running_in_factor", "1.0"),
            ("lubrication", "enabled", "false"),
        ],
    },
    Preset {
        name: "rv-20e",
        summary: "RV-20E class: catalogue rated torque 167 N m, ratio 81; internal dimensions \
                  estimated (the paper's stage x 0.740); the example's play and modifications",
        edits: RV20E,
    },
    Preset {
        name: "rv-80e",
        summary: "RV-80E class: catalogue rated torque 784 N m, ratio 81; internal dimensions \
                  estimated (the paper's stage x 1.239); the example's play and modifications",
        edits: RV80E,
    },
    Preset {
        name: "single-stage",
        summary: "single-stage cycloid drive, estimated: the paper's cycloid stage with the \
                  input on the eccentric shaft (ratio 39), two discs 180 deg apart, output by 8 \
                  pins in holes on the 40.5 mm circle (pin radius 8 mm), rated torque taken as \
                  the RV's 412 N m (same discs and pins); modifications 8 um equidistant and \
                  -5 um offset (estimated assembly play); accuracy spec 2 arcmin of lost \
                  motion and backlash (estimate for a general-purpose single-stage cycloid \
                  drive; 1.45 arcmin new); no multibody or FE model",
        edits: &[
            ("dynamics", "enabled", "false"),
            ("fem", "enabled", "false"),
            ("cycloid.modification", "equidistant_mm", "0.008"),
            ("cycloid.modification", "offset_mm", "-0.005"),
            ("reducer.bearings", "crank_disc_clearance_um", "0.0"),
            ("contact", "pin_support", "\"rigid\""),
            ("life", "lost_motion_arcmin", "2.0"),
            ("life", "backlash_arcmin", "2.0"),
        ],
    },
];

/// The example's first-stage lines, replaced by the single-stage drive's.
const FIRST_STAGE: &str = "sun_teeth = 20                 # Z1, input sun gear
planet_teeth = 40              # Z2, planet gear on each crankshaft (Z2/Z1 = 2)
planets = 2                    # planets = crankshafts
";

const SINGLE_STAGE: &str =
    "drive = \"single_stage\"         # (preset) input on the eccentric shaft, ratio -Zc
discs = 2                      # (preset) 1 to 3; disc_phases_deg default 360 d / discs
";

const OUTPUT_PINS: &str = "
[reducer.output_pins]          # (preset) pins in holes: the single-stage drive's output
count = 8
circle_radius_mm = 40.5
pin_radius_mm = 8.0            # hole radius = pin + eccentricity + clearance
hole_clearance_um = 0.0
# stiffness_n_per_um = 500.0   # default: reducer.bearings.crank_disc_stiffness_n_per_um
";

/// The example's accuracy spec; the `paper` preset judges it within its study's 7500 h.
const LIFE_SPEC: &str = "[life]
lost_motion_arcmin = 1.0
backlash_arcmin = 1.0
";

/// Replaces the value of `key` in `[table]` of a commented TOML text, keeping the comment.
fn set_value(text: &str, table: &str, key: &str, value: &str) -> Option<String> {
    let mut current = String::new();
    let mut done = false;
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split('#').next().unwrap_or("").trim();
        if let Some(t) = code.strip_prefix('[').and_then(|c| c.strip_suffix(']')) {
            current = t.trim().to_string();
        }
        let is_key = code.split_once('=').is_some_and(|(k, _)| k.trim() == key);
        if !done && current == table && is_key {
            out.push(format!("{key} = {value}  # (preset)"));
            done = true;
        } else {
            out.push(line.to_string());
        }
    }
    done.then(|| out.join("\n") + "\n")
}

/// The config text of the preset `name`: the example with the preset's values and a header
/// naming the preset and its sources.
///
/// # Errors
/// [`Error::Invalid`] naming `--preset` for an unknown name, with the list.
pub fn preset_text(name: &str) -> Result<String> {
    let p = PRESETS.iter().find(|p| p.name == name).ok_or_else(|| {
        Error::invalid(
            "--preset",
            format!("\"{name}\""),
            format!(
                "must be one of {}",
                PRESETS
                    .iter()
                    .map(|p| p.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )
    })?;
    if p.edits.is_empty() {
        return Ok(EXAMPLE_TOML.to_string());
    }
    let mut text = format!(
        "# preset {}: {}.\n# Values marked (preset) replace the paper's; sizes left out default \
         from [cycloid].\n#\n{EXAMPLE_TOML}",
        p.name, p.summary
    );
    if p.name == "single-stage" {
        if !text.contains(FIRST_STAGE) {
            return Err(Error::numerical(
                "preset",
                "the example's first stage is not where the preset expects it",
            ));
        }
        text = text.replace(FIRST_STAGE, SINGLE_STAGE).replace(
            "# overall ratio i_H = 1 + (Z2/Z1) Zp = 81\n",
            "# ratio -Zc = -39: the output turns against the input; [reducer.gears] is not used\n",
        );
        text = text.replace(
            "\n[reducer.gears]",
            &format!("{OUTPUT_PINS}\n[reducer.gears]"),
        );
    }
    if p.name == "paper" {
        // The paper's study ends at 7500 h: the life is judged within it, not searched beyond.
        if !text.contains(LIFE_SPEC) {
            return Err(Error::numerical(
                "preset",
                "the example's [life] is not where the preset expects it",
            ));
        }
        text = text.replace(
            LIFE_SPEC,
            &format!(
                "{LIFE_SPEC}max_hours = 7500.0               # (preset) the paper's study ends here\n"
            ),
        );
    }
    for (table, key, value) in p.edits {
        text = set_value(&text, table, key, value).ok_or_else(|| {
            Error::numerical(
                "preset",
                format!("the example has no key {table}.{key} for the preset"),
            )
        })?;
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every preset parses and validates (physical checks included), and the estimated classes
    /// keep the paper's proportions: the same K1 = a Zp / Rp to 1 %.
    #[test]
    fn every_preset_validates_with_the_paper_proportions() {
        let paper = Config::example().validate().unwrap();
        let k1 = |m: &crate::config::Model| m.cycloid.geometry.k1();
        for p in PRESETS {
            let text = preset_text(p.name).unwrap();
            let m = Config::from_toml_str(&text, p.name)
                .unwrap()
                .validate()
                .unwrap_or_else(|e| panic!("{}: {e}", p.name));
            assert!((k1(&m) / k1(&paper) - 1.0).abs() < 0.01, "{}", p.name);
        }
        assert!(preset_text("rv-1000e").is_err());
    }
}
