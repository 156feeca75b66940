//! `rvlife sweep`: the designs of `--vary`, one study each, and the console's table.

use std::path::{Path, PathBuf};

use rvlife::config::Config;
use rvlife::Result;

use crate::{progress_bar, progress_to};

/// The config text of `config` (the built-in example without one), where it came from, and
/// the directory its relative paths start from.
///
/// # Errors
/// [`rvlife::Error::Io`] if the file cannot be read.
pub(crate) fn config_text(config: Option<&Path>) -> Result<(String, String, Option<PathBuf>)> {
    Ok(match config {
        Some(p) => (
            Config::read_text(p)?,
            p.display().to_string(),
            p.parent().map(Path::to_path_buf),
        ),
        None => (
            rvlife::config::EXAMPLE_TOML.to_string(),
            "<built-in>".to_string(),
            None,
        ),
    })
}

/// `rvlife sweep`: every design is built and validated, and the whole sweep's work checked,
/// before the first study runs.
pub(crate) fn sweep(
    config: Option<&Path>,
    budget: f64,
    vary: &[String],
    set: &[String],
    out: &Path,
    force: bool,
) -> Result<()> {
    use rvlife::sweep::{designs, parse_value, Vary};
    let (text, origin, base_dir) = config_text(config)?;
    let varies = vary
        .iter()
        .map(|v| Vary::parse("--vary", v))
        .collect::<Result<Vec<_>>>()?;
    let sets = set
        .iter()
        .map(|s| match s.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => {
                Ok((k.trim().to_string(), parse_value("--set", s, v)?))
            }
            _ => Err(rvlife::Error::invalid(
                "--set",
                s,
                "KEY=VALUE (dynamics.enabled=false)",
            )),
        })
        .collect::<Result<Vec<_>>>()?;
    let designs = designs(&text, &origin, base_dir.as_deref(), &sets, &varies, budget)?;
    let staging = rvlife::output::Staging::prepare(out, force)?;
    let pb = progress_bar(designs.len() as u64);
    pb.set_message("designs");
    let start = std::time::Instant::now();
    let outcomes = rvlife::sweep::run(designs, &progress_to(&pb));
    pb.set_message("writing");
    staging.commit(|dir| rvlife::output::sweep::write_files(dir, &varies, &outcomes))?;
    pb.finish_and_clear();
    let failed = outcomes.iter().filter(|o| o.study.is_err()).count();
    say!(
        "rvlife sweep: {} designs ({failed} failed), {:.2} s; results in {}",
        outcomes.len(),
        start.elapsed().as_secs_f64(),
        out.display()
    );
    let keys: Vec<String> = varies
        .iter()
        .map(|v| format!("{:>14}", short_key(&v.key)))
        .collect();
    say!(
        "{:>6} {} {:>12} {}",
        "design",
        keys.join(" "),
        "life_h",
        "limited by / status"
    );
    for o in &outcomes {
        let vals: Vec<String> = o
            .design
            .values
            .iter()
            .map(|(_, v)| format!("{:>14}", v.to_string().trim_matches('"')))
            .collect();
        let (life, by) = match &o.study {
            Ok(s) => match &s.life {
                Some(l) => (
                    l.accuracy_life_h
                        .map_or(format!("> {:.0}", l.horizon_h), |h| format!("{h:.0}")),
                    l.limited_by.unwrap_or("within spec").to_string(),
                ),
                None => ("-".to_string(), "no spec".to_string()),
            },
            Err(e) => ("-".to_string(), format!("failed: {e}")),
        };
        say!(
            "{:>6} {} {:>12} {}",
            o.design.index,
            vals.join(" "),
            life,
            by
        );
    }
    Ok(())
}

/// The last part of a dotted key (the column header of the sweep's console table).
pub(crate) fn short_key(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}
