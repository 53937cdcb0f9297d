//! The house rule of the layout (README "Layout"): a module uses only modules below it, so
//! the numerical core never reaches the files, the terminal or the commands. This test reads
//! the sources and fails on any `crate::X` path in code (not in comments) that points up.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::path::Path;

/// Bottom first; each module may use those before it. `cli` is the binary and sits on top.
const LAYERS: [&str; 20] = [
    "cancel",
    "continuation",
    "text",
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
    "select",
    "tradeoff",
    "io",
    "fea",
    "export",
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
