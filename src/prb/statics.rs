//! Kinematics and statics of a PRB chain (DESIGN §3), nondimensional (L = 1, E I0 = 1).
//!
//! The configuration `q` holds one joint angle `theta_i` per revolute row and one extension
//! `delta_i` per prismatic row, in row order. With `Theta_i = sum_{j<=i} theta_j` and
//! `l_i = gamma_i + delta_i`, the tip is `a = sum l_i cos Theta_i`, `b = sum l_i sin Theta_i`,
//! `phi = Theta_N`. Equilibrium (`tau = J^T F`) is
//!
//! ```text
//! k_theta_i theta_i = beta + sum_{j>=i} l_j Q_j                 each R joint
//! (k_ex_i / c_e) delta_i = N_i                                  each P joint
//! ```
//!
//! with `N_j = alpha_x cos Theta_j + alpha_y sin Theta_j` and
//! `Q_j = -alpha_x sin Theta_j + alpha_y cos Theta_j` the axial and transverse components of
//! the tip force in segment j, and `c_e = I0 / (A0 L^2)` (the P equation is DESIGN's divided by
//! `c_e`, which makes the tangent stiffness symmetric: it is the Hessian of the potential
//! energy). Newton's method on the analytic Jacobian solves it; each load is reached by
//! continuation from zero, like the beam (the crate's one driver, [`crate::continuation`]),
//! and an equilibrium is accepted only where the tangent stiffness is positive definite (a
//! stable equilibrium: Cholesky succeeds).
//!
//! This file holds the solver's public face; the equations and the linearisation are in
//! `chain.rs`, the path following (Newton, predictor, branch test) in `path.rs`.

use crate::beam::{Load, TipPose};

use super::chain::Dof;
use super::matrix::PrbMatrix;
use super::path::MAX_NEWTON;

/// Why a PRB equilibrium could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PrbError {
    /// The requested load has a NaN or infinite component; holds that load.
    #[error("load is not finite: {0}")]
    NonFiniteLoad(Load),
    /// Continuation stalled: Newton diverged, the tip jumped off the followed branch, or the
    /// iteration budget ran out before the end of the load path.
    #[error(
        "the PRB model has no equilibrium for {load} past {:.4} of the load path ({reason})",
        fraction
    )]
    NoEquilibrium {
        /// The end of the load path (nondimensional `alpha_x`, `alpha_y`, `beta`).
        load: Load,
        /// The last load-path fraction (0 to 1) where an equilibrium was accepted.
        fraction: f64,
        /// What stopped the continuation, in words.
        reason: String,
    },
    /// The tangent stiffness stopped being positive definite on the load path: the chain
    /// buckles or snaps through there, and the stable branch ends.
    #[error(
        "the PRB model reaches a critical point (its tangent stiffness turns singular) at {:.4} \
         of the load path to {load}: it buckles or snaps there",
        fraction
    )]
    Unstable {
        /// The end of the load path (nondimensional `alpha_x`, `alpha_y`, `beta`).
        load: Load,
        /// The last load-path fraction (0 to 1) where a stable equilibrium was accepted.
        fraction: f64,
    },
}

/// An equilibrium of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct PrbSolution {
    /// The load solved for (nondimensional `alpha_x`, `alpha_y`, `beta`).
    pub load: Load,
    /// The chain's tip: `a`, `b` in units of L, `phi` (the last segment's angle `Theta_N`)
    /// in radians.
    pub tip: TipPose,
    /// Joint angles (radians, revolute rows) and extensions (units of L, prismatic rows), in
    /// row order.
    pub q: Vec<f64>,
    /// Newton iterations spent on this load, continuation sub-steps included.
    pub iterations: u32,
}

/// One equilibrium as handed to a visitor: the configuration is borrowed, so following a load
/// path allocates nothing per case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrbCase<'a> {
    /// The load solved for (nondimensional `alpha_x`, `alpha_y`, `beta`).
    pub load: Load,
    /// The chain's tip: `a`, `b` in units of L, `phi` in radians.
    pub tip: TipPose,
    /// Joint angles (radians, revolute rows) and extensions (units of L, prismatic rows), in
    /// row order; borrowed from the solver's buffer.
    pub q: &'a [f64],
    /// Newton iterations spent on this load, continuation sub-steps included.
    pub iterations: u32,
}

