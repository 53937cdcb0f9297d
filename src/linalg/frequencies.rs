//! Natural frequencies of a stiffness and mass pair, a constrained mechanism's included.

use super::solve::solve_many;

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
    use proptest::prelude::*;

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
        let k = super::super::spd_test_matrix(k, m);
        for i in 0..m {
            a[i * n..i * n + m].copy_from_slice(&k[i * m..(i + 1) * m]);
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
}
