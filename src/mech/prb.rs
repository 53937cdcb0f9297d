//! The PRB mechanism: every flexure replaced by the scene's PRB matrix scaled to it (DESIGN
//! §8; the matrix is nondimensional, so it serves flexures of any size), the closed chain's
//! equilibrium solved by the same outer Newton as the exact mechanism ([`super::solve`]).
//!
//! A chain's unknowns are its tip wrench *and* its joint coordinates `q` (angles,
//! extensions), its extra equations the joints' equilibrium `K q - J(q)^T w = 0`, all with
//! the analytic Jacobian of [`PrbSolver::linearise`]. Being unknowns, the joint coordinates
//! are never solved under a given load, so a chain past its own load-controlled limit (a
//! compressed flexure held by the stage) is as regular as any other.
//!
//! A chain with fewer degrees of freedom than its tip must have (a 1R model whose tip must
//! keep its angle while it moves, as in a fixed-guided flexure) makes the mechanism's
//! Jacobian singular in the unloaded pose, reported as [`MechError::Immobile`].

use crate::beam::{BeamModel, Load, Stress};
use crate::cancel::CancelToken;
use crate::linalg::lu_solve;
use std::cell::RefCell;

use crate::prb::{Linearised, PrbMatrix, PrbSolver};
use crate::scene::Mechanism;

use super::geometry::Geometry;
use super::solve::{FlexEval, FlexureModel, MechSolver};
use super::{MechCase, MechError, TipFailure};

/// One flexure as a PRB chain.
#[derive(Debug, Clone)]
pub struct ChainFlexure {
    /// The chain's statics (the flexure's own axial compliance).
    pub solver: PrbSolver,
    /// Storage reused by every linearisation.
    scratch: RefCell<Linearised>,
    /// The beam whose section the chain stands for, for its stress estimate (DESIGN §11;
    /// none: no estimate, as in a fit's trials).
    section: Option<BeamModel>,
}

impl ChainFlexure {
    /// The chain of `solver`.
    pub fn new(solver: PrbSolver) -> ChainFlexure {
        let scratch = RefCell::new(solver.linearised());
        ChainFlexure {
            solver,
            scratch,
            section: None,
        }
    }

    /// The chain that also estimates its stress with `section`'s cross-section
    /// ([`PrbSolver::max_stress`]).
    pub fn with_section(mut self, section: BeamModel) -> ChainFlexure {
        self.section = Some(section);
        self
    }
}

impl FlexureModel for ChainFlexure {
    fn internal(&self) -> usize {
        self.solver.dof_count()
    }

    fn eval(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
        let m = z.len();
        let mut lin = self.scratch.borrow_mut();
        self.solver
            .linearise_into(Load::new(w[0], w[1], w[2]), z, &mut lin);
        let cols = 3 + m;
        let mut jacobian = vec![0.0; (4 + m) * cols];
        // Tip rows: d(a, b, phi)/dq.
        for r in 0..3 {
            jacobian[r * cols + 3..(r + 1) * cols]
                .copy_from_slice(&lin.tip_jacobian[r * m..(r + 1) * m]);
        }
        // The tip moment is the unknown w itself.
        jacobian[3 * cols + 2] = 1.0;
        // Joint equilibrium rows: d/dw = -J^T, d/dq = the tangent stiffness.
        for r in 0..m {
            let row = (4 + r) * cols;
            for c in 0..3 {
                jacobian[row + c] = -lin.tip_jacobian[c * m + r];
            }
            jacobian[row + 3..row + cols].copy_from_slice(&lin.stiffness[r * m..(r + 1) * m]);
        }
        Ok(FlexEval {
            tip: lin.tip,
            tip_moment: w[2],
            internal: lin.residual.clone(),
            jacobian,
            shape: Vec::new(),
        })
    }

    fn load_stable(&self, eval: &FlexEval, _w: [f64; 3], z: &[f64]) -> bool {
        // The tangent stiffness positive definite: its determinant's sign along the path
        // from the unloaded chain (positive there) and no negative pivot.
        let m = z.len();
        let cols = 3 + m;
        let mut k: Vec<f64> = (0..m)
            .flat_map(|r| eval.jacobian[(4 + r) * cols + 3..(4 + r + 1) * cols].to_vec())
            .collect();
        let mut rhs = vec![0.0; m];
        m == 0 || lu_solve(&mut k, &mut rhs, m).is_some_and(|lu| lu.det_sign > 0.0)
    }

