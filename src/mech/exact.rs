//! The exact mechanism: every flexure is the §2 beam (DESIGN §8), solved by
//! [`BeamSolver::solve_near`] under its tip wrench, warm-started from its last equilibrium.
//!
//! Cost: each Newton iteration of the mechanism solves every flexure `1 + n_i` times
//! (finite-difference Jacobian, `n_i` = 3 clamped, 2 pinned or coupled), each a warm-started
//! shooting Newton of one to three shots. The analytic tip compliance from the beam's
//! variational equations would replace the `n_i` extra solves; it is not done yet.
//!
//! Accuracy: Newton stops at the solver's `tol` on every tip compatibility residual; the
//! beam's tips are good to its `Resolution::claimed_tip_error` (10 times the beam's tol), so
//! pick the mechanism's `tol` at about the beam's.

use crate::beam::warm::WarmBeam;
use crate::beam::{BeamSolver, Load, Resolution, TipPose};
use crate::scene::Mechanism;

use super::geometry::Geometry;
use super::solve::{MechSolver, TipModel};
use super::{MechCase, MechError, TipFailure};

/// One flexure as the exact beam.
#[derive(Debug, Clone, Copy)]
pub struct BeamTip {
    /// Its solver (its own slenderness, effects and resolution).
    pub solver: BeamSolver,
}

impl TipModel for BeamTip {
    type Warm = WarmBeam;

    fn unloaded(&self) -> WarmBeam {
        WarmBeam::unloaded()
    }

    fn solve(&self, wrench: Load, from: &WarmBeam) -> Result<WarmBeam, TipFailure> {
        Ok(self.solver.solve_near(wrench, Some(from))?)
    }

    fn tip(&self, state: &WarmBeam) -> TipPose {
        state.tip
    }

    fn load_stability(&self, state: &WarmBeam) -> f64 {
        if state.stability < 0.0 {
            -1.0
        } else {
            1.0
        }
    }
}

/// The exact mechanism solver of `mechanism`: each flexure its own beam at `resolution`
/// (its shape sampling is not used; two points are kept), Newton at the resolution's tol.
pub fn solver(
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<MechSolver<BeamTip>, MechError> {
    let resolution = Resolution {
        shape_points: 2,
        ..resolution
    };
    let mut models = Vec::with_capacity(mechanism.flexures.len());
    for (i, f) in mechanism.flexures.iter().enumerate() {
        let solver =
            BeamSolver::new(f.beam.model(), resolution).map_err(|e| MechError::Flexure {
                flexure: i + 1,
                source: e.into(),
            })?;
        models.push(BeamTip { solver });
    }
    Ok(MechSolver::new(
        Geometry::new(mechanism),
        models,
        resolution.tol,
    ))
}

/// Every drive path of `mechanism`, solved exactly: one `Vec` of cases per drive.
pub fn solve(
    mechanism: &Mechanism,
    resolution: Resolution,
) -> Result<Vec<Vec<MechCase>>, MechError> {
    let s = solver(mechanism, resolution)?;
    mechanism
        .drives
        .iter()
        .enumerate()
        .map(|(i, d)| s.solve_drive(&mechanism.nondimensional(d), d.steps, i + 1))
        .collect()
}
