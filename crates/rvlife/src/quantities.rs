//! Every quantity rvlife reports for a stage, declared once: its name (with its unit), unit,
//! label, description, the models that produce it and how to read it off a stage's record.
//!
//! The outputs are views of these declarations: [`STAGE`], the full set in the order of
//! `summary.json`, gives `stages.csv`, the stage records of `summary.json`, the report's stage
//! table, `rvlife run --all` and the Python study's columns; [`CONSOLE`] is the console's stage
//! table; [`ACCURACY`] the quantities of the accuracy spec (Monte Carlo's `stages.csv` and
//! percentiles, the accuracy life); [`LIFE`] the thresholds of `[life]`. A quantity the study
//! gains is a `const` here, a field of [`StageSummary`] and an entry of [`STAGE`]
//! (docs/architecture.md: "Add an output quantity").

use serde::ser::{Serialize, SerializeMap, Serializer};

#[cfg(feature = "ts")]
pub mod typescript;

/// The models that produce a quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Models {
    /// The static analysis of the reducer with rigid discs (every stage; docs/model.md
    /// sections 5 and 6).
    Static,
    /// The multibody model (`[dynamics] enabled`; docs/model.md section 8).
    Dynamics,
    /// The flexible disc (`[fem] enabled`; docs/model.md section 9).
    Flexible,
    /// The losses and efficiency (`[lubrication] enabled`; docs/model.md section 18).
    Lubrication,
}

/// The value of a quantity at one stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A real number in the quantity's unit.
    Number(f64),
    /// A count.
    Count(usize),
    /// Smallest and largest value, in the quantity's unit.
    Pair([f64; 2]),
    /// Not computed at this stage (its model is off).
    Absent,
}

impl Value {
    /// The value as one number (a count as a real; the pair's range; `None` when absent).
    pub fn number(self) -> Option<f64> {
        match self {
            Value::Number(v) => Some(v),
            Value::Count(n) => Some(n as f64),
            Value::Pair([a, b]) => Some(b - a),
            Value::Absent => None,
        }
    }

    /// Whether every number of the value is finite (an absent value is).
    pub fn is_finite(self) -> bool {
        match self {
            Value::Number(v) => v.is_finite(),
            Value::Pair([a, b]) => a.is_finite() && b.is_finite(),
            Value::Count(_) | Value::Absent => true,
        }
    }

    /// The value's CSV cells, one per column of its quantity: numbers with 6 decimals, counts
    /// as integers, empty when absent.
    pub(crate) fn csv_cells(self, columns: usize) -> Vec<String> {
        match self {
            Value::Number(v) => vec![format!("{v:.6}")],
            Value::Count(n) => vec![n.to_string()],
            Value::Pair(p) => p.iter().map(|v| format!("{v:.6}")).collect(),
            Value::Absent => vec![String::new(); columns],
        }
    }
}

/// One reported quantity of a stage.
#[derive(Debug, Clone, Copy)]
pub struct Quantity {
    /// Its name in every output, with its unit (`lost_motion_arcmin`): the key of
    /// `summary.json`, the column of `stages.csv`.
    pub name: &'static str,
    /// Its unit (`arcmin`, `um`, `N m/arcmin`; empty for a pure number).
    pub unit: &'static str,
    /// A short label for plots and tables (`lost motion`).
    pub label: &'static str,
    /// What it is, with its definition and source.
    pub description: &'static str,
    /// The models that produce it.
    pub models: Models,
    /// Its value in a stage's record.
    pub stage: fn(&StageSummary) -> Value,
    /// Its value in an accuracy point (the quantities of the accuracy spec, [`ACCURACY`]).
    pub accuracy: Option<fn(&AccuracyPoint) -> f64>,
    /// The two CSV columns of a smallest-largest pair (`None`: one column, [`Quantity::name`]).
    pub pair_columns: Option<[&'static str; 2]>,
}

impl Quantity {
    /// Its CSV columns: its name, or the pair's two columns.
    pub fn columns(&self) -> Vec<&'static str> {
        match self.pair_columns {
            Some(p) => p.to_vec(),
            None => vec![self.name],
        }
    }
}

