//! The library's structure, checked from its sources (`cargo test -p rvlife --test layers`):
//!
//! - the top-level modules form layers ([`LAYERS`], described in `docs/architecture.md`): a
//!   module refers only to modules of lower layers, so there is no import circle between them
//!   and the study's path from the config to the solvers only goes down;
//! - within a module, its files refer to each other without a circle (a `mod.rs` that
//!   re-exports its children, `pub use child::...`, is the module's front, not a use);
//! - no source file under `crates/` exceeds [`MAX_LINES`] lines;
//! - every citation of the model document, `docs/model.md section N`, names a section that
//!   exists, and nothing cites a document outside the repository.
//!
//! References are read as text: every path through `crate::`, `super::`, `self::` or a child
//! module, outside comments and string literals (method calls are not paths, so they are not
//! seen; the layers of the types they act on are).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's modules from the bottom layer up: a module may refer only to modules of
/// lower layers (`crate::Result` and `crate::Error`, re-exported at the root, are `error`'s).
const LAYERS: &[&[&str]] = &[
    &["error", "units", "quantities", "input"],
    &["geometry"],
    &["contact"],
    &["reducer"],
    &["statics"],
    &["tribology"],
    &["te"],
    &["budget", "fem"],
    &["dynamics"],
    &["wear"],
    &["config", "efficiency"],
    &["life"],
    &["study", "montecarlo"],
    &["calibration", "sensitivity", "sweep"],
    &["optimize"],
    &["output"],
    &["api"],
];

/// Longest source file, lines.
const MAX_LINES: usize = 1200;

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn repo_dir() -> PathBuf {
    crate_dir().join("../..")
}

