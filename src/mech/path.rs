//! A mechanism along a drive path, as a problem of the continuation driver
//! ([`crate::continuation`]): the state is the unknown vector (flexure wrenches, chains'
//! joint coordinates, the stage's loaded coordinates), the corrector damped Newton on the
//! analytic Jacobian, the critical-point indicator that Jacobian's determinant sign (and, at
//! a stall, its equilibrated pivot spread). See the parent module for the honesty rules.

use crate::beam::Load;
use crate::continuation::{
    self, Corrected, Crossing, Effort, Growth, Halving, History, Limits, PathProblem, Predictor,
    Stop, Tally, TestOrder,
};
use crate::linalg::lu_solve;
use crate::scene::{Coordinate, DrivePath, Mechanism};

use super::solve::{FlexEval, FlexureModel, Kind, MechSolver};
use super::system::equilibrate;
use super::{FlexureCase, MechCase, MechError, SolvedState};

mod chord;
use chord::{Chord, Reference};

/// An equilibrated Jacobian (see [`equilibrate`]) of the unloaded pose whose smallest pivot
/// is this small next to its largest is singular. The unloaded flexures are straight, so a
/// structurally singular pose (an inextensible flexure pushed along its axis, a 1R that
/// cannot keep its tip angle, a stage coordinate nothing holds, inextensible flexures in
/// parallel) has exact zeros where the motion or force is free, and its smallest pivot is
/// nought or rounding (`n eps`, below 1e-14 for any mechanism's size). A stiff but
/// legitimate one's smallest pivot is its stiffest direction's compliance over its softest:
/// three stretchy flexures in parallel bring the axial over the bending compliance, about
/// `(t / L)^2 / 2` (5.6e-6 at slenderness 100, 5.6e-8 at 1000, 5.6e-13 at the slenderness
/// limit 1e6), and no scaling of rows and columns removes it, because it is the mechanism's
/// own. The threshold sits between the two, so no legitimate stage is refused however stiff
/// its stretch (tests/mech_parallel.rs); a singular one is then told apart as a self-stress
/// ([`MechError::Indeterminate`]) or a free motion ([`MechError::Immobile`]) by its null
/// vector.
const SINGULAR: f64 = 1e-13;
/// Continuation that stalls where the equilibrated Jacobian's pivot spread has fallen below
/// this fraction of the unloaded mechanism's has reached a limit point: the spread falls
/// like the distance to the fold, and Newton's basin at a fixed drive fraction with it (the
/// Su 3R parallel stage at `(Ax, Ay, B) = (-10, 6, 3)` stalls at 0.7% of its unloaded spread;
/// the solved points of that design grid, beam and PRB, stay above 13%).
const NEAR_CRITICAL: f64 = 0.02;
/// Rejected continuation sub-steps one case of a drive may have. A healthy case has none
/// or a few; a steep one more (the fixed-guided segment's last ninth of a 0.9 L stroke, where
/// the force climbs steeply, has 67); a path that keeps failing in steps near the smallest
/// (a sliver of progress, then rejected again: a steel flexure stretched along its axis, past
/// the root shot's force range) could otherwise crawl for minutes, so past this the path is
/// reported as not followed rather than left running.
const REJECTIONS_PER_CASE: u32 = 200;
/// No flexure tip moves by more than this (units of its `L`, radians) in one sub-step, so the
/// path cannot hop to another branch.
const MAX_TIP_STEP: f64 = 0.3;
/// A case's prediction converges as it stands where its residual is within this (units of L,
/// radians, the load's scale, as the tolerance), a hundredth of the default tolerance 1e-9
/// (and the whole of any tolerance finer than this): continuation's cubic predictor through
/// points Newton has refined ([`Point::ahead`]) meets it at 99 % of the parallel stage's 1000
/// cases (residual ratios 2e-4 to 4e-3 of the limit), and a case accepted so is as accurate
/// as one corrected by a Newton step and checked by values, which the rest still are (every
/// output as far from a solve at `tol` 1e-12 as before: tips 5.8e-11 where they were
/// 5.7e-11). Absolute, not a fraction of the tolerance, so that at a coarse tolerance a case
/// is still about as accurate as Newton's step and check would leave it.
const AS_PREDICTED: f64 = 1e-11;

