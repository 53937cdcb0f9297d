//! The background worker: baseline solves, evaluations and fits, off the UI thread.
//!
//! The UI hands jobs to a [`LatestJob`] queue: the worker always takes the newest one (older
//! ones waiting are dropped unstarted, the running one is cancelled), and every message
//! carries its job's id so the UI can drop what a stale job still sends. Exports are side
//! effects the user asked for: they go through the queue's kept lane, are never cancelled by a
//! newer job and their result is always delivered.
//!
//! Results carry what they were computed from: every `Progress` and `Done` holds the
//! [`BaselineView`] its model (and the model compared against, if any) was judged on, as does
//! a compare job's `Compared`, so no order of messages can pair a model with
//! another beam's baseline, or with none. The baseline of the last scene is cached and
//! re-solved only when the beam, the loads, the targets or the fidelity change.
//!
//! A failure in a job (a load the beam cannot reach, even a panic) becomes a `Failed`
//! message; the worker then waits for the next job.
//!
//! Mechanism scenes (DESIGN §8) take their own path (`worker/mech.rs`): the exact mechanism in place
//! of the baseline, its own messages (`Mech*`) with views of mechanisms. A data scene's
//! (DESIGN §9) baseline is its rows, with the scene's beam solved at the measured loads
//! beside them ([`MeasuredView`], `worker/data.rs`); a mechanism data scene's truth is its
//! measured cases, with the beam mechanism beside them ([`MechMeasuredView`]).

mod data;
mod mech;

pub use data::{measured_view, BeamBeside, Cancelled, MeasuredView};
pub use mech::{
    mech_baseline_view, mech_model_view, CaseErrors, MechBaselineView, MechMeasuredView,
    MechModelView,
};

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::beam::{Effects, Load, Resolution};
use crate::cancel::CancelToken;
use crate::eval::{tip_figures, Baseline, CaseError};
use crate::fit::{Fidelity, FitOptions, FitReport};
use crate::mech::figures::Figures;
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::data::DataTruth;
use crate::scene::{Accuracy, BeamSpec, LoadPath, Scene};
use crate::study::select::{Rung, Selection};
use crate::study::tradeoff::Knob;
use crate::study::{resolve_effects, EffectsDecision, Sampling, Study};

use super::latest_job::{Cancellable, LatestJob, Taken};

/// The thread's name, which the panic hook uses to tell worker panics from UI panics.
pub const WORKER_THREAD: &str = "prbfit-worker";

/// How long quitting waits for the worker to notice its job was cancelled before leaving the
/// thread behind (the process is about to end).
pub const SHUTDOWN_DEADLINE: Duration = Duration::from_millis(200);

/// What a job does.
#[derive(Debug, Clone, PartialEq)]
pub enum JobKind {
    /// Write the matrix to a file, in the format its extension names.
    Export {
        /// The file.
        path: std::path::PathBuf,
        /// The links' density (kg/m^3), for the masses of the robot formats.
        density: f64,
        /// Replace the file if it exists (the user said so).
        overwrite: bool,
    },
    /// Judge the matrix.
    Judge,
    /// Judge, then fit its free cells.
    Fit,
    /// Fit the topology ladder, judge the published models, measure the trade-off.
    Select,
    /// Judge the matrix as the model the user compares against (a kept job: it neither
    /// cancels nor is cancelled by the fit of the model being worked on).
    Compare,
}

/// One request: the scene as it was when the job was made, and the matrix.
#[derive(Debug, Clone)]
pub struct Job {
    /// Numbers jobs in the order the UI made them; every message names its job.
    pub id: u64,
    /// The scene (beam, loads, targets, angle weight) the job works on.
    pub scene: Arc<Scene>,
    /// The PRB matrix to judge, fit or export.
    pub matrix: PrbMatrix,
    /// The model to compare against: a judge or fit job judges it too, on the same
    /// baseline, and its messages carry it.
    pub compare: Option<PrbMatrix>,
    /// How finely the beam is solved and the fit sampled.
    pub fidelity: Fidelity,
    /// What to do.
    pub kind: JobKind,
    /// Stops the job; cancelled when a newer job is submitted (except for exports).
    pub cancel: CancelToken,
}

