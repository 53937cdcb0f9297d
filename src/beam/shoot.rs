//! One shot: integrate the beam from the clamped root with a guessed root moment. What every
//! shot shares: the state layout, the right-hand side and its variational equations, the
//! settings, segments, shape samples and the effort meter. The integrators are
//! [`super::dopri`] (any beam) and [`super::taylor`] (the plain-bending beam);
//! [`super::shot`] picks the one a model needs.
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
//! ## References
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
pub(crate) const PSI: usize = 0;
pub(crate) const MOM: usize = 1;
pub(crate) const X: usize = 2;
pub(crate) const Y: usize = 3;

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
    pub(crate) fn tick(&mut self) -> Result<(), ShotFailure> {
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

/// `[f(0), f(1), ...]` over the lanes: an array of `L` starting at `init`, filled by a loop
/// (which the compiler unrolls and interleaves; `std::array::from_fn` is not always inlined).
macro_rules! each {
    ($init:expr, |$l:ident| $e:expr) => {{
        let mut out = [$init; L];
        for $l in 0..L {
            out[$l] = $e;
        }
        out
    }};
}

/// The right-hand side of the shot's state (and, for `N > 4`, its variational equations) for
/// one beam.
#[inline(always)]
pub(crate) fn rhs<const N: usize>(
    model: &BeamModel,
    f: TipForce,
    u: &State<N>,
) -> Result<State<N>, MaterialLimit> {
    let [out] = rhs_lanes([model], [f], [u], None);
    out
}

/// [`rhs`] of `L` independent beams (lanes), written operation by operation across the lanes
/// so that the processor overlaps their chains of dependent arithmetic; each lane's result
/// is exactly what [`rhs`] gives it alone.
#[inline(always)]
pub(crate) fn rhs_lanes<const N: usize, const L: usize>(
    model: [&BeamModel; L],
    f: [TipForce; L],
    u: [&State<N>; L],
    second: Option<&mut [[f64; 4]; L]>,
) -> [Result<State<N>, MaterialLimit>; L] {
    let trig: [(f64, f64); L] = each!((0.0, 0.0), |l| crate::trig::sin_cos(u[l][PSI]));
    let sn: [f64; L] = each!(0.0, |l| trig[l].0);
    let cs: [f64; L] = each!(0.0, |l| trig[l].1);
    let m: [f64; L] = each!(0.0, |l| u[l][MOM]);
    let n: [f64; L] = each!(0.0, |l| f[l].alpha_x * cs[l] + f[l].alpha_y * sn[l]);
    let q: [f64; L] = each!(0.0, |l| -f[l].alpha_x * sn[l] + f[l].alpha_y * cs[l]);
    let strain: [Result<(f64, f64, f64), MaterialLimit>; L] =
        each!(Ok((0.0, 0.0, 1.0)), |l| model[l].axial_strain(n[l]));
    let eps: [f64; L] = each!(0.0, |l| strain[l].map_or(0.0, |s| s.0));
    let de_dn: [f64; L] = each!(0.0, |l| strain[l].map_or(0.0, |s| s.1));
    let p: [f64; L] = each!(0.0, |l| strain[l].map_or(1.0, |s| s.2));
    let poisson: [bool; L] = each!(false, |l| model[l].effects.poisson);
    let shear: [bool; L] = each!(false, |l| model[l].effects.shear);
    // d/dpsi of N is Q and of Q is -N.
    let eps_psi: [f64; L] = each!(0.0, |l| de_dn[l] * q[l]);
    // One division for every power of 1/p below.
    let inv_p: [f64; L] = each!(0.0, |l| if poisson[l] { 1.0 / p[l] } else { 1.0 });
    let inv_p2: [f64; L] = each!(0.0, |l| inv_p[l] * inv_p[l]);
    let plate: [f64; L] = each!(0.0, |l| model[l].plate_compliance());
    let p_psi: [f64; L] = each!(0.0, |l| {
        if poisson[l] {
            -model[l].nu * eps_psi[l]
        } else {
            0.0
        }
    });
    let bend_compliance: [f64; L] = each!(0.0, |l| {
        if poisson[l] {
            plate[l] * inv_p2[l] * inv_p2[l]
        } else {
            plate[l]
        }
    });
    let c_s: [f64; L] = each!(0.0, |l| model[l].shear_compliance());
    let gamma: [f64; L] = each!(0.0, |l| {
        if shear[l] {
            c_s[l] * q[l] * inv_p2[l]
        } else {
            0.0
        }
    });
    let gamma_psi: [f64; L] = each!(0.0, |l| {
        if shear[l] {
            c_s[l] * (-n[l] * inv_p2[l] - 2.0 * q[l] * p_psi[l] * inv_p2[l] * inv_p[l])
        } else {
            0.0
        }
    });
    let stretch: [f64; L] = each!(0.0, |l| 1.0 + eps[l]);
    let mut out: [State<N>; L] = [[0.0; N]; L];
    for l in 0..L {
        out[l][0] = m[l] * bend_compliance[l];
        out[l][1] = -stretch[l] * q[l] + gamma[l] * n[l];
        out[l][2] = stretch[l] * cs[l] - gamma[l] * sn[l];
        out[l][3] = stretch[l] * sn[l] + gamma[l] * cs[l];
    }
    if N > 4 || second.is_some() {
        // Variational equations, linearised about this state.
        let f1_psi: [f64; L] = each!(0.0, |l| -4.0
            * m[l]
            * p_psi[l]
            * bend_compliance[l]
            * inv_p[l]);
        let f2_psi: [f64; L] = each!(0.0, |l| -eps_psi[l] * q[l]
            + stretch[l] * n[l]
            + gamma_psi[l] * n[l]
            + gamma[l] * q[l]);
        let dx_psi: [f64; L] = each!(0.0, |l| eps_psi[l] * cs[l]
            - stretch[l] * sn[l]
            - gamma_psi[l] * sn[l]
            - gamma[l] * cs[l]);
        let dy_psi: [f64; L] = each!(0.0, |l| eps_psi[l] * sn[l]
            + stretch[l] * cs[l]
            + gamma_psi[l] * cs[l]
            - gamma[l] * sn[l]);
        // The linearisation applied to a direction `(v_psi, v_m)`.
        let along = |l: usize, v_psi: f64, v_m: f64| {
            [
                f1_psi[l] * v_psi + bend_compliance[l] * v_m,
                f2_psi[l] * v_psi,
                dx_psi[l] * v_psi,
                dy_psi[l] * v_psi,
            ]
        };
        for base in (4..N).step_by(4) {
            for l in 0..L {
                let d = along(l, u[l][base], u[l][base + 1]);
                out[l][base..base + 4].copy_from_slice(&d);
            }
        }
        // The second derivatives `(psi'', M'', x'', y'')`: the linearisation applied to the
        // state's own direction `(psi', M')`.
        if let Some(second) = second {
            for l in 0..L {
                second[l] = along(l, out[l][PSI], out[l][MOM]);
            }
        }
    }
    if N == 16 {
        // The force's own terms: the right-hand side's partial derivatives with respect to
        // the section forces N and Q at fixed psi, M (the psi-derivatives above are these
        // chained through N_psi = Q, Q_psi = -N), chained through N_ax = cos, Q_ax = -sin,
        // N_ay = sin, Q_ay = cos.
        for l in 0..L {
            let d_n = de_dn[l];
            let p_n = if poisson[l] { -model[l].nu * d_n } else { 0.0 };
            let bc_n = -4.0 * bend_compliance[l] * inv_p[l] * p_n;
            let (g_n, g_q) = if shear[l] {
                (
                    -2.0 * c_s[l] * q[l] * inv_p2[l] * inv_p[l] * p_n,
                    c_s[l] * inv_p2[l],
                )
            } else {
                (0.0, 0.0)
            };
            let (sn, cs, n, q) = (sn[l], cs[l], n[l], q[l]);
            let d_n_row = [
                m[l] * bc_n,
                -d_n * q + g_n * n + gamma[l],
                d_n * cs - g_n * sn,
                d_n * sn + g_n * cs,
            ];
            let d_q_row = [0.0, -stretch[l] + g_q * n, -g_q * sn, g_q * cs];
            for k in 0..4 {
                out[l][8 + k] += d_n_row[k] * cs - d_q_row[k] * sn;
                out[l][12 + k] += d_n_row[k] * sn + d_q_row[k] * cs;
            }
        }
    }
    each!(Ok([0.0; N]), |l| strain[l].map(|_| out[l]))
}

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
