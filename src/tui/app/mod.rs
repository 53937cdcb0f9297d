//! The UI's state and its update logic, free of any terminal: keys in, state changes and
//! commands (jobs for the worker, files to write) out. Rendering reads this state only.
//!
//! The app holds what the panels share (the scene, the matrix, the jobs, the messages); each
//! panel's cursor and edit handling is in [`state`](super::state), and every key goes through
//! the [`keymap`].

mod data;
mod prompts;
mod results;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::beam::Effects;
use crate::cancel::CancelToken;
use crate::fit::{Fidelity, FitReport, StopReason};
use crate::format::Format;
use crate::io::ModelFile;
use crate::mech::figures::MechFigures;
use crate::prb::published::NAMES as PUBLISHED;
use crate::prb::{Column, PrbMatrix};
use crate::scene::data::Units;
use crate::scene::{EffectsChoice, Scene};

use super::keymap::{self, Action, Scope};
use super::state::beam::{toggled_effect, BeamField, BeamState};
use super::state::loads::{self, held_forces, Hold, LoadsState};
use super::state::matrix::MatrixState;
use super::state::mech::{self as mech_state, MechField, MechState};
use super::state::select::SelectState;
pub use super::state::Panel;
use super::units::trim_number;
use super::worker::{
    BaselineView, FitStatus, Job, JobKind, MechBaselineView, MechModelView, ModelView, WorkerMsg,
};

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
    /// A row of the mechanism panel.
    Mech(MechField),
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

pub use super::state::text::TextBox;

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
enum TextKey {
    /// A row of the keymap's text scope.
    Action(Action),
    /// A character to type.
    Char(char),
    /// Nothing (Ctrl with a key the text box does not use, a function key).
    None,
}

fn text_action(key: &KeyEvent) -> TextKey {
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
fn has_masses(format: Format) -> bool {
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
        Ok(d) if d.is_finite() && d > 0.0 => Ok(d),
        _ => Err(format!(
            "density: `{t}` is not a number of kg/m^3 > 0 (steel 7850, aluminium 2700)"
        )),
    }
}

/// Checks an edited scene by the rules a scene file obeys ([`Scene::validate`]).
pub fn validate_scene(scene: &Scene) -> Result<(), String> {
    scene.validate().map_err(|e| match e.key {
        Some(key) => format!("{key}: {}", e.message),
        None => e.message,
    })
}

/// A job waiting out the debounce.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pending {
    /// When the change behind it was accepted.
    at: Instant,
    /// Fit (else judge).
    fit: bool,
    /// The user asked for it (an edit), not the program (start-up, open).
    by_user: bool,
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
    pending: Option<Pending>,
    /// The newest job was asked for by the user (an edit, `r`), so the model it fits is the
    /// user's work (see [`App::unsaved`]).
    current_job_by_user: bool,
    /// The message shown is a worker's failure, cleared by the next good result.
    message_from_worker: bool,
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
    /// The selection view of a mechanism scene, when open.
    pub mech_select: Option<SelectState<MechFigures>>,
    /// The matrix came from the scene's `[prb] matrix`: the first job judges it as saved.
    model_from_scene: bool,
    /// The density the exported links get (kg/m^3).
    pub export_density: f64,
    /// The export file waiting for its density.
    export_path: Option<PathBuf>,
    /// The write waiting for "overwrite? (y/n)".
    overwrite: Option<Command>,
    /// The model compared against (`C`): its name and matrix.
    pub compare: Option<(String, PrbMatrix)>,
    /// The compared model as judged, with the baseline it was judged on.
    pub compare_view: Option<(Arc<BaselineView>, ModelView)>,
    /// The last selection's model (its choice, else the closest row), which `C` offers.
    pub selection_model: Option<(String, PrbMatrix)>,
    /// A mechanism scene's panel cursor and what its charts show.
    pub mech_state: MechState,
    /// A mechanism scene's exact mechanism the shown model was judged on.
    pub mech_exact: Option<Arc<MechBaselineView>>,
    /// A mechanism scene's shown model.
    pub mech_model: Option<MechModelView>,
    /// A mechanism scene's compared model as judged, with the exact mechanism it was judged
    /// on.
    pub mech_compare: Option<(Arc<MechBaselineView>, MechModelView)>,
}

