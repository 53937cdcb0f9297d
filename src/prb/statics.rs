//! Kinematics and statics of a PRB chain (DESIGN §3), nondimensional (L = 1, E I0 = 1).
//!
//! The configuration `q` holds one joint angle `theta_i` per revolute row and one extension
//! `delta_i` per prismatic row, in row order. With `Theta_i = sum_{j<=i} theta_j` and
//! `l_i = gamma_i + delta_i`, the tip is `a = sum l_i cos Theta_i`, `b = sum l_i sin Theta_i`,
//! `phi = Theta_N`. Equilibrium (`tau = J^T F`) is
//!
//! ```text
//! k_theta_i theta_i = beta + sum_{j>=i} l_j Q_j                 each R joint
//! (k_ex_i / c_e) delta_i = N_i                                  each P joint
//! ```
//!
//! with `N_j = alpha_x cos Theta_j + alpha_y sin Theta_j` and
//! `Q_j = -alpha_x sin Theta_j + alpha_y cos Theta_j` the axial and transverse components of
//! the tip force in segment j, and `c_e = I0 / (A0 L^2)` (the P equation is DESIGN's divided by
//! `c_e`, which makes the tangent stiffness symmetric: it is the Hessian of the potential
//! energy). Newton's method on the analytic Jacobian solves it; each load is reached by
//! continuation from zero, like the beam, and an equilibrium is accepted only where the
//! tangent stiffness is positive definite (a stable equilibrium: Cholesky succeeds).

use crate::beam::{Load, TipPose};
use crate::linalg::cholesky_solve;

use super::matrix::PrbMatrix;

/// Why a PRB equilibrium could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PrbError {
    /// The requested load has a NaN or infinite component; holds that load.
    #[error("load is not finite: {0}")]
    NonFiniteLoad(Load),
    /// Continuation stalled: Newton diverged, the tip jumped off the followed branch, or the
    /// iteration budget ran out before the end of the load path.
    #[error(
        "the PRB model has no equilibrium for {load} past {:.4} of the load path ({reason})",
        fraction
    )]
    NoEquilibrium {
        /// The end of the load path (nondimensional `alpha_x`, `alpha_y`, `beta`).
        load: Load,
        /// The last load-path fraction (0 to 1) where an equilibrium was accepted.
        fraction: f64,
        /// What stopped the continuation, in words.
        reason: String,
    },
    /// The tangent stiffness stopped being positive definite on the load path: the chain
    /// buckles or snaps through there, and the stable branch ends.
    #[error(
        "the PRB model reaches a critical point (its tangent stiffness turns singular) at {:.4} \
         of the load path to {load}: it buckles or snaps there",
        fraction
    )]
    Unstable {
        /// The end of the load path (nondimensional `alpha_x`, `alpha_y`, `beta`).
        load: Load,
        /// The last load-path fraction (0 to 1) where a stable equilibrium was accepted.
        fraction: f64,
    },
}

/// One degree of freedom: which row, and whether it is the joint angle or the extension.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Dof {
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

/// An equilibrium of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct PrbSolution {
    /// The load solved for (nondimensional `alpha_x`, `alpha_y`, `beta`).
    pub load: Load,
    /// The chain's tip: `a`, `b` in units of L, `phi` (the last segment's angle `Theta_N`)
    /// in radians.
    pub tip: TipPose,
    /// Joint angles (radians, revolute rows) and extensions (units of L, prismatic rows), in
    /// row order.
    pub q: Vec<f64>,
    /// Newton iterations spent on this load, continuation sub-steps included.
    pub iterations: u32,
}

/// One equilibrium as handed to a visitor: the configuration is borrowed, so following a load
/// path allocates nothing per case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrbCase<'a> {
    /// The load solved for (nondimensional `alpha_x`, `alpha_y`, `beta`).
    pub load: Load,
    /// The chain's tip: `a`, `b` in units of L, `phi` in radians.
    pub tip: TipPose,
    /// Joint angles (radians, revolute rows) and extensions (units of L, prismatic rows), in
    /// row order; borrowed from the solver's buffer.
    pub q: &'a [f64],
    /// Newton iterations spent on this load, continuation sub-steps included.
    pub iterations: u32,
}

impl PrbCase<'_> {
    /// An owned copy of this equilibrium.
    pub fn to_solution(&self) -> PrbSolution {
        PrbSolution {
            load: self.load,
            tip: self.tip,
            q: self.q.to_vec(),
            iterations: self.iterations,
        }
    }
}

