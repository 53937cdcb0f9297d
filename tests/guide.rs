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
//! names a file that exists, and docs/README.md (the table of contents) links every page.
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

/// The targets of a page's inline links `[text](target)`, without `#anchors`; web links and
/// pure anchors are left out.
fn relative_links(text: &str) -> Vec<String> {
    let mut links = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].split('#').next().unwrap_or("");
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            links.push(target.to_string());
        }
        rest = &rest[end..];
    }
    links
}

#[test]
fn every_link_of_the_guide_names_a_file_and_the_contents_list_every_page() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = fs::read_to_string(&page).unwrap();
        for link in relative_links(&text) {
            if !page.parent().unwrap().join(&link).exists() {
                broken.push(format!("{}: {link}", page.display()));
            }
        }
    }
    assert!(broken.is_empty(), "links to no file: {broken:#?}");

    let contents = fs::read_to_string(root().join("docs/README.md")).unwrap();
    let listed = relative_links(&contents);
    for page in pages().iter().skip(1) {
        let name = page.file_name().unwrap().to_str().unwrap();
        if name != "README.md" {
            assert!(
                listed.iter().any(|l| l == name),
                "docs/README.md does not link {name}"
            );
        }
    }
}