/// Every file under `dir` whose name ends with one of `exts`, skipping build output and
/// dependencies.
fn files(dir: &Path, exts: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if p.is_dir() {
                if !matches!(name, "target" | "node_modules" | ".git" | "__pycache__")
                    && !name.starts_with('.')
                {
                    stack.push(p);
                }
            } else if exts.iter().any(|x| name.ends_with(x)) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The text of Rust code with comments and the contents of string and character literals
/// blanked (line breaks kept).
fn code_only(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied().unwrap_or('\0');
        if c == '/' && next == '/' {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == '*' {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if b[i] == '\n' {
                        out.push('\n');
                    }
                    i += 1;
                }
            }
        } else if c == 'r' && (next == '"' || next == '#') && !is_ident(b.get(i.wrapping_sub(1))) {
            // Raw string r"..." or r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            out.push_str("\"\"");
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                if b[j] == '\n' {
                    out.push('\n');
                }
                j += 1;
            }
            i = j;
        } else if c == '"' {
            out.push_str("\"\"");
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                if b.get(i) == Some(&'\n') {
                    out.push('\n');
                }
                i += 1;
            }
            i += 1;
        } else if c == '\'' && next != '\0' && b.get(i + 2) == Some(&'\'') {
            out.push_str("' '");
            i += 3;
        } else if c == '\'' && next == '\\' {
            out.push_str("' '");
            i += 2;
            while i < b.len() && b[i] != '\'' {
                i += 1;
            }
            i += 1;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn is_ident(c: Option<&char>) -> bool {
    c.is_some_and(|c| c.is_alphanumeric() || *c == '_')
}

/// The module path of a source file (`src/config/reducer.rs` is `config::reducer`, a
/// `mod.rs` its folder's module, `lib.rs` the root).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// Statements `pub use ...;` (and `pub(crate) use ...;`) removed: a module's front, not a use.
fn without_reexports(code: &str) -> String {
    without_statements(&without_statements(code, "pub use "), "pub(crate) use ")
}

/// The statements starting with `start` (at the start of a line) removed, line breaks kept.
fn without_statements(code: &str, start: &str) -> String {
    let mut out = String::new();
    let mut rest = code;
    while let Some(i) = rest.find(start) {
        let at_start = rest[..i]
            .chars()
            .rev()
            .take_while(|c| *c != '\n')
            .all(char::is_whitespace);
        if !at_start {
            out.push_str(&rest[..i + start.len()]);
            rest = &rest[i + start.len()..];
            continue;
        }
        out.push_str(&rest[..i]);
        let end = rest[i..].find(';').map_or(rest.len(), |j| i + j + 1);
        out.extend(rest[i..end].chars().filter(|c| *c == '\n'));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The identifiers that start each path in `s` after `prefix` (`crate::`): `a` of `a::b`,
/// and every first segment of a group `{a::x, b}`.
fn heads_after(code: &str, prefix: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find(prefix) {
        let before = rest[..i].chars().last();
        let after = &rest[i + prefix.len()..];
        rest = after;
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        out.extend(paths_from(after));
    }
    out
}

/// The paths (segments) starting at `s`: one path `a::b::c`, or a group `{...}` of them.
fn paths_from(s: &str) -> Vec<Vec<String>> {
    let s = s.trim_start();
    if let Some(group) = s.strip_prefix('{') {
        let mut depth = 0;
        let mut item = String::new();
        let mut items = Vec::new();
        for c in group.chars() {
            match c {
                '{' => {
                    depth += 1;
                    item.push(c);
                }
                '}' if depth == 0 => {
                    items.push(std::mem::take(&mut item));
                    break;
                }
                '}' => {
                    depth -= 1;
                    item.push(c);
                }
                ',' if depth == 0 => items.push(std::mem::take(&mut item)),
                _ => item.push(c),
            }
        }
        return items
            .iter()
            .filter(|i| !i.trim().is_empty())
            .flat_map(|i| paths_from(i))
            .collect();
    }
    let mut segs = Vec::new();
    let mut rest = s;
    loop {
        let ident: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if ident.is_empty() {
            break;
        }
        rest = &rest[ident.len()..];
        segs.push(ident);
        match rest.strip_prefix("::") {
            Some(r) if !r.starts_with('{') => rest = r,
            Some(r) => {
                return paths_from(r)
                    .into_iter()
                    .map(|p| segs.iter().cloned().chain(p).collect())
                    .collect()
            }
            None => break,
        }
    }
    if segs.is_empty() {
        Vec::new()
    } else {
        vec![segs]
    }
}

/// The module paths a file refers to.
fn references(
    module: &[String],
    code: &str,
    modules: &BTreeSet<Vec<String>>,
) -> BTreeSet<Vec<String>> {
    let code = without_reexports(code);
    let resolve = |base: Vec<String>, rest: &[String]| -> Vec<String> {
        let mut full = base;
        full.extend(rest.iter().cloned());
        while !full.is_empty() && !modules.contains(&full) {
            full.pop();
        }
        full
    };
    let mut out = BTreeSet::new();
    for p in heads_after(&code, "crate::") {
        out.insert(resolve(Vec::new(), &p));
    }
    for p in heads_after(&code, "super::") {
        // `super::super::x`: each `super` climbs one module.
        let ups = 1 + p.iter().take_while(|s| *s == "super").count();
        let rest: Vec<String> = p.iter().skip_while(|s| *s == "super").cloned().collect();
        let base = module[..module.len().saturating_sub(ups)].to_vec();
        out.insert(resolve(base, &rest));
    }
    for p in heads_after(&code, "self::") {
        out.insert(resolve(module.to_vec(), &p));
    }
    // Child modules named directly (`use reducer::Rating;` in `config`).
    let children: Vec<&Vec<String>> = modules
        .iter()
        .filter(|m| m.len() == module.len() + 1 && m.starts_with(module))
        .collect();
    for child in children {
        let name = child.last().unwrap();
        let pat = format!("{name}::");
        for (i, _) in code.match_indices(&pat) {
            let before = code[..i].chars().last();
            if !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                out.insert(child.clone());
            }
        }
    }
    out.remove(module);
    out
}

/// A circle in `edges`, if any (depth-first search).
fn circle(edges: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Option<Vec<Vec<String>>> {
    fn visit(
        n: &Vec<String>,
        edges: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        state: &mut BTreeMap<Vec<String>, u8>,
        path: &mut Vec<Vec<String>>,
    ) -> Option<Vec<Vec<String>>> {
        match state.get(n) {
            Some(2) => return None,
            Some(1) => {
                let i = path.iter().position(|p| p == n).unwrap();
                let mut c = path[i..].to_vec();
                c.push(n.clone());
                return Some(c);
            }
            _ => {}
        }
        state.insert(n.clone(), 1);
        path.push(n.clone());
        for m in edges.get(n).into_iter().flatten() {
            if let Some(c) = visit(m, edges, state, path) {
                return Some(c);
            }
        }
        path.pop();
        state.insert(n.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in edges.keys() {
        if let Some(c) = visit(n, edges, &mut state, &mut Vec::new()) {
            return Some(c);
        }
    }
    None
}

fn show(path: &[String]) -> String {
    if path.is_empty() {
        "crate".into()
    } else {
        path.join("::")
    }
}

#[test]
fn modules_form_layers_without_circles() {
    let src = crate_dir().join("src");
    let sources = files(&src, &[".rs"]);
    let modules: BTreeSet<Vec<String>> = sources.iter().map(|f| module_path(&src, f)).collect();
    let layer = |top: &str| LAYERS.iter().position(|l| l.contains(&top));
    let mut problems = Vec::new();
    let mut within: BTreeMap<String, BTreeMap<Vec<String>, BTreeSet<Vec<String>>>> =
        BTreeMap::new();
    for f in &sources {
        let module = module_path(&src, f);
        let Some(top) = module.first() else {
            continue;
        };
        // The crate's own tests (`src/tests/`) are not its structure.
        if top == "tests" {
            continue;
        }
        let Some(l) = layer(top) else {
            problems.push(format!("module {top} is in no layer of LAYERS"));
            continue;
        };
        let text = std::fs::read_to_string(f).unwrap();
        // Unit tests (`#[cfg(test)]`, at the end of a file) are not the library's structure.
        let library = text.split("#[cfg(test)]").next().unwrap_or("");
        let code = code_only(library);
        for target in references(&module, &code, &modules) {
            let t = target.first().map_or("error", String::as_str);
            if t == top {
                within
                    .entry(top.clone())
                    .or_default()
                    .entry(module.clone())
                    .or_default()
                    .insert(target);
                continue;
            }
            match layer(t) {
                Some(lt) if lt < l => {}
                Some(lt) => problems.push(format!(
                    "{} (layer {l}) refers to {} (layer {lt}): a module may refer only to \
                     lower layers",
                    show(&module),
                    show(&target)
                )),
                None => problems.push(format!("{} refers to unknown {}", show(&module), t)),
            }
        }
    }
    for (top, edges) in &within {
        if let Some(c) = circle(edges) {
            let names: Vec<String> = c.iter().map(|p| show(p)).collect();
            problems.push(format!(
                "files of {top} refer in a circle: {}",
                names.join(" -> ")
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // Every layer's modules exist.
    for l in LAYERS {
        for m in *l {
            assert!(
                modules
                    .iter()
                    .any(|p| p.first().map(String::as_str) == Some(*m)),
                "LAYERS names {m}, which is not a module"
            );
        }
    }
}

#[test]
fn no_source_file_is_longer_than_the_limit() {
    let long: Vec<String> = files(&repo_dir().join("crates"), &[".rs", ".py"])
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).ok()?.lines().count();
            (n > MAX_LINES).then(|| format!("{}: {n} lines", f.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "longer than {MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}

/// The sections `N` of the citations `docs/model.md section N` (and `sections N and M`,
/// `sections N-M`) in `text`.
fn cited_sections(text: &str) -> Vec<u32> {
    let flat = text
        .replace("\n//! ", " ")
        .replace("\n/// ", " ")
        .replace('\n', " ");
    let mut out = Vec::new();
    for (i, _) in flat.match_indices("docs/model.md") {
        let rest = flat[i + "docs/model.md".len()..].trim_start();
        let Some(nums) = rest
            .strip_prefix("sections ")
            .or_else(|| rest.strip_prefix("section "))
        else {
            continue;
        };
        let mut expect_more = true;
        for word in nums.split(' ') {
            let w = word.trim_end_matches([',', ')', ';', '.', ':']);
            if let Some((a, b)) = w.split_once('-') {
                if let (Ok(a), Ok(b)) = (a.parse::<u32>(), b.parse::<u32>()) {
                    out.extend(a..=b);
                    expect_more = false;
                    continue;
                }
            }
            match w.parse::<u32>() {
                Ok(n) if expect_more => {
                    out.push(n);
                    expect_more = false;
                }
                _ if w == "and" || w == "or" => expect_more = true,
                _ => break,
            }
            if word.ends_with(',') {
                expect_more = true;
            }
        }
    }
    out
}

#[test]
fn citations_of_the_model_document_exist_and_stay_in_the_repository() {
    let repo = repo_dir();
    let model = std::fs::read_to_string(repo.join("docs/model.md")).expect("docs/model.md");
    let sections: BTreeSet<u32> = model
        .lines()
        .filter_map(|l| l.strip_prefix("## "))
        .filter_map(|l| l.split('.').next()?.parse().ok())
        .collect();
    assert!(
        sections.len() >= 10,
        "docs/model.md has sections {sections:?}"
    );
    assert!(repo.join("docs/architecture.md").is_file());
    let mut problems = Vec::new();
    let mut citations = 0;
    let mut scanned = files(
        &repo.join("crates"),
        &[".rs", ".py", ".pyi", ".toml", ".md"],
    );
    scanned.extend(files(&repo.join("docs"), &[".md"]));
    scanned.extend(files(&repo.join("scripts"), &[""]));
    scanned.push(repo.join("README.md"));
    scanned.push(repo.join("CHANGELOG.md"));
    for f in &scanned {
        let Ok(text) = std::fs::read_to_string(f) else {
            continue;
        };
        for n in cited_sections(&text) {
            citations += 1;
            if !sections.contains(&n) {
                problems.push(format!("{}: cites docs/model.md section {n}", f.display()));
            }
        }
        // Documents and places outside the repository (spelled in pieces, so that this file
        // does not cite them itself).
        let outside = [
            concat!("physics", "-notes"),
            concat!("../", "shared"),
            concat!("/wo", "rk/"),
            concat!("shared", "/paper"),
        ];
        let lower = text.to_lowercase();
        for o in outside {
            if lower.contains(o) {
                problems.push(format!(
                    "{}: cites `{o}`, outside the repository",
                    f.display()
                ));
            }
        }
    }
    assert!(
        citations > 30,
        "only {citations} citations of docs/model.md found"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
