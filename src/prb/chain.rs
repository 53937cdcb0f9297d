//! A PRB chain as the solver holds it (DESIGN §3), nondimensional: its rows and degrees of
//! freedom, the limits of its path following, and its kinematics and equilibrium equations:
//! the tip of a configuration `q`, the residual `K q - tau(q)` with its analytic tangent
//! stiffness, and the linearisation a closed mechanism's solver takes (see `statics.rs` for
//! the equations). Exact up to rounding: no approximation beyond the PRB model itself.

use crate::beam::{Load, TipPose};

use super::matrix::PrbMatrix;
use super::workspace::{Parts, Workspace};

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
    /// `d(a, b, phi) / d(cells)` at fixed `q`, filled (and sized) by
    /// [`PrbSolver::cell_partials`] only; empty until then.
    pub cell_tip: Vec<f64>,
    /// `d(K q - tau) / d(cells)` at fixed `q`, filled (and sized) by
    /// [`PrbSolver::cell_partials`] only; empty until then.
    pub cell_residual: Vec<f64>,
    /// Scratch: [`PrbSolver::tip_sensitivity`]'s adjoint `K^-1 T^T`.
    adjoint: Vec<f64>,
    /// Scratch.
    work: Workspace,
}

/// How hard a solver tries before it gives up on a load path. A fit's trial models use tight
/// limits, so that failing ones cost little; the defaults suit a model being judged.
///
/// Only the smallest step reaches the continuation at present: the Newton limit and the
/// per-case budget are checked and stored but have never been applied (every attempt may
/// take 40 iterations, and no case has a budget), and applying them would change fitted
/// results.
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
    pub(super) gamma: Vec<f64>,
    pub(super) k_theta: Vec<f64>,
    /// `k_ex / c_e` per row (infinite for rows without an extension spring).
    pub(super) k_ex_scaled: Vec<f64>,
    /// The beam's `c_e` the extension springs are scaled by.
    axial_compliance: f64,
    /// Each segment's mass as a fraction of the beam's (DESIGN §10: mu, or gamma).
    pub(super) mu: Vec<f64>,
    pub(super) dofs: Vec<Dof>,
    /// The smallest continuation step before giving up on a load path.
    pub(super) min_step: f64,
    /// Newton iterations one load path may spend per case, all attempts counted.
    case_budget: u32,
    /// Newton iterations one attempt may take before the step is halved.
    newton_limit: u32,
}

