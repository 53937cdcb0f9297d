//! Levenberg-Marquardt for the fit's least-squares form, `J = |r(p)|^2`, on the residuals'
//! exact Jacobian where the target gives it (by the implicit function theorem through each
//! case's equilibrium, a cantilever's chain or a mechanism:
//! [`super::Target::residuals_with_cells`]), else on forward differences.
//!
//! Written here rather than taken from a crate because the fit needs three things a general
//! solver does not give together: a residual function that may refuse (cancellation) at any
//! call, finite penalties for parameter sets whose PRB model cannot follow the loads (steps
//! into them are simply rejected), and a per-iteration hook for progress. The problem is
//! tiny (a dozen parameters, a few hundred residuals), so normal equations with Marquardt's
//! diagonal scaling are accurate enough and cheapest.
//!
//! With the exact Jacobian an iteration costs one evaluation per trial step; differencing
//! adds one per parameter (the 3R fit of the built-in scene at draft: 71 evaluations against
//! 305).
//!
//! On the exact Jacobian the damping follows Nielsen's rule (the gain ratio of each accepted
//! step sets the next damping; rejections in a row grow it 2, 4, 8... times, so a run that no
//! step helps stalls after about a dozen rejections where times 4 took about 25): the 20-case 3R
//! fit at draft takes 20 evaluations where dividing by 3 on success and multiplying by 4 on
//! failure took 26, to the same `J`. Over the example scenes (14 scenes; `L-R`, `L-R-R`,
//! `L-R-R-R`, `L-RP-RP-RP`) it takes 1484 evaluations where that took 1802 for 53 draft
//! fits, and 14474 where it took 16384 for 39 normal ones. `J` is within 0.1 % on 37 and 27
//! of them, lower on 9 and 9, higher on 7 and 3 (a different path to a different stop on a
//! flat valley, or below the floor where the errors are a negligible part of the targets),
//! and every fit meets or misses its targets as before. On
//! differences (a dynamic fit, whose masses have no exact derivatives) it keeps divide-by-3
//! and times-4: there the model's predicted decrease carries the differencing error, and the
//! ringing flexure's staged fit with two modes (`tests/dynamic_fit.rs`), whose trial steps
//! keep falling off the penalty cliff of models that cannot follow the loads, stalled under
//! Nielsen's rule at `J` 1.3e-3 with a 2.8 % frequency error where this reaches 2.7e-7.
//!
//! On the exact Jacobian a run may also stop after one small step, where the Gauss-Newton
//! model (`g^T A^-1 g`, the decrease a full undamped step would give) predicts less than
//! `gain_tol` of `J` still to gain ([`LmOptions::gain_tol`]; draft's setting, inert in a
//! staged dynamic fit's last stage, which borrows draft's tolerances but differences). Where
//! the residuals do not vanish at the optimum, as a PRB model's against its beam do not, the
//! model over-predicts near the optimum (the scipy job's fit: gain ratios 0.2-0.6 in its last
//! steps; 9.7e-4 of `J` predicted where 4.0e-4 was left), so it is a cautious judge of what
//! is left; where they go to zero every late step removes most of what is left and the rule
//! never fires.
//!
//! A differenced run that stops on small steps far above its floor (more than 100 times it)
//! goes on once more with differences of `1e-5` where they were `1e-7`. Such a stop is where
//! two of the model's frequencies meet: `J` pairs the first N in order, so it has a kink
//! there, differences at `1e-7` see one side of it, and the damped steps crawl along it. The
//! ringing flexure's staged fit with two modes (`tests/dynamic_fit.rs`) stopped so at `J`
//! 7.0e-3 (modes 2 and 3 at 640.71985 and 640.71989 Hz, mode 2 11 % low) once the normal
//! equations were summed in another order, where it had reached 7.6e-8 by the luck of the
//! last bits (with base steps of 5e-8 to 1e-5 it passed in either order). With the wider
//! differences it reaches 2.7e-7 (frequencies within 4e-5), and 5.5e-8 to 7.3e-8 with base
//! steps of 3e-8 to 1e-6.
//!
//! The normal equations are summed here, in the residuals' order, so they come out the same
//! on every processor; nalgebra's product handed them to
//! `matrixmultiply`, whose kernel (and order of summation) is chosen by the processor's
//! features at run time, and whose first call enumerated them all (26-33 us of `cpuid` traps
//! on a virtual machine, a tenth of the 20-case 3R fit's own time in the command).
//!
//! ## References
//! - D. W. Marquardt, "An algorithm for least-squares estimation of nonlinear parameters",
//!   SIAM J. Appl. Math. 11 (1963) 431-441.
//! - H. B. Nielsen, "Damping parameter in Marquardt's method", IMM-REP-1999-05, Technical
//!   University of Denmark (1999); K. Madsen, H. B. Nielsen, O. Tingleff, "Methods for
//!   non-linear least squares problems", 2nd ed., IMM DTU (2004), §3.2.

