//! The keys of a config as a form shows them (the web page's editor): every key the text sets
//! or names in a commented-out line, grouped by its section, with its value, the comment the
//! text gives it, and the unit and allowed range the validator checks it against.
//!
//! The ranges are not a second copy of the validator's: [`keys`] runs the validation of the
//! text and records every range it checks (`range::recording`), so a form shows exactly the
//! range of the message a bad value gets. A key the validation does not read for this config
//! (a disabled section's, a key of another model) has no range.

use serde::Serialize;
use serde_json::Value as Json;

pub use super::range::Checked;
use super::Config;
use crate::error::Result;

/// One key of a config, for a form.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct KeyDoc {
    /// The section's dotted name (`cycloid.modification`; empty for top-level keys).
    pub section: String,
    /// The dotted key (`cycloid.modification.offset_mm`).
    pub key: String,
    /// The value the text sets (its JSON form), or `None` if it only names the key in a
    /// commented-out line (the key then takes its default).
    pub value: Option<Json>,
    /// The value of the commented-out line (`# crank_disc_roller_diameter_mm = 4.05`), as
    /// written: the default or an example.
    pub commented: Option<String>,
    /// The text's comment on the key (its trailing comment and the indented comment lines
    /// that continue it), without the `#`.
    pub comment: String,
    /// The unit of the key: the validator's, else read off the key's name (`_mm`: mm).
    pub unit: String,
    /// The allowed range in the words of the validator's message, if the validation of this
    /// config checks the key.
    pub allowed: Option<String>,
}

/// A key's unit from its name's suffix (the config's convention: units in the key names).
fn unit_of(key: &str) -> &'static str {
    const SUFFIXES: &[(&str, &str)] = &[
        ("_n_per_um", "N/um"),
        ("_nm_per_rad", "N m/rad"),
        ("_nm_per_arcmin", "N m/arcmin"),
        ("_mm3_per_n_m", "mm^3/(N m)"),
        ("_m2_per_n", "m^2/N"),
        ("_mm", "mm"),
        ("_um", "um"),
        ("_deg", "deg"),
        ("_arcmin", "arcmin"),
        ("_nm", "N m"),
        ("_n", "N"),
        ("_rpm", "rpm"),
        ("_gpa", "GPa"),
        ("_mpa", "MPa"),
        ("_h", "h"),
        ("_s", "s"),
        ("_hz", "Hz"),
        ("_kg", "kg"),
        ("_min", "min"),
    ];
    SUFFIXES
        .iter()
        .find(|(s, _)| key.ends_with(s))
        .map_or("", |(_, u)| u)
}

/// A `[section]` or `[[section]]` header's name.
fn header(line: &str) -> Option<String> {
    let t = line.trim();
    let inner = t.strip_prefix('[')?.split(']').next()?;
    Some(inner.trim_start_matches('[').trim().to_string())
}

/// `name = value  # comment` (`commented`: after a leading `#`): the name, the value text and
/// the comment.
fn key_line(line: &str, commented: bool) -> Option<(String, String, String)> {
    let mut t = line.trim_start();
    if commented {
        t = t.strip_prefix('#')?.trim_start();
    }
    let (name, rest) = t.split_once('=')?;
    let name = name.trim();
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    {
        return None;
    }
    let (value, comment) = match rest.find(" #") {
        Some(i) => (&rest[..i], rest[i + 2..].trim()),
        None => (rest, ""),
    };
    let value = value.trim();
    // A commented line is a key only if its value parses as TOML.
    if commented && format!("v = {value}").parse::<toml::Table>().is_err() {
        return None;
    }
    Some((name.to_string(), value.to_string(), comment.to_string()))
}

/// The JSON value at dotted `key` of `json`.
fn at<'a>(json: &'a Json, key: &str) -> Option<&'a Json> {
    key.split('.').try_fold(json, |v, k| v.get(k))
}

