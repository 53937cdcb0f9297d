//! Legendre polynomials on `[0, 1]`: Gauss-Legendre nodes and weights, and the spectral
//! integration matrix that maps a function's values at the nodes to its integral from 0 to
//! each node (or to any station).

/// `P_0..P_{count-1}` at `x` in `[-1, 1]`, by the three-term recurrence.
pub(crate) fn legendre_all(x: f64, count: usize, out: &mut [f64]) {
    if count == 0 {
        return;
    }
    out[0] = 1.0;
    if count > 1 {
        out[1] = x;
    }
    for k in 2..count {
        let kf = k as f64;
        out[k] = ((2.0 * kf - 1.0) * x * out[k - 1] - (kf - 1.0) * out[k - 2]) / kf;
    }
}

/// `P_n(x)` and `P_n'(x)`.
fn legendre_with_slope(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let nf = n as f64;
    let slope = nf * (x * p1 - p0) / (x * x - 1.0);
    (p1, slope)
}

/// The `n`-point Gauss-Legendre rule on `[0, 1]`: nodes ascending, weights summing to 1.
/// Newton's method on `P_n` from Chebyshev guesses converges to round-off in a few steps for
/// every `n` used here (up to a few hundred).
pub(crate) fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    let nf = n as f64;
    for i in 0..n {
        // Root i of P_n, descending in x; mapped so s ascends.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        let mut slope = 1.0;
        // Quadratic convergence from a guess within the root's spacing: 3 to 5 steps.
        for _ in 0..12 {
            let (p, dp) = legendre_with_slope(n, x);
            slope = dp;
            let dx = p / dp;
            x -= dx;
            if dx.abs() <= 1e-15 {
                break;
            }
        }
        let (_, dp) = legendre_with_slope(n, x);
        if dp.is_finite() {
            slope = dp;
        }
        let w = 2.0 / ((1.0 - x * x) * slope * slope);
        nodes[i] = 0.5 * (1.0 - x);
        weights[i] = 0.5 * w;
    }
    (nodes, weights)
}

/// The quadrature of the modes: `n` Gauss nodes on `[0, 1]`, their weights, and the
/// integration matrix (row-major, `n x n`): `sum_r S[q][r] f(s_r)` is `int_0^{s_q} f`, exact
/// for polynomials of degree below `n` and spectrally accurate for smooth `f`.
#[derive(Debug, Clone)]
pub(crate) struct Quadrature {
    /// The nodes, ascending in `(0, 1)`.
    pub nodes: Vec<f64>,
    /// The weights (sum 1).
    pub weights: Vec<f64>,
    /// `int_0^{s_q}` as a matrix on the node values.
    pub integrate: Vec<f64>,
}

impl Quadrature {
    /// The `n`-point rule and its integration matrix, built once per `n` and shared.
    pub fn shared(n: usize) -> std::sync::Arc<Quadrature> {
        use std::collections::HashMap;
        use std::sync::{Arc, Mutex, OnceLock};
        static CACHE: OnceLock<Mutex<HashMap<usize, Arc<Quadrature>>>> = OnceLock::new();
        let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
        // A poisoned lock only means another thread panicked mid-insert: build afresh.
        match cache.lock() {
            Ok(mut map) => map
                .entry(n)
                .or_insert_with(|| Arc::new(Quadrature::new(n)))
                .clone(),
            Err(_) => Arc::new(Quadrature::new(n)),
        }
    }

    /// The `n`-point rule and its integration matrix.
    pub fn new(n: usize) -> Quadrature {
        let (nodes, weights) = gauss_legendre(n);
        let integrate = integration_matrix(&nodes, &weights, &nodes);
        Quadrature {
            nodes,
            weights,
            integrate,
        }
    }

    /// The number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }
}

/// `int_0^{t_k} f` for each target `t_k` in `[0, 1]` from `f` at the Gauss nodes (row-major,
/// `targets x nodes`): `f`'s Legendre coefficients by the rule, integrated exactly.
pub(crate) fn integration_matrix(nodes: &[f64], weights: &[f64], targets: &[f64]) -> Vec<f64> {
    let n = nodes.len();
    let mut out = vec![0.0; targets.len() * n];
    let mut p_nodes = vec![0.0; n * n];
    let mut buf = vec![0.0; n + 1];
    for (r, &s) in nodes.iter().enumerate() {
        legendre_all(2.0 * s - 1.0, n, &mut buf);
        p_nodes[r * n..(r + 1) * n].copy_from_slice(&buf[..n]);
    }
    for (k, &t) in targets.iter().enumerate() {
        // int_0^t P_j(2s-1) ds = (1/2) int_{-1}^{x} P_j = (1/2) (P_{j+1} - P_{j-1}) / (2j+1).
        let x = 2.0 * t - 1.0;
        legendre_all(x, n + 1, &mut buf);
        let row = &mut out[k * n..(k + 1) * n];
        for j in 0..n {
            let integral = if j == 0 {
                0.5 * (x + 1.0)
            } else {
                0.5 * (buf[j + 1] - buf[j - 1]) / (2.0 * j as f64 + 1.0)
            };
            // Coefficient of P_j: (2j+1) int_0^1 f P_j ds = (2j+1) sum_r w_r f_r P_j(x_r).
            let c = (2.0 * j as f64 + 1.0) * integral;
            for r in 0..n {
                row[r] += c * weights[r] * p_nodes[r * n + j];
            }
        }
    }
    out
}

/// `int_0^s P_j(2t - 1) dt` for `j` below `count`, at `s` in `[0, 1]`.
pub(crate) fn integrated_legendre(s: f64, count: usize, out: &mut [f64], buf: &mut [f64]) {
    let x = 2.0 * s - 1.0;
    legendre_all(x, count + 1, buf);
    for j in 0..count {
        out[j] = if j == 0 {
            0.5 * (x + 1.0)
        } else {
            0.5 * (buf[j + 1] - buf[j - 1]) / (2.0 * j as f64 + 1.0)
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_integrates_polynomials_exactly() {
        let q = Quadrature::new(12);
        let sum: f64 = q.weights.iter().sum();
        assert!((sum - 1.0).abs() < 1e-14);
        // int_0^1 s^k = 1 / (k + 1), exact up to degree 23.
        for k in 0..24 {
            let v: f64 = q
                .nodes
                .iter()
                .zip(&q.weights)
                .map(|(s, w)| w * s.powi(k))
                .sum();
            assert!((v - 1.0 / (k as f64 + 1.0)).abs() < 1e-14, "degree {k}");
        }
    }

    #[test]
    fn the_integration_matrix_integrates_to_each_node() {
        let q = Quadrature::new(16);
        let n = q.len();
        // f = cos(3 s): int_0^s = sin(3 s) / 3, spectrally accurate at 16 nodes.
        for (i, &s) in q.nodes.iter().enumerate() {
            let v: f64 = (0..n)
                .map(|r| q.integrate[i * n + r] * (3.0 * q.nodes[r]).cos())
                .sum();
            assert!((v - (3.0 * s).sin() / 3.0).abs() < 1e-13, "node {i}");
        }
    }
}
