//! The worker's jobs on a mechanism scene (DESIGN §8): the exact mechanism solved once per
//! scene (cached like the cantilever's baseline, re-solved only when the mechanism, the
//! beam, the targets or the fidelity change), then the PRB mechanism of the job's matrix
//! judged against it, or fitted ([`fit_mechanism`]) with the same progress messages as the
//! cantilever's fit.
//!
//! What the charts draw travels with the results: the exact cases and their drawn poses
//! ([`MechBaselineView`]), the model's cases, errors, figures and poses ([`MechModelView`]).
//! Every message carries the exact view its model was judged on, as the cantilever's carry
//! their baseline. A selection job fits the topology ladder on the mechanism
//! ([`select_mechanism`]) row by row; the trade-off is measured on cantilever scenes only.

use std::sync::Arc;
use std::time::Instant;

use crate::beam::Effects;
use crate::fit::mech::{fit_mechanism, MechFitReport, MECH_TOL};
use crate::fit::{Fidelity, FitOptions};
use crate::mech::figures::{compare, MechFigures};
use crate::mech::pose::{self, Pose};
use crate::mech::{exact, prb, MechCase};
use crate::prb::PrbMatrix;
use crate::scene::{Accuracy, BeamSpec, Mechanism, Scene};
use crate::select::{resolve_effects, select_mechanism, EffectsDecision};

use super::{FitStatus, Job, JobKind, WorkerMsg};

/// The exact (beam) mechanism over a job's drives: what the charts draw of it.
#[derive(Debug, Clone, PartialEq)]
pub struct MechBaselineView {
    /// The mechanism as solved (its flexures' effects decided).
    pub mechanism: Mechanism,
    /// Flexure 1's effects as solved.
    pub effects: Effects,
    /// How `auto` effects were decided, when they were.
    pub decision: Option<EffectsDecision>,
    /// Per drive, the exact mechanism's cases.
    pub cases: Vec<Vec<MechCase>>,
    /// Per drive, per case, the exact mechanism as drawn.
    pub poses: Vec<Vec<Pose>>,
    /// The unloaded mechanism as drawn.
    pub unloaded: Pose,
    /// How long the exact solve took.
    pub seconds: f64,
}

impl MechBaselineView {
    /// Cases over every drive.
    pub fn case_count(&self) -> usize {
        self.cases.iter().map(Vec::len).sum()
    }
}

/// One case's errors: stage position (units of flexure 1's `L`), stage angle (radians),
/// reaction (fraction of each prescribed coordinate's largest), as `eval` reports them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CaseErrors {
    /// Over the loaded position coordinates.
    pub pos: f64,
    /// When `dphi` is loaded.
    pub ang: f64,
    /// Over the prescribed coordinates.
    pub force: f64,
}

/// A PRB mechanism judged against the exact one: what the charts and the status line show.
#[derive(Debug, Clone, PartialEq)]
pub struct MechModelView {
    /// The matrix in every flexure.
    pub matrix: PrbMatrix,
    /// The seven figures of DESIGN §8.
    pub figures: MechFigures,
    /// Per drive, the PRB mechanism's cases.
    pub cases: Vec<Vec<MechCase>>,
    /// Per drive, per case, its errors.
    pub errors: Vec<Vec<CaseErrors>>,
    /// Per drive, per case, the PRB mechanism as drawn.
    pub poses: Vec<Vec<Pose>>,
}

/// The exact mechanism's cache key: everything its solve depends on (the targets too,
/// through `effects = "auto"`).
#[derive(Debug, Clone, PartialEq)]
struct Key {
    mechanism: Mechanism,
    beam: BeamSpec,
    accuracy: Accuracy,
    fidelity: Fidelity,
}

/// A solved exact mechanism and what it was solved from.
#[derive(Debug, Clone)]
pub(super) struct Solved {
    key: Key,
    view: Arc<MechBaselineView>,
}

