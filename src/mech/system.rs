//! The mechanism's equations at one drive fraction (see the parent module for the
//! formulation): the unknowns' layout, the residual (every flexure's joint rows and internal
//! rows, then the stage's balance in its loaded coordinates) and its analytic Jacobian,
//! checked against central differences in the tests below.

use crate::scene::Coordinate;

use super::geometry::{cross, rotate, Joint};
use super::solve::{FlexEval, FlexureModel, Kind, MechSolver};
use super::{MechError, TipFailure};

/// One evaluation of the whole system at an unknown vector.
pub(super) struct System {
    pub evals: Vec<FlexEval>,
    pub residual: Vec<f64>,
    /// The load the flexures put on the stage at `P` (flexure 1's units).
    pub load: [f64; 3],
}

impl System {
    /// Whether every flexure's Jacobian came with it (not an evaluation by values).
    pub fn has_jacobian(&self) -> bool {
        self.evals.iter().all(|e| !e.jacobian.is_empty())
    }
}

impl<M: FlexureModel> MechSolver<M> {
    /// The unknowns of the unloaded mechanism (couplers along their unloaded direction).
    pub(super) fn start(&self, drive: &[Coordinate; 3]) -> Vec<f64> {
        let mut x = vec![0.0; self.flexure_unknowns];
        for (f, &o) in self.geometry.frames.iter().zip(&self.offsets) {
            if let Joint::Link { to, .. } = f.joint {
                let tip = f.unloaded_tip();
                x[o + 1] = (to[1] - tip[1]).atan2(to[0] - tip[0]);
            }
        }
        x.extend(drive.iter().filter(|c| !c.is_prescribed()).map(|_| 0.0));
        x
    }

    /// Flexure `i`'s wrench parameters in its own frame and units, and their derivatives
    /// with respect to its first two unknowns (`d(alpha_x, alpha_y) / d(u0, u1)`, row-major).
    pub(super) fn own_wrench(&self, i: usize, x: &[f64]) -> ([f64; 3], [f64; 4]) {
        let f = &self.geometry.frames[i];
        let u = &x[self.offsets[i]..self.offsets[i] + 3];
        match f.joint {
            Joint::Clamped | Joint::Pinned => ([u[0], u[1], u[2]], [1.0, 0.0, 0.0, 1.0]),
            Joint::Link { .. } => {
                // A coupler's tension `t` and direction `psi` (global, flexure 1's units).
                let (s, c) = u[1].sin_cos();
                let local = f.force_to_local([u[0] * c, u[0] * s]);
                let d_t = f.force_to_local([c, s]);
                let d_psi = f.force_to_local([-u[0] * s, u[0] * c]);
                (
                    [local[0], local[1], u[2]],
                    [d_t[0], d_psi[0], d_t[1], d_psi[1]],
                )
            }
        }
    }

    /// The stage pose for unknowns `x` with the drive's coordinates at `at`.
    pub(super) fn pose(&self, at: &[Coordinate; 3], x: &[f64]) -> [f64; 3] {
        let mut k = self.flexure_unknowns;
        let mut pose = [0.0; 3];
        for (p, c) in pose.iter_mut().zip(at) {
            *p = match c {
                Coordinate::Prescribed(v) => *v,
                Coordinate::Loaded(_) => {
                    k += 1;
                    x[k - 1]
                }
            };
        }
        pose
    }

    /// The geometry's equations (every flexure's three joint rows, then the stage's loaded
    /// coordinates' balance) for unknowns `x` and flexure outputs `outs`, appended to `out`;
    /// returns the load the flexures put on the stage at `P`.
    pub(super) fn joints(
        &self,
        at: &[Coordinate; 3],
        x: &[f64],
        outs: &[[f64; 4]],
        out: &mut Vec<f64>,
    ) -> [f64; 3] {
        let pose = self.pose(at, x);
        let p = self.geometry.stage_point_at(pose);
        let mut sum = [0.0; 3];
        for (i, (f, o)) in self.geometry.frames.iter().zip(outs).enumerate() {
            let u = &x[self.offsets[i]..self.offsets[i] + 3];
            let (at, force) = match f.joint {
                Joint::Clamped | Joint::Pinned => {
                    let at = self.geometry.stage_map(pose, f.unloaded_tip());
                    let want = f.to_local(at);
                    let third = if f.joint == Joint::Clamped {
                        o[2] - pose[2]
                    } else {
                        o[3]
                    };
                    out.extend([o[0] - want[0], o[1] - want[1], third]);
                    (at, f.force_to_global([u[0], u[1]]))
                }
                Joint::Link { to, length } => {
                    let (s, c) = u[1].sin_cos();
                    let end = self.geometry.stage_map(pose, to);
                    let at = [end[0] - length * c, end[1] - length * s];
                    let want = f.to_local(at);
                    out.extend([o[0] - want[0], o[1] - want[1], o[3]]);
                    (at, [u[0] * c, u[0] * s])
                }
            };
            sum[0] += force[0];
            sum[1] += force[1];
            sum[2] += cross([at[0] - p[0], at[1] - p[1]], force) + f.moment_to_global(o[3]);
        }
        for (c, s) in at.iter().zip(sum) {
            if let Coordinate::Loaded(v) = c {
                out.push(s - v);
            }
        }
        sum
    }

