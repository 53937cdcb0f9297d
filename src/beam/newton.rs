//! The beam's Newton iteration at a fixed load: multiple shooting with `(psi, M)` at the start
//! of every segment as unknowns (as many segments as the load needs), the banded Jacobian
//! from the variational equations, and the Morse-index stability of the shape it converges
//! to (see the parent module for the method and its accuracy).

use super::band::Band;
use super::model::BeamModel;
use super::shoot::{Meter, Samples, Segment, Shot, ShotFailure, ShotSettings, TipForce};
use super::shot::shoot;
use super::{BeamSolver, Convergence, Load, ShapePoint, TipPose};
use crate::continuation::Effort;

/// Newton gives up when its residual has not halved in this many shots.
const STAGNATION_SHOTS: u32 = 8;
/// The first shot's update is accepted (applied linearly) when the error it leaves, estimated
/// from the contraction constant measured on earlier cases of the path, is below a tenth of
/// the tolerance even with this constant taken this many times larger: the constant varies
/// slowly along a path, and a wrong acceptance would go unnoticed.
const PRIOR_CONTRACTION_SAFETY: f64 = 10.0;
/// Shooting segments are short enough that perturbations grow by at most about
/// `exp(SEGMENT_GROWTH)` across one (they grow like `exp(sqrt(|alpha|) s)`).
const SEGMENT_GROWTH: f64 = 3.0;
/// Enough segments for `sqrt(alpha)` up to about 12000 (`alpha` ~ 1.5e8). The banded Newton
/// system makes a segment cost little more than the integration steps it holds.
const MAX_SEGMENTS: usize = 4096;

/// Newton's storage, kept by a path from case to case so that a case allocates next to
/// nothing; `shape` is the buffer the next solve samples its shape into (the path hands back
/// the one its point no longer needs).
pub(super) struct NewtonScratch {
    pub shape: Vec<ShapePoint>,
    sensitivities: Vec<[f64; 6]>,
    first_sample: Vec<usize>,
    ends: Vec<[f64; 12]>,
    jacobian: Band,
    residual: Vec<f64>,
}

impl Default for NewtonScratch {
    fn default() -> NewtonScratch {
        NewtonScratch {
            shape: Vec::new(),
            sensitivities: Vec::new(),
            first_sample: Vec::new(),
            ends: Vec::new(),
            jacobian: Band::new(0, 2, 1),
            residual: Vec::new(),
        }
    }
}

/// The outcome of one Newton solve at a fixed load.
pub(super) struct NewtonResult {
    pub nodes: Vec<[f64; 2]>,
    pub shape: Vec<ShapePoint>,
    pub tip: TipPose,
    pub shots: u32,
    pub rk_steps: u32,
    pub convergence: Convergence,
    /// The stability of the shape (see [`chain_stability`]).
    pub chain: Chain,
    /// Newton's contraction constant `C` (the error left by an update of size `d` is about
    /// `C d^2`), measured on this solve's last two updates when both were in the asymptotic
    /// regime; `None` when it could not be measured (one shot, or damped updates).
    pub contraction: Option<f64>,
}

/// Why Newton at a fixed load failed.
pub(super) enum NewtonFailure {
    Shot(ShotFailure),
    Diverged(String),
    /// The case's budget of Newton shots ran out.
    OutOfShots,
}

