//! The UI's state and its update logic, free of any terminal: keys in, state changes and
//! commands (jobs for the worker, files to write) out. Rendering reads this state only.
//!
//! The app holds what the panels share (the scene, the matrix, the jobs, the messages); each
//! panel's cursor and edit handling is in [`state`](super::state), and every key goes through
//! the [`keymap`](super::keymap).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::cancel::CancelToken;
use crate::fit::{Fidelity, FitReport, StopReason};
use crate::io::ModelFile;
use crate::prb::published::NAMES as PUBLISHED;
use crate::prb::{Column, PrbMatrix};
use crate::scene::{EffectsChoice, Scene};

use super::keymap::{self, Action, Scope};
use super::state::beam::{toggled_effect, BeamField, BeamState};
use super::state::loads::{self, LoadsState};
use super::state::matrix::MatrixState;
use super::state::select::SelectState;
pub use super::state::Panel;
use super::worker::{BaselineView, FitStatus, Job, JobKind, ModelView, WorkerMsg};

/// Edits closer together than this are sent as one job.
pub const DEBOUNCE: Duration = Duration::from_millis(30);

/// What a text box is editing.
#[derive(Debug, Clone, PartialEq)]
pub enum EditTarget {
    /// A field of the beam panel.
    Beam(BeamField),
    /// A cell of the load table.
    Load {
        /// The path.
        row: usize,
        /// The column, an index into [`LOAD_COLUMNS`](super::state::loads::LOAD_COLUMNS).
        col: usize,
    },
    /// A cell of the matrix.
    Cell {
        /// The segment.
        row: usize,
        /// The column.
        col: Column,
    },
}

/// What a prompt asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PromptKind {
    /// A path to save the scene to.
    SaveScene,
    /// A scene file to open.
    OpenScene,
    /// A path to export the model to.
    ExportModel,
    /// A topology or published model name.
    Topology,
    /// Whether to quit with unsaved work.
    ConfirmQuit,
}

impl PromptKind {
    /// The prompt's question.
    pub fn question(self) -> &'static str {
        match self {
            PromptKind::SaveScene => "save scene to",
            PromptKind::OpenScene => "open scene",
            PromptKind::ExportModel => "export model to (.toml .json .xml/.mjcf .urdf .sdf .csv)",
            PromptKind::Topology => "topology (e.g. L-R-R-R, L-RP) or howell-1r, su-3r, chen-3r",
            PromptKind::ConfirmQuit => "unsaved changes: quit anyway? (y/n)",
        }
    }
}

/// A line of text being typed.
#[derive(Debug, Clone, PartialEq)]
pub struct TextBox {
    /// The text so far.
    pub text: String,
}

/// How a message should look.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tone {
    /// News.
    Info,
    /// Something was refused or failed.
    Error,
}

/// Where the worker is with the latest job.
#[derive(Debug, Clone, PartialEq)]
pub enum Activity {
    /// Nothing asked.
    Idle,
    /// Sent, nothing back yet.
    Waiting,
    /// Fitting, this far.
    Fitting(FitStatus),
    /// Finished.
    Done {
        /// How long the job took.
        seconds: f64,
        /// Why the fit stopped (none for a judge job).
        stop: Option<StopReason>,
        /// Fit iterations.
        iterations: u32,
        /// Objective evaluations.
        evaluations: u64,
    },
    /// Failed, saying why.
    Failed(String),
    /// The fit was cancelled.
    Cancelled,
}

/// Side effects the run loop carries out.
#[derive(Debug)]
pub enum Command {
    /// Hand a job to the worker.
    Submit(Job),
    /// Write the scene to a file.
    SaveScene(PathBuf),
    /// Read a scene from a file.
    OpenScene(PathBuf),
}

/// Checks an edited scene by the rules a scene file obeys ([`Scene::validate`]).
pub fn validate_scene(scene: &Scene) -> Result<(), String> {
    scene.validate().map_err(|e| match e.key {
        Some(key) => format!("{key}: {}", e.message),
        None => e.message,
    })
}