    /// Every flexure evaluated at `x` as `kind` says: with its Jacobian, also with its shape,
    /// or by values where that is cheaper ([`FlexureModel::eval_values`]).
    pub(super) fn evaluate(&self, x: &[f64], kind: Kind) -> Result<Vec<FlexEval>, MechError> {
        let at: Vec<([f64; 3], &[f64])> = (0..self.models.len())
            .map(|i| {
                let (w, _) = self.own_wrench(i, x);
                let o = self.offsets[i] + 3;
                (w, &x[o..o + self.models[i].internal()])
            })
            .collect();
        M::eval_all(&self.models, &at, kind)
            .into_iter()
            .enumerate()
            .map(|(i, eval)| eval.map_err(|e| flexure_error(i, e)))
            .collect()
    }

    /// The flexures' outputs that the geometry's equations read: `[a, b, phi, tip_moment]`.
    pub(super) fn outputs(evals: &[FlexEval]) -> Vec<[f64; 4]> {
        evals
            .iter()
            .map(|e| [e.tip.a, e.tip.b, e.tip.phi, e.tip_moment])
            .collect()
    }

    /// The whole system at `x`: flexures, residual (joint rows, internal rows, balance).
    pub(super) fn system(&self, at: &[Coordinate; 3], x: &[f64]) -> Result<System, MechError> {
        self.system_with(at, x, Kind::Full)
    }

    /// [`MechSolver::system`] with the flexures evaluated as `kind` says: by values alone
    /// where that is cheaper ([`Kind::Values`]: its residual, load and outputs are the same
    /// to the shots' integration tolerance, but the Jacobian cannot be formed from it,
    /// [`System::has_jacobian`]), or with their shapes too ([`Kind::Shaped`]).
    pub(super) fn system_with(
        &self,
        at: &[Coordinate; 3],
        x: &[f64],
        kind: Kind,
    ) -> Result<System, MechError> {
        let evals = self.evaluate(x, kind)?;
        let mut joint = Vec::with_capacity(x.len());
        let load = self.joints(at, x, &Self::outputs(&evals), &mut joint);
        Ok(System {
            residual: self.assemble_rows(&joint, &evals),
            evals,
            load,
        })
    }

    /// Rows in the unknowns' order: flexure i's three joint rows then its internal rows, and
    /// the balance rows last.
    pub(super) fn assemble_rows(&self, joint: &[f64], evals: &[FlexEval]) -> Vec<f64> {
        let mut r = Vec::with_capacity(joint.len() + self.flexure_unknowns);
        for (i, e) in evals.iter().enumerate() {
            r.extend_from_slice(&joint[3 * i..3 * i + 3]);
            r.extend_from_slice(&e.internal);
        }
        r.extend_from_slice(&joint[3 * evals.len()..]);
        r
    }

    /// The Jacobian (row-major) at `x`: each flexure's own block from its model (the beam's
    /// variational equations, the chain's analytic tangent), chained with the geometry's
    /// derivatives, written out below (a rigid stage, straight couplers).
    pub(super) fn jacobian(&self, at: &[Coordinate; 3], x: &[f64], sys: &System) -> Vec<f64> {
        self.jacobian_and_load(at, x, sys).0
    }