use nalgebra::{DMatrix, DVector};

/// When to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmOptions {
    /// Stop when an accepted step lowers J by less than this fraction.
    pub ftol: f64,
    /// Stop as converged once J is at or below this ([`super::Target::objective_floor`]: the
    /// errors are then a negligible part of the targets); 0 never stops on J alone.
    pub floor: f64,
    /// Stop when a step moves no parameter by more than this.
    pub xtol: f64,
    /// On the exact Jacobian only (a differenced step resets it): stop as converged when the
    /// last accepted step lowered `J` by less than this fraction and the undamped
    /// Gauss-Newton model predicts that a full step from there would lower it by less than
    /// this fraction more: one small step, confirmed by the model, where `ftol` waits for a
    /// second (see the module). 0: never.
    pub gain_tol: f64,
    /// Most iterations (accepted steps, each with its Jacobian) before the run gives up with
    /// [`LmStop::IterationLimit`].
    pub max_iterations: u32,
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LmStop {
    /// Two accepted steps in a row were small (below `ftol` or `xtol`), or one was and the
    /// Gauss-Newton model predicts little more (`gain_tol`), or `J` reached the floor, or
    /// there is no parameter to move.
    Converged,
    /// `max_iterations` ran out before the run converged.
    IterationLimit,
    /// No step direction lowers J any more (the damping ran away).
    Stalled,
    /// The residual function refused (the fit was cancelled); the result is the last accepted
    /// point.
    Cancelled,
}

/// The result of a run.
#[derive(Debug, Clone)]
pub struct LmResult {
    /// The last accepted parameter vector (the start if no step was accepted).
    pub p: DVector<f64>,
    /// `J = |r(p)|^2` at `p` (infinite if cancelled before the first evaluation).
    pub objective: f64,
    /// Iterations begun, the last included.
    pub iterations: u32,
    /// Why the run ended.
    pub stop: LmStop,
    /// The residuals at `p` and their Jacobian, as the run last evaluated them (none if
    /// cancelled before the first evaluation): a run continuing from `p`
    /// ([`minimise_from`]) starts with them instead of evaluating `p` again.
    pub evaluation: Option<Evaluated>,
}

/// The residuals at a point and their Jacobian there, from one evaluation.
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// `r(p)`.
    pub residuals: Vec<f64>,
    /// `d r / d p`, meaningful only when `exact` (a run without it differences).
    pub jacobian: DMatrix<f64>,
    /// Whether the evaluation gave the Jacobian exactly.
    pub exact: bool,
}

/// One evaluation of the residuals at `p`: fills `out`, and the Jacobian `d r / d p` (`m`
/// x `n`) when it has it exactly. `Some(true)`: both filled; `Some(false)`: the residuals
/// only (the run then takes forward differences); `None`: cancelled.
pub type Residuals<'a> =
    dyn FnMut(&DVector<f64>, &mut Vec<f64>, &mut DMatrix<f64>) -> Option<bool> + 'a;

/// Minimises `|r(p)|^2` from `p0`. `residuals` (see [`Residuals`]) gives the Jacobian
/// itself where it can, else the run differences it; `on_iteration(iteration, objective,
/// p)` runs after every accepted step.
pub fn minimise(
    p0: DVector<f64>,
    options: LmOptions,
    residuals: &mut Residuals<'_>,
    on_iteration: &mut dyn FnMut(u32, f64, &DVector<f64>),
) -> LmResult {
    minimise_from(p0, None, options, residuals, on_iteration)
}

