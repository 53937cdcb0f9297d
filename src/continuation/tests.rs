//! The driver on a toy problem with a known fold: `x - x^3 / 3 = mu lambda`, followed from
//! `x = 0`. Its left side peaks at `2 / 3` (at `x = 1`, where `d/dx = 1 - x^2` vanishes), so
//! a path to `mu = 1` has a limit point at `lambda = 2 / 3` and no equilibrium on its branch
//! beyond; `mu = 1 / 2` has none.

use super::*;

/// The toy path, with knobs that force failures and a record of what the driver did.
struct Fold {
    mu: f64,
    /// Attempts whose step (from the last accepted point) exceeds this fail.
    fail_above: f64,
    /// Cancels this token once this many cases are reported.
    cancel_after: Option<(u32, CancelToken)>,
    /// Every attempt's `lambda`, in order.
    tried: Vec<f64>,
    /// Every case reported: `(lambda, x, tally)`.
    cases: Vec<(f64, f64, Tally)>,
    /// A warm start: a first guess per case.
    hints: Vec<f64>,
}

impl Fold {
    fn new(mu: f64) -> Fold {
        Fold {
            mu,
            fail_above: f64::INFINITY,
            cancel_after: None,
            tried: Vec::new(),
            cases: Vec::new(),
            hints: Vec::new(),
        }
    }
}

fn left(x: f64) -> f64 {
    x - x * x * x / 3.0
}

impl PathProblem for Fold {
    type Point = f64;
    type Failure = String;
    type Error = (Stop<String>, f64);

    fn tangent(&self, start: &f64, _step: f64, trial: &mut f64) {
        *trial = *start;
    }

    fn secant(&self, last: &f64, before: &f64, t: f64, trial: &mut f64) {
        *trial = last + t * (last - before);
    }

    fn hint(&mut self, case: u32, trial: &mut f64) -> Option<u32> {
        *trial = *self.hints.get(case as usize - 1)?;
        Some(6)
    }

    fn correct(
        &mut self,
        lambda: f64,
        history: &History<f64>,
        x: &mut f64,
        effort: &mut Effort,
    ) -> Corrected<String, Self::Error> {
        self.tried.push(lambda);
        if lambda - history.last().lambda > self.fail_above {
            return Corrected::Failed("forced".into());
        }
        for iteration in 1..=effort.newton_limit() {
            if !effort.spend_iteration() {
                return Corrected::Failed("out of iterations".into());
            }
            let update = (left(*x) - self.mu * lambda) / (1.0 - *x * *x);
            if !update.is_finite() {
                return Corrected::Failed("singular".into());
            }
            *x -= update;
            if update.abs() < 1e-13 {
                return Corrected::Converged(iteration);
            }
        }
        Corrected::Failed("Newton did not converge".into())
    }

    fn on_branch(&self, history: &History<f64>, x: &f64) -> Result<(), String> {
        if (x - history.last().point).abs() > 0.5 {
            return Err("jumped".into());
        }
        Ok(())
    }

    fn regular(&self, x: &f64) -> bool {
        1.0 - x * x > 0.0
    }

    fn near_critical(&mut self, history: &History<f64>, _failure: &String) -> bool {
        let x = history.last().point;
        1.0 - x * x < 0.01
    }

    fn report(&mut self, lambda: f64, x: &mut f64, tally: Tally, _effort: &mut Effort) {
        self.cases.push((lambda, *x, tally));
        if let Some((after, token)) = &self.cancel_after {
            if tally.case == *after {
                token.cancel();
            }
        }
    }

    fn stop(&self, why: Stop<String>, fraction: f64, _effort: &Effort) -> Self::Error {
        (why, fraction)
    }
}

const STEPS: u32 = 10;

/// The attempts' parameters, to rounding.
fn assert_close(tried: &[f64], want: &[f64]) {
    assert_eq!(tried.len(), want.len(), "{tried:?}");
    for (t, w) in tried.iter().zip(want) {
        assert!((t - w).abs() < 1e-12, "{tried:?} != {want:?}");
    }
}

fn limits() -> Limits {
    Limits::new(STEPS, 1e-7, 30)
}

#[test]
fn a_path_without_a_fold_reaches_its_end() {
    let mut toy = Fold::new(0.5);
    follow(&mut toy, 0.0, STEPS, &limits(), None).unwrap();
    assert_eq!(toy.cases.len(), STEPS as usize);
    for (k, (lambda, x, tally)) in toy.cases.iter().enumerate() {
        assert_eq!(*lambda, (k + 1) as f64 / STEPS as f64);
        assert!((left(*x) - 0.5 * lambda).abs() < 1e-12, "case {k}: x = {x}");
        assert_eq!(tally.case, k as u32 + 1);
        assert!(tally.accepted >= 1 && tally.iterations >= 1);
    }
}

