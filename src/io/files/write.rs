//! Writing output files atomically, never over a device and through a symbolic link into
//! its target, keeping a replaced file's permissions; see the module docs of [`super`].

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

use super::kind::{shown, FileKind};

/// Why a file could not be written. `Display` is `path: reason` (see [`WriteError::reason`]).
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The file exists and overwriting was not asked for.
    #[error("{}: {}", shown(.0), self.reason())]
    Exists(PathBuf),
    /// The path (or the final target of the symbolic link it is) exists and is not a regular
    /// file: a directory, a device, a fifo or a socket, which a write would replace.
    #[error("{}: {}", shown(.path), self.reason())]
    NotARegularFile {
        /// The path as given.
        path: PathBuf,
        /// What it is.
        kind: FileKind,
    },
    /// The path is a symbolic link to something that does not exist.
    #[error("{}: {}", shown(.path), self.reason())]
    DanglingSymlink {
        /// The link.
        path: PathBuf,
        /// Where it points (as written in the link).
        target: PathBuf,
    },
    /// The operating system refused (no such directory, permission denied, disk full...).
    #[error("{}: {}", shown(.path), self.reason())]
    Io {
        /// The file being written: the path as given or, through a symbolic link, its target.
        path: PathBuf,
        /// What the operating system said. Part of the message, deliberately not the error's
        /// `source`, so that it is printed once.
        error: io::Error,
    },
}

impl WriteError {
    /// Whether the output could not be written for want of room or a working device (a full
    /// disk, a quota, a file too large, an I/O error), which the CLI counts as a failure
    /// (exit status 1), not as bad input: the same request succeeds once there is room.
    pub fn is_out_of_room(&self) -> bool {
        /// `EIO` and `EDQUOT` on Linux (`io::ErrorKind` names neither on stable Rust).
        const EIO: i32 = 5;
        const EDQUOT: i32 = 122;
        match self {
            WriteError::Io { error, .. } => {
                matches!(
                    error.kind(),
                    io::ErrorKind::StorageFull
                        | io::ErrorKind::FileTooLarge
                        | io::ErrorKind::WriteZero
                ) || matches!(error.raw_os_error(), Some(EIO | EDQUOT))
            }
            _ => false,
        }
    }

    /// The path the error is about.
    pub fn path(&self) -> &Path {
        match self {
            WriteError::Exists(path)
            | WriteError::NotARegularFile { path, .. }
            | WriteError::DanglingSymlink { path, .. }
            | WriteError::Io { path, .. } => path,
        }
    }

    /// What went wrong, without the path (for a caller that names the file itself).
    pub fn reason(&self) -> String {
        match self {
            WriteError::Exists(_) => "file exists (use --force to overwrite it)".into(),
            WriteError::NotARegularFile { kind, .. } => {
                format!("not a regular file ({kind}); refusing to replace it")
            }
            WriteError::DanglingSymlink { target, .. } => format!(
                "a symbolic link to {}, which does not exist; refusing to write through it \
                 (create the target or remove the link)",
                shown(target)
            ),
            WriteError::Io { error, .. } => error.to_string(),
        }
    }
}

/// Where a write goes: the file to replace (or create) and, when one exists, its metadata.
struct Target {
    file: PathBuf,
    existing: Option<fs::Metadata>,
}

/// Decides where writing `path` goes, refusing what may not be written (see the module
/// docs). Touches nothing.
fn resolve_target(path: &Path, overwrite: bool) -> Result<Target, WriteError> {
    let io_error = |error| WriteError::Io {
        path: path.to_path_buf(),
        error,
    };
    let meta = match fs::symlink_metadata(path) {
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            // A new file: its directory must be there, or a long computation would end in a
            // write that cannot happen.
            let dir = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            // (A directory that is a plain file was refused above: `Not a directory`.)
            return match fs::metadata(dir) {
                Ok(_) => Ok(Target {
                    file: path.to_path_buf(),
                    existing: None,
                }),
                Err(e) if e.kind() == io::ErrorKind::NotFound => Err(io_error(io::Error::new(
                    io::ErrorKind::NotFound,
                    format!("its directory {} does not exist", shown(dir)),
                ))),
                Err(e) => Err(io_error(e)),
            };
        }
        Err(e) => return Err(io_error(e)),
    };
    let (file, meta) = if meta.file_type().is_symlink() {
        match fs::canonicalize(path) {
            Ok(real) => {
                let meta = fs::symlink_metadata(&real).map_err(io_error)?;
                (real, meta)
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                return Err(WriteError::DanglingSymlink {
                    path: path.to_path_buf(),
                    target: fs::read_link(path).map_err(io_error)?,
                })
            }
            Err(e) => return Err(io_error(e)),
        }
    } else {
        (path.to_path_buf(), meta)
    };
    if let Some(kind) = FileKind::of(meta.file_type()) {
        return Err(WriteError::NotARegularFile {
            path: path.to_path_buf(),
            kind,
        });
    }
    if !overwrite {
        return Err(WriteError::Exists(path.to_path_buf()));
    }
    Ok(Target {
        file,
        existing: Some(meta),
    })
}

