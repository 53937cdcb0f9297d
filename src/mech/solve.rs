//! The mechanism's equations and their Newton continuation, for any flexure model (the exact
//! beam or a PRB chain). See the parent module for the formulation.

use crate::beam::{Load, TipPose};
use crate::linalg::lu_solve;
use crate::scene::{Coordinate, DrivePath, Mechanism};

use super::geometry::{cross, rotate, Geometry, Joint};
use super::{FlexureCase, MechCase, MechError, TipFailure};

/// A flexure whose state is given by three wrench parameters and, for a PRB chain, its
/// joint coordinates: the exact beam (root shot) or a PRB chain (joint coordinates and tip
/// wrench, the chain's equilibrium as extra equations).
pub trait FlexureModel {
    /// How many unknowns besides the three wrench parameters (the chain's joint
    /// coordinates; none for the beam), and as many equations.
    fn internal(&self) -> usize;
    /// The flexure at `(alpha_x, alpha_y, w)` (its own frame and units; `w` is the root
    /// moment of a beam, the tip moment of a chain) and internal unknowns `z`.
    fn eval(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure>;
    /// Whether the flexure is stable under its tip wrench as a *given* (dead) load.
    fn load_stable(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> bool;
}

/// A flexure model evaluated at its unknowns.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexEval {
    /// Its tip (own frame and units).
    pub tip: TipPose,
    /// The moment on its tip (own units).
    pub tip_moment: f64,
    /// The internal equations' residuals.
    pub internal: Vec<f64>,
    /// `d(a, b, phi, tip_moment, internal...) / d(alpha_x, alpha_y, w, z...)`, row-major,
    /// `4 + k` rows of `3 + k` (`k` = [`FlexureModel::internal`]).
    pub jacobian: Vec<f64>,
}

/// Newton iterations at one point of the path before the step is halved.
const MAX_NEWTON: u32 = 25;
/// The smallest continuation step before giving up.
const MIN_STEP: f64 = 1e-6;
/// An equilibrated Jacobian (see [`equilibrate`]) whose smallest pivot is this small next to
/// its largest is singular: a regular mechanism's pivots are within a few orders of
/// magnitude, an exactly singular one's at rounding (the beam's variational equations are
/// integrated to a relative 1e-7 at most).
const SINGULAR: f64 = 1e-5;
/// Continuation that stalls where the equilibrated Jacobian's pivot spread has fallen below
/// this fraction of the unloaded mechanism's has reached a limit point: the spread falls
/// like the distance to the fold, and Newton's basin at a fixed drive fraction with it (the
/// Su 3R parallel stage at `(Ax, Ay, B) = (-10, 6, 3)` stalls at 0.7% of its unloaded spread;
/// the solved points of that design grid, beam and PRB, stay above 13%).
const NEAR_CRITICAL: f64 = 0.02;
/// Rejected continuation sub-steps one case of a drive may have. A healthy case has none
/// or a few; a steep one more (the fixed-guided segment's last ninth of a 0.9 L stroke, where
/// the force climbs steeply, has 67); a path that keeps failing in steps near the smallest
/// (a sliver of progress, then rejected again: a steel flexure stretched along its axis, past
/// the root shot's force range) could otherwise crawl for minutes, so past this the path is
/// reported as not followed rather than left running.
const REJECTIONS_PER_CASE: u32 = 200;
/// No flexure tip moves by more than this (units of its `L`, radians) in one sub-step, so the
/// path cannot hop to another branch.
const MAX_TIP_STEP: f64 = 0.3;

/// The solver of one mechanism with one model per flexure.
#[derive(Debug, Clone)]
pub struct MechSolver<M> {
    geometry: Geometry,
    models: Vec<M>,
    tol: f64,
    /// Where each flexure's unknowns start in the unknown vector.
    offsets: Vec<usize>,
    /// Flexure unknowns in all (the stage's loaded coordinates follow).
    flexure_unknowns: usize,
    /// Newton iterations at one point before the step is halved.
    max_newton: u32,
    /// The smallest continuation step (a fraction of the drive) before giving up.
    min_step: f64,
}

/// Newton iterations per point for a fit's trial models: a healthy model needs three or
/// four from the secant predictor; one that needs more is about to fail anyway.
const TRIAL_NEWTON: u32 = 12;
/// The smallest continuation step of a fit's trial models: they give up on a drive once
/// they need steps below this fraction of it, so failing trials stay cheap (the
/// cantilever's trials stop at the same fraction).
const TRIAL_MIN_STEP: f64 = 1e-3;

/// One evaluation of the whole system at an unknown vector.
struct System {
    evals: Vec<FlexEval>,
    residual: Vec<f64>,
    /// The load the flexures put on the stage at `P` (flexure 1's units).
    load: [f64; 3],
}

/// A point of the path, with the flexures evaluated there.
struct Point {
    lambda: f64,
    x: Vec<f64>,
    evals: Vec<FlexEval>,
    /// The load the flexures put on the stage.
    load: [f64; 3],
}

impl Point {
    fn tip(&self, i: usize) -> TipPose {
        self.evals[i].tip
    }
}

/// What one Newton solve found.
struct Converged {
    point: Point,
    det_sign: f64,
    iterations: u32,
}

impl<M: FlexureModel> MechSolver<M> {
    /// A solver for `geometry` with one model per flexure; Newton stops at `tol` (units of
    /// each flexure's `L`, radians; loads relative to `1 + |load|`).
    pub fn new(geometry: Geometry, models: Vec<M>, tol: f64) -> MechSolver<M> {
        let mut at = 0;
        let offsets = models
            .iter()
            .map(|m| {
                let o = at;
                at += 3 + m.internal();
                o
            })
            .collect();
        MechSolver {
            geometry,
            models,
            tol,
            offsets,
            flexure_unknowns: at,
            max_newton: MAX_NEWTON,
            min_step: MIN_STEP,
        }
    }

