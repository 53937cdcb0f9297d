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
//! ## References
//! - D. W. Marquardt, "An algorithm for least-squares estimation of nonlinear parameters",
//!   SIAM J. Appl. Math. 11 (1963) 431-441.

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
    /// Most iterations (accepted steps, each with its Jacobian) before the run gives up with
    /// [`LmStop::IterationLimit`].
    pub max_iterations: u32,
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LmStop {
    /// Two accepted steps in a row were small (below `ftol` or `xtol`), or there is no
    /// parameter to move.
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
    let n = p0.len();
    let mut p = p0;
    let mut r = Vec::new();
    // The Jacobian at `p`, and at the last trial (kept when the trial is accepted).
    let mut jac = DMatrix::<f64>::zeros(0, 0);
    let mut trial_jac = DMatrix::<f64>::zeros(0, 0);
    let Some(mut exact) = residuals(&p, &mut r, &mut jac) else {
        return finish(p, f64::INFINITY, 0, LmStop::Cancelled);
    };
    let m = r.len();
    let mut objective = sum_sq(&r);
    if n == 0 {
        return finish(p, objective, 0, LmStop::Converged);
    }
    let mut trial = Vec::with_capacity(m);
    let mut lambda = 1e-3;
    let mut small_steps = 0;
    for iteration in 1..=options.max_iterations {
        if !exact {
            // Forward differences, step relative to the parameter's size.
            if jac.shape() != (m, n) {
                jac = DMatrix::zeros(m, n);
            }
            for j in 0..n {
                let h = 1e-7 * (1.0 + p[j].abs());
                let mut q = p.clone();
                q[j] += h;
                if residuals(&q, &mut trial, &mut trial_jac).is_none() {
                    return finish(p, objective, iteration, LmStop::Cancelled);
                }
                for i in 0..m {
                    jac[(i, j)] = (trial[i] - r[i]) / h;
                }
            }
        }
        let jt = jac.transpose();
        let a = &jt * &jac;
        let g = &jt * DVector::from_column_slice(&r);
        loop {
            let mut damped = a.clone();
            for j in 0..n {
                damped[(j, j)] += lambda * (a[(j, j)] + 1e-12);
            }
            let Some(step) = damped.cholesky().map(|c| c.solve(&(-&g))) else {
                lambda *= 10.0;
                if lambda > 1e12 {
                    return finish(p, objective, iteration, LmStop::Stalled);
                }
                continue;
            };
            let q = &p + &step;
            let Some(trial_exact) = residuals(&q, &mut trial, &mut trial_jac) else {
                return finish(p, objective, iteration, LmStop::Cancelled);
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
                exact = trial_exact;
                objective = new_objective;
                lambda = (lambda / 3.0).max(1e-12);
                on_iteration(iteration, objective, &p);
                if objective <= options.floor {
                    return finish(p, objective, iteration, LmStop::Converged);
                }
                // Two small steps in a row: converged.
                if decrease < options.ftol || moved < options.xtol {
                    small_steps += 1;
                    if small_steps >= 2 {
                        return finish(p, objective, iteration, LmStop::Converged);
                    }
                } else {
                    small_steps = 0;
                }
                break;
            }
            lambda *= 4.0;
            if lambda > 1e12 {
                // No direction helps: a minimum to the accuracy the residuals allow.
                return finish(p, objective, iteration, LmStop::Stalled);
            }
        }
    }
    finish(p, objective, options.max_iterations, LmStop::IterationLimit)
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

fn finish(p: DVector<f64>, objective: f64, iterations: u32, stop: LmStop) -> LmResult {
    LmResult {
        p,
        objective,
        iterations,
        stop,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // Each differenced iteration spends 2 evaluations on its Jacobian that the exact
        // run does not.
        assert!(
            exact_calls + 2 * exact.iterations.min(differenced.iterations) <= plain_calls + 2,
            "exact {exact_calls} evaluations in {} iterations, differenced {plain_calls} in {}",
            exact.iterations,
            differenced.iterations
        );
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
