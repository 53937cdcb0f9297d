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
//! ## Two shots side by side
//!
//! A mechanism evaluates its flexures two by two ([`integrate_pair`]). Each order of the full
//! beam's series waits on the order before through a chain of about twenty dependent
//! operations (`psi`'s order k gives `sin psi`'s, then the axial force's, the strain's, the
//! shrink's, `1 / p^4`'s and `psi`'s order k + 1), which leaves most of the processor idle.
//! So two shots step together, and where their series are of one kind (the same effects
//! carried, the same order) they are built in the two lanes of one SSE2 register
//! ([`num::Two`]): the same operations, one instruction for both. Each lane's arithmetic is
//! the scalar build's, so each shot comes out as it would alone, to the bit (a test).
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

mod num;
mod series;
use num::{Num, Two};
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
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    let mut run = Run::<N>::new(model, force, segment, settings, shape);
    run.run_to_end(meter)?;
    run.end()
}

/// Two shots integrated side by side, each as [`integrate`] would integrate it alone (the
/// same steps and bits): each step's series of both are built order by order, interleaved,
/// so that the processor overlaps their chains of dependent arithmetic (each order of the
/// full beam's series waits on the one before, and one shot alone leaves most of the
/// processor idle). A shot that ends first leaves the other to go on alone.
pub(crate) fn integrate_pair<const N: usize>(
    shots: [PairShot<'_, '_>; 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::wide() {
        // SAFETY: `wide` has just checked that this processor has AVX2 and FMA, the only
        // features `integrate_pair_wide` enables.
        return unsafe { integrate_pair_wide::<N>(shots, meters) };
    }
    integrate_pair_any::<N>(shots, meters)
}

/// One shot of a pair: its beam, force, segment, settings and samples.
pub(crate) type PairShot<'m, 's> = (
    &'m BeamModel,
    TipForce,
    Segment,
    ShotSettings,
    Option<Samples<'s>>,
);

/// [`integrate_pair`] compiled with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn integrate_pair_wide<const N: usize>(
    shots: [PairShot<'_, '_>; 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    integrate_pair_any::<N>(shots, meters)
}

/// [`integrate_pair`]'s body, inlined into each of its builds.
#[inline(always)]
fn integrate_pair_any<const N: usize>(
    shots: [PairShot<'_, '_>; 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    let [(ma, fa, ga, sa, sha), (mb, fb, gb, sb, shb)] = shots;
    let [meter_a, meter_b] = meters;
    let mut a = Run::<N>::new(ma, fa, ga, sa, sha);
    let mut b = Run::<N>::new(mb, fb, gb, sb, shb);
    // Side by side while both go on with series of one kind and order.
    let together = a.p == b.p && a.law.is_some() == b.law.is_some();
    let (mut ra, mut rb) = (Ok(()), Ok(()));
    let mut pair = PairSeries {
        z: [[Two::splat(0.0); MAX_ORDER + 1]; 4],
        aux: Aux::default(),
    };
    if together {
        loop {
            match (a.begin(meter_a), b.begin(meter_b)) {
                (Ok(true), Ok(true)) => {
                    a.coefficients_with(&mut b, &mut pair);
                    ra = a.finish();
                    rb = b.finish();
                }
                // One has ended (or failed): the other takes the step it began alone.
                (ga, gb) => {
                    ra = ga.and_then(|go| a.step_begun(go));
                    rb = gb.and_then(|go| b.step_begun(go));
                }
            }
            if a.s >= a.s_end || b.s >= b.s_end || ra.is_err() || rb.is_err() {
                break;
            }
        }
    }
    let finish = |r: Result<(), ShotFailure>, run: &mut Run<'_, '_, N>, meter| {
        r?;
        run.run_to_end(meter)?;
        run.end()
    };
    [finish(ra, &mut a, meter_a), finish(rb, &mut b, meter_b)]
}

/// Two shots' series, lane by lane ([`Run::coefficients_with`]), kept from step to step
/// (each step writes every order it reads).
struct PairSeries {
    z: [[Two; MAX_ORDER + 1]; 4],
    aux: Aux<Two>,
}

/// One Taylor shot in progress: the integrator's whole state between steps.
struct Run<'m, 's, const N: usize> {
    model: &'m BeamModel,
    force: TipForce,
    settings: ShotSettings,
    u: State<N>,
    s: f64,
    s_end: f64,
    origin: (f64, f64),
    /// The series' order.
    p: usize,
    inv_tol: f64,
    inv_var_tol: f64,
    inv_m: f64,
    shape: Option<Samples<'s>>,
    next_sample: usize,
    /// Taylor coefficients: z[i][k] of state component i, and those of sin psi, cos psi.
    z: [[f64; MAX_ORDER + 1]; N],
    sn: [f64; MAX_ORDER + 1],
    cs: [f64; MAX_ORDER + 1],
    /// k psi_k, the factor of the sine and cosine recurrences.
    kpsi: [f64; MAX_ORDER + 1],
    /// The other effects' constants, `None` for the plain beam (`N = 4` only: [`integrate`]
    /// has sent any other shot of such a beam elsewhere), their series, and the step's
    /// start as they need it: the law's strain, `sin psi` and `cos psi`.
    law: Option<Law>,
    aux: Option<Aux<f64>>,
    start: (f64, (f64, f64)),
    steps: u32,
}

impl<'m, 's, const N: usize> Run<'m, 's, N> {
    #[inline(always)]
    fn new(
        model: &'m BeamModel,
        force: TipForce,
        segment: Segment,
        settings: ShotSettings,
        mut shape: Option<Samples<'s>>,
    ) -> Self {
        let next_sample = shape.as_mut().map_or(0, |samples| samples.start(&segment));
        Run {
            model,
            force,
            settings,
            u: segment.initial_state(),
            s: segment.s_start,
            s_end: segment.s_end,
            origin: segment.origin,
            p: order_for(settings.tol),
            inv_tol: 1.0 / settings.tol,
            inv_var_tol: 1.0 / settings.variational_tol,
            inv_m: 1.0 / settings.moment_scale.max(1.0),
            shape,
            next_sample,
            z: [[0.0; MAX_ORDER + 1]; N],
            sn: [0.0; MAX_ORDER + 1],
            cs: [0.0; MAX_ORDER + 1],
            kpsi: [0.0; MAX_ORDER + 1],
            law: (N == 4 && !model.is_plain()).then(|| Law::of(model)),
            aux: None,
            start: (0.0, (0.0, 0.0)),
            steps: 0,
        }
    }

    /// Steps to the segment's end.
    #[inline(always)]
    fn run_to_end(&mut self, meter: &mut Meter<'_>) -> Result<(), ShotFailure> {
        loop {
            let go = self.begin(meter)?;
            if !go {
                return Ok(());
            }
            self.step_begun(go)?;
        }
    }

    /// The rest of a step [`Run::begin`] has begun (`go`; nothing if it found the end).
    #[inline(always)]
    fn step_begun(&mut self, go: bool) -> Result<(), ShotFailure> {
        if go {
            self.coefficients();
            self.finish()?;
        }
        Ok(())
    }

    /// Begins a step: whether there is one to take (false at the segment's end), charged to
    /// `meter`, with the step's start in the series and, for the full beam, the law's own
    /// strain there (or its limit).
    #[inline(always)]
    fn begin(&mut self, meter: &mut Meter<'_>) -> Result<bool, ShotFailure> {
        if self.s >= self.s_end {
            return Ok(false);
        }
        if self.steps >= self.settings.max_steps {
            return Err(ShotFailure::StepBudget);
        }
        meter.tick_weighted(if self.law.is_some() {
            FULL_STEP_WEIGHT
        } else {
            STEP_WEIGHT
        })?;
        for i in 0..N {
            self.z[i][0] = self.u[i];
        }
        if self.law.is_some() {
            let (s0, c0) = crate::trig::sin_cos(self.u[0]);
            let (ax, ay) = (self.force.alpha_x, self.force.alpha_y);
            let (eps0, _, _) = self
                .model
                .axial_strain(ax * c0 + ay * s0)
                .map_err(ShotFailure::Material)?;
            self.start = (eps0, (s0, c0));
        }
        Ok(true)
    }

    /// The step's series.
    #[inline(always)]
    fn coefficients(&mut self) {
        let (ax, ay) = (self.force.alpha_x, self.force.alpha_y);
        match self.law {
            None => {
                let c = self.model.plate_compliance();
                let Run {
                    z, sn, cs, kpsi, p, ..
                } = self;
                coefficients::<N>(z, sn, cs, kpsi, *p, c, ax, ay);
            }
            Some(law) => {
                let (eps0, sc0) = self.start;
                // The state alone (`applies`): its four rows, so that the series are built
                // once, not once per state size. (Every state has them.)
                if let Some(state) = self.z.first_chunk_mut::<4>() {
                    let aux = self.aux.get_or_insert_with(Aux::default);
                    coefficients_full(state, aux, self.p, law.one(), eps0, sc0, ax, ay);
                }
            }
        }
    }

    /// [`Run::coefficients`] of this step and `other`'s, built side by side in the lanes of
    /// `aux` where both are the full beam's series of one kind and order (the elastica's
    /// keep their own loops).
    #[inline(always)]
    fn coefficients_with(&mut self, other: &mut Run<'_, '_, N>, pair: &mut PairSeries) {
        let laws = match (self.law, other.law) {
            (Some(la), Some(lb)) if self.p == other.p => Law::two(la, lb),
            _ => None,
        };
        let Some(law) = laws else {
            self.coefficients();
            other.coefficients();
            return;
        };
        let p = self.p;
        let two = |a: f64, b: f64| Two::new(a, b);
        let PairSeries { z, aux } = pair;
        for (i, row) in z.iter_mut().enumerate() {
            row[0] = two(self.z[i][0], other.z[i][0]);
        }
        let ((ea, (sa, ca)), (eb, (sb, cb))) = (self.start, other.start);
        let (fa, fb) = (self.force, other.force);
        coefficients_full(
            z,
            aux,
            p,
            law,
            two(ea, eb),
            (two(sa, sb), two(ca, cb)),
            two(fa.alpha_x, fb.alpha_x),
            two(fa.alpha_y, fb.alpha_y),
        );
        for (i, row) in z.iter().enumerate() {
            for (k, v) in row.iter().enumerate().take(p + 1).skip(1) {
                v.store(&mut self.z[i][k], &mut other.z[i][k]);
            }
        }
    }

    /// The weight of component `i`'s error (its value `value`): the inverse of its tolerance.
    #[inline(always)]
    fn weights(&self) -> impl Fn(usize, f64) -> f64 {
        let (inv_m, inv_tol, inv_var_tol) = (self.inv_m, self.inv_tol, self.inv_var_tol);
        move |i, value| match i {
            1 => inv_m * inv_tol,
            // The sensitivities only steer Newton and the stability test: their looser,
            // relative tolerance, as in the Runge-Kutta shot.
            _ if i >= 4 => inv_var_tol / (1.0 + value.abs()),
            _ => inv_tol,
        }
    }

    /// Ends a step whose series are built: its length, its samples, the state at its end.
    #[inline(always)]
    fn finish(&mut self) -> Result<(), ShotFailure> {
        let (p, u, z) = (self.p, self.u, &self.z);
        let weight = self.weights();
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
        let remaining = self.s_end - self.s;
        let mut h = h_limit;
        let last = h >= remaining - 1e-12;
        if last {
            h = remaining;
        } else if h < 1e-12 {
            return Err(ShotFailure::StepBudget);
        }
        let s_new = if last { self.s_end } else { self.s + h };
        if self.shape.is_some() {
            let step = Step {
                s: self.s,
                s_new,
                h,
                p,
                origin: self.origin,
            };
            // The sensitivities sampled: d(psi, x, y)/dM, and d(psi, x, y)/dpsi for N = 12.
            let next = &mut self.next_sample;
            if N == 12 {
                let which = [4, 6, 7, 8 % N, 10 % N, 11 % N];
                let weights = which.map(|i| weight(i, u[i]));
                if let Some(samples) = self.shape.as_mut() {
                    sample_step(z, which, weights, &step, samples, next);
                }
            } else if N > 4 {
                let which = [4, 6, 7];
                let weights = which.map(|i| weight(i, u[i]));
                if let Some(samples) = self.shape.as_mut() {
                    sample_step(z, which, weights, &step, samples, next);
                }
            } else if let Some(samples) = self.shape.as_mut() {
                // The state alone (N = 4): no sensitivities to sample.
                sample_step::<N, 0>(z, [], [], &step, samples, next);
            }
        }
        self.u = evaluate(z, std::array::from_fn(|i| i), p, h);
        self.s = s_new;
        self.steps += 1;
        Ok(())
    }

    /// The state at the segment's end and the steps taken.
    fn end(&self) -> Result<(State<N>, u32), ShotFailure> {
        if self.u.iter().any(|v| !v.is_finite()) {
            return Err(ShotFailure::NonFinite);
        }
        Ok((self.u, self.steps))
    }
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
