//! The fit's unknowns: the free cells of a PRB matrix, reparameterised so that every point of
//! the search space is a valid matrix (no penalties that stall the optimiser):
//!
//! - free gammas share what the fixed ones leave, `1 - sum(fixed)`, through a softmax of
//!   logits (the first logit is pinned at 0, which removes the softmax's redundant direction);
//! - free spring constants are `exp(u)`, positive for every real `u`.

use nalgebra::DVector;

use crate::prb::{Column, PrbMatrix};

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
        })
    }

    /// Number of parameters (zero: nothing to fit).
    pub fn len(&self) -> usize {
        self.free_gammas.len().saturating_sub(1) + self.free_springs.len()
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
        PrbMatrix::new(rows).ok()
    }

    /// Box for a global search in parameter space: logits within +-3 of the start (gamma
    /// ratios up to e^3 either way) and spring constants from 1/20 to 20 times the start's.
    pub fn search_box(&self, start: &DVector<f64>) -> (DVector<f64>, DVector<f64>) {
        let n_logits = self.free_gammas.len().saturating_sub(1);
        let widths: Vec<f64> = (0..self.len())
            .map(|k| if k < n_logits { 3.0 } else { 20f64.ln() })
            .collect();
        let lower =
            DVector::from_iterator(self.len(), start.iter().zip(&widths).map(|(s, w)| s - w));
        let upper =
            DVector::from_iterator(self.len(), start.iter().zip(&widths).map(|(s, w)| s + w));
        (lower, upper)
    }
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