/// A stage's record: every quantity of [`STAGE`] at one working-hour stage (engineering units
/// in the names). Serialised (`summary.json`) as the object of [`STAGE`]'s names, in its
/// order, the absent values left out. The default is all zero and absent.
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
#[serde(default)]
pub struct StageSummary {
    /// Working hours, h.
    pub hours: f64,
    /// Maximum wear depth along the profile, um.
    pub max_wear_um: f64,
    /// Mean forward STE over a revolution, arcmin.
    pub ste_mean_arcmin: f64,
    /// Peak-to-peak forward STE, arcmin.
    pub ste_peak_to_peak_arcmin: f64,
    /// Mean reverse-direction STE, arcmin.
    pub ste_reverse_mean_arcmin: f64,
    /// Backlash, arcmin.
    pub backlash_arcmin: f64,
    /// Largest play, arcmin.
    pub backlash_max_arcmin: f64,
    /// Angular transmission error, arcmin.
    pub angular_te_arcmin: f64,
    /// Angular TE of the new reducer (its part errors and assembly play), arcmin.
    pub angular_te_assembly_arcmin: f64,
    /// Angular TE's change from the crank bearings' wear, arcmin.
    pub angular_te_bearing_wear_arcmin: f64,
    /// Angular TE's change from the pins' wear, arcmin.
    pub angular_te_pin_wear_arcmin: f64,
    /// Angular TE's change from the discs' wear (the remainder), arcmin.
    pub angular_te_disc_wear_arcmin: f64,
    /// Lost motion (catalogue), arcmin.
    pub lost_motion_arcmin: f64,
    /// Hysteresis loss, arcmin.
    pub hysteresis_loss_arcmin: f64,
    /// Mean loaded TE, arcmin.
    pub loaded_te_mean_arcmin: f64,
    /// Peak-to-peak loaded TE, arcmin.
    pub loaded_te_peak_to_peak_arcmin: f64,
    /// Largest pin force, N.
    pub max_force_n: f64,
    /// Largest Hertz pressure, MPa.
    pub max_pressure_mpa: f64,
    /// Fewest pins in contact on one disc.
    pub pins_in_contact: usize,
    /// Most pins in contact on one disc.
    pub pins_in_contact_max: usize,
    /// Disc 1's share of the output torque.
    pub disc_load_share: f64,
    /// Lost motion's part from the elastic compliance (lost motion minus backlash), arcmin.
    pub lost_motion_elastic_arcmin: f64,
    /// Lost motion's part from the assembly play (the new reducer's backlash), arcmin.
    pub lost_motion_assembly_arcmin: f64,
    /// Lost motion's part from the crank bearings' wear, arcmin.
    pub lost_motion_bearing_wear_arcmin: f64,
    /// Lost motion's part from the pins' wear, arcmin.
    pub lost_motion_pin_wear_arcmin: f64,
    /// Lost motion's part from the discs' wear (the remainder), arcmin.
    pub lost_motion_disc_wear_arcmin: f64,
    /// Largest wear depth of the pins, um.
    pub pin_max_wear_um: f64,
    /// Radial internal clearance of each crank-disc bearing at this stage (assembly plus
    /// wear), um.
    pub crank_disc_clearance_um: f64,
    /// Radial internal clearance of each crank-carrier bearing at this stage, um.
    pub crank_carrier_clearance_um: f64,
    /// Torsional stiffness `b/a`, N m/arcmin.
    pub torsional_stiffness_nm_per_arcmin: f64,
    /// Tangent stiffness at the loaded-TE torque, N m/arcmin.
    pub tangent_stiffness_nm_per_arcmin: f64,
    /// Flexible `b/a`, N m/arcmin (flexible disc).
    pub flexible_torsional_stiffness_nm_per_arcmin: Option<f64>,
    /// Flexible reverse STE mean, arcmin (flexible disc).
    pub flexible_ste_reverse_mean_arcmin: Option<f64>,
    /// Flexible reverse loaded TE mean, arcmin (flexible disc).
    pub flexible_loaded_te_reverse_mean_arcmin: Option<f64>,
    /// Flexible backlash, arcmin (flexible disc).
    pub flexible_backlash_arcmin: Option<f64>,
    /// Flexible lost motion, arcmin (flexible disc).
    pub flexible_lost_motion_arcmin: Option<f64>,
    /// Flexible STE mean, arcmin (flexible disc).
    pub flexible_ste_mean_arcmin: Option<f64>,
    /// Flexible STE peak-to-peak, arcmin (flexible disc).
    pub flexible_ste_peak_to_peak_arcmin: Option<f64>,
    /// Flexible loaded TE mean, arcmin (flexible disc).
    pub flexible_loaded_te_mean_arcmin: Option<f64>,
    /// Flexible loaded TE peak-to-peak, arcmin (flexible disc).
    pub flexible_loaded_te_peak_to_peak_arcmin: Option<f64>,
    /// Rigid loaded TE mean over the flexible analysis' crank angles, arcmin (flexible disc).
    pub rigid_loaded_te_revolution_mean_arcmin: Option<f64>,
    /// Largest von Mises stress, MPa (flexible disc).
    pub max_von_mises_mpa: Option<f64>,
    /// Largest tooth-root stress, MPa (flexible disc).
    pub max_root_stress_mpa: Option<f64>,
    /// Efficiency at the rated torque and speed (lubrication).
    pub efficiency: Option<f64>,
    /// Loss of the disc-pin contacts there, W (lubrication).
    pub loss_disc_pins_w: Option<f64>,
    /// Loss of the pins in their grooves there, W (lubrication).
    pub loss_pin_grooves_w: Option<f64>,
    /// Loss of the crank bearings there, W (lubrication).
    pub loss_crank_bearings_w: Option<f64>,
    /// Loss of the sun-planet meshes there, W (lubrication).
    pub loss_gear_meshes_w: Option<f64>,
    /// Load-weighted mean lambda ratio of the disc-pin contacts there (lubrication).
    pub lambda_mean: Option<f64>,
    /// Oil temperature there, deg C (lubrication; the heat balance's when on).
    pub oil_temperature_c: Option<f64>,
    /// Friction torque of the hysteresis curve at the rated torque, N m (lubrication).
    pub friction_torque_nm: Option<f64>,
    /// DTE mean, arcmin (dynamics).
    pub dte_mean_arcmin: Option<f64>,
    /// DTE peak-to-peak, arcmin (dynamics).
    pub dte_peak_to_peak_arcmin: Option<f64>,
    /// DTE RMS, arcmin (dynamics).
    pub dte_rms_arcmin: Option<f64>,
    /// Smallest and largest DTE, arcmin (dynamics).
    pub dte_range_arcmin: Option<[f64; 2]>,
}

impl StageSummary {
    /// The value of `q` at this stage.
    pub fn value(&self, q: &Quantity) -> Value {
        (q.stage)(self)
    }
}

impl Serialize for StageSummary {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let present: Vec<(&Quantity, Value)> = STAGE
            .iter()
            .map(|q| (*q, self.value(q)))
            .filter(|(_, v)| *v != Value::Absent)
            .collect();
        let mut map = serializer.serialize_map(Some(present.len()))?;
        for (q, v) in present {
            match v {
                Value::Number(x) => map.serialize_entry(q.name, &x)?,
                Value::Count(n) => map.serialize_entry(q.name, &n)?,
                Value::Pair(p) => map.serialize_entry(q.name, &p)?,
                Value::Absent => {}
            }
        }
        map.end()
    }
}

/// The quantities of the accuracy spec at one working-hour point: what `[life]` limits and
/// what Monte Carlo samples ([`ACCURACY`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AccuracyPoint {
    /// Working hours, h.
    pub hours: f64,
    /// Maximum wear depth, um.
    pub max_wear_um: f64,
    /// Backlash, arcmin.
    pub backlash_arcmin: f64,
    /// Lost motion (catalogue), arcmin.
    pub lost_motion_arcmin: f64,
    /// Angular TE over an output revolution, arcmin.
    pub angular_te_arcmin: f64,
    /// Torsional stiffness, N m/arcmin.
    pub torsional_stiffness_nm_per_arcmin: f64,
}

