//! The Dormand-Prince 5(4) integrator of one segment of any beam (the state, right-hand side,
//! settings and samples are [`super::shoot`]'s): local error control on `psi, x, y`
//! (absolute, units of L and radians) and `M` (relative to the load), the
//! first-same-as-last property, and quintic Hermite dense output for the shape samples (cubic
//! for their sensitivities).
//!
//! A shot is a [`Lane`], its whole state between steps, so that two independent shots (a
//! mechanism's two flexures) can be integrated side by side ([`integrate_pair`]): one shot
//! alone waits on each stage's chain of dependent arithmetic, two interleaved fill the wait,
//! and each gives exactly the numbers it gives alone.
//!
//! ## References
//! - J. R. Dormand, P. J. Prince, "A family of embedded Runge-Kutta formulae",
//!   J. Comput. Appl. Math. 6 (1980) 19-26.

use super::model::{BeamModel, MaterialLimit};
use super::shoot::{
    rhs, rhs_lanes, Meter, Samples, Segment, ShotFailure, ShotSettings, State, TipForce, MOM, PSI,
    X, Y,
};
use super::ShapePoint;

// Dormand-Prince 5(4) tableau (the nodes c_i are not needed: the system is autonomous).
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// Error coefficients: fifth-order minus fourth-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// Longest step: keeps the dense output of the shape accurate even where the error
/// estimate alone would allow one step over the whole beam (a pure moment).
const MAX_STEP: f64 = 0.1;

/// One segment's integration by the Dormand-Prince pair ([`super::shot`] chooses the
/// integrator), returning the whole end state. Position states start at zero (they are
/// increments), the sensitivities at the identity. Every attempted step is charged to
/// `meter`.
pub(crate) fn integrate<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    let mut lane = Lane::new(model, force, segment, settings, shape)?;
    lane.run(meter)?;
    lane.end()
}

/// One shot to integrate: its beam, force, segment, settings and samples (as
/// [`integrate`] takes them).
pub(crate) struct ShotSpec<'a, 's> {
    pub model: &'a BeamModel,
    pub force: TipForce,
    pub segment: Segment,
    pub settings: ShotSettings,
    pub shape: Option<Samples<'s>>,
}

impl<'a, 's> ShotSpec<'a, 's> {
    fn lane<const N: usize>(self) -> Result<Lane<'a, 's, N>, ShotFailure> {
        Lane::new(
            self.model,
            self.force,
            self.segment,
            self.settings,
            self.shape,
        )
    }
}

