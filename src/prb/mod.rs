//! PRB models: the PRB matrix, topology names, kinematics and statics (DESIGN §3), natural
//! frequencies (modes.rs, DESIGN §10), and the published models.

mod chain;
mod matrix;
mod modes;
mod notation;
mod path;
pub mod published;
mod statics;
mod stress;
mod workspace;

pub use chain::{Linearised, PrbSolver, SolverLimits, CELLS_PER_ROW};
pub use matrix::{
    Column, MatrixError, PrbMatrix, PrbRow, GAMMA_SUM_TOL, MAX_SEGMENTS, MAX_SPRING, MU_SUM_TOL,
};
pub use modes::{ModesError, TipBody};
pub use path::{PrbCase, PrbError, PrbSolution, WarmStart};
