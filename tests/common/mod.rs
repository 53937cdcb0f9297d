//! Helpers shared by the integration tests.
#![allow(dead_code)]

use prbfit::beam::{BeamModel, BeamSolution};

/// Checks a returned shape against the beam's equations *independently of the solver*:
/// fourth-order central differences of the sampled `psi, x, y` against `M(s) / EI(s)` (moment from DESIGN
/// Eq. 3 with the returned tip) and the strained tangent. Returns the largest defect, relative
/// to `1 + |load|`.
pub fn equilibrium_defect(model: &BeamModel, sol: &BeamSolution) -> f64 {
    let (ax, ay, beta) = (sol.load.alpha_x, sol.load.alpha_y, sol.load.beta);
    let (a, b) = (sol.tip.a, sol.tip.b);
    let pts = &sol.shape;
    let scale = 1.0 + sol.load.magnitude();
    let mut worst = 0.0_f64;
    let d = |f: &dyn Fn(&prbfit::beam::ShapePoint) -> f64, w: &[prbfit::beam::ShapePoint]| {
        let h = w[3].s - w[2].s;
        (-f(&w[4]) + 8.0 * f(&w[3]) - 8.0 * f(&w[1]) + f(&w[0])) / (12.0 * h)
    };
    for w in pts.windows(5) {
        let p1 = w[2];
        let (sn, cs) = p1.psi.sin_cos();
        let n = ax * cs + ay * sn;
        let q = -ax * sn + ay * cs;
        let (eps, gamma, stiffness) = model.section_strains(n, q).expect("valid state");
        let m = beta + ay * (a - p1.x) - ax * (b - p1.y);
        let curvature = d(&|p| p.psi, w);
        let dx = d(&|p| p.x, w);
        let dy = d(&|p| p.y, w);
        worst = worst
            .max((curvature * stiffness - m).abs() / scale)
            .max((dx - ((1.0 + eps) * cs - gamma * sn)).abs())
            .max((dy - ((1.0 + eps) * sn + gamma * cs)).abs());
    }
    worst
}
