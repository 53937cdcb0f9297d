//! Writing results: every command builds a report that derives `Serialize` (the `--json`
//! form) and implements `Display` (the text form); this module prints one or the other.
//!
//! Output that cannot be written is handled like Unix tools do: a closed pipe
//! (`prbfit solve | head -1`) ends the program quietly, any other failed write (`> /dev/full`)
//! is one line on stderr and exit status 1 — never a panic.

use std::fmt::{self, Display};
use std::io::Write;

use serde::Serialize;

use prbfit::select::EffectsDecision;

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
        writeln!(
            f,
            "effects auto: kept [{}]; dropped [{}] (together {:.1}% of target; threshold {:.0}%)",
            part(true),
            part(false),
            d.dropped_together_fraction * 100.0,
            d.threshold * 100.0
        )
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