impl AccuracyPoint {
    /// The point of a stage's record.
    pub fn of(s: &StageSummary) -> AccuracyPoint {
        AccuracyPoint {
            hours: s.hours,
            max_wear_um: s.max_wear_um,
            backlash_arcmin: s.backlash_arcmin,
            lost_motion_arcmin: s.lost_motion_arcmin,
            angular_te_arcmin: s.angular_te_arcmin,
            torsional_stiffness_nm_per_arcmin: s.torsional_stiffness_nm_per_arcmin,
        }
    }
}

impl AccuracyPoint {
    /// The point at `hours` (h) of the values of the [`ACCURACY`] quantities, in its order.
    ///
    /// # Panics
    /// If `values` holds fewer than [`ACCURACY`]`.len()` numbers.
    #[cfg_attr(not(feature = "files"), allow(dead_code))]
    pub(crate) fn from_accuracy(hours: f64, values: &[f64]) -> AccuracyPoint {
        let at = |q: &Quantity| {
            let i = ACCURACY.iter().position(|a| a.name == q.name);
            values[i.expect("an accuracy quantity")]
        };
        AccuracyPoint {
            hours,
            max_wear_um: at(&MAX_WEAR),
            backlash_arcmin: at(&BACKLASH),
            lost_motion_arcmin: at(&LOST_MOTION),
            angular_te_arcmin: at(&ANGULAR_TE),
            torsional_stiffness_nm_per_arcmin: at(&TORSIONAL_STIFFNESS),
        }
    }
}

/// A quantity of the rigid static analysis, always present.
const fn number(
    name: &'static str,
    unit: &'static str,
    label: &'static str,
    description: &'static str,
    stage: fn(&StageSummary) -> Value,
) -> Quantity {
    Quantity {
        name,
        unit,
        label,
        description,
        models: Models::Static,
        stage,
        accuracy: None,
        pair_columns: None,
    }
}

/// A quantity of an optional model.
const fn optional(
    name: &'static str,
    unit: &'static str,
    label: &'static str,
    description: &'static str,
    models: Models,
    stage: fn(&StageSummary) -> Value,
) -> Quantity {
    Quantity {
        name,
        unit,
        label,
        description,
        models,
        stage,
        accuracy: None,
        pair_columns: None,
    }
}

/// `Some(v)` as a number, `None` as absent.
fn opt(v: Option<f64>) -> Value {
    v.map_or(Value::Absent, Value::Number)
}

