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
use std::fs::File;
use std::io::{self, BufReader, Write};
use std::path::Path;
use std::sync::Arc;

use arrow_array::builder::{ArrayBuilder, StringBuilder};
use arrow_array::cast::AsArray;
use arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch};
use arrow_buffer::{NullBuffer, ScalarBuffer};
use arrow_ipc::reader::FileReader;
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

fn arrow_error(path: &Path, e: ArrowError) -> FileError {
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
/// (found by `tests/issue_18_arrow_files.rs`, a flipped byte in a batch
/// body: `arrow-buffer` asserts a slice bound), and bad input must be an
/// error naming the file.
fn guarded<T>(path: &Path, step: impl FnOnce() -> Result<T, ArrowError>) -> Result<T, FileError> {
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
fn ordered_meta(schema: &Metadata, footer: &HashMap<String, String>) -> TrialMeta {
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

/// One column of the current batch, as read.
enum ColumnView {
    /// `Float64` numbers, as stored.
    Float(arrow_array::Float64Array),
    /// Numbers (any numeric or boolean Arrow type, converted once per batch).
    Number { values: Vec<f64>, valid: Vec<bool> },
    /// Text.
    Text(arrow_array::StringArray),
    /// Text with 64-bit offsets.
    LargeText(arrow_array::LargeStringArray),
}

/// The rows of an Arrow IPC file, batch by batch.
pub(crate) struct ArrowSource {
    reader: FileReader<BufReader<File>>,
    columns: Vec<ColumnView>,
    batch_rows: usize,
    /// Next row in the current batch.
    row: usize,
    /// Rows of the batches before the current one.
    rows_before: u64,
}

/// What [`ArrowSource::open`] finds before the first row.
pub(crate) struct ArrowHead {
    pub meta: TrialMeta,
    pub header: Vec<String>,
}

impl ArrowSource {
    /// Opens `path` and reads its schema and footer.
    pub(crate) fn open(path: &Path) -> Result<(Self, ArrowHead), FileError> {
        let file = File::open(path).map_err(|e| FileError::io(path, e))?;
        let reader = guarded(path, || FileReader::try_new_buffered(file, None))?;
        let schema = reader.schema();
        let mut header = Vec::with_capacity(schema.fields().len());
        for f in schema.fields() {
            let supported = matches!(
                f.data_type(),
                DataType::Float64
                    | DataType::Float32
                    | DataType::Int8
                    | DataType::Int16
                    | DataType::Int32
                    | DataType::Int64
                    | DataType::UInt8
                    | DataType::UInt16
                    | DataType::UInt32
                    | DataType::UInt64
                    | DataType::Boolean
                    | DataType::Utf8
                    | DataType::LargeUtf8
            );
            if !supported {
                return Err(FileError::Header {
                    path: path.to_path_buf(),
                    line: 0,
                    message: format!(
                        "column `{}` has the Arrow type {}: expected numbers (float, integer, boolean) or text",
                        f.name(),
                        f.data_type()
                    ),
                });
            }
            header.push(f.name().clone());
        }
        let meta = ordered_meta(schema.metadata(), reader.custom_metadata());
        let source = ArrowSource {
            reader,
            columns: Vec::new(),
            batch_rows: 0,
            row: 0,
            rows_before: 0,
        };
        Ok((source, ArrowHead { meta, header }))
    }

    /// Moves to the next row; its 1-based row number, `None` at the end.
    pub(crate) fn advance(&mut self, path: &Path) -> Result<Option<u64>, FileError> {
        while self.row >= self.batch_rows {
            let reader = &mut self.reader;
            let Some(batch) = guarded(path, || reader.next().transpose())? else {
                return Ok(None);
            };
            self.rows_before += self.batch_rows as u64;
            self.batch_rows = batch.num_rows();
            self.row = 0;
            self.load(&batch);
        }
        self.row += 1;
        Ok(Some(self.rows_before + self.row as u64))
    }

    fn load(&mut self, batch: &RecordBatch) {
        self.columns.clear();
        for c in batch.columns() {
            self.columns.push(view(c));
        }
    }

    /// The number in column `col` of the current row: `Ok(None)` when null,
    /// `Err(())` when a text cell is not a number.
    #[inline]
    pub(crate) fn number(&self, col: usize) -> Result<Option<f64>, ()> {
        let r = self.row - 1;
        match &self.columns[col] {
            ColumnView::Float(a) => Ok(a.is_valid(r).then(|| a.value(r))),
            ColumnView::Number { values, valid } => Ok(valid[r].then_some(values[r])),
            ColumnView::Text(a) => text_number(a.is_valid(r).then(|| a.value(r))),
            ColumnView::LargeText(a) => text_number(a.is_valid(r).then(|| a.value(r))),
        }
    }

    /// The text of column `col` of the current row (empty when null or a number).
    pub(crate) fn text(&self, col: usize) -> &[u8] {
        let r = self.row - 1;
        match &self.columns[col] {
            ColumnView::Float(_) | ColumnView::Number { .. } => b"",
            ColumnView::Text(a) if a.is_valid(r) => a.value(r).as_bytes(),
            ColumnView::LargeText(a) if a.is_valid(r) => a.value(r).as_bytes(),
            _ => b"",
        }
    }

    /// The cell as text, for an error message.
    pub(crate) fn found(&self, col: usize) -> String {
        match self.number(col) {
            Ok(Some(v)) => v.to_string(),
            _ => String::from_utf8_lossy(self.text(col)).into_owned(),
        }
    }
}

fn text_number(text: Option<&str>) -> Result<Option<f64>, ()> {
    match text.map(str::trim) {
        None | Some("") => Ok(None),
        Some(t) => crate::cell_format::parse_number(t.as_bytes())
            .map(Some)
            .ok_or(()),
    }
}

/// The column as numbers (converted once) or text.
fn view(c: &ArrayRef) -> ColumnView {
    fn numbers<T: arrow_array::ArrowPrimitiveType>(
        c: &ArrayRef,
        to_f64: impl Fn(T::Native) -> f64,
    ) -> ColumnView {
        let a = c.as_primitive::<T>();
        ColumnView::Number {
            values: a.values().iter().map(|&v| to_f64(v)).collect(),
            valid: (0..a.len()).map(|i| a.is_valid(i)).collect(),
        }
    }
    match c.data_type() {
        DataType::Float64 => ColumnView::Float(c.as_primitive::<Float64Type>().clone()),
        DataType::Float32 => numbers::<Float32Type>(c, f64::from),
        DataType::Int8 => numbers::<Int8Type>(c, f64::from),
        DataType::Int16 => numbers::<Int16Type>(c, f64::from),
        DataType::Int32 => numbers::<Int32Type>(c, f64::from),
        DataType::Int64 => numbers::<Int64Type>(c, |v| v as f64),
        DataType::UInt8 => numbers::<UInt8Type>(c, f64::from),
        DataType::UInt16 => numbers::<UInt16Type>(c, f64::from),
        DataType::UInt32 => numbers::<UInt32Type>(c, f64::from),
        DataType::UInt64 => numbers::<UInt64Type>(c, |v| v as f64),
        DataType::Boolean => {
            let a = c.as_boolean();
            ColumnView::Number {
                values: (0..a.len())
                    .map(|i| if a.value(i) { 1.0 } else { 0.0 })
                    .collect(),
                valid: (0..a.len()).map(|i| a.is_valid(i)).collect(),
            }
        }
        DataType::LargeUtf8 => ColumnView::LargeText(c.as_string::<i64>().clone()),
        // Checked at open: the remaining type is Utf8.
        _ => ColumnView::Text(c.as_string::<i32>().clone()),
    }
}

/// The number of rows of an Arrow IPC file (reads every batch).
pub(crate) fn row_count(path: &Path) -> Result<u64, FileError> {
    let file = File::open(path).map_err(|e| FileError::io(path, e))?;
    let mut reader = guarded(path, || FileReader::try_new_buffered(file, None))?;
    let mut rows = 0u64;
    while let Some(batch) = guarded(path, || reader.next().transpose())? {
        rows += batch.num_rows() as u64;
    }
    Ok(rows)
}

/// What a column of a table being written holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ColumnKind {
    /// Numbers (`Float64`).
    Number,
    /// Labels (`Utf8`).
    Label,
}

/// Writes a table's rows into an Arrow IPC file, batch by batch.
///
/// A row's number cells are staged row-major, one store each, a missing
/// value as NaN (a non-finite value is written missing, as in CSV, so NaN
/// is free to mean missing); [`ArrowSink::end_row`] of the batch's last row
/// transposes them into the columns. Label cells go to a text builder per
/// label column.
pub(crate) struct ArrowSink<W: Write> {
    writer: FileWriter<W>,
    schema: Arc<Schema>,
    kinds: Vec<ColumnKind>,
    /// Number cells of the batch, row-major (label columns hold NaN).
    cells: Vec<f64>,
    /// Per column: its text builder, for a label column.
    labels: Vec<Option<StringBuilder>>,
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
        self.cells.push(match v {
            Some(v) if v.is_finite() => v,
            _ => f64::NAN,
        });
    }

    /// The next cell of the row: a label (`None`: null). In a number
    /// column, the label's number.
    fn label(&mut self, v: Option<&str>) {
        let col = self.cells.len() - self.rows * self.kinds.len();
        match self.labels.get_mut(col) {
            Some(Some(b)) => {
                b.append_option(v);
                self.cells.push(f64::NAN);
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
        let columns: Vec<(String, ColumnKind)> = names
            .into_iter()
            .map(|name| {
                let kind = if name == label {
                    ColumnKind::Label
                } else {
                    ColumnKind::Number
                };
                (name, kind)
            })
            .collect();
        let fields: Vec<Field> = columns
            .iter()
            .map(|(name, kind)| {
                let t = match kind {
                    ColumnKind::Number => DataType::Float64,
                    ColumnKind::Label => DataType::Utf8,
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
        let kinds: Vec<ColumnKind> = columns.iter().map(|(_, k)| *k).collect();
        let labels = kinds
            .iter()
            .map(|k| (*k == ColumnKind::Label).then(StringBuilder::new))
            .collect();
        Ok(ArrowSink {
            writer,
            schema,
            cells: Vec::with_capacity(BATCH_ROWS * kinds.len()),
            kinds,
            labels,
            rows: 0,
        })
    }

    /// Ends the row (a short row is padded with nulls); writes a full batch.
    pub(crate) fn end_row(&mut self) -> io::Result<()> {
        let n = self.kinds.len();
        self.rows += 1;
        // A row written short (not done by limbfuse's writers) or long.
        self.cells.resize(self.rows * n, f64::NAN);
        for b in self.labels.iter_mut().flatten() {
            while b.len() < self.rows {
                b.append_null();
            }
        }
        if self.rows == BATCH_ROWS {
            self.write_batch()?;
        }
        Ok(())
    }

    fn write_batch(&mut self) -> io::Result<()> {
        if self.rows == 0 {
            return Ok(());
        }
        let n = self.kinds.len();
        // One sequential pass over the staged rows into the columns.
        let mut columns: Vec<Vec<f64>> = (0..n).map(|_| Vec::with_capacity(self.rows)).collect();
        for row in self.cells.chunks_exact(n) {
            for (column, &v) in columns.iter_mut().zip(row) {
                column.push(v);
            }
        }
        let columns: Vec<ArrayRef> = columns
            .into_iter()
            .zip(self.labels.iter_mut())
            .map(|(mut values, label)| match label {
                Some(b) => Arc::new(b.finish()) as ArrayRef,
                None => {
                    let nulls = values
                        .iter()
                        .any(|v| v.is_nan())
                        .then(|| NullBuffer::from_iter(values.iter().map(|v| !v.is_nan())));
                    for v in values.iter_mut().filter(|v| v.is_nan()) {
                        *v = 0.0;
                    }
                    Arc::new(Float64Array::new(ScalarBuffer::from(values), nulls)) as ArrayRef
                }
            })
            .collect();
        self.cells.clear();
        let batch = RecordBatch::try_new(self.schema.clone(), columns).map_err(io_error)?;
        self.writer.write(&batch).map_err(io_error)?;
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
