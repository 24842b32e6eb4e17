//! A hint that memory is about to be read, so that a table lookup's cache miss overlaps other
//! work instead of stalling it. It changes no result, only when the data arrives.

/// Asks for the cache line holding `*r` to be loaded into every cache level.
#[inline(always)]
pub fn prefetch<T>(r: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch never faults, whatever the address; SSE is part of x86-64.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>((r as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = r;
}