/// How hard a solver tries before it gives up on a load path. A fit's trial models use tight
/// limits, so that failing ones cost little; the defaults suit a model being judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverLimits {
    /// Newton iterations one attempt may take before the continuation step is halved (from a
    /// good predictor Newton converges in a handful).
    newton_limit: u32,
    /// Newton iterations a load path may spend per case, all attempts counted (the path gets
    /// `case_budget * steps + 100`).
    case_budget: u32,
    /// The smallest continuation step, as a fraction of the path, before giving up; a reported
    /// critical load is located only to within it.
    min_step: f64,
}

impl SolverLimits {
    /// Validated limits: every count at least 1, the step in (0, 1). A `const` built with
    /// this is checked when the crate compiles.
    pub const fn new(newton_limit: u32, case_budget: u32, min_step: f64) -> SolverLimits {
        assert!(newton_limit >= 1, "a Newton limit of 0 allows no iteration");
        assert!(case_budget >= 1, "a case budget of 0 allows no iteration");
        assert!(
            min_step > 0.0 && min_step < 1.0,
            "the smallest step must be in (0, 1)"
        );
        SolverLimits {
            newton_limit,
            case_budget,
            min_step,
        }
    }

    /// Checked at run time: the error says which limit is wrong.
    pub fn checked(
        newton_limit: u32,
        case_budget: u32,
        min_step: f64,
    ) -> Result<SolverLimits, String> {
        if newton_limit == 0 {
            return Err("the Newton limit must be at least 1".into());
        }
        if case_budget == 0 {
            return Err("the per-case Newton budget must be at least 1".into());
        }
        if !(min_step > 0.0 && min_step < 1.0) {
            return Err(format!(
                "the smallest continuation step must be in (0, 1), got {}",
                crate::text::bounded(min_step)
            ));
        }
        Ok(SolverLimits::new(newton_limit, case_budget, min_step))
    }
}

impl Default for SolverLimits {
    fn default() -> Self {
        SolverLimits::new(MAX_NEWTON, u32::MAX, MIN_STEP)
    }
}

/// Solves a PRB chain's statics. Cheap to build; holds no scratch between calls.
#[derive(Debug, Clone)]
pub struct PrbSolver {
    gamma: Vec<f64>,
    k_theta: Vec<f64>,
    /// `k_ex / c_e` per row (infinite for rows without an extension spring).
    k_ex_scaled: Vec<f64>,
    dofs: Vec<Dof>,
    /// The smallest continuation step before giving up on a load path.
    min_step: f64,
    /// Newton iterations one load path may spend per case, all attempts counted.
    case_budget: u32,
    /// Newton iterations one attempt may take before the step is halved.
    newton_limit: u32,
}

/// Newton stops when the update is below this (radians, units of L).
const NEWTON_TOL: f64 = 1e-13;
const MAX_NEWTON: u32 = 40;
/// No Newton update turns a joint by more than this (radians).
const MAX_TURN: f64 = 0.5;
const MAX_TIP_JUMP: f64 = 1.0;
const MIN_STEP: f64 = 1e-7;

impl PrbSolver {
    /// `axial_compliance` is `c_e = I0 / (A0 L^2) = 1 / (12 (L/t0)^2)` of the beam; it only
    /// matters for extension springs.
    pub fn new(matrix: &PrbMatrix, axial_compliance: f64) -> PrbSolver {
        let rows = matrix.rows();
        let mut dofs = Vec::new();
        for (i, r) in rows.iter().enumerate() {
            if r.has_revolute() {
                dofs.push(Dof::Theta(i));
            }
            if r.has_prismatic() {
                dofs.push(Dof::Delta(i));
            }
        }
        PrbSolver {
            gamma: rows.iter().map(|r| r.gamma).collect(),
            k_theta: rows.iter().map(|r| r.k_theta).collect(),
            k_ex_scaled: rows.iter().map(|r| r.k_ex / axial_compliance).collect(),
            dofs,
            min_step: MIN_STEP,
            case_budget: u32::MAX,
            newton_limit: MAX_NEWTON,
        }
    }

    /// The solver with these effort limits (checked when the limits were made).
    pub fn with_limits(mut self, limits: SolverLimits) -> PrbSolver {
        self.newton_limit = limits.newton_limit;
        self.case_budget = limits.case_budget;
        self.min_step = limits.min_step;
        self
    }

    /// Degrees of freedom of the chain.
    pub fn dof_count(&self) -> usize {
        self.dofs.len()
    }

