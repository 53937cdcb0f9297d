//! The solver's public face: a validated beam with a [`Resolution`] and an [`EffortBudget`],
//! solving one load or a load path from the unloaded beam (see the parent module for the
//! method and its accuracy), with the plate correction of a wide section applied case by
//! case.

use serde::{Deserialize, Serialize};

use super::{plate, BeamModel, BeamSolution, Load, SolveError};
use crate::cancel::CancelToken;
use crate::text::bounded;

/// The solver's resolution: the speed/accuracy knob.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Resolution {
    /// Local error tolerance of the integrator (units of L and radians).
    pub tol: f64,
    /// Points of the deformed shape returned with each solution (root and tip included).
    pub shape_points: usize,
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution {
            tol: 1e-9,
            shape_points: 41,
        }
    }
}

impl Resolution {
    /// A resolution with the given tolerance and the default shape sampling.
    pub fn with_tol(tol: f64) -> Resolution {
        Resolution {
            tol,
            ..Resolution::default()
        }
    }

    /// The tip error (units of L, radians) this resolution promises, for loads within the
    /// solver's range. Calibrated by `cargo bench --bench beam` and enforced by
    /// `tests/beam_properties.rs`.
    pub fn claimed_tip_error(&self) -> f64 {
        10.0 * self.tol
    }

    pub(super) fn validate(&self) -> Result<(), SolveError> {
        if !(self.tol.is_finite() && self.tol >= 1e-14 && self.tol <= 1e-2) {
            return Err(SolveError::BadResolution(format!(
                "tolerance must be in [1e-14, 1e-2], got {}",
                bounded(self.tol)
            )));
        }
        if self.shape_points < 2 || self.shape_points > 100_000 {
            return Err(SolveError::BadResolution(format!(
                "shape points must be in [2, 100000], got {}",
                self.shape_points
            )));
        }
        Ok(())
    }
}

/// How much work the solver may spend on one load case (one [`BeamSolver::solve`], or one
/// case of a path, counted from the previous case) before it gives up with
/// [`SolveError::EffortExceeded`]. Every count includes the attempts that failed.
///
/// The default bounds one case to roughly a second of CPU in a release build, whatever
/// the load (the integration steps dominate; one costs well under a microsecond); loads in
/// the solver's range use a small fraction of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct EffortBudget {
    /// Continuation steps tried (accepted or rejected).
    pub continuation_steps: u32,
    /// Newton shots (each integrates the whole beam once).
    pub shots: u32,
    /// Integration steps tried, over all shots; with the Poisson effect on each counts
    /// twice, as its material law makes a step cost about that much more.
    pub rk_steps: u64,
}

impl Default for EffortBudget {
    fn default() -> Self {
        EffortBudget {
            continuation_steps: 400,
            shots: 4_000,
            rk_steps: 4_000_000,
        }
    }
}

/// The solver: a validated beam, a resolution, and the most work it may spend on a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamSolver {
    /// The beam: slenderness, Poisson's ratio, shear coefficient and effects.
    pub model: BeamModel,
    /// Integrator tolerance and shape sampling.
    pub resolution: Resolution,
    /// The most work one load case may take; [`BeamSolver::new`] sets the default.
    pub budget: EffortBudget,
}

/// Shape points of the narrow-beam solutions that give a wide section's cases their plate
/// fractions (the moment is averaged along the beam over them).
const PLATE_SHAPE_POINTS: usize = 41;

impl BeamSolver {
    /// A solver for `model` at `resolution`, with the default [`EffortBudget`]; fails with
    /// [`SolveError::BadResolution`] if the resolution is out of range.
    pub fn new(model: BeamModel, resolution: Resolution) -> Result<BeamSolver, SolveError> {
        resolution.validate()?;
        Ok(BeamSolver {
            model,
            resolution,
            budget: EffortBudget::default(),
        })
    }

    /// The same solver with another effort budget.
    pub fn with_budget(self, budget: EffortBudget) -> BeamSolver {
        BeamSolver { budget, ..self }
    }

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
        })
    }

    /// This solver with the plate fraction of the case whose narrow-beam solution is
    /// `narrow`, and no width (so that it solves with that fraction as it is).
    fn with_case_plate(&self, narrow: &BeamSolution) -> BeamSolver {
        let m = &self.model;
        let width_ratio = m.width_ratio().unwrap_or(f64::INFINITY);
        let (phi, _) = plate::case_fraction(width_ratio, m.slenderness, m.nu, narrow);
        let mut model = m.with_plate_fraction(phi);
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
            // Each case at its own plate fraction, solved from the unloaded beam along the
            // same ray (so on the branch the path follows).
            return narrow
                .follow_path(end, steps, cancel)?
                .iter()
                .map(|c| self.with_case_plate(c).solve_cancellable(c.load, cancel))
                .collect();
        }
        self.follow_path(end, steps, cancel)
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
