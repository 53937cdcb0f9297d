//! The PRB mechanism: every flexure replaced by the scene's PRB matrix scaled to it (DESIGN
//! §8; the matrix is nondimensional, so it serves flexures of any size), the closed chain
//! solved by the same outer Newton as the exact mechanism ([`super::solve`]): each chain is
//! solved under its unknown tip wrench, and the loop is closed on the tip poses.
//!
//! A chain under a wrench is solved by Newton on the PRB statics' analytic tangent stiffness
//! from its last configuration (a few iterations), falling back to
//! [`PrbSolver::solve`]'s continuation from the unloaded chain if that fails. Chains are
//! exact to 1e-13 (the PRB Newton's tolerance), so the mechanism's accuracy is its `tol`.
//!
//! A chain with fewer degrees of freedom than its tip must have (a 1R model whose tip must
//! keep its angle while it moves, as in a fixed-guided flexure) makes the mechanism's
//! Jacobian singular in the unloaded pose, reported as [`MechError::Immobile`].

use crate::beam::{Load, TipPose};
use crate::linalg::solve_dense;
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::Mechanism;

use super::geometry::Geometry;
use super::solve::{MechSolver, TipModel};
use super::{MechCase, MechError, TipFailure};

/// Newton iterations of a warm chain solve before falling back to continuation.
const CHAIN_NEWTON: u32 = 30;
/// The warm chain solve stops when its update is below this.
const CHAIN_TOL: f64 = 1e-13;

/// One flexure as a PRB chain.
#[derive(Debug, Clone)]
pub struct ChainTip {
    /// The chain's statics (the flexure's own axial compliance).
    pub solver: PrbSolver,
}

/// A chain's configuration and tip.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainState {
    /// Joint angles and extensions (see [`PrbSolver`]).
    pub q: Vec<f64>,
    /// Its tip.
    pub tip: TipPose,
    /// The wrench it balances.
    pub load: Load,
}

impl ChainTip {
    fn newton(&self, wrench: Load, from: &[f64]) -> Option<Vec<f64>> {
        let m = from.len();
        let mut q = from.to_vec();
        for _ in 0..CHAIN_NEWTON {
            let (r, mut jac) = self.solver.residual_and_jacobian(wrench, &q);
            let mut step: Vec<f64> = r.iter().map(|v| -v).collect();
            if !solve_dense(&mut jac, &mut step, m) {
                return None;
            }
            let size = step.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            // Damped: no joint turns by more than half a radian per iteration.
            let damping = if size > 0.5 { 0.5 / size } else { 1.0 };
            q.iter_mut().zip(&step).for_each(|(a, d)| *a += damping * d);
            if size <= CHAIN_TOL {
                return Some(q);
            }
        }
        None
    }
}

impl TipModel for ChainTip {
    type Warm = ChainState;

    fn unloaded(&self) -> ChainState {
        let q = vec![0.0; self.solver.dof_count()];
        ChainState {
            tip: self.solver.tip_pose(&q),
            load: Load::default(),
            q,
        }
    }

    fn solve(&self, wrench: Load, from: &ChainState) -> Result<ChainState, TipFailure> {
        let q = match self.newton(wrench, &from.q) {
            Some(q) => q,
            None => self.solver.solve(wrench)?.q,
        };
        Ok(ChainState {
            tip: self.solver.tip_pose(&q),
            load: wrench,
            q,
        })
    }

    fn tip(&self, state: &ChainState) -> TipPose {
        state.tip
    }

    fn load_stability(&self, state: &ChainState) -> f64 {
        // The sign of the tangent stiffness's determinant: the chain's compliance has its
        // poles where that determinant crosses zero.
        let m = state.q.len();
        let (_, mut k) = self.solver.residual_and_jacobian(state.load, &state.q);
        let mut rhs = vec![0.0; m];
        crate::mech::solve::det_sign(&mut k, &mut rhs, m)
    }
}

/// The PRB mechanism solver: `matrix` in place of every flexure of `mechanism`, Newton at
/// `tol`.
pub fn solver(mechanism: &Mechanism, matrix: &PrbMatrix, tol: f64) -> MechSolver<ChainTip> {
    let models = mechanism
        .flexures
        .iter()
        .map(|f| ChainTip {
            solver: PrbSolver::new(matrix, f.beam.model().axial_compliance()),
        })
        .collect();
    MechSolver::new(Geometry::new(mechanism), models, tol)
}

/// Every drive path of `mechanism` with `matrix` for every flexure.
pub fn solve(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    tol: f64,
) -> Result<Vec<Vec<MechCase>>, MechError> {
    let s = solver(mechanism, matrix, tol);
    mechanism
        .drives
        .iter()
        .enumerate()
        .map(|(i, d)| s.solve_drive(&mechanism.nondimensional(d), d.steps, i + 1))
        .collect()
}