/// Two independent shots integrated together: each exactly as [`integrate`] would
/// integrate it alone (its own steps, errors and samples, bit for bit), but stage by stage
/// side by side, so that the processor overlaps the two right-hand sides' long chains of
/// dependent arithmetic (one shot alone leaves most of its units idle: each stage waits on
/// the one before). A mechanism's flexures are evaluated this way in pairs.
pub(crate) fn integrate_pair<const N: usize>(
    shots: [ShotSpec<'_, '_>; 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::wide() {
        // SAFETY: `wide` has just checked that this processor has AVX2 and FMA.
        return unsafe { integrate_pair_wide::<N>(shots, meters) };
    }
    integrate_pair_any::<N>(shots, meters)
}

/// [`integrate_pair`] compiled with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn integrate_pair_wide<const N: usize>(
    shots: [ShotSpec<'_, '_>; 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    integrate_pair_any::<N>(shots, meters)
}

#[inline(always)]
fn integrate_pair_any<const N: usize>(
    shots: [ShotSpec<'_, '_>; 2],
    meters: [&mut Meter<'_>; 2],
) -> [Result<(State<N>, u32), ShotFailure>; 2] {
    let [a, b] = shots;
    let [meter_a, meter_b] = meters;
    let mut lanes = match (a.lane(), b.lane()) {
        (Ok(a), Ok(b)) => [a, b],
        (a, b) => return [finish_alone(a, meter_a), finish_alone(b, meter_b)],
    };
    loop {
        let [a, b] = &mut lanes;
        match (a.attempt(meter_a), b.attempt(meter_b)) {
            (Ok(true), Ok(true)) => {
                let [fa, fb] = trial_steps(&mut lanes);
                let [a, b] = &mut lanes;
                match (a.accept(fa), b.accept(fb)) {
                    (Ok(()), Ok(())) => {}
                    (sa, sb) => {
                        let [a, b] = lanes;
                        return [
                            sa.and_then(|()| finish_alone(Ok(a), meter_a)),
                            sb.and_then(|()| finish_alone(Ok(b), meter_b)),
                        ];
                    }
                }
            }
            // One lane has ended (or failed) before this attempt: the other goes on alone,
            // its attempt already charged.
            (ga, gb) => {
                let [mut a, mut b] = lanes;
                let a = ga
                    .and_then(|go| if go { a.step() } else { Ok(()) })
                    .and_then(|()| finish_alone(Ok(a), meter_a));
                let b = gb
                    .and_then(|go| if go { b.step() } else { Ok(()) })
                    .and_then(|()| finish_alone(Ok(b), meter_b));
                return [a, b];
            }
        }
    }
}

/// Integrates a lane to its end on its own.
fn finish_alone<const N: usize>(
    lane: Result<Lane<'_, '_, N>, ShotFailure>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    let mut lane = lane?;
    lane.run(meter)?;
    lane.end()
}

/// One shot in progress: the integrator's whole state between steps.
struct Lane<'a, 's, const N: usize> {
    model: &'a BeamModel,
    force: TipForce,
    u: State<N>,
    /// The right-hand side at `u` (first same as last).
    k1: State<N>,
    s: f64,
    s_end: f64,
    h: f64,
    /// Whether the step being attempted ends the segment.
    last: bool,
    inv_tol: f64,
    inv_var_tol: f64,
    inv_m: f64,
    max_steps: u32,
    origin: (f64, f64),
    shape: Option<Samples<'s>>,
    /// The next sample index to emit, and the second derivatives at the step's start.
    next_sample: usize,
    g0: [f64; 4],
    steps: u32,
    tries: u32,
    /// The step attempted: its end state, the right-hand side there and its error over the
    /// tolerance.
    u_new: State<N>,
    k7: State<N>,
    /// The second derivatives at `u_new` (where the lane samples its shape).
    g_new: [f64; 4],
    ratio: f64,
}

impl<'a, 's, const N: usize> Lane<'a, 's, N> {
    fn new(
        model: &'a BeamModel,
        force: TipForce,
        segment: Segment,
        settings: ShotSettings,
        mut shape: Option<Samples<'s>>,
    ) -> Result<Self, ShotFailure> {
        let u: State<N> = segment.initial_state();
        let k1 = rhs(model, force, &u).map_err(ShotFailure::Material)?;
        let mut next_sample = 0usize;
        let mut g0 = [0.0; 4];
        if let Some(samples) = shape.as_mut() {
            g0 = second_derivatives(model, force, &u, &k1)?;
            next_sample = samples.start(&segment);
        }
        Ok(Lane {
            model,
            force,
            u,
            k1,
            s: segment.s_start,
            s_end: segment.s_end,
            h: settings.h0.clamp(1e-6, MAX_STEP),
            last: false,
            inv_tol: 1.0 / settings.tol,
            inv_var_tol: 1.0 / settings.variational_tol,
            inv_m: 1.0 / settings.moment_scale.max(1.0),
            max_steps: settings.max_steps,
            origin: segment.origin,
            shape,
            next_sample,
            g0,
            steps: 0,
            tries: 0,
            u_new: [0.0; N],
            k7: [0.0; N],
            g_new: [0.0; 4],
            ratio: 0.0,
        })
    }

    /// Steps to the segment's end.
    fn run(&mut self, meter: &mut Meter<'_>) -> Result<(), ShotFailure> {
        while self.attempt(meter)? {
            self.step()?;
        }
        Ok(())
    }

    /// The step [`Lane::attempt`] readied, on its own.
    fn step(&mut self) -> Result<(), ShotFailure> {
        let [failed] = trial_steps(std::array::from_mut(self));
        self.accept(failed)
    }

    /// Readies the next attempted step, charging it to `meter`: false once the segment's end
    /// is reached.
    #[inline(always)]
    fn attempt(&mut self, meter: &mut Meter<'_>) -> Result<bool, ShotFailure> {
        // Written as the old loop's `while s < s_end`, which also ends at once on a NaN end.
        let going = self.s < self.s_end;
        if !going {
            return Ok(false);
        }
        self.tries += 1;
        if self.tries > self.max_steps || self.h < 1e-12 {
            return Err(ShotFailure::StepBudget);
        }
        meter.tick()?;
        self.last = self.s + self.h >= self.s_end - 1e-12;
        if self.last {
            self.h = self.s_end - self.s;
        }
        Ok(true)
    }

    /// The error test of the step attempted ([`trial_steps`], which failed if `failed`), its
    /// samples if it is accepted, and the next step size.
    #[inline(always)]
    fn accept(&mut self, failed: Option<MaterialLimit>) -> Result<(), ShotFailure> {
        if let Some(e) = failed {
            return Err(ShotFailure::Material(e));
        }
        let (ratio, u_new, k7) = (self.ratio, &self.u_new, &self.k7);
        let h = self.h;
        if !ratio.is_finite() {
            return Err(ShotFailure::NonFinite);
        }
        if ratio <= 1.0 {
            let s = self.s;
            let s_new = if self.last { self.s_end } else { s + h };
            if let Some(samples) = self.shape.as_mut() {
                let g1 = self.g_new;
                let n = samples.count;
                let (ox, oy) = self.origin;
                while self.next_sample < n {
                    let sj = self.next_sample as f64 / (n - 1) as f64;
                    if sj > s_new + 1e-12 {
                        break;
                    }
                    let (u, k1, g0) = (&self.u, &self.k1, &self.g0);
                    let mut point = hermite(s, h, u, k1, g0, u_new, k7, &g1, sj);
                    point.x += ox;
                    point.y += oy;
                    samples.points.push(point);
                    if let Some(sens) = samples.sensitivities.as_mut() {
                        sens.push(sensitivities_at(s, h, u, k1, u_new, k7, sj));
                    }
                    self.next_sample += 1;
                }
                self.g0 = g1;
            }
            self.s = s_new;
            self.u = self.u_new;
            self.k1 = self.k7;
            self.steps += 1;
        }
        // Standard step-size controller for a fifth-order pair.
        let factor = if ratio == 0.0 {
            5.0
        } else {
            (0.9 * ratio.powf(-0.2)).clamp(0.2, 5.0)
        };
        self.h = (h * factor).min(MAX_STEP);
        Ok(())
    }

    /// The end state and the accepted steps.
    fn end(self) -> Result<(State<N>, u32), ShotFailure> {
        if self.u.iter().any(|v| !v.is_finite()) {
            return Err(ShotFailure::NonFinite);
        }
        Ok((self.u, self.steps))
    }
}

/// Each lane's attempted step ([`Lane::u_new`], [`Lane::k7`], [`Lane::ratio`]), computed
/// stage by stage across the lanes (the lanes' arithmetic is independent, so each lane's
/// result is what it would be alone). A lane whose right-hand side has no state (the
/// material law) fails with it: its failure is returned, and the rest of its step is not
/// read.
#[inline(always)]
fn trial_steps<const N: usize, const L: usize>(
    lanes: &mut [Lane<'_, '_, N>; L],
) -> [Option<MaterialLimit>; L] {
    let mut failed: [Option<MaterialLimit>; L] = [None; L];
    let model: [&BeamModel; L] = std::array::from_fn(|l| lanes[l].model);
    let force: [TipForce; L] = std::array::from_fn(|l| lanes[l].force);
    let h: [f64; L] = std::array::from_fn(|l| lanes[l].h);
    // k[0] is the step's first stage (the right-hand side at its start), k[1..6] the rest.
    let mut k = [[[0.0; N]; L]; 6];
    for l in 0..L {
        k[0][l] = lanes[l].k1;
    }
    let mut v = [[0.0; N]; L];
    // Stage `j` (1 to 5) from its argument `u + h sum(a_i k_i)` with the row `a` of the
    // tableau; a lane that has failed goes on with zeros, unread.
    let rows: [&[f64]; 5] = [
        &[A21],
        &[A31, A32],
        &[A41, A42, A43],
        &[A51, A52, A53, A54],
        &[A61, A62, A63, A64, A65],
    ];
    for (j, a) in rows.iter().enumerate() {
        for l in 0..L {
            for i in 0..N {
                let mut sum = a[0] * k[0][l][i];
                for (q, &a_q) in a.iter().enumerate().skip(1) {
                    sum += a_q * k[q][l][i];
                }
                v[l][i] = lanes[l].u[i] + h[l] * sum;
            }
        }
        let out = rhs_lanes(model, force, std::array::from_fn(|l| &v[l]), None);
        for l in 0..L {
            match out[l] {
                Ok(kl) if failed[l].is_none() => k[j + 1][l] = kl,
                Ok(_) => {}
                Err(e) => {
                    failed[l].get_or_insert(e);
                }
            }
        }
    }
    // The new state: the sixth row's weights (b2 is zero), and its right-hand side.
    for (l, lane) in lanes.iter_mut().enumerate() {
        #[allow(clippy::needless_range_loop)] // `i` indexes five arrays alike
        for i in 0..N {
            lane.u_new[i] = lane.u[i]
                + h[l]
                    * (B1 * k[0][l][i]
                        + B3 * k[2][l][i]
                        + B4 * k[3][l][i]
                        + B5 * k[4][l][i]
                        + B6 * k[5][l][i]);
        }
    }
    // With the new state's second derivatives where a lane samples its shape.
    let mut g = [[0.0; 4]; L];
    let sampling = lanes.iter().any(|l| l.shape.is_some());
    let out = rhs_lanes(
        model,
        force,
        std::array::from_fn(|l| &lanes[l].u_new),
        sampling.then_some(&mut g),
    );
    for l in 0..L {
        let k7 = match out[l] {
            Ok(k7) => k7,
            Err(e) => {
                failed[l].get_or_insert(e);
                continue;
            }
        };
        let lane = &mut lanes[l];
        let mut ratio = 0.0_f64;
        for i in 0..N {
            let e = h[l]
                * (E1 * k[0][l][i]
                    + E3 * k[2][l][i]
                    + E4 * k[3][l][i]
                    + E5 * k[4][l][i]
                    + E6 * k[5][l][i]
                    + E7 * k7[i]);
            let w = match i {
                MOM => lane.inv_m * lane.inv_tol,
                // The sensitivities only steer Newton and the stability test, so they are
                // held to a looser, relative tolerance.
                _ if i >= 4 => lane.inv_var_tol / (1.0 + lane.u_new[i].abs()),
                _ => lane.inv_tol,
            };
            ratio = ratio.max((e * w).abs());
        }
        lane.k7 = k7;
        lane.g_new = g[l];
        lane.ratio = ratio;
    }
    failed
}

/// Second derivatives `(psi'', M'', x'', y'')` from the linearisation: the variational
/// right-hand side applied to the direction `(psi', M')`.
#[inline(always)]
fn second_derivatives<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    u: &State<N>,
    f: &State<N>,
) -> Result<[f64; 4], ShotFailure> {
    // The direction's variational right-hand side needs only the state and the direction
    // (`x, y` do not enter it): one column of it, whatever the shot carries.
    let mut probe = [0.0; 8];
    probe[..4].copy_from_slice(&u[..4]);
    probe[4] = f[PSI];
    probe[5] = f[MOM];
    let d = rhs(model, force, &probe).map_err(ShotFailure::Material)?;
    Ok([d[4], d[5], d[6], d[7]])
}

/// Cubic Hermite interpolation of the sensitivities of `psi, x, y` inside one accepted step
/// (the layout of [`Samples::sensitivities`]). They only carry Newton's last update, which is
/// already small, so the interpolation's O(h^4) error is negligible in the shape.
#[inline(always)]
fn sensitivities_at<const N: usize>(
    s0: f64,
    h: f64,
    u0: &State<N>,
    f0: &State<N>,
    u1: &State<N>,
    f1: &State<N>,
    s: f64,
) -> [f64; 6] {
    let t = ((s - s0) / h).clamp(0.0, 1.0);
    let t2 = t * t;
    let t3 = t2 * t;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = 3.0 * t2 - 2.0 * t3;
    let h11 = t3 - t2;
    let interp = |i: usize| {
        if i < N {
            h00 * u0[i] + h10 * h * f0[i] + h01 * u1[i] + h11 * h * f1[i]
        } else {
            0.0
        }
    };
    // Slots 4, 6, 7: d(psi, x, y)/dM; 8, 10, 11: d(psi, x, y)/dpsi (N = 12 only).
    [
        interp(4),
        interp(6),
        interp(7),
        if N == 12 { interp(8) } else { 0.0 },
        if N == 12 { interp(10) } else { 0.0 },
        if N == 12 { interp(11) } else { 0.0 },
    ]
}

/// Quintic Hermite interpolation of `psi, x, y` inside one accepted step, from values, first
/// and second derivatives at both ends (local error O(h^6)).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn hermite<const N: usize>(
    s0: f64,
    h: f64,
    u0: &State<N>,
    f0: &State<N>,
    g0: &[f64; 4],
    u1: &State<N>,
    f1: &State<N>,
    g1: &[f64; 4],
    s: f64,
) -> ShapePoint {
    let t = ((s - s0) / h).clamp(0.0, 1.0);
    let t2 = t * t;
    let t3 = t2 * t;
    let t4 = t3 * t;
    let t5 = t4 * t;
    let h0 = 1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5;
    let h1 = t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5;
    let h2 = 0.5 * t2 - 1.5 * t3 + 1.5 * t4 - 0.5 * t5;
    let h3 = 0.5 * t3 - t4 + 0.5 * t5;
    let h4 = -4.0 * t3 + 7.0 * t4 - 3.0 * t5;
    let h5 = 10.0 * t3 - 15.0 * t4 + 6.0 * t5;
    let hh = h * h;
    // Index i of the state; index j of the second-derivative array.
    let interp = |i: usize, j: usize| {
        h0 * u0[i]
            + h1 * h * f0[i]
            + h2 * hh * g0[j]
            + h3 * hh * g1[j]
            + h4 * h * f1[i]
            + h5 * u1[i]
    };
    ShapePoint {
        s,
        x: interp(X, 2),
        y: interp(Y, 3),
        psi: interp(PSI, 0),
    }
}
