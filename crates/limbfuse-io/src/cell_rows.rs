//! Rows of an estimate file kept as numbers and formatted as CSV text on
//! every core (issue 18 item 6): the writer of an estimate *file* collects
//! a block of rows here, then each thread formats a contiguous part of the
//! block into its own byte buffer and the buffers are written in order.
//! The text is byte for byte what [`crate::cell_sink::CsvLine`] writes
//! row by row (the same cell formatter).

use std::io::{self, Write};

use crate::cell_format::push_value;
use crate::cell_sink::CellSink;

/// Rows collected before they are formatted and written.
pub(crate) const BLOCK_ROWS: usize = 16384;

/// A block of rows, row-major; a missing number is NaN (a file holds no
/// non-finite number: they are written as missing cells), a label its
/// index in `labels` (NaN: missing).
pub(crate) struct CellRows {
    values: Vec<f64>,
    /// Cells per row, known once the first row has ended (0 before).
    width: usize,
    /// Whether each column holds labels (from the first row).
    is_label: Vec<bool>,
    labels: Vec<String>,
    rows: usize,
    /// One text buffer per thread, reused from block to block.
    texts: Vec<Vec<u8>>,
}

impl CellRows {
    /// An empty block, formatted on `threads` threads.
    pub(crate) fn new(threads: usize) -> Self {
        CellRows {
            values: Vec::new(),
            width: 0,
            is_label: Vec::new(),
            labels: Vec::new(),
            rows: 0,
            texts: (0..threads.max(1)).map(|_| Vec::new()).collect(),
        }
    }

    /// Ends the current row.
    #[inline]
    pub(crate) fn end_row(&mut self) {
        if self.width == 0 {
            self.width = self.is_label.len();
        }
        self.rows += 1;
    }

    /// Rows collected and not yet written.
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.rows
    }

    /// Formats the collected rows, writes them to `out` in order and
    /// empties the block.
    pub(crate) fn write_to<W: Write + ?Sized>(&mut self, out: &mut W) -> io::Result<()> {
        if self.rows == 0 {
            return Ok(());
        }
        if self.width == 0 || self.values.len() != self.rows * self.width {
            return Err(io::Error::other(
                "estimate rows of different lengths (an internal error)",
            ));
        }
        let per_part = self.rows.div_ceil(self.texts.len()).max(1);
        let (values, width) = (&self.values, self.width);
        let (is_label, labels) = (&self.is_label[..], &self.labels[..]);
        let parts = values.chunks(per_part * width);
        std::thread::scope(|s| {
            let mut texts = self.texts.iter_mut().zip(parts);
            let first = texts.next();
            for (text, part) in texts {
                s.spawn(move || format_rows(part, width, is_label, labels, text));
            }
            if let Some((text, part)) = first {
                format_rows(part, width, is_label, labels, text);
            }
        });
        let used = self.rows.div_ceil(per_part);
        for text in &self.texts[..used] {
            out.write_all(text)?;
        }
        self.values.clear();
        self.rows = 0;
        Ok(())
    }
}

/// Formats rows of `width` cells as CSV lines into `text` (emptied first).
fn format_rows(values: &[f64], width: usize, is_label: &[bool], labels: &[String], text: &mut Vec<u8>) {
    text.clear();
    let mut buf = zmij::Buffer::new();
    for row in values.chunks_exact(width) {
        for (c, (&v, &label)) in row.iter().zip(is_label).enumerate() {
            if c > 0 {
                text.push(b',');
            }
            if label {
                if let Some(l) = (!v.is_nan()).then(|| labels.get(v as usize)).flatten() {
                    text.extend_from_slice(l.as_bytes());
                }
            } else {
                push_value(text, &mut buf, Some(v));
            }
        }
        text.push(b'\n');
    }
}

impl CellSink for CellRows {
    #[inline]
    fn number(&mut self, v: Option<f64>) {
        if self.width == 0 {
            self.is_label.push(false);
        }
        self.values
            .push(v.filter(|v| v.is_finite()).unwrap_or(f64::NAN));
    }

    fn label(&mut self, v: Option<&str>) {
        if self.width == 0 {
            self.is_label.push(true);
        }
        let code = v.map_or(f64::NAN, |v| {
            let k = match self.labels.iter().position(|l| l == v) {
                Some(k) => k,
                None => {
                    self.labels.push(v.to_string());
                    self.labels.len() - 1
                }
            };
            k as f64
        });
        self.values.push(code);
    }
}
