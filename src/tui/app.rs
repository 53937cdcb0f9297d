//! The UI's state and its update logic, free of any terminal: keys in, state changes and
//! commands (jobs for the worker, files to write) out. Rendering reads this state only.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::fit::{CancelToken, Fidelity, FitReport, StopReason};
use crate::prb::{Column, PrbMatrix, PrbRow};
use crate::scene::{EffectsChoice, ModelFile, Scene, PUBLISHED};

use super::units::{format_quantity, parse_quantity, trim_number, Quantity};
use super::worker::{BaselineView, FitStatus, Job, JobKind, ModelView, WorkerMsg};
use crate::select::Rung;
use crate::tradeoff::Knob;

/// Edits closer together than this are sent as one job.
pub const DEBOUNCE: Duration = Duration::from_millis(30);

/// The panels that take the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Panel {
    Beam,
    Loads,
    Matrix,
}

impl Panel {
    fn next(self) -> Panel {
        match self {
            Panel::Beam => Panel::Loads,
            Panel::Loads => Panel::Matrix,
            Panel::Matrix => Panel::Beam,
        }
    }

    fn prev(self) -> Panel {
        match self {
            Panel::Beam => Panel::Matrix,
            Panel::Loads => Panel::Beam,
            Panel::Matrix => Panel::Loads,
        }
    }
}

/// The rows of the beam panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeamField {
    Length,
    Width,
    Thickness,
    YoungsModulus,
    PoissonRatio,
    ShearCoefficient,
    Effects,
    /// The scene's targets and the fit's angle weight.
    MaxPosErr,
    MaxAngErr,
    AngleWeight,
}

impl BeamField {
    pub const ALL: [BeamField; 10] = [
        BeamField::Length,
        BeamField::Width,
        BeamField::Thickness,
        BeamField::YoungsModulus,
        BeamField::PoissonRatio,
        BeamField::ShearCoefficient,
        BeamField::Effects,
        BeamField::MaxPosErr,
        BeamField::MaxAngErr,
        BeamField::AngleWeight,
    ];

    pub fn label(self) -> &'static str {
        match self {
            BeamField::Length => "length",
            BeamField::Width => "width",
            BeamField::Thickness => "thickness",
            BeamField::YoungsModulus => "E",
            BeamField::PoissonRatio => "nu",
            BeamField::ShearCoefficient => "kappa",
            BeamField::Effects => "effects",
            BeamField::MaxPosErr => "pos target",
            BeamField::MaxAngErr => "ang target",
            BeamField::AngleWeight => "ang weight",
        }
    }

    fn quantity(self) -> Quantity {
        match self {
            BeamField::Length | BeamField::Width | BeamField::Thickness => Quantity::Length,
            BeamField::YoungsModulus => Quantity::Pressure,
            _ => Quantity::Plain,
        }
    }
}

/// The load table's columns.
pub const LOAD_COLUMNS: [&str; 4] = ["alpha_x", "alpha_y", "beta", "steps"];

/// What a text box is editing.
#[derive(Debug, Clone, PartialEq)]
pub enum EditTarget {
    Beam(BeamField),
    Load { row: usize, col: usize },
    Cell { row: usize, col: Column },
}

/// What a prompt asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PromptKind {
    SaveScene,
    OpenScene,
    ExportModel,
    Topology,
    ConfirmQuit,
}

impl PromptKind {
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
    pub text: String,
}

/// How a message should look.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tone {
    Info,
    Error,
}

/// Where the worker is with the latest job.
#[derive(Debug, Clone, PartialEq)]
pub enum Activity {
    Idle,
    /// Sent, nothing back yet.
    Waiting,
    Fitting(FitStatus),
    Done {
        seconds: f64,
        stop: Option<StopReason>,
        iterations: u32,
        evaluations: u64,
    },
    Failed(String),
    Cancelled,
}

