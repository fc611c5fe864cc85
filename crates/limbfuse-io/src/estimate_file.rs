//! Estimate files (SPEC section 3): the [`EstimateWriter`] observer and the
//! streaming [`EstimateReader`].
//!
//! Layout: `# method: NAME`, then `# key: value` lines with the parameters
//! used, then (when the writer knows it) `# command:` (the command that
//! made the file), then (when the writer knows its trial) `# trial: FILE NAME` and
//! `# trial_hash: xxh3:HEX` (the trial file's [`ContentHash`]), then `t`, the
//! estimated quantities (`trunk`, ..., `ankle`, `phase`, `speed`) and the
//! method's diagnostics with a `diag_` prefix.
//!
//! [`EstimateWriter::for_path`] writes an Arrow IPC file instead for a path
//! ending in `.arrow`/`.feather` (`crate::arrow_file`: the same columns;
//! the header entries as schema metadata, the trial hash in the footer).

use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Estimator, GaitPhase, Record, MAX_DIAG};

use crate::arrow_file::{self, ArrowSink};
use crate::cell_sink::{CellSink, CsvLine};
use crate::content_hash::{ContentHash, STREAMED_HASH, TRIAL_HASH_KEY, TRIAL_KEY};
use crate::diagnostic_columns::DiagnosticColumns;
use crate::error::FileError;
use crate::meta::TrialMeta;
use crate::table::TableReader;

/// Writes every estimate of a run to an estimate file.
pub struct EstimateWriter<W: Write> {
    /// The output (CSV; an Arrow file's until its schema is written).
    out: Option<W>,
    /// Write an Arrow IPC file.
    arrow: bool,
    /// The Arrow file, once the run has started.
    sink: Option<Box<ArrowSink<W>>>,
    outputs: Outputs,
    /// The diagnostics asked for, and their indices in `Estimate::diag`
    /// once the run has started.
    diagnostics: DiagnosticColumns,
    diag_columns: Vec<usize>,
    line: CsvLine,
    /// The trial's file name, for the `# trial:` header line.
    trial: Option<String>,
    /// Byte offset of the `# trial_hash:` value, once the header is written.
    hash_offset: Option<u64>,
    /// The header says `# trial_hash: streamed` (no hash to stamp).
    streamed: bool,
    /// The command that made the file, for the `# command:` header line.
    command: Option<String>,
    /// CSV rows are written [`ROW_BLOCK_BYTES`] at a time, not one by one.
    in_blocks: bool,
}

/// Bytes of CSV rows gathered before one write ([`EstimateWriter::in_blocks`]).
const ROW_BLOCK_BYTES: usize = 64 << 10;

/// Header key of the command that wrote an estimate file (`# command: ...`).
pub const COMMAND_KEY: &str = "command";

/// Written in place of the trial hash until [`EstimateWriter::stamp_trial_hash`].
const HASH_PLACEHOLDER: &str = "xxh3:????????????????";

impl<W: Write> EstimateWriter<W> {
    /// A writer that writes its header when the run starts.
    pub fn new(out: W) -> Self {
        EstimateWriter {
            out: Some(out),
            arrow: false,
            sink: None,
            outputs: Outputs::default(),
            diagnostics: DiagnosticColumns::All,
            diag_columns: Vec::new(),
            line: CsvLine::with_capacity(ROW_BLOCK_BYTES + 4096),
            trial: None,
            hash_offset: None,
            streamed: false,
            command: None,
            in_blocks: false,
        }
    }

    /// Writes CSV rows in blocks of 64 KiB instead of one by one: for a
    /// file (one copy and one write call less per row), not for a stream
    /// whose reader wants each row as it is made (docs/STREAMING.md).
    pub fn in_blocks(mut self) -> Self {
        self.in_blocks = true;
        self
    }

    /// A writer of an Arrow IPC estimate file (docs/ARROW.md).
    pub fn arrow(out: W) -> Self {
        let mut w = Self::new(out);
        w.arrow = true;
        w
    }

