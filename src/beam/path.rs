//! The beam along a load path, as a problem of the continuation driver
//! ([`crate::continuation`]): the state is `(psi, M)` at the start of every shooting segment,
//! the corrector the multiple-shooting Newton iteration, the critical-point indicator the
//! stability slope `dM(L)/dM(0)` (see the parent module for the method and its accuracy).

use super::model::BeamModel;
use super::newton::{segment_count, Chain, NewtonFailure, NewtonScratch};
use super::shoot::{Meter, ShotFailure};
use super::stress::StressScratch;
use super::{BeamSolution, BeamSolver, Convergence, Load, ShapePoint, SolveError, TipPose};
use crate::continuation::{
    Corrected, Crossing, Effort, Growth, Halving, History, Limits, PathProblem, Predictor, Stop,
    Tally, TestOrder,
};

/// Continuation never takes a step that turns the tip by more than this (radians) ...
const MAX_TIP_TURN: f64 = 1.0;
/// ... or moves it by more than this (units of L), so it cannot hop to another branch.
const MAX_TIP_MOVE: f64 = 0.6;
/// ... or, once extension has stretched the beam past 2.4 L, by more than this fraction of
/// the tip's distance from the root: a pull of 1e6 on a stubby beam stretches it 800-fold,
/// and an absolute limit would take thousands of steps along a straight line.
const STRETCHED_MOVE: f64 = 0.25;
/// Newton's correction of the predicted tip may always be this large (units of L, radians).
const MIN_CORRECTION: f64 = 0.15;
/// A continuation stuck where `dM(L)/dM(0)` has fallen below this fraction of its largest
/// value on the path has reached a critical point.
const NEAR_CRITICAL: f64 = 0.01;
/// The same for the slope's direction ([`Chain::direction`]), which falls like the slope near a
/// limit point but is bounded by 1, so a huge load's fold shows in it only close by.
const NEAR_CRITICAL_DIRECTION: f64 = 0.1;
/// The smallest continuation step before the solver gives up, for loads up to 100; a huge
/// load, whose shape changes and critical points sit within the path's first millionths,
/// gets a proportionally finer one, so that those are located as precisely.
const MIN_STEP: f64 = 1e-7;
/// Newton shots one continuation attempt may take.
const MAX_NEWTON: u32 = 30;
/// The state at one point of a load path: `(psi, M)` at the start of every shooting segment,
/// and what Newton found there.
#[derive(Debug, Clone)]
pub(super) struct PathPoint {
    nodes: Vec<[f64; 2]>,
    tip: TipPose,
    /// The tip the predictor expected (of the attempt that found this point).
    predicted: TipPose,
    /// The deformed centre line, as the last shot sampled it.
    shape: Vec<ShapePoint>,
    /// Integration steps of the last shot.
    rk_steps: u32,
    convergence: Convergence,
    /// The shape's stability (`chain.slope` is `convergence.stability`).
    chain: Chain,
    /// Newton's contraction constant, as last measured on this path (see
    /// [`NewtonResult::contraction`]).
    contraction: Option<f64>,
}

impl PathPoint {
    /// The unloaded beam, shot in `segments` segments: where every path starts.
    fn unloaded(segments: usize) -> PathPoint {
        PathPoint {
            nodes: vec![[0.0, 0.0]; segments],
            tip: TipPose::STRAIGHT,
            predicted: TipPose::STRAIGHT,
            shape: Vec::new(),
            rk_steps: 0,
            convergence: Convergence {
                residual: 0.0,
                last_update: 0.0,
                stability: 1.0,
            },
            chain: Chain {
                slope: 1.0,
                // (dpsi, dM)(L) = (L, 1) for the unloaded beam.
                direction: std::f64::consts::FRAC_1_SQRT_2,
                focal_point: false,
            },
            contraction: None,
        }
    }
}

