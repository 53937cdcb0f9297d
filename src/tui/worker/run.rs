//! One job, whatever the scene: its study (cached), then a judge, a fit, a selection, a
//! compare or an export, every result sent with the truth view it was judged on.
//!
//! The cache holds one [`Study`] and its [`TruthView`] per scene key: the job's scene (its
//! beam, loads or mechanism, targets, weights and data; no model) and its fidelity. A job on
//! the same key reuses them; any other solves the truth again, deciding `auto` effects as
//! every front end decides them ([`Study::solve`]).

use std::sync::Arc;
use std::time::Instant;

use crate::fit::{Fidelity, FitOptions, FitProgress};
use crate::format::Format;
use crate::scene::Scene;
use crate::study::{CaseForm, Sampling, Study, StudyError};

use super::job::{FitStatus, Job, JobKind, WorkerMsg};
use super::truth::truth_view;
use super::view::{model_view, ModelView, TruthView};

/// A solved study: the scene key it was solved for, and the charts' view of its truth.
#[derive(Clone)]
pub(super) struct Solved {
    key: (Scene, Fidelity),
    study: Arc<Study>,
    view: Arc<TruthView>,
}

/// The study of `scene` at `fidelity`, its `auto` effects decided as every front end decides
/// them; cancellable (a load the beam struggles with never keeps the worker from a newer
/// job).
pub fn study_of(
    scene: &Scene,
    fidelity: Fidelity,
    cancel: &crate::cancel::CancelToken,
) -> Result<Study, String> {
    Study::solve(
        scene,
        Sampling::Fidelity(fidelity),
        cancel,
        &mut |_, _, _| {},
    )
    .map_err(|e| match e {
        StudyError::Cancelled => "cancelled".to_string(),
        e => format!("the truth cannot be solved: {e}"),
    })
}

/// The study for `job`: the cached one when the job's scene key is the one it was solved
/// for, else solved now (and cached).
fn solve(job: &Job, cache: &mut Option<Solved>) -> Result<Solved, String> {
    let mut scene = (*job.scene).clone();
    // The model being worked on is the job's matrix, not the scene's.
    scene.prb = None;
    let key = (scene, job.fidelity);
    if let Some(c) = cache.as_ref().filter(|c| c.key == key) {
        return Ok(c.clone());
    }
    let study = study_of(&key.0, job.fidelity, &job.cancel)?;
    let view = truth_view(&study, &job.cancel)?;
    let solved = Solved {
        key,
        study: Arc::new(study),
        view: Arc::new(view),
    };
    *cache = Some(solved.clone());
    Ok(solved)
}

