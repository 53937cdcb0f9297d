//! One continuation driver for every equilibrium path in prbfit: the beam along a load path
//! (DESIGN §2), a PRB chain along a load path or through measured rows (§3, §9) and a
//! mechanism along a drive (§8), each followed from rest so that the solution stays on the
//! branch the physical system reaches, and a limit point or a bifurcation is reported, not
//! jumped over.
//!
//! # Method
//! A problem ([`PathProblem`]) is a state `u(lambda)` defined by equations at a path
//! parameter `lambda` in `[0, 1]` (`0`: unloaded, `1`: the end of the path), reported in
//! cases at `lambda = k / steps`. The driver ([`follow`]) walks from the unloaded state to
//! each case in sub-steps, each a predictor and a corrector:
//! - **predictor**: the secant through the last two accepted points,
//!   `u = u1 + t (u1 - u0)` with `t = (lambda - lambda1) / (lambda1 - lambda0)`; before there
//!   are two, the problem's tangent at the unloaded state (the beam's linear theory, or the
//!   unloaded state itself). A problem whose corrector can stop after one iteration when the
//!   prediction is close enough asks for [`Predictor::Quadratic`]: the parabola through the
//!   last three accepted points, `u = sum w_i u_i` with Lagrange's weights, whose error is
//!   `O(dlambda^3)` where the secant's is `O(dlambda^2)` (on a path of 1000 cases, 1e-9
//!   against 1e-6 of the state's scale: the beam's Newton then needs one shot a case); and
//!   [`Predictor::Cubic`], the cubic through the last four on a steady stretch (equal
//!   steps; the secant elsewhere), `O(dlambda^4)`, for a problem
//!   whose corrector stops at its first evaluation when the prediction meets the tolerance
//!   (a mechanism: its accepted points are then as close to the solution as its Newton
//!   would bring them, [`crate::mech`]);
//! - **corrector**: the problem's Newton iteration at the fixed `lambda`, at most
//!   [`Limits::newton_iterations`] iterations per attempt;
//! - **tests**: a converged point is accepted only on the branch followed (the problem's
//!   branch test: the tip may not jump, nor land far from the prediction) and on the
//!   unloaded state's side of every critical point (the problem's indicator: the sign of the
//!   beam's `dM(s)/dM(0)`, a PRB chain's positive definite tangent stiffness, the sign of the
//!   mechanism Jacobian's determinant);
//! - **step control**: a rejected attempt halves the step; an accepted one doubles it, up to
//!   a largest step and a cap the problem may set from how far the last step moved the
//!   state;
//! - **critical points**: a point past the indicator's sign change either ends the path at
//!   once, at the last accepted fraction ([`Crossing::Stop`]), or is rejected like a failed
//!   attempt, so that the step halves toward the crossing ([`Crossing::Bisect`]); a step
//!   halved below [`Limits::min_step`] after a crossing, or next to a collapsed indicator
//!   (a limit point, past which Newton finds no equilibrium on the branch), ends the path
//!   with the problem's critical-point error. A step halved that far anywhere else ends it
//!   with the problem's "no equilibrium" error and the corrector's last reason;
//! - **effort and cancel**: every case runs under a budget ([`Limits`]: attempts, rejected
//!   attempts, Newton iterations), and a [`CancelToken`] is read before every attempt;
//! - **warm start**: a problem may offer, for each case, a prediction from outside the path
//!   ([`PathProblem::hint`]: the same case of a fit's previous trial model). The driver tries
//!   it first, in one step to the case and with few Newton iterations, under the same tests;
//!   one that fails them is forgotten and the case is followed as without it. An accepted
//!   hint is a step of the path like any other, so it is as safe as the problem's branch
//!   test makes a one-step attempt (see the PRB chain's below).
//!
//! # Why each problem's numbers differ
//! Each problem passes its own [`Limits`], the numbers it was tuned and tested with; the
//! driver keeps every one, so no result changed when the three loops became this one.
//! - The **beam** (`crate::beam`): a shot integrates the whole beam, and a huge load's shape
//!   settles within the path's first millionths, so its smallest step (1e-7) shrinks with
//!   the load and with the fraction reached ([`Limits::min_step_relative`]); its first step
//!   comes from linear theory; its steps grow only as far as the tip's last motion allows
//!   ([`PathProblem::step_cap`]), as a rejected step costs a whole Newton solve; a rejected
//!   step halves the step *tried* ([`Halving::Tried`]: one clipped at a case would otherwise
//!   be retried unchanged). Newton may take 30 shots an attempt, and its effort budget
//!   (`EffortBudget`: attempts, shots, and integration steps counted by the beam itself)
//!   bounds a case to about a second of CPU. An unstable landing is tested first and
//!   bisected, so a buckling load is located to within the smallest step. It is the one
//!   problem a user cancels.
//! - The **PRB chain** (`crate::prb`): Newton on a handful of unknowns costs well under a
//!   microsecond, so it may take 40 iterations an attempt and needs no budget beyond the
//!   smallest step (1e-7; a fit's trial models give up at 1e-3, `SolverLimits`). Its
//!   indicator is evaluated inside Newton (the Cholesky factorisation of the tangent
//!   stiffness), and a failure there is bisected like the beam's unstable landing. A fit's
//!   trial chains are warm-started from the previous trial's equilibria (`prb::WarmStart`):
//!   the 20-case 3R fit's cases then take 3.1 Newton iterations where they took 4.
//! - The **mechanism** (`crate::mech`): a step never exceeds one case (its cases are the
//!   drive's own positions, sometimes measured rows), a step within `1e-12` of a case snaps
//!   onto it so that the last case carries the drive's own end values, and the step grows
//!   only after two successes in a row ([`Growth::AfterTwoSuccesses`]: a steep stretch is
//!   crossed at the step it allows instead of doubling into a rejection every other
//!   sub-step). Newton may take 25 iterations an attempt (12 for a fit's trial models),
//!   the smallest step is 1e-6 (1e-3), and 200 rejected attempts end a case that only
//!   crawls. Its Newton converges on both sides of a fold and the determinant's sign is read
//!   off the converged point, after the branch test (a jump may land where the sign means
//!   nothing): a sign change is bisected ([`Crossing::Bisect`]), as the beam's unstable
//!   landing is. Ending the path at the first sign change instead stopped a cantilever's
//!   3R, followed as the one-flexure mechanism, near an imperfect bifurcation (`alpha =
//!   (-5, 0.01, 0)` in four steps: a secant step landed on the unstable branch beside the
//!   stable one) where the chain's own path, with smaller steps, went on: the two must
//!   agree (`tests/mech.rs`). It offers no warm
//!   start: on the parallel stage (10 cases) a fit's previous trial saved no iteration over
//!   the secant (31 and 31), and its Newton stops at its residual tolerance, so a hinted case
//!   lands anywhere within it, not where continuation lands: the fit target's differenced
//!   Jacobian check went from 1.4e-8 to 3e-5 of its columns.
//!
//! # Accuracy
//! The driver adds no error of its own: an accepted point is the corrector's converged
//! solution at exactly the case's `lambda`. A critical point is reported at the last
//! accepted fraction: with [`Crossing::Bisect`] or at a stall, within about twice the
//! smallest step before it; with [`Crossing::Stop`], within one sub-step.

