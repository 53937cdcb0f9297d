//! The driver's predictors: the tangent from the start, the secant, and the polynomials
//! through the last three or four accepted points (see the parent module's docs).

use super::{History, PathProblem};

/// How the driver predicts the next point from the accepted ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// The secant through the last two points.
    Secant,
    /// The parabola through the last three (the secant until there are three, and after a
    /// rejected attempt until one is accepted again), for a problem that implements
    /// [`PathProblem::extrapolate`].
    Quadratic,
    /// The cubic through the last four where they are equally spaced and the step is the
    /// same (a steady stretch of the path); the secant elsewhere, and after a rejected attempt
    /// until one is accepted again.
    Cubic,
}

/// The prediction at `lambda` from the accepted points (see the module docs).
pub(super) fn predict<P: PathProblem>(
    problem: &P,
    predictor: Predictor,
    history: &History<P::Point>,
    lambda: f64,
    trial: &mut P::Point,
) {
    let last = history.last();
    let Some(before) = history.before() else {
        problem.tangent(&last.point, lambda - last.lambda, trial);
        return;
    };
    let t = (lambda - last.lambda) / (last.lambda - before.lambda);
    // The accepted points the polynomial may pass through, latest first.
    let through = [Some(last), Some(before), history.oldest(), history.eldest()];
    // The cubic only on a steady stretch: four points equally spaced and the step the same
    // (near trouble, where the steps vary, the secant, as it always has).
    let steady = || {
        let spacing = last.lambda - before.lambda;
        let same = |d: f64| (d - spacing).abs() <= 1e-9 * spacing;
        match (history.oldest(), history.eldest()) {
            (Some(o), Some(e)) => {
                same(lambda - last.lambda)
                    && same(before.lambda - o.lambda)
                    && same(o.lambda - e.lambda)
            }
            _ => false,
        }
    };
    let degree = match predictor {
        Predictor::Secant => 1,
        Predictor::Quadratic => 2,
        Predictor::Cubic if steady() => 3,
        Predictor::Cubic => 1,
    };
    let known = through.iter().take_while(|p| p.is_some()).count();
    let count = (degree + 1).min(known);
    if count >= 3 {
        // On the stack: a path predicts at every attempt.
        let lambdas = through.map(|a| a.map_or(0.0, |a| a.lambda));
        let mut weights = [0.0; 4];
        if count == 3 {
            // The parabola's weights written out, as they always were.
            let [l2, l1, l0, _] = lambdas;
            weights[..3].copy_from_slice(&[
                (lambda - l0) * (lambda - l1) / ((l2 - l0) * (l2 - l1)),
                (lambda - l0) * (lambda - l2) / ((l1 - l0) * (l1 - l2)),
                (lambda - l1) * (lambda - l2) / ((l0 - l1) * (l0 - l2)),
            ]);
        } else {
            // Lagrange's.
            for (i, w) in weights.iter_mut().enumerate().take(count) {
                let (num, den) = (0..count)
                    .filter(|&j| j != i)
                    .fold((1.0, 1.0), |(n, d), j| {
                        (n * (lambda - lambdas[j]), d * (lambdas[i] - lambdas[j]))
                    });
                *w = num / den;
            }
        }
        let points = through.map(|a| a.map(|a| &a.point));
        let mut chosen = [&last.point; 4];
        for (c, p) in chosen.iter_mut().zip(points.iter().flatten()) {
            *c = p;
        }
        let weights = &weights[..count];
        if weights.iter().all(|w| w.is_finite())
            && problem.extrapolate(&chosen[..count], weights, t, trial)
        {
            return;
        }
    }
    problem.secant(&last.point, &before.point, t, trial);
}
