//! What a beam solve returns: the equilibrium ([`BeamSolution`]) with how well it is pinned
//! down ([`Convergence`]), or why there is none ([`SolveError`]).

use std::fmt;

use serde::Serialize;

use super::{Load, ShapePoint, Stress, TipPose};

/// How a solve ended. A solve that did not converge is an `Err`, so this records how well
/// the accepted equilibrium is pinned down.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Convergence {
    /// `|M(L) - beta|` at the last shot, before the final linear correction.
    pub residual: f64,
    /// The last Newton update of the root moment.
    pub last_update: f64,
    /// `dM(L)/dM(0)`: positive for a stable equilibrium, zero at a buckling point. It grows
    /// like `exp(sqrt(alpha))` under a force and saturates at `f64::MAX` (from about
    /// `alpha = 5e5`).
    pub stability: f64,
}

/// One equilibrium of the beam.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BeamSolution {
    /// The load this equilibrium carries.
    pub load: Load,
    /// The tip pose under it.
    pub tip: TipPose,
    /// Bending moment at the clamp, units of `E I0 / L`.
    pub root_moment: f64,
    /// The deformed centre line at uniform `s`.
    pub shape: Vec<ShapePoint>,
    /// Newton iterations (shots) spent on this load, continuation sub-steps included.
    pub iterations: u32,
    /// Continuation steps taken to reach this load from the previous one.
    pub continuation_steps: u32,
    /// Integration steps of the final shot.
    pub rk_steps: u32,
    /// How well the equilibrium is pinned down, and how stable it is.
    pub convergence: Convergence,
    /// The largest fibre stress along the beam and where it is (DESIGN §11); `None` where
    /// there is no shape to read it from (a measured tip).
    pub stress: Option<Stress>,
}

/// Why the beam could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// A component of the requested load is infinite or NaN.
    #[error("load is not finite: {0}")]
    NonFiniteLoad(Load),
    /// [`BeamSolver::new`](super::BeamSolver::new) was given a tolerance outside
    /// `[1e-14, 1e-2]` or a shape sampling outside `[2, 100000]` points; the text says which.
    #[error("bad resolution: {0}")]
    BadResolution(String),
    /// Continuation could not make progress: its step fell below the smallest allowed
    /// while Newton kept failing (stagnation, a singular Jacobian, a shot that overflowed
    /// or whose step size collapsed) or kept jumping to another branch, with no sign of a
    /// critical point.
    #[error(
        "no equilibrium found for {load}: stuck at {} of the load path ({reason})",
        Fraction(*fraction)
    )]
    NoConvergence {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction `lambda` of `load` reached, i.e. the last accepted equilibrium.
        fraction: f64,
        /// What the last failed attempt ran into.
        reason: String,
    },
    /// The equilibrium followed from zero stops being stable: `dM(s)/dM(0)` reaches zero
    /// somewhere along the beam (a buckling bifurcation, e.g. axial compression past Euler's
    /// load), or continuation is stuck where that slope has collapsed (a snap-through limit
    /// point).
    #[error(
        "the equilibrium path for {load} reaches a critical point at {} of the load \
         (dM(L)/dM(0) -> 0): a snap-through limit point, past which the beam jumps to another \
         shape, or a buckling bifurcation, past which the shape is not unique (for an exactly \
         axial compression, tilt the load slightly to choose the buckling direction)",
        Fraction(*fraction)
    )]
    Unstable {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last stable equilibrium before the critical point.
        fraction: f64,
    },
    /// The constitutive law has no state for the axial force met on the path: with
    /// Poisson's effect a tension past the peak of `eps (1 - nu eps)^2 = N / (E A0)` (the
    /// section necks), or a compression that shortens the centre line to nothing
    /// (`1 + eps <= 0`).
    #[error(
        "the material law fails for {load} at {} of the load path: {reason}",
        Fraction(*fraction)
    )]
    MaterialLimit {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last accepted equilibrium.
        fraction: f64,
        /// The axial force and which limit it passed.
        reason: String,
    },
    /// The solve was still following the load path when its
    /// [`EffortBudget`](super::EffortBudget) ran out.
    #[error(
        "gave up on {load} at {} of the load path: the effort budget ran out ({steps} \
         continuation steps, {shots} Newton shots, {rk_steps} integration steps for one load \
         case) before the path reached its end; to proceed, solve a smaller load (this \
         fraction of it was reached), loosen the tolerance, or raise the solver's effort \
         budget",
        Fraction(*fraction)
    )]
    EffortExceeded {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last accepted equilibrium.
        fraction: f64,
        /// Continuation steps tried on this load case.
        steps: u32,
        /// Newton shots tried on this load case.
        shots: u32,
        /// Integration steps tried on this load case.
        rk_steps: u64,
    },
    /// The caller's [`CancelToken`](crate::cancel::CancelToken) was cancelled.
    #[error("solve of {load} cancelled at {} of the load path", Fraction(*fraction))]
    Cancelled {
        /// The load whose path was being followed (its end).
        load: Load,
        /// The fraction of `load` at the last accepted equilibrium.
        fraction: f64,
    },
}

/// A fraction of a load path, printed with four decimals, or four significant digits when it
/// is below a thousandth (a huge load's critical point can sit at 2.467e-4 of it).
struct Fraction(f64);

impl fmt::Display for Fraction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0 == 0.0 || self.0.abs() >= 1e-3 {
            write!(f, "{:.4}", self.0)
        } else {
            write!(f, "{:.3e}", self.0)
        }
    }
}
