//! The TypeScript type of a stage's record, written from [`STAGE`]: the page's types are
//! generated from the result types (ts-rs), and a stage's record is serialised from the
//! declarations rather than derived, so its type is too.

use super::{Models, StageSummary, STAGE};
use ts_rs::{Config, TS};

/// The TypeScript union of every stage quantity's name (`"hours" | "max_wear_um" | ...`),
/// in [`STAGE`]'s order: the keys of `summary.json`'s stages.
pub fn quantity_name_type() -> String {
    STAGE
        .iter()
        .map(|q| format!("\"{}\"", q.name))
        .collect::<Vec<_>>()
        .join(" | ")
}

impl TS for StageSummary {
    type WithoutGenerics = Self;
    type OptionInnerType = Self;

    fn docs() -> Option<String> {
        Some(ts_rs::format_docs(&[
            "A stage of `summary.json`: every stage quantity by its name (`quantities`), in \
             its unit; a value its model did not produce (dynamics, the flexible disc, the \
             lubrication) left out; a smallest-largest pair as two numbers.",
        ]))
    }

    fn name(_: &Config) -> String {
        "StageSummary".into()
    }

    /// `{ hours: number, ..., flexible_ste_peak_to_peak_arcmin?: number, ... }`: the
    /// quantities of the static analysis always present, the others optional.
    fn inline(_: &Config) -> String {
        let fields: Vec<String> = STAGE
            .iter()
            .map(|q| {
                let ty = if q.pair_columns.is_some() {
                    "[number, number]"
                } else {
                    "number"
                };
                let optional = if q.models == Models::Static { "" } else { "?" };
                let unit = if q.unit.is_empty() {
                    String::new()
                } else {
                    format!(", {}", q.unit)
                };
                format!("/** {}{unit}. */ {}{optional}: {ty}, ", q.label, q.name)
            })
            .collect();
        format!("{{ {}}}", fields.concat())
    }

    fn decl(cfg: &Config) -> String {
        format!("type StageSummary = {};", Self::inline(cfg))
    }

    fn decl_concrete(cfg: &Config) -> String {
        Self::decl(cfg)
    }
}
