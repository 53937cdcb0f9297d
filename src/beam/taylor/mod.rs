//! Taylor-series integration of a shot of the plain-bending beam (no shear, no extension,
//! no Poisson; plane strain only scales the bending compliance `c`).
//!
//! There the shot's system is the elastica's, with `S = sin psi`, `C = cos psi`:
//!
//! ```text
//! psi' = c M        M' = alpha_x S - alpha_y C        x' = C        y' = S
//! ```
//!
//! and each variational column `(P, Q, X, Y)` (a derivative of the state with respect to the
//! starting `M` or `psi`, or to the force's `alpha_x` or `alpha_y`) obeys
//!
//! ```text
//! P' = c Q          Q' = n P (+ S for alpha_x, - C for alpha_y)   X' = -S P   Y' = C P
//! ```
//!
//! with `n = alpha_x C + alpha_y S` the axial force. Every right-hand side is a product of a
//! series with `S` or `C`, and `S, C` themselves follow from `psi` by the recurrences of
//! `S' = C psi'` and `C' = -S psi'`, so the Taylor coefficients of the whole state to any
//! order cost a few dot products each (automatic differentiation by recurrences). One step
//! of order `p` then replaces many Runge-Kutta steps: the series is exact to `O(h^(p+1))`,
//! its step comes from the decay of its last two coefficients (Jorba and Zou's rule), and
//! the shape samples inside a step are the same polynomial evaluated there, as accurate as
//! the step itself.
//!
//! ## The shearing, stretching, shrinking beam
//!
//! With the other effects on (DESIGN §2) the state alone (`N = 4`, no sensitivities) follows
//!
//! ```text
//! psi' = b M    M' = -(1 + eps) Q + gamma N    x' = (1 + eps) C - gamma S
//!                                              y' = (1 + eps) S + gamma C
//! ```
//!
//! with `N = alpha_x C + alpha_y S`, `Q = -alpha_x S + alpha_y C`, the strain `eps` the root of
//! `eps p^2 = c_e N` (`p = 1 - nu eps` the section's shrink, 1 without Poisson), the bending
//! compliance `b = c / p^4` and the shear strain `gamma = c_s Q / p^2`. Each is a series too:
//! `eps`'s coefficient of order `k` is the one unknown of the order-`k` coefficient of
//! `eps p^2 = c_e N`, linear in it (`eps_k p_0 (1 - 3 nu eps_0)` plus known terms); `1 / p^2`
//! follows by the division recurrence, and the rest are products. Every product of the
//! strain or `gamma` with `N` or `Q` is a combination of their products with `S` and `C`, so
//! a step needs four convolutions beyond the elastica's, and six more with Poisson's shrink.
//! The material law's limits (necking, crushing) are checked at each step's start by the
//! law itself: its strain there is the series' first coefficient.
//!
//! The tolerances mean what they mean for the Runge-Kutta pair of [`super::shoot`]: the
//! local error of a step, absolute on `psi, x, y`, relative to the load on `M`, and the
//! looser relative `variational_tol` on the sensitivities.
//!
//! ## References
//! - A. Jorba, M. Zou, "A software package for the numerical integration of ODEs by means of
//!   high-order Taylor methods", Experimental Mathematics 14 (2005) 99-117 (the order and
//!   step-size rules).
//! - R. E. Moore, "Methods and Applications of Interval Analysis", SIAM (1979), ch. 3 (the
//!   recurrences of sin and cos).

use super::model::BeamModel;
use super::shoot::{Meter, Samples, Segment, ShotFailure, ShotSettings, State, TipForce};
use super::ShapePoint;

mod series;
use series::{coefficients, coefficients_full, Aux, Law};

/// The highest order a step may use.
const MAX_ORDER: usize = 24;
/// What a Taylor step is charged against the solve's effort budget, in Runge-Kutta steps of
/// the elastica: at the default tolerance (order 12) one costs about as much as two or three
/// of them (the profile of the 1000-case beam job: 3.9 Taylor steps a shot, about 0.35 us
/// each with its samples, where a Dormand-Prince step took about 0.15 us), so the budget
/// still bounds the time it did.
pub(crate) const STEP_WEIGHT: u64 = 3;