impl Cancellable for Job {
    fn cancel_token(&self) -> &CancelToken {
        &self.cancel
    }
}

/// What the beam looks like over a job's load cases.
#[derive(Debug, Clone, PartialEq)]
pub struct BaselineView {
    /// The effects the beam was solved with (`auto` decided).
    pub effects: Effects,
    /// How `auto` effects were decided, when they were.
    pub decision: Option<EffectsDecision>,
    /// The load paths as sampled.
    pub paths: Vec<LoadPath>,
    /// Per case, in path order.
    pub loads: Vec<Load>,
    /// Per case, the deformed centre line (empty for measured data: only the tip was
    /// measured).
    pub shapes: Vec<Vec<(f64, f64)>>,
    /// How long the beam solves took.
    pub seconds: f64,
    /// A data scene's truth and the beam beside it; `None` when the truth is the beam.
    pub measured: Option<MeasuredView>,
}

/// A PRB model judged on the baseline: what the charts draw.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelView {
    /// The matrix judged.
    pub matrix: PrbMatrix,
    /// Its objective and maximum errors.
    pub figures: Figures,
    /// Per case, the tip errors.
    pub cases: Vec<CaseError>,
    /// Per case, the linkage: root, then every segment's end.
    pub linkages: Vec<Vec<(f64, f64)>>,
}

/// How far a fit has got.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitStatus {
    /// Optimiser iterations so far.
    pub iteration: u32,
    /// Objective evaluations so far.
    pub evaluations: u64,
    /// Time since the job started.
    pub seconds: f64,
}

/// Messages to the UI.
#[derive(Debug, Clone)]
pub enum WorkerMsg {
    /// The job's starting matrix judged (before any fitting), or the best matrix so far.
    Progress {
        /// The job.
        id: u64,
        /// The baseline the model was judged on.
        baseline: Arc<BaselineView>,
        /// The model.
        model: Box<ModelView>,
        /// How far the fit has got.
        status: FitStatus,
        /// The job's compare model, judged on the same baseline.
        compare: Option<Box<ModelView>>,
    },
    /// The job's final model.
    Done {
        /// The job.
        id: u64,
        /// The baseline the model was judged on.
        baseline: Arc<BaselineView>,
        /// The model.
        model: Box<ModelView>,
        /// The fit's report (none for a judge job).
        report: Option<Box<FitReport>>,
        /// Time the job took.
        seconds: f64,
        /// The job's compare model, judged on the same baseline.
        compare: Option<Box<ModelView>>,
    },
    /// A compare job's model, judged.
    Compared {
        /// The job.
        id: u64,
        /// The baseline it was judged on.
        baseline: Arc<BaselineView>,
        /// The model.
        model: Box<ModelView>,
    },
    /// The job failed, saying why.
    Failed {
        /// The job.
        id: u64,
        /// Why, for the user.
        message: String,
    },
    /// One row of a selection, as soon as it is fitted.
    SelectRow {
        /// The job.
        id: u64,
        /// The row.
        row: Box<Rung>,
    },
    /// An export finished (or failed, saying why). Never stale: the user asked for it.
    Exported {
        /// The job.
        id: u64,
        /// The file.
        path: std::path::PathBuf,
        /// Written, or why not.
        result: Result<(), String>,
    },
    /// A mechanism job's starting matrix judged (before any fitting), or the best so far.
    MechProgress {
        /// The job.
        id: u64,
        /// The exact mechanism the model was judged on.
        exact: Arc<MechBaselineView>,
        /// The model.
        model: Box<MechModelView>,
        /// How far the fit has got.
        status: FitStatus,
        /// The job's compare model, judged on the same exact mechanism.
        compare: Option<Box<MechModelView>>,
    },
    /// A mechanism job's final model.
    MechDone {
        /// The job.
        id: u64,
        /// The exact mechanism the model was judged on.
        exact: Arc<MechBaselineView>,
        /// The model.
        model: Box<MechModelView>,
        /// The fit's report (none for a judge job).
        report: Option<Box<FitReport>>,
        /// Time the job took.
        seconds: f64,
        /// The job's compare model, judged on the same exact mechanism.
        compare: Option<Box<MechModelView>>,
    },
    /// One row of a mechanism scene's selection, as soon as it is fitted.
    MechSelectRow {
        /// The job.
        id: u64,
        /// The row.
        row: Box<Rung>,
    },
    /// A mechanism scene's whole selection.
    MechSelectDone {
        /// The job.
        id: u64,
        /// The ladder, its choice and the models that cannot follow.
        selection: Box<Selection>,
    },
    /// A mechanism compare job's model, judged.
    MechCompared {
        /// The job.
        id: u64,
        /// The exact mechanism it was judged on.
        exact: Arc<MechBaselineView>,
        /// The model.
        model: Box<MechModelView>,
    },
    /// The whole selection and the trade-off measurements.
    SelectDone {
        /// The job.
        id: u64,
        /// The ladder and its choice.
        selection: Box<Selection>,
        /// The trade-off measurements.
        knobs: Vec<Knob>,
    },
}

