//! The command line (DESIGN §6): parses the flags, has the library build the command's
//! report ([`prbfit::report`], one file per command, each report deriving `Serialize` — the
//! `--json` form — and implementing `Display` — the text form), and prints it. `plot` and
//! `tradeoff`, which no other front end has, are built here.
//!
//! Exit status: 0 on success; 2 for bad input (a malformed scene file, a bad flag value, a file
//! that may not be written), with one line on stderr naming the file, line, key or flag; 1 when
//! the computation itself fails (a load past a critical point, say) or the output cannot be
//! written. A closed stdout pipe ends the program quietly with status 0.

mod args;
mod commands;
mod output;
mod plot;
mod tradeoff;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{CommandFactory, FromArgMatches};

use prbfit::cancel::CancelToken;
use prbfit::io::files::{ReadError, WriteError};
use prbfit::prb::PrbMatrix;
use prbfit::report::{self, ReportError};
use prbfit::scene::{Scene, SceneError};
use prbfit::study::{EffectsDecision, Sampling, Study};

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
    Ok(report::parse_matrix(flag, text)?)
}

/// The exit status of a UI ended by a signal (128 + its number), if `e` is that.
#[cfg(feature = "tui")]
fn signalled(e: &anyhow::Error) -> Option<u8> {
    e.downcast_ref::<prbfit::tui::Signalled>()
        .and_then(|s| u8::try_from(128 + s.number).ok())
}

#[cfg(not(feature = "tui"))]
fn signalled(_: &anyhow::Error) -> Option<u8> {
    None
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
        Some(Command::Solve(args)) => commands::solve(args),
        Some(Command::Eval(args)) => commands::eval(args),
        Some(Command::Fit(args)) => commands::fit(args),
        Some(Command::Select(args)) => commands::select(args),
        Some(Command::Tradeoff(args)) => tradeoff::run(args),
        Some(Command::Export(args)) => commands::export(args),
        Some(Command::Plot(args)) => plot::run(args, matches.subcommand_matches("plot")),
        Some(Command::Calibrate(args)) => commands::calibrate(args),
        Some(Command::Fea(args)) => commands::fea(args),
        Some(Command::Modes(args)) => commands::modes(args),
        Some(Command::Tui { scene, scene_flag }) => tui(scene.or(scene_flag)),
        None => tui(None),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.downcast_ref::<output::StdoutClosed>().is_some() => ExitCode::SUCCESS,
        Err(e) if signalled(&e).is_some() => {
            let _ = std::io::Write::write_all(
                &mut std::io::stderr(),
                format!("prbfit: {e}\n").as_bytes(),
            );
            ExitCode::from(signalled(&e).unwrap_or(1))
        }
        Err(e) if e.downcast_ref::<output::Interrupted>().is_some() => {
            let _ = std::io::Write::write_all(
                &mut std::io::stderr(),
                format!("prbfit: {e}\n").as_bytes(),
            );
            ExitCode::from(130)
        }
        Err(e) => {
            let input = e
                .downcast_ref::<ReportError>()
                .is_some_and(ReportError::is_input)
                || e.downcast_ref::<BadInput>().is_some()
                || e.downcast_ref::<SceneError>().is_some()
                || e.downcast_ref::<WriteError>()
                    .is_some_and(|w| !w.is_out_of_room())
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
        let text = report::safe(&cause.to_string().replace('\n', " ")).into_owned();
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
    Ok(report::scene_model(scene)?)
}

/// The scene named by `--scene`, or the built-in one: a cantilever or a mechanism scene.
fn load_scene(common: &Common) -> Result<Scene> {
    Ok(match &common.scene {
        None => Scene::builtin(),
        Some(path) => Scene::from_file(path)?,
    })
}

/// A data scene refused by `command` (see [`report::refuse_data`]).
fn refuse_data(scene: &Scene, command: &str, why: &str) -> Result<()> {
    Ok(report::refuse_data(scene, command, why)?)
}

/// The study of `scene` (its effects decided, its truth solved as `sampling` says), with a
/// progress line; a failure names the scene.
fn study(scene: &Scene, sampling: Sampling) -> Result<Study> {
    let mut line = output::ProgressLine::default();
    let mut progress = |p: &report::Progress<'_>| line.show(p);
    let mut ctl = report::Control {
        cancel: CancelToken::new(),
        progress: &mut progress,
    };
    Ok(report::study(scene, sampling, &mut ctl)?)
}

/// The cantilever scene `command` works on, with `effects = "auto"` decided, and the
/// decision; a mechanism scene is refused.
fn resolved_scene(common: &Common, command: &str) -> Result<(Scene, Option<EffectsDecision>)> {
    let scene = load_scene(common)?;
    report::refuse_mechanism(&scene, command)?;
    Ok(report::resolve_scene(&scene, &CancelToken::new())?)
}

#[cfg(feature = "tui")]
fn tui(path: Option<PathBuf>) -> Result<()> {
    let scene = match &path {
        Some(p) => Scene::from_file(p)?,
        None => Scene::builtin(),
    };
    prbfit::tui::run(scene, path).map_err(|e| match e.downcast::<prbfit::tui::Signalled>() {
        Ok(signalled) => signalled.into(),
        Err(e) => bad(format!("{e:#}")),
    })
}

#[cfg(not(feature = "tui"))]
fn tui(_path: Option<PathBuf>) -> Result<()> {
    Err(bad(
        "this prbfit was built without the terminal UI (cargo feature `tui`); \
         use the headless commands: prbfit --help",
    ))
}
