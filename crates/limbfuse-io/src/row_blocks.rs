//! A trial file parsed in blocks on every core (issue 18 item 6): the
//! file is read in blocks of 1 MiB; the whole lines of a block are split
//! at line breaks into one chunk per thread, and each chunk's cells are
//! parsed straight into a compact row-major table of numbers (only the
//! columns a record reads; a missing cell is NaN, which a file cannot hold
//! since non-finite numbers are errors). [`crate::TrialReader`] builds its
//! records from those numbers in file order, then the next block is read.
//! Memory: one block and its numbers, whatever the file length.
//!
//! Only clean rows take this path. At the first line that the streaming
//! reader might read differently (a quote, a malformed or non-finite number,
//! an empty time, a contact other than 0/1, an unknown gait phase, a row of
//! the wrong length, a line longer than a block), the rows before it are
//! read as usual and the streaming reader takes over at that line, with the
//! rest of the file, its line count and the content hash so far: it finds
//! and reports the error (or reads the row) exactly as it always did. A
//! time that does not increase is found on the parsed path, with the same
//! error.

use std::fs::File;
use std::io::{Cursor, Read};
use std::path::Path;

use limbfuse_core::GaitPhase;
use memchr::{memchr, memchr_iter, memrchr};

use crate::cell_format::parse_number;
use crate::content_hash::{HashHandle, HashingReader};
use crate::csv_lines::{is_blank, split_plain};
use crate::error::FileError;
use crate::table::TableReader;
use crate::trial_reader::{ColumnPlan, RowCells, PHASE_EXPECTED};

/// Bytes read and parsed at a time.
const BLOCK_BYTES: usize = 1 << 20;

/// Gait phases by the code stored for them.
const PHASES: [GaitPhase; 3] = [GaitPhase::Ss1, GaitPhase::Ds, GaitPhase::Ss2];

/// How many threads parse and format: the cores available, at most 8.
pub(crate) fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(8))
}

/// How a column's cells are checked.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// The time: present.
    Time,
    /// A number or empty.
    Number,
    /// A foot contact: 0, 1 or empty.
    Contact,
    /// A gait phase label or empty (stored as its index in [`PHASES`]).
    Phase,
}

/// The parsed rows of one chunk of a block.
#[derive(Debug, Default)]
struct Chunk {
    /// Row-major numbers, `width` per row.
    values: Vec<f64>,
    /// The line of each row, counted from the chunk's first line (0).
    lines: Vec<u32>,
    /// Lines in the chunk before its stop (blank ones too).
    n_lines: u64,
    /// The byte offset (in the chunk) of the first line that is not clean.
    stop: Option<usize>,
    /// 1-based line number of the chunk's first line.
    first_line: u64,
    /// Byte offset of the chunk in the block.
    offset: usize,
}

/// A trial file being read in parsed blocks.
pub(crate) struct RowBlocks {
    /// The file (`None` once handed over to the streaming reader).
    file: Option<HashingReader<File>>,
    hash: HashHandle,
    buf: Vec<u8>,
    /// Bytes of `buf` read from the file.
    valid: usize,
    /// Bytes of `buf` parsed (the rest is a partial line).
    parsed: usize,
    at_end: bool,
    /// 1-based line number of the line at `parsed`.
    next_line: u64,
    n_columns: usize,
    /// The file column and kind of each slot of a row.
    slots: Vec<(usize, Kind)>,
    /// The slot of each file column (`u32::MAX`: not read).
    slot_of: Vec<u32>,
    chunks: Vec<Chunk>,
    chunk: usize,
    row: usize,
}

impl std::fmt::Debug for RowBlocks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RowBlocks")
            .field("next_line", &self.next_line)
            .finish()
    }
}

/// What comes next in a file read in blocks.
pub(crate) enum Next<'a> {
    /// A parsed row.
    Row(ParsedRow<'a>),
    /// The end of the file.
    End,
    /// The streaming reader takes over: the rest of the file from the
    /// line after `lines_read`, hashed into `hash`.
    Stream {
        source: Box<dyn Read + Send>,
        lines_read: u64,
        hash: HashHandle,
    },
}