impl WorkerMsg {
    /// The job the message belongs to.
    pub fn id(&self) -> u64 {
        match self {
            WorkerMsg::Progress { id, .. }
            | WorkerMsg::Done { id, .. }
            | WorkerMsg::Failed { id, .. }
            | WorkerMsg::Compared { id, .. }
            | WorkerMsg::SelectRow { id, .. }
            | WorkerMsg::Exported { id, .. }
            | WorkerMsg::SelectDone { id, .. }
            | WorkerMsg::MechProgress { id, .. }
            | WorkerMsg::MechDone { id, .. }
            | WorkerMsg::MechCompared { id, .. }
            | WorkerMsg::MechSelectRow { id, .. }
            | WorkerMsg::MechSelectDone { id, .. } => *id,
        }
    }
}

/// The worker thread, its job queue and its messages.
pub struct Worker {
    queue: LatestJob<Job>,
    /// What the worker sends back.
    pub messages: Receiver<WorkerMsg>,
    handle: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the worker thread.
    pub fn spawn() -> std::io::Result<Worker> {
        let queue = LatestJob::new();
        let (msg_tx, msg_rx) = channel::<WorkerMsg>();
        let jobs = queue.clone();
        let handle = std::thread::Builder::new()
            .name(WORKER_THREAD.into())
            .spawn(move || worker_loop(&jobs, &msg_tx))?;
        Ok(Worker {
            queue,
            messages: msg_rx,
            handle: Some(handle),
        })
    }

    /// Queues a job. An export or a compare is kept until done; any other job replaces the
    /// one waiting and cancels the one running.
    pub fn submit(&self, job: Job) {
        if matches!(job.kind, JobKind::Export { .. } | JobKind::Compare) {
            self.queue.submit_kept(job);
        } else {
            self.queue.submit(job);
        }
    }

    /// Stops the worker: cancels its job and waits up to `deadline` for the thread to end;
    /// past that the thread is left to finish on its own. Returns whether it ended.
    pub fn shutdown(mut self, deadline: Duration) -> bool {
        self.stop(deadline)
    }

    fn stop(&mut self, deadline: Duration) -> bool {
        self.queue.close();
        let Some(handle) = self.handle.take() else {
            return true;
        };
        if join_within(handle, deadline).is_none() {
            return false;
        }
        true
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.stop(SHUTDOWN_DEADLINE);
    }
}