/// Working hours of the stage.
pub const HOURS: Quantity = number("hours", "h", "hours", "Working hours of the stage.", |s| {
    Value::Number(s.hours)
});
/// Maximum wear depth.
pub const MAX_WEAR: Quantity = Quantity {
    accuracy: Some(|p| p.max_wear_um),
    ..number(
        "max_wear_um",
        "um",
        "max wear",
        "Largest wear depth along the profile normal (a measured deviation is not wear; \
         docs/model.md section 7).",
        |s| Value::Number(s.max_wear_um),
    )
};
/// Mean forward STE.
pub const STE_MEAN: Quantity = number(
    "ste_mean_arcmin",
    "arcmin",
    "STE",
    "Mean forward static TE over a mesh cycle: the first contact when the output turns \
     counter-clockwise at no load, the T -> 0+ limit of the loaded twist (docs/model.md \
     section 6).",
    |s| Value::Number(s.ste_mean_arcmin),
);
/// Peak-to-peak forward STE.
pub const STE_PEAK_TO_PEAK: Quantity = number(
    "ste_peak_to_peak_arcmin",
    "arcmin",
    "STE peak-to-peak",
    "Peak-to-peak of the forward static TE over a mesh cycle.",
    |s| Value::Number(s.ste_peak_to_peak_arcmin),
);
/// Mean reverse STE.
pub const STE_REVERSE_MEAN: Quantity = number(
    "ste_reverse_mean_arcmin",
    "arcmin",
    "reverse STE",
    "Mean static TE turning the other way (clockwise), as a positive angle.",
    |s| Value::Number(s.ste_reverse_mean_arcmin),
);
/// Backlash.
pub const BACKLASH: Quantity = Quantity {
    accuracy: Some(|p| p.backlash_arcmin),
    ..number(
        "backlash_arcmin",
        "arcmin",
        "backlash",
        "Backlash (catalogue): the width of the hysteresis curve at zero torque, the play \
         between the two directions, mean over a mesh cycle (docs/model.md section 6).",
        |s| Value::Number(s.backlash_arcmin),
    )
};
/// Largest play.
pub const BACKLASH_MAX: Quantity = number(
    "backlash_max_arcmin",
    "arcmin",
    "largest backlash",
    "Largest play over a mesh cycle (over the output revolution with part errors).",
    |s| Value::Number(s.backlash_max_arcmin),
);
/// Angular transmission error.
pub const ANGULAR_TE: Quantity = Quantity {
    accuracy: Some(|p| p.angular_te_arcmin),
    ..number(
        "angular_te_arcmin",
        "arcmin",
        "angular TE",
        "Angular transmission error (catalogue): peak-to-peak of the forward STE over one \
         output revolution (the mesh-cycle ripple without part errors; docs/model.md \
         section 10).",
        |s| Value::Number(s.angular_te_arcmin),
    )
};
/// Angular TE's part from the new reducer.
pub const ANGULAR_TE_ASSEMBLY: Quantity = number(
    "angular_te_assembly_arcmin",
    "arcmin",
    "angular TE: new reducer",
    "Part of the angular TE that the new reducer has (its part errors, modifications and \
     assembly play): its angular TE when new (docs/model.md section 6.5).",
    |s| Value::Number(s.angular_te_assembly_arcmin),
);
/// Angular TE's change from the crank bearings' wear.
pub const ANGULAR_TE_BEARING_WEAR: Quantity = number(
    "angular_te_bearing_wear_arcmin",
    "arcmin",
    "angular TE: bearing wear",
    "Change of the angular TE from the crank bearings' wear: the angular TE of the unworn disc \
     on the stage's bearings minus the new reducer's (docs/model.md section 6.5).",
    |s| Value::Number(s.angular_te_bearing_wear_arcmin),
);
/// Angular TE's change from the pins' wear.
pub const ANGULAR_TE_PIN_WEAR: Quantity = number(
    "angular_te_pin_wear_arcmin",
    "arcmin",
    "angular TE: pin wear",
    "Change of the angular TE from the pins' wear: the angular TE of the unworn disc on the \
     stage's bearings and pins minus that on the stage's bearings and unworn pins \
     (docs/model.md section 6.5).",
    |s| Value::Number(s.angular_te_pin_wear_arcmin),
);
/// Angular TE's change from the discs' wear.
pub const ANGULAR_TE_DISC_WEAR: Quantity = number(
    "angular_te_disc_wear_arcmin",
    "arcmin",
    "angular TE: disc wear",
    "Change of the angular TE from the discs' wear: the stage's angular TE minus that of the \
     unworn disc on the stage's bearings and pins (docs/model.md section 6.5; a peak-to-peak value, so \
     a part can be negative).",
    |s| Value::Number(s.angular_te_disc_wear_arcmin),
);
/// Lost motion.
pub const LOST_MOTION: Quantity = Quantity {
    accuracy: Some(|p| p.lost_motion_arcmin),
    ..number(
        "lost_motion_arcmin",
        "arcmin",
        "lost motion",
        "Lost motion (Nabtesco catalogue): the twist between the hysteresis curve's midpoints \
         at +- the measuring torque (3 % of rated), curve averaged over a mesh cycle \
         (docs/model.md section 6).",
        |s| Value::Number(s.lost_motion_arcmin),
    )
};
/// Hysteresis loss.
pub const HYSTERESIS_LOSS: Quantity = number(
    "hysteresis_loss_arcmin",
    "arcmin",
    "hysteresis loss",
    "Hysteresis loss: the width of the loop at zero torque after loading to +- rated torque \
     (equal to the backlash in this frictionless model).",
    |s| Value::Number(s.hysteresis_loss_arcmin),
);
/// Mean loaded TE.
pub const LOADED_TE_MEAN: Quantity = number(
    "loaded_te_mean_arcmin",
    "arcmin",
    "loaded TE",
    "Mean loaded TE at the loaded-TE torque (te.loaded_torque_nm, default rated), over a \
     mesh cycle.",
    |s| Value::Number(s.loaded_te_mean_arcmin),
);
/// Peak-to-peak loaded TE.
pub const LOADED_TE_PEAK_TO_PEAK: Quantity = number(
    "loaded_te_peak_to_peak_arcmin",
    "arcmin",
    "loaded TE peak-to-peak",
    "Peak-to-peak loaded TE over a mesh cycle.",
    |s| Value::Number(s.loaded_te_peak_to_peak_arcmin),
);
/// Largest pin force.
pub const MAX_FORCE: Quantity = number(
    "max_force_n",
    "N",
    "largest pin force",
    "Largest pin force over a mesh cycle at the loaded-TE torque.",
    |s| Value::Number(s.max_force_n),
);
/// Largest Hertz pressure.
pub const MAX_PRESSURE: Quantity = number(
    "max_pressure_mpa",
    "MPa",
    "largest Hertz pressure",
    "Largest Hertz pressure over a mesh cycle at the loaded-TE torque (docs/model.md \
     section 3).",
    |s| Value::Number(s.max_pressure_mpa),
);
/// Fewest pins in contact.
pub const PINS_IN_CONTACT: Quantity = number(
    "pins_in_contact",
    "",
    "pins in contact",
    "Fewest pins in contact on one disc over a mesh cycle at the loaded-TE torque.",
    |s| Value::Count(s.pins_in_contact),
);
/// Most pins in contact.
pub const PINS_IN_CONTACT_MAX: Quantity = number(
    "pins_in_contact_max",
    "",
    "most pins in contact",
    "Most pins in contact on one disc over a mesh cycle at the loaded-TE torque.",
    |s| Value::Count(s.pins_in_contact_max),
);
/// Disc 1's load share.
pub const DISC_LOAD_SHARE: Quantity = number(
    "disc_load_share",
    "",
    "disc 1 load share",
    "Share of the output torque carried by disc 1 at the loaded-TE torque (moment of its pin \
     forces over both discs'), mean over a mesh cycle; the rigid support's fixed load_share \
     otherwise.",
    |s| Value::Number(s.disc_load_share),
);
/// Lost motion's elastic part.
pub const LOST_MOTION_ELASTIC: Quantity = number(
    "lost_motion_elastic_arcmin",
    "arcmin",
    "lost motion: elastic",
    "Part of the lost motion from the elastic compliance of the reducer: the lost motion minus \
     the backlash (the twist between the no-load points and the midpoints at +-3 % of rated \
     torque; docs/model.md section 6.5).",
    |s| Value::Number(s.lost_motion_elastic_arcmin),
);
/// Lost motion's part from the assembly play.
pub const LOST_MOTION_ASSEMBLY: Quantity = number(
    "lost_motion_assembly_arcmin",
    "arcmin",
    "lost motion: assembly play",
    "Part of the lost motion from the play of the new reducer (profile modifications, bearing \
     clearances, mesh backlash): its backlash when new; the same part of the backlash, whose \
     four play parts add up to it (docs/model.md section 6.5).",
    |s| Value::Number(s.lost_motion_assembly_arcmin),
);
/// Lost motion's part from the crank bearings' wear.
pub const LOST_MOTION_BEARING_WEAR: Quantity = number(
    "lost_motion_bearing_wear_arcmin",
    "arcmin",
    "lost motion: bearing wear",
    "Part of the lost motion from the crank bearings' wear: the backlash of the unworn disc on \
     the stage's bearings minus the new reducer's; the same part of the backlash \
     (docs/model.md section 6.5).",
    |s| Value::Number(s.lost_motion_bearing_wear_arcmin),
);
/// Lost motion's part from the pins' wear.
pub const LOST_MOTION_PIN_WEAR: Quantity = number(
    "lost_motion_pin_wear_arcmin",
    "arcmin",
    "lost motion: pin wear",
    "Part of the lost motion from the pins' wear: the backlash of the unworn disc on the \
     stage's bearings and pins minus that on the stage's bearings and unworn pins; the same \
     part of the backlash (docs/model.md section 6.5).",
    |s| Value::Number(s.lost_motion_pin_wear_arcmin),
);
/// Largest wear depth of the pins.
pub const PIN_MAX_WEAR: Quantity = number(
    "pin_max_wear_um",
    "um",
    "pin max wear",
    "Largest wear depth of the pins around their circumference (docs/model.md section 7.11; \
     0 when wear.pin_archard_coefficient_mm3_per_n_m is 0).",
    |s| Value::Number(s.pin_max_wear_um),
);
/// Lost motion's part from the discs' wear.
pub const LOST_MOTION_DISC_WEAR: Quantity = number(
    "lost_motion_disc_wear_arcmin",
    "arcmin",
    "lost motion: disc wear",
    "Part of the lost motion from the discs' wear: the stage's backlash minus that of the \
     unworn disc on the stage's bearings and pins; the same part of the backlash \
     (docs/model.md section 6.5).",
    |s| Value::Number(s.lost_motion_disc_wear_arcmin),
);
/// Clearance of the crank-disc bearings.
pub const CRANK_DISC_CLEARANCE: Quantity = number(
    "crank_disc_clearance_um",
    "um",
    "crank-disc bearing clearance",
    "Radial internal clearance of each crank-disc (eccentric) bearing at the stage: the \
     assembly clearance plus the wear of its raceways (docs/model.md section 7.9).",
    |s| Value::Number(s.crank_disc_clearance_um),
);
/// Clearance of the crank-carrier bearings.
pub const CRANK_CARRIER_CLEARANCE: Quantity = number(
    "crank_carrier_clearance_um",
    "um",
    "crank-carrier bearing clearance",
    "Radial internal clearance of each crank-carrier bearing at the stage: the assembly \
     clearance plus the wear of its raceways (docs/model.md section 7.9).",
    |s| Value::Number(s.crank_carrier_clearance_um),
);
/// Torsional stiffness `b/a`.
pub const TORSIONAL_STIFFNESS: Quantity = Quantity {
    accuracy: Some(|p| p.torsional_stiffness_nm_per_arcmin),
    ..number(
        "torsional_stiffness_nm_per_arcmin",
        "N m/arcmin",
        "torsional stiffness",
        "Torsional stiffness b/a of the hysteresis curve (catalogue: the secant of the loading \
         branches between the measuring and the rated torque, mean of both senses).",
        |s| Value::Number(s.torsional_stiffness_nm_per_arcmin),
    )
};
/// Tangent stiffness.
pub const TANGENT_STIFFNESS: Quantity = number(
    "tangent_stiffness_nm_per_arcmin",
    "N m/arcmin",
    "tangent stiffness",
    "Mean tangent stiffness dT/dpsi at the loaded-TE torque.",
    |s| Value::Number(s.tangent_stiffness_nm_per_arcmin),
);
/// Flexible torsional stiffness.
pub const FLEXIBLE_TORSIONAL_STIFFNESS: Quantity = optional(
    "flexible_torsional_stiffness_nm_per_arcmin",
    "N m/arcmin",
    "flexible torsional stiffness",
    "Torsional stiffness b/a of the flexible-disc model between the STE measuring torque and \
     the rated torque, mean of both senses.",
    Models::Flexible,
    |s| opt(s.flexible_torsional_stiffness_nm_per_arcmin),
);
/// Flexible reverse STE.
pub const FLEXIBLE_STE_REVERSE_MEAN: Quantity = optional(
    "flexible_ste_reverse_mean_arcmin",
    "arcmin",
    "flexible reverse STE",
    "Mean TE of the flexible disc at minus the STE measuring torque over a crank revolution.",
    Models::Flexible,
    |s| opt(s.flexible_ste_reverse_mean_arcmin),
);
/// Flexible reverse loaded TE.
pub const FLEXIBLE_LOADED_TE_REVERSE_MEAN: Quantity = optional(
    "flexible_loaded_te_reverse_mean_arcmin",
    "arcmin",
    "flexible reverse loaded TE",
    "Mean TE of the flexible disc at minus the rated torque over a crank revolution.",
    Models::Flexible,
    |s| opt(s.flexible_loaded_te_reverse_mean_arcmin),
);
/// Flexible backlash.
pub const FLEXIBLE_BACKLASH: Quantity = optional(
    "flexible_backlash_arcmin",
    "arcmin",
    "flexible backlash",
    "Backlash of the flexible-disc model: the play between the two senses' first contacts, \
     mean over a crank revolution (the rigid play over those crank angles).",
    Models::Flexible,
    |s| opt(s.flexible_backlash_arcmin),
);
/// Flexible lost motion.
pub const FLEXIBLE_LOST_MOTION: Quantity = optional(
    "flexible_lost_motion_arcmin",
    "arcmin",
    "flexible lost motion",
    "Lost motion of the flexible-disc model: the twist between the flexible TEs at plus and \
     minus the measuring torque, mean over a crank revolution.",
    Models::Flexible,
    |s| opt(s.flexible_lost_motion_arcmin),
);
/// Flexible STE.
pub const FLEXIBLE_STE_MEAN: Quantity = optional(
    "flexible_ste_mean_arcmin",
    "arcmin",
    "flexible STE",
    "Mean TE of the flexible disc at the STE measuring torque (fem.ste_torque_fraction of \
     the rated torque) over a crank revolution (docs/model.md section 9).",
    Models::Flexible,
    |s| opt(s.flexible_ste_mean_arcmin),
);
/// Flexible STE peak-to-peak.
pub const FLEXIBLE_STE_PEAK_TO_PEAK: Quantity = optional(
    "flexible_ste_peak_to_peak_arcmin",
    "arcmin",
    "flexible STE peak-to-peak",
    "Peak-to-peak of the flexible STE over a crank revolution.",
    Models::Flexible,
    |s| opt(s.flexible_ste_peak_to_peak_arcmin),
);
/// Flexible loaded TE.
pub const FLEXIBLE_LOADED_TE_MEAN: Quantity = optional(
    "flexible_loaded_te_mean_arcmin",
    "arcmin",
    "flexible loaded TE",
    "Mean TE of the flexible disc at the rated torque over a crank revolution.",
    Models::Flexible,
    |s| opt(s.flexible_loaded_te_mean_arcmin),
);
/// Flexible loaded TE peak-to-peak.
pub const FLEXIBLE_LOADED_TE_PEAK_TO_PEAK: Quantity = optional(
    "flexible_loaded_te_peak_to_peak_arcmin",
    "arcmin",
    "flexible loaded TE peak-to-peak",
    "Peak-to-peak of the flexible loaded TE over a crank revolution.",
    Models::Flexible,
    |s| opt(s.flexible_loaded_te_peak_to_peak_arcmin),
);
/// Rigid loaded TE over the flexible analysis' crank angles.
pub const RIGID_LOADED_TE_REVOLUTION_MEAN: Quantity = optional(
    "rigid_loaded_te_revolution_mean_arcmin",
    "arcmin",
    "rigid loaded TE (crank revolution)",
    "Mean TE of the rigid disc at the rated torque over the flexible analysis' crank angles \
     (its comparison).",
    Models::Flexible,
    |s| opt(s.rigid_loaded_te_revolution_mean_arcmin),
);
/// Largest von Mises stress.
pub const MAX_VON_MISES: Quantity = optional(
    "max_von_mises_mpa",
    "MPa",
    "largest von Mises stress",
    "Largest von Mises stress in the disc at the rated torque, away from the pin load \
     patches, at the crank angles whose largest pin force is within 1 % of the largest.",
    Models::Flexible,
    |s| opt(s.max_von_mises_mpa),
);
/// Efficiency.
pub const EFFICIENCY: Quantity = optional(
    "efficiency",
    "",
    "efficiency",
    "Output over input power at the rated torque and the rated input speed, the oil at \
     [lubrication] temperature_c: friction at the disc-pin contacts with the oil film's \
     coefficient, Palmgren's bearing moments, ISO/TR 14179-2's mesh loss, on the loads of \
     the frictionless static analysis over a mesh cycle (docs/model.md section 18.4).",
    Models::Lubrication,
    |s| opt(s.efficiency),
);
/// Disc-pin loss.
pub const LOSS_DISC_PINS: Quantity = optional(
    "loss_disc_pins_w",
    "W",
    "loss: disc-pin contacts",
    "Power lost by the sliding disc-pin contacts at the efficiency's operating point, mean \
     over a mesh cycle (docs/model.md section 18.4).",
    Models::Lubrication,
    |s| opt(s.loss_disc_pins_w),
);
/// Groove loss.
pub const LOSS_PIN_GROOVES: Quantity = optional(
    "loss_pin_grooves_w",
    "W",
    "loss: pins in grooves",
    "Power lost by the pins turning in their housing grooves there (0 for pins held).",
    Models::Lubrication,
    |s| opt(s.loss_pin_grooves_w),
);
/// Bearing loss.
pub const LOSS_CRANK_BEARINGS: Quantity = optional(
    "loss_crank_bearings_w",
    "W",
    "loss: crank bearings",
    "Power lost by the crank-disc and crank-carrier bearings there (Palmgren's load and \
     viscous moments).",
    Models::Lubrication,
    |s| opt(s.loss_crank_bearings_w),
);
/// Mesh loss.
pub const LOSS_GEAR_MESHES: Quantity = optional(
    "loss_gear_meshes_w",
    "W",
    "loss: sun-planet meshes",
    "Power lost by the sun-planet meshes there (ISO/TR 14179-2, Ohlendorf's loss factor).",
    Models::Lubrication,
    |s| opt(s.loss_gear_meshes_w),
);
/// Lambda ratio.
pub const LAMBDA_MEAN: Quantity = optional(
    "lambda_mean",
    "",
    "lambda ratio of the disc-pin contacts",
    "Minimum film thickness (Pan and Hamrock) over the composite roughness, load-weighted mean \
     over the loaded disc-pin contacts at the efficiency's operating point (docs/model.md \
     section 18.2).",
    Models::Lubrication,
    |s| opt(s.lambda_mean),
);
/// Oil temperature.
pub const OIL_TEMPERATURE: Quantity = optional(
    "oil_temperature_c",
    "deg C",
    "oil temperature",
    "Oil temperature of the efficiency's operating point: [lubrication] temperature_c, or with \
     heat_balance the steady temperature where the losses leave through the housing \
     (docs/model.md section 18.5).",
    Models::Lubrication,
    |s| opt(s.oil_temperature_c),
);
/// Friction torque of the hysteresis curve.
pub const FRICTION_TORQUE: Quantity = optional(
    "friction_torque_nm",
    "N m",
    "friction torque at rated torque",
    "Coulomb friction torque resisting the output's twist at the rated torque with the input \
     locked (the half-width of the hysteresis loop in torque there), mean over a mesh cycle \
     (docs/model.md section 18.3).",
    Models::Lubrication,
    |s| opt(s.friction_torque_nm),
);
/// Largest root stress.
pub const MAX_ROOT_STRESS: Quantity = optional(
    "max_root_stress_mpa",
    "MPa",
    "largest root stress",
    "Largest von Mises stress at the tooth roots (the lower quarter of the tooth height), same \
     crank angles.",
    Models::Flexible,
    |s| opt(s.max_root_stress_mpa),
);
/// DTE mean.
pub const DTE_MEAN: Quantity = optional(
    "dte_mean_arcmin",
    "arcmin",
    "DTE",
    "Mean dynamic TE over the window of the multibody simulation (docs/model.md section 8).",
    Models::Dynamics,
    |s| opt(s.dte_mean_arcmin),
);
/// DTE peak-to-peak.
pub const DTE_PEAK_TO_PEAK: Quantity = optional(
    "dte_peak_to_peak_arcmin",
    "arcmin",
    "DTE peak-to-peak",
    "Peak-to-peak dynamic TE over the window.",
    Models::Dynamics,
    |s| opt(s.dte_peak_to_peak_arcmin),
);
/// DTE RMS.
pub const DTE_RMS: Quantity = optional(
    "dte_rms_arcmin",
    "arcmin",
    "DTE RMS",
    "RMS of the dynamic TE over the window.",
    Models::Dynamics,
    |s| opt(s.dte_rms_arcmin),
);
/// DTE range.
pub const DTE_RANGE: Quantity = Quantity {
    pair_columns: Some(["dte_min_arcmin", "dte_max_arcmin"]),
    ..optional(
        "dte_range_arcmin",
        "arcmin",
        "DTE range",
        "Smallest and largest dynamic TE over the window (two columns in CSV).",
        Models::Dynamics,
        |s| s.dte_range_arcmin.map_or(Value::Absent, Value::Pair),
    )
};

