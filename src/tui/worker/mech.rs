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
//!
//! A mechanism data scene (DESIGN §9 with §8) has its measured cases as the truth in place
//! of the exact mechanism ([`measured::truth`], as every command judges it), so the fit,
//! the selection and the export are the CLI's; the exact (beam) mechanism is solved along
//! the measured drives beside them ([`MechMeasuredView`]), drawn in grey and judged against
//! the data as the reports' "beam vs data" ([`measured::beam_against_data`]).

use std::sync::Arc;
use std::time::Instant;

use crate::beam::{Effects, Resolution};
use crate::fit::{Fidelity, FitOptions, FitReport};
use crate::mech::figures::{compare, Figures, Judgement};
use crate::mech::pose::{self, Pose};
use crate::mech::{exact, prb, MechCase};
use crate::prb::PrbMatrix;
use crate::scene::data::DataTruth;
use crate::scene::{Accuracy, BeamSpec, Mechanism, Scene};
use crate::study::{resolve_effects, EffectsDecision, Sampling, Study, PRB_TOL};

use super::{FitStatus, Job, JobKind, WorkerMsg};

/// The truth over a job's drives: the exact (beam) mechanism, or a data scene's measured
/// cases with the beam mechanism beside them; what the charts draw of it.
#[derive(Debug, Clone, PartialEq)]
pub struct MechBaselineView {
    /// The mechanism as solved (its flexures' effects decided; a data scene's drives are
    /// its measured paths).
    pub mechanism: Mechanism,
    /// Flexure 1's effects as solved.
    pub effects: Effects,
    /// How `auto` effects were decided, when they were.
    pub decision: Option<EffectsDecision>,
    /// Per drive, the truth's cases: the exact mechanism's, or the measured ones.
    pub cases: Vec<Vec<MechCase>>,
    /// Per drive, per case, the exact mechanism as drawn (on a data scene, the beam
    /// mechanism along the measured drives; no case when it cannot follow them).
    pub poses: Vec<Vec<Pose>>,
    /// A data scene's file and the beam mechanism beside the data; `None` when the truth
    /// is the beam.
    pub measured: Option<MechMeasuredView>,
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

    /// On a data scene, the beam mechanism judged against the measured cases as
    /// [`crate::mech::measured::beam_against_data`] judges it (the data in the truth slot, the beam in
    /// the model's), with the weights `w` and `w_f` (taken when drawn: an edit of a weight
    /// needs no new solve); or why it has none. `None` when the truth is the beam.
    pub fn beam_against_data(
        &self,
        angle_weight: f64,
        force_weight: f64,
    ) -> Option<Result<Judgement, String>> {
        let m = self.measured.as_ref()?;
        Some(match &m.beam {
            Ok(beam) => compare(
                &self.mechanism.drives,
                beam,
                &self.cases,
                angle_weight,
                force_weight,
            )
            .map_err(|e| e.to_string()),
            Err(why) => Err(why.clone()),
        })
    }
}

/// A mechanism data scene's truth as the charts and the status line show it (DESIGN §9).
#[derive(Debug, Clone, PartialEq)]
pub struct MechMeasuredView {
    /// The data file as the scene names it (sanitized when drawn).
    pub file: String,
    /// SHA-256 of its bytes, lowercase hex.
    pub sha256: String,
    /// The exact (beam) mechanism along the measured drives, per drive, or why it cannot
    /// follow them (no failure of the job: the data are the truth, the beam is only beside
    /// them).
    pub beam: Result<Vec<Vec<MechCase>>, String>,
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
    /// The figures of DESIGN §8.
    pub figures: Figures,
    /// Per drive, the PRB mechanism's cases.
    pub cases: Vec<Vec<MechCase>>,
    /// Per drive, per case, its errors.
    pub errors: Vec<Vec<CaseErrors>>,
    /// Per drive, per case, the PRB mechanism as drawn.
    pub poses: Vec<Vec<Pose>>,
}

/// The exact mechanism's cache key: everything its solve depends on (the targets too,
/// through `effects = "auto"`; a data scene's measurements).
#[derive(Debug, Clone, PartialEq)]
struct Key {
    mechanism: Mechanism,
    beam: BeamSpec,
    accuracy: Accuracy,
    fidelity: Fidelity,
    truth: Option<DataTruth>,
}

/// A solved exact mechanism and what it was solved from.
#[derive(Debug, Clone)]
pub(super) struct Solved {
    key: Key,
    view: Arc<MechBaselineView>,
    study: Arc<Study>,
}