/// The selection view: the ladder's table (rows arrive as they are fitted) and the trade-off.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectView {
    pub job: u64,
    pub rows: Vec<Rung>,
    pub chosen: Option<usize>,
    pub closest: Option<usize>,
    pub knobs: Vec<Knob>,
    pub selected: usize,
    pub running: bool,
}

/// Side effects the run loop carries out.
#[derive(Debug)]
pub enum Command {
    Submit(Job),
    SaveScene(PathBuf),
    OpenScene(PathBuf),
}

/// The whole UI state.
#[derive(Debug)]
pub struct App {
    pub scene: Scene,
    pub scene_path: Option<PathBuf>,
    pub scene_dirty: bool,
    pub matrix: PrbMatrix,
    /// The matrix changed since it was last exported.
    pub model_dirty: bool,
    pub focus: Panel,
    pub beam_row: usize,
    pub load_row: usize,
    pub load_col: usize,
    pub matrix_row: usize,
    pub matrix_col: usize,
    pub editing: Option<(EditTarget, TextBox)>,
    pub prompt: Option<(PromptKind, TextBox)>,
    pub help: bool,
    pub message: Option<(String, Tone)>,
    pub fidelity: Fidelity,
    pub live: bool,
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
    pub activity: Activity,
    pub baseline: Option<Arc<BaselineView>>,
    pub model: Option<ModelView>,
    /// The last fit's report.
    pub report: Option<FitReport>,
    /// Which published model `m` loads next.
    next_published: usize,
    /// The selection view, when open.
    pub select_view: Option<SelectView>,
    /// The matrix panel shows (and takes) SI values for the scene's beam.
    pub si: bool,
}

