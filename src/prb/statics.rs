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
//! stable equilibrium: Cholesky succeeds).//!
//! This file holds the solving of loads and load paths; the solver, its limits and the
//! equations with their linearisation are in `chain.rs`, the path following (Newton,
//! predictor, branch test) and what a path returns in `path.rs`.

use crate::beam::Load;

use super::chain::PrbSolver;
use super::path::{PrbCase, PrbError, PrbSolution, WarmStart};

impl PrbSolver {
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
        self.follow_with(end, steps.max(1), |lambda| end.scaled(lambda), None, visit)
    }

    /// As [`Self::solve_path_with`] (or [`Self::solve_rows_with`], given `rows`), each case
    /// first tried from `warm`'s equilibrium of the same case (see [`WarmStart`]).
    pub fn solve_warm_with(
        &self,
        end: Load,
        steps: u32,
        rows: Option<&[Load]>,
        warm: &WarmStart,
        visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        match rows {
            Some(rows) => self.rows_with(rows, Some(warm), visit),
            None => self.follow_with(
                end,
                steps.max(1),
                |lambda| end.scaled(lambda),
                Some(warm),
                visit,
            ),
        }
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
        self.rows_with(rows, None, visit)
    }

    /// The work of [`Self::solve_rows_with`], warm-started or not.
    fn rows_with(
        &self,
        rows: &[Load],
        warm: Option<&WarmStart>,
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
        self.follow_with(last, n as u32, at, warm, visit)
    }
}