    /// [`MechSolver::jacobian`], and the derivatives of the load the flexures put on the
    /// stage ([`System::load`]) with respect to the unknowns: 3 rows of `n`, row-major (a
    /// loaded coordinate's row is its balance row; a prescribed one's is its reaction's).
    pub(super) fn jacobian_and_load(
        &self,
        at: &[Coordinate; 3],
        x: &[f64],
        sys: &System,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = x.len();
        let mut jac = vec![0.0; n * n];
        let mut load_jac = vec![0.0; 3 * n];
        let pose = self.pose(at, x);
        let p = self.geometry.stage_point_at(pose);
        let p0 = self.geometry.stage_point;
        // Columns of the stage's loaded coordinates; rows of their balance.
        let mut pose_col = [None; 3];
        let mut next = self.flexure_unknowns;
        for (c, coordinate) in at.iter().enumerate() {
            if !coordinate.is_prescribed() {
                pose_col[c] = Some(next);
                next += 1;
            }
        }
        let balance_row = pose_col;
        for (i, f) in self.geometry.frames.iter().enumerate() {
            let e = &sys.evals[i];
            let k = self.models[i].internal();
            let cols = 3 + k;
            let o = self.offsets[i];
            let u = &x[o..o + 3];
            let (_, dw) = self.own_wrench(i, x);
            // d(model output `row`) / d(own unknown `c`): the model's Jacobian chained with
            // the wrench parameters' (a coupler's tension and direction).
            let own = |row: usize, c: usize| -> f64 {
                let jr = &e.jacobian[row * cols..(row + 1) * cols];
                match c {
                    0 => jr[0] * dw[0] + jr[1] * dw[2],
                    1 => jr[0] * dw[1] + jr[1] * dw[3],
                    _ => jr[c],
                }
            };
            // Where the tip force acts, the force (global), and their derivatives with
            // respect to the stage pose, the coupler's direction and the force parameters.
            let stage_end = match f.joint {
                Joint::Link { to, .. } => to,
                _ => f.unloaded_tip(),
            };
            let rel = rotate([stage_end[0] - p0[0], stage_end[1] - p0[1]], pose[2]);
            let d_at_pose = [[1.0, 0.0], [0.0, 1.0], [-rel[1], rel[0]]];
            let (at, d_at_psi, force, d_force) = match f.joint {
                Joint::Clamped | Joint::Pinned => (
                    self.geometry.stage_map(pose, stage_end),
                    [0.0, 0.0],
                    f.force_to_global([u[0], u[1]]),
                    [f.force_to_global([1.0, 0.0]), f.force_to_global([0.0, 1.0])],
                ),
                Joint::Link { length, .. } => {
                    let (s, c) = u[1].sin_cos();
                    let end = self.geometry.stage_map(pose, stage_end);
                    (
                        [end[0] - length * c, end[1] - length * s],
                        [length * s, -length * c],
                        [u[0] * c, u[0] * s],
                        [[c, s], [-u[0] * s, u[0] * c]],
                    )
                }
            };
            // Joint rows: the tip minus where the stage wants it, in the flexure's frame.
            let local = |v: [f64; 2]| {
                let r = rotate(v, -f.angle);
                [r[0] / f.length, r[1] / f.length]
            };
            for (c, col) in pose_col.iter().enumerate() {
                if let Some(col) = *col {
                    let d = local(d_at_pose[c]);
                    jac[o * n + col] -= d[0];
                    jac[(o + 1) * n + col] -= d[1];
                }
            }
            if matches!(f.joint, Joint::Link { .. }) {
                let d = local(d_at_psi);
                jac[o * n + o + 1] -= d[0];
                jac[(o + 1) * n + o + 1] -= d[1];
            }
            let third = if f.joint == Joint::Clamped {
                if let Some(col) = pose_col[2] {
                    jac[(o + 2) * n + col] -= 1.0;
                }
                2
            } else {
                3
            };
            for c in 0..cols {
                jac[o * n + o + c] += own(0, c);
                jac[(o + 1) * n + o + c] += own(1, c);
                jac[(o + 2) * n + o + c] += own(third, c);
            }
            // The flexure's internal equations.
            for r in 0..k {
                for c in 0..cols {
                    jac[(o + 3 + r) * n + o + c] = own(4 + r, c);
                }
            }
            // The stage's balance: force components, and the moment about P of the force
            // at `at` plus the tip moment.
            let arm = [at[0] - p[0], at[1] - p[1]];
            for b in 0..3 {
                let at_row = |c: usize| b * n + c;
                for (j, df) in d_force.iter().enumerate() {
                    load_jac[at_row(o + j)] += match b {
                        0 => df[0],
                        1 => df[1],
                        _ => cross(arm, *df),
                    };
                }
                if b < 2 {
                    continue;
                }
                if matches!(f.joint, Joint::Link { .. }) {
                    load_jac[at_row(o + 1)] += cross(d_at_psi, force);
                }
                for (c, col) in pose_col.iter().enumerate() {
                    if let Some(col) = *col {
                        // P moves with the stage's translation; `at` with all of the pose.
                        let dp = [f64::from(c == 0), f64::from(c == 1)];
                        let d_arm = [d_at_pose[c][0] - dp[0], d_at_pose[c][1] - dp[1]];
                        load_jac[at_row(col)] += cross(d_arm, force);
                    }
                }
                let to_global = f.moment_to_global(1.0);
                for c in 0..cols {
                    load_jac[at_row(o + c)] += to_global * own(3, c);
                }
            }
        }
        // The balance rows of the loaded coordinates are their loads' rows.
        for (b, row) in balance_row.iter().enumerate() {
            if let Some(row) = *row {
                jac[row * n..(row + 1) * n].copy_from_slice(&load_jac[b * n..(b + 1) * n]);
            }
        }
        (jac, load_jac)
    }