impl App {
    pub fn new(scene: Scene, scene_path: Option<PathBuf>) -> App {
        let matrix = ModelFile::load("su-3r")
            .map(|m| m.prb)
            .unwrap_or_else(|_| PrbMatrix::from_topology("L-R-R-R").expect("valid topology"));
        App {
            scene,
            scene_path,
            scene_dirty: false,
            matrix,
            model_dirty: false,
            focus: Panel::Matrix,
            beam_row: 0,
            load_row: 0,
            load_col: 0,
            matrix_row: 1,
            matrix_col: 1,
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
            select_view: None,
            si: false,
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
                if let Some(v) = &mut self.select_view {
                    v.running = false;
                }
            }
            // Taken above, whatever its job.
            WorkerMsg::Exported { .. } => {}
            WorkerMsg::SelectRow { id, row } => {
                if let Some(v) = self.select_view.as_mut().filter(|v| v.job == id) {
                    v.rows.push(*row);
                }
            }
            WorkerMsg::SelectDone {
                id,
                selection,
                knobs,
            } => {
                if let Some(v) = self.select_view.as_mut().filter(|v| v.job == id) {
                    v.rows = selection.rows;
                    v.chosen = selection.chosen;
                    v.closest = Some(selection.closest);
                    v.knobs = knobs;
                    v.selected = selection.chosen.unwrap_or(selection.closest);
                    v.running = false;
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
        self.select_view = Some(SelectView {
            job,
            rows: Vec::new(),
            chosen: None,
            closest: None,
            knobs: Vec::new(),
            selected: 0,
            running: true,
        });
        cmd
    }

    /// Keys while the selection view is open.
    fn select_key(&mut self, key: KeyEvent, now: Instant) -> Vec<Command> {
        let Some(view) = &mut self.select_view else {
            return Vec::new();
        };
        let n = view.rows.len();
        match key.code {
            KeyCode::Up | KeyCode::Char('k') => view.selected = view.selected.saturating_sub(1),
            KeyCode::Down | KeyCode::Char('j') => {
                view.selected = (view.selected + 1).min(n.saturating_sub(1))
            }
            KeyCode::Char('c') if view.running => {
                if let Some((_, token)) = &self.current_job {
                    token.cancel();
                }
                view.running = false;
                self.set_info("selection cancelled");
            }
            KeyCode::Enter => {
                if let Some(row) = view.rows.get(view.selected) {
                    let (name, m) = (row.name.clone(), row.prb.clone());
                    self.close_selection();
                    self.set_info(format!("matrix: {name} from the selection"));
                    self.replace_matrix(m, now);
                }
            }
            KeyCode::Esc | KeyCode::Char('q') => {
                self.close_selection();
                // Back to the matrix being edited: judge or fit it again.
                self.changed(now);
            }
            _ => {}
        }
        Vec::new()
    }

    fn close_selection(&mut self) {
        if let Some(v) = self.select_view.take() {
            if v.running {
                if let Some((_, token)) = &self.current_job {
                    token.cancel();
                }
            }
        }
    }

    pub fn set_error(&mut self, m: impl Into<String>) {
        self.message = Some((m.into(), Tone::Error));
    }

    pub fn set_info(&mut self, m: impl Into<String>) {
        self.message = Some((m.into(), Tone::Info));
    }

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
        if self.select_view.is_some() {
            if ctrl_c {
                self.close_selection();
                self.request_quit();
                return Vec::new();
            }
            return self.select_key(key, now);
        }
        if ctrl_c {
            self.request_quit();
            return Vec::new();
        }
        let mut out = Vec::new();
        match key.code {
            KeyCode::Char('q') => self.request_quit(),
            KeyCode::Char('?') | KeyCode::F(1) => self.help = true,
            KeyCode::Tab => self.focus = self.focus.next(),
            KeyCode::BackTab => self.focus = self.focus.prev(),
            KeyCode::Up | KeyCode::Char('k') => self.move_cursor(0, -1),
            KeyCode::Down | KeyCode::Char('j') => self.move_cursor(0, 1),
            KeyCode::Left | KeyCode::Char('h') => self.move_cursor(-1, 0),
            KeyCode::Right | KeyCode::Char('l') => self.move_cursor(1, 0),
            KeyCode::Enter => self.start_edit(),
            KeyCode::Char('r') => out.push(self.submit(true)),
            KeyCode::Char('S') => out.push(self.open_selection()),
            KeyCode::Char('c') | KeyCode::Esc => self.cancel_fit(),
            KeyCode::Char(' ') => {
                self.live = !self.live;
                self.set_info(if self.live {
                    "live refit on: every edit refits"
                } else {
                    "live refit paused: edits are judged, not fitted (r fits)"
                });
            }
            KeyCode::Char('v') => {
                self.fidelity = match self.fidelity {
                    Fidelity::Draft => Fidelity::Normal,
                    Fidelity::Normal => Fidelity::Precise,
                    Fidelity::Precise => Fidelity::Draft,
                };
                self.set_info(format!("fidelity: {}", self.fidelity));
                self.changed(now);
            }
            KeyCode::Char('s') => self.open_prompt(
                PromptKind::SaveScene,
                self.scene_path
                    .as_ref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_else(|| "scene.toml".into()),
            ),
            KeyCode::Char('o') => self.open_prompt(PromptKind::OpenScene, String::new()),
            KeyCode::Char('e') => self.open_prompt(PromptKind::ExportModel, "model.toml".into()),
            KeyCode::Char('t') => self.open_prompt(PromptKind::Topology, self.matrix.topology()),
            KeyCode::Char('m') => self.next_published_model(now),
            KeyCode::Char('f') if self.focus == Panel::Matrix => self.toggle_free(now),
            KeyCode::Char(c @ ('1' | '2' | '3')) if self.focus == Panel::Beam => {
                self.toggle_effect(c, now)
            }
            KeyCode::Char('a') => self.add_row(now),
            KeyCode::Char('d') => self.delete_row(now),
            KeyCode::Char('u') => {
                self.si = !self.si;
                self.set_info(if self.si {
                    "matrix in SI for this beam: segment lengths, N m/rad, N/m"
                } else {
                    "matrix nondimensional: gamma, k_theta (E I0/L), k_ex (E A0/L)"
                });
            }
            KeyCode::Char('[') => self.select_path(-1),
            KeyCode::Char(']') => self.select_path(1),
            _ => {}
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

    fn select_path(&mut self, delta: i32) {
        let n = self.scene.loads.len() as i32;
        self.load_row = ((self.load_row as i32 + delta).rem_euclid(n)) as usize;
    }

    fn move_cursor(&mut self, dx: i32, dy: i32) {
        let step = |v: usize, d: i32, n: usize| -> usize {
            if n == 0 {
                0
            } else {
                (v as i32 + d).clamp(0, n as i32 - 1) as usize
            }
        };
        match self.focus {
            Panel::Beam => self.beam_row = step(self.beam_row, dy, BeamField::ALL.len()),
            Panel::Loads => {
                self.load_row = step(self.load_row, dy, self.scene.loads.len());
                self.load_col = step(self.load_col, dx, LOAD_COLUMNS.len());
            }
            Panel::Matrix => {
                self.matrix_row = step(self.matrix_row, dy, self.matrix.len());
                self.matrix_col = step(self.matrix_col, dx, 3);
            }
        }
    }

    /// The text a field shows and starts its editor with.
    pub fn beam_text(&self, field: BeamField) -> String {
        let b = &self.scene.beam;
        match field {
            BeamField::Length => format_quantity(b.length, Quantity::Length),
            BeamField::Width => format_quantity(b.width, Quantity::Length),
            BeamField::Thickness => format_quantity(b.thickness, Quantity::Length),
            BeamField::YoungsModulus => format_quantity(b.youngs_modulus, Quantity::Pressure),
            BeamField::PoissonRatio => trim_number(b.poisson_ratio, 6),
            BeamField::ShearCoefficient => match b.shear_coefficient {
                Some(k) => trim_number(k, 6),
                None => format!("auto ({})", trim_number(b.kappa(), 4)),
            },
            BeamField::Effects => match b.effects {
                EffectsChoice::Auto => {
                    match self.baseline.as_ref().filter(|v| v.decision.is_some()) {
                        Some(v) => format!("auto ({})", v.effects),
                        None => "auto (deciding...)".into(),
                    }
                }
                EffectsChoice::Fixed(e) => e.to_string(),
            },
            BeamField::MaxPosErr => format!(
                "{} L ({}%)",
                trim_number(self.scene.accuracy.max_pos_err, 6),
                trim_number(self.scene.accuracy.max_pos_err * 100.0, 4)
            ),
            BeamField::MaxAngErr => format!(
                "{} rad ({} deg)",
                trim_number(self.scene.accuracy.max_ang_err, 6),
                trim_number(self.scene.accuracy.max_ang_err.to_degrees(), 4)
            ),
            BeamField::AngleWeight => trim_number(self.scene.fit.angle_weight, 6),
        }
    }

    pub fn load_text(&self, row: usize, col: usize) -> String {
        let p = &self.scene.loads[row];
        match col {
            0 => trim_number(p.end.alpha_x, 6),
            1 => trim_number(p.end.alpha_y, 6),
            2 => trim_number(p.end.beta, 6),
            _ => p.steps.to_string(),
        }
    }

    pub fn cell_text(&self, row: usize, col: Column) -> String {
        let v = self.matrix.rows()[row].get(col);
        if v == f64::INFINITY {
            "inf".into()
        } else if self.si {
            let si = v * self.si_factor(col);
            match col {
                Column::Gamma => format_quantity(si, Quantity::Length),
                _ => trim_number(si, 5),
            }
        } else {
            trim_number(v, 6)
        }
    }

    /// SI value per nondimensional unit of a column for the scene's beam: L (m) for gamma,
    /// E I0 / L (N m/rad) for k_theta, E A0 / L (N/m) for k_ex.
    pub fn si_factor(&self, col: Column) -> f64 {
        let b = &self.scene.beam;
        match col {
            Column::Gamma => b.length,
            Column::KTheta => b.youngs_modulus * b.second_moment() / b.length,
            Column::KEx => b.youngs_modulus * b.area() / b.length,
        }
    }

    fn start_edit(&mut self) {
        let (target, text) = match self.focus {
            Panel::Beam => {
                let f = BeamField::ALL[self.beam_row];
                let text = match f {
                    BeamField::ShearCoefficient if self.scene.beam.shear_coefficient.is_none() => {
                        "auto".into()
                    }
                    BeamField::Effects => self.scene.beam.effects.to_string(),
                    BeamField::MaxPosErr => trim_number(self.scene.accuracy.max_pos_err, 6),
                    BeamField::MaxAngErr => trim_number(self.scene.accuracy.max_ang_err, 6),
                    _ => self.beam_text(f),
                };
                (EditTarget::Beam(f), text)
            }
            Panel::Loads => (
                EditTarget::Load {
                    row: self.load_row,
                    col: self.load_col,
                },
                self.load_text(self.load_row, self.load_col),
            ),
            Panel::Matrix => {
                let col = Column::ALL[self.matrix_col];
                (
                    EditTarget::Cell {
                        row: self.matrix_row,
                        col,
                    },
                    self.cell_text(self.matrix_row, col),
                )
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
                let (target, tb) = self.editing.take().expect("editing");
                match self.apply_edit(&target, &tb.text) {
                    Ok(()) => self.changed(now),
                    Err(e) => self.set_error(format!("rejected: {e} (the old value is kept)")),
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
                let mut scene = self.scene.clone();
                let b = &mut scene.beam;
                match field {
                    BeamField::ShearCoefficient if text.trim() == "auto" => {
                        b.shear_coefficient = None
                    }
                    BeamField::Effects => {
                        b.effects = match text.trim() {
                            "auto" => EffectsChoice::Auto,
                            other => EffectsChoice::Fixed(
                                crate::beam::Effects::parse_list(other)
                                    .map_err(|e| e.to_string())?,
                            ),
                        }
                    }
                    f => {
                        let v = parse_quantity(text, f.quantity())?;
                        match f {
                            BeamField::Length => b.length = v,
                            BeamField::Width => b.width = v,
                            BeamField::Thickness => b.thickness = v,
                            BeamField::YoungsModulus => b.youngs_modulus = v,
                            BeamField::PoissonRatio => b.poisson_ratio = v,
                            BeamField::ShearCoefficient => b.shear_coefficient = Some(v),
                            BeamField::MaxPosErr => scene.accuracy.max_pos_err = v,
                            BeamField::MaxAngErr => scene.accuracy.max_ang_err = v,
                            BeamField::AngleWeight => scene.fit.angle_weight = v,
                            BeamField::Effects => unreachable!("handled above"),
                        }
                    }
                }
                // The scene file's own validation decides what is acceptable.
                Scene::from_toml_str(&scene.to_toml(), "edit").map_err(|e| {
                    format!(
                        "{}: {}",
                        e.key.unwrap_or_else(|| field.label().into()),
                        e.message
                    )
                })?;
                if scene != self.scene {
                    self.scene = scene;
                    self.scene_dirty = true;
                }
            }
            EditTarget::Load { row, col } => {
                let mut path = self.scene.loads[*row];
                if *col == 3 {
                    let steps: i64 = text
                        .trim()
                        .parse()
                        .map_err(|_| format!("steps: `{}` is not a whole number", text.trim()))?;
                    if !(1..=crate::scene::MAX_STEPS).contains(&steps) {
                        return Err(format!("steps must be 1 to {}", crate::scene::MAX_STEPS));
                    }
                    path.steps = steps as u32;
                } else {
                    let v = parse_quantity(text, Quantity::Plain)
                        .map_err(|e| format!("{}: {e}", LOAD_COLUMNS[*col]))?;
                    match col {
                        0 => path.end.alpha_x = v,
                        1 => path.end.alpha_y = v,
                        _ => path.end.beta = v,
                    }
                    if path.end.magnitude() == 0.0 {
                        return Err("a load path cannot be all zero".into());
                    }
                }
                if path != self.scene.loads[*row] {
                    self.scene.loads[*row] = path;
                    self.scene_dirty = true;
                }
            }
            EditTarget::Cell { row, col } => {
                let v = match text.trim().to_ascii_lowercase().as_str() {
                    "inf" => f64::INFINITY,
                    _ if self.si => {
                        // SI input: a length for gamma, N m/rad or N/m for the springs.
                        let q = if *col == Column::Gamma {
                            Quantity::Length
                        } else {
                            Quantity::Plain
                        };
                        parse_quantity(text, q).map_err(|e| format!("{col}: {e}"))?
                            / self.si_factor(*col)
                    }
                    _ => {
                        parse_quantity(text, Quantity::Plain).map_err(|e| format!("{col}: {e}"))?
                    }
                };
                // Typing a gamma keeps the gammas summing to 1: the difference goes to another
                // segment (a free one first).
                let m = if *col == Column::Gamma && self.matrix.len() > 1 {
                    self.rebalance_gamma(*row, v)?
                } else {
                    self.matrix
                        .with_cell(*row, *col, v)
                        .map_err(|e| e.to_string())?
                };
                if m != self.matrix {
                    self.matrix = m;
                    self.model_dirty = true;
                }
            }
        }
        Ok(())
    }

    /// Sets gamma of `row` to `v` and takes the difference from another segment (the next
    /// free one, else any other), so the gammas still sum to 1.
    fn rebalance_gamma(&self, row: usize, v: f64) -> Result<PrbMatrix, String> {
        let rows = self.matrix.rows();
        let delta = v - rows[row].gamma;
        let donor = (0..rows.len())
            .filter(|&i| i != row)
            .max_by_key(|&i| (rows[i].is_free(Column::Gamma), i > row, i))
            .ok_or("a single segment's gamma is always 1")?;
        let mut new_rows = rows.to_vec();
        new_rows[row].gamma = v;
        new_rows[donor].gamma -= delta;
        PrbMatrix::new(new_rows)
            .map_err(|e| format!("{e} (segment {} would get the rest)", donor + 1))
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
                    PromptKind::ExportModel => {
                        // Exported by the worker from its baseline: no solve on this thread.
                        vec![self.export(PathBuf::from(text))]
                    }
                    PromptKind::Topology => {
                        self.load_named_matrix(&text, Instant::now());
                        Vec::new()
                    }
                    PromptKind::ConfirmQuit => unreachable!("handled above"),
                };
            }
            _ => {}
        }
        Vec::new()
    }

    /// A topology name or a published model's name.
    fn load_named_matrix(&mut self, name: &str, now: Instant) {
        let m = if PUBLISHED.iter().any(|(n, _)| *n == name) {
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
        let (name, _) = PUBLISHED[self.next_published % PUBLISHED.len()];
        self.next_published += 1;
        self.load_named_matrix(name, now);
    }

    fn replace_matrix(&mut self, m: PrbMatrix, now: Instant) {
        self.matrix = m;
        self.model_dirty = true;
        self.matrix_row = self.matrix_row.min(self.matrix.len() - 1);
        self.changed(now);
    }

    /// 1, 2, 3 switch shear, extension, poisson (poisson needs extension, so they move
    /// together where they must).
    fn toggle_effect(&mut self, which: char, now: Instant) {
        // From what the beam uses now (`auto` as decided, when known).
        let mut e = match (self.scene.beam.effects, &self.baseline) {
            (EffectsChoice::Auto, Some(v)) => v.effects,
            (choice, _) => choice.resolve(),
        };
        match which {
            '1' => e.shear = !e.shear,
            '2' => {
                e.extension = !e.extension;
                e.poisson &= e.extension;
            }
            _ => {
                e.poisson = !e.poisson;
                e.extension |= e.poisson;
            }
        }
        self.scene.beam.effects = EffectsChoice::Fixed(e);
        self.scene_dirty = true;
        self.set_info(format!("effects: {e}"));
        self.changed(now);
    }

    fn toggle_free(&mut self, now: Instant) {
        let col = Column::ALL[self.matrix_col];
        let row = self.matrix_row;
        if self.matrix.rows()[row].get(col) == f64::INFINITY {
            self.set_error("an inf cell is topology, not a parameter: type a value first");
            return;
        }
        let free = self.matrix.rows()[row].free[col.index()];
        self.matrix.set_free(row, col, !free);
        self.model_dirty = true;
        self.changed(now);
    }

    fn add_row(&mut self, now: Instant) {
        match self.focus {
            Panel::Loads => {
                let copy = self.scene.loads[self.load_row];
                self.scene.loads.insert(self.load_row + 1, copy);
                self.load_row += 1;
                self.scene_dirty = true;
                self.changed(now);
            }
            Panel::Matrix => {
                // Split the selected segment in two halves; the new one gets a joint.
                let rows = self.matrix.rows();
                let r = rows[self.matrix_row];
                let half = r.gamma / 2.0;
                let mut new_rows = rows.to_vec();
                new_rows[self.matrix_row].gamma = half;
                let k = if r.has_revolute() {
                    r.k_theta
                } else {
                    self.matrix.revolute_count().max(1) as f64
                };
                new_rows.insert(
                    self.matrix_row + 1,
                    PrbRow {
                        gamma: half,
                        k_theta: k,
                        k_ex: f64::INFINITY,
                        free: [true; 3],
                    },
                );
                match PrbMatrix::new(new_rows) {
                    Ok(m) => {
                        self.matrix_row += 1;
                        self.replace_matrix(m, now);
                    }
                    Err(e) => self.set_error(format!("rejected: {e}")),
                }
            }
            Panel::Beam => {}
        }
    }

    fn delete_row(&mut self, now: Instant) {
        match self.focus {
            Panel::Loads => {
                if self.scene.loads.len() <= 1 {
                    self.set_error("a scene needs at least one load path");
                    return;
                }
                self.scene.loads.remove(self.load_row);
                self.load_row = self.load_row.min(self.scene.loads.len() - 1);
                self.scene_dirty = true;
                self.changed(now);
            }
            Panel::Matrix => {
                if self.matrix.len() <= 1 {
                    self.set_error("a PRB model needs at least one segment");
                    return;
                }
                // The removed segment's length goes to its neighbour.
                let mut rows = self.matrix.rows().to_vec();
                let gone = rows.remove(self.matrix_row);
                let neighbour = self.matrix_row.saturating_sub(1).min(rows.len() - 1);
                rows[neighbour].gamma += gone.gamma;
                match PrbMatrix::new(rows) {
                    Ok(m) => self.replace_matrix(m, now),
                    Err(e) => self.set_error(format!("rejected: {e}")),
                }
            }
            Panel::Beam => {}
        }
    }

    /// The scene was replaced (opened from a file).
    pub fn set_scene(&mut self, scene: Scene, path: PathBuf, now: Instant) {
        self.scene = scene;
        self.scene_path = Some(path);
        self.scene_dirty = false;
        self.load_row = 0;
        self.baseline = None;
        self.model = None;
        self.changed(now);
    }

    /// The load path whose cases the shape chart draws.
    pub fn shown_path(&self) -> usize {
        self.load_row.min(self.scene.loads.len().saturating_sub(1))
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