/// [`STEP_WEIGHT`] of a step of the shearing, stretching, shrinking beam's series, which
/// cost about 0.6 us each with their samples on the parallel stage's 1000 cases (three steps
/// a shot at tol 1e-9): four elastica Runge-Kutta steps.
const FULL_STEP_WEIGHT: u64 = 4;

/// Whether this module integrates a shot of `model` with `N` states: the plain-bending beam's
/// with or without sensitivities, any other beam's state alone (`N = 4`: the series of the
/// shearing, stretching, shrinking beam below; its sensitivities are the Runge-Kutta pair's).
pub(crate) fn applies<const N: usize>(model: &BeamModel) -> bool {
    N == 4 || model.is_plain()
}

/// The order for a local error tolerance `tol`: Jorba and Zou's `-ln(tol) / 2 + 1`, which
/// minimises the work per unit length when a step's cost grows like the square of its
/// order. Measured on the 1000 cases of `benches/scipy`'s beam job at tol 1e-9 (order 11),
/// orders two below and up to ten above it were all slower.
fn order_for(tol: f64) -> usize {
    let p = (-tol.ln() * 0.5).ceil() + 1.0;
    (p.max(6.0) as usize).min(MAX_ORDER)
}

/// [`super::shoot`]'s integration of one segment, by Taylor series: same inputs, same
/// state layout and samples, same failures. A shot this module does not integrate ([`applies`]:
/// the sensitivities of a beam with the other effects) is the Dormand-Prince pair's.
///
/// Built twice (see [`crate::cpu`]): with AVX2 and FMA where the processor has them, for the
/// baseline otherwise; both give the same bits.
pub(crate) fn integrate<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    if !applies::<N>(model) {
        // Sensitivities of a beam with the other effects: not this module's.
        return super::dopri::integrate::<N>(model, force, segment, settings, shape, meter);
    }
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::wide() {
        // SAFETY: `wide` has just checked that this processor has AVX2 and FMA, the only
        // features `integrate_wide` enables.
        return unsafe { integrate_wide::<N>(model, force, segment, settings, shape, meter) };
    }
    integrate_any::<N>(model, force, segment, settings, shape, meter)
}

/// [`integrate`] compiled with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn integrate_wide<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    integrate_any::<N>(model, force, segment, settings, shape, meter)
}