/// Whether [`write_atomic`] with this `path` and `overwrite` would be refused before it
/// touches anything (the file exists, is not a regular file, is a dangling link, or cannot
/// be looked at): for a command to check its output before a long computation rather than
/// after. Touches nothing; the write itself checks again.
pub fn check_target(path: &Path, overwrite: bool) -> Result<(), WriteError> {
    resolve_target(path, overwrite).map(|_| ())
}

/// A temporary file name next to `file`, unique within the process and very likely across
/// processes (pid, a counter and the clock); kept well within the 255-byte name limit.
fn temporary_path(file: &Path) -> (PathBuf, PathBuf) {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let dir = match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "prbfit".into());
    let mut end = name.len().min(100);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    let count = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = dir.join(format!(
        ".{}.{}.{count}.{nanos}.tmp",
        &name[..end],
        std::process::id()
    ));
    (dir, tmp)
}

/// Puts the finished temporary file in place. Without `overwrite` it must not replace a file
/// that appeared meanwhile: a hard link fails if the name is taken, atomically; where the
/// file system has no hard links, a check just before the rename has to do.
fn install(tmp: &Path, file: &Path, overwrite: bool) -> io::Result<()> {
    if overwrite {
        return fs::rename(tmp, file);
    }
    match fs::hard_link(tmp, file) {
        Ok(()) => {
            let _ = fs::remove_file(tmp);
            Ok(())
        }
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Err(e),
        Err(_) => {
            if fs::symlink_metadata(file).is_ok() {
                return Err(io::ErrorKind::AlreadyExists.into());
            }
            fs::rename(tmp, file)
        }
    }
}

/// The permissions a file replacing `old` gets: its read, write and execute bits, but not
/// set-user-ID, set-group-ID or sticky, which on a file now owned by whoever runs prbfit
/// (root, say) would mean something else.
fn kept_permissions(old: &fs::Metadata) -> fs::Permissions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        fs::Permissions::from_mode(old.permissions().mode() & 0o777)
    }
    #[cfg(not(unix))]
    old.permissions()
}

/// Writes `contents` to `path` atomically. With `overwrite` false an existing file is an
/// error and is left untouched. Only a regular file is ever replaced, keeping its
/// permissions; through a symbolic link the link's final target is written and the link
/// stays (see the module docs).
pub fn write_atomic(path: &Path, contents: &[u8], overwrite: bool) -> Result<(), WriteError> {
    let target = resolve_target(path, overwrite)?;
    let (dir, tmp) = temporary_path(&target.file);
    let io_error = |error| WriteError::Io {
        path: target.file.clone(),
        error,
    };
    let mut f = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(io_error)?;
    let written = (|| {
        if let Some(old) = &target.existing {
            // Before any contents go in, so a private file never is readable by others.
            f.set_permissions(kept_permissions(old))?;
        }
        f.write_all(contents)?;
        f.sync_all()
    })();
    drop(f);
    let result = written.and_then(|()| install(&tmp, &target.file, overwrite));
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        if e.kind() == io::ErrorKind::AlreadyExists && !overwrite {
            return Err(WriteError::Exists(path.to_path_buf()));
        }
        return Err(io_error(e));
    }
    // Make the rename itself durable. Best effort: not every system can sync a directory.
    #[cfg(unix)]
    if let Ok(d) = fs::File::open(&dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

#[cfg(test)]
mod tests;
