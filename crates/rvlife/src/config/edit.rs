//! Editing a config's TOML text by key, its comments and layout kept (docs/config.md,
//! "Editing a config"): what the Python package's `Config.replace` and `Config.from_dict`, and
//! the design sweep's `--vary` and `--set`, do to a config.
//!
//! - [`set`]: each dotted key (`cycloid.eccentricity_mm`) gets its value whole; a missing
//!   section on its path is created; `null` removes the key (back to its default).
//! - [`merge`]: a nested patch (`{"cycloid": {"eccentricity_mm": 1.2}}`) merged over the text
//!   as a JSON merge patch (RFC 7396): objects merge key by key into the sections and inline
//!   tables they name, anything else replaces the value, `null` removes it.
//!
//! A number keeps the type of the value it replaces: a whole number written over an integer
//! (`cycloid.pins = 38.0`) stays an integer, an integer written over a float becomes one.
//! After each key the text is parsed again ([`Config`]'s structure, not yet its ranges), so
//! an unknown key or a value of the wrong type is refused naming the dotted key as written;
//! the ranges are checked when the edited config is validated.

use serde_json::Value as Json;
use toml_edit::{Array, DocumentMut, InlineTable, Item, Table, TableLike, Value};

use super::Config;
use crate::error::{Error, Result};

/// The parts of a dotted key, each non-empty lower-case ASCII letters, digits and `_`.
///
/// # Errors
/// [`Error::Invalid`] naming `key` otherwise.
fn parts(key: &str) -> Result<Vec<&str>> {
    let ps: Vec<&str> = key.split('.').collect();
    let ok = ps.iter().all(|p| {
        !p.is_empty()
            && p.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
    });
    if ok {
        Ok(ps)
    } else {
        Err(Error::invalid(
            key,
            "(the key)",
            "a dotted key of the config: sections and key joined by `.`, each part lower-case \
             letters, digits and `_` (`cycloid.eccentricity_mm`)",
        ))
    }
}

/// `v` as a TOML value, a number taking the type of `like` (the value it replaces) where it
/// can ([module documentation](self)).
///
/// # Errors
/// A `null` inside an array or a table (TOML has none), described for the caller's message.
fn toml_value(v: &Json, like: Option<&Value>) -> std::result::Result<Value, String> {
    Ok(match v {
        Json::Null => return Err("null inside an array or a table (TOML has no null)".into()),
        Json::Bool(b) => Value::from(*b),
        Json::Number(n) => {
            let whole = n.as_i64().or_else(|| {
                n.as_f64()
                    .filter(|x| x.fract() == 0.0 && x.abs() < 9e15)
                    .map(|x| x as i64)
            });
            match (like, whole) {
                (Some(Value::Float(_)), _) | (_, None) => {
                    Value::from(n.as_f64().ok_or("a number out of range")?)
                }
                (Some(Value::Integer(_)), Some(i)) => Value::from(i),
                (_, Some(i)) if n.is_i64() || n.is_u64() => Value::from(i),
                _ => Value::from(n.as_f64().ok_or("a number out of range")?),
            }
        }
        Json::String(s) => Value::from(s.as_str()),
        Json::Array(a) => {
            let first = match like {
                Some(Value::Array(x)) => x.get(0),
                _ => None,
            };
            let mut arr = Array::new();
            for x in a {
                arr.push(toml_value(x, first)?);
            }
            Value::Array(arr)
        }
        Json::Object(m) => {
            let mut t = InlineTable::new();
            for (k, x) in m {
                let like = match like {
                    Some(Value::InlineTable(old)) => old.get(k),
                    _ => None,
                };
                t.insert(k, toml_value(x, like)?);
            }
            Value::InlineTable(t)
        }
    })
}

