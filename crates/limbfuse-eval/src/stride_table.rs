//! One row per stride of a `gait-events` or `lowback-speed` estimate (the
//! per-stride table of gaitmap and mobgap; docs/GAIT_EVENTS.md "Stride
//! table"): the strides the methods write as sparse `diag_*` cells, put
//! back together, and when a trial is given the reference `evaluate` pairs
//! with each one.
//!
//! The rows are built by the code that scores them
//! ([`crate::gait_events_evaluation`]), so the table holds exactly the
//! strides and numbers `evaluate` scores: the per-stride speed error of
//! `evaluate --json` (`speed_mae_mps`) is the mean of
//! `|speed_m_s - speed_ref_m_s|` over the rows that have both. The table
//! adds, for `lowback-speed`, the strides whose speed the method withholds
//! (turns; no speed, so not scored).

use std::io::Write;
use std::path::Path;

use crate::blended_stride_speed::{row_at, ROW_TOLERANCE_S};
use crate::evaluation::{EvalError, TimeWindow};
use crate::gait_event_columns::Columns;
use crate::gait_events_evaluation::GaitEventEvaluation;

/// Which foot a stride belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StrideFoot {
    /// Left foot.
    Left,
    /// Right foot.
    Right,
    /// A foot not told (`lowback-speed`, whose stride is two steps, initial
    /// contact to the second next, when it could not tell its first
    /// contact's side: docs/GAIT_EVENTS.md, `lowback-speed` item 7).
    Unknown,
}

impl StrideFoot {
    /// `left`, `right` or `unknown` (the table's `foot` column).
    pub fn name(self) -> &'static str {
        match self {
            StrideFoot::Left => "left",
            StrideFoot::Right => "right",
            StrideFoot::Unknown => "unknown",
        }
    }

    /// The foot of side index `s` ([`limbfuse_core::Side::index`]).
    pub(crate) fn of_side(s: usize) -> Self {
        if s == 0 {
            StrideFoot::Left
        } else {
            StrideFoot::Right
        }
    }

    /// The side index of a known foot (the inverse of [`StrideFoot::of_side`]).
    fn side_index(self) -> Option<usize> {
        match self {
            StrideFoot::Left => Some(0),
            StrideFoot::Right => Some(1),
            StrideFoot::Unknown => None,
        }
    }
}

/// Why a stride has no speed: `lowback-speed`'s `diag_stride_withheld`, or
/// a `gait-events` stride with a time and no length (it turns).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpeedWithheld {
    /// The stride turns (mean heading rate above `turn_rate`): `turn`.
    Turn,
    /// The stride before it turned (`withhold_after_turn`): `after_turn`.
    AfterTurn,
}

impl SpeedWithheld {
    /// `turn` or `after_turn`.
    pub fn name(self) -> &'static str {
        match self {
            SpeedWithheld::Turn => "turn",
            SpeedWithheld::AfterTurn => "after_turn",
        }
    }

    fn from_code(code: f64) -> Option<Self> {
        match code as i64 {
            1 => Some(SpeedWithheld::Turn),
            2 => Some(SpeedWithheld::AfterTurn),
            _ => None,
        }
    }
}