/// Every quantity of a stage, in the order of `summary.json`: `stages.csv`, the report's stage
/// table, `rvlife run --all` and the Python study's columns list them all.
pub const STAGE: [&Quantity; 55] = [
    &HOURS,
    &MAX_WEAR,
    &PIN_MAX_WEAR,
    &STE_MEAN,
    &STE_PEAK_TO_PEAK,
    &STE_REVERSE_MEAN,
    &BACKLASH,
    &BACKLASH_MAX,
    &ANGULAR_TE,
    &ANGULAR_TE_ASSEMBLY,
    &ANGULAR_TE_BEARING_WEAR,
    &ANGULAR_TE_PIN_WEAR,
    &ANGULAR_TE_DISC_WEAR,
    &LOST_MOTION,
    &LOST_MOTION_ELASTIC,
    &LOST_MOTION_ASSEMBLY,
    &LOST_MOTION_BEARING_WEAR,
    &LOST_MOTION_PIN_WEAR,
    &LOST_MOTION_DISC_WEAR,
    &HYSTERESIS_LOSS,
    &LOADED_TE_MEAN,
    &LOADED_TE_PEAK_TO_PEAK,
    &MAX_FORCE,
    &MAX_PRESSURE,
    &PINS_IN_CONTACT,
    &PINS_IN_CONTACT_MAX,
    &DISC_LOAD_SHARE,
    &CRANK_DISC_CLEARANCE,
    &CRANK_CARRIER_CLEARANCE,
    &TORSIONAL_STIFFNESS,
    &TANGENT_STIFFNESS,
    &FLEXIBLE_TORSIONAL_STIFFNESS,
    &FLEXIBLE_STE_REVERSE_MEAN,
    &FLEXIBLE_LOADED_TE_REVERSE_MEAN,
    &FLEXIBLE_BACKLASH,
    &FLEXIBLE_LOST_MOTION,
    &FLEXIBLE_STE_MEAN,
    &FLEXIBLE_STE_PEAK_TO_PEAK,
    &FLEXIBLE_LOADED_TE_MEAN,
    &FLEXIBLE_LOADED_TE_PEAK_TO_PEAK,
    &RIGID_LOADED_TE_REVOLUTION_MEAN,
    &MAX_VON_MISES,
    &MAX_ROOT_STRESS,
    &FRICTION_TORQUE,
    &EFFICIENCY,
    &LOSS_DISC_PINS,
    &LOSS_PIN_GROOVES,
    &LOSS_CRANK_BEARINGS,
    &LOSS_GEAR_MESHES,
    &LAMBDA_MEAN,
    &OIL_TEMPERATURE,
    &DTE_MEAN,
    &DTE_PEAK_TO_PEAK,
    &DTE_RMS,
    &DTE_RANGE,
];

