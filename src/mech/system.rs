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
mod tests {
    use super::*;
    use crate::beam::{Effects, Resolution};
    use crate::mech::{exact, prb};
    use crate::prb::PrbMatrix;
    use crate::scene::{Attach, BeamSpec, DrivePath, EffectsChoice, Flexure, Mechanism};
    use Coordinate::{Loaded, Prescribed};

    /// Three flexures of different sizes, directions and attachments, every effect on.
    fn mixed() -> Mechanism {
        let effects = Effects {
            shear: true,
            extension: true,
            poisson: true,
            plane_strain: false,
        };
        let beam = |length: f64, thickness: f64| BeamSpec {
            length,
            width: 0.01,
            thickness,
            youngs_modulus: 2e9,
            poisson_ratio: 0.45,
            shear_coefficient: None,
            density: None,
            effects: EffectsChoice::Fixed(effects),
            allowable_stress: None,
        };
        let flexure = |root: [f64; 2], deg: f64, attach, b| Flexure {
            root,
            angle: f64::to_radians(deg),
            attach,
            beam: b,
        };
        Mechanism {
            flexures: vec![
                flexure([0.0, 0.03], 0.0, Attach::Clamped, beam(0.1, 0.01)),
                flexure([0.0, -0.03], 10.0, Attach::Pinned, beam(0.12, 0.008)),
                flexure(
                    [0.12, 0.1],
                    -80.0,
                    Attach::Link { to: [0.09, 0.0] },
                    beam(0.08, 0.01),
                ),
            ],
            stage_point: [0.1, 0.03],
            drives: Vec::new(),
        }
    }

    /// The analytic Jacobian against central differences of the whole residual at a point
    /// away from equilibrium. Differences with h = 1e-6 err by O(h^2) relative to the
    /// residual's curvature plus the shots' tolerance 1e-12 / h = 1e-6; the beam's
    /// sensitivities are integrated to a relative 1e-7. So 1e-4 relative to the column.
    fn check<M: FlexureModel>(s: &MechSolver<M>, drive: &[Coordinate; 3]) {
        let x0 = s.start(drive);
        let x: Vec<f64> = x0
            .iter()
            .enumerate()
            .map(|(j, v)| v + 0.05 * ((j as f64 * 1.7).sin() + 0.3))
            .collect();
        let n = x.len();
        let at = DrivePath::proportional(*drive, 1).at(0.6);
        let sys = s.system(&at, &x).unwrap();
        let jac = s.jacobian(&at, &x, &sys);
        for col in 0..n {
            let h = 1e-6;
            let mut xp = x.clone();
            let mut xm = x.clone();
            xp[col] += h;
            xm[col] -= h;
            let rp = s.system(&at, &xp).unwrap().residual;
            let rm = s.system(&at, &xm).unwrap().residual;
            let scale = (0..n).fold(1.0_f64, |m, r| m.max(jac[r * n + col].abs()));
            for row in 0..n {
                let fd = (rp[row] - rm[row]) / (2.0 * h);
                let an = jac[row * n + col];
                assert!(
                    (fd - an).abs() <= 1e-4 * scale,
                    "row {row} col {col}: analytic {an}, differences {fd}"
                );
            }
        }
    }

    #[test]
    fn analytic_jacobian_matches_differences() {
        let m = mixed();
        let drives = [
            [Loaded(0.3), Loaded(-1.0), Loaded(0.2)],
            [Prescribed(0.01), Loaded(2.0), Prescribed(0.05)],
        ];
        let beam = exact::solver(&m, Resolution::with_tol(1e-12)).unwrap();
        let su =
            PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,40; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
        let chain = prb::solver(&m, &su, 1e-10);
        for d in &drives {
            check(&beam, d);
            check(&chain, d);
        }
    }

    /// Evaluations of a model, counted: full ones and checks by values.
    #[derive(Default)]
    struct Counts {
        full: std::cell::Cell<u32>,
        by_values: std::cell::Cell<u32>,
    }

