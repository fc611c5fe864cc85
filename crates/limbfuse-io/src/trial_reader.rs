//! Streaming reader of trial files (SPEC section 2).
//!
//! Columns are found by name, in any order; unknown columns are ignored. A
//! 3-axis vector (or quaternion) is present in a sample only when all its
//! cells are present: a partly empty vector is a missing sample.

use std::io::Read;
use std::path::Path;

use limbfuse_core::runner::RecordSource;
use limbfuse_core::sample::{GaitPhase, ModelInputs};
use limbfuse_core::{Joint, Record, Segment, Side};
use nalgebra::Vector3;

use crate::error::FileError;
use crate::late_rows::{LateRowFilter, LateRowLog, LateRows};
use crate::layout::{contact_ref_column, other_leg_prefix, TrialLayout, AXES, QUAT};
use crate::meta::TrialMeta;
use crate::table::TableReader;

/// Column indices of every known channel.
#[derive(Debug, Clone, Default)]
struct ColumnPlan {
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
    /// The numeric columns a record reads (all but `t` and the phase
    /// label), in the order [`TrialReader::read_into`] used to parse them
    /// one by one, so that a row's first bad cell is the same one.
    fn number_columns(&self) -> Vec<usize> {
        let mut cols = Vec::new();
        let flat = |g: Option<[usize; 3]>| g.into_iter().flatten();
        for i in 0..4 {
            cols.extend(flat(self.acc[i]));
            cols.extend(flat(self.gyr[i]));
            cols.extend(self.quat[i].into_iter().flatten());
            cols.extend(self.segment_ref[i]);
        }
        for i in 0..4 {
            cols.extend(flat(self.other_acc[i]));
            cols.extend(flat(self.other_gyr[i]));
        }
        cols.extend(self.contact_ref.iter().flatten());
        cols.extend(self.speed_ref);
        for i in 0..3 {
            cols.extend(self.encoder[i]);
            cols.extend(self.motor[i]);
            cols.extend(self.joint_ref[i]);
        }
        cols.extend(self.stim.iter().flatten());
        cols.extend(self.com_meas.iter().flatten());
        cols.extend(flat(self.com_pos));
        cols.extend(flat(self.com_vel));
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
    /// [`LateRows::Drop`]: the rule over rows out of time order.
    late: Option<Box<LateRowFilter>>,
    /// [`ColumnPlan::number_columns`], and the current row's values by column.
    number_columns: Vec<usize>,
    values: Vec<Option<f64>>,
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
        if path.is_dir() {
            return Err(FileError::Directory {
                path: path.to_path_buf(),
                hint: crate::trial_hints::directory_hint(path),
            });
        }
        Self::from_table(TableReader::open(path)?)
    }

    /// Reads a trial from any byte source; `path` names it in errors.
    pub fn from_reader(path: &Path, source: Box<dyn Read + Send>) -> Result<Self, FileError> {
        Self::from_table(TableReader::from_reader(path, source)?)
    }

