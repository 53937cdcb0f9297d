//! The background worker: baseline solves, evaluations and fits, off the UI thread.
//!
//! Shaped like gitui's `AsyncSingleJob`: the UI sends jobs over a channel; the worker always
//! takes the newest one waiting (older ones are dropped unstarted), the UI cancels the
//! running job's token when it sends a newer one, and every message carries its job's id so
//! the UI can drop what a stale job still sends. The baseline of the last scene is cached
//! and re-solved only when the beam, the loads or the fidelity change.
//!
//! A failure in a job — a load the beam cannot reach, even a panic — becomes a `Failed`
//! message; the worker then waits for the next job.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Instant;

use crate::beam::Effects;
use crate::beam::Load;
use crate::eval::{Baseline, CaseError, ErrorFigures};
use crate::fit::{fit, CancelToken, Fidelity, FitOptions, FitReport};
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::{Accuracy, BeamSpec, EffectsChoice, LoadPath, Scene};
use crate::select::{decide_effects, select, EffectsDecision, Rung, Selection};
use crate::tradeoff::Knob;

/// The thread's name, which the panic hook uses to tell worker panics from UI panics.
pub const WORKER_THREAD: &str = "prbfit-worker";

/// What a job does.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JobKind {
    /// Write the matrix to a file, in the format its extension names.
    Export(std::path::PathBuf),
    /// Judge the matrix.
    Judge,
    /// Judge, then fit its free cells.
    Fit,
    /// Fit the topology ladder, judge the published models, measure the trade-off.
    Select,
}

/// One request on the scene's beam and loads.
#[derive(Debug, Clone)]
pub struct Job {
    pub id: u64,
    pub scene_name: String,
    pub beam: BeamSpec,
    pub loads: Vec<LoadPath>,
    pub accuracy: Accuracy,
    pub angle_weight: f64,
    pub matrix: PrbMatrix,
    pub fidelity: Fidelity,
    pub kind: JobKind,
    pub cancel: CancelToken,
}

/// What the beam looks like over the job's load cases (shared, sent once per baseline).
#[derive(Debug, Clone, PartialEq)]
pub struct BaselineView {
    /// The effects the beam was solved with (`auto` decided).
    pub effects: Effects,
    pub decision: Option<EffectsDecision>,
    pub paths: Vec<LoadPath>,
    /// Per case, in path order.
    pub loads: Vec<Load>,
    /// Per case, the deformed centre line.
    pub shapes: Vec<Vec<(f64, f64)>>,
    pub seconds: f64,
}

/// A PRB model judged on the baseline: what the charts draw.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelView {
    pub matrix: PrbMatrix,
    pub figures: ErrorFigures,
    pub cases: Vec<CaseError>,
    /// Per case, the linkage: root, then every segment's end.
    pub linkages: Vec<Vec<(f64, f64)>>,
}

/// How far a fit has got.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitStatus {
    pub iteration: u32,
    pub evaluations: u64,
    pub seconds: f64,
}

/// Messages to the UI.
#[derive(Debug, Clone)]
pub enum WorkerMsg {
    Baseline {
        id: u64,
        view: Arc<BaselineView>,
    },
    /// The job's starting matrix judged (before any fitting), or the best matrix so far.
    Progress {
        id: u64,
        model: Box<ModelView>,
        status: FitStatus,
    },
    Done {
        id: u64,
        model: Box<ModelView>,
        report: Option<Box<FitReport>>,
        seconds: f64,
    },
    Failed {
        id: u64,
        message: String,
    },
    /// One row of a selection, as soon as it is fitted.
    SelectRow {
        id: u64,
        row: Box<Rung>,
    },
    /// An export finished (or failed, saying why).
    Exported {
        id: u64,
        path: std::path::PathBuf,
        result: Result<(), String>,
    },
    /// The whole selection and the trade-off measurements.
    SelectDone {
        id: u64,
        selection: Box<Selection>,
        knobs: Vec<Knob>,
    },
}

impl WorkerMsg {
    pub fn id(&self) -> u64 {
        match self {
            WorkerMsg::Baseline { id, .. }
            | WorkerMsg::Progress { id, .. }
            | WorkerMsg::Done { id, .. }
            | WorkerMsg::Failed { id, .. }
            | WorkerMsg::SelectRow { id, .. }
            | WorkerMsg::Exported { id, .. }
            | WorkerMsg::SelectDone { id, .. } => *id,
        }
    }
}