/// Opens `path` and reads its comments and header; `None` when the file
/// must be read by the streaming reader from its start (Arrow, unreadable,
/// quotes or no line break in its first block).
pub(crate) fn open(path: &Path) -> Option<(TableReader, RowBlocks)> {
    if crate::arrow_file::is_arrow_path(path) {
        return None;
    }
    let (file, hash) = HashingReader::new(File::open(path).ok()?);
    let mut blocks = RowBlocks {
        file: Some(file),
        hash,
        buf: vec![0; BLOCK_BYTES],
        valid: 0,
        parsed: 0,
        at_end: false,
        next_line: 1,
        n_columns: 0,
        slots: Vec::new(),
        slot_of: Vec::new(),
        chunks: (0..threads()).map(|_| Chunk::default()).collect(),
        chunk: 0,
        row: 0,
    };
    blocks.fill().ok()?;
    let head = &blocks.buf[..blocks.valid];
    // The header must be one line (no quotes) within the first block.
    let header_end = memrchr(b'\n', head)?;
    let table =
        TableReader::from_reader(path, Box::new(Cursor::new(head[..=header_end].to_vec()))).ok()?;
    let header_line = table.header_line();
    let nth = usize::try_from(header_line.checked_sub(1)?).ok()?;
    let end = memchr_iter(b'\n', head).nth(nth)?;
    if memchr(b'"', &head[..end]).is_some() {
        return None;
    }
    blocks.parsed = end + 1;
    blocks.next_line = header_line + 1;
    Some((table, blocks))
}

impl RowBlocks {
    /// Sets which columns a record reads; `None` when the plan cannot be
    /// parsed ahead (then the streaming reader reads the file).
    pub(crate) fn plan(mut self, plan: &ColumnPlan, n_columns: usize) -> Option<Self> {
        let mut slots: Vec<(usize, Kind)> = plan
            .number_columns()
            .into_iter()
            .map(|c| (c, Kind::Number))
            .collect();
        for (c, kind) in &mut slots {
            if *c == plan.time() {
                *kind = Kind::Time;
            } else if plan.contact_columns().any(|k| k == *c) {
                *kind = Kind::Contact;
            }
        }
        if let Some(c) = plan.phase_column() {
            if slots.iter().any(|&(s, _)| s == c) {
                return None;
            }
            slots.push((c, Kind::Phase));
        }
        let mut slot_of = vec![u32::MAX; n_columns];
        for (k, &(c, _)) in slots.iter().enumerate() {
            *slot_of.get_mut(c)? = u32::try_from(k).ok()?;
        }
        self.slots = slots;
        self.slot_of = slot_of;
        self.n_columns = n_columns;
        Some(self)
    }

    /// Reads until the buffer is full or the file ends.
    fn fill(&mut self) -> std::io::Result<()> {
        while self.valid < self.buf.len() && !self.at_end {
            let Some(file) = &mut self.file else {
                self.at_end = true;
                break;
            };
            match file.read(&mut self.buf[self.valid..]) {
                Ok(0) => self.at_end = true,
                Ok(n) => self.valid += n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(())
    }

    /// The next row, the end, or the streaming reader's turn.
    pub(crate) fn next_row<'a>(
        &'a mut self,
        path: &'a Path,
        header: &'a [String],
    ) -> Result<Next<'a>, FileError> {
        loop {
            if self.chunk >= self.chunks.len() {
                if self.parsed == self.valid && self.at_end {
                    // Reach the end of the source so that its hash is final.
                    self.fill().map_err(|e| FileError::io(path, e))?;
                    return Ok(Next::End);
                }
                self.next_block(path)?;
                continue;
            }
            let (n_rows, stop) = {
                let c = &self.chunks[self.chunk];
                (c.lines.len(), c.stop)
            };
            if self.row < n_rows {
                let r = self.row;
                self.row += 1;
                let width = self.slots.len();
                let chunk = &self.chunks[self.chunk];
                return Ok(Next::Row(ParsedRow {
                    values: &chunk.values[r * width..(r + 1) * width],
                    slot_of: &self.slot_of,
                    line: chunk.first_line + u64::from(chunk.lines[r]),
                    path,
                    header,
                }));
            }
            if let Some(stop) = stop {
                let chunk = &self.chunks[self.chunk];
                let at = chunk.offset + stop;
                let lines_read = chunk.first_line + chunk.n_lines - 1;
                return Ok(self.hand_over(at, lines_read));
            }
            self.chunk += 1;
            self.row = 0;
        }
    }

