//! The app's plain words: what a prompt asks ([`PromptKind`]), how a message looks
//! ([`Tone`]), the side effects the run loop carries out ([`Command`]), and how a key reads
//! in a text box; no state.

use std::path::PathBuf;

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use crate::format::Format;

use super::super::keymap::{self, Action, Scope};
use super::super::worker::Job;

/// What a prompt asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PromptKind {
    /// A path to save the scene to.
    SaveScene,
    /// A scene file to open.
    OpenScene,
    /// A path to export the model to.
    ExportModel,
    /// A path to export a mechanism scene's PRB mechanism (or its model file) to.
    ExportMechanism,
    /// A topology or published model name.
    Topology,
    /// Whether to quit with unsaved work.
    ConfirmQuit,
    /// Whether to open another scene over unsaved work.
    ConfirmOpen,
    /// Whether to write over an existing file.
    ConfirmOverwrite,
    /// The density of the exported links (kg/m^3), for their masses.
    ExportDensity,
}

impl PromptKind {
    /// Whether it is a yes/no question, answered by one key (no text).
    pub fn is_question(self) -> bool {
        matches!(
            self,
            PromptKind::ConfirmQuit | PromptKind::ConfirmOpen | PromptKind::ConfirmOverwrite
        )
    }

    /// The prompt's question.
    pub fn question(self) -> &'static str {
        match self {
            PromptKind::SaveScene => "save scene to",
            PromptKind::OpenScene => "open scene",
            PromptKind::ExportModel => "export model to (.toml .json .xml/.mjcf .urdf .sdf .csv)",
            PromptKind::ExportMechanism => {
                "export the PRB mechanism to (.xml/.mjcf: MuJoCo; .toml .json: model file)"
            }
            PromptKind::Topology => "topology (e.g. L-R-R-R, L-RP) or howell-1r, su-3r, chen-3r",
            PromptKind::ConfirmQuit => "unsaved changes: quit anyway? (y/n)",
            PromptKind::ConfirmOpen => "unsaved changes: open another scene anyway? (y/n)",
            PromptKind::ConfirmOverwrite => "the file exists: overwrite? (y/n)",
            PromptKind::ExportDensity => "density of the links, for their masses (kg/m^3)",
        }
    }
}

/// How a message should look.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tone {
    /// News.
    Info,
    /// Something was refused or failed.
    Error,
}

/// Side effects the run loop carries out.
#[derive(Debug)]
pub enum Command {
    /// Hand a job to the worker.
    Submit(Job),
    /// Write the scene, with the model being worked on as its `[prb] matrix`, to a file.
    SaveScene {
        /// The file.
        path: PathBuf,
        /// Replace it if it exists (the user said so).
        overwrite: bool,
    },
    /// Read a scene from a file.
    OpenScene(PathBuf),
    /// Export the model to a file (checked here, written by the worker).
    Export {
        /// The file.
        path: PathBuf,
        /// Replace it if it exists (the user said so).
        overwrite: bool,
    },
}

/// The density the exported links get unless the user types another (water's, kg/m^3).
pub const DEFAULT_DENSITY: f64 = 1000.0;

/// What a key does in a text box.
pub(super) enum TextKey {
    /// A row of the keymap's text scope.
    Action(Action),
    /// A character to type.
    Char(char),
    /// Nothing (Ctrl with a key the text box does not use, a function key).
    None,
}

/// How `key` reads in a text box (an editor or a prompt).
pub(super) fn text_action(key: &KeyEvent) -> TextKey {
    if let Some(a) = keymap::action(key, Scope::TEXT) {
        return TextKey::Action(a);
    }
    match key.code {
        KeyCode::Char(c)
            if !key
                .modifiers
                .intersects(KeyModifiers::CONTROL | KeyModifiers::ALT) =>
        {
            TextKey::Char(c)
        }
        _ => TextKey::None,
    }
}

/// Whether an export in `format` has link masses (the robot formats).
pub(super) fn has_masses(format: Format) -> bool {
    matches!(format, Format::Mjcf | Format::Urdf | Format::Sdf)
}

/// A density typed as a number of kg/m^3, with or without the unit.
pub fn parse_density(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let number = ["kg/m^3", "kg/m3", "kg/m³"]
        .iter()
        .find_map(|u| t.strip_suffix(u))
        .unwrap_or(t)
        .trim();
    match number.parse::<f64>() {
        // The scene's rule, so the prompt keeps no density the export would refuse.
        Ok(d) => crate::scene::rules::density(d)
            .map(|()| d)
            .map_err(|why| format!("density: {why} (steel 7850, aluminium 2700)")),
        Err(_) => Err(format!(
            "density: `{t}` is not a number of kg/m^3 > 0 (steel 7850, aluminium 2700)"
        )),
    }
}
