//! Monte Carlo's files: `samples.csv` and `stages.csv` (the records), `percentiles.csv`,
//! `summary.json`, `config.toml`, `plots/` and `report.html` of a whole run
//! ([`super::mc_report`]); a shard's records and
//! meta-data (`shard.json`); and the merge of shards into exactly the unsharded run's files.

use std::path::Path;

use super::mc_report::status_key;
pub use super::mc_report::{verdict, McSummary, ShardMeta};
use crate::error::{Error, Result};
pub use crate::montecarlo::records_csv;
use crate::montecarlo::{life_distribution, percentiles, SampleRecord};
use crate::quantities::{AccuracyPoint, ACCURACY};

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

/// Reads the records written by [`write_records`].
///
/// # Errors
/// [`Error::Invalid`] naming the file if it is missing or malformed.
pub(crate) fn read_records(dir: &Path) -> Result<Vec<SampleRecord>> {
    let bad = |p: &Path, what: String| {
        Error::invalid(
            p.display().to_string(),
            what,
            "must be a samples.csv / stages.csv written by rvlife montecarlo",
        )
    };
    // Checked like computed values: a number that is not finite (`nan`, `inf`) is refused.
    let finite = |p: &Path, f: &str| -> Result<f64> {
        match f.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(bad(p, format!("{f}: not a finite number"))),
            Err(e) => Err(bad(p, format!("{f}: {e}"))),
        }
    };
    let sp = dir.join("samples.csv");
    let mut rd = csv::Reader::from_reader(crate::input::open(&sp).map_err(|e| bad(&sp, e))?);
    let mut records = Vec::new();
    for row in rd.records() {
        let row = row.map_err(|e| bad(&sp, e.to_string()))?;
        let num = |i: usize| -> Result<Option<f64>> {
            let f = row.get(i).unwrap_or("");
            if f.is_empty() {
                Ok(None)
            } else {
                finite(&sp, f).map(Some)
            }
        };
        records.push(SampleRecord {
            sample: row
                .get(0)
                .unwrap_or("")
                .parse()
                .map_err(|e| bad(&sp, format!("sample: {e}")))?,
            status: row.get(1).unwrap_or("").to_string(),
            points: Vec::new(),
            accuracy_life_h: num(2)?,
            limited_by: row.get(3).filter(|s| !s.is_empty()).map(str::to_string),
        });
    }
    let tp = dir.join("stages.csv");
    let mut rd = csv::Reader::from_reader(crate::input::open(&tp).map_err(|e| bad(&tp, e))?);
    for row in rd.records() {
        let row = row.map_err(|e| bad(&tp, e.to_string()))?;
        let v: Vec<f64> = row.iter().map(|f| finite(&tp, f)).collect::<Result<_>>()?;
        if v.len() != 2 + ACCURACY.len() {
            return Err(bad(&tp, format!("{} columns", v.len())));
        }
        if v[0] < 0.0 || v[0].fract() != 0.0 {
            return Err(bad(&tp, format!("sample {}: not a sample index", v[0])));
        }
        let sample = v[0] as usize;
        let r = records
            .iter_mut()
            .find(|r| r.sample == sample)
            .ok_or_else(|| bad(&tp, format!("sample {sample} not in samples.csv")))?;
        r.points.push(AccuracyPoint::from_accuracy(v[1], &v[2..]));
    }
    Ok(records)
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
        life: life_distribution(records),
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

/// Reads shards written by [`write_shard`] and checks that they are the parts of one run:
/// same version, samples, seed, options, stages and config, every shard of `1..=N` present
/// once, and every sample index once.
///
/// # Errors
/// [`Error::Invalid`] naming the directory and what does not match.
pub fn merge(dirs: &[std::path::PathBuf]) -> Result<(ShardMeta, Vec<SampleRecord>)> {
    let mut metas: Vec<ShardMeta> = Vec::new();
    let mut records = Vec::new();
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
        if let Some(first) = metas.first() {
            let mut a = first.clone();
            a.plan.shard.0 = meta.plan.shard.0;
            if a != meta {
                return Err(Error::invalid(
                    d.display().to_string(),
                    format!("shard {}/{}", meta.plan.shard.0, meta.plan.shard.1),
                    format!(
                        "belongs to another run than {} (samples, seed, options, stages, \
                         config and version must match)",
                        dirs[0].display()
                    ),
                ));
            }
        }
        records.extend(read_records(d)?);
        metas.push(meta);
    }
    let n = metas[0].plan.shard.1;
    let mut seen: Vec<usize> = metas.iter().map(|m| m.plan.shard.0).collect();
    seen.sort_unstable();
    if seen != (1..=n).collect::<Vec<_>>() {
        return Err(Error::invalid(
            "shards",
            format!("{seen:?} of {n}"),
            format!("must be every shard 1..={n} once"),
        ));
    }
    records.sort_by_key(|r| r.sample);
    let total = metas[0].plan.samples;
    if records.len() != total || records.iter().enumerate().any(|(i, r)| r.sample != i) {
        return Err(Error::invalid(
            "shards",
            format!("{} sample records", records.len()),
            format!("must hold every sample 0..{total} once"),
        ));
    }
    let mut meta = metas.swap_remove(0);
    meta.plan.shard = (1, 1);
    Ok((meta, records))
}
