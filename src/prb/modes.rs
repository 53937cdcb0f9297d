//! The PRB chain's natural frequencies (DESIGN §10): small free vibration about an
//! equilibrium, `K q = omega^2 M q` in the joint coordinates, nondimensional (L = 1,
//! E I0 = 1, and the beam's mass per length `rho A0 = 1`, so that the frequencies are the
//! nondimensional `Omega = omega sqrt(rho A0 L^4 / (E I0))`).
//!
//! - `K` is the chain's tangent stiffness at the equilibrium ([`PrbSolver::linearise`]):
//!   the springs and the dead load's geometric stiffness (the derivative of the joints'
//!   generalised load, which lowers the frequencies under compression).
//! - `M` is the kinetic energy's matrix: segment i carries mass `mu_i` (its share of
//!   `rho A0 L`) at its middle and a uniform rod's rotary inertia `mu_i gamma_i^2 / 12`; the
//!   tip body ([`TipBody`]) its mass at the tip point and its inertia. A segment that no
//!   joint moves (a rigid root) contributes nothing: mass on it does not move.
//!
//! The eigenvalues come from [`crate::linalg::frequencies`], which also takes a joint that
//! carries no mass (a massless tip segment): its frequency is infinite and left out.

use crate::beam::modes::ModePoint;
use crate::beam::Load;
use crate::linalg::frequencies;

use super::chain::{Dof, PrbSolver};

/// A rigid body at the chain's tip (nondimensional: mass in units of the beam's `rho A0 L`,
/// inertia about the tip point, its centre of mass there, in `rho A0 L^3`).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct TipBody {
    /// Mass / (`rho A0 L`).
    pub mass: f64,
    /// Inertia / (`rho A0 L^3`).
    pub inertia: f64,
}

/// Why a chain has no natural frequencies at an equilibrium.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModesError {
    /// The tangent stiffness is singular or not positive there (at or past a critical load).
    #[error("the PRB chain is not stable at this equilibrium (omega^2 = {0:.3e}): the load is at or past its critical point")]
    Unstable(f64),
    /// The PRB mechanism cannot hold its unloaded pose (its equations are singular there: a
    /// self-stress or a motion nothing holds), the mechanism solver's own diagnosis.
    #[error("{0}")]
    Mechanism(String),
    /// `q` does not fit the chain.
    #[error("expected {expected} joint coordinates, got {got}")]
    Coordinates {
        /// The chain's degrees of freedom.
        expected: usize,
        /// What was given.
        got: usize,
    },
}

impl PrbSolver {
    /// The mass matrix (row-major, `m` x `m` for the chain's `m` degrees of freedom) at
    /// configuration `q`, with `tip` bolted to the tip: symmetric, positive semi-definite,
    /// and definite when every joint moves some mass.
    pub fn mass_matrix(&self, q: &[f64], tip: TipBody) -> Vec<f64> {
        let n = self.gamma.len();
        let m = self.dofs.len();
        let mut theta = vec![0.0; n];
        let mut length = vec![0.0; n];
        self.segments(q, &mut theta, &mut length);
        // Joint positions (each segment's root) and centres of mass.
        let mut root = vec![[0.0; 2]; n + 1];
        let mut centre = vec![[0.0; 2]; n];
        let dir: Vec<[f64; 2]> = theta
            .iter()
            .map(|t| {
                let (s, c) = t.sin_cos();
                [c, s]
            })
            .collect();
        for i in 0..n {
            centre[i] = [
                root[i][0] + 0.5 * length[i] * dir[i][0],
                root[i][1] + 0.5 * length[i] * dir[i][1],
            ];
            root[i + 1] = [
                root[i][0] + length[i] * dir[i][0],
                root[i][1] + length[i] * dir[i][1],
            ];
        }
        let tip_point = root[n];
        // Velocity of a point `p` of segment `i` (its rotation rate) per unit rate of `dof`.
        let rate = |dof: Dof, i: usize, p: [f64; 2], at_centre: bool| -> ([f64; 2], f64) {
            match dof {
                Dof::Theta(k) if k <= i => {
                    let r = [p[0] - root[k][0], p[1] - root[k][1]];
                    ([-r[1], r[0]], 1.0)
                }
                Dof::Delta(k) if k < i || (k == i && !at_centre) => (dir[k], 0.0),
                Dof::Delta(k) if k == i => ([0.5 * dir[k][0], 0.5 * dir[k][1]], 0.0),
                _ => ([0.0, 0.0], 0.0),
            }
        };
        let mut mass = vec![0.0; m * m];
        for a in 0..m {
            for b in a..m {
                let mut sum = 0.0;
                for (i, &c) in centre.iter().enumerate() {
                    let mu = self.mu[i];
                    if mu == 0.0 {
                        continue;
                    }
                    let (va, wa) = rate(self.dofs[a], i, c, true);
                    let (vb, wb) = rate(self.dofs[b], i, c, true);
                    let inertia = mu * self.gamma[i] * self.gamma[i] / 12.0;
                    sum += mu * (va[0] * vb[0] + va[1] * vb[1]) + inertia * wa * wb;
                }
                if tip.mass != 0.0 || tip.inertia != 0.0 {
                    let (va, wa) = rate(self.dofs[a], n - 1, tip_point, false);
                    let (vb, wb) = rate(self.dofs[b], n - 1, tip_point, false);
                    sum += tip.mass * (va[0] * vb[0] + va[1] * vb[1]) + tip.inertia * wa * wb;
                }
                mass[a * m + b] = sum;
                mass[b * m + a] = sum;
            }
        }
        mass
    }