#[test]
fn a_limit_point_is_bisected_and_reported_as_critical() {
    for order in [TestOrder::BranchFirst, TestOrder::IndicatorFirst] {
        let mut toy = Fold::new(1.0);
        let limits = Limits { order, ..limits() };
        let (why, fraction) = follow(&mut toy, 0.0, STEPS, &limits, None).unwrap_err();
        assert_eq!(why, Stop::Critical, "{order:?}");
        // Located to within the smallest step (and Newton's slow convergence next to it).
        assert!(
            fraction <= 2.0 / 3.0 && fraction > 2.0 / 3.0 - 1e-5,
            "{order:?}: {fraction}"
        );
        // Every case before the fold was reported, none after.
        assert_eq!(toy.cases.len(), 6, "{order:?}");
        assert!(toy.cases.iter().all(|c| c.1 < 1.0));
    }
}

#[test]
fn a_crossing_ends_the_path_at_once_when_asked() {
    // A path whose corrector reports every point past lambda = 0.45 as critical.
    struct Past(Fold);
    impl PathProblem for Past {
        type Point = f64;
        type Failure = String;
        type Error = (Stop<String>, f64);
        fn tangent(&self, start: &f64, step: f64, trial: &mut f64) {
            self.0.tangent(start, step, trial)
        }
        fn secant(&self, last: &f64, before: &f64, t: f64, trial: &mut f64) {
            self.0.secant(last, before, t, trial)
        }
        fn correct(
            &mut self,
            lambda: f64,
            history: &History<f64>,
            x: &mut f64,
            effort: &mut Effort,
        ) -> Corrected<String, Self::Error> {
            if lambda > 0.45 {
                self.0.tried.push(lambda);
                return Corrected::Critical;
            }
            self.0.correct(lambda, history, x, effort)
        }
        fn on_branch(&self, history: &History<f64>, x: &f64) -> Result<(), String> {
            self.0.on_branch(history, x)
        }
        fn regular(&self, x: &f64) -> bool {
            self.0.regular(x)
        }
        fn near_critical(&mut self, history: &History<f64>, failure: &String) -> bool {
            self.0.near_critical(history, failure)
        }
        fn report(&mut self, lambda: f64, x: &mut f64, tally: Tally, effort: &mut Effort) {
            self.0.report(lambda, x, tally, effort)
        }
        fn stop(&self, why: Stop<String>, fraction: f64, effort: &Effort) -> Self::Error {
            self.0.stop(why, fraction, effort)
        }
    }
    let run = |crossing| {
        let mut toy = Past(Fold::new(0.5));
        let limits = Limits {
            crossing,
            ..limits()
        };
        let err = follow(&mut toy, 0.0, STEPS, &limits, None).unwrap_err();
        (err, toy.0.tried.len())
    };
    // Stop: the first crossing (at 0.5, after the four cases before it) ends the path at
    // the last case, 0.4.
    let ((why, fraction), tried) = run(Crossing::Stop);
    assert_eq!((why, fraction, tried), (Stop::Critical, 0.4, 5));
    // Bisect: halved down to the smallest step next to 0.45.
    let ((why, fraction), tried) = run(Crossing::Bisect);
    assert_eq!(why, Stop::Critical);
    assert!(fraction <= 0.45 && fraction > 0.45 - 1e-6, "{fraction}");
    assert!(tried > 20, "{tried}");

    // A converged point past the fold (the indicator read off it) does the same: with the
    // indicator tested first, the far root x < -sqrt(3) that Newton finds past the fold is a
    // crossing, not a jump.
    let mut toy = Fold::new(1.0);
    let limits = Limits {
        order: TestOrder::IndicatorFirst,
        crossing: Crossing::Stop,
        ..limits()
    };
    let (why, fraction) = follow(&mut toy, 0.0, STEPS, &limits, None).unwrap_err();
    assert_eq!(why, Stop::Critical);
    assert!(fraction <= 2.0 / 3.0, "{fraction}");
}

