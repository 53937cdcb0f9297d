//! The fit's unknowns: the free cells of a PRB matrix, reparameterised so that every point of
//! the search space is a valid matrix (no penalties that stall the optimiser):
//!
//! - free gammas share what the fixed ones leave, `1 - sum(fixed)`, through a softmax of
//!   logits (the first logit is pinned at 0, which removes the softmax's redundant direction);
//! - free spring constants are `exp(u)`, positive for every real `u`;
//! - in a dynamic fit ([`Parameterisation::with_masses`], DESIGN §10) the free mus share what
//!   the fixed ones leave through a softmax of their own, after the springs; a statics-only
//!   fit leaves the mus alone (the statics do not see them).

use nalgebra::{DMatrix, DVector};

use crate::prb::{Column, PrbMatrix, CELLS_PER_ROW};

/// Spring constants stay within `exp(+-SPRING_LOG_LIMIT)` = 1e-9 .. 1e9: beyond, a spring is
/// rigid or absent for every practical load, and the optimiser gains nothing by wandering
/// further (a spring the fit drives to 1e9 is telling the user the joint is not needed).
pub const SPRING_LOG_LIMIT: f64 = 20.723_265_836_946_41; // ln(1e9)

/// Gamma logits stay within +-LOGIT_LIMIT: free segments differ in length by at most
/// e^(2 LOGIT_LIMIT) ~ 5e8, so no segment shrinks to a degenerate 1e-100 L that only slows
/// the statics down.
pub const LOGIT_LIMIT: f64 = 10.0;

/// Why a matrix cannot be fitted as marked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// Some gammas are free but the fixed ones already take the whole length (their sum,
    /// held here as a fraction of L, is 1 or more).
    #[error(
        "the fixed gammas sum to {0}, leaving no length for the free ones: free a gamma or \
         lower a fixed one"
    )]
    NoLengthLeft(f64),
}

/// Maps parameter vectors to matrices for one template (its topology and free flags).
#[derive(Debug, Clone)]
pub struct Parameterisation {
    template: PrbMatrix,
    /// Rows whose gamma is free.
    free_gammas: Vec<usize>,
    /// What the free gammas share.
    free_length: f64,
    /// Free spring cells.
    free_springs: Vec<(usize, Column)>,
    /// Rows whose mu is free (a dynamic fit only).
    free_mus: Vec<usize>,
    /// What the free mus share.
    free_mass: f64,
}