/// One stride. Times in s, lengths in m, speeds in m/s; `None`: not known.
#[derive(Debug, Clone, PartialEq)]
pub struct StrideRow {
    /// Foot.
    pub foot: StrideFoot,
    /// Start: the back-dated initial contact (s).
    pub ic_s: f64,
    /// The foot's final contact inside the stride (s), `gait-events` only.
    pub fc_s: Option<f64>,
    /// End: the next initial contact of the same foot (s).
    pub end_s: f64,
    /// The row time at which the method decided the stride (s).
    pub decided_s: f64,
    /// Stride time (s).
    pub stride_time_s: Option<f64>,
    /// Stance time: `fc_s - ic_s` (s), `gait-events` only.
    pub stance_time_s: Option<f64>,
    /// Swing time: `end_s - fc_s` (s), `gait-events` only.
    pub swing_time_s: Option<f64>,
    /// Stride length (m).
    pub stride_length_m: Option<f64>,
    /// Speed: stride length / stride time (m/s).
    pub speed_m_s: Option<f64>,
    /// `gait-events`: the time its accelerometer was at full scale while
    /// the foot moved (s; longer than 0.04 s: a clipped swing, the stride
    /// short, docs/GAIT_EVENTS.md "Clipped swings").
    pub acc_clipped_s: Option<f64>,
    /// `lowback-speed`: the stride's first step length (m).
    pub step_length_1_m: Option<f64>,
    /// `lowback-speed`: its second step length (m).
    pub step_length_2_m: Option<f64>,
    /// Mean heading rate over the stride (rad/s, signed): the trunk's
    /// (`lowback-speed`) or the foot's (`gait-events`).
    pub turn_rate_rad_s: Option<f64>,
    /// Why the stride has no speed (a turn; `lowback-speed`: or the stride
    /// after one).
    pub speed_withheld: Option<SpeedWithheld>,
    /// The reference initial contact paired with `ic_s` (s).
    pub ic_ref_s: Option<f64>,
    /// The reference final contact paired with `fc_s` (s): the pairing
    /// that scores `evaluate`'s final-contact timing.
    pub fc_ref_s: Option<f64>,
    /// Reference stride time: between the reference contacts paired with
    /// `ic_s` and `end_s` (s).
    pub stride_time_ref_s: Option<f64>,
    /// Reference stance time: `fc_ref_s - ic_ref_s` (s).
    pub stance_time_ref_s: Option<f64>,
    /// Reference swing time: the reference initial contact paired with
    /// `end_s` minus `fc_ref_s` (s).
    pub swing_time_ref_s: Option<f64>,
    /// Mean `speed_ref` over the stride's rows, all known (m/s).
    pub speed_ref_m_s: Option<f64>,
    /// `speed_ref_m_s` x `stride_time_ref_s` (m).
    pub stride_length_ref_m: Option<f64>,
    /// The row of `decided_s` (where the stride's diagnostics are).
    decided_row: usize,
}

/// The table's CSV columns, in order.
pub const STRIDE_COLUMNS: [&str; 22] = [
    "foot",
    "ic_s",
    "fc_s",
    "end_s",
    "decided_s",
    "stride_time_s",
    "stance_time_s",
    "swing_time_s",
    "stride_length_m",
    "speed_m_s",
    "acc_clipped_s",
    "step_length_1_m",
    "step_length_2_m",
    "turn_rate_rad_s",
    "speed_withheld",
    "ic_ref_s",
    "fc_ref_s",
    "stride_time_ref_s",
    "stance_time_ref_s",
    "swing_time_ref_s",
    "speed_ref_m_s",
    "stride_length_ref_m",
];

impl StrideRow {
    /// The numeric cells, in [`STRIDE_COLUMNS`] order without `foot` and
    /// `speed_withheld`.
    pub fn numbers(&self) -> [(&'static str, Option<f64>); 20] {
        [
            ("ic_s", Some(self.ic_s)),
            ("fc_s", self.fc_s),
            ("end_s", Some(self.end_s)),
            ("decided_s", Some(self.decided_s)),
            ("stride_time_s", self.stride_time_s),
            ("stance_time_s", self.stance_time_s),
            ("swing_time_s", self.swing_time_s),
            ("stride_length_m", self.stride_length_m),
            ("speed_m_s", self.speed_m_s),
            ("acc_clipped_s", self.acc_clipped_s),
            ("step_length_1_m", self.step_length_1_m),
            ("step_length_2_m", self.step_length_2_m),
            ("turn_rate_rad_s", self.turn_rate_rad_s),
            ("ic_ref_s", self.ic_ref_s),
            ("fc_ref_s", self.fc_ref_s),
            ("stride_time_ref_s", self.stride_time_ref_s),
            ("stance_time_ref_s", self.stance_time_ref_s),
            ("swing_time_ref_s", self.swing_time_ref_s),
            ("speed_ref_m_s", self.speed_ref_m_s),
            ("stride_length_ref_m", self.stride_length_ref_m),
        ]
    }
}

/// The strides of one estimate, by start time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StrideTable {
    /// Method name.
    pub method: String,
    /// One row per stride, sorted by `ic_s` (then foot).
    pub rows: Vec<StrideRow>,
}

