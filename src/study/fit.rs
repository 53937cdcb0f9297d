//! The fit on a study (DESIGN §4, §8): the free cells of a matrix that make the PRB model
//! follow the truth, minimising the scene's `J`, by the search of [`crate::fit`] (starts,
//! swarm, polish, presets, progress, cancel) on one of two targets: a cantilever's
//! ([`CantileverTarget`]: three residuals per load case from the chain's own statics along
//! each load path) or a mechanism's (one residual per stage coordinate per case from the PRB
//! mechanism along each drive). Both are the same `J`, both give their residuals' exact
//! derivatives with respect to the matrix's cells for the polish (the chain's or the
//! mechanism's equilibrium, by the implicit function theorem), and both stop their polish
//! once `J` is a negligible part of the scene's targets ([`target_objective`]).
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
    objective_of, polish, push_residual, search, CancelToken, CantileverTarget, Fidelity,
    FitOptions, FitProgress, FitReport, Found, SearchError, StopReason, Target, PENALTY,
};
use crate::mech::figures::{
    compare, reaction_divisor, reaction_scales, signed_errors, CompareError,
};
use crate::mech::{prb, MechCase};
use crate::prb::{Column, PrbMatrix, CELLS_PER_ROW};
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
    /// The cap of a frequency's residual, `PENALTY sqrt(w_omega)` (a ratio error of
    /// `sqrt(N)`, [`PENALTY`]).
    cap: f64,
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
            cap: PENALTY * w.sqrt(),
            target_objective: w * study.scene().accuracy.max_freq_err.powi(2),
            last_statics: std::cell::RefCell::new((Vec::new(), Vec::new())),
        })
    }
}

impl Target for ModesTarget<'_> {
    fn len(&self) -> usize {
        self.statics.len() + self.beam.len()
    }

    fn missed_all(&self, out: &mut Vec<f64>) {
        self.statics.missed_all(out);
        out.extend(std::iter::repeat_n(self.cap, self.beam.len()));
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

    /// No cells: the frequencies' residuals are differenced.
    fn residuals_with_cells(
        &self,
        matrix: &PrbMatrix,
        out: &mut Vec<f64>,
        _cells: Option<&mut Vec<f64>>,
    ) -> bool {
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
            out.push(model.get(i).map_or(self.cap, |m| {
                (self.scale * (m / b - 1.0)).clamp(-self.cap, self.cap)
            }));
        }
        false
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
    /// The caps of those residuals: [`PENALTY`] times the `sqrt` of each weight.
    loaded_cap: [f64; 3],
    prescribed_cap: f64,
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
            loaded_cap: [PENALTY, PENALTY, PENALTY * angle_weight.sqrt()],
            prescribed_cap: PENALTY * force_weight.sqrt(),
            cases,
            target_objective,
        })
    }
}

impl MechanismTarget<'_> {
    /// The caps of one case's three residuals on `drive`.
    fn caps(&self, drive: &Drive) -> [f64; 3] {
        std::array::from_fn(|c| {
            if drive.coordinates[c].is_prescribed() {
                self.prescribed_cap
            } else {
                self.loaded_cap[c]
            }
        })
    }
}