impl Parameterisation {
    /// The parameterisation of `template`'s free cells: one logit per free gamma after the
    /// first, one log spring constant per free finite `k_theta` or `k_ex`. Fails when gammas
    /// are free but the fixed ones leave them no length.
    pub fn new(template: &PrbMatrix) -> Result<Parameterisation, ParamError> {
        let rows = template.rows();
        let free_gammas: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].is_free(Column::Gamma))
            .collect();
        let fixed: f64 = (0..rows.len())
            .filter(|i| !free_gammas.contains(i))
            .map(|i| rows[i].gamma)
            .sum();
        let free_length = 1.0 - fixed;
        if !free_gammas.is_empty() && free_length <= 0.0 {
            return Err(ParamError::NoLengthLeft(fixed));
        }
        let mut free_springs = Vec::new();
        for (i, r) in rows.iter().enumerate() {
            for c in [Column::KTheta, Column::KEx] {
                if r.is_free(c) {
                    free_springs.push((i, c));
                }
            }
        }
        Ok(Parameterisation {
            template: template.clone(),
            free_gammas,
            free_length,
            free_springs,
            free_mus: Vec::new(),
            free_mass: 0.0,
        })
    }

    /// As [`Parameterisation::new`], the mu cells not pinned with `!` free too (a dynamic
    /// fit): the template's mus are written out (a three-column matrix's are its gammas) and
    /// the free ones share `1 - sum(fixed mus)` through one logit each after the first. When
    /// the fixed mus leave nothing, the free ones stay at 0.
    pub fn with_masses(template: &PrbMatrix) -> Result<Parameterisation, ParamError> {
        let explicit = template.with_explicit_mu();
        let mut p = Parameterisation::new(&explicit)?;
        let rows = explicit.rows();
        let free: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].is_free(Column::Mu))
            .collect();
        let fixed: f64 = (0..rows.len())
            .filter(|i| !free.contains(i))
            .map(|i| rows[i].mass())
            .sum();
        if fixed < 1.0 {
            p.free_mus = free;
            p.free_mass = 1.0 - fixed;
        }
        Ok(p)
    }

    /// The number of mu logits (one per free mu after the first).
    fn n_mu_logits(&self) -> usize {
        self.free_mus.len().saturating_sub(1)
    }

    /// Number of parameters (zero: nothing to fit).
    pub fn len(&self) -> usize {
        self.free_gammas.len().saturating_sub(1) + self.free_springs.len() + self.n_mu_logits()
    }

    /// Whether there is no parameter, i.e. nothing to fit.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The matrix this parameterisation was built from: its topology, fixed cells and free
    /// flags stay; [`Self::decode`] overwrites its free cells from the parameters.
    pub fn template(&self) -> &PrbMatrix {
        &self.template
    }

    /// The parameters that reproduce `matrix`'s free cells (same topology as the template).
    pub fn encode(&self, matrix: &PrbMatrix) -> DVector<f64> {
        let rows = matrix.rows();
        let mut p = Vec::with_capacity(self.len());
        if let Some((&first, rest)) = self.free_gammas.split_first() {
            let g0 = rows[first].gamma;
            for &i in rest {
                p.push((rows[i].gamma / g0).ln());
            }
        }
        for &(i, c) in &self.free_springs {
            p.push(rows[i].get(c).ln());
        }
        if let Some((&first, rest)) = self.free_mus.split_first() {
            // A mu of 0 (mass parked elsewhere) is the softmax's far edge.
            let tiny = (-2.0 * LOGIT_LIMIT).exp() * self.free_mass;
            let m0 = rows[first].mass().max(tiny);
            for &i in rest {
                p.push(
                    (rows[i].mass().max(tiny) / m0)
                        .ln()
                        .clamp(-LOGIT_LIMIT, LOGIT_LIMIT),
                );
            }
        }
        DVector::from_vec(p)
    }

    /// The matrix for parameters `p`; `None` only if `p` is not finite or an extreme `p`
    /// rounds a cell to 0 or infinity.
    pub fn decode(&self, p: &DVector<f64>) -> Option<PrbMatrix> {
        if p.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mut rows = self.template.rows().to_vec();
        let n_logits = self.free_gammas.len().saturating_sub(1);
        if !self.free_gammas.is_empty() {
            // Softmax with the first logit at 0, shifted by the largest for stability.
            let logits: Vec<f64> = std::iter::once(0.0)
                .chain(
                    p.iter()
                        .take(n_logits)
                        .map(|l| l.clamp(-LOGIT_LIMIT, LOGIT_LIMIT)),
                )
                .collect();
            let top = logits.iter().cloned().fold(f64::MIN, f64::max);
            let weights: Vec<f64> = logits.iter().map(|l| (l - top).exp()).collect();
            let total: f64 = weights.iter().sum();
            for (&i, w) in self.free_gammas.iter().zip(&weights) {
                rows[i].gamma = self.free_length * w / total;
            }
            // The gammas must sum to 1 to round-off: give the residue to the largest free one.
            let sum: f64 = rows.iter().map(|r| r.gamma).sum();
            // `free_gammas` is not empty here, so there is always a largest.
            if let Some(&largest) = self
                .free_gammas
                .iter()
                .max_by(|&&a, &&b| rows[a].gamma.total_cmp(&rows[b].gamma))
            {
                rows[largest].gamma += 1.0 - sum;
            }
        }
        for (&(i, c), u) in self.free_springs.iter().zip(p.iter().skip(n_logits)) {
            rows[i].set(c, u.clamp(-SPRING_LOG_LIMIT, SPRING_LOG_LIMIT).exp());
        }
        if !self.free_mus.is_empty() {
            let skip = n_logits + self.free_springs.len();
            let shares = softmax(p.iter().skip(skip).copied(), self.free_mus.len());
            for (&i, w) in self.free_mus.iter().zip(&shares) {
                rows[i].mu = Some(self.free_mass * w);
            }
            // The mus must sum to 1 to round-off: the largest free one takes the residue.
            let sum: f64 = rows.iter().map(|r| r.mass()).sum();
            if let Some(&largest) = self
                .free_mus
                .iter()
                .max_by(|&&a, &&b| rows[a].mass().total_cmp(&rows[b].mass()))
            {
                rows[largest].mu = Some((rows[largest].mass() + 1.0 - sum).max(0.0));
            }
        }
        PrbMatrix::new(rows).ok()
    }

    /// The derivatives of residuals with respect to the parameters, `out` (`m` x
    /// [`Self::len`]), from their derivatives with respect to the matrix's statics cells,
    /// `cells` (`m` rows of [`CELLS_PER_ROW`] per matrix row, row-major, as
    /// [`crate::prb::PrbSolver::tip_sensitivity`] lays them out), at parameters `p`.
    ///
    /// A free gamma `g_i = F s_i` (`s` the softmax of the logits, the first pinned) moves
    /// with logit `k` as `F s_i (delta_ik - s_k)`; a free spring `exp(u)` as itself. A
    /// parameter past its clamp moves nothing (0), as [`Self::decode`] clamps it. The mus
    /// (a dynamic fit) are not statics cells: their columns are 0.
    pub fn chain_rule(&self, p: &DVector<f64>, cells: &[f64], m: usize, out: &mut DMatrix<f64>) {
        let width = CELLS_PER_ROW * self.template.rows().len();
        debug_assert_eq!(cells.len(), m * width);
        if out.shape() != (m, self.len()) {
            *out = DMatrix::zeros(m, self.len());
        }
        // On the storage: nalgebra's element iterator took 1.3 % of a 3R fit's time here.
        out.as_mut_slice().fill(0.0);
        let n_logits = self.free_gammas.len().saturating_sub(1);
        if n_logits > 0 {
            let shares = softmax(p.iter().copied(), self.free_gammas.len());
            for row in 0..m {
                let d = &cells[row * width..(row + 1) * width];
                // sum_i s_i dr/dg_i, shared by every logit's column.
                let mean: f64 = self
                    .free_gammas
                    .iter()
                    .zip(&shares)
                    .map(|(&i, s)| s * d[CELLS_PER_ROW * i])
                    .sum();
                for k in 1..self.free_gammas.len() {
                    if p[k - 1].abs() < LOGIT_LIMIT {
                        let i = self.free_gammas[k];
                        out[(row, k - 1)] =
                            self.free_length * shares[k] * (d[CELLS_PER_ROW * i] - mean);
                    }
                }
            }
        }
        for (j, &(i, c)) in self.free_springs.iter().enumerate() {
            let u = p[n_logits + j];
            if u.abs() >= SPRING_LOG_LIMIT {
                continue;
            }
            let value = u.exp();
            let column = CELLS_PER_ROW * i + c.index();
            for row in 0..m {
                out[(row, n_logits + j)] = value * cells[row * width + column];
            }
        }
    }

    /// Box for a global search in parameter space: logits within +-3 of the start (gamma
    /// and mu ratios up to e^3 either way) and spring constants from 1/20 to 20 times the start's.
    pub fn search_box(&self, start: &DVector<f64>) -> (DVector<f64>, DVector<f64>) {
        let n_logits = self.free_gammas.len().saturating_sub(1);
        let springs = n_logits..n_logits + self.free_springs.len();
        let widths: Vec<f64> = (0..self.len())
            .map(|k| {
                if springs.contains(&k) {
                    20f64.ln()
                } else {
                    3.0
                }
            })
            .collect();
        let lower =
            DVector::from_iterator(self.len(), start.iter().zip(&widths).map(|(s, w)| s - w));
        let upper =
            DVector::from_iterator(self.len(), start.iter().zip(&widths).map(|(s, w)| s + w));
        (lower, upper)
    }
}

