//! The Taylor coefficients of one step ([`super`]'s integrator takes them and steps): the
//! plain-bending beam's, with its sensitivities, and the shearing, stretching, shrinking
//! beam's state (the module notes of [`super`] give both systems and their recurrences).

use super::num::{Num, Two};
use super::MAX_ORDER;
use crate::beam::BeamModel;

/// Fills the Taylor coefficients of orders `1..=p` of the state `z[i][k]` from its values
/// `z[i][0]`, with those of `sin psi`, `cos psi` up to order `p - 1`.
///
/// Order `k + 1` of every component needs the convolutions of order `k`: the sine and cosine
/// recurrences and, per variational column, `S * P` and `C * P`. Their sums run side by side
/// in one loop (independent chains of additions, which the processor overlaps, where one
/// sum after another would wait on each addition's latency).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn coefficients<const N: usize>(
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

/// The constants of the shearing, stretching, shrinking beam's series.
#[derive(Debug, Clone, Copy)]
pub(super) struct Law {
    /// The bending compliance before the shrink, `E / E_eff`.
    bend: f64,
    /// The axial compliance `c_e E / E_eff`; 0 without extension.
    axial: f64,
    /// Poisson's ratio where the section shrinks (Poisson on and `nu > 0`), else 0.
    nu: f64,
    /// The shear compliance; 0 without shear.
    shear: f64,
}

impl Law {
    pub(super) fn of(model: &BeamModel) -> Law {
        let e = model.effects;
        let bend = model.plate_compliance();
        Law {
            bend,
            axial: if e.extension {
                model.axial_compliance() * bend
            } else {
                0.0
            },
            nu: if e.extension && e.poisson {
                model.nu
            } else {
                0.0
            },
            shear: if e.shear {
                model.shear_compliance()
            } else {
                0.0
            },
        }
    }

    /// The law as the series take it, for one shot.
    pub(super) fn one(self) -> Laws<f64> {
        Laws {
            bend: self.bend,
            axial: self.axial,
            nu: self.nu,
            shear: self.shear,
            stretch: self.axial != 0.0,
            shrink: self.nu != 0.0,
        }
    }

    /// Two laws side by side, where their series are of one kind (the same effects carried).
    pub(super) fn two(a: Law, b: Law) -> Option<Laws<Two>> {
        let (la, lb) = (a.one(), b.one());
        (la.stretch == lb.stretch && la.shrink == lb.shrink).then_some(Laws {
            bend: Two::new(a.bend, b.bend),
            axial: Two::new(a.axial, b.axial),
            nu: Two::new(a.nu, b.nu),
            shear: Two::new(a.shear, b.shear),
            stretch: la.stretch,
            shrink: la.shrink,
        })
    }
}

/// [`Law`]'s constants in `T`'s lanes (one shot's, or two side by side), and which series
/// they need (the same in every lane).
#[derive(Clone, Copy)]
pub(super) struct Laws<T> {
    bend: T,
    axial: T,
    nu: T,
    shear: T,
    /// Extension on: the strain has a series.
    stretch: bool,
    /// Poisson's shrink on: so have `p`, `p^2`, `1 / p^2` and `1 / p^4`.
    shrink: bool,
}

/// The series of the full beam's step: `k psi_k`, `sin psi` and `cos psi`, and the other
/// effects': the strain `e`, the shrink `p` and its square `p2`, `w2 = 1 / p^2`, `w4 = 1 /
/// p^4`, the shear force `q` and strain `g`; and `1 / (p_0 (1 - 3 nu eps_0))`, what the
/// order-k coefficient of `eps p^2` multiplies `eps_k` by, inverted.
pub(super) struct Aux<T> {
    kpsi: [T; MAX_ORDER + 1],
    sn: [T; MAX_ORDER + 1],
    cs: [T; MAX_ORDER + 1],
    e: [T; MAX_ORDER + 1],
    p: [T; MAX_ORDER + 1],
    p2: [T; MAX_ORDER + 1],
    w2: [T; MAX_ORDER + 1],
    w4: [T; MAX_ORDER + 1],
    q: [T; MAX_ORDER + 1],
    g: [T; MAX_ORDER + 1],
    inv_slope: T,
    /// The step's constants: the axial force at its start, the shear force times the shear
    /// compliance there, and how the order-k coefficients of the strain, `1 / p^2` and `1 /
    /// p^4` change with those of the axial force and the strain (the terms of order 0 with
    /// order k).
    n0: T,
    shear_q0: T,
    strain_of_force: T,
    w2_of_strain: T,
    w4_of_strain: T,
}