impl Target for MechanismTarget<'_> {
    fn len(&self) -> usize {
        3 * self.cases
    }

    fn missed_all(&self, out: &mut Vec<f64>) {
        out.clear();
        for (drive, exact) in self.mechanism.drives.iter().zip(self.exact) {
            for _ in exact {
                out.extend_from_slice(&self.caps(drive));
            }
        }
    }

    /// Errors at `fraction` of the nearest accuracy target: `fraction^2` times the `J` of
    /// errors exactly on target.
    fn objective_floor(&self, fraction: f64) -> f64 {
        fraction * fraction * self.target_objective
    }

    /// With `cells`, each case's sensitivity through the PRB mechanism's equilibrium
    /// ([`crate::mech::sensitivity`]), scaled as its residuals are. A case whose sensitivity
    /// cannot be had (a singular Jacobian: a trial at a critical point) gets 0 there, which
    /// only slows the polish.
    fn residuals_with_cells(
        &self,
        matrix: &PrbMatrix,
        out: &mut Vec<f64>,
        mut cells: Option<&mut Vec<f64>>,
    ) -> bool {
        out.clear();
        let width = CELLS_PER_ROW * matrix.rows().len();
        if let Some(c) = cells.as_deref_mut() {
            c.clear();
        }
        let solver = prb::solver(self.mechanism, matrix, PRB_TOL)
            .without_stress()
            .for_trials();
        for (i, (drive, exact)) in self.mechanism.drives.iter().zip(self.exact).enumerate() {
            match solver.solve_path(&self.mechanism.drive_path(drive), i + 1) {
                Ok(cases) if cases.len() == exact.len() => {
                    for (p, e) in cases.iter().zip(exact) {
                        let errors = signed_errors(drive, p, e, &self.reaction_scale);
                        let sensitivity = cells
                            .as_ref()
                            .and_then(|_| solver.case_sensitivity(p, width));
                        for (c, err) in errors.iter().enumerate() {
                            let prescribed = drive.coordinates[c].is_prescribed();
                            let (scale, cap) = if prescribed {
                                (self.prescribed_scale, self.prescribed_cap)
                            } else {
                                (self.loaded_scale[c], self.loaded_cap[c])
                            };
                            // The error's derivative: the pose's, or the reaction's over
                            // its scale (as `signed_errors` divides it).
                            let (row, over) = match &sensitivity {
                                Some(s) if prescribed => (
                                    Some(&s.stage_load[c * width..(c + 1) * width]),
                                    reaction_divisor(&self.reaction_scale, c),
                                ),
                                Some(s) => (Some(&s.stage[c * width..(c + 1) * width]), 1.0),
                                None => (None, 1.0),
                            };
                            let r = err * scale;
                            let scales = (scale, over);
                            push_residual(out, cells.as_deref_mut(), r, row, scales, cap, width);
                        }
                    }
                }
                _ => {
                    let caps = self.caps(drive);
                    for _ in exact {
                        out.extend_from_slice(&caps);
                    }
                    if let Some(cells) = cells.as_deref_mut() {
                        cells.extend(std::iter::repeat_n(0.0, 3 * width * exact.len()));
                    }
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::Resolution;
    use crate::mech::exact;
    use crate::scene::{Attach, BeamSpec, Coordinate, Drive, Flexure};
    use Coordinate::{Loaded, Prescribed};

    /// `d r / d p` of a target's residuals (its cells' derivatives chained through the
    /// parameterisation) against central differences of its residuals, at `matrix`'s
    /// parameters; also checks the residuals given with the cells are the plain ones.
    /// Returns, over the parameters, the largest difference in a column over that column's
    /// largest derivative; every column must move the residuals (by more than 1e-3).
    fn target_jacobian_error(target: &dyn Target, matrix: &PrbMatrix, h: f64) -> f64 {
        let param = crate::fit::Parameterisation::new(matrix).unwrap();
        let p0 = param.encode(matrix);
        let (mut r, mut plain, mut cells) = (Vec::new(), Vec::new(), Vec::new());
        let at = param.decode(&p0).unwrap();
        assert!(target.residuals_with_cells(&at, &mut r, Some(&mut cells)));
        target.residuals(&at, &mut plain);
        // The same to rounding: a cantilever's second evaluation of the model is
        // warm-started from its first.
        assert_eq!(r.len(), plain.len());
        for (a, b) in r.iter().zip(&plain) {
            assert!((a - b).abs() <= 1e-14, "{a} against {b}");
        }
        let mut analytic = nalgebra::DMatrix::zeros(0, 0);
        param.chain_rule(&p0, &cells, r.len(), &mut analytic);
        let mut error = 0.0_f64;
        for j in 0..param.len() {
            let (mut up, mut down) = (p0.clone(), p0.clone());
            up[j] += h;
            down[j] -= h;
            let (mut ru, mut rd) = (Vec::new(), Vec::new());
            target.residuals(&param.decode(&up).unwrap(), &mut ru);
            target.residuals(&param.decode(&down).unwrap(), &mut rd);
            let (mut worst, mut largest) = (0.0_f64, 0.0_f64);
            for i in 0..r.len() {
                let fd = (ru[i] - rd[i]) / (2.0 * h);
                worst = worst.max((analytic[(i, j)] - fd).abs());
                largest = largest.max(fd.abs());
            }
            assert!(largest > 1e-3, "parameter {j} moves nothing: {largest}");
            error = error.max(worst / largest);
        }
        error
    }

    /// Both targets' exact Jacobians against differences of their residuals, column by
    /// column, scaling and chain rule included; the extension spring is soft enough (k_ex
    /// 2e-4 E A0 / L) that its column counts. Central differences err by `h^2` times the
    /// residuals' third derivative (O(1) here: 1e-12 at the cantilever's h = 1e-6, 1e-8 at
    /// the mechanism's h = 1e-4) plus the equilibria's own error over `h`: the chain's
    /// Newton stops on a step of 1e-13 and the mechanism's on residuals of `PRB_TOL` = 1e-8,
    /// but both converge quadratically, so their last iterate is far closer (measured:
    /// 9e-10 and 1.4e-8 of the columns). 1e-6 and 1e-5 leave that margin; a wrong scale (a
    /// reaction not divided by its scale, the angle weight left out) is off by a factor, a
    /// missed term by O(0.1) or more of its column.
    #[test]
    fn targets_give_the_jacobian_of_their_residuals() {
        let scene = crate::scene::Scene::builtin();
        let study =
            Study::as_given(&scene, crate::study::Sampling::Fidelity(Fidelity::Draft)).unwrap();
        let su =
            PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,2e-4; 0.15,2.58,inf").unwrap();
        let cantilever = CantileverTarget::new(study.baseline().unwrap(), 0.7);
        let error = target_jacobian_error(&cantilever, &su, 1e-6);
        assert!(error < 1e-6, "cantilever: {error}");

        let m = mixed_stage();
        let exact = exact::solve(&m, Resolution::with_tol(1e-10)).unwrap();
        let target = MechanismTarget::new(&m, &exact, 0.7, 2.5, &Accuracy::default()).unwrap();
        let error = target_jacobian_error(&target, &su, 1e-4);
        assert!(error < 1e-5, "mechanism: {error}");
    }

    /// Two clamped flexures carrying one stage, driven with loaded and prescribed
    /// coordinates.
    fn mixed_stage() -> Mechanism {
        let flexure = |y: f64| Flexure {
            root: [0.0, y],
            angle: 0.0,
            attach: Attach::Clamped,
            beam: BeamSpec::unit_elastica(0.01),
        };
        Mechanism {
            flexures: vec![flexure(0.3), flexure(-0.3)],
            stage_point: [1.0, 0.0],
            drives: vec![
                Drive::proportional([Loaded(1.0), Prescribed(0.2), Loaded(0.3)], 3),
                Drive::proportional([Loaded(-2.0), Loaded(4.0), Loaded(0.5)], 2),
            ],
        }
    }

    /// A mechanism case's sensitivity to the matrix's cells, chained to the fit's
    /// parameters, against central differences of the mechanism solved again at nudged
    /// parameters: the stage pose of loaded coordinates and the reactions of prescribed
    /// ones (a prescribed angle's moment included), on a clamped, a pinned and a linked
    /// flexure carrying one stage, with revolute and prismatic joints. Solved at tol 1e-13,
    /// the differences (h = 1e-5) err by about `h^2` (1e-10) plus 1e-13 / h (1e-8) relative
    /// to the largest derivative, so 1e-5 tells a right derivative from a wrong one (a
    /// missed term is O(0.1)).
    #[test]
    fn mechanism_sensitivities_match_differences() {
        let flexure = |root: [f64; 2], angle: f64, attach, thickness| Flexure {
            root,
            angle,
            attach,
            beam: BeamSpec::unit_elastica(thickness),
        };
        let m = Mechanism {
            flexures: vec![
                flexure([0.0, 0.3], 0.0, Attach::Clamped, 0.05),
                flexure([0.0, -0.3], 0.2, Attach::Pinned, 0.04),
                flexure(
                    [1.2, 1.0],
                    -std::f64::consts::FRAC_PI_2,
                    Attach::Link { to: [1.0, 0.2] },
                    0.05,
                ),
            ],
            stage_point: [1.0, 0.0],
            drives: vec![
                Drive::proportional([Loaded(0.8), Prescribed(0.15), Loaded(0.3)], 3),
                Drive::proportional([Prescribed(0.05), Loaded(0.5), Prescribed(0.03)], 2),
            ],
        };
        let matrix =
            PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,0.05; 0.40,2.99,inf; 0.15,2.58,0.08")
                .unwrap();
        let param = crate::fit::Parameterisation::new(&matrix).unwrap();
        let p0 = param.encode(&matrix);
        let width = CELLS_PER_ROW * matrix.rows().len();
        let mut checked = 0;
        for (d, drive) in m.drives.iter().enumerate() {
            let path = m.drive_path(drive);
            let solve = |p: &nalgebra::DVector<f64>| {
                let decoded = param.decode(p).unwrap();
                let solver = prb::solver(&m, &decoded, 1e-13).without_stress();
                let cases = solver.solve_path(&path, d + 1).unwrap();
                (solver, cases)
            };
            let (solver, cases) = solve(&p0);
            for (k, case) in cases.iter().enumerate() {
                let s = solver.case_sensitivity(case, width).unwrap();
                let rows: Vec<f64> = s.stage.iter().chain(&s.stage_load).copied().collect();
                let mut analytic = nalgebra::DMatrix::zeros(0, 0);
                param.chain_rule(&p0, &rows, 6, &mut analytic);
                let h = 1e-5;
                for j in 0..param.len() {
                    let (mut up, mut down) = (p0.clone(), p0.clone());
                    up[j] += h;
                    down[j] -= h;
                    let (a, b) = (&solve(&up).1[k], &solve(&down).1[k]);
                    let fd: Vec<f64> = (0..3)
                        .map(|c| (a.stage[c] - b.stage[c]) / (2.0 * h))
                        .chain((0..3).map(|c| (a.stage_load[c] - b.stage_load[c]) / (2.0 * h)))
                        .collect();
                    let scale = fd.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
                    for (r, f) in fd.iter().enumerate() {
                        assert!(
                            (analytic[(r, j)] - f).abs() <= 1e-5 * scale,
                            "drive {d}, case {k}, output {r}, parameter {j}: {} against {f}",
                            analytic[(r, j)]
                        );
                    }
                    checked += 1;
                }
                // What moves: the loaded coordinates' pose, the prescribed ones' reactions;
                // the rest is given.
                for (c, coordinate) in drive.coordinates.iter().enumerate() {
                    let (moves, given) = if coordinate.is_prescribed() {
                        (c + 3, c)
                    } else {
                        (c, c + 3)
                    };
                    assert!(
                        analytic.row(moves).amax() > 1e-4,
                        "drive {d} coordinate {c}"
                    );
                    assert_eq!(analytic.row(given).amax(), 0.0);
                }
            }
        }
        assert_eq!(checked, 5 * param.len());
    }

    #[test]
    fn residuals_square_to_the_figures_objective() {
        let m = mixed_stage();
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
