//! Helpers of the file tests: a scratch directory, temporary files left behind, an error
//! chain as the CLI prints it, fifos and symbolic links.
#![allow(clippy::unwrap_used)]

use std::fs;
use std::path::{Path, PathBuf};

/// A fresh directory for the test `name`.
pub(super) fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("prbfit-files-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Names in `dir` that look like our temporary files.
pub(super) fn leftovers(dir: &Path) -> usize {
    fs::read_dir(dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".tmp")
        })
        .count()
}

/// The whole error chain on one line, as the CLI prints it.
pub(super) fn chain(e: impl std::error::Error + Send + Sync + 'static) -> String {
    anyhow::Error::from(e)
        .chain()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(": ")
}

/// A fifo at `path`.
#[cfg(unix)]
pub(super) fn mkfifo(path: &Path) {
    let ok = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .unwrap()
        .success();
    assert!(ok, "mkfifo {}", path.display());
}

/// Whether `path` is a symbolic link (not followed).
pub(super) fn is_symlink(path: &Path) -> bool {
    fs::symlink_metadata(path).unwrap().file_type().is_symlink()
}
