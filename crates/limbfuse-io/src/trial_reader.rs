//! Streaming reader of trial files (SPEC section 2).
//!
//! Columns are found by name, in any order; unknown columns are ignored. A
//! 3-axis vector (or quaternion) is present in a sample only when all its
//! cells are present: a partly empty vector is a missing sample.

use std::io::Read;
use std::path::Path;

use limbfuse_core::sample::{GaitPhase, ModelInputs};
use limbfuse_core::{Joint, Record, Segment, Side};
use nalgebra::Vector3;

use crate::error::FileError;
use crate::layout::{contact_ref_column, other_leg_prefix, TrialLayout, AXES, QUAT};
use crate::meta::TrialMeta;
use crate::table::{Row, TableReader};
use crate::whole_file::ParsedRows;

/// Column indices of every known channel.
#[derive(Debug, Clone, Default)]
pub(crate) struct ColumnPlan {
    t: usize,
    acc: [Option<[usize; 3]>; 4],
    gyr: [Option<[usize; 3]>; 4],
    quat: [Option<[usize; 4]>; 4],
    encoder: [Option<usize>; 3],
    stim: [Option<usize>; 4],
    motor: [Option<usize>; 3],
    segment_ref: [Option<usize>; 4],
    joint_ref: [Option<usize>; 3],
    com_pos: Option<[usize; 3]>,
    com_vel: Option<[usize; 3]>,
    phase_ref: Option<usize>,
    com_meas: [Option<usize>; 6],
    other_acc: [Option<[usize; 3]>; 4],
    other_gyr: [Option<[usize; 3]>; 4],
    contact_ref: [Option<usize>; 2],
    speed_ref: Option<usize>,
}

impl ColumnPlan {
    /// The time column.
    pub(crate) fn time(&self) -> usize {
        self.t
    }

    /// The foot contact columns (cells 0, 1 or empty).
    pub(crate) fn contact_columns(&self) -> impl Iterator<Item = usize> + '_ {
        self.contact_ref.iter().flatten().copied()
    }

    /// The gait phase label column.
    pub(crate) fn phase_column(&self) -> Option<usize> {
        self.phase_ref
    }

    /// Every column a record reads as a number (the time and the contact
    /// columns included), in file order, each once.
    pub(crate) fn number_columns(&self) -> Vec<usize> {
        let mut cols = vec![self.t];
        let groups3 = self
            .acc
            .iter()
            .chain(&self.gyr)
            .chain(&self.other_acc)
            .chain(&self.other_gyr)
            .chain([&self.com_pos, &self.com_vel]);
        for g in groups3.flatten() {
            cols.extend_from_slice(g);
        }
        for q in self.quat.iter().flatten() {
            cols.extend_from_slice(q);
        }
        let singles = self
            .encoder
            .iter()
            .chain(&self.stim)
            .chain(&self.motor)
            .chain(&self.segment_ref)
            .chain(&self.joint_ref)
            .chain(&self.com_meas)
            .chain(&self.contact_ref)
            .chain([&self.speed_ref]);
        cols.extend(singles.flatten());
        cols.sort_unstable();
        cols.dedup();
        cols
    }
}

/// Reads a trial file one [`Record`] at a time.
#[derive(Debug)]
pub struct TrialReader {
    table: TableReader,
    plan: ColumnPlan,
    layout: TrialLayout,
    previous_t: Option<f64>,
    rows: u64,
    /// The rows of a file read whole ([`TrialReader::open_whole`]).
    parsed: Option<ParsedRows>,
}

/// Finds a group of columns `prefix + suffix`; all or none must exist.
fn group<const K: usize>(
    table: &TableReader,
    prefix: &str,
    suffixes: [&str; K],
) -> Result<Option<[usize; K]>, FileError> {
    let found: Vec<Option<usize>> = suffixes
        .iter()
        .map(|s| table.column(&format!("{prefix}{s}")))
        .collect();
    if found.iter().all(Option::is_none) {
        return Ok(None);
    }
    if let Some(k) = found.iter().position(Option::is_none) {
        return Err(FileError::Header {
            path: table.path().to_path_buf(),
            line: table.header_line(),
            message: format!(
                "incomplete channel group: found `{prefix}...` columns but not `{prefix}{}` (expected all of {})",
                suffixes[k],
                suffixes.iter().map(|s| format!("{prefix}{s}")).collect::<Vec<_>>().join(", ")
            ),
        });
    }
    let mut out = [0usize; K];
    for (o, f) in out.iter_mut().zip(found) {
        *o = f.unwrap_or_default();
    }
    Ok(Some(out))
}