impl StrideTable {
    /// Writes the table as CSV: a header line of [`STRIDE_COLUMNS`], then
    /// one line per stride; unknown cells empty.
    pub fn write_csv(&self, mut w: impl Write) -> std::io::Result<()> {
        writeln!(w, "{}", STRIDE_COLUMNS.join(","))?;
        // (the numbers before `speed_withheld`: its column less `foot`)
        let before_withheld = STRIDE_COLUMNS
            .iter()
            .position(|&c| c == "speed_withheld")
            .map_or(0, |k| k - 1);
        for r in &self.rows {
            let cell = |v: Option<f64>| v.map_or_else(String::new, |x| x.to_string());
            let n = r.numbers();
            let mut line = vec![r.foot.name().to_string()];
            line.extend(n[..before_withheld].iter().map(|&(_, v)| cell(v)));
            line.push(r.speed_withheld.map_or("", SpeedWithheld::name).to_string());
            line.extend(n[before_withheld..].iter().map(|&(_, v)| cell(v)));
            writeln!(w, "{}", line.join(","))?;
        }
        Ok(())
    }
}

/// Why `estimate` can give no stride table (no `diag_stride_length*` or
/// `diag_stride_withheld` column: another method, or `--diagnostics
/// none`), or `None` when it can.
fn why_no_strides(estimate: &Path) -> Result<Option<String>, EvalError> {
    let er = limbfuse_io::EstimateReader::open(estimate)?;
    let stride_columns = er
        .diagnostic_names()
        .any(|n| n.starts_with("stride_length") || n == "stride_withheld");
    Ok((!stride_columns).then(|| {
        format!(
            "{}: the estimate (method `{}`) has no stride columns (`diag_stride_length*`): \
             strides come from `gait-events` and `lowback-speed` estimates written with their \
             default diagnostics",
            estimate.display(),
            er.method()
        )
    }))
}

/// The table of the `rows` [`crate::gait_events_evaluation`] scored.
fn table_of(method: String, mut rows: Vec<StrideRow>) -> StrideTable {
    rows.sort_by(|a, b| a.ic_s.total_cmp(&b.ic_s));
    StrideTable { method, rows }
}

/// The stride table of `estimate` (`gait-events`, `lowback-speed`), with
/// the references of `trial` when given (over `window`, as `evaluate
/// --window` scores them). An estimate without stride columns (another
/// method, or `--diagnostics none`) is [`EvalError::NoStrides`].
pub fn stride_table_of_files(
    trial: Option<&Path>,
    estimate: &Path,
    allow_trial_mismatch: bool,
    window: &TimeWindow,
) -> Result<StrideTable, EvalError> {
    // (refused before any scoring, as before the evaluation was shared)
    if let Some(why) = why_no_strides(estimate)? {
        return Err(EvalError::NoStrides(why));
    }
    scored_table(None, trial, estimate, allow_trial_mismatch, window)?
        .1
        .map_err(EvalError::NoStrides)
}

/// The evaluation of [`crate::gait_events_evaluation::evaluate_gait_event_files_in`]
/// and the stride table of [`stride_table_of_files`] from one pass over the
/// files (`evaluate --strides` and the report need both; scoring twice cost
/// a report about a second per ten minutes of walking and estimate). The
/// table is the message of [`EvalError::NoStrides`] when the estimate has no
/// stride columns; any other error is returned.
pub fn evaluation_and_stride_table(
    trial: Option<&Path>,
    estimate: &Path,
    allow_trial_mismatch: bool,
    window: &TimeWindow,
) -> Result<(GaitEventEvaluation, Result<StrideTable, String>), EvalError> {
    let why = why_no_strides(estimate)?;
    scored_table(why, trial, estimate, allow_trial_mismatch, window)
}

/// The evaluation and, unless `why` says the estimate has no strides, its
/// stride table.
fn scored_table(
    why: Option<String>,
    trial: Option<&Path>,
    estimate: &Path,
    allow_trial_mismatch: bool,
    window: &TimeWindow,
) -> Result<(GaitEventEvaluation, Result<StrideTable, String>), EvalError> {
    let (ev, rows) = crate::gait_events_evaluation::evaluate_with_strides(
        trial,
        estimate,
        allow_trial_mismatch,
        window,
    )?;
    let table = match why {
        Some(why) => Err(why),
        None => Ok(table_of(ev.method.clone(), rows)),
    };
    Ok((ev, table))
}