/// One load path of one solver in progress.
pub(super) struct BeamPath<'a> {
    solver: &'a BeamSolver,
    end: Load,
    /// The case's integration steps against its budget, and the caller's cancel flag.
    meter: Meter<'a>,
    /// The largest stability slope and direction of the case so far (the last two points
    /// before it included).
    peak_stability: f64,
    peak_direction: f64,
    /// The cases reached, in order.
    cases: Vec<BeamSolution>,
    /// Newton's storage, reused from case to case.
    scratch: NewtonScratch,
    /// The stress search's storage, likewise.
    stress: StressScratch,
    /// With a wide section's plane strain: the plate fraction of each case `k / steps`
    /// (`k = 1..=steps`), which the model takes at the case and linearly in between
    /// ([`BeamPath::solver_at`]); `None`: the solver's own model throughout.
    plate: Option<&'a [f64]>,
}

impl BeamSolver {
    /// Follows the proportional path to `end` (finite), returning the cases at `k / steps`,
    /// `k = 1..=steps`.
    pub(super) fn follow(
        &self,
        end: Load,
        steps: u32,
        cancel: &crate::cancel::CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        self.follow_with_plate(end, steps, None, cancel)
    }

    /// As [`BeamSolver::follow`], with the plate fraction varying along the path: `plate`
    /// holds case `k / steps`'s (`k = 1..=steps`), taken exactly at the case and linearly in
    /// between, so each case is solved at its own fraction on the branch the path follows,
    /// in one continuation.
    pub(super) fn follow_with_plate(
        &self,
        end: Load,
        steps: u32,
        plate: Option<&[f64]>,
        cancel: &crate::cancel::CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        let steps = steps.max(1);
        let limits = Limits {
            first_step: first_step(&self.model, end, 1.0 / steps as f64),
            max_step: 1.0,
            min_step: MIN_STEP * (100.0 / end.magnitude()).min(1.0),
            min_step_relative: MIN_STEP,
            snap: 0.0,
            halving: Halving::Tried,
            growth: Growth::Always,
            // An unstable landing is rejected before the branch test, and bisected to the
            // critical point.
            order: TestOrder::IndicatorFirst,
            crossing: Crossing::Bisect,
            // The parabola through the last three points: on a finely sampled path its
            // prediction is close enough for Newton to stop after one shot.
            predictor: Predictor::Quadratic,
            newton_iterations: MAX_NEWTON,
            attempts_per_case: Some(self.budget.continuation_steps),
            rejections_per_case: None,
            iterations_per_case: Some(self.budget.shots),
        };
        let mut path = BeamPath {
            solver: self,
            end,
            meter: Meter::new(self.budget.rk_steps, &self.model, cancel),
            peak_stability: 1.0,
            peak_direction: 0.0,
            cases: Vec::with_capacity(steps as usize),
            scratch: NewtonScratch::default(),
            stress: StressScratch::default(),
            plate,
        };
        let start = PathPoint::unloaded(segment_count(&self.model, end));
        crate::continuation::follow(&mut path, start, steps, &limits, Some(cancel))?;
        Ok(path.cases)
    }
}

impl BeamPath<'_> {
    /// The solver at path fraction `lambda`: the solver's own, or with the plate fraction
    /// interpolated between the cases' (constant before the first case).
    fn solver_at(&self, lambda: f64) -> BeamSolver {
        let Some(phis) = self.plate.filter(|p| !p.is_empty()) else {
            return *self.solver;
        };
        let x = (lambda * phis.len() as f64).clamp(0.0, phis.len() as f64);
        // Case k (from 1) sits at x = k; below case 1 the first fraction holds.
        let k = (x.ceil() as usize).clamp(1, phis.len());
        let phi = if k == 1 {
            phis[0]
        } else {
            let t = x - (k - 1) as f64;
            phis[k - 2] + (phis[k - 1] - phis[k - 2]) * t
        };
        let mut model = self.solver.model.with_plate_fraction(phi);
        model.forget_width();
        BeamSolver {
            model,
            ..*self.solver
        }
    }

    /// How far a step from `from` to `to` turns and moves the tip, and the move allowed.
    fn motion(from: &TipPose, to: &TipPose) -> (f64, f64, f64) {
        let turn = (to.phi - from.phi).abs();
        let move_limit = MAX_TIP_MOVE.max(STRETCHED_MOVE * from.a.hypot(from.b));
        let moved = (to.a - from.a).hypot(to.b - from.b);
        (turn, moved, move_limit)
    }

    /// [`SolveError::EffortExceeded`] at `fraction` with the case's counts.
    fn exceeded(&self, fraction: f64, effort: &Effort) -> SolveError {
        SolveError::EffortExceeded {
            load: self.end,
            fraction,
            steps: effort.attempts,
            shots: effort.iterations,
            rk_steps: self.meter.tries,
        }
    }
}

