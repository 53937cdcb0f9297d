//! The file system: the only module that reads or writes files for the user.
//!
//! **Writing** is atomic: the contents go to a temporary file in the target's directory,
//! which is flushed to disk and then renamed over the target, so a crash or a full disk never
//! leaves a half-written file and a failed write leaves the old file as it was. An existing
//! file is never replaced unless asked (`overwrite`, the CLI's `--force`). Beyond that:
//!
//! - Only a *regular file* is ever replaced. Renaming over a device, a fifo or a socket does
//!   not write into it, it unlinks it and puts a regular file in its place: `--force -o
//!   /dev/full` run as root used to replace the device node (and `/dev/null` would have gone
//!   the same way, breaking every program on the machine). So a target that exists and is
//!   not a regular file is refused ([`WriteError::NotARegularFile`]); nobody asks for a model
//!   file to become a device node.
//! - A *symbolic link* is written through, not replaced: the user named the link meaning the
//!   file it points to (dotfile managers, a `latest.toml` link to a dated file), so the
//!   link's final target (all links followed) is written atomically in *its* directory and the
//!   link stays a link. A link whose target does not exist is refused
//!   ([`WriteError::DanglingSymlink`]) rather than guessed at, and a link to something other
//!   than a regular file is refused like that thing itself.
//! - A replaced file keeps its permission bits (a `0600` file stays private), except
//!   set-user-ID, set-group-ID and sticky. Its owner and other hard links to it are not
//!   carried over: the new contents are a new file.
//!
//! **Reading** input ([`read_text_capped`], [`read_input`]) is bounded: `--scene /dev/zero`
//! used to grow memory until the machine gave out, and a 50 MB scene with a million load
//! paths ran for minutes before saying anything. Only regular files are read (a fifo would
//! block, a device may never end; the check follows symbolic links, so a link to a scene is
//! fine), at most [`MAX_INPUT_BYTES`] of them — checked against the file's size before
//! reading *and* while reading, so a file that grows meanwhile (or a `/proc` file that
//! reports no size) is capped too — and it must be UTF-8.
//!
//! Every error names the path, says what is wrong in words a user can act on, and says it
//! once: the OS error is part of the message and is not also reported as the error's
//! `source`, which would make `anyhow`'s chain print it twice. Paths in messages go through
//! [`sanitize_terminal`], since a file name can hold escape sequences too.

use std::fmt;
use std::fs;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::text::sanitize_terminal;

/// The most an input file (scene, model file) may hold: 16 MiB, far beyond any real scene
/// and small enough to read and parse in well under a second.
pub const MAX_INPUT_BYTES: u64 = 16 * 1024 * 1024;

/// What a path is when it is not a regular file, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A directory.
    Directory,
    /// A character device (`/dev/null`, `/dev/zero`, a terminal).
    CharDevice,
    /// A block device (a disk).
    BlockDevice,
    /// A fifo (named pipe).
    Fifo,
    /// A Unix domain socket.
    Socket,
    /// A symbolic link (only seen where links are not followed).
    Symlink,
    /// Anything else that is not a regular file.
    Other,
}

impl FileKind {
    /// The kind of `file_type`; `None` for a regular file.
    pub fn of(file_type: fs::FileType) -> Option<FileKind> {
        if file_type.is_file() {
            return None;
        }
        if file_type.is_dir() {
            return Some(FileKind::Directory);
        }
        if file_type.is_symlink() {
            return Some(FileKind::Symlink);
        }
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            if file_type.is_char_device() {
                return Some(FileKind::CharDevice);
            }
            if file_type.is_block_device() {
                return Some(FileKind::BlockDevice);
            }
            if file_type.is_fifo() {
                return Some(FileKind::Fifo);
            }
            if file_type.is_socket() {
                return Some(FileKind::Socket);
            }
        }
        Some(FileKind::Other)
    }
}

impl fmt::Display for FileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileKind::Directory => "a directory",
            FileKind::CharDevice => "a character device",
            FileKind::BlockDevice => "a block device",
            FileKind::Fifo => "a fifo",
            FileKind::Socket => "a socket",
            FileKind::Symlink => "a symbolic link",
            FileKind::Other => "a special file",
        })
    }
}

/// `path` as it may be printed: lossily decoded, control characters replaced.
fn shown(path: &Path) -> String {
    sanitize_terminal(&path.to_string_lossy()).into_owned()
}