/// Joins `handle` if its thread ends within `deadline`; otherwise detaches it and returns
/// `None`.
pub fn join_within<T>(handle: JoinHandle<T>, deadline: Duration) -> Option<std::thread::Result<T>> {
    let t0 = Instant::now();
    while !handle.is_finished() {
        if t0.elapsed() >= deadline {
            return None;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    Some(handle.join())
}

/// The baseline cache key: everything the beam solves depend on (the targets too, through
/// `effects = "auto"`).
#[derive(Debug, Clone, PartialEq)]
struct BaselineKey {
    beam: BeamSpec,
    loads: Vec<LoadPath>,
    accuracy: Accuracy,
    fidelity: Fidelity,
    /// A data scene's rows (as converted with the beam) and its file's hash.
    truth: Option<DataTruth>,
}

impl BaselineKey {
    fn of(job: &Job) -> BaselineKey {
        BaselineKey {
            beam: job.scene.beam,
            loads: job.scene.loads.clone(),
            accuracy: job.scene.accuracy,
            fidelity: job.fidelity,
            truth: job.scene.truth.clone(),
        }
    }
}

/// A solved baseline: what it was solved from, the solutions, the charts' view of them and
/// the beam with its effects as solved.
#[derive(Clone)]
struct Solved {
    key: BaselineKey,
    study: Arc<Study>,
    view: Arc<BaselineView>,
}

impl Solved {
    /// The cantilever's beam solutions (a cantilever study always has them).
    fn baseline(&self) -> Result<&Baseline, String> {
        self.study
            .baseline()
            .ok_or_else(|| "internal error: a cantilever job on a mechanism scene".to_string())
    }
}

fn worker_loop(jobs: &LatestJob<Job>, out: &Sender<WorkerMsg>) {
    let mut cache: Option<Solved> = None;
    let mut mech_cache: Option<mech::Solved> = None;
    while let Some(taken) = jobs.take() {
        if taken.job.cancel.is_cancelled() {
            continue;
        }
        let id = taken.job.id;
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            run_job(&taken, jobs, &mut cache, &mut mech_cache, out)
        }));
        let failure = match outcome {
            Ok(Ok(())) => None,
            Ok(Err(message)) => Some(message),
            Err(panic) => {
                cache = None;
                mech_cache = None;
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                Some(format!("internal error in the worker: {what}"))
            }
        };
        // A cancelled job's failure (its solve stopped on the token) is no news: a newer job
        // or the user's cancel already speaks for it.
        if let Some(message) = failure.filter(|_| !taken.job.cancel.is_cancelled()) {
            if out.send(WorkerMsg::Failed { id, message }).is_err() {
                return;
            }
        }
    }
}

/// Judges a matrix on a baseline for the charts: the errors and the linkage of every case,
/// from one PRB solve of each load path.
pub fn model_view(
    matrix: &PrbMatrix,
    baseline: &Baseline,
    angle_weight: f64,
) -> Result<ModelView, String> {
    let solver = PrbSolver::new(matrix, baseline.model.axial_compliance());
    let mut cases = Vec::with_capacity(baseline.case_count());
    let mut linkages = Vec::with_capacity(baseline.case_count());
    baseline
        .follow(
            &solver,
            |b, sol| {
                cases.push(CaseError::new(sol.load, b.tip, sol.tip));
                linkages.push(
                    solver
                        .joint_positions(sol.q)
                        .into_iter()
                        .map(|p| (p[0], p[1]))
                        .collect(),
                );
            },
            |_, _| std::ops::ControlFlow::Break(()),
        )
        .map_err(|e| format!("the PRB model fails: {e}"))?;
    if cases.len() != baseline.case_count() {
        return Err(format!(
            "internal error: {} PRB cases for {} beam cases",
            cases.len(),
            baseline.case_count()
        ));
    }
    Ok(ModelView {
        matrix: matrix.clone(),
        figures: tip_figures(&cases, angle_weight),
        cases,
        linkages,
    })
}