/// The exact mechanism of `scene` (a mechanism scene) at `fidelity`'s resolution, with
/// `effects = "auto"` decided as for every scene ([`resolve_effects`]).
pub fn mech_baseline_view(scene: &Scene, fidelity: Fidelity) -> Result<MechBaselineView, String> {
    let t0 = Instant::now();
    let resolution = fidelity.resolution();
    let (resolved, decision) = resolve_effects(scene, resolution)
        .map_err(|e| format!("the beam effects cannot be decided: {e}"))?;
    let mechanism = resolved
        .mechanism
        .ok_or("internal error: a mechanism job on a cantilever scene")?;
    let cases = exact::solve(&mechanism, resolution)
        .map_err(|e| format!("the exact (beam) mechanism: {e}"))?;
    let poses = pose::exact(&mechanism, resolution, &cases)
        .map_err(|e| format!("the exact mechanism's shapes: {e}"))?;
    let effects = mechanism
        .flexures
        .first()
        .map_or(Effects::ALL, |f| f.beam.effects.resolve());
    Ok(MechBaselineView {
        unloaded: pose::unloaded(&mechanism),
        // A decision names the effects only where the flexures use them.
        decision: decision.filter(|d| d.effects == effects),
        effects,
        mechanism,
        cases,
        poses,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// `matrix` in every flexure of the exact view's mechanism, judged against it with `J`'s
/// weights `angle_weight` (`w`) and `force_weight` (`w_f`).
pub fn mech_model_view(
    exact: &MechBaselineView,
    matrix: &PrbMatrix,
    angle_weight: f64,
    force_weight: f64,
) -> Result<MechModelView, String> {
    let m = &exact.mechanism;
    let cases = prb::solve(m, matrix, MECH_TOL).map_err(|e| {
        format!(
            "the PRB mechanism ({}) cannot follow: {e}",
            matrix.topology()
        )
    })?;
    let e = compare(&m.drives, &cases, &exact.cases, angle_weight, force_weight)
        .map_err(|e| format!("internal error: {e}"))?;
    let mut errors: Vec<Vec<CaseErrors>> =
        cases.iter().map(|d| Vec::with_capacity(d.len())).collect();
    for c in &e.cases {
        if let Some(drive) = errors.get_mut(c.drive.wrapping_sub(1)) {
            drive.push(CaseErrors {
                pos: c.pos_err,
                ang: c.ang_err,
                force: c.force_err,
            });
        }
    }
    Ok(MechModelView {
        matrix: matrix.clone(),
        figures: e.figures,
        poses: pose::chains(m, matrix, &cases),
        cases,
        errors,
    })
}

/// The exact mechanism for `job`: the cached one when nothing it depends on changed.
fn solve_exact(job: &Job, cache: &mut Option<Solved>) -> Result<Arc<MechBaselineView>, String> {
    let mechanism = job
        .scene
        .mechanism
        .clone()
        .ok_or("internal error: a mechanism job on a cantilever scene")?;
    let key = Key {
        mechanism,
        beam: job.scene.beam,
        accuracy: job.scene.accuracy,
        fidelity: job.fidelity,
    };
    if let Some(c) = cache.as_ref().filter(|c| c.key == key) {
        return Ok(c.view.clone());
    }
    let view = Arc::new(mech_baseline_view(&job.scene, job.fidelity)?);
    *cache = Some(Solved {
        key,
        view: view.clone(),
    });
    Ok(view)
}

/// Runs a judge, fit or compare job on a mechanism scene.
pub(super) fn run_job(
    job: &Job,
    cache: &mut Option<Solved>,
    send: &dyn Fn(WorkerMsg),
) -> Result<(), String> {
    let t0 = Instant::now();
    let exact = solve_exact(job, cache)?;
    if let JobKind::Export {
        path,
        density,
        overwrite,
    } = &job.kind
    {
        let result = export_file(job, &exact, path, *density, *overwrite);
        send(WorkerMsg::Exported {
            id: job.id,
            path: path.clone(),
            result,
        });
        return Ok(());
    }
    if job.cancel.is_cancelled() {
        return Ok(());
    }
    if job.kind == JobKind::Select {
        let selection = select_mechanism(
            &job.scene,
            &exact.mechanism,
            &exact.cases,
            job.fidelity,
            &job.cancel,
            &mut |row| {
                send(WorkerMsg::MechSelectRow {
                    id: job.id,
                    row: Box::new(row.clone()),
                })
            },
        )
        .map_err(|e| format!("selection: {e}"))?;
        send(WorkerMsg::MechSelectDone {
            id: job.id,
            selection: Box::new(selection),
        });
        return Ok(());
    }
    let (w, w_f) = (job.scene.fit.angle_weight, job.scene.fit.force_weight);
    if job.kind == JobKind::Compare {
        let model = mech_model_view(&exact, &job.matrix, w, w_f)?;
        send(WorkerMsg::MechCompared {
            id: job.id,
            exact,
            model: Box::new(model),
        });
        return Ok(());
    }
    // The compared model on the same exact mechanism, once; one that cannot follow is just
    // not shown.
    let compare = job
        .compare
        .as_ref()
        .and_then(|m| mech_model_view(&exact, m, w, w_f).ok())
        .map(Box::new);
    let start = mech_model_view(&exact, &job.matrix, w, w_f);
    if job.kind == JobKind::Judge {
        send(WorkerMsg::MechDone {
            id: job.id,
            exact: exact.clone(),
            model: Box::new(start?),
            report: None,
            seconds: t0.elapsed().as_secs_f64(),
            compare,
        });
        return Ok(());
    }
    let progress = |model: MechModelView, status: FitStatus| WorkerMsg::MechProgress {
        id: job.id,
        exact: exact.clone(),
        model: Box::new(model),
        status,
        compare: compare.clone(),
    };
    // The edited matrix at once, so the charts answer the edit before any fitting.
    if let Ok(model) = start {
        let status = FitStatus {
            iteration: 0,
            evaluations: 0,
            seconds: t0.elapsed().as_secs_f64(),
        };
        send(progress(model, status));
    }
    let options = FitOptions {
        fidelity: job.fidelity,
        angle_weight: w,
        seed: 1,
    };
    let mut on_progress = |p: &crate::fit::FitProgress| {
        if let Ok(model) = mech_model_view(&exact, p.best, w, w_f) {
            let status = FitStatus {
                iteration: p.iteration,
                evaluations: p.evaluations,
                seconds: t0.elapsed().as_secs_f64(),
            };
            send(progress(model, status));
        }
    };
    let report: MechFitReport = fit_mechanism(
        &exact.mechanism,
        &exact.cases,
        &job.matrix,
        &options,
        w_f,
        &job.scene.accuracy,
        &mut on_progress,
        &job.cancel,
    )
    .map_err(|e| format!("fit: {e}"))?;
    let model = mech_model_view(&exact, &report.matrix, w, w_f)?;
    send(WorkerMsg::MechDone {
        id: job.id,
        exact,
        model: Box::new(model),
        report: Some(Box::new(report)),
        seconds: t0.elapsed().as_secs_f64(),
        compare,
    });
    Ok(())
}

/// Writes the job's PRB mechanism (MJCF) or its model judged on the mechanism (TOML, JSON),
/// in the format the path's extension names; over an existing file only when `overwrite`.
fn export_file(
    job: &Job,
    exact: &MechBaselineView,
    path: &std::path::Path,
    density: f64,
    overwrite: bool,
) -> Result<(), String> {
    use crate::export::{export_mechanism, mechanism_formats, MechExportInput};
    use crate::format::Format;
    let supported = || {
        mechanism_formats()
            .iter()
            .map(|f| f.name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let format = Format::from_path(path).ok_or_else(|| {
        format!(
            "{}: name a mechanism export .xml or .mjcf (MuJoCo), .toml or .json ({})",
            path.display(),
            supported()
        )
    })?;
    // The scene as solved: its flexures' effects decided.
    let mut scene = (*job.scene).clone();
    scene.mechanism = Some(exact.mechanism.clone());
    let input = MechExportInput {
        name: format!("{}-mechanism", job.matrix.topology().to_lowercase()),
        matrix: &job.matrix,
        scene: &scene,
        mechanism: &exact.mechanism,
        fidelity: job.fidelity,
        density,
    };
    let text = export_mechanism(&input, format).map_err(|e| e.to_string())?;
    crate::io::files::write_atomic(path, text.as_bytes(), overwrite).map_err(super::write_error)
}
