//! Non-temporal stores for the output columns of a run.
//!
//! A run writes about 40 output columns, 8 bytes of each per sample, into
//! fresh memory (132 MB for a 1-hour estimate of mjls's 46 columns).
//! A plain store first reads each line into the cache
//! (read-for-ownership) only to overwrite it, and the stream of lines
//! evicts the estimator's own data; [`stream_line`] writes a whole line
//! without either (x86-64 `movntpd`; a plain copy elsewhere). It changes
//! no value.

/// Cells (f64) per 64-byte cache line.
pub const LINE: usize = 8;

/// Copies `src` to `dst` with non-temporal stores when `dst` is 16-byte
/// aligned (a plain copy otherwise). [`stream_fence`] must follow the
/// last such copy before another thread reads `dst`.
#[inline(always)]
pub fn stream_line(dst: &mut [f64; LINE], src: &[f64; LINE]) {
    #[cfg(target_arch = "x86_64")]
    if (dst.as_ptr() as usize).is_multiple_of(16) {
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
