//! The commands' reports (DESIGN §6, §12): what `prbfit solve`, `eval`, `fit`, `select`,
//! `calibrate`, `export` and `fea` compute from a scene and their arguments, as one value per
//! command that derives `Serialize` (the CLI's `--json` object, the Python module's
//! `to_dict()`) and implements `Display` (the CLI's text). One file per command; the CLI
//! (the binary) and the Python module (`python/`) are thin front ends over it.
//!
//! Every command takes the scene, its arguments as a plain struct, and a [`Control`] (a
//! cancel token and a progress callback), and returns its report or a [`ReportError`]: bad
//! input ([`ReportError::Input`], the CLI's exit status 2) or a failed computation
//! ([`ReportError::Solve`], exit status 1), with the CLI's one-line message.

pub mod calibrate;
mod common;
pub mod eval;
pub mod export;
pub mod fea;
pub mod fea_mech;
pub mod fit;
pub mod modes;
pub mod select;
pub mod solve;
mod stage;

use std::error::Error as StdError;
use std::fmt;

use crate::beam::Resolution;
use crate::cancel::CancelToken;
use crate::fit::FitProgress;
use crate::io::files::{ReadError, WriteError};
use crate::prb::PrbMatrix;
use crate::scene::{Scene, SceneError};
use crate::study::{resolve_effects, EffectsDecision, Sampling, Study};

pub use common::{fixed, frequency_lines, met, mpa, num, safe, DecisionLine, TruthInfo, TruthLine};

/// Why a command produced no report.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReportError {
    /// Bad input (a malformed scene, a bad argument, a file that may not be written): the
    /// CLI's exit status 2. The message names the argument, file, line or key.
    #[error("{0}")]
    Input(String),
    /// The computation failed (a load past a critical point, no model can follow the
    /// scene): the CLI's exit status 1.
    #[error("{0}")]
    Solve(String),
}

impl ReportError {
    /// Bad input with this message.
    pub fn input(message: impl Into<String>) -> ReportError {
        ReportError::Input(message.into())
    }

    /// A failed computation with this message.
    pub fn solve(message: impl Into<String>) -> ReportError {
        ReportError::Solve(message.into())
    }

