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
        // Dense costs about 10 n^3, the subspace iteration about 12 steps of 6 n^2 p with
        // p = count + 4: the block wins from n of about 60 (a mechanism's flexures).
        if k.nrows() > 64 {
            if let Some(found) = subspace(&chol, m, count) {
                return Ok(found);
            }
        }
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

/// As [`lowest`], the frequencies alone (no vectors: empty): at a stable equilibrium of up
/// to 64 unknowns the reduced problem's eigenvalues without its eigenvectors, which is most
/// of the dense solve's cost; otherwise [`lowest`]'s.
pub(crate) fn lowest_values(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    count: usize,
) -> Result<Lowest, ModesError> {
    let count = count.min(k.nrows());
    if k.nrows() > 64 {
        return lowest(k, m, count);
    }
    let Some(chol) = Cholesky::new(k.clone()) else {
        return lowest(k, m, count);
    };
    let c = reduced_matrix(&chol.l(), m)?;
    let mut mu: Vec<f64> = c.symmetric_eigenvalues().iter().copied().collect();
    mu.sort_by(|a, b| b.total_cmp(a));
    let mut omega_sq = Vec::with_capacity(count);
    for &v in mu.iter().take(count) {
        if v.is_nan() || v <= 0.0 {
            return Err(ModesError::Singular(
                "the mass matrix is not positive definite",
            ));
        }
        omega_sq.push(1.0 / v);
    }
    Ok(Lowest {
        omega_sq,
        vectors: Vec::new(),
    })
}

/// Subspace iteration for the lowest `count` modes: the block `X` of `count + 4` vectors
/// goes to `K^-1 M X` and is replaced by the Ritz vectors of the pencil on it, until the
/// wanted Ritz values agree with the last to 1e-14. The block's share of each unwanted
/// mode shrinks by `omega_wanted^2 / omega_(count+5)^2` per step (0.012 for a cantilever's
/// third and eighth), so a few steps do; the Ritz values never fall below the true ones
/// (min-max), and the block is started from generic (pseudo-random) vectors so that no mode
/// is missing from it. The Ritz pencil uses `Y^T K Y = Y^T M X`, so `K`'s huge axial and
/// shear entries never multiply anything. `None` if it has not converged in 60 steps (the
/// caller then solves the dense problem).
fn subspace(chol: &Cholesky<f64, nalgebra::Dyn>, m: &DMatrix<f64>, count: usize) -> Option<Lowest> {
    let n = m.nrows();
    let p = (count + 4).min(n);
    if p == n {
        return None;
    }
    // A fixed linear congruential sequence: generic, and the same answer every run.
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut x = DMatrix::<f64>::from_fn(n, p, |_, _| {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    });
    let mut last = vec![f64::INFINITY; count];
    for step in 0..60 {
        let mx = m * &x;
        let y = chol.solve(&mx);
        let kr = sym(y.transpose() * &mx);
        let my = m * &y;
        let mr = sym(y.transpose() * &my);
        let lr = Cholesky::new(mr)?.l();
        let a = lr.solve_lower_triangular(&kr)?;
        let c = sym(lr.solve_lower_triangular(&a.transpose())?);
        let eig = SymmetricEigen::new(c);
        let mut order: Vec<usize> = (0..p).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        // Ritz vectors: Y L^-T w, unit modal mass.
        let mut z = DMatrix::<f64>::zeros(p, p);
        for (c, &i) in order.iter().enumerate() {
            let w = lr
                .transpose()
                .solve_upper_triangular(&eig.eigenvectors.column(i).into_owned())?;
            z.set_column(c, &w);
        }
        x = &y * z;
        let values: Vec<f64> = order
            .iter()
            .take(count)
            .map(|&i| eig.eigenvalues[i])
            .collect();
        if values.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return None;
        }
        let settled = values
            .iter()
            .zip(&last)
            .all(|(v, l)| (v - l).abs() <= 1e-14 * v);
        last = values;
        if settled && step >= 1 {
            let vectors = (0..count).map(|c| x.column(c).into_owned()).collect();
            return Some(Lowest {
                omega_sq: last,
                vectors,
            });
        }
    }
    None
}

/// `(a + a^T) / 2`.
fn sym(a: DMatrix<f64>) -> DMatrix<f64> {
    (&a + a.transpose()) * 0.5
}

/// The eigen-decomposition of `L^-1 A L^-T`.
fn reduced(
    l: &DMatrix<f64>,
    a: &DMatrix<f64>,
) -> Result<SymmetricEigen<f64, nalgebra::Dyn>, ModesError> {
    Ok(SymmetricEigen::new(reduced_matrix(l, a)?))
}

/// `L^-1 A L^-T`, exactly symmetric.
fn reduced_matrix(l: &DMatrix<f64>, a: &DMatrix<f64>) -> Result<DMatrix<f64>, ModesError> {
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
    Ok(c)
}
