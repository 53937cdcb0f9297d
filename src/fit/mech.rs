//! Fitting on a mechanism scene (DESIGN §8): one PRB matrix, scaled to every flexure,
//! fitted so that the PRB mechanism follows the exact one along the scene's drives.
//!
//! The residuals are one per stage coordinate per case ([`signed_errors`]): a loaded
//! coordinate's motion error (`sqrt(w)` times it for the angle), a prescribed one's reaction
//! error over its reaction scale times `sqrt(w_f)`, all over `sqrt(n)`; their squares sum to
//! the scene's `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`. A drive a trial model cannot
//! follow costs [`PENALTY`] for every residual of its cases. The search is the cantilever's
//! ([`super::search`]): the same starts, swarm, polish, presets, progress and cancel.

use std::time::Instant;

use crate::mech::figures::{compare, signed_errors, CompareError, MechFigures};
use crate::mech::{prb, MechCase, MechError};
use crate::prb::PrbMatrix;
use crate::scene::{Accuracy, Mechanism};

use super::{search, CancelToken, FitError, FitOptions, FitProgress, FitReport, Target, PENALTY};

/// The PRB mechanism's Newton tolerance in trials and in the final figures (the exact
/// mechanism's own is the scene's resolution; 1e-8 is far below any model error).
pub const MECH_TOL: f64 = 1e-8;

/// A mechanism's drives as the fit's target.
pub struct MechTarget<'a> {
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

impl<'a> MechTarget<'a> {
    /// The target of `mechanism` whose exact solution is `exact` (one path per drive), with
    /// `J`'s angle and force weights.
    pub fn new(
        mechanism: &'a Mechanism,
        exact: &'a [Vec<MechCase>],
        angle_weight: f64,
        force_weight: f64,
        accuracy: &Accuracy,
    ) -> Result<MechTarget<'a>, CompareError> {
        let coordinates = || {
            mechanism
                .drives
                .iter()
                .flat_map(|d| d.coordinates.iter().enumerate())
        };
        let mut target_objective = f64::INFINITY;
        if coordinates().any(|(c, k)| c < 2 && !k.is_prescribed()) {
            target_objective = target_objective.min(accuracy.max_pos_err.powi(2));
        }
        if coordinates().any(|(c, k)| c == 2 && !k.is_prescribed()) && angle_weight > 0.0 {
            target_objective = target_objective.min(angle_weight * accuracy.max_ang_err.powi(2));
        }
        if coordinates().any(|(_, k)| k.is_prescribed()) && force_weight > 0.0 {
            target_objective = target_objective.min(force_weight * accuracy.max_force_err.powi(2));
        }
        let reaction_scale = compare(&mechanism.drives, exact, exact, 1.0, 1.0)?.reaction_scale;
        let cases: usize = exact.iter().map(Vec::len).sum();
        let per_case = 1.0 / (cases.max(1) as f64).sqrt();
        Ok(MechTarget {
            mechanism,
            exact,
            reaction_scale,
            loaded_scale: [per_case, per_case, angle_weight.sqrt() * per_case],
            prescribed_scale: force_weight.sqrt() * per_case,
            cases,
            target_objective: if target_objective.is_finite() {
                target_objective
            } else {
                0.0
            },
        })
    }
}

impl Target for MechTarget<'_> {
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
        let solver = prb::solver(self.mechanism, matrix, MECH_TOL).for_trials();
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

/// What a mechanism fit found.
pub type MechFitReport = FitReport<MechFigures>;

/// Why a mechanism fit has no model to report.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MechFitError {
    /// The search could not start.
    #[error(transparent)]
    Fit(#[from] FitError),
    /// The exact solution does not pair with the mechanism's drives.
    #[error(transparent)]
    Compare(#[from] CompareError),
    /// Even the best matrix found cannot follow the mechanism.
    #[error("no fitted model follows the mechanism: {0}")]
    NoFeasibleModel(MechError),
}

/// Fits the free cells of `start` so that the PRB mechanism follows `exact`, the exact
/// mechanism's cases along every drive of `mechanism`; `force_weight` is `J`'s `w_f`, and
/// `accuracy` the scene's targets (the polish stops once what it gains is a small part of
/// them: [`Target::objective_floor`]).
#[allow(clippy::too_many_arguments)] // the fit's inputs, each its own thing
pub fn fit_mechanism(
    mechanism: &Mechanism,
    exact: &[Vec<MechCase>],
    start: &PrbMatrix,
    options: &FitOptions,
    force_weight: f64,
    accuracy: &Accuracy,
    progress: &mut dyn FnMut(&FitProgress),
    cancel: &CancelToken,
) -> Result<MechFitReport, MechFitError> {
    let t0 = Instant::now();
    let target = MechTarget::new(
        mechanism,
        exact,
        options.angle_weight,
        force_weight,
        accuracy,
    )?;
    let found = search(&target, start, options, progress, cancel)?;
    let cases =
        prb::solve(mechanism, &found.matrix, MECH_TOL).map_err(MechFitError::NoFeasibleModel)?;
    let e = compare(
        &mechanism.drives,
        &cases,
        exact,
        options.angle_weight,
        force_weight,
    )?;
    Ok(found.report(e.figures, t0, options.fidelity))
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
            effects: EffectsChoice::Fixed(Effects::NONE),
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
        let target = MechTarget::new(&m, &exact, w, w_f, &Accuracy::default()).unwrap();
        let mut r = Vec::new();
        target.residuals(&su, &mut r);
        assert_eq!(r.len(), target.len());
        let j: f64 = r.iter().map(|v| v * v).sum();
        let prb_cases = prb::solve(&m, &su, MECH_TOL).unwrap();
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
        };
        let target = MechTarget::new(&m, &exact, w, w_f, &accuracy).unwrap();
        let floor = target.objective_floor(1e-3);
        assert!((floor - 1e-6 * 6.25e-5).abs() < 1e-18, "{floor}");
        // With nothing prescribed and the angle unweighted, only position counts: 0.1^2.
        let mut loaded = m.clone();
        loaded.drives[0].coordinates[1] = Loaded(0.5);
        let exact = exact::solve(&loaded, Resolution::with_tol(1e-10)).unwrap();
        let target = MechTarget::new(&loaded, &exact, 0.0, w_f, &accuracy).unwrap();
        assert!((target.objective_floor(1e-3) - 1e-6 * 1e-2).abs() < 1e-18);
    }
}