/// A converged point of the path, with the flexures evaluated there.
#[derive(Debug, Clone)]
struct Point {
    lambda: f64,
    x: Vec<f64>,
    /// Where a beam mechanism's point is its case's prediction, converged as it stood: `x`
    /// moved by Newton's step from the Jacobian factored at `x` (its error is then the square
    /// of the residual there), the predictor's base ([`Point::base`]). None elsewhere (a
    /// point reached by a Newton step is already that close; a PRB mechanism's points are not
    /// refined).
    ahead: Option<Vec<f64>>,
    evals: Vec<FlexEval>,
    /// The load the flexures put on the stage.
    load: [f64; 3],
    /// The sign of the Jacobian's determinant there.
    det_sign: f64,
    /// Where a beam mechanism's point took its prediction as the case with a full
    /// evaluation (its Jacobian factored at the point itself), that Jacobian as assembled
    /// (row-major), a [`Reference`] for the next [`Chord`]. None elsewhere.
    jacobian: Option<Vec<f64>>,
}

impl Point {
    /// The unknowns the predictor extrapolates from: the refined ones where there are.
    fn base(&self) -> &[f64] {
        self.ahead.as_deref().unwrap_or(&self.x)
    }
}

impl<M: FlexureModel> MechSolver<M> {
    /// The unloaded pose's Jacobian `jac` (`n` x `n`, row-major) checked for regularity, as
    /// drive `index` (from 1) meets it: its determinant's sign and its equilibrated pivot
    /// spread, or why nothing can follow the drive from there (a self-stress,
    /// [`MechError::Indeterminate`], or a free or impossible motion, [`MechError::Immobile`]).
    pub(crate) fn regular_unloaded(
        &self,
        mut jac: Vec<f64>,
        n: usize,
        index: usize,
    ) -> Result<(f64, f64), MechError> {
        let mut rhs = vec![0.0; n];
        equilibrate(&mut jac, n);
        let equilibrated = jac.clone();
        match lu_solve(&mut jac, &mut rhs, n) {
            Some(lu) if lu.pivot_ratio > SINGULAR => Ok((lu.det_sign, lu.pivot_ratio)),
            other => {
                let ratio = other.map_or(0.0, |l| l.pivot_ratio);
                Err(match self.self_stress(&equilibrated, n) {
                    Some(flexures) => MechError::Indeterminate {
                        drive: index,
                        flexures,
                    },
                    None => MechError::Immobile {
                        drive: index,
                        detail: format!("its smallest pivot is {ratio:.1e} of its largest"),
                    },
                })
            }
        }
    }
}

/// One drive path of one solver in progress.
struct MechPath<'a, M> {
    solver: &'a MechSolver<M>,
    path: &'a DrivePath,
    /// The drive's number in errors (from 1).
    index: usize,
    /// The unloaded pose's determinant sign and equilibrated pivot spread.
    sign0: f64,
    ratio0: f64,
    cases: Vec<MechCase>,
    /// The last accepted point's factored Jacobian, and the chord it and the one before
    /// give the cases after it (beam mechanisms: [`Chord`]).
    reference: Option<Reference>,
    chord: Option<Chord>,
}

impl<M: FlexureModel> MechSolver<M> {
    /// Solves one proportional drive path (`drive` nondimensional: see
    /// `Mechanism::nondimensional`), returning the cases at `k / steps`. `index` names the
    /// drive in errors (from 1).
    pub fn solve_drive(
        &self,
        drive: &[Coordinate; 3],
        steps: u32,
        index: usize,
    ) -> Result<Vec<MechCase>, MechError> {
        self.solve_path(&DrivePath::proportional(*drive, steps), index)
    }

    /// Solves one drive path (proportional, or through a measured path's rows in order),
    /// returning the cases at `k / steps` (a measured path's rows). `index` names the drive
    /// in errors (from 1).
    pub fn solve_path(&self, path: &DrivePath, index: usize) -> Result<Vec<MechCase>, MechError> {
        self.follow(path, index)
    }

    /// Every drive path of `mechanism` (whose geometry this solver was built from): one
    /// `Vec` of cases per drive.
    pub fn solve_all(&self, mechanism: &Mechanism) -> Result<Vec<Vec<MechCase>>, MechError> {
        mechanism
            .drives
            .iter()
            .enumerate()
            .map(|(i, d)| self.solve_path(&mechanism.drive_path(d), i + 1))
            .collect()
    }

