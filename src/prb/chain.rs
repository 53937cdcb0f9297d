//! A PRB chain's kinematics and equilibrium equations (DESIGN §3), nondimensional: the tip
//! of a configuration `q`, the residual `K q - tau(q)` with its analytic tangent stiffness,
//! and the linearisation a closed mechanism's solver takes (see [`super::statics`] for the
//! equations). Exact up to rounding: no approximation beyond the PRB model itself.

use crate::beam::{Load, TipPose};

use super::statics::PrbSolver;

/// One degree of freedom: which row, and whether it is the joint angle or the extension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Dof {
    Theta(usize),
    Delta(usize),
}

/// A chain linearised at a configuration: see [`PrbSolver::linearise`].
#[derive(Debug, Clone, PartialEq)]
pub struct Linearised {
    /// The tip.
    pub tip: TipPose,
    /// `K q - tau(q)`, one row per degree of freedom.
    pub residual: Vec<f64>,
    /// Its Jacobian with respect to `q` (the tangent stiffness), row-major.
    pub stiffness: Vec<f64>,
    /// `d(a, b, phi) / dq`, 3 rows of `m`, row-major.
    pub tip_jacobian: Vec<f64>,
    /// Scratch.
    work: Workspace,
}

impl PrbSolver {
    /// Cumulative angles and lengths of the segments for configuration `q`.
    pub(super) fn segments(&self, q: &[f64], theta_cum: &mut [f64], length: &mut [f64]) {
        let n = self.gamma.len();
        length[..n].copy_from_slice(&self.gamma);
        theta_cum[..n].iter_mut().for_each(|t| *t = 0.0);
        for (dof, &v) in self.dofs.iter().zip(q) {
            match *dof {
                Dof::Theta(i) => theta_cum[i] = v,
                Dof::Delta(i) => length[i] += v,
            }
        }
        for i in 1..n {
            theta_cum[i] += theta_cum[i - 1];
        }
    }

    /// The tip pose for configuration `q`.
    pub fn tip_pose(&self, q: &[f64]) -> TipPose {
        let mut ws = Workspace::new(self.gamma.len(), self.dofs.len());
        self.tip(q, &mut ws)
    }

    pub(super) fn tip(&self, q: &[f64], ws: &mut Workspace) -> TipPose {
        let n = self.gamma.len();
        self.segments(q, &mut ws.theta_cum, &mut ws.length);
        let (mut a, mut b) = (0.0, 0.0);
        for j in 0..n {
            let (s, c) = ws.theta_cum[j].sin_cos();
            a += ws.length[j] * c;
            b += ws.length[j] * s;
        }
        TipPose {
            a,
            b,
            phi: ws.theta_cum[n - 1],
        }
    }

    /// The root, every segment's end, in order: `n + 1` points for drawing the linkage.
    pub fn joint_positions(&self, q: &[f64]) -> Vec<[f64; 2]> {
        let n = self.gamma.len();
        let mut theta_cum = vec![0.0; n];
        let mut length = vec![0.0; n];
        self.segments(q, &mut theta_cum, &mut length);
        let mut pts = Vec::with_capacity(n + 1);
        let (mut x, mut y) = (0.0, 0.0);
        pts.push([x, y]);
        for i in 0..n {
            let (s, c) = theta_cum[i].sin_cos();
            x += length[i] * c;
            y += length[i] * s;
            pts.push([x, y]);
        }
        pts
    }

    /// Residual `K q - tau(q)` and tangent stiffness (row-major, symmetric) at `q`.
    /// Returns the tip pose too.
    pub(super) fn residual(&self, load: Load, q: &[f64], ws: &mut Workspace) -> TipPose {
        let n = self.gamma.len();
        let m = self.dofs.len();
        self.segments(q, &mut ws.theta_cum, &mut ws.length);
        let (mut a, mut b) = (0.0, 0.0);
        for j in 0..n {
            let (s, c) = ws.theta_cum[j].sin_cos();
            ws.axial[j] = load.alpha_x * c + load.alpha_y * s;
            ws.transverse[j] = -load.alpha_x * s + load.alpha_y * c;
            a += ws.length[j] * c;
            b += ws.length[j] * s;
        }
        // Suffix sums: moment of the tip force about joint i, and its derivative.
        let (mut sq, mut sn) = (0.0, 0.0);
        for j in (0..n).rev() {
            sq += ws.length[j] * ws.transverse[j];
            sn += ws.length[j] * ws.axial[j];
            ws.suffix_q[j] = sq;
            ws.suffix_n[j] = sn;
        }
        for (r, dof) in self.dofs.iter().enumerate() {
            ws.res[r] = match *dof {
                Dof::Theta(i) => self.k_theta[i] * q[r] - (load.beta + ws.suffix_q[i]),
                Dof::Delta(i) => self.k_ex_scaled[i] * q[r] - ws.axial[i],
            };
            for (c, other) in self.dofs.iter().enumerate() {
                ws.jac[r * m + c] = match (*dof, *other) {
                    (Dof::Theta(i), Dof::Theta(k)) => {
                        let diag = if r == c { self.k_theta[i] } else { 0.0 };
                        diag + ws.suffix_n[i.max(k)]
                    }
                    (Dof::Theta(i), Dof::Delta(p)) => {
                        if p >= i {
                            -ws.transverse[p]
                        } else {
                            0.0
                        }
                    }
                    (Dof::Delta(p), Dof::Theta(k)) => {
                        if k <= p {
                            -ws.transverse[p]
                        } else {
                            0.0
                        }
                    }
                    (Dof::Delta(p), Dof::Delta(_)) => {
                        if r == c {
                            self.k_ex_scaled[p]
                        } else {
                            0.0
                        }
                    }
                };
            }
        }
        TipPose {
            a,
            b,
            phi: ws.theta_cum[n - 1],
        }
    }

