//! Small dense linear algebra for the solvers' Newton steps (systems of a few unknowns,
//! where a library's generality costs more than it saves).

/// Gaussian elimination with partial pivoting on a small dense row-major system; the
/// solution replaces `rhs`. Returns false for a singular matrix.
pub fn solve_dense(matrix: &mut [f64], rhs: &mut [f64], n: usize) -> bool {
    lu_solve(matrix, rhs, n).is_some()
}

/// Gaussian elimination with partial pivoting of the `n` x `n` row-major `matrix` against
/// `m` right-hand sides at once (`rhs`, `n` x `m` row-major), the solutions replacing them:
/// one elimination for all of them. `false` for a non-finite or exactly singular matrix or a
/// non-finite solution.
pub fn solve_many(matrix: &mut [f64], rhs: &mut [f64], n: usize, m: usize) -> bool {
    // A PRB chain's tip sensitivity: a few unknowns against the tip's three rows, in every
    // case of every fit evaluation. The same arithmetic, in the same order, on arrays.
    match (n, m) {
        (1, 3) => solve_many_fixed::<1, 3>(matrix, rhs),
        (2, 3) => solve_many_fixed::<2, 3>(matrix, rhs),
        (3, 3) => solve_many_fixed::<3, 3>(matrix, rhs),
        (4, 3) => solve_many_fixed::<4, 3>(matrix, rhs),
        _ => solve_many_general(matrix, rhs, n, m),
    }
}

/// [`solve_many`] for `N` x `N` against `M` right-hand sides: the same operations in the
/// same order (so the same result to the bit), on arrays the compiler unrolls.
fn solve_many_fixed<const N: usize, const M: usize>(matrix: &mut [f64], rhs: &mut [f64]) -> bool {
    let mut a = [[0.0; N]; N];
    let mut x = [[0.0; M]; N];
    for i in 0..N {
        a[i].copy_from_slice(&matrix[i * N..(i + 1) * N]);
        x[i].copy_from_slice(&rhs[i * M..(i + 1) * M]);
    }
    let solved = eliminate_arrays(&mut a, &mut x);
    for i in 0..N {
        matrix[i * N..(i + 1) * N].copy_from_slice(&a[i]);
        rhs[i * M..(i + 1) * M].copy_from_slice(&x[i]);
    }
    solved && x.iter().flatten().all(|v| v.is_finite())
}

/// The elimination and back substitution of [`solve_many_fixed`].
#[allow(clippy::needless_range_loop)] // the general version's index order, kept to the bit
fn eliminate_arrays<const N: usize, const M: usize>(
    a: &mut [[f64; N]; N],
    x: &mut [[f64; M]; N],
) -> bool {
    for col in 0..N {
        let mut pivot = col;
        let mut best = a[col][col].abs();
        for i in col + 1..N {
            let v = a[i][col].abs();
            if v > best {
                best = v;
                pivot = i;
            }
        }
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        if pivot != col {
            a.swap(col, pivot);
            x.swap(col, pivot);
        }
        let p = a[col][col];
        for i in col + 1..N {
            let f = a[i][col] / p;
            if f == 0.0 {
                continue;
            }
            for j in col..N {
                a[i][j] -= f * a[col][j];
            }
            for j in 0..M {
                x[i][j] -= f * x[col][j];
            }
        }
    }
    for i in (0..N).rev() {
        let d = a[i][i];
        for j in 0..M {
            let mut v = x[i][j];
            for k in i + 1..N {
                v -= a[i][k] * x[k][j];
            }
            x[i][j] = v / d;
        }
    }
    true
}