/// The keys of the config `text` (read as from `origin`), in the text's order, each with its
/// section, value, comment, unit and allowed range ([`KeyDoc`]), and the result of `validate`
/// on the parsed config: the ranges are those its checks record, so a caller that validates
/// the text anyway (the web page: `crate::api::validated`, with the work budget) passes its own
/// validation and runs it once. Keys of inline tables and arrays of tables are listed as one
/// key holding the whole value.
///
/// # Errors
/// [`crate::Error::Config`] if the text does not parse (syntax, types, unknown keys). A value
/// out of range is not an error here: the key is listed, its range recorded as far as the
/// validation got, and the validation's error returned beside the keys.
pub fn keys<T>(
    text: &str,
    origin: &str,
    validate: impl FnOnce(&Config) -> T,
) -> Result<(Vec<KeyDoc>, T)> {
    let json = super::edit::to_json(text, origin)?;
    let config = Config::from_toml_in(text, origin, None)?;
    let (validated, checked) = super::range::recording(|| validate(&config));
    let mut out: Vec<KeyDoc> = Vec::new();
    let mut section = String::new();
    let mut last: Option<usize> = None;
    for line in text.lines() {
        let t = line.trim_start();
        if let Some(h) = header(line) {
            section = h;
            last = None;
            continue;
        }
        let indented = line.starts_with(char::is_whitespace);
        let parsed = key_line(line, false)
            .map(|k| (k, false))
            .or_else(|| key_line(line, true).map(|k| (k, true)));
        match parsed {
            Some(((name, value, comment), commented)) if !(indented && commented) => {
                let key = if section.is_empty() {
                    name.clone()
                } else {
                    format!("{section}.{name}")
                };
                if out.iter().any(|k| k.key == key) {
                    last = None;
                    continue;
                }
                let check = checked.iter().find(|c| c.key == key);
                out.push(KeyDoc {
                    section: section.clone(),
                    value: if commented {
                        None
                    } else {
                        at(&json, &key).cloned()
                    },
                    commented: commented.then_some(value),
                    comment,
                    unit: check
                        .map(|c| c.unit.clone())
                        .filter(|u| !u.is_empty())
                        .unwrap_or_else(|| unit_of(&name).to_string()),
                    allowed: check.map(|c| c.allowed.clone()),
                    key,
                });
                last = Some(out.len() - 1);
            }
            _ => match (last, t.strip_prefix('#')) {
                // An indented comment line continues the last key's comment.
                (Some(i), Some(more)) if indented => {
                    let c = &mut out[i].comment;
                    if !c.is_empty() {
                        c.push(' ');
                    }
                    c.push_str(more.trim());
                }
                _ => last = None,
            },
        }
    }
    Ok((out, validated))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{preset_text, PRESETS};

    #[test]
    fn every_key_the_example_sets_is_listed_with_its_value_and_range() {
        let text = crate::config::EXAMPLE_TOML;
        let (keys, model) = keys(text, "<built-in>", Config::validate).unwrap();
        assert!(model.is_ok());
        let e = keys
            .iter()
            .find(|k| k.key == "cycloid.eccentricity_mm")
            .unwrap();
        assert_eq!(e.section, "cycloid");
        assert_eq!(e.value, Some(serde_json::json!(1.3)));
        assert_eq!(e.unit, "mm");
        assert_eq!(e.comment, "a");
        // The range is the validator's: the message of a bad value carries the same words.
        let allowed = e.allowed.clone().unwrap();
        let bad = crate::config::edit::set(
            text,
            "<built-in>",
            &[(
                "cycloid.eccentricity_mm".into(),
                Some(serde_json::json!(-1.0)),
            )],
        )
        .unwrap();
        let err = Config::from_toml_in(&bad, "<built-in>", None)
            .unwrap()
            .validate()
            .unwrap_err()
            .to_string();
        assert!(err.contains(&allowed), "{err} / {allowed}");
        // A commented-out key: no value, its line's value and its continued comment.
        let d = keys
            .iter()
            .find(|k| k.key == "reducer.bearings.crank_disc_roller_diameter_mm")
            .unwrap();
        assert_eq!(d.value, None);
        assert_eq!(d.commented.as_deref(), Some("2.83"));
        assert!(
            d.comment.starts_with("default: the needles filling"),
            "{}",
            d.comment
        );
        assert!(d.comment.ends_with("not their stiffness"), "{}", d.comment);
        assert_eq!(d.unit, "mm");
        // Every key every preset sets is listed, with the value the config holds.
        for p in PRESETS {
            let text = preset_text(p.name).unwrap();
            let json = crate::config::edit::to_json(&text, p.name).unwrap();
            let (keys, _) = super::keys(&text, p.name, Config::validate).unwrap();
            let mut n = 0;
            fn leaves(prefix: &str, v: &Json, out: &mut Vec<String>) {
                match v.as_object() {
                    Some(o) if !o.is_empty() => {
                        for (k, x) in o {
                            let key = if prefix.is_empty() {
                                k.clone()
                            } else {
                                format!("{prefix}.{k}")
                            };
                            leaves(&key, x, out);
                        }
                    }
                    _ => out.push(prefix.to_string()),
                }
            }
            let mut all = Vec::new();
            leaves("", &json, &mut all);
            for key in &all {
                let listed = keys
                    .iter()
                    .find(|k| k.key == *key || key.starts_with(&format!("{}.", k.key)));
                assert!(listed.is_some(), "{}: {key} not listed", p.name);
                n += 1;
            }
            assert!(n > 50, "{}: {n} keys", p.name);
            // Most numeric keys carry the validator's range.
            let ranged = keys.iter().filter(|k| k.allowed.is_some()).count();
            assert!(ranged > 40, "{}: {ranged} keys with a range", p.name);
        }
    }
}
