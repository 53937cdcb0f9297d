//! The Taylor coefficients of one step ([`super`]'s integrator takes them and steps): the
//! plain-bending beam's, with its sensitivities, and the shearing, stretching, shrinking
//! beam's state (the module notes of [`super`] give both systems and their recurrences).

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
}

/// The series of the other effects: the strain `e`, the shrink `p` and its square `p2`, `w2 =
/// 1 / p^2`, `w4 = 1 / p^4`, the shear force `q` and strain `g`; and `1 / (p_0 (1 - 3 nu
/// eps_0))`, what the order-k coefficient of `eps p^2` multiplies `eps_k` by, inverted.
#[derive(Default)]
pub(super) struct Aux {
    e: [f64; MAX_ORDER + 1],
    p: [f64; MAX_ORDER + 1],
    p2: [f64; MAX_ORDER + 1],
    w2: [f64; MAX_ORDER + 1],
    w4: [f64; MAX_ORDER + 1],
    q: [f64; MAX_ORDER + 1],
    g: [f64; MAX_ORDER + 1],
    inv_slope: f64,
}

/// [`coefficients`] of the shearing, stretching, shrinking beam's state (`N = 4`; see the
/// module's notes), its strain at the start `eps0` given by the law, and `sin psi`, `cos psi`
/// there in `sn[0]`, `cs[0]`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn coefficients_full(
    z: &mut [[f64; MAX_ORDER + 1]; 4],
    sn: &mut [f64; MAX_ORDER + 1],
    cs: &mut [f64; MAX_ORDER + 1],
    kpsi: &mut [f64; MAX_ORDER + 1],
    aux: &mut Aux,
    p: usize,
    law: Law,
    eps0: f64,
    ax: f64,
    ay: f64,
) {
    if law.nu == 0.0 {
        // `1 / p^4` is 1.
        aux.w4[0] = 1.0;
    }
    // One function per order (`K`), each called while below `p`: every sum's length is then
    // a constant, its loop unrolled, where loops of a different length at every order would
    // branch and mispredict their ends.
    macro_rules! orders {
        ($($k:literal)*) => {$(
            if $k < p {
                order_full::<$k>(z, sn, cs, kpsi, aux, law, eps0, ax, ay);
            }
        )*};
    }
    const _: () = assert!(MAX_ORDER == 24);
    orders!(0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23);
}

/// Order `K` of [`coefficients_full`]: the coefficients of order `K` of the auxiliary series
/// and `K + 1` of the state. The sums below pair order j of one series with order k - j of
/// another: a slice and a reversed slice zipped (no bounds checks inside the loops), several
/// sums to a loop (independent chains of additions, which the processor overlaps).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn order_full<const K: usize>(
    z: &mut [[f64; MAX_ORDER + 1]; 4],
    sn: &mut [f64; MAX_ORDER + 1],
    cs: &mut [f64; MAX_ORDER + 1],
    kpsi: &mut [f64; MAX_ORDER + 1],
    aux: &mut Aux,
    law: Law,
    eps0: f64,
    ax: f64,
    ay: f64,
) {
    let Aux {
        e,
        p: pp,
        p2,
        w2,
        w4,
        q,
        g,
        inv_slope,
    } = aux;
    let (stretch, shrink) = (law.axial != 0.0, law.nu != 0.0);
    let nu = law.nu;
    let k = K;
    if k > 0 {
        kpsi[k] = k as f64 * z[0][k];
        let (mut ss, mut cc) = (0.0, 0.0);
        for (kp, (c, s)) in kpsi[1..=k]
            .iter()
            .zip(cs[..k].iter().rev().zip(sn[..k].iter().rev()))
        {
            ss += kp * c;
            cc += kp * s;
        }
        sn[k] = ss * INV[k];
        cs[k] = -cc * INV[k];
    }
    let (s_k, c_k) = (sn[k], cs[k]);
    let n_k = ax * c_k + ay * s_k;
    let q_k = -ax * s_k + ay * c_k;
    q[k] = q_k;
    if stretch {
        if k == 0 {
            e[0] = eps0;
            if shrink {
                pp[0] = 1.0 - nu * eps0;
                p2[0] = pp[0] * pp[0];
                w2[0] = 1.0 / p2[0];
                w4[0] = w2[0] * w2[0];
                *inv_slope = 1.0 / (pp[0] * (1.0 - 3.0 * nu * eps0));
            }
        } else if shrink {
            // Order k of `eps p^2 = c_e N`, solved for its one unknown `eps_k`.
            let (mut t, mut known) = (0.0, 0.0);
            for ((pj, ej), (pk, p2k)) in pp[1..k]
                .iter()
                .zip(&e[1..k])
                .zip(pp[1..k].iter().rev().zip(p2[1..k].iter().rev()))
            {
                t += pj * pk;
                known += ej * p2k;
            }
            e[k] = (law.axial * n_k - e[0] * t - known) * *inv_slope;
            pp[k] = -nu * e[k];
            p2[k] = 2.0 * pp[0] * pp[k] + t;
            // 1 / p^2 by the division recurrence.
            let mut sum = 0.0;
            for (a, b) in p2[1..=k].iter().zip(w2[..k].iter().rev()) {
                sum += a * b;
            }
            w2[k] = -sum * w2[0];
        } else {
            e[k] = law.axial * n_k;
        }
    }
    // 1 / p^4, and the shear strain `c_s Q / p^2`: the terms with the newest `w2_k` added
    // last, so that the rest are summed while it is computed.
    if shrink {
        if k > 0 {
            let (mut sq, mut qw) = (0.0, 0.0);
            for ((wj, qj), wk) in w2[1..k].iter().zip(&q[1..k]).zip(w2[1..k].iter().rev()) {
                sq += wj * wk;
                qw += qj * wk;
            }
            w4[k] = sq + 2.0 * w2[0] * w2[k];
            g[k] = law.shear * (qw + q[k] * w2[0] + q[0] * w2[k]);
        } else {
            g[0] = law.shear * q[0] * w2[0];
        }
    } else {
        g[k] = law.shear * q_k;
    }
    // The strain's and the shear strain's products with S and C, and the bending
    // compliance's with M: one pass.
    let (mut es, mut ec, mut gs, mut gc, mut bm) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (((ej, gj), wj), ((s, c), m)) in e[..=k].iter().zip(&g[..=k]).zip(&w4[..=k]).zip(
        sn[..=k]
            .iter()
            .rev()
            .zip(cs[..=k].iter().rev())
            .zip(z[1][..=k].iter().rev()),
    ) {
        es += ej * s;
        ec += ej * c;
        gs += gj * s;
        gc += gj * c;
        bm += wj * m;
    }
    let bm = law.bend * bm;
    let inv = INV[k + 1];
    z[0][k + 1] = bm * inv;
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
