//! Banded LU with partial pivoting, for the multiple-shooting Newton system.
//!
//! Segment `k`'s end depends only on its own start, so the shooting Jacobian is banded: with
//! the unknowns ordered `M_0, psi_1, M_1, psi_2, ...` and the continuity rows in segment order,
//! every nonzero lies at most `kl` below and `ku` above the diagonal. Gaussian elimination with
//! row pivoting then costs `O(n (kl + ku) kl)` instead of the dense `O(n^3)`, which is what
//! lets a huge load use hundreds of segments. Pivoting can widen the upper band to `kl + ku`
//! (as in LAPACK's `dgbtf2`), so the storage keeps room for that fill.
//!
//! Storage is by column: column `j` holds rows `j - kl - ku ..= j + kl`, so swapping two rows
//! inside the active window never leaves it.

/// A square banded matrix with room for the fill of partial pivoting.
#[derive(Debug, Clone)]
pub(crate) struct Band {
    n: usize,
    kl: usize,
    ku: usize,
    /// `ld = 2 kl + ku + 1` values per column.
    data: Vec<f64>,
    pivots: Vec<usize>,
}

impl Band {
    /// A zero `n x n` matrix with `kl` subdiagonals and `ku` superdiagonals.
    pub(crate) fn new(n: usize, kl: usize, ku: usize) -> Band {
        let ld = 2 * kl + ku + 1;
        Band {
            n,
            kl,
            ku,
            data: vec![0.0; ld * n],
            pivots: vec![0; n],
        }
    }

    /// This matrix made a zero `n x n` one with `kl` subdiagonals and `ku` superdiagonals,
    /// in the storage it has (a Newton iteration's, reused from case to case).
    pub(crate) fn reshape(&mut self, n: usize, kl: usize, ku: usize) {
        self.n = n;
        self.kl = kl;
        self.ku = ku;
        let len = self.ld() * n;
        self.data.clear();
        self.data.resize(len, 0.0);
        self.pivots.clear();
        self.pivots.resize(n, 0);
    }

    pub(crate) fn size(&self) -> usize {
        self.n
    }

    fn ld(&self) -> usize {
        2 * self.kl + self.ku + 1
    }

    /// Offset of `(row, col)`, which must lie inside the (fill-extended) band.
    #[inline]
    fn at(&self, row: usize, col: usize) -> usize {
        let kv = self.kl + self.ku;
        debug_assert!(
            row + kv >= col && row <= col + self.kl,
            "({row}, {col}) off the band"
        );
        col * self.ld() + kv + row - col
    }

    pub(crate) fn clear(&mut self) {
        self.data.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Sets entry `(row, col)`, which must lie within the declared band.
    pub(crate) fn set(&mut self, row: usize, col: usize, value: f64) {
        debug_assert!(col <= row + self.ku, "({row}, {col}) above the band");
        let i = self.at(row, col);
        self.data[i] = value;
    }

    /// Solves `A x = rhs` in place (`A` is overwritten by its factors). Returns false for a
    /// zero or non-finite pivot, or a non-finite solution, like `linalg::solve_dense`.
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) -> bool {
        let (n, kl) = (self.n, self.kl);
        let kv = self.kl + self.ku;
        debug_assert_eq!(rhs.len(), n);
        for j in 0..n {
            let last_row = (j + kl).min(n - 1);
            let last_col = (j + kv).min(n - 1);
            let mut p = j;
            let mut best = self.data[self.at(j, j)].abs();
            for r in j + 1..=last_row {
                let v = self.data[self.at(r, j)].abs();
                if v > best {
                    best = v;
                    p = r;
                }
            }
            self.pivots[j] = p;
            let pivot = self.data[self.at(p, j)];
            if pivot == 0.0 || !pivot.is_finite() {
                return false;
            }
            if p != j {
                for c in j..=last_col {
                    let (a, b) = (self.at(j, c), self.at(p, c));
                    self.data.swap(a, b);
                }
            }
            let inv = 1.0 / pivot;
            for r in j + 1..=last_row {
                let i = self.at(r, j);
                self.data[i] *= inv;
            }
            for c in j + 1..=last_col {
                let u = self.data[self.at(j, c)];
                if u == 0.0 {
                    continue;
                }
                for r in j + 1..=last_row {
                    let l = self.data[self.at(r, j)];
                    let i = self.at(r, c);
                    self.data[i] -= l * u;
                }
            }
        }
        // Forward substitution with the row swaps, then back substitution.
        for j in 0..n {
            rhs.swap(j, self.pivots[j]);
            let v = rhs[j];
            if v != 0.0 {
                let last = (j + kl).min(n - 1);
                for (r, x) in rhs.iter_mut().enumerate().take(last + 1).skip(j + 1) {
                    *x -= self.data[self.at(r, j)] * v;
                }
            }
        }
        for j in (0..n).rev() {
            let last = (j + kv).min(n - 1);
            let mut v = rhs[j];
            for (c, x) in rhs.iter().enumerate().take(last + 1).skip(j + 1) {
                v -= self.data[self.at(j, c)] * x;
            }
            rhs[j] = v / self.data[self.at(j, j)];
        }
        rhs.iter().all(|v| v.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random banded system solved by the band solver and densely agree, including cases
    /// that need pivoting (a zero on the diagonal).
    #[test]
    fn matches_dense_elimination() {
        let (kl, ku) = (2, 1);
        for n in [1usize, 2, 3, 5, 17, 40] {
            let mut seed = 12345u64 + n as u64;
            let mut rand = || {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
            };
            let mut dense = vec![0.0; n * n];
            let mut band = Band::new(n, kl, ku);
            for r in 0..n {
                for c in r.saturating_sub(kl)..=(r + ku).min(n - 1) {
                    // Every third diagonal entry zero forces a row swap.
                    let v = if r == c && r % 3 == 1 { 0.0 } else { rand() };
                    dense[r * n + c] = v;
                    band.set(r, c, v);
                }
            }
            let b: Vec<f64> = (0..n).map(|_| rand()).collect();
            let mut x = b.clone();
            assert!(band.solve(&mut x), "n = {n}");
            for r in 0..n {
                let ax: f64 = (0..n).map(|c| dense[r * n + c] * x[c]).sum();
                assert!(
                    (ax - b[r]).abs() < 1e-10,
                    "n = {n}, row {r}: {ax} vs {}",
                    b[r]
                );
            }
        }
    }

    #[test]
    fn singular_is_reported() {
        let mut band = Band::new(3, 2, 1);
        band.set(0, 0, 1.0);
        band.set(1, 0, 1.0);
        let mut x = vec![1.0, 1.0, 1.0];
        assert!(!band.solve(&mut x));
    }
}
