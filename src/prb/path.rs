//! A PRB chain along a load curve, as a problem of the continuation driver
//! ([`crate::continuation`]): the state is the configuration `q`, the corrector Newton on the
//! analytic tangent stiffness, and the critical-point indicator that stiffness's positive
//! definiteness (Cholesky succeeds), tested inside every Newton iteration; and what a path
//! hands back ([`PrbSolution`], [`PrbCase`], [`PrbError`]).
//!
//! Newton stops when no update moves a joint by more than `1e-13` (radians, units of L), or
//! when the update it has just made is in the quadratic regime (below `1e-7`) and the last
//! two updates predict the next below `1e-14`, so an accepted configuration is exact to
//! rounding. The prediction saves the iteration that would only confirm it (the 20-case 3R
//! fit of `benches/scipy`: 670 Newton iterations where it took 820, with the same evaluations
//! and `J`).

use crate::beam::{Load, TipPose};
use crate::continuation::{self, Corrected, Effort, History, Limits, PathProblem, Stop, Tally};
use crate::linalg::cholesky_solve;

use super::chain::{PrbSolver, MAX_NEWTON};
use super::workspace::{Inline, Workspace};

/// Why a PRB equilibrium could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PrbError {
    /// The requested load has a NaN or infinite component; holds that load.
    #[error("load is not finite: {0}")]
    NonFiniteLoad(Load),
    /// Continuation stalled: Newton diverged, the tip jumped off the followed branch, or the
    /// iteration budget ran out before the end of the load path.
    #[error(
        "the PRB model has no equilibrium for {load} past {:.4} of the load path ({reason})",
        fraction
    )]
    NoEquilibrium {
        /// The end of the load path (nondimensional `alpha_x`, `alpha_y`, `beta`).
        load: Load,
        /// The last load-path fraction (0 to 1) where an equilibrium was accepted.
        fraction: f64,
        /// What stopped the continuation, in words.
        reason: String,
    },
    /// The tangent stiffness stopped being positive definite on the load path: the chain
    /// buckles or snaps through there, and the stable branch ends.
    #[error(
        "the PRB model reaches a critical point (its tangent stiffness turns singular) at {:.4} \
         of the load path to {load}: it buckles or snaps there",
        fraction
    )]
    Unstable {
        /// The end of the load path (nondimensional `alpha_x`, `alpha_y`, `beta`).
        load: Load,
        /// The last load-path fraction (0 to 1) where a stable equilibrium was accepted.
        fraction: f64,
    },
}

/// An equilibrium of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct PrbSolution {
    /// The load solved for (nondimensional `alpha_x`, `alpha_y`, `beta`).
    pub load: Load,
    /// The chain's tip: `a`, `b` in units of L, `phi` (the last segment's angle `Theta_N`)
    /// in radians.
    pub tip: TipPose,
    /// Joint angles (radians, revolute rows) and extensions (units of L, prismatic rows), in
    /// row order.
    pub q: Vec<f64>,
    /// Newton iterations spent on this load, continuation sub-steps included.
    pub iterations: u32,
}

/// One equilibrium as handed to a visitor: the configuration is borrowed, so following a load
/// path allocates nothing per case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrbCase<'a> {
    /// The load solved for (nondimensional `alpha_x`, `alpha_y`, `beta`).
    pub load: Load,
    /// The chain's tip: `a`, `b` in units of L, `phi` in radians.
    pub tip: TipPose,
    /// Joint angles (radians, revolute rows) and extensions (units of L, prismatic rows), in
    /// row order; borrowed from the solver's buffer.
    pub q: &'a [f64],
    /// Newton iterations spent on this load, continuation sub-steps included.
    pub iterations: u32,
    /// The workspace Newton left converging to this case, for its sensitivities without a
    /// linearisation of their own ([`PrbSolver::tip_sensitivity_converged`]).
    pub(crate) work: Option<&'a Workspace>,
}

impl PrbCase<'_> {
    /// An owned copy of this equilibrium.
    pub fn to_solution(&self) -> PrbSolution {
        PrbSolution {
            load: self.load,
            tip: self.tip,
            q: self.q.to_vec(),
            iterations: self.iterations,
        }
    }
}

/// Newton stops when the update is below this (radians, units of L).
const NEWTON_TOL: f64 = 1e-13;
/// Updates below this (radians, units of L) are in Newton's quadratic regime, where the next
/// update is predicted from the last two; its square (what the tip's linear update from the
/// last configuration leaves out) is 1e-14.
const QUADRATIC_FROM: f64 = 1e-7;
/// No Newton update turns a joint by more than this (radians).
const MAX_TURN: f64 = 0.5;
/// No accepted step moves the tip by more than this (units of L, radians).
const MAX_TIP_JUMP: f64 = 1.0;