impl PrbCase<'_> {
    /// An owned copy of this equilibrium.
    pub fn to_solution(&self) -> PrbSolution {
        PrbSolution {
            load: self.load,
            tip: self.tip,
            q: self.q.to_vec(),
            iterations: self.iterations,
        }
    }
}

/// How hard a solver tries before it gives up on a load path. A fit's trial models use tight
/// limits, so that failing ones cost little; the defaults suit a model being judged.
///
/// Only the smallest step reaches the continuation at present: the Newton limit and the
/// per-case budget are checked and stored but have never been applied (every attempt may
/// take 40 iterations, and no case has a budget), and applying them would change fitted
/// results.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverLimits {
    /// Newton iterations one attempt may take before the continuation step is halved (from a
    /// good predictor Newton converges in a handful).
    newton_limit: u32,
    /// Newton iterations a load path may spend per case, all attempts counted (the path gets
    /// `case_budget * steps + 100`).
    case_budget: u32,
    /// The smallest continuation step, as a fraction of the path, before giving up; a reported
    /// critical load is located only to within it.
    min_step: f64,
}

impl SolverLimits {
    /// Validated limits: every count at least 1, the step in (0, 1). A `const` built with
    /// this is checked when the crate compiles.
    pub const fn new(newton_limit: u32, case_budget: u32, min_step: f64) -> SolverLimits {
        assert!(newton_limit >= 1, "a Newton limit of 0 allows no iteration");
        assert!(case_budget >= 1, "a case budget of 0 allows no iteration");
        assert!(
            min_step > 0.0 && min_step < 1.0,
            "the smallest step must be in (0, 1)"
        );
        SolverLimits {
            newton_limit,
            case_budget,
            min_step,
        }
    }

    /// Checked at run time: the error says which limit is wrong.
    pub fn checked(
        newton_limit: u32,
        case_budget: u32,
        min_step: f64,
    ) -> Result<SolverLimits, String> {
        if newton_limit == 0 {
            return Err("the Newton limit must be at least 1".into());
        }
        if case_budget == 0 {
            return Err("the per-case Newton budget must be at least 1".into());
        }
        if !(min_step > 0.0 && min_step < 1.0) {
            return Err(format!(
                "the smallest continuation step must be in (0, 1), got {}",
                crate::text::bounded(min_step)
            ));
        }
        Ok(SolverLimits::new(newton_limit, case_budget, min_step))
    }
}

impl Default for SolverLimits {
    fn default() -> Self {
        SolverLimits::new(MAX_NEWTON, u32::MAX, MIN_STEP)
    }
}

/// Solves a PRB chain's statics. Cheap to build; holds no scratch between calls.
#[derive(Debug, Clone)]
pub struct PrbSolver {
    pub(super) gamma: Vec<f64>,
    pub(super) k_theta: Vec<f64>,
    /// `k_ex / c_e` per row (infinite for rows without an extension spring).
    pub(super) k_ex_scaled: Vec<f64>,
    pub(super) dofs: Vec<Dof>,
    /// The smallest continuation step before giving up on a load path.
    pub(super) min_step: f64,
    /// Newton iterations one load path may spend per case, all attempts counted.
    case_budget: u32,
    /// Newton iterations one attempt may take before the step is halved.
    newton_limit: u32,
}

/// The smallest continuation step (a fraction of the path) of a model being judged.
const MIN_STEP: f64 = 1e-7;

impl PrbSolver {
    /// `axial_compliance` is `c_e = I0 / (A0 L^2) = 1 / (12 (L/t0)^2)` of the beam; it only
    /// matters for extension springs.
    pub fn new(matrix: &PrbMatrix, axial_compliance: f64) -> PrbSolver {
        let rows = matrix.rows();
        let mut dofs = Vec::new();
        for (i, r) in rows.iter().enumerate() {
            if r.has_revolute() {
                dofs.push(Dof::Theta(i));
            }
            if r.has_prismatic() {
                dofs.push(Dof::Delta(i));
            }
        }
        PrbSolver {
            gamma: rows.iter().map(|r| r.gamma).collect(),
            k_theta: rows.iter().map(|r| r.k_theta).collect(),
            k_ex_scaled: rows.iter().map(|r| r.k_ex / axial_compliance).collect(),
            dofs,
            min_step: MIN_STEP,
            case_budget: u32::MAX,
            newton_limit: MAX_NEWTON,
        }
    }