/// [`solve_many`] for any size.
fn solve_many_general(matrix: &mut [f64], rhs: &mut [f64], n: usize, m: usize) -> bool {
    for col in 0..n {
        let pivot = pivot_row(matrix, n, col);
        let best = matrix[pivot * n + col].abs();
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        if pivot != col {
            for j in 0..n {
                matrix.swap(col * n + j, pivot * n + j);
            }
            for j in 0..m {
                rhs.swap(col * m + j, pivot * m + j);
            }
        }
        let p = matrix[col * n + col];
        for i in col + 1..n {
            let f = matrix[i * n + col] / p;
            if f == 0.0 {
                continue;
            }
            for j in col..n {
                matrix[i * n + j] -= f * matrix[col * n + j];
            }
            for j in 0..m {
                rhs[i * m + j] -= f * rhs[col * m + j];
            }
        }
    }
    for i in (0..n).rev() {
        let d = matrix[i * n + i];
        for j in 0..m {
            let mut v = rhs[i * m + j];
            for k in i + 1..n {
                v -= matrix[i * n + k] * rhs[k * m + j];
            }
            rhs[i * m + j] = v / d;
        }
    }
    rhs.iter().all(|v| v.is_finite())
}

/// Partial pivoting: the row at or below `col` with the largest entry in column `col` (the
/// first of equals).
#[inline]
fn pivot_row(matrix: &[f64], n: usize, col: usize) -> usize {
    let mut pivot = col;
    let mut best = matrix[col * n + col].abs();
    for i in col + 1..n {
        let v = matrix[i * n + col].abs();
        if v > best {
            (pivot, best) = (i, v);
        }
    }
    pivot
}

/// What an elimination learnt about the matrix besides the solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LuInfo {
    /// The sign of the determinant (+1 or -1): a change of sign along a path marks a limit
    /// point or a bifurcation.
    pub det_sign: f64,
    /// Smallest pivot over largest: near round-off, the matrix is numerically singular.
    pub pivot_ratio: f64,
}

/// As [`solve_dense`], also giving the determinant's sign and the pivots' spread; `None` for
/// a non-finite or exactly singular matrix, or a non-finite solution.
pub fn lu_solve(matrix: &mut [f64], rhs: &mut [f64], n: usize) -> Option<LuInfo> {
    let mut sign = 1.0;
    let (mut smallest, mut largest) = (f64::INFINITY, 0.0_f64);
    for col in 0..n {
        let pivot = pivot_row(matrix, n, col);
        let p = matrix[pivot * n + col];
        if p == 0.0 || !p.is_finite() {
            return None;
        }
        if pivot != col {
            for j in 0..n {
                matrix.swap(col * n + j, pivot * n + j);
            }
            rhs.swap(col, pivot);
            sign = -sign;
        }
        sign *= p.signum();
        smallest = smallest.min(p.abs());
        largest = largest.max(p.abs());
        // Row slices, so the inner loop has no bounds checks and vectorises (the mechanism's
        // Jacobians are mostly zeros, skipped by the factor test).
        let (upper, lower) = matrix.split_at_mut((col + 1) * n);
        let pivot_row = &upper[col * n + col..(col + 1) * n];
        for (k, row) in lower.chunks_exact_mut(n).enumerate() {
            let factor = row[col] / p;
            if factor != 0.0 {
                for (t, &v) in row[col..].iter_mut().zip(pivot_row) {
                    *t -= factor * v;
                }
                rhs[col + 1 + k] -= factor * rhs[col];
            }
        }
    }
    for col in (0..n).rev() {
        let row = &matrix[col * n..(col + 1) * n];
        let v = rhs[col]
            - row[col + 1..]
                .iter()
                .zip(&rhs[col + 1..n])
                .map(|(a, b)| a * b)
                .sum::<f64>();
        rhs[col] = v / row[col];
    }
    rhs.iter().all(|v| v.is_finite()).then_some(LuInfo {
        det_sign: sign,
        pivot_ratio: smallest / largest,
    })
}

/// Solves `A x = b` for a symmetric positive definite `A` (row-major, overwritten by its
/// Cholesky factor); the solution replaces `rhs`. Returns false when `A` is not positive
/// definite, which for a tangent stiffness means an unstable or critical equilibrium.
pub fn cholesky_solve(matrix: &mut [f64], rhs: &mut [f64], n: usize) -> bool {
    // A PRB chain's tangent stiffness is this small in almost every Newton iteration of a
    // fit: the same arithmetic, in the same order, on fixed-size arrays.
    match n {
        1 => cholesky_fixed::<1>(matrix, rhs),
        2 => cholesky_fixed::<2>(matrix, rhs),
        3 => cholesky_fixed::<3>(matrix, rhs),
        4 => cholesky_fixed::<4>(matrix, rhs),
        _ => cholesky_general(matrix, rhs, n),
    }
}