impl BeamSolver {
    /// Newton's method for multiple shooting at a fixed load.
    ///
    /// The unknowns are the root moment and `(psi, M)` at the start of every later segment;
    /// the equations are continuity of `(psi, M)` between segments and `M(L) = beta`. With one
    /// segment this is plain shooting on the root moment. More segments keep each shot's
    /// sensitivity near `exp(SEGMENT_GROWTH)` where a single shot's would be
    /// `exp(sqrt(alpha))` and Newton's basin would shrink to nothing. An update that makes
    /// the (scaled) residual grow is halved.
    ///
    /// The last update is applied linearly to the tip and to the shape sampled on the last
    /// shot (from the sensitivities the shot carries), which removes its Newton error; with
    /// `prior`, the contraction constant measured on an earlier case of the path, a first
    /// shot whose update leaves an error well below the tolerance is accepted at once.
    pub(super) fn newton(
        &self,
        load: Load,
        mut nodes: Vec<[f64; 2]>,
        prior: Option<f64>,
        meter: &mut Meter<'_>,
        effort: &mut Effort,
        scratch: &mut NewtonScratch,
    ) -> Result<NewtonResult, NewtonFailure> {
        let force = TipForce {
            alpha_x: load.alpha_x,
            alpha_y: load.alpha_y,
        };
        let settings = self.settings(load);
        let magnitude = load.magnitude();
        let moment_weight = 1.0 / (1.0 + magnitude);
        // The tip must be right to the tolerance, relative to the deflection for tiny loads
        // so that a load of 1e-9 still agrees with linear theory to many digits.
        let tip_tol = self.resolution.tol * magnitude.min(1.0);
        let segments = nodes.len();
        let unknowns = 2 * segments - 1;
        let samples = self.resolution.shape_points;
        let mut shape = std::mem::take(&mut scratch.shape);
        shape.reserve(samples);
        let NewtonScratch {
            sensitivities,
            first_sample,
            ends,
            jacobian,
            residual,
            ..
        } = scratch;
        sensitivities.reserve(samples);
        // Where each segment's samples start in `shape`.
        first_sample.clear();
        first_sample.resize(segments + 1, 0);
        ends.clear();
        ends.resize(segments, [0.0; 12]);
        // Row 2k (psi continuity) reaches from column 2k - 1 to 2k + 1, row 2k + 1 (moment
        // continuity) from 2k - 1 to 2k + 2: two subdiagonals and one superdiagonal.
        jacobian.reshape(unknowns, 2, 1);
        residual.clear();
        residual.resize(unknowns, 0.0);
        // The last iterate that improved the residual, and the update taken from it.
        let mut base: Option<(Vec<[f64; 2]>, f64, Vec<f64>)> = None;
        let mut last_measure = f64::INFINITY;
        let (mut best_merit, mut best_shot) = (f64::INFINITY, 0);
        nodes[0][0] = 0.0;
        let limit = effort.newton_limit();
        for shot_no in 1..=limit {
            if !effort.spend_iteration() {
                return Err(NewtonFailure::OutOfShots);
            }
            // Shoot every segment; the shape is sampled on every iteration, which is far
            // cheaper than one more pass at the end.
            shape.clear();
            sensitivities.clear();
            let mut origin = (0.0, 0.0);
            let mut rk_steps = 0;
            for (k, node) in nodes.iter().enumerate() {
                first_sample[k] = shape.len();
                let segment = Segment {
                    s_start: k as f64 / segments as f64,
                    s_end: (k + 1) as f64 / segments as f64,
                    psi: node[0],
                    moment: node[1],
                    origin,
                };
                let sampling = Samples {
                    points: &mut shape,
                    count: samples,
                    sensitivities: Some(&mut *sensitivities),
                };
                // The first segment starts at the clamp, where psi = 0 is no unknown.
                let shot = if k == 0 {
                    shoot::<8>(&self.model, force, segment, settings, Some(sampling), meter)
                } else {
                    shoot::<12>(&self.model, force, segment, settings, Some(sampling), meter)
                };
                let Shot { end, steps } = shot.map_err(NewtonFailure::Shot)?;
                origin = (origin.0 + end[2], origin.1 + end[3]);
                ends[k] = end;
                rk_steps += steps;
            }
            first_sample[segments] = shape.len();
            let last = &ends[segments - 1];

            // Residual and Jacobian. Column of psi_k is 2k - 1 (k >= 1), of M_k is 2k.
            jacobian.clear();
            for k in 0..segments {
                let e = &ends[k];
                let (row_psi, row_m) = (2 * k, 2 * k + 1);
                let rows: &[(usize, usize, usize)] = if k + 1 < segments {
                    residual[row_psi] = e[0] - nodes[k + 1][0];
                    residual[row_m] = e[1] - nodes[k + 1][1];
                    jacobian.set(row_psi, 2 * k + 1, -1.0);
                    jacobian.set(row_m, 2 * k + 2, -1.0);
                    &[(row_psi, 8, 4), (row_m, 9, 5)]
                } else {
                    residual[row_psi] = e[1] - load.beta;
                    &[(row_psi, 9, 5)]
                };
                for &(row, d_psi, d_m) in rows {
                    if k > 0 {
                        jacobian.set(row, 2 * k - 1, e[d_psi]);
                    }
                    jacobian.set(row, 2 * k, e[d_m]);
                }
            }
            let merit = residual
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    if i % 2 == 1 || i == unknowns - 1 {
                        r * moment_weight
                    } else {
                        *r
                    }
                })
                .fold(0.0_f64, |acc, r| acc.max(r.abs()));