    /// The same solver with a fit's trial limits: fewer Newton iterations per point and a
    /// larger smallest step, so a trial model that struggles fails fast (a fit's model that
    /// needs more is useless anyway; the fitted model is judged without these limits).
    pub fn for_trials(mut self) -> MechSolver<M> {
        self.max_newton = TRIAL_NEWTON;
        self.min_step = TRIAL_MIN_STEP;
        self
    }

    /// The geometry solved.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The unknowns of the unloaded mechanism (couplers along their unloaded direction).
    fn start(&self, drive: &[Coordinate; 3]) -> Vec<f64> {
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
    fn own_wrench(&self, i: usize, x: &[f64]) -> ([f64; 3], [f64; 4]) {
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
    fn pose(&self, at: &[Coordinate; 3], x: &[f64]) -> [f64; 3] {
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
    fn joints(
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

    /// Every flexure evaluated at `x`.
    fn evaluate(&self, x: &[f64]) -> Result<Vec<FlexEval>, MechError> {
        (0..self.models.len())
            .map(|i| {
                let (w, _) = self.own_wrench(i, x);
                let o = self.offsets[i] + 3;
                let z = &x[o..o + self.models[i].internal()];
                self.models[i].eval(w, z).map_err(|e| flexure_error(i, e))
            })
            .collect()
    }

    /// The flexures' outputs that the geometry's equations read: `[a, b, phi, tip_moment]`.
    fn outputs(evals: &[FlexEval]) -> Vec<[f64; 4]> {
        evals
            .iter()
            .map(|e| [e.tip.a, e.tip.b, e.tip.phi, e.tip_moment])
            .collect()
    }

    /// The whole system at `x`: flexures, residual (joint rows, internal rows, balance).
    fn system(&self, at: &[Coordinate; 3], x: &[f64]) -> Result<System, MechError> {
        let evals = self.evaluate(x)?;
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
    fn assemble_rows(&self, joint: &[f64], evals: &[FlexEval]) -> Vec<f64> {
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
    fn jacobian(&self, at: &[Coordinate; 3], x: &[f64], sys: &System) -> Vec<f64> {
        let n = x.len();
        let mut jac = vec![0.0; n * n];
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
            for (b, row) in balance_row.iter().enumerate() {
                let Some(row) = *row else { continue };
                let at_row = |c: usize| row * n + c;
                for (j, df) in d_force.iter().enumerate() {
                    jac[at_row(o + j)] += match b {
                        0 => df[0],
                        1 => df[1],
                        _ => cross(arm, *df),
                    };
                }
                if b < 2 {
                    continue;
                }
                if matches!(f.joint, Joint::Link { .. }) {
                    jac[at_row(o + 1)] += cross(d_at_psi, force);
                }
                for (c, col) in pose_col.iter().enumerate() {
                    if let Some(col) = *col {
                        // P moves with the stage's translation; `at` with all of the pose.
                        let dp = [f64::from(c == 0), f64::from(c == 1)];
                        let d_arm = [d_at_pose[c][0] - dp[0], d_at_pose[c][1] - dp[1]];
                        jac[at_row(col)] += cross(d_arm, force);
                    }
                }
                let to_global = f.moment_to_global(1.0);
                for c in 0..cols {
                    jac[at_row(o + c)] += to_global * own(3, c);
                }
            }
        }
        jac
    }

    /// Whether a residual meets the tolerance.
    fn converged(&self, r: &[f64], load: [f64; 3]) -> bool {
        let scale = 1.0 + load.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut row = 0;
        for (i, f) in self.geometry.frames.iter().enumerate() {
            // Position rows in units of L, then an angle or a moment, then internal
            // (moment) rows.
            let moment_row = if f.joint == Joint::Clamped { 3 } else { 2 };
            let rows = 3 + self.models[i].internal();
            for k in 0..rows {
                let limit = if k < moment_row {
                    self.tol
                } else {
                    self.tol * scale
                };
                if r[row + k].abs() > limit {
                    return false;
                }
            }
            row += rows;
        }
        r[row..].iter().all(|v| v.abs() <= self.tol * scale)
    }

    /// Newton at `lambda` from the guess `x`.
    fn newton(&self, path: &DrivePath, lambda: f64, mut x: Vec<f64>) -> Result<Converged, String> {
        let n = x.len();
        let at = path.at(lambda);
        let mut sys = self.system(&at, &x).map_err(|e| e.to_string())?;
        // The determinant's sign of the last Jacobian factored: at the last iterate but one,
        // within Newton's last (tiny) step of the solution, so a converged point needs no
        // Jacobian of its own.
        let mut det_sign = None;
        for iteration in 1..=self.max_newton {
            let converged = self.converged(&sys.residual, sys.load);
            if let (true, Some(det_sign)) = (converged, det_sign) {
                return Ok(Converged {
                    point: Point {
                        lambda,
                        x,
                        evals: sys.evals,
                        load: sys.load,
                    },
                    det_sign,
                    iterations: iteration,
                });
            }
            let mut jac = self.jacobian(&at, &x, &sys);
            let mut step: Vec<f64> = sys.residual.iter().map(|v| -v).collect();
            let lu = lu_solve(&mut jac, &mut step, n).ok_or("singular Jacobian")?;
            det_sign = Some(lu.det_sign);
            if converged {
                continue;
            }
            // Damped: halve the step while the residual grows.
            let norm0 = norm(&sys.residual);
            let mut t = 1.0;
            loop {
                let trial: Vec<f64> = x.iter().zip(&step).map(|(a, d)| a + t * d).collect();
                if let Ok(st) = self.system(&at, &trial) {
                    if norm(&st.residual) < norm0 || t < 0.1 {
                        (x, sys) = (trial, st);
                        break;
                    }
                }
                t *= 0.5;
                if t < 0.01 {
                    return Err("Newton's step does not reduce the residual".into());
                }
            }
        }
        Err(format!(
            "Newton did not converge in {} iterations",
            self.max_newton
        ))
    }

    /// Solves one proportional drive path (`drive` nondimensional: see
    /// `Mechanism::nondimensional`), returning the cases at `k / steps`. `index` names the
    /// drive in errors (from 1).
    pub fn solve_drive(
        &self,
        drive: &[Coordinate; 3],
        steps: u32,
        index: usize,
    ) -> Result<Vec<MechCase>, MechError> {
        self.solve_path(&DrivePath::proportional(*drive, steps), index)
    }

    /// Solves one drive path (proportional, or through a measured path's rows in order),
    /// returning the cases at `k / steps` (a measured path's rows). `index` names the drive
    /// in errors (from 1).
    pub fn solve_path(&self, path: &DrivePath, index: usize) -> Result<Vec<MechCase>, MechError> {
        let steps = path.steps.max(1);
        let x0 = self.start(&path.end);
        let n = x0.len();
        // The unloaded pose: its Jacobian's sign is the reference, and a singular one means
        // the drive asks for a motion nothing can make.
        let at0 = path.at(0.0);
        let sys0 = self.system(&at0, &x0)?;
        let mut jac = self.jacobian(&at0, &x0, &sys0);
        let mut rhs = vec![0.0; n];
        let immobile = |ratio: f64| MechError::Immobile {
            drive: index,
            detail: format!("its smallest pivot is {ratio:.1e} of its largest"),
        };
        equilibrate(&mut jac, n);
        let (sign0, ratio0) = match lu_solve(&mut jac, &mut rhs, n) {
            Some(lu) if lu.pivot_ratio > SINGULAR => (lu.det_sign, lu.pivot_ratio),
            other => return Err(immobile(other.map_or(0.0, |l| l.pivot_ratio))),
        };
        let mut prev = Point {
            lambda: 0.0,
            x: x0,
            evals: sys0.evals,
            load: sys0.load,
        };
        let mut prev2: Option<(f64, Vec<f64>)> = None;
        let mut out = Vec::with_capacity(steps as usize);
        let mut dlam = 1.0 / steps as f64;
        let mut rejected = false;
        for k in 1..=steps {
            let target = k as f64 / steps as f64;
            let mut iterations = 0;
            let mut rejections = 0u32;
            loop {
                if rejections > REJECTIONS_PER_CASE {
                    return Err(MechError::NoEquilibrium {
                        drive: index,
                        fraction: prev.lambda,
                        reason: format!(
                            "continuation rejected more than {REJECTIONS_PER_CASE} sub-steps \
                             of one case without reaching it"
                        ),
                    });
                }
                // Snap onto the case's fraction when within rounding of it, so the last case
                // reports the drive's own end values.
                let lambda = if prev.lambda + dlam >= target - 1e-12 {
                    target
                } else {
                    prev.lambda + dlam
                };
                let guess: Vec<f64> = match &prev2 {
                    Some((l2, x2)) => {
                        let t = (lambda - prev.lambda) / (prev.lambda - l2);
                        prev.x
                            .iter()
                            .zip(x2)
                            .map(|(a, b)| a + t * (a - b))
                            .collect()
                    }
                    None => prev.x.clone(),
                };
                let failure = match self.newton(path, lambda, guess) {
                    Ok(c) => {
                        iterations += c.iterations;
                        let jump = (0..self.models.len())
                            .fold(0.0_f64, |m, i| m.max(c.point.tip(i).max_diff(&prev.tip(i))));
                        if jump <= MAX_TIP_STEP {
                            if c.det_sign != sign0 {
                                return Err(MechError::Critical {
                                    drive: index,
                                    fraction: prev.lambda,
                                });
                            }
                            prev2 = Some((prev.lambda, std::mem::take(&mut prev.x)));
                            prev = c.point;
                            // Grow the step only after two successes in a row: right after a
                            // rejection the step that worked is kept, so a hard stretch is
                            // crossed at the step it allows instead of by doubling into a
                            // rejection at every other sub-step.
                            if !rejected {
                                dlam = (2.0 * dlam).min(1.0 / steps as f64);
                            }
                            rejected = false;
                            if lambda >= target {
                                out.push(self.case(path, &prev, iterations));
                                break;
                            }
                            continue;
                        }
                        "the equilibrium jumps away from the path".to_string()
                    }
                    Err(reason) => reason,
                };
                dlam *= 0.5;
                rejected = true;
                rejections += 1;
                if dlam < self.min_step {
                    // Stuck next to a nearly singular Jacobian: a limit point, where the
                    // path turns back and no equilibrium lies further along the drive.
                    if self.pivot_ratio(path, &prev) < NEAR_CRITICAL * ratio0 {
                        return Err(MechError::Critical {
                            drive: index,
                            fraction: prev.lambda,
                        });
                    }
                    return Err(MechError::NoEquilibrium {
                        drive: index,
                        fraction: prev.lambda,
                        reason: failure,
                    });
                }
            }
        }
        Ok(out)
    }

    /// Every drive path of `mechanism` (whose geometry this solver was built from): one
    /// `Vec` of cases per drive.
    pub fn solve_all(&self, mechanism: &Mechanism) -> Result<Vec<Vec<MechCase>>, MechError> {
        mechanism
            .drives
            .iter()
            .enumerate()
            .map(|(i, d)| self.solve_path(&mechanism.drive_path(d), i + 1))
            .collect()
    }

    /// The equilibrated Jacobian's smallest pivot over its largest at an accepted point (0
    /// if it cannot be evaluated).
    fn pivot_ratio(&self, path: &DrivePath, point: &Point) -> f64 {
        let n = point.x.len();
        let at = path.at(point.lambda);
        let Ok(sys) = self.system(&at, &point.x) else {
            return 0.0;
        };
        let mut jac = self.jacobian(&at, &point.x, &sys);
        equilibrate(&mut jac, n);
        let mut rhs = vec![0.0; n];
        lu_solve(&mut jac, &mut rhs, n).map_or(0.0, |lu| lu.pivot_ratio)
    }

    /// The reported case at an accepted point.
    fn case(&self, path: &DrivePath, point: &Point, iterations: u32) -> MechCase {
        let at = path.at(point.lambda);
        let mut stage_load = point.load;
        for (l, c) in stage_load.iter_mut().zip(&at) {
            if let Coordinate::Loaded(v) = c {
                *l = *v;
            }
        }
        let flexures = point
            .evals
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let (w, _) = self.own_wrench(i, &point.x);
                let o = self.offsets[i] + 3;
                let z = &point.x[o..o + self.models[i].internal()];
                FlexureCase {
                    tip: e.tip,
                    wrench: Load::new(w[0], w[1], e.tip_moment),
                    load_stable: self.models[i].load_stable(e, w, z),
                }
            })
            .collect();
        let joints = self
            .offsets
            .iter()
            .zip(&self.models)
            .map(|(&o, m)| point.x[o + 3..o + 3 + m.internal()].to_vec())
            .collect();
        MechCase {
            fraction: point.lambda,
            stage: self.pose(&at, &point.x),
            stage_load,
            flexures,
            iterations,
            joints,
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

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Scales every row, then every column, of a square matrix (row-major) to a largest entry of
/// 1, so that a pivot's size says how singular the matrix is, not in which units its
/// unknowns and equations are written (a flexure's axial compliance is `1e-9` of its
/// bending compliance at `L / t0 = 1e4`, and is no singularity). Positive scaling keeps the
/// determinant's sign.
fn equilibrate(matrix: &mut [f64], n: usize) {
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
    use crate::scene::{Attach, BeamSpec, EffectsChoice, Flexure, Mechanism};
    use Coordinate::{Loaded, Prescribed};

    /// Three flexures of different sizes, directions and attachments, every effect on.
    fn mixed() -> Mechanism {
        let beam = |length: f64, thickness: f64| BeamSpec {
            length,
            width: 0.01,
            thickness,
            youngs_modulus: 2e9,
            poisson_ratio: 0.45,
            shear_coefficient: None,
            effects: EffectsChoice::Fixed(Effects {
                shear: true,
                extension: true,
                poisson: true,
                plane_strain: false,
            }),
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
}
