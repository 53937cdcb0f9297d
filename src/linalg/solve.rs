//! Dense solves of a few unknowns: Gaussian elimination with partial pivoting (one or many
//! right-hand sides, with the determinant's sign and the pivots' spread) and Cholesky. The
//! smallest systems (a PRB chain's, in every Newton iteration of a fit) run the same
//! algorithm on fixed-size arrays.

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
    // A PRB chain's tip sensitivity (a few unknowns against the tip's three rows, in every
    // case of every fit evaluation) runs on fixed-size arrays the compiler unrolls.
    let solved = match (n, m) {
        (1, 3) => on_arrays::<1, 3>(matrix, rhs, eliminate),
        (2, 3) => on_arrays::<2, 3>(matrix, rhs, eliminate),
        (3, 3) => on_arrays::<3, 3>(matrix, rhs, eliminate),
        (4, 3) => on_arrays::<4, 3>(matrix, rhs, eliminate),
        _ => eliminate(&mut Rows::new(matrix, n, n), &mut Rows::new(rhs, n, m)),
    };
    solved && rhs.iter().all(|v| v.is_finite())
}

/// Solves `A x = b` for a symmetric positive definite `A` (row-major, overwritten by its
/// Cholesky factors `L D L^T`); the solution replaces `rhs`. Returns false when `A` is not positive
/// definite, which for a tangent stiffness means an unstable or critical equilibrium.
pub fn cholesky_solve(matrix: &mut [f64], rhs: &mut [f64], n: usize) -> bool {
    // A PRB chain's tangent stiffness is this small in almost every Newton iteration of a
    // fit: fixed-size arrays the compiler unrolls.
    let definite = match n {
        1 => on_arrays::<1, 1>(matrix, rhs, cholesky),
        2 => on_arrays::<2, 1>(matrix, rhs, cholesky),
        3 => on_arrays::<3, 1>(matrix, rhs, cholesky),
        4 => on_arrays::<4, 1>(matrix, rhs, cholesky),
        _ => cholesky(&mut Rows::new(matrix, n, n), &mut Rows::new(rhs, n, 1)),
    };
    definite && rhs.iter().all(|v| v.is_finite())
}

/// Solves `A x = b` for `m` right-hand sides (`rhs`, `n` x `m` row-major, replaced by the
/// solutions) given `factor`, the `L D L^T` factors [`cholesky_solve`] left of a positive
/// definite `A` (`n` x `n` row-major). False for a non-finite solution.
pub fn factored_solve(factor: &[f64], rhs: &mut [f64], n: usize, m: usize) -> bool {
    // A 3R's or 4R's adjoint (three right-hand sides) in every case of every fit evaluation:
    // fixed-size arrays the compiler unrolls.
    match (n, m) {
        (1, 3) => factored_on_arrays::<1, 3>(factor, rhs),
        (2, 3) => factored_on_arrays::<2, 3>(factor, rhs),
        (3, 3) => factored_on_arrays::<3, 3>(factor, rhs),
        (4, 3) => factored_on_arrays::<4, 3>(factor, rhs),
        _ => {
            let mut a = factor[..n * n].to_vec();
            substitute(&Rows::new(&mut a, n, n), &mut Rows::new(rhs, n, m));
        }
    }
    rhs.iter().all(|v| v.is_finite())
}

/// [`factored_solve`] on copies in arrays, written back.
fn factored_on_arrays<const N: usize, const M: usize>(factor: &[f64], rhs: &mut [f64]) {
    let mut a = [[0.0; N]; N];
    let mut x = [[0.0; M]; N];
    for i in 0..N {
        a[i].copy_from_slice(&factor[i * N..(i + 1) * N]);
        x[i].copy_from_slice(&rhs[i * M..(i + 1) * M]);
    }
    substitute(&a, &mut x);
    for i in 0..N {
        rhs[i * M..(i + 1) * M].copy_from_slice(&x[i]);
    }
}

/// `L y = b`, `z = D^-1 y`, `L^T x = z` for every column of `x`, given `L D L^T` in `a`.
fn substitute(a: &impl Dense, x: &mut impl Dense) {
    let (n, m) = (a.rows(), x.cols());
    for i in 0..n {
        for k in 0..i {
            let l = a.at(i, k);
            for j in 0..m {
                *x.at_mut(i, j) -= l * x.at(k, j);
            }
        }
    }
    for i in 0..n {
        let d = a.at(i, i);
        for j in 0..m {
            *x.at_mut(i, j) /= d;
        }
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            let l = a.at(k, i);
            for j in 0..m {
                *x.at_mut(i, j) -= l * x.at(k, j);
            }
        }
    }
}

