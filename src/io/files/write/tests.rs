//! The atomic writer's tests: what it writes, refuses and leaves alone, and how it says so.
#![allow(clippy::unwrap_used)]

use super::super::scratch::{chain, leftovers, scratch};
use super::*;

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

/// A new file whose directory is missing is refused before anything is written (and before a
/// command spends time on what it would write), naming the directory; the check and the
/// write say the same. One under a plain file gets the system's `Not a directory`.
#[test]
fn a_missing_directory_is_named_before_the_write() {
    let dir = scratch("once");
    let missing = dir.join("no/such/dir/m.toml");
    for e in [
        check_target(&missing, false).unwrap_err(),
        write_atomic(&missing, b"new", true).unwrap_err(),
    ] {
        assert!(std::error::Error::source(&e).is_none());
        assert_eq!(e.path(), missing);
        assert!(
            matches!(&e, WriteError::Io { error, .. } if error.kind() == io::ErrorKind::NotFound)
        );
        assert!(!e.is_out_of_room());
        assert_eq!(
            chain(e),
            format!(
                "{}: its directory {} does not exist",
                missing.display(),
                dir.join("no/such/dir").display()
            )
        );
    }
    let file = dir.join("plain");
    fs::write(&file, b"x").unwrap();
    let under_file = file.join("m.toml");
    let e = check_target(&under_file, true).unwrap_err();
    assert_eq!(
        chain(e),
        format!(
            "{}: {}",
            under_file.display(),
            io::Error::from_raw_os_error(20)
        )
    );
    // A file in the working directory has one.
    check_target(Path::new("prbfit-no-such-file-here.toml"), false).unwrap();
    assert_eq!(leftovers(&dir), 0);
    fs::remove_dir_all(&dir).unwrap();
}

/// The operating system's message is printed once, not again as the error's source.
#[test]
fn an_os_error_is_printed_once() {
    // A permission error built by hand (root can't provoke one).
    let e = WriteError::Io {
        path: "m.toml".into(),
        error: io::Error::from_raw_os_error(13),
    };
    assert!(std::error::Error::source(&e).is_none());
    let printed = chain(e);
    assert_eq!(
        printed,
        format!("m.toml: {}", io::Error::from_raw_os_error(13))
    );
    assert_eq!(printed.matches("os error 13").count(), 1, "{printed:?}");
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
}

#[cfg(unix)]
mod unix {
    use super::super::super::scratch::{is_symlink, leftovers, mkfifo, scratch};
    use super::*;
    use std::os::unix::fs::{symlink, FileTypeExt, PermissionsExt};
    use std::process::Command;

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
}

/// A full disk (or quota, or a failing device) is the output that cannot be written, which
/// the CLI reports with exit status 1; a path that may not be written (no such directory,
/// no permission, an existing file) is bad input, exit status 2.
#[test]
fn a_full_disk_is_out_of_room_and_a_forbidden_path_is_not() {
    let io = |error: io::Error| WriteError::Io {
        path: PathBuf::from("out.svg"),
        error,
    };
    for room in [28, 122, 5, 27] {
        // ENOSPC, EDQUOT, EIO, EFBIG.
        assert!(
            io(io::Error::from_raw_os_error(room)).is_out_of_room(),
            "{room}"
        );
    }
    assert!(io(io::ErrorKind::WriteZero.into()).is_out_of_room());
    for refused in [2, 13, 21, 30] {
        // ENOENT, EACCES, EISDIR, EROFS.
        assert!(
            !io(io::Error::from_raw_os_error(refused)).is_out_of_room(),
            "{refused}"
        );
    }
    assert!(!WriteError::Exists(PathBuf::from("out.svg")).is_out_of_room());
}