impl TrialReader {
    /// Opens a trial file.
    pub fn open(path: &Path) -> Result<Self, FileError> {
        Self::from_table(TableReader::open(path)?)
    }

    /// Opens a trial file and reads it whole, parsing its rows on every
    /// core (`crate::whole_file`); the records, errors and content hash are
    /// those of [`TrialReader::open`], which is used instead for an Arrow
    /// file, a file larger than 1 GiB, a file with quoted cells or one with
    /// an error (so that the error is found and reported as it always was).
    /// Holds the file's numbers in memory (8 bytes per cell read); not for
    /// standard input, which must stay streamed.
    pub fn open_whole(path: &Path) -> Result<Self, FileError> {
        let Some(whole) = crate::whole_file::load(path) else {
            return Self::open(path);
        };
        let (table, body) = whole.into_parts();
        let Ok(mut reader) = Self::from_table(table) else {
            return Self::open(path);
        };
        match body.parse(&reader.plan, reader.table.header().len()) {
            Some(rows) => {
                reader.parsed = Some(rows);
                Ok(reader)
            }
            None => Self::open(path),
        }
    }

    /// Reads a trial from any byte source; `path` names it in errors.
    pub fn from_reader(path: &Path, source: Box<dyn Read + Send>) -> Result<Self, FileError> {
        Self::from_table(TableReader::from_reader(path, source)?)
    }

    fn from_table(table: TableReader) -> Result<Self, FileError> {
        let t = table.time_column()?;
        let mut plan = ColumnPlan {
            t,
            ..Default::default()
        };
        let mut layout = TrialLayout::default();
        for s in Segment::ALL {
            let i = s.index();
            let n = s.name();
            plan.acc[i] = group(&table, &format!("{n}_acc_"), AXES)?;
            plan.gyr[i] = group(&table, &format!("{n}_gyr_"), AXES)?;
            plan.quat[i] = group(&table, &format!("{n}_quat_"), QUAT)?;
            plan.segment_ref[i] = table.column(&format!("{n}_ref"));
            layout.acc[i] = plan.acc[i].is_some();
            layout.gyr[i] = plan.gyr[i].is_some();
            layout.quat[i] = plan.quat[i].is_some();
            layout.segment_ref[i] = plan.segment_ref[i].is_some();
        }
        for j in Joint::ALL {
            let i = j.index();
            plan.encoder[i] = table.column(&format!("{}_enc", j.name()));
            plan.joint_ref[i] = table.column(&format!("{}_ref", j.name()));
            plan.motor[i] = table.column(&format!("tau_{}_motor", j.name()));
            layout.encoder[i] = plan.encoder[i].is_some();
            layout.joint_ref[i] = plan.joint_ref[i].is_some();
            layout.motor_torque[i] = plan.motor[i].is_some();
        }
        for (k, name) in ModelInputs::STIM_NAMES.iter().enumerate() {
            plan.stim[k] = table.column(name);
            layout.stim[k] = plan.stim[k].is_some();
        }
        plan.com_pos = group(&table, "com_", ["x", "y", "z"])?;
        plan.com_vel = group(&table, "com_", ["vx", "vy", "vz"])?;
        plan.phase_ref = table.column("phase_ref");
        for (k, name) in limbfuse_core::ComMeasurement::NAMES.iter().enumerate() {
            plan.com_meas[k] = table.column(name);
            layout.com_meas[k] = plan.com_meas[k].is_some();
        }
        let own_leg = match table.meta().get("leg") {
            None => Side::Right,
            Some(text) => Side::parse(text).ok_or_else(|| FileError::Header {
                path: table.path().to_path_buf(),
                line: table.header_line(),
                message: format!("metadata `# leg: {text}`: expected `left` or `right`"),
            })?,
        };
        layout.leg = own_leg;
        for s in Segment::ALL {
            let i = s.index();
            let p = other_leg_prefix(s, layout.other_leg());
            plan.other_acc[i] = group(&table, &format!("{p}acc_"), AXES)?;
            plan.other_gyr[i] = group(&table, &format!("{p}gyr_"), AXES)?;
            layout.other_acc[i] = plan.other_acc[i].is_some();
            layout.other_gyr[i] = plan.other_gyr[i].is_some();
        }
        for side in Side::BOTH {
            plan.contact_ref[side.index()] = table.column(&contact_ref_column(side));
            layout.contact_ref[side.index()] = plan.contact_ref[side.index()].is_some();
        }
        plan.speed_ref = table.column("speed_ref");
        layout.speed_ref = plan.speed_ref.is_some();
        layout.com_pos = plan.com_pos.is_some();
        layout.com_vel = plan.com_vel.is_some();
        layout.phase_ref = plan.phase_ref.is_some();
        Ok(TrialReader {
            table,
            plan,
            layout,
            previous_t: None,
            rows: 0,
            parsed: None,
        })
    }