/// Row-major storage the small solvers work in, by row and column: a slice of any size, or
/// nested arrays whose constant size lets the compiler unroll the loops. One algorithm runs
/// on both, so the fixed-size path gives the slice path's results to the bit.
trait Dense {
    fn rows(&self) -> usize;
    fn cols(&self) -> usize;
    fn at(&self, i: usize, j: usize) -> f64;
    fn at_mut(&mut self, i: usize, j: usize) -> &mut f64;
    fn swap_rows(&mut self, a: usize, b: usize);
}

/// The first `rows` x `cols` entries of a row-major slice.
struct Rows<'a> {
    data: &'a mut [f64],
    rows: usize,
    cols: usize,
}

impl<'a> Rows<'a> {
    fn new(data: &'a mut [f64], rows: usize, cols: usize) -> Rows<'a> {
        Rows { data, rows, cols }
    }
}

impl Dense for Rows<'_> {
    fn rows(&self) -> usize {
        self.rows
    }
    fn cols(&self) -> usize {
        self.cols
    }
    #[inline]
    fn at(&self, i: usize, j: usize) -> f64 {
        self.data[i * self.cols + j]
    }
    #[inline]
    fn at_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self.data[i * self.cols + j]
    }
    fn swap_rows(&mut self, a: usize, b: usize) {
        for j in 0..self.cols {
            self.data.swap(a * self.cols + j, b * self.cols + j);
        }
    }
}

impl<const R: usize, const C: usize> Dense for [[f64; C]; R] {
    fn rows(&self) -> usize {
        R
    }
    fn cols(&self) -> usize {
        C
    }
    #[inline]
    fn at(&self, i: usize, j: usize) -> f64 {
        self[i][j]
    }
    #[inline]
    fn at_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self[i][j]
    }
    fn swap_rows(&mut self, a: usize, b: usize) {
        self.swap(a, b);
    }
}

/// Runs `solve` on copies of `matrix` (`N` x `N`) and `rhs` (`N` x `M`) in arrays, and
/// writes both back, whatever it returns.
fn on_arrays<const N: usize, const M: usize>(
    matrix: &mut [f64],
    rhs: &mut [f64],
    solve: impl FnOnce(&mut [[f64; N]; N], &mut [[f64; M]; N]) -> bool,
) -> bool {
    let mut a = [[0.0; N]; N];
    let mut x = [[0.0; M]; N];
    for i in 0..N {
        a[i].copy_from_slice(&matrix[i * N..(i + 1) * N]);
        x[i].copy_from_slice(&rhs[i * M..(i + 1) * M]);
    }
    let done = solve(&mut a, &mut x);
    for i in 0..N {
        matrix[i * N..(i + 1) * N].copy_from_slice(&a[i]);
        rhs[i * M..(i + 1) * M].copy_from_slice(&x[i]);
    }
    done
}

/// [`solve_many`]'s elimination and back substitution, in place; false at a zero or
/// non-finite pivot.
fn eliminate(a: &mut impl Dense, x: &mut impl Dense) -> bool {
    let (n, m) = (a.rows(), x.cols());
    for col in 0..n {
        // Partial pivoting: the row at or below `col` with the largest entry in column `col`
        // (the first of equals).
        let (mut pivot, mut best) = (col, a.at(col, col).abs());
        for i in col + 1..n {
            let v = a.at(i, col).abs();
            if v > best {
                (pivot, best) = (i, v);
            }
        }
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        if pivot != col {
            a.swap_rows(col, pivot);
            x.swap_rows(col, pivot);
        }
        let p = a.at(col, col);
        for i in col + 1..n {
            let f = a.at(i, col) / p;
            if f == 0.0 {
                continue;
            }
            for j in col..n {
                *a.at_mut(i, j) -= f * a.at(col, j);
            }
            for j in 0..m {
                *x.at_mut(i, j) -= f * x.at(col, j);
            }
        }
    }
    for i in (0..n).rev() {
        let d = a.at(i, i);
        for j in 0..m {
            let mut v = x.at(i, j);
            for k in i + 1..n {
                v -= a.at(i, k) * x.at(k, j);
            }
            *x.at_mut(i, j) = v / d;
        }
    }
    true
}

