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
//! The check is made once per process. In a virtual machine each `cpuid` traps to the
//! hypervisor: 3.6 us a query on one host, 12.5 us on another (two queries 25 us, timed in a
//! throwaway program). The standard library's `is_x86_feature_detected!` enumerates every
//! feature on its first call (88-92 us there), more than the wide build saves on a 20-case
//! solve. But the C library has already asked: glibc reads the processor's features when it
//! loads (to choose its own `memcpy`), and since 2.33 it publishes what it found and which of
//! it the OS enabled (`<sys/platform/x86.h>`, `__x86_get_cpuid_feature_leaf`). Where that is
//! there, [`wide`] reads it (0.4-3 us, the symbol looked up with `dlsym` so that an older
//! glibc or another C library still links); elsewhere it asks the processor itself: two
//! `cpuid` queries and one `xgetbv`.

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
                let wide = from_glibc().unwrap_or_else(detect);
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

/// What glibc found when it loaded: AVX2, FMA and AVX each *active* (present, and its
/// registers enabled by the OS); `None` without glibc's `__x86_get_cpuid_feature_leaf`.
///
/// The layout and indices are glibc's public ones (`<bits/platform/x86.h>`): leaf index 0 is
/// `cpuid` leaf 1 and index 1 is leaf 7; each holds the four registers as the processor gave
/// them, then the same four with only the active features' bits set (eax, ebx, ecx, edx).
#[cfg(all(target_arch = "x86_64", target_os = "linux", target_env = "gnu"))]
fn from_glibc() -> Option<bool> {
    use std::ffi::{c_char, c_void};
    #[repr(C)]
    struct CpuidFeature {
        _present: [u32; 4],
        active: [u32; 4],
    }
    extern "C" {
        fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
    }
    const ECX: usize = 2;
    const EBX: usize = 1;
    // SAFETY: `dlsym` with `RTLD_DEFAULT` (null) and a NUL-terminated name only looks the
    // symbol up.
    let found = unsafe {
        dlsym(
            std::ptr::null_mut(),
            c"__x86_get_cpuid_feature_leaf".as_ptr(),
        )
    };
    if found.is_null() {
        return None;
    }
    // SAFETY: the symbol is glibc's `const struct cpuid_feature *(unsigned int)`.
    let leaf: unsafe extern "C" fn(u32) -> *const CpuidFeature =
        unsafe { std::mem::transmute(found) };
    // SAFETY: glibc returns a pointer to its static table for every index (a zeroed entry
    // past its last), valid for the process's life.
    let (leaf1, leaf7) = unsafe { (leaf(0).as_ref()?, leaf(1).as_ref()?) };
    let active = |reg: u32, bit: u32| reg & (1 << bit) != 0;
    Some(
        active(leaf1.active[ECX], 12)
            && active(leaf1.active[ECX], 28)
            && active(leaf7.active[EBX], 5),
    )
}

/// Without glibc there is no table to read.
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_os = "linux", target_env = "gnu"))
))]
fn from_glibc() -> Option<bool> {
    None
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
        // glibc's table where there is one (2.33 and later; a `glibc.cpu.hwcaps` tunable
        // that masks AVX2 would make it say no, and the baseline build would run).
        #[cfg(all(target_os = "linux", target_env = "gnu"))]
        {
            if let Some(glibc_says) = super::from_glibc() {
                assert_eq!(glibc_says, std_says, "glibc's table");
            }
        }
        assert_eq!(super::wide(), std_says);
        assert_eq!(super::wide(), std_says, "the cached answer");
    }
}
