//! Where the writers put a row's cells: a CSV line ([`CsvLine`]) or the
//! column builders of an Arrow file (`crate::arrow_file::ArrowSink`). The
//! trial and estimate writers lay out a row once, generic over
//! [`CellSink`], so both formats hold the same columns in the same order.

use crate::cell_format::push_cell;

/// Receives a row's cells in column order.
pub(crate) trait CellSink {
    /// A number cell (`None`: missing; non-finite values are written missing).
    fn number(&mut self, v: Option<f64>);
    /// A label cell (`None`: missing).
    fn label(&mut self, v: Option<&str>);
}

/// One CSV line being built: every cell is preceded by a comma, so the
/// line to write is [`CsvLine::take`] without its first byte.
pub(crate) struct CsvLine {
    line: Vec<u8>,
    buf: zmij::Buffer,
}

impl CsvLine {
    /// An empty line with room for `capacity` bytes.
    pub(crate) fn with_capacity(capacity: usize) -> Self {
        CsvLine {
            line: Vec::with_capacity(capacity),
            buf: zmij::Buffer::new(),
        }
    }

    /// Starts a new line.
    #[inline]
    pub(crate) fn clear(&mut self) {
        self.line.clear();
    }

    /// The finished line with its `\n`, without the leading comma.
    #[inline]
    pub(crate) fn finish(&mut self) -> &[u8] {
        self.line.push(b'\n');
        &self.line[1..]
    }

    /// Bytes held: several rows can be built one after the other
    /// ([`CsvLine::end_row`]) and taken at once ([`CsvLine::take_rows`]).
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.line.len()
    }

    /// Ends the row that started at byte `at` (its leading comma): a row
    /// after another one starts with the line break that ends the other.
    #[inline]
    pub(crate) fn end_row(&mut self, at: usize) {
        if at > 0 {
            self.line[at] = b'\n';
        }
    }

    /// The rows built since the last call (each ended with `\n`; empty if
    /// none); [`CsvLine::clear`] before the next row.
    pub(crate) fn take_rows(&mut self) -> &[u8] {
        if self.line.is_empty() {
            return &[];
        }
        self.finish()
    }
}

impl CellSink for CsvLine {
    #[inline]
    fn number(&mut self, v: Option<f64>) {
        push_cell(&mut self.line, &mut self.buf, v);
    }

    #[inline]
    fn label(&mut self, v: Option<&str>) {
        self.line.push(b',');
        if let Some(t) = v {
            self.line.extend_from_slice(t.as_bytes());
        }
    }
}
