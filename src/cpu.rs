//! Which instructions the hot kernels may use on this processor.
//!
//! The release binary and the Python wheel are built for the baseline x86-64 (SSE2), so that
//! they run on any machine. The Taylor integrator of the plain beam is most of a beam solve
//! (61 % of `benches/scipy`'s 1000-case job, in a profile), and its sums run side by side in
//! lanes: built for AVX2 they take half the instructions. So it is compiled twice, for the
//! baseline and with AVX2 and FMA, and [`wide`] chooses at run time.
//!
//! The two builds give the same bits. Rust never fuses a multiply and an add on its own
//! (no floating-point contraction), and the compiler vectorises a sum only where that keeps
//! its order, so enabling the instructions changes how the arithmetic is issued, not its
//! results (a test compares them).

/// Whether this processor has AVX2 and FMA (checked once, then cached by the standard
/// library's detection).
#[inline]
pub(crate) fn wide() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
