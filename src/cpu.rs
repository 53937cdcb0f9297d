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
//!
//! The check asks the processor itself, once per process: two `cpuid` queries and one
//! `xgetbv`. The standard library's `is_x86_feature_detected!` enumerates every feature on
//! its first call, and in a virtual machine each `cpuid` traps to the hypervisor: 26-33 us
//! there (3.6 us a query), more than the wide build saves on a 20-case solve.

#[cfg(target_arch = "x86_64")]
use std::sync::atomic::{AtomicU8, Ordering};

/// [`wide`]'s answer once known: `UNKNOWN`, `NO` or `YES`.
#[cfg(target_arch = "x86_64")]
static WIDE: AtomicU8 = AtomicU8::new(UNKNOWN);
#[cfg(target_arch = "x86_64")]
const UNKNOWN: u8 = 0;
#[cfg(target_arch = "x86_64")]
const NO: u8 = 1;
#[cfg(target_arch = "x86_64")]
const YES: u8 = 2;

/// Whether this processor (and its operating system) runs AVX2 and FMA instructions.
#[inline]
pub(crate) fn wide() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        match WIDE.load(Ordering::Relaxed) {
            YES => true,
            NO => false,
            _ => {
                let wide = detect();
                WIDE.store(if wide { YES } else { NO }, Ordering::Relaxed);
                wide
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Asks the processor (Intel SDM vol. 2A, `CPUID`; vol. 1 §14.3, detecting AVX):
/// - leaf 1, `ecx`: FMA (bit 12), OSXSAVE (bit 27: the OS enabled `xgetbv`), AVX (bit 28);
/// - `XCR0` bits 1 and 2: the OS saves the SSE and AVX registers on a context switch;
/// - leaf 7, sub-leaf 0, `ebx`: AVX2 (bit 5). A processor with AVX and XSAVE has leaf 13
///   (XSAVE's), so its largest basic leaf is at least 13 and leaf 7 needs no check of leaf 0.
#[cfg(target_arch = "x86_64")]
#[cold]
fn detect() -> bool {
    use std::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
    // `__cpuid` is safe in the Rust this is built with and unsafe in older ones (rust-version).
    #[allow(unused_unsafe)]
    // SAFETY: `cpuid` exists on every x86-64 processor.
    let leaf1 = unsafe { __cpuid(1) };
    let has = |bit: u32| leaf1.ecx & (1 << bit) != 0;
    if !(has(12) && has(27) && has(28)) {
        return false;
    }
    // SAFETY: OSXSAVE (checked above) means the OS enabled `xgetbv`.
    let xcr0 = unsafe { xgetbv0() };
    if xcr0 & 0b110 != 0b110 {
        return false;
    }
    #[allow(unused_unsafe)]
    // SAFETY: as above; leaf 7 exists (see the function's docs).
    let leaf7 = unsafe { __cpuid_count(7, 0) };
    return leaf7.ebx & (1 << 5) != 0;

    /// `XCR0`.
    #[target_feature(enable = "xsave")]
    unsafe fn xgetbv0() -> u64 {
        _xgetbv(0)
    }
}

#[cfg(test)]
mod tests {
    /// The processor's own answer agrees with the standard library's enumeration.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn agrees_with_the_standard_library() {
        let std_says = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        assert_eq!(super::detect(), std_says);
        assert_eq!(super::wide(), std_says);
        assert_eq!(super::wide(), std_says, "the cached answer");
    }
}
