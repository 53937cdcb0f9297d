//! One shot: integrate the beam from the clamped root with a guessed root moment (the
//! Dormand-Prince integrator of any beam, and what every shot shares; [`super::shot`] picks the
//! integrator a model needs).
//!
//! Because the tip load keeps its direction, differentiating DESIGN's Eq. 3,
//! `M = beta + alpha_y (a - x) - alpha_x (b - y)`, along the beam gives
//!
//! ```text
//! dM/ds = -alpha_y dx/ds + alpha_x dy/ds = -(1 + eps) Q + gamma N
//! ```
//!
//! which no longer contains the unknown tip `(a, b)`. `(psi, M)` obey an autonomous 2-state
//! system and `x, y` follow by quadrature, so a shot over a segment of the beam needs only
//! `(psi, M)` at its start. Each shot also integrates the variational equations (the
//! derivatives of the state with respect to the starting `psi` and `M`), which give Newton
//! its exact Jacobian and the tip's sensitivity for free.
//!
//! The integrator is the Dormand-Prince 5(4) pair with local error control on
//! `psi, x, y` (absolute, units of L and radians) and `M` (relative to the load), the
//! first-same-as-last property, and cubic Hermite dense output for the shape samples.
//!
//! ## References
//! - J. R. Dormand, P. J. Prince, "A family of embedded Runge-Kutta formulae",
//!   J. Comput. Appl. Math. 6 (1980) 19-26.
//! - E. Reissner, "On one-dimensional finite-strain beam theory: the plane problem",
//!   ZAMP 23 (1972) 795-804.

use super::model::{BeamModel, MaterialLimit};
use super::ShapePoint;
use crate::cancel::CancelToken;

/// State layout: `psi, M, x, y`, then their derivatives with respect to the starting `M`
/// (slots 4..8) and, when `N = 12`, to the starting `psi` (slots 8..12). A shot from the
/// clamp (where `psi = 0` is known) needs only the first eight. With `N = 16` the slots
/// 8..12 and 12..16 are the derivatives with respect to the tip force's `alpha_x` and
/// `alpha_y` instead (a root shot whose force is itself an unknown: [`root_shot`]).
pub(crate) type State<const N: usize> = [f64; N];
const PSI: usize = 0;
const MOM: usize = 1;
const X: usize = 2;
const Y: usize = 3;

/// The end of one shot: the state at `s = L` and the work it took.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Shot {
    pub end: State<12>,
    pub steps: u32,
}

/// Why a shot could not reach the tip.
#[derive(Debug, Clone, Copy)]
pub(crate) enum ShotFailure {
    Material(MaterialLimit),
    /// The step size collapsed or the step budget ran out (a wildly wrong guess).
    StepBudget,
    NonFinite,
    /// The solve's effort budget of integration steps ran out.
    OutOfEffort,
    Cancelled,
}

/// Counts the integration steps (accepted or not) of every shot of one solve against its
/// budget, and watches the cancel flag, so no shot can run away with the CPU.
pub(crate) struct Meter<'a> {
    /// Integration steps tried.
    pub tries: u64,
    /// Their cost, in units of an elastica step: `weight` per step.
    pub cost: u64,
    pub weight: u64,
    /// The most `cost` allowed.
    pub limit: u64,
    pub cancel: &'a CancelToken,
}

impl<'a> Meter<'a> {
    /// Steps between looks at the cancel flag: a few microseconds of work.
    const CANCEL_STRIDE: u64 = 64;