    /// Metadata from the file's comment lines.
    pub fn meta(&self) -> &TrialMeta {
        self.table.meta()
    }

    /// The channels this trial has.
    pub fn layout(&self) -> &TrialLayout {
        &self.layout
    }

    /// The file path.
    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// The content hash of the trial file, hashed as it was read; `Some`
    /// once every record has been read (the estimate file records it).
    pub fn content_hash(&self) -> Option<crate::ContentHash> {
        if let Some(rows) = &self.parsed {
            return rows.content_hash();
        }
        self.table.content_hash()
    }

    /// Reads the next record; `Ok(None)` at the end of the file. A file with
    /// a header and no rows is an error ([`FileError::NoRows`]).
    pub fn next_record(&mut self) -> Result<Option<Record>, FileError> {
        if let Some(rows) = &mut self.parsed {
            let Some(row) = rows.next_row(self.table.path(), self.table.header()) else {
                return Ok(None);
            };
            let rec = build_record(&self.plan, &row, self.previous_t)?;
            self.previous_t = Some(rec.sample.t);
            self.rows += 1;
            return Ok(Some(rec));
        }
        let header_line = self.table.header_line();
        let Some(row) = self.table.next_row()? else {
            if self.rows == 0 {
                return Err(FileError::NoRows {
                    path: self.table.path().to_path_buf(),
                    line: header_line + 1,
                });
            }
            return Ok(None);
        };
        let rec = build_record(&self.plan, &row, self.previous_t)?;
        self.previous_t = Some(rec.sample.t);
        self.rows += 1;
        Ok(Some(rec))
    }
}

/// The cells a record is built from: a row of the file ([`Row`]), or the
/// row's numbers parsed ahead (`crate::whole_file`).
pub(crate) trait RowCells {
    /// The finite number in column `col`, `None` when the cell is empty.
    fn number(&self, col: usize) -> Result<Option<f64>, FileError>;
    /// The time in column `col`: present, finite, and after `previous`.
    fn time(&self, col: usize, previous: Option<f64>) -> Result<f64, FileError>;
    /// The gait phase label in column `col`, `None` when the cell is empty.
    fn phase(&self, col: usize) -> Result<Option<GaitPhase>, FileError>;
    /// An error about column `col` of this row.
    fn cell_error(&self, col: usize, expected: &'static str) -> FileError;
    /// The number in an optional column.
    #[inline]
    fn opt_number(&self, col: Option<usize>) -> Result<Option<f64>, FileError> {
        match col {
            Some(c) => self.number(c),
            None => Ok(None),
        }
    }
}

/// What a gait phase cell must hold.
pub(crate) const PHASE_EXPECTED: &str = "a gait phase `SS1`, `DS` or `SS2`";

/// What a foot contact cell must hold.
pub(crate) const CONTACT_EXPECTED: &str =
    "a foot contact 1 (on the ground), 0 (swing) or an empty cell";

impl RowCells for Row<'_> {
    #[inline]
    fn number(&self, col: usize) -> Result<Option<f64>, FileError> {
        Row::number(self, col)
    }
    #[inline]
    fn time(&self, col: usize, previous: Option<f64>) -> Result<f64, FileError> {
        Row::time(self, col, previous)
    }
    fn phase(&self, col: usize) -> Result<Option<GaitPhase>, FileError> {
        let text = self.text(col);
        if text.is_empty() {
            return Ok(None);
        }
        let label = std::str::from_utf8(text)
            .ok()
            .and_then(GaitPhase::from_label);
        Ok(Some(
            label.ok_or_else(|| Row::cell_error(self, col, PHASE_EXPECTED))?,
        ))
    }
    fn cell_error(&self, col: usize, expected: &'static str) -> FileError {
        Row::cell_error(self, col, expected)
    }
}