use crate::cancel::CancelToken;

mod history;
mod predict;
#[cfg(test)]
mod tests;

pub use history::History;
use predict::predict;
pub use predict::Predictor;

/// An accepted point of the path and its parameter.
#[derive(Debug, Clone)]
pub struct Accepted<P> {
    /// The path parameter, `0` (unloaded) to `1` (the path's end).
    pub lambda: f64,
    /// The problem's state there.
    pub point: P,
}

/// How a rejected attempt shortens the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Halving {
    /// Half the step actually tried (a step clipped at a case is shortened at once).
    Tried,
    /// Half the step size (a step clipped at a case is retried unchanged until the halving
    /// reaches below the distance to the case).
    Step,
}

/// When an accepted attempt lengthens the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Growth {
    /// After every accepted attempt.
    Always,
    /// Only after two accepted attempts in a row (the step that worked right after a
    /// rejection is kept).
    AfterTwoSuccesses,
}

/// Which test a converged point meets first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TestOrder {
    /// The critical-point indicator, then the branch test.
    IndicatorFirst,
    /// The branch test, then the critical-point indicator.
    BranchFirst,
}

/// What a converged point past a critical point (the indicator's sign has changed) does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Crossing {
    /// It ends the path at once: a critical point at the last accepted fraction.
    Stop,
    /// It is rejected like a failed attempt, so the step halves toward the critical point
    /// until it falls below the smallest step, where the stall reports the critical point:
    /// located to within the smallest step.
    Bisect,
}

