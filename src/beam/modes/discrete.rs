//! The Ritz discretisation of one beam about its equilibrium: stiffness (material and
//! geometric), distributed mass, and the tip's motion, as matrices on the coefficients of
//! the strain fields (see the parent module for the formulation).

use nalgebra::DMatrix;

use super::basis::{integrated_legendre, legendre_all, Quadrature};
use super::equilibrium::Sampled;

/// Which fields a beam has and how many coefficients each takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Layout {
    /// Coefficients per field (Legendre degrees `0..degree`).
    pub degree: usize,
    /// The axial strain is a field (extension on).
    pub extension: bool,
    /// The shear strain is a field (shear on).
    pub shear: bool,
}

impl Layout {
    /// All the beam's coefficients.
    pub fn dofs(&self) -> usize {
        self.degree * (1 + usize::from(self.extension) + usize::from(self.shear))
    }

    /// Where the axial strain's coefficients start.
    fn e_start(&self) -> usize {
        self.degree
    }

    /// Where the shear strain's coefficients start.
    fn g_start(&self) -> usize {
        self.degree * (1 + usize::from(self.extension))
    }
}

/// One beam about its equilibrium, in its own units (its `L`, `E I0`, `rho A0`) and frame
/// (clamp at the origin, unloaded along +x).
#[derive(Debug, Clone)]
pub(crate) struct BeamMatrices {
    /// The fields and their coefficients.
    pub layout: Layout,
    /// The second variation of the potential (the tip load's geometric stiffness included).
    pub stiffness: DMatrix<f64>,
    /// The distributed mass (with the rotary inertia when shear is on), no tip body.
    pub mass: DMatrix<f64>,
    /// `3 x dofs`: the tip's `(da, db, dphi)` per coefficient.
    pub tip: DMatrix<f64>,
    /// `Q x dofs`: the slope of the centre line's motion `d r'(s)` at the nodes, x and y.
    pub slope_x: DMatrix<f64>,
    /// As `slope_x`, the y component.
    pub slope_y: DMatrix<f64>,
    /// The equilibrium's centre-line slope `r'(s)` at the nodes, x and y.
    pub centre_slope: Vec<(f64, f64)>,
}

