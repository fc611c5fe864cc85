//! The columns a gait-event evaluation reads from a trial and its estimate
//! ([`crate::gait_events_evaluation`]), row by row, the references outside
//! the evaluation window blanked.

use std::path::Path;

use limbfuse_core::{GaitPhase, Side};
use limbfuse_io::{EstimateReader, TrialReader};

use crate::evaluation::{EvalError, TimeWindow};

/// The columns, one entry per row (events and strides as they occur).
#[derive(Default)]
pub(crate) struct Columns {
    /// Row times (s).
    pub(crate) t: Vec<f64>,
    /// Rows inside the evaluation window.
    pub(crate) n_inside: u64,
    /// `contact_*_ref` per side (left, right), unknown outside the window.
    pub(crate) reference: [Vec<Option<bool>>; 2],
    /// `speed_ref`, unknown outside the window; on a trial whose speed
    /// reference is its CoM velocity ([`crate::speed_from_com`]), the
    /// row's horizontal CoM speed `hypot(com_vx, com_vz)` (y is up).
    pub(crate) speed_ref: Vec<Option<f64>>,
    /// The speed reference is the CoM velocity.
    pub(crate) speed_from_com: bool,
    /// The estimate's contact per side.
    pub(crate) contact: [Vec<Option<bool>>; 2],
    /// The estimate's gait phase.
    pub(crate) phase: Vec<Option<GaitPhase>>,
    /// Estimated initial contact times per side (s): `gait-events`'
    /// contacts, or the contacts of `ic_any` whose side `lowback-speed`
    /// told.
    pub(crate) ic: [Vec<f64>; 2],
    /// Estimated final contact times per side (s).
    pub(crate) fc: [Vec<f64>; 2],
    /// (row, length, time) per side; no length: a turning stride
    /// (`gait-events` gives its time but withholds its length).
    pub(crate) strides: [Vec<(usize, Option<f64>, f64)>; 2],
    /// (row, `diag_stride_turn_rate_*`) per side: the stride's mean heading
    /// rate (`gait-events`).
    pub(crate) turn_rate: [Vec<(usize, f64)>; 2],
    /// (row, `diag_stride_clipped_*`) per side: the stride's accelerometer
    /// time at full scale (`gait-events`).
    pub(crate) clipped: [Vec<(usize, f64)>; 2],
    /// Initial contacts of either foot (`diag_ic`, methods that do not tell the side).
    pub(crate) ic_any: Vec<f64>,
    /// Strides of either foot (`diag_stride_length`, `diag_stride_time`).
    pub(crate) strides_any: Vec<(usize, Option<f64>, f64)>,
    /// (row, `diag_step_length`): steps of either foot (`lowback-speed`).
    pub(crate) steps_any: Vec<(usize, f64)>,
    /// (row, `diag_stride_turn_rate`) (`lowback-speed`).
    pub(crate) turn_rate_any: Vec<(usize, f64)>,
    /// (row, `diag_stride_withheld`): strides without a speed (`lowback-speed`).
    pub(crate) withheld_any: Vec<(usize, f64)>,
    /// (row, `diag_ic`): the row where each initial contact of either foot is decided.
    pub(crate) ic_any_rows: Vec<usize>,
    /// The estimate has pooled contacts (`diag_ic`) and side columns
    /// (`diag_ic_<side>`): `lowback-speed` since 2026-12-07.
    pub(crate) has_ic_sides: bool,
}

fn diag_index(er: &EstimateReader, name: &str) -> Option<usize> {
    er.diagnostic_names().position(|n| n == name)
}