/// The charts' view of a baseline.
pub fn baseline_view(baseline: &Baseline, decision: Option<EffectsDecision>) -> BaselineView {
    BaselineView {
        effects: baseline.model.effects,
        decision,
        paths: baseline.paths.clone(),
        loads: baseline.solutions.iter().map(|s| s.load).collect(),
        shapes: baseline
            .solutions
            .iter()
            .map(|s| s.shape.iter().map(|p| (p.x, p.y)).collect())
            .collect(),
        seconds: baseline.seconds,
        measured: None,
    }
}

/// The baseline for `job`: the cached one when the job's beam, loads, targets and fidelity
/// are those it was solved from, else solved now (and cached).
fn solve_baseline(job: &Job, cache: &mut Option<Solved>) -> Result<Solved, String> {
    let key = BaselineKey::of(job);
    if let Some(c) = cache.as_ref().filter(|c| c.key == key) {
        return Ok(c.clone());
    }
    // `auto` effects are decided here, off the UI thread, as every front end decides them;
    // the truth is the study's (cancellable: a load the beam struggles with never keeps the
    // worker from a newer job).
    let (scene, decision) = resolve_effects(&job.scene, Resolution::default(), &job.cancel)
        .map_err(|e| format!("the beam cannot be solved: {e}"))?;
    let study = Study::decided(
        scene,
        decision.clone(),
        Sampling::Fidelity(job.fidelity),
        &job.cancel,
        &mut |_, _, _| {},
    )
    .map_err(|e| format!("the beam cannot be solved: {e}"))?;
    let beam = study.scene().beam;
    // Measured data is what it is (no resolution or sampling to choose); the beam beside it
    // is solved at the fidelity's resolution.
    let measured = match &study.scene().truth {
        Some(truth) => Some(
            measured_view(truth, &beam, job.fidelity.resolution(), &job.cancel)
                .map_err(|Cancelled| "cancelled".to_string())?,
        ),
        None => None,
    };
    let b = study
        .baseline()
        .ok_or("internal error: a cantilever job on a mechanism scene")?;
    let mut view = baseline_view(b, decision);
    view.measured = measured;
    let solved = Solved {
        key,
        view: Arc::new(view),
        study: Arc::new(study),
    };
    *cache = Some(solved.clone());
    Ok(solved)
}

fn run_job(
    taken: &Taken<Job>,
    jobs: &LatestJob<Job>,
    cache: &mut Option<Solved>,
    mech_cache: &mut Option<mech::Solved>,
    out: &Sender<WorkerMsg>,
) -> Result<(), String> {
    let job = &taken.job;
    let t0 = Instant::now();
    let send = |msg: WorkerMsg| {
        // A newer job was submitted: the UI would drop this. An export is never stale.
        if !jobs.is_stale(taken) {
            // The UI has gone: nothing left to do.
            let _ = out.send(msg);
        }
    };
    if job.scene.mechanism.is_some() {
        return mech::run_job(job, mech_cache, &send);
    }
    let solved = solve_baseline(job, cache)?;
    let baseline = solved.baseline()?;
    match &job.kind {
        JobKind::Select => return run_selection(job, &solved, &send),
        JobKind::Export {
            path,
            density,
            overwrite,
        } => {
            let result = export_file(job, &solved, path, *density, *overwrite);
            send(WorkerMsg::Exported {
                id: job.id,
                path: path.clone(),
                result,
            });
            return Ok(());
        }
        _ => {}
    }
    if job.cancel.is_cancelled() {
        return Ok(());
    }
    let angle_weight = job.scene.fit.angle_weight;
    if job.kind == JobKind::Compare {
        let model = model_view(&job.matrix, baseline, angle_weight)?;
        send(WorkerMsg::Compared {
            id: job.id,
            baseline: solved.view.clone(),
            model: Box::new(model),
        });
        return Ok(());
    }
    // The compared model on the same baseline, once; a model that fails here is just not
    // shown (the main model is what the job is for).
    let compare = job
        .compare
        .as_ref()
        .and_then(|m| model_view(m, baseline, angle_weight).ok())
        .map(Box::new);
    let progress = |model: ModelView, status: FitStatus| WorkerMsg::Progress {
        id: job.id,
        baseline: solved.view.clone(),
        model: Box::new(model),
        status,
        compare: compare.clone(),
    };
    // The edited matrix at once, so the charts answer the edit before any fitting.
    let start_view = model_view(&job.matrix, baseline, angle_weight);
    if job.kind == JobKind::Judge {
        let model = start_view?;
        send(WorkerMsg::Done {
            id: job.id,
            baseline: solved.view.clone(),
            model: Box::new(model),
            report: None,
            seconds: t0.elapsed().as_secs_f64(),
            compare,
        });
        return Ok(());
    }
    if let Ok(model) = start_view {
        let status = FitStatus {
            iteration: 0,
            evaluations: 0,
            seconds: t0.elapsed().as_secs_f64(),
        };
        send(progress(model, status));
    }
    let options = FitOptions {
        fidelity: job.fidelity,
        angle_weight,
        seed: 1,
    };
    let mut on_progress = |p: &crate::fit::FitProgress| {
        if let Ok(model) = model_view(p.best, baseline, angle_weight) {
            let status = FitStatus {
                iteration: p.iteration,
                evaluations: p.evaluations,
                seconds: t0.elapsed().as_secs_f64(),
            };
            send(progress(model, status));
        }
    };
    let report = solved
        .study
        .fit(&job.matrix, &options, &mut on_progress, &job.cancel)
        .map_err(|e| format!("fit: {e}"))?;
    let model = model_view(&report.matrix, baseline, angle_weight)?;
    send(WorkerMsg::Done {
        id: job.id,
        baseline: solved.view.clone(),
        model: Box::new(model),
        report: Some(Box::new(report)),
        seconds: t0.elapsed().as_secs_f64(),
        compare,
    });
    Ok(())
}

