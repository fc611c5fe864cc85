//! Trial and estimate tables as Arrow IPC files (`.arrow`, `.feather`:
//! the Arrow IPC file format, Feather v2), beside the CSV form (issue 18
//! item 6; docs/ARROW.md). Ours, not SPEC's: SPEC defines the CSV files;
//! an Arrow file holds the same table, column for column.
//!
//! Layout: one column per CSV column, with the CSV header's names and
//! order. Numbers are nullable `Float64` (null = an empty cell); the label
//! columns (`phase`, `phase_ref`) are nullable `Utf8`. The `# key: value`
//! comment lines are the schema's metadata, in order (their keys joined by
//! newlines under [`KEY_ORDER`], since Arrow metadata is a map); entries
//! known only at the end of a run (the trial's content hash) are the file
//! footer's metadata. Rows are written in batches of [`BATCH_ROWS`].
//!
//! Reading accepts what other tools write: `Float64`, `Float32`, integer
//! and boolean columns read as numbers, `Utf8` columns as text (parsed as
//! numbers where a number is needed); LZ4-compressed files (pyarrow's
//! default for Feather) are read, ZSTD ones are refused with a message.
//! In errors, the "line" of an Arrow file is the 1-based row number.

use std::cell::Cell;
use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;
use std::sync::Arc;

use arrow_array::builder::StringBuilder;
use arrow_array::{ArrayRef, Float64Array, RecordBatch};
use arrow_buffer::{Buffer, NullBuffer, ScalarBuffer};
use arrow_ipc::writer::FileWriter;
use arrow_schema::{ArrowError, DataType, Field, Metadata, Schema};

use crate::cell_sink::CellSink;
use crate::error::FileError;
use crate::meta::TrialMeta;

/// Rows per record batch written (82 s at 100 Hz; 3 MB for the 46 columns
/// of an mjls estimate: fewer page faults and cache misses than larger
/// batches, measured in docs/PERFORMANCE.md).
pub const BATCH_ROWS: usize = 1 << 13;

/// Metadata key holding the other metadata keys in their order, one per line.
pub const KEY_ORDER: &str = "limbfuse_key_order";

/// True when `path` names an Arrow IPC file (`.arrow`, `.feather`, `.ipc`,
/// any case): the readers and writers choose the format by this.
pub fn is_arrow_path(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        ["arrow", "feather", "ipc"]
            .iter()
            .any(|x| e.eq_ignore_ascii_case(x))
    })
}

pub(crate) fn arrow_error(path: &Path, e: ArrowError) -> FileError {
    let text = e.to_string();
    let hint = if text.to_ascii_lowercase().contains("zstd") {
        " (ZSTD-compressed Arrow files are not supported: write it uncompressed or with LZ4)"
    } else {
        ""
    };
    FileError::at(path, 0, format!("a readable Arrow IPC file: {text}{hint}"))
}

thread_local! {
    static GUARDED_READ: Cell<bool> = const { Cell::new(false) };
}

/// True while this thread runs an arrow-rs reading step whose panic is
/// caught and reported as a [`FileError`]: a process-wide panic hook (the
/// CLI's) should then return quietly and let the panic unwind to it.
pub fn in_guarded_read() -> bool {
    GUARDED_READ.with(Cell::get)
}

/// Runs an arrow-rs reading step, turning a panic into an error: arrow-rs
/// validates what it reads, but some corrupted files still make it panic
/// (found by `tests/integration/issue_18_arrow_files.rs`, a flipped byte in a batch
/// body: `arrow-buffer` asserts a slice bound), and bad input must be an
/// error naming the file.
pub(crate) fn guarded<T>(
    path: &Path,
    step: impl FnOnce() -> Result<T, ArrowError>,
) -> Result<T, FileError> {
    GUARDED_READ.with(|g| g.set(true));
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(step));
    GUARDED_READ.with(|g| g.set(false));
    match outcome {
        Ok(r) => r.map_err(|e| arrow_error(path, e)),
        Err(_) => Err(FileError::at(
            path,
            0,
            "a readable Arrow IPC file: the Arrow reader failed on its contents (the file is corrupt)",
        )),
    }
}

/// Metadata in order: the schema's (ordered by [`KEY_ORDER`] where given),
/// then the footer's.
pub(crate) fn ordered_meta(schema: &Metadata, footer: &HashMap<String, String>) -> TrialMeta {
    let mut meta = TrialMeta::new();
    let mut rest: Vec<(&String, &String)> = schema
        .iter()
        .chain(footer.iter())
        .filter(|(k, _)| *k != KEY_ORDER)
        .collect();
    if let Some(order) = schema.get(KEY_ORDER) {
        for key in order.lines() {
            if let Some(v) = schema.get(key).or_else(|| footer.get(key)) {
                meta.set(key, v);
            }
        }
    }
    rest.sort();
    for (k, v) in rest {
        if meta.get(k).is_none() {
            meta.set(k.as_str(), v);
        }
    }
    meta
}

/// Writes a table's rows into an Arrow IPC file, batch by batch.
///
/// A row's number cells go straight into their columns (a missing value as
/// NaN: a non-finite value is written missing, as in CSV, so NaN is free
/// to mean missing), and a full batch's columns become its arrays without
/// being copied. Label cells go to a text builder per label column.
pub(crate) struct ArrowSink<W: Write> {
    writer: FileWriter<W>,
    schema: Arc<Schema>,
    /// Per column: its numbers in this batch (empty for a label column).
    numbers: Vec<Vec<f64>>,
    /// Per column: its text builder, for a label column.
    labels: Vec<Option<StringBuilder>>,
    /// The column of the next cell of the row.
    col: usize,
    rows: usize,
}