/// A problem's numbers for the driver: steps, Newton iterations, and the effort one case may
/// take. See the module docs for why they differ between problems.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// The first step, as a fraction of the path.
    pub first_step: f64,
    /// The largest step.
    pub max_step: f64,
    /// The smallest step before the path is given up (or a critical point reported) ...
    pub min_step: f64,
    /// ... or this fraction of the path reached, if larger.
    pub min_step_relative: f64,
    /// A step ending within this of a case lands on the case.
    pub snap: f64,
    /// How a rejected attempt shortens the step.
    pub halving: Halving,
    /// When an accepted attempt lengthens the step.
    pub growth: Growth,
    /// Which test a converged point meets first.
    pub order: TestOrder,
    /// What a converged point past a critical point does.
    pub crossing: Crossing,
    /// How the next point is predicted.
    pub predictor: Predictor,
    /// Newton iterations one attempt may take (the corrector reads them from [`Effort`]).
    pub newton_iterations: u32,
    /// Attempts (accepted or rejected) one case may take; `None`: no limit.
    pub attempts_per_case: Option<u32>,
    /// Rejected attempts one case may have before the next attempt; `None`: no limit.
    pub rejections_per_case: Option<u32>,
    /// Newton iterations one case may take, all attempts counted; `None`: no limit.
    pub iterations_per_case: Option<u32>,
}

impl Limits {
    /// The simplest limits: a first step of one case, steps up to the whole path, halving
    /// the step size, growing after every success, the branch tested first, a critical
    /// point bisected, no effort budget.
    pub fn new(steps: u32, min_step: f64, newton_iterations: u32) -> Limits {
        Limits {
            first_step: 1.0 / steps.max(1) as f64,
            max_step: 1.0,
            min_step,
            min_step_relative: 0.0,
            snap: 0.0,
            halving: Halving::Step,
            growth: Growth::Always,
            order: TestOrder::BranchFirst,
            crossing: Crossing::Bisect,
            predictor: Predictor::Secant,
            newton_iterations,
            attempts_per_case: None,
            rejections_per_case: None,
            iterations_per_case: None,
        }
    }
}

/// The work spent on one case so far, and what the corrector may spend.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Effort {
    newton_iterations: u32,
    iteration_budget: Option<u32>,
    /// Attempts tried, the current one included.
    pub attempts: u32,
    /// Attempts rejected.
    pub rejections: u32,
    /// Newton iterations spent, over all attempts.
    pub iterations: u32,
}

impl Effort {
    /// A case's effort before its first attempt.
    pub fn new(limits: &Limits) -> Effort {
        Effort {
            newton_iterations: limits.newton_iterations,
            iteration_budget: limits.iterations_per_case,
            attempts: 0,
            rejections: 0,
            iterations: 0,
        }
    }

    /// Newton iterations one attempt may take.
    pub fn newton_limit(&self) -> u32 {
        self.newton_iterations
    }

    /// Counts one Newton iteration; `false` (and nothing counted) when the case's budget of
    /// iterations has run out.
    pub fn spend_iteration(&mut self) -> bool {
        if self.iteration_budget.is_some_and(|b| self.iterations >= b) {
            return false;
        }
        self.iterations += 1;
        true
    }
}

/// What one corrector attempt did.
#[derive(Debug, Clone, PartialEq)]
pub enum Corrected<F, E> {
    /// Newton converged in this many iterations; the point still meets the tests.
    Converged(u32),
    /// Newton failed: the step halves.
    Failed(F),
    /// Newton met the far side of a critical point (an indicator the corrector evaluates
    /// itself, like a Cholesky factorisation that fails): handled as [`Limits::crossing`]
    /// says.
    Critical,
    /// The path ends now with this error (cancelled inside the corrector, out of effort).
    Stop(E),
}

