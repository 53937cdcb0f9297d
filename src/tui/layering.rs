//! The house rule inside the terminal UI (issue 23.4), as a test: its modules use only those
//! below them ([`ORDER`]), and no file uses another that uses it back, directly or through
//! others (a parent `mod.rs` and its children included). The sources are read as text: every
//! path in code (not in comments) that starts at `super`, `self`, `crate::tui` or, in a
//! `mod.rs`, at one of its child modules is resolved to the file it names (an inline
//! `mod tests` is read as its file: its paths name files with `crate::tui::`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The UI's modules, bottom first: each uses only those before it (this module's own
/// `mod.rs`, the event loop, uses them all).
const ORDER: [&str; 8] = [
    "units",
    "panel",
    "keymap",
    "latest_job",
    "worker",
    "state",
    "app",
    "ui",
];

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let p = entry.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module path (from `src/tui`) of the file `rel` (relative to `src/tui`), and whether
/// it is a `mod.rs`.
fn module_of(rel: &Path) -> (Vec<String>, bool) {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    let is_mod = parts.last().is_some_and(|l| l == "mod");
    if is_mod {
        parts.pop();
    }
    (parts, is_mod)
}

/// The file of module `module` under `root`, if there is one.
fn file_of(root: &Path, module: &[String]) -> Option<PathBuf> {
    let dir: PathBuf = module.iter().collect();
    let m = root.join(&dir).join("mod.rs");
    if m.is_file() {
        return Some(m);
    }
    let (last, parent) = module.split_last()?;
    let f = root
        .join(parent.iter().collect::<PathBuf>())
        .join(format!("{last}.rs"));
    f.is_file().then_some(f)
}

/// The longest prefix of `path` (from `src/tui`) that names a file, and that file.
fn resolve(root: &Path, path: &[String]) -> Option<PathBuf> {
    (0..=path.len())
        .rev()
        .find_map(|n| file_of(root, &path[..n]))
}

/// The code of a line: what is before a `//` comment.
fn code(line: &str) -> &str {
    line.split("//").next().unwrap_or("")
}

/// Every path in `text` as a list of segments, with the names in a `{...}` group right after
/// it (each a path of its own).
fn paths(text: &str) -> Vec<Vec<String>> {
    let chars: Vec<char> = text.chars().collect();
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        // A path starts at an identifier not itself after `::`.
        let after_colons = i >= 2 && chars[i - 1] == ':' && chars[i - 2] == ':';
        if !ident(chars[i]) || (i > 0 && ident(chars[i - 1])) || after_colons {
            i += 1;
            continue;
        }
        let mut segments = Vec::new();
        let mut j = i;
        loop {
            let start = j;
            while j < chars.len() && ident(chars[j]) {
                j += 1;
            }
            segments.push(chars[start..j].iter().collect::<String>());
            if j + 2 < chars.len() && chars[j] == ':' && chars[j + 1] == ':' {
                if ident(chars[j + 2]) {
                    j += 2;
                    continue;
                }
                if chars[j + 2] == '{' {
                    // One level of a use group: `a::b::{c, d::e, self}`.
                    let close = chars[j + 3..].iter().position(|&c| c == '}');
                    let group: String = match close {
                        Some(k) => chars[j + 3..j + 3 + k].iter().collect(),
                        None => String::new(),
                    };
                    for item in group.split(',') {
                        let item: Vec<String> = item
                            .trim()
                            .split("::")
                            .map(|s| s.trim().to_string())
                            .filter(|s| !s.is_empty() && s != "self" && s.chars().all(ident))
                            .collect();
                        let mut p = segments.clone();
                        p.extend(item);
                        out.push(p);
                    }
                }
            }
            break;
        }
        if segments.len() > 1 {
            out.push(segments);
        }
        i = j.max(i + 1);
    }
    out
}

/// The module `name` inside `module`.
fn child(module: &[String], name: &str) -> Vec<String> {
    let mut m = module.to_vec();
    m.push(name.to_string());
    m
}