fn io_error(e: ArrowError) -> io::Error {
    match e {
        ArrowError::IoError(_, e) => e,
        e => io::Error::other(e),
    }
}

impl<W: Write> CellSink for ArrowSink<W> {
    /// The next cell of the row: a number (`None`: null).
    #[inline]
    fn number(&mut self, v: Option<f64>) {
        let v = match v {
            Some(v) if v.is_finite() => v,
            _ => f64::NAN,
        };
        if let Some(column) = self.numbers.get_mut(self.col) {
            column.push(v);
        }
        self.col += 1;
    }

    /// The next cell of the row: a label (`None`: null). In a number
    /// column, the label's number.
    fn label(&mut self, v: Option<&str>) {
        match self.labels.get_mut(self.col) {
            Some(Some(b)) => {
                b.append_option(v);
                self.col += 1;
            }
            _ => self.number(v.and_then(|t| t.trim().parse().ok())),
        }
    }
}

impl<W: Write> ArrowSink<W> {
    /// Writes the schema to `out`: the columns `names`, all numbers but the
    /// one named `label` (text), and the metadata `meta`.
    pub(crate) fn new(
        out: W,
        names: Vec<String>,
        label: &str,
        meta: &TrialMeta,
    ) -> io::Result<Self> {
        let fields: Vec<Field> = names
            .iter()
            .map(|name| {
                let t = if name == label {
                    DataType::Utf8
                } else {
                    DataType::Float64
                };
                Field::new(name, t, true)
            })
            .collect();
        let mut metadata: HashMap<String, String> = meta
            .entries()
            .iter()
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        let order: Vec<&str> = meta.entries().iter().map(|(k, _)| k.as_str()).collect();
        metadata.insert(KEY_ORDER.to_string(), order.join("\n"));
        let schema = Arc::new(Schema::new_with_metadata(fields, metadata));
        let writer = FileWriter::try_new(out, &schema).map_err(io_error)?;
        let is_label = |name: &String| name == label;
        let labels = names
            .iter()
            .map(|n| is_label(n).then(StringBuilder::new))
            .collect();
        let numbers = names
            .iter()
            .map(|n| {
                if is_label(n) {
                    Vec::new()
                } else {
                    Vec::with_capacity(BATCH_ROWS)
                }
            })
            .collect();
        Ok(ArrowSink {
            writer,
            schema,
            numbers,
            labels,
            col: 0,
            rows: 0,
        })
    }

    /// Ends the row (a short row is padded with nulls, a long row's extra
    /// cells were dropped); writes a full batch.
    pub(crate) fn end_row(&mut self) -> io::Result<()> {
        self.rows += 1;
        if self.col < self.numbers.len() {
            for (column, label) in self.numbers[self.col..]
                .iter_mut()
                .zip(&mut self.labels[self.col..])
            {
                match label {
                    Some(b) => b.append_null(),
                    None => column.push(f64::NAN),
                }
            }
        }
        self.col = 0;
        if self.rows == BATCH_ROWS {
            self.write_batch()?;
        }
        Ok(())
    }

    fn write_batch(&mut self) -> io::Result<()> {
        if self.rows == 0 {
            return Ok(());
        }
        // The number columns' memory goes into the batch as it is, and
        // comes back for the next batch once the batch is written (a fresh
        // buffer per batch cost a page fault every 4 KiB: most of an Arrow
        // `estimate`'s page faults).
        let mut lent: Vec<Option<Buffer>> = Vec::with_capacity(self.numbers.len());
        let columns: Vec<ArrayRef> = self
            .numbers
            .iter_mut()
            .zip(self.labels.iter_mut())
            .map(|(values, label)| match label {
                Some(b) => {
                    lent.push(None);
                    Arc::new(b.finish()) as ArrayRef
                }
                None => {
                    let nulls = values
                        .iter()
                        .any(|v| v.is_nan())
                        .then(|| NullBuffer::from_iter(values.iter().map(|v| !v.is_nan())));
                    if nulls.is_some() {
                        for v in values.iter_mut().filter(|v| v.is_nan()) {
                            *v = 0.0;
                        }
                    }
                    let buffer = Buffer::from_vec(std::mem::take(values));
                    let n = buffer.len() / std::mem::size_of::<f64>();
                    lent.push(Some(buffer.clone()));
                    Arc::new(Float64Array::new(ScalarBuffer::new(buffer, 0, n), nulls)) as ArrayRef
                }
            })
            .collect();
        let batch = RecordBatch::try_new(self.schema.clone(), columns).map_err(io_error)?;
        self.writer.write(&batch).map_err(io_error)?;
        drop(batch);
        for (values, buffer) in self.numbers.iter_mut().zip(lent) {
            if let Some(buffer) = buffer {
                *values = buffer.into_vec::<f64>().map_or_else(
                    |_| Vec::with_capacity(BATCH_ROWS),
                    |mut v| {
                        v.clear();
                        v
                    },
                );
            }
        }
        self.rows = 0;
        Ok(())
    }

    /// Adds a metadata entry to the footer (known only at the end of a run).
    pub(crate) fn footer_entry(&mut self, key: &str, value: &str) {
        self.writer.write_metadata(key, value);
    }

    /// Writes the last batch and the footer; returns the output.
    pub(crate) fn finish(mut self) -> io::Result<W> {
        self.write_batch()?;
        self.writer.finish().map_err(io_error)?;
        self.writer.into_inner().map_err(io_error)
    }
}