    /// A meter for one load case of `model`, allowing `limit` integration steps (the
    /// [`EffortBudget`](super::EffortBudget)'s `rk_steps`).
    pub(crate) fn new(limit: u64, model: &BeamModel, cancel: &'a CancelToken) -> Meter<'a> {
        Meter {
            tries: 0,
            cost: 0,
            // Poisson's law solves an equation for the strain at every evaluation.
            weight: if model.effects.poisson { 2 } else { 1 },
            limit,
            cancel,
        }
    }

    #[inline]
    fn tick(&mut self) -> Result<(), ShotFailure> {
        self.tick_weighted(self.weight)
    }

    /// Charges one integration step that costs `weight` elastica steps.
    #[inline]
    pub(crate) fn tick_weighted(&mut self, weight: u64) -> Result<(), ShotFailure> {
        if self.cost + weight > self.limit {
            return Err(ShotFailure::OutOfEffort);
        }
        self.tries += 1;
        self.cost += weight;
        if self.tries.is_multiple_of(Self::CANCEL_STRIDE) && self.cancel.is_cancelled() {
            return Err(ShotFailure::Cancelled);
        }
        Ok(())
    }
}

/// A tip load in the nondimensional core.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TipForce {
    pub alpha_x: f64,
    pub alpha_y: f64,
}

#[inline]
pub(crate) fn rhs<const N: usize>(
    model: &BeamModel,
    f: TipForce,
    u: &State<N>,
) -> Result<State<N>, MaterialLimit> {
    let (sn, cs) = crate::trig::sin_cos(u[PSI]);
    let m = u[MOM];
    let n = f.alpha_x * cs + f.alpha_y * sn;
    let q = -f.alpha_x * sn + f.alpha_y * cs;
    let (eps, de_dn, p) = model.axial_strain(n)?;
    // d/dpsi of N is Q and of Q is -N.
    let eps_psi = de_dn * q;
    // One division for every power of 1/p below.
    let inv_p = if model.effects.poisson { 1.0 / p } else { 1.0 };
    let inv_p2 = inv_p * inv_p;
    let plate = model.plate_compliance();
    let (p_psi, bend_compliance) = if model.effects.poisson {
        (-model.nu * eps_psi, plate * inv_p2 * inv_p2)
    } else {
        (0.0, plate)
    };
    let (gamma, gamma_psi) = if model.effects.shear {
        let c_s = model.shear_compliance();
        (
            c_s * q * inv_p2,
            c_s * (-n * inv_p2 - 2.0 * q * p_psi * inv_p2 * inv_p),
        )
    } else {
        (0.0, 0.0)
    };
    let stretch = 1.0 + eps;
    let dx = stretch * cs - gamma * sn;
    let dy = stretch * sn + gamma * cs;
    let dpsi = m * bend_compliance;
    let dm = -stretch * q + gamma * n;

    // Variational equations, linearised about this state.
    let f1_psi = -4.0 * m * p_psi * bend_compliance * inv_p;
    let f2_psi = -eps_psi * q + stretch * n + gamma_psi * n + gamma * q;
    let dx_psi = eps_psi * cs - stretch * sn - gamma_psi * sn - gamma * cs;
    let dy_psi = eps_psi * sn + stretch * cs + gamma_psi * cs - gamma * sn;
    let mut out = [0.0; N];
    out[0] = dpsi;
    out[1] = dm;
    out[2] = dx;
    out[3] = dy;
    for base in (4..N).step_by(4) {
        let (v_psi, v_m) = (u[base], u[base + 1]);
        out[base] = f1_psi * v_psi + bend_compliance * v_m;
        out[base + 1] = f2_psi * v_psi;
        out[base + 2] = dx_psi * v_psi;
        out[base + 3] = dy_psi * v_psi;
    }
    if N == 16 {
        // The force's own terms: the right-hand side's partial derivatives with respect to
        // the section forces N and Q at fixed psi, M (the psi-derivatives above are these
        // chained through N_psi = Q, Q_psi = -N), chained through N_ax = cos, Q_ax = -sin,
        // N_ay = sin, Q_ay = cos.
        let d_n = de_dn;
        let p_n = if model.effects.poisson {
            -model.nu * d_n
        } else {
            0.0
        };
        let bc_n = -4.0 * bend_compliance * inv_p * p_n;
        let (g_n, g_q) = if model.effects.shear {
            let c_s = model.shear_compliance();
            (-2.0 * c_s * q * inv_p2 * inv_p * p_n, c_s * inv_p2)
        } else {
            (0.0, 0.0)
        };
        let d_n_row = [
            m * bc_n,
            -d_n * q + g_n * n + gamma,
            d_n * cs - g_n * sn,
            d_n * sn + g_n * cs,
        ];
        let d_q_row = [0.0, -stretch + g_q * n, -g_q * sn, g_q * cs];
        for k in 0..4 {
            out[8 + k] += d_n_row[k] * cs - d_q_row[k] * sn;
            out[12 + k] += d_n_row[k] * sn + d_q_row[k] * cs;
        }
    }
    Ok(out)
}

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

