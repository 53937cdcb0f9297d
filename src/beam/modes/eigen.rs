//! The symmetric-definite eigenproblem `K q = omega^2 M q`, lowest modes first.

use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen};

use super::ModesError;

/// The lowest modes: `omega^2` ascending (negative for an unstable equilibrium) and the
/// coefficient vectors, `M`-normalised.
#[derive(Debug, Clone)]
pub(crate) struct Lowest {
    /// `omega^2`, ascending.
    pub omega_sq: Vec<f64>,
    /// One vector per mode.
    pub vectors: Vec<DVector<f64>>,
}

/// The `count` lowest eigenpairs of `K q = omega^2 M q` (`K`, `M` symmetric, `M` positive
/// definite).
///
/// A stable equilibrium has `K` positive definite: then the problem is solved as
/// `L^-1 M L^-T y = (1 / omega^2) y` with `K = L L^T`, whose largest eigenvalues are the
/// wanted ones, so they come with an error of round-off relative to themselves however stiff
/// the axial and shear fields make `K` (their huge `omega^2` become tiny eigenvalues that
/// cannot spoil the large ones). Otherwise (at or past a critical point) it is solved
/// through `M = L L^T` and the negative `omega^2` are reported.
pub(crate) fn lowest(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    count: usize,
) -> Result<Lowest, ModesError> {
    let count = count.min(k.nrows());
    if let Some(chol) = Cholesky::new(k.clone()) {
        let l = chol.l();
        let pairs = reduced(&l, m)?;
        let mut order: Vec<usize> = (0..pairs.eigenvalues.len()).collect();
        order.sort_by(|&a, &b| pairs.eigenvalues[b].total_cmp(&pairs.eigenvalues[a]));
        let mut omega_sq = Vec::with_capacity(count);
        let mut vectors = Vec::with_capacity(count);
        for &i in order.iter().take(count) {
            let mu = pairs.eigenvalues[i];
            if mu.is_nan() || mu <= 0.0 {
                return Err(ModesError::Singular(
                    "the mass matrix is not positive definite",
                ));
            }
            let y = pairs.eigenvectors.column(i).into_owned();
            let q = l
                .transpose()
                .solve_upper_triangular(&y)
                .ok_or(ModesError::Singular("the stiffness matrix"))?;
            // y is unit, so q^T K q = 1 and q^T M q = mu: scale to unit modal mass.
            omega_sq.push(1.0 / mu);
            vectors.push(q / mu.sqrt());
        }
        return Ok(Lowest { omega_sq, vectors });
    }
    let chol = Cholesky::new(m.clone()).ok_or(ModesError::Singular(
        "the mass matrix is not positive definite",
    ))?;
    let l = chol.l();
    let pairs = reduced(&l, k)?;
    let mut order: Vec<usize> = (0..pairs.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| pairs.eigenvalues[a].total_cmp(&pairs.eigenvalues[b]));
    let mut omega_sq = Vec::with_capacity(count);
    let mut vectors = Vec::with_capacity(count);
    for &i in order.iter().take(count) {
        let y = pairs.eigenvectors.column(i).into_owned();
        let q = l
            .transpose()
            .solve_upper_triangular(&y)
            .ok_or(ModesError::Singular(
                "the mass matrix is not positive definite",
            ))?;
        omega_sq.push(pairs.eigenvalues[i]);
        vectors.push(q);
    }
    Ok(Lowest { omega_sq, vectors })
}

/// The eigen-decomposition of `L^-1 A L^-T`.
fn reduced(
    l: &DMatrix<f64>,
    a: &DMatrix<f64>,
) -> Result<SymmetricEigen<f64, nalgebra::Dyn>, ModesError> {
    let x = l
        .solve_lower_triangular(a)
        .ok_or(ModesError::Singular("a triangular factor"))?;
    let mut c = l
        .solve_lower_triangular(&x.transpose())
        .ok_or(ModesError::Singular("a triangular factor"))?;
    // Symmetric up to round-off; make it exactly so.
    let n = c.nrows();
    for i in 0..n {
        for j in 0..i {
            let v = 0.5 * (c[(i, j)] + c[(j, i)]);
            c[(i, j)] = v;
            c[(j, i)] = v;
        }
    }
    if c.iter().any(|v| !v.is_finite()) {
        return Err(ModesError::NotFinite("the reduced eigenproblem"));
    }
    Ok(SymmetricEigen::new(c))
}
