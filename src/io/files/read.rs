//! Reading input files (scenes, model files, data files), bounded: only a regular file (links
//! followed), at most a limit of bytes checked before and while reading, UTF-8 text; see the
//! module docs of [`super`].

use std::fs;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

use super::kind::{human_size, shown, FileKind};

/// The most an input file (scene, model file) may hold: 16 MiB, far beyond any real scene
/// and small enough to read and parse in well under a second.
pub const MAX_INPUT_BYTES: u64 = 16 * 1024 * 1024;

/// Why an input file could not be read. `Display` is `path: reason` (see
/// [`ReadError::reason`]).
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// There is no such file.
    #[error("{}: {}", shown(.path), self.reason())]
    NotFound {
        /// The path as given.
        path: PathBuf,
    },
    /// The path (after following symbolic links) is a directory, a device, a fifo or a
    /// socket; it was not opened.
    #[error("{}: {}", shown(.path), self.reason())]
    NotARegularFile {
        /// The path as given.
        path: PathBuf,
        /// What it is.
        kind: FileKind,
    },
    /// The file holds more than the limit.
    #[error("{}: {}", shown(.path), self.reason())]
    TooLarge {
        /// The path as given.
        path: PathBuf,
        /// Its size in bytes, as far as known (at least `limit + 1`).
        size: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// The file is not UTF-8 text.
    #[error("{}: {}", shown(.path), self.reason())]
    NotUtf8 {
        /// The path as given.
        path: PathBuf,
        /// The line (from 1) holding the first byte that is not UTF-8.
        line: usize,
    },
    /// The operating system refused (permission denied, an I/O error...).
    #[error("{}: {}", shown(.path), self.reason())]
    Io {
        /// The path as given.
        path: PathBuf,
        /// What the operating system said. Part of the message, deliberately not the error's
        /// `source`, so that it is printed once.
        error: io::Error,
    },
}

impl ReadError {
    /// The path the error is about.
    pub fn path(&self) -> &Path {
        match self {
            ReadError::NotFound { path }
            | ReadError::NotARegularFile { path, .. }
            | ReadError::TooLarge { path, .. }
            | ReadError::NotUtf8 { path, .. }
            | ReadError::Io { path, .. } => path,
        }
    }

    /// What went wrong, without the path (for a caller that names the file itself).
    pub fn reason(&self) -> String {
        match self {
            ReadError::NotFound { .. } => "no such file".into(),
            ReadError::NotARegularFile { kind, .. } => format!("not a regular file ({kind})"),
            ReadError::TooLarge { size, limit, .. } => format!(
                "{size} bytes is more than the {} an input file may have",
                human_size(*limit)
            ),
            ReadError::NotUtf8 { line, .. } => {
                format!("not UTF-8 text (line {line} holds a byte that is not UTF-8)")
            }
            ReadError::Io { error, .. } => error.to_string(),
        }
    }
}

/// Reads the text file at `path`, refusing anything but a regular file (symbolic links are
/// followed), anything over `limit` bytes and anything that is not UTF-8. A device or fifo is
/// refused without being opened, so `/dev/zero` or a fifo with no writer returns at once.
///
/// The size is checked before reading and the reading itself stops after `limit + 1` bytes,
/// so a file that grows while it is read, or one whose size the system does not report, is
/// capped too. (A path swapped for a fifo between the check and the open could still block
/// the open; what was opened is checked again.)
pub fn read_text_capped(path: &Path, limit: u64) -> Result<String, ReadError> {
    let fail = |error: io::Error| {
        if error.kind() == io::ErrorKind::NotFound {
            ReadError::NotFound {
                path: path.to_path_buf(),
            }
        } else {
            ReadError::Io {
                path: path.to_path_buf(),
                error,
            }
        }
    };
    let check = |meta: &fs::Metadata| {
        if let Some(kind) = FileKind::of(meta.file_type()) {
            return Err(ReadError::NotARegularFile {
                path: path.to_path_buf(),
                kind,
            });
        }
        if meta.len() > limit {
            return Err(ReadError::TooLarge {
                path: path.to_path_buf(),
                size: meta.len(),
                limit,
            });
        }
        Ok(())
    };
    check(&fs::metadata(path).map_err(fail)?)?;
    let file = fs::File::open(path).map_err(fail)?;
    let meta = file.metadata().map_err(fail)?;
    check(&meta)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    (&file)
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(fail)?;
    let read = bytes.len() as u64;
    if read > limit {
        let now = file.metadata().map(|m| m.len()).unwrap_or(0);
        return Err(ReadError::TooLarge {
            path: path.to_path_buf(),
            size: read.max(now),
            limit,
        });
    }
    String::from_utf8(bytes).map_err(|e| {
        let bad = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..bad].iter().filter(|&&b| b == b'\n').count();
        ReadError::NotUtf8 {
            path: path.to_path_buf(),
            line,
        }
    })
}

/// Reads an input file (scene, model file) with the [`MAX_INPUT_BYTES`] limit: see
/// [`read_text_capped`].
pub fn read_input(path: &Path) -> Result<String, ReadError> {
    read_text_capped(path, MAX_INPUT_BYTES)
}

#[cfg(test)]
mod tests;
