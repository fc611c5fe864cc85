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
    /// Estimated initial contact times per side (s).
    pub(crate) ic: [Vec<f64>; 2],
    /// Estimated final contact times per side (s).
    pub(crate) fc: [Vec<f64>; 2],
    /// (row, length, time) per side.
    pub(crate) strides: [Vec<(usize, f64, f64)>; 2],
    /// Initial contacts of either foot (`diag_ic`, methods that do not tell the side).
    pub(crate) ic_any: Vec<f64>,
    /// Strides of either foot (`diag_stride_length`, `diag_stride_time`).
    pub(crate) strides_any: Vec<(usize, f64, f64)>,
}

fn diag_index(er: &EstimateReader, name: &str) -> Option<usize> {
    er.diagnostic_names().position(|n| n == name)
}

/// Reads `tr` and `er` whole; `true` with the columns when the estimate
/// has per-foot event columns.
pub(crate) fn read_columns(
    trial: &Path,
    estimate: &Path,
    tr: &mut TrialReader,
    er: &mut EstimateReader,
    window: &TimeWindow,
) -> Result<(Columns, bool), EvalError> {
    let mut c = Columns::default();
    let key = |what: &str, side: Side| format!("{what}_{}", side.name());
    let ic_col = Side::BOTH.map(|s| diag_index(er, &key("ic", s)));
    let fc_col = Side::BOTH.map(|s| diag_index(er, &key("fc", s)));
    let len_col = Side::BOTH.map(|s| diag_index(er, &key("stride_length", s)));
    let time_col = Side::BOTH.map(|s| diag_index(er, &key("stride_time", s)));
    let (ic_any_col, len_any_col, time_any_col) = (
        diag_index(er, "ic"),
        diag_index(er, "stride_length"),
        diag_index(er, "stride_time"),
    );
    let has_event_columns = ic_col.iter().chain(fc_col.iter()).any(Option::is_some);
    c.speed_from_com = crate::speed_from_com(tr.layout());
    let mut row = 0usize;
    loop {
        match (tr.next_record()?, er.next_estimate()?) {
            (None, None) => break,
            (Some(r), Some((line, e))) => {
                EvalError::check_same_time(estimate, line, row as u64, e.t, r.sample.t)?;
                // Outside the window the reference counts as unknown: no
                // event, stride or row there is scored.
                let inside = window.contains(r.sample.t);
                c.n_inside += u64::from(inside);
                c.t.push(r.sample.t);
                let speed = match c.speed_from_com {
                    true => r.reference.com_vel.map(|v| v.x.hypot(v.z)),
                    false => r.reference.speed,
                };
                c.speed_ref.push(speed.filter(|_| inside));
                c.phase.push(e.phase);
                if let Some(v) = ic_any_col.and_then(|k| e.diag[k]) {
                    c.ic_any.push(v);
                }
                if let (Some(l), Some(tm)) = (
                    len_any_col.and_then(|k| e.diag[k]),
                    time_any_col.and_then(|k| e.diag[k]),
                ) {
                    c.strides_any.push((row, l, tm));
                }
                for s in 0..2 {
                    c.reference[s].push(r.reference.contact[s].filter(|_| inside));
                    c.contact[s].push(e.contact[s]);
                    if let Some(v) = ic_col[s].and_then(|k| e.diag[k]) {
                        c.ic[s].push(v);
                    }
                    if let Some(v) = fc_col[s].and_then(|k| e.diag[k]) {
                        c.fc[s].push(v);
                    }
                    if let (Some(l), Some(tm)) = (
                        len_col[s].and_then(|k| e.diag[k]),
                        time_col[s].and_then(|k| e.diag[k]),
                    ) {
                        c.strides[s].push((row, l, tm));
                    }
                }
            }
            _ => {
                return Err(EvalError::LengthMismatch(format!(
                    "{} and {} have different numbers of samples (mismatch after {row})",
                    trial.display(),
                    estimate.display()
                )))
            }
        }
        row += 1;
    }
    Ok((c, has_event_columns))
}
