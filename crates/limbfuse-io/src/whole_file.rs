//! A trial file read whole and parsed on every core (issue 18 item 6):
//! the rows after the header are split at line breaks into one chunk per
//! thread, and each chunk's cells are parsed straight into a compact
//! row-major table of numbers (only the columns a record reads; a missing
//! cell is NaN, which a file cannot hold since non-finite numbers are
//! errors). [`crate::TrialReader`] then builds its records from those
//! numbers in file order.
//!
//! Only clean files take this path: at the first cell, row or line that the
//! streaming reader would refuse or read differently (a quote, a malformed
//! or non-finite number, an empty time, a time not after the previous one,
//! a contact other than 0/1, an unknown gait phase, a row of the wrong
//! length, a very long line, no rows at all), parsing stops and the caller
//! reads the file with the streaming reader instead, which finds and
//! reports the first error by file order exactly as before.

use std::io::Cursor;
use std::path::Path;

use limbfuse_core::GaitPhase;
use memchr::{memchr, memchr_iter};

use crate::cell_format::parse_number;
use crate::content_hash::ContentHash;
use crate::csv_lines::{is_blank, split_plain, MAX_LINE_BYTES};
use crate::error::FileError;
use crate::table::TableReader;
use crate::trial_reader::{ColumnPlan, RowCells, PHASE_EXPECTED};

/// Files larger than this are streamed (memory stays bounded).
const WHOLE_FILE_LIMIT: u64 = 1 << 30;

/// The comments and header must end within this many bytes.
const HEAD_LIMIT: usize = 1 << 20;

/// Gait phases by the code stored for them.
const PHASES: [GaitPhase; 3] = [GaitPhase::Ss1, GaitPhase::Ds, GaitPhase::Ss2];

/// How many threads parse and format: the cores available, at most 8.
pub(crate) fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get().min(8))
}

/// A trial file in memory, its header read.
pub(crate) struct WholeFile {
    table: TableReader,
    body: Body,
}

/// The bytes of a file and where its rows start.
pub(crate) struct Body {
    bytes: Vec<u8>,
    start: usize,
    /// 1-based line number of the first line after the header.
    first_line: u64,
}

/// Reads `path` whole and its header; `None` when the file must be
/// streamed instead (Arrow, too large, quoted cells, an unreadable head).
pub(crate) fn load(path: &Path) -> Option<WholeFile> {
    if crate::arrow_file::is_arrow_path(path) {
        return None;
    }
    if std::fs::metadata(path).ok()?.len() > WHOLE_FILE_LIMIT {
        return None;
    }
    let bytes = std::fs::read(path).ok()?;
    if memchr(b'"', &bytes).is_some() {
        return None;
    }
    let head = bytes[..bytes.len().min(HEAD_LIMIT)].to_vec();
    let table = TableReader::from_reader(path, Box::new(Cursor::new(head))).ok()?;
    // No quotes: the header is one line, line `header_line`.
    let header_line = table.header_line();
    let nth = usize::try_from(header_line.checked_sub(1)?).ok()?;
    let end = memchr_iter(b'\n', &bytes[..bytes.len().min(HEAD_LIMIT)]).nth(nth)?;
    Some(WholeFile {
        table,
        body: Body {
            bytes,
            start: end + 1,
            first_line: header_line + 1,
        },
    })
}

impl WholeFile {
    /// The header (as a streaming table) and the rows still to parse.
    pub(crate) fn into_parts(self) -> (TableReader, Body) {
        (self.table, self.body)
    }
}

/// How a column's cells are checked.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// The time: present and increasing.
    Time,
    /// A number or empty.
    Number,
    /// A foot contact: 0, 1 or empty.
    Contact,
    /// A gait phase label or empty (stored as its index in [`PHASES`]).
    Phase,
}

/// The rows of one chunk.
struct Chunk {
    /// Row-major numbers, `width` per row.
    values: Vec<f64>,
    /// The line of each row, counted from the chunk's first line (0).
    lines: Vec<u32>,
    /// Lines in the chunk (blank ones too).
    n_lines: u64,
    /// 1-based line number of the chunk's first line (set after parsing).
    first_line: u64,
}