/// The record of one row, read as [`TrialReader::next_record`] reads it.
#[inline]
pub(crate) fn build_record<C: RowCells>(
    plan: &ColumnPlan,
    row: &C,
    previous_t: Option<f64>,
) -> Result<Record, FileError> {
    let t = row.time(plan.t, previous_t)?;
    let mut rec = Record::default();
    rec.sample.t = t;
    for i in 0..4 {
        rec.sample.imu[i].acc = vector(row, plan.acc[i])?;
        rec.sample.imu[i].gyr = vector(row, plan.gyr[i])?;
        rec.sample.imu[i].quat = match plan.quat[i] {
            Some(cols) => numbers(row, cols)?,
            None => None,
        };
        rec.reference.segment[i] = row.opt_number(plan.segment_ref[i])?;
    }
    for i in 0..4 {
        rec.sample.other_leg_imu[i].acc = vector(row, plan.other_acc[i])?;
        rec.sample.other_leg_imu[i].gyr = vector(row, plan.other_gyr[i])?;
    }
    for side in 0..2 {
        if let Some(c) = plan.contact_ref[side] {
            rec.reference.contact[side] = match row.number(c)? {
                None => None,
                Some(0.0) => Some(false),
                Some(1.0) => Some(true),
                Some(_) => return Err(row.cell_error(c, CONTACT_EXPECTED)),
            };
        }
    }
    rec.reference.speed = row.opt_number(plan.speed_ref)?;
    for i in 0..3 {
        rec.sample.encoder[i] = row.opt_number(plan.encoder[i])?;
        rec.sample.inputs.motor_torque[i] = row.opt_number(plan.motor[i])?;
        rec.reference.joint[i] = row.opt_number(plan.joint_ref[i])?;
    }
    for k in 0..4 {
        rec.sample.inputs.stim[k] = row.opt_number(plan.stim[k])?;
    }
    for k in 0..6 {
        rec.sample.com.set(k, row.opt_number(plan.com_meas[k])?);
    }
    rec.reference.com_pos = vector(row, plan.com_pos)?;
    rec.reference.com_vel = vector(row, plan.com_vel)?;
    if let Some(c) = plan.phase_ref {
        rec.reference.phase = row.phase(c)?;
    }
    Ok(rec)
}

fn numbers<C: RowCells, const K: usize>(
    row: &C,
    cols: [usize; K],
) -> Result<Option<[f64; K]>, FileError> {
    let mut out = [0.0; K];
    let mut complete = true;
    for (o, c) in out.iter_mut().zip(cols) {
        match row.number(c)? {
            Some(v) => *o = v,
            None => complete = false,
        }
    }
    Ok(complete.then_some(out))
}

fn vector<C: RowCells>(row: &C, cols: Option<[usize; 3]>) -> Result<Option<Vector3<f64>>, FileError> {
    match cols {
        Some(c) => Ok(numbers(row, c)?.map(Vector3::from)),
        None => Ok(None),
    }
}

impl Iterator for TrialReader {
    type Item = Result<Record, FileError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_record().transpose()
    }
}