/// The selection table, row by row, then the trade-off measurements.
fn run_selection(job: &Job, solved: &Solved, send: &dyn Fn(WorkerMsg)) -> Result<(), String> {
    let scene = solved.study.scene();
    let selection = solved
        .study
        .select(job.fidelity, &job.cancel, &mut |row| {
            send(WorkerMsg::SelectRow {
                id: job.id,
                row: Box::new(row.clone()),
            });
        })
        .map_err(|e| format!("selection: {e}"))?;
    // The trade-off measures the beam's resolution and the load sampling, which measured
    // data does not have (the CLI's `tradeoff` refuses a data scene for the same reason).
    let knobs = if scene.truth.is_some() {
        Vec::new()
    } else {
        crate::study::tradeoff::measure(scene, &job.matrix, &job.cancel)
            .map_err(|e| format!("trade-off: {e}"))?
    };
    send(WorkerMsg::SelectDone {
        id: job.id,
        selection: Box::new(selection),
        knobs,
    });
    Ok(())
}

/// Writes the job's matrix in the format the path's extension names; over an existing file
/// only when `overwrite` (the UI asked the user).
fn export_file(
    job: &Job,
    solved: &Solved,
    path: &std::path::Path,
    density: f64,
    overwrite: bool,
) -> Result<(), String> {
    use crate::format::Format;
    let format = Format::from_path(path).ok_or_else(|| {
        format!(
            "{}: use .toml, .json, .xml or .mjcf (MuJoCo), .urdf, .sdf or .csv",
            path.display()
        )
    })?;
    let name = format!("{}-model", job.matrix.topology().to_lowercase());
    let text = solved
        .study
        .export(&name, &job.matrix, format, density)
        .map_err(|e| e.to_string())?;
    crate::io::files::write_atomic(path, text.as_bytes(), overwrite).map_err(write_error)
}

/// A write error as the UI says it: an existing file is a question the UI asks (no `--force`
/// in a terminal UI).
pub fn write_error(e: crate::io::files::WriteError) -> String {
    match e {
        crate::io::files::WriteError::Exists(p) => format!("{}: the file exists", p.display()),
        e => e.to_string(),
    }
}
