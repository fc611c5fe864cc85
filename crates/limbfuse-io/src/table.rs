//! A streaming reader of limbfuse CSV tables: leading `# key: value`
//! comment lines, one header row, then rows of numeric (or label) cells found
//! by column name. Shared by the trial and estimate readers.
//!
//! Heap memory is one row, whatever the file length: a regular file is
//! mapped and its lines read in place (`crate::mapped_file`), anything else
//! streamed through one buffer. Every error names the file, the 1-based
//! line and, for cells, the 1-based column and its name.
//!
//! A path ending in `.arrow` or `.feather` is read as an Arrow IPC file
//! holding the same table (`crate::arrow_source`: batches decoded in place
//! from the mapped file; the "line" of its rows is the 1-based row number).

use std::fs::File;
use std::io::Read;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::arrow_file;
use crate::arrow_source::ArrowSource;
use crate::content_hash::{ContentHash, HashHandle, HashingReader};
use crate::csv_lines::{self, LineError, LineSource};
use crate::error::FileError;
use crate::mapped_file::MappedFile;
use crate::meta::TrialMeta;

/// A CSV table being read row by row.
pub struct TableReader {
    path: PathBuf,
    meta: TrialMeta,
    header: Vec<String>,
    lines: LineSource,
    /// 1-based line number of the header row.
    header_line: u64,
    /// Physical lines read so far.
    lines_read: u64,
    /// Cell bounds of the current row (in the line, or in `quoted` text).
    cells: Vec<(u32, u32)>,
    /// A record with quotes: its raw lines, and its cell texts unquoted.
    record: Vec<u8>,
    quoted: Vec<u8>,
    /// Hash of the bytes read so far.
    hash: HashHandle,
    /// The rows of an Arrow IPC file (then `lines` is empty), and the
    /// file's hash once its last row has been read.
    arrow: Option<(ArrowSource, Option<ContentHash>)>,
    /// The last line, left out: fewer cells than the header and no line
    /// break (a recording cut off while it was written).
    cut_last_line: Option<CutLine>,
}

/// A last line left out of a table ([`TableReader::cut_last_line`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CutLine {
    /// Its 1-based line number.
    pub line: u64,
    /// Cells it has.
    pub found: usize,
    /// Cells a row has (the header's).
    pub expected: usize,
}

impl CutLine {
    /// What a reader's user is told.
    pub fn message(&self, path: &Path) -> String {
        format!(
            "{}:{}: the last line has {} of {} cells and no line break: the recording was cut off \
             while it was written, and that line is left out",
            path.display(),
            self.line,
            self.found,
            self.expected
        )
    }
}

impl std::fmt::Debug for TableReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TableReader")
            .field("path", &self.path)
            .field("header", &self.header)
            .finish()
    }
}

/// One data row, borrowed from the reader until the next call.
pub struct Row<'a> {
    path: &'a Path,
    header: &'a [String],
    text: &'a [u8],
    cells: &'a [(u32, u32)],
    line: u64,
    /// The row of an Arrow file (then `text` and `cells` are empty).
    arrow: Option<&'a ArrowSource>,
}

impl std::fmt::Debug for Row<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Row")
            .field("path", &self.path)
            .field("line", &self.line)
            .finish()
    }
}

/// Where the cells of the current record are.
enum Cells {
    /// In the line, in the reader's buffer.
    Line(Range<usize>),
    /// In the unquoted text of a quoted record.
    Quoted,
}

impl TableReader {
    /// Opens `path` and reads its comments and header (its schema, for an
    /// Arrow file: [`arrow_file::is_arrow_path`]).
    pub fn open(path: &Path) -> Result<Self, FileError> {
        if arrow_file::is_arrow_path(path) {
            return Self::open_arrow(path);
        }
        let file = File::open(path).map_err(|e| FileError::io(path, e))?;
        match MappedFile::map(&file) {
            // A regular file: its lines are read in place.
            Some(map) => {
                let hash = HashHandle::default();
                Self::from_lines(path, LineSource::mapped(map, hash.clone()), hash)
            }
            None => Self::from_reader(path, Box::new(file)),
        }
    }

    fn open_arrow(path: &Path) -> Result<Self, FileError> {
        let (source, head) = ArrowSource::open(path)?;
        let table = TableReader {
            path: path.to_path_buf(),
            meta: head.meta,
            header: head.header,
            lines: LineSource::none(),
            header_line: 0,
            lines_read: 0,
            cells: Vec::new(),
            record: Vec::new(),
            quoted: Vec::new(),
            hash: HashHandle::default(),
            arrow: Some((source, None)),
            cut_last_line: None,
        };
        table.check_header(0)?;
        Ok(table)
    }

