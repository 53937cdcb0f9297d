//! Judging a PRB model against the beam (DESIGN §4): per load case, the tip position error
//! `e_pos = |(a, b)_PRB - (a, b)_beam|` (units of L) and angle error
//! `e_ang = phi_PRB - phi_beam` (radians); over a scene their RMS and maxima and the objective
//! `J = mean(e_pos^2 + w e_ang^2)`.
//!
//! A scene's baseline (every beam solve) is computed once into a [`Baseline`] and reused for
//! every model judged on it.

use std::ops::ControlFlow;
use std::time::Instant;

use serde::Serialize;

use crate::beam::{
    BeamModel, BeamSolution, BeamSolver, Convergence, Load, Resolution, SolveError, TipPose,
};
use crate::cancel::CancelToken;
use crate::mech::figures::Figures;
use crate::prb::{PrbCase, PrbError, PrbMatrix, PrbSolver, WarmStart};
use crate::scene::data::DataTruth;
use crate::scene::{LoadPath, Scene};

/// The beam's answer for every load case of a scene.
#[derive(Debug, Clone)]
pub struct Baseline {
    /// The beam that was solved (effects decided).
    pub model: BeamModel,
    /// The load paths, as sampled.
    pub paths: Vec<LoadPath>,
    /// One per case, path by path.
    pub solutions: Vec<BeamSolution>,
    /// The solver's resolution.
    pub resolution: Resolution,
    /// Wall-clock time of the solves.
    pub seconds: f64,
    /// A data scene's truth (DESIGN §9): each path's measured loads, which the PRB model
    /// follows row by row (`solutions` then holds the measured tips); `None` for the beam.
    pub measured: Option<Vec<Vec<Load>>>,
}

/// Which load path failed, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("load path {path} of the scene: {source}")]
pub struct BaselineError {
    /// 1-based.
    pub path: usize,
    /// Why the beam failed there.
    pub source: SolveError,
}

impl Baseline {
    /// Solves every case of the scene's beam; a data scene's baseline is its data
    /// ([`Baseline::from_data`]).
    pub fn compute(scene: &Scene, resolution: Resolution) -> Result<Baseline, BaselineError> {
        if let Some(truth) = &scene.truth {
            return Ok(Baseline::from_data(scene.beam.model(), truth));
        }
        Baseline::for_model(scene.beam.model(), &scene.loads, resolution)
    }

    /// Solves every case of `paths` for a given beam.
    pub fn for_model(
        model: BeamModel,
        paths: &[LoadPath],
        resolution: Resolution,
    ) -> Result<Baseline, BaselineError> {
        Baseline::solve(
            model,
            paths,
            resolution,
            &CancelToken::new(),
            &mut |_, _| {},
        )
    }

    /// As [`Baseline::for_model`], stopping with [`SolveError::Cancelled`] soon after
    /// `cancel` is set (the beam checks it every continuation step), and telling
    /// `on_path(paths_done, cases_done)` after each path (for progress).
    pub fn solve(
        model: BeamModel,
        paths: &[LoadPath],
        resolution: Resolution,
        cancel: &CancelToken,
        on_path: &mut dyn FnMut(usize, usize),
    ) -> Result<Baseline, BaselineError> {
        Baseline::solve_keeping(model, paths, resolution, cancel, on_path, true, None)
    }

    /// [`Baseline::solve`], keeping the cases' shapes or not (`shapes`: a caller that reads
    /// only tips and stresses, like the effects decision comparing models, spares the
    /// memory), and with `narrow`, the same paths' cases solved by the narrow beam, where a
    /// plane-strain model takes its plate fractions from them
    /// ([`BeamSolver::solve_path_on_narrow`]).
    pub fn solve_keeping(
        model: BeamModel,
        paths: &[LoadPath],
        resolution: Resolution,
        cancel: &CancelToken,
        on_path: &mut dyn FnMut(usize, usize),
        shapes: bool,
        narrow: Option<&[BeamSolution]>,
    ) -> Result<Baseline, BaselineError> {
        let t0 = Instant::now();
        let solver = BeamSolver::new(model, resolution)
            .map_err(|source| BaselineError { path: 0, source })?;
        let solver = if shapes {
            solver
        } else {
            solver.without_shapes()
        };
        let mut solutions = Vec::new();
        for (i, p) in paths.iter().enumerate() {
            let first = solutions.len();
            let sols = match narrow {
                Some(n) => {
                    let cases = n.get(first..first + p.steps.max(1) as usize).unwrap_or(&[]);
                    solver.solve_path_on_narrow(p.end, p.steps, cases, cancel)
                }
                None => solver.solve_path_cancellable(p.end, p.steps, cancel),
            };
            let sols = sols.map_err(|source| BaselineError {
                path: i + 1,
                source,
            })?;
            solutions.extend(sols);
            on_path(i + 1, solutions.len());
        }
        Ok(Baseline {
            model,
            paths: paths.to_vec(),
            solutions,
            resolution,
            seconds: t0.elapsed().as_secs_f64(),
            measured: None,
        })
    }