/// The initial contacts of one track and the reference paired with them.
pub(crate) struct TrackEvents<'a> {
    /// Estimated initial contacts (s).
    pub(crate) estimated: &'a [f64],
    /// Reference initial contacts (s).
    pub(crate) reference: &'a [f64],
    /// (reference index, estimated index) pairs.
    pub(crate) pairs: &'a [(usize, usize)],
}

impl TrackEvents<'_> {
    fn reference_of(&self, j: usize) -> Option<f64> {
        self.pairs
            .iter()
            .find(|p| p.1 == j)
            .map(|p| self.reference[p.0])
    }
}

/// The strides `(row, length, time)` of one track, each ending at the
/// track's last initial contact at or before its row (a stride whose end is
/// not found is left out, as `evaluate` leaves it out); `fc`: the foot's
/// final contacts and the reference paired with them (the pairing of
/// `evaluate`'s final-contact timing), `None` when the method has none.
pub(crate) fn track_strides(
    foot: StrideFoot,
    strides: &[(usize, Option<f64>, f64)],
    ev: &TrackEvents<'_>,
    fc: Option<&TrackEvents<'_>>,
    c: &Columns,
) -> Vec<StrideRow> {
    let mut rows = Vec::new();
    for &(row, length, time) in strides {
        let t_row = c.t[row];
        let Some(end_j) = ev
            .estimated
            .iter()
            .rposition(|&x| x <= t_row + ROW_TOLERANCE_S)
        else {
            continue;
        };
        let end = ev.estimated[end_j];
        let mut r = placed(foot, end - time, end, row, ev, end_j, c);
        if let Some(fc) = fc {
            with_stance_and_swing(&mut r, fc, ev.reference_of(end_j));
        }
        r.stride_time_s = Some(time);
        r.stride_length_m = length;
        r.speed_m_s = length.map(|l| l / time);
        // (each pushed in row order)
        let at_row = |rows: &[(usize, f64)]| {
            rows.binary_search_by_key(&row, |&(k, _)| k)
                .ok()
                .map(|i| rows[i].1)
        };
        r.acc_clipped_s = foot.side_index().and_then(|s| at_row(&c.clipped[s]));
        if let Some(s) = foot.side_index() {
            r.turn_rate_rad_s = at_row(&c.turn_rate[s]);
            // `gait-events` gives a turning stride its time, not its length.
            if length.is_none() {
                r.speed_withheld = Some(SpeedWithheld::Turn);
            }
        }
        rows.push(r);
    }
    rows
}

/// Sets the stride's final contact (the first of `fc` strictly between its
/// two initial contacts), its stance and swing times, and their references
/// from the reference final contact paired with it, the reference initial
/// contact paired with the stride's start (`r.ic_ref_s`) and `end_ref` (the
/// one paired with its end).
fn with_stance_and_swing(r: &mut StrideRow, fc: &TrackEvents<'_>, end_ref: Option<f64>) {
    let Some(j) = fc.estimated.iter().position(|&x| x > r.ic_s && x < r.end_s) else {
        return;
    };
    let at = fc.estimated[j];
    r.fc_s = Some(at);
    r.stance_time_s = Some(at - r.ic_s);
    r.swing_time_s = Some(r.end_s - at);
    r.fc_ref_s = fc.reference_of(j);
    r.stance_time_ref_s = r.fc_ref_s.zip(r.ic_ref_s).map(|(f, i)| f - i);
    r.swing_time_ref_s = end_ref.zip(r.fc_ref_s).map(|(e, f)| e - f);
}

/// Whether a stride of `foot` has its own reference: on a trial with a
/// contact reference for the foot, it must be paired with a reference
/// stride (`paired`: both its initial contacts paired with reference ones,
/// as its reference length needs). `speed_ref` holds in each row the mean
/// of the reference strides (left and right) that contain it, so over a
/// stride the reference does not list (before the foot's first listed
/// contact, after its last, one the reference lost in a turn) the rows'
/// speed is the other foot's alone, not this stride's: such a stride is not
/// scored per stride, as it has no reference length either (issue 19,
/// 2026-12-06; docs/GAIT_EVENTS.md "Evaluation"). On a trial without a
/// contact reference for the foot, and for a stride of unknown foot, every
/// stride with a speed reference is scored.
fn has_own_reference(foot: StrideFoot, paired: bool, c: &Columns) -> bool {
    let Some(side) = foot.side_index() else {
        return true;
    };
    paired || !c.reference[side].iter().any(Option::is_some)
}