            // Past a limit point there is no root, only a minimum of the residual, where
            // damped Newton cycles for ever: give up once the residual stops halving, and let
            // the continuation halve its step instead.
            if merit < 0.5 * best_merit {
                best_merit = merit;
                best_shot = shot_no;
            } else if shot_no - best_shot >= STAGNATION_SHOTS {
                return Err(NewtonFailure::Diverged(format!(
                    "Newton stagnated: the residual did not halve in {STAGNATION_SHOTS} shots"
                )));
            }
            if let Some((base_nodes, base_merit, update)) = &base {
                let noise_level = last_measure <= 10.0 * tip_tol;
                if merit > *base_merit && !noise_level {
                    let half: Vec<f64> = update.iter().map(|u| 0.5 * u).collect();
                    nodes = apply(base_nodes, &half);
                    base = Some((base_nodes.clone(), *base_merit, half));
                    last_measure *= 0.5;
                    continue;
                }
            }

            let mut update: Vec<f64> = residual.iter().map(|r| -r).collect();
            debug_assert_eq!(jacobian.size(), unknowns);
            if !jacobian.solve(&mut update) {
                return Err(NewtonFailure::Diverged("singular shooting Jacobian".into()));
            }

            // How far the update moves the tip (by the linearisation) and the nodes.
            let mut delta = TipPose {
                a: 0.0,
                b: 0.0,
                phi: 0.0,
            };
            let mut node_change = 0.0_f64;
            for (k, e) in ends.iter().enumerate() {
                let d_psi = if k > 0 { update[2 * k - 1] } else { 0.0 };
                let d_m = update[2 * k];
                delta.a += e[10] * d_psi + e[6] * d_m;
                delta.b += e[11] * d_psi + e[7] * d_m;
                if k + 1 == segments {
                    delta.phi = e[8] * d_psi + e[4] * d_m;
                }
                node_change = node_change.max(d_psi.abs()).max(d_m.abs() * moment_weight);
            }
            let measure = delta.max_diff(&TipPose::default()).max(node_change);
            if !measure.is_finite() {
                return Err(NewtonFailure::Diverged(
                    "the Newton update is not finite".into(),
                ));
            }
            // Stop when the update moves the tip and nodes by less than the tolerance; or
            // when Newton's quadratic convergence (contraction C = measure / last^2) says the
            // error left after applying this update, C measure^2, is well below it; or when
            // the integrator's noise keeps the updates from shrinking any further.
            // The contraction is only trusted once both updates are small (the asymptotic
            // regime), and never below 1: after a long damped step it would be estimated far
            // too small and accept an update that is not yet converged.
            // On the first shot, the contraction measured earlier on the path stands in.
            let contracting = measure < 0.5 * last_measure;
            let measured = (last_measure <= 1e-2 && contracting)
                .then(|| (measure / (last_measure * last_measure)).max(1.0));
            let contraction = match (measured, prior) {
                (Some(c), _) => Some(c),
                (None, Some(c)) if shot_no == 1 => Some(PRIOR_CONTRACTION_SAFETY * c.max(1.0)),
                _ => None,
            };
            let quadratic = contraction
                .is_some_and(|c| measure <= 1e-3 && measure * measure * c <= 0.1 * tip_tol);
            let stalled = !contracting && measure <= 100.0 * self.resolution.tol;
            if measure <= tip_tol || quadratic || stalled {
                // Apply the last update linearly: free, and it removes the Newton error.
                let tip = TipPose {
                    a: origin.0 + delta.a,
                    b: origin.1 + delta.b,
                    phi: last[0] + delta.phi,
                };
                let chain = chain_stability(ends);
                carry_to_shape(&mut shape, sensitivities, first_sample, ends, &update);
                return Ok(NewtonResult {
                    nodes: {
                        apply_in_place(&mut nodes, &update);
                        nodes
                    },
                    shape,
                    tip,
                    shots: shot_no,
                    rk_steps,
                    convergence: Convergence {
                        residual: merit,
                        last_update: measure,
                        stability: chain.slope,
                    },
                    chain,
                    contraction: measured,
                });
            }
            // Damp wild updates: angles beyond a radian or moments beyond what the load can
            // produce mean the linearisation is useless here.
            let biggest = update
                .iter()
                .enumerate()
                .map(|(i, u)| {
                    if i % 2 == 0 {
                        u.abs() / (2.0 * (magnitude + 1.0))
                    } else {
                        u.abs()
                    }
                })
                .fold(0.0_f64, f64::max);
            if biggest > 1.0 {
                update.iter_mut().for_each(|u| *u /= biggest);
            }
            let next = apply(&nodes, &update);
            base = Some((std::mem::replace(&mut nodes, next), merit, update));
            last_measure = measure;
        }
        Err(NewtonFailure::Diverged(format!(
            "Newton did not converge in {limit} iterations"
        )))
    }

    pub(super) fn settings(&self, load: Load) -> ShotSettings {
        let magnitude = load.magnitude();
        ShotSettings {
            tol: self.resolution.tol,
            // A slope good to 1e-5 still gains five digits per Newton step.
            variational_tol: (self.resolution.tol * 1e3).clamp(1e-7, 1e-5),
            moment_scale: magnitude,
            h0: 0.1 / (1.0 + magnitude.sqrt()),
            max_steps: 200_000,
        }
    }
}

