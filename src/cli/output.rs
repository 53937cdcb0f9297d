//! Writing results: every command builds a report that derives `Serialize` (the `--json`
//! form) and implements `Display` (the text form); this module prints one or the other.
//!
//! Output that cannot be written is handled like Unix tools do: a closed pipe
//! (`prbfit solve | head -1`) ends the program quietly, any other failed write (`> /dev/full`)
//! is one line on stderr and exit status 1 — never a panic.

use std::fmt::{self, Display};
use std::io::Write;

use serde::Serialize;

use prbfit::mech::figures::Figures;
use prbfit::study::{CaseForm, EffectsDecision, Study};

/// The reader of stdout has gone (a closed pipe): stop quietly.
#[derive(Debug, thiserror::Error)]
#[error("stdout was closed")]
pub struct StdoutClosed;

/// Stdout could not be written (a full disk, `/dev/full`).
#[derive(Debug, thiserror::Error)]
#[error("cannot write the output: {0}")]
pub struct OutputFailed(std::io::Error);

/// JSON keys whose value may be `null` by design; any other `null` would be a non-finite
/// number that serde_json wrote as `null`, and is refused.
const NULLABLE: [&str; 2] = ["effects_decision", "chosen"];

/// Prints `report` as JSON (`json`) or as text.
pub fn emit<R: Serialize + Display>(report: &R, json: bool) -> anyhow::Result<()> {
    let text = if json {
        let value = serde_json::to_value(report)?;
        anyhow::ensure!(
            finite(&value),
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

fn finite(v: &serde_json::Value) -> bool {
    match v {
        serde_json::Value::Null => false,
        serde_json::Value::Array(a) => a.iter().all(finite),
        serde_json::Value::Object(o) => o
            .iter()
            .all(|(k, v)| (v.is_null() && NULLABLE.contains(&k.as_str())) || finite(v)),
        _ => true,
    }
}

/// A number in bounded width: plain in `[1e-4, 1e6)`, else scientific; at most `sig`
/// significant digits. `1e300` prints as `1e300`, never as 301 digits.
pub fn num(x: f64) -> String {
    prbfit::text::bounded(x)
}

/// Text that came from a file (a scene's name), safe to print on a terminal.
pub fn safe(s: &str) -> std::borrow::Cow<'_, str> {
    prbfit::text::sanitize_terminal(s)
}

/// One line saying what `effects = "auto"` decided, when it was decided.
pub struct DecisionLine<'a>(pub &'a Option<EffectsDecision>);

impl Display for DecisionLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(d) = self.0 else { return Ok(()) };
        let part = |kept: bool| {
            d.impacts
                .iter()
                .filter(|i| i.kept == kept)
                .map(|i| {
                    format!(
                        "{} ({:.1}% of target)",
                        i.effect,
                        i.fraction_of_target * 100.0
                    )
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        write!(
            f,
            "effects auto: kept [{}]; dropped [{}] (together {:.1}% of target; threshold {:.0}%)",
            part(true),
            part(false),
            d.dropped_together_fraction * 100.0,
            d.threshold * 100.0
        )?;
        match &d.plate {
            Some(p) => writeln!(
                f,
                "; section {} (mean plate fraction {:.2}, w0/t0 = {}, w0/L = {}, largest Searle w0^2/(R t0) = {})",
                if p.wide { "wide" } else { "narrow" },
                p.plate_fraction,
                num(p.width_over_thickness),
                num(p.width_over_length),
                num(p.largest_searle)
            ),
            None => writeln!(f),
        }
    }
}

/// "met" or "NOT met".
pub fn met(ok: bool) -> &'static str {
    if ok {
        "met"
    } else {
        "NOT met"
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

/// A data scene's truth as the reports show it (DESIGN §9): the file, its hash, its size, and
/// the scene's own beam judged against it.
#[derive(Debug, Serialize)]
pub struct TruthInfo {
    /// The data file as the scene names it.
    data: String,
    /// SHA-256 of its bytes.
    sha256: String,
    /// Rows (load cases) and paths.
    rows: usize,
    paths: usize,
    /// The beam theory's own error against the data (the scene's nominal `[beam]`; a
    /// mechanism's exact beam mechanism along the measured drives).
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_vs_data: Option<Figures>,
    /// Why the beam could not be judged, when it could not.
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_failure: Option<String>,
    /// How the scene's cases read (the beam's line or the beam mechanism's).
    #[serde(skip)]
    form: CaseForm,
}

impl TruthInfo {
    /// The truth of `study`, if it is measured data, with the scene's own beam (beam
    /// mechanism) judged against it.
    pub fn of(study: &Study) -> Option<TruthInfo> {
        let scene = study.scene();
        let truth = scene.truth.as_ref()?;
        let (beam_vs_data, beam_failure) = match study.beam_against_data() {
            Some(Ok(f)) => (Some(f), None),
            Some(Err(e)) => (None, Some(e)),
            None => (None, None),
        };
        Some(TruthInfo {
            form: study.case_form(),
            data: truth.file.clone(),
            sha256: truth.sha256.clone(),
            rows: truth.row_count(),
            paths: truth
                .stage
                .as_ref()
                .map_or(truth.paths.len(), |s| s.paths.len()),
            beam_vs_data,
            beam_failure,
        })
    }
}

/// The line a report gives a data scene's truth (nothing for a beam scene).
pub struct TruthLine<'a>(pub &'a Option<TruthInfo>);

impl Display for TruthLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(t) = self.0 else { return Ok(()) };
        writeln!(
            f,
            "truth: measured data {} ({} rows in {} path(s), sha256 {}...)",
            safe(&t.data),
            t.rows,
            t.paths,
            t.sha256.get(..12).unwrap_or(&t.sha256)
        )?;
        match (&t.beam_vs_data, &t.beam_failure) {
            (Some(b), _) if t.form == CaseForm::Tip => writeln!(
                f,
                "the scene's beam against the data: rms pos {:.3e}, max pos {:.3e} L; rms ang \
                 {:.3e}, max ang {:.3e} rad; J {:.4e}",
                b.rms_pos_err, b.max_pos_err, b.rms_ang_err, b.max_ang_err, b.objective
            ),
            (Some(b), _) => writeln!(
                f,
                "the scene's beam mechanism against the data: max pos {:.3e} L, max ang {:.3e} \
                 rad, reaction rms {:.3e} max {:.3e}; J {:.4e}",
                b.max_pos_err,
                b.max_ang_err,
                b.rms_force_err.unwrap_or(0.0),
                b.max_force(),
                b.objective
            ),
            (None, Some(why)) => writeln!(f, "the scene's beam against the data: {}", safe(why)),
            (None, None) => Ok(()),
        }
    }
}
