//! What the app's actions set going, joining its parts: an edit's outcome becomes a
//! debounced job (or a message), jobs are made from the scene and the model being edited,
//! an opened scene replaces what is shown, a model is loaded by name or compared against,
//! the selection view opens and closes.

use std::path::PathBuf;
use std::time::Instant;

use crate::format::Format;
use crate::io::ModelFile;
use crate::prb::published::NAMES as PUBLISHED;
use crate::prb::PrbMatrix;
use crate::scene::Scene;

use super::super::state::select::SelectState;
use super::super::worker::{Job, JobKind};
use super::jobs::kind;
use super::{App, Command, PromptKind};

impl App {
    /// An edit's outcome: a change (`Ok(true)`) is sent as a job once the debounce is over,
    /// a refusal is said; `Ok(false)` did nothing.
    pub(super) fn edited(&mut self, outcome: Result<bool, String>, now: Instant) {
        match outcome {
            Ok(true) => self.jobs.changed(now),
            Ok(false) => {}
            Err(e) => self.set_error(e),
        }
    }

    /// The job of `kind` for the current state (not sent yet).
    fn job(&mut self, kind: JobKind) -> Job {
        let compare = self.shown.compare.as_ref().map(|(_, m)| m);
        self.jobs
            .job(kind, &self.edit.scene, &self.edit.matrix, compare)
    }

    /// Sends a job of `kind` now, cancelling the one before; `by_user`: the user asked for
    /// it, so a fit that changes the model is unsaved work.
    fn send(&mut self, kind: JobKind, by_user: bool) -> Command {
        let job = self.job(kind);
        self.jobs.send(&job, by_user);
        Command::Submit(job)
    }

    /// Sends a fit (or, with `fit` false, a judge) job now, cancelling the one before: the
    /// user asked for it (`r`), so a fit that changes the model is unsaved work.
    pub fn submit(&mut self, fit: bool) -> Command {
        self.send(kind(fit), true)
    }

    /// The first job, at start-up: a fit with live refit on, or only a judge when the scene
    /// brought its own model (`[prb] matrix`: shown as saved; `r` fits it). Not the user's
    /// work: the model it fits does not make the scene "unsaved".
    pub fn start(&mut self) -> Command {
        let fit = self.jobs.live && !self.edit.model_from_scene;
        self.send(kind(fit), false)
    }

    /// Time passes: sends a debounced job when due.
    pub fn tick(&mut self, now: Instant) -> Option<Command> {
        let (kind, by_user) = self.jobs.due(now)?;
        Some(self.send(kind, by_user))
    }

    /// Whether a debounced job is waiting.
    pub fn has_pending(&self) -> bool {
        self.jobs.has_pending()
    }

    /// An export of the current matrix, never over an existing file. Unlike the other jobs
    /// it is a side effect the user asked for: it cancels nothing, a newer job does not
    /// cancel it, and its result is shown whatever job is current by then.
    pub fn export(&mut self, path: PathBuf) -> Command {
        Command::Submit(self.export_job(path, false))
    }

    /// The export job for `path` (replacing the file when `overwrite`), with the links'
    /// density: the scene's `[beam] density`, else, for a robot format, the one typed at the
    /// prompt; else none (a model file without masses, as the CLI writes it).
    pub fn export_job(&mut self, path: PathBuf, overwrite: bool) -> Job {
        let typed = self.export_asks_density(&path);
        let density = self
            .edit
            .scene
            .beam
            .density
            .or(typed.then_some(self.export_density));
        self.job(JobKind::Export {
            path,
            density,
            overwrite,
        })
    }

    /// Whether an export to `path` takes the density typed at its prompt: a robot format
    /// (MJCF, URDF, SDF: their links need masses) of a scene without `[beam] density`.
    pub(super) fn export_asks_density(&self, path: &std::path::Path) -> bool {
        Format::from_path(path).is_some_and(super::dialog::has_masses)
            && self.edit.scene.beam.density.is_none()
    }

