//! The numbers the full beam's series are built of: one shot's `f64`, or two shots' side by
//! side in the two lanes of a [`Two`] (an SSE2 register on x86-64, part of its baseline).
//! Every operation is the same single IEEE rounding in each lane as on an `f64`, so a shot's
//! series come out the same to the bit whether it is built alone or beside another.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic of the series.
pub(super) trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
}

impl Num for f64 {
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
}

/// Two shots' numbers, one per lane.
#[derive(Clone, Copy)]
pub(super) struct Two(imp::V);

impl Two {
    /// `a` in the first lane, `b` in the second.
    #[inline(always)]
    pub(super) fn new(a: f64, b: f64) -> Two {
        Two(imp::new(a, b))
    }

    /// The two lanes stored into `a` and `b`.
    #[inline(always)]
    pub(super) fn store(self, a: &mut f64, b: &mut f64) {
        imp::store(self.0, a, b)
    }
}

impl Num for Two {
    #[inline(always)]
    fn splat(x: f64) -> Two {
        Two::new(x, x)
    }
}

macro_rules! binary {
    ($($tr:ident $f:ident)*) => {$(
        impl $tr for Two {
            type Output = Two;
            #[inline(always)]
            fn $f(self, o: Two) -> Two {
                Two(imp::$f(self.0, o.0))
            }
        }
    )*};
}
binary!(Add add Sub sub Mul mul Div div);

impl Neg for Two {
    type Output = Two;
    #[inline(always)]
    fn neg(self) -> Two {
        Two(imp::neg(self.0))
    }
}

#[cfg(target_arch = "x86_64")]
mod imp {
    use std::arch::x86_64::*;

    pub(super) type V = __m128d;

    // SAFETY (every block below): SSE2 is part of x86-64, so its instructions run on every
    // processor this code is built for.
    #[inline(always)]
    pub(super) fn new(a: f64, b: f64) -> V {
        unsafe { _mm_set_pd(b, a) }
    }
    #[inline(always)]
    pub(super) fn store(v: V, a: &mut f64, b: &mut f64) {
        unsafe {
            _mm_store_sd(a, v);
            _mm_storeh_pd(b, v);
        }
    }
    #[inline(always)]
    pub(super) fn add(a: V, b: V) -> V {
        unsafe { _mm_add_pd(a, b) }
    }
    #[inline(always)]
    pub(super) fn sub(a: V, b: V) -> V {
        unsafe { _mm_sub_pd(a, b) }
    }
    #[inline(always)]
    pub(super) fn mul(a: V, b: V) -> V {
        unsafe { _mm_mul_pd(a, b) }
    }
    #[inline(always)]
    pub(super) fn div(a: V, b: V) -> V {
        unsafe { _mm_div_pd(a, b) }
    }
    /// The sign bit flipped, as `-x` does.
    #[inline(always)]
    pub(super) fn neg(a: V) -> V {
        unsafe { _mm_xor_pd(a, _mm_set1_pd(-0.0)) }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    pub(super) type V = [f64; 2];

    #[inline(always)]
    pub(super) fn new(a: f64, b: f64) -> V {
        [a, b]
    }
    #[inline(always)]
    pub(super) fn store(v: V, a: &mut f64, b: &mut f64) {
        [*a, *b] = v;
    }
    #[inline(always)]
    pub(super) fn add(a: V, b: V) -> V {
        [a[0] + b[0], a[1] + b[1]]
    }
    #[inline(always)]
    pub(super) fn sub(a: V, b: V) -> V {
        [a[0] - b[0], a[1] - b[1]]
    }
    #[inline(always)]
    pub(super) fn mul(a: V, b: V) -> V {
        [a[0] * b[0], a[1] * b[1]]
    }
    #[inline(always)]
    pub(super) fn div(a: V, b: V) -> V {
        [a[0] / b[0], a[1] / b[1]]
    }
    #[inline(always)]
    pub(super) fn neg(a: V) -> V {
        [-a[0], -a[1]]
    }
}
