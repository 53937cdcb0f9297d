//! The fit (DESIGN §4): the free cells of a PRB matrix that make the PRB tip follow the beam
//! tip over a scene's loads, i.e. that minimise
//!
//! ```text
//! J = mean over cases of (e_pos^2 + w e_ang^2)
//! ```
//!
//! written as least squares, `J = |r|^2` with three residuals per case,
//! `(da, db, sqrt(w) dphi) / sqrt(n)`.
//!
//! # Method
//! 1. The free cells are reparameterised (`param`) so every parameter vector is a valid
//!    matrix: gammas positive and summing to 1, spring constants positive.
//! 2. Starts: the given matrix, the published models of the same topology (so a fitted 3R is
//!    never worse than Su's or Chen's), and seeded random points.
//! 3. A global phase (`normal`, `precise`): argmin's particle swarm, its population seeded
//!    with the starts, in a box around them.
//! 4. A local polish: Levenberg-Marquardt ([`lm`]) from the swarm's best and from every start;
//!    the best result wins. It takes the residuals' exact Jacobian where the target gives it
//!    ([`Target::residuals_with_cells`], by the implicit function theorem through each case's
//!    equilibrium: a cantilever's chain, from the beam or from data, or a whole mechanism,
//!    chained through the reparameterisation), and differences the residuals otherwise (a
//!    dynamic fit's frequencies).
//!
//! A parameter set whose PRB model cannot follow a load path (it buckles or snaps where the
//! beam does not) gets a finite penalty residual for the cases it misses, so the optimisers
//! see a large but finite cost — never NaN, never infinity.
//!
//! The fit checks a [`CancelToken`] at every evaluation of `J` (tens of microseconds apart),
//! so a cancelled fit returns within milliseconds with the best matrix found so far.

//!
//! The parts: `param` (the reparameterisation), `starts`, `swarm` (the global phase),
//! [`lm`] (the polish), `objective` (J as residuals), `progress` (best-so-far reports), and
//! `presets` (what each [`Fidelity`] means for the fit).

pub mod lm;
mod objective;
mod param;
mod presets;
mod progress;
mod starts;
mod swarm;

use std::fmt;
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::mech::figures::Figures;
use crate::prb::PrbMatrix;

pub use crate::cancel::CancelToken;
pub use crate::fidelity::Fidelity;
pub(crate) use objective::push_residual;
pub use objective::PENALTY;
pub use param::{ParamError, Parameterisation};
pub use progress::{FitProgress, HEARTBEAT, PROGRESS_INTERVAL};

use objective::Objective;
pub use objective::{CantileverTarget, Target};
use progress::Tracker;

/// How to fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// How hard to try.
    pub fidelity: Fidelity,
    /// `w` in J.
    pub angle_weight: f64,
    /// Seed of the random starts and the swarm: the same seed gives the same fit.
    pub seed: u64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            fidelity: Fidelity::Normal,
            angle_weight: 1.0,
            seed: 1,
        }
    }
}

impl FitOptions {
    /// Checks the options: the angle weight must be a finite number >= 0 (a NaN weight would
    /// turn every figure into NaN later, far from its cause).
    pub fn validate(&self) -> Result<(), SearchError> {
        if self.angle_weight.is_finite() && self.angle_weight >= 0.0 {
            Ok(())
        } else {
            Err(SearchError::AngleWeight(self.angle_weight))
        }
    }
}

/// Why a fit stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The polish converged to its tolerance.
    Converged,
    /// The polish ran out of iterations before converging.
    IterationLimit,
    /// Cancelled; the report holds the best matrix so far.
    Cancelled,
    /// No cell is free.
    NothingToFit,
    /// Nothing found beats the starting matrix: it is already optimal to the fidelity's
    /// tolerance.
    CouldNotImprove,
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration limit reached",
            StopReason::Cancelled => "cancelled",
            StopReason::NothingToFit => "nothing to fit: no cell is free",
            StopReason::CouldNotImprove => "could not improve on the starting matrix",
        })
    }
}