impl Body {
    /// Parses the rows on [`threads`] threads; `None` when a row is not
    /// clean (see the module documentation) or there are none.
    pub(crate) fn parse(self, plan: &ColumnPlan, n_columns: usize) -> Option<ParsedRows> {
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
        let text = &self.bytes[self.start..];
        let bounds = chunk_bounds(text, threads());
        let (chunks, hash) = std::thread::scope(|s| {
            let workers: Vec<_> = bounds
                .windows(2)
                .map(|w| {
                    let part = &text[w[0]..w[1]];
                    let slots = &slots;
                    s.spawn(move || parse_chunk(part, n_columns, slots))
                })
                .collect();
            let hash = ContentHash::of_bytes(&self.bytes);
            let chunks: Option<Vec<Chunk>> = workers
                .into_iter()
                .map(|w| w.join().ok().flatten())
                .collect();
            (chunks, hash)
        });
        let mut chunks = chunks?;
        drop(self.bytes);
        let width = slots.len();
        let t_slot = slots.iter().position(|&(_, k)| k == Kind::Time)?;
        let mut line = self.first_line;
        let mut last_t: Option<f64> = None;
        for chunk in &mut chunks {
            chunk.first_line = line;
            line += chunk.n_lines;
            if let Some(&first) = chunk.values.get(t_slot) {
                if last_t.is_some_and(|last| first <= last) {
                    return None;
                }
                last_t = chunk.values.get(chunk.values.len() - width + t_slot).copied();
            }
        }
        last_t?;
        chunks.retain(|c| !c.values.is_empty());
        Some(ParsedRows {
            chunks,
            width,
            slot_of,
            chunk: 0,
            row: 0,
            hash,
            finished: false,
        })
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

/// Parses the lines of `text` (whole lines only); `None` at the first row
/// that is not clean.
fn parse_chunk(text: &[u8], n_columns: usize, slots: &[(usize, Kind)]) -> Option<Chunk> {
    let width = slots.len();
    let mut chunk = Chunk {
        values: Vec::with_capacity(text.len() / (n_columns * 16).max(1) * width),
        lines: Vec::new(),
        n_lines: 0,
        first_line: 0,
    };
    let mut cells: Vec<(u32, u32)> = Vec::with_capacity(n_columns);
    let mut previous_t = f64::NEG_INFINITY;
    let mut start = 0;
    let mut breaks = memchr_iter(b'\n', text);
    while start < text.len() {
        let end = breaks.next().unwrap_or(text.len());
        let line = &text[start..end];
        start = end + 1;
        let index = u32::try_from(chunk.n_lines).ok()?;
        chunk.n_lines += 1;
        if line.len() >= MAX_LINE_BYTES / 2 || !split_plain(line, &mut cells) {
            return None;
        }
        if is_blank(&cells) {
            continue;
        }
        if cells.len() != n_columns {
            return None;
        }
        for &(c, kind) in slots {
            let (a, b) = cells[c];
            let raw = &line[a as usize..b as usize];
            let v = match kind {
                Kind::Phase => phase_code(raw)?,
                _ if raw.is_empty() => {
                    if kind == Kind::Time {
                        return None;
                    }
                    f64::NAN
                }
                _ => {
                    let v = parse_number(raw).filter(|v| v.is_finite())?;
                    match kind {
                        Kind::Time if v <= previous_t => return None,
                        Kind::Time => previous_t = v,
                        Kind::Contact if v != 0.0 && v != 1.0 => return None,
                        _ => {}
                    }
                    v
                }
            };
            chunk.values.push(v);
        }
        chunk.lines.push(index);
    }
    Some(chunk)
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

/// The parsed rows of a whole file, read in order.
#[derive(Debug)]
pub(crate) struct ParsedRows {
    chunks: Vec<Chunk>,
    width: usize,
    /// The slot of each file column (`u32::MAX`: not read).
    slot_of: Vec<u32>,
    chunk: usize,
    row: usize,
    hash: ContentHash,
    finished: bool,
}

impl std::fmt::Debug for Chunk {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Chunk")
            .field("rows", &self.lines.len())
            .field("first_line", &self.first_line)
            .finish()
    }
}

impl ParsedRows {
    /// The next row; `None` after the last one (and from then on the
    /// content hash is known).
    pub(crate) fn next_row<'a>(
        &'a mut self,
        path: &'a Path,
        header: &'a [String],
    ) -> Option<ParsedRow<'a>> {
        while self.chunk < self.chunks.len() && self.row >= self.chunks[self.chunk].lines.len() {
            self.chunk += 1;
            self.row = 0;
        }
        let Some(chunk) = self.chunks.get(self.chunk) else {
            self.finished = true;
            return None;
        };
        let r = self.row;
        self.row += 1;
        Some(ParsedRow {
            values: &chunk.values[r * self.width..(r + 1) * self.width],
            slot_of: &self.slot_of,
            line: chunk.first_line + u64::from(chunk.lines[r]),
            path,
            header,
        })
    }

    /// The file's content hash once every row has been read.
    pub(crate) fn content_hash(&self) -> Option<ContentHash> {
        self.finished.then_some(self.hash)
    }
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
