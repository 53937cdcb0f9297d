//! The PRB model's own estimate of the largest fibre stress (DESIGN §11): the fibre stress
//! of its largest joint or root moment.
//!
//! A PRB chain's links are rigid, so along each the moment `M(s) = beta + alpha_y (a - x) -
//! alpha_x (b - y)` (statics, from the tip load and the chain's own shape) is linear, and its
//! largest magnitude is at a link's end: the root, a joint, or the tip. At each such point
//! the estimate is the beam's fibre stress of that section ([`BeamModel::fibre_stress`]:
//! `sigma = |N| / A + 6 |M| / (b t^2)` with the beam's section, shrunk by Poisson's effect as
//! the beam's stress is), `N` the axial force of the link on either side (the larger
//! stress); its place is the point's `s / L` along the unloaded chain. At a joint the
//! moment is also the joint spring's `k_theta theta` (its equilibrium), so a PRB model's
//! estimate is as good as its springs carry the beam's moment.

use crate::beam::{BeamModel, Load, Stress};

use super::PrbSolver;

impl PrbSolver {
    /// The chain's largest fibre stress and where it is (module docs), in the equilibrium
    /// `q` under `load`, with `section` the beam whose section it stands for (its units:
    /// `sigma / E`); the root first where several points are equal (a pure moment's).
    /// `None` where the material law has no state (a necked or crushed section).
    pub fn max_stress(&self, section: &BeamModel, load: Load, q: &[f64]) -> Option<Stress> {
        let n = self.gamma.len();
        let mut theta = vec![0.0; n];
        let mut length = vec![0.0; n];
        self.segments(q, &mut theta, &mut length);
        // The points (root, joints, tip), each with its nominal s and the axial force of
        // the links on its two sides.
        let mut points = Vec::with_capacity(n + 1);
        let (mut x, mut y, mut s) = (0.0, 0.0, 0.0);
        let axial = |j: usize| {
            let (sn, cs) = theta[j].sin_cos();
            load.alpha_x * cs + load.alpha_y * sn
        };
        for j in 0..n {
            let before = if j == 0 { axial(0) } else { axial(j - 1) };
            points.push((x, y, s, before, axial(j)));
            let (sn, cs) = theta[j].sin_cos();
            x += length[j] * cs;
            y += length[j] * sn;
            s += self.gamma[j];
        }
        let last = n.checked_sub(1).map_or(0.0, axial);
        points.push((x, y, s, last, last));
        let mut best: Option<Stress> = None;
        for &(px, py, ps, n0, n1) in &points {
            let m = load.beta + load.alpha_y * (x - px) - load.alpha_x * (y - py);
            let sigma = section
                .fibre_stress(n0, m)?
                .max(section.fibre_stress(n1, m)?);
            if best.is_none_or(|b| sigma > b.max) {
                best = Some(Stress { max: sigma, at: ps });
            }
        }
        best
    }
}
