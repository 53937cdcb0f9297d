//! The fit on a study (DESIGN §4, §8): the free cells of a matrix that make the PRB model
//! follow the truth, minimising the scene's `J`, by the search of [`crate::fit`] (starts,
//! swarm, polish, presets, progress, cancel) on one of two targets: a cantilever's
//! ([`CantileverTarget`]: three residuals per load case from the chain's own statics along
//! each load path) or a mechanism's (one residual per stage coordinate per case from the PRB
//! mechanism along each drive). Both are the same `J`, and both stop their polish once `J` is
//! a negligible part of the scene's targets ([`target_objective`]).
//!
//! The mechanism's residuals: a loaded coordinate's motion error (`sqrt(w)` times it for the
//! angle), a prescribed one's reaction error over its reaction scale times `sqrt(w_f)`, all
//! over `sqrt(n)`; their squares sum to `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`. A
//! drive a trial model cannot follow costs [`PENALTY`] for every residual of its cases.
//!
//! A dynamic fit (`[fit] modes = N`, DESIGN §10) wraps either target in a `ModesTarget`,
//! which appends the first N frequencies' relative errors (about the unloaded equilibrium,
//! [`Study::prb_frequencies`]) weighted by `frequency_weight`, and frees the mus not pinned
//! with `!`; it runs in three stages (statics, mus, a joint polish: `staged`). One code path for every kind of scene: the study gives the frequencies.

use std::time::Instant;

use crate::fit::{
    objective_of, polish, search, CancelToken, CantileverTarget, Fidelity, FitOptions, FitProgress,
    FitReport, Found, SearchError, StopReason, Target, PENALTY,
};
use crate::mech::figures::{compare, reaction_scales, signed_errors, CompareError};
use crate::mech::{prb, MechCase};
use crate::prb::{Column, PrbMatrix};
use crate::scene::{Accuracy, Drive, Mechanism};

use super::{JudgeError, Study, PRB_TOL};

/// Why a fit has no model to report.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The search could not start.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// The truth does not pair with the scene's paths (a bug if ever seen).
    #[error(transparent)]
    Compare(#[from] CompareError),
    /// Even the best matrix found cannot follow the scene.
    #[error("no fitted model follows every load of the scene: {0}")]
    NoFeasibleModel(JudgeError),
}

/// `J` of errors exactly at the accuracy targets, per kind of error the paths have: the
/// smallest of `max_pos_err^2` (some position loaded), `w max_ang_err^2` (the angle loaded)
/// and `w_f max_force_err^2` (some coordinate prescribed); 0 when none counts.
pub fn target_objective(
    drives: &[Drive],
    angle_weight: f64,
    force_weight: f64,
    accuracy: &Accuracy,
) -> f64 {
    let coordinates = || drives.iter().flat_map(|d| d.coordinates.iter().enumerate());
    let mut j = f64::INFINITY;
    if coordinates().any(|(c, k)| c < 2 && !k.is_prescribed()) {
        j = j.min(accuracy.max_pos_err.powi(2));
    }
    if coordinates().any(|(c, k)| c == 2 && !k.is_prescribed()) && angle_weight > 0.0 {
        j = j.min(angle_weight * accuracy.max_ang_err.powi(2));
    }
    if coordinates().any(|(_, k)| k.is_prescribed()) && force_weight > 0.0 {
        j = j.min(force_weight * accuracy.max_force_err.powi(2));
    }
    if j.is_finite() {
        j
    } else {
        0.0
    }
}

impl Study {
    /// Fits the free cells of `start` so the PRB model follows the truth (`options`' angle
    /// weight and the scene's force weight in `J`), reporting progress and stopping soon
    /// after `cancel`; the report's figures are the fitted matrix judged on the truth.
    pub fn fit(
        &self,
        start: &PrbMatrix,
        options: &FitOptions,
        progress: &mut dyn FnMut(&FitProgress),
        cancel: &CancelToken,
    ) -> Result<FitReport, FitError> {
        let t0 = Instant::now();
        options.validate()?;
        let (w, w_f) = (options.angle_weight, self.scene().fit.force_weight);
        let floor_j = target_objective(self.drives(), w, w_f, &self.scene().accuracy);
        let cantilever;
        let mechanism;
        let statics: &dyn Target = match self.baseline() {
            Some(baseline) => {
                cantilever = CantileverTarget::new(baseline, w).with_target_objective(floor_j);
                &cantilever
            }
            None => {
                mechanism = MechanismTarget::new(
                    self.mechanism(),
                    self.truth(),
                    w,
                    w_f,
                    &self.scene().accuracy,
                )?;
                &mechanism
            }
        };
        let found = match ModesTarget::new(self, statics) {
            Some(target) => staged(&target, statics, start, options, progress, cancel)?,
            None => search(statics, start, options, progress, cancel)?,
        };
        let judged = self
            .judge_weighted(&found.matrix, w)
            .map_err(FitError::NoFeasibleModel)?;
        Ok(found.report(judged.figures, t0, options.fidelity))
    }
}

