//! The charts' view of a study's truth ([`truth_view`]): the study's cases as they are, and
//! what only one kind of truth has, drawn as poses:
//!
//! - a cantilever's beam shapes are its beam's own solutions (the study's fast path,
//!   [`Study::baseline`]), each a pose of the one-flexure mechanism;
//! - a mechanism's are its flexures' beams shot under the wrenches the exact mechanism
//!   found ([`pose::exact`]);
//! - on a data scene (DESIGN §9) the beam is solved beside the data as the reports' "beam
//!   vs data" solves it: a cantilever's beam at every measured load, each by continuation
//!   from the unloaded beam (`eval::beam_against_data`), a mechanism's beam mechanism along
//!   the measured drives (`measured::beam_against_data`); each judged against the measured
//!   cases as a model would be, so the UI's "beam vs data" is the CLI's to the bit.

use std::time::Instant;

use crate::beam::{BeamSolver, Resolution, SolveError, TipPose};
use crate::cancel::CancelToken;
use crate::eval::{Baseline, CaseError};
use crate::mech::figures::{compare, JudgedCase};
use crate::mech::pose::{self, Pose};
use crate::mech::{exact, MechCase, MechError};
use crate::scene::data::DataTruth;
use crate::study::truth::tip_case;
use crate::study::Study;

use super::view::{per_path, MeasuredView, TruthView};

/// The job was cancelled while the beam beside the data was being solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Cancelled;

/// The charts' view of `study`'s truth, the beam beside a data scene's data solved at the
/// study's resolution. A beam that cannot follow the data is no failure (the data are the
/// truth; the beam is only shown beside them): the view says why instead.
///
/// # Errors
/// `cancelled` soon after `cancel` is set; the exact mechanism's shapes, when its beams
/// cannot be shot again (a resolution the solver refuses).
pub fn truth_view(study: &Study, cancel: &CancelToken) -> Result<TruthView, String> {
    let t0 = Instant::now();
    let resolution = study.sampling().resolution();
    let mechanism = study.mechanism().clone();
    let cases = study.truth().to_vec();
    let (poses, measured) = match (&study.scene().truth, study.baseline()) {
        (None, Some(baseline)) => (beam_poses(baseline), None),
        (None, None) => (
            pose::exact(&mechanism, study.resolution(), &cases)
                .map_err(|e| format!("the exact mechanism's shapes: {e}"))?,
            None,
        ),
        (Some(data), _) => {
            let (beam, poses) =
                beside(study, data, resolution, cancel).map_err(|Cancelled| "cancelled")?;
            let measured = MeasuredView {
                file: data.file.clone(),
                sha256: data.sha256.clone(),
                beam,
            };
            (poses, Some(measured))
        }
    };
    Ok(TruthView {
        form: study.case_form(),
        unloaded: pose::unloaded(&mechanism),
        decision: study.decision().cloned(),
        mechanism,
        cases,
        poses,
        measured,
        // Measured data has no stress, so no limit (and no solves spent looking).
        stroke_limits: study
            .scene()
            .truth
            .is_none()
            .then(|| study.stroke_limits())
            .flatten(),
        seconds: study.seconds() + t0.elapsed().as_secs_f64(),
    })
}

/// A cantilever's beam solutions, path by path, as poses of its one-flexure mechanism:
/// the centre line from the clamp, the stage (its tip) where the line ends.
fn beam_poses(baseline: &Baseline) -> Vec<Vec<Pose>> {
    let mut out = Vec::with_capacity(baseline.paths.len());
    let mut start = 0;
    for path in &baseline.paths {
        let end = (start + path.steps as usize).min(baseline.solutions.len());
        out.push(
            baseline.solutions[start..end]
                .iter()
                .map(|s| tip_pose(s.shape.iter().map(|p| [p.x, p.y]).collect(), s.tip))
                .collect(),
        );
        start = end;
    }
    out
}