/// Sets `path` in `root` to `v` (`None`: removes it), creating missing sections on the way
/// (inline tables inside an inline table) and keeping the replaced value's trailing comment.
fn set_in(
    root: &mut dyn TableLike,
    path: &[&str],
    v: Option<&Json>,
) -> std::result::Result<(), String> {
    let (last, head) = path.split_last().ok_or("an empty key")?;
    let mut table: &mut dyn TableLike = root;
    let mut inline = false;
    for p in head {
        if table.get(p).is_none() {
            if v.is_none() {
                return Ok(());
            }
            let item = if inline {
                Item::Value(Value::InlineTable(InlineTable::new()))
            } else {
                let mut t = Table::new();
                t.set_implicit(true);
                Item::Table(t)
            };
            table.insert(p, item);
        }
        let item = table.get_mut(p).ok_or("a section that vanished")?;
        inline |= item.is_inline_table();
        table = item
            .as_table_like_mut()
            .ok_or_else(|| format!("`{p}` is a value, not a section"))?;
    }
    match v {
        None => {
            table.remove(last);
        }
        Some(v) => {
            let old = table.get(last).and_then(Item::as_value).cloned();
            let mut new = toml_value(v, old.as_ref())?;
            if let Some(old) = &old {
                *new.decor_mut() = old.decor().clone();
            }
            match table.get_mut(last) {
                Some(item) if item.is_value() => *item = Item::Value(new),
                _ => {
                    table.insert(last, Item::Value(new));
                }
            }
        }
    }
    Ok(())
}

/// A JSON value as the user wrote it, for messages (`1.2`, `"rollers"`, `null`).
fn shown(v: Option<&Json>) -> String {
    v.map_or("null".to_string(), Json::to_string)
}

/// `text` with each dotted key of `edits` set to its value (`None`: removed) in turn, its
/// comments and layout kept ([module documentation](self)).
///
/// # Errors
/// [`Error::Config`] if `text` is not TOML; [`Error::Invalid`] naming the dotted key whose
/// edit leaves a text that is not a config (an unknown key, a value of the wrong type, a
/// key inside a value), with the value and the parser's reason.
pub fn set(text: &str, origin: &str, edits: &[(String, Option<Json>)]) -> Result<String> {
    apply(document(text, origin)?, origin, edits)
}

/// The TOML document of `text`, for editing.
///
/// # Errors
/// [`Error::Config`] if `text` is not TOML.
fn document(text: &str, origin: &str) -> Result<DocumentMut> {
    text.parse()
        .map_err(|e: toml_edit::TomlError| Error::Config {
            path: origin.into(),
            message: e.to_string().trim().to_string(),
        })
}

/// [`set`] on the parsed document `doc`.
fn apply(mut doc: DocumentMut, origin: &str, edits: &[(String, Option<Json>)]) -> Result<String> {
    let sections: Vec<String> = doc.as_table().iter().map(|(k, _)| k.to_string()).collect();
    for (key, v) in edits {
        let path = parts(key)?;
        let refuse = |why: String| Error::invalid(key.as_str(), shown(v.as_ref()), why);
        set_in(doc.as_table_mut(), &path, v.as_ref()).map_err(&refuse)?;
        if let Err(e) = Config::from_toml_str(&doc.to_string(), origin) {
            let why = match e {
                Error::Config { message, .. } => message,
                other => other.to_string(),
            };
            return Err(refuse(format!(
                "a key of the config with a value of its type ({why})"
            )));
        }
    }
    // A new section goes after the text's trailing comments, which belong to the last
    // section before it (commented-out keys of `[life]`, say).
    let trailing = doc.trailing().as_str().unwrap_or_default().to_string();
    let new = doc
        .as_table()
        .iter()
        .find(|(k, i)| i.is_table() && !sections.iter().any(|s| s == k))
        .map(|(k, _)| k.to_string());
    if let (Some(k), false) = (new, trailing.trim().is_empty()) {
        if let Some(t) = doc.get_mut(&k).and_then(Item::as_table_mut) {
            t.decor_mut()
                .set_prefix(format!("{}\n\n", trailing.trim_end()));
            doc.set_trailing("");
        }
    }
    Ok(doc.to_string())
}

/// The dotted edits of a JSON merge patch over `doc`: objects recurse into the sections and
/// inline tables they name, anything else is one edit.
fn flatten(
    doc: &dyn TableLike,
    prefix: &str,
    patch: &serde_json::Map<String, Json>,
    out: &mut Vec<(String, Option<Json>)>,
) {
    for (k, v) in patch {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match (v, doc.get(k).and_then(Item::as_table_like)) {
            (Json::Object(sub), Some(t)) => flatten(t, &key, sub, out),
            (Json::Null, _) => out.push((key, None)),
            _ => out.push((key, Some(v.clone()))),
        }
    }
}

