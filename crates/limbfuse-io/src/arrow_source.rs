//! Reading the rows of an Arrow IPC file (`crate::arrow_file` describes the
//! layout): the file's bytes are mapped into memory ([`MappedFile`]; read
//! whole when it cannot be mapped) and each record batch is decoded in
//! place by arrow-ipc's `FileDecoder`, so its columns are views of the
//! file's pages: no batch is copied or allocated (issue 18 item 6; before,
//! `FileReader` read every batch into a fresh zeroed buffer). The content
//! hash is taken over the same bytes.

use std::fs::File;
use std::io::{Cursor, Read};
use std::path::Path;
use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use arrow_array::{Array, ArrayRef, RecordBatch};
use arrow_buffer::{Buffer, ScalarBuffer};
use arrow_ipc::reader::{read_footer_length, FileDecoder, FileReader};
use arrow_ipc::Block;
use arrow_schema::{ArrowError, DataType};

use crate::arrow_file::{guarded, ordered_meta};
use crate::content_hash::ContentHash;
use crate::error::FileError;
use crate::mapped_file::MappedFile;
use crate::meta::TrialMeta;

/// One column of the current batch, as read.
enum ColumnView {
    /// `Float64` numbers without nulls (the common case: one load per cell).
    Dense(ScalarBuffer<f64>),
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
    /// The whole file.
    bytes: Buffer,
    decoder: FileDecoder,
    /// The record batches' blocks, and the next one to read.
    blocks: Vec<Block>,
    next_block: usize,
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

/// The bytes of the file at `path`: mapped, or read whole when it cannot be.
fn file_bytes(path: &Path) -> Result<Buffer, FileError> {
    let mut file = File::open(path).map_err(|e| FileError::io(path, e))?;
    if let Some(map) = MappedFile::map(&file) {
        let (ptr, len) = (map.ptr(), map.bytes().len());
        // SAFETY: `ptr` maps `len` readable bytes for as long as `map`
        // lives, and the buffer owns `map`.
        return Ok(unsafe { Buffer::from_custom_allocation(ptr, len, Arc::new(map)) });
    }
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes)
        .map_err(|e| FileError::io(path, e))?;
    Ok(Buffer::from_vec(bytes))
}

/// What the file's footer lists (already verified by `FileReader::try_new`).
struct Footer {
    batches: Vec<Block>,
    dictionaries: Vec<Block>,
    version: arrow_ipc::MetadataVersion,
}

/// The record-batch and dictionary blocks and the version in the footer.
fn footer(bytes: &[u8]) -> Result<Footer, ArrowError> {
    let short = || ArrowError::ParseError("the file is too short for an Arrow IPC footer".into());
    let tail = bytes.len().checked_sub(10).ok_or_else(short)?;
    let mut end = [0u8; 10];
    end.copy_from_slice(&bytes[tail..]);
    let start = tail
        .checked_sub(read_footer_length(end)?)
        .ok_or_else(short)?;
    let footer = arrow_ipc::root_as_footer(&bytes[start..tail])
        .map_err(|e| ArrowError::ParseError(format!("Unable to get root as footer: {e:?}")))?;
    Ok(Footer {
        batches: footer
            .recordBatches()
            .map(|b| b.iter().copied().collect())
            .unwrap_or_default(),
        dictionaries: footer
            .dictionaries()
            .map(|b| b.iter().copied().collect())
            .unwrap_or_default(),
        version: footer.version(),
    })
}

/// The bytes of `block` in `bytes`, checked to lie inside the file.
fn block_bytes(bytes: &Buffer, block: &Block) -> Result<Buffer, ArrowError> {
    let offset = usize::try_from(block.offset()).ok();
    let meta = usize::try_from(block.metaDataLength()).ok();
    let body = usize::try_from(block.bodyLength()).ok();
    let range = offset.zip(meta).zip(body).and_then(|((o, m), b)| {
        let len = m.checked_add(b)?;
        (o.checked_add(len)? <= bytes.len()).then_some((o, len))
    });
    let (offset, len) = range.ok_or_else(|| {
        ArrowError::ParseError(format!(
            "a record batch block (offset {}, {} + {} bytes) beyond the end of the file ({} bytes)",
            block.offset(),
            block.metaDataLength(),
            block.bodyLength(),
            bytes.len()
        ))
    })?;
    Ok(bytes.slice_with_length(offset, len))
}