/// A cantilever's pose: its centre line `line` (clamp first) ending at `tip`.
fn tip_pose(line: Vec<[f64; 2]>, tip: TipPose) -> Pose {
    Pose {
        flexures: vec![line],
        couplers: Vec::new(),
        stage_point: [tip.a, tip.b],
        stage: vec![[tip.a, tip.b]],
        roots: vec![[0.0, 0.0]],
    }
}

/// The scene's beam beside its data, judged against the measured cases, per path, and as
/// drawn; or why it cannot follow them.
type Beside = (Result<Vec<Vec<JudgedCase>>, String>, Vec<Vec<Pose>>);

/// The beam beside a data scene's measured cases: a cantilever's beam solved at every
/// measured load, a mechanism's beam mechanism along the measured drives.
fn beside(
    study: &Study,
    data: &DataTruth,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<Beside, Cancelled> {
    let truth = study.truth();
    let none = || vec![Vec::new(); truth.len()];
    if study.baseline().is_some() {
        return Ok(match beam_at_rows(study, data, resolution, cancel)? {
            Ok((cases, poses)) => (Ok(cases), poses),
            Err(why) => (Err(why), none()),
        });
    }
    let mechanism = study.mechanism();
    let beam = match exact::solver(mechanism, resolution)
        .and_then(|s| s.with_cancel(cancel).solve_all(mechanism))
    {
        Ok(b) => b,
        Err(MechError::Cancelled) => return Err(Cancelled),
        Err(e) => {
            let why = format!("the beam mechanism along the measured drives: {e}");
            return Ok((Err(why), none()));
        }
    };
    let (w, w_f) = study.weights();
    let judged = compare(&mechanism.drives, &beam, truth, w, w_f)
        .map(|j| per_path(j.cases, truth.len()))
        .map_err(|e| e.to_string());
    let poses = pose::exact(mechanism, resolution, &beam).unwrap_or_else(|_| none());
    Ok((judged, poses))
}

/// A cantilever's beam (its effects decided) solved at every measured load at
/// `resolution`, against the measured tips as `eval::beam_against_data` judges it; or why
/// it cannot reach a row.
#[allow(clippy::type_complexity)]
fn beam_at_rows(
    study: &Study,
    data: &DataTruth,
    resolution: Resolution,
    cancel: &CancelToken,
) -> Result<Result<(Vec<Vec<JudgedCase>>, Vec<Vec<Pose>>), String>, Cancelled> {
    let solver = match BeamSolver::new(study.scene().beam.model(), resolution) {
        Ok(s) => s,
        Err(e) => return Ok(Err(format!("the beam cannot be solved: {e}"))),
    };
    let mut cases = Vec::with_capacity(data.paths.len());
    let mut poses = Vec::with_capacity(data.paths.len());
    for (i, (path, truth)) in data.paths.iter().zip(study.truth()).enumerate() {
        let (mut judged, mut drawn) = (Vec::new(), Vec::new());
        for (row, t) in path.rows.iter().zip(truth) {
            let solved = match solver.solve_cancellable(row.load, cancel) {
                Ok(s) => s,
                Err(SolveError::Cancelled { .. }) => return Err(Cancelled),
                Err(e) => {
                    return Ok(Err(format!(
                        "the beam cannot reach line {} of {}: {e}",
                        row.line, data.file
                    )))
                }
            };
            // The data in the truth slot, the beam in the model's.
            let e = CaseError::new(row.load, row.tip, solved.tip);
            let model: MechCase = tip_case(
                t.fraction,
                row.load,
                solved.tip,
                solved.iterations,
                solved.stress,
            );
            judged.push(JudgedCase {
                path: i + 1,
                fraction: t.fraction,
                truth: t.clone(),
                model,
                pos_err: e.pos_err,
                ang_err: e.ang_err,
                force_err: 0.0,
                tip_err: 0.0,
            });
            let line = solved.shape.iter().map(|p| [p.x, p.y]).collect();
            drawn.push(tip_pose(line, solved.tip));
        }
        cases.push(judged);
        poses.push(drawn);
    }
    Ok(Ok((cases, poses)))
}