/// What a fit found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitReport {
    /// The fitted matrix (the start when nothing better was found).
    pub matrix: PrbMatrix,
    /// On the fit's truth (as sampled at its fidelity).
    pub figures: Figures,
    /// `J` of the starting matrix (the penalty value if it cannot follow the loads).
    pub start_objective: f64,
    /// Swarm iterations plus polish iterations.
    pub iterations: u32,
    /// Evaluations of J (each a PRB solve of every load case).
    pub evaluations: u64,
    /// Wall-clock time of the fit.
    pub seconds: f64,
    /// Why it stopped.
    pub stop: StopReason,
    /// The preset it ran at.
    pub fidelity: Fidelity,
}

/// A fit that cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SearchError {
    /// The matrix cannot be fitted as given.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// A bad option.
    #[error("angle weight must be a finite number >= 0, got {}", crate::text::bounded(*.0))]
    AngleWeight(f64),
}

/// What [`search`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// The fitted matrix (the start when nothing better was found).
    pub matrix: PrbMatrix,
    /// `J` of the starting matrix (the penalty value if it cannot follow the target).
    pub start_objective: f64,
    /// Swarm iterations plus polish iterations.
    pub iterations: u32,
    /// Evaluations of `J`.
    pub evaluations: u64,
    /// Why it stopped.
    pub stop: StopReason,
}

impl Found {
    /// The report of this search, judged by `figures`, started at `t0`.
    pub fn report(self, figures: Figures, t0: Instant, fidelity: Fidelity) -> FitReport {
        FitReport {
            matrix: self.matrix,
            figures,
            start_objective: self.start_objective,
            iterations: self.iterations,
            evaluations: self.evaluations,
            seconds: t0.elapsed().as_secs_f64(),
            stop: self.stop,
            fidelity,
        }
    }
}

/// The fit's search for any [`Target`] (a cantilever's loads, a mechanism's drives; the
/// study's `fit` chooses it):
/// starts, the swarm and the polish of `options.fidelity`, reporting progress and stopping
/// soon after `cancel`.
pub fn search(
    target: &dyn Target,
    start: &PrbMatrix,
    options: &FitOptions,
    progress: &mut dyn FnMut(&FitProgress),
    cancel: &CancelToken,
) -> Result<Found, SearchError> {
    search_in(target, start, options, progress, cancel, None)
}

/// A polish alone from `start` (no other starts, no swarm) with the Levenberg-Marquardt
/// settings `lm` (its floor set from the target): [`search`]'s local phase, for a start
/// already near the optimum (a staged fit's last stage).
pub fn polish(
    target: &dyn Target,
    start: &PrbMatrix,
    options: &FitOptions,
    lm: lm::LmOptions,
    progress: &mut dyn FnMut(&FitProgress),
    cancel: &CancelToken,
) -> Result<Found, SearchError> {
    search_in(target, start, options, progress, cancel, Some(lm))
}

/// `J` of `matrix` on `target` with the cells `template` frees (and the mus when the target
/// fits them); `None` if the matrix cannot be parameterised or `J` is not finite.
pub fn objective_of(target: &dyn Target, template: &PrbMatrix, matrix: &PrbMatrix) -> Option<f64> {
    let param = if target.masses() {
        Parameterisation::with_masses(template).ok()?
    } else {
        Parameterisation::new(template).ok()?
    };
    let cancel = CancelToken::new();
    Objective::new(target, &param, &cancel)
        .matrix_value(matrix)
        .filter(|j| j.is_finite())
}

/// `points` without repeats, in order. The same point twice among the polish's candidates
/// (`--topology`'s start is the topology's default; a published model given as the start is
/// also among the published starts) would be polished twice, the same way, to the same end.
fn distinct(points: Vec<DVector<f64>>) -> Vec<DVector<f64>> {
    let mut out: Vec<DVector<f64>> = Vec::with_capacity(points.len());
    for p in points {
        if !out.contains(&p) {
            out.push(p);
        }
    }
    out
}