/// Reads `tr` (when a trial is given: its path and reader) and `er` whole;
/// `true` with the columns when the estimate has per-foot event columns.
/// Without a trial every reference is unknown.
pub(crate) fn read_columns(
    mut trial: Option<(&Path, &mut TrialReader)>,
    estimate: &Path,
    er: &mut EstimateReader,
    window: &TimeWindow,
) -> Result<(Columns, bool), EvalError> {
    let mut c = Columns::default();
    let key = |what: &str, side: Side| format!("{what}_{}", side.name());
    let ic_col = Side::BOTH.map(|s| diag_index(er, &key("ic", s)));
    let fc_col = Side::BOTH.map(|s| diag_index(er, &key("fc", s)));
    let len_col = Side::BOTH.map(|s| diag_index(er, &key("stride_length", s)));
    let time_col = Side::BOTH.map(|s| diag_index(er, &key("stride_time", s)));
    let clipped_col = Side::BOTH.map(|s| diag_index(er, &key("stride_clipped", s)));
    let turn_col = Side::BOTH.map(|s| diag_index(er, &key("stride_turn_rate", s)));
    let (ic_any_col, len_any_col, time_any_col) = (
        diag_index(er, "ic"),
        diag_index(er, "stride_length"),
        diag_index(er, "stride_time"),
    );
    let (step_any_col, turn_any_col, withheld_any_col) = (
        diag_index(er, "step_length"),
        diag_index(er, "stride_turn_rate"),
        diag_index(er, "stride_withheld"),
    );
    // Per-foot events, unless the method writes its contacts pooled
    // (`diag_ic`): `lowback-speed`'s `diag_ic_<side>` are the sides it could
    // tell, 2 s later, scored apart ([`crate::contact_sides`]).
    let has_event_columns =
        ic_any_col.is_none() && ic_col.iter().chain(fc_col.iter()).any(Option::is_some);
    c.has_ic_sides = ic_any_col.is_some() && ic_col.iter().any(Option::is_some);
    c.speed_from_com = trial
        .as_ref()
        .is_some_and(|(_, tr)| crate::speed_from_com(tr.layout()));
    let mut row = 0usize;
    loop {
        let record = match trial.as_mut() {
            Some((_, tr)) => Some(tr.next_record()?),
            None => None,
        };
        match (record, er.next_estimate()?) {
            (Some(None), None) | (None, None) => break,
            (Some(Some(_)), None) | (Some(None), Some(_)) => {
                let cut = crate::evaluation::cut_lines(trial.as_ref().map(|(_, tr)| &**tr), er);
                return Err(crate::evaluation::length_mismatch(
                    format!(
                        "{} and {} have different numbers of samples (mismatch after {row})",
                        trial.map_or_else(String::new, |(p, _)| p.display().to_string()),
                        estimate.display()
                    ),
                    cut,
                ));
            }
            (record, Some((line, e))) => {
                let r = record.flatten();
                if let Some(r) = &r {
                    EvalError::check_same_time(estimate, line, row as u64, e.t, r.sample.t)?;
                }
                // Outside the window the reference counts as unknown: no
                // event, stride or row there is scored.
                let t_row = r.as_ref().map_or(e.t, |r| r.sample.t);
                let inside = window.contains(t_row);
                c.n_inside += u64::from(inside);
                c.t.push(t_row);
                let speed = r.as_ref().and_then(|r| match c.speed_from_com {
                    true => r.reference.com_vel.map(|v| v.x.hypot(v.z)),
                    false => r.reference.speed,
                });
                c.speed_ref.push(speed.filter(|_| inside));
                c.phase.push(e.phase);
                if let Some(v) = ic_any_col.and_then(|k| e.diag[k]) {
                    c.ic_any.push(v);
                    c.ic_any_rows.push(row);
                }
                let at_row = |col: Option<usize>, out: &mut Vec<(usize, f64)>| {
                    if let Some(v) = col.and_then(|k| e.diag[k]) {
                        out.push((row, v));
                    }
                };
                at_row(step_any_col, &mut c.steps_any);
                at_row(turn_any_col, &mut c.turn_rate_any);
                at_row(withheld_any_col, &mut c.withheld_any);
                if let (Some(l), Some(tm)) = (
                    len_any_col.and_then(|k| e.diag[k]),
                    time_any_col.and_then(|k| e.diag[k]),
                ) {
                    c.strides_any.push((row, Some(l), tm));
                }
                for s in 0..2 {
                    let reference = r.as_ref().and_then(|r| r.reference.contact[s]);
                    c.reference[s].push(reference.filter(|_| inside));
                    c.contact[s].push(e.contact[s]);
                    if let Some(v) = ic_col[s].and_then(|k| e.diag[k]) {
                        c.ic[s].push(v);
                    }
                    if let Some(v) = fc_col[s].and_then(|k| e.diag[k]) {
                        c.fc[s].push(v);
                    }
                    // (a stride's time without its length: it turns)
                    if let Some(tm) = time_col[s].and_then(|k| e.diag[k]) {
                        c.strides[s].push((row, len_col[s].and_then(|k| e.diag[k]), tm));
                    }
                    if let Some(v) = turn_col[s].and_then(|k| e.diag[k]) {
                        c.turn_rate[s].push((row, v));
                    }
                    if let Some(v) = clipped_col[s].and_then(|k| e.diag[k]) {
                        c.clipped[s].push((row, v));
                    }
                }
            }
        }
        row += 1;
    }
    Ok((c, has_event_columns))
}