/// A dynamic fit in three stages, each of which costs little where one joint search over
/// every cell cost much (the frequencies' residuals made the swarm and the scouts wander in
/// the statics cells, each trial a full statics solve: 4.25x the statics fit's evaluations):
/// 1. the statics fit alone (the statics target, the fidelity's whole search);
/// 2. the mus alone against the dynamic target, the statics cells pinned (their residuals are
///    cached, so each trial costs one frequency computation, microseconds);
/// 3. a polish from there with every cell the start frees, which trades a little statics
///    for the frequencies where the two meet, to draft's tolerances (its start is already
///    both stages' optimum: on the built-in scene's 3R it ends at the joint search's figures
///    to the digits `tests/dynamic_fit.rs` prints, in half the full polish's evaluations).
///
/// The report counts all three stages' iterations and evaluations, and `J` of the start on
/// the dynamic target.
fn staged(
    target: &ModesTarget<'_>,
    statics: &dyn Target,
    start: &PrbMatrix,
    options: &FitOptions,
    progress: &mut dyn FnMut(&FitProgress),
    cancel: &CancelToken,
) -> Result<Found, SearchError> {
    let start_objective = objective_of(target, start, start).unwrap_or(f64::INFINITY);
    let first = search(statics, start, options, progress, cancel)?;
    let mut spent = (first.iterations, first.evaluations);
    let mut mus_only = first.matrix.with_explicit_mu();
    for i in 0..mus_only.len() {
        for column in Column::STATICS {
            mus_only.set_free(i, column, false);
        }
    }
    let (matrix, stop) = if first.stop == StopReason::Cancelled {
        (first.matrix, StopReason::Cancelled)
    } else {
        let second = search(target, &mus_only, options, progress, cancel)?;
        spent = (spent.0 + second.iterations, spent.1 + second.evaluations);
        let mut joint = second.matrix;
        for (i, row) in start.rows().iter().enumerate() {
            for column in Column::STATICS {
                joint.set_free(i, column, row.is_free(column));
            }
        }
        if second.stop == StopReason::Cancelled {
            (joint, StopReason::Cancelled)
        } else {
            // Draft's tolerances with the fit's own iteration limit: the polish starts where
            // the statics are optimal and the frequencies matched, and only balances the two.
            let mut short = Fidelity::Draft.lm();
            short.max_iterations = options.fidelity.lm().max_iterations;
            let third = polish(target, &joint, options, short, progress, cancel)?;
            spent = (spent.0 + third.iterations, spent.1 + third.evaluations);
            // Not improving on stage 2's point means stage 2's point is the optimum.
            let stop = match third.stop {
                StopReason::CouldNotImprove | StopReason::NothingToFit => StopReason::Converged,
                other => other,
            };
            (third.matrix, stop)
        }
    };
    let improved = objective_of(target, start, &matrix).is_some_and(|j| j < start_objective);
    let (matrix, stop) = match (improved, stop) {
        (true, _) | (false, StopReason::Cancelled) => (matrix, stop),
        (false, _) => (start.clone(), StopReason::CouldNotImprove),
    };
    Ok(Found {
        matrix,
        start_objective,
        iterations: spent.0,
        evaluations: spent.1,
        stop,
    })
}

/// A dynamic fit's target (DESIGN §10, `[fit] modes = N`): the statics' residuals and, after
/// them, `sqrt(w_omega / N) (Omega_PRB,i / Omega_beam,i - 1)` for the first N frequencies
/// about the unloaded equilibrium (a missing or unstable one costs [`PENALTY`]), so that
/// `J` gains `w_omega mean_i (Omega_PRB,i / Omega_beam,i - 1)^2`. It frees the mus.
struct ModesTarget<'a> {
    statics: &'a dyn Target,
    study: &'a Study,
    /// The truth's first N `Omega`.
    beam: Vec<f64>,
    body: crate::prb::TipBody,
    /// `sqrt(w_omega / N)`.
    scale: f64,
    /// `J` of frequency errors exactly at `max_freq_err`: `w_omega max_freq_err^2`.
    target_objective: f64,
    /// The last statics residuals and the statics cells (gamma, k_theta, k_ex per row) they
    /// are of: the polish's finite differences in a mu change only the frequencies, so they
    /// reuse them instead of solving every load case again.
    last_statics: std::cell::RefCell<(Vec<f64>, Vec<f64>)>,
}