impl ArrowSource {
    /// Opens `path` and reads its schema and footer.
    pub(crate) fn open(path: &Path) -> Result<(Self, ArrowHead), FileError> {
        let bytes = file_bytes(path)?;
        // The footer, schema and metadata as `FileReader` reads them (the
        // same checks and messages); the batches are then decoded in place.
        let reader = guarded(path, || {
            FileReader::try_new(Cursor::new(bytes.clone()), None)
        })?;
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
        drop(reader);
        let footer = guarded(path, || footer(&bytes))?;
        let mut decoder = FileDecoder::new(schema, footer.version);
        for block in &footer.dictionaries {
            guarded(path, || {
                decoder.read_dictionary(block, &block_bytes(&bytes, block)?)
            })?;
        }
        let source = ArrowSource {
            bytes,
            decoder,
            blocks: footer.batches,
            next_block: 0,
            columns: Vec::new(),
            batch_rows: 0,
            row: 0,
            rows_before: 0,
        };
        Ok((source, ArrowHead { meta, header }))
    }

    /// The content hash of the whole file.
    pub(crate) fn content_hash(&self) -> ContentHash {
        ContentHash::of_bytes(&self.bytes)
    }

    /// The next record batch; `None` after the last.
    fn next_batch(&mut self, path: &Path) -> Result<Option<RecordBatch>, FileError> {
        let Some(block) = self.blocks.get(self.next_block) else {
            return Ok(None);
        };
        self.next_block += 1;
        let (bytes, decoder) = (&self.bytes, &self.decoder);
        guarded(path, || {
            decoder.read_record_batch(block, &block_bytes(bytes, block)?)
        })
    }

    /// Moves to the next row; its 1-based row number, `None` at the end.
    pub(crate) fn advance(&mut self, path: &Path) -> Result<Option<u64>, FileError> {
        while self.row >= self.batch_rows {
            let Some(batch) = self.next_batch(path)? else {
                // A block without a batch ends the file, as for `FileReader`.
                self.blocks.truncate(self.next_block);
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
            ColumnView::Dense(v) => Ok(Some(v[r])),
            ColumnView::Float(a) => Ok(a.is_valid(r).then(|| a.value(r))),
            ColumnView::Number { values, valid } => Ok(valid[r].then_some(values[r])),
            ColumnView::Text(a) => text_number(a.is_valid(r).then(|| a.value(r))),
            ColumnView::LargeText(a) => text_number(a.is_valid(r).then(|| a.value(r))),
        }
    }

    /// The numbers of the columns `cols` of the current row into
    /// `out[col]`; at the first cell that is neither a finite number nor
    /// null, `Err(col)` (the caller builds the error).
    #[inline]
    pub(crate) fn numbers_into(
        &self,
        cols: &[usize],
        out: &mut [Option<f64>],
    ) -> Result<(), usize> {
        let r = self.row - 1;
        for &c in cols {
            let v = match &self.columns[c] {
                ColumnView::Dense(v) => Some(v[r]),
                _ => self.number(c).map_err(|()| c)?,
            };
            if v.is_some_and(|v| !v.is_finite()) {
                return Err(c);
            }
            out[c] = v;
        }
        Ok(())
    }

    /// The text of column `col` of the current row (empty when null or a number).
    pub(crate) fn text(&self, col: usize) -> &[u8] {
        let r = self.row - 1;
        match &self.columns[col] {
            ColumnView::Dense(_) | ColumnView::Float(_) | ColumnView::Number { .. } => b"",
            ColumnView::Text(a) if a.is_valid(r) => a.value(r).as_bytes(),
            ColumnView::LargeText(a) if a.is_valid(r) => a.value(r).as_bytes(),
            _ => b"",
        }
    }

    /// The cell as text, for an error message: a text cell as written (an
    /// audit: `1e999` in a `Utf8` column was shown as `inf`, where the CSV
    /// reader shows `1e999`), a number as `ShownNumber` writes it.
    pub(crate) fn found(&self, col: usize) -> String {
        match &self.columns[col] {
            ColumnView::Text(_) | ColumnView::LargeText(_) => {
                String::from_utf8_lossy(self.text(col)).into_owned()
            }
            _ => match self.number(col) {
                Ok(Some(v)) => limbfuse_core::ShownNumber(v).to_string(),
                _ => String::new(),
            },
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
        DataType::Float64 => {
            let a = c.as_primitive::<Float64Type>();
            if a.null_count() == 0 {
                ColumnView::Dense(a.values().clone())
            } else {
                ColumnView::Float(a.clone())
            }
        }
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

/// The content hash and the number of rows of an Arrow IPC file (decodes
/// every batch in place).
pub(crate) fn hash_and_rows(path: &Path) -> Result<(ContentHash, u64), FileError> {
    let (mut source, _) = ArrowSource::open(path)?;
    let mut rows = 0u64;
    while let Some(batch) = source.next_batch(path)? {
        rows += batch.num_rows() as u64;
    }
    Ok((source.content_hash(), rows))
}