    fn from_table(table: TableReader) -> Result<Self, FileError> {
        let t = table.time_column()?;
        // A channel written another way would be ignored as an unknown column.
        if let Some((column, found, name)) =
            crate::column_spelling::misspelt_channel(table.header())
        {
            return Err(FileError::Header {
                path: table.path().to_path_buf(),
                line: table.header_line(),
                message: format!(
                    "column {column} `{found}` is the channel `{name}` written another way: SPEC \
                     section 2 spells channel names in lowercase with `_` and no unit (its units \
                     are SI: m/s^2, rad/s, rad); rename it (as it is, it would be ignored like \
                     any column limbfuse does not know)"
                ),
            });
        }
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
        // An estimate file where a trial is expected (an audit: `tune` said
        // "no reference angle column").
        if let (Some(method), Some(_)) = (
            table.meta().get("method"),
            table.meta().get(crate::content_hash::TRIAL_HASH_KEY),
        ) {
            return Err(FileError::Header {
                path: table.path().to_path_buf(),
                line: table.header_line(),
                message: format!(
                    "an estimate file (`# method: {}`), not a trial: give the trial it was made \
                     from{}",
                    method.trim(),
                    table
                        .meta()
                        .get(crate::content_hash::TRIAL_KEY)
                        .map_or(String::new(), |t| format!(" (`{}`)", t.trim()))
                ),
            });
        }
        // A later version of the format (an audit: `# format:
        // limbfuse-trial/99` was read as version 1 with nothing said).
        if let Some(f) = table.meta().get("format") {
            let version = f.trim().strip_prefix("limbfuse-trial/");
            if version.is_some_and(|v| v.trim() != "1") {
                return Err(FileError::Header {
                    path: table.path().to_path_buf(),
                    line: table.header_line(),
                    message: format!(
                        "`# format: {f}`: this limbfuse reads limbfuse-trial/1 (SPEC section 2); \
                         a newer limbfuse wrote this file"
                    ),
                });
            }
        }
        let own_leg = table.meta().leg().map_err(|message| FileError::Header {
            path: table.path().to_path_buf(),
            line: table.header_line(),
            message,
        })?;
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
        let number_columns = plan.number_columns();
        let values = vec![None; table.header().len()];
        Ok(TrialReader {
            table,
            plan,
            layout,
            previous_t: None,
            rows: 0,
            late: None,
            number_columns,
            values,
        })
    }

    /// Stops reading the reference columns (`*_ref`, `com_*`, `phase_ref`,
    /// `contact_*_ref`, `speed_ref`): the records' references stay empty
    /// and those cells are neither parsed nor checked (a row must still
    /// have every cell). For a run that does not look at the truth
    /// (`estimate`: about a fifth of a simulated trial's cells); the
    /// [`TrialReader::layout`] still lists them, and `evaluate` reads them.
    pub fn skip_references(&mut self) {
        let p = &mut self.plan;
        p.segment_ref = [None; 4];
        p.joint_ref = [None; 3];
        p.com_pos = None;
        p.com_vel = None;
        p.phase_ref = None;
        p.contact_ref = [None; 2];
        p.speed_ref = None;
        self.number_columns = self.plan.number_columns();
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
        self.table.content_hash()
    }

    /// Reads the next record; `Ok(None)` at the end of the file. A file with
    /// a header and no rows is an error ([`FileError::NoRows`]).
    pub fn next_record(&mut self) -> Result<Option<Record>, FileError> {
        let mut rec = Record::default();
        Ok(self.read_into(&mut rec)?.then_some(rec))
    }

    /// What to do with a row whose time does not follow the row before it
    /// ([`LateRows`]; SPEC's refusal by default). Set before the first read.
    pub fn with_late_rows(mut self, late: LateRows) -> Self {
        self.late = match late {
            LateRows::Refuse => None,
            LateRows::Drop => Some(Box::default()),
        };
        self
    }

    /// The last line, left out because it was cut off (fewer cells than
    /// the header and no line break): known once every record was read.
    pub fn cut_last_line(&self) -> Option<crate::table::CutLine> {
        self.table.cut_last_line()
    }

    /// With [`LateRows::Drop`], the rows dropped so far.
    pub fn late_rows(&self) -> Option<&LateRowLog> {
        self.late.as_ref().map(|l| l.log())
    }

    /// [`TrialReader::next_record`] parsed straight into `rec` (every field
    /// overwritten): `Ok(false)` at the end of the file. The runner reads a
    /// whole trial into one record this way ([`RecordSource`]).
    pub fn read_into(&mut self, rec: &mut Record) -> Result<bool, FileError> {
        let Some(mut late) = self.late.take() else {
            return Ok(self.read_row(rec, true)?.is_some());
        };
        let more = self.read_in_order(rec, &mut late);
        self.late = Some(late);
        more
    }