/// A stride from `start` to the estimated contact `end_j` of `ev`, decided
/// on `row`, with its reference (no length, time or speed yet).
fn placed(
    foot: StrideFoot,
    start: f64,
    end: f64,
    row: usize,
    ev: &TrackEvents<'_>,
    end_j: usize,
    c: &Columns,
) -> StrideRow {
    // Reference stride time from the reference contacts paired with both ends.
    let start_j = ev.estimated.iter().position(|&x| (x - start).abs() < 1e-6);
    let ic_ref_s = start_j.and_then(|j| ev.reference_of(j));
    let stride_time_ref_s = match (ev.reference_of(end_j), ic_ref_s) {
        (Some(r1), Some(r0)) => Some(r1 - r0),
        _ => None,
    };
    let (k0, k1) = (row_at(&c.t, start), row_at(&c.t, end));
    let speed_ref_m_s = (k1 > k0 && has_own_reference(foot, stride_time_ref_s.is_some(), c))
        .then(|| {
            c.speed_ref[k0..k1]
                .iter()
                .copied()
                .collect::<Option<Vec<f64>>>()
        })
        .flatten()
        .map(|refs| refs.iter().sum::<f64>() / refs.len() as f64);
    StrideRow {
        foot,
        ic_s: start,
        fc_s: None,
        end_s: end,
        decided_s: c.t[row],
        stride_time_s: None,
        stance_time_s: None,
        swing_time_s: None,
        stride_length_m: None,
        speed_m_s: None,
        acc_clipped_s: None,
        step_length_1_m: None,
        step_length_2_m: None,
        turn_rate_rad_s: None,
        speed_withheld: None,
        ic_ref_s,
        fc_ref_s: None,
        stride_time_ref_s,
        stance_time_ref_s: None,
        swing_time_ref_s: None,
        speed_ref_m_s,
        stride_length_ref_m: speed_ref_m_s.zip(stride_time_ref_s).map(|(v, t)| v * t),
        decided_row: row,
    }
}

/// `lowback-speed`'s strides (scored ones from [`track_strides`]) with the
/// withheld ones added, each with its step lengths and turn rate.
pub(crate) fn unknown_foot_strides(
    mut scored: Vec<StrideRow>,
    ev: &TrackEvents<'_>,
    c: &Columns,
) -> Vec<StrideRow> {
    for &(row, code) in &c.withheld_any {
        // The stride ends at the contact decided on this row and starts two
        // contacts before: a contact that replaces a too-close one restarts
        // the step chain, so a stride's three contacts are consecutive.
        let Some(end_j) = c.ic_any_rows.iter().position(|&r| r == row) else {
            continue;
        };
        if end_j < 2 || end_j >= ev.estimated.len() {
            continue;
        }
        let (start, end) = (ev.estimated[end_j - 2], ev.estimated[end_j]);
        let mut r = placed(StrideFoot::Unknown, start, end, row, ev, end_j, c);
        r.speed_withheld = SpeedWithheld::from_code(code);
        scored.push(r);
    }
    let at =
        |v: &[(usize, f64)], row: usize| v.iter().position(|&(r, _)| r == row).map(|k| (k, v[k].1));
    for r in &mut scored {
        // The stride's foot: its first contact's side, when the method told it.
        let told = |s: usize| c.ic[s].iter().any(|&x| (x - r.ic_s).abs() <= 1e-9);
        if told(1) {
            r.foot = StrideFoot::of_side(1);
        } else if told(0) {
            r.foot = StrideFoot::of_side(0);
        }
        r.turn_rate_rad_s = at(&c.turn_rate_any, r.decided_row).map(|x| x.1);
        if let Some((k, second)) = at(&c.steps_any, r.decided_row) {
            r.step_length_2_m = Some(second);
            r.step_length_1_m = k.checked_sub(1).map(|k| c.steps_any[k].1);
        }
    }
    scored
}

#[cfg(test)]
#[path = "stride_table_tests.rs"]
mod tests;