/// The whole UI state.
#[derive(Debug)]
pub struct App {
    /// The scene being edited.
    pub scene: Scene,
    /// Where it was read from or last saved to.
    pub scene_path: Option<PathBuf>,
    /// The scene changed since it was last saved.
    pub scene_dirty: bool,
    /// The PRB matrix being edited.
    pub matrix: PrbMatrix,
    /// The matrix changed since it was last exported.
    pub model_dirty: bool,
    /// The panel that takes the keys.
    pub focus: Panel,
    /// The beam panel's cursor.
    pub beam_state: BeamState,
    /// The load panel's cursor.
    pub loads_state: LoadsState,
    /// The matrix panel's cursor and display mode.
    pub matrix_state: MatrixState,
    /// The field being edited and its text.
    pub editing: Option<(EditTarget, TextBox)>,
    /// The prompt open and its text.
    pub prompt: Option<(PromptKind, TextBox)>,
    /// The help overlay is shown.
    pub help: bool,
    /// The last message.
    pub message: Option<(String, Tone)>,
    /// How finely jobs solve and fit.
    pub fidelity: Fidelity,
    /// Every edit refits (else it is only judged).
    pub live: bool,
    /// The loop should end.
    pub quit: bool,
    /// Monochrome (NO_COLOR).
    pub mono: bool,
    /// The newest job sent and its cancel token.
    pub current_job: Option<(u64, CancelToken)>,
    job_counter: u64,
    /// An accepted edit waiting out the debounce.
    pending: Option<(Instant, bool)>,
    /// When the edit behind the newest job was accepted (for timing the UI's response).
    pub edit_accepted_at: Option<Instant>,
    /// Where the worker is.
    pub activity: Activity,
    /// The baseline the shown model was judged on.
    pub baseline: Option<Arc<BaselineView>>,
    /// The shown model.
    pub model: Option<ModelView>,
    /// The last fit's report.
    pub report: Option<FitReport>,
    /// Which published model `m` loads next.
    next_published: usize,
    /// The selection view, when open.
    pub select: Option<SelectState>,
}

impl App {
    /// The app on `scene`, with Su's 3R model (or an L-R-R-R matrix) to start from.
    pub fn new(scene: Scene, scene_path: Option<PathBuf>) -> App {
        #[allow(clippy::expect_used)]
        let matrix = ModelFile::load("su-3r").map(|m| m.prb).unwrap_or_else(|_| {
            // "L-R-R-R" is a constant the topology parser accepts (a test builds every
            // topology of the ladder), so this cannot fail.
            PrbMatrix::from_topology("L-R-R-R").expect("valid topology")
        });
        App {
            scene,
            scene_path,
            scene_dirty: false,
            matrix,
            model_dirty: false,
            focus: Panel::Matrix,
            beam_state: BeamState::default(),
            loads_state: LoadsState::default(),
            matrix_state: MatrixState::default(),
            editing: None,
            prompt: None,
            help: false,
            message: None,
            fidelity: Fidelity::Normal,
            live: true,
            quit: false,
            mono: false,
            current_job: None,
            job_counter: 0,
            pending: None,
            edit_accepted_at: None,
            activity: Activity::Idle,
            baseline: None,
            model: None,
            report: None,
            next_published: 0,
            select: None,
        }
    }

    /// The job for the current state.
    fn job(&mut self, kind: JobKind) -> Job {
        self.job_counter += 1;
        Job {
            id: self.job_counter,
            scene: Arc::new(self.scene.clone()),
            matrix: self.matrix.clone(),
            fidelity: self.fidelity,
            kind,
            cancel: CancelToken::new(),
        }
    }

    /// An export of the current matrix. Unlike the other jobs it is a side effect the user
    /// asked for: it cancels nothing, a newer job does not cancel it, and its result is shown
    /// whatever job is current by then.
    pub fn export(&mut self, path: PathBuf) -> Command {
        Command::Submit(self.job(JobKind::Export(path)))
    }

    /// Sends a fit (or, with `fit` false, a judge) job now, cancelling the one before.
    pub fn submit(&mut self, fit: bool) -> Command {
        self.submit_kind(if fit { JobKind::Fit } else { JobKind::Judge })
    }

    /// Sends a job now, cancelling the one before.
    pub fn submit_kind(&mut self, kind: JobKind) -> Command {
        if let Some((_, token)) = &self.current_job {
            token.cancel();
        }
        let job = self.job(kind);
        self.current_job = Some((job.id, job.cancel.clone()));
        self.activity = Activity::Waiting;
        self.edit_accepted_at = self.pending.map(|p| p.0);
        self.pending = None;
        Command::Submit(job)
    }

    /// An edit was accepted: (re)start the debounce.
    fn changed(&mut self, now: Instant) {
        self.pending = Some((now, self.live));
    }

