//! The numeric columns of an estimate in one allocation, column after
//! column, written one row at a time and handed to numpy without a copy
//! (views into one array that owns the block).
//!
//! A 1-hour 100 Hz estimate of 40 columns is 115 MB of fresh memory; with
//! 4 KiB pages the first write to each page is a page fault (about 28 000
//! of them): 9.5 % of the CPU time of `estimate` in `perf`, about as much
//! as the rest of the package's path around the estimator
//! (docs/PERFORMANCE.md). On Linux the block asks for transparent huge
//! pages (`MADV_HUGEPAGE`, 2 MiB pages: 512 times fewer faults) and
//! populates them in one call (`MADV_POPULATE_WRITE`, Linux 5.14); both
//! are hints, ignored where unsupported, and change no value.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PySlice;

use crate::cache_hints::{has_nan, stream_fence, stream_line, LINE};

/// `width` columns of room for `rows` values each, filled one row at a
/// time, with a record of which columns hold a NaN.
///
/// Rows are staged in a small buffer (one cache line per column, in L1)
/// and moved into the columns a whole cache line at a time with
/// non-temporal stores ([`stream_line`]), so that the block's memory is
/// never read back into the cache only to be overwritten.
///
/// Column `k` starts at `start + k * stride`, on a 64-byte boundary; the
/// stride is `rows` rounded up to whole 4 KiB pages plus one cache line, so
/// that the lines of a row fall into different cache sets.
#[derive(Debug, Default)]
pub struct ColumnBlock {
    data: Vec<f64>,
    start: usize,
    width: usize,
    rows: usize,
    stride: usize,
    len: usize,
    /// The rows since the last whole line: column `k`'s are
    /// `stage[k][..len % LINE]`.
    stage: Vec<[f64; LINE]>,
    /// Whether column `k` holds a NaN (among the rows moved out of the
    /// stage).
    nan: Vec<bool>,
}

/// Columns as numpy arrays, and whether each holds a NaN.
pub type NumpyColumns<'py> = (Vec<Bound<'py, PyArray1<f64>>>, Vec<bool>);

/// Values per 4 KiB page.
const PAGE_VALUES: usize = 512;

impl ColumnBlock {
    /// Room for `width` columns of `rows` values.
    pub fn new(width: usize, rows: usize) -> Self {
        let stride = rows.next_multiple_of(PAGE_VALUES) + LINE;
        let data = vec![0.0; width * stride + LINE];
        // Values up to the first 64-byte boundary (the allocation is
        // 8-byte aligned).
        let start =
            (data.as_ptr() as usize).next_multiple_of(LINE * 8) / 8 - data.as_ptr() as usize / 8;
        prepare_pages(&data);
        ColumnBlock {
            data,
            start,
            width,
            rows,
            stride,
            len: 0,
            stage: vec![[0.0; LINE]; width],
            nan: vec![false; width],
        }
    }

    /// Appends one row: `head`, then `tail` (`None` or a non-finite
    /// value as NaN), one value per column in order (`width` in all). A
    /// row beyond the block's room is dropped (a run pushes no more rows
    /// than it announced).
    #[inline]
    pub fn push_row(&mut self, head: &[f64], tail: &[Option<f64>]) {
        let i = self.len;
        if i >= self.rows {
            return;
        }
        let r = i % LINE;
        let (stage_head, stage_tail) = self.stage.split_at_mut(head.len().min(self.width));
        for (line, &v) in stage_head.iter_mut().zip(head) {
            line[r] = v;
        }
        for (line, v) in stage_tail.iter_mut().zip(tail) {
            line[r] = finite_or_nan(*v);
        }
        self.len += 1;
        if r == LINE - 1 {
            self.move_stage(i - r, LINE);
        }
    }

    /// Moves the first `n` staged rows (row `row0` on) into the columns:
    /// a whole line with non-temporal stores, a partial one (the last
    /// rows of a run) with plain stores.
    fn move_stage(&mut self, row0: usize, n: usize) {
        let columns = self.data[self.start..].chunks_exact_mut(self.stride);
        for ((col, line), nan) in columns.zip(&self.stage).zip(&mut self.nan) {
            let Some(dst) = col.get_mut(row0..row0 + n) else {
                continue;
            };
            *nan |= match <&mut [f64; LINE]>::try_from(&mut *dst) {
                Ok(whole) => stream_line(whole, line),
                Err(_) => {
                    dst.copy_from_slice(&line[..n]);
                    has_nan(&line[..n])
                }
            };
        }
    }

    /// The columns as numpy arrays (views into one array that owns the
    /// block: no copy), and whether each holds a NaN.
    pub fn into_numpy(mut self, py: Python<'_>) -> PyResult<NumpyColumns<'_>> {
        let staged = self.len % LINE;
        if staged > 0 {
            self.move_stage(self.len - staged, staged);
        }
        stream_fence();
        let (width, len, start, stride) = (self.width, self.len, self.start, self.stride);
        let block = PyArray1::from_vec(py, self.data);
        let arrays = (0..width)
            .map(|k| {
                let a = start + k * stride;
                let view = block.get_item(PySlice::new(py, a as isize, (a + len) as isize, 1))?;
                Ok(view.downcast_into::<PyArray1<f64>>()?)
            })
            .collect::<PyResult<_>>()?;
        Ok((arrays, self.nan))
    }
}

/// `v` when it is a finite value, NaN otherwise (the same NaN,
/// [`f64::NAN`]), as selects rather than a jump per cell: which
/// diagnostics are missing changes from sample to sample (the gain shares
/// after a predict-only step), and mispredicted jumps cost more than the
/// selects.
#[inline(always)]
pub fn finite_or_nan(v: Option<f64>) -> f64 {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    let bits = v.unwrap_or(f64::NAN).to_bits();
    let finite = bits & EXP != EXP;
    f64::from_bits(if finite { bits } else { f64::NAN.to_bits() })
}

/// Asks the kernel to back `data` with transparent huge pages, populated
/// at once (hints: the values stay zero).
#[cfg(target_os = "linux")]
fn prepare_pages(data: &[f64]) {
    const PAGE: usize = 4096;
    const HUGE: usize = 2 << 20;
    let bytes = std::mem::size_of_val(data);
    if bytes < 2 * HUGE {
        return;
    }
    let start = data.as_ptr() as usize;
    let aligned = start.next_multiple_of(PAGE);
    let len = (start + bytes - aligned) / PAGE * PAGE;
    // SAFETY: the range lies inside `data`'s allocation and is page
    // aligned; neither advice changes the content, only how and when the
    // kernel backs the pages. A failure (no THP, an older kernel) leaves
    // normal pages, faulted in on first write.
    unsafe {
        libc::madvise(aligned as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
        libc::madvise(aligned as *mut libc::c_void, len, libc::MADV_POPULATE_WRITE);
    }
}

#[cfg(not(target_os = "linux"))]
fn prepare_pages(_data: &[f64]) {}