/// Why the driver ended a path early; the problem turns it into its own error.
#[derive(Debug, Clone, PartialEq)]
pub enum Stop<F> {
    /// The [`CancelToken`] was cancelled.
    Cancelled,
    /// A critical point: a point past the indicator's sign change ([`Crossing::Stop`]), a
    /// stall after one ([`Crossing::Bisect`]), or a stall next to a collapsed indicator.
    Critical,
    /// The step fell below the smallest, away from any sign of a critical point; the last
    /// attempt's failure.
    Stuck(F),
    /// The case's attempts ran out ([`Limits::attempts_per_case`]).
    Attempts,
    /// The case's rejected attempts ran out ([`Limits::rejections_per_case`]).
    Rejections,
}

/// One case's tally, handed to [`PathProblem::report`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tally {
    /// Which case, from 1.
    pub case: u32,
    /// Newton iterations of the attempts that converged (accepted or not).
    pub iterations: u32,
    /// Accepted sub-steps, the case's own included.
    pub accepted: u32,
}

/// An equilibrium path: a state, its corrector, its critical-point indicator and what it
/// reports per case. [`follow`] drives it.
pub trait PathProblem {
    /// The state at one point of the path, with whatever the tests read.
    type Point: Clone;
    /// Why one attempt failed (the step halves; the last one is reported if the path stalls).
    type Failure;
    /// Why the path ended early.
    type Error;

    /// The prediction a `step` along the path from the unloaded state `start`, before there
    /// is a secant (the first attempt, and its retries): written into `trial`.
    fn tangent(&self, start: &Self::Point, step: f64, trial: &mut Self::Point);

    /// The secant prediction `last + t (last - before)`, written into `trial`.
    fn secant(&self, last: &Self::Point, before: &Self::Point, t: f64, trial: &mut Self::Point);

    /// The prediction `sum weights[i] points[i]` (the weights sum to 1) of the last three
    /// points ([`Predictor::Quadratic`]) or four ([`Predictor::Cubic`]), latest first,
    /// written into `trial`; `false` if the problem has none or judges the polynomial
    /// untrustworthy here (the driver then takes the secant, whose `t` is `secant_t`).
    fn extrapolate(
        &self,
        _points: &[&Self::Point],
        _weights: &[f64],
        _secant_t: f64,
        _trial: &mut Self::Point,
    ) -> bool {
        false
    }

    /// Newton at `lambda` from the prediction in `trial`, leaving the solution there.
    /// Counts its iterations with [`Effort::spend_iteration`] and stops at
    /// [`Effort::newton_limit`].
    fn correct(
        &mut self,
        lambda: f64,
        history: &History<Self::Point>,
        trial: &mut Self::Point,
        effort: &mut Effort,
    ) -> Corrected<Self::Failure, Self::Error>;

    /// Whether a converged `trial` lies on the branch followed from `history`'s last point.
    fn on_branch(
        &self,
        history: &History<Self::Point>,
        trial: &Self::Point,
    ) -> Result<(), Self::Failure>;

    /// The critical-point indicator: whether `point` lies on the unloaded state's side of
    /// every critical point.
    fn regular(&self, point: &Self::Point) -> bool;

    /// At a stall (the step below the smallest): whether the last accepted point sits next
    /// to a critical point, judged by the indicator's collapse or by the last `failure`.
    fn near_critical(&mut self, history: &History<Self::Point>, failure: &Self::Failure) -> bool;

    /// The largest next step after `trial` was accepted from `last` by a step of `taken`
    /// (before the doubling's own limit): how far the step may grow given how far the state
    /// moved. No cap by default.
    fn step_cap(&self, last: &Self::Point, trial: &Self::Point, taken: f64) -> f64 {
        let _ = (last, trial, taken);
        f64::INFINITY
    }

    /// Called before each case's first attempt.
    fn begin_case(&mut self, history: &History<Self::Point>) {
        let _ = history;
    }