    /// Reads a table from any byte source; `path` is used in error messages.
    pub fn from_reader(path: &Path, source: Box<dyn Read + Send>) -> Result<Self, FileError> {
        let (source, hash) = HashingReader::new(source);
        Self::from_lines(path, LineSource::new(Box::new(source)), hash)
    }

    /// Reads the comments and header from `lines`, whose bytes `hash` hashes.
    fn from_lines(path: &Path, lines: LineSource, hash: HashHandle) -> Result<Self, FileError> {
        let mut table = TableReader {
            path: path.to_path_buf(),
            meta: TrialMeta::new(),
            header: Vec::new(),
            lines,
            header_line: 0,
            lines_read: 0,
            cells: Vec::new(),
            record: Vec::new(),
            quoted: Vec::new(),
            hash,
            arrow: None,
            cut_last_line: None,
        };
        table
            .lines
            .skip_byte_order_mark()
            .map_err(|e| table.line_error(e))?;
        table.read_comments()?;
        table.read_header()?;
        Ok(table)
    }

    fn line_error(&self, e: LineError) -> FileError {
        match e {
            LineError::Io(e) => FileError::io(&self.path, e),
            LineError::TooLong => FileError::at(
                &self.path,
                self.lines_read + 1,
                format!(
                    "a line of at most {} MiB (no line break found)",
                    csv_lines::MAX_LINE_BYTES >> 20
                ),
            ),
        }
    }

    /// The leading `# key: value` lines.
    fn read_comments(&mut self) -> Result<(), FileError> {
        while self.lines.peek().map_err(|e| self.line_error(e))? == Some(b'#') {
            let Some(line) = self.lines.next_line().map_err(|e| self.line_error(e))? else {
                break;
            };
            self.lines_read += 1;
            let text = std::str::from_utf8(self.lines.bytes(line))
                .map_err(|_| FileError::at(&self.path, self.lines_read, "a UTF-8 comment line"))?;
            let body = text.trim_start_matches('#').trim();
            if let Some((k, v)) = body.split_once(':') {
                self.meta.set(k.trim(), v.trim());
            }
        }
        Ok(())
    }

    /// The header row: the first non-blank line after the comments.
    fn read_header(&mut self) -> Result<(), FileError> {
        let expected_at = self.lines_read + 1;
        let Some((line, cells)) = self.next_record()? else {
            return Err(FileError::Empty {
                path: self.path.clone(),
                line: expected_at,
            });
        };
        self.header_line = line;
        let text = match cells {
            Cells::Line(r) => self.lines.bytes(r),
            Cells::Quoted => &self.quoted,
        };
        let mut header = Vec::with_capacity(self.cells.len());
        for &(a, b) in &self.cells {
            let name = std::str::from_utf8(&text[a as usize..b as usize])
                .map_err(|_| FileError::at(&self.path, line, "UTF-8 text"))?;
            header.push(name.trim().to_string());
        }
        self.header = header;
        self.check_header(line)
    }

    /// Names present, none empty (but the last), none twice.
    fn check_header(&self, line: u64) -> Result<(), FileError> {
        let header = &self.header;
        if let Some(kind) = crate::trial_hints::other_format(&self.path, header) {
            return Err(FileError::Header {
                path: self.path.clone(),
                line,
                message: format!(
                    "{kind}, not a CSV table: expected a header row of column names (`t,...`)"
                ),
            });
        }
        if header.iter().all(String::is_empty) {
            return Err(FileError::Empty {
                path: self.path.clone(),
                line,
            });
        }
        for (i, name) in header.iter().enumerate() {
            // A header line ending in `,` (loggers that end every line with
            // the separator): the unnamed last column is ignored, like any
            // column no channel is named after.
            if name.is_empty() && i + 1 == header.len() {
                continue;
            }
            if name.is_empty() {
                return Err(FileError::Header {
                    path: self.path.clone(),
                    line,
                    message: format!("column {} has an empty name", i + 1),
                });
            }
            if let Some(j) = header[..i].iter().position(|n| n == name) {
                return Err(FileError::Header {
                    path: self.path.clone(),
                    line,
                    message: format!(
                        "duplicate column `{name}` (columns {} and {})",
                        j + 1,
                        i + 1
                    ),
                });
            }
        }
        Ok(())
    }