/// `text` with the nested `patch` merged over it (a JSON merge patch, RFC 7396; [module
/// documentation](self)), comments and layout kept.
///
/// # Errors
/// As [`set`]; [`Error::Invalid`] if `patch` is not an object of sections.
pub fn merge(text: &str, origin: &str, patch: &Json) -> Result<String> {
    let Json::Object(m) = patch else {
        return Err(Error::invalid(
            "config",
            shown(Some(patch)),
            "a dict of sections ({\"cycloid\": {\"eccentricity_mm\": 1.2}})",
        ));
    };
    let doc = document(text, origin)?;
    let mut edits = Vec::new();
    flatten(doc.as_table(), "", m, &mut edits);
    apply(doc, origin, &edits)
}

/// The config text as a JSON object (its sections as objects; what `Config.to_dict` gives).
///
/// # Errors
/// [`Error::Config`] if `text` is not TOML.
pub fn to_json(text: &str, origin: &str) -> Result<Json> {
    let t: toml::Table = text.parse().map_err(|e: toml::de::Error| Error::Config {
        path: origin.into(),
        message: e.to_string().trim().to_string(),
    })?;
    serde_json::to_value(&t).map_err(|e| Error::numerical("config as JSON", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    const EX: &str = super::super::EXAMPLE_TOML;

    fn edit(k: &str, v: Json) -> (String, Option<Json>) {
        (k.to_string(), Some(v))
    }

    #[test]
    fn a_set_key_changes_that_value_only_and_keeps_the_comments() {
        let t = set(EX, "<ex>", &[edit("cycloid.eccentricity_mm", json!(1.2))]).unwrap();
        assert!(t.contains("eccentricity_mm = 1.2"), "{t}");
        assert!(
            t.contains("# a\n") || t.contains("# a\r\n"),
            "the trailing comment is kept"
        );
        let (a, b) = (to_json(EX, "a").unwrap(), to_json(&t, "b").unwrap());
        let mut a2 = a.clone();
        a2["cycloid"]["eccentricity_mm"] = json!(1.2);
        assert_eq!(a2, b);
        // Lines other than the edited one are unchanged.
        let changed = EX.lines().zip(t.lines()).filter(|(x, y)| x != y).count();
        assert_eq!(changed, 1);
        assert_eq!(EX.lines().count(), t.lines().count());
    }

    #[test]
    fn numbers_keep_the_type_they_replace() {
        let t = set(
            EX,
            "<ex>",
            &[
                edit("cycloid.pins", json!(38.0)),
                edit("cycloid.eccentricity_mm", json!(1)),
            ],
        )
        .unwrap();
        let v = to_json(&t, "t").unwrap();
        assert_eq!(v["cycloid"]["pins"], json!(38));
        assert!(v["cycloid"]["eccentricity_mm"].is_f64());
    }

    #[test]
    fn unknown_keys_and_wrong_types_name_the_dotted_key() {
        for (k, v) in [
            ("cycloid.eccentricty_mm", json!(1.2)),
            ("cycloid.pins", json!("forty")),
            ("cycloid.pins.count", json!(3)),
            ("nosuch.key", json!(1)),
            ("Cycloid.pins", json!(3)),
        ] {
            let e = set(EX, "<ex>", &[edit(k, v)]).unwrap_err().to_string();
            assert!(e.contains(k), "{k}: {e}");
        }
    }

    #[test]
    fn a_merge_patch_recurses_into_sections_and_null_removes() {
        let p = json!({"cycloid": {"eccentricity_mm": 1.25, "modification": {"offset_mm": 0.005}},
                       "tolerances": {"pin_radius_um": {"iso_grade": 6}, "rotation_arcmin": null},
                       "errors": {"crank_phase_arcmin": [0.5, -0.5]}});
        let t = merge(EX, "<ex>", &p).unwrap();
        let v = to_json(&t, "t").unwrap();
        assert_eq!(v["cycloid"]["eccentricity_mm"], json!(1.25));
        assert_eq!(v["cycloid"]["modification"]["offset_mm"], json!(0.005));
        assert_eq!(v["cycloid"]["modification"]["equidistant_mm"], json!(0.01));
        assert_eq!(v["tolerances"]["pin_radius_um"], json!({"iso_grade": 6}));
        assert!(v["tolerances"].get("rotation_arcmin").is_none());
        assert_eq!(v["errors"]["crank_phase_arcmin"], json!([0.5, -0.5]));
        if let Err(e) = Config::from_toml_str(&t, "t").unwrap().validate() {
            panic!("{e}");
        }
    }
}