/// Runs `job`, handing its messages to `send`.
pub(super) fn run_job(
    job: &Job,
    cache: &mut Option<Solved>,
    send: &dyn Fn(WorkerMsg),
) -> Result<(), String> {
    let t0 = Instant::now();
    let solved = solve(job, cache)?;
    let (study, truth) = (&solved.study, &solved.view);
    match &job.kind {
        JobKind::Export {
            path,
            density,
            overwrite,
        } => {
            let result = export_file(job, study, path, *density, *overwrite);
            send(WorkerMsg::Exported {
                id: job.id,
                path: path.clone(),
                result,
            });
            return Ok(());
        }
        _ if job.cancel.is_cancelled() => return Ok(()),
        JobKind::Select => return run_selection(job, study, send),
        JobKind::Compare => {
            send(WorkerMsg::Compared {
                id: job.id,
                truth: truth.clone(),
                model: Box::new(model_view(study, &job.matrix)?),
            });
            return Ok(());
        }
        JobKind::Judge | JobKind::Fit => {}
    }
    // The compared model on the same truth, once; a model that fails here is just not
    // shown (the main model is what the job is for).
    let compare = job
        .compare
        .as_ref()
        .and_then(|m| model_view(study, m).ok())
        .map(Box::new);
    let done = |model: ModelView, report| WorkerMsg::Done {
        id: job.id,
        truth: truth.clone(),
        model: Box::new(model),
        report,
        seconds: t0.elapsed().as_secs_f64(),
        compare: compare.clone(),
    };
    // The edited matrix at once, so the charts answer the edit before any fitting.
    let start = model_view(study, &job.matrix);
    if job.kind == JobKind::Judge {
        send(done(start?, None));
        return Ok(());
    }
    let status = |phase, iteration, evaluations| FitStatus {
        phase,
        iteration,
        evaluations,
        seconds: t0.elapsed().as_secs_f64(),
    };
    let progress = |model: ModelView, status| WorkerMsg::Progress {
        id: job.id,
        truth: truth.clone(),
        model: Box::new(model),
        status,
        compare: compare.clone(),
    };
    if let Ok(model) = start {
        send(progress(model, status("start", 0, 0)));
    }
    let options = FitOptions {
        fidelity: job.fidelity,
        angle_weight: job.scene.fit.angle_weight,
        seed: 1,
    };
    // A better model is judged and shown; a heartbeat (no better model) moves the status.
    let mut on_progress = |p: &FitProgress| {
        let now = status(p.phase, p.iteration, p.evaluations);
        if !p.improved {
            send(WorkerMsg::Fitting {
                id: job.id,
                status: now,
            });
        } else if let Ok(model) = model_view(study, p.best) {
            send(progress(model, now));
        }
    };
    let report = study
        .fit(&job.matrix, &options, &mut on_progress, &job.cancel)
        .map_err(|e| format!("fit: {e}"))?;
    let model = model_view(study, &report.matrix)?;
    send(done(model, Some(Box::new(report))));
    Ok(())
}

/// The selection table, row by row, then the trade-off measurements.
fn run_selection(job: &Job, study: &Study, send: &dyn Fn(WorkerMsg)) -> Result<(), String> {
    let t0 = Instant::now();
    let selection = study
        .select_with_progress(
            job.fidelity,
            &job.cancel,
            &mut |row| {
                send(WorkerMsg::SelectRow {
                    id: job.id,
                    row: Box::new(row.clone()),
                });
            },
            &mut |_, fit| {
                send(WorkerMsg::Fitting {
                    id: job.id,
                    status: FitStatus {
                        phase: fit.phase,
                        iteration: fit.iteration,
                        evaluations: fit.evaluations,
                        seconds: t0.elapsed().as_secs_f64(),
                    },
                });
            },
        )
        .map_err(|e| format!("selection: {e}"))?;
    // The trade-off measures a cantilever beam's resolution and its load sampling, which a
    // mechanism and measured data do not have (the CLI's `tradeoff` refuses them too).
    let knobs = if study.case_form() == CaseForm::Tip && !study.is_measured() {
        crate::study::tradeoff::measure(study.scene(), &job.matrix, &job.cancel)
            .map_err(|e| format!("trade-off: {e}"))?
    } else {
        Vec::new()
    };
    send(WorkerMsg::SelectDone {
        id: job.id,
        selection: Box::new(selection),
        knobs,
    });
    Ok(())
}

/// Writes the job's model in the format the path's extension names (a cantilever's chain or
/// a mechanism's PRB mechanism, or its model file judged on the truth); over an existing
/// file only when `overwrite` (the UI asked the user).
fn export_file(
    job: &Job,
    study: &Study,
    path: &std::path::Path,
    density: Option<f64>,
    overwrite: bool,
) -> Result<(), String> {
    let (name, formats) = match study.case_form() {
        CaseForm::Tip => (
            "model",
            ".toml, .json, .xml or .mjcf (MuJoCo), .urdf, .sdf or .csv",
        ),
        CaseForm::Stage => ("mechanism", ".xml or .mjcf (MuJoCo), .toml or .json"),
    };
    let format =
        Format::from_path(path).ok_or_else(|| format!("{}: use {formats}", path.display()))?;
    let name = format!("{}-{name}", job.matrix.topology().to_lowercase());
    let text = study
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
