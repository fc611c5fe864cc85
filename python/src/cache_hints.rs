//! Cache hints for the columns a run streams through.
//!
//! A run reads about 30 input columns and writes about 40 output columns,
//! 8 bytes of each per sample: more concurrent streams than the hardware
//! prefetchers follow. [`prefetch`] asks for an input line a few samples
//! ahead; [`stream_line`] writes a whole output line without first reading
//! it into the cache (a non-temporal store: no read-for-ownership of the
//! 115 MB of a 1-hour estimate, and the estimator's own data stays
//! cached). On x86-64 they are `prefetcht0` and `movntpd`; elsewhere a
//! no-op and a plain copy. Neither changes a value.

/// Cells (f64) per 64-byte cache line.
pub const LINE: usize = 8;

/// How far ahead (in samples) of the current one an input line is
/// requested: two lines, tens of microseconds of estimator work, far more
/// than a memory access takes.
pub const AHEAD: usize = 2 * LINE;

/// Hints that `column[at]` will be read soon (no-op when `at` is outside
/// `column`).
#[inline(always)]
pub fn prefetch(column: &[f64], at: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(cell) = column.get(at) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: `cell` is a valid reference; a prefetch only moves the
        // line into the cache and has no other architectural effect.
        unsafe { _mm_prefetch::<_MM_HINT_T0>((cell as *const f64).cast::<i8>()) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (column, at);
}

/// Copies `src` to `dst` with non-temporal stores when `dst` is 16-byte
/// aligned (a plain copy otherwise). [`stream_fence`] must follow the
/// last such copy before another thread reads `dst`.
#[inline(always)]
pub fn stream_line(dst: &mut [f64; LINE], src: &[f64; LINE]) {
    #[cfg(target_arch = "x86_64")]
    if (dst.as_ptr() as usize) % 16 == 0 {
        use std::arch::x86_64::{_mm_loadu_pd, _mm_stream_pd};
        for (d, s) in dst.chunks_exact_mut(2).zip(src.chunks_exact(2)) {
            // SAFETY: `d` and `s` are two valid f64 each; `d` is 16-byte
            // aligned (the line is, and each pair starts 16 bytes after
            // the previous one).
            unsafe { _mm_stream_pd(d.as_mut_ptr(), _mm_loadu_pd(s.as_ptr())) };
        }
        return;
    }
    *dst = *src;
}

/// Orders the non-temporal stores of [`stream_line`] before every later
/// store (x86-64 `sfence`; nothing elsewhere).
#[inline]
pub fn stream_fence() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is part of the x86-64 baseline; a fence has no operand.
    unsafe {
        std::arch::x86_64::_mm_sfence()
    };
}
