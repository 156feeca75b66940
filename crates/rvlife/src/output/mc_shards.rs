//! A Monte Carlo run in parts, without files: a shard's meta-data ([`ShardMeta`]), its records
//! as the texts of `samples.csv` and `stages.csv` read back to the same bits
//! ([`parse_records`]), and the merge of the parts into the records of the whole run
//! ([`merge_parts`]). The command line's `rvlife merge` reads shards' directories into these;
//! the page's Monte Carlo, spread over Web Workers, hands the texts between them.

use crate::error::{Error, Result};
use crate::montecarlo::{Plan, SampleRecord};
use crate::quantities::{AccuracyPoint, ACCURACY};
use serde::{Deserialize, Serialize};

/// The meta-data a shard carries so that merging can check the shards belong together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardMeta {
    /// rvlife version.
    pub rvlife_version: String,
    /// The plan (with this shard's `(I, N)`).
    pub plan: Plan,
    /// The stages, h.
    pub stage_hours: Vec<f64>,
    /// The config text the run read (`<built-in>` example: its text).
    pub config_toml: String,
}

/// One part of a run for [`merge_parts`]: where it came from (named in errors: a directory, a
/// worker), its meta-data and its records.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Where the part came from, as errors name it.
    pub origin: String,
    /// Its meta-data.
    pub meta: ShardMeta,
    /// Its samples' records.
    pub records: Vec<SampleRecord>,
}

/// The records of `samples.csv` and `stages.csv` ([`crate::montecarlo::records_csv`]: floats
/// in Rust's shortest round-trip form, so the records read back have the same bits).
/// `samples` and `stages` are `(name, text)`: the name is what errors call the table.
///
/// # Errors
/// [`Error::Invalid`] naming the table if it is malformed: a number that is not finite, a row
/// of another width, a stage row of a sample not in `samples.csv`.
pub fn parse_records(samples: (&str, &str), stages: (&str, &str)) -> Result<Vec<SampleRecord>> {
    let bad = |name: &str, what: String| {
        Error::invalid(
            name,
            what,
            "must be a samples.csv / stages.csv written by rvlife montecarlo",
        )
    };
    // Checked like computed values: a number that is not finite (`nan`, `inf`) is refused.
    let finite = |name: &str, f: &str| -> Result<f64> {
        match f.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            Ok(_) => Err(bad(name, format!("{f}: not a finite number"))),
            Err(e) => Err(bad(name, format!("{f}: {e}"))),
        }
    };
    let (sp, text) = samples;
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    let mut records = Vec::new();
    for row in rd.records() {
        let row = row.map_err(|e| bad(sp, e.to_string()))?;
        let num = |i: usize| -> Result<Option<f64>> {
            let f = row.get(i).unwrap_or("");
            if f.is_empty() {
                Ok(None)
            } else {
                finite(sp, f).map(Some)
            }
        };
        records.push(SampleRecord {
            sample: row
                .get(0)
                .unwrap_or("")
                .parse()
                .map_err(|e| bad(sp, format!("sample: {e}")))?,
            status: row.get(1).unwrap_or("").to_string(),
            points: Vec::new(),
            accuracy_life_h: num(2)?,
            limited_by: row.get(3).filter(|s| !s.is_empty()).map(str::to_string),
            // Absent from the shards of earlier versions (censored at the run's horizon).
            censored_h: num(4)?,
        });
    }
    let (tp, text) = stages;
    let mut rd = csv::Reader::from_reader(text.as_bytes());
    for row in rd.records() {
        let row = row.map_err(|e| bad(tp, e.to_string()))?;
        let v: Vec<f64> = row.iter().map(|f| finite(tp, f)).collect::<Result<_>>()?;
        if v.len() != 2 + ACCURACY.len() {
            return Err(bad(tp, format!("{} columns", v.len())));
        }
        if v[0] < 0.0 || v[0].fract() != 0.0 {
            return Err(bad(tp, format!("sample {}: not a sample index", v[0])));
        }
        let sample = v[0] as usize;
        let r = records
            .iter_mut()
            .find(|r| r.sample == sample)
            .ok_or_else(|| bad(tp, format!("sample {sample} not in samples.csv")))?;
        r.points.push(AccuracyPoint::from_accuracy(v[1], &v[2..]));
    }
    Ok(records)
}

