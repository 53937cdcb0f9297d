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

/// The highest order a step may use.
const MAX_ORDER: usize = 24;
/// What a Taylor step is charged against the solve's effort budget, in Runge-Kutta steps of
/// the elastica: at the default tolerance (order 12) one costs about as much as two or three
/// of them (the profile of the 1000-case beam job: 3.9 Taylor steps a shot, about 0.35 us
/// each with its samples, where a Dormand-Prince step took about 0.15 us), so the budget
/// still bounds the time it did.
pub(crate) const STEP_WEIGHT: u64 = 3;

/// Whether a shot of `model` is the plain-bending system this module integrates.
pub(crate) fn applies(model: &BeamModel) -> bool {
    !model.effects.shear && !model.effects.extension && !model.effects.poisson
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
/// state layout and samples, same failures.
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
        meter.tick_weighted(STEP_WEIGHT)?;
        for i in 0..N {
            z[i][0] = u[i];
        }
        coefficients::<N>(&mut z, &mut sn, &mut cs, &mut kpsi, p, c, ax, ay);
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

/// Fills the Taylor coefficients of orders `1..=p` of the state `z[i][k]` from its values
/// `z[i][0]`, with those of `sin psi`, `cos psi` up to order `p - 1`.
///
/// Order `k + 1` of every component needs the convolutions of order `k`: the sine and cosine
/// recurrences and, per variational column, `S * P` and `C * P`. Their sums run side by side
/// in one loop (independent chains of additions, which the processor overlaps, where one
/// sum after another would wait on each addition's latency).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn coefficients<const N: usize>(
    z: &mut [[f64; MAX_ORDER + 1]; N],
    sn: &mut [f64; MAX_ORDER + 1],
    cs: &mut [f64; MAX_ORDER + 1],
    kpsi: &mut [f64; MAX_ORDER + 1],
    p: usize,
    c: f64,
    ax: f64,
    ay: f64,
) {
    const COLS: usize = 3;
    let columns = (N - 4) / 4;
    for k in 0..p {
        let mut sp = [0.0_f64; COLS];
        let mut cp = [0.0_f64; COLS];
        if k == 0 {
            let (s0, c0) = crate::trig::sin_cos(z[0][0]);
            sn[0] = s0;
            cs[0] = c0;
        } else {
            kpsi[k] = k as f64 * z[0][k];
            let (mut ss, mut cc) = (0.0, 0.0);
            for j in 1..=k {
                let kp = kpsi[j];
                ss += kp * cs[k - j];
                cc += kp * sn[k - j];
                // The columns' terms S_(j-1) P_(k-j+1): all but the last, S_k P_0.
                let (sj, cj) = (sn[j - 1], cs[j - 1]);
                for col in 0..columns {
                    let pz = z[4 + 4 * col][k + 1 - j];
                    sp[col] += sj * pz;
                    cp[col] += cj * pz;
                }
            }
            sn[k] = ss * INV[k];
            cs[k] = -cc * INV[k];
        }
        let inv = INV[k + 1];
        z[0][k + 1] = c * z[1][k] * inv;
        z[1][k + 1] = (ax * sn[k] - ay * cs[k]) * inv;
        z[2][k + 1] = cs[k] * inv;
        z[3][k + 1] = sn[k] * inv;
        for col in 0..columns {
            let b = 4 + 4 * col;
            let (sp, cp) = (sp[col] + sn[k] * z[b][0], cp[col] + cs[k] * z[b][0]);
            // The force's own columns (N = 16: alpha_x, then alpha_y) are forced.
            let forcing = match (N, col) {
                (16, 1) => sn[k],
                (16, 2) => -cs[k],
                _ => 0.0,
            };
            z[b][k + 1] = c * z[b + 1][k] * inv;
            z[b + 1][k + 1] = (ax * cp + ay * sp + forcing) * inv;
            z[b + 2][k + 1] = -sp * inv;
            z[b + 3][k + 1] = cp * inv;
        }
    }
}

/// `1 / k` for every order (`INV[0]` unused).
const INV: [f64; MAX_ORDER + 2] = {
    let mut t = [0.0; MAX_ORDER + 2];
    let mut k = 1;
    while k < MAX_ORDER + 2 {
        t[k] = 1.0 / k as f64;
        k += 1;
    }
    t
};

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
mod tests {
    use super::*;
    use crate::beam::shoot::rhs;
    use crate::beam::{BeamModel, Effects};
    use crate::cancel::CancelToken;

    fn settings(tol: f64) -> ShotSettings {
        ShotSettings {
            tol,
            variational_tol: 1e-12,
            moment_scale: 1.0,
            h0: 0.1,
            max_steps: 200_000,
        }
    }