impl<T: Num> Default for Aux<T> {
    fn default() -> Aux<T> {
        let zero = [T::splat(0.0); MAX_ORDER + 1];
        Aux {
            kpsi: zero,
            sn: zero,
            cs: zero,
            e: zero,
            p: zero,
            p2: zero,
            w2: zero,
            w4: zero,
            q: zero,
            g: zero,
            inv_slope: T::splat(0.0),
            n0: T::splat(0.0),
            shear_q0: T::splat(0.0),
            strain_of_force: T::splat(0.0),
            w2_of_strain: T::splat(0.0),
            w4_of_strain: T::splat(0.0),
        }
    }
}

/// [`coefficients`] of the shearing, stretching, shrinking beam's state (`N = 4`; see the
/// module's notes), of one shot (`T = f64`) or two side by side ([`Two`]): its strain at the
/// start `eps0` given by the law, and `sin psi`, `cos psi` there `s0`, `c0`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn coefficients_full<T: Num>(
    z: &mut [[T; MAX_ORDER + 1]; 4],
    aux: &mut Aux<T>,
    p: usize,
    law: Laws<T>,
    eps0: T,
    (s0, c0): (T, T),
    ax: T,
    ay: T,
) {
    // One function per order (`K`), each called while below `p`: every sum's length is then
    // a constant, its loop unrolled, where loops of a different length at every order would
    // branch and mispredict their ends.
    macro_rules! orders {
        ($($k:literal)*) => {$(
            if $k < p {
                order_full::<$k, T>(z, aux, law, eps0, (s0, c0), ax, ay);
            }
        )*};
    }
    const _: () = assert!(MAX_ORDER == 24);
    orders!(0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23);
}

/// `sum a_j b_(K - j)` over `0 < j < K`. The terms of orders 2 to `K - 2` come first, in
/// four sums (by `j` mod 4: independent chains of additions, which the processor overlaps)
/// that need nothing of the order before; then the two with order `K - 1`, the newest.
#[inline(always)]
fn mid<const K: usize, T: Num>(a: &[T; MAX_ORDER + 1], b: &[T; MAX_ORDER + 1]) -> T {
    let plus = |x: Option<T>, y: Option<T>| match (x, y) {
        (Some(x), Some(y)) => Some(x + y),
        (x, None) => x,
        (None, y) => y,
    };
    if K < 2 {
        return T::splat(0.0);
    }
    let mut acc: [Option<T>; 4] = [None; 4];
    for j in 2..K - 1 {
        acc[(j - 2) % 4] = plus(acc[(j - 2) % 4], Some(a[j] * b[K - j]));
    }
    let inner = plus(plus(acc[0], acc[2]), plus(acc[1], acc[3]));
    let newest = if K == 2 {
        a[1] * b[1]
    } else {
        a[1] * b[K - 1] + a[K - 1] * b[1]
    };
    plus(inner, Some(newest)).unwrap_or(newest)
}