/// Checks that `parts` are the parts of one run (same version, samples, seed, options, stages
/// and config; every shard of `1..=N` present once; every sample index once) and merges them:
/// the whole run's meta-data (shard `(1, 1)`) and its records sorted by sample index, exactly
/// those the unsharded run gives.
///
/// # Errors
/// [`Error::Invalid`] naming the part's origin and what does not match, or `shards` for a
/// missing or repeated shard or sample; `shards` if `parts` is empty.
pub fn merge_parts(parts: Vec<Part>) -> Result<(ShardMeta, Vec<SampleRecord>)> {
    let Some(first) = parts.first() else {
        return Err(Error::invalid(
            "shards",
            "none",
            "must be at least one shard",
        ));
    };
    let (first_meta, first_origin) = (first.meta.clone(), first.origin.clone());
    let n = first_meta.plan.shard.1;
    let total = first_meta.plan.samples;
    let mut seen = Vec::with_capacity(parts.len());
    let mut records = Vec::new();
    for p in parts {
        let mut a = first_meta.clone();
        a.plan.shard.0 = p.meta.plan.shard.0;
        if a != p.meta {
            return Err(Error::invalid(
                p.origin,
                format!("shard {}/{}", p.meta.plan.shard.0, p.meta.plan.shard.1),
                format!(
                    "belongs to another run than {first_origin} (samples, seed, options, \
                     stages, config and version must match)"
                ),
            ));
        }
        seen.push(p.meta.plan.shard.0);
        records.extend(p.records);
    }
    seen.sort_unstable();
    if seen != (1..=n).collect::<Vec<_>>() {
        return Err(Error::invalid(
            "shards",
            format!("{seen:?} of {n}"),
            format!("must be every shard 1..={n} once"),
        ));
    }
    records.sort_by_key(|r| r.sample);
    if records.len() != total || records.iter().enumerate().any(|(i, r)| r.sample != i) {
        return Err(Error::invalid(
            "shards",
            format!("{} sample records", records.len()),
            format!("must hold every sample 0..{total} once"),
        ));
    }
    let mut meta = first_meta;
    meta.plan.shard = (1, 1);
    Ok((meta, records))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::montecarlo::records_csv;

    /// Records of samples `range` whose values are awkward floats (thirds, tiny and huge).
    fn records(range: std::ops::Range<usize>) -> Vec<SampleRecord> {
        range
            .map(|i| SampleRecord {
                sample: i,
                status: if i % 3 == 2 {
                    "failed: no equilibrium".into()
                } else {
                    "ok".into()
                },
                points: (0..3)
                    .map(|k| {
                        let v: Vec<f64> = (0..ACCURACY.len())
                            .map(|q| (i * 7 + k * 3 + q) as f64 / 3.0 * 10f64.powi(q as i32 - 6))
                            .collect();
                        AccuracyPoint::from_accuracy(2500.0 * k as f64, &v)
                    })
                    .collect(),
                accuracy_life_h: (i % 2 == 0).then_some(12_345.678_9 / (i + 1) as f64),
                limited_by: (i % 2 == 0).then(|| "lost_motion_arcmin".to_string()),
                censored_h: (i % 2 == 1 && i % 3 != 2).then_some(75_000.0 / (i + 1) as f64),
            })
            .collect()
    }

    /// A `samples.csv` of an earlier version, without `censored_h`, is read with no censoring
    /// times (its samples within spec are censored at the run's horizon, as that version did).
    #[test]
    fn samples_without_censoring_times_are_read() {
        let samples =
            "sample,status,accuracy_life_h,limited_by\n0,ok,1234.5,lost_motion_arcmin\n1,ok,,\n";
        let r = parse_records(("samples.csv", samples), ("stages.csv", "sample,hours\n")).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].accuracy_life_h, Some(1234.5));
        assert_eq!((r[1].accuracy_life_h, r[1].censored_h), (None, None));
        // This version's records round-trip with theirs.
        let mine = records(0..6);
        let (s, t) = records_csv(&mine);
        let back = parse_records(("samples.csv", &s), ("stages.csv", &t)).unwrap();
        for (a, b) in mine.iter().zip(&back) {
            assert_eq!(a.censored_h, b.censored_h);
        }
        assert!(mine.iter().any(|m| m.censored_h.is_some()));
    }

    fn part(k: usize, n: usize, samples: usize, seed: u64) -> Part {
        let plan = Plan {
            samples,
            seed,
            shard: (k, n),
            full_wear: false,
            samples_per_mesh_cycle: 16,
        };
        let rs = records(plan.indices());
        let (s, t) = records_csv(&rs);
        Part {
            origin: format!("part {k}"),
            meta: ShardMeta {
                rvlife_version: "0".into(),
                plan,
                stage_hours: vec![0.0, 2500.0, 5000.0],
                config_toml: "[reducer]\n".into(),
            },
            records: parse_records(("samples.csv", &s), ("stages.csv", &t)).unwrap(),
        }
    }

    #[test]
    fn records_read_back_from_their_tables_have_the_same_bits() {
        let rs = records(0..7);
        let (s, t) = records_csv(&rs);
        assert_eq!(parse_records(("s", &s), ("t", &t)).unwrap(), rs);
    }

    #[test]
    fn parts_in_any_order_merge_into_the_whole_run() {
        let whole = records(0..11);
        for n in 1..=5 {
            let mut parts: Vec<Part> = (1..=n).map(|k| part(k, n, 11, 3)).collect();
            parts.reverse();
            let (meta, merged) = merge_parts(parts).unwrap();
            assert_eq!(meta.plan.shard, (1, 1));
            assert_eq!(merged, whole, "{n} parts");
        }
    }

    #[test]
    fn parts_of_another_run_or_missing_ones_are_refused_by_name() {
        let key = |r: Result<(ShardMeta, Vec<SampleRecord>)>| match r {
            Err(Error::Invalid { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(
            key(merge_parts(vec![part(1, 2, 8, 3), part(2, 2, 8, 4)])),
            "part 2"
        );
        assert_eq!(key(merge_parts(vec![part(1, 2, 8, 3)])), "shards");
        assert_eq!(
            key(merge_parts(vec![part(1, 2, 8, 3), part(1, 2, 8, 3)])),
            "shards"
        );
        assert_eq!(key(merge_parts(Vec::new())), "shards");
        let mut short = part(2, 2, 8, 3);
        short.records.pop();
        assert_eq!(key(merge_parts(vec![part(1, 2, 8, 3), short])), "shards");
    }

    #[test]
    fn a_table_with_a_number_that_is_not_finite_is_refused() {
        let (s, t) = records_csv(&records(0..2));
        let t = t.replacen("2500", "NaN", 1);
        assert!(parse_records(("s", &s), ("stages.csv", &t)).is_err());
    }
}
