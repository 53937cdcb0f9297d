//! PRB models: the PRB matrix, topology names, kinematics and statics (DESIGN §3), and the
//! published models.

mod matrix;
pub mod published;
mod statics;

pub use matrix::{Column, MatrixError, PrbMatrix, PrbRow, GAMMA_SUM_TOL, MAX_SPRING};
pub use statics::{Linearised, PrbCase, PrbError, PrbSolution, PrbSolver, SolverLimits};