/// [`integrate`]'s body, inlined into each of its builds.
#[inline(always)]
fn integrate_any<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    mut shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    let mut u: State<N> = segment.initial_state();
    let p = order_for(settings.tol);
    let c = model.plate_compliance();
    let (ax, ay) = (force.alpha_x, force.alpha_y);
    let inv_tol = 1.0 / settings.tol;
    let inv_var_tol = 1.0 / settings.variational_tol;
    let inv_m = 1.0 / settings.moment_scale.max(1.0);
    let mut s = segment.s_start;
    let s_end = segment.s_end;

    let mut next_sample = shape.as_mut().map_or(0, |samples| samples.start(&segment));

    // Taylor coefficients: z[i][k] of state component i, and those of sin psi, cos psi.
    let mut z = [[0.0_f64; MAX_ORDER + 1]; N];
    let mut sn = [0.0_f64; MAX_ORDER + 1];
    let mut cs = [0.0_f64; MAX_ORDER + 1];
    // k psi_k, the factor of the sine and cosine recurrences.
    let mut kpsi = [0.0_f64; MAX_ORDER + 1];
    // The other effects' series (zero where an effect is off).
    // (`N = 4` only: [`integrate`] has sent any other shot of such a beam elsewhere.)
    let law = (N == 4 && !model.is_plain()).then(|| Law::of(model));
    let mut aux = Aux::default();
    let weight = |i: usize, value: f64| match i {
        1 => inv_m * inv_tol,
        // The sensitivities only steer Newton and the stability test: their looser,
        // relative tolerance, as in the Runge-Kutta shot.
        _ if i >= 4 => inv_var_tol / (1.0 + value.abs()),
        _ => inv_tol,
    };
    let mut steps = 0u32;
    while s < s_end {
        if steps >= settings.max_steps {
            return Err(ShotFailure::StepBudget);
        }
        meter.tick_weighted(if law.is_some() {
            FULL_STEP_WEIGHT
        } else {
            STEP_WEIGHT
        })?;
        for i in 0..N {
            z[i][0] = u[i];
        }
        match law {
            None => coefficients::<N>(&mut z, &mut sn, &mut cs, &mut kpsi, p, c, ax, ay),
            Some(law) => {
                // The law's own strain at the step's start (or its limit).
                let (s0, c0) = crate::trig::sin_cos(u[0]);
                let (eps0, _, _) = model
                    .axial_strain(ax * c0 + ay * s0)
                    .map_err(ShotFailure::Material)?;
                sn[0] = s0;
                cs[0] = c0;
                // The state alone (`applies`): its four rows, so that the series are built
                // once, not once per state size. (Every state has them.)
                let Some(state) = z.first_chunk_mut::<4>() else {
                    return Err(ShotFailure::NonFinite);
                };
                coefficients_full(
                    state, &mut sn, &mut cs, &mut kpsi, &mut aux, p, law, eps0, ax, ay,
                );
            }
        }
        // The step from the last two coefficients, each scaled by its tolerance: the
        // truncation error is about the first neglected term.
        let (mut e_last, mut e_prev) = (0.0_f64, 0.0_f64);
        for i in 0..N {
            let w = weight(i, u[i]);
            e_last = e_last.max((z[i][p] * w).abs());
            e_prev = e_prev.max((z[i][p - 1] * w).abs());
        }
        if !(e_last.is_finite() && e_prev.is_finite()) {
            return Err(ShotFailure::NonFinite);
        }
        // h = safety * min(e_last^(-1/p), e_prev^(-1/(p-1))), by logarithms (cheaper than
        // two powers); a zero coefficient sets no limit.
        let log_h = |e: f64, k: usize| {
            if e > 0.0 {
                -e.ln() / k as f64
            } else {
                f64::INFINITY
            }
        };
        let log_safety = -0.7 / (p - 1) as f64;
        let h_limit = (log_safety + log_h(e_last, p).min(log_h(e_prev, p - 1))).exp();
        let remaining = s_end - s;
        let mut h = h_limit;
        let last = h >= remaining - 1e-12;
        if last {
            h = remaining;
        } else if h < 1e-12 {
            return Err(ShotFailure::StepBudget);
        }
        let s_new = if last { s_end } else { s + h };
        if let Some(samples) = shape.as_mut() {
            let step = Step {
                s,
                s_new,
                h,
                p,
                origin: segment.origin,
            };
            // The sensitivities sampled: d(psi, x, y)/dM, and d(psi, x, y)/dpsi for N = 12.
            if N == 12 {
                let which = [4, 6, 7, 8 % N, 10 % N, 11 % N];
                let weights = which.map(|i| weight(i, u[i]));
                sample_step(&z, which, weights, &step, samples, &mut next_sample);
            } else if N > 4 {
                let which = [4, 6, 7];
                let weights = which.map(|i| weight(i, u[i]));
                sample_step(&z, which, weights, &step, samples, &mut next_sample);
            } else {
                // The state alone (N = 4): no sensitivities to sample.
                sample_step::<N, 0>(&z, [], [], &step, samples, &mut next_sample);
            }
        }
        u = evaluate(&z, std::array::from_fn(|i| i), p, h);
        s = s_new;
        steps += 1;
    }
    if u.iter().any(|v| !v.is_finite()) {
        return Err(ShotFailure::NonFinite);
    }
    Ok((u, steps))
}

/// One accepted step, as its samples need it.
struct Step {
    s: f64,
    s_new: f64,
    h: f64,
    p: usize,
    /// The segment's start, added to the samples' `x, y`.
    origin: (f64, f64),
}

