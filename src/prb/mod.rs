//! PRB models: the PRB matrix, topology names, kinematics and statics (DESIGN §3), and the
//! published models.

mod chain;
mod matrix;
mod notation;
mod path;
pub mod published;
mod statics;
mod stress;

pub use chain::{Linearised, PrbSolver, SolverLimits};
pub use matrix::{Column, MatrixError, PrbMatrix, PrbRow, GAMMA_SUM_TOL, MAX_SEGMENTS, MAX_SPRING};
pub use path::{PrbCase, PrbError, PrbSolution};
