//! The solver: a validated beam with a [`Resolution`] (the speed/accuracy knob) and an
//! [`EffortBudget`] (the most work one load case may take). What it solves and how is in
//! `solve.rs` (see the parent module for the method and its accuracy).

use serde::{Deserialize, Serialize};

use super::{BeamModel, SolveError};
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
    /// Whether solutions keep their shapes ([`BeamSolver::new`]: yes). Each case's stress
    /// is found on its shape either way; a caller that wants only tips and stresses of many
    /// cases ([`BeamSolver::without_shapes`]) spares the memory, `shape_points` points a case
    /// (1.3 kB at the default 41), and the time of filling it.
    pub keep_shapes: bool,
}

impl BeamSolver {
    /// A solver for `model` at `resolution`, with the default [`EffortBudget`]; fails with
    /// [`SolveError::BadResolution`] if the resolution is out of range.
    pub fn new(model: BeamModel, resolution: Resolution) -> Result<BeamSolver, SolveError> {
        resolution.validate()?;
        Ok(BeamSolver {
            model,
            resolution,
            budget: EffortBudget::default(),
            keep_shapes: true,
        })
    }

    /// The same solver, returning solutions without their shapes (an empty
    /// [`BeamSolution::shape`](super::BeamSolution::shape)); tips, stresses and the rest as
    /// before, bit for bit.
    pub fn without_shapes(self) -> BeamSolver {
        BeamSolver {
            keep_shapes: false,
            ..self
        }
    }

    /// The same solver with another effort budget.
    pub fn with_budget(self, budget: EffortBudget) -> BeamSolver {
        BeamSolver { budget, ..self }
    }
}