    /// The next non-blank record split into `self.cells`, with the line it
    /// starts on; `None` at the end.
    fn next_record(&mut self) -> Result<Option<(u64, Cells)>, FileError> {
        loop {
            let Some(range) = self.lines.next_line().map_err(|e| self.line_error(e))? else {
                return Ok(None);
            };
            self.lines_read += 1;
            let first_line = self.lines_read;
            let line = self.lines.bytes(range.clone());
            if csv_lines::split_plain(line, &mut self.cells) {
                if csv_lines::is_blank(&self.cells) {
                    continue;
                }
                return Ok(Some((first_line, Cells::Line(range))));
            }
            self.record.clear();
            self.record.extend_from_slice(line);
            while !csv_lines::split_quoted(&self.record, &mut self.quoted, &mut self.cells) {
                let Some(next) = self.lines.next_line().map_err(|e| self.line_error(e))? else {
                    return Err(FileError::at(
                        &self.path,
                        first_line,
                        "a closing `\"` for the quoted cell opened on this line",
                    ));
                };
                self.lines_read += 1;
                if self.record.len() > csv_lines::MAX_LINE_BYTES {
                    return Err(self.line_error(LineError::TooLong));
                }
                self.record.push(b'\n');
                self.record.extend_from_slice(self.lines.bytes(next));
            }
            if csv_lines::is_blank(&self.cells) {
                continue;
            }
            return Ok(Some((first_line, Cells::Quoted)));
        }
    }

    /// The last line, left out because it was cut off (fewer cells than
    /// the header, no line break); known once the rows have been read.
    pub fn cut_last_line(&self) -> Option<CutLine> {
        self.cut_last_line
    }

    /// The file path used in messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The hash of the whole source once every row has been read
    /// ([`TableReader::next_row`] returned `Ok(None)`); `None` before.
    pub fn content_hash(&self) -> Option<ContentHash> {
        match &self.arrow {
            Some((_, hash)) => *hash,
            None => self.hash.finished(),
        }
    }

    /// Metadata from the leading comment lines.
    pub fn meta(&self) -> &TrialMeta {
        &self.meta
    }

    /// Column names in file order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// 1-based line number of the header row.
    pub fn header_line(&self) -> u64 {
        self.header_line
    }

    /// 0-based index of the required time column `t`.
    pub fn time_column(&self) -> Result<usize, FileError> {
        self.column("t").ok_or_else(|| FileError::Header {
            path: self.path.clone(),
            line: self.header_line(),
            message: format!(
                "missing required column `t` (time in seconds){}{}{}",
                self.separator_hint(),
                crate::trial_hints::importer_hint(&self.path, &self.header),
                crate::column_spelling::time_column_hint(&self.header)
            ),
        })
    }

    /// A hint when the header is one cell holding another separator (a
    /// spreadsheet's `;` export with decimal commas, a tab-separated file):
    /// the whole line became one column name.
    fn separator_hint(&self) -> String {
        let [only] = self.header.as_slice() else {
            return String::new();
        };
        match [';', '\t'].into_iter().find(|c| only.contains(*c)) {
            Some(c) => format!(
                "; the header is one column `{}`: its cells are separated by {}, and trial files are comma-separated with `.` as the decimal point (SPEC section 2)",
                {
                    let head: String = only.chars().take(40).collect();
                    let more = if head.len() < only.len() { "..." } else { "" };
                    format!("{}{more}", head.replace('\t', "\\t"))
                },
                if c == ';' { "`;`" } else { "tabs" }
            ),
            None => String::new(),
        }
    }