/// Integration settings of one shot.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ShotSettings {
    /// Local error tolerance (absolute on `psi, x, y`).
    pub tol: f64,
    /// Relative tolerance of the sensitivities (Newton's slope, the stability test).
    pub variational_tol: f64,
    /// Scale of the bending moment, for the relative error test on `M`.
    pub moment_scale: f64,
    /// First trial step.
    pub h0: f64,
    pub max_steps: u32,
}

/// Where a shot starts and ends on the beam.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub s_start: f64,
    pub s_end: f64,
    /// `psi` and `M` at `s_start`.
    pub psi: f64,
    pub moment: f64,
    /// Position of the segment's start, added to the shape samples.
    pub origin: (f64, f64),
}

impl Segment {
    /// The whole beam from its clamp (at the origin, along +x) with the root moment `moment`.
    pub(crate) fn from_clamp(moment: f64) -> Segment {
        Segment {
            s_start: 0.0,
            s_end: 1.0,
            psi: 0.0,
            moment,
            origin: (0.0, 0.0),
        }
    }

    /// The state a shot of this segment starts from: `psi` and `M` given, positions zero
    /// (they are increments), the sensitivities the identity (slot 5, `dM/dM`, unless `N = 4`,
    /// the state alone; and slot 8, `dpsi/dpsi`, when `N = 12`).
    pub(crate) fn initial_state<const N: usize>(&self) -> State<N> {
        let mut u: State<N> = [0.0; N];
        u[PSI] = self.psi;
        u[MOM] = self.moment;
        if N > 4 {
            u[5] = 1.0;
        }
        if N == 12 {
            u[8] = 1.0;
        }
        u
    }
}

/// Shape samples: uniform in `s` over the whole beam, `count` of them (root and tip
/// included); a shot appends those inside its segment.
pub(crate) struct Samples<'a> {
    pub points: &'a mut Vec<ShapePoint>,
    pub count: usize,
    /// With each sample, if asked, its sensitivities: `(psi, x, y)` (`x, y` relative to the
    /// segment's start) differentiated with respect to the segment's starting `M` and then
    /// its starting `psi` (zero for the clamped first segment), so that Newton can carry its
    /// last update to the shape linearly.
    pub sensitivities: Option<&'a mut Vec<[f64; 6]>>,
}

impl Samples<'_> {
    /// Readies the samples for a shot of `segment`: the clamp's own sample when the segment
    /// starts there (it does not move: zero sensitivities), and the index of the first
    /// sample the shot owes (samples on a segment boundary belong to the segment that ends
    /// there).
    pub(crate) fn start(&mut self, segment: &Segment) -> usize {
        let spacing = 1.0 / (self.count - 1) as f64;
        if segment.s_start != 0.0 {
            return (segment.s_start / spacing + 1e-9).floor() as usize + 1;
        }
        self.points.push(ShapePoint {
            s: 0.0,
            x: segment.origin.0,
            y: segment.origin.1,
            psi: segment.psi,
        });
        if let Some(sens) = self.sensitivities.as_mut() {
            sens.push([0.0; 6]);
        }
        1
    }
}

