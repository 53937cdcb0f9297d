//! The guide cannot drift: every ```` ```console ```` block of README.md and docs/*.md is run
//! here by trycmd. Each `$ prbfit ...` line runs the binary this build made, and what it prints
//! (stdout and stderr together) must be what the page shows below it, with `[..]` standing for
//! the rest of a line's text (timings) and a `...` line for any number of lines; `? N` after a
//! command is its exit status (default 0). Blocks of other kinds (`sh`, `text`, `toml`) are
//! not run, and a fence with no kind at all is read as a console block, so every page names
//! its blocks' kind. `TRYCMD=overwrite cargo test --test guide` rewrites the shown output
//! from a run (keeping the `[..]` it can).
//!
//! The commands run in a scratch directory holding a fresh copy of `assets/`, so the pages'
//! paths (`assets/scenes/slider-crank.toml`) work as they do from the repository root, and the
//! files the pages write (`-o crank-3r.toml`) land there, not in the repository. One page's
//! commands run in order (a page may read a file an earlier command wrote); pages run side by
//! side, so no two pages write the same file name.
//!
//! The second test checks the guide's links: every relative link of README.md and docs/*.md
//! names a file that exists (and a heading of it, for a `#anchor`), and docs/README.md (the
//! table of contents) links every page.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::fs;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The guide's pages: README.md and docs/*.md, sorted.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md")];
    let mut docs: Vec<PathBuf> = fs::read_dir(root().join("docs"))
        .expect("a docs/ directory")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let p = entry.unwrap().path();
        let target = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &target);
        } else {
            fs::copy(&p, &target).unwrap();
        }
    }
}

#[test]
fn every_console_block_prints_what_the_page_shows() {
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("guide");
    if work.exists() {
        fs::remove_dir_all(&work).unwrap();
    }
    copy_dir(&root().join("assets"), &work.join("assets"));
    // trycmd runs a markdown page's commands in the test's working directory.
    std::env::set_current_dir(&work).unwrap();
    let cases = trycmd::TestCases::new();
    cases
        .register_bin("prbfit", Path::new(env!("CARGO_BIN_EXE_prbfit")))
        .env("NO_COLOR", "1");
    for page in pages() {
        cases.case(page);
    }
    cases.run();
}

/// A page's inline links `[text](target)` to other files of the guide, as (file, anchor):
/// web links are left out, and a link to an anchor of the page itself has the page's name.
fn relative_links(page: &Path, text: &str) -> Vec<(PathBuf, Option<String>)> {
    let mut links = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = &rest[..end];
        rest = &rest[end..];
        if target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (file, anchor) = match target.split_once('#') {
            Some((file, anchor)) => (file, Some(anchor.to_string())),
            None => (target, None),
        };
        let file = if file.is_empty() {
            page.to_path_buf()
        } else {
            page.parent().unwrap().join(file)
        };
        links.push((file, anchor));
    }
    links
}

/// The anchors GitHub gives a markdown file's headings: lower case, spaces to `-`, and only
/// letters, digits, `-` and `_` kept.
fn anchors(text: &str) -> Vec<String> {
    let mut in_fence = false;
    let mut anchors = Vec::new();
    for line in text.lines() {
        if line.starts_with("```") {
            in_fence = !in_fence;
        } else if !in_fence && line.starts_with('#') {
            let heading = line.trim_start_matches('#').trim();
            let anchor: String = heading
                .to_lowercase()
                .chars()
                .filter_map(|c| match c {
                    ' ' => Some('-'),
                    c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                    _ => None,
                })
                .collect();
            anchors.push(anchor);
        }
    }
    anchors
}

#[test]
fn every_link_of_the_guide_names_a_file_and_the_contents_list_every_page() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = fs::read_to_string(&page).unwrap();
        for (file, anchor) in relative_links(&page, &text) {
            if !file.exists() {
                broken.push(format!(
                    "{}: {} (no such file)",
                    page.display(),
                    file.display()
                ));
            } else if let Some(anchor) = anchor {
                let target = fs::read_to_string(&file).unwrap_or_default();
                if !anchors(&target).contains(&anchor) {
                    broken.push(format!("{}: {}#{anchor}", page.display(), file.display()));
                }
            }
        }
    }
    assert!(broken.is_empty(), "links to nothing: {broken:#?}");

    let contents_page = root().join("docs/README.md");
    let contents = fs::read_to_string(&contents_page).unwrap();
    let listed: Vec<PathBuf> = relative_links(&contents_page, &contents)
        .into_iter()
        .map(|(file, _)| file)
        .collect();
    for page in pages().iter().skip(1) {
        if *page != contents_page {
            assert!(
                listed.contains(page),
                "docs/README.md does not link {}",
                page.display()
            );
        }
    }
}
