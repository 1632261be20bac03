//! Software prefetch of a cache line: the traversal's large read-mostly arrays (nodes put off
//! for later, the hit's primitive entry) are asked for before they are read, so that their
//! cache misses overlap other work in large scenes. A hint only: no result changes.

/// Starts loading the cache line holding `p` into all cache levels. Never faults, whatever the
/// address (a pointer past an array's end included); a no-op off x86-64.
#[inline(always)]
pub(crate) fn prefetch_line<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing and never faults, whatever the address; SSE is part of
    // x86-64.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