/// The worker thread and its channels.
pub struct Worker {
    jobs: Option<Sender<Job>>,
    pub messages: Receiver<WorkerMsg>,
    handle: Option<JoinHandle<()>>,
}

impl Worker {
    pub fn spawn() -> std::io::Result<Worker> {
        let (job_tx, job_rx) = channel::<Job>();
        let (msg_tx, msg_rx) = channel::<WorkerMsg>();
        let handle = std::thread::Builder::new()
            .name(WORKER_THREAD.into())
            .spawn(move || worker_loop(job_rx, msg_tx))?;
        Ok(Worker {
            jobs: Some(job_tx),
            messages: msg_rx,
            handle: Some(handle),
        })
    }

    /// Queues a job (the worker drops any older one not yet started).
    pub fn submit(&self, job: Job) {
        if let Some(tx) = &self.jobs {
            // A send fails only if the worker is gone; the UI then sees no answer and says so
            // through the job's timeout display, never a panic.
            let _ = tx.send(job);
        }
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // Closing the channel ends the loop once the current job returns.
        self.jobs = None;
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// The baseline cache key: everything the beam solves depend on (the targets too, through
/// `effects = "auto"`).
#[derive(Debug, Clone, PartialEq)]
struct BaselineKey {
    beam: BeamSpec,
    loads: Vec<LoadPath>,
    accuracy: Accuracy,
    fidelity: Fidelity,
}

/// A cached baseline with the effects it was solved with.
struct Cached {
    key: BaselineKey,
    baseline: Arc<Baseline>,
    beam: BeamSpec,
}

fn worker_loop(jobs: Receiver<Job>, out: Sender<WorkerMsg>) {
    let mut cache: Option<Cached> = None;
    while let Ok(mut job) = jobs.recv() {
        // Only the newest job matters.
        while let Ok(newer) = jobs.try_recv() {
            job = newer;
        }
        if job.cancel.is_cancelled() {
            continue;
        }
        let id = job.id;
        let outcome = catch_unwind(AssertUnwindSafe(|| run_job(&job, &mut cache, &out)));
        let failure = match outcome {
            Ok(Ok(())) => None,
            Ok(Err(message)) => Some(message),
            Err(panic) => {
                cache = None;
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                Some(format!("internal error in the worker: {what}"))
            }
        };
        if let Some(message) = failure {
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
    let mut beam = baseline.solutions.iter();
    for path in &baseline.paths {
        solver
            .solve_path_with(path.end, path.steps, |sol| {
                let b = beam.next().expect("one beam solution per case");
                cases.push(CaseError::new(sol.load, b.tip, sol.tip));
                linkages.push(
                    solver
                        .joint_positions(sol.q)
                        .into_iter()
                        .map(|p| (p[0], p[1]))
                        .collect(),
                );
            })
            .map_err(|e| format!("the PRB model fails: {e}"))?;
    }
    Ok(ModelView {
        matrix: matrix.clone(),
        figures: ErrorFigures::from_cases(&cases, angle_weight),
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
    }
}

fn run_job(job: &Job, cache: &mut Option<Cached>, out: &Sender<WorkerMsg>) -> Result<(), String> {
    let t0 = Instant::now();
    let send = |msg: WorkerMsg| {
        // The UI has gone: nothing left to do.
        let _ = out.send(msg);
    };
    let key = BaselineKey {
        beam: job.beam,
        loads: job.loads.clone(),
        accuracy: job.accuracy,
        fidelity: job.fidelity,
    };
    let (baseline, beam) = match cache {
        Some(c) if c.key == key => (c.baseline.clone(), c.beam),
        _ => {
            // `auto` effects are decided here, off the UI thread.
            let (beam, decision) = match job.beam.effects {
                EffectsChoice::Auto => {
                    let d = decide_effects(
                        &job.beam,
                        &job.loads,
                        &job.accuracy,
                        job.fidelity.resolution(),
                    )
                    .map_err(|e| format!("the beam cannot be solved: {e}"))?;
                    let mut b = job.beam;
                    b.effects = EffectsChoice::Fixed(d.effects);
                    (b, Some(d))
                }
                EffectsChoice::Fixed(_) => (job.beam, None),
            };
            let b = Baseline::for_model(
                beam.model(),
                &job.fidelity.sample(&job.loads),
                job.fidelity.resolution(),
            )
            .map_err(|e| format!("the beam cannot be solved: {e}"))?;
            let b = Arc::new(b);
            *cache = Some(Cached {
                key,
                baseline: b.clone(),
                beam,
            });
            send(WorkerMsg::Baseline {
                id: job.id,
                view: Arc::new(baseline_view(&b, decision)),
            });
            (b, beam)
        }
    };
    match &job.kind {
        JobKind::Select => return run_selection(job, &baseline, beam, out),
        JobKind::Export(path) => {
            let result = export_file(job, &baseline, beam, path);
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
    // The edited matrix at once, so the charts answer the edit before any fitting.
    let start_view = model_view(&job.matrix, &baseline, job.angle_weight);
    if job.kind == JobKind::Judge {
        let model = start_view?;
        send(WorkerMsg::Done {
            id: job.id,
            model: Box::new(model),
            report: None,
            seconds: t0.elapsed().as_secs_f64(),
        });
        return Ok(());
    }
    if let Ok(model) = &start_view {
        send(WorkerMsg::Progress {
            id: job.id,
            model: Box::new(model.clone()),
            status: FitStatus {
                iteration: 0,
                evaluations: 0,
                seconds: t0.elapsed().as_secs_f64(),
            },
        });
    }
    let options = FitOptions {
        fidelity: job.fidelity,
        angle_weight: job.angle_weight,
        seed: 1,
    };
    let mut on_progress = |p: &crate::fit::FitProgress| {
        if let Ok(model) = model_view(p.best, &baseline, job.angle_weight) {
            send(WorkerMsg::Progress {
                id: job.id,
                model: Box::new(model),
                status: FitStatus {
                    iteration: p.iteration,
                    evaluations: p.evaluations,
                    seconds: t0.elapsed().as_secs_f64(),
                },
            });
        }
    };
    let report = fit(
        &baseline,
        &job.matrix,
        &options,
        &mut on_progress,
        &job.cancel,
    )
    .map_err(|e| format!("fit: {e}"))?;
    let model = model_view(&report.matrix, &baseline, job.angle_weight)?;
    send(WorkerMsg::Done {
        id: job.id,
        model: Box::new(model),
        report: Some(Box::new(report)),
        seconds: t0.elapsed().as_secs_f64(),
    });
    Ok(())
}

/// The selection table, row by row, then the trade-off measurements.
fn run_selection(
    job: &Job,
    baseline: &Baseline,
    beam: BeamSpec,
    out: &Sender<WorkerMsg>,
) -> Result<(), String> {
    let scene = job_scene(job, beam);
    let selection = select(&scene, baseline, job.fidelity, &job.cancel, &mut |row| {
        let _ = out.send(WorkerMsg::SelectRow {
            id: job.id,
            row: Box::new(row.clone()),
        });
    })
    .map_err(|e| format!("selection: {e}"))?;
    let knobs = crate::tradeoff::measure(&scene, &job.matrix, &job.cancel)
        .map_err(|e| format!("trade-off: {e}"))?;
    let _ = out.send(WorkerMsg::SelectDone {
        id: job.id,
        selection: Box::new(selection),
        knobs,
    });
    Ok(())
}

/// The scene of a job, with its beam's effects as solved.
fn job_scene(job: &Job, beam: BeamSpec) -> Scene {
    Scene {
        name: job.scene_name.clone(),
        beam,
        loads: job.loads.clone(),
        accuracy: job.accuracy,
        fit: crate::scene::FitSettings {
            angle_weight: job.angle_weight,
        },
        prb: Some(job.matrix.clone()),
    }
}

/// Writes the job's matrix in the format the path's extension names, never over a file.
fn export_file(
    job: &Job,
    baseline: &Baseline,
    beam: BeamSpec,
    path: &std::path::Path,
) -> Result<(), String> {
    use crate::export::{export, ExportInput};
    use crate::format::Format as ExportFormat;
    let format = ExportFormat::from_path(path).ok_or_else(|| {
        format!(
            "{}: use .toml, .json, .xml or .mjcf (MuJoCo), .urdf, .sdf or .csv",
            path.display()
        )
    })?;
    let scene = job_scene(job, beam);
    let input = ExportInput {
        name: format!("{}-model", job.matrix.topology().to_lowercase()),
        matrix: &job.matrix,
        scene: &scene,
        baseline,
        fidelity: job.fidelity.to_string(),
        density: 1000.0,
    };
    let text = export(&input, format).map_err(|e| e.to_string())?;
    crate::io::files::write_atomic(path, text.as_bytes(), false).map_err(|e| e.to_string())
}