    /// At the end: the lines read and the hash of the file.
    pub(crate) fn lines_read_and_hash(&self) -> (u64, HashHandle) {
        (self.next_line - 1, self.hash.clone())
    }

    /// The streaming reader's source from byte `at` of the block on.
    fn hand_over(&mut self, at: usize, lines_read: u64) -> Next<'static> {
        let rest = Cursor::new(self.buf[at..self.valid].to_vec());
        self.chunks.clear();
        let source: Box<dyn Read + Send> = match self.file.take() {
            Some(file) => Box::new(rest.chain(file)),
            None => Box::new(rest),
        };
        Next::Stream {
            source,
            lines_read,
            hash: self.hash.clone(),
        }
    }

    /// Reads and parses the next block.
    fn next_block(&mut self, path: &Path) -> Result<(), FileError> {
        self.buf.copy_within(self.parsed..self.valid, 0);
        self.valid -= self.parsed;
        self.parsed = 0;
        self.fill().map_err(|e| FileError::io(path, e))?;
        let end = if self.at_end {
            self.valid
        } else {
            match memrchr(b'\n', &self.buf[..self.valid]) {
                Some(i) => i + 1,
                // A line longer than a block: the streaming reader reads it.
                None => 0,
            }
        };
        let text = &self.buf[..end];
        let n = self.chunks.len();
        let bounds = chunk_bounds(text, n);
        let (n_columns, slots) = (self.n_columns, &self.slots[..]);
        std::thread::scope(|s| {
            let mut parts = self.chunks.iter_mut().zip(bounds.windows(2));
            let first = parts.next();
            for (chunk, w) in parts {
                s.spawn(move || parse_chunk(&text[w[0]..w[1]], w[0], n_columns, slots, chunk));
            }
            if let Some((chunk, w)) = first {
                parse_chunk(&text[w[0]..w[1]], w[0], n_columns, slots, chunk);
            }
        });
        let mut line = self.next_line;
        let mut stopped = false;
        for chunk in &mut self.chunks {
            chunk.first_line = line;
            line += chunk.n_lines;
            if stopped {
                chunk.lines.clear();
                chunk.stop = Some(0);
            }
            stopped |= chunk.stop.is_some();
        }
        if end == 0 && !self.at_end {
            // Nothing parsed: hand the long line over.
            if let Some(c) = self.chunks.first_mut() {
                c.stop = Some(0);
            }
        }
        self.next_line = line;
        self.parsed = end;
        self.chunk = 0;
        self.row = 0;
        Ok(())
    }
}

/// Splits `text` into `n` parts at line breaks: `n + 1` increasing
/// offsets (some parts may be empty).
fn chunk_bounds(text: &[u8], n: usize) -> Vec<usize> {
    let mut bounds = vec![0];
    for k in 1..n {
        let target = (text.len() * k / n).max(*bounds.last().unwrap_or(&0));
        let cut = match memchr(b'\n', &text[target..]) {
            Some(i) => target + i + 1,
            None => text.len(),
        };
        bounds.push(cut);
    }
    bounds.push(text.len());
    bounds
}