    /// [`EstimateWriter::arrow`] when `path` names an Arrow file
    /// ([`arrow_file::is_arrow_path`]), else [`EstimateWriter::new`] (CSV)
    /// writing [`EstimateWriter::in_blocks`]: `out` is that file.
    pub fn for_path(path: &Path, out: W) -> Self {
        if arrow_file::is_arrow_path(path) {
            Self::arrow(out)
        } else {
            Self::new(out).in_blocks()
        }
    }

    /// Records the trial in the header: `# trial: NAME` and a
    /// `# trial_hash:` line whose value [`EstimateWriter::stamp_trial_hash`]
    /// fills in after the run (the trial is hashed as it is read, so the hash
    /// is known only at its end).
    pub fn recording_trial(mut self, name: impl Into<String>) -> Self {
        let name: String = name.into();
        self.trial = Some(name.replace(['\n', '\r'], " "));
        self
    }

    /// Records the trial of an estimate written as it is made, to an output
    /// that cannot be rewritten (standard output): `# trial: NAME` and
    /// `# trial_hash: streamed` ([`STREAMED_HASH`]), since the hash is
    /// known only at the trial's end.
    pub fn streaming_trial(mut self, name: impl Into<String>) -> Self {
        self = self.recording_trial(name);
        self.streamed = true;
        self
    }

    /// Records the command that makes the file: a `# command:` header line
    /// after the parameters (line breaks become spaces).
    pub fn recording_command(mut self, command: impl Into<String>) -> Self {
        let command: String = command.into();
        self.command = Some(command.replace(['\n', '\r'], " "));
        self
    }

    /// Writes only the diagnostics `columns` selects (default: all); the
    /// run fails at its start if it names one the estimator does not have.
    pub fn with_diagnostics(mut self, columns: DiagnosticColumns) -> Self {
        self.diagnostics = columns;
        self
    }

    /// Flushes (an Arrow file: writes its last batch and footer) and
    /// returns the underlying writer.
    pub fn into_inner(mut self) -> std::io::Result<W> {
        if let Some(sink) = self.sink.take() {
            return sink.finish();
        }
        self.write_rows()?;
        let mut out = self
            .out
            .take()
            .ok_or_else(|| std::io::Error::other("the estimate writer has no output"))?;
        out.flush()?;
        Ok(out)
    }

    /// Writes the CSV rows gathered ([`EstimateWriter::in_blocks`]).
    fn write_rows(&mut self) -> std::io::Result<()> {
        if !self.in_blocks {
            return Ok(());
        }
        if let Some(out) = self.out.as_mut() {
            out.write_all(self.line.take_rows())?;
        }
        self.line.clear();
        Ok(())
    }

    fn csv_out(&mut self) -> std::io::Result<&mut W> {
        self.out
            .as_mut()
            .ok_or_else(|| std::io::Error::other("the estimate writer has no output"))
    }
}