/// The quantities of the accuracy spec, in the order of Monte Carlo's `stages.csv`,
/// `percentiles.csv` and plots; each has an [`AccuracyPoint`] accessor.
pub const ACCURACY: [&Quantity; 5] = [
    &MAX_WEAR,
    &BACKLASH,
    &LOST_MOTION,
    &ANGULAR_TE,
    &TORSIONAL_STIFFNESS,
];

/// Which side of a `[life]` threshold is inside the spec.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    /// The quantity must stay at or below the threshold.
    AtMost,
    /// The quantity must stay at or above the threshold.
    AtLeast,
}

/// One threshold of `[life]`: its key, the quantity it limits and the sense.
#[derive(Debug, Clone, Copy)]
pub struct Limit {
    /// The `[life]` key (without the section), also the accuracy life's `limited_by`.
    pub key: &'static str,
    /// The quantity limited.
    pub quantity: &'static Quantity,
    /// Inside the spec below or above the threshold.
    pub sense: Sense,
}

/// The thresholds of `[life]`, in the order ties between margins are broken.
pub const LIFE: [Limit; 4] = [
    Limit {
        key: "lost_motion_arcmin",
        quantity: &LOST_MOTION,
        sense: Sense::AtMost,
    },
    Limit {
        key: "backlash_arcmin",
        quantity: &BACKLASH,
        sense: Sense::AtMost,
    },
    Limit {
        key: "angular_te_arcmin",
        quantity: &ANGULAR_TE,
        sense: Sense::AtMost,
    },
    Limit {
        key: "torsional_stiffness_min_nm_per_arcmin",
        quantity: &TORSIONAL_STIFFNESS,
        sense: Sense::AtLeast,
    },
];