    /// The work of [`MechSolver::solve_path`].
    fn follow(&self, path: &DrivePath, index: usize) -> Result<Vec<MechCase>, MechError> {
        let steps = path.steps.max(1);
        let x0 = self.start(&path.end);
        let n = x0.len();
        // The unloaded pose: its Jacobian's sign is the reference, and a singular one means
        // the drive asks for a motion nothing can make.
        let at0 = path.at(0.0);
        let sys0 = self.system(&at0, &x0)?;
        let jac = self.jacobian(&at0, &x0, &sys0);
        let reference = self
            .predicted()
            .then(|| self.reference(0.0, jac.clone(), &sys0.evals))
            .flatten();
        let (sign0, ratio0) = self.regular_unloaded(jac, n, index)?;
        let start = Point {
            lambda: 0.0,
            ahead: None,
            x: x0,
            evals: sys0.evals,
            load: sys0.load,
            det_sign: sign0,
            jacobian: None,
        };
        let case_step = 1.0 / steps as f64;
        let limits = Limits {
            first_step: case_step,
            max_step: case_step,
            min_step: self.min_step,
            min_step_relative: 0.0,
            // Snap onto the case's fraction when within rounding of it, so the last case
            // reports the drive's own end values.
            snap: 1e-12,
            halving: Halving::Step,
            growth: Growth::AfterTwoSuccesses,
            // A jump is rejected before the determinant's sign is read; a sign change is
            // bisected (Newton converges on both sides of a fold, and a long secant step
            // near an imperfect bifurcation can land on the unstable branch beside the
            // stable one, which a shorter step follows).
            order: TestOrder::BranchFirst,
            crossing: Crossing::Bisect,
            predictor: if self.predicted() {
                Predictor::Cubic
            } else {
                Predictor::Secant
            },
            newton_iterations: self.max_newton,
            attempts_per_case: None,
            rejections_per_case: Some(REJECTIONS_PER_CASE),
            iterations_per_case: None,
        };
        let mut problem = MechPath {
            solver: self,
            path,
            index,
            sign0,
            ratio0,
            cases: Vec::with_capacity(steps as usize),
            reference,
            chord: None,
        };
        continuation::follow(&mut problem, start, steps, &limits, self.cancel.as_ref())?;
        Ok(problem.cases)
    }