impl<W: Write> Observer for EstimateWriter<W> {
    fn start(&mut self, estimator: &dyn Estimator) -> Result<(), BoxError> {
        let mut meta = TrialMeta::new();
        meta.set("method", estimator.name());
        let mut head = format!("# method: {}\n", estimator.name());
        let mut params = String::new();
        estimator.describe_parameters(&mut params)?;
        for l in params.lines().filter(|l| !l.trim().is_empty()) {
            head.push_str(&format!("# {l}\n"));
            if let Some((k, v)) = l.split_once(':') {
                meta.set(k.trim(), v.trim());
            }
        }
        if let Some(c) = &self.command {
            head.push_str(&format!("# {COMMAND_KEY}: {c}\n"));
            meta.set(COMMAND_KEY, c);
        }
        if let Some(name) = &self.trial {
            meta.set(TRIAL_KEY, name);
            head.push_str(&format!("# {TRIAL_KEY}: {name}\n# {TRIAL_HASH_KEY}: "));
            if self.streamed {
                head.push_str(STREAMED_HASH);
                meta.set(TRIAL_HASH_KEY, STREAMED_HASH);
            } else {
                self.hash_offset = Some(head.len() as u64);
                head.push_str(HASH_PLACEHOLDER);
            }
            head.push('\n');
        }
        self.outputs = estimator.outputs();
        let names = estimator.diagnostic_names();
        self.diag_columns = self.diagnostics.resolve(estimator.name(), names)?;
        let mut header = vec!["t".to_string()];
        for c in AngleChannel::ALL {
            if output_has(&self.outputs, c) {
                header.push(c.name().into());
            }
        }
        if self.outputs.phase {
            header.push("phase".into());
        }
        if self.outputs.speed {
            header.push("speed".into());
        }
        if self.outputs.com {
            header.extend(COM_COLUMNS.iter().map(|c| c.to_string()));
        }
        if self.outputs.contact {
            header.extend(CONTACT_COLUMNS.iter().map(|c| c.to_string()));
        }
        header.extend(
            self.diag_columns
                .iter()
                .map(|&i| format!("diag_{}", names[i])),
        );
        if self.arrow {
            let out = self.out.take().ok_or("the estimate writer has no output")?;
            self.sink = Some(Box::new(ArrowSink::new(out, header, "phase", &meta)?));
            return Ok(());
        }
        let out = self.csv_out()?;
        out.write_all(head.as_bytes())?;
        writeln!(out, "{}", header.join(","))?;
        Ok(())
    }

    fn observe(&mut self, _record: &Record, e: &Estimate) -> Result<(), BoxError> {
        if let Some(sink) = &mut self.sink {
            write_estimate(sink.as_mut(), &self.outputs, &self.diag_columns, e);
            sink.end_row()?;
            return Ok(());
        }
        let line = &mut self.line;
        if self.in_blocks {
            let at = line.len();
            write_estimate(line, &self.outputs, &self.diag_columns, e);
            line.end_row(at);
            if line.len() >= ROW_BLOCK_BYTES {
                self.write_rows()?;
            }
            return Ok(());
        }
        line.clear();
        write_estimate(line, &self.outputs, &self.diag_columns, e);
        let out = self
            .out
            .as_mut()
            .ok_or("the estimate writer has no output")?;
        out.write_all(line.finish())?;
        Ok(())
    }

    fn finish(&mut self) -> Result<(), BoxError> {
        self.write_rows()?;
        if let Some(out) = &mut self.out {
            out.flush()?;
        }
        Ok(())
    }
}

/// The cells of `e` in the column order of the header ([`Observer::start`]).
fn write_estimate<S: CellSink + ?Sized>(
    line: &mut S,
    outputs: &Outputs,
    diag_columns: &[usize],
    e: &Estimate,
) {
    line.number(Some(e.t));
    for c in AngleChannel::ALL {
        if output_has(outputs, c) {
            line.number(e.angle(c));
        }
    }
    if outputs.phase {
        line.label(e.phase.map(|p| p.label()));
    }
    if outputs.speed {
        line.number(e.speed);
    }
    if outputs.com {
        for k in 0..3 {
            line.number(e.com_pos.map(|v| v[k]));
        }
        for k in 0..3 {
            line.number(e.com_vel.map(|v| v[k]));
        }
    }
    if outputs.contact {
        for c in e.contact {
            line.number(c.map(|c| if c { 1.0 } else { 0.0 }));
        }
    }
    for &i in diag_columns {
        line.number(e.diag[i]);
    }
}

impl<W: Write + Seek> EstimateWriter<W> {
    /// Writes the trial's hash into the `# trial_hash:` line of the header
    /// (after the run; needs [`EstimateWriter::recording_trial`] and a
    /// started run). `out` must have been empty when the writer was made.
    ///
    /// An Arrow file gets the hash as a footer metadata entry instead.
    pub fn stamp_trial_hash(&mut self, hash: ContentHash) -> std::io::Result<()> {
        if let Some(sink) = &mut self.sink {
            if self.trial.is_none() {
                return Err(std::io::Error::other(
                    "no trial to stamp a hash for: the writer does not record its trial",
                ));
            }
            sink.footer_entry(TRIAL_HASH_KEY, &hash.to_string());
            return Ok(());
        }
        let Some(offset) = self.hash_offset else {
            return Err(std::io::Error::other(
                "no `# trial_hash:` line to stamp: the writer does not record its trial or the run did not start",
            ));
        };
        let text = hash.to_string();
        debug_assert_eq!(text.len(), HASH_PLACEHOLDER.len());
        self.write_rows()?;
        let out = self.csv_out()?;
        out.flush()?;
        out.seek(SeekFrom::Start(offset))?;
        out.write_all(text.as_bytes())?;
        out.seek(SeekFrom::End(0))?;
        Ok(())
    }
}

