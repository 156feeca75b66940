//! Monte Carlo's files: `samples.csv` and `stages.csv` (the records), `percentiles.csv`,
//! `summary.json`, `config.toml`, `plots/` and `report.html` of a whole run
//! ([`super::mc_report`]); a shard's records and
//! meta-data (`shard.json`); and the merge of shards into exactly the unsharded run's files.

use std::path::Path;

use super::mc_report::status_key;
pub use super::mc_report::{verdict, McSummary};
pub use super::mc_shards::{merge_parts, parse_records, Part, ShardMeta};
use crate::error::{Error, Result};
pub use crate::montecarlo::records_csv;
use crate::montecarlo::{life_distribution, percentiles, SampleRecord};

/// Writes `samples.csv` (one row per sample) and `stages.csv` (one row per sample and stage)
/// into `dir`; floats in Rust's shortest round-trip form, so reading them back gives the same
/// bits.
///
/// # Errors
/// [`Error::Io`].
pub(crate) fn write_records(dir: &Path, records: &[SampleRecord]) -> Result<()> {
    let (s, t) = records_csv(records);
    write(dir, "samples.csv", &s)?;
    write(dir, "stages.csv", &t)
}

fn write(dir: &Path, name: &str, text: &str) -> Result<()> {
    let p = dir.join(name);
    std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
}

/// Reads the records written by [`write_records`] ([`parse_records`]).
///
/// # Errors
/// [`Error::Invalid`] naming the file if it is missing or malformed.
pub(crate) fn read_records(dir: &Path) -> Result<Vec<SampleRecord>> {
    let read = |name: &str| -> Result<(String, String)> {
        let p = dir.join(name);
        let shown = p.display().to_string();
        let text = crate::input::read_text(&p).map_err(|e| {
            Error::invalid(
                shown.as_str(),
                e,
                "must be a samples.csv / stages.csv written by rvlife montecarlo",
            )
        })?;
        Ok((shown, text))
    };
    let (sp, s) = read("samples.csv")?;
    let (tp, t) = read("stages.csv")?;
    parse_records((&sp, &s), (&tp, &t))
}

/// Writes the results of a whole run (all samples, sorted by index) into `dir`: the records,
/// `percentiles.csv`, `summary.json`, `config.toml`, and `plots/` (histogram of the accuracy
/// life and of each quantity at the last stage, a fan chart of each quantity against hours).
///
/// # Errors
/// [`Error::Io`].
pub fn write_results(dir: &Path, meta: &ShardMeta, records: &[SampleRecord]) -> Result<()> {
    let mut plan = meta.plan;
    plan.shard = (1, 1);
    write_records(dir, records)?;
    write(dir, "config.toml", &meta.config_toml)?;
    let pct = percentiles(records, &meta.stage_hours);
    let mut p = String::from("hours,quantity,n,p5,p50,p95,mean\n");
    for x in &pct {
        p.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            x.hours, x.quantity, x.n, x.p5, x.p50, x.p95, x.mean
        ));
    }
    write(dir, "percentiles.csv", &p)?;
    let mut status_counts = std::collections::BTreeMap::new();
    for r in records {
        *status_counts.entry(status_key(&r.status)).or_insert(0) += 1;
    }
    let summary = McSummary {
        rvlife_version: env!("CARGO_PKG_VERSION"),
        plan,
        status_counts,
        life: life_distribution(
            records,
            super::mc_report::spec_of(&meta.config_toml).horizon_h(&meta.stage_hours),
        ),
        percentiles: pct.clone(),
        percentile_standard_error_note: "standard error of a percentile p from n samples: \
            sqrt(p (1 - p) / n) / f(x_p); for a normal quantity 1.25 sigma / sqrt(n) at the \
            median, 2.11 sigma / sqrt(n) at 5 and 95 %",
    };
    let json = serde_json::to_string_pretty(&summary)
        .map_err(|e| Error::numerical("summary", e.to_string()))?;
    write(dir, "summary.json", &(json + "\n"))?;
    super::mc_report::write(dir, meta, records, &summary)
}

/// Writes a shard's results: its records and `shard.json` ([`ShardMeta`]).
///
/// # Errors
/// [`Error::Io`].
pub fn write_shard(dir: &Path, meta: &ShardMeta, records: &[SampleRecord]) -> Result<()> {
    write_records(dir, records)?;
    let json =
        serde_json::to_string_pretty(meta).map_err(|e| Error::numerical("shard", e.to_string()))?;
    write(dir, "shard.json", &(json + "\n"))
}

/// Reads shards written by [`write_shard`] and merges them ([`merge_parts`]: the parts of one
/// run, every shard and every sample index once) into exactly the unsharded run's records.
///
/// # Errors
/// [`Error::Invalid`] naming the directory and what does not match.
pub fn merge(dirs: &[std::path::PathBuf]) -> Result<(ShardMeta, Vec<SampleRecord>)> {
    let mut parts = Vec::with_capacity(dirs.len());
    for d in dirs {
        let p = d.join("shard.json");
        let text = crate::input::read_text(&p).map_err(|e| {
            Error::invalid(
                d.display().to_string(),
                format!("no shard.json ({e})"),
                "must be a results directory of rvlife montecarlo --shard I/N",
            )
        })?;
        let meta: ShardMeta = serde_json::from_str(&text).map_err(|e| {
            Error::invalid(
                p.display().to_string(),
                e.to_string(),
                "must be a shard.json of rvlife",
            )
        })?;
        parts.push(Part {
            origin: d.display().to_string(),
            meta,
            records: read_records(d)?,
        });
    }
    merge_parts(parts)
}