    /// A failed computation: `e` and its causes on one line.
    pub fn failed(e: &(dyn StdError + 'static)) -> ReportError {
        ReportError::Solve(chain_line(None, e))
    }

    /// A failed computation in `context`: the context, `e` and its causes on one line.
    pub fn failed_in(context: impl fmt::Display, e: &(dyn StdError + 'static)) -> ReportError {
        ReportError::Solve(chain_line(Some(context.to_string()), e))
    }

    /// Bad input in `context` (a scene or a file the user gave).
    pub fn input_in(context: impl fmt::Display, e: &(dyn StdError + 'static)) -> ReportError {
        ReportError::Input(chain_line(Some(context.to_string()), e))
    }

    /// Whether this is bad input (exit status 2) rather than a failed computation.
    pub fn is_input(&self) -> bool {
        matches!(self, ReportError::Input(_))
    }

    /// The one-line message.
    pub fn message(&self) -> &str {
        match self {
            ReportError::Input(m) | ReportError::Solve(m) => m,
        }
    }
}

/// An error and its causes on one line, after `context` if given. A cause whose text the
/// line already contains (an error that displays its source and also returns it from
/// `source()`) is not repeated.
pub fn chain_line(context: Option<String>, e: &(dyn StdError + 'static)) -> String {
    let mut out = context.unwrap_or_default();
    let mut cause = Some(e);
    while let Some(c) = cause {
        let text = c.to_string().replace('\n', " ");
        if !out.contains(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&text);
        }
        cause = c.source();
    }
    out
}

impl From<SceneError> for ReportError {
    fn from(e: SceneError) -> ReportError {
        ReportError::Input(chain_line(None, &e))
    }
}

impl From<ReadError> for ReportError {
    fn from(e: ReadError) -> ReportError {
        ReportError::Input(chain_line(None, &e))
    }
}

/// A file that may not be written is bad input (exit status 2); one that cannot be written
/// for want of room (a full disk) is a failure (exit status 1), as docs/cli.md says.
impl From<WriteError> for ReportError {
    fn from(e: WriteError) -> ReportError {
        if e.is_out_of_room() {
            ReportError::Solve(chain_line(None, &e))
        } else {
            ReportError::Input(chain_line(None, &e))
        }
    }
}

/// The report layer's result.
pub type Result<T> = std::result::Result<T, ReportError>;

/// How far a long command has got, for a progress line or a callback.
#[derive(Debug, Clone, Copy)]
pub enum Progress<'a> {
    /// The scene's truth being solved: `done` of `paths` load paths (drives), `cases` so far.
    Truth {
        /// Paths done.
        done: usize,
        /// Paths in all.
        paths: usize,
        /// Cases so far.
        cases: usize,
    },
    /// `solve` along the scene's load paths: path `path` (from 1) of `paths`.
    Solving {
        /// The path being solved, from 1.
        path: usize,
        /// Paths in all.
        paths: usize,
        /// Cases so far.
        cases: usize,
    },
    /// A fit's search.
    Fit(&'a FitProgress<'a>),
    /// `select`: `done` models judged, the last one named.
    Select {
        /// Models judged so far.
        done: usize,
        /// The last model judged.
        last: &'a str,
    },
    /// `select`: the ladder's fit of `topology` under way, `done` models judged before it.
    SelectFit {
        /// Models judged so far.
        done: usize,
        /// The topology being fitted.
        topology: &'a str,
        /// Its fit's progress.
        fit: &'a FitProgress<'a>,
    },
    /// `fea`: load path `path` of `paths` solved by CalculiX.
    Fea {
        /// The path solved, from 1.
        path: usize,
        /// Paths in all.
        paths: usize,
    },
}

impl Progress<'_> {
    /// The phase, as a progress line's label.
    pub fn label(&self) -> &'static str {
        match self {
            Progress::Truth { .. } => "solving the truth",
            Progress::Solving { .. } => "solving",
            Progress::Fit(_) => "fitting",
            Progress::Select { .. } | Progress::SelectFit { .. } => "selecting",
            Progress::Fea { .. } => "fea",
        }
    }
}

impl fmt::Display for Progress<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Progress::Truth { done, paths, cases } => {
                write!(f, "path {done}/{paths}, {cases} cases")
            }
            Progress::Solving { path, paths, cases } => {
                write!(f, "load path {path}/{paths}, {cases} cases so far")
            }
            Progress::Fit(p) => write!(
                f,
                "{} iteration {}, {} evaluations, best J {:.4e}",
                p.phase, p.iteration, p.evaluations, p.best_objective
            ),
            Progress::Select { done, last } => write!(f, "{done} models judged, last {last}"),
            Progress::SelectFit {
                done,
                topology,
                fit,
            } => write!(
                f,
                "{done} models judged; fitting {topology}: {}",
                Progress::Fit(fit)
            ),
            Progress::Fea { path, paths } => write!(f, "load path {path}/{paths} solved"),
        }
    }
}

/// What a caller controls in a running command: a cancel token the long loops check, and
/// where progress goes.
pub struct Control<'a> {
    /// Cancelled: the command stops at its next check (its result is then an error or a
    /// partial one; the caller that cancelled knows to discard it).
    pub cancel: CancelToken,
    /// Called as the command goes.
    pub progress: &'a mut dyn FnMut(&Progress<'_>),
}

impl fmt::Debug for Control<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Control")
            .field("cancel", &self.cancel)
            .finish_non_exhaustive()
    }
}

/// Parses the matrix given to `flag`; errors name the flag and the text.
pub fn parse_matrix(flag: &str, text: &str) -> Result<PrbMatrix> {
    PrbMatrix::parse(text).map_err(|e| ReportError::input(format!("{flag} \"{text}\": {e}")))
}

/// The scene's own model (`[prb] matrix`), named "scene", for commands given no model.
pub fn scene_model(scene: &Scene) -> Result<(String, PrbMatrix)> {
    scene
        .prb
        .clone()
        .map(|m| ("scene".to_string(), m))
        .ok_or_else(|| {
            ReportError::input(format!(
                "give a model (--prb MATRIX or --model NAME_OR_FILE), or put one in the scene \
             \"{}\" as [prb] matrix = \"...\"",
                safe(&scene.name)
            ))
        })
}