    /// Time passes: sends a debounced job when due.
    pub fn tick(&mut self, now: Instant) -> Option<Command> {
        match self.pending {
            Some((at, fit)) if now.duration_since(at) >= DEBOUNCE => Some(self.submit(fit)),
            _ => None,
        }
    }

    /// Whether a debounced job is waiting.
    pub fn has_pending(&self) -> bool {
        self.pending.is_some()
    }

    /// A message from the worker; stale ones (not the newest job's) are dropped, except an
    /// export's. A model is always shown with the baseline it was judged on, which comes with
    /// it.
    pub fn on_worker(&mut self, msg: WorkerMsg) -> bool {
        if let WorkerMsg::Exported { path, result, .. } = msg {
            match result {
                Ok(()) => {
                    self.model_dirty = false;
                    self.set_info(format!("exported {}", path.display()));
                }
                Err(e) => self.set_error(format!("not exported: {e}")),
            }
            return true;
        }
        let Some((current, _)) = &self.current_job else {
            return false;
        };
        if msg.id() != *current {
            return false;
        }
        match msg {
            WorkerMsg::Progress {
                baseline,
                model,
                status,
                ..
            } => {
                self.baseline = Some(baseline);
                self.model = Some(*model);
                self.activity = Activity::Fitting(status);
            }
            WorkerMsg::Done {
                baseline,
                model,
                report,
                seconds,
                ..
            } => {
                let (stop, iterations, evaluations) = match &report {
                    Some(r) => (Some(r.stop), r.iterations, r.evaluations),
                    None => (None, 0, 0),
                };
                if let Some(r) = &report {
                    // The fitted values replace the free cells (not a user edit: no refit).
                    if r.matrix != self.matrix {
                        self.matrix = r.matrix.clone();
                        self.model_dirty = true;
                    }
                    self.activity = if r.stop == StopReason::Cancelled {
                        Activity::Cancelled
                    } else {
                        Activity::Done {
                            seconds,
                            stop,
                            iterations,
                            evaluations,
                        }
                    };
                } else {
                    self.activity = Activity::Done {
                        seconds,
                        stop,
                        iterations,
                        evaluations,
                    };
                }
                self.report = report.map(|r| *r);
                self.baseline = Some(baseline);
                self.model = Some(*model);
            }
            WorkerMsg::Failed { message, .. } => {
                self.set_error(message.clone());
                self.activity = Activity::Failed(message);
                if let Some(v) = &mut self.select {
                    v.running = false;
                }
            }
            // Taken above, whatever its job.
            WorkerMsg::Exported { .. } => {}
            WorkerMsg::SelectRow { id, row } => {
                if let Some(v) = &mut self.select {
                    v.on_row(id, *row);
                }
            }
            WorkerMsg::SelectDone {
                id,
                selection,
                knobs,
            } => {
                if let Some(v) = &mut self.select {
                    v.on_done(id, *selection, knobs);
                }
                self.activity = Activity::Idle;
            }
        }
        true
    }

    /// Opens the selection view and starts the selection job.
    fn open_selection(&mut self) -> Command {
        let cmd = self.submit_kind(JobKind::Select);
        let job = self.current_job.as_ref().map_or(0, |(id, _)| *id);
        self.select = Some(SelectState::new(job));
        cmd
    }

