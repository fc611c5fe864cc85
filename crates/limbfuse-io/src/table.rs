//! A streaming reader of limbfuse CSV tables: leading `# key: value`
//! comment lines, one header row, then rows of numeric (or label) cells found
//! by column name. Shared by the trial and estimate readers.
//!
//! Memory use is one row, whatever the file length. Every error names the
//! file, the 1-based line and, for cells, the 1-based column and its name.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use crate::content_hash::{ContentHash, HashHandle, HashingReader};
use crate::error::FileError;
use crate::meta::TrialMeta;

/// A CSV table being read row by row.
pub struct TableReader {
    path: PathBuf,
    meta: TrialMeta,
    header: Vec<String>,
    csv: csv::Reader<Box<dyn Read + Send>>,
    /// Number of physical lines before the header (comment lines).
    line_offset: u64,
    record: csv::ByteRecord,
    /// Hash of the bytes read so far.
    hash: HashHandle,
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
#[derive(Debug)]
pub struct Row<'a> {
    path: &'a Path,
    header: &'a [String],
    record: &'a csv::ByteRecord,
    line: u64,
}

impl TableReader {
    /// Opens `path` and reads its comments and header.
    pub fn open(path: &Path) -> Result<Self, FileError> {
        let file = File::open(path).map_err(|e| FileError::io(path, e))?;
        Self::from_reader(path, Box::new(file))
    }

    /// Reads a table from any byte source; `path` is used in error messages.
    pub fn from_reader(path: &Path, source: Box<dyn Read + Send>) -> Result<Self, FileError> {
        let (source, hash) = HashingReader::new(source);
        let mut buf = BufReader::with_capacity(1 << 16, source);
        let mut meta = TrialMeta::new();
        let mut line_offset = 0u64;
        loop {
            let peek = buf.fill_buf().map_err(|e| FileError::io(path, e))?;
            if peek.first() != Some(&b'#') {
                break;
            }
            let mut line = String::new();
            buf.read_line(&mut line).map_err(|e| match e.kind() {
                std::io::ErrorKind::InvalidData => {
                    FileError::at(path, line_offset + 1, "a UTF-8 comment line")
                }
                _ => FileError::io(path, e),
            })?;
            line_offset += 1;
            let body = line.trim_start_matches('#').trim();
            if let Some((k, v)) = body.split_once(':') {
                meta.set(k.trim(), v.trim());
            }
        }
        let mut csv = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(Box::new(buf) as Box<dyn Read + Send>);
        let mut header_rec = csv::StringRecord::new();
        let got = csv
            .read_record(&mut header_rec)
            .map_err(|e| FileError::csv(path, line_offset, e))?;
        let header_line = line_offset + 1;
        if !got || header_rec.iter().all(|c| c.is_empty()) {
            return Err(FileError::Empty {
                path: path.to_path_buf(),
                line: header_line,
            });
        }
        let header: Vec<String> = header_rec.iter().map(str::to_string).collect();
        for (i, name) in header.iter().enumerate() {
            if name.is_empty() {
                return Err(FileError::Header {
                    path: path.to_path_buf(),
                    line: header_line,
                    message: format!("column {} has an empty name", i + 1),
                });
            }
            if let Some(j) = header[..i].iter().position(|n| n == name) {
                return Err(FileError::Header {
                    path: path.to_path_buf(),
                    line: header_line,
                    message: format!(
                        "duplicate column `{name}` (columns {} and {})",
                        j + 1,
                        i + 1
                    ),
                });
            }
        }
        Ok(TableReader {
            path: path.to_path_buf(),
            meta,
            header,
            csv,
            line_offset,
            record: csv::ByteRecord::new(),
            hash,
        })
    }

    /// The file path used in messages.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The hash of the whole source once every row has been read
    /// ([`TableReader::next_row`] returned `Ok(None)`); `None` before.
    pub fn content_hash(&self) -> Option<ContentHash> {
        self.hash.finished()
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
        self.line_offset + 1
    }

    /// 0-based index of the required time column `t`.
    pub fn time_column(&self) -> Result<usize, FileError> {
        self.column("t").ok_or_else(|| FileError::Header {
            path: self.path.clone(),
            line: self.header_line(),
            message: "missing required column `t` (time in seconds)".into(),
        })
    }

    /// 0-based index of the column named `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// Reads the next row; `Ok(None)` at the end. Blank lines are skipped.
    pub fn next_row(&mut self) -> Result<Option<Row<'_>>, FileError> {
        loop {
            let got = self
                .csv
                .read_byte_record(&mut self.record)
                .map_err(|e| FileError::csv(&self.path, self.line_offset, e))?;
            if !got {
                return Ok(None);
            }
            let line = self.line_offset + self.record.position().map_or(0, |p| p.line());
            if self.record.len() == 1 && self.record[0].is_empty() {
                continue;
            }
            if self.record.len() != self.header.len() {
                return Err(FileError::RowLength {
                    path: self.path.clone(),
                    line,
                    expected: self.header.len(),
                    found: self.record.len(),
                });
            }
            return Ok(Some(Row {
                path: &self.path,
                header: &self.header,
                record: &self.record,
                line,
            }));
        }
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
        &self.record[col]
    }

    /// An error about column `col` of this row.
    pub fn cell_error(&self, col: usize, expected: &'static str) -> FileError {
        FileError::Cell {
            path: self.path.to_path_buf(),
            line: self.line,
            column: col + 1,
            name: self.header[col].clone(),
            expected,
            found: String::from_utf8_lossy(&self.record[col]).into_owned(),
        }
    }

    /// The finite number in column `col`, `None` when the cell is empty.
    pub fn number(&self, col: usize) -> Result<Option<f64>, FileError> {
        let raw = &self.record[col];
        if raw.is_empty() {
            return Ok(None);
        }
        let v = std::str::from_utf8(raw)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| self.cell_error(col, "a number or an empty cell"))?;
        if !v.is_finite() {
            return Err(self.cell_error(col, "a finite number (NaN and inf are not allowed; leave the cell empty for a missing value)"));
        }
        Ok(Some(v))
    }

    /// The time in column `col`: present, finite, and after `previous`.
    pub fn time(&self, col: usize, previous: Option<f64>) -> Result<f64, FileError> {
        let t = self
            .number(col)?
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

    /// The number in an optional column.
    pub fn opt_number(&self, col: Option<usize>) -> Result<Option<f64>, FileError> {
        match col {
            Some(c) => self.number(c),
            None => Ok(None),
        }
    }
}