impl PathProblem for BeamPath<'_> {
    type Point = PathPoint;
    type Failure = SolveError;
    type Error = SolveError;

    /// The linear-theory tangent at the start: `M(s) = beta + alpha_y (1 - s)`, `psi` its
    /// integral, the tip moving by the Euler-Bernoulli compliance.
    fn tangent(&self, p: &PathPoint, dl: f64, trial: &mut PathPoint) {
        let end = self.end;
        let segments = p.nodes.len();
        trial.nodes.clear();
        trial.nodes.extend((0..segments).map(|k| {
            let s = k as f64 / segments as f64;
            let m = end.beta + end.alpha_y * (1.0 - s);
            let psi = end.beta * s + end.alpha_y * (s - 0.5 * s * s);
            [p.nodes[k][0] + dl * psi, p.nodes[k][1] + dl * m]
        }));
        trial.tip = TipPose {
            a: p.tip.a,
            b: p.tip.b + dl * (end.alpha_y / 3.0 + end.beta / 2.0),
            phi: p.tip.phi + dl * (end.alpha_y / 2.0 + end.beta),
        };
    }

    fn secant(&self, p1: &PathPoint, p0: &PathPoint, t: f64, trial: &mut PathPoint) {
        trial.nodes.clear();
        trial.nodes.extend(
            p1.nodes
                .iter()
                .zip(&p0.nodes)
                .map(|(n1, n0)| [n1[0] + t * (n1[0] - n0[0]), n1[1] + t * (n1[1] - n0[1])]),
        );
        trial.tip = TipPose {
            a: p1.tip.a + t * (p1.tip.a - p0.tip.a),
            b: p1.tip.b + t * (p1.tip.b - p0.tip.b),
            phi: p1.tip.phi + t * (p1.tip.phi - p0.tip.phi),
        };
    }

    /// The parabola, unless it bends away from the secant by more than a quarter of the
    /// secant's own step: the path turns sharply there (toward a fold, whose state goes like
    /// `sqrt(lambda_c - lambda)`), and the parabola would overshoot where the secant has
    /// always bisected safely.
    fn extrapolate(
        &self,
        points: &[&PathPoint],
        weights: &[f64],
        secant_t: f64,
        trial: &mut PathPoint,
    ) -> bool {
        let (&[p0, p1, p2], &[w0, w1, w2]) = (points, weights) else {
            return false;
        };
        if p0.nodes.len() != p1.nodes.len() || p1.nodes.len() != p2.nodes.len() {
            return false;
        }
        let mix = |f: fn(&TipPose) -> f64| w0 * f(&p0.tip) + w1 * f(&p1.tip) + w2 * f(&p2.tip);
        let tip = TipPose {
            a: mix(|t| t.a),
            b: mix(|t| t.b),
            phi: mix(|t| t.phi),
        };
        let secant = TipPose {
            a: p0.tip.a + secant_t * (p0.tip.a - p1.tip.a),
            b: p0.tip.b + secant_t * (p0.tip.b - p1.tip.b),
            phi: p0.tip.phi + secant_t * (p0.tip.phi - p1.tip.phi),
        };
        if tip.max_diff(&secant) > 0.25 * secant.max_diff(&p0.tip) {
            return false;
        }
        trial.nodes.clear();
        trial.nodes.extend(
            p0.nodes
                .iter()
                .zip(&p1.nodes)
                .zip(&p2.nodes)
                .map(|((a, b), c)| {
                    [
                        w0 * a[0] + w1 * b[0] + w2 * c[0],
                        w0 * a[1] + w1 * b[1] + w2 * c[1],
                    ]
                }),
        );
        trial.tip = tip;
        true
    }

    fn correct(
        &mut self,
        lambda: f64,
        history: &History<PathPoint>,
        trial: &mut PathPoint,
        effort: &mut Effort,
    ) -> Corrected<SolveError, SolveError> {
        let (end, fraction) = (self.end, history.last().lambda);
        let prior = history.last().point.contraction;
        trial.predicted = trial.tip;
        let guess = std::mem::take(&mut trial.nodes);
        let failure = |reason: String| {
            Corrected::Failed(SolveError::NoConvergence {
                load: end,
                fraction,
                reason,
            })
        };
        // The trial's old shape is the buffer the new one is sampled into.
        self.scratch.shape = std::mem::take(&mut trial.shape);
        match self.solver_at(lambda).newton(
            end.scaled(lambda),
            guess,
            prior,
            &mut self.meter,
            effort,
            &mut self.scratch,
        ) {
            Ok(result) => {
                trial.contraction = result.contraction.or(prior);
                trial.nodes = result.nodes;
                trial.tip = result.tip;
                trial.shape = result.shape;
                trial.rk_steps = result.rk_steps;
                trial.convergence = result.convergence;
                trial.chain = result.chain;
                Corrected::Converged(result.shots)
            }
            Err(NewtonFailure::Shot(ShotFailure::Material(limit))) => {
                Corrected::Failed(SolveError::MaterialLimit {
                    load: end,
                    fraction,
                    reason: limit.to_string(),
                })
            }
            Err(NewtonFailure::Shot(ShotFailure::StepBudget)) => {
                failure("the integrator's step size collapsed".into())
            }
            Err(NewtonFailure::Shot(ShotFailure::NonFinite)) => failure("a shot overflowed".into()),
            Err(NewtonFailure::Shot(ShotFailure::Cancelled)) => {
                Corrected::Stop(SolveError::Cancelled {
                    load: end,
                    fraction,
                })
            }
            Err(NewtonFailure::Shot(ShotFailure::OutOfEffort) | NewtonFailure::OutOfShots) => {
                Corrected::Stop(self.exceeded(fraction, effort))
            }
            Err(NewtonFailure::Diverged(reason)) => failure(reason),
        }
    }

    /// Newton may correct the predictor, but not by much more than the step itself: a big
    /// correction means it found another branch. Nor may the tip turn or move too far.
    fn on_branch(&self, history: &History<PathPoint>, trial: &PathPoint) -> Result<(), SolveError> {
        let prev_tip = &history.last().point.tip;
        let (turn, moved, move_limit) = Self::motion(prev_tip, &trial.tip);
        let correction = trial.tip.max_diff(&trial.predicted);
        let allowed = MIN_CORRECTION + 0.5 * trial.predicted.max_diff(prev_tip);
        if turn > MAX_TIP_TURN || moved > move_limit || correction > allowed {
            return Err(SolveError::NoConvergence {
                load: self.end,
                fraction: history.last().lambda,
                reason: "continuation step too large".into(),
            });
        }
        Ok(())
    }

    /// Stable: `dM(s)/dM(0) > 0` along the whole beam (see `chain_stability`).
    fn regular(&self, point: &PathPoint) -> bool {
        !(point.convergence.stability <= 0.0 || point.chain.focal_point)
    }

    /// Stuck where the stability slope has collapsed: a limit point, past which the
    /// equilibrium followed from zero no longer exists (the beam snaps). Under a huge force
    /// the slope carries a factor `exp(sqrt(alpha))` that grows along the path and hides its
    /// collapse; its direction does not.
    fn near_critical(&mut self, history: &History<PathPoint>, _failure: &SolveError) -> bool {
        let last = &history.last().point;
        last.convergence.stability < NEAR_CRITICAL * self.peak_stability
            || last.chain.direction < NEAR_CRITICAL_DIRECTION * self.peak_direction
    }

    /// Double the step, but not past what this step's tip motion says would break a limit:
    /// the tip moves about in proportion to the step, and a rejected step costs a whole
    /// Newton solve. (A huge pull with extension on stretches the beam by 0.5 L per step;
    /// doubling blindly had every second step rejected.) The step just accepted kept within
    /// the limits, so the next is at least 0.9 of it: the step size cannot collapse here.
    fn step_cap(&self, last: &PathPoint, trial: &PathPoint, taken: f64) -> f64 {
        let (turn, moved, move_limit) = Self::motion(&last.tip, &trial.tip);
        let mut cap = f64::INFINITY;
        if turn > 0.0 {
            cap = cap.min(0.9 * MAX_TIP_TURN / turn * taken);
        }
        if moved > 0.0 {
            cap = cap.min(0.9 * move_limit / moved * taken);
        }
        cap
    }

    /// A fresh meter for the case's budget, and the stability peaks from the two points the
    /// case starts from.
    fn begin_case(&mut self, history: &History<PathPoint>) {
        self.meter = Meter::new(
            self.solver.budget.rk_steps,
            &self.solver.model,
            self.meter.cancel,
        );
        self.peak_stability = history
            .iter()
            .map(|p| p.point.convergence.stability)
            .fold(1.0, f64::max);
        self.peak_direction = history
            .iter()
            .map(|p| p.point.chain.direction)
            .fold(0.0, f64::max);
    }

    fn accepted(&mut self, point: &PathPoint) {
        self.peak_stability = self.peak_stability.max(point.convergence.stability);
        self.peak_direction = self.peak_direction.max(point.chain.direction);
    }

    /// Newton's last update reached the tip and the shape linearly (see
    /// [`BeamSolver::newton`]), so the point is the case's solution as it stands; its shape
    /// moves into the solution (Newton samples a new one for every point), unless the solver
    /// keeps none.
    fn report(&mut self, lambda: f64, point: &mut PathPoint, tally: Tally, _effort: &mut Effort) {
        let load = self.end.scaled(lambda);
        let stress = self
            .solver
            .max_stress_with(load, point.tip, &point.shape, &mut self.stress);
        let solution = BeamSolution {
            load,
            tip: point.tip,
            root_moment: point.nodes[0][1],
            shape: if self.solver.keep_shapes {
                std::mem::take(&mut point.shape)
            } else {
                Vec::new()
            },
            iterations: tally.iterations,
            continuation_steps: tally.accepted,
            rk_steps: point.rk_steps,
            convergence: point.convergence,
            stress,
        };
        self.cases.push(solution);
    }

    fn stop(&self, why: Stop<SolveError>, fraction: f64, effort: &Effort) -> SolveError {
        match why {
            Stop::Cancelled => SolveError::Cancelled {
                load: self.end,
                fraction,
            },
            Stop::Critical => SolveError::Unstable {
                load: self.end,
                fraction,
            },
            Stop::Stuck(failure) => failure,
            Stop::Attempts | Stop::Rejections => self.exceeded(fraction, effort),
        }
    }
}