/// [`cholesky_solve`] for any `n`.
fn cholesky_general(matrix: &mut [f64], rhs: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = matrix[j * n + j];
        for k in 0..j {
            d -= matrix[j * n + k] * matrix[j * n + k];
        }
        if d.is_nan() || d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        matrix[j * n + j] = d;
        for i in j + 1..n {
            let mut v = matrix[i * n + j];
            for k in 0..j {
                v -= matrix[i * n + k] * matrix[j * n + k];
            }
            matrix[i * n + j] = v / d;
        }
    }
    // Forward (L y = b) then backward (L^T x = y) substitution.
    for i in 0..n {
        let mut v = rhs[i];
        for k in 0..i {
            v -= matrix[i * n + k] * rhs[k];
        }
        rhs[i] = v / matrix[i * n + i];
    }
    for i in (0..n).rev() {
        let mut v = rhs[i];
        for k in i + 1..n {
            v -= matrix[k * n + i] * rhs[k];
        }
        rhs[i] = v / matrix[i * n + i];
    }
    rhs.iter().all(|v| v.is_finite())
}

/// [`cholesky_solve`] for `N` x `N`: the same operations in the same order (so the same
/// result to the bit), on arrays the compiler unrolls.
fn cholesky_fixed<const N: usize>(matrix: &mut [f64], rhs: &mut [f64]) -> bool {
    let mut a = [[0.0; N]; N];
    for (i, row) in a.iter_mut().enumerate() {
        row.copy_from_slice(&matrix[i * N..(i + 1) * N]);
    }
    let mut x = [0.0; N];
    x.copy_from_slice(&rhs[..N]);
    let definite = cholesky_arrays(&mut a, &mut x);
    for (i, row) in a.iter().enumerate() {
        matrix[i * N..(i + 1) * N].copy_from_slice(row);
    }
    if !definite {
        return false;
    }
    rhs[..N].copy_from_slice(&x);
    x.iter().all(|v| v.is_finite())
}

/// The factorisation and both substitutions of [`cholesky_fixed`].
#[allow(clippy::needless_range_loop)] // the general version's index order, kept to the bit
fn cholesky_arrays<const N: usize>(a: &mut [[f64; N]; N], x: &mut [f64; N]) -> bool {
    for j in 0..N {
        let mut d = a[j][j];
        for k in 0..j {
            d -= a[j][k] * a[j][k];
        }
        if d.is_nan() || d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j][j] = d;
        for i in j + 1..N {
            let mut v = a[i][j];
            for k in 0..j {
                v -= a[i][k] * a[j][k];
            }
            a[i][j] = v / d;
        }
    }
    for i in 0..N {
        let mut v = x[i];
        for k in 0..i {
            v -= a[i][k] * x[k];
        }
        x[i] = v / a[i][i];
    }
    for i in (0..N).rev() {
        let mut v = x[i];
        for k in i + 1..N {
            v -= a[k][i] * x[k];
        }
        x[i] = v / a[i][i];
    }
    true
}

