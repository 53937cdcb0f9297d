//! The house rule of the layout (docs/architecture.md): a module uses only modules below it, so
//! the numerical core never reaches the files, the terminal or the commands. This test reads
//! the sources and fails on any `crate::X` path in code (not in comments) that points up.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::path::Path;

/// Bottom first; each module may use those before it. `cli` is the binary and sits on top.
const LAYERS: [&str; 22] = [
    "cancel",
    "cpu",
    "continuation",
    "text",
    "trig",
    "linalg",
    "beam",
    "prb",
    "scene",
    "mech",
    "si",
    "fidelity",
    "format",
    "eval",
    "fit",
    "io",
    "fea",
    "export",
    "study",
    "report",
    "plot",
    "tui",
];

fn rank(module: &str) -> Option<usize> {
    LAYERS.iter().position(|m| *m == module)
}

fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_module_uses_one_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let mut upward = Vec::new();
    let mut unranked = Vec::new();
    for path in &files {
        let rel = path.strip_prefix(&src).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        if top == "lib" || top == "main" || top == "cli" {
            continue;
        }
        let Some(own) = rank(&top) else {
            unranked.push(top);
            continue;
        };
        let text = std::fs::read_to_string(path).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for part in code.split("crate::").skip(1) {
                let used: String = part
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                if let Some(r) = rank(&used) {
                    if r > own {
                        upward.push(format!("{}:{}: {top} uses {used}", rel.display(), n + 1));
                    }
                }
            }
        }
    }
    assert!(
        unranked.is_empty(),
        "modules missing from LAYERS: {unranked:?}"
    );
    assert!(upward.is_empty(), "upward uses:\n{}", upward.join("\n"));
}

/// Every `super::NAME` and `crate::DIR::NAME` a file uses, as `(module, sibling)` pairs
/// within one directory of `src`: the module graph of that directory.
fn sibling_uses(dir: &Path, module_path: &str) -> Vec<(String, String)> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        let name = p.file_stem().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            let inner = p.join("mod.rs");
            if inner.exists() {
                files.push((name, inner));
            }
        } else if p.extension().is_some_and(|e| e == "rs") && name != "mod" {
            files.push((name, p));
        }
    }
    let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
    let mut edges = Vec::new();
    for (name, path) in &files {
        let text = std::fs::read_to_string(path).unwrap();
        // Only the code outside the file's tests module: tests may reach anywhere.
        let code = text.split("#[cfg(test)]").next().unwrap_or("");
        let own_prefix = format!("crate::{module_path}::");
        for line in code.lines() {
            let line = line.split("//").next().unwrap_or("");
            for prefix in ["super::", own_prefix.as_str()] {
                for part in line.split(prefix).skip(1) {
                    // `use super::{a, b::c}` names several.
                    let head: String = part
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || "_{}, :".contains(*c))
                        .collect();
                    for used in head
                        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                        .filter(|w| !w.is_empty())
                    {
                        if used != name && names.iter().any(|n| n == used) {
                            edges.push((name.clone(), used.to_string()));
                        }
                    }
                }
            }
        }
    }
    edges.sort();
    edges.dedup();
    edges
}

/// A cycle in `edges`, if any, as the modules along it.
fn cycle(edges: &[(String, String)]) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        edges: &[(String, String)],
        stack: &mut Vec<String>,
        done: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = stack.iter().position(|n| n == node) {
            let mut c = stack[i..].to_vec();
            c.push(node.to_string());
            return Some(c);
        }
        if done.iter().any(|n| n == node) {
            return None;
        }
        stack.push(node.to_string());
        for (_, to) in edges.iter().filter(|(from, _)| from == node) {
            if let Some(c) = visit(to, edges, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        done.push(node.to_string());
        None
    }
    let mut done = Vec::new();
    for (from, _) in edges {
        if let Some(c) = visit(from, edges, &mut Vec::new(), &mut done) {
            return Some(c);
        }
    }
    None
}

/// No module directory has an import cycle among its files (DESIGN §7: one file, one job,
/// used in one direction): `cli/`, `plot/`, `study/` and the rest.
#[test]
fn no_import_cycle_inside_a_module() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut dirs = vec![(src.clone(), String::new())];
    let mut cycles = Vec::new();
    while let Some((dir, module_path)) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                let name = p.file_name().unwrap().to_string_lossy().to_string();
                let path = if module_path.is_empty() {
                    name
                } else {
                    format!("{module_path}::{name}")
                };
                dirs.push((p, path));
            }
        }
        if module_path.is_empty() {
            continue;
        }
        if let Some(c) = cycle(&sibling_uses(&dir, &module_path)) {
            cycles.push(format!(
                "src/{}: {}",
                module_path.replace("::", "/"),
                c.join(" -> ")
            ));
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}