#[test]
fn a_stall_away_from_a_fold_is_stuck_with_the_last_failure() {
    let mut toy = Fold::new(0.5);
    toy.fail_above = 0.0;
    let (why, fraction) = follow(&mut toy, 0.0, STEPS, &limits(), None).unwrap_err();
    assert_eq!(why, Stop::Stuck("forced".into()));
    assert_eq!(fraction, 0.0);
    // Halved from 0.1 until below 1e-7: 20 attempts.
    assert_eq!(toy.tried.len(), 20);
}

#[test]
fn halving_recovers_from_forced_failures() {
    let mut toy = Fold::new(0.5);
    toy.fail_above = 0.03;
    follow(&mut toy, 0.0, STEPS, &limits(), None).unwrap();
    assert_eq!(toy.cases.len(), STEPS as usize);
    let first = toy.cases[0].2;
    // 0.1 and 0.05 fail, 0.025 is accepted; then the step grows to 0.05 and fails again.
    assert_close(&toy.tried[..4], &[0.1, 0.05, 0.025, 0.075]);
    assert!(first.accepted >= 4, "{first:?}");
    for (lambda, x, _) in &toy.cases {
        assert!((left(*x) - 0.5 * lambda).abs() < 1e-12);
    }
}

#[test]
fn halving_the_tried_step_shortens_a_clipped_one_at_once() {
    let run = |halving| {
        let mut toy = Fold::new(0.5);
        toy.fail_above = 0.05;
        let limits = Limits {
            first_step: 0.8,
            halving,
            ..limits()
        };
        follow(&mut toy, 0.0, STEPS, &limits, None).unwrap();
        toy.tried[..5].to_vec()
    };
    // A first step of 0.8 is clipped at the first case, 0.1, and fails: halving the step
    // tried goes to 0.05 at once, halving the step size retries 0.1 until it is below 0.1.
    assert_close(&run(Halving::Tried), &[0.1, 0.05, 0.1, 0.2, 0.15]);
    assert_close(&run(Halving::Step), &[0.1, 0.1, 0.1, 0.1, 0.05]);
}

#[test]
fn growth_after_two_successes_keeps_the_step_that_worked() {
    let run = |growth| {
        let mut toy = Fold::new(0.5);
        toy.fail_above = 0.03;
        let limits = Limits { growth, ..limits() };
        follow(&mut toy, 0.0, STEPS, &limits, None).unwrap();
        toy.tried[..5].to_vec()
    };
    // 0.1 and 0.05 fail, 0.025 is accepted; doubling at once fails again at 0.075, waiting
    // for a second success reaches 0.05 first and only then tries a step of 0.05.
    assert_close(&run(Growth::Always), &[0.1, 0.05, 0.025, 0.075, 0.05]);
    assert_close(
        &run(Growth::AfterTwoSuccesses),
        &[0.1, 0.05, 0.025, 0.05, 0.1],
    );
}

#[test]
fn a_step_within_the_snap_lands_on_the_case() {
    let mut toy = Fold::new(0.5);
    let limits = Limits {
        first_step: 0.1 - 1e-13,
        snap: 1e-12,
        ..limits()
    };
    follow(&mut toy, 0.0, STEPS, &limits, None).unwrap();
    assert_eq!(toy.tried[0], 0.1);
}

#[test]
fn cancel_stops_the_path_before_the_next_attempt() {
    let token = CancelToken::new();
    let mut toy = Fold::new(0.5);
    toy.cancel_after = Some((3, token.clone()));
    let (why, fraction) = follow(&mut toy, 0.0, STEPS, &limits(), Some(&token)).unwrap_err();
    assert_eq!(why, Stop::Cancelled);
    assert_eq!(fraction, 0.3);
    assert_eq!(toy.cases.len(), 3);
    assert_eq!(toy.tried.len(), 3);

    // Cancelled before it starts: nothing is tried.
    let mut toy = Fold::new(0.5);
    let (why, fraction) = follow(&mut toy, 0.0, STEPS, &limits(), Some(&token)).unwrap_err();
    assert_eq!((why, fraction), (Stop::Cancelled, 0.0));
    assert!(toy.tried.is_empty());
}

