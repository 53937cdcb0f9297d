//! Stroke limits (DESIGN §11): along each load path or drive, the fraction of its end value
//! at which the largest fibre stress of any flexure first reaches that flexure's allowable
//! stress (`[beam] allowable_stress`, or a flexure's own).
//!
//! # Method
//! A case's *stress ratio* is the largest, over the flexures that have an allowable stress,
//! of `max_stress / allowable`. The truth's cases bracket the limit: the first case whose
//! ratio reaches 1 and the case before it (the unloaded state, ratio 0, before the first).
//! Between them the truth is solved at single fractions of the path (a cantilever's beam
//! from the unloaded beam to `lambda` times its end load; a mechanism's beam mechanism along
//! its drive to `lambda`), and `ratio(lambda) = 1` is found by regula falsi with the
//! Illinois safeguard, until the bracket is within [`FRACTION_TOL`] or the ratio within
//! `1e-10` of 1. The ratio is smooth and, inside one case step, close to linear, so a few
//! solves do (the search's solves are counted and at most [`MAX_SHOTS`]).
//!
//! A path whose ratio stays below 1 over all its cases has no limit (`None`): the stress
//! may still reach the allowable past its end, which the scene does not ask about. A limit
//! between two cases where the ratio rises above 1 and falls back is not seen (the cases
//! are the bracket). Measured data has no stress, so no limit either.
//!
//! [`Study::within_stroke`] (`select --within-stroke`) is the study with each path ending at
//! its limit, solved afresh as fully as the whole path, so a model is judged only on the
//! stroke the part survives.

use serde::Serialize;

use crate::beam::BeamSolver;
use crate::cancel::CancelToken;
use crate::mech::{exact, MechCase};
use crate::scene::{Coordinate, DrivePath};

use super::{Study, StudyError};

/// How close the stroke limit is found, as a fraction of the path.
pub const FRACTION_TOL: f64 = 1e-6;
/// The most solves the search spends on one path.
pub const MAX_SHOTS: u32 = 20;

/// One path's stroke limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StrokeLimit {
    /// The path (load path or drive), from 1.
    pub path: usize,
    /// The fraction of the path's end value where the stress first reaches the allowable,
    /// `None` if it does not within the path (or cannot be told: measured data).
    pub fraction: Option<f64>,
    /// The flexure (from 1) that reaches its allowable there.
    pub flexure: Option<usize>,
    /// Solves the search spent.
    pub shots: u32,
}

impl StrokeLimit {
    /// Whether a case at `fraction` of the path lies past this limit.
    pub fn passed_by(&self, fraction: f64) -> bool {
        self.fraction.is_some_and(|l| fraction > l)
    }
}

/// A case's stress ratio and the flexure (from 0) that sets it; `None` when a flexure with
/// an allowable stress has no stress (measured data) or no flexure has an allowable.
fn ratio(allowables: &[Option<f64>], youngs: &[f64], case: &MechCase) -> Option<(f64, usize)> {
    let mut worst: Option<(f64, usize)> = None;
    for (i, f) in case.flexures.iter().enumerate() {
        let Some(allowable) = allowables.get(i).copied().flatten() else {
            continue;
        };
        let r = f.stress?.max * youngs.get(i).copied()? / allowable;
        if worst.is_none_or(|(w, _)| r > w) {
            worst = Some((r, i));
        }
    }
    worst
}

/// The stroke limit of path `path` (from 1) from its cases in order, each `(fraction,
/// stress ratio and the flexure that sets it)` (a `None` ratio: unknown, so no limit),
/// solving the truth at single fractions with `ratio_at(lambda)` (`None` where it cannot)
/// inside the bracket the cases give (module docs). Every kind of scene's limits go through
/// here: the study's ([`Study::stroke_limits`]) and `solve`'s beam with its own flags.
pub fn path_limit(
    path: usize,
    cases: impl IntoIterator<Item = (f64, Option<(f64, usize)>)>,
    ratio_at: &dyn Fn(f64) -> Option<f64>,
) -> StrokeLimit {
    let mut limit = StrokeLimit {
        path,
        fraction: None,
        flexure: None,
        shots: 0,
    };
    let mut before = (0.0, -1.0);
    for (fraction, ratio) in cases {
        let Some((r, i)) = ratio else {
            return limit;
        };
        if r >= 1.0 {
            let (at, shots) = search(before, (fraction, r - 1.0), &|l| {
                ratio_at(l).map(|r| r - 1.0)
            });
            limit.flexure = Some(i + 1);
            limit.fraction = Some(at);
            limit.shots = shots;
            break;
        }
        before = (fraction, r - 1.0);
    }
    limit
}

