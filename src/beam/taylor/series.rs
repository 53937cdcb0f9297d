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
    let nu = law.nu;
    let k = K;
    let zero = T::splat(0.0);
    let one = T::splat(1.0);
    let two = T::splat(2.0);
    let (s_k, c_k) = if k > 0 {
        let kpsi_k = T::splat(k as f64) * z[0][k];
        aux.kpsi[k] = kpsi_k;
        let ss = mid::<K, T>(&aux.kpsi, &aux.cs) + kpsi_k * c0;
        let cc = mid::<K, T>(&aux.kpsi, &aux.sn) + kpsi_k * s0;
        let inv = T::splat(INV[k]);
        (ss * inv, -cc * inv)
    } else {
        (s0, c0)
    };
    aux.sn[k] = s_k;
    aux.cs[k] = c_k;
    let n_k = ax * c_k + ay * s_k;
    let q_k = -ax * s_k + ay * c_k;
    aux.q[k] = q_k;
    let e_k = if !stretch {
        zero
    } else if k == 0 {
        if shrink {
            let p0 = one - nu * eps0;
            let p2 = p0 * p0;
            let w2 = one / p2;
            aux.p[0] = p0;
            aux.p2[0] = p2;
            aux.w2[0] = w2;
            aux.w4[0] = w2 * w2;
            aux.inv_slope = one / (p0 * (one - T::splat(3.0) * nu * eps0));
        }
        eps0
    } else if shrink {
        // Order k of `eps p^2 = c_e N`, solved for its one unknown `eps_k`.
        let t = mid::<K, T>(&aux.p, &aux.p);
        let known = mid::<K, T>(&aux.e, &aux.p2);
        let e_k = (law.axial * n_k - aux.e[0] * t - known) * aux.inv_slope;
        let p_k = -nu * e_k;
        let p2_k = two * aux.p[0] * p_k + t;
        aux.p[k] = p_k;
        aux.p2[k] = p2_k;
        // 1 / p^2 by the division recurrence.
        aux.w2[k] = -(mid::<K, T>(&aux.p2, &aux.w2) + p2_k * aux.w2[0]) * aux.w2[0];
        e_k
    } else {
        law.axial * n_k
    };
    aux.e[k] = e_k;
    // 1 / p^4, and the shear strain `c_s Q / p^2`.
    let (w4_k, g_k) = if !shrink {
        (if k == 0 { one } else { zero }, law.shear * q_k)
    } else if k > 0 {
        let (w2_0, w2_k) = (aux.w2[0], aux.w2[k]);
        let sq = mid::<K, T>(&aux.w2, &aux.w2);
        let qw = mid::<K, T>(&aux.q, &aux.w2);
        (
            sq + two * w2_0 * w2_k,
            law.shear * (qw + q_k * w2_0 + aux.q[0] * w2_k),
        )
    } else {
        (aux.w4[0], law.shear * q_k * aux.w2[0])
    };
    aux.w4[k] = w4_k;
    aux.g[k] = g_k;
    // The strain's and the shear strain's products with S and C, and the bending
    // compliance's with M.
    let m_k = z[1][k];
    let (es, ec, gs, gc, bm) = if k == 0 {
        (e_k * s0, e_k * c0, g_k * s0, g_k * c0, w4_k * m_k)
    } else {
        let (e0, g0, w0, m0) = (aux.e[0], aux.g[0], aux.w4[0], z[1][0]);
        (
            mid::<K, T>(&aux.e, &aux.sn) + e0 * s_k + e_k * s0,
            mid::<K, T>(&aux.e, &aux.cs) + e0 * c_k + e_k * c0,
            mid::<K, T>(&aux.g, &aux.sn) + g0 * s_k + g_k * s0,
            mid::<K, T>(&aux.g, &aux.cs) + g0 * c_k + g_k * c0,
            mid::<K, T>(&aux.w4, &z[1]) + w0 * m_k + w4_k * m0,
        )
    };
    let inv = T::splat(INV[k + 1]);
    z[0][k + 1] = law.bend * bm * inv;
    // (eps Q) = -ax (eps S) + ay (eps C), (gamma N) = ax (gamma C) + ay (gamma S).
    z[1][k + 1] = (-(q_k + (-ax * es + ay * ec)) + (ax * gc + ay * gs)) * inv;
    z[2][k + 1] = (c_k + ec - gs) * inv;
    z[3][k + 1] = (s_k + es + gc) * inv;
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