impl<'a> ModesTarget<'a> {
    /// The dynamic target over `statics` when the study's scene asks for modes (and so has
    /// the truth's frequencies); `None` for a statics-only fit.
    fn new(study: &'a Study, statics: &'a dyn Target) -> Option<ModesTarget<'a>> {
        let n = study.scene().fit.modes as usize;
        let truth = study.truth_modes()?;
        if n == 0 || truth.omega.len() < n {
            return None;
        }
        let w = study.scene().fit.frequency_weight;
        Some(ModesTarget {
            statics,
            study,
            beam: truth.omega[..n].to_vec(),
            body: truth.body,
            scale: (w / n as f64).sqrt(),
            target_objective: w * study.scene().accuracy.max_freq_err.powi(2),
            last_statics: std::cell::RefCell::new((Vec::new(), Vec::new())),
        })
    }
}

impl Target for ModesTarget<'_> {
    fn len(&self) -> usize {
        self.statics.len() + self.beam.len()
    }

    /// The nearer of the statics' floor and frequency errors at `fraction` of
    /// `max_freq_err`.
    fn objective_floor(&self, fraction: f64) -> f64 {
        let own = fraction * fraction * self.target_objective;
        let statics = self.statics.objective_floor(fraction);
        if statics > 0.0 {
            statics.min(own)
        } else {
            own
        }
    }

    fn residuals(&self, matrix: &PrbMatrix, out: &mut Vec<f64>) {
        let key: Vec<f64> = matrix
            .rows()
            .iter()
            .flat_map(|r| [r.gamma, r.k_theta, r.k_ex])
            .collect();
        {
            let mut last = self.last_statics.borrow_mut();
            if last.0 == key {
                out.clear();
                out.extend_from_slice(&last.1);
            } else {
                self.statics.residuals(matrix, out);
                *last = (key, out.clone());
            }
        }
        let model = self
            .study
            .prb_frequencies(matrix, self.body)
            .unwrap_or_default();
        for (i, b) in self.beam.iter().enumerate() {
            out.push(model.get(i).map_or(PENALTY, |m| {
                (self.scale * (m / b - 1.0)).clamp(-PENALTY, PENALTY)
            }));
        }
    }

    fn masses(&self) -> bool {
        true
    }
}

/// A mechanism's drives as the fit's target.
struct MechanismTarget<'a> {
    mechanism: &'a Mechanism,
    exact: &'a [Vec<MechCase>],
    reaction_scale: [Option<f64>; 3],
    /// `sqrt` of the weights of the three coordinates' errors as loaded (position, position,
    /// angle) and prescribed (reaction), over `sqrt(n)`.
    loaded_scale: [f64; 3],
    prescribed_scale: f64,
    cases: usize,
    /// `J` of errors exactly at the accuracy targets, per kind of error the scene has: the
    /// smallest of `max_pos_err^2` (some position loaded), `w max_ang_err^2` (the angle
    /// loaded) and `w_f max_force_err^2` (some coordinate prescribed).
    target_objective: f64,
}

impl<'a> MechanismTarget<'a> {
    /// The target of `mechanism` whose truth is `exact` (one path per drive), with `J`'s
    /// angle and force weights.
    fn new(
        mechanism: &'a Mechanism,
        exact: &'a [Vec<MechCase>],
        angle_weight: f64,
        force_weight: f64,
        accuracy: &Accuracy,
    ) -> Result<MechanismTarget<'a>, CompareError> {
        let target_objective =
            target_objective(&mechanism.drives, angle_weight, force_weight, accuracy);
        // Checks that the truth pairs with the drives, as every judgement will.
        compare(&mechanism.drives, exact, exact, 1.0, 1.0)?;
        let reaction_scale = reaction_scales(&mechanism.drives, exact);
        let cases: usize = exact.iter().map(Vec::len).sum();
        let per_case = 1.0 / (cases.max(1) as f64).sqrt();
        Ok(MechanismTarget {
            mechanism,
            exact,
            reaction_scale,
            loaded_scale: [per_case, per_case, angle_weight.sqrt() * per_case],
            prescribed_scale: force_weight.sqrt() * per_case,
            cases,
            target_objective,
        })
    }
}

