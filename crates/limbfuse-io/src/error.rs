//! Errors of reading and writing limbfuse files. Every variant names the file
//! and, where there is one, the 1-based line and column.

use std::path::{Path, PathBuf};

/// A problem with a trial or estimate file.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file could not be opened, read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// A directory where a trial file is expected (`hint`: what it holds,
    /// or the importer that reads it; may be empty).
    #[error("{}: is a directory; a trial file is expected{hint}", path.display())]
    Directory {
        /// The directory.
        path: PathBuf,
        /// `; it holds trial.csv`, `; ... limbfuse import --format gaittoolbox ...`.
        hint: String,
    },
    /// The file has no header row.
    #[error("{}:{line}: the file is empty: expected a header row (e.g. `t,thigh_gyr_x,...`)", path.display())]
    Empty {
        /// File path.
        path: PathBuf,
        /// Line where the header was expected.
        line: u64,
    },
    /// The file has a header but no data row.
    #[error("{}:{line}: no samples: expected at least one data row after the header", path.display())]
    NoRows {
        /// File path.
        path: PathBuf,
        /// Line after the header.
        line: u64,
    },
    /// The header row is malformed (duplicate, missing or incomplete columns).
    #[error("{}:{line}: header: {message}", path.display())]
    Header {
        /// File path.
        path: PathBuf,
        /// Header line.
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// A row has a different number of cells than the header.
    #[error("{}:{line}: expected {expected} cells (as many as header columns), found {found}", path.display())]
    RowLength {
        /// File path.
        path: PathBuf,
        /// Row line.
        line: u64,
        /// Number of header columns.
        expected: usize,
        /// Number of cells found.
        found: usize,
    },
    /// A cell does not hold what its column needs.
    #[error("{}:{line}: column {column} (`{name}`): expected {expected}, found `{found}`", path.display())]
    Cell {
        /// File path.
        path: PathBuf,
        /// Row line.
        line: u64,
        /// 1-based column number.
        column: usize,
        /// Column name.
        name: String,
        /// What was expected.
        expected: &'static str,
        /// The cell text.
        found: String,
    },
    /// Time is not strictly increasing.
    #[error("{}:{line}: column {column} (`t`): time must increase strictly, but {t} follows {previous} (`limbfuse repair-time`, Python `limbfuse.repair_time`, writes a copy without the rows that break the order; for a live stream, `limbfuse estimate --late-rows drop` drops them as it reads: docs/ROBUST_INPUT.md)", path.display())]
    TimeNotIncreasing {
        /// File path.
        path: PathBuf,
        /// Row line.
        line: u64,
        /// 1-based column of `t`.
        column: usize,
        /// Offending time.
        t: f64,
        /// Previous row's time.
        previous: f64,
    },
    /// Any other problem at a line.
    #[error("{}:{line}: expected {expected}", path.display())]
    At {
        /// File path.
        path: PathBuf,
        /// Line.
        line: u64,
        /// What was expected.
        expected: String,
    },
}

impl FileError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        FileError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn at(path: &Path, line: u64, expected: impl Into<String>) -> Self {
        FileError::At {
            path: path.to_path_buf(),
            line,
            expected: expected.into(),
        }
    }
}