    /// Keys while the selection view is open.
    fn select_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        let Some(view) = &mut self.select else {
            return Vec::new();
        };
        match keymap::action(&key, Scope::SELECT) {
            Some(Action::Up) => view.move_by(-1),
            Some(Action::Down) => view.move_by(1),
            Some(Action::SelectStop) if view.running => {
                if let Some((_, token)) = &self.current_job {
                    token.cancel();
                }
                view.running = false;
                self.set_info("selection cancelled");
            }
            Some(Action::SelectLoad) => {
                if let Some(row) = view.selected_row() {
                    let (name, m) = (row.name.clone(), row.prb.clone());
                    self.close_selection();
                    self.set_info(format!("matrix: {name} from the selection"));
                    self.replace_matrix(m, now);
                }
            }
            Some(Action::SelectClose) => {
                self.close_selection();
                // Back to the matrix being edited: judge or fit it again.
                self.changed(now);
            }
            _ => {}
        }
        Vec::new()
    }

    fn close_selection(&mut self) {
        if let Some(v) = self.select.take() {
            if v.running {
                if let Some((_, token)) = &self.current_job {
                    token.cancel();
                }
            }
        }
    }

    /// Shows an error message.
    pub fn set_error(&mut self, m: impl Into<String>) {
        self.message = Some((m.into(), Tone::Error));
    }

    /// Shows an information message.
    pub fn set_info(&mut self, m: impl Into<String>) {
        self.message = Some((m.into(), Tone::Info));
    }

    /// Whether the scene or the model has changes not written anywhere.
    pub fn unsaved(&self) -> bool {
        self.scene_dirty || self.model_dirty
    }

    /// Handles one key; returns the commands it causes.
    pub fn on_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        if key.kind == KeyEventKind::Release {
            return Vec::new();
        }
        let ctrl_c =
            key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL);
        if self.prompt.is_some() {
            return self.prompt_key(key, ctrl_c);
        }
        if self.editing.is_some() {
            if ctrl_c {
                self.editing = None;
                return Vec::new();
            }
            return self.edit_key(key, now);
        }
        if self.help {
            // Any key closes the help.
            self.help = false;
            return Vec::new();
        }
        if self.select.is_some() {
            if ctrl_c {
                self.close_selection();
                self.request_quit();
                return Vec::new();
            }
            return self.select_key(key, now);
        }
        match keymap::action(&key, Scope::of(self.focus)) {
            Some(action) => self.act(action, now),
            None => Vec::new(),
        }
    }

    /// Does what a key in the focused panel asked for.
    fn act(&mut self, action: Action, now: Instant) -> Vec<Command> {
        let mut out = Vec::new();
        match action {
            Action::Quit => self.request_quit(),
            Action::Help => self.help = true,
            Action::NextPanel => self.focus = self.focus.next(),
            Action::PrevPanel => self.focus = self.focus.prev(),
            Action::Up => self.move_cursor(0, -1),
            Action::Down => self.move_cursor(0, 1),
            Action::Left => self.move_cursor(-1, 0),
            Action::Right => self.move_cursor(1, 0),
            Action::Edit => self.start_edit(),
            Action::Fit => out.push(self.submit(true)),
            Action::Selection => out.push(self.open_selection()),
            Action::Cancel => self.cancel_fit(),
            Action::ToggleLive => {
                self.live = !self.live;
                self.set_info(if self.live {
                    "live refit on: every edit refits"
                } else {
                    "live refit paused: edits are judged, not fitted (r fits)"
                });
            }
            Action::CycleFidelity => {
                self.fidelity = match self.fidelity {
                    Fidelity::Draft => Fidelity::Normal,
                    Fidelity::Normal => Fidelity::Precise,
                    Fidelity::Precise => Fidelity::Draft,
                };
                self.set_info(format!("fidelity: {}", self.fidelity));
                self.changed(now);
            }
            Action::Save => self.open_prompt(
                PromptKind::SaveScene,
                self.scene_path
                    .as_ref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_else(|| "scene.toml".into()),
            ),
            Action::Open => self.open_prompt(PromptKind::OpenScene, String::new()),
            Action::Export => self.open_prompt(PromptKind::ExportModel, "model.toml".into()),
            Action::Topology => self.open_prompt(PromptKind::Topology, self.matrix.topology()),
            Action::NextPublished => self.next_published_model(now),
            Action::ToggleFree => self.toggle_free(now),
            Action::ToggleShear => self.toggle_effect('1', now),
            Action::ToggleExtension => self.toggle_effect('2', now),
            Action::TogglePoisson => self.toggle_effect('3', now),
            Action::AddRow => self.add_row(now),
            Action::DeleteRow => self.delete_row(now),
            Action::ToggleSi => {
                self.matrix_state.si = !self.matrix_state.si;
                self.set_info(if self.matrix_state.si {
                    "matrix in SI for this beam: segment lengths, N m/rad, N/m"
                } else {
                    "matrix nondimensional: gamma, k_theta (E I0/L), k_ex (E A0/L)"
                });
            }
            Action::PrevPath => self.loads_state.cycle_path(-1, self.scene.loads.len()),
            Action::NextPath => self.loads_state.cycle_path(1, self.scene.loads.len()),
            // The selection view's own keys never reach here.
            Action::SelectLoad | Action::SelectStop | Action::SelectClose => {}
        }
        out
    }

    fn request_quit(&mut self) {
        if self.unsaved() {
            self.open_prompt(PromptKind::ConfirmQuit, String::new());
        } else {
            self.quit = true;
        }
    }

    fn cancel_fit(&mut self) {
        if let Some((_, token)) = &self.current_job {
            if matches!(self.activity, Activity::Waiting | Activity::Fitting(_)) {
                token.cancel();
                self.set_info("fit cancelled");
            }
        }
        self.pending = None;
    }

    fn open_prompt(&mut self, kind: PromptKind, text: String) {
        self.prompt = Some((kind, TextBox { text }));
    }

    fn move_cursor(&mut self, dx: i32, dy: i32) {
        match self.focus {
            Panel::Beam => self.beam_state.move_by(dy),
            Panel::Loads => self.loads_state.move_by(dx, dy, self.scene.loads.len()),
            Panel::Matrix => self.matrix_state.move_by(dx, dy, self.matrix.len()),
        }
    }

    /// The text of a matrix cell as the matrix panel shows it.
    pub fn cell_text(&self, row: usize, col: Column) -> String {
        self.matrix_state
            .cell_text(&self.matrix, &self.scene.beam, row, col)
    }

    fn start_edit(&mut self) {
        let (target, text) = match self.focus {
            Panel::Beam => {
                let f = self.beam_state.field();
                (
                    EditTarget::Beam(f),
                    f.edit_text(&self.scene, self.baseline.as_deref()),
                )
            }
            Panel::Loads => {
                let (row, col) = (self.loads_state.row, self.loads_state.col);
                let text = self
                    .scene
                    .loads
                    .get(row)
                    .map(|p| loads::load_text(p, col))
                    .unwrap_or_default();
                (EditTarget::Load { row, col }, text)
            }
            Panel::Matrix => {
                let (row, col) = (self.matrix_state.row, self.matrix_state.column());
                (EditTarget::Cell { row, col }, self.cell_text(row, col))
            }
        };
        self.editing = Some((target, TextBox { text }));
    }

    fn edit_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        let Some((_, tb)) = &mut self.editing else {
            return Vec::new();
        };
        match key.code {
            KeyCode::Esc => self.editing = None,
            KeyCode::Enter => {
                if let Some((target, tb)) = self.editing.take() {
                    match self.apply_edit(&target, &tb.text) {
                        Ok(()) => self.changed(now),
                        Err(e) => self.set_error(format!("rejected: {e} (the old value is kept)")),
                    }
                }
            }
            KeyCode::Backspace => {
                tb.text.pop();
            }
            KeyCode::Char(c) if tb.text.len() < 64 => tb.text.push(c),
            _ => {}
        }
        Vec::new()
    }

    /// Applies an edit if valid; on error nothing changes.
    pub fn apply_edit(&mut self, target: &EditTarget, text: &str) -> Result<(), String> {
        match target {
            EditTarget::Beam(field) => {
                let scene = field.edited(&self.scene, text)?;
                validate_scene(&scene)?;
                if scene != self.scene {
                    self.scene = scene;
                    self.scene_dirty = true;
                }
            }
            EditTarget::Load { row, col } => {
                let old = self.scene.loads.get(*row).ok_or("no such load path")?;
                let path = loads::edited(old, *col, text)?;
                if path != *old {
                    self.scene.loads[*row] = path;
                    self.scene_dirty = true;
                }
            }
            EditTarget::Cell { row, col } => {
                let m =
                    self.matrix_state
                        .edited(&self.matrix, &self.scene.beam, *row, *col, text)?;
                if m != self.matrix {
                    self.matrix = m;
                    self.model_dirty = true;
                }
            }
        }
        Ok(())
    }

    fn prompt_key(&mut self, key: KeyEvent, ctrl_c: bool) -> Vec<Command> {
        let Some((kind, tb)) = &mut self.prompt else {
            return Vec::new();
        };
        let kind = *kind;
        if kind == PromptKind::ConfirmQuit {
            match key.code {
                KeyCode::Char('y') | KeyCode::Char('Y') => self.quit = true,
                _ => self.prompt = None,
            }
            return Vec::new();
        }
        match key.code {
            KeyCode::Esc => self.prompt = None,
            _ if ctrl_c => self.prompt = None,
            KeyCode::Backspace => {
                tb.text.pop();
            }
            KeyCode::Char(c) if tb.text.len() < 256 => tb.text.push(c),
            KeyCode::Enter => {
                let text = tb.text.trim().to_string();
                self.prompt = None;
                if text.is_empty() {
                    return Vec::new();
                }
                return match kind {
                    PromptKind::SaveScene => vec![Command::SaveScene(PathBuf::from(text))],
                    PromptKind::OpenScene => vec![Command::OpenScene(PathBuf::from(text))],
                    // Exported by the worker from its baseline: no solve on this thread.
                    PromptKind::ExportModel => vec![self.export(PathBuf::from(text))],
                    PromptKind::Topology => {
                        self.load_named_matrix(&text, Instant::now());
                        Vec::new()
                    }
                    // Answered above, before any text is typed.
                    PromptKind::ConfirmQuit => Vec::new(),
                };
            }
            _ => {}
        }
        Vec::new()
    }

    /// A topology name or a published model's name.
    fn load_named_matrix(&mut self, name: &str, now: Instant) {
        let m = if PUBLISHED.contains(&name) {
            ModelFile::load(name)
                .map(|m| m.prb)
                .map_err(|e| e.to_string())
        } else {
            PrbMatrix::from_topology(name).map_err(|e| e.to_string())
        };
        match m {
            Ok(m) => {
                self.set_info(format!("matrix: {name}"));
                self.replace_matrix(m, now);
            }
            Err(e) => self.set_error(format!("rejected: {e}")),
        }
    }

    fn next_published_model(&mut self, now: Instant) {
        let name = PUBLISHED[self.next_published % PUBLISHED.len()];
        self.next_published += 1;
        self.load_named_matrix(name, now);
    }

    fn replace_matrix(&mut self, m: PrbMatrix, now: Instant) {
        self.matrix = m;
        self.model_dirty = true;
        self.matrix_state.clamp(self.matrix.len());
        self.changed(now);
    }

    /// 1, 2, 3 switch shear, extension, poisson.
    fn toggle_effect(&mut self, which: char, now: Instant) {
        let e = toggled_effect(&self.scene, self.baseline.as_deref(), which);
        self.scene.beam.effects = EffectsChoice::Fixed(e);
        self.scene_dirty = true;
        self.set_info(format!("effects: {e}"));
        self.changed(now);
    }

    fn toggle_free(&mut self, now: Instant) {
        match self.matrix_state.toggled_free(&self.matrix) {
            Ok(m) => {
                self.matrix = m;
                self.model_dirty = true;
                self.changed(now);
            }
            Err(e) => self.set_error(e),
        }
    }

    fn add_row(&mut self, now: Instant) {
        match self.focus {
            Panel::Loads => {
                self.loads_state.add(&mut self.scene);
                self.scene_dirty = true;
                self.changed(now);
            }
            Panel::Matrix => match self.matrix_state.split_row(&self.matrix) {
                Ok(m) => {
                    self.matrix_state.row += 1;
                    self.replace_matrix(m, now);
                }
                Err(e) => self.set_error(format!("rejected: {e}")),
            },
            Panel::Beam => {}
        }
    }

    fn delete_row(&mut self, now: Instant) {
        match self.focus {
            Panel::Loads => match self.loads_state.delete(&mut self.scene) {
                Ok(()) => {
                    self.scene_dirty = true;
                    self.changed(now);
                }
                Err(e) => self.set_error(e),
            },
            Panel::Matrix => match self.matrix_state.remove_row(&self.matrix) {
                Ok(m) => self.replace_matrix(m, now),
                Err(e) => self.set_error(e),
            },
            Panel::Beam => {}
        }
    }

    /// The scene was replaced (opened from a file).
    pub fn set_scene(&mut self, scene: Scene, path: PathBuf, now: Instant) {
        self.scene = scene;
        self.scene_path = Some(path);
        self.scene_dirty = false;
        self.loads_state.row = 0;
        self.baseline = None;
        self.model = None;
        self.changed(now);
    }

    /// The load path whose cases the shape chart draws.
    pub fn shown_path(&self) -> usize {
        self.loads_state.shown_path(self.scene.loads.len())
    }

    /// The cases (indices into the baseline) of the shown path.
    pub fn shown_cases(&self) -> std::ops::Range<usize> {
        let Some(b) = &self.baseline else { return 0..0 };
        let path = self.shown_path().min(b.paths.len().saturating_sub(1));
        let start: usize = b.paths[..path].iter().map(|p| p.steps as usize).sum();
        let len = b.paths.get(path).map_or(0, |p| p.steps as usize);
        start..(start + len).min(b.shapes.len())
    }
}