    /// A prediction of case `case`'s point (from 1) from outside the path, written into
    /// `trial`, and the Newton iterations its correction may take: the same case of a
    /// neighbouring problem already solved (a fit's previous trial model, whose equilibria
    /// move little with its parameters). The driver tries it first, in one step from the
    /// last accepted point to the case, under the same tests as any attempt; a hint whose
    /// correction does not converge in those iterations, or fails the tests, is forgotten,
    /// and the case is followed as without one. The hint's attempt and iterations count
    /// against the case's budget ([`Limits`]). Like any one-step attempt, it cannot see a
    /// critical point between the cases that the tests do not show at the case itself: the
    /// problem's branch test must be strict enough for the hints it gives. `None` (the
    /// default): no hint.
    fn hint(&mut self, case: u32, trial: &mut Self::Point) -> Option<u32> {
        let _ = (case, trial);
        None
    }

    /// Called for every accepted point.
    fn accepted(&mut self, point: &Self::Point) {
        let _ = point;
    }

    /// The case at `lambda` was reached at `point`. The problem may take what it keeps of the
    /// case out of `point` (its shape, say, instead of a copy): the path goes on from the
    /// point's unknowns and never reads the rest again.
    fn report(&mut self, lambda: f64, point: &mut Self::Point, tally: Tally, effort: &mut Effort);

    /// The error that ends the path at `fraction`, the last accepted point's parameter.
    fn stop(&self, why: Stop<Self::Failure>, fraction: f64, effort: &Effort) -> Self::Error;
}

/// Follows `problem` from `start` (the unloaded state, `lambda = 0`) to `lambda = 1`,
/// reporting the cases at `k / steps`, `k = 1..=steps` (at least one), in order. Stops at the
/// first case it cannot reach, with the problem's error (see the module docs).
pub fn follow<P: PathProblem>(
    problem: &mut P,
    start: P::Point,
    steps: u32,
    limits: &Limits,
    cancel: Option<&CancelToken>,
) -> Result<(), P::Error> {
    let steps = steps.max(1);
    let mut trial = start.clone();
    let mut history = History::new(start);
    let mut dlam = limits.first_step;
    // The last attempt was rejected (for `Growth::AfterTwoSuccesses`; kept across cases).
    let mut rejected = false;
    for k in 1..=steps {
        let target = k as f64 / steps as f64;
        let mut effort = Effort::new(limits);
        let mut tally = Tally {
            case: k,
            iterations: 0,
            accepted: 0,
        };
        problem.begin_case(&history);
        if let Some(newton_iterations) = problem.hint(k, &mut trial) {
            if cancel.is_some_and(CancelToken::is_cancelled) {
                return Err(problem.stop(Stop::Cancelled, history.last().lambda, &effort));
            }
            let mut hinted = Effort {
                newton_iterations: newton_iterations.min(limits.newton_iterations),
                ..effort
            };
            hinted.attempts += 1;
            let verdict = match problem.correct(target, &history, &mut trial, &mut hinted) {
                Corrected::Converged(iterations) => {
                    tally.iterations += iterations;
                    Some(judge(problem, limits.order, &history, &trial))
                }
                Corrected::Stop(e) => return Err(e),
                Corrected::Critical | Corrected::Failed(_) => None,
            };
            // The hint's work counts against the case's budget, accepted or not.
            effort.attempts = hinted.attempts;
            effort.iterations = hinted.iterations;
            if let Some(Verdict::Accepted) = verdict {
                // Accepted as a step of the path: the step grows as after any other, so a
                // case followed later without a hint starts from a step that reaches it.
                accept_step(
                    problem,
                    limits,
                    &mut history,
                    &mut trial,
                    target,
                    &mut dlam,
                    &mut rejected,
                );
                tally.accepted += 1;
                problem.report(target, &mut history.last_mut().point, tally, &mut effort);
                continue;
            }
        }
        loop {
            let from = history.last().lambda;
            if cancel.is_some_and(CancelToken::is_cancelled) {
                return Err(problem.stop(Stop::Cancelled, from, &effort));
            }
            if limits
                .attempts_per_case
                .is_some_and(|a| effort.attempts >= a)
            {
                return Err(problem.stop(Stop::Attempts, from, &effort));
            }
            if limits
                .rejections_per_case
                .is_some_and(|r| effort.rejections > r)
            {
                return Err(problem.stop(Stop::Rejections, from, &effort));
            }
            effort.attempts += 1;
            let lambda = if from + dlam >= target - limits.snap {
                target
            } else {
                from + dlam
            };
            // After a rejection the step is being halved toward trouble (a critical point, a
            // steep stretch), where a parabola overshoots: the secant bisects as it always has.
            let predictor = if rejected {
                Predictor::Secant
            } else {
                limits.predictor
            };
            predict(problem, predictor, &history, lambda, &mut trial);
            let failure = match problem.correct(lambda, &history, &mut trial, &mut effort) {
                Corrected::Converged(iterations) => {
                    tally.iterations += iterations;
                    match judge(problem, limits.order, &history, &trial) {
                        Verdict::Rejected(f) => Failure::Problem(f),
                        Verdict::Crossed => Failure::Crossed,
                        Verdict::Accepted => {
                            accept_step(
                                problem,
                                limits,
                                &mut history,
                                &mut trial,
                                lambda,
                                &mut dlam,
                                &mut rejected,
                            );
                            tally.accepted += 1;
                            if lambda >= target {
                                problem.report(
                                    lambda,
                                    &mut history.last_mut().point,
                                    tally,
                                    &mut effort,
                                );
                                break;
                            }
                            continue;
                        }
                    }
                }
                Corrected::Critical => Failure::Crossed,
                Corrected::Failed(f) => Failure::Problem(f),
                Corrected::Stop(e) => return Err(e),
            };
            if matches!(failure, Failure::Crossed) && limits.crossing == Crossing::Stop {
                return Err(problem.stop(Stop::Critical, from, &effort));
            }
            effort.rejections += 1;
            rejected = true;
            dlam = match limits.halving {
                Halving::Tried => 0.5 * (lambda - from),
                Halving::Step => 0.5 * dlam,
            };
            if dlam < limits.min_step.max(limits.min_step_relative * from) {
                let why = match failure {
                    Failure::Crossed => Stop::Critical,
                    Failure::Problem(f) if problem.near_critical(&history, &f) => Stop::Critical,
                    Failure::Problem(f) => Stop::Stuck(f),
                };
                return Err(problem.stop(why, from, &effort));
            }
        }
    }
    Ok(())
}