/// Assembles the matrices of a beam whose equilibrium is `eq` (sampled at `quad`'s nodes),
/// with rotary inertia `rotary` (`rho I0 / (rho A0 L^2)`, used only with shear on).
pub(crate) fn assemble(
    layout: Layout,
    quad: &Quadrature,
    eq: &Sampled,
    rotary: f64,
) -> BeamMatrices {
    let nq = quad.len();
    let n = layout.degree;
    let dofs = layout.dofs();
    // Legendre values (strains, curvature) and their integrals (rotation) at the nodes.
    let mut p = DMatrix::<f64>::zeros(nq, n);
    let mut phi = DMatrix::<f64>::zeros(nq, n);
    let mut buf = vec![0.0; n + 2];
    let mut row = vec![0.0; n + 1];
    for (q, &s) in quad.nodes.iter().enumerate() {
        legendre_all(2.0 * s - 1.0, n, &mut row);
        for k in 0..n {
            p[(q, k)] = row[k];
        }
        integrated_legendre(s, n, &mut row, &mut buf);
        for k in 0..n {
            phi[(q, k)] = row[k];
        }
    }
    // Weighted products A^T diag(w f) B.
    let weighted = |a: &DMatrix<f64>, f: &dyn Fn(usize) -> f64, b: &DMatrix<f64>| {
        let mut scaled = b.clone();
        for q in 0..nq {
            let c = quad.weights[q] * f(q);
            scaled.row_mut(q).scale_mut(c);
        }
        a.transpose() * scaled
    };
    let nodes = &eq.nodes;
    let mut k = DMatrix::<f64>::zeros(dofs, dofs);
    let kappa = 2;
    let set = |k: &mut DMatrix<f64>, r0: usize, c0: usize, block: DMatrix<f64>| {
        k.view_mut((r0, c0), (n, n)).copy_from(&block);
        if r0 != c0 {
            k.view_mut((c0, r0), (n, n)).copy_from(&block.transpose());
        }
    };
    let tt = weighted(&p, &|q| nodes[q].d[kappa][kappa], &p)
        + weighted(
            &phi,
            &|q| (1.0 + nodes[q].eps) * nodes[q].n + nodes[q].gamma * nodes[q].q,
            &phi,
        );
    set(&mut k, 0, 0, tt);
    if layout.extension {
        let e0 = layout.e_start();
        let te = weighted(&p, &|q| nodes[q].d[kappa][0], &p) + weighted(&phi, &|q| -nodes[q].q, &p);
        set(&mut k, 0, e0, te);
        set(&mut k, e0, e0, weighted(&p, &|q| nodes[q].d[0][0], &p));
    }
    if layout.shear {
        let g0 = layout.g_start();
        let tg = weighted(&p, &|q| nodes[q].d[kappa][1], &p) + weighted(&phi, &|q| nodes[q].n, &p);
        set(&mut k, 0, g0, tg);
        set(&mut k, g0, g0, weighted(&p, &|q| nodes[q].d[1][1], &p));
        if layout.extension {
            set(
                &mut k,
                layout.e_start(),
                g0,
                weighted(&p, &|q| nodes[q].d[0][1], &p),
            );
        }
    }
    // The centre line's motion: d r' = e t + g n + theta ((1 + eps) n - gamma t).
    let mut fx = DMatrix::<f64>::zeros(nq, dofs);
    let mut fy = DMatrix::<f64>::zeros(nq, dofs);
    let mut centre_slope = Vec::with_capacity(nq);
    for (q, st) in nodes.iter().enumerate() {
        let (s, c) = st.psi.sin_cos();
        let (rx, ry) = (
            -(1.0 + st.eps) * s - st.gamma * c,
            (1.0 + st.eps) * c - st.gamma * s,
        );
        centre_slope.push((
            (1.0 + st.eps) * c - st.gamma * s,
            (1.0 + st.eps) * s + st.gamma * c,
        ));
        for j in 0..n {
            fx[(q, j)] = phi[(q, j)] * rx;
            fy[(q, j)] = phi[(q, j)] * ry;
            if layout.extension {
                fx[(q, layout.e_start() + j)] = p[(q, j)] * c;
                fy[(q, layout.e_start() + j)] = p[(q, j)] * s;
            }
            if layout.shear {
                fx[(q, layout.g_start() + j)] = -p[(q, j)] * s;
                fy[(q, layout.g_start() + j)] = p[(q, j)] * c;
            }
        }
    }
    let integrate = DMatrix::from_row_slice(nq, nq, &quad.integrate);
    let rx = &integrate * &fx;
    let ry = &integrate * &fy;
    let one = |_: usize| 1.0;
    let mut m = weighted(&rx, &one, &rx) + weighted(&ry, &one, &ry);
    if layout.shear && rotary > 0.0 {
        let rot = weighted(&phi, &|_| rotary, &phi);
        let mut block = m.view_mut((0, 0), (n, n));
        block += rot;
    }
    let mut tip = DMatrix::<f64>::zeros(3, dofs);
    for j in 0..dofs {
        let (mut a, mut b) = (0.0, 0.0);
        for q in 0..nq {
            a += quad.weights[q] * fx[(q, j)];
            b += quad.weights[q] * fy[(q, j)];
        }
        tip[(0, j)] = a;
        tip[(1, j)] = b;
    }
    // theta(1) = int_0^1 P_k = 1 for k = 0, else 0.
    tip[(2, 0)] = 1.0;
    BeamMatrices {
        layout,
        stiffness: k,
        mass: m,
        tip,
        slope_x: fx,
        slope_y: fy,
        centre_slope,
    }
}