/// Parses the lines of `text` (whole lines; at byte `offset` of the block)
/// into `chunk`, up to the first line that is not clean.
fn parse_chunk(
    text: &[u8],
    offset: usize,
    n_columns: usize,
    slots: &[(usize, Kind)],
    chunk: &mut Chunk,
) {
    chunk.values.clear();
    chunk.lines.clear();
    chunk.n_lines = 0;
    chunk.stop = None;
    chunk.offset = offset;
    let mut cells: Vec<(u32, u32)> = Vec::with_capacity(n_columns);
    let mut start = 0;
    let mut breaks = memchr_iter(b'\n', text);
    while start < text.len() {
        let end = breaks.next().unwrap_or(text.len());
        let line = &text[start..end];
        let clean = u32::try_from(chunk.n_lines)
            .ok()
            .and_then(|index| parse_line(line, index, n_columns, slots, &mut cells, chunk));
        if clean.is_none() {
            // Drop the partial row.
            chunk.values.truncate(chunk.lines.len() * slots.len());
            chunk.stop = Some(start);
            return;
        }
        start = end + 1;
        chunk.n_lines += 1;
    }
}

/// Parses one line into `chunk`; `None` when it is not clean.
#[inline]
fn parse_line(
    line: &[u8],
    index: u32,
    n_columns: usize,
    slots: &[(usize, Kind)],
    cells: &mut Vec<(u32, u32)>,
    chunk: &mut Chunk,
) -> Option<()> {
    if !split_plain(line, cells) {
        return None;
    }
    if is_blank(cells) {
        return Some(());
    }
    if cells.len() != n_columns {
        return None;
    }
    for &(c, kind) in slots {
        let (a, b) = cells[c];
        let raw = &line[a as usize..b as usize];
        let v = match kind {
            Kind::Phase => phase_code(raw)?,
            Kind::Time if raw.is_empty() => return None,
            _ if raw.is_empty() => f64::NAN,
            _ => {
                let v = parse_number(raw).filter(|v| v.is_finite())?;
                if kind == Kind::Contact && v != 0.0 && v != 1.0 {
                    return None;
                }
                v
            }
        };
        chunk.values.push(v);
    }
    chunk.lines.push(index);
    Some(())
}

/// The stored code of a gait phase cell (NaN when empty).
fn phase_code(raw: &[u8]) -> Option<f64> {
    if raw.is_empty() {
        return Some(f64::NAN);
    }
    let phase = GaitPhase::from_label(std::str::from_utf8(raw).ok()?)?;
    PHASES
        .iter()
        .position(|&p| p == phase)
        .map(|k| k as f64)
}

/// One parsed row.
pub(crate) struct ParsedRow<'a> {
    values: &'a [f64],
    slot_of: &'a [u32],
    line: u64,
    path: &'a Path,
    header: &'a [String],
}

impl ParsedRow<'_> {
    #[inline]
    fn value(&self, col: usize) -> Option<f64> {
        let slot = *self.slot_of.get(col)? as usize;
        self.values.get(slot).copied().filter(|v| !v.is_nan())
    }
}

impl RowCells for ParsedRow<'_> {
    #[inline]
    fn number(&self, col: usize) -> Result<Option<f64>, FileError> {
        Ok(self.value(col))
    }

    #[inline]
    fn time(&self, col: usize, previous: Option<f64>) -> Result<f64, FileError> {
        let t = self
            .value(col)
            .ok_or_else(|| self.cell_error(col, "a time in seconds (t cannot be empty)"))?;
        match previous {
            Some(previous) if t <= previous => Err(FileError::TimeNotIncreasing {
                path: self.path.to_path_buf(),
                line: self.line,
                column: col + 1,
                t,
                previous,
            }),
            _ => Ok(t),
        }
    }

    fn phase(&self, col: usize) -> Result<Option<GaitPhase>, FileError> {
        match self.value(col) {
            None => Ok(None),
            Some(code) => PHASES
                .get(code as usize)
                .copied()
                .map(Some)
                .ok_or_else(|| self.cell_error(col, PHASE_EXPECTED)),
        }
    }

    fn cell_error(&self, col: usize, expected: &'static str) -> FileError {
        FileError::Cell {
            path: self.path.to_path_buf(),
            line: self.line,
            column: col + 1,
            name: self.header.get(col).cloned().unwrap_or_default(),
            expected,
            found: self.value(col).map(|v| v.to_string()).unwrap_or_default(),
        }
    }
}