/// Accepts the converged `trial` at `lambda`, a step from the last accepted point: the
/// problem sees it, the history keeps it, and the next step `dlam` grows as the limits allow
/// (after every success, or only after two in a row: `rejected` says whether the last
/// attempt was) up to the problem's cap.
fn accept_step<P: PathProblem>(
    problem: &mut P,
    limits: &Limits,
    history: &mut History<P::Point>,
    trial: &mut P::Point,
    lambda: f64,
    dlam: &mut f64,
    rejected: &mut bool,
) {
    let taken = lambda - history.last().lambda;
    let cap = problem.step_cap(&history.last().point, trial, taken);
    problem.accepted(trial);
    history.accept(lambda, trial);
    if limits.growth == Growth::Always || !*rejected {
        *dlam = (2.0 * *dlam).min(cap).min(limits.max_step);
    }
    *rejected = false;
}

/// What the tests made of a converged point.
enum Verdict<F> {
    Accepted,
    Rejected(F),
    /// Past a critical point.
    Crossed,
}

/// Why an attempt was not accepted.
enum Failure<F> {
    /// The problem's reason.
    Problem(F),
    /// It crossed a critical point (and [`Crossing::Bisect`] goes on).
    Crossed,
}

/// The branch test and the critical-point indicator, in the problem's order.
fn judge<P: PathProblem>(
    problem: &P,
    order: TestOrder,
    history: &History<P::Point>,
    trial: &P::Point,
) -> Verdict<P::Failure> {
    let branch = |problem: &P| match problem.on_branch(history, trial) {
        Ok(()) => Verdict::Accepted,
        Err(f) => Verdict::Rejected(f),
    };
    match order {
        TestOrder::IndicatorFirst if !problem.regular(trial) => Verdict::Crossed,
        TestOrder::IndicatorFirst => branch(problem),
        TestOrder::BranchFirst => match branch(problem) {
            Verdict::Accepted if !problem.regular(trial) => Verdict::Crossed,
            verdict => verdict,
        },
    }
}