    /// The solver with these effort limits (checked when the limits were made).
    pub fn with_limits(mut self, limits: SolverLimits) -> PrbSolver {
        self.newton_limit = limits.newton_limit;
        self.case_budget = limits.case_budget;
        self.min_step = limits.min_step;
        self
    }

    /// Degrees of freedom of the chain.
    pub fn dof_count(&self) -> usize {
        self.dofs.len()
    }

    /// Solves one load by continuation from the unloaded chain.
    pub fn solve(&self, load: Load) -> Result<PrbSolution, PrbError> {
        let mut v = self.solve_path(load, 1)?;
        // `solve_path_with` hands `visit` one case for each of its steps before it returns
        // `Ok`, so a one-step path that succeeded holds exactly one solution.
        #[allow(clippy::expect_used)]
        let last = v.pop().expect("a successful one-step path has one case");
        Ok(last)
    }

    /// Solves the proportional path to `end` at `k / steps`, `k = 1..=steps`, each case
    /// warm-started from the previous ones.
    pub fn solve_path(&self, end: Load, steps: u32) -> Result<Vec<PrbSolution>, PrbError> {
        let mut out = Vec::with_capacity(steps as usize);
        self.solve_path_with(end, steps, |case| out.push(case.to_solution()))?;
        Ok(out)
    }

    /// As [`Self::solve_path`], handing each case to `visit` (no allocation per case).
    pub fn solve_path_with(
        &self,
        end: Load,
        steps: u32,
        visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        self.follow_with(end, steps.max(1), |lambda| end.scaled(lambda), visit)
    }

    /// Follows the loads of `rows` in order, from the unloaded chain (measured data, DESIGN
    /// §9: a specimen's path is the polyline through its rows), handing the case at each row
    /// to `visit`. Between rows the load moves along the straight line from one row's load to
    /// the next (from zero to the first), with the same continuation as a proportional path.
    pub fn solve_rows_with(
        &self,
        rows: &[Load],
        visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        let Some(&last) = rows.last() else {
            return Ok(());
        };
        if let Some(bad) = rows.iter().find(|l| !l.is_finite()) {
            return Err(PrbError::NonFiniteLoad(*bad));
        }
        let n = rows.len();
        let at = |lambda: f64| {
            let x = lambda * n as f64;
            // At a row's own fraction (to rounding), the row's load exactly.
            let nearest = x.round();
            if (x - nearest).abs() < 1e-9 && nearest >= 1.0 {
                return rows[(nearest as usize).min(n) - 1];
            }
            let k = (x.floor().max(0.0) as usize).min(n - 1);
            let t = x - k as f64;
            let from = if k == 0 {
                Load {
                    alpha_x: 0.0,
                    alpha_y: 0.0,
                    beta: 0.0,
                }
            } else {
                rows[k - 1]
            };
            let to = rows[k];
            Load {
                alpha_x: from.alpha_x + t * (to.alpha_x - from.alpha_x),
                alpha_y: from.alpha_y + t * (to.alpha_y - from.alpha_y),
                beta: from.beta + t * (to.beta - from.beta),
            }
        };
        self.follow_with(last, n as u32, at, visit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_checked() {
        assert!(SolverLimits::checked(0, 5, 1e-3)
            .unwrap_err()
            .contains("Newton limit"));
        assert!(SolverLimits::checked(5, 0, 1e-3)
            .unwrap_err()
            .contains("budget"));
        for bad in [0.0, -1.0, 1.0, f64::NAN] {
            assert!(SolverLimits::checked(5, 5, bad).is_err(), "{bad}");
        }
        assert_eq!(
            SolverLimits::checked(12, 20, 1e-3),
            Ok(SolverLimits::new(12, 20, 1e-3))
        );
    }
}