impl Target for MechanismTarget<'_> {
    fn len(&self) -> usize {
        3 * self.cases
    }

    /// Errors at `fraction` of the nearest accuracy target: `fraction^2` times the `J` of
    /// errors exactly on target.
    fn objective_floor(&self, fraction: f64) -> f64 {
        fraction * fraction * self.target_objective
    }

    fn residuals(&self, matrix: &PrbMatrix, out: &mut Vec<f64>) {
        out.clear();
        let solver = prb::solver(self.mechanism, matrix, PRB_TOL)
            .without_stress()
            .for_trials();
        for (i, (drive, exact)) in self.mechanism.drives.iter().zip(self.exact).enumerate() {
            match solver.solve_path(&self.mechanism.drive_path(drive), i + 1) {
                Ok(cases) if cases.len() == exact.len() => {
                    for (p, e) in cases.iter().zip(exact) {
                        let errors = signed_errors(drive, p, e, &self.reaction_scale);
                        for (c, err) in errors.iter().enumerate() {
                            let scale = if drive.coordinates[c].is_prescribed() {
                                self.prescribed_scale
                            } else {
                                self.loaded_scale[c]
                            };
                            out.push((err * scale).clamp(-PENALTY, PENALTY));
                        }
                    }
                }
                _ => out.extend(std::iter::repeat_n(PENALTY, 3 * exact.len())),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{Effects, Resolution};
    use crate::mech::exact;
    use crate::scene::{Attach, BeamSpec, Coordinate, Drive, EffectsChoice, Flexure};
    use Coordinate::{Loaded, Prescribed};

    /// The residuals' squares sum to the `J` that `compare` reports, on a mechanism with
    /// loaded and prescribed coordinates in two drives: the fit minimises what eval judges.
    #[test]
    fn residuals_square_to_the_figures_objective() {
        let beam = BeamSpec {
            length: 1.0,
            width: 1.0,
            thickness: 0.01,
            youngs_modulus: 12e6,
            poisson_ratio: 0.3,
            shear_coefficient: None,
            density: None,
            effects: EffectsChoice::Fixed(Effects::NONE),
            allowable_stress: None,
        };
        let flexure = |y: f64| Flexure {
            root: [0.0, y],
            angle: 0.0,
            attach: Attach::Clamped,
            beam,
        };
        let m = Mechanism {
            flexures: vec![flexure(0.3), flexure(-0.3)],
            stage_point: [1.0, 0.0],
            drives: vec![
                Drive::proportional([Loaded(1.0), Prescribed(0.2), Loaded(0.3)], 3),
                Drive::proportional([Loaded(-2.0), Loaded(4.0), Loaded(0.5)], 2),
            ],
        };
        let exact = exact::solve(&m, Resolution::with_tol(1e-10)).unwrap();
        let su =
            PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
        let (w, w_f) = (0.7, 2.5);
        let target = MechanismTarget::new(&m, &exact, w, w_f, &Accuracy::default()).unwrap();
        let mut r = Vec::new();
        target.residuals(&su, &mut r);
        assert_eq!(r.len(), target.len());
        let j: f64 = r.iter().map(|v| v * v).sum();
        let prb_cases = prb::solve(&m, &su, PRB_TOL).unwrap();
        let figures = compare(&m.drives, &prb_cases, &exact, w, w_f)
            .unwrap()
            .figures;
        assert!(j > 0.0);
        assert!(
            (j - figures.objective).abs() <= 1e-12 * figures.objective,
            "{j} vs {figures:?}"
        );

        // The floor: the nearest target's J. Position and angle are loaded, one coordinate
        // is prescribed: min(0.1^2, 0.7 * 0.02^2, 2.5 * 0.005^2) = 6.25e-5.
        let accuracy = Accuracy {
            max_pos_err: 0.1,
            max_ang_err: 0.02,
            max_force_err: 0.005,
            ..Accuracy::default()
        };
        let target = MechanismTarget::new(&m, &exact, w, w_f, &accuracy).unwrap();
        let floor = target.objective_floor(1e-3);
        assert!((floor - 1e-6 * 6.25e-5).abs() < 1e-18, "{floor}");
        // With nothing prescribed and the angle unweighted, only position counts: 0.1^2.
        let mut loaded = m.clone();
        loaded.drives[0].coordinates[1] = Loaded(0.5);
        let exact = exact::solve(&loaded, Resolution::with_tol(1e-10)).unwrap();
        let target = MechanismTarget::new(&loaded, &exact, 0.0, w_f, &accuracy).unwrap();
        assert!((target.objective_floor(1e-3) - 1e-6 * 1e-2).abs() < 1e-18);
    }
}