#[test]
fn a_case_stops_when_its_effort_runs_out() {
    let budgets = [
        (
            Limits {
                attempts_per_case: Some(3),
                ..limits()
            },
            Stop::Attempts,
            3,
        ),
        (
            Limits {
                rejections_per_case: Some(3),
                ..limits()
            },
            Stop::Rejections,
            4,
        ),
    ];
    for (limits, stop, tried) in budgets {
        let mut toy = Fold::new(0.5);
        toy.fail_above = 0.0;
        let (why, fraction) = follow(&mut toy, 0.0, STEPS, &limits, None).unwrap_err();
        assert_eq!((why, fraction), (stop, 0.0));
        assert_eq!(toy.tried.len(), tried);
    }
    // Newton iterations per case: one attempt's worth and no more.
    let mut toy = Fold::new(0.5);
    let limits = Limits {
        iterations_per_case: Some(2),
        ..limits()
    };
    let (why, _) = follow(&mut toy, 0.0, STEPS, &limits, None).unwrap_err();
    assert_eq!(why, Stop::Stuck("out of iterations".into()));
}

#[test]
fn the_newton_limit_reaches_the_corrector() {
    let mut toy = Fold::new(0.5);
    let limits = Limits::new(STEPS, 1e-7, 1);
    let (why, _) = follow(&mut toy, 0.0, STEPS, &limits, None).unwrap_err();
    assert_eq!(why, Stop::Stuck("Newton did not converge".into()));
}

/// The cases of a plain run of `mu` (to `STEPS`), as `(lambda, x)`.
fn plain_cases(mu: f64) -> Vec<(f64, f64)> {
    let mut fold = Fold::new(mu);
    follow(&mut fold, 0.0, STEPS, &limits(), None).unwrap();
    fold.cases.iter().map(|&(l, x, _)| (l, x)).collect()
}

/// A warm start from a neighbouring problem's cases (`mu` 0.49 for 0.5): every case is
/// tried once, at its own fraction from the hint, and lands on the plain run's equilibrium
/// (to Newton's tolerance).
#[test]
fn good_hints_reach_each_case_in_one_attempt() {
    let plain = plain_cases(0.5);
    let mut fold = Fold::new(0.5);
    fold.hints = plain_cases(0.49).iter().map(|&(_, x)| x).collect();
    follow(&mut fold, 0.0, STEPS, &limits(), None).unwrap();
    let fractions: Vec<f64> = (1..=STEPS).map(|k| k as f64 / STEPS as f64).collect();
    assert_close(&fold.tried, &fractions);
    assert_eq!(fold.cases.len(), plain.len());
    for (&(l, x, tally), &(pl, px)) in fold.cases.iter().zip(&plain) {
        assert_eq!(l, pl);
        assert!((x - px).abs() < 1e-12, "{x} against {px}");
        assert_eq!(tally.accepted, 1);
    }
}

/// Hints on another branch (the equilibria near `x = -2`, where `x - x^3/3 = mu lambda`
/// also holds for small loads) converge there, fail the branch test and are forgotten:
/// the cases are the plain run's, each after one wasted attempt.
#[test]
fn hints_off_the_branch_are_forgotten() {
    let plain = plain_cases(0.5);
    let mut fold = Fold::new(0.5);
    fold.hints = vec![-1.9; STEPS as usize];
    follow(&mut fold, 0.0, STEPS, &limits(), None).unwrap();
    assert_eq!(fold.cases.len(), plain.len());
    for (&(_, x, _), &(_, px)) in fold.cases.iter().zip(&plain) {
        assert!((x - px).abs() < 1e-12, "{x} against {px}");
    }
    // Each case tried its hint first.
    assert!(fold.tried.len() >= 2 * STEPS as usize, "{:?}", fold.tried);
}

/// Hints past the fold (`mu = 1`: the branch ends at `lambda = 2/3`; hints at `x = 1.2`,
/// where the indicator has changed sign) are rejected as crossings: the path still ends
/// at the critical point, as it does without them.
#[test]
fn hints_past_a_critical_point_do_not_hide_it() {
    let mut plain = Fold::new(1.0);
    let want = follow(&mut plain, 0.0, STEPS, &limits(), None).unwrap_err();
    let mut fold = Fold::new(1.0);
    fold.hints = vec![1.2; STEPS as usize];
    let got = follow(&mut fold, 0.0, STEPS, &limits(), None).unwrap_err();
    assert!(matches!(got.0, Stop::Critical), "{got:?}");
    assert!((got.1 - want.1).abs() < 1e-6, "{got:?} against {want:?}");
    assert_eq!(fold.cases.len(), plain.cases.len());
}

/// A path whose state is a cubic in `lambda`, `x = c(lambda)`, recording each prediction the
/// driver hands its corrector.
struct Cubic {
    /// Every attempt's `(lambda, prediction)`.
    predicted: Vec<(f64, f64)>,
}

fn cubic(lambda: f64) -> f64 {
    2.0 * lambda * lambda * lambda - 3.0 * lambda * lambda + 0.5 * lambda
}