/// The lowest natural frequencies of the linear system `A v = omega^2 B v` (`n` x `n`,
/// row-major): `A` the stiffness (the Jacobian of the restoring forces and of any
/// constraints, nonsingular at a regular equilibrium), `B` the mass (zero in the rows and
/// columns of massless coordinates and of constraints' multipliers), in ascending order.
///
/// Solved as the eigenvalues `mu = 1 / omega^2` of `A^-1 B` (Schur decomposition), which
/// holds for a symmetric pair and for a constrained mechanism's unsymmetric saddle-point
/// system alike, and leaves the massless coordinates at `mu = 0` (an infinite frequency,
/// dropped) instead of dividing by their zero mass. The lowest frequencies are the largest
/// `mu`, computed to the Schur decomposition's relative accuracy (about `n` ulp of the
/// largest); frequencies more than 1000 times the lowest are not resolved and left out. A
/// `mu` with an imaginary part or a negative one means `A` is not a stable stiffness: `Err`
/// with the most negative `omega^2`, or NaN.
///
/// Two reductions keep the decomposed matrix small:
/// - Only the coordinates with mass have a column in `A^-1 B`: with the others (massless
///   coordinates, multipliers) ordered last it is block lower triangular, `[[C_mm, 0], [C_om,
///   0]]`, so its nonzero eigenvalues are those of `C_mm`, the massive rows and columns of
///   `A^-1 B_m`: one factorisation of `A` and as many solves as masses.
/// - When every massless unknown is a constraint's multiplier (`A_oo = 0`: a mechanism's tip
///   wrenches), `A = [[A_mm, E], [C, 0]]` and the motion is confined to the constraints' null
///   space, `v = N z` with `C N = 0`. The multipliers drop out on the left null space of `E`
///   (`N_L^T E = 0`), leaving the `r` x `r` pencil `N_L^T A_mm N z = omega^2 N_L^T B_mm N z`
///   of the mechanism's `r` degrees of freedom (3 for a parallel stage of two 3R chains,
///   against 9 massive coordinates). It has none of `C_mm`'s zero eigenvalues, which form
///   Jordan blocks that round-off splits by the square root of the unit round-off. Both
///   bases come from Gauss-Jordan elimination with complete pivoting; a rank-deficient `C`
///   or `E` (pivot below `1e-12` of the largest entry: a redundant constraint) keeps the
///   first reduction.
pub fn frequencies(a: &[f64], b: &[f64], n: usize) -> Result<Vec<f64>, f64> {
    if n == 0 {
        return Ok(Vec::new());
    }
    let massive = massive_columns(b, n);
    if massive.is_empty() {
        return Ok(Vec::new());
    }
    let pencil = constrained_pencil(a, b, n, &massive);
    let c = match pencil {
        Some((mut stiffness, mut mass, r)) => {
            if !solve_many(&mut stiffness, &mut mass, r, r) {
                return Err(0.0);
            }
            nalgebra::DMatrix::from_row_slice(r, r, &mass)
        }
        None => massive_block(a, b, n, &massive)?,
    };
    eigen_frequencies(c)
}

/// The coordinates with mass: the columns of `b` (`n` x `n`) with a nonzero entry.
fn massive_columns(b: &[f64], n: usize) -> Vec<usize> {
    (0..n)
        .filter(|&j| (0..n).any(|i| b[i * n + j] != 0.0))
        .collect()
}

/// [`frequencies`] by the first reduction alone: the massive block `C_mm` of `A^-1 B`.
#[cfg(test)]
fn frequencies_unreduced(a: &[f64], b: &[f64], n: usize) -> Result<Vec<f64>, f64> {
    let massive = massive_columns(b, n);
    eigen_frequencies(massive_block(a, b, n, &massive)?)
}

/// `C_mm`, the `massive` rows and columns of `A^-1 B` ([`frequencies`]' first reduction);
/// `Err(0.0)` for a singular `A`.
fn massive_block(
    a: &[f64],
    b: &[f64],
    n: usize,
    massive: &[usize],
) -> Result<nalgebra::DMatrix<f64>, f64> {
    let m = massive.len();
    let mut factor = a.to_vec();
    let mut c: Vec<f64> = (0..n)
        .flat_map(|i| massive.iter().map(move |&j| b[i * n + j]))
        .collect();
    if !solve_many(&mut factor, &mut c, n, m) {
        return Err(0.0);
    }
    Ok(nalgebra::DMatrix::from_fn(m, m, |i, j| {
        c[massive[i] * m + j]
    }))
}