/// One column of the console's stage table.
#[derive(Debug, Clone, Copy)]
pub struct ConsoleColumn {
    /// The quantity shown.
    pub quantity: &'static Quantity,
    /// Column header.
    pub header: &'static str,
    /// Column width, characters.
    pub width: usize,
    /// Decimals of a number.
    pub decimals: usize,
}

impl ConsoleColumn {
    /// The cell of one stage (`None`: absent at that stage).
    pub fn cell(&self, s: &StageSummary) -> Option<String> {
        match s.value(self.quantity) {
            Value::Number(v) => Some(format!("{v:.d$}", d = self.decimals)),
            Value::Count(n) => Some(n.to_string()),
            Value::Pair([a, b]) => Some(format!("{a:.d$}..{b:.d$}", d = self.decimals)),
            Value::Absent => None,
        }
    }
}

const fn column(
    quantity: &'static Quantity,
    header: &'static str,
    width: usize,
    decimals: usize,
) -> ConsoleColumn {
    ConsoleColumn {
        quantity,
        header,
        width,
        decimals,
    }
}

/// The console's stage table of `rvlife run` (a column shows when every stage has its value).
pub const CONSOLE: [ConsoleColumn; 16] = [
    column(&HOURS, "hours", 7, 0),
    column(&MAX_WEAR, "wear", 7, 2),
    column(&STE_MEAN, "STE", 8, 4),
    column(&STE_PEAK_TO_PEAK, "STE_pp", 8, 4),
    column(&BACKLASH, "backlash", 8, 4),
    column(&LOST_MOTION, "LM", 8, 4),
    column(&LOADED_TE_MEAN, "loadTE", 8, 4),
    column(&DTE_MEAN, "DTE", 8, 4),
    column(&DTE_PEAK_TO_PEAK, "DTE_pp", 8, 4),
    column(&FLEXIBLE_STE_MEAN, "flexSTE", 8, 4),
    column(&FLEXIBLE_LOADED_TE_MEAN, "flexLTE", 8, 4),
    column(&FLEXIBLE_LOST_MOTION, "flexLM", 8, 4),
    column(&MAX_FORCE, "Fmax", 7, 0),
    column(&MAX_PRESSURE, "pmax", 6, 0),
    column(&PINS_IN_CONTACT, "pins", 4, 0),
    column(&DISC_LOAD_SHARE, "share", 5, 3),
];

