//! The UI's state and its update logic, free of any terminal: keys and worker messages in,
//! state changes and commands (jobs for the worker, files to write) out. Drawing reads this
//! state only.
//!
//! The state is in three parts (bottom's state per widget), each knowing nothing of the
//! others:
//! - [`Editing`] (`edit.rs`, with `data.rs` for a data scene's read-only rows): the scene,
//!   the PRB matrix and each panel's state;
//! - [`JobClient`] (`jobs.rs`): the jobs sent to the worker, the debounce of edits, where the
//!   worker is;
//! - [`Shown`] (`shown.rs`): what the worker answered, one result slot for every kind of
//!   scene, and the selection view.
//!
//! This file holds them with what is the whole screen's (the prompt, the help, the message);
//! the files that join the parts are the key handling (`keys.rs`, with `prompts.rs` for the
//! prompts and `actions.rs` for what an edit sets going) and the worker's messages
//! (`results.rs`). Plain words (prompts, tones, commands) are in `dialog.rs`; every key goes
//! through the [`keymap`](super::keymap).

mod actions;
mod data;
mod dialog;
mod edit;
mod jobs;
mod keys;
mod prompts;
mod results;
mod shown;

use std::path::PathBuf;

use crate::scene::Scene;

pub use super::panel::Panel;
pub use super::state::text::TextBox;
pub use dialog::{parse_density, Command, PromptKind, Tone, DEFAULT_DENSITY};
pub use edit::{EditTarget, Editing};
pub use jobs::{Activity, JobClient, DEBOUNCE};
pub use shown::{Judged, Shown};

/// A mechanism's mode shapes are drawn with their largest motion this fraction of the
/// unloaded mechanism's size (its bounding box's larger side): visible, and small enough
/// that the modes read as motions about the equilibrium drawn under them.
pub const MODE_SCALE: f64 = 0.15;

/// The whole UI state.
#[derive(Debug)]
pub struct App {
    /// What is being edited: the scene, the model, each panel's state.
    pub edit: Editing,
    /// The jobs sent to the worker and where it is with them.
    pub jobs: JobClient,
    /// What the worker answered, as shown.
    pub shown: Shown,
    /// The prompt open and its text.
    pub prompt: Option<(PromptKind, TextBox)>,
    /// The help overlay is shown.
    pub help: bool,
    /// The help's first line shown (it scrolls where the terminal is too low for every key).
    pub help_scroll: u16,
    /// The last first line the help could show when it was last drawn (its lines less those
    /// that fit): scrolling stops there, so the way back is never dead keys.
    pub help_scroll_max: std::cell::Cell<u16>,
    /// The last message.
    pub message: Option<(String, Tone)>,
    /// The loop should end.
    pub quit: bool,
    /// Monochrome (NO_COLOR).
    pub mono: bool,
    /// The shape chart shows the mode shapes (`M`) instead of the deformed shapes.
    pub show_modes: bool,
    /// The density the exported links get (kg/m^3).
    pub export_density: f64,
    /// The message shown is a worker's failure, cleared by the next good result.
    message_from_worker: bool,
    /// The export file waiting for its density.
    export_path: Option<PathBuf>,
    /// The write waiting for "overwrite? (y/n)".
    overwrite: Option<Command>,
    /// The terminal is below the UI's minimum size, so only the "too small" note is drawn
    /// (set by the event loop from the terminal's size): keys then do only what the note
    /// says ([`App::on_key`]).
    pub too_small: bool,
}

impl App {
    /// The app on `scene`, starting from the scene's own model (`[prb] matrix`) if it has
    /// one ([`Editing::new`]).
    pub fn new(scene: Scene, scene_path: Option<PathBuf>) -> App {
        App {
            edit: Editing::new(scene, scene_path),
            jobs: JobClient::default(),
            shown: Shown::default(),
            prompt: None,
            help: false,
            help_scroll: 0,
            help_scroll_max: std::cell::Cell::new(u16::MAX),
            message: None,
            quit: false,
            mono: false,
            show_modes: false,
            export_density: DEFAULT_DENSITY,
            message_from_worker: false,
            export_path: None,
            overwrite: None,
            too_small: false,
        }
    }

    /// Shows an error message.
    pub fn set_error(&mut self, m: impl Into<String>) {
        self.message = Some((m.into(), Tone::Error));
        self.message_from_worker = false;
    }

    /// Shows an information message.
    pub fn set_info(&mut self, m: impl Into<String>) {
        self.message = Some((m.into(), Tone::Info));
        self.message_from_worker = false;
    }

    /// A message is news about the last action only: the next action that succeeds clears
    /// it (and sets its own, if it has one).
    fn clear_message(&mut self) {
        self.message = None;
        self.message_from_worker = false;
    }

    /// Whether the user has work that is not in any file: an edit of the scene or of the
    /// model since the last save or open (an export writes the model, so it clears the
    /// model's part). What the fits do counts as the user's work only when the user asked
    /// for the fit: `r`, or the live refit of an edit, changes the model they would lose; the
    /// fit the program runs at start-up or after an open does not.
    pub fn unsaved(&self) -> bool {
        self.edit.scene_dirty || self.edit.model_dirty
    }

    /// The scene was written to `path`: nothing is unsaved any more.
    pub fn saved(&mut self, path: PathBuf) {
        self.set_info(format!("saved {} (with the model)", path.display()));
        self.edit.saved(path);
    }

    /// A write would replace `cmd`'s existing file: ask first; `y` sends `cmd` again with
    /// `overwrite` set.
    pub fn ask_overwrite(&mut self, cmd: Command) {
        self.overwrite = Some(cmd);
        self.open_prompt(PromptKind::ConfirmOverwrite, String::new());
    }

    /// How many cases the path the charts show has in the truth shown.
    pub fn shown_cases(&self) -> usize {
        self.shown
            .truth()
            .and_then(|t| t.cases.get(self.edit.shown_path()))
            .map_or(0, Vec::len)
    }

    fn open_prompt(&mut self, kind: PromptKind, text: String) {
        self.prompt = Some((kind, TextBox::new(text)));
    }
}
