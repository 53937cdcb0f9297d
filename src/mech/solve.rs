//! The mechanism's equations and their Newton continuation, for any tip model (the exact
//! beam or a PRB chain). See the parent module for the formulation.

use crate::beam::{Load, TipPose};
use crate::linalg::lu_solve;
use crate::scene::Coordinate;

use super::geometry::{cross, Geometry, Joint};
use super::{FlexureCase, MechCase, MechError, TipFailure};

/// A flexure's tip under a wrench: the exact beam or a PRB chain.
pub trait TipModel {
    /// A converged state a nearby wrench can start from.
    type Warm: Clone;
    /// The unloaded flexure.
    fn unloaded(&self) -> Self::Warm;
    /// The tip under `wrench` (own frame and units), started from `from`.
    fn solve(&self, wrench: Load, from: &Self::Warm) -> Result<Self::Warm, TipFailure>;
    /// The tip of a state.
    fn tip(&self, state: &Self::Warm) -> TipPose;
    /// The sign of the flexure's stability under its wrench as a *given* load (+1 stable):
    /// it flips where the tip's compliance passes through a pole (a limit point of the
    /// load-controlled flexure, harmless to the mechanism), and so does the sign of the
    /// mechanism's Jacobian with it.
    fn load_stability(&self, state: &Self::Warm) -> f64;
}

/// Newton iterations at one point of the path before the step is halved.
const MAX_NEWTON: u32 = 25;
/// Relative finite-difference step of the Jacobian.
const FD_STEP: f64 = 1e-6;
/// The smallest continuation step before giving up.
const MIN_STEP: f64 = 1e-6;
/// An equilibrated Jacobian (see [`equilibrate`]) whose smallest pivot is this small next to
/// its largest is singular: the finite differences' truncation error leaves about 1e-8 of an
/// exactly singular one, a regular mechanism's pivots are within a few orders of magnitude.
const SINGULAR: f64 = 1e-6;
/// No flexure tip moves by more than this (units of its `L`, radians) in one sub-step, so the
/// path cannot hop to another branch.
const MAX_TIP_STEP: f64 = 0.3;

/// The solver of one mechanism with one tip model per flexure.
#[derive(Debug, Clone)]
pub struct MechSolver<M> {
    geometry: Geometry,
    models: Vec<M>,
    tol: f64,
}

/// Unknown counts per flexure.
fn unknowns_of(joint: Joint) -> usize {
    match joint {
        Joint::Clamped => 3,
        Joint::Pinned | Joint::Link { .. } => 2,
    }
}

/// A point of the path: the unknowns and every flexure's state there.
#[derive(Clone)]
struct Point<W> {
    lambda: f64,
    x: Vec<f64>,
    states: Vec<W>,
}

/// What one Newton solve found.
struct Converged<W> {
    point: Point<W>,
    det_sign: f64,
    iterations: u32,
}

impl<M: TipModel> MechSolver<M> {
    /// A solver for `geometry` with one tip model per flexure; Newton stops at `tol` (units
    /// of each flexure's `L`, radians).
    pub fn new(geometry: Geometry, models: Vec<M>, tol: f64) -> MechSolver<M> {
        MechSolver {
            geometry,
            models,
            tol,
        }
    }