/// The files each file of `root` uses.
fn uses(root: &Path) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let mut files = Vec::new();
    sources(root, &mut files);
    let mut graph = BTreeMap::new();
    for file in &files {
        let rel = file.strip_prefix(root).unwrap_or(file);
        let (module, is_mod) = module_of(rel);
        let text = std::fs::read_to_string(file).unwrap_or_default();
        let code: String = text.lines().map(code).collect::<Vec<_>>().join("\n");
        let mut used = BTreeSet::new();
        for path in paths(&code) {
            let mut base = module.clone();
            let mut rest = path.as_slice();
            match rest.first().map(String::as_str) {
                Some("crate") if rest.get(1).is_some_and(|s| s == "tui") => {
                    base.clear();
                    rest = &rest[2..];
                }
                Some("self") => rest = &rest[1..],
                Some("super") => {
                    while rest.first().is_some_and(|s| s == "super") {
                        base.pop();
                        rest = &rest[1..];
                    }
                }
                // A `mod.rs`'s own child module.
                Some(first) if is_mod && file_of(root, &child(&module, first)).is_some() => {}
                _ => continue,
            }
            let mut full = base;
            full.extend(rest.iter().cloned());
            if let Some(target) = resolve(root, &full).filter(|t| t != file) {
                used.insert(target);
            }
        }
        graph.insert(file.clone(), used);
    }
    graph
}

/// A cycle through `start`, if there is one: the files in order.
fn cycle(graph: &BTreeMap<PathBuf, BTreeSet<PathBuf>>, start: &Path) -> Option<Vec<PathBuf>> {
    let mut stack = vec![(start.to_path_buf(), vec![start.to_path_buf()])];
    let mut seen = BTreeSet::new();
    while let Some((at, trail)) = stack.pop() {
        for next in graph.get(&at).into_iter().flatten() {
            if next == start {
                return Some(trail);
            }
            if seen.insert(next.clone()) {
                let mut t = trail.clone();
                t.push(next.clone());
                stack.push((next.clone(), t));
            }
        }
    }
    None
}

/// The UI's top module of a file (`None` for `tui/mod.rs`).
fn top(root: &Path, file: &Path) -> Option<String> {
    let (module, _) = module_of(file.strip_prefix(root).unwrap_or(file));
    module.first().cloned()
}

#[test]
fn no_module_uses_one_above_it_and_no_file_uses_itself_back() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/tui");
    let graph = uses(&root);
    assert!(graph.len() > 20, "the sources were read: {}", graph.len());
    let edges: usize = graph.values().map(BTreeSet::len).sum();
    assert!(edges > 60, "the uses were read: {edges}");
    let rank = |m: &str| ORDER.iter().position(|o| *o == m);
    let name = |p: &Path| p.strip_prefix(&root).unwrap_or(p).display().to_string();
    let mut wrong = Vec::new();
    for (file, used) in &graph {
        // The event loop (tui/mod.rs) uses every module; this test, none.
        let Some(own) = top(&root, file).filter(|m| m != "layering") else {
            continue;
        };
        let Some(r) = rank(&own) else {
            wrong.push(format!("{}: {own} is not in ORDER", name(file)));
            continue;
        };
        for u in used {
            match top(&root, u) {
                Some(m) if m == own => {}
                Some(m) if rank(&m).is_some_and(|x| x < r) => {}
                m => wrong.push(format!("{} ({own}) uses {} ({m:?})", name(file), name(u))),
            }
        }
    }
    for file in graph.keys() {
        if let Some(c) = cycle(&graph, file) {
            let c: Vec<String> = c.iter().map(|p| name(p)).collect();
            wrong.push(format!("a cycle: {} -> back", c.join(" -> ")));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn paths_are_read_as_the_compiler_reads_them() {
    let p = paths("use super::super::state::{beam::BeamField, self, loads};\nrun::run_job(x)");
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert!(p.contains(&s(&["super", "super", "state", "beam", "BeamField"])));
    assert!(p.contains(&s(&["super", "super", "state", "loads"])));
    assert!(p.contains(&s(&["run", "run_job"])));
    assert_eq!(module_of(Path::new("app/mod.rs")), (s(&["app"]), true));
    assert_eq!(
        module_of(Path::new("app/keys.rs")),
        (s(&["app", "keys"]), false)
    );
}