/// One segment's integration by the Dormand-Prince pair ([`super::shot`] chooses the
/// integrator), returning the whole end state. Position states start at zero (they are
/// increments), the sensitivities at the identity. Every attempted step is charged to
/// `meter`.
pub(crate) fn integrate<const N: usize>(
    model: &BeamModel,
    force: TipForce,
    segment: Segment,
    settings: ShotSettings,
    mut shape: Option<Samples<'_>>,
    meter: &mut Meter<'_>,
) -> Result<(State<N>, u32), ShotFailure> {
    let mut u: State<N> = segment.initial_state();
    let mut k1 = rhs(model, force, &u).map_err(ShotFailure::Material)?;
    let mut s = segment.s_start;
    let s_end = segment.s_end;
    let mut h = settings.h0.clamp(1e-6, MAX_STEP);
    let inv_tol = 1.0 / settings.tol;
    let inv_var_tol = 1.0 / settings.variational_tol;
    let inv_m = 1.0 / settings.moment_scale.max(1.0);
    let (ox, oy) = segment.origin;
    // The next sample index to emit, and the second derivatives at the step's start.
    let mut next_sample = 0usize;
    let mut g0 = [0.0; 4];
    if let Some(samples) = shape.as_mut() {
        g0 = second_derivatives(model, force, &u, &k1)?;
        next_sample = samples.start(&segment);
    }
    let mut steps = 0u32;
    let mut tries = 0u32;
    while s < s_end {
        tries += 1;
        if tries > settings.max_steps || h < 1e-12 {
            return Err(ShotFailure::StepBudget);
        }
        meter.tick()?;
        let last = s + h >= s_end - 1e-12;
        if last {
            h = s_end - s;
        }
        let stage = |v: State<N>| rhs(model, force, &v).map_err(ShotFailure::Material);
        // Stage arguments written out so that each is one fused, vectorisable loop.
        let k2 = stage(std::array::from_fn(|i| u[i] + h * (A21 * k1[i])))?;
        let k3 = stage(std::array::from_fn(|i| {
            u[i] + h * (A31 * k1[i] + A32 * k2[i])
        }))?;
        let k4 = stage(std::array::from_fn(|i| {
            u[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i])
        }))?;
        let k5 = stage(std::array::from_fn(|i| {
            u[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
        }))?;
        let k6 = stage(std::array::from_fn(|i| {
            u[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i])
        }))?;
        let u_new: State<N> = std::array::from_fn(|i| {
            u[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i])
        });
        let k7 = stage(u_new)?;
        let mut ratio = 0.0_f64;
        for i in 0..N {
            let e =
                h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let w = match i {
                MOM => inv_m * inv_tol,
                // The sensitivities only steer Newton and the stability test, so they are
                // held to a looser, relative tolerance.
                _ if i >= 4 => inv_var_tol / (1.0 + u_new[i].abs()),
                _ => inv_tol,
            };
            ratio = ratio.max((e * w).abs());
        }
        if !ratio.is_finite() {
            return Err(ShotFailure::NonFinite);
        }
        if ratio <= 1.0 {
            let s_new = if last { s_end } else { s + h };
            if let Some(samples) = shape.as_mut() {
                let g1 = second_derivatives(model, force, &u_new, &k7)?;
                let n = samples.count;
                while next_sample < n {
                    let sj = next_sample as f64 / (n - 1) as f64;
                    if sj > s_new + 1e-12 {
                        break;
                    }
                    let mut point = hermite(s, h, &u, &k1, &g0, &u_new, &k7, &g1, sj);
                    point.x += ox;
                    point.y += oy;
                    samples.points.push(point);
                    if let Some(sens) = samples.sensitivities.as_mut() {
                        sens.push(sensitivities_at(s, h, &u, &k1, &u_new, &k7, sj));
                    }
                    next_sample += 1;
                }
                g0 = g1;
            }
            s = s_new;
            u = u_new;
            k1 = k7;
            steps += 1;
        }
        // Standard step-size controller for a fifth-order pair.
        let factor = if ratio == 0.0 {
            5.0
        } else {
            (0.9 * ratio.powf(-0.2)).clamp(0.2, 5.0)
        };
        h = (h * factor).min(MAX_STEP);
    }
    if u.iter().any(|v| !v.is_finite()) {
        return Err(ShotFailure::NonFinite);
    }
    Ok((u, steps))
}

/// Second derivatives `(psi'', M'', x'', y'')` from the linearisation: the variational
/// right-hand side applied to the direction `(psi', M')`.
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
