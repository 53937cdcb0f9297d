//! `sin` and `cos` of one angle together, for the beam shooting's right-hand side and the PRB
//! chain's kinematics.
//!
//! A profile of `prbfit solve` on 1000 elastica cases put a fifth of the time in the C
//! library's `sincos`, which is general (any argument, correctly rounded in most cases) and
//! called through the dynamic linker; a profile of the 20-case 3R fit at draft, 14 %. The
//! beam's section angles and a chain's joint angles are moderate (a full loop is `2 pi`; the
//! largest a solve meets are a few hundred radians), so this reduces the argument
//! by `pi/2` in two parts (Cody and Waite) and evaluates the classic fdlibm minimax kernels on
//! `[-pi/4, pi/4]` (error below one unit in the last place there), inline. Arguments beyond
//! [`FAST_RANGE`], and non-finite ones, go to the standard library.
//!
//! The result differs from the C library's by at most a couple of units in the last place
//! (test `agrees_with_the_standard_library`), far below the integrator's tolerance.
//!
//! ## References
//! - W. J. Cody, W. Waite, *Software Manual for the Elementary Functions*, Prentice-Hall, 1980.
//! - fdlibm 5.3 (Sun Microsystems, 1993), `k_sin.c`, `k_cos.c`, `e_rem_pio2.c`: the kernel
//!   coefficients and the two-part `pi/2` below ("Permission to use, copy, modify, and
//!   distribute this software is freely granted, provided that this notice is preserved.").

// The constants are fdlibm's, digit for digit as published (each rounds to the intended
// double), so that they can be checked against the source.
#![allow(clippy::excessive_precision)]

/// Largest argument reduced here; beyond it the reduction's first part would lose bits.
const FAST_RANGE: f64 = 1e6;
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
/// The first 33 bits of `pi/2` (so `n * PIO2_1` is exact for `n < 2^20`) and the rest.
const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
const PIO2_1T: f64 = 6.077_100_506_506_192_249_32e-11;
/// Adding and subtracting this rounds to the nearest integer (for `|x| < 2^51`).
const TO_INT: f64 = 1.5 / f64::EPSILON;

const S1: f64 = -1.666_666_666_666_663_243_48e-1;
const S2: f64 = 8.333_333_333_322_489_461_24e-3;
const S3: f64 = -1.984_126_982_985_794_931_34e-4;
const S4: f64 = 2.755_731_370_707_006_767_89e-6;
const S5: f64 = -2.505_076_025_340_686_341_95e-8;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-2;
const C2: f64 = -1.388_888_888_887_410_957_49e-3;
const C3: f64 = 2.480_158_728_947_672_941_78e-5;
const C4: f64 = -2.755_731_435_139_066_330_35e-7;
const C5: f64 = 2.087_572_321_298_174_827_90e-9;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// `(sin x, cos x)`.
// Always inline: called once per right-hand side, and a call costs a fifth of it.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > FAST_RANGE {
        return outside_fast_range(x);
    }
    let n = (x * INV_PIO2 + TO_INT) - TO_INT;
    let r = x - n * PIO2_1;
    let w = n * PIO2_1T;
    let hi = r - w;
    let lo = (r - hi) - w;
    let (s, c) = (kernel_sin(hi, lo), kernel_cos(hi, lo));
    match (n as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// The standard library's `sin_cos`, out of line: inline, the optimiser may hoist it out of
/// [`sin_cos`]'s branch (the library functions have no side effects) and call it for every
/// argument, as it did for the beam shot's right-hand side written across lanes.
#[cold]
#[inline(never)]
fn outside_fast_range(x: f64) -> (f64, f64) {
    x.sin_cos()
}

/// `sin(x + y)` for `|x| <= pi/4`, `|y|` below half an ulp of `x`.
#[inline]
fn kernel_sin(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    x - ((z * (0.5 * y - v * r) - y) - v * S1)
}

/// `cos(x + y)` for `|x| <= pi/4`, `|y|` below half an ulp of `x`.
#[inline]
fn kernel_cos(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place between `a` and `b`, measured at the larger magnitude (and at
    /// least at 1e-300, so values near zero compare absolutely).
    fn ulps(a: f64, b: f64) -> f64 {
        let scale = a.abs().max(b.abs()).max(1e-300);
        (a - b).abs() / (scale * f64::EPSILON)
    }

    #[test]
    fn agrees_with_the_standard_library() {
        // A deterministic spread over the fast range: small angles, loops, a few hundred
        // radians, the range's edge, and multiples of pi/2 (the reduction's hardest cases).
        let mut xs: Vec<f64> = Vec::new();
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..200_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            let magnitude = 10f64.powf(-8.0 + 14.0 * u);
            xs.push(if seed & 1 == 0 { magnitude } else { -magnitude });
        }
        xs.extend((-2000..=2000).map(|k| k as f64 * std::f64::consts::FRAC_PI_2));
        xs.extend([0.0, -0.0, 1e-300, FAST_RANGE, -FAST_RANGE]);
        let mut worst = 0.0_f64;
        for &x in &xs {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            // Near a zero of sin or cos the value is tiny and its relative error is the
            // argument's rounding, so the comparison is on the scale of 1 there: an
            // absolute error of a few units of 1's last place is all the ODE can see.
            let es = ulps(s, s0).min((s - s0).abs() / f64::EPSILON);
            let ec = ulps(c, c0).min((c - c0).abs() / f64::EPSILON);
            worst = worst.max(es).max(ec);
        }
        // fdlibm's kernels are good to 1 ulp and glibc's to less: 2 ulp apart at most, plus
        // the reduction's rounding for arguments up to 1e6 (`n ulp(PIO2_1T)`, far below).
        assert!(worst <= 2.0, "worst disagreement {worst} ulp");
    }

    #[test]
    fn far_and_non_finite_arguments_go_to_the_standard_library() {
        for x in [1e7, -3.5e12, f64::INFINITY, f64::NAN] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!(
                s.to_bits() == s0.to_bits() || (s.is_nan() && s0.is_nan()),
                "{x}"
            );
            assert!(
                c.to_bits() == c0.to_bits() || (c.is_nan() && c0.is_nan()),
                "{x}"
            );
        }
    }
}