    /// Classical RK4 on the same right-hand side with a tiny fixed step: an independent
    /// reference (global error about 1e-14 at 4000 steps on these loads).
    fn rk4<const N: usize>(model: &BeamModel, force: TipForce, u0: State<N>, len: f64) -> State<N> {
        let steps = 4000;
        let h = len / steps as f64;
        let f = |u: &State<N>| rhs(model, force, u).unwrap();
        let mut u = u0;
        for _ in 0..steps {
            let k1 = f(&u);
            let k2 = f(&std::array::from_fn(|i| u[i] + 0.5 * h * k1[i]));
            let k3 = f(&std::array::from_fn(|i| u[i] + 0.5 * h * k2[i]));
            let k4 = f(&std::array::from_fn(|i| u[i] + h * k3[i]));
            u = std::array::from_fn(|i| {
                u[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        u
    }

    fn check<const N: usize>(model: &BeamModel, force: TipForce, segment: Segment) {
        let cancel = CancelToken::new();
        let mut meter = Meter::new(u64::MAX / 4, model, &cancel);
        let (u, steps) =
            integrate::<N>(model, force, segment, settings(1e-12), None, &mut meter).unwrap();
        let mut u0: State<N> = [0.0; N];
        u0[0] = segment.psi;
        u0[1] = segment.moment;
        u0[5] = 1.0;
        if N == 12 {
            u0[8] = 1.0;
        }
        let reference = rk4(model, force, u0, segment.s_end - segment.s_start);
        for i in 0..N {
            assert!(
                (u[i] - reference[i]).abs() <= 1e-10 * (1.0 + reference[i].abs()),
                "N = {N}, component {i}: Taylor {} vs RK4 {} ({steps} steps)",
                u[i],
                reference[i]
            );
        }
    }

    /// The samples and their sensitivities (summed to fewer orders) against the
    /// Dormand-Prince shot's, both at tol 1e-12: the shape to 1e-10, the sensitivities to the
    /// production variational tolerance's 1e-6 (relative), whose truncation they carry.
    #[test]
    fn taylor_samples_match_the_runge_kutta_shots() {
        let model = BeamModel::elastica();
        let cancel = CancelToken::new();
        let force = TipForce {
            alpha_x: -2.0,
            alpha_y: 4.0,
        };
        let mut settings = settings(1e-12);
        settings.variational_tol = 1e-6;
        settings.moment_scale = 4.5;
        for (segment, columns) in [
            (
                Segment {
                    s_start: 0.0,
                    s_end: 0.5,
                    psi: 0.0,
                    moment: 2.5,
                    origin: (0.0, 0.0),
                },
                3,
            ),
            (
                Segment {
                    s_start: 0.5,
                    s_end: 1.0,
                    psi: 0.9,
                    moment: 1.1,
                    origin: (0.45, 0.2),
                },
                6,
            ),
        ] {
            let run = |taylor: bool| {
                let mut points = Vec::new();
                let mut sens = Vec::new();
                let samples = Samples {
                    points: &mut points,
                    count: 41,
                    sensitivities: Some(&mut sens),
                };
                let mut meter = Meter::new(u64::MAX / 4, &model, &cancel);
                let shape = Some(samples);
                if columns == 3 && taylor {
                    integrate::<8>(&model, force, segment, settings, shape, &mut meter).unwrap();
                } else if columns == 3 {
                    crate::beam::shoot::integrate::<8>(
                        &model, force, segment, settings, shape, &mut meter,
                    )
                    .unwrap();
                } else if taylor {
                    integrate::<12>(&model, force, segment, settings, shape, &mut meter).unwrap();
                } else {
                    crate::beam::shoot::integrate::<12>(
                        &model, force, segment, settings, shape, &mut meter,
                    )
                    .unwrap();
                }
                (points, sens)
            };
            let (points, sens) = run(true);
            let (ref_points, ref_sens) = run(false);
            // Root and 20 samples on the first half; the second's 20 after its start.
            assert_eq!(points.len(), if columns == 3 { 21 } else { 20 });
            assert_eq!(points.len(), ref_points.len());
            for (a, b) in points.iter().zip(&ref_points) {
                assert_eq!(a.s, b.s);
                let diff = (a.x - b.x)
                    .abs()
                    .max((a.y - b.y).abs())
                    .max((a.psi - b.psi).abs());
                assert!(diff <= 1e-10, "sample at s = {}: {a:?} vs {b:?}", a.s);
            }
            for (a, b) in sens.iter().zip(&ref_sens) {
                for m in 0..6 {
                    let tol = 1e-6 * (1.0 + b[m].abs());
                    assert!(
                        (a[m] - b[m]).abs() <= tol,
                        "sensitivity {m}: {a:?} vs {b:?}"
                    );
                    if m >= columns {
                        assert_eq!(a[m], 0.0);
                    }
                }
            }
        }
    }

    /// The two plain-bending models: the elastica and a plate (plane strain, L/t = 30).
    fn plain_models() -> [BeamModel; 2] {
        [
            BeamModel::elastica(),
            BeamModel::new(30.0, 0.3, None, Effects::NONE.with_plane_strain(true)).unwrap(),
        ]
    }

    /// The whole beam from its clamp, and an inner segment, both starting with the moment
    /// `m0`.
    fn whole_and_inner(m0: f64) -> (Segment, Segment) {
        let whole = Segment {
            s_start: 0.0,
            s_end: 1.0,
            psi: 0.0,
            moment: m0,
            origin: (0.0, 0.0),
        };
        let inner = Segment {
            s_start: 0.25,
            s_end: 0.75,
            psi: 0.4,
            moment: m0,
            origin: (0.1, 0.2),
        };
        (whole, inner)
    }

    #[test]
    fn taylor_shots_match_a_fine_runge_kutta_reference() {
        let loads = [
            (0.0, 3.0, 1.2),
            (-7.0, 7.0, -2.5),
            (2.0, -1.0, 6.0),
            (0.0, 0.0, 2.0),
        ];
        for model in &plain_models() {
            for &(ax, ay, m0) in &loads {
                let force = TipForce {
                    alpha_x: ax,
                    alpha_y: ay,
                };
                let (whole, inner) = whole_and_inner(m0);
                check::<8>(model, force, whole);
                check::<16>(model, force, whole);
                check::<12>(model, force, inner);
            }
        }
    }

    /// The AVX2 build of the integrator gives the baseline build's bits: end states, step
    /// counts, samples and their sensitivities, for every state size, on the elastica and a
    /// plate, at a tight and a loose tolerance.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn both_builds_give_the_same_bits() {
        if !crate::cpu::wide() {
            eprintln!("this processor has no AVX2 and FMA: only the baseline build runs here");
            return;
        }
        let cancel = CancelToken::new();
        fn run<const N: usize>(
            wide: bool,
            model: &BeamModel,
            force: TipForce,
            segment: Segment,
            settings: ShotSettings,
            cancel: &CancelToken,
        ) -> (Vec<u64>, u32) {
            let mut points = Vec::new();
            let mut sens = Vec::new();
            let shape = Some(Samples {
                points: &mut points,
                count: 41,
                sensitivities: Some(&mut sens),
            });
            let mut meter = Meter::new(u64::MAX / 4, model, cancel);
            let (u, steps) = if wide {
                // SAFETY: `cpu::wide` said this processor has AVX2 and FMA.
                unsafe { integrate_wide::<N>(model, force, segment, settings, shape, &mut meter) }
            } else {
                integrate_any::<N>(model, force, segment, settings, shape, &mut meter)
            }
            .unwrap();
            let mut values = u.to_vec();
            values.extend(points.iter().flat_map(|p| [p.s, p.x, p.y, p.psi]));
            values.extend(sens.iter().flatten());
            (values.iter().map(|v| v.to_bits()).collect(), steps)
        }
        let mut compared = 0;
        for model in &plain_models() {
            for (ax, ay, m0) in [
                (0.0, 3.0, 1.2),
                (-7.0, 7.0, -2.5),
                (2.0, -1.0, 6.0),
                (-20.0, 1.0, 9.0),
            ] {
                let force = TipForce {
                    alpha_x: ax,
                    alpha_y: ay,
                };
                let (whole, inner) = whole_and_inner(m0);
                for tol in [1e-12, 1e-9, 1e-5] {
                    let mut settings = settings(tol);
                    settings.variational_tol = 1e-6;
                    let same = [
                        run::<4>(true, model, force, whole, settings, &cancel)
                            == run::<4>(false, model, force, whole, settings, &cancel),
                        run::<8>(true, model, force, whole, settings, &cancel)
                            == run::<8>(false, model, force, whole, settings, &cancel),
                        run::<12>(true, model, force, inner, settings, &cancel)
                            == run::<12>(false, model, force, inner, settings, &cancel),
                        run::<16>(true, model, force, whole, settings, &cancel)
                            == run::<16>(false, model, force, whole, settings, &cancel),
                    ];
                    assert_eq!(same, [true; 4], "loads ({ax}, {ay}, {m0}), tol {tol}");
                    compared += 4;
                }
            }
        }
        assert_eq!(compared, 96);
    }
}
