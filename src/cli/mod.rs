//! The command line (DESIGN §6): one file per command, each building a report that derives
//! `Serialize` (the `--json` form) and implements `Display` (the text form).
//!
//! Exit status: 0 on success; 2 for bad input (a malformed scene file, a bad flag value, a file
//! that may not be written), with one line on stderr naming the file, line, key or flag; 1 when
//! the computation itself fails (a load past a critical point, say) or the output cannot be
//! written. A closed stdout pipe ends the program quietly with status 0.

mod args;
mod calibrate;
mod eval;
mod export;
mod fea;
mod fea_mech;
mod fit;
mod output;
mod plot;
mod select;
mod solve;
mod stage;
mod tradeoff;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{CommandFactory, FromArgMatches};

use prbfit::beam::Resolution;
use prbfit::cancel::CancelToken;
use prbfit::io::files::{ReadError, WriteError};
use prbfit::prb::PrbMatrix;
use prbfit::scene::{Scene, SceneError};
use prbfit::study::{resolve_effects, EffectsDecision, Sampling, Study};

use args::{Cli, Command, Common};

/// An error in what the user gave us: exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct BadInput(String);

/// A bad-input error with this message.
fn bad(message: impl Into<String>) -> anyhow::Error {
    BadInput(message.into()).into()
}

/// Parses the matrix given to `flag`; errors name the flag and the text.
fn parse_matrix(flag: &str, text: &str) -> Result<PrbMatrix> {
    PrbMatrix::parse(text).map_err(|e| bad(format!("{flag} \"{text}\": {e}")))
}

/// Parses the command line and runs the command; the process's exit status.
pub fn run() -> ExitCode {
    // The matches are kept beside the parsed flags: `plot` needs the order in which its
    // repeatable --model and --prb were given, which the derived struct loses.
    let matches = match Cli::command().try_get_matches() {
        Ok(m) => m,
        Err(e) => return clap_error(e),
    };
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => return clap_error(e.format(&mut Cli::command())),
    };
    let outcome = match cli.command {
        Some(Command::Solve(args)) => solve::run(args),
        Some(Command::Eval(args)) => eval::run(args),
        Some(Command::Fit(args)) => fit::run(args),
        Some(Command::Select(args)) => select::run(args),
        Some(Command::Tradeoff(args)) => tradeoff::run(args),
        Some(Command::Export(args)) => export::run(args),
        Some(Command::Plot(args)) => plot::run(args, matches.subcommand_matches("plot")),
        Some(Command::Calibrate(args)) => calibrate::run(args),
        Some(Command::Fea(args)) => fea::run(args),
        Some(Command::Tui { scene }) => tui(scene),
        None => tui(None),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.downcast_ref::<output::StdoutClosed>().is_some() => ExitCode::SUCCESS,
        Err(e) => {
            let input = e.downcast_ref::<BadInput>().is_some()
                || e.downcast_ref::<SceneError>().is_some()
                || e.downcast_ref::<WriteError>().is_some()
                || e.downcast_ref::<ReadError>().is_some();
            // stderr may be closed too; there is nowhere left to say so.
            let _ = std::io::Write::write_all(
                &mut std::io::stderr(),
                format!("prbfit: {}\n", one_line(&e)).as_bytes(),
            );
            ExitCode::from(if input { 2 } else { 1 })
        }
    }
}

/// clap's message is several lines; the contract is one line naming the flag: the message
/// up to the usage, joined. Help and version go to stdout with status 0.
fn clap_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        return match output::write_stdout(e.render().to_string().as_bytes()) {
            Ok(()) => ExitCode::SUCCESS,
            Err(err) if err.downcast_ref::<output::StdoutClosed>().is_some() => ExitCode::SUCCESS,
            Err(_) => ExitCode::from(1),
        };
    }
    let text = e.to_string();
    let joined = text
        .lines()
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("tip:"))
        .collect::<Vec<_>>()
        .join(" ");
    let first = if joined.is_empty() {
        "invalid arguments"
    } else {
        joined.as_str()
    };
    let first = first.trim_start_matches("error: ");
    let _ = std::io::Write::write_all(
        &mut std::io::stderr(),
        format!("prbfit: {first} (see prbfit --help)\n").as_bytes(),
    );
    ExitCode::from(2)
}

/// The error and its causes on one line. A cause whose text the message before it already
/// contains (an error that displays its source and also returns it from `source()`) is not
/// repeated.
fn one_line(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = output::safe(&cause.to_string().replace('\n', " ")).into_owned();
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out
}