/// `stages.csv` of stage records: the columns of every quantity of [`STAGE`] (a pair as two),
/// then one row per stage.
pub fn stages_csv(stages: &[StageSummary]) -> (Vec<String>, Vec<Vec<String>>) {
    stages_csv_of(&written(stages), stages)
}

/// [`stages_csv`] with the columns of `quantities` (a table of several studies: the
/// [`written`] quantities of all their stages).
pub fn stages_csv_of(
    quantities: &[&Quantity],
    stages: &[StageSummary],
) -> (Vec<String>, Vec<Vec<String>>) {
    let header = quantities
        .iter()
        .flat_map(|q| q.columns())
        .map(str::to_string)
        .collect();
    let rows = stages
        .iter()
        .map(|s| {
            quantities
                .iter()
                .flat_map(|q| s.value(q).csv_cells(q.columns().len()))
                .collect()
        })
        .collect();
    (header, rows)
}

/// The quantities of [`STAGE`] that `stages.csv` writes for `stages`: all, but those of the
/// losses and efficiency ([`Models::Lubrication`]) only where a stage has them (a study
/// without `[lubrication] enabled` writes the columns it wrote before the section existed).
pub fn written(stages: &[StageSummary]) -> Vec<&'static Quantity> {
    STAGE
        .iter()
        .copied()
        .filter(|q| {
            q.models != Models::Lubrication || stages.iter().any(|s| s.value(q) != Value::Absent)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names are unique, every unit is in its name, every accuracy quantity reads the same off
    /// an accuracy point as off the stage record, every `[life]` limit is an accuracy quantity.
    #[test]
    fn the_table_is_consistent() {
        let mut names: Vec<&str> = STAGE.iter().flat_map(|q| q.columns()).collect();
        names.push("dte_range_arcmin");
        let n = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), n, "a name is declared twice");
        let suffix = |u: &str| match u {
            "h" => "hours",
            "um" => "_um",
            "arcmin" => "_arcmin",
            "N" => "_n",
            "MPa" => "_mpa",
            "N m/arcmin" => "_nm_per_arcmin",
            _ => "",
        };
        for q in STAGE {
            assert!(q.name.ends_with(suffix(q.unit)), "{} ({})", q.name, q.unit);
        }
        let s = StageSummary {
            hours: 1.0,
            max_wear_um: 2.0,
            ste_mean_arcmin: 3.0,
            ste_peak_to_peak_arcmin: 4.0,
            ste_reverse_mean_arcmin: 5.0,
            backlash_arcmin: 6.0,
            backlash_max_arcmin: 7.0,
            angular_te_arcmin: 8.0,
            lost_motion_arcmin: 9.0,
            hysteresis_loss_arcmin: 10.0,
            loaded_te_mean_arcmin: 11.0,
            loaded_te_peak_to_peak_arcmin: 12.0,
            max_force_n: 13.0,
            max_pressure_mpa: 14.0,
            pins_in_contact: 15,
            pins_in_contact_max: 16,
            disc_load_share: 0.5,
            torsional_stiffness_nm_per_arcmin: 18.0,
            tangent_stiffness_nm_per_arcmin: 19.0,

            ..Default::default()
        };
        let p = AccuracyPoint::of(&s);
        for q in ACCURACY {
            let get = q
                .accuracy
                .expect("an accuracy quantity reads an accuracy point");
            assert_eq!(Some(get(&p)), s.value(q).number(), "{}", q.name);
        }
        let values: Vec<f64> = ACCURACY.iter().map(|q| q.accuracy.unwrap()(&p)).collect();
        assert_eq!(AccuracyPoint::from_accuracy(p.hours, &values), p);
        for l in LIFE {
            assert!(
                ACCURACY.iter().any(|q| q.name == l.quantity.name),
                "{}",
                l.key
            );
        }
        for c in CONSOLE {
            assert!(
                STAGE.iter().any(|q| q.name == c.quantity.name),
                "{}",
                c.header
            );
        }
        // The static quantities are present, the optional ones absent here.
        for q in STAGE {
            let present = s.value(q) != Value::Absent;
            assert_eq!(present, q.models == Models::Static, "{}", q.name);
        }
    }
}