    /// 0-based index of the column named `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// Reads the next row; `Ok(None)` at the end. Blank lines are skipped.
    pub fn next_row(&mut self) -> Result<Option<Row<'_>>, FileError> {
        if let Some((source, hash)) = &mut self.arrow {
            let Some(line) = source.advance(&self.path)? else {
                if hash.is_none() {
                    *hash = Some(source.content_hash());
                }
                return Ok(None);
            };
            return Ok(Some(Row {
                path: &self.path,
                header: &self.header,
                text: &[],
                cells: &[],
                line,
                arrow: self.arrow.as_ref().map(|(s, _)| s),
            }));
        }
        let Some((line, cells)) = self.next_record()? else {
            return Ok(None);
        };
        if self.cells.len() < self.header.len()
            && matches!(cells, Cells::Line(_))
            && self.lines.last_line_unterminated()
        {
            // A writer stopped mid-line (a logger switched off, a copy of a
            // file still being written): the row is incomplete, and the
            // last. Read on to the end so that the hash is finished.
            self.cut_last_line = Some(CutLine {
                line,
                found: self.cells.len(),
                expected: self.header.len(),
            });
            let _ = self.lines.next_line().map_err(|e| self.line_error(e))?;
            return Ok(None);
        }
        if self.cells.len() != self.header.len() {
            return Err(FileError::RowLength {
                path: self.path.clone(),
                line,
                expected: self.header.len(),
                found: self.cells.len(),
            });
        }
        let text = match cells {
            Cells::Line(r) => self.lines.bytes(r),
            Cells::Quoted => &self.quoted,
        };
        Ok(Some(Row {
            path: &self.path,
            header: &self.header,
            text,
            cells: &self.cells,
            line,
            arrow: None,
        }))
    }
}

impl Row<'_> {
    /// 1-based line number of this row.
    pub fn line(&self) -> u64 {
        self.line
    }

    /// The file path.
    pub fn path(&self) -> &Path {
        self.path
    }

    /// Raw text of column `col` (0-based).
    pub fn text(&self, col: usize) -> &[u8] {
        if let Some(source) = self.arrow {
            return source.text(col);
        }
        let (a, b) = self.cells[col];
        &self.text[a as usize..b as usize]
    }

    /// An error about column `col` of this row.
    pub fn cell_error(&self, col: usize, expected: &'static str) -> FileError {
        FileError::Cell {
            path: self.path.to_path_buf(),
            line: self.line,
            column: col + 1,
            name: self.header[col].clone(),
            expected,
            found: match self.arrow {
                Some(source) => source.found(col),
                None => String::from_utf8_lossy(self.text(col)).into_owned(),
            },
        }
    }

    /// The finite number in column `col`, `None` when the cell is empty.
    pub fn number(&self, col: usize) -> Result<Option<f64>, FileError> {
        if let Some(source) = self.arrow {
            let v = source
                .number(col)
                .map_err(|()| self.cell_error(col, "a number or an empty cell"))?;
            return match v {
                Some(v) if !v.is_finite() => Err(self.cell_error(col, "a finite number (NaN and inf are not allowed; leave the cell empty (null) for a missing value)")),
                v => Ok(v),
            };
        }
        let raw = self.text(col);
        if raw.is_empty() {
            return Ok(None);
        }
        let v = crate::cell_format::parse_number(raw)
            .ok_or_else(|| self.cell_error(col, "a number or an empty cell"))?;
        if !v.is_finite() {
            return Err(self.cell_error(col, "a finite number (NaN and inf are not allowed; leave the cell empty for a missing value)"));
        }
        Ok(Some(v))
    }

    /// The numbers of the columns `cols` into `out[col]`, each as
    /// [`Row::number`] reads it, in the order of `cols`: the first cell that
    /// is neither a finite number nor empty is the error, the same one
    /// [`Row::number`] gives. One loop for a whole row: the record reader's
    /// path (one call and one `Result` per cell before: ~5 % of reading).
    pub fn numbers_into(&self, cols: &[usize], out: &mut [Option<f64>]) -> Result<(), FileError> {
        if let Some(source) = self.arrow {
            // At a bad cell: the error of `number`.
            return source
                .numbers_into(cols, out)
                .or_else(|c| self.number(c).map(|_| ()));
        }
        for &c in cols {
            let (a, b) = self.cells[c];
            let raw = &self.text[a as usize..b as usize];
            out[c] = if raw.is_empty() {
                None
            } else {
                match crate::cell_format::parse_number(raw) {
                    Some(v) if v.is_finite() => Some(v),
                    // Not a finite number: the error of `number`.
                    _ => self.number(c)?,
                }
            };
        }
        Ok(())
    }

    /// The time in column `col`: present, finite, and after `previous`.
    pub fn time(&self, col: usize, previous: Option<f64>) -> Result<f64, FileError> {
        // Not `number`'s advice to leave a cell empty: `t` must be there.
        let t = self.number(col).ok().flatten().ok_or_else(|| {
            self.cell_error(
                col,
                "a finite time in seconds (t cannot be empty, NaN or inf)",
            )
        })?;
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

    /// The number in an optional column.
    pub fn opt_number(&self, col: Option<usize>) -> Result<Option<f64>, FileError> {
        match col {
            Some(c) => self.number(c),
            None => Ok(None),
        }
    }
}