/// The scene's own model (`[prb] matrix`), named "scene", for commands given no model.
fn scene_model(scene: &Scene) -> Result<(String, PrbMatrix)> {
    scene
        .prb
        .clone()
        .map(|m| ("scene".to_string(), m))
        .ok_or_else(|| {
            bad(format!(
                "give a model (--prb MATRIX or --model NAME_OR_FILE), or put one in the scene \
             \"{}\" as [prb] matrix = \"...\"",
                output::safe(&scene.name)
            ))
        })
}

/// The scene named by `--scene`, or the built-in one: a cantilever or a mechanism scene.
fn load_scene(common: &Common) -> Result<Scene> {
    Ok(match &common.scene {
        None => Scene::builtin(),
        Some(path) => Scene::from_file(path)?,
    })
}

/// Mechanism scenes (DESIGN §8) are solved, judged, fitted and selected on by `solve`,
/// `eval`, `fit` and `select`, drawn by `plot`, exported by `export` and edited in the UI;
/// the other commands cannot take them yet: say so (bad input, exit 2) instead of
/// judging a cantilever that is not there.
fn refuse_mechanism(scene: &Scene, command: &str) -> Result<()> {
    match &scene.mechanism {
        None => Ok(()),
        Some(m) => Err(bad(format!(
            "\"{}\" is a mechanism scene ({} flexures, {} drive paths): mechanism scenes are \
             not supported by `{command}` yet (`solve`, `eval`, `fit`, `select`, `plot`, \
             `export` and the UI take them)",
            output::safe(&scene.name),
            m.flexures.len(),
            m.drives.len()
        ))),
    }
}

/// Commands that have nothing to say about measured data refuse a data scene (DESIGN §9),
/// naming what does work on it, instead of solving the nominal beam as if it were the truth.
fn refuse_data(scene: &Scene, command: &str, why: &str) -> Result<()> {
    match &scene.truth {
        None => Ok(()),
        Some(t) => Err(bad(format!(
            "\"{}\" is a data scene (its truth is {}): `{command}` {why}; eval, fit, select, \
             calibrate, export, plot{} work on it (eval shows the beam's own error against the \
             data)",
            output::safe(&scene.name),
            output::safe(&t.file),
            if scene.mechanism.is_some() {
                ""
            } else {
                " and the UI (prbfit tui)"
            }
        ))),
    }
}

/// The scene with `effects = "auto"` decided, and the decision.
fn resolve_scene(scene: &Scene) -> Result<(Scene, Option<EffectsDecision>)> {
    resolve_effects(scene, Resolution::default(), &CancelToken::new())
        .context("deciding the beam effects")
}

/// The beam resolution of `--tol`, checked on every flexure's beam so that a bad `--tol` is
/// bad input naming the flag.
fn resolution(scene: &Scene, tol: f64) -> Result<Resolution> {
    let resolution = Resolution::with_tol(tol);
    Study::check_resolution(scene, resolution)
        .map_err(|e| bad(format!("--tol {}: {e}", output::num(tol))))?;
    Ok(resolution)
}

/// The study of `scene` (its effects decided, its truth solved as `sampling` says), with a
/// progress line; a failure names the scene.
fn study(scene: &Scene, sampling: Sampling) -> Result<Study> {
    let mut progress = output::Progress::new("solving the truth");
    let study = Study::solve(
        scene,
        sampling,
        &CancelToken::new(),
        &mut |done, paths, cases| {
            progress.update(|| format!("path {done}/{paths}, {cases} cases"));
        },
    )
    .with_context(|| format!("scene \"{}\"", output::safe(&scene.name)))?;
    progress.finish();
    Ok(study)
}

/// The cantilever scene `command` works on, with `effects = "auto"` decided, and the
/// decision; a mechanism scene is refused.
fn resolved_scene(common: &Common, command: &str) -> Result<(Scene, Option<EffectsDecision>)> {
    let scene = load_scene(common)?;
    refuse_mechanism(&scene, command)?;
    resolve_scene(&scene)
}

#[cfg(feature = "tui")]
fn tui(path: Option<PathBuf>) -> Result<()> {
    let scene = match &path {
        Some(p) => Scene::from_file(p)?,
        None => Scene::builtin(),
    };
    prbfit::tui::run(scene, path).map_err(|e| bad(format!("{e:#}")))
}

#[cfg(not(feature = "tui"))]
fn tui(_path: Option<PathBuf>) -> Result<()> {
    Err(bad(
        "this prbfit was built without the terminal UI (cargo feature `tui`); \
         use the headless commands: prbfit --help",
    ))
}
