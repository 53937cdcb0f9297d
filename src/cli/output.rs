//! Writing results: every command builds a report that derives `Serialize` (the `--json`
//! form) and implements `Display` (the text form); this module prints one or the other.
//!
//! Output that cannot be written is handled like Unix tools do: a closed pipe
//! (`prbfit solve | head -1`) ends the program quietly, any other failed write (`> /dev/full`)
//! is one line on stderr and exit status 1 — never a panic.

use prbfit::cancel::CancelToken;
use std::fmt::Display;
use std::io::Write;

use serde::Serialize;

/// The reader of stdout has gone (a closed pipe): stop quietly.
#[derive(Debug, thiserror::Error)]
#[error("stdout was closed")]
pub struct StdoutClosed;

/// The command was interrupted (Ctrl-C): exit status 130, the shell's for SIGINT.
#[derive(Debug, thiserror::Error)]
#[error("interrupted (Ctrl-C){0}")]
pub struct Interrupted(pub &'static str);

/// Makes Ctrl-C (SIGINT) cancel `cancel` instead of killing the process, so a long run stops
/// at its next check and says what it has; a second Ctrl-C ends the process at once (status
/// 130). Should the handler not install, Ctrl-C keeps its default, which also ends the run.
pub fn cancel_on_interrupt(cancel: &CancelToken) {
    use signal_hook::consts::SIGINT;
    use signal_hook::flag;
    // The first registered action runs first: with the flag already set (a second Ctrl-C)
    // the process ends; otherwise the flag is set.
    if flag::register_conditional_shutdown(SIGINT, 130, cancel.flag()).is_ok() {
        let _ = flag::register(SIGINT, cancel.flag());
    }
}

/// Stdout could not be written (a full disk, `/dev/full`).
#[derive(Debug, thiserror::Error)]
#[error("cannot write the output: {0}")]
pub struct OutputFailed(std::io::Error);

/// Prints `report` as JSON (`json`) or as text.
pub fn emit<R: Serialize + Display>(report: &R, json: bool) -> anyhow::Result<()> {
    let text = if json {
        let value = serde_json::to_value(report)?;
        anyhow::ensure!(
            prbfit::report::all_finite(&value),
            "internal error: a result is not a finite number"
        );
        let mut s = serde_json::to_string_pretty(&value)?;
        s.push('\n');
        s
    } else {
        report.to_string()
    };
    write_stdout(text.as_bytes())
}

/// Writes to stdout, mapping a closed pipe to [`StdoutClosed`] and other failures to
/// [`OutputFailed`].
pub fn write_stdout(bytes: &[u8]) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(StdoutClosed.into()),
        Err(e) => Err(OutputFailed(e).into()),
    }
}

/// A progress line on stderr for long runs, shown only when stderr is a terminal and only
/// once a run has taken longer than [`Progress::DELAY`] (quick commands print nothing extra),
/// redrawn at most every [`Progress::INTERVAL`], and erased when done, so stdout (text or
/// JSON) is never touched.
pub struct Progress {
    label: &'static str,
    start: std::time::Instant,
    last: Option<std::time::Instant>,
    out: Option<Box<dyn Write>>,
    delay: std::time::Duration,
}

impl Progress {
    /// How long a run goes before its progress shows.
    pub const DELAY: std::time::Duration = std::time::Duration::from_millis(500);
    /// Least time between redraws.
    pub const INTERVAL: std::time::Duration = std::time::Duration::from_millis(100);

    /// Progress of `label` on stderr, when stderr is a terminal.
    pub fn new(label: &'static str) -> Progress {
        use std::io::IsTerminal;
        let out: Option<Box<dyn Write>> = std::io::stderr()
            .is_terminal()
            .then(|| Box::new(std::io::stderr()) as Box<dyn Write>);
        Progress::to(label, out, Self::DELAY)
    }

    /// Progress written to `out` (tests), shown after `delay`.
    pub fn to(
        label: &'static str,
        out: Option<Box<dyn Write>>,
        delay: std::time::Duration,
    ) -> Progress {
        Progress {
            label,
            start: std::time::Instant::now(),
            last: None,
            out,
            delay,
        }
    }

    /// Redraws the line with `what` (built only when it will be shown).
    pub fn update(&mut self, what: impl FnOnce() -> String) {
        let Some(out) = self.out.as_mut() else { return };
        let now = std::time::Instant::now();
        let elapsed = now.duration_since(self.start);
        let due = self
            .last
            .is_none_or(|t| now.duration_since(t) >= Self::INTERVAL);
        if elapsed < self.delay || !due {
            return;
        }
        self.last = Some(now);
        // A progress line that cannot be drawn is not worth failing the run for.
        let _ = write!(
            out,
            "\r\x1b[2K{}: {} ({:.1} s)",
            self.label,
            what(),
            elapsed.as_secs_f64()
        );
        let _ = out.flush();
    }

    /// Erases the line, if one was drawn.
    pub fn finish(&mut self) {
        if let (Some(out), Some(_)) = (self.out.as_mut(), self.last) {
            let _ = write!(out, "\r\x1b[2K");
            let _ = out.flush();
            self.last = None;
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// The progress line of the phase running now: a new line (the old one erased) when the
/// phase changes.
#[derive(Default)]
pub struct ProgressLine(Option<(&'static str, Progress)>);

impl ProgressLine {
    /// Shows `p` on the line of its phase.
    pub fn show(&mut self, p: &prbfit::report::Progress<'_>) {
        let label = p.label();
        if self.0.as_ref().is_none_or(|(l, _)| *l != label) {
            // The old phase's line is erased when it is dropped.
            self.0 = None;
            self.0 = Some((label, Progress::new(label)));
        }
        if let Some((_, line)) = self.0.as_mut() {
            line.update(|| p.to_string());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    #[derive(Clone, Default)]
    struct Sink(Arc<Mutex<Vec<u8>>>);

    impl Write for Sink {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0
                .lock()
                .map_err(|_| std::io::ErrorKind::Other)?
                .extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn progress_shows_only_on_a_terminal_after_the_delay_and_is_erased() {
        let sink = Sink::default();
        let mut p = Progress::to("solve", Some(Box::new(sink.clone())), Progress::DELAY);
        p.update(|| "1/3 paths".into());
        assert!(sink.0.lock().unwrap().is_empty(), "shown before the delay");
        drop(p);
        assert!(
            sink.0.lock().unwrap().is_empty(),
            "erased what was never drawn"
        );

        let mut p = Progress::to("solve", Some(Box::new(sink.clone())), Duration::ZERO);
        p.update(|| "2/3 paths".into());
        p.update(|| "3/3 paths".into()); // within the interval: not drawn
        p.finish();
        let text = String::from_utf8(sink.0.lock().unwrap().clone()).unwrap();
        assert!(text.contains("solve: 2/3 paths"), "{text:?}");
        assert!(!text.contains("3/3"), "{text:?}");
        assert!(text.ends_with("\r\x1b[2K"), "{text:?}");

        // Not a terminal: nothing at all, and the message is never even built.
        let mut p = Progress::to("solve", None, Duration::ZERO);
        p.update(|| unreachable!("no terminal, no text"));
    }

    use std::time::Duration;
}
