//! Judging a PRB model against the beam (DESIGN §4): per load case, the tip position error
//! `e_pos = |(a, b)_PRB - (a, b)_beam|` (units of L) and angle error
//! `e_ang = phi_PRB - phi_beam` (radians); over a scene their RMS and maxima and the objective
//! `J = mean(e_pos^2 + w e_ang^2)`.
//!
//! A scene's baseline (every beam solve) is computed once into a [`Baseline`] and reused for
//! every model judged on it.

use std::time::Instant;

use serde::Serialize;

use crate::beam::{BeamModel, BeamSolution, BeamSolver, Load, Resolution, SolveError, TipPose};
use crate::prb::{PrbError, PrbMatrix, PrbSolver};
use crate::scene::{LoadPath, Scene};

/// The beam's answer for every load case of a scene.
#[derive(Debug, Clone)]
pub struct Baseline {
    pub model: BeamModel,
    pub paths: Vec<LoadPath>,
    /// One per case, path by path.
    pub solutions: Vec<BeamSolution>,
    pub resolution: Resolution,
    /// Wall-clock time of the solves.
    pub seconds: f64,
}

/// Which load path failed, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("load path {path} of the scene: {source}")]
pub struct BaselineError {
    /// 1-based.
    pub path: usize,
    pub source: SolveError,
}

impl Baseline {
    /// Solves every case of the scene's beam.
    pub fn compute(scene: &Scene, resolution: Resolution) -> Result<Baseline, BaselineError> {
        Baseline::for_model(scene.beam.model(), &scene.loads, resolution)
    }

    /// Solves every case of `paths` for a given beam.
    pub fn for_model(
        model: BeamModel,
        paths: &[LoadPath],
        resolution: Resolution,
    ) -> Result<Baseline, BaselineError> {
        let t0 = Instant::now();
        let solver = BeamSolver::new(model, resolution)
            .map_err(|source| BaselineError { path: 0, source })?;
        let mut solutions = Vec::new();
        for (i, p) in paths.iter().enumerate() {
            let sols = solver
                .solve_path(p.end, p.steps)
                .map_err(|source| BaselineError {
                    path: i + 1,
                    source,
                })?;
            solutions.extend(sols);
        }
        Ok(Baseline {
            model,
            paths: paths.to_vec(),
            solutions,
            resolution,
            seconds: t0.elapsed().as_secs_f64(),
        })
    }

    pub fn case_count(&self) -> usize {
        self.solutions.len()
    }
}

/// One load case: both tips and the errors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CaseError {
    pub load: Load,
    pub beam: TipPose,
    pub prb: TipPose,
    pub pos_err: f64,
    pub ang_err: f64,
}

impl CaseError {
    pub fn new(load: Load, beam: TipPose, prb: TipPose) -> CaseError {
        CaseError {
            load,
            beam,
            prb,
            pos_err: (prb.a - beam.a).hypot(prb.b - beam.b),
            ang_err: prb.phi - beam.phi,
        }
    }
}

/// The five error figures of DESIGN §4.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorFigures {
    pub rms_pos_err: f64,
    pub max_pos_err: f64,
    pub rms_ang_err: f64,
    pub max_ang_err: f64,
    /// `J = mean(e_pos^2 + w e_ang^2)`.
    pub objective: f64,
}

impl ErrorFigures {
    pub fn from_cases(cases: &[CaseError], angle_weight: f64) -> ErrorFigures {
        let n = cases.len().max(1) as f64;
        let (mut sp, mut sa, mut mp, mut ma) = (0.0, 0.0, 0.0_f64, 0.0_f64);
        for c in cases {
            sp += c.pos_err * c.pos_err;
            sa += c.ang_err * c.ang_err;
            mp = mp.max(c.pos_err);
            ma = ma.max(c.ang_err.abs());
        }
        ErrorFigures {
            rms_pos_err: (sp / n).sqrt(),
            max_pos_err: mp,
            rms_ang_err: (sa / n).sqrt(),
            max_ang_err: ma,
            objective: (sp + angle_weight * sa) / n,
        }
    }

    /// Whether the figures meet a scene's targets.
    pub fn meets(&self, accuracy: &crate::scene::Accuracy) -> bool {
        self.max_pos_err <= accuracy.max_pos_err && self.max_ang_err <= accuracy.max_ang_err
    }
}

/// A model judged on a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    pub cases: Vec<CaseError>,
    pub figures: ErrorFigures,
}

/// The PRB model fails to follow one of the scene's load paths.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("load path {path}: {source}")]
pub struct EvalError {
    /// 1-based.
    pub path: usize,
    pub source: PrbError,
}

/// Judges `matrix` against the baseline.
pub fn evaluate(
    matrix: &PrbMatrix,
    baseline: &Baseline,
    angle_weight: f64,
) -> Result<Evaluation, EvalError> {
    let solver = PrbSolver::new(matrix, baseline.model.axial_compliance());
    let mut cases = Vec::with_capacity(baseline.case_count());
    let mut beam = baseline.solutions.iter();
    for (i, path) in baseline.paths.iter().enumerate() {
        solver
            .solve_path_with(path.end, path.steps, |sol| {
                let b = beam.next().expect("one beam solution per case");
                cases.push(CaseError::new(sol.load, b.tip, sol.tip));
            })
            .map_err(|source| EvalError {
                path: i + 1,
                source,
            })?;
    }
    let figures = ErrorFigures::from_cases(&cases, angle_weight);
    Ok(Evaluation { cases, figures })
}