    /// Newton at `lambda` from the guess `x`.
    ///
    /// With a `chord` (a beam mechanism, within its reach: [`Chord`]), the guess is first
    /// checked by values alone; within [`AS_PREDICTED`] it is the case, its determinant's sign
    /// and flexures' Jacobians the chord's, its predictor base the chord step from it. That
    /// is most cases of a long drive, at a little over half the cost of a full evaluation.
    /// Otherwise, and without a chord, it goes on as follows.
    ///
    /// The guess is evaluated in full, with the flexures' shapes where `shaped` (the last
    /// case was its prediction, so this one likely is too: [`Kind::Shaped`]). Where every
    /// flexure asks for it ([`FlexureModel::predicted`]), a continuation prediction whose
    /// residual is within [`AS_PREDICTED`] is the case: its Jacobian gives
    /// the determinant's sign, the flexures' stability and the Newton step that refines the
    /// point for the next prediction ([`Point::ahead`]), and its shapes the stresses, at the
    /// cost of one evaluation. (A PRB mechanism's prediction converges within the tolerance
    /// itself, as it always has.)
    ///
    /// Otherwise, an iterate that Newton's last step should bring within the tolerance is
    /// evaluated by values alone: where the residual the step came from was at most
    /// `sqrt(0.1 / tol)` times its limit (`sqrt(0.1 tol)` in the limit's units), quadratic
    /// convergence leaves the next one a tenth of the limit times Newton's contraction
    /// constant. The check ([`FlexureModel::eval_values`]) is the beam's shot without its
    /// variational equations; if it has converged, its flexures keep the Jacobians of the
    /// iterate before, one tiny step away, for their stability test. If not, it is evaluated
    /// again in full.
    fn newton(
        &self,
        path: &DrivePath,
        lambda: f64,
        mut x: Vec<f64>,
        effort: &mut Effort,
        shaped: bool,
        chord: Option<&Chord>,
    ) -> Result<(Point, u32), String> {
        let n = x.len();
        let at = path.at(lambda);
        if let Some(chord) = chord {
            // The prediction checked by values, with the Jacobian of the reference.
            if let Ok(sys) = self.system_with(&at, &x, Kind::Values) {
                if self.residual_ratio(&sys.residual, sys.load)
                    <= (AS_PREDICTED / self.tol).min(1.0)
                {
                    effort.spend_iteration();
                    let mut evals = sys.evals;
                    for (e, j) in evals.iter_mut().zip(&chord.jacobians) {
                        if e.jacobian.is_empty() {
                            e.jacobian.clone_from(j);
                        }
                    }
                    let point = Point {
                        lambda,
                        ahead: Some(chord.step(&x, &sys.residual)),
                        x,
                        evals,
                        load: sys.load,
                        det_sign: chord.det_sign,
                        jacobian: None,
                    };
                    return Ok((point, 1));
                }
            }
        }
        let first = if shaped { Kind::Shaped } else { Kind::Full };
        let mut sys = self
            .system_with(&at, &x, first)
            .map_err(|e| e.to_string())?;
        // Newton's step from the prediction, where the prediction has converged.
        let mut ahead: Option<Vec<f64>> = None;
        // The determinant's sign of the last Jacobian factored: at the last iterate but one,
        // within Newton's last (tiny) step of the solution, so a converged point needs no
        // Jacobian of its own.
        let mut det_sign = None;
        // The flexures' Jacobians at that iterate, for a point checked by values alone.
        let mut jacobians: Vec<Vec<f64>> = Vec::new();
        // A prediction taken as the case: its Jacobian as assembled, for a [`Chord`].
        let mut factored: Option<Vec<f64>> = None;
        // Below this residual ratio, Newton's next iterate is expected to converge.
        let quadratic = (0.1 / self.tol).sqrt();
        let limit = effort.newton_limit();
        for iteration in 1..=limit {
            effort.spend_iteration();
            let mut ratio = self.residual_ratio(&sys.residual, sys.load);
            if ratio > 1.0 && !sys.has_jacobian() {
                // Checked by values and not converged: Newton needs the Jacobian here.
                sys = self.system(&at, &x).map_err(|e| e.to_string())?;
                ratio = self.residual_ratio(&sys.residual, sys.load);
            }
            // The prediction itself is accepted only well within the tolerance, where it is
            // as close to the solution as Newton's step and check would bring it.
            let converged = ratio
                <= if iteration == 1 && self.predicted() {
                    (AS_PREDICTED / self.tol).min(1.0)
                } else {
                    1.0
                };
            if let (true, Some(det_sign)) = (converged, det_sign) {
                let mut evals = sys.evals;
                for (e, j) in evals.iter_mut().zip(jacobians.drain(..)) {
                    if e.jacobian.is_empty() {
                        e.jacobian = j;
                    }
                }
                let point = Point {
                    lambda,
                    // A reference only where the Jacobian was factored at the point itself
                    // (the prediction taken as the case), not at Newton's iterate before it.
                    jacobian: factored,
                    ahead,
                    x,
                    evals,
                    load: sys.load,
                    det_sign,
                };
                return Ok((point, iteration));
            }
            let mut jac = self.jacobian(&at, &x, &sys);
            // A prediction taken as the case keeps its Jacobian as assembled, for a chord.
            let keep = (converged && self.predicted()).then(|| jac.clone());
            let mut step: Vec<f64> = sys.residual.iter().map(|v| -v).collect();
            let lu = lu_solve(&mut jac, &mut step, n).ok_or("singular Jacobian")?;
            det_sign = Some(lu.det_sign);
            if converged {
                if keep.is_some() {
                    ahead = Some(x.iter().zip(&step).map(|(a, d)| a + d).collect());
                    factored = keep;
                }
                continue;
            }
            // A prediction within the tolerance but not within AS_PREDICTED of it: Newton's
            // step only refines it, so it is taken whole (a residual at the level of the
            // integration's noise need not shrink, and halving would cost full evaluations).
            let refine = iteration == 1 && ratio <= 1.0;
            // Damped: halve the step while the residual grows.
            let norm0 = norm(&sys.residual);
            let full = ratio > quadratic;
            let mut t = 1.0;
            loop {
                let trial: Vec<f64> = x.iter().zip(&step).map(|(a, d)| a + t * d).collect();
                let kind = if full || t < 1.0 {
                    Kind::Full
                } else {
                    Kind::Values
                };
                if let Ok(st) = self.system_with(&at, &trial, kind) {
                    if refine || norm(&st.residual) < norm0 || t < 0.1 {
                        let by_values = !st.has_jacobian();
                        let before = std::mem::replace(&mut sys, st);
                        jacobians.clear();
                        if by_values {
                            jacobians.extend(
                                before
                                    .evals
                                    .into_iter()
                                    .map(|mut e| std::mem::take(&mut e.jacobian)),
                            );
                        }
                        x = trial;
                        break;
                    }
                }
                t *= 0.5;
                if t < 0.01 {
                    return Err("Newton's step does not reduce the residual".into());
                }
            }
        }
        Err(format!("Newton did not converge in {limit} iterations"))
    }