/// Why Newton failed at a fixed load.
#[derive(Debug, Clone, Copy)]
enum Failure {
    /// The tangent stiffness is not positive definite: an unstable or critical state.
    NotPositiveDefinite,
    Diverged,
}

/// Why an attempt was rejected, other than a critical point.
#[derive(Debug, Clone, Copy)]
enum Stall {
    /// Newton did not converge.
    Diverged,
    /// Converged, but off the branch followed.
    Jumped,
}

/// A chain's configuration, inline up to eight degrees of freedom, so that the points a
/// path copies (its start, its trial, the history's first three) allocate nothing for the
/// chains a fit tries (a 3R's three; those copies were 3 % of a 3R fit's time, in `malloc`
/// and `free`), and on the heap beyond.
type Config = Inline<8>;

/// The state at one point of the path.
#[derive(Debug, Clone)]
struct Point {
    /// The load there.
    load: Load,
    q: Config,
    tip: TipPose,
    /// The tip the predictor expected (of the attempt that found this point).
    predicted: TipPose,
    /// Whether the prediction was a [`WarmStart`]'s (every predictor clears it).
    hinted: bool,
    /// With `hinted`, the warm start's tip at the case before (the unloaded tip before the
    /// first): the step the neighbouring chain took to this case is `predicted - this`.
    hint_before: TipPose,
    /// With `hinted`, the tip continuation's secant predicts at this case (none before there
    /// are two accepted points), which the landing must meet as continuation's own would.
    continued: Option<TipPose>,
}

/// A hinted attempt converges in at most this many Newton iterations: from a neighbouring
/// model's equilibrium Newton's updates shrink quadratically from the first (the 20-case 3R
/// fit's polish takes three or four), and one that needs more is followed from the last case
/// instead.
const HINT_ITERATIONS: u32 = 5;
/// A hinted attempt lands within this of the hint's tip, and its step from the case before
/// differs from the neighbouring chain's step between the same cases by at most this (units
/// of L, radians): a trial model a fit's step away moves its tips by less (the 3R fit's first
/// polish step, by about 0.02), and a step that snaps through a fold between the cases, where
/// the neighbouring chain did not, differs from that chain's by the snap. A hinted landing
/// must also meet continuation's own branch test against the secant's prediction, so a hint
/// on another stable branch (the 1R buckled the other way) is forgotten where continuation
/// would follow its own (`tests/prb_model.rs`). As for any one-step attempt (continuation
/// also steps a whole case when it can), a fold whose snap is smaller than these is not
/// seen.
const HINT_RADIUS: f64 = 0.05;

/// The equilibria along one load path of a neighbouring chain with the same degrees of
/// freedom (a fit's previous trial model), case by case: the first guesses of a warm-started
/// path ([`PrbSolver::solve_warm_with`]), each corrected at its own case in one step from
/// the case before. A hint that does not hold is forgotten, and that case is followed by
/// continuation as without one: Newton needs more than five iterations from it, or lands
/// more than 0.05 (units of L, radians) from the hint's tip, or by a step more than 0.05 from
/// the neighbouring chain's step between the same cases, or where continuation's own branch
/// test against its secant would not accept it. The equilibria reported are the plain
/// path's to rounding wherever the tests tell the branches apart (a proptest over random
/// chains and loads, a buckling load, a hint on the mirror branch); only the cost differs.
#[derive(Debug, Clone, Default)]
pub struct WarmStart {
    /// Degrees of freedom of the chain the equilibria belong to.
    m: usize,
    /// The cases' configurations, `m` each.
    q: Vec<f64>,
    tips: Vec<TipPose>,
}

impl WarmStart {
    /// Forgets every case, keeping the storage, for a chain of `m` degrees of freedom.
    pub fn clear(&mut self, m: usize) {
        self.m = m;
        self.q.clear();
        self.tips.clear();
    }

    /// Adds the next case.
    pub fn push(&mut self, case: &PrbCase<'_>) {
        self.q.extend_from_slice(case.q);
        self.tips.push(case.tip);
    }

    /// Case `k` (from 0) for a chain of `m` degrees of freedom.
    fn get(&self, k: usize, m: usize) -> Option<(&[f64], TipPose)> {
        let tip = *self.tips.get(k)?;
        (m == self.m).then(|| (&self.q[k * m..(k + 1) * m], tip))
    }
}

/// One load curve of one chain in progress.
struct PrbPath<'a, F, V> {
    solver: &'a PrbSolver,
    /// The end of the curve, named in errors.
    end: Load,
    load_at: F,
    visit: V,
    ws: Workspace,
    /// First guesses for the cases, if warm-started.
    warm: Option<&'a WarmStart>,
}