/// The first continuation step from the unloaded beam: `wanted`, shortened so that linear
/// theory (tip turn `alpha_y / 2 + beta`, deflection `alpha_y / 3 + beta / 2`, stretch
/// `c_e alpha_x`) keeps it inside the step limits. Linear theory overestimates a large load's
/// deflection, so this never asks too much; without it a huge load would start by halving the
/// whole path down to its first few thousandths, each halving a failed Newton solve far from
/// any equilibrium (99% of the work of an `alpha_y = 1e4` solve).
fn first_step(model: &BeamModel, end: Load, wanted: f64) -> f64 {
    let turn = 0.5 * end.alpha_y.abs() + end.beta.abs();
    let stretch = if model.effects.extension {
        model.axial_compliance() * end.alpha_x.abs()
    } else {
        0.0
    };
    let moved = end.alpha_y.abs() / 3.0 + 0.5 * end.beta.abs() + stretch;
    // A margin below the limits, so that round-off cannot put the step just past one.
    let mut step = wanted;
    if turn * step > 0.9 * MAX_TIP_TURN {
        step = 0.9 * MAX_TIP_TURN / turn;
    }
    if moved * step > 0.9 * MAX_TIP_MOVE {
        step = 0.9 * MAX_TIP_MOVE / moved;
    }
    step
}
