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
