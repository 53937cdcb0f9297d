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
//! [`sanitize_terminal`](crate::text::sanitize_terminal), since a file name can hold escape
//! sequences too.
//!
//! `kind.rs` says what a path is and prints paths and sizes; `read.rs` reads input,
//! `write.rs` writes output; this file adds the clock for provenance.

mod kind;
mod read;
#[cfg(test)]
mod scratch;
mod write;

pub use kind::FileKind;
pub use read::{read_input, read_text_capped, ReadError, MAX_INPUT_BYTES};
pub use write::{check_target, write_atomic, WriteError};

use std::time::{SystemTime, UNIX_EPOCH};

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

    #[test]
    fn timestamps_look_right() {
        let t = utc_timestamp();
        assert_eq!(t.len(), 20);
        assert!(t.starts_with("20") && t.ends_with('Z'));
    }
}
