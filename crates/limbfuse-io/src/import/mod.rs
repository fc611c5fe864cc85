//! Importers that turn real recordings into trials (SPEC section 2), see
//! `docs/IMPORTERS.md` for the datasets, mappings and measured figures.
//!
//! - [`import_gaittoolbox`]: the gaittoolbox walking trial (Xsens IMUs + Vicon
//!   joint centres), with reference sagittal angles derived by
//!   [`sagittal_reference`].
//! - [`import_knee_rig`]: the robotic knee rig (two MPU6050 + stepper knee angle).
//!
//! Importers keep the raw (unaligned) 3-axis sensor channels in SI units, turn
//! dropouts into rows whose channels are `None`, and never panic on bad input:
//! every [`ImportError`] names the file, the 1-based line and (for a cell) the
//! column, and what was expected.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use limbfuse_core::Record;

use crate::layout::TrialLayout;
use crate::meta::TrialMeta;

mod gaittoolbox;
mod gaittoolbox_leg;
mod knee_rig;
pub mod sagittal_reference;

pub use gaittoolbox::{import_gaittoolbox, import_gaittoolbox_with, GaittoolboxOptions};
pub use knee_rig::{import_knee_rig, import_knee_rig_with, KneeRigOptions};

/// A recording converted to limbfuse conventions, ready for a trial writer.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedTrial {
    /// Metadata (`format`, `source`, `sample_rate_hz`, `leg`, `g`, and notes).
    pub meta: TrialMeta,
    /// Channels present.
    pub layout: TrialLayout,
    /// One record per sample time (`t` from 0 s, strictly increasing).
    pub records: Vec<Record>,
}

/// Why an import failed. Every variant names the file and, where there is
/// one, the 1-based line (and column), and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// A file or folder could not be opened or read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// A header row lacks a required column.
    #[error("{}:{line}: header: missing column `{name}`; expected {expected}", path.display())]
    MissingColumn {
        /// File path.
        path: PathBuf,
        /// Line of the header row (or where it was expected).
        line: u64,
        /// Name of the missing column.
        name: String,
        /// What was expected.
        expected: String,
    },
    /// A cell does not hold what its column needs (also a row that ends
    /// before this column: `found` then says so).
    #[error("{}:{line}: column {column} (`{name}`): expected {expected}, found {found}", path.display())]
    Cell {
        /// File path.
        path: PathBuf,
        /// Line of the row.
        line: u64,
        /// 1-based column number.
        column: usize,
        /// Column name.
        name: String,
        /// What was expected.
        expected: String,
        /// What was found (quoted cell text, or a description).
        found: String,
    },
    /// A problem with a whole line or with the file as a whole (empty file,
    /// missing metadata line, sample counts that disagree between files).
    #[error("{}:{line}: {problem}; expected {expected}", path.display())]
    Line {
        /// File path.
        path: PathBuf,
        /// Line (the last line read when the problem is about the whole file).
        line: u64,
        /// What is wrong.
        problem: String,
        /// What was expected.
        expected: String,
    },
}

impl ImportError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        ImportError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn line(
        path: &Path,
        line: u64,
        problem: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        ImportError::Line {
            path: path.to_path_buf(),
            line,
            problem: problem.into(),
            expected: expected.into(),
        }
    }
}

/// Reads a text file as numbered lines (1-based), `\r` and a leading
/// byte-order mark stripped. A line longer than the trial reader's bound
/// ([`crate::csv_lines::MAX_LINE_BYTES`], 64 MiB) is an error naming its
/// line: a file without line breaks (`/dev/zero`) is not read whole into
/// one string (an audit: `import --format knee-rig /dev/zero` grew memory
/// without bound).
pub(crate) fn read_lines(path: &Path) -> Result<Vec<(u64, String)>, ImportError> {
    let file = File::open(path).map_err(|e| ImportError::io(path, e))?;
    let mut reader = BufReader::new(file);
    let mut out = Vec::new();
    let mut buf = Vec::new();
    for n in 1u64.. {
        buf.clear();
        let read = (&mut reader)
            .take(crate::csv_lines::MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut buf)
            .map_err(|e| ImportError::io(path, e))?;
        if read == 0 {
            break;
        }
        if buf.last() == Some(&b'\n') {
            buf.pop();
        } else if buf.len() > crate::csv_lines::MAX_LINE_BYTES {
            return Err(ImportError::line(
                path,
                n,
                "no line break found",
                format!(
                    "a line of at most {} MiB",
                    crate::csv_lines::MAX_LINE_BYTES >> 20
                ),
            ));
        }
        let line = std::str::from_utf8(&buf)
            .map_err(|_| ImportError::line(path, n, "not UTF-8 text", "UTF-8 text"))?;
        // (a UTF-8 byte-order mark before the first line, as spreadsheet
        // programs write it, is not part of the text)
        let line = if n == 1 {
            line.strip_prefix('\u{feff}').unwrap_or(line)
        } else {
            line
        };
        out.push((n, line.trim_end_matches('\r').to_string()));
    }
    Ok(out)
}

