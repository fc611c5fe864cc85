//! The numeric columns of an estimate in one allocation, column after
//! column, handed to numpy without a copy (one 2-D array whose rows are
//! the columns).
//!
//! A 1-hour 100 Hz estimate of 40 columns is 115 MB of fresh memory; with
//! 4 KiB pages the first write to each page is a page fault (about 28 000
//! of them): 9.5 % of the CPU time of `estimate` in `perf`, about as much
//! as the rest of the package's path around the estimator
//! (docs/PERFORMANCE.md). On Linux the block asks for transparent huge
//! pages (`MADV_HUGEPAGE`, 2 MiB pages: 512 times fewer faults) and
//! populates them in one call (`MADV_POPULATE_WRITE`, Linux 5.14); both
//! are hints, ignored where unsupported, and change no value.

use numpy::ndarray::Array2;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PySlice;

/// `width` columns of room for `rows` values each, filled a block of rows
/// at a time.
#[derive(Debug, Default)]
pub struct ColumnBlock {
    /// Column `k` is `data[k * rows..(k + 1) * rows]`.
    data: Vec<f64>,
    width: usize,
    rows: usize,
    len: usize,
}

impl ColumnBlock {
    /// Room for `width` columns of `rows` values (no memory touched yet).
    pub fn new(width: usize, rows: usize) -> Self {
        let data = vec![0.0; width * rows];
        prepare_pages(&data);
        ColumnBlock {
            data,
            width,
            rows,
            len: 0,
        }
    }

    /// Appends `staged` rows of `stage` (row-major, `width` values per row)
    /// to the columns, one column at a time. Rows beyond the block's room
    /// are dropped (a run pushes no more rows than it announced).
    pub fn append_rows(&mut self, stage: &[f64], staged: usize) {
        let staged = staged.min(self.rows - self.len);
        let (width, start) = (self.width, self.len);
        for (k, col) in self.data.chunks_exact_mut(self.rows.max(1)).enumerate() {
            if let Some(dst) = col.get_mut(start..start + staged) {
                for (r, d) in dst.iter_mut().enumerate() {
                    *d = stage[r * width + k];
                }
            }
        }
        self.len += staged;
    }

    /// The columns as numpy arrays: views into one array that owns the
    /// block (no copy).
    pub fn into_numpy(self, py: Python<'_>) -> PyResult<Vec<Bound<'_, PyArray1<f64>>>> {
        let (width, len) = (self.width, self.len);
        let shape = (width, self.rows);
        let array = Array2::from_shape_vec(shape, self.data)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        let block = PyArray2::from_owned_array(py, array);
        let rows = PySlice::new(py, 0, len as isize, 1);
        (0..width)
            .map(|k| {
                let view = block.get_item((k, &rows))?;
                Ok(view.downcast_into::<PyArray1<f64>>()?)
            })
            .collect()
    }
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