    /// The baseline of a data scene (DESIGN §9): the measured tips are the truth, and `model`
    /// (the scene's nominal beam, effects decided) only gives the PRB model its axial
    /// compliance. Each measured row becomes a solution with the measured tip; its root
    /// moment is the statics of the measured pose (`beta + a alpha_y - b alpha_x`), and it
    /// has no shape.
    pub fn from_data(model: BeamModel, truth: &DataTruth) -> Baseline {
        let solutions = truth
            .paths
            .iter()
            .flat_map(|p| &p.rows)
            .map(|r| BeamSolution {
                load: r.load,
                tip: r.tip,
                root_moment: r.load.beta + r.tip.a * r.load.alpha_y - r.tip.b * r.load.alpha_x,
                shape: Vec::new(),
                iterations: 0,
                continuation_steps: 0,
                rk_steps: 0,
                convergence: Convergence {
                    residual: 0.0,
                    last_update: 0.0,
                    stability: 1.0,
                },
                stress: None,
            })
            .collect();
        let paths = truth
            .paths
            .iter()
            .filter_map(|p| {
                p.rows.last().map(|last| LoadPath {
                    end: last.load,
                    steps: u32::try_from(p.rows.len()).unwrap_or(u32::MAX),
                })
            })
            .collect();
        Baseline {
            model,
            paths,
            solutions,
            resolution: Resolution::default(),
            seconds: 0.0,
            measured: Some(truth.loads()),
        }
    }

    /// Whether the truth is measured data rather than the beam.
    pub fn is_measured(&self) -> bool {
        self.measured.is_some()
    }

    /// Load cases in all.
    pub fn case_count(&self) -> usize {
        self.solutions.len()
    }