/// Foot-contact estimate columns (SPEC section 3), in [`Estimate::contact`] order (left, right).
pub const CONTACT_COLUMNS: [&str; 2] = ["contact_left", "contact_right"];

/// CoM estimate columns (SPEC section 3: `com_*` without `_ref`), position then velocity.
pub const COM_COLUMNS: [&str; 6] = ["com_x", "com_y", "com_z", "com_vx", "com_vy", "com_vz"];

fn output_has(o: &Outputs, c: AngleChannel) -> bool {
    match c {
        AngleChannel::Segment(s) => o.segment[s.index()],
        AngleChannel::Joint(j) => o.joint[j.index()],
    }
}

/// Reads an estimate file row by row.
#[derive(Debug)]
pub struct EstimateReader {
    table: TableReader,
    t: usize,
    angle: [Option<usize>; 7],
    phase: Option<usize>,
    speed: Option<usize>,
    com: [Option<usize>; 6],
    contact: [Option<usize>; 2],
    diag: Vec<(String, usize)>,
    previous_t: Option<f64>,
}

impl EstimateReader {
    /// Opens an estimate file.
    pub fn open(path: &Path) -> Result<Self, FileError> {
        Self::from_table(TableReader::open(path)?)
    }

    /// Reads estimates from any byte source; `path` names it in errors.
    pub fn from_reader(path: &Path, source: Box<dyn Read + Send>) -> Result<Self, FileError> {
        Self::from_table(TableReader::from_reader(path, source)?)
    }

    fn from_table(table: TableReader) -> Result<Self, FileError> {
        let t = table.time_column()?;
        let angle = AngleChannel::ALL.map(|c| table.column(c.name()));
        let outputs = angle.iter().any(Option::is_some)
            || ["phase", "speed"]
                .into_iter()
                .chain(COM_COLUMNS)
                .chain(CONTACT_COLUMNS)
                .any(|c| table.column(c).is_some());
        if !outputs {
            // A trial file given as the estimate (an audit: `evaluate w.csv
            // w.csv` gave an empty table, exit 0).
            let sensor = table
                .header()
                .iter()
                .find(|h| h.contains("_gyr_") || h.contains("_acc_") || h.ends_with("_ref"));
            return Err(FileError::Header {
                path: table.path().to_path_buf(),
                line: table.header_line(),
                message: format!(
                    "no estimate column (an angle `thigh` ... `ankle`, `speed`, `phase`, `com_*` or \
                     `contact_*`, SPEC section 3){}",
                    sensor.map_or(String::new(), |c| format!(
                        "; it has `{c}`: a trial file, not an estimate?"
                    ))
                ),
            });
        }
        let diag: Vec<(String, usize)> = table
            .header()
            .iter()
            .enumerate()
            .filter_map(|(i, h)| h.strip_prefix("diag_").map(|n| (n.to_string(), i)))
            .take(MAX_DIAG)
            .collect();
        Ok(EstimateReader {
            phase: table.column("phase"),
            speed: table.column("speed"),
            com: COM_COLUMNS.map(|c| table.column(c)),
            contact: CONTACT_COLUMNS.map(|c| table.column(c)),
            table,
            t,
            angle,
            diag,
            previous_t: None,
        })
    }

    /// The `# method:` entry (`unknown` if absent) .
    pub fn method(&self) -> &str {
        self.table.meta().get("method").unwrap_or("unknown")
    }