    /// The residual `r` in units of its convergence limit (its largest row over that row's
    /// limit): it meets the tolerance at 1 or below.
    pub(super) fn residual_ratio(&self, r: &[f64], load: [f64; 3]) -> f64 {
        let scale = 1.0 + load.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let (inv_tol, inv_scaled) = (1.0 / self.tol, 1.0 / (self.tol * scale));
        let mut ratio = 0.0_f64;
        let mut row = 0;
        for (i, f) in self.geometry.frames.iter().enumerate() {
            // Position rows in units of L, then an angle or a moment, then internal
            // (moment) rows.
            let moment_row = if f.joint == Joint::Clamped { 3 } else { 2 };
            let rows = 3 + self.models[i].internal();
            for k in 0..rows {
                let inv = if k < moment_row { inv_tol } else { inv_scaled };
                ratio = ratio.max(r[row + k].abs() * inv);
            }
            row += rows;
        }
        let ratio = r[row..]
            .iter()
            .fold(ratio, |m, v| m.max(v.abs() * inv_scaled));
        // `max` passes over a NaN: a residual that is not a number meets no limit.
        if r.iter().any(|v| v.is_nan()) {
            f64::INFINITY
        } else {
            ratio
        }
    }
}

/// Flexure `i`'s (from 0) failure, numbered from 1.
fn flexure_error(i: usize, source: TipFailure) -> MechError {
    MechError::Flexure {
        flexure: i + 1,
        source,
    }
}

/// Scales every row, then every column, of a square matrix (row-major) to a largest entry of
/// 1, so that a pivot's size says how singular the matrix is, not in which units its
/// unknowns and equations are written (a flexure's axial compliance is `1e-9` of its
/// bending compliance at `L / t0 = 1e4`, and is no singularity). Positive scaling keeps the
/// determinant's sign.
impl<M: FlexureModel> MechSolver<M> {
    /// Whether the singular equilibrated Jacobian `jac` (row-major, `n` by `n`) of the
    /// unloaded pose has a self-stress for its null vector: a change of the flexures' forces
    /// alone (no stage coordinate, chain coordinate or coupler direction moves) that keeps
    /// every equation satisfied. Returns the flexures (from 1) that carry it, or `None` when
    /// the null vector moves something (a motion nothing resists, reported as immobile).
    pub(super) fn self_stress(&self, jac: &[f64], n: usize) -> Option<Vec<usize>> {
        let svd = nalgebra::DMatrix::from_row_slice(n, n, jac).svd(false, true);
        let v_t = svd.v_t?;
        let (k, _) = svd
            .singular_values
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))?;
        let v = v_t.row(k);
        let big = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        // The null vector of an exactly singular matrix is found to rounding; a component
        // this far below the largest is nought.
        let moves = |x: f64| x.abs() > 1e-8 * big;
        let mut flexures = Vec::new();
        for (j, &vj) in v.iter().enumerate() {
            let force = self
                .offsets
                .iter()
                .zip(&self.geometry.frames)
                .position(|(&o, f)| {
                    // A coupler's second unknown is its direction: a motion, not a force.
                    let direction = matches!(f.joint, Joint::Link { .. }) && j == o + 1;
                    (o..o + 3).contains(&j) && !direction
                });
            match force {
                Some(i) if moves(vj) && !flexures.contains(&(i + 1)) => flexures.push(i + 1),
                Some(_) => {}
                None if moves(vj) => return None,
                None => {}
            }
        }
        (flexures.len() > 1).then_some(flexures)
    }
}

pub(super) fn equilibrate(matrix: &mut [f64], n: usize) {
    for row in matrix.chunks_mut(n.max(1)) {
        let big = row.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if big > 0.0 {
            row.iter_mut().for_each(|v| *v /= big);
        }
    }
    for col in 0..n {
        let big = (0..n).fold(0.0_f64, |m, r| m.max(matrix[r * n + col].abs()));
        if big > 0.0 {
            (0..n).for_each(|r| matrix[r * n + col] /= big);
        }
    }
}

#[cfg(test)]
mod tests;