    /// The geometry solved.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    fn offsets(&self) -> Vec<usize> {
        let mut at = 0;
        self.geometry
            .frames
            .iter()
            .map(|f| {
                let o = at;
                at += unknowns_of(f.joint);
                o
            })
            .collect()
    }

    fn flexure_unknowns(&self) -> usize {
        self.geometry
            .frames
            .iter()
            .map(|f| unknowns_of(f.joint))
            .sum()
    }

    /// The unknowns of the unloaded mechanism (couplers along their unloaded direction).
    fn start(&self, drive: &[Coordinate; 3]) -> Vec<f64> {
        let mut x = Vec::new();
        for f in &self.geometry.frames {
            match f.joint {
                Joint::Clamped => x.extend([0.0; 3]),
                Joint::Pinned => x.extend([0.0; 2]),
                Joint::Link { to, .. } => {
                    let tip = f.unloaded_tip();
                    x.extend([0.0, (to[1] - tip[1]).atan2(to[0] - tip[0])]);
                }
            }
        }
        x.extend(drive.iter().filter(|c| !c.is_prescribed()).map(|_| 0.0));
        x
    }

    /// Flexure `i`'s wrench (own frame and units) from its unknowns `u`.
    fn wrench(&self, i: usize, u: &[f64]) -> Load {
        let f = &self.geometry.frames[i];
        match f.joint {
            Joint::Clamped => Load::new(u[0], u[1], u[2]),
            Joint::Pinned => Load::new(u[0], u[1], 0.0),
            Joint::Link { .. } => {
                let (s, c) = u[1].sin_cos();
                let local = f.force_to_local([u[0] * c, u[0] * s]);
                Load::new(local[0], local[1], 0.0)
            }
        }
    }

    /// The stage pose at `lambda` for unknowns `x`.
    fn pose(&self, drive: &[Coordinate; 3], lambda: f64, x: &[f64]) -> [f64; 3] {
        let mut k = self.flexure_unknowns();
        let mut pose = [0.0; 3];
        for (p, c) in pose.iter_mut().zip(drive) {
            *p = match c {
                Coordinate::Prescribed(v) => lambda * v,
                Coordinate::Loaded(_) => {
                    k += 1;
                    x[k - 1]
                }
            };
        }
        pose
    }

    /// The residual of the mechanism's equations and the load the flexures put on the stage
    /// (`[alpha_x, alpha_y, beta]` at `P`, flexure 1's units).
    fn residual(
        &self,
        drive: &[Coordinate; 3],
        lambda: f64,
        x: &[f64],
        tips: &[TipPose],
        out: &mut Vec<f64>,
    ) -> [f64; 3] {
        out.clear();
        let pose = self.pose(drive, lambda, x);
        let p = self.geometry.stage_point_at(pose);
        let mut sum = [0.0; 3];
        let mut k = 0;
        for (f, tip) in self.geometry.frames.iter().zip(tips) {
            let u = &x[k..k + unknowns_of(f.joint)];
            k += u.len();
            let (at, force, moment) = match f.joint {
                Joint::Clamped | Joint::Pinned => {
                    let at = self.geometry.stage_map(pose, f.unloaded_tip());
                    let want = f.to_local(at);
                    out.extend([tip.a - want[0], tip.b - want[1]]);
                    let moment = if f.joint == Joint::Clamped {
                        out.push(tip.phi - pose[2]);
                        f.moment_to_global(u[2])
                    } else {
                        0.0
                    };
                    (at, f.force_to_global([u[0], u[1]]), moment)
                }
                Joint::Link { to, length } => {
                    let (s, c) = u[1].sin_cos();
                    let end = self.geometry.stage_map(pose, to);
                    let at = [end[0] - length * c, end[1] - length * s];
                    let want = f.to_local(at);
                    out.extend([tip.a - want[0], tip.b - want[1]]);
                    (at, [u[0] * c, u[0] * s], 0.0)
                }
            };
            sum[0] += force[0];
            sum[1] += force[1];
            sum[2] += cross([at[0] - p[0], at[1] - p[1]], force) + moment;
        }
        for (c, s) in drive.iter().zip(sum) {
            if let Coordinate::Loaded(v) = c {
                out.push(s - lambda * v);
            }
        }
        sum
    }

    /// Whether a residual meets the tolerance.
    fn converged(&self, r: &[f64], tip_rows: usize, load: [f64; 3]) -> bool {
        let scale = 1.0 + load.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        r[..tip_rows].iter().all(|v| v.abs() <= self.tol)
            && r[tip_rows..].iter().all(|v| v.abs() <= self.tol * scale)
    }

    fn tips(&self, states: &[M::Warm]) -> Vec<TipPose> {
        self.models
            .iter()
            .zip(states)
            .map(|(m, s)| m.tip(s))
            .collect()
    }

    /// Every flexure solved at the wrenches of `x`, from `from`.
    fn solve_flexures(&self, x: &[f64], from: &[M::Warm]) -> Result<Vec<M::Warm>, MechError> {
        let offsets = self.offsets();
        let mut out = Vec::with_capacity(from.len());
        for (i, (m, w)) in self.models.iter().zip(from).enumerate() {
            let n = unknowns_of(self.geometry.frames[i].joint);
            let u = &x[offsets[i]..offsets[i] + n];
            out.push(
                m.solve(self.wrench(i, u), w)
                    .map_err(|e| flexure_error(i, e))?,
            );
        }
        Ok(out)
    }

    /// The finite-difference Jacobian (row-major) at `x`, whose flexures are in `states`.
    fn jacobian(
        &self,
        drive: &[Coordinate; 3],
        lambda: f64,
        x: &[f64],
        states: &[M::Warm],
        r0: &[f64],
    ) -> Result<Vec<f64>, MechError> {
        let n = x.len();
        let offsets = self.offsets();
        let mut tips = self.tips(states);
        let mut jac = vec![0.0; n * n];
        let mut xp = x.to_vec();
        let mut r = Vec::with_capacity(n);
        for j in 0..n {
            let h = FD_STEP * (1.0 + x[j].abs());
            xp[j] = x[j] + h;
            // Which flexure owns unknown j, if any.
            let owner = offsets
                .iter()
                .enumerate()
                .rev()
                .find(|(i, &o)| j >= o && j < o + unknowns_of(self.geometry.frames[*i].joint))
                .map(|(i, _)| i);
            if let Some(i) = owner {
                let nu = unknowns_of(self.geometry.frames[i].joint);
                let u = &xp[offsets[i]..offsets[i] + nu];
                let s = self.models[i]
                    .solve(self.wrench(i, u), &states[i])
                    .map_err(|e| flexure_error(i, e))?;
                tips[i] = self.models[i].tip(&s);
            }
            self.residual(drive, lambda, &xp, &tips, &mut r);
            for row in 0..n {
                jac[row * n + j] = (r[row] - r0[row]) / h;
            }
            if let Some(i) = owner {
                tips[i] = self.models[i].tip(&states[i]);
            }
            xp[j] = x[j];
        }
        Ok(jac)
    }

    /// Newton at `lambda` from the guess `x` with the flexures started from `states`.
    fn newton(
        &self,
        drive: &[Coordinate; 3],
        lambda: f64,
        mut x: Vec<f64>,
        states: &[M::Warm],
    ) -> Result<Converged<M::Warm>, String> {
        let n = x.len();
        let tip_rows = self.flexure_unknowns();
        let mut states = self.solve_flexures(&x, states).map_err(|e| e.to_string())?;
        let mut r = Vec::with_capacity(n);
        let mut load = self.residual(drive, lambda, &x, &self.tips(&states), &mut r);
        for iteration in 1..=MAX_NEWTON {
            let mut jac = self
                .jacobian(drive, lambda, &x, &states, &r)
                .map_err(|e| e.to_string())?;
            let mut step: Vec<f64> = r.iter().map(|v| -v).collect();
            let lu = lu_solve(&mut jac, &mut step, n).ok_or("singular Jacobian")?;
            if self.converged(&r, tip_rows, load) {
                let flexure_signs: f64 = self
                    .models
                    .iter()
                    .zip(&states)
                    .map(|(m, s)| m.load_stability(s))
                    .product();
                return Ok(Converged {
                    point: Point { lambda, x, states },
                    det_sign: lu.det_sign * flexure_signs,
                    iterations: iteration,
                });
            }
            // Damped: halve the step while the residual grows.
            let norm0 = norm(&r);
            let mut t = 1.0;
            loop {
                let trial: Vec<f64> = x.iter().zip(&step).map(|(a, d)| a + t * d).collect();
                let mut rt = Vec::with_capacity(n);
                let accepted = match self.solve_flexures(&trial, &states) {
                    Ok(st) => {
                        let lt = self.residual(drive, lambda, &trial, &self.tips(&st), &mut rt);
                        if norm(&rt) < norm0 || t < 0.1 {
                            Some((st, lt))
                        } else {
                            None
                        }
                    }
                    Err(_) => None,
                };
                if let Some((st, lt)) = accepted {
                    (x, states, load, r) = (trial, st, lt, rt);
                    break;
                }
                t *= 0.5;
                if t < 0.01 {
                    return Err("Newton's step does not reduce the residual".into());
                }
            }
        }
        Err(format!(
            "Newton did not converge in {MAX_NEWTON} iterations"
        ))
    }

    /// Solves one drive path (`drive` nondimensional: see
    /// `Mechanism::nondimensional`), returning the cases at `k / steps`. `index` names the
    /// drive in errors (from 1).
    pub fn solve_drive(
        &self,
        drive: &[Coordinate; 3],
        steps: u32,
        index: usize,
    ) -> Result<Vec<MechCase>, MechError> {
        let steps = steps.max(1);
        let x0 = self.start(drive);
        let states0: Vec<M::Warm> = self.models.iter().map(|m| m.unloaded()).collect();
        let n = x0.len();
        // The unloaded pose: its Jacobian's sign is the reference, and a singular one means
        // the drive asks for a motion nothing can make.
        let tips0 = self.tips(&states0);
        let mut r0 = Vec::with_capacity(n);
        self.residual(drive, 0.0, &x0, &tips0, &mut r0);
        let mut jac = self.jacobian(drive, 0.0, &x0, &states0, &r0)?;
        let mut rhs = vec![0.0; n];
        let immobile = |ratio: f64| MechError::Immobile {
            drive: index,
            detail: format!("its smallest pivot is {ratio:.1e} of its largest"),
        };
        equilibrate(&mut jac, n);
        let sign0 = match lu_solve(&mut jac, &mut rhs, n) {
            Some(lu) if lu.pivot_ratio > SINGULAR => lu.det_sign,
            other => return Err(immobile(other.map_or(0.0, |l| l.pivot_ratio))),
        };
        let mut prev = Point {
            lambda: 0.0,
            x: x0,
            states: states0,
        };
        let mut prev2: Option<(f64, Vec<f64>)> = None;
        let mut out = Vec::with_capacity(steps as usize);
        let mut dlam = 1.0 / steps as f64;
        for k in 1..=steps {
            let target = k as f64 / steps as f64;
            let mut iterations = 0;
            loop {
                let lambda = (prev.lambda + dlam).min(target);
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
                let failure = match self.newton(drive, lambda, guess, &prev.states) {
                    Ok(c) => {
                        iterations += c.iterations;
                        let jump = self
                            .tips(&c.point.states)
                            .iter()
                            .zip(self.tips(&prev.states))
                            .fold(0.0_f64, |m, (a, b)| m.max(a.max_diff(&b)));
                        if c.det_sign != sign0 {
                            return Err(MechError::Critical {
                                drive: index,
                                fraction: prev.lambda,
                            });
                        }
                        if jump <= MAX_TIP_STEP {
                            prev2 = Some((prev.lambda, std::mem::take(&mut prev.x)));
                            prev = c.point;
                            dlam = (2.0 * dlam).min(1.0 / steps as f64);
                            if lambda >= target {
                                out.push(self.case(drive, &prev, iterations));
                                break;
                            }
                            continue;
                        }
                        "the equilibrium jumps away from the path".to_string()
                    }
                    Err(reason) => reason,
                };
                dlam *= 0.5;
                if dlam < MIN_STEP {
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

    /// The reported case at an accepted point.
    fn case(&self, drive: &[Coordinate; 3], point: &Point<M::Warm>, iterations: u32) -> MechCase {
        let tips = self.tips(&point.states);
        let mut r = Vec::new();
        let sum = self.residual(drive, point.lambda, &point.x, &tips, &mut r);
        let mut stage_load = sum;
        for (l, c) in stage_load.iter_mut().zip(drive) {
            if let Coordinate::Loaded(v) = c {
                *l = point.lambda * v;
            }
        }
        let offsets = self.offsets();
        let flexures = tips
            .iter()
            .enumerate()
            .map(|(i, tip)| {
                let n = unknowns_of(self.geometry.frames[i].joint);
                FlexureCase {
                    tip: *tip,
                    wrench: self.wrench(i, &point.x[offsets[i]..offsets[i] + n]),
                    load_stable: self.models[i].load_stability(&point.states[i]) > 0.0,
                }
            })
            .collect();
        MechCase {
            fraction: point.lambda,
            stage: self.pose(drive, point.lambda, &point.x),
            stage_load,
            flexures,
            iterations,
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

/// The sign of a square matrix's determinant (row-major, destroyed; `rhs` is scratch of
/// length `n`), 0 for a singular one.
pub fn det_sign(matrix: &mut [f64], rhs: &mut [f64], n: usize) -> f64 {
    lu_solve(matrix, rhs, n).map_or(0.0, |lu| lu.det_sign)
}