    /// The `# trial:` entry: the file name of the trial the estimate was
    /// made from (absent in files written before limbfuse recorded it).
    pub fn recorded_trial(&self) -> Option<&str> {
        self.table.meta().get(TRIAL_KEY)
    }

    /// The `# trial_hash:` entry as written (`xxh3:HEX`); parse it with
    /// [`ContentHash::parse`].
    pub fn recorded_trial_hash(&self) -> Option<&str> {
        self.table.meta().get(TRIAL_HASH_KEY)
    }

    /// All metadata (method and parameters).
    pub fn meta(&self) -> &TrialMeta {
        self.table.meta()
    }

    /// Names of the diagnostic columns (without `diag_`), in [`Estimate::diag`] order.
    pub fn diagnostic_names(&self) -> impl Iterator<Item = &str> {
        self.diag.iter().map(|(n, _)| n.as_str())
    }

    /// True when the file has `contact_left` or `contact_right`.
    pub fn has_contact(&self) -> bool {
        self.contact.iter().any(Option::is_some)
    }

    /// True when the file has a `speed` column.
    pub fn has_speed(&self) -> bool {
        self.speed.is_some()
    }

    /// True when the file holds any segment or joint angle.
    pub fn has_any_angle(&self) -> bool {
        self.angle.iter().any(Option::is_some)
    }

    /// Which angle channels the file holds.
    pub fn has_angle(&self, c: AngleChannel) -> bool {
        AngleChannel::ALL
            .iter()
            .position(|&a| a == c)
            .is_some_and(|i| self.angle[i].is_some())
    }

    /// The file path.
    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// The last line, left out when it was cut off mid-row (known once the
    /// reader reached the end; [`crate::table::CutLine`]).
    pub fn cut_last_line(&self) -> Option<crate::table::CutLine> {
        self.table.cut_last_line()
    }

    /// Reads the next estimate and its line number; `Ok(None)` at the end.
    pub fn next_estimate(&mut self) -> Result<Option<(u64, Estimate)>, FileError> {
        let Some(row) = self.table.next_row()? else {
            return Ok(None);
        };
        let t = row.time(self.t, self.previous_t)?;
        let mut e = Estimate::empty(t);
        for (k, c) in AngleChannel::ALL.iter().enumerate() {
            let v = row.opt_number(self.angle[k])?;
            match c {
                AngleChannel::Segment(s) => e.segment[s.index()] = v,
                AngleChannel::Joint(j) => e.joint[j.index()] = v,
            }
        }
        if let Some(c) = self.phase {
            let text = row.text(c);
            if !text.is_empty() {
                let p = std::str::from_utf8(text)
                    .ok()
                    .and_then(GaitPhase::from_label);
                e.phase =
                    Some(p.ok_or_else(|| row.cell_error(c, "a gait phase `SS1`, `DS` or `SS2`"))?);
            }
        }
        e.speed = row.opt_number(self.speed)?;
        let mut com = [None; 6];
        for (v, c) in com.iter_mut().zip(self.com) {
            *v = row.opt_number(c)?;
        }
        if let [Some(x), Some(y), Some(z), ..] = com {
            e.com_pos = Some(nalgebra::Vector3::new(x, y, z));
        }
        if let [.., Some(x), Some(y), Some(z)] = com {
            e.com_vel = Some(nalgebra::Vector3::new(x, y, z));
        }
        for (side, col) in self.contact.iter().enumerate() {
            if let Some(c) = *col {
                e.contact[side] = match row.number(c)? {
                    None => None,
                    Some(0.0) => Some(false),
                    Some(1.0) => Some(true),
                    Some(_) => {
                        return Err(row.cell_error(
                            c,
                            "a foot contact 1 (stance), 0 (swing) or an empty cell",
                        ))
                    }
                };
            }
        }
        for (k, (_, c)) in self.diag.iter().enumerate() {
            e.diag[k] = row.number(*c)?;
        }
        let line = row.line();
        self.previous_t = Some(t);
        Ok(Some((line, e)))
    }
}
