//! Small dense linear algebra for the solvers' Newton steps (systems of a few unknowns,
//! where a library's generality costs more than it saves): the solves, and the natural
//! frequencies built on them.

mod frequencies;
mod solve;

pub use frequencies::frequencies;
pub use solve::{cholesky_solve, factored_solve, lu_solve, solve_dense, solve_many, LuInfo};

/// `B B^T + n I` of the `n` x `n` row-major `b`: symmetric positive definite with every
/// eigenvalue at least `n`, the tests' well-conditioned matrix.
#[cfg(test)]
fn spd_test_matrix(b: &[f64], n: usize) -> Vec<f64> {
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let mut v = if i == j { n as f64 } else { 0.0 };
            for t in 0..n {
                v += b[i * n + t] * b[j * n + t];
            }
            a[i * n + j] = v;
        }
    }
    a
}
