//! Small dense linear algebra for the solvers' Newton steps (systems of a few unknowns,
//! where a library's generality costs more than it saves): the solves, and the natural
//! frequencies built on them.

mod frequencies;
mod solve;

pub use frequencies::frequencies;
pub use solve::{cholesky_solve, lu_solve, solve_dense, solve_many, LuInfo};