/// The zero of `g(lambda)` between `lo` (below) and `hi` (at or above), each
/// `(lambda, g)`: `(lambda, solves spent)`.
fn search(lo: (f64, f64), hi: (f64, f64), g: &dyn Fn(f64) -> Option<f64>) -> (f64, u32) {
    let ((mut a, mut ga), (mut b, mut gb)) = (lo, hi);
    if gb == 0.0 {
        return (b, 0);
    }
    let mut shots = 0;
    let mut side = 0i8;
    let mut guess = b;
    while shots < MAX_SHOTS && b - a > FRACTION_TOL {
        guess = (a * gb - b * ga) / (gb - ga);
        if !(guess > a && guess < b) {
            guess = 0.5 * (a + b);
        }
        shots += 1;
        let Some(gx) = g(guess) else {
            // A fraction the solver cannot reach inside a bracket the path's own cases
            // reached: keep the bracket's end, which did.
            return (b, shots);
        };
        if gx.abs() <= 1e-10 {
            return (guess, shots);
        }
        if gx < 0.0 {
            (a, ga) = (guess, gx);
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            (b, gb) = (guess, gx);
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    if b - a <= FRACTION_TOL {
        // The root lies in [a, b]: its secant estimate.
        guess = ((a * gb - b * ga) / (gb - ga)).clamp(a, b);
    }
    (guess, shots)
}

impl Study {
    /// The allowable stress of each flexure (Pa; a cantilever's is its beam's), `None` where
    /// none is given.
    pub fn allowable_stresses(&self) -> Vec<Option<f64>> {
        self.mechanism
            .flexures
            .iter()
            .map(|f| f.beam.allowable_stress)
            .collect()
    }

    /// A case's stress ratio (its largest `max_stress / allowable` over the flexures that
    /// have an allowable) and the flexure (from 0) that sets it; `None` when one of those
    /// flexures has no stress (measured data) or none has an allowable.
    pub fn stress_ratio(&self, case: &MechCase) -> Option<(f64, usize)> {
        let allowables = self.allowable_stresses();
        let youngs: Vec<f64> = self
            .mechanism
            .flexures
            .iter()
            .map(|f| f.beam.youngs_modulus)
            .collect();
        ratio(&allowables, &youngs, case)
    }

    /// Each path's stroke limit, in order (module docs); `None` when no flexure has an
    /// allowable stress.
    pub fn stroke_limits(&self) -> Option<Vec<StrokeLimit>> {
        if self.allowable_stresses().iter().all(Option::is_none) {
            return None;
        }
        Some(
            self.truth
                .iter()
                .enumerate()
                .map(|(p, cases)| {
                    let measured = self.is_measured();
                    path_limit(
                        p + 1,
                        cases
                            .iter()
                            .map(|c| (c.fraction, self.stress_ratio(c).filter(|_| !measured))),
                        &|l| {
                            self.case_at(p, l)
                                .and_then(|c| self.stress_ratio(&c))
                                .map(|r| r.0)
                        },
                    )
                })
                .collect(),
        )
    }

    /// The truth's case at `lambda` of path `p`, solved on its own from the unloaded state.
    fn case_at(&self, p: usize, lambda: f64) -> Option<MechCase> {
        if let Some(baseline) = &self.beam {
            let path = baseline.paths.get(p)?;
            let solver = BeamSolver::new(baseline.model, self.resolution).ok()?;
            let s = solver.solve(path.end.scaled(lambda)).ok()?;
            return Some(super::truth::tip_case(
                lambda,
                s.load,
                s.tip,
                s.iterations,
                s.stress,
            ));
        }
        let drive = self.mechanism.drives.get(p)?;
        let path = self.mechanism.drive_path(drive);
        let to = DrivePath::proportional(path.at(lambda), 1);
        let solver = exact::solver(&self.mechanism, self.resolution).ok()?;
        let mut cases = solver.solve_path(&to, p + 1).ok()?;
        let mut case = cases.pop()?;
        case.fraction = lambda;
        Some(case)
    }
}

impl Study {
    /// This study judged only up to the stroke limits (`select --within-stroke`): the scene
    /// with each path ending at its limit (a cantilever's end load, a drive's end values
    /// times the limit's fraction; a path without a limit whole), its truth solved afresh
    /// with the same effects, sampling and steps, so every judgement, fit and selection sees
    /// the shorter paths as fully as the whole ones. `None` when no flexure has an allowable
    /// stress.
    pub fn within_stroke(
        &self,
        cancel: &CancelToken,
    ) -> Result<Option<(Study, Vec<StrokeLimit>)>, StudyError> {
        let Some(limits) = self.stroke_limits() else {
            return Ok(None);
        };
        let mut scene = self.scene.clone();
        let fraction = |i: usize| limits.get(i).and_then(|l| l.fraction);
        for (i, path) in scene.loads.iter_mut().enumerate() {
            if let Some(l) = fraction(i) {
                path.end = path.end.scaled(l);
            }
        }
        if let Some(m) = &mut scene.mechanism {
            // Measured drives (rows) have no stress, so no limit: only sampled drives scale.
            for (i, d) in m.drives.iter_mut().enumerate() {
                if let (Some(l), true) = (fraction(i), d.rows.is_empty()) {
                    d.coordinates = d.coordinates.map(|c| match c {
                        Coordinate::Prescribed(v) => Coordinate::Prescribed(v * l),
                        Coordinate::Loaded(v) => Coordinate::Loaded(v * l),
                    });
                }
            }
        }
        let study = Study::decided(
            scene,
            self.decision.clone(),
            self.sampling,
            cancel,
            &mut |_, _, _| {},
        )?;
        Ok(Some((study, limits)))
    }
}