/// The smallest continuation step (a fraction of the path) of a model being judged.
const MIN_STEP: f64 = 1e-7;
/// Newton iterations one continuation attempt may take.
pub(super) const MAX_NEWTON: u32 = 40;

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
            axial_compliance,
            mu: rows.iter().map(|r| r.mass()).collect(),
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
        let ws = ws.parts();
        self.segments(q, ws.theta_cum, ws.length);
        let (mut a, mut b) = (0.0, 0.0);
        for j in 0..n {
            let (s, c) = segment_sin_cos(ws.theta_cum[j]);
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
            let (s, c) = segment_sin_cos(theta_cum[i]);
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
        let ws = ws.parts();
        self.segments(q, ws.theta_cum, ws.length);
        let (mut a, mut b) = (0.0, 0.0);
        for j in 0..n {
            let (s, c) = segment_sin_cos(ws.theta_cum[j]);
            ws.sin[j] = s;
            ws.cos[j] = c;
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

    /// The tip `tip` of the configuration [`PrbSolver::residual`] last saw, moved to first
    /// order by the Newton update `q -= ws.step` made since: `tip - T step`, with `T` the
    /// tip's Jacobian there. The rest is the update's square, so for Newton's last update
    /// (below 1e-13) this is the updated configuration's tip to rounding, without its sines
    /// and cosines. Overwrites the workspace's suffix sums.
    pub(super) fn tip_moved(&self, tip: TipPose, mut ws: Parts<'_>) -> TipPose {
        self.turn_suffixes(&mut ws);
        let (mut a, mut b, mut phi) = (tip.a, tip.b, tip.phi);
        for (dof, &d) in self.dofs.iter().zip(ws.step.iter()) {
            match *dof {
                Dof::Theta(i) => {
                    a -= ws.suffix_q[i] * d;
                    b -= ws.suffix_n[i] * d;
                    phi -= d;
                }
                Dof::Delta(i) => {
                    a -= ws.cos[i] * d;
                    b -= ws.sin[i] * d;
                }
            }
        }
        TipPose { a, b, phi }
    }

    /// `d(a, b)/d(theta_i)` for every joint `i` into the workspace's suffix sums
    /// (`suffix_q`, `suffix_n`), from the sines, cosines and lengths [`PrbSolver::residual`]
    /// last left: turning joint `i` turns every segment beyond it.
    fn turn_suffixes(&self, ws: &mut Parts<'_>) {
        let (mut sa, mut sb) = (0.0, 0.0);
        for j in (0..self.gamma.len()).rev() {
            sa -= ws.length[j] * ws.sin[j];
            sb += ws.length[j] * ws.cos[j];
            ws.suffix_q[j] = sa;
            ws.suffix_n[j] = sb;
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

    /// Whether `lin` is storage for this solver's chain (the same segments and degrees of
    /// freedom), so that a fit's next trial model may reuse the last one's.
    pub fn fits(&self, lin: &Linearised) -> bool {
        let (n, m) = (self.gamma.len(), self.dofs.len());
        lin.residual.len() == m && lin.work.n == n && lin.work.m == m
    }

    /// Storage for [`PrbSolver::linearise_into`], sized for this chain.
    pub fn linearised(&self) -> Linearised {
        let m = self.dofs.len();
        Linearised {
            tip: TipPose::STRAIGHT,
            residual: vec![0.0; m],
            stiffness: vec![0.0; m * m],
            tip_jacobian: vec![0.0; 3 * m],
            cell_tip: Vec::new(),
            cell_residual: Vec::new(),
            adjoint: Vec::new(),
            work: Workspace::new(self.gamma.len(), m),
        }
    }

    /// [`PrbSolver::linearise`] into storage from [`PrbSolver::linearised`], allocating
    /// nothing (a mechanism's Newton iteration calls it for every chain at every step).
    pub fn linearise_into(&self, load: Load, q: &[f64], out: &mut Linearised) {
        let m = self.dofs.len();
        out.tip = self.residual(load, q, &mut out.work);
        let mut ws = out.work.parts();
        self.turn_suffixes(&mut ws);
        self.tip_jacobian_into(&ws, &mut out.tip_jacobian);
        out.residual.copy_from_slice(&ws.res[..m]);
        out.stiffness.copy_from_slice(&ws.jac[..m * m]);
    }

    /// `d(a, b, phi) / dq` (3 rows of `m`, row-major) into `out`, from the turn suffixes,
    /// sines and cosines in `ws` ([`PrbSolver::turn_suffixes`]).
    fn tip_jacobian_into(&self, ws: &Parts<'_>, out: &mut [f64]) {
        let m = self.dofs.len();
        for (c, dof) in self.dofs.iter().enumerate() {
            let (da, db, dphi) = match *dof {
                Dof::Theta(i) => (ws.suffix_q[i], ws.suffix_n[i], 1.0),
                Dof::Delta(i) => (ws.cos[i], ws.sin[i], 0.0),
            };
            out[c] = da;
            out[m + c] = db;
            out[2 * m + c] = dphi;
        }
    }

    /// The partial derivatives of the chain's tip and equilibrium residual with respect to
    /// the matrix's statics cells at fixed joint coordinates, as [`PrbSolver::linearise_into`]
    /// last left `lin` (at `q`): `lin.cell_tip` (3 rows `a, b, phi`) and `lin.cell_residual`
    /// (one row per degree of freedom), each row with row `i`'s `(gamma, k_theta, k_ex)` at
    /// columns `3 i .. 3 i + 3` ([`CELLS_PER_ROW`]). A spring the row does not have (infinite)
    /// has no column entry (0).
    ///
    /// - `gamma_j` lengthens segment `j`: the tip moves along it, and every joint at or
    ///   before `j` carries more of the tip force's moment (`dR/d gamma_j = -transverse_j`).
    /// - `k_theta_i`, `k_ex_i`: the spring's own row, `dR/dk = q` (over `c_e` for `k_ex`,
    ///   which the chain scales by).
    pub fn cell_partials(&self, q: &[f64], lin: &mut Linearised) {
        let n = self.gamma.len();
        let cols = CELLS_PER_ROW * n;
        let ws = lin.work.parts();
        lin.cell_tip.clear();
        lin.cell_tip.resize(3 * cols, 0.0);
        lin.cell_residual.clear();
        lin.cell_residual.resize(self.dofs.len() * cols, 0.0);
        for j in 0..n {
            lin.cell_tip[CELLS_PER_ROW * j] = ws.cos[j];
            lin.cell_tip[cols + CELLS_PER_ROW * j] = ws.sin[j];
        }
        for (r, dof) in self.dofs.iter().enumerate() {
            let row = &mut lin.cell_residual[r * cols..(r + 1) * cols];
            match *dof {
                Dof::Theta(i) => {
                    for j in i..n {
                        row[CELLS_PER_ROW * j] = -ws.transverse[j];
                    }
                    row[CELLS_PER_ROW * i + 1] = q[r];
                }
                Dof::Delta(i) => row[CELLS_PER_ROW * i + 2] = q[r] / self.axial_compliance,
            }
        }
    }

    /// The tip's derivatives with respect to the matrix's statics cells at an equilibrium
    /// `q` under `load`, by the implicit function theorem: the equilibrium `R(q, c) = 0`
    /// moves with a cell `c` as `dq/dc = -K^-1 dR/dc` (`K` the tangent stiffness), so
    /// `d tip/dc = d tip/dc|_q - (K^-1 T^T)^T dR/dc` with `T = d tip/dq`: one factorisation
    /// of `K` against the tip's three rows, whatever the number of cells.
    ///
    /// `out` (length `3 * CELLS_PER_ROW * rows`) gets three rows `(a, b, phi)` laid out as
    /// [`PrbSolver::cell_partials`]' rows. `lin` is storage from [`PrbSolver::linearised`].
    /// False when `K` is singular (no equilibrium to follow).
    pub fn tip_sensitivity(
        &self,
        load: Load,
        q: &[f64],
        lin: &mut Linearised,
        out: &mut [f64],
    ) -> bool {
        let m = self.dofs.len();
        self.linearise_into(load, q, lin);
        self.cell_partials(q, lin);
        self.through_adjoint(lin, out, |lin, lambda| {
            crate::linalg::solve_many(&mut lin.stiffness, lambda, m, 3)
        })
    }

    /// The sensitivities' last step, from `lin`'s tip Jacobian `T` and cell partials: the
    /// adjoint `Lambda = K^-1 T^T` (`m` x 3, row-major; `K` is symmetric), which `solve`
    /// finds in place from `T^T`, then `out = d tip/dc|_q - Lambda^T dR/dc`. False where
    /// `solve` fails.
    fn through_adjoint(
        &self,
        lin: &mut Linearised,
        out: &mut [f64],
        solve: impl FnOnce(&mut Linearised, &mut [f64]) -> bool,
    ) -> bool {
        let cols = CELLS_PER_ROW * self.gamma.len();
        let m = self.dofs.len();
        let mut lambda = std::mem::take(&mut lin.adjoint);
        lambda.clear();
        lambda.extend((0..3 * m).map(|i| lin.tip_jacobian[(i % 3) * m + i / 3]));
        let solved = solve(lin, &mut lambda);
        if solved {
            out[..3 * cols].copy_from_slice(&lin.cell_tip);
            for r in 0..m {
                let d_res = &lin.cell_residual[r * cols..(r + 1) * cols];
                for k in 0..3 {
                    let l = lambda[r * 3 + k];
                    if l != 0.0 {
                        for (o, d) in out[k * cols..(k + 1) * cols].iter_mut().zip(d_res) {
                            *o -= l * d;
                        }
                    }
                }
            }
        }
        lin.adjoint = lambda;
        solved
    }

    /// [`PrbSolver::tip_sensitivity`] at the equilibrium `q` Newton has just converged to,
    /// from the workspace it left (`work`, the path's): the sines, cosines and transverse
    /// loads of its last residual, the turn suffixes of its last tip update, and its tangent
    /// stiffness already factored (`L D L^T`). These are taken one Newton update before `q`
    /// (below `1e-7` by Newton's stopping rule, typically `1e-10`), so the sensitivities
    /// differ from [`PrbSolver::tip_sensitivity`]'s at `q` by that much relative; a fit's
    /// Jacobian needs far less, and the linearisation and elimination this spares were 10 %
    /// of a 3R fit's time. False where `work` is not this chain's, or `K` is singular.
    pub(crate) fn tip_sensitivity_converged(
        &self,
        q: &[f64],
        work: &Workspace,
        lin: &mut Linearised,
        out: &mut [f64],
    ) -> bool {
        let (n, m) = (self.gamma.len(), self.dofs.len());
        if work.n != n || work.m != m || !self.fits(lin) {
            return false;
        }
        lin.work.buf.copy_from_slice(&work.buf);
        let ws = lin.work.parts();
        self.tip_jacobian_into(&ws, &mut lin.tip_jacobian);
        self.cell_partials(q, lin);
        self.through_adjoint(lin, out, |lin, lambda| {
            crate::linalg::factored_solve(lin.work.jac(), lambda, m, 3)
        })
    }

    /// The residual and Jacobian at `q`, for testing the analytic Jacobian.
    pub fn residual_and_jacobian(&self, load: Load, q: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let m = self.dofs.len();
        let mut ws = Workspace::new(self.gamma.len(), m);
        self.residual(load, q, &mut ws);
        let ws = ws.parts();
        (ws.res.to_vec(), ws.jac.to_vec())
    }
}

/// `(sin, cos)` of a segment's absolute angle. The segments before a chain's first joint
/// (the rigid first link of every `L-R...` topology) lie at exactly 0, whose sine is the
/// angle itself (keeping its sign) and cosine 1, as [`crate::trig::sin_cos`] gives them: a
/// quarter of a 3R fit's sines and cosines, 3 % of its time, skipped.
#[inline(always)]
fn segment_sin_cos(theta: f64) -> (f64, f64) {
    if theta == 0.0 {
        (theta, 1.0)
    } else {
        crate::trig::sin_cos(theta)
    }
}

/// Cells per matrix row in [`PrbSolver::tip_sensitivity`]: gamma, k_theta, k_ex.
pub const CELLS_PER_ROW: usize = 3;

#[cfg(test)]
mod tests {
    use super::*;

    /// The shortcut at a zero angle gives the general function's bits, for either zero, and
    /// every other angle goes to it.
    #[test]
    fn a_segment_at_zero_has_the_general_sine_and_cosine() {
        let bits = |(s, c): (f64, f64)| (s.to_bits(), c.to_bits());
        for theta in [0.0, -0.0, 1e-300, -0.3, 2.0] {
            assert_eq!(
                bits(segment_sin_cos(theta)),
                bits(crate::trig::sin_cos(theta)),
                "{theta:e}"
            );
        }
    }

    /// The sensitivities from the workspace Newton left at each case of a path are the
    /// linearisation's at the case, to within what the last Newton update (below 1e-7 by
    /// the stopping rule; the sensitivities' own derivatives here are a few units) moves
    /// them: 1e-6 relative. A wrong slice of the workspace (turn suffixes for the load's, or
    /// the factor taken for the stiffness) is off by O(0.1). On a chain with revolute and
    /// prismatic joints (the latter's workspace is on the heap) under a combined load, and a
    /// 3R (inline).
    #[test]
    fn sensitivities_from_newton_s_workspace_are_the_linearisation_s() {
        for text in [
            "0.1,inf,inf; 0.3,3.0,0.4; 0.35,2.5,inf; 0.25,2.0,0.6",
            "0.1,inf,inf; 0.35,3.5,inf; 0.4,2.9,inf; 0.15,2.6,inf",
        ] {
            let matrix = PrbMatrix::parse(text).unwrap();
            let solver = PrbSolver::new(&matrix, 0.01);
            let cols = CELLS_PER_ROW * solver.gamma.len();
            let (mut lin, mut lin_plain) = (solver.linearised(), solver.linearised());
            let (mut from_work, mut plain) = (vec![0.0; 3 * cols], vec![0.0; 3 * cols]);
            let mut cases = 0;
            solver
                .solve_path_with(Load::new(-1.2, 2.5, 0.7), 6, |case| {
                    let work = case.work.expect("a path hands its workspace over");
                    assert!(solver.tip_sensitivity_converged(
                        case.q,
                        work,
                        &mut lin,
                        &mut from_work
                    ));
                    assert!(solver.tip_sensitivity(case.load, case.q, &mut lin_plain, &mut plain));
                    for (a, b) in from_work.iter().zip(&plain) {
                        assert!(
                            (a - b).abs() <= 1e-6 * (1.0 + b.abs()),
                            "{text}: {a} against {b}"
                        );
                    }
                    cases += 1;
                })
                .unwrap();
            assert_eq!(cases, 6);
        }
    }

    /// The implicit-function sensitivities match central differences of the equilibrium
    /// solved again with each cell nudged, on a chain with revolute and prismatic joints
    /// under a combined load. The differences' own error is about `h^2` (1e-12) plus the
    /// equilibrium's tolerance over `h` (Newton's 1e-13 on the joint coordinates over
    /// 2e-6: 5e-8), so 1e-6 separates a right sensitivity from a wrong one (a sign or a
    /// missed term is O(0.1)).
    #[test]
    fn tip_sensitivities_match_central_differences() {
        let matrix =
            PrbMatrix::parse("0.1,inf,inf; 0.3,3.0,0.4; 0.35,2.5,inf; 0.25,2.0,0.6").unwrap();
        let c_e = 0.01;
        let solver = PrbSolver::new(&matrix, c_e);
        let load = Load::new(-1.2, 2.5, 0.7);
        let sol = solver.solve(load).unwrap();
        let n = solver.gamma.len();
        let mut lin = solver.linearised();
        let mut sens = vec![0.0; 3 * CELLS_PER_ROW * n];
        assert!(solver.tip_sensitivity(load, &sol.q, &mut lin, &mut sens));
        let tip = |s: &PrbSolver| {
            let t = s.solve(load).unwrap().tip;
            [t.a, t.b, t.phi]
        };
        let mut checked = 0;
        for i in 0..n {
            for cell in 0..CELLS_PER_ROW {
                let value = match cell {
                    0 => solver.gamma[i],
                    1 => solver.k_theta[i],
                    _ => solver.k_ex_scaled[i] * c_e,
                };
                let column = CELLS_PER_ROW * i + cell;
                if !value.is_finite() {
                    for k in 0..3 {
                        assert_eq!(sens[k * CELLS_PER_ROW * n + column], 0.0);
                    }
                    continue;
                }
                let h = 1e-6 * value.abs().max(0.1);
                let nudged = |d: f64| {
                    let mut s = solver.clone();
                    match cell {
                        0 => s.gamma[i] += d,
                        1 => s.k_theta[i] += d,
                        _ => s.k_ex_scaled[i] = (value + d) / c_e,
                    }
                    tip(&s)
                };
                let (up, down) = (nudged(h), nudged(-h));
                for k in 0..3 {
                    let fd = (up[k] - down[k]) / (2.0 * h);
                    let analytic = sens[k * CELLS_PER_ROW * n + column];
                    assert!(
                        (fd - analytic).abs() < 1e-6 * (1.0 + fd.abs()),
                        "row {i} cell {cell} tip {k}: {analytic} against {fd}"
                    );
                }
                checked += 1;
            }
        }
        // 4 gammas, 3 torsion springs, 2 extension springs.
        assert_eq!(checked, 9);
    }

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