impl PathProblem for Cubic {
    type Point = f64;
    type Failure = String;
    type Error = Stop<String>;

    fn tangent(&self, start: &f64, _step: f64, trial: &mut f64) {
        *trial = *start;
    }

    fn secant(&self, last: &f64, before: &f64, t: f64, trial: &mut f64) {
        *trial = last + t * (last - before);
    }

    fn extrapolate(&self, points: &[&f64], weights: &[f64], _t: f64, trial: &mut f64) -> bool {
        *trial = points.iter().zip(weights).map(|(p, w)| *p * w).sum();
        true
    }

    fn correct(
        &mut self,
        lambda: f64,
        _history: &History<f64>,
        x: &mut f64,
        effort: &mut Effort,
    ) -> Corrected<String, Self::Error> {
        self.predicted.push((lambda, *x));
        effort.spend_iteration();
        *x = cubic(lambda);
        Corrected::Converged(1)
    }

    fn on_branch(&self, _history: &History<f64>, _x: &f64) -> Result<(), String> {
        Ok(())
    }

    fn regular(&self, _x: &f64) -> bool {
        true
    }

    fn near_critical(&mut self, _history: &History<f64>, _failure: &String) -> bool {
        false
    }

    fn report(&mut self, _lambda: f64, _x: &mut f64, _tally: Tally, _effort: &mut Effort) {}

    fn stop(&self, why: Stop<String>, _fraction: f64, _effort: &Effort) -> Self::Error {
        why
    }
}

/// Each predictor's error on a cubic path: the cubic through the last four points (the
/// unloaded start among them) is exact from the fourth attempt on (the first three come from
/// the tangent and the secant), where
/// the parabola's is `c''' / 3! (3 h) (2 h) h = 12 h^3`, 0.012 at the steps of `h = 1/10`:
/// neither can pass for the other.
#[test]
fn the_cubic_predictor_is_exact_on_a_cubic_path() {
    let error_from_fourth = |predictor| {
        let mut path = Cubic {
            predicted: Vec::new(),
        };
        let limits = Limits {
            predictor,
            ..Limits::new(STEPS, 1e-7, 30)
        };
        follow(&mut path, 0.0, STEPS, &limits, None).unwrap();
        assert_eq!(path.predicted.len(), STEPS as usize);
        path.predicted[3..]
            .iter()
            .map(|&(lambda, x)| (x - cubic(lambda)).abs())
            .fold(0.0_f64, f64::max)
    };
    let cubic_error = error_from_fourth(Predictor::Cubic);
    let parabola_error = error_from_fourth(Predictor::Quadratic);
    assert!(cubic_error < 1e-14, "cubic: {cubic_error:e}");
    assert!(
        (parabola_error - 0.012).abs() < 1e-12,
        "parabola: {parabola_error:e}"
    );
}

/// The history keeps the last four accepted points, newest first, whatever number were
/// accepted, and each acceptance hands the trial the storage of the point it forgets (a
/// clone of the point that was last while fewer than four are kept).
#[test]
fn the_history_keeps_the_last_four_points_and_recycles_the_fifth() {
    let mut history = History::new(vec![0.0]);
    let mut trial = vec![f64::NAN];
    for k in 1..=7 {
        let x = k as f64;
        trial[0] = x * 10.0;
        history.accept(x, &mut trial);
        let kept: Vec<(f64, f64)> = (0..4)
            .map_while(|back| history.back(back))
            .map(|a| (a.lambda, a.point[0]))
            .collect();
        let expected: Vec<(f64, f64)> = (0..=k)
            .rev()
            .take(4)
            .map(|j| (j as f64, j as f64 * 10.0))
            .collect();
        assert_eq!(kept, expected, "after {k} accepted");
        assert_eq!(history.last().lambda, x);
        assert_eq!(history.before().map(|b| b.lambda), Some(x - 1.0));
        assert_eq!(
            history.oldest().map(|a| a.lambda),
            (k >= 2).then_some(x - 2.0)
        );
        assert_eq!(
            history.eldest().map(|a| a.lambda),
            (k >= 3).then_some(x - 3.0)
        );
        // The trial's storage: the forgotten point's once four are kept, else a clone of the
        // point that was last.
        let spare = if k >= 4 {
            (x - 4.0) * 10.0
        } else {
            (x - 1.0) * 10.0
        };
        assert_eq!(trial[0], spare, "after {k} accepted");
    }
}
