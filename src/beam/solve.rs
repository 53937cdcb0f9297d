//! Solving one load, or a proportional load path, from the unloaded beam (see the parent
//! module for the method and its accuracy), with a wide section's plate correction applied
//! case by case: each case takes the plate fraction its narrow-beam shape gives. A path is
//! followed twice, narrow and then wide, the wide continuation's solver changing its plate
//! fraction from case to case (interpolated between them), so each wide case starts from its
//! neighbour instead of from the unloaded beam.

use super::{plate, BeamSolution, BeamSolver, Load, Resolution, SolveError};
use crate::cancel::CancelToken;

/// Shape points of the narrow-beam solutions that give a wide section's cases their plate
/// fractions (the moment is averaged along the beam over them).
const PLATE_SHAPE_POINTS: usize = 41;

impl BeamSolver {
    /// Solves one load by continuation from the unloaded beam.
    pub fn solve(&self, load: Load) -> Result<BeamSolution, SolveError> {
        self.solve_cancellable(load, &CancelToken::new())
    }

    /// As [`BeamSolver::solve`], stopping with [`SolveError::Cancelled`] soon after `cancel`
    /// is cancelled.
    pub fn solve_cancellable(
        &self,
        load: Load,
        cancel: &CancelToken,
    ) -> Result<BeamSolution, SolveError> {
        if let Some(narrow) = self.plate_refined() {
            let last = narrow.follow_to(load, cancel)?;
            return self.with_case_plate(&last).solve_cancellable(load, cancel);
        }
        self.follow_to(load, cancel)
    }

    /// With plane strain on a section of known width, the narrow-beam solver whose solutions
    /// give each case its plate fraction ([`plate::case_fraction`]); `None` otherwise.
    fn plate_refined(&self) -> Option<BeamSolver> {
        let m = &self.model;
        if !m.effects.plane_strain || m.width_ratio().is_none() {
            return None;
        }
        let narrow = m.narrow();
        Some(BeamSolver {
            model: narrow,
            resolution: Resolution {
                shape_points: self.resolution.shape_points.max(PLATE_SHAPE_POINTS),
                ..self.resolution
            },
            budget: self.budget,
            // Each case's plate fraction comes from the narrow beam's shape.
            keep_shapes: true,
        })
    }

    /// The plate fraction of the case whose narrow-beam solution is `narrow`.
    fn case_plate(&self, narrow: &BeamSolution) -> f64 {
        let m = &self.model;
        let width_ratio = m.width_ratio().unwrap_or(f64::INFINITY);
        plate::case_fraction(width_ratio, m.slenderness, m.nu, narrow).0
    }

    /// This solver with the plate fraction of the case whose narrow-beam solution is
    /// `narrow`, and no width (so that it solves with that fraction as it is).
    fn with_case_plate(&self, narrow: &BeamSolution) -> BeamSolver {
        let mut model = self.model.with_plate_fraction(self.case_plate(narrow));
        model.forget_width();
        BeamSolver { model, ..*self }
    }

    /// Solves the proportional path to `end`, returning the cases at `k / steps`,
    /// `k = 1..=steps` (DESIGN §5). Each case warm-starts from the previous ones.
    pub fn solve_path(&self, end: Load, steps: u32) -> Result<Vec<BeamSolution>, SolveError> {
        self.solve_path_cancellable(end, steps, &CancelToken::new())
    }

    /// As [`BeamSolver::solve_path`], stopping with [`SolveError::Cancelled`] soon after
    /// `cancel` is cancelled: the flag is read before every continuation step and every few
    /// dozen integration steps, i.e. every few microseconds of work.
    pub fn solve_path_cancellable(
        &self,
        end: Load,
        steps: u32,
        cancel: &CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        if let Some(narrow) = self.plate_refined() {
            // Each case at its own plate fraction (from its narrow-beam solution), all in one
            // continuation along the path with the fraction varying between the cases: each
            // case on the branch the path follows, no case re-solved from rest.
            let narrow_cases = narrow.follow_path(end, steps, cancel)?;
            return self.follow_on_narrow(end, steps, &narrow_cases, cancel);
        }
        self.follow_path(end, steps, cancel)
    }

    /// As [`BeamSolver::solve_path_cancellable`], given `narrow`: this path's cases as the
    /// narrow beam solves them (this model without plane strain, at this resolution with
    /// shapes of at least 41 points: an [`Effects::ALL`](super::Effects::ALL) solve of the
    /// same path, say). With plane strain on a section of known width, each case takes its
    /// plate fraction from them instead of solving the narrow beam again; otherwise, or when
    /// `narrow` does not hold the path's cases (their number, loads and shapes), it is
    /// ignored. The cases are the same, bit for bit.
    pub fn solve_path_on_narrow(
        &self,
        end: Load,
        steps: u32,
        narrow: &[BeamSolution],
        cancel: &CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        let given = self.plate_refined().is_some()
            && narrow.len() == steps.max(1) as usize
            && self.resolution.shape_points >= PLATE_SHAPE_POINTS
            && narrow
                .iter()
                .all(|c| c.shape.len() == self.resolution.shape_points)
            && narrow.iter().enumerate().all(|(k, c)| {
                // Case k + 1 of the path (the cases are at k / steps).
                let at = end.scaled((k + 1) as f64 / steps.max(1) as f64);
                let scale = 1e-12 * (1.0 + end.magnitude());
                (c.load.alpha_x - at.alpha_x).abs() <= scale
                    && (c.load.alpha_y - at.alpha_y).abs() <= scale
                    && (c.load.beta - at.beta).abs() <= scale
            });
        if !given {
            return self.solve_path_cancellable(end, steps, cancel);
        }
        self.follow_on_narrow(end, steps, narrow, cancel)
    }

    /// The wide beam's path, each case at the plate fraction of its narrow-beam solution in
    /// `narrow`.
    fn follow_on_narrow(
        &self,
        end: Load,
        steps: u32,
        narrow: &[BeamSolution],
        cancel: &CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        let phis: Vec<f64> = narrow.iter().map(|c| self.case_plate(c)).collect();
        if !end.is_finite() {
            return Err(SolveError::NonFiniteLoad(end));
        }
        self.follow_with_plate(end, steps, Some(&phis), cancel)
    }

    /// The cases of the proportional path to `end` at `k / steps`, `k = 1..=steps` (one at
    /// least), for a narrow beam or one with its plate fraction set.
    fn follow_path(
        &self,
        end: Load,
        steps: u32,
        cancel: &CancelToken,
    ) -> Result<Vec<BeamSolution>, SolveError> {
        if !end.is_finite() {
            return Err(SolveError::NonFiniteLoad(end));
        }
        self.follow(end, steps, cancel)
    }

    /// The last case of [`BeamSolver::follow_path`]: the load itself.
    fn follow_to(&self, load: Load, cancel: &CancelToken) -> Result<BeamSolution, SolveError> {
        let mut cases = self.follow_path(load, 1, cancel)?;
        // The driver reports a case for each of its steps before it returns `Ok`, so a
        // one-step path that succeeded holds exactly one.
        #[allow(clippy::expect_used)]
        let last = cases
            .pop()
            .expect("a successful one-step path has one case");
        Ok(last)
    }
}