/// Appends the samples inside `step` (from `*next`) with, if asked, their sensitivities `which`
/// (three, or six for N = 12; weights their tolerances), and advances `*next`.
#[inline(always)]
fn sample_step<const N: usize, const B: usize>(
    z: &[[f64; MAX_ORDER + 1]; N],
    which: [usize; B],
    weights: [f64; B],
    step: &Step,
    samples: &mut Samples<'_>,
    next: &mut usize,
) {
    let q = if samples.sensitivities.is_some() {
        sensitivity_order(z, which, weights, step.p, step.h)
    } else {
        0
    };
    let n = samples.count;
    // The samples in chunks of LANES, each evaluated by Horner's scheme on every lane at once
    // (independent chains of multiply-adds, where one sample at a time waits on each).
    loop {
        let mut ts = [0.0; LANES];
        let mut ss = [0.0; LANES];
        let mut lanes = 0;
        while lanes < LANES && *next < n {
            let sj = *next as f64 / (n - 1) as f64;
            if sj > step.s_new + 1e-12 {
                break;
            }
            ss[lanes] = sj;
            ts[lanes] = (sj - step.s).clamp(0.0, step.h);
            lanes += 1;
            *next += 1;
        }
        if lanes == 0 {
            return;
        }
        let v = horner_lanes(z, [0, 2, 3], step.p, &ts);
        let d = if q > 0 {
            horner_lanes(z, which, q, &ts)
        } else {
            [[0.0; LANES]; B]
        };
        for l in 0..lanes {
            samples.points.push(ShapePoint {
                s: ss[l],
                x: step.origin.0 + v[1][l],
                y: step.origin.1 + v[2][l],
                psi: v[0][l],
            });
            if let Some(sens) = samples.sensitivities.as_mut() {
                sens.push(std::array::from_fn(|m| if m < B { d[m][l] } else { 0.0 }));
            }
        }
        if lanes < LANES {
            return;
        }
    }
}

/// Samples evaluated side by side.
const LANES: usize = 8;

/// The components `which` of the series `z`, summed to order `p` by Horner's scheme, at the
/// points `ts` (one lane each).
#[inline(always)]
fn horner_lanes<const N: usize, const M: usize>(
    z: &[[f64; MAX_ORDER + 1]; N],
    which: [usize; M],
    p: usize,
    ts: &[f64; LANES],
) -> [[f64; LANES]; M] {
    let mut acc = [[0.0; LANES]; M];
    for m in 0..M {
        acc[m] = [z[which[m]][p]; LANES];
    }
    for k in (0..p).rev() {
        for m in 0..M {
            let c = z[which[m]][k];
            for l in 0..LANES {
                acc[m][l] = acc[m][l] * ts[l] + c;
            }
        }
    }
    acc
}

/// The largest term a sensitivity sample leaves out, in units of its tolerance.
const SAMPLE_TERM: f64 = 1e-2;

/// The order to which the samples' sensitivities are summed over a step of length `h`: past
/// it, every term of each of `which` at the step's end is below [`SAMPLE_TERM`] of its
/// (looser, relative) tolerance. They need fewer orders than the state, whose samples take
/// the step's own.
#[inline(always)]
fn sensitivity_order<const N: usize, const M: usize>(
    z: &[[f64; MAX_ORDER + 1]; N],
    which: [usize; M],
    weights: [f64; M],
    p: usize,
    h: f64,
) -> usize {
    let mut q = p;
    let mut hq = h.powi(p as i32);
    let inv_h = 1.0 / h;
    while q > 1 {
        let term = (0..M).fold(0.0_f64, |acc, m| {
            acc.max((z[which[m]][q] * weights[m]).abs())
        });
        if term * hq > SAMPLE_TERM {
            break;
        }
        q -= 1;
        hq *= inv_h;
    }
    q
}

/// The components `which` of the series `z` at `t` (orders up to `p`). The powers of `t` are
/// formed once and every component summed beside the others: one Horner scheme per
/// component would be a chain of dependent multiply-adds each.
// `k` indexes the same order of several series at once.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn evaluate<const N: usize, const M: usize>(
    z: &[[f64; MAX_ORDER + 1]; N],
    which: [usize; M],
    p: usize,
    t: f64,
) -> [f64; M] {
    let mut out: [f64; M] = std::array::from_fn(|m| z[which[m]][0]);
    let mut tk = 1.0;
    for k in 1..=p {
        tk *= t;
        for m in 0..M {
            out[m] += z[which[m]][k] * tk;
        }
    }
    out
}

#[cfg(test)]
mod tests;
