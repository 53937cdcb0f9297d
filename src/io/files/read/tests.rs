//! The bounded reader's tests: what it reads, what it refuses (devices, fifos, directories,
//! large files, text that is not UTF-8) without blocking, and how it says so.
#![allow(clippy::unwrap_used)]

use super::super::scratch::chain;
use super::*;

#[test]
fn an_os_error_is_printed_once() {
    // A permission error built by hand (root can't provoke one).
    let e = ReadError::Io {
        path: "s.toml".into(),
        error: io::Error::from_raw_os_error(13),
    };
    assert_eq!(
        chain(e),
        format!("s.toml: {}", io::Error::from_raw_os_error(13))
    );
}

#[test]
fn messages_read_well() {
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
}

#[cfg(unix)]
mod unix {
    use super::super::super::scratch::{mkfifo, scratch};
    use super::*;
    use std::os::unix::fs::symlink;
    use std::time::{Duration, Instant};

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