/// The softmax of `n` shares whose first logit is pinned at 0 and the rest are `logits`
/// (clamped to [`LOGIT_LIMIT`]), shifted by the largest for stability.
fn softmax(logits: impl Iterator<Item = f64>, n: usize) -> Vec<f64> {
    let logits: Vec<f64> = std::iter::once(0.0)
        .chain(
            logits
                .take(n.saturating_sub(1))
                .map(|l| l.clamp(-LOGIT_LIMIT, LOGIT_LIMIT)),
        )
        .collect();
    let top = logits.iter().cloned().fold(f64::MIN, f64::max);
    let weights: Vec<f64> = logits.iter().map(|l| (l - top).exp()).collect();
    let total: f64 = weights.iter().sum();
    weights.iter().map(|w| w / total).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_decode_round_trip() {
        let m =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4!,2.99,5; 0.15,2.58!,inf").unwrap();
        let p = Parameterisation::new(&m).unwrap();
        // Free gammas: rows 1, 2, 4 (3 -> 2 logits); free springs: 3.51, 2.99, 5.
        assert_eq!(p.len(), 2 + 3);
        let back = p.decode(&p.encode(&m)).unwrap();
        for (a, b) in back.rows().iter().zip(m.rows()) {
            for c in Column::ALL {
                let (x, y) = (a.get(c), b.get(c));
                assert!(x == y || (x - y).abs() < 1e-15, "{x} vs {y}");
            }
        }
        assert_eq!(back.rows()[2].gamma, 0.4, "fixed cells are untouched");
    }

    /// A dynamic fit frees the mus not pinned: a three-column matrix's are its gammas,
    /// written out; they round-trip, keep summing to 1, and a pinned one stays.
    #[test]
    fn mus_are_free_only_in_a_dynamic_fit() {
        let m =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
        let statics = Parameterisation::new(&m).unwrap();
        let dynamic = Parameterisation::with_masses(&m).unwrap();
        assert_eq!(dynamic.len(), statics.len() + 3);
        let back = dynamic.decode(&dynamic.encode(&m)).unwrap();
        assert!(back.has_mu());
        for (a, b) in back.rows().iter().zip(m.rows()) {
            assert!((a.mass() - b.gamma).abs() < 1e-14, "{back:?}");
        }
        // Pin the root's mu at 0.3: the others share 0.7 whatever the parameters.
        let pinned = PrbMatrix::parse(
            "0.1,inf,inf,0.3!; 0.35,3.51,inf,0.2; 0.4,2.99,inf,0.3; 0.15,2.58,inf,0.2",
        )
        .unwrap();
        let p = Parameterisation::with_masses(&pinned).unwrap();
        let mut v = p.encode(&pinned);
        let n = v.len();
        v[n - 1] += 1.7;
        v[n - 2] -= 0.4;
        let d = p.decode(&v).unwrap();
        assert_eq!(d.rows()[0].mass(), 0.3);
        let sum: f64 = d.rows().iter().map(|r| r.mass()).sum();
        assert!((sum - 1.0).abs() < 1e-15, "{sum}");
        // A mu of 0 encodes to the softmax's edge and decodes to its floor, e^-LOGIT_LIMIT
        // of the other (4.5e-5: a negligible mass).
        let zero = PrbMatrix::parse("0.15,inf,inf,0; 0.85,2.25,inf,1").unwrap();
        let p = Parameterisation::with_masses(&zero).unwrap();
        let d = p.decode(&p.encode(&zero)).unwrap();
        assert!(d.rows()[0].mass() <= 1.0001 * (-LOGIT_LIMIT).exp(), "{d:?}");
    }

    /// The chain rule against central differences of `decode`: a residual that is a fixed
    /// linear form of the cells, `r = sum w_c cell_c`, has `dr/dcell = w`, so its
    /// parameter derivatives are the differences of `w . cells(decode(p))`. On a matrix with
    /// free and fixed gammas and springs of both kinds; one logit past its clamp has none.
    #[test]
    fn the_chain_rule_matches_differences_of_decode() {
        let m =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4!,2.99,5; 0.15,2.58!,inf").unwrap();
        let param = Parameterisation::new(&m).unwrap();
        let rows = m.rows().len();
        let width = CELLS_PER_ROW * rows;
        let weights: Vec<f64> = (0..2 * width)
            .map(|k| ((k * 37 % 11) as f64) - 5.0)
            .collect();
        let linear = |p: &DVector<f64>, r: usize| -> f64 {
            let d = param.decode(p).unwrap();
            (0..rows)
                .flat_map(|i| {
                    let row = &d.rows()[i];
                    [row.gamma, row.k_theta, row.k_ex]
                })
                .zip(&weights[r * width..(r + 1) * width])
                .map(|(v, w)| if v.is_finite() { v * w } else { 0.0 })
                .sum()
        };
        for clamped in [false, true] {
            let mut p = param.encode(&m);
            if clamped {
                p[1] = LOGIT_LIMIT + 1.0;
            }
            let mut out = DMatrix::zeros(0, 0);
            param.chain_rule(&p, &weights, 2, &mut out);
            assert_eq!(out.shape(), (2, param.len()));
            for r in 0..2 {
                for k in 0..param.len() {
                    let h = 1e-6;
                    let (mut up, mut down) = (p.clone(), p.clone());
                    up[k] += h;
                    down[k] -= h;
                    let fd = (linear(&up, r) - linear(&down, r)) / (2.0 * h);
                    // Central differences of smooth exponentials: error about h^2 times
                    // the third derivative (O(10) here) plus round-off 1e-16 / h.
                    assert!(
                        (out[(r, k)] - fd).abs() < 1e-7 * (1.0 + fd.abs()),
                        "clamped {clamped}, residual {r}, parameter {k}: {} against {fd}",
                        out[(r, k)]
                    );
                }
            }
            if clamped {
                assert_eq!(out[(0, 1)], 0.0);
            }
        }
    }

    #[test]
    fn every_parameter_vector_is_a_valid_matrix() {
        let m = PrbMatrix::from_topology("L-RP-R").unwrap();
        let p = Parameterisation::new(&m).unwrap();
        for seed in 0..200u32 {
            let v = DVector::from_fn(p.len(), |i, _| {
                ((seed * 7919 + i as u32 * 104729) % 2001) as f64 / 100.0 - 10.0
            });
            assert!(p.decode(&v).is_some(), "{v}");
        }
    }

    #[test]
    fn fixed_gammas_that_leave_nothing_are_an_error() {
        let m = PrbMatrix::parse("0.6!,inf,inf; 0.4!,2,inf").unwrap();
        // Both fixed: nothing free to share, which is fine (gammas simply stay).
        assert!(Parameterisation::new(&m).is_ok());
        let m = PrbMatrix::parse("1!,inf,inf; 1e-300,2,inf");
        assert!(m.is_ok());
        let p = Parameterisation::new(&m.unwrap());
        assert!(matches!(p, Err(ParamError::NoLengthLeft(_))));
    }
}
