//! The console's tables: the stage table, every quantity of every stage, the sensitivity of
//! the new reducer's catalogue quantities.

use rvlife::quantities::{self, ConsoleColumn, StageSummary, CONSOLE, STAGE};

/// The sensitivity table of `rvlife hysteresis --sensitivity`, to stdout.
pub(crate) fn print_sensitivity(t: &rvlife::sensitivity::SensitivityTable) {
    say!(
        "sensitivity of the new reducer (b/a {:.1} N m/arcmin, lost motion {:.4} arcmin) to each \
         estimate moved by -+{:.0} %:",
        t.stiffness_nm_per_arcmin,
        t.lost_motion_arcmin,
        100.0 * t.fraction
    );
    say!(
        "  {:48} {:>10} {:>19} {:>19} {:>19}",
        "key",
        "value",
        "tried",
        "b/a change %",
        "lost motion %"
    );
    for r in &t.rows {
        say!(
            "  {:48} {:>10.4} {:>9.4} {:>9.4} {:>+9.2} {:>+9.2} {:>+9.2} {:>+9.2}",
            r.key,
            r.value,
            r.tried[0],
            r.tried[1],
            100.0 * r.stiffness_change[0],
            100.0 * r.stiffness_change[1],
            100.0 * r.lost_motion_change[0],
            100.0 * r.lost_motion_change[1]
        );
    }
}

/// Prints the stage table: units in a line above it, then one row per stage; the DTE columns
/// appear when the dynamic model ran, the flexible-disc columns when the FE disc did
/// ([`rvlife::quantities::CONSOLE`]).
pub(crate) fn print_stage_table(stages: &[StageSummary]) {
    // A column is shown when every stage has its value.
    let shown: Vec<&ConsoleColumn> = CONSOLE
        .iter()
        .filter(|c| stages.iter().all(|s| c.cell(s).is_some()))
        .collect();
    let flexible = shown.iter().any(|c| c.header.starts_with("flex"));
    let dynamic = shown.iter().any(|c| c.header.starts_with("DTE"));
    say!("units: hours h, wear um (largest depth), Fmax N, pmax MPa, every other column arcmin");
    say!(
        "STE, STE_pp: no-load mean and peak-to-peak; LM: lost motion (+-3 % of rated torque); \
         loadTE: loaded TE{}{}",
        if dynamic { "; DTE: dynamic run" } else { "" },
        if flexible { "; flex*: FE disc" } else { "" }
    );
    let header: Vec<String> = shown
        .iter()
        .map(|c| format!("{:>w$}", c.header, w = c.width))
        .collect();
    say!("{}", header.join(" "));
    for st in stages {
        let row: Vec<String> = shown
            .iter()
            .map(|c| format!("{:>w$}", c.cell(st).unwrap_or_default(), w = c.width))
            .collect();
        say!("{}", row.join(" "));
    }
}

/// Prints every quantity of the stage table ([`rvlife::quantities::STAGE`]), one row per
/// quantity (its name with its unit) and one column per stage (`-` where it is absent).
pub(crate) fn print_all_quantities(stages: &[StageSummary]) {
    let width = STAGE.iter().map(|q| q.name.len()).max().unwrap_or(0);
    say!("every quantity of the stages (stages.csv, summary.json):");
    for q in STAGE {
        let cells: Vec<String> = stages
            .iter()
            .map(|s| match s.value(q) {
                quantities::Value::Number(v) => format!("{v:>12.6}"),
                quantities::Value::Count(n) => format!("{n:>12}"),
                quantities::Value::Pair([a, b]) => format!("{:>12}", format!("{a:.4}..{b:.4}")),
                quantities::Value::Absent => format!("{:>12}", "-"),
            })
            .collect();
        say!("  {:w$} {}", q.name, cells.join(" "), w = width);
    }
}