/// [`cholesky_solve`]'s factorisation and substitutions, in place (`x` one column); false,
/// with `x` untouched, where `a` is not positive definite.
///
/// The factorisation is Cholesky's without its square roots, `A = L D L^T` (`L` unit lower
/// triangular below the diagonal of `a`, `D` on it): positive definite exactly where every
/// pivot of `D` is positive, as Cholesky's. Its chain of dependent operations is two
/// divisions and no square root in a 3 x 3, where `L L^T` chained three square roots and
/// eight divisions (11 % of a 3R fit's time, in every Newton iteration of every case, was
/// this solve waiting on them).
fn cholesky(a: &mut impl Dense, x: &mut impl Dense) -> bool {
    let n = a.rows();
    for j in 0..n {
        // d_j = a_jj - sum_k l_jk^2 d_k
        let mut d = a.at(j, j);
        for k in 0..j {
            d -= a.at(j, k) * a.at(j, k) * a.at(k, k);
        }
        if d.is_nan() || d <= 0.0 || !d.is_finite() {
            return false;
        }
        *a.at_mut(j, j) = d;
        // l_ij = (a_ij - sum_k l_ik l_jk d_k) / d_j
        for i in j + 1..n {
            let mut v = a.at(i, j);
            for k in 0..j {
                v -= a.at(i, k) * a.at(j, k) * a.at(k, k);
            }
            *a.at_mut(i, j) = v / d;
        }
    }
    // L y = b, then z = D^-1 y (independent divisions), then L^T x = z.
    for i in 0..n {
        let mut v = x.at(i, 0);
        for k in 0..i {
            v -= a.at(i, k) * x.at(k, 0);
        }
        *x.at_mut(i, 0) = v;
    }
    for i in 0..n {
        *x.at_mut(i, 0) /= a.at(i, i);
    }
    for i in (0..n).rev() {
        let mut v = x.at(i, 0);
        for k in i + 1..n {
            v -= a.at(k, i) * x.at(k, 0);
        }
        *x.at_mut(i, 0) = v;
    }
    true
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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
    fn cholesky_rejects_indefinite() {
        let mut m = vec![1.0, 2.0, 2.0, 1.0];
        let mut b = vec![1.0, 1.0];
        assert!(!cholesky_solve(&mut m, &mut b, 2));
    }

    proptest! {
        /// Both solvers reproduce b from their solution: A x = b for random well-conditioned
        /// SPD matrices A = B B^T + n I.
        #[test]
        fn solvers_invert_spd_systems(entries in proptest::collection::vec(-1.0..1.0f64, 16),
                                      b in proptest::collection::vec(-1.0..1.0f64, 4)) {
            let n = 4;
            let a = super::super::spd_test_matrix(&entries, n);
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

    proptest! {
        /// The verdict is positive definiteness: on random symmetric matrices (n = 1 to 5,
        /// the fixed-size and the slice paths), it agrees with the sign of the smallest
        /// eigenvalue from nalgebra's symmetric eigensolver wherever that is not within 1e-9
        /// of zero, and a definite system's solution solves it to rounding (each row's
        /// residual within 1e-10 of the row's size).
        #[test]
        fn cholesky_says_definite_exactly_where_it_is(
            n in 1usize..=5,
            entries in proptest::collection::vec(-1.0..1.0f64, 25),
            shift in -2.0..4.0f64,
            b in proptest::collection::vec(-1.0..1.0f64, 5),
        ) {
            let a = shifted_gram(&entries, 5, n, shift);
            let smallest = nalgebra::DMatrix::from_row_slice(n, n, &a)
                .symmetric_eigenvalues()
                .min();
            prop_assume!(smallest.abs() > 1e-9);
            let (mut m, mut x) = (a.clone(), b[..n].to_vec());
            let definite = cholesky_solve(&mut m, &mut x, n);
            prop_assert_eq!(definite, smallest > 0.0);
            if definite {
                for i in 0..n {
                    let terms = (0..n).map(|j| a[i * n + j] * x[j]);
                    let size: f64 = terms.clone().map(f64::abs).sum::<f64>() + b[i].abs();
                    let residual = terms.sum::<f64>() - b[i];
                    prop_assert!(residual.abs() <= 1e-10 * size, "row {i}: {residual:e}");
                }
            }
        }
    }

    proptest! {
        /// The factors `cholesky_solve` leaves solve the system for more right-hand sides:
        /// on random well-conditioned SPD matrices (`B B^T + n I`, n = 1 to 5: the fixed-size
        /// three-column path and the slices), each column of `A X = B` holds to rounding
        /// (1e-12 of the row's terms), and the fixed-size path is the slices' to the bit.
        #[test]
        fn the_factors_solve_more_right_hand_sides(
            n in 1usize..=5,
            entries in proptest::collection::vec(-1.0..1.0f64, 25),
            b in proptest::collection::vec(-1.0..1.0f64, 15),
        ) {
            let a = super::super::spd_test_matrix(&entries[..n * n], n);
            let mut factor = a.clone();
            let mut first = vec![0.0; n];
            prop_assert!(cholesky_solve(&mut factor, &mut first, n));
            let mut x = b[..3 * n].to_vec();
            prop_assert!(factored_solve(&factor, &mut x, n, 3));
            for i in 0..n {
                for j in 0..3 {
                    let terms = (0..n).map(|k| a[i * n + k] * x[k * 3 + j]);
                    let size: f64 = terms.clone().map(f64::abs).sum::<f64>() + b[i * 3 + j].abs();
                    let residual = terms.sum::<f64>() - b[i * 3 + j];
                    prop_assert!(residual.abs() <= 1e-12 * size, "({i}, {j}): {residual:e}");
                }
            }
            let mut general = b[..3 * n].to_vec();
            let mut copy = factor.clone();
            substitute(&Rows::new(&mut copy, n, n), &mut Rows::new(&mut general, n, 3));
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&general), bits(&x));
        }
    }

    /// `E E^T + shift I` (`n` x `n`, row-major) from the first `n` columns of the first `n`
    /// rows of `entries` (rows `stride` long): symmetric, definite or not as `shift` says.
    fn shifted_gram(entries: &[f64], stride: usize, n: usize, shift: f64) -> Vec<f64> {
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let mut v = if i == j { shift } else { 0.0 };
                for k in 0..n {
                    v += entries[i * stride + k] * entries[j * stride + k];
                }
                a[i * n + j] = v;
            }
        }
        a
    }

    /// A NaN or an infinity of either sign.
    fn non_finite() -> impl Strategy<Value = f64> {
        prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)]
    }

    proptest! {
        /// The fixed-size arrays' Cholesky (n = 1 to 4) is the slice's to the bit: its factor,
        /// its solution and its verdict, on symmetric matrices definite or not (the diagonal
        /// shift ranges from well inside to well outside definiteness), sometimes with a NaN
        /// or an infinity in one entry.
        #[test]
        fn fixed_size_cholesky_is_the_slices(
            n in 1usize..=4,
            entries in proptest::collection::vec(-1.0..1.0f64, 16),
            shift in -2.0..4.0f64,
            b in proptest::collection::vec(-1.0..1.0f64, 4),
            special in proptest::option::of((0usize..16, non_finite())),
        ) {
            let mut a = shifted_gram(&entries, 4, n, shift);
            if let Some((k, v)) = special.filter(|&(k, _)| k < n * n) {
                a[k] = v;
            }
            let (mut ma, mut xa) = (a.clone(), b[..n].to_vec());
            let (mut mb, mut xb) = (a, b[..n].to_vec());
            let general = cholesky(&mut Rows::new(&mut ma, n, n), &mut Rows::new(&mut xa, n, 1))
                && xa.iter().all(|v| v.is_finite());
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
        /// The fixed-size arrays' elimination against three right-hand sides (n = 1 to 4) is
        /// the slice's to the bit, pivots and all, on random (unsymmetric, occasionally
        /// singular: a zeroed row; sometimes a NaN or an infinity in one entry) matrices.
        #[test]
        fn fixed_size_elimination_is_the_slices(
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
            let general = eliminate(&mut Rows::new(&mut ma, n, n), &mut Rows::new(&mut xa, n, 3))
                && xa.iter().all(|v| v.is_finite());
            let fixed = solve_many(&mut mb, &mut xb, n, 3);
            prop_assert_eq!(general, fixed);
            if general {
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                prop_assert_eq!(bits(&ma), bits(&mb));
                prop_assert_eq!(bits(&xa), bits(&xb));
            }
        }
    }
}