/// [`frequencies`]' second reduction: the constrained pencil `(N_L^T A_mm N, N_L^T B_mm N)`
/// (row-major, `r` x `r`) and `r`; `None` when it does not apply (a massless unknown that is
/// not a multiplier, or a rank-deficient constraint block).
fn constrained_pencil(
    a: &[f64],
    b: &[f64],
    n: usize,
    massive: &[usize],
) -> Option<(Vec<f64>, Vec<f64>, usize)> {
    let m = massive.len();
    let p = n - m;
    if p == 0 || p >= m {
        return None;
    }
    let mut is_massive = vec![false; n];
    for &j in massive {
        is_massive[j] = true;
    }
    let other: Vec<usize> = (0..n).filter(|&j| !is_massive[j]).collect();
    if other
        .iter()
        .any(|&i| other.iter().any(|&j| a[i * n + j] != 0.0))
    {
        return None;
    }
    // C = A_om (p x m) and E^T = A_mo^T (p x m).
    let constraints: Vec<f64> = other
        .iter()
        .flat_map(|&i| massive.iter().map(move |&j| a[i * n + j]))
        .collect();
    let multipliers: Vec<f64> = other
        .iter()
        .flat_map(|&j| massive.iter().map(move |&i| a[i * n + j]))
        .collect();
    let right = null_space(constraints, p, m)?;
    let left = null_space(multipliers, p, m)?;
    let r = m - p;
    // N_L^T X N for X the massive block of `a` and of `b`.
    let project = |x: &[f64]| {
        let mut xn = vec![0.0; m * r];
        for (i, &gi) in massive.iter().enumerate() {
            for (k, &gk) in massive.iter().enumerate() {
                let v = x[gi * n + gk];
                if v != 0.0 {
                    for t in 0..r {
                        xn[i * r + t] += v * right[k * r + t];
                    }
                }
            }
        }
        let mut out = vec![0.0; r * r];
        for i in 0..m {
            for s in 0..r {
                let l = left[i * r + s];
                if l != 0.0 {
                    for t in 0..r {
                        out[s * r + t] += l * xn[i * r + t];
                    }
                }
            }
        }
        out
    };
    Some((project(a), project(b), r))
}

/// A basis of the null space of the `p` x `m` row-major `rows` (full row rank, `p < m`), as
/// the `m` x `(m - p)` row-major matrix of its columns: Gauss-Jordan elimination with
/// complete pivoting to `[I F]` in permuted columns, whose null space is `[-F; I]`. `None`
/// when a pivot falls below `1e-12` of the largest entry (the rows are dependent) or an
/// entry is not finite.
fn null_space(mut rows: Vec<f64>, p: usize, m: usize) -> Option<Vec<f64>> {
    let largest = rows.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let mut order: Vec<usize> = (0..m).collect();
    for k in 0..p {
        let (mut pr, mut pc, mut best) = (k, k, 0.0);
        for i in k..p {
            for j in k..m {
                let v = rows[i * m + j].abs();
                if v > best {
                    (pr, pc, best) = (i, j, v);
                }
            }
        }
        if best <= 1e-12 * largest {
            return None;
        }
        if pr != k {
            for j in 0..m {
                rows.swap(k * m + j, pr * m + j);
            }
        }
        if pc != k {
            for i in 0..p {
                rows.swap(i * m + k, i * m + pc);
            }
            order.swap(k, pc);
        }
        let pivot = rows[k * m + k];
        for j in k..m {
            rows[k * m + j] /= pivot;
        }
        for i in (0..p).filter(|&i| i != k) {
            let f = rows[i * m + k];
            if f != 0.0 {
                for j in k..m {
                    rows[i * m + j] -= f * rows[k * m + j];
                }
            }
        }
    }
    let r = m - p;
    let mut basis = vec![0.0; m * r];
    for t in 0..r {
        for i in 0..p {
            basis[order[i] * r + t] = -rows[i * m + p + t];
        }
        basis[order[p + t] * r + t] = 1.0;
    }
    Some(basis)
}