/// Whether two matrices of the same rows hold the same cells to rounding (1e-12 relative;
/// infinite cells equal).
fn same_to_rounding(a: &PrbMatrix, b: &PrbMatrix) -> bool {
    let close = |x: f64, y: f64| x == y || (x - y).abs() <= 1e-12 * x.abs().max(y.abs());
    a.rows().len() == b.rows().len()
        && a.rows().iter().zip(b.rows()).all(|(r, s)| {
            close(r.gamma, s.gamma)
                && close(r.k_theta, s.k_theta)
                && close(r.k_ex, s.k_ex)
                && match (r.mu, s.mu) {
                    (Some(x), Some(y)) => close(x, y),
                    (x, y) => x == y,
                }
        })
}

/// [`search`] (`local: None`) or [`polish`] (`local`: its settings).
fn search_in(
    target: &dyn Target,
    start: &PrbMatrix,
    options: &FitOptions,
    progress: &mut dyn FnMut(&FitProgress),
    cancel: &CancelToken,
    local: Option<lm::LmOptions>,
) -> Result<Found, SearchError> {
    let global = local.is_none();
    let t0 = Instant::now();
    options.validate()?;
    let param = if target.masses() {
        Parameterisation::with_masses(start)?
    } else {
        Parameterisation::new(start)?
    };
    let objective = Objective::new(target, &param, cancel);
    let p_start = param.encode(start);
    // J of the start matrix itself, from one evaluation that the polish from `p_start` then
    // begins with (below: where `p_start` decodes to the start).
    let mut start_evaluation = if param.is_empty() {
        None
    } else {
        objective.matrix_evaluation(start, &p_start)
    };
    let start_objective = match &start_evaluation {
        Some(e) => e.residuals.iter().map(|v| v * v).sum(),
        None if param.is_empty() => objective.matrix_value(start).unwrap_or(f64::INFINITY),
        None => f64::INFINITY,
    };
    // The polish takes it as its evaluation at `p_start` only where that decodes to the start
    // to rounding: the decoding clamps (a mu of 0, springs past 1e-9..1e9, extreme ratios),
    // and residuals of another matrix would skew its first step (and, differenced, every
    // column of its first Jacobian).
    if !param
        .decode(&p_start)
        .is_some_and(|decoded| same_to_rounding(&decoded, start))
    {
        start_evaluation = None;
    }

    let report = |matrix: PrbMatrix, stop, iterations, evaluations| {
        Ok(Found {
            matrix,
            start_objective,
            iterations,
            evaluations,
            stop,
        })
    };
    if param.is_empty() {
        return report(
            start.clone(),
            StopReason::NothingToFit,
            0,
            objective.evaluations(),
        );
    }

    let fidelity = options.fidelity;
    let mut tracker = Tracker::new(&param, t0, progress);
    tracker.offer(
        "start",
        0,
        start_objective,
        &p_start,
        objective.evaluations(),
    );
    let mut starts = starts::starts(&param, start, fidelity, options.seed);
    let mut iterations = 0u32;

    // Global phase: a particle swarm seeded with the starts.
    let mut candidates = if global {
        starts.points.clone()
    } else {
        vec![p_start.clone()]
    };
    if let (true, Some(size)) = (global, fidelity.swarm()) {
        let (best, swarm_iterations) =
            swarm::run(&objective, &mut tracker, &mut starts, size, options.seed);
        if let Some(best) = best {
            candidates.insert(0, best);
        }
        iterations += swarm_iterations;
    }
    let mut candidates = distinct(candidates);

    // Local polish in two rounds: a short one from every candidate, then the full polish
    // from the best few that have not converged (`Fidelity::scouting`), so hopeless
    // candidates cost little. Once a polish reaches the
    // target's floor (errors a negligible part of the targets) the search is done.
    let mut best: Option<lm::LmResult> = None;
    let mut polish = local.unwrap_or_else(|| fidelity.lm());
    polish.floor = target.objective_floor(fidelity.floor_fraction());
    let mut scout = polish;
    let (scout_iterations, polished) = fidelity.scouting(candidates.len());
    scout.max_iterations = scout_iterations;
    let mut scouted: Vec<lm::LmResult> = Vec::new();
    for round in 0..2 {
        // A polish continues where its scout stopped, with the scout's last evaluation.
        let starts: Vec<(DVector<f64>, Option<lm::Evaluated>)> = if round == 0 {
            std::mem::take(&mut candidates)
                .into_iter()
                .map(|p| {
                    let known = if p == p_start {
                        start_evaluation.take()
                    } else {
                        None
                    };
                    (p, known)
                })
                .collect()
        } else {
            scouted.sort_by(|a, b| a.objective.total_cmp(&b.objective));
            scouted
                .iter_mut()
                .filter(|r| r.stop == lm::LmStop::IterationLimit)
                .take(polished)
                .map(|r| (r.p.clone(), r.evaluation.take()))
                .collect()
        };
        for (candidate, evaluated) in starts {
            // A polish that reached the floor is as good as any: the rest cannot gain.
            let at_floor = best.as_ref().is_some_and(|b| b.objective <= polish.floor);
            if cancel.is_cancelled() || at_floor {
                break;
            }
            let mut residuals = |p: &DVector<f64>, out: &mut Vec<f64>, jac: &mut DMatrix<f64>| {
                objective.residuals_and_jacobian(p, out, jac)
            };
            let mut on_iteration = |it: u32, j: f64, p: &DVector<f64>| {
                tracker.offer("polish", it, j, p, objective.evaluations());
            };
            let options = if round == 0 { scout } else { polish };
            let run = lm::minimise_from(
                candidate,
                evaluated,
                options,
                &mut residuals,
                &mut on_iteration,
            );
            iterations += run.iterations;
            if best.as_ref().is_none_or(|b| run.objective < b.objective) {
                best = Some(run.clone());
            }
            if round == 0 {
                scouted.push(run);
            }
        }
    }
    tracker.flush("polish", iterations, objective.evaluations());

    let evaluations = objective.evaluations();
    let (p, stop) = match &best {
        // Cancelled before any polish finished: the best point seen anywhere.
        None => (tracker.best_p.clone(), StopReason::Cancelled),
        Some(b) => {
            let stop = if cancel.is_cancelled() {
                StopReason::Cancelled
            } else {
                match b.stop {
                    lm::LmStop::Converged | lm::LmStop::Stalled => StopReason::Converged,
                    lm::LmStop::IterationLimit => StopReason::IterationLimit,
                    lm::LmStop::Cancelled => StopReason::Cancelled,
                }
            };
            // The tracker may hold a better point (e.g. from the swarm) than the polish ended on.
            if tracker.best_j < b.objective {
                (tracker.best_p.clone(), stop)
            } else {
                (b.p.clone(), stop)
            }
        }
    };
    // The polish's own J where it ended; a point only the tracker saw is evaluated again.
    let best_j = match &best {
        Some(b) if b.p == p && b.evaluation.is_some() => b.objective,
        _ => objective.value(&p).unwrap_or(tracker.best_j),
    };
    let improved = best_j < start_objective;
    let (matrix, stop) = if !improved {
        (
            start.clone(),
            if stop == StopReason::Cancelled {
                stop
            } else {
                StopReason::CouldNotImprove
            },
        )
    } else {
        (param.decode(&p).unwrap_or_else(|| start.clone()), stop)
    };
    report(matrix, stop, iterations, evaluations)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    /// A toy target over a matrix's cells: the first row's gamma should be 0.2 and the last
    /// row's spring 2, and a third residual (0.3) no model removes. It records the first
    /// row's gamma and the last row's spring of every matrix it evaluates.
    struct Toy {
        seen: RefCell<Vec<(f64, f64)>>,
    }

    impl Target for Toy {
        fn len(&self) -> usize {
            3
        }
        fn missed_all(&self, out: &mut Vec<f64>) {
            out.clear();
            out.extend([PENALTY; 3]);
        }
        fn residuals_with_cells(
            &self,
            matrix: &PrbMatrix,
            out: &mut Vec<f64>,
            cells: Option<&mut Vec<f64>>,
        ) -> bool {
            let rows = matrix.rows();
            let last = rows.len() - 1;
            self.seen
                .borrow_mut()
                .push((rows[0].gamma, rows[last].k_theta));
            out.clear();
            out.extend([rows[0].gamma - 0.2, rows[last].k_theta - 2.0, 0.3]);
            if let Some(cells) = cells {
                let width = crate::prb::CELLS_PER_ROW * rows.len();
                cells.clear();
                cells.resize(3 * width, 0.0);
                cells[0] = 1.0;
                cells[width + crate::prb::CELLS_PER_ROW * last + 1] = 1.0;
            }
            true
        }
    }

    /// The start is evaluated once where nothing else visits it (a draft search, a polish
    /// alone; a swarm's seeded particle is its own evaluation): its `J` is the start
    /// matrix's own, and the polish from it begins with that evaluation instead of
    /// evaluating the start's encoding (the same matrix to rounding) again. From a spring of
    /// 2.7, whose logarithm's exponential is not 2.7 to the bit.
    #[test]
    fn the_start_is_evaluated_once() {
        let start = PrbMatrix::parse("0.3,inf,inf; 0.7,2.7,inf").unwrap();
        for local in [false, true] {
            let toy = Toy {
                seen: RefCell::new(Vec::new()),
            };
            let options = FitOptions {
                fidelity: Fidelity::Draft,
                ..FitOptions::default()
            };
            let (cancel, progress) = (CancelToken::new(), &mut |_: &FitProgress| {});
            let found = if local {
                polish(
                    &toy,
                    &start,
                    &options,
                    Fidelity::Normal.lm(),
                    progress,
                    &cancel,
                )
            } else {
                search(&toy, &start, &options, progress, &cancel)
            }
            .unwrap();
            let near_start = toy
                .seen
                .borrow()
                .iter()
                .filter(|(_, k)| (k - 2.7).abs() < 1e-12)
                .count();
            assert_eq!(
                near_start,
                1,
                "polish alone {local}: {:?}",
                toy.seen.borrow()
            );
            // J of the start matrix itself, its residuals summed in order.
            let expected: f64 = [0.3f64 - 0.2, 2.7 - 2.0, 0.3].iter().map(|v| v * v).sum();
            assert_eq!(found.start_objective, expected);
            assert!(
                (found.matrix.rows()[1].k_theta - 2.0).abs() < 1e-4,
                "{found:?}"
            );
        }
    }

    /// A start whose encoding decodes to another matrix (a first gamma of 1e-6 against
    /// 0.999999, a ratio past the parameterisation's e^10, decodes to about 4.5e-5) keeps its
    /// own `J`, but the polish's first evaluation is of the decoded start (the spring still
    /// 2.7), not a step taken from the start's residuals as if they were the decoded point's.
    #[test]
    fn a_start_the_encoding_clamps_is_not_taken_for_its_encoding() {
        let start = PrbMatrix::parse("1e-6,inf,inf; 0.999999,2.7,inf").unwrap();
        let toy = Toy {
            seen: RefCell::new(Vec::new()),
        };
        let options = FitOptions {
            fidelity: Fidelity::Draft,
            ..FitOptions::default()
        };
        let found = search(&toy, &start, &options, &mut |_| {}, &CancelToken::new()).unwrap();
        let seen = toy.seen.borrow();
        assert_eq!(seen[0], (1e-6, 2.7), "the start itself first: {seen:?}");
        let (gamma, k) = seen[1];
        assert!(
            gamma > 1e-5 && (k - 2.7).abs() < 1e-12,
            "the decoded start next: {seen:?}"
        );
        let expected: f64 = [1e-6f64 - 0.2, 2.7 - 2.0, 0.3].iter().map(|v| v * v).sum();
        assert_eq!(found.start_objective, expected);
    }

    /// Repeated candidates are polished once: the first of each kept, in order; points
    /// that differ in any coordinate, however little, are all kept.
    #[test]
    fn repeated_candidates_are_dropped() {
        let v = |x: &[f64]| DVector::from_column_slice(x);
        let points = vec![
            v(&[1.0, 2.0]),
            v(&[1.0, 2.0]),
            v(&[0.5, 2.0]),
            v(&[1.0, 2.0 + 1e-15]),
            v(&[0.5, 2.0]),
        ];
        let kept = distinct(points);
        assert_eq!(
            kept,
            vec![v(&[1.0, 2.0]), v(&[0.5, 2.0]), v(&[1.0, 2.0 + 1e-15])]
        );
    }
}