    /// Whether every flexure asks for closely predicted cases ([`FlexureModel::predicted`]).
    fn predicted(&self) -> bool {
        self.models.iter().all(FlexureModel::predicted)
    }

    /// The [`Reference`] of the Jacobian `jacobian` factored at `lambda` with the flexures
    /// `evals`; `None` if a flexure has no stability indicator.
    fn reference(&self, lambda: f64, jacobian: Vec<f64>, evals: &[FlexEval]) -> Option<Reference> {
        let indicators = self
            .models
            .iter()
            .zip(evals)
            .map(|(m, e)| m.stability_indicator(e))
            .collect::<Option<Vec<f64>>>()?;
        Some(Reference {
            lambda,
            jacobian,
            indicators,
        })
    }

    /// The equilibrated Jacobian's smallest pivot over its largest at an accepted point (0
    /// if it cannot be evaluated).
    fn pivot_ratio(&self, path: &DrivePath, point: &Point) -> f64 {
        let n = point.x.len();
        let at = path.at(point.lambda);
        let Ok(sys) = self.system(&at, &point.x) else {
            return 0.0;
        };
        let mut jac = self.jacobian(&at, &point.x, &sys);
        equilibrate(&mut jac, n);
        let mut rhs = vec![0.0; n];
        lu_solve(&mut jac, &mut rhs, n).map_or(0.0, |lu| lu.pivot_ratio)
    }

    /// The reported case at an accepted point.
    fn case(&self, path: &DrivePath, point: &Point, iterations: u32) -> MechCase {
        let at = path.at(point.lambda);
        let mut stage_load = point.load;
        for (l, c) in stage_load.iter_mut().zip(&at) {
            if let Coordinate::Loaded(v) = c {
                *l = *v;
            }
        }
        let flexures = point
            .evals
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let (w, _) = self.own_wrench(i, &point.x);
                let o = self.offsets[i] + 3;
                let z = &point.x[o..o + self.models[i].internal()];
                FlexureCase {
                    tip: e.tip,
                    wrench: Load::new(w[0], w[1], e.tip_moment),
                    load_stable: self.models[i].load_stable(e, w, z),
                    stress: self.models[i].stress(e, w, z),
                }
            })
            .collect();
        let joints = self
            .offsets
            .iter()
            .zip(&self.models)
            .map(|(&o, m)| point.x[o + 3..o + 3 + m.internal()].to_vec())
            .collect();
        MechCase {
            fraction: point.lambda,
            stage: self.pose(&at, &point.x),
            stage_load,
            flexures,
            iterations,
            joints,
            state: Some(SolvedState {
                unknowns: point.x.clone(),
                at,
            }),
        }
    }
}