/// The response `(dpsi, dM)` of the beam to a change of its root moment, as far as the
/// stability tests need it.
#[derive(Debug, Clone, Copy)]
pub(super) struct Chain {
    /// `dM(L)/dM(0)`, saturating at `f64::MAX`.
    pub slope: f64,
    /// `dM(L) / |(dpsi(L), dM(L))|`: the slope's sign without the factor
    /// `exp(sqrt(alpha))` a huge force puts in front of it. Near a limit point it falls like
    /// the slope; far from one it is of order 1 at any load, where the slope can be 1e300.
    pub direction: f64,
    /// `dM(s)/dM(0)` is already non-positive at the end of an inner segment.
    pub focal_point: bool,
}

/// `dM(L)/dM(0)` through the chain of segments, and whether `dM(s)/dM(0)` is already
/// non-positive at the end of an inner segment.
///
/// `(dpsi, dM)(s)`, the response to a change of the root moment, is the Jacobi field of the
/// beam's energy with the clamp's `dpsi(0) = 0`; `dM(s) = 0` is the free end's natural
/// boundary condition at `s`. By the Morse index theorem the equilibrium is stable (no
/// neighbouring shape of lower energy) exactly when `dM(s) > 0` on all of `(0, L]`, not only
/// at the tip: under a compression well past Euler's load `dM(L)` returns to positive values
/// (for an axial load it is `cos(sqrt(alpha) s)`), and one long continuation step could land
/// there with no sign change seen at the tip. A segment spans at most about
/// [`SEGMENT_GROWTH`] `< pi` of that oscillation's phase, so no zero can hide inside one.
///
/// At huge loads the product grows like `exp(sqrt(alpha))`, past the range of a double, so
/// it is rescaled as it goes and a stable equilibrium too stiff to represent saturates at
/// `f64::MAX`.
pub(super) fn chain_stability(ends: &[[f64; 12]]) -> Chain {
    let mut v = [0.0, 1.0];
    let mut log_scale = 0.0;
    let mut focal_point = false;
    for (k, e) in ends.iter().enumerate() {
        v = [e[8] * v[0] + e[4] * v[1], e[9] * v[0] + e[5] * v[1]];
        if k + 1 < ends.len() && v[1] <= 0.0 {
            focal_point = true;
        }
        let big = v[0].abs().max(v[1].abs());
        // Rescaling only past 1e100 leaves every ordinary load's value untouched.
        if big > 1e100 && big.is_finite() {
            v = [v[0] / big, v[1] / big];
            log_scale += big.ln();
        }
    }
    let norm = v[0].hypot(v[1]);
    let direction = if norm > 0.0 { v[1] / norm } else { 0.0 };
    let slope = if log_scale == 0.0 || v[1] == 0.0 {
        v[1]
    } else {
        let magnitude = v[1].abs().ln() + log_scale;
        if magnitude >= f64::MAX.ln() {
            f64::MAX.copysign(v[1])
        } else {
            magnitude.exp().copysign(v[1])
        }
    };
    Chain {
        slope,
        direction,
        focal_point,
    }
}

