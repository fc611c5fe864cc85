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
/// aligned (a plain copy otherwise) and returns whether `src` holds a
/// NaN (tested on the values as they pass, without a branch per value).
/// [`stream_fence`] must follow the last such copy before another thread
/// reads `dst`.
#[inline(always)]
pub fn stream_line(dst: &mut [f64; LINE], src: &[f64; LINE]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if (dst.as_ptr() as usize).is_multiple_of(16) {
        use std::arch::x86_64::{
            _mm_cmpunord_pd, _mm_loadu_pd, _mm_movemask_pd, _mm_or_pd, _mm_setzero_pd,
            _mm_stream_pd,
        };
        // SAFETY: SSE2 is part of the x86-64 baseline; a register op.
        let mut nan = unsafe { _mm_setzero_pd() };
        for (d, s) in dst.chunks_exact_mut(2).zip(src.chunks_exact(2)) {
            // SAFETY: `d` and `s` are two valid f64 each; `d` is 16-byte
            // aligned (the line is, and each pair starts 16 bytes after
            // the previous one).
            unsafe {
                let v = _mm_loadu_pd(s.as_ptr());
                _mm_stream_pd(d.as_mut_ptr(), v);
                nan = _mm_or_pd(nan, _mm_cmpunord_pd(v, v));
            }
        }
        // SAFETY: a register op.
        return unsafe { _mm_movemask_pd(nan) } != 0;
    }
    *dst = *src;
    has_nan(src)
}

/// Whether `v` holds a NaN (one pass, no early exit: the comparisons
/// vectorise).
#[inline(always)]
pub fn has_nan(v: &[f64]) -> bool {
    v.iter().fold(false, |acc, x| acc | x.is_nan())
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