/// [`minimise`] from `p0` whose residuals and Jacobian `at_p0` are already known (the end
/// of an earlier run: [`LmResult::evaluation`]), so the run does not evaluate `p0` again.
pub fn minimise_from(
    p0: DVector<f64>,
    at_p0: Option<Evaluated>,
    options: LmOptions,
    residuals: &mut Residuals<'_>,
    on_iteration: &mut dyn FnMut(u32, f64, &DVector<f64>),
) -> LmResult {
    let n = p0.len();
    let mut p = p0;
    // The residuals and Jacobian at `p`, and at the last trial (kept when it is accepted).
    let mut trial_jac = DMatrix::<f64>::zeros(0, 0);
    let (mut r, mut jac, mut exact) = match at_p0 {
        Some(e) => (e.residuals, e.jacobian, e.exact),
        None => {
            let mut r = Vec::new();
            let mut jac = DMatrix::<f64>::zeros(0, 0);
            let Some(exact) = residuals(&p, &mut r, &mut jac) else {
                return LmResult {
                    p,
                    objective: f64::INFINITY,
                    iterations: 0,
                    stop: LmStop::Cancelled,
                    evaluation: None,
                };
            };
            (r, jac, exact)
        }
    };
    // Every return below hands back the evaluation at `p`.
    let finish = |p, objective, iterations, stop, residuals, jacobian, exact| LmResult {
        p,
        objective,
        iterations,
        stop,
        evaluation: Some(Evaluated {
            residuals,
            jacobian,
            exact,
        }),
    };
    let m = r.len();
    let mut objective = sum_sq(&r);
    if n == 0 {
        return finish(p, objective, 0, LmStop::Converged, r, jac, exact);
    }
    let mut trial = Vec::with_capacity(m);
    // The relative decrease of the last accepted step on the exact Jacobian (none yet).
    let mut last_decrease: Option<f64> = None;
    let mut lambda = 1e-3;
    // Nielsen's growth factor for a rejected step: doubles with every rejection in a row.
    let mut nu = 2.0;
    let mut small_steps = 0;
    // Forward differences' relative step: `WIDE_FD_STEP` once a run stalls (see the module).
    let mut fd_step = 1e-7;
    for iteration in 1..=options.max_iterations {
        if !exact {
            // Forward differences, step relative to the parameter's size.
            if jac.shape() != (m, n) {
                jac = DMatrix::zeros(m, n);
            }
            for j in 0..n {
                let h = fd_step * (1.0 + p[j].abs());
                let mut q = p.clone();
                q[j] += h;
                if residuals(&q, &mut trial, &mut trial_jac).is_none() {
                    return finish(p, objective, iteration, LmStop::Cancelled, r, jac, exact);
                }
                for i in 0..m {
                    jac[(i, j)] = (trial[i] - r[i]) / h;
                }
            }
        }
        let (a, g) = normal_equations(&jac, &r);
        let small = last_decrease.is_some_and(|d| d < options.gain_tol);
        if exact && small {
            if let Some(gain) = gauss_newton_gain(&a, &g) {
                if gain < options.gain_tol * objective {
                    return finish(p, objective, iteration, LmStop::Converged, r, jac, exact);
                }
            }
        }
        loop {
            let mut damped = a.clone();
            for j in 0..n {
                damped[(j, j)] += lambda * (a[(j, j)] + 1e-12);
            }
            let Some(step) = damped.cholesky().map(|c| c.solve(&(-&g))) else {
                lambda *= 10.0;
                if lambda > 1e12 {
                    return finish(p, objective, iteration, LmStop::Stalled, r, jac, exact);
                }
                continue;
            };
            let q = &p + &step;
            let Some(trial_exact) = residuals(&q, &mut trial, &mut trial_jac) else {
                return finish(p, objective, iteration, LmStop::Cancelled, r, jac, exact);
            };
            let new_objective = sum_sq(&trial);
            if new_objective < objective {
                let decrease = (objective - new_objective) / objective.max(f64::MIN_POSITIVE);
                let moved = step.amax();
                p = q;
                std::mem::swap(&mut r, &mut trial);
                if trial_exact {
                    std::mem::swap(&mut jac, &mut trial_jac);
                }
                // The damping: Nielsen's where the step came from the exact Jacobian, whose
                // model's predicted decrease the gain ratio trusts; divided by 3 on a
                // differenced one (a dynamic fit near its penalty cliff: see the module).
                lambda = if exact {
                    nielsen_damping(lambda, &step, &a, &g, objective - new_objective)
                } else {
                    lambda / 3.0
                }
                .max(1e-12);
                last_decrease = (exact && trial_exact).then_some(decrease);
                nu = 2.0;
                exact = trial_exact;
                objective = new_objective;
                on_iteration(iteration, objective, &p);
                if objective <= options.floor {
                    return finish(p, objective, iteration, LmStop::Converged, r, jac, exact);
                }
                // Two small steps in a row: converged.
                if decrease < options.ftol || moved < options.xtol {
                    small_steps += 1;
                    if small_steps >= 2 {
                        // On differences, far above the floor: a stall on a kink (see the
                        // module); once more with wide differences.
                        let stalled = objective > STALL_ABOVE_FLOOR * options.floor;
                        if !exact && fd_step < WIDE_FD_STEP && stalled {
                            fd_step = WIDE_FD_STEP;
                            small_steps = 0;
                            lambda = 1e-3;
                            nu = 2.0;
                            break;
                        }
                        return finish(p, objective, iteration, LmStop::Converged, r, jac, exact);
                    }
                } else {
                    small_steps = 0;
                }
                break;
            }
            if exact {
                lambda *= nu;
                nu *= 2.0;
            } else {
                lambda *= 4.0;
            }
            if lambda > 1e12 {
                // No direction helps: a minimum to the accuracy the residuals allow.
                return finish(p, objective, iteration, LmStop::Stalled, r, jac, exact);
            }
        }
    }
    finish(
        p,
        objective,
        options.max_iterations,
        LmStop::IterationLimit,
        r,
        jac,
        exact,
    )
}