impl PrbSolver {
    /// Follows the load curve `load_at(lambda)`, `lambda` from 0 (unloaded) to 1 (`end`),
    /// handing the cases at `k / steps` to `visit`.
    pub(super) fn follow_with(
        &self,
        end: Load,
        steps: u32,
        load_at: impl Fn(f64) -> Load,
        warm: Option<&WarmStart>,
        visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        if !end.is_finite() {
            return Err(PrbError::NonFiniteLoad(end));
        }
        let steps = steps.max(1);
        let m = self.dofs.len();
        // The Newton limit and per-case budget of `SolverLimits` are not applied: the path
        // has always run with MAX_NEWTON and no budget (its iterations were never counted),
        // and applying them would change every fit's results. The smallest step is applied.
        let limits = Limits::new(steps, self.min_step, MAX_NEWTON);
        let mut path = PrbPath {
            solver: self,
            end,
            load_at,
            visit,
            ws: Workspace::new(self.gamma.len(), m),
            warm,
        };
        let start = Point {
            load: Load::default(),
            q: Config::zeros(m),
            tip: TipPose::STRAIGHT,
            predicted: TipPose::STRAIGHT,
            hinted: false,
            hint_before: TipPose::STRAIGHT,
            continued: None,
        };
        continuation::follow(&mut path, start, steps, &limits, None)
    }

    /// Newton at a fixed load from `q` (updated in place). Returns the tip and iterations; a
    /// tangent stiffness that is not positive definite (an unstable or critical state) fails.
    fn newton(
        &self,
        load: Load,
        q: &mut [f64],
        ws: &mut Workspace,
        effort: &mut Effort,
    ) -> Result<(TipPose, u32), Failure> {
        let m = self.dofs.len();
        // The previous update's size, for the convergence estimate.
        let mut previous = f64::INFINITY;
        for iteration in 1..=effort.newton_limit() {
            if !effort.spend_iteration() {
                return Err(Failure::Diverged);
            }
            let tip = self.residual(load, q, ws);
            let parts = ws.parts();
            parts.step.copy_from_slice(parts.res);
            if !cholesky_solve(parts.jac, parts.step, m) {
                return Err(Failure::NotPositiveDefinite);
            }
            // The solve left every entry finite; a plain comparison, where `f64::max`'s NaN
            // handling took 1.6 % of a 3R fit's time.
            let biggest =
                parts
                    .step
                    .iter()
                    .fold(0.0_f64, |acc, v| if v.abs() > acc { v.abs() } else { acc });
            if !biggest.is_finite() {
                return Err(Failure::Diverged);
            }
            let scale = if biggest > MAX_TURN {
                MAX_TURN / biggest
            } else {
                1.0
            };
            for (qi, si) in q.iter_mut().zip(parts.step.iter()) {
                *qi -= scale * si;
            }
            // Quadratic convergence, `d_(k+1) = C d_k^2` with `C = d_k / d_(k-1)^2` from the
            // last two updates, predicts the next update; below a tenth of NEWTON_TOL it
            // would move nothing, so this one is the last.
            let converged = biggest <= NEWTON_TOL
                || (biggest <= QUADRATIC_FROM
                    && biggest * biggest * biggest <= 0.1 * NEWTON_TOL * previous * previous);
            previous = biggest;
            if converged {
                // The last update moved nothing by more than QUADRATIC_FROM: the tip moves
                // with it to first order (the rest is its square, 1e-14 at most), so the
                // tip is the converged configuration's however small or large the last
                // update was.
                return Ok((self.tip_moved(tip, parts), iteration));
            }
        }
        Err(Failure::Diverged)
    }
}