    /// Follows every load path with the PRB `solver` (continuation from the unloaded chain,
    /// as the beam was followed), handing each case to `visit` together with the beam's
    /// solution for the same load. This is the one loop that pairs PRB cases with beam cases:
    /// evaluation, the fit's residuals, the UI's charts and the CSV export all go through it.
    ///
    /// A path the model cannot follow is handed to `on_failure` with the beam solutions of
    /// the cases it did not reach and why: `Continue` goes on with the next path, `Break`
    /// stops with that path's error.
    pub fn follow(
        &self,
        solver: &PrbSolver,
        visit: impl FnMut(&BeamSolution, &PrbCase<'_>),
        on_failure: impl FnMut(&[BeamSolution], &EvalError) -> ControlFlow<()>,
    ) -> Result<(), EvalError> {
        self.follow_warm(solver, None, visit, on_failure)
    }

    /// As [`Baseline::follow`], with a warm start: given `warm` (one [`WarmStart`] per
    /// path and a spare's storage, grown as needed) and whether to use it, each path's cases are first tried from
    /// the equilibria `warm` holds, and `warm` then holds this solver's (a fit's next trial
    /// model starts from them). The equilibria reported are the same; only the cost differs.
    pub fn follow_warm(
        &self,
        solver: &PrbSolver,
        mut warm: Option<(&mut Vec<WarmStart>, bool)>,
        mut visit: impl FnMut(&BeamSolution, &PrbCase<'_>),
        mut on_failure: impl FnMut(&[BeamSolution], &EvalError) -> ControlFlow<()>,
    ) -> Result<(), EvalError> {
        let paths = self.paths.len();
        // The storage of the warm start each path replaces, for the next path's: kept after
        // the paths' own (one more entry), so that the next call's first path reuses the
        // last path's instead of growing new storage.
        let mut spare = match warm.as_mut() {
            Some((starts, _)) => {
                starts.resize_with(paths + 1, WarmStart::default);
                std::mem::take(&mut starts[paths])
            }
            None => WarmStart::default(),
        };
        let dofs = solver.dof_count();
        let mut start = 0;
        for (i, path) in self.paths.iter().enumerate() {
            let end = (start + path.steps as usize).min(self.solutions.len());
            let beam = &self.solutions[start..end];
            start = end;
            let mut reached = 0;
            let mut fresh = std::mem::take(&mut spare);
            fresh.clear(dofs);
            let mut on_case = |case: PrbCase<'_>| {
                if let Some(b) = beam.get(reached) {
                    visit(b, &case);
                }
                reached += 1;
                fresh.push(&case);
            };
            let rows = self
                .measured
                .as_ref()
                .and_then(|m| m.get(i))
                .map(Vec::as_slice);
            let outcome = match &mut warm {
                Some((starts, true)) => {
                    solver.solve_warm_with(path.end, path.steps, rows, &starts[i], &mut on_case)
                }
                _ => match rows {
                    Some(rows) => solver.solve_rows_with(rows, &mut on_case),
                    None => solver.solve_path_with(path.end, path.steps, &mut on_case),
                },
            };
            if let Some((starts, _)) = warm.as_mut() {
                spare = std::mem::replace(&mut starts[i], fresh);
            }
            if let Err(source) = outcome {
                let missed = &beam[reached.min(beam.len())..];
                let error = EvalError {
                    path: i + 1,
                    source,
                };
                if on_failure(missed, &error).is_break() {
                    return Err(error);
                }
            }
        }
        if let Some((starts, _)) = warm.as_mut() {
            starts[paths] = spare;
        }
        Ok(())
    }
}

/// The scene's own beam judged against a data scene's measurements (DESIGN §9: how far the
/// ideal beam is from the specimen): per row, the beam's tip under the row's load (solved by
/// continuation from the unloaded beam) against the measured tip, as [`CaseError`]s with the
/// data in the `beam` slot and the beam theory in the `prb` slot, and their figures. `None`
/// for a scene without data, and for a mechanism's (see `mech::measured::beam_against_data`).
pub fn beam_against_data(
    scene: &Scene,
    resolution: Resolution,
) -> Result<Option<Evaluation>, BaselineError> {
    let Some(truth) = scene.truth.as_ref().filter(|_| scene.mechanism.is_none()) else {
        return Ok(None);
    };
    beam_against_rows(&scene.beam, truth, 1.0, resolution, scene.fit.angle_weight).map(Some)
}

/// [`beam_against_data`] for `beam` (which may differ from the nominal beam the rows were
/// converted with): the rows' nondimensional loads are multiplied by `load_scale`, the
/// nominal `E I0` over this beam's, so that they stay the same physical loads.
pub(crate) fn beam_against_rows(
    beam: &crate::scene::BeamSpec,
    truth: &DataTruth,
    load_scale: f64,
    resolution: Resolution,
    angle_weight: f64,
) -> Result<Evaluation, BaselineError> {
    let solver = BeamSolver::new(beam.model(), resolution)
        .map_err(|source| BaselineError { path: 0, source })?;
    let mut cases = Vec::with_capacity(truth.row_count());
    for (i, path) in truth.paths.iter().enumerate() {
        for row in &path.rows {
            let load = row.load.scaled(load_scale);
            let solved = solver.solve(load).map_err(|source| BaselineError {
                path: i + 1,
                source,
            })?;
            cases.push(CaseError::new(row.load, row.tip, solved.tip));
        }
    }
    let figures = tip_figures(&cases, angle_weight);
    Ok(Evaluation { cases, figures })
}

/// One load case: both tips and the errors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CaseError {
    /// The load.
    pub load: Load,
    /// The beam's tip.
    pub beam: TipPose,
    /// The PRB model's tip.
    pub prb: TipPose,
    /// `|(a, b)_PRB - (a, b)_beam|`, units of L.
    pub pos_err: f64,
    /// `phi_PRB - phi_beam`, radians.
    pub ang_err: f64,
}

impl CaseError {
    /// The errors of the PRB tip against the beam tip.
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

/// A model judged on a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Per case, path by path.
    pub cases: Vec<CaseError>,
    /// Over all cases.
    pub figures: Figures,
}

/// The PRB model fails to follow one of the scene's load paths.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("load path {path}: {source}")]
pub struct EvalError {
    /// 1-based.
    pub path: usize,
    /// Why the model failed there.
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
    baseline.follow(
        &solver,
        |beam, prb| cases.push(CaseError::new(prb.load, beam.tip, prb.tip)),
        |_, _| ControlFlow::Break(()),
    )?;
    let figures = tip_figures(&cases, angle_weight);
    Ok(Evaluation { cases, figures })
}

/// §4's figures of tip errors, `J = mean(e_pos^2 + w e_ang^2)`: a cantilever's, with no
/// reaction or flexure tip figures.
pub fn tip_figures(cases: &[CaseError], angle_weight: f64) -> Figures {
    Figures::from_errors(
        cases.iter().map(|c| [c.pos_err, c.ang_err, 0.0, 0.0]),
        (angle_weight, 0.0),
        false,
        false,
    )
}