    /// [`TrialReader::read_into`] under [`LateRows::Drop`] (module
    /// [`crate::late_rows`]).
    fn read_in_order(
        &mut self,
        rec: &mut Record,
        filter: &mut LateRowFilter,
    ) -> Result<bool, FileError> {
        if let Some(next) = filter.take_pending() {
            *rec = next;
            return Ok(true);
        }
        loop {
            let Some(line) = self.read_row(rec, false)? else {
                return Ok(match filter.finish() {
                    Some(held) => {
                        *rec = held;
                        true
                    }
                    None => false,
                });
            };
            if filter.offer(rec, line) {
                return Ok(true);
            }
        }
    }

    /// Parses the next row into `rec`; its line, or `None` at the end of
    /// the file. `ordered`: a time not after the row before is an error.
    fn read_row(&mut self, rec: &mut Record, ordered: bool) -> Result<Option<u64>, FileError> {
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
        let line = row.line();
        let plan = &self.plan;
        let t = row.time(plan.t, self.previous_t.filter(|_| ordered))?;
        row.numbers_into(&self.number_columns, &mut self.values)?;
        let v = &self.values;
        let opt = |c: Option<usize>| c.and_then(|c| v[c]);
        let axes = |g: Option<[usize; 3]>| g.map_or([None; 3], |g| g.map(|c| v[c]));
        rec.sample.t = t;
        for i in 0..4 {
            rec.sample.imu[i].set_acc_axes(axes(plan.acc[i]));
            rec.sample.imu[i].set_gyr_axes(axes(plan.gyr[i]));
            rec.sample.imu[i].quat = plan.quat[i].and_then(|g| all(v, g));
            rec.reference.segment[i] = opt(plan.segment_ref[i]);
        }
        for i in 0..4 {
            let other = &mut rec.sample.other_leg_imu[i];
            other.set_acc_axes(axes(plan.other_acc[i]));
            other.set_gyr_axes(axes(plan.other_gyr[i]));
            other.quat = None;
        }
        for side in 0..2 {
            rec.reference.contact[side] = match plan.contact_ref[side] {
                None => None,
                Some(c) => match v[c] {
                    None => None,
                    Some(0.0) => Some(false),
                    Some(1.0) => Some(true),
                    Some(_) => {
                        return Err(row.cell_error(
                            c,
                            "a foot contact 1 (on the ground), 0 (swing) or an empty cell",
                        ))
                    }
                },
            };
        }
        rec.reference.speed = opt(plan.speed_ref);
        for i in 0..3 {
            rec.sample.encoder[i] = opt(plan.encoder[i]);
            rec.sample.inputs.motor_torque[i] = opt(plan.motor[i]);
            rec.reference.joint[i] = opt(plan.joint_ref[i]);
        }
        for k in 0..4 {
            rec.sample.inputs.stim[k] = opt(plan.stim[k]);
        }
        for k in 0..6 {
            rec.sample.com.set(k, opt(plan.com_meas[k]));
        }
        rec.reference.com_pos = plan.com_pos.and_then(|g| all(v, g)).map(Vector3::from);
        rec.reference.com_vel = plan.com_vel.and_then(|g| all(v, g)).map(Vector3::from);
        rec.reference.phase = None;
        if let Some(c) = plan.phase_ref {
            let text = row.text(c);
            if !text.is_empty() {
                let label = std::str::from_utf8(text)
                    .ok()
                    .and_then(GaitPhase::from_label);
                rec.reference.phase = Some(
                    label.ok_or_else(|| row.cell_error(c, "a gait phase `SS1`, `DS` or `SS2`"))?,
                );
            }
        }
        self.previous_t = Some(t);
        self.rows += 1;
        Ok(Some(line))
    }
}

impl RecordSource for TrialReader {
    type Error = FileError;

    fn read_into(&mut self, record: &mut Record) -> Result<bool, FileError> {
        TrialReader::read_into(self, record)
    }
}

/// The values of a group of columns when every one is present.
fn all<const K: usize>(values: &[Option<f64>], cols: [usize; K]) -> Option<[f64; K]> {
    let mut out = [0.0; K];
    for (o, c) in out.iter_mut().zip(cols) {
        *o = values[c]?;
    }
    Some(out)
}

impl Iterator for TrialReader {
    type Item = Result<Record, FileError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_record().transpose()
    }
}