impl App {
    /// The app on `scene`, starting from the scene's own model (`[prb] matrix`) if it has
    /// one, else from Su's 3R model (or an L-R-R-R matrix). The model lives in
    /// [`App::matrix`]; the scene's copy goes back in when it is saved
    /// ([`App::scene_to_save`]).
    pub fn new(mut scene: Scene, scene_path: Option<PathBuf>) -> App {
        let from_scene = scene.prb.take();
        let model_from_scene = from_scene.is_some();
        #[allow(clippy::expect_used)]
        let matrix = from_scene.unwrap_or_else(|| {
            ModelFile::load("su-3r").map(|m| m.prb).unwrap_or_else(|_| {
                // "L-R-R-R" is a constant the topology parser accepts (a test builds every
                // topology of the ladder), so this cannot fail.
                PrbMatrix::from_topology("L-R-R-R").expect("valid topology")
            })
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
            current_job_by_user: false,
            message_from_worker: false,
            edit_accepted_at: None,
            activity: Activity::Idle,
            baseline: None,
            model: None,
            report: None,
            next_published: 0,
            select: None,
            mech_select: None,
            model_from_scene,
            export_density: DEFAULT_DENSITY,
            export_path: None,
            overwrite: None,
            compare: None,
            compare_view: None,
            selection_model: None,
            mech_state: MechState::default(),
            mech_exact: None,
            mech_model: None,
            mech_compare: None,
        }
    }

    /// Whether the scene is a mechanism (DESIGN §8).
    pub fn is_mechanism(&self) -> bool {
        self.scene.mechanism.is_some()
    }

    /// What `auto` effects were decided as, once the worker decided them.
    pub fn decided_effects(&self) -> Option<Effects> {
        if self.is_mechanism() {
            self.mech_exact.as_ref().map(|v| v.effects)
        } else {
            self.baseline
                .as_ref()
                .filter(|v| v.decision.is_some())
                .map(|v| v.effects)
        }
    }

    /// A mechanism scene's compared model to draw, when it was judged for the compared
    /// matrix on the exact mechanism the main model is shown with.
    pub fn shown_mech_compare(&self) -> Option<(&str, &MechModelView)> {
        let (name, matrix) = self.compare.as_ref()?;
        let (exact, view) = self.mech_compare.as_ref()?;
        let shown = self.mech_exact.as_ref()?;
        let same = Arc::ptr_eq(exact, shown) || **exact == **shown;
        (same && view.matrix == *matrix).then_some((name.as_str(), view))
    }

    /// The compared model to draw: its name and view, when it was judged for the compared
    /// matrix on the baseline the main model is shown with (never another beam's).
    pub fn shown_compare(&self) -> Option<(&str, &ModelView)> {
        let (name, matrix) = self.compare.as_ref()?;
        let (baseline, view) = self.compare_view.as_ref()?;
        let shown = self.baseline.as_ref()?;
        let same = Arc::ptr_eq(baseline, shown) || **baseline == **shown;
        (same && view.matrix == *matrix).then_some((name.as_str(), view))
    }

    /// `C`: the next model to compare against: none, the published ones, the selection's.
    fn cycle_compare(&mut self) -> Option<Command> {
        let mut choices: Vec<(String, PrbMatrix)> = PUBLISHED
            .iter()
            .filter_map(|n| ModelFile::load(n).ok().map(|m| (n.to_string(), m.prb)))
            .collect();
        choices.extend(self.selection_model.clone());
        let now = self.compare.as_ref().map(|(n, _)| n.clone());
        let next = match now.and_then(|n| choices.iter().position(|(c, _)| *c == n)) {
            None => choices.into_iter().next(),
            Some(i) => choices.into_iter().nth(i + 1),
        };
        self.compare = next;
        match self.compare.clone() {
            None => {
                self.compare_view = None;
                self.mech_compare = None;
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

    /// The scene as a file stores it: the model being worked on goes in as `[prb] matrix`.
    pub fn scene_to_save(&self) -> Scene {
        let mut scene = self.scene.clone();
        scene.prb = Some(self.matrix.clone());
        scene
    }

    /// The scene was written to `path`: nothing is unsaved any more.
    pub fn saved(&mut self, path: PathBuf) {
        self.set_info(format!("saved {} (with the model)", path.display()));
        self.scene_path = Some(path);
        self.scene_dirty = false;
        self.model_dirty = false;
    }

    /// A write would replace `cmd`'s existing file: ask first; `y` sends `cmd` again with
    /// `overwrite` set.
    pub fn ask_overwrite(&mut self, cmd: Command) {
        self.overwrite = Some(cmd);
        self.open_prompt(PromptKind::ConfirmOverwrite, String::new());
    }

    /// The job for the current state.
    fn job(&mut self, kind: JobKind) -> Job {
        self.job_counter += 1;
        Job {
            id: self.job_counter,
            scene: Arc::new(self.scene.clone()),
            matrix: self.matrix.clone(),
            compare: self.compare.as_ref().map(|(_, m)| m.clone()),
            fidelity: self.fidelity,
            kind,
            cancel: CancelToken::new(),
        }
    }

    /// An export of the current matrix, never over an existing file. Unlike the other jobs
    /// it is a side effect the user asked for: it cancels nothing, a newer job does not
    /// cancel it, and its result is shown whatever job is current by then.
    pub fn export(&mut self, path: PathBuf) -> Command {
        Command::Submit(self.export_job(path, false))
    }

    /// The export job for `path` (replacing the file when `overwrite`), with the links'
    /// density.
    pub fn export_job(&mut self, path: PathBuf, overwrite: bool) -> Job {
        let density = self.export_density;
        self.job(JobKind::Export {
            path,
            density,
            overwrite,
        })
    }

    /// Sends a fit (or, with `fit` false, a judge) job now, cancelling the one before: the
    /// user asked for it (`r`), so a fit that changes the model is unsaved work.
    pub fn submit(&mut self, fit: bool) -> Command {
        self.current_job_by_user = true;
        self.submit_kind(if fit { JobKind::Fit } else { JobKind::Judge })
    }

    /// The first job, at start-up: a fit with live refit on, or only a judge when the scene
    /// brought its own model (`[prb] matrix`: shown as saved; `r` fits it). Not the user's
    /// work: the model it fits does not make the scene "unsaved".
    pub fn start(&mut self) -> Command {
        let fit = self.live && !self.model_from_scene;
        let cmd = self.submit_kind(if fit { JobKind::Fit } else { JobKind::Judge });
        self.current_job_by_user = false;
        cmd
    }

    /// Sends a job now, cancelling the one before.
    pub fn submit_kind(&mut self, kind: JobKind) -> Command {
        if let Some((_, token)) = &self.current_job {
            token.cancel();
        }
        let job = self.job(kind);
        self.current_job = Some((job.id, job.cancel.clone()));
        self.activity = Activity::Waiting;
        self.edit_accepted_at = self.pending.map(|p| p.at);
        self.pending = None;
        Command::Submit(job)
    }

    /// An edit was accepted: (re)start the debounce.
    fn changed(&mut self, now: Instant) {
        self.pending = Some(Pending {
            at: now,
            fit: self.live,
            by_user: true,
        });
    }

    /// The program (not the user) wants the model judged or fitted again: after an open, or
    /// back from the selection view.
    fn refresh(&mut self, now: Instant, fit: bool) {
        self.pending = Some(Pending {
            at: now,
            fit,
            by_user: false,
        });
    }

    /// Time passes: sends a debounced job when due.
    pub fn tick(&mut self, now: Instant) -> Option<Command> {
        match self.pending {
            Some(p) if now.duration_since(p.at) >= DEBOUNCE => {
                let cmd = self.submit_kind(if p.fit { JobKind::Fit } else { JobKind::Judge });
                self.current_job_by_user = p.by_user;
                Some(cmd)
            }
            _ => None,
        }
    }

    /// Whether a debounced job is waiting.
    pub fn has_pending(&self) -> bool {
        self.pending.is_some()
    }

    /// Opens the selection view (a mechanism scene's on a mechanism scene) and starts the
    /// selection job.
    fn open_selection(&mut self) -> Command {
        let cmd = self.submit_kind(JobKind::Select);
        let job = self.current_job.as_ref().map_or(0, |(id, _)| *id);
        if self.is_mechanism() {
            self.mech_select = Some(SelectState::new(job));
        } else {
            self.select = Some(SelectState::new(job));
        }
        cmd
    }

    /// Whether a selection view is open.
    pub fn selection_open(&self) -> bool {
        self.select.is_some() || self.mech_select.is_some()
    }

    /// Whether the open selection's job still runs.
    fn selection_running(&self) -> bool {
        self.select.as_ref().is_some_and(|v| v.running)
            || self.mech_select.as_ref().is_some_and(|v| v.running)
    }

    /// The open selection's job ended (done, failed, stopped).
    pub(super) fn selection_stopped(&mut self) {
        if let Some(v) = &mut self.select {
            v.running = false;
        }
        if let Some(v) = &mut self.mech_select {
            v.running = false;
        }
    }

    /// The model of the row under the open selection's cursor.
    fn selected_model(&self) -> Option<(String, PrbMatrix)> {
        let row = |name: &str, m: &PrbMatrix| (name.to_string(), m.clone());
        match (&self.select, &self.mech_select) {
            (Some(v), _) => v.selected_row().map(|r| row(&r.name, &r.prb)),
            (None, Some(v)) => v.selected_row().map(|r| row(&r.name, &r.prb)),
            (None, None) => None,
        }
    }

    /// Keys while the selection view is open.
    fn select_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        if !self.selection_open() {
            return Vec::new();
        }
        match keymap::action(&key, Scope::SELECT) {
            Some(a @ (Action::Up | Action::Down)) => {
                let dy = if a == Action::Up { -1 } else { 1 };
                if let Some(v) = &mut self.select {
                    v.move_by(dy);
                }
                if let Some(v) = &mut self.mech_select {
                    v.move_by(dy);
                }
            }
            Some(Action::SelectStop) if self.selection_running() => {
                if let Some((_, token)) = &self.current_job {
                    token.cancel();
                }
                self.selection_stopped();
                self.set_info("selection cancelled");
            }
            Some(Action::SelectLoad) => {
                if let Some((name, m)) = self.selected_model() {
                    self.close_selection();
                    self.set_info(format!("matrix: {name} from the selection (r fits it)"));
                    self.replace_matrix(m, now);
                    // As the table showed it.
                    self.judge_only();
                }
            }
            Some(Action::SelectClose) => {
                self.close_selection();
                // Back to the matrix being edited: judge or fit it again.
                self.refresh(now, self.live);
            }
            _ => {}
        }
        Vec::new()
    }

    fn close_selection(&mut self) {
        let running = self.selection_running();
        self.select = None;
        self.mech_select = None;
        if running {
            if let Some((_, token)) = &self.current_job {
                token.cancel();
            }
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
            return self.prompt_key(key, ctrl_c, now);
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
        if self.selection_open() {
            if ctrl_c {
                self.close_selection();
                self.request_quit();
                return Vec::new();
            }
            return self.select_key(key, now);
        }
        match keymap::action(&key, Scope::of(self.focus)) {
            Some(action) => {
                // The last message was about the last action.
                self.clear_message();
                self.act(action, now)
            }
            None => Vec::new(),
        }
    }

    /// Does what a key in the focused panel asked for.
    fn act(&mut self, action: Action, now: Instant) -> Vec<Command> {
        let mut out = Vec::new();
        match action {
            Action::Quit => self.request_quit(),
            Action::Help => self.help = true,
            Action::NextPanel => self.focus = self.focus.next(self.is_mechanism()),
            Action::PrevPanel => self.focus = self.focus.prev(self.is_mechanism()),
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
            Action::Open => {
                if self.unsaved() {
                    self.open_prompt(PromptKind::ConfirmOpen, String::new());
                } else {
                    self.open_prompt(PromptKind::OpenScene, String::new());
                }
            }
            Action::Export if self.is_mechanism() => {
                self.open_prompt(PromptKind::ExportMechanism, "mechanism.xml".into())
            }
            Action::Export => self.open_prompt(PromptKind::ExportModel, "model.toml".into()),
            Action::Topology => self.open_prompt(PromptKind::Topology, self.matrix.topology()),
            Action::NextPublished => self.next_published_model(now),
            Action::CycleCompare => out.extend(self.cycle_compare()),
            Action::ToggleFree => self.toggle_free(now),
            Action::ToggleShear => self.toggle_effect('1', now),
            Action::ToggleExtension => self.toggle_effect('2', now),
            Action::TogglePoisson => self.toggle_effect('3', now),
            Action::TogglePlaneStrain => self.toggle_effect('4', now),
            Action::AddRow => self.add_row(now),
            Action::DeleteRow => self.delete_row(now),
            Action::ToggleSi => {
                self.matrix_state.si = !self.matrix_state.si;
                self.set_info(if self.matrix_state.si {
                    "SI for this beam: segment lengths, N m/rad, N/m; loads in N, N m"
                } else {
                    "nondimensional: gamma, k_theta (E I0/L), k_ex (E A0/L); alpha, beta"
                });
            }
            Action::ToggleHold if self.is_data() => self.data_hold_message(),
            Action::ToggleHold => {
                self.loads_state.hold = match self.loads_state.hold {
                    Hold::Alpha => Hold::Force,
                    Hold::Force => Hold::Alpha,
                };
                self.set_info(match self.loads_state.hold {
                    Hold::Alpha => "hold: alpha (a beam edit keeps alpha; the forces follow)",
                    Hold::Force => "hold: force (a beam edit keeps Fx, Fy, Mz; the alphas follow)",
                });
            }
            Action::PrevPath | Action::NextPath => {
                let delta = if action == Action::PrevPath { -1 } else { 1 };
                match &self.scene.mechanism {
                    Some(m) => self.mech_state.cycle_drive(delta, m.drives.len()),
                    None if self.is_data() => self.cycle_data_path(delta),
                    None => self.loads_state.cycle_path(delta, self.scene.loads.len()),
                }
            }
            Action::PrevCase | Action::NextCase => {
                let delta = if action == Action::PrevCase { -1 } else { 1 };
                let cases = self.shown_drive_cases();
                self.mech_state.cycle_case(delta, cases);
            }
            Action::NextChart => self.mech_state.chart += 1,
            Action::ToggleKind => self.toggle_kind(now),
            // The selection view's and the text boxes' own keys never reach here.
            Action::SelectLoad
            | Action::SelectStop
            | Action::SelectClose
            | Action::TextAccept
            | Action::TextCancel
            | Action::TextLeft
            | Action::TextRight
            | Action::TextStart
            | Action::TextEnd
            | Action::TextBackspace
            | Action::TextDelete
            | Action::TextClearStart
            | Action::TextClearEnd
            | Action::TextDeleteWord => {}
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
        self.prompt = Some((kind, TextBox::new(text)));
    }

    fn move_cursor(&mut self, dx: i32, dy: i32) {
        let mechanism = self.is_mechanism();
        match self.focus {
            Panel::Beam => self.beam_state.move_by(dy, mechanism),
            Panel::Loads => self.loads_state.move_by(dx, dy, self.load_rows()),
            Panel::Matrix => self.matrix_state.move_by(dx, dy, self.matrix.len()),
            Panel::Mechanism => {
                let rows = self
                    .scene
                    .mechanism
                    .as_ref()
                    .map_or(0, |m| mech_state::fields(m).len());
                self.mech_state.move_by(dy, rows);
                // The charts follow the drive the cursor is on.
                if let Some(d) = self.mech_field().and_then(MechField::drive) {
                    if d != self.mech_state.drive {
                        self.mech_state.drive = d;
                        self.mech_state.case = None;
                        self.mech_state.chart = 0;
                    }
                }
            }
        }
    }

    /// The mechanism panel's selected row.
    pub fn mech_field(&self) -> Option<MechField> {
        self.mech_state.field(self.scene.mechanism.as_ref()?)
    }

    /// The drive the mechanism charts show.
    pub fn shown_drive(&self) -> usize {
        let drives = self.scene.mechanism.as_ref().map_or(0, |m| m.drives.len());
        self.mech_state.shown_drive(drives)
    }

    /// How many cases the shown drive has in the exact mechanism shown.
    pub fn shown_drive_cases(&self) -> usize {
        self.mech_exact
            .as_ref()
            .and_then(|v| v.cases.get(self.shown_drive()))
            .map_or(0, Vec::len)
    }

    /// The beam the SI view (`u`) shows the matrix and the loads for, when it is on.
    pub fn si_beam(&self) -> Option<&crate::scene::BeamSpec> {
        self.matrix_state.si.then_some(&self.scene.beam)
    }

    /// The text of a matrix cell as the matrix panel shows it.
    pub fn cell_text(&self, row: usize, col: Column) -> String {
        self.matrix_state
            .cell_text(&self.matrix, &self.scene.beam, row, col)
    }

    fn start_edit(&mut self) {
        let (target, text) = match self.focus {
            Panel::Beam => {
                let f = self.beam_state.field(self.is_mechanism());
                (EditTarget::Beam(f), f.edit_text(&self.scene))
            }
            Panel::Mechanism => {
                let Some((m, f)) = self.scene.mechanism.as_ref().zip(self.mech_field()) else {
                    return;
                };
                if self.is_mech_data() && f.drive().is_some() {
                    self.refuse_drive_edit();
                    return;
                }
                (EditTarget::Mech(f), f.edit_text(m))
            }
            Panel::Loads if self.is_data() => {
                self.refuse_load_edit();
                return;
            }
            Panel::Loads => {
                let (row, col) = (self.loads_state.row, self.loads_state.col);
                let text = self
                    .scene
                    .loads
                    .get(row)
                    .map(|p| loads::load_text(p, col, self.si_beam()))
                    .unwrap_or_default();
                (EditTarget::Load { row, col }, text)
            }
            Panel::Matrix => {
                let (row, col) = (self.matrix_state.row, self.matrix_state.column());
                (EditTarget::Cell { row, col }, self.cell_text(row, col))
            }
        };
        self.editing = Some((target, TextBox::new(text)));
    }

    fn edit_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        let Some((_, tb)) = &mut self.editing else {
            return Vec::new();
        };
        match text_action(&key) {
            TextKey::Action(Action::TextCancel) => self.editing = None,
            TextKey::Action(Action::TextAccept) => {
                if let Some((target, tb)) = self.editing.take() {
                    match self.apply_edit(&target, &tb.text) {
                        Ok(()) => {
                            self.clear_message();
                            self.changed(now);
                        }
                        Err(e) => self.set_error(format!("rejected: {e} (the old value is kept)")),
                    }
                }
            }
            TextKey::Action(a) => {
                tb.apply(a);
            }
            TextKey::Char(c) => tb.insert(c),
            TextKey::None => {}
        }
        Vec::new()
    }

    /// Applies an edit if valid; on error nothing changes.
    pub fn apply_edit(&mut self, target: &EditTarget, text: &str) -> Result<(), String> {
        match target {
            EditTarget::Beam(field) => {
                let mut scene = field.edited(&self.scene, text)?;
                // A data scene's loads are its rows: they follow the beam as its file's
                // units say (take_scene), whatever the hold.
                if self.loads_state.hold == Hold::Force && !self.is_data() {
                    scene.loads = held_forces(&scene.loads, &self.scene.beam, &scene.beam);
                }
                self.take_scene(scene)?;
            }
            EditTarget::Mech(field) if self.is_mech_data() && field.drive().is_some() => {
                let file = self.scene.truth.as_ref().map_or("", |t| t.file.as_str());
                return Err(data::drives_read_only(file));
            }
            EditTarget::Mech(field) => {
                let m = self
                    .scene
                    .mechanism
                    .as_ref()
                    .ok_or("not a mechanism scene")?;
                let mut scene = self.scene.clone();
                scene.mechanism = Some(field.edited(m, text)?);
                self.take_scene(scene)?;
            }
            EditTarget::Load { .. } if self.is_data() => {
                return Err("a data scene's loads are its file's rows (read-only)".into());
            }
            EditTarget::Load { row, col } => {
                let old = self.scene.loads.get(*row).ok_or("no such load path")?;
                let path = loads::edited(old, *col, text, self.si_beam())?;
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

    /// Takes an edited scene if it obeys the scene file's rules (on a mechanism scene the
    /// flexures first follow a beam edit: [`mech_state::rebased`]; on a data scene the rows
    /// are converted again with the edited beam).
    fn take_scene(&mut self, mut scene: Scene) -> Result<(), String> {
        if let Some(m) = &scene.mechanism {
            if scene.beam != self.scene.beam {
                scene.mechanism = Some(mech_state::rebased(m, &self.scene.beam, &scene.beam));
            }
            mech_state::validate(&scene)?;
        } else {
            scene = self.rebase_data(scene)?;
            validate_scene(&scene)?;
        }
        if scene != self.scene {
            self.scene = scene;
            self.scene_dirty = true;
        }
        Ok(())
    }

    /// `p` on the mechanism panel: the selected coordinate prescribed or loaded, or the
    /// selected flexure's next attachment that makes a valid mechanism.
    fn toggle_kind(&mut self, now: Instant) {
        let (Some(m), Some(field)) = (self.scene.mechanism.as_ref(), self.mech_field()) else {
            return;
        };
        if self.is_mech_data() && field.drive().is_some() {
            self.refuse_drive_edit();
            return;
        }
        let choices = mech_state::toggled(m, field, self.mech_exact.as_deref());
        if choices.is_empty() {
            self.set_error("p: on a drive coordinate (x, y, phi) or a flexure's attach row");
            return;
        }
        let mut last_error = String::new();
        for choice in choices {
            let mut scene = self.scene.clone();
            scene.mechanism = Some(choice);
            match self.take_scene(scene) {
                Ok(()) => {
                    self.changed(now);
                    return;
                }
                Err(e) => last_error = e,
            }
        }
        self.set_error(format!("rejected: {last_error} (the old value is kept)"));
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
            Ok(m) if PUBLISHED.contains(&name) => {
                // A published model is a comparison: its own figures first, judged, not
                // fitted (live refit resumes with the next edit; r fits it now).
                self.set_info(format!(
                    "matrix: {name}, the published values (r fits them)"
                ));
                self.replace_matrix(m, now);
                self.judge_only();
            }
            Ok(m) => {
                self.set_info(format!("matrix: {name}"));
                self.replace_matrix(m, now);
            }
            Err(e) => self.set_error(format!("rejected: {e}")),
        }
    }

    /// The change waiting is judged, not fitted, even with live refit on.
    fn judge_only(&mut self) {
        if let Some(p) = &mut self.pending {
            p.fit = false;
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

    /// 1, 2, 3, 4 switch shear, extension, poisson, plane strain.
    fn toggle_effect(&mut self, which: char, now: Instant) {
        let e = toggled_effect(&self.scene, self.decided_effects(), which);
        let mut scene = self.scene.clone();
        scene.beam.effects = EffectsChoice::Fixed(e);
        match self.take_scene(scene) {
            Ok(()) => {
                self.set_info(format!("effects: {e}"));
                self.changed(now);
            }
            Err(err) => self.set_error(format!("rejected: {err}")),
        }
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
            Panel::Loads if self.is_data() => self.refuse_load_edit(),
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
            Panel::Mechanism => self.edit_drives(true, now),
            Panel::Beam => {}
        }
    }

    /// `a` / `d` on the mechanism panel: a copy of the selected drive after it, or the
    /// selected drive deleted (a mechanism keeps at least one); refused on a mechanism data
    /// scene, whose drives are its file's paths.
    fn edit_drives(&mut self, add: bool, now: Instant) {
        let Some(m) = self.scene.mechanism.as_ref() else {
            return;
        };
        if self.is_mech_data() {
            self.refuse_drive_edit();
            return;
        }
        let Some(d) = self.mech_field().and_then(MechField::drive) else {
            self.set_error("a / d: on a drive's rows (flexures are added in the scene file)");
            return;
        };
        let mut new = m.clone();
        if add {
            let Some(copy) = m.drives.get(d).cloned() else {
                return;
            };
            new.drives.insert(d + 1, copy);
        } else if m.drives.len() > 1 {
            new.drives.remove(d);
        } else {
            self.set_error("a mechanism needs at least one drive");
            return;
        }
        let mut scene = self.scene.clone();
        scene.mechanism = Some(new);
        match self.take_scene(scene) {
            Ok(()) => {
                let shown = if add { d + 1 } else { d.saturating_sub(1) };
                self.mech_state.drive = shown;
                self.mech_state.case = None;
                // The cursor to the shown drive's first row.
                if let Some(m) = &self.scene.mechanism {
                    self.mech_state.row = mech_state::fields(m)
                        .iter()
                        .position(|f| f.drive() == Some(shown))
                        .unwrap_or(0);
                }
                self.changed(now);
            }
            Err(e) => self.set_error(format!("rejected: {e}")),
        }
    }

    fn delete_row(&mut self, now: Instant) {
        match self.focus {
            Panel::Loads if self.is_data() => self.refuse_load_edit(),
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
            Panel::Mechanism => self.edit_drives(false, now),
            Panel::Beam => {}
        }
    }

    /// The scene was replaced (opened from a file). Nothing is unsaved after an open. A
    /// scene with its own model (`[prb] matrix`) brings it, judged as saved (`r` fits it);
    /// without one the model being worked on stays.
    pub fn set_scene(&mut self, mut scene: Scene, path: PathBuf, now: Instant) {
        let fit = match scene.prb.take() {
            Some(m) => {
                self.matrix = m;
                self.matrix_state.clamp(self.matrix.len());
                false
            }
            None => self.live,
        };
        self.scene = scene;
        self.scene_path = Some(path);
        self.scene_dirty = false;
        self.model_dirty = false;
        self.loads_state.row = 0;
        self.baseline = None;
        self.model = None;
        self.mech_state = MechState::default();
        self.mech_exact = None;
        self.mech_model = None;
        self.mech_compare = None;
        self.focus = self.focus.on_scene(self.is_mechanism());
        self.refresh(now, fit);
    }

    /// The load path whose cases the shape chart draws (on a data scene, the path of the
    /// row the load panel's cursor is on).
    pub fn shown_path(&self) -> usize {
        if self.is_data() {
            return self.path_of_row(self.loads_state.row);
        }
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