/// The relative difference step of a differenced run that stalled far above its floor
/// (see the module): wide enough to span a kink where two frequencies meet, and with `J`'s
/// residuals smooth to rounding (their difference quotients settle by a step of 1e-12) still
/// a Jacobian good to about 1e-5, which steers the steps without deciding where they end.
const WIDE_FD_STEP: f64 = 1e-5;
/// How far above its floor a differenced run's stop on small steps is taken for a stall.
/// Two decades: a fit that cannot reach its floor (most dynamic fits) pays one differenced
/// Jacobian and a few steps more.
const STALL_ABOVE_FLOOR: f64 = 100.0;

/// The Gauss-Newton normal equations' `A = J^T J` and `g = J^T r`, each entry summed over the
/// residuals in their order (see the module).
fn normal_equations(jac: &DMatrix<f64>, r: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let (m, n) = jac.shape();
    let column = |j: usize| &jac.as_slice()[j * m..(j + 1) * m];
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).fold(0.0, |acc, (a, b)| acc + a * b);
    let mut a = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in 0..=i {
            let v = dot(column(i), column(j));
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
    let g = DVector::from_fn(n, |j, _| dot(column(j), r));
    (a, g)
}

/// Nielsen's damping after an accepted step `h` that lowered `J` by `decrease`: the gain
/// ratio `rho` of that decrease to the one the damped Gauss-Newton model predicted
/// (`lambda h^T D h - g^T h`, positive, with `D` the Marquardt scaling `diag(A) + 1e-12` the
/// step was solved with) sets it, so a step the model predicted well is followed by a bolder
/// one and a poor one by a more cautious one: `lambda max(1/3, 1 - (2 rho - 1)^3)`, up to
/// twice `lambda`.
fn nielsen_damping(
    lambda: f64,
    step: &DVector<f64>,
    a: &DMatrix<f64>,
    g: &DVector<f64>,
    decrease: f64,
) -> f64 {
    let scaled: f64 = (0..step.len())
        .map(|j| step[j] * step[j] * (a[(j, j)] + 1e-12))
        .sum();
    let predicted = lambda * scaled - step.dot(g);
    let rho = if predicted > 0.0 {
        decrease / predicted
    } else {
        1.0
    };
    lambda * (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0)
}