    /// The chain linearised at `q` under `load` (for solvers that take `q` and the load as
    /// unknowns together, like a closed mechanism's): the residual `K q - tau(q)`, its
    /// Jacobian with respect to `q`, the tip and the tip's Jacobian `d(a, b, phi) / dq`
    /// (3 rows of `m`, row-major). `tau = J^T (alpha_x, alpha_y, beta)` is the virtual work
    /// of the tip wrench, so the residual's derivative with respect to the wrench is minus
    /// the tip Jacobian's transpose.
    pub fn linearise(&self, load: Load, q: &[f64]) -> Linearised {
        let mut out = self.linearised();
        self.linearise_into(load, q, &mut out);
        out
    }

    /// Storage for [`PrbSolver::linearise_into`], sized for this chain.
    pub fn linearised(&self) -> Linearised {
        let m = self.dofs.len();
        Linearised {
            tip: TipPose::STRAIGHT,
            residual: vec![0.0; m],
            stiffness: vec![0.0; m * m],
            tip_jacobian: vec![0.0; 3 * m],
            work: Workspace::new(self.gamma.len(), m),
        }
    }

    /// [`PrbSolver::linearise`] into storage from [`PrbSolver::linearised`], allocating
    /// nothing (a mechanism's Newton iteration calls it for every chain at every step).
    pub fn linearise_into(&self, load: Load, q: &[f64], out: &mut Linearised) {
        let n = self.gamma.len();
        let m = self.dofs.len();
        let ws = &mut out.work;
        out.tip = self.residual(load, q, ws);
        // Suffix sums of the segments' projections: d(a, b)/d(theta_i) turns everything
        // beyond joint i.
        let (mut sa, mut sb) = (0.0, 0.0);
        for j in (0..n).rev() {
            let (s, c) = ws.theta_cum[j].sin_cos();
            sa -= ws.length[j] * s;
            sb += ws.length[j] * c;
            ws.suffix_q[j] = sa;
            ws.suffix_n[j] = sb;
        }
        for (c, dof) in self.dofs.iter().enumerate() {
            let (da, db, dphi) = match *dof {
                Dof::Theta(i) => (ws.suffix_q[i], ws.suffix_n[i], 1.0),
                Dof::Delta(i) => {
                    let (s, co) = ws.theta_cum[i].sin_cos();
                    (co, s, 0.0)
                }
            };
            out.tip_jacobian[c] = da;
            out.tip_jacobian[m + c] = db;
            out.tip_jacobian[2 * m + c] = dphi;
        }
        out.residual.copy_from_slice(&ws.res[..m]);
        out.stiffness.copy_from_slice(&ws.jac[..m * m]);
    }

    /// The residual and Jacobian at `q`, for testing the analytic Jacobian.
    pub fn residual_and_jacobian(&self, load: Load, q: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let m = self.dofs.len();
        let mut ws = Workspace::new(self.gamma.len(), m);
        self.residual(load, q, &mut ws);
        (ws.res[..m].to_vec(), ws.jac[..m * m].to_vec())
    }
}

/// Scratch space for one path solve, so Newton allocates nothing.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Workspace {
    theta_cum: Vec<f64>,
    length: Vec<f64>,
    axial: Vec<f64>,
    transverse: Vec<f64>,
    suffix_q: Vec<f64>,
    suffix_n: Vec<f64>,
    pub(super) res: Vec<f64>,
    pub(super) step: Vec<f64>,
    pub(super) jac: Vec<f64>,
}

impl Workspace {
    pub(super) fn new(n: usize, m: usize) -> Workspace {
        Workspace {
            theta_cum: vec![0.0; n],
            length: vec![0.0; n],
            axial: vec![0.0; n],
            transverse: vec![0.0; n],
            suffix_q: vec![0.0; n],
            suffix_n: vec![0.0; n],
            res: vec![0.0; m],
            step: vec![0.0; m],
            jac: vec![0.0; m * m],
        }
    }
}
