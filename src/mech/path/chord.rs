//! The Jacobian a beam mechanism's drive carries from case to case ([`Chord`]), and how far
//! it may.

use crate::linalg::solve_many;

use super::Point;

/// A Jacobian factored at an accepted point serves the cases after it ([`Chord`]) while the
/// last two factored along the drive say it is within this fraction of the one there:
/// `|| J0^-1 (J - J0) ||` at most this, where `J0` is the reference, so that `J = J0 (I +
/// A)` with `|| A || < 1` is regular with `J0`'s determinant sign along the way (the Banach
/// lemma), and each flexure's stability indicator moves by at most this fraction of itself,
/// so keeps its sign. Both are extrapolated linearly in the drive fraction from the last two
/// references; a quarter leaves the extrapolation a factor four of curvature.
const CHORD_REACH: f64 = 0.25;

/// A Jacobian factored at an accepted point of a beam mechanism's drive, kept for the cases
/// after it: a case whose prediction, checked by values alone (the beam's shot without its
/// variational equations, a little over half the work of a shot with them), converges as it
/// stands ([`AS_PREDICTED`](super::AS_PREDICTED)) takes its determinant's sign and its
/// flexures' Jacobians (their stability) from here, and its predictor base
/// ([`Point::ahead`]) from the chord step `x - J0^-1 r`. Honest while the Jacobian cannot
/// have changed by much ([`CHORD_REACH`]): up to `reach` along the drive.
#[derive(Debug, Clone)]
pub(super) struct Chord {
    /// The largest drive fraction it serves.
    pub(super) reach: f64,
    /// `J0^-1`, row-major.
    pub(super) inverse: Vec<f64>,
    pub(super) det_sign: f64,
    /// The flexures' own Jacobians there.
    pub(super) jacobians: Vec<Vec<f64>>,
}

/// An accepted point's factored Jacobian, for the next [`Chord`].
#[derive(Debug, Clone)]
pub(super) struct Reference {
    pub(super) lambda: f64,
    pub(super) jacobian: Vec<f64>,
    /// Each flexure's stability indicator ([`FlexureModel::stability_indicator`]).
    pub(super) indicators: Vec<f64>,
}

impl Chord {
    /// The chord from the reference `now`, accepted at `point`, with the one before it,
    /// `before`: `None` where the two do not bound the Jacobian's change (a flexure without
    /// an indicator, a singular reference).
    pub(super) fn new(before: &Reference, now: &Reference, point: &Point) -> Option<Chord> {
        let n = point.x.len();
        let span = now.lambda - before.lambda;
        if span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
            || now.indicators.len() != before.indicators.len()
        {
            return None;
        }
        let mut inverse = vec![0.0; n * n];
        for i in 0..n {
            inverse[i * n + i] = 1.0;
        }
        let mut factored = now.jacobian.clone();
        if !solve_many(&mut factored, &mut inverse, n, n) {
            return None;
        }
        // A = J0^-1 (J0 - J_before): its largest row and column sums, the smaller of the two
        // norms bounding it.
        let mut rows = vec![0.0_f64; n];
        let mut columns = vec![0.0_f64; n];
        for (i, row) in rows.iter_mut().enumerate() {
            for (j, column) in columns.iter_mut().enumerate() {
                let a: f64 = (0..n)
                    .map(|k| {
                        inverse[i * n + k] * (now.jacobian[k * n + j] - before.jacobian[k * n + j])
                    })
                    .sum();
                *row += a.abs();
                *column += a.abs();
            }
        }
        let change = rows
            .iter()
            .fold(0.0_f64, |m, &v| m.max(v))
            .min(columns.iter().fold(0.0_f64, |m, &v| m.max(v)));
        // Each bound on how far the reference serves; a NaN one (an indicator at zero that
        // did not move, a non-finite figure) serves no case.
        let bounds = std::iter::once(span / change).chain(
            now.indicators
                .iter()
                .zip(&before.indicators)
                .map(|(&s, &s0)| span * s.abs() / (s - s0).abs()),
        );
        let reach = bounds.fold(
            f64::INFINITY,
            |m, b| if b.is_nan() { 0.0 } else { m.min(b) },
        ) * CHORD_REACH;
        Some(Chord {
            reach: now.lambda + reach,
            inverse,
            det_sign: point.det_sign,
            jacobians: point.evals.iter().map(|e| e.jacobian.clone()).collect(),
        })
    }

    /// The chord step's end from `x` with residual `r`.
    pub(super) fn step(&self, x: &[f64], r: &[f64]) -> Vec<f64> {
        let n = x.len();
        x.iter()
            .enumerate()
            .map(|(i, v)| {
                v - self.inverse[i * n..(i + 1) * n]
                    .iter()
                    .zip(r)
                    .map(|(a, b)| a * b)
                    .sum::<f64>()
            })
            .collect()
    }
}