    /// The scene was replaced (opened from a file). Nothing is unsaved after an open. A
    /// scene with its own model (`[prb] matrix`) brings it, judged as saved (`r` fits it);
    /// without one the model starts again from Su's 3R, fitted, as at start-up.
    pub fn set_scene(&mut self, scene: Scene, path: PathBuf, now: Instant) {
        let brought = self.edit.open(scene, path);
        self.shown.clear_result();
        self.jobs.refresh(now, self.jobs.live && !brought);
    }

    /// The model is now `m`, an edit (sent once the debounce is over).
    pub(super) fn replace_matrix(&mut self, m: PrbMatrix, now: Instant) {
        self.edit.replace_matrix(m);
        self.jobs.changed(now);
    }

    /// A topology name or a published model's name.
    pub(super) fn load_named_matrix(&mut self, name: &str, now: Instant) {
        let published = PUBLISHED.contains(&name);
        let m = if published {
            ModelFile::load(name)
                .map(|m| m.prb)
                .map_err(|e| e.to_string())
        } else {
            PrbMatrix::from_topology(name).map_err(|e| e.to_string())
        };
        match m {
            Ok(m) if published => {
                // A published model is a comparison: its own figures first, judged, not
                // fitted (live refit resumes with the next edit; r fits it now).
                self.set_info(format!(
                    "matrix: {name}, the published values (r fits them)"
                ));
                self.replace_matrix(m, now);
                self.jobs.judge_only();
            }
            Ok(m) => {
                self.set_info(format!("matrix: {name}"));
                self.replace_matrix(m, now);
            }
            Err(e) => self.set_error(format!("rejected: {e}")),
        }
    }

    /// `C`: the next model to compare against: none, the published ones, the selection's.
    pub(super) fn cycle_compare(&mut self) -> Option<Command> {
        let mut choices: Vec<(String, PrbMatrix)> = PUBLISHED
            .iter()
            .filter_map(|n| ModelFile::load(n).ok().map(|m| (n.to_string(), m.prb)))
            .collect();
        choices.extend(self.shown.selection_model.clone());
        let now = self.shown.compare.as_ref().map(|(n, _)| n.clone());
        let next = match now.and_then(|n| choices.iter().position(|(c, _)| *c == n)) {
            None => choices.into_iter().next(),
            Some(i) => choices.into_iter().nth(i + 1),
        };
        self.shown.compare = next;
        match self.shown.compare.clone() {
            None => {
                self.shown.compared = None;
                self.set_info("compare: none");
                None
            }
            Some((name, matrix)) => {
                self.set_info(format!("compare with {name} (C: next)"));
                let mut job = self.job(JobKind::Compare);
                job.matrix = matrix;
                Some(Command::Submit(job))
            }
        }
    }

    /// Opens the selection view and starts the selection job.
    pub(super) fn open_selection(&mut self) -> Command {
        let cmd = self.send(JobKind::Select, true);
        self.shown.select = Some(SelectState::new(self.jobs.current_id()));
        cmd
    }

    /// Closes the selection view, cancelling its job if it still runs.
    pub(super) fn close_selection(&mut self) {
        if self.shown.selection_running() {
            self.jobs.cancel();
        }
        self.shown.select = None;
    }

    /// `c`: cancels the fit (or judge) running, and the edit waiting to be sent.
    pub(super) fn cancel_fit(&mut self) {
        if self.jobs.current.is_some() && self.jobs.busy() {
            self.jobs.cancel();
            self.set_info("fit cancelled");
        }
        self.jobs.drop_pending();
    }

    /// `q`: quits, or asks first when there is unsaved work.
    pub(super) fn request_quit(&mut self) {
        if self.unsaved() {
            self.open_prompt(PromptKind::ConfirmQuit, String::new());
        } else {
            self.quit = true;
        }
    }
}