/// The shape sampled on the last shot moved linearly by Newton's last update (laid out as
/// the unknowns): each segment's samples by the update of its start and the move of its
/// origin, the sum of the earlier segments' end moves.
fn carry_to_shape(
    shape: &mut [ShapePoint],
    sensitivities: &[[f64; 6]],
    first_sample: &[usize],
    ends: &[[f64; 12]],
    update: &[f64],
) {
    if sensitivities.len() != shape.len() {
        return;
    }
    let mut origin = (0.0, 0.0);
    for (k, e) in ends.iter().enumerate() {
        let d_psi = if k > 0 { update[2 * k - 1] } else { 0.0 };
        let d_m = update[2 * k];
        let range = first_sample[k]..first_sample[k + 1];
        for (point, d) in shape[range.clone()].iter_mut().zip(&sensitivities[range]) {
            point.psi += d[0] * d_m + d[3] * d_psi;
            point.x += origin.0 + d[1] * d_m + d[4] * d_psi;
            point.y += origin.1 + d[2] * d_m + d[5] * d_psi;
        }
        origin.0 += e[6] * d_m + e[10] * d_psi;
        origin.1 += e[7] * d_m + e[11] * d_psi;
    }
}

/// `nodes` moved in place by a Newton update laid out as the unknowns
/// (`M_0, psi_1, M_1, ...`).
fn apply_in_place(nodes: &mut [[f64; 2]], update: &[f64]) {
    for (k, n) in nodes.iter_mut().enumerate() {
        let d_psi = if k > 0 { update[2 * k - 1] } else { 0.0 };
        *n = [n[0] + d_psi, n[1] + update[2 * k]];
    }
}

/// `nodes` moved by a Newton update laid out as the unknowns (`M_0, psi_1, M_1, ...`).
fn apply(nodes: &[[f64; 2]], update: &[f64]) -> Vec<[f64; 2]> {
    let mut moved = nodes.to_vec();
    apply_in_place(&mut moved, update);
    moved
}

/// How many shooting segments a load path needs (see [`SEGMENT_GROWTH`]).
///
/// Near a straight stretch under a tension `F` perturbations of `psi` obey
/// `psi'' = (1 + eps) F psi / (E I / E I0)`, so they grow at the rate
/// `sqrt(F (1 + eps) / p^4)` (the stretch lengthens the lever, Poisson's shrink softens the
/// section); under a compression they oscillate at up to `sqrt(F (1 + c_s F))`. The largest
/// force on a proportional path is at its end. Past [`MAX_SEGMENTS`] (`alpha` beyond about
/// 1.5e8) segments amplify more and Newton's basin shrinks; such loads usually end in the
/// effort budget.
pub(super) fn segment_count(model: &BeamModel, end: Load) -> usize {
    let force = end.alpha_x.hypot(end.alpha_y);
    let tension = match model.axial_strain(force) {
        Ok((eps, _, p)) => (1.0 + eps.max(0.0)) * model.plate_compliance() / p.powi(4),
        // A force the material cannot carry fails on the path anyway.
        Err(_) => 1.0,
    };
    // Under compression the same perturbations oscillate instead, at the rate
    // `sqrt(F (1 + c_s F))`: shear adds `gamma N` to `dM/ds`. Segments must also hold that
    // oscillation to less than half a period (see `chain_stability`).
    let compression = if model.effects.shear {
        1.0 + model.shear_compliance() * force
    } else {
        1.0
    };
    let softening = tension.max(compression);
    let rate = (force * softening).sqrt();
    let wanted = (rate / SEGMENT_GROWTH).ceil();
    if wanted.is_finite() {
        (wanted as usize).clamp(1, MAX_SEGMENTS)
    } else {
        MAX_SEGMENTS
    }
}