/// `bytes` in the largest binary unit that divides it: `16 MiB`, `4 KiB`, `1000 bytes`.
fn human_size(bytes: u64) -> String {
    const KIB: u64 = 1024;
    const MIB: u64 = 1024 * KIB;
    match bytes {
        0 => "0 bytes".into(),
        1 => "1 byte".into(),
        b if b % MIB == 0 => format!("{} MiB", b / MIB),
        b if b % KIB == 0 => format!("{} KiB", b / KIB),
        b => format!("{b} bytes"),
    }
}

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
            return Ok(Target {
                file: path.to_path_buf(),
                existing: None,
            })
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

/// The current UTC time as `YYYY-MM-DDTHH:MM:SSZ`, for provenance.
pub fn utc_timestamp() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("prbfit-files-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Names in `dir` that look like our temporary files.
    fn leftovers(dir: &Path) -> usize {
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
    fn chain(e: impl std::error::Error + Send + Sync + 'static) -> String {
        anyhow::Error::from(e)
            .chain()
            .map(|c| c.to_string())
            .collect::<Vec<_>>()
            .join(": ")
    }

    #[test]
    fn writes_refuses_and_overwrites() {
        let dir = scratch("basic");
        let p = dir.join("m.toml");
        write_atomic(&p, b"one", false).unwrap();
        assert!(matches!(
            write_atomic(&p, b"two", false),
            Err(WriteError::Exists(_))
        ));
        assert_eq!(fs::read(&p).unwrap(), b"one");
        assert!(matches!(
            check_target(&p, false),
            Err(WriteError::Exists(_))
        ));
        check_target(&p, true).unwrap();
        check_target(&dir.join("new.toml"), false).unwrap();
        write_atomic(&p, b"three", true).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"three");
        // No temporary files left behind.
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_failed_write_leaves_the_old_file() {
        let dir = scratch("fail");
        let p = dir.join("m.toml");
        write_atomic(&p, b"old", false).unwrap();
        // Writing into a directory that does not exist fails before touching anything.
        let missing = dir.join("no/such/dir/m.toml");
        assert!(write_atomic(&missing, b"new", true).is_err());
        // A directory is not replaced: the target stays as it was.
        let target_dir = dir.join("sub");
        fs::create_dir(&target_dir).unwrap();
        fs::write(target_dir.join("keep"), b"x").unwrap();
        assert!(matches!(
            write_atomic(&target_dir, b"new", true),
            Err(WriteError::NotARegularFile {
                kind: FileKind::Directory,
                ..
            })
        ));
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert_eq!(fs::read(target_dir.join("keep")).unwrap(), b"x");
        assert_eq!(leftovers(&dir), 0);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_os_error_is_printed_once() {
        let dir = scratch("once");
        let missing = dir.join("no/such/dir/m.toml");
        let e = write_atomic(&missing, b"new", true).unwrap_err();
        assert!(matches!(&e, WriteError::Io { .. }), "{e:?}");
        assert!(std::error::Error::source(&e).is_none());
        assert_eq!(e.path(), missing);
        assert!(
            matches!(&e, WriteError::Io { error, .. } if error.kind() == io::ErrorKind::NotFound)
        );
        let printed = chain(e);
        assert_eq!(
            printed.matches("os error 2").count(),
            1,
            "printed {printed:?}"
        );
        assert!(printed.starts_with(&format!("{}: ", missing.display())));
        // The same for a permission error built by hand (root can't provoke one).
        let e = WriteError::Io {
            path: "m.toml".into(),
            error: io::Error::from_raw_os_error(13),
        };
        assert_eq!(
            chain(e),
            format!("m.toml: {}", io::Error::from_raw_os_error(13))
        );
        let e = ReadError::Io {
            path: "s.toml".into(),
            error: io::Error::from_raw_os_error(13),
        };
        assert_eq!(
            chain(e),
            format!("s.toml: {}", io::Error::from_raw_os_error(13))
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn messages_read_well() {
        let e = WriteError::NotARegularFile {
            path: "/dev/full".into(),
            kind: FileKind::CharDevice,
        };
        assert_eq!(
            e.to_string(),
            "/dev/full: not a regular file (a character device); refusing to replace it"
        );
        assert_eq!(
            e.reason(),
            "not a regular file (a character device); refusing to replace it"
        );
        let e = WriteError::DanglingSymlink {
            path: "latest.toml".into(),
            target: "gone.toml".into(),
        };
        assert_eq!(
            e.to_string(),
            "latest.toml: a symbolic link to gone.toml, which does not exist; refusing to \
             write through it (create the target or remove the link)"
        );
        let e = ReadError::TooLarge {
            path: "big.toml".into(),
            size: 52_428_800,
            limit: MAX_INPUT_BYTES,
        };
        assert_eq!(
            e.to_string(),
            "big.toml: 52428800 bytes is more than the 16 MiB an input file may have"
        );
        let e = ReadError::NotARegularFile {
            path: "scene.toml".into(),
            kind: FileKind::CharDevice,
        };
        assert_eq!(
            e.to_string(),
            "scene.toml: not a regular file (a character device)"
        );
        let e = ReadError::NotFound {
            path: "scene\u{1b}[2J.toml".into(),
        };
        assert_eq!(e.to_string(), "scene?[2J.toml: no such file");
        assert_eq!(human_size(4096), "4 KiB");
        assert_eq!(human_size(1000), "1000 bytes");
    }

    #[test]
    fn timestamps_look_right() {
        let t = utc_timestamp();
        assert_eq!(t.len(), 20);
        assert!(t.starts_with("20") && t.ends_with('Z'));
    }

    #[cfg(unix)]
    mod unix {
        use super::*;
        use std::os::unix::fs::{symlink, FileTypeExt, PermissionsExt};
        use std::process::Command;
        use std::time::{Duration, Instant};

        fn mkfifo(path: &Path) {
            let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
            assert!(ok, "mkfifo {}", path.display());
        }

        fn is_symlink(path: &Path) -> bool {
            fs::symlink_metadata(path).unwrap().file_type().is_symlink()
        }

        #[test]
        fn a_fifo_is_refused_and_left_alone() {
            let dir = scratch("fifo");
            let p = dir.join("pipe");
            mkfifo(&p);
            for overwrite in [true, false] {
                let e = write_atomic(&p, b"x", overwrite).unwrap_err();
                assert!(
                    matches!(
                        e,
                        WriteError::NotARegularFile {
                            kind: FileKind::Fifo,
                            ..
                        }
                    ),
                    "{e:?}"
                );
            }
            assert!(matches!(
                check_target(&p, true),
                Err(WriteError::NotARegularFile { .. })
            ));
            assert!(fs::symlink_metadata(&p).unwrap().file_type().is_fifo());
            assert_eq!(leftovers(&dir), 0);
            fs::remove_dir_all(&dir).unwrap();
        }

        /// A character device to write at. A copy of `/dev/null` made with `mknod` in a
        /// scratch directory when we may (root), so that should this ever regress it is the
        /// copy that gets replaced, not the machine's `/dev/null`; otherwise `/dev/null`
        /// itself, which a user who cannot `mknod` cannot replace either. `None` (the test is
        /// skipped) when we could replace `/dev/null` but not make a copy.
        fn char_device(dir: &Path) -> Option<PathBuf> {
            let copy = dir.join("null");
            let made = Command::new("mknod")
                .arg(&copy)
                .args(["c", "1", "3"])
                .status()
                .is_ok_and(|s| s.success());
            if made {
                return Some(copy);
            }
            let probe = Path::new("/dev").join(format!(".prbfit-probe-{}", std::process::id()));
            if fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&probe)
                .is_ok()
            {
                let _ = fs::remove_file(&probe);
                eprintln!("skipped: /dev is writable and mknod is not available");
                return None;
            }
            Some(PathBuf::from("/dev/null"))
        }

        #[test]
        fn a_device_is_refused_and_left_alone() {
            let dir = scratch("device");
            let Some(dev) = char_device(&dir) else {
                return;
            };
            for overwrite in [true, false] {
                let e = write_atomic(&dev, b"x", overwrite).unwrap_err();
                assert!(
                    matches!(
                        e,
                        WriteError::NotARegularFile {
                            kind: FileKind::CharDevice,
                            ..
                        }
                    ),
                    "{e:?}"
                );
            }
            assert!(fs::symlink_metadata(&dev)
                .unwrap()
                .file_type()
                .is_char_device());
            assert!(fs::symlink_metadata("/dev/null")
                .unwrap()
                .file_type()
                .is_char_device());
            assert_eq!(leftovers(&dir), 0);
            // Through a link too.
            let link = dir.join("link");
            symlink(&dev, &link).unwrap();
            assert!(matches!(
                write_atomic(&link, b"x", true),
                Err(WriteError::NotARegularFile {
                    kind: FileKind::CharDevice,
                    ..
                })
            ));
            assert!(is_symlink(&link));
            assert!(fs::symlink_metadata(&dev)
                .unwrap()
                .file_type()
                .is_char_device());
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn a_symlink_is_written_through() {
            let dir = scratch("symlink");
            fs::create_dir(dir.join("real")).unwrap();
            fs::create_dir(dir.join("links")).unwrap();
            let target = dir.join("real/model.toml");
            fs::write(&target, b"old").unwrap();
            // links/latest.toml -> ../real/model.toml, links/again.toml -> latest.toml
            let link = dir.join("links/latest.toml");
            symlink("../real/model.toml", &link).unwrap();
            let again = dir.join("links/again.toml");
            symlink("latest.toml", &again).unwrap();

            // Without overwrite the existing target counts as existing.
            assert!(matches!(
                write_atomic(&link, b"new", false),
                Err(WriteError::Exists(_))
            ));
            assert_eq!(fs::read(&target).unwrap(), b"old");

            write_atomic(&link, b"new", true).unwrap();
            assert!(is_symlink(&link));
            assert_eq!(fs::read(&target).unwrap(), b"new");
            write_atomic(&again, b"newer", true).unwrap();
            assert!(is_symlink(&again) && is_symlink(&link));
            assert_eq!(fs::read(&target).unwrap(), b"newer");
            assert_eq!(
                fs::read_link(&link).unwrap(),
                Path::new("../real/model.toml")
            );
            assert_eq!(leftovers(&dir.join("real")), 0);
            assert_eq!(leftovers(&dir.join("links")), 0);
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn a_dangling_symlink_is_refused() {
            let dir = scratch("dangling");
            let link = dir.join("latest.toml");
            symlink("gone.toml", &link).unwrap();
            for overwrite in [true, false] {
                let e = write_atomic(&link, b"new", overwrite).unwrap_err();
                match &e {
                    WriteError::DanglingSymlink { path, target } => {
                        assert_eq!(path, &link);
                        assert_eq!(target, Path::new("gone.toml"));
                    }
                    _ => panic!("{e:?}"),
                }
            }
            assert!(matches!(
                check_target(&link, true),
                Err(WriteError::DanglingSymlink { .. })
            ));
            assert!(is_symlink(&link));
            assert!(!dir.join("gone.toml").exists());
            assert_eq!(leftovers(&dir), 0);
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn a_symlink_to_a_fifo_is_refused() {
            let dir = scratch("link-fifo");
            let pipe = dir.join("pipe");
            mkfifo(&pipe);
            let link = dir.join("link");
            symlink(&pipe, &link).unwrap();
            assert!(matches!(
                write_atomic(&link, b"x", true),
                Err(WriteError::NotARegularFile {
                    kind: FileKind::Fifo,
                    ..
                })
            ));
            assert!(is_symlink(&link));
            assert!(fs::symlink_metadata(&pipe).unwrap().file_type().is_fifo());
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn a_replaced_file_keeps_its_permissions() {
            let dir = scratch("mode");
            let p = dir.join("secret.toml");
            fs::write(&p, b"old").unwrap();
            fs::set_permissions(&p, fs::Permissions::from_mode(0o600)).unwrap();
            write_atomic(&p, b"new", true).unwrap();
            assert_eq!(fs::read(&p).unwrap(), b"new");
            assert_eq!(
                fs::metadata(&p).unwrap().permissions().mode() & 0o7777,
                0o600
            );
            // Set-user-ID and the like are not carried over to a file with a new owner.
            fs::set_permissions(&p, fs::Permissions::from_mode(0o4755)).unwrap();
            write_atomic(&p, b"newer", true).unwrap();
            assert_eq!(
                fs::metadata(&p).unwrap().permissions().mode() & 0o7777,
                0o755
            );
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn reads_a_file_and_through_a_link() {
            let dir = scratch("read");
            let p = dir.join("scene.toml");
            fs::write(&p, "name = \"µ\"\n").unwrap();
            assert_eq!(read_input(&p).unwrap(), "name = \"µ\"\n");
            let link = dir.join("link.toml");
            symlink(&p, &link).unwrap();
            assert_eq!(read_input(&link).unwrap(), "name = \"µ\"\n");
            // Exactly at the limit is fine, one byte over is not.
            fs::write(&p, [b'x'; 10]).unwrap();
            assert_eq!(read_text_capped(&p, 10).unwrap().len(), 10);
            assert!(matches!(
                read_text_capped(&p, 9),
                Err(ReadError::TooLarge {
                    size: 10,
                    limit: 9,
                    ..
                })
            ));
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn a_missing_file_is_not_found() {
            let dir = scratch("missing");
            let p = dir.join("nope.toml");
            let e = read_input(&p).unwrap_err();
            assert!(
                matches!(&e, ReadError::NotFound { path } if path == &p),
                "{e:?}"
            );
            // A dangling link reads as a missing file.
            let link = dir.join("link.toml");
            symlink("nope.toml", &link).unwrap();
            assert!(matches!(read_input(&link), Err(ReadError::NotFound { .. })));
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn devices_fifos_and_directories_are_not_read() {
            let dir = scratch("read-special");
            let start = Instant::now();
            for (path, kind) in [
                (PathBuf::from("/dev/zero"), FileKind::CharDevice),
                (PathBuf::from("/dev/null"), FileKind::CharDevice),
                (dir.clone(), FileKind::Directory),
            ] {
                let e = read_input(&path).unwrap_err();
                assert!(
                    matches!(&e, ReadError::NotARegularFile { kind: k, .. } if *k == kind),
                    "{e:?}"
                );
            }
            // A fifo with no writer: opening it would block forever.
            let pipe = dir.join("pipe");
            mkfifo(&pipe);
            assert!(matches!(
                read_input(&pipe),
                Err(ReadError::NotARegularFile {
                    kind: FileKind::Fifo,
                    ..
                })
            ));
            // A link to /dev/zero is followed, and refused.
            let link = dir.join("zero.toml");
            symlink("/dev/zero", &link).unwrap();
            assert!(matches!(
                read_input(&link),
                Err(ReadError::NotARegularFile {
                    kind: FileKind::CharDevice,
                    ..
                })
            ));
            assert!(start.elapsed() < Duration::from_secs(2));
            fs::remove_dir_all(&dir).unwrap();
        }

        #[test]
        fn a_large_file_is_refused_before_reading() {
            let dir = scratch("large");
            let p = dir.join("big.toml");
            let f = fs::File::create(&p).unwrap();
            // Sparse: takes no disk space.
            f.set_len(MAX_INPUT_BYTES + 1024 * 1024).unwrap();
            drop(f);
            let start = Instant::now();
            let e = read_input(&p).unwrap_err();
            assert!(start.elapsed() < Duration::from_secs(1));
            assert!(
                matches!(
                    e,
                    ReadError::TooLarge {
                        size,
                        limit: MAX_INPUT_BYTES,
                        ..
                    } if size == 17 * 1024 * 1024
                ),
                "{e:?}"
            );
            fs::remove_dir_all(&dir).unwrap();
        }

        /// A file whose size is not what the metadata says (a `/proc` file reports 0 bytes;
        /// a growing file reports its size at the time): the reading itself stops at the
        /// limit.
        #[cfg(target_os = "linux")]
        #[test]
        fn the_limit_holds_while_reading() {
            let status = Path::new("/proc/self/status");
            assert_eq!(fs::metadata(status).unwrap().len(), 0);
            let e = read_text_capped(status, 10).unwrap_err();
            assert!(
                matches!(
                    e,
                    ReadError::TooLarge {
                        size: 11,
                        limit: 10,
                        ..
                    }
                ),
                "{e:?}"
            );
            assert!(read_text_capped(status, MAX_INPUT_BYTES)
                .unwrap()
                .contains("Name:"));
        }

        #[test]
        fn text_that_is_not_utf8_is_refused() {
            let dir = scratch("utf8");
            let p = dir.join("scene.toml");
            fs::write(&p, b"a = 1\nb = 2\nc = \"\xff\"\n").unwrap();
            let e = read_input(&p).unwrap_err();
            assert!(matches!(e, ReadError::NotUtf8 { line: 3, .. }), "{e:?}");
            fs::remove_dir_all(&dir).unwrap();
        }
    }
}