impl<F, V> PathProblem for PrbPath<'_, F, V>
where
    F: Fn(f64) -> Load,
    V: FnMut(PrbCase<'_>),
{
    type Point = Point;
    type Failure = Stall;
    type Error = PrbError;

    /// From the unloaded chain, the previous configuration.
    fn tangent(&self, start: &Point, _step: f64, trial: &mut Point) {
        trial.q.copy_from_slice(&start.q);
        trial.tip = start.tip;
        trial.hinted = false;
    }

    /// The warm start's equilibrium of the same case.
    fn hint(&mut self, case: u32, trial: &mut Point) -> Option<u32> {
        let warm = self.warm?;
        let m = trial.q.len();
        let k = case as usize - 1;
        let (q, tip) = warm.get(k, m)?;
        trial.hint_before = match k {
            0 => TipPose::STRAIGHT,
            _ => warm.get(k - 1, m)?.1,
        };
        trial.q.copy_from_slice(q);
        trial.tip = tip;
        trial.hinted = true;
        Some(HINT_ITERATIONS)
    }

    fn secant(&self, last: &Point, before: &Point, t: f64, trial: &mut Point) {
        trial.hinted = false;
        for ((q, q1), q0) in trial.q.iter_mut().zip(last.q.iter()).zip(before.q.iter()) {
            *q = q1 + t * (q1 - q0);
        }
        let (p1, p0) = (&last.tip, &before.tip);
        trial.tip = TipPose {
            a: p1.a + t * (p1.a - p0.a),
            b: p1.b + t * (p1.b - p0.b),
            phi: p1.phi + t * (p1.phi - p0.phi),
        };
    }

    fn correct(
        &mut self,
        lambda: f64,
        history: &History<Point>,
        trial: &mut Point,
        effort: &mut Effort,
    ) -> Corrected<Stall, PrbError> {
        trial.predicted = trial.tip;
        trial.continued = if trial.hinted {
            history.before().map(|before| {
                let last = history.last();
                let t = (lambda - last.lambda) / (last.lambda - before.lambda);
                let (p1, p0) = (&last.point.tip, &before.point.tip);
                TipPose {
                    a: p1.a + t * (p1.a - p0.a),
                    b: p1.b + t * (p1.b - p0.b),
                    phi: p1.phi + t * (p1.phi - p0.phi),
                }
            })
        } else {
            None
        };
        trial.load = (self.load_at)(lambda);
        match self
            .solver
            .newton(trial.load, &mut trial.q, &mut self.ws, effort)
        {
            Ok((tip, iterations)) => {
                trial.tip = tip;
                Corrected::Converged(iterations)
            }
            // Cholesky failed: an unstable state, bisected to the critical point.
            Err(Failure::NotPositiveDefinite) => Corrected::Critical,
            Err(Failure::Diverged) => Corrected::Failed(Stall::Diverged),
        }
    }

    /// The tip may not jump, nor (once there is a secant) land far from the prediction. A
    /// hinted landing must also meet the hint ([`HINT_RADIUS`]) and, once there is a secant,
    /// continuation's own test against the secant's prediction: it is accepted only where
    /// continuation would accept it, had its Newton landed there.
    fn on_branch(&self, history: &History<Point>, trial: &Point) -> Result<(), Stall> {
        let prev_tip = &history.last().point.tip;
        let jump = trial.tip.max_diff(prev_tip);
        let off = |predicted: &TipPose| {
            trial.tip.max_diff(predicted) > 0.15 + 0.5 * predicted.max_diff(prev_tip)
        };
        let off_prediction = trial.tip.max_diff(&trial.predicted);
        let off_hinted_step = || {
            let (t, h) = (&trial.tip, &trial.predicted);
            let (p, b) = (prev_tip, &trial.hint_before);
            ((t.a - p.a) - (h.a - b.a))
                .abs()
                .max(((t.b - p.b) - (h.b - b.b)).abs())
                .max(((t.phi - p.phi) - (h.phi - b.phi)).abs())
        };
        if jump > MAX_TIP_JUMP
            || (trial.hinted && (off_prediction > HINT_RADIUS || off_hinted_step() > HINT_RADIUS))
            || trial.continued.as_ref().is_some_and(off)
            || (history.before().is_some() && off(&trial.predicted))
        {
            return Err(Stall::Jumped);
        }
        Ok(())
    }

    /// Newton only converges where the tangent stiffness is positive definite (it reports
    /// [`Corrected::Critical`] otherwise).
    fn regular(&self, _point: &Point) -> bool {
        true
    }

    /// A stall whose last attempt diverged or jumped is no critical point.
    fn near_critical(&mut self, _history: &History<Point>, _failure: &Stall) -> bool {
        false
    }

    fn report(&mut self, _lambda: f64, point: &mut Point, tally: Tally, _effort: &mut Effort) {
        // The continuation reports a point right after its Newton converged and it was
        // accepted (nothing between touches the workspace): the workspace is that Newton's.
        (self.visit)(PrbCase {
            load: point.load,
            tip: point.tip,
            q: &point.q,
            iterations: tally.iterations,
            work: Some(&self.ws),
        });
    }

    fn stop(&self, why: Stop<Stall>, fraction: f64, _effort: &Effort) -> PrbError {
        let no_equilibrium = |reason: &str| PrbError::NoEquilibrium {
            load: self.end,
            fraction,
            reason: reason.into(),
        };
        match why {
            Stop::Critical => PrbError::Unstable {
                load: self.end,
                fraction,
            },
            Stop::Stuck(Stall::Diverged) => no_equilibrium("Newton did not converge"),
            Stop::Stuck(Stall::Jumped) => {
                no_equilibrium("the equilibrium jumps away from the path")
            }
            // Neither is ever asked for: a PRB path has no cancel token and no budget.
            Stop::Cancelled => no_equilibrium("cancelled"),
            Stop::Attempts | Stop::Rejections => {
                no_equilibrium("the effort budget ran out before the load was reached")
            }
        }
    }
}