impl<M: FlexureModel> PathProblem for MechPath<'_, M> {
    type Point = Point;
    type Failure = String;
    type Error = MechError;

    /// From the unloaded pose, the unloaded unknowns.
    fn tangent(&self, start: &Point, _step: f64, trial: &mut Point) {
        trial.x.clear();
        trial.x.extend_from_slice(start.base());
    }

    fn secant(&self, last: &Point, before: &Point, t: f64, trial: &mut Point) {
        trial.x.clear();
        trial.x.extend(
            last.base()
                .iter()
                .zip(before.base())
                .map(|(a, b)| a + t * (a - b)),
        );
    }

    /// The polynomial, unless it bends away from the secant by more than a quarter of the
    /// secant's own step (toward a fold, where it would overshoot; the beam's path takes the
    /// same test).
    fn extrapolate(
        &self,
        points: &[&Point],
        weights: &[f64],
        secant_t: f64,
        trial: &mut Point,
    ) -> bool {
        let (Some(p0), Some(p1)) = (points.first(), points.get(1)) else {
            return false;
        };
        let (mut bend, mut step) = (0.0_f64, 0.0_f64);
        trial.x.clear();
        for (k, (a, b)) in p0.base().iter().zip(p1.base()).enumerate() {
            let polynomial: f64 = points
                .iter()
                .zip(weights)
                .map(|(p, w)| w * p.base()[k])
                .sum();
            let secant = a + secant_t * (a - b);
            bend = bend.max((polynomial - secant).abs());
            step = step.max((secant - a).abs());
            trial.x.push(polynomial);
        }
        bend <= 0.25 * step
    }

    fn correct(
        &mut self,
        lambda: f64,
        history: &History<Point>,
        trial: &mut Point,
        effort: &mut Effort,
    ) -> Corrected<String, MechError> {
        let guess = std::mem::take(&mut trial.x);
        // Where the last case was its prediction, this one likely is too: its first
        // evaluation samples the shapes, and is by values alone within a chord's reach (on a
        // drive of few cases, whose predictions seldom converge as they stand, a check by
        // values would mostly be followed by a full evaluation).
        let shaped = history.last().point.ahead.is_some();
        let chord = self.chord.as_ref().filter(|c| shaped && lambda <= c.reach);
        let chorded = chord.is_some();
        let result = self
            .solver
            .newton(self.path, lambda, guess, effort, shaped, chord);
        // A prediction the chord could not take (Newton went on in full, or failed) may be
        // the Jacobian's change showing itself: the chord and its references are retired,
        // and the drive takes fresh ones, a case apart, before it checks by values again.
        let taken = matches!(&result, Ok((p, _)) if p.jacobian.is_none() && p.ahead.is_some());
        if chorded && !taken {
            self.chord = None;
            self.reference = None;
        }
        match result {
            Ok((point, iterations)) => {
                *trial = point;
                Corrected::Converged(iterations)
            }
            Err(reason) => Corrected::Failed(reason),
        }
    }

    /// No flexure tip moves by more than [`MAX_TIP_STEP`].
    fn on_branch(&self, history: &History<Point>, trial: &Point) -> Result<(), String> {
        let last = &history.last().point;
        let jump = (0..self.solver.models.len()).fold(0.0_f64, |m, i| {
            m.max(trial.evals[i].tip.max_diff(&last.evals[i].tip))
        });
        if jump <= MAX_TIP_STEP {
            Ok(())
        } else {
            Err("the equilibrium jumps away from the path".to_string())
        }
    }

    /// The Jacobian's determinant keeps the unloaded pose's sign: it changes only through a
    /// singular Jacobian (a limit point or a bifurcation).
    fn regular(&self, point: &Point) -> bool {
        point.det_sign == self.sign0
    }

    /// Stuck next to a nearly singular Jacobian: a limit point, where the path turns back and
    /// no equilibrium lies further along the drive.
    fn near_critical(&mut self, history: &History<Point>, _failure: &String) -> bool {
        self.solver.pivot_ratio(self.path, &history.last().point) < NEAR_CRITICAL * self.ratio0
    }

    /// A point with a factored Jacobian is the next chord's reference.
    fn accepted(&mut self, point: &Point) {
        let Some(jacobian) = &point.jacobian else {
            return;
        };
        let now = self
            .solver
            .reference(point.lambda, jacobian.clone(), &point.evals);
        self.chord = match (&self.reference, &now) {
            (Some(before), Some(now)) => Chord::new(before, now, point),
            _ => None,
        };
        self.reference = now;
    }

    fn report(&mut self, _lambda: f64, point: &mut Point, tally: Tally, _effort: &mut Effort) {
        let case = self.solver.case(self.path, point, tally.iterations);
        self.cases.push(case);
    }

    fn stop(&self, why: Stop<String>, fraction: f64, _effort: &Effort) -> MechError {
        let no_equilibrium = |reason: String| MechError::NoEquilibrium {
            drive: self.index,
            fraction,
            reason,
        };
        match why {
            Stop::Critical => MechError::Critical {
                drive: self.index,
                fraction,
            },
            Stop::Stuck(reason) => no_equilibrium(reason),
            Stop::Rejections => no_equilibrium(format!(
                "continuation rejected more than {REJECTIONS_PER_CASE} sub-steps of one case \
                 without reaching it"
            )),
            Stop::Cancelled => MechError::Cancelled,
            // Never asked for: a drive has no attempt budget.
            Stop::Attempts => no_equilibrium("the effort budget ran out".into()),
        }
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}