    /// Cumulative angles and lengths of the segments for configuration `q`.
    fn segments(&self, q: &[f64], theta_cum: &mut [f64], length: &mut [f64]) {
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

    fn tip(&self, q: &[f64], ws: &mut Workspace) -> TipPose {
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
    fn residual(&self, load: Load, q: &[f64], ws: &mut Workspace) -> TipPose {
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

    /// Newton at a fixed load from `q` (updated in place). Returns the tip and iterations; a
    /// tangent stiffness that is not positive definite (an unstable or critical state) fails.
    fn newton(
        &self,
        load: Load,
        q: &mut [f64],
        ws: &mut Workspace,
    ) -> Result<(TipPose, u32), Failure> {
        let m = self.dofs.len();
        for iteration in 1..=MAX_NEWTON {
            let tip = self.residual(load, q, ws);
            ws.step[..m].copy_from_slice(&ws.res[..m]);
            if !cholesky_solve(&mut ws.jac[..m * m], &mut ws.step[..m], m) {
                return Err(Failure::NotPositiveDefinite);
            }
            let biggest = ws.step[..m].iter().fold(0.0_f64, |acc, v| acc.max(v.abs()));
            if !biggest.is_finite() {
                return Err(Failure::Diverged);
            }
            let scale = if biggest > MAX_TURN {
                MAX_TURN / biggest
            } else {
                1.0
            };
            for (qi, si) in q.iter_mut().zip(&ws.step[..m]) {
                *qi -= scale * si;
            }
            if biggest <= NEWTON_TOL {
                // The last update moved nothing by more than NEWTON_TOL: the tip stands.
                return Ok((tip, iteration));
            }
        }
        Err(Failure::Diverged)
    }

    /// Solves one load by continuation from the unloaded chain.
    pub fn solve(&self, load: Load) -> Result<PrbSolution, PrbError> {
        let mut v = self.solve_path(load, 1)?;
        // `solve_path_with` hands `visit` one case for each of its steps before it returns
        // `Ok`, so a one-step path that succeeded holds exactly one solution.
        #[allow(clippy::expect_used)]
        let last = v.pop().expect("a successful one-step path has one case");
        Ok(last)
    }

    /// Solves the proportional path to `end` at `k / steps`, `k = 1..=steps`, each case
    /// warm-started from the previous ones.
    pub fn solve_path(&self, end: Load, steps: u32) -> Result<Vec<PrbSolution>, PrbError> {
        let mut out = Vec::with_capacity(steps as usize);
        self.solve_path_with(end, steps, |case| out.push(case.to_solution()))?;
        Ok(out)
    }

    /// As [`Self::solve_path`], handing each case to `visit` (no allocation per case).
    pub fn solve_path_with(
        &self,
        end: Load,
        steps: u32,
        visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        self.follow_with(end, steps.max(1), |lambda| end.scaled(lambda), visit)
    }

    /// Follows the loads of `rows` in order, from the unloaded chain (measured data, DESIGN
    /// §9: a specimen's path is the polyline through its rows), handing the case at each row
    /// to `visit`. Between rows the load moves along the straight line from one row's load to
    /// the next (from zero to the first), with the same continuation as a proportional path.
    pub fn solve_rows_with(
        &self,
        rows: &[Load],
        visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        let Some(&last) = rows.last() else {
            return Ok(());
        };
        if let Some(bad) = rows.iter().find(|l| !l.is_finite()) {
            return Err(PrbError::NonFiniteLoad(*bad));
        }
        let n = rows.len();
        let at = |lambda: f64| {
            let x = lambda * n as f64;
            // At a row's own fraction (to rounding), the row's load exactly.
            let nearest = x.round();
            if (x - nearest).abs() < 1e-9 && nearest >= 1.0 {
                return rows[(nearest as usize).min(n) - 1];
            }
            let k = (x.floor().max(0.0) as usize).min(n - 1);
            let t = x - k as f64;
            let from = if k == 0 {
                Load {
                    alpha_x: 0.0,
                    alpha_y: 0.0,
                    beta: 0.0,
                }
            } else {
                rows[k - 1]
            };
            let to = rows[k];
            Load {
                alpha_x: from.alpha_x + t * (to.alpha_x - from.alpha_x),
                alpha_y: from.alpha_y + t * (to.alpha_y - from.alpha_y),
                beta: from.beta + t * (to.beta - from.beta),
            }
        };
        self.follow_with(last, n as u32, at, visit)
    }

    /// The continuation of [`Self::solve_path_with`] along any load curve `load_at(lambda)`,
    /// `lambda` from 0 (unloaded) to 1 (`end`), with cases at `k / steps`.
    fn follow_with(
        &self,
        end: Load,
        steps: u32,
        load_at: impl Fn(f64) -> Load,
        mut visit: impl FnMut(PrbCase<'_>),
    ) -> Result<(), PrbError> {
        if !end.is_finite() {
            return Err(PrbError::NonFiniteLoad(end));
        }
        let steps = steps.max(1);
        let m = self.dofs.len();
        let mut ws = Workspace::new(self.gamma.len(), m);
        let budget = self.case_budget.saturating_mul(steps).saturating_add(100);
        // The last two accepted points, for the secant predictor; their configurations live
        // in two buffers that swap roles, so accepting a step allocates nothing.
        let (mut prev_lambda, mut prev_tip) = (0.0, TipPose::STRAIGHT);
        let mut prev_q = vec![0.0; m];
        let mut prev2: Option<(f64, TipPose)> = None;
        let mut prev2_q = vec![0.0; m];
        let mut dlam = 1.0 / steps as f64;
        let mut q = vec![0.0; m];
        for k in 1..=steps {
            let target = k as f64 / steps as f64;
            let mut iterations = 0;
            loop {
                let lambda = (prev_lambda + dlam).min(target);
                // Predictor: secant through the last two points; from the unloaded chain,
                // the previous configuration.
                let mut predicted_tip = prev_tip;
                match prev2 {
                    Some((l2, t2)) => {
                        let t = (lambda - prev_lambda) / (prev_lambda - l2);
                        for i in 0..m {
                            q[i] = prev_q[i] + t * (prev_q[i] - prev2_q[i]);
                        }
                        predicted_tip = TipPose {
                            a: prev_tip.a + t * (prev_tip.a - t2.a),
                            b: prev_tip.b + t * (prev_tip.b - t2.b),
                            phi: prev_tip.phi + t * (prev_tip.phi - t2.phi),
                        };
                    }
                    None => q.copy_from_slice(&prev_q),
                }
                let load = load_at(lambda);
                let outcome = self.newton(load, &mut q, &mut ws);
                let failure = match outcome {
                    Ok((tip, its)) => {
                        iterations += its;
                        let jump = tip.max_diff(&prev_tip);
                        let off_prediction = tip.max_diff(&predicted_tip);
                        if jump > MAX_TIP_JUMP
                            || (prev2.is_some()
                                && off_prediction > 0.15 + 0.5 * predicted_tip.max_diff(&prev_tip))
                        {
                            Failure::Jumped
                        } else {
                            prev2 = Some((prev_lambda, prev_tip));
                            std::mem::swap(&mut prev_q, &mut prev2_q);
                            prev_q.copy_from_slice(&q);
                            (prev_lambda, prev_tip) = (lambda, tip);
                            dlam = (dlam * 2.0).min(1.0);
                            if lambda >= target {
                                visit(PrbCase {
                                    load,
                                    tip,
                                    q: &q,
                                    iterations,
                                });
                                break;
                            }
                            continue;
                        }
                    }
                    Err(f) => f,
                };
                dlam *= 0.5;
                if ws.spent > budget {
                    return Err(PrbError::NoEquilibrium {
                        load: end,
                        fraction: prev_lambda,
                        reason: format!("{} Newton iterations without reaching the load", ws.spent),
                    });
                }
                if dlam < self.min_step {
                    return Err(match failure {
                        Failure::NotPositiveDefinite => PrbError::Unstable {
                            load: end,
                            fraction: prev_lambda,
                        },
                        Failure::Diverged => PrbError::NoEquilibrium {
                            load: end,
                            fraction: prev_lambda,
                            reason: "Newton did not converge".into(),
                        },
                        Failure::Jumped => PrbError::NoEquilibrium {
                            load: end,
                            fraction: prev_lambda,
                            reason: "the equilibrium jumps away from the path".into(),
                        },
                    });
                }
            }
        }
        Ok(())
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

#[derive(Debug, Clone, Copy)]
enum Failure {
    NotPositiveDefinite,
    Diverged,
    Jumped,
}

/// Scratch space for one path solve, so Newton allocates nothing.
#[derive(Debug, Clone, PartialEq)]
struct Workspace {
    /// Newton iterations spent on the current path.
    spent: u32,
    theta_cum: Vec<f64>,
    length: Vec<f64>,
    axial: Vec<f64>,
    transverse: Vec<f64>,
    suffix_q: Vec<f64>,
    suffix_n: Vec<f64>,
    res: Vec<f64>,
    step: Vec<f64>,
    jac: Vec<f64>,
}

impl Workspace {
    fn new(n: usize, m: usize) -> Workspace {
        Workspace {
            spent: 0,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_checked() {
        assert!(SolverLimits::checked(0, 5, 1e-3)
            .unwrap_err()
            .contains("Newton limit"));
        assert!(SolverLimits::checked(5, 0, 1e-3)
            .unwrap_err()
            .contains("budget"));
        for bad in [0.0, -1.0, 1.0, f64::NAN] {
            assert!(SolverLimits::checked(5, 5, bad).is_err(), "{bad}");
        }
        assert_eq!(
            SolverLimits::checked(12, 20, 1e-3),
            Ok(SolverLimits::new(12, 20, 1e-3))
        );
    }
}