/// The frequencies `1 / sqrt(mu)` from the eigenvalues `mu` of `c` ([`frequencies`]' rules).
fn eigen_frequencies(c: nalgebra::DMatrix<f64>) -> Result<Vec<f64>, f64> {
    if c.iter().any(|v| !v.is_finite()) {
        return Err(0.0);
    }
    let eig = c.complex_eigenvalues();
    let largest = eig.iter().fold(0.0_f64, |a, z| a.max(z.norm()));
    if largest == 0.0 || !largest.is_finite() {
        return Ok(Vec::new());
    }
    // The zero eigenvalues of the massless coordinates and constraints form Jordan blocks
    // (a constrained system's saddle point), which round-off splits by about the square root
    // of the unit round-off: they are told from true modes by size, `RESOLVED` of the largest
    // (frequencies more than 1000 times the lowest are left out, far above any asked for).
    const RESOLVED: f64 = 1e-6;
    let floor = RESOLVED * largest;
    let mut out = Vec::new();
    for z in eig.iter() {
        if z.norm() <= floor {
            continue; // a massless coordinate or a constraint
        }
        let complex = z.im.abs() > 1e-6 * z.norm();
        if complex || z.re < 0.0 {
            return Err(if complex { f64::NAN } else { 1.0 / z.re });
        }
        out.push(1.0 / z.re.sqrt());
    }
    out.sort_by(f64::total_cmp);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn many_right_hand_sides_are_each_solved() {
        // A permutation-needing 3x3 against two right-hand sides, checked by substitution.
        let a = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 4.0];
        let b = [1.0, 0.0, 2.0, -1.0, 0.5, 3.0];
        let (mut f, mut x) = (a, b);
        assert!(solve_many(&mut f, &mut x, 3, 2));
        for j in 0..2 {
            for i in 0..3 {
                let r: f64 = (0..3).map(|k| a[i * 3 + k] * x[k * 2 + j]).sum();
                assert!((r - b[i * 2 + j]).abs() < 1e-14, "row {i} rhs {j}: {r}");
            }
        }
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert!(!solve_many(&mut singular, &mut [1.0, 1.0], 2, 1));
    }

    #[test]
    fn frequencies_of_a_spring_mass_chain() {
        // Two unit masses, springs 1 (ground) and 1 (between): omega^2 = (3 -+ sqrt 5) / 2.
        let k = [2.0, -1.0, -1.0, 1.0];
        let m = [1.0, 0.0, 0.0, 1.0];
        let w = frequencies(&k, &m, 2).unwrap();
        let want = [
            ((3.0 - 5f64.sqrt()) / 2.0).sqrt(),
            ((3.0 + 5f64.sqrt()) / 2.0).sqrt(),
        ];
        for (a, b) in w.iter().zip(want) {
            assert!((a - b).abs() < 1e-14, "{w:?}");
        }
        // A massless second coordinate (a free spring end): it follows the first, which
        // keeps its own spring alone: one finite frequency, 1.
        let w = frequencies(&k, &[1.0, 0.0, 0.0, 0.0], 2).unwrap();
        assert_eq!(w.len(), 1);
        assert!((w[0] - 1.0).abs() < 1e-14, "{w:?}");
        // Unstable: a negative stiffness.
        assert!(frequencies(&[-1.0], &[1.0], 1).is_err());
    }
    use proptest::prelude::*;

    proptest! {
        /// Both solvers reproduce b from their solution: A x = b for random well-conditioned
        /// SPD matrices A = B B^T + n I.
        #[test]
        fn solvers_invert_spd_systems(entries in proptest::collection::vec(-1.0..1.0f64, 16),
                                      b in proptest::collection::vec(-1.0..1.0f64, 4)) {
            let n = 4;
            let mut a = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    let mut v = if i == j { n as f64 } else { 0.0 };
                    for k in 0..n {
                        v += entries[i * n + k] * entries[j * n + k];
                    }
                    a[i * n + j] = v;
                }
            }
            for solver in [cholesky_solve as fn(&mut [f64], &mut [f64], usize) -> bool, solve_dense] {
                let mut m = a.clone();
                let mut x = b.clone();
                prop_assert!(solver(&mut m, &mut x, n));
                for i in 0..n {
                    let ax: f64 = (0..n).map(|j| a[i * n + j] * x[j]).sum();
                    prop_assert!((ax - b[i]).abs() < 1e-12);
                }
            }
        }
    }

    /// A NaN or an infinity of either sign.
    fn non_finite() -> impl Strategy<Value = f64> {
        prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)]
    }

    proptest! {
        /// The fixed-size Cholesky (n = 1 to 4) is the general one to the bit: its factor,
        /// its solution and its verdict, on symmetric matrices definite or not (the diagonal
        /// shift ranges from well inside to well outside definiteness), sometimes with a NaN
        /// or an infinity in one entry.
        #[test]
        fn fixed_size_cholesky_is_the_general_one(
            n in 1usize..=4,
            entries in proptest::collection::vec(-1.0..1.0f64, 16),
            shift in -2.0..4.0f64,
            b in proptest::collection::vec(-1.0..1.0f64, 4),
            special in proptest::option::of((0usize..16, non_finite())),
        ) {
            let mut a = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    let mut v = if i == j { shift } else { 0.0 };
                    for k in 0..n {
                        v += entries[i * 4 + k] * entries[j * 4 + k];
                    }
                    a[i * n + j] = v;
                }
            }
            if let Some((k, v)) = special.filter(|&(k, _)| k < n * n) {
                a[k] = v;
            }
            let (mut ma, mut xa) = (a.clone(), b[..n].to_vec());
            let (mut mb, mut xb) = (a, b[..n].to_vec());
            let general = cholesky_general(&mut ma, &mut xa, n);
            let fixed = cholesky_solve(&mut mb, &mut xb, n);
            prop_assert_eq!(general, fixed);
            if general {
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                prop_assert_eq!(bits(&ma), bits(&mb));
                prop_assert_eq!(bits(&xa), bits(&xb));
            }
        }
    }

    proptest! {
        /// The fixed-size elimination against three right-hand sides (n = 1 to 4) is the
        /// general one to the bit, pivots and all, on random (unsymmetric, occasionally
        /// singular: a zeroed row; sometimes a NaN or an infinity in one entry) matrices.
        #[test]
        fn fixed_size_elimination_is_the_general_one(
            n in 1usize..=4,
            entries in proptest::collection::vec(-1.0..1.0f64, 16),
            zero_row in proptest::option::of(0usize..4),
            b in proptest::collection::vec(-1.0..1.0f64, 12),
            special in proptest::option::of((0usize..16, non_finite())),
        ) {
            let mut a: Vec<f64> = (0..n * n).map(|k| entries[k]).collect();
            if let Some(r) = zero_row.filter(|&r| r < n) {
                a[r * n..(r + 1) * n].iter_mut().for_each(|v| *v = 0.0);
            }
            if let Some((k, v)) = special.filter(|&(k, _)| k < n * n) {
                a[k] = v;
            }
            let (mut ma, mut xa) = (a.clone(), b[..3 * n].to_vec());
            let (mut mb, mut xb) = (a, b[..3 * n].to_vec());
            let general = solve_many_general(&mut ma, &mut xa, n, 3);
            let fixed = solve_many(&mut mb, &mut xb, n, 3);
            prop_assert_eq!(general, fixed);
            if general {
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                prop_assert_eq!(bits(&ma), bits(&mb));
                prop_assert_eq!(bits(&xa), bits(&xb));
            }
        }
    }

    /// A constrained pencil in the mechanism solver's form: `S = [[K, C^T], [C, 0]]` (`K`
    /// symmetric positive definite, `m` x `m`; `C` `p` x `m` random), `B = diag(M, 0)`, each
    /// row scaled by its own positive factor (a chain's equations in its own units: `A = D S`,
    /// `B = D B`), so `A` is unsymmetric and the frequencies those of the symmetric pair.
    fn scaled_saddle(
        k: &[f64],
        c: &[f64],
        masses: &[f64],
        scales: &[f64],
        m: usize,
        p: usize,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = m + p;
        let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n * n]);
        for i in 0..m {
            for j in 0..m {
                let mut v = if i == j { m as f64 } else { 0.0 };
                for t in 0..m {
                    v += k[i * m + t] * k[j * m + t];
                }
                a[i * n + j] = v;
            }
            b[i * n + i] = masses[i];
            for r in 0..p {
                a[i * n + m + r] = c[r * m + i];
                a[(m + r) * n + i] = c[r * m + i];
            }
        }
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] *= scales[i];
                b[i * n + j] *= scales[i];
            }
        }
        (a, b)
    }

    proptest! {
        /// The constrained pencil's reduction to the constraints' null space gives the
        /// frequencies of the symmetric reference computed another way (the null space from
        /// the eigenvectors of `C^T C`, the pencil `N^T K N, N^T M N` by Cholesky and a
        /// symmetric eigen-solver), and those of the unreduced massive block `C_mm`: a
        /// well-conditioned pencil (`K >= m I`, masses in [0.5, 2]) has frequencies to about
        /// 1e-12 relative by each route; 1e-9 allows for the constraint bases' conditioning.
        #[test]
        fn constrained_frequencies_are_the_null_space_pencils(
            k in proptest::collection::vec(-1.0..1.0f64, 36),
            c in proptest::collection::vec(-1.0..1.0f64, 12),
            masses in proptest::collection::vec(0.5..2.0f64, 6),
            scales in proptest::collection::vec(0.1..10.0f64, 8),
        ) {
            let (m, p) = (6, 2);
            let (a, b) = scaled_saddle(&k, &c, &masses, &scales, m, p);
            let got = frequencies(&a, &b, m + p).unwrap();
            let unreduced = frequencies_unreduced(&a, &b, m + p).unwrap();

            let kk = nalgebra::DMatrix::from_fn(m, m, |i, j| a[i * (m + p) + j] / scales[i]);
            let cc = nalgebra::DMatrix::from_row_slice(p, m, &c);
            let ctc = nalgebra::SymmetricEigen::new(cc.transpose() * &cc);
            let mut order: Vec<usize> = (0..m).collect();
            order.sort_by(|&i, &j| ctc.eigenvalues[i].total_cmp(&ctc.eigenvalues[j]));
            let basis = nalgebra::DMatrix::from_fn(m, m - p, |i, t| ctc.eigenvectors[(i, order[t])]);
            let kr = basis.transpose() * kk * &basis;
            let mr = basis.transpose() * nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_row_slice(&masses)) * &basis;
            let l = mr.cholesky().unwrap().l();
            let l_inv = l.try_inverse().unwrap();
            let g = &l_inv * kr * l_inv.transpose();
            let mut want: Vec<f64> = nalgebra::SymmetricEigen::new((&g + g.transpose()) * 0.5)
                .eigenvalues.iter().map(|w2| w2.sqrt()).collect();
            want.sort_by(f64::total_cmp);

            prop_assert_eq!(got.len(), m - p);
            prop_assert_eq!(unreduced.len(), m - p);
            for ((g, u), w) in got.iter().zip(&unreduced).zip(&want) {
                prop_assert!((g / w - 1.0).abs() < 1e-9, "{got:?} against {want:?}");
                prop_assert!((u / w - 1.0).abs() < 1e-9, "{unreduced:?} against {want:?}");
            }
        }
    }

    #[test]
    fn dependent_constraints_have_no_null_space_basis() {
        // Two proportional rows: the second pivot vanishes.
        assert!(null_space(vec![1.0, 2.0, 3.0, 2.0, 4.0, 6.0], 2, 3).is_none());
        // One row: a two-column basis, each column orthogonal to the row.
        let basis = null_space(vec![1.0, 2.0, 3.0], 1, 3).unwrap();
        for t in 0..2 {
            let dot: f64 = (0..3).map(|i| [1.0, 2.0, 3.0][i] * basis[i * 2 + t]).sum();
            assert!(dot.abs() < 1e-15, "column {t}: {dot}");
        }
    }

    #[test]
    fn cholesky_rejects_indefinite() {
        let mut m = vec![1.0, 2.0, 2.0, 1.0];
        let mut b = vec![1.0, 1.0];
        assert!(!cholesky_solve(&mut m, &mut b, 2));
    }
}