/// The truth of `scene` (a mechanism scene) at `fidelity`'s resolution, with
/// `effects = "auto"` decided as for every scene ([`resolve_effects`]): the exact mechanism,
/// or a data scene's measured cases (`measured::truth`) with the beam mechanism solved
/// along the measured drives beside them.
pub fn mech_baseline_view(scene: &Scene, fidelity: Fidelity) -> Result<MechBaselineView, String> {
    view_of(&mech_study(scene, fidelity)?)
}

/// The study of `scene` (a mechanism scene) at `fidelity`, its `auto` effects decided as
/// every front end decides them.
fn mech_study(scene: &Scene, fidelity: Fidelity) -> Result<Study, String> {
    let cancel = crate::cancel::CancelToken::new();
    let (resolved, decision) = resolve_effects(scene, Resolution::default(), &cancel)
        .map_err(|e| format!("the beam effects cannot be decided: {e}"))?;
    Study::decided(
        resolved,
        decision,
        Sampling::Fidelity(fidelity),
        &cancel,
        &mut |_, _, _| {},
    )
    .map_err(|e| e.to_string())
}

/// What the charts draw of a mechanism study's truth.
fn view_of(study: &Study) -> Result<MechBaselineView, String> {
    let t0 = Instant::now();
    let resolution = study.sampling().resolution();
    let resolved = study.scene();
    let decision = study.decision().cloned();
    let mechanism = study.mechanism().clone();
    let cases = study.truth().to_vec();
    let (poses, measured) = match &resolved.truth {
        None => (
            pose::exact(&mechanism, resolution, &cases)
                .map_err(|e| format!("the exact mechanism's shapes: {e}"))?,
            None,
        ),
        Some(t) => {
            let beam = exact::solve(&mechanism, resolution)
                .map_err(|e| format!("the beam mechanism along the measured drives: {e}"));
            let poses = beam
                .as_ref()
                .ok()
                .and_then(|b| pose::exact(&mechanism, resolution, b).ok())
                .unwrap_or_else(|| vec![Vec::new(); mechanism.drives.len()]);
            let view = MechMeasuredView {
                file: t.file.clone(),
                sha256: t.sha256.clone(),
                beam,
            };
            (poses, Some(view))
        }
    };
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
        measured,
        seconds: study.seconds() + t0.elapsed().as_secs_f64(),
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
    let cases = prb::solve(m, matrix, PRB_TOL).map_err(|e| {
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
        if let Some(drive) = errors.get_mut(c.path.wrapping_sub(1)) {
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

/// The truth for `job`: the cached one when nothing it depends on changed.
fn solve_exact(
    job: &Job,
    cache: &mut Option<Solved>,
) -> Result<(Arc<MechBaselineView>, Arc<Study>), String> {
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
        truth: job.scene.truth.clone(),
    };
    if let Some(c) = cache.as_ref().filter(|c| c.key == key) {
        return Ok((c.view.clone(), c.study.clone()));
    }
    let study = Arc::new(mech_study(&job.scene, job.fidelity)?);
    let view = Arc::new(view_of(&study)?);
    *cache = Some(Solved {
        key,
        view: view.clone(),
        study: study.clone(),
    });
    Ok((view, study))
}

/// Runs a judge, fit or compare job on a mechanism scene.
pub(super) fn run_job(
    job: &Job,
    cache: &mut Option<Solved>,
    send: &dyn Fn(WorkerMsg),
) -> Result<(), String> {
    let t0 = Instant::now();
    let (exact, study) = solve_exact(job, cache)?;
    if let JobKind::Export {
        path,
        density,
        overwrite,
    } = &job.kind
    {
        let result = export_file(job, &study, path, *density, *overwrite);
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
        let selection = study
            .select(job.fidelity, &job.cancel, &mut |row| {
                send(WorkerMsg::MechSelectRow {
                    id: job.id,
                    row: Box::new(row.clone()),
                })
            })
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
    let report: FitReport = study
        .fit(&job.matrix, &options, &mut on_progress, &job.cancel)
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
    study: &Study,
    path: &std::path::Path,
    density: f64,
    overwrite: bool,
) -> Result<(), String> {
    use crate::export::mechanism_formats;
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
    let name = format!("{}-mechanism", job.matrix.topology().to_lowercase());
    let text = study
        .export(&name, &job.matrix, format, density)
        .map_err(|e| e.to_string())?;
    crate::io::files::write_atomic(path, text.as_bytes(), overwrite).map_err(super::write_error)
}