/// Order `K` of [`coefficients_full`]: the coefficients of order `K` of the auxiliary series
/// and `K + 1` of the state. Each sum pairs order j of one series with order k - j of another:
/// the terms of orders 1 to k - 1 ([`mid`]), which need nothing of this order (the processor
/// sums them while the newest terms are computed), and then those with order 0 or k.
///
/// Order k's only new inputs are `k psi_k` and `M_k`, and every quantity of the order is
/// affine in them with coefficients of older orders. The chain from one order's `k psi_k` to
/// the next order's is kept short by taking each quantity on it straight from the one before
/// by such an affine map (computed off the chain): the axial force from `k psi_k`, not from
/// `sin psi` and `cos psi`; the strain from the force; `1 / p^2` and `1 / p^4` from the strain,
/// not through `p` and `p^2`; and the next `k psi_k` from the bending moment's series without
/// going through `psi`'s coefficient. About eleven dependent operations an order, where
/// following the recurrences literally took twenty-two.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn order_full<const K: usize, T: Num>(
    z: &mut [[T; MAX_ORDER + 1]; 4],
    aux: &mut Aux<T>,
    law: Laws<T>,
    eps0: T,
    (s0, c0): (T, T),
    ax: T,
    ay: T,
) {
    let (stretch, shrink) = (law.stretch, law.shrink);
    let (nu, shear) = (law.nu, law.shear);
    let k = K;
    let zero = T::splat(0.0);
    let one = T::splat(1.0);
    let two = T::splat(2.0);
    let inv_next = T::splat(INV[k + 1]);
    if k == 0 {
        // The step's start, and the constants of its affine maps.
        let n0 = ax * c0 + ay * s0;
        let q0 = -ax * s0 + ay * c0;
        aux.sn[0] = s0;
        aux.cs[0] = c0;
        aux.q[0] = q0;
        aux.n0 = n0;
        aux.shear_q0 = shear * q0;
        let e0 = if stretch { eps0 } else { zero };
        aux.e[0] = e0;
        let (w2_0, w4_0) = if shrink {
            let p0 = one - nu * eps0;
            let p2 = p0 * p0;
            let w2 = one / p2;
            aux.p[0] = p0;
            aux.p2[0] = p2;
            aux.w2[0] = w2;
            aux.inv_slope = one / (p0 * (one - T::splat(3.0) * nu * eps0));
            aux.strain_of_force = law.axial * aux.inv_slope;
            // d(1 / p^2) / d eps = 2 nu p / p^4 at order 0, and d(1 / p^4) / d eps twice
            // that times 1 / p^2.
            aux.w2_of_strain = two * nu * p0 * w2 * w2;
            aux.w4_of_strain = two * w2 * aux.w2_of_strain;
            (w2, w2 * w2)
        } else {
            (one, one)
        };
        aux.w4[0] = w4_0;
        let g0 = if shrink {
            shear * q0 * w2_0
        } else {
            shear * q0
        };
        aux.g[0] = g0;
        let bm = w4_0 * z[1][0];
        let kpsi_next = law.bend * bm;
        aux.kpsi[1] = kpsi_next;
        z[0][1] = kpsi_next * inv_next;
        let (es, ec, gs, gc) = (e0 * s0, e0 * c0, g0 * s0, g0 * c0);
        // (eps Q) = -ax (eps S) + ay (eps C), (gamma N) = ax (gamma C) + ay (gamma S).
        z[1][1] = (-(q0 + (-ax * es + ay * ec)) + (ax * gc + ay * gs)) * inv_next;
        z[2][1] = (c0 + ec - gs) * inv_next;
        z[3][1] = (s0 + es + gc) * inv_next;
        return;
    }
    let (n0, q0) = (aux.n0, aux.q[0]);
    let kpsi_k = aux.kpsi[k];
    let inv_k = T::splat(INV[k]);
    // The sine and cosine recurrences: `S_k = sum (j psi_j) C_(k-j) / k`, and `C_k` alike.
    let (mss, mcc) = (
        mid::<K, T>(&aux.kpsi, &aux.cs),
        mid::<K, T>(&aux.kpsi, &aux.sn),
    );
    let s_k = (mss + kpsi_k * c0) * inv_k;
    let c_k = -(mcc + kpsi_k * s0) * inv_k;
    aux.sn[k] = s_k;
    aux.cs[k] = c_k;
    // `N_k = ax C_k + ay S_k` and `Q_k = -ax S_k + ay C_k`, straight from `k psi_k`.
    let n_k = (ay * mss - ax * mcc + kpsi_k * q0) * inv_k;
    let q_k = (-(ax * mss) - ay * mcc - kpsi_k * n0) * inv_k;
    aux.q[k] = q_k;
    // The strain, and `1 / p^2`, `1 / p^4` and the shear strain `c_s Q / p^2`.
    let (e_k, w4_k, g_k) = if !stretch {
        (zero, zero, shear * q_k)
    } else if shrink {
        // Order k of `eps p^2 = c_e N`, solved for its one unknown `eps_k`.
        let (e0, p0, w2_0) = (aux.e[0], aux.p[0], aux.w2[0]);
        let t = mid::<K, T>(&aux.p, &aux.p);
        let known = mid::<K, T>(&aux.e, &aux.p2);
        let e_k = aux.strain_of_force * n_k - (e0 * t + known) * aux.inv_slope;
        let p_k = -nu * e_k;
        let p2_k = two * p0 * p_k + t;
        // `1 / p^2` by the division recurrence, `-(sum p2_j w2_(k-j), j = 1..k) w2_0`, its
        // `p2_k` term taken through `eps_k`.
        let w2_old = -(mid::<K, T>(&aux.p2, &aux.w2) + t * w2_0) * w2_0;
        let w2_k = w2_old + aux.w2_of_strain * e_k;
        let w4_old = mid::<K, T>(&aux.w2, &aux.w2) + two * w2_0 * w2_old;
        let w4_k = w4_old + aux.w4_of_strain * e_k;
        let g_k = shear * (mid::<K, T>(&aux.q, &aux.w2) + q_k * w2_0) + aux.shear_q0 * w2_k;
        aux.p[k] = p_k;
        aux.p2[k] = p2_k;
        aux.w2[k] = w2_k;
        (e_k, w4_k, g_k)
    } else {
        (law.axial * n_k, zero, shear * q_k)
    };
    aux.e[k] = e_k;
    aux.w4[k] = w4_k;
    aux.g[k] = g_k;
    // The bending compliance's product with M, and so the next order's `k psi_k`.
    let (w0, m0, m_k) = (aux.w4[0], z[1][0], z[1][k]);
    let bm = mid::<K, T>(&aux.w4, &z[1]) + w0 * m_k + w4_k * m0;
    let kpsi_next = law.bend * bm;
    aux.kpsi[k + 1] = kpsi_next;
    z[0][k + 1] = kpsi_next * inv_next;
    // The strain's and the shear strain's products with S and C: their terms of order 0 and
    // k in `S_k`, `C_k` (all but the newest), then the newest.
    let (e0, g0) = (aux.e[0], aux.g[0]);
    let es = mid::<K, T>(&aux.e, &aux.sn) + e0 * s_k;
    let ec = mid::<K, T>(&aux.e, &aux.cs) + e0 * c_k;
    let gs = mid::<K, T>(&aux.g, &aux.sn) + g0 * s_k;
    let gc = mid::<K, T>(&aux.g, &aux.cs) + g0 * c_k;
    // M' = -(1 + eps) Q + gamma N: `-Q_k + ax (eps S) - ay (eps C) + ax (gamma C) + ay
    // (gamma S)`, whose terms in `eps_k` and `gamma_k` are `-eps_k Q_0 + gamma_k N_0`.
    let old = ax * es - ay * ec + (ax * gc + ay * gs) - q_k;
    z[1][k + 1] = (old - e_k * q0 + g_k * n0) * inv_next;
    let (es, ec, gs, gc) = (es + e_k * s0, ec + e_k * c0, gs + g_k * s0, gc + g_k * c0);
    z[2][k + 1] = (c_k + ec - gs) * inv_next;
    z[3][k + 1] = (s_k + es + gc) * inv_next;
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