    /// The exact beam, counting its evaluations; `checks` false: evaluated in full at every
    /// Newton iterate (the trait's default, no check by values).
    struct Counted<'a> {
        beam: exact::BeamFlexure,
        checks: bool,
        /// Whether it asks for closely predicted cases, as the beam does.
        predicted: bool,
        counts: &'a Counts,
    }

    impl FlexureModel for Counted<'_> {
        fn internal(&self) -> usize {
            0
        }
        fn eval(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
            self.counts.full.set(self.counts.full.get() + 1);
            self.beam.eval(w, z)
        }
        fn predicted(&self) -> bool {
            self.predicted
        }
        fn eval_shaped(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
            self.counts.full.set(self.counts.full.get() + 1);
            self.beam.eval_shaped(w, z)
        }
        fn eval_values(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
            if !self.checks {
                return self.eval(w, z);
            }
            self.counts.by_values.set(self.counts.by_values.get() + 1);
            let e = self.beam.eval_values(w, z)?;
            assert!(
                e.jacobian.is_empty(),
                "the beam's check leaves its Jacobian out"
            );
            Ok(e)
        }
        fn load_stable(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> bool {
            self.beam.load_stable(eval, w, z)
        }
        fn stability_indicator(&self, eval: &FlexEval) -> Option<f64> {
            self.beam.stability_indicator(eval)
        }
        fn stress(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> Option<crate::beam::Stress> {
            self.beam.stress(eval, w, z)
        }
    }

    /// Newton's last iterate checked by values alone (the beam's shot without its
    /// variational equations) gives the cases that full evaluations give: the same Newton
    /// iterations, the same stability, and poses, wrenches and stresses that differ at most
    /// by the shots' integration error (the two shots may step differently where the
    /// sensitivities limit the step; at tol 1e-10 both are good to about 1e-10, so 1e-8 of
    /// each figure is a hundred times that). On three flexures with every effect on
    /// (Dormand-Prince shots), and on a parallel stage of elastica flexures (Taylor shots),
    /// pushed sideways, then with its upper flexure compressed past its buckling load as a
    /// dead load (not load-stable: the stability test reads the Jacobian the check carries
    /// over). Most cases end on a check, which spares each flexure a full evaluation. (Both
    /// follow the drives by the secant and Newton's step, as a PRB chain does: the beam's own
    /// cubic prediction is the next test's.)
    #[test]
    fn a_check_by_values_gives_the_full_evaluations_cases() {
        let clamped = |root: [f64; 2]| Flexure {
            root,
            angle: 0.0,
            attach: Attach::Clamped,
            beam: BeamSpec::unit_elastica(0.01),
        };
        let stage = Mechanism {
            flexures: vec![clamped([0.0, 0.3]), clamped([0.0, -0.3])],
            stage_point: [1.0, 0.0],
            drives: Vec::new(),
        };
        let everything = [Loaded(0.3), Loaded(-1.0), Loaded(0.2)];
        let prescribed = [Prescribed(0.01), Loaded(2.0), Prescribed(0.05)];
        let scenes = [
            (mixed(), vec![everything, prescribed]),
            (
                stage,
                vec![
                    [Loaded(0.0), Loaded(2.0), Loaded(0.0)],
                    [Loaded(-0.941), Loaded(1.878), Loaded(0.299)],
                ],
            ),
        ];
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-8 * (1.0 + a.abs()),
                "{what}: {a} vs {b}"
            );
        };
        let mut unstable = 0;
        for (m, drives) in &scenes {
            let exact = exact::solver(m, Resolution::with_tol(1e-10)).unwrap();
            let (fast_counts, full_counts) = (Counts::default(), Counts::default());
            let with = |checks, counts| {
                let models = exact.models.iter().map(|&beam| Counted {
                    beam,
                    checks,
                    predicted: false,
                    counts,
                });
                MechSolver::new(exact.geometry.clone(), models.collect(), exact.tol)
            };
            let (fast, full) = (with(true, &fast_counts), with(false, &full_counts));
            for d in drives {
                let a = fast.solve_drive(d, 12, 1).unwrap();
                let b = full.solve_drive(d, 12, 1).unwrap();
                assert_eq!(a.len(), b.len());
                for (ca, cb) in a.iter().zip(&b) {
                    assert_eq!(ca.iterations, cb.iterations);
                    for k in 0..3 {
                        close(ca.stage[k], cb.stage[k], "stage");
                        close(ca.stage_load[k], cb.stage_load[k], "stage load");
                    }
                    for (fa, fb) in ca.flexures.iter().zip(&cb.flexures) {
                        assert_eq!(fa.load_stable, fb.load_stable);
                        unstable += usize::from(!fa.load_stable);
                        close(fa.tip.a, fb.tip.a, "tip a");
                        close(fa.tip.b, fb.tip.b, "tip b");
                        close(fa.tip.phi, fb.tip.phi, "tip phi");
                        close(fa.wrench.alpha_x, fb.wrench.alpha_x, "alpha x");
                        close(fa.wrench.alpha_y, fb.wrench.alpha_y, "alpha y");
                        close(fa.wrench.beta, fb.wrench.beta, "tip moment");
                        let (sa, sb) = (fa.stress.unwrap(), fb.stress.unwrap());
                        close(sa.max, sb.max, "stress");
                    }
                }
            }
            // A case that ends on a check spares each flexure a full evaluation: at least
            // half of them do.
            let (checked, fast_full) = (fast_counts.by_values.get(), fast_counts.full.get());
            let slow_full = full_counts.full.get();
            let evaluations = (drives.len() * 12 * m.flexures.len()) as u32;
            assert!(
                checked > 0 && fast_full + evaluations / 2 <= slow_full,
                "{checked} checks and {fast_full} full evaluations against {slow_full}"
            );
        }
        assert!(unstable > 0, "the compressed flexure is not load-stable");
    }

    /// A drive that carries factored Jacobians from case to case (`path.rs`, `Chord`: a
    /// case checked by values alone takes its determinant's sign and its flexures' stability
    /// from an earlier case's Jacobian) reports every case's stability as a drive that
    /// evaluates every case in full: the parallel stage of elastica flexures pushed until its
    /// upper flexure is compressed past its buckling load as a dead load, in 240 cases, so
    /// that the indicator crosses zero between references. Poses and wrenches agree to the
    /// tolerance (1e-10 here, so 1e-8 of `1 + |output|` is a hundred times it: the two follow
    /// the drive by different predictors and stop at different residuals).
    #[test]
    fn a_chord_keeps_every_case_s_stability() {
        let clamped = |root: [f64; 2]| Flexure {
            root,
            angle: 0.0,
            attach: Attach::Clamped,
            beam: BeamSpec::unit_elastica(0.01),
        };
        let stage = Mechanism {
            flexures: vec![clamped([0.0, 0.3]), clamped([0.0, -0.3])],
            stage_point: [1.0, 0.0],
            drives: Vec::new(),
        };
        let exact = exact::solver(&stage, Resolution::with_tol(1e-10)).unwrap();
        let (chorded_counts, full_counts) = (Counts::default(), Counts::default());
        let with = |predicted, counts| {
            let models = exact.models.iter().map(|&beam| Counted {
                beam,
                checks: true,
                predicted,
                counts,
            });
            MechSolver::new(exact.geometry.clone(), models.collect(), exact.tol)
        };
        let (chorded, full) = (with(true, &chorded_counts), with(false, &full_counts));
        let drive = [Loaded(-0.941), Loaded(1.878), Loaded(0.299)];
        let steps = 240;
        let a = chorded.solve_drive(&drive, steps, 1).unwrap();
        let b = full.solve_drive(&drive, steps, 1).unwrap();
        assert_eq!(a.len(), b.len());
        let (mut flips, mut last) = (0, None);
        for (ca, cb) in a.iter().zip(&b) {
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-8 * (1.0 + y.abs());
            for k in 0..3 {
                assert!(close(ca.stage[k], cb.stage[k]), "{ca:?} against {cb:?}");
            }
            let flags: Vec<bool> = ca.flexures.iter().map(|f| f.load_stable).collect();
            for (fa, fb) in ca.flexures.iter().zip(&cb.flexures) {
                assert_eq!(fa.load_stable, fb.load_stable, "at {}", ca.fraction);
                assert!(close(fa.wrench.alpha_y, fb.wrench.alpha_y));
                assert!(close(fa.wrench.beta, fb.wrench.beta));
            }
            flips += usize::from(last.is_some_and(|l| l != flags));
            last = Some(flags);
        }
        assert_eq!(flips, 1, "the upper flexure becomes unstable once");
        // Most cases were checked by values alone, with a Jacobian carried over.
        let (checks, fulls) = (chorded_counts.by_values.get(), chorded_counts.full.get());
        assert!(
            checks >= 2 * steps * 3 / 4 && fulls < checks / 4,
            "{checks} checks and {fulls} full evaluations for {steps} cases of two flexures"
        );
    }

    /// On a drive of many cases the continuation's prediction is the case: the shipped
    /// parallel stage (slenderness 100, every effect on) pushed sideways, alone and with a pull
    /// along its flexures, 500 cases each at tol 1e-9. Each flexure takes about one
    /// evaluation a case, by values alone (the cubic's prediction checked, with the Jacobian
    /// of an earlier case: `path.rs`, `Chord`), and a full one in a few percent of them (the
    /// start and the first cases of a drive, before the cubic has four points, take Newton
    /// steps and checks; a new reference every few cases), where Newton's step and its check
    /// took one full evaluation and one check a case; and every stage pose, tip and wrench is
    /// within the tolerance (relative to `1 + |output|`) of a solve at tol 1e-12: the solves
    /// before this measured at most 5.8e-10 on the same drives, as does this one.
    #[test]
    fn a_drive_of_many_cases_costs_about_one_evaluation_a_case() {
        let beam = BeamSpec {
            length: 0.05,
            width: 0.01,
            thickness: 0.0005,
            youngs_modulus: 200e9,
            poisson_ratio: 0.3,
            shear_coefficient: None,
            density: None,
            effects: EffectsChoice::Fixed(Effects::ALL),
            allowable_stress: None,
        };
        let clamped = |y: f64| Flexure {
            root: [0.0, y],
            angle: 0.0,
            attach: Attach::Clamped,
            beam,
        };
        let stage = Mechanism {
            flexures: vec![clamped(0.015), clamped(-0.015)],
            stage_point: [0.05, 0.0],
            drives: Vec::new(),
        };
        let exact = exact::solver(&stage, Resolution::with_tol(1e-9)).unwrap();
        let reference = exact::solver(&stage, Resolution::with_tol(1e-12)).unwrap();
        let counts = Counts::default();
        let models = exact.models.iter().map(|&beam| Counted {
            beam,
            checks: true,
            predicted: true,
            counts: &counts,
        });
        let counted = MechSolver::new(exact.geometry.clone(), models.collect(), exact.tol);
        let steps = 500;
        let drives = [
            [Loaded(0.0), Loaded(2.4), Loaded(0.0)],
            [Loaded(1.2), Loaded(2.4), Loaded(0.0)],
        ];
        // Each output's difference relative to `1 + |output|`, the scale of Newton's
        // residuals.
        let (mut worst, mut stress) = (0.0_f64, 0.0_f64);
        let mut differ = |a: f64, b: f64| worst = worst.max((a - b).abs() / (1.0 + b.abs()));
        for d in &drives {
            let got = counted.solve_drive(d, steps, 1).unwrap();
            let want = reference.solve_drive(d, steps, 1).unwrap();
            assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                for k in 0..3 {
                    differ(g.stage[k], w.stage[k]);
                }
                for (fg, fw) in g.flexures.iter().zip(&w.flexures) {
                    assert_eq!(fg.load_stable, fw.load_stable);
                    differ(fg.tip.a, fw.tip.a);
                    differ(fg.tip.b, fw.tip.b);
                    differ(fg.tip.phi, fw.tip.phi);
                    differ(fg.wrench.alpha_x, fw.wrench.alpha_x);
                    differ(fg.wrench.alpha_y, fw.wrench.alpha_y);
                    differ(fg.wrench.beta, fw.wrench.beta);
                    // The stress is the curvature, a derivative of the shape the shots
                    // integrate to the tolerance: within ten times it (8.4e-10 measured on
                    // the 1000-case stage, before this and after).
                    let (sg, sw) = (fg.stress.unwrap().max, fw.stress.unwrap().max);
                    stress = stress.max((sg - sw).abs() / sw.abs());
                }
            }
        }
        assert!(worst <= 1e-9, "{worst:e} from the solve at tol 1e-12");
        assert!(
            stress <= 1e-8,
            "stresses {stress:e} from the solve at tol 1e-12"
        );
        // Per flexure: every case's evaluations, the drives' starts included.
        let cases = drives.len() as u32 * steps;
        let (full, checks) = (counts.full.get() / 2, counts.by_values.get() / 2);
        // Measured: 30 full evaluations and 984 checks for the 1000 cases.
        assert!(
            full + checks <= cases + cases / 20 && full <= cases / 20,
            "{full} full evaluations and {checks} checks a flexure for {cases} cases"
        );
    }
}