    /// The chain's natural frequencies `Omega`, lowest first, about the equilibrium `q`
    /// under `load` (from the statics: [`PrbSolver::solve`]), with `tip` at the tip. At most
    /// as many as the chain has degrees of freedom that carry mass.
    pub fn modes(&self, load: Load, q: &[f64], tip: TipBody) -> Result<Vec<f64>, ModesError> {
        let m = self.dofs.len();
        if q.len() != m {
            return Err(ModesError::Coordinates {
                expected: m,
                got: q.len(),
            });
        }
        let lin = self.linearise(load, q);
        let mass = self.mass_matrix(q, tip);
        frequencies(&lin.stiffness, &mass, m).map_err(ModesError::Unstable)
    }

    /// The chain's root, every joint and its tip at configuration `q` (the chain's own frame
    /// and units: root at the origin, unloaded along +x) and their motion for the rate `dq`
    /// of the joint coordinates, for drawing a mode: per point its arc length along the
    /// unloaded chain (`s`, the sum of the gammas before it), position (`x`, `y`), motion
    /// (`dx`, `dy`: a revolute joint's rate turns everything beyond it about the joint, an
    /// extension moves it along its segment) and the rotation of the segment that ends there
    /// (`dpsi`, 0 at the root).
    pub fn joint_motion(&self, q: &[f64], dq: &[f64]) -> Vec<ModePoint> {
        let n = self.gamma.len();
        let mut theta = vec![0.0; n];
        let mut length = vec![0.0; n];
        self.segments(q, &mut theta, &mut length);
        let mut root = vec![[0.0; 2]; n + 1];
        let mut s = vec![0.0; n + 1];
        for i in 0..n {
            let (sn, c) = theta[i].sin_cos();
            root[i + 1] = [root[i][0] + length[i] * c, root[i][1] + length[i] * sn];
            s[i + 1] = s[i] + self.gamma[i];
        }
        (0..=n)
            .map(|j| {
                let p = root[j];
                let (mut dx, mut dy, mut dpsi) = (0.0, 0.0, 0.0);
                for (dof, &rate) in self.dofs.iter().zip(dq) {
                    match *dof {
                        Dof::Theta(k) if k < j => {
                            dx -= rate * (p[1] - root[k][1]);
                            dy += rate * (p[0] - root[k][0]);
                            dpsi += rate;
                        }
                        Dof::Delta(k) if k < j => {
                            let (sn, c) = theta[k].sin_cos();
                            dx += rate * c;
                            dy += rate * sn;
                        }
                        _ => {}
                    }
                }
                ModePoint {
                    s: s[j],
                    x: p[0],
                    y: p[1],
                    dx,
                    dy,
                    dpsi,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prb::PrbMatrix;

    fn solver(text: &str) -> PrbSolver {
        PrbSolver::new(&PrbMatrix::parse(text).unwrap(), 1.0 / 1200.0)
    }

    /// A 1R's joint rate turns its link about the joint: the root and the joint stay, the tip
    /// moves across the link by its length, straight or turned a quarter.
    #[test]
    fn joint_motion_turns_the_link_about_its_joint() {
        let s = solver("0.15,inf,inf; 0.85,2.2525,inf");
        let pts = s.joint_motion(&[0.0], &[1.0]);
        assert_eq!(pts.len(), 3);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert!(close(pts[1].s, 0.15) && close(pts[2].s, 1.0));
        for p in &pts[..2] {
            assert!(p.dx == 0.0 && p.dy == 0.0 && p.dpsi == 0.0, "{p:?}");
        }
        let tip = pts[2];
        assert!(close(tip.x, 1.0) && close(tip.dx, 0.0) && close(tip.dy, 0.85));
        assert!(close(tip.dpsi, 1.0));
        let turned = s.joint_motion(&[std::f64::consts::FRAC_PI_2], &[2.0]);
        let tip = turned[2];
        assert!(close(tip.x, 0.15) && close(tip.y, 0.85), "{tip:?}");
        assert!(close(tip.dx, -1.7) && tip.dy.abs() < 1e-15, "{tip:?}");
    }

    /// Howell's 1R, its mass spread over its link (mu = gamma = 0.85): a rod of mass 0.85
    /// and length 0.85 pivoting at its root, `I = m l^2 / 3`, so `Omega^2 = k / I` =
    /// 2.2525 / (0.85^3 / 3): Omega = 3.3117, 5.8 % below the beam's 3.516015 (DESIGN §10
    /// says "about 5.7 %").
    #[test]
    fn howell_1r_is_a_pivoting_rod() {
        let s = solver("0.15,inf,inf; 0.85,2.2525,inf");
        let w = s
            .modes(Load::new(0.0, 0.0, 0.0), &[0.0], TipBody::default())
            .unwrap();
        let want = (2.2525 / (0.85_f64.powi(3) / 3.0)).sqrt();
        assert_eq!(w.len(), 1);
        assert!((w[0] - want).abs() < 1e-12 * want, "{w:?} vs {want}");
        let low = 1.0 - w[0] / 3.516015;
        assert!((0.05..0.065).contains(&low), "{low}");
        // Mass parked on the rigid root does not move: mu = (0.15, 0.85) rings the same, and
        // moving mass off the link raises the frequency (a lighter rod).
        let parked = solver("0.15,inf,inf,0.35; 0.85,2.2525,inf,0.65");
        let w2 = parked
            .modes(Load::new(0.0, 0.0, 0.0), &[0.0], TipBody::default())
            .unwrap();
        let want2 = (2.2525 / (0.65 * 0.85_f64.powi(2) / 3.0)).sqrt();
        assert!((w2[0] - want2).abs() < 1e-12 * want2, "{w2:?}");
        // A tip mass M at distance 0.85: I = m l^2/3 + M l^2.
        let tip = TipBody {
            mass: 0.5,
            inertia: 0.01,
        };
        let w3 = s.modes(Load::new(0.0, 0.0, 0.0), &[0.0], tip).unwrap();
        let i = 0.85_f64.powi(3) / 3.0 + 0.5 * 0.85 * 0.85 + 0.01;
        assert!((w3[0] - (2.2525 / i).sqrt()).abs() < 1e-12, "{w3:?}");
    }

    /// Under an axial tip force the 1R's stiffness is `k - alpha_x l` (a compressive one
    /// lowers it: `k + alpha_x gamma` with alpha_x < 0), so the frequency reaches zero at the
    /// 1R's buckling load `-k / gamma`.
    #[test]
    fn axial_load_moves_the_1r_frequency() {
        let s = solver("0.15,inf,inf; 0.85,2.2525,inf");
        let i = 0.85_f64.powi(3) / 3.0;
        for ax in [2.0, -1.0, -2.5] {
            let w = s
                .modes(Load::new(ax, 0.0, 0.0), &[0.0], TipBody::default())
                .unwrap();
            let want = ((2.2525 + ax * 0.85) / i).sqrt();
            assert!((w[0] - want).abs() < 1e-12, "{ax}: {w:?} vs {want}");
        }
        assert!(s
            .modes(Load::new(-2.7, 0.0, 0.0), &[0.0], TipBody::default())
            .is_err());
    }

    /// A two-link pendulum-like chain: the mass matrix is the textbook double rod's.
    #[test]
    fn two_rods_mass_matrix() {
        let s = solver("0.5,1,inf; 0.5,1,inf");
        let m = s.mass_matrix(&[0.0, 0.0], TipBody::default());
        // Rod 1 (m = 0.5, l = 0.5) about its root: m l^2 / 3; rod 2 about joint 1: the same,
        // plus its motion with joint 0: m (l + l/2)^2 + m l^2/12 about the root.
        let (mr, l) = (0.5_f64, 0.5_f64);
        let m11 = mr * l * l / 3.0 + mr * (1.5 * l).powi(2) + mr * l * l / 12.0;
        let m12 = mr * (1.5 * l) * (0.5 * l) + mr * l * l / 12.0;
        let m22 = mr * l * l / 3.0;
        for (got, want) in m.iter().zip([m11, m12, m12, m22]) {
            assert!((got - want).abs() < 1e-15, "{m:?}");
        }
    }
}