/// What a full Gauss-Newton step from here would lower `J` by, by the model:
/// `g^T (A + 1e-12 D)^-1 g` (the tiny Marquardt term keeps a parameter the residuals do not
/// see from making `A` singular); `None` if even that cannot be factored.
fn gauss_newton_gain(a: &DMatrix<f64>, g: &DVector<f64>) -> Option<f64> {
    let mut undamped = a.clone();
    for j in 0..a.nrows() {
        undamped[(j, j)] += 1e-12 * (a[(j, j)] + 1e-12);
    }
    let step = undamped.cholesky()?.solve(g);
    Some(step.dot(g)).filter(|v| v.is_finite())
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The normal equations against nalgebra's products: equal to rounding, `A` exactly
    /// symmetric, and `g` in the residuals' order to the bit. Each entry sums 37 products
    /// below 20.25 in size (entries below 4.5): two orders of summation differ by at most
    /// `2 * 37 * eps * 750`, 1.2e-11.
    #[test]
    fn the_normal_equations_are_the_products() {
        let (m, n) = (37, 6);
        let jac = DMatrix::from_fn(m, n, |i, j| ((i * 7 + j * 13) % 17) as f64 / 1.7 - 4.5);
        let r: Vec<f64> = (0..m).map(|i| (i as f64 * 0.37).sin() * 3.0).collect();
        let (a, g) = normal_equations(&jac, &r);
        let a_ref = jac.transpose() * &jac;
        let g_ref = jac.transpose() * DVector::from_column_slice(&r);
        assert!((&a - &a_ref).amax() <= 1.2e-11, "{a} vs {a_ref}");
        assert!((&g - &g_ref).amax() <= 1.2e-11, "{g} vs {g_ref}");
        assert_eq!(a, a.transpose());
        let g1: f64 = (0..m).fold(0.0, |acc, i| acc + jac[(i, 1)] * r[i]);
        assert_eq!(g[1], g1);
    }

    /// A residual function without a Jacobian (the run differences it), from one that
    /// returns false to cancel.
    fn plain(
        mut f: impl FnMut(&DVector<f64>, &mut Vec<f64>) -> bool,
    ) -> impl FnMut(&DVector<f64>, &mut Vec<f64>, &mut DMatrix<f64>) -> Option<bool> {
        move |p, out, _| f(p, out).then_some(false)
    }

    /// Rosenbrock's residuals with their exact Jacobian, counting evaluations.
    fn rosenbrock_exact(
        calls: &mut u32,
    ) -> impl FnMut(&DVector<f64>, &mut Vec<f64>, &mut DMatrix<f64>) -> Option<bool> + '_ {
        move |p, out, jac| {
            *calls += 1;
            out.clear();
            out.push(10.0 * (p[1] - p[0] * p[0]));
            out.push(1.0 - p[0]);
            *jac = DMatrix::from_row_slice(2, 2, &[-20.0 * p[0], 10.0, -1.0, 0.0]);
            Some(true)
        }
    }

    /// Given the exact Jacobian the run uses it: the same minimum, with one evaluation per
    /// trial step instead of one per parameter more each iteration.
    #[test]
    fn an_exact_jacobian_is_used_instead_of_differences() {
        let opts = LmOptions {
            ftol: 1e-14,
            xtol: 1e-12,
            gain_tol: 0.0,
            max_iterations: 200,
            floor: 0.0,
        };
        let start = DVector::from_vec(vec![-1.2, 1.0]);
        let mut exact_calls = 0;
        let exact = minimise(
            start.clone(),
            opts,
            &mut rosenbrock_exact(&mut exact_calls),
            &mut |_, _, _| {},
        );
        let mut plain_calls = 0;
        let differenced = minimise(
            start,
            opts,
            &mut plain(|p, out| {
                plain_calls += 1;
                out.clear();
                out.push(10.0 * (p[1] - p[0] * p[0]));
                out.push(1.0 - p[0]);
                true
            }),
            &mut |_, _, _| {},
        );
        for run in [&exact, &differenced] {
            assert!((run.p[0] - 1.0).abs() < 1e-6 && (run.p[1] - 1.0).abs() < 1e-6);
        }
        // A differenced iteration spends 2 evaluations on its Jacobian and at least one on
        // its trial step (3 or more); the exact run (whose damping differs: Nielsen's)
        // spends none on differences, so fewer than 3 an iteration on average.
        let report = format!(
            "exact {exact_calls} evaluations in {} iterations, differenced {plain_calls} in {}",
            exact.iterations, differenced.iterations
        );
        assert!(exact_calls < 1 + 3 * exact.iterations, "{report}");
    }

    /// A run continued from where another stopped, with that run's last evaluation, takes
    /// the same path as one that evaluates the point again, one evaluation fewer.
    #[test]
    fn a_continued_run_reuses_the_last_evaluation() {
        let opts = |max_iterations| LmOptions {
            ftol: 1e-14,
            xtol: 1e-12,
            gain_tol: 0.0,
            max_iterations,
            floor: 0.0,
        };
        let mut calls = 0;
        let scout = minimise(
            DVector::from_vec(vec![-1.2, 1.0]),
            opts(3),
            &mut rosenbrock_exact(&mut calls),
            &mut |_, _, _| {},
        );
        assert_eq!(scout.stop, LmStop::IterationLimit);
        let (mut again, mut continued) = (0, 0);
        let fresh = minimise(
            scout.p.clone(),
            opts(200),
            &mut rosenbrock_exact(&mut again),
            &mut |_, _, _| {},
        );
        let reused = minimise_from(
            scout.p.clone(),
            scout.evaluation.clone(),
            opts(200),
            &mut rosenbrock_exact(&mut continued),
            &mut |_, _, _| {},
        );
        assert_eq!(continued + 1, again);
        assert_eq!(reused.p, fresh.p);
        assert_eq!(reused.objective, fresh.objective);
        assert_eq!(reused.iterations, fresh.iterations);
    }

    /// Nielsen's damping after an accepted step: divided by 3 when the decrease is what the
    /// model predicted (`rho = 1`), unchanged at `rho = 1/2`, doubled as `rho` goes to 0. One
    /// parameter, `A = 1`, `g = -1`, step 1, `lambda = 1`: the predicted decrease is
    /// `lambda h^2 (A + 1e-12) - h g = 2` (to 1e-12).
    #[test]
    fn the_damping_follows_the_gain_ratio() {
        let (step, a, g) = (
            DVector::from_vec(vec![1.0]),
            DMatrix::from_element(1, 1, 1.0),
            DVector::from_vec(vec![-1.0]),
        );
        let after = |decrease: f64| nielsen_damping(1.0, &step, &a, &g, decrease);
        assert!((after(2.0) - 1.0 / 3.0).abs() < 1e-12, "{}", after(2.0));
        assert!((after(1.0) - 1.0).abs() < 1e-11, "{}", after(1.0));
        assert!((after(1e-9) - 2.0).abs() < 1e-8, "{}", after(1e-9));
        // Better than predicted is no bolder than as predicted.
        assert!((after(3.0) - 1.0 / 3.0).abs() < 1e-12, "{}", after(3.0));
    }

    /// `a exp(b t)` against twelve points off that curve (a residual that does not vanish at
    /// the optimum, as a PRB model's against its beam), with the exact Jacobian.
    fn exponential_exact(
        calls: &mut u32,
    ) -> impl FnMut(&DVector<f64>, &mut Vec<f64>, &mut DMatrix<f64>) -> Option<bool> + '_ {
        move |p, out, jac| {
            *calls += 1;
            out.clear();
            *jac = DMatrix::zeros(12, 2);
            for i in 0..12 {
                let t = i as f64 / 11.0;
                let e = (p[1] * t).exp();
                let data = 2.0 * (0.7 * t).exp() + 0.05 * (3.0 * i as f64).sin();
                out.push(p[0] * e - data);
                jac[(i, 0)] = e;
                jac[(i, 1)] = p[0] * t * e;
            }
            Some(true)
        }
    }

    /// With `gain_tol` (draft's 1e-3), a run stops once one accepted step lowered `J` by less
    /// than that fraction and the Gauss-Newton model predicts less than that fraction more:
    /// on a residual that does not vanish it stops before `ftol`'s second small step, as
    /// converged, and no further from the optimum than the fraction promises. A run whose
    /// residuals go to zero (Rosenbrock: every late step removes most of what is left) is
    /// never stopped by it.
    #[test]
    fn the_model_s_predicted_gain_ends_a_run_a_step_early() {
        let opts = |ftol: f64, gain_tol: f64| LmOptions {
            ftol,
            xtol: 1e-12,
            gain_tol,
            max_iterations: 200,
            floor: 0.0,
        };
        let start = || DVector::from_vec(vec![1.0, 2.0]);
        let run = |o: LmOptions, calls: &mut u32| {
            minimise(start(), o, &mut exponential_exact(calls), &mut |_, _, _| {})
        };
        let (mut c_best, mut c_plain, mut c_gain) = (0, 0, 0);
        let best = run(opts(1e-15, 0.0), &mut c_best);
        let plain = run(opts(1e-5, 0.0), &mut c_plain);
        let gained = run(opts(1e-5, 1e-3), &mut c_gain);
        assert!(
            best.objective > 1e-3,
            "the residual does not vanish: {best:?}"
        );
        assert_eq!(gained.stop, LmStop::Converged);
        assert!(
            gained.iterations < plain.iterations,
            "{gained:?} vs {plain:?}"
        );
        assert!(c_gain < c_plain, "{c_gain} vs {c_plain} evaluations");
        assert!(
            gained.objective <= best.objective * (1.0 + 1e-3),
            "{gained:?} vs {best:?}"
        );

        let (mut a, mut b) = (0, 0);
        let rosenbrock = |o: LmOptions, calls: &mut u32| {
            let p0 = DVector::from_vec(vec![-1.2, 1.0]);
            minimise(p0, o, &mut rosenbrock_exact(calls), &mut |_, _, _| {})
        };
        let (without, with) = (
            rosenbrock(opts(1e-14, 0.0), &mut a),
            rosenbrock(opts(1e-14, 1e-3), &mut b),
        );
        assert!(with.objective < 1e-12, "{with:?}");
        assert_eq!((with.iterations, with.p), (without.iterations, without.p));
    }

    /// Rosenbrock as residuals (10 (y - x^2), 1 - x): minimum 0 at (1, 1).
    #[test]
    fn finds_the_rosenbrock_minimum() {
        let mut res = plain(|p: &DVector<f64>, out: &mut Vec<f64>| {
            out.clear();
            out.push(10.0 * (p[1] - p[0] * p[0]));
            out.push(1.0 - p[0]);
            true
        });
        let opts = LmOptions {
            ftol: 1e-14,
            xtol: 1e-12,
            gain_tol: 0.0,
            max_iterations: 200,
            floor: 0.0,
        };
        let out = minimise(
            DVector::from_vec(vec![-1.2, 1.0]),
            opts,
            &mut res,
            &mut |_, _, _| {},
        );
        assert!(
            (out.p[0] - 1.0).abs() < 1e-6 && (out.p[1] - 1.0).abs() < 1e-6,
            "{}",
            out.p
        );
        assert!(out.objective < 1e-12);
    }

    /// With a floor, the run stops as converged at the first step at or below it, earlier
    /// than the tolerances alone would stop it.
    #[test]
    fn a_floor_ends_the_run_once_reached() {
        let res = |p: &DVector<f64>, out: &mut Vec<f64>| {
            out.clear();
            out.push(10.0 * (p[1] - p[0] * p[0]));
            out.push(1.0 - p[0]);
            true
        };
        let run = |floor: f64| {
            let opts = LmOptions {
                ftol: 1e-14,
                xtol: 1e-12,
                gain_tol: 0.0,
                max_iterations: 200,
                floor,
            };
            minimise(
                DVector::from_vec(vec![-1.2, 1.0]),
                opts,
                &mut plain(res),
                &mut |_, _, _| {},
            )
        };
        let (full, floored) = (run(0.0), run(1e-4));
        assert_eq!(floored.stop, LmStop::Converged);
        assert!(floored.objective <= 1e-4 && floored.objective > full.objective);
        assert!(
            floored.iterations < full.iterations,
            "{floored:?} vs {full:?}"
        );
    }

    #[test]
    fn cancellation_stops_at_once() {
        let mut calls = 0;
        let mut res = plain(|p: &DVector<f64>, out: &mut Vec<f64>| {
            calls += 1;
            out.clear();
            out.push(p[0] - 3.0);
            calls < 3
        });
        let opts = LmOptions {
            ftol: 0.0,
            xtol: 0.0,
            gain_tol: 0.0,
            max_iterations: 1000,
            floor: 0.0,
        };
        let out = minimise(
            DVector::from_vec(vec![0.0]),
            opts,
            &mut res,
            &mut |_, _, _| {},
        );
        assert_eq!(out.stop, LmStop::Cancelled);
    }
}
