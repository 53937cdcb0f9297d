//! The Jacobian a beam mechanism's drive carries from case to case ([`Chord`]), and how far
//! it may.

use crate::linalg::solve_many;

use super::Point;

/// A Jacobian factored at an accepted point serves the cases after it ([`Chord`]) while the
/// change from the last two references, extrapolated linearly in the drive fraction, keeps it
/// within this fraction of the one there: `|| J0^-1 (J - J0) ||` at most this, where `J0` is
/// the reference (were that so, `J = J0 (I + A)` with `|| A || < 1` would be regular with
/// `J0`'s determinant sign all the way, by the Banach lemma), and each flexure's stability
/// indicator within this fraction of itself. A quarter leaves the linear extrapolation a
/// factor four: over [`CHORD_SPANS`] spans, enough for a change up to cubic in the drive
/// fraction (`1 - (lambda / c)^3` from references half a span apart takes four times the
/// linear estimate's change over the next two spans). An estimate, not a bound: a change
/// that steepens faster between two references could still turn a sign unseen, as a step
/// of the continuation could before.
const CHORD_REACH: f64 = 0.25;

/// A chord serves at most this many times the distance between its two references past
/// its own: the extrapolation is not trusted far beyond what it was measured over, and the
/// references' spacing grows geometrically along a smooth drive (a few dozen over 500
/// cases).
const CHORD_SPANS: f64 = 2.0;

/// A Jacobian factored at an accepted point of a beam mechanism's drive, kept for the cases
/// after it: a case whose prediction, checked by values alone (the beam's shot without its
/// variational equations, a little over half the work of a shot with them), converges as it
/// stands ([`AS_PREDICTED`](super::AS_PREDICTED)) takes its determinant's sign and its
/// flexures' Jacobians (their stability) from here, and its predictor base
/// ([`Point::ahead`]) from the chord step `x - J0^-1 r`, while the Jacobian's change,
/// extrapolated from the last two references, stays small ([`CHORD_REACH`],
/// [`CHORD_SPANS`]): up to `reach` along the drive.
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

/// The Jacobian factored at an accepted point that took its prediction as the case (so at the
/// point itself), for the next [`Chord`].
#[derive(Debug, Clone)]
pub(super) struct Reference {
    pub(super) lambda: f64,
    pub(super) jacobian: Vec<f64>,
    /// Each flexure's stability indicator ([`FlexureModel::stability_indicator`]).
    pub(super) indicators: Vec<f64>,
}

impl Chord {
    /// The chord from the reference `now`, accepted at `point`, with the one before it,
    /// `before`: `None` where the two give no estimate of the Jacobian's change (the same
    /// drive fraction, a singular reference, a non-finite change).
    pub(super) fn new(before: &Reference, now: &Reference, point: &Point) -> Option<Chord> {
        let n = point.x.len();
        let span = now.lambda - before.lambda;
        if span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
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
        if !rows.iter().chain(&columns).all(|v| v.is_finite()) {
            return None;
        }
        let change = rows
            .iter()
            .fold(0.0_f64, |m, &v| m.max(v))
            .min(columns.iter().fold(0.0_f64, |m, &v| m.max(v)));
        // Each bound on how far the reference serves, in spans; a NaN one (an indicator at
        // zero that did not move, a non-finite indicator) serves no case.
        let bounds = std::iter::once(CHORD_SPANS / CHORD_REACH)
            .chain(std::iter::once(1.0 / change))
            .chain(
                now.indicators
                    .iter()
                    .zip(&before.indicators)
                    .map(|(&s, &s0)| s.abs() / (s - s0).abs()),
            );
        let reach = span
            * CHORD_REACH
            * bounds.fold(
                f64::INFINITY,
                |m, b| if b.is_nan() { 0.0 } else { m.min(b) },
            );
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