/// Mechanism scenes (DESIGN §8) are solved, judged, fitted and selected on by `solve`,
/// `eval`, `fit` and `select`, drawn by `plot`, exported by `export` and edited in the UI;
/// the other commands cannot take them yet: say so (bad input) instead of judging a
/// cantilever that is not there.
pub fn refuse_mechanism(scene: &Scene, command: &str) -> Result<()> {
    match &scene.mechanism {
        None => Ok(()),
        Some(m) => Err(ReportError::input(format!(
            "\"{}\" is a mechanism scene ({} flexures, {} drive paths): mechanism scenes are \
             not supported by `{command}` yet (`solve`, `eval`, `fit`, `select`, `plot`, \
             `export` and the UI take them)",
            safe(&scene.name),
            m.flexures.len(),
            m.drives.len()
        ))),
    }
}

/// Commands that have nothing to say about measured data refuse a data scene (DESIGN §9),
/// naming what does work on it, instead of solving the nominal beam as if it were the truth.
pub fn refuse_data(scene: &Scene, command: &str, why: &str) -> Result<()> {
    match &scene.truth {
        None => Ok(()),
        Some(t) => Err(ReportError::input(format!(
            "\"{}\" is a data scene (its truth is {}): `{command}` {why}; eval, fit, select, \
             calibrate, export, plot{} work on it (eval shows the beam's own error against the \
             data)",
            safe(&scene.name),
            safe(&t.file),
            if scene.mechanism.is_some() {
                ""
            } else {
                " and the UI (prbfit tui)"
            }
        ))),
    }
}

/// The scene with `effects = "auto"` decided, and the decision.
pub fn resolve_scene(
    scene: &Scene,
    cancel: &CancelToken,
) -> Result<(Scene, Option<EffectsDecision>)> {
    resolve_effects(scene, Resolution::default(), cancel)
        .map_err(|e| ReportError::failed_in("deciding the beam effects", &e))
}

/// The beam resolution of `--tol`, checked on every flexure's beam so that a bad `--tol` is
/// bad input naming the flag.
pub fn resolution(scene: &Scene, tol: f64) -> Result<Resolution> {
    let resolution = Resolution::with_tol(tol);
    Study::check_resolution(scene, resolution)
        .map_err(|e| ReportError::input(format!("--tol {}: {e}", num(tol))))?;
    Ok(resolution)
}

/// The study of `scene` (its effects decided, its truth solved as `sampling` says), its
/// progress reported; a failure names the scene.
pub fn study(scene: &Scene, sampling: Sampling, ctl: &mut Control<'_>) -> Result<Study> {
    let progress = &mut *ctl.progress;
    Study::solve(scene, sampling, &ctl.cancel, &mut |done, paths, cases| {
        progress(&Progress::Truth { done, paths, cases });
    })
    .map_err(|e| ReportError::failed_in(format!("scene \"{}\"", safe(&scene.name)), &e))
}

/// JSON keys whose value may be `null` by design (or, for a list, hold `null`s: a path
/// without a stroke limit, a flexure without an allowable stress); any other `null` would be
/// a non-finite number that serde_json wrote as `null`, and is refused.
const NULLABLE: [&str; 7] = [
    "effects_decision",
    "chosen",
    "max_stress",
    "max_stress_at",
    "allowable_stress",
    "stroke_limits",
    "within_stroke",
];

/// Whether a report's JSON holds only finite numbers: serde_json writes NaN and infinity as
/// `null`, so any `null` outside the keys that may be null by design was one. The CLI's
/// `--json` and the Python module's results both refuse such a report.
pub fn all_finite(v: &serde_json::Value) -> bool {
    match v {
        serde_json::Value::Null => false,
        serde_json::Value::Array(a) => a.iter().all(all_finite),
        serde_json::Value::Object(o) => o.iter().all(|(k, v)| {
            let nullable = NULLABLE.contains(&k.as_str());
            match v {
                serde_json::Value::Null => nullable,
                serde_json::Value::Array(a) if nullable => {
                    a.iter().all(|x| x.is_null() || all_finite(x))
                }
                _ => all_finite(v),
            }
        }),
        _ => true,
    }
}