    fn cell_derivatives(&self, w: [f64; 3], z: &[f64], out: &mut Vec<f64>) -> bool {
        let mut lin = self.scratch.borrow_mut();
        self.solver
            .linearise_into(Load::new(w[0], w[1], w[2]), z, &mut lin);
        self.solver.cell_partials(z, &mut lin);
        let cols = lin.cell_tip.len() / 3;
        out.clear();
        out.extend_from_slice(&lin.cell_tip);
        // The tip moment is the unknown itself.
        out.extend(std::iter::repeat_n(0.0, cols));
        out.extend_from_slice(&lin.cell_residual);
        true
    }

    fn stress(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> Option<Stress> {
        let section = self.section.as_ref()?;
        self.solver
            .max_stress(section, Load::new(w[0], w[1], eval.tip_moment), z)
    }
}

/// The PRB mechanism solver: `matrix` in place of every flexure of `mechanism`, Newton at
/// `tol`; each chain estimates its flexure's stress ([`PrbSolver::max_stress`]).
pub fn solver(mechanism: &Mechanism, matrix: &PrbMatrix, tol: f64) -> MechSolver<ChainFlexure> {
    let models = mechanism
        .flexures
        .iter()
        .map(|f| {
            let model = f.model();
            ChainFlexure::new(PrbSolver::new(matrix, model.axial_compliance())).with_section(model)
        })
        .collect();
    MechSolver::new(Geometry::new(mechanism), models, tol)
}

impl MechSolver<ChainFlexure> {
    /// The solver without the chains' stress estimates (a fit's trials need none).
    pub fn without_stress(mut self) -> MechSolver<ChainFlexure> {
        for m in &mut self.models {
            m.section = None;
        }
        self
    }
}

/// Every drive path of `mechanism` with `matrix` for every flexure, without the chains'
/// stress estimates (judging a whole model's motion and its cost; [`follow`] gives them).
pub fn solve(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    tol: f64,
) -> Result<Vec<Vec<MechCase>>, MechError> {
    solver(mechanism, matrix, tol)
        .without_stress()
        .solve_all(mechanism)
}

/// One model along every drive: the cases it reached per drive, and why it stopped where it
/// did not reach the end.
pub struct Followed {
    /// Per drive, the cases reached.
    pub drives: Vec<Vec<MechCase>>,
    /// Per drive, why it stopped, if it did.
    pub failures: Vec<Option<MechError>>,
}

/// `matrix` in every flexure of `mechanism`, along each drive (through a measured drive's
/// rows), each chain's stress estimated ([`PrbSolver::max_stress`]); where it stops at a critical point (or finds no equilibrium) after `k` cases, the
/// drive's first `k` cases are solved again as a drive of their own (the same cases).
///
/// Stops soon after `cancel` is cancelled: the drive it was on ends there
/// ([`MechError::Cancelled`]), and the drives after it are not followed.
pub fn follow(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    tol: f64,
    cancel: &CancelToken,
) -> Followed {
    let solver = solver(mechanism, matrix, tol).with_cancel(cancel);
    let mut out = Followed {
        drives: Vec::with_capacity(mechanism.drives.len()),
        failures: Vec::with_capacity(mechanism.drives.len()),
    };
    for (i, d) in mechanism.drives.iter().enumerate() {
        if cancel.is_cancelled() {
            out.drives.push(Vec::new());
            out.failures.push(Some(MechError::Cancelled));
            continue;
        }
        let path = mechanism.drive_path(d);
        let steps = path.steps.max(1);
        match solver.solve_path(&path, i + 1) {
            Ok(cases) => {
                out.drives.push(cases);
                out.failures.push(None);
            }
            Err(e) => {
                let reached_fraction = match &e {
                    MechError::Critical { fraction, .. }
                    | MechError::NoEquilibrium { fraction, .. } => *fraction,
                    MechError::Immobile { .. }
                    | MechError::Indeterminate { .. }
                    | MechError::Flexure { .. }
                    | MechError::Cancelled => 0.0,
                };
                // Cases sit at k / steps; the small margin absorbs the fraction's rounding.
                let k = ((reached_fraction * f64::from(steps) + 1e-6).floor() as u32).min(steps);
                let part = f64::from(k) / f64::from(steps);
                let cases = if k == 0 {
                    Vec::new()
                } else {
                    solver
                        .solve_path(&path.first(k), i + 1)
                        .map(|cases| {
                            cases
                                .into_iter()
                                .map(|mut c| {
                                    c.fraction *= part;
                                    c
                                })
                                .collect()
                        })
                        .unwrap_or_default()
                };
                out.drives.push(cases);
                out.failures.push(Some(e));
            }
        }
    }
    out
}