/// Splits a comma-separated line into trimmed cells.
pub(crate) fn split_cells(line: &str) -> Vec<&str> {
    line.split(',').map(str::trim).collect()
}

/// A header row: column names and where to find them.
#[derive(Debug)]
pub(crate) struct Header<'a> {
    pub path: &'a Path,
    pub line: u64,
    pub names: Vec<String>,
}

impl<'a> Header<'a> {
    pub fn new(path: &'a Path, line: u64, text: &str) -> Self {
        Header {
            path,
            line,
            names: split_cells(text).into_iter().map(String::from).collect(),
        }
    }

    /// 0-based index of a required column (its first occurrence). A
    /// missing column is an error; when another column is named twice, the
    /// error says so (an audit: a `G1Y` renamed `G1X` was reported only as
    /// `G1Y` missing).
    pub fn require(&self, name: &str, expected: &str) -> Result<usize, ImportError> {
        if let Some(i) = self.names.iter().position(|n| n == name) {
            return Ok(i);
        }
        let twice = self.names.iter().enumerate().find_map(|(i, n)| {
            let j = self.names[i + 1..].iter().position(|m| m == n)?;
            Some((n, i + 1, i + j + 2))
        });
        if let Some((dup, i, j)) = twice {
            return Err(ImportError::line(
                self.path,
                self.line,
                format!(
                    "header: missing column `{name}`, and column `{dup}` is there twice \
                     (columns {i} and {j}: one renamed?)"
                ),
                format!("each column once; {expected}"),
            ));
        }
        Err(ImportError::MissingColumn {
            path: self.path.to_path_buf(),
            line: self.line,
            name: name.to_string(),
            expected: expected.to_string(),
        })
    }

    /// The cells of a data row, checked to be as many as the header's
    /// names (one more, empty, is a separator ending the row): a row with a
    /// cell too few or too many would put every later value under the
    /// wrong name. `needed` (0-based index of the last column this
    /// importer reads) is within the header's names.
    pub fn cells<'l>(
        &self,
        line: u64,
        text: &'l str,
        needed: usize,
    ) -> Result<Vec<&'l str>, ImportError> {
        debug_assert!(needed < self.names.len().max(1));
        let mut cells = split_cells(text);
        let want = self.names.len();
        if cells.len() == want + 1 && cells.last().is_some_and(|c| c.trim().is_empty()) {
            cells.pop();
        }
        if cells.len() == want {
            return Ok(cells);
        }
        let k = cells.len();
        let expected = format!(
            "{want} comma-separated cells as in the header (line {})",
            self.line
        );
        Err(if k < want {
            ImportError::Cell {
                path: self.path.to_path_buf(),
                line,
                column: k + 1,
                name: self.names.get(k).cloned().unwrap_or_default(),
                expected,
                found: format!("end of row after {k} cell(s) (a cell missing or a truncated row)"),
            }
        } else {
            ImportError::Cell {
                path: self.path.to_path_buf(),
                line,
                column: want + 1,
                name: "beyond the header".into(),
                expected,
                found: format!("{k} cells (a cell too many)"),
            }
        })
    }

    /// Parses cell `col` of a row as a finite number; `Ok(None)` for an empty
    /// cell (or `NaN` when `nan_is_missing`), an error for anything else.
    pub fn number(
        &self,
        line: u64,
        cells: &[&str],
        col: usize,
        nan_is_missing: bool,
    ) -> Result<Option<f64>, ImportError> {
        let text = cells.get(col).copied().unwrap_or("");
        if text.is_empty() || (nan_is_missing && text.eq_ignore_ascii_case("nan")) {
            return Ok(None);
        }
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => Err(self.bad_cell(line, col, text, "a finite number")),
        }
    }

    /// An error about cell `col` of a row.
    pub fn bad_cell(
        &self,
        line: u64,
        col: usize,
        found: &str,
        expected: impl Into<String>,
    ) -> ImportError {
        ImportError::Cell {
            path: self.path.to_path_buf(),
            line,
            column: col + 1,
            name: self.names.get(col).cloned().unwrap_or_default(),
            expected: expected.into(),
            found: format!("`{found}`"),
        }
    }
}

/// Median of a slice (NaN-free); `None` when empty.
pub(crate) fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// Formats a number for metadata with `digits` decimals.
pub(crate) fn fmt(value: f64, digits: usize) -> String {
    format!("{value:.digits$}")
}
