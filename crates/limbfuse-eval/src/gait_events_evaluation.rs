//! Evaluation of foot contacts, gait events, phase and walking speed
//! against `contact_left_ref` / `contact_right_ref` / `speed_ref` (SPEC
//! section 2's gait references; docs/GAIT_EVENTS.md "Evaluation").
//!
//! - **Events.** Reference initial contacts are the 0 -> 1 steps of a
//!   contact reference, final contacts the 1 -> 0 steps (both cells known).
//!   Estimated events are the back-dated times of the estimate's
//!   `diag_ic_<side>` / `diag_fc_<side>` columns when it has them (methods
//!   that decide events with latency), else the steps of its
//!   `contact_<side>` column. Each reference event is paired with the
//!   nearest unpaired estimated event of the same kind and side within
//!   [`MATCH_TOLERANCE_S`]; unpaired reference events are missed, unpaired
//!   estimated events at a time where the reference is known are extra. A
//!   foot the trial has no IMU for and the estimate says nothing about is
//!   not scored ([`crate::scored_feet`]).
//! - **Contact / phase accuracy**: % of rows where both are known and equal.
//!   The reference phase: DS when both feet are down; a single support is
//!   SS2 in its first half (after the other foot's lift-off) and SS1 in its
//!   second (paper 003's phases).
//! - **Speed, per stride**: each estimated stride (`diag_stride_length_<side>`,
//!   `diag_stride_time_<side>`, ending at that side's last initial contact)
//!   against the mean `speed_ref` over its rows (all known); the stride
//!   length against `speed_ref` x the reference stride time (the reference
//!   contacts paired with the stride's two initial contacts). The same with
//!   the estimate blended as `speed_ref` is: [`crate::blended_stride_speed`].
//! - **Stance and swing time, per stride** (methods with final contacts):
//!   [`crate::stance_swing`], from the contacts paired above.

use std::path::Path;

use limbfuse_core::GaitPhase;
use limbfuse_io::{EstimateReader, TrialReader};

use crate::blended_stride_speed::{
    blended_stride_speed, row_at, StrideFigures, TrackStride, ROW_TOLERANCE_S,
};
use crate::evaluation::{EvalError, TimeWindow};
use crate::gait_event_columns::{read_columns, Columns};
use crate::stance_swing::StanceSwingFigures;
use crate::stride_table::{
    track_strides, unknown_foot_strides, StrideFoot, StrideRow, TrackEvents,
};

/// Largest time difference (s) at which an estimated event can pair with a
/// reference event: a quarter of a typical 1.0-1.2 s stride, under half the
/// shortest interval between two events of one kind and foot.
pub const MATCH_TOLERANCE_S: f64 = 0.25;

/// Timing of one kind of event (both sides pooled).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EventTiming {
    /// Reference events.
    pub n_reference: usize,
    /// Paired events.
    pub n_matched: usize,
    /// Reference events without an estimated one.
    pub missed: usize,
    /// Estimated events without a reference one, where the reference is known.
    pub extra: usize,
    /// Median |error| (ms).
    pub median_abs_ms: Option<f64>,
    /// 95th percentile |error| (ms).
    pub p95_abs_ms: Option<f64>,
    /// Mean signed error, estimate - reference (ms).
    pub mean_ms: Option<f64>,
}

/// Everything [`evaluate_gait_event_files`] measures.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GaitEventEvaluation {
    /// Method name.
    pub method: String,
    /// Samples compared.
    pub n_samples: u64,
    /// Initial contacts.
    pub initial_contact: EventTiming,
    /// Final contacts (toe off); `None` when the method does not estimate them.
    pub final_contact: Option<EventTiming>,
    /// Whether events were compared per foot (`false`: pooled over both feet,
    /// for methods that do not tell which foot, or tell it apart and later:
    /// `lowback-speed`).
    pub per_foot: bool,
    /// The sides of pooled contacts (`lowback-speed`'s `diag_ic_<side>`),
    /// against the foot of the reference contact each is paired with;
    /// `None` when the estimate has pooled contacts without side columns,
    /// or per-foot events.
    pub contact_sides: Option<crate::contact_sides::ContactSides>,
    /// % of rows (both sides pooled) where the contact equals the reference.
    pub contact_accuracy_pct: Option<f64>,
    /// % of rows where the phase equals the phase of the contact references.
    pub phase_accuracy_pct: Option<f64>,
    /// Stride speed and length, each estimated stride against the mean
    /// `speed_ref` over its rows.
    pub per_stride: StrideFigures,
    /// Strides with a speed reference whose speed and length the method
    /// withheld (turning strides: `gait-events` and `lowback-speed`'s
    /// `turn_rate`; `lowback-speed`'s stride after a turn): not in
    /// `per_stride` or `blended`.
    pub n_withheld: u64,
    /// Stance and swing time per stride (methods with final contacts).
    pub stance_swing: StanceSwingFigures,
    /// Stride speed and length with the estimate blended as the reference is
    /// ([`crate::blended_stride_speed`]).
    pub blended: StrideFigures,
    /// Whether the estimate file records this trial.
    pub trial_check: crate::trial_check::TrialCheck,
    /// The speed reference is the trial's CoM velocity, row by row (no
    /// `speed_ref` column; [`crate::speed_from_com`]); the blended
    /// comparison, made for a per-stride `speed_ref`, is then not made.
    pub speed_from_com: bool,
    /// What the figures cannot say (an estimate of `gait-events` without
    /// its event diagnostics).
    pub warnings: Vec<String>,
    /// Which of `contact_left_ref`, `contact_right_ref` the trial has (by
    /// [`limbfuse_core::Side::index`]): with neither, no event can be scored
    /// and the text says that the columns are absent.
    pub contact_ref_columns: [bool; 2],
}

/// Times of the `from -> to` steps of a contact column.
pub(crate) fn steps(t: &[f64], v: &[Option<bool>], to: bool) -> Vec<f64> {
    (1..v.len())
        .filter(|&k| v[k - 1] == Some(!to) && v[k] == Some(to))
        .map(|k| t[k])
        .collect()
}

/// Times where a contact column goes from unknown to `to` or from `!to` to unknown.
fn edge_steps(t: &[f64], v: &[Option<bool>], to: bool) -> Vec<f64> {
    (1..v.len())
        .filter(|&k| {
            (v[k - 1].is_none() && v[k] == Some(to)) || (v[k - 1] == Some(!to) && v[k].is_none())
        })
        .map(|k| t[k])
        .collect()
}

/// Row nearest to time `x` (t sorted).
fn nearest_row(t: &[f64], x: f64) -> usize {
    let k = row_at(t, x);
    if k == 0 {
        0
    } else if k >= t.len() {
        t.len() - 1
    } else if x - t[k - 1] <= t[k] - x {
        k - 1
    } else {
        k
    }
}

fn percentile(sorted: &[f64], p: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let pos = p / 100.0 * (sorted.len() - 1) as f64;
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    Some(sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64))
}

/// Pairs reference and estimated events; returns (ref index, est index) pairs.
fn pair(reference: &[f64], estimated: &[f64]) -> Vec<(usize, usize)> {
    let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
    for (i, &r) in reference.iter().enumerate() {
        for (j, &e) in estimated.iter().enumerate() {
            let d = (e - r).abs();
            if d <= MATCH_TOLERANCE_S + ROW_TOLERANCE_S {
                candidates.push((d, i, j));
            }
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut used_r, mut used_e) = (vec![false; reference.len()], vec![false; estimated.len()]);
    let mut out = Vec::new();
    for (_, i, j) in candidates {
        if !used_r[i] && !used_e[j] {
            used_r[i] = true;
            used_e[j] = true;
            out.push((i, j));
        }
    }
    out
}

struct SideEvents {
    /// Reference events that cannot be scored: a contact that starts or
    /// ends at the edge of the known reference (empty -> 1 or 1 -> empty).
    /// An estimated event near one is neither paired nor extra.
    unscored: Vec<f64>,
    reference: Vec<f64>,
    estimated: Vec<f64>,
    pairs: Vec<(usize, usize)>,
}

impl SideEvents {
    fn track(&self) -> TrackEvents<'_> {
        TrackEvents {
            estimated: &self.estimated,
            reference: &self.reference,
            pairs: &self.pairs,
        }
    }
}

/// Timing over tracks; `side_of[i]`: the reference side of track `i`
/// (`None`: either side).
fn timing(sides: &[SideEvents], c: &Columns, side_of: &[Option<usize>]) -> EventTiming {
    let mut errors = Vec::new();
    let mut out = EventTiming::default();
    let known = |s: Option<usize>, row: usize| match s {
        Some(s) => c.reference[s][row].is_some(),
        None => c.reference[0][row].is_some() || c.reference[1][row].is_some(),
    };
    for (se, &s) in sides.iter().zip(side_of) {
        out.n_reference += se.reference.len();
        out.n_matched += se.pairs.len();
        out.missed += se.reference.len() - se.pairs.len();
        let paired: Vec<usize> = se.pairs.iter().map(|p| p.1).collect();
        out.extra += se
            .estimated
            .iter()
            .enumerate()
            .filter(|(j, &x)| {
                !paired.contains(j)
                    && known(s, nearest_row(&c.t, x))
                    && !se
                        .unscored
                        .iter()
                        .any(|u| (u - x).abs() <= MATCH_TOLERANCE_S + ROW_TOLERANCE_S)
            })
            .count();
        errors.extend(
            se.pairs
                .iter()
                .map(|&(i, j)| (se.estimated[j] - se.reference[i]) * 1e3),
        );
    }
    if !errors.is_empty() {
        out.mean_ms = Some(errors.iter().sum::<f64>() / errors.len() as f64);
        let mut abs: Vec<f64> = errors.iter().map(|e| e.abs()).collect();
        abs.sort_by(f64::total_cmp);
        out.median_abs_ms = percentile(&abs, 50.0);
        out.p95_abs_ms = percentile(&abs, 95.0);
    }
    out
}

/// Reference phase per row from the two contact references.
fn reference_phase(c: &Columns) -> Vec<Option<GaitPhase>> {
    let n = c.t.len();
    let state: Vec<Option<(bool, bool)>> = (0..n)
        .map(|k| c.reference[0][k].zip(c.reference[1][k]))
        .collect();
    let mut out = vec![None; n];
    let mut k = 0;
    while k < n {
        match state[k] {
            Some((true, true)) => {
                out[k] = Some(GaitPhase::Ds);
                k += 1;
            }
            Some((l, r)) if l != r => {
                let start = k;
                while k < n && state[k] == Some((l, r)) {
                    k += 1;
                }
                // A single support is split at its midpoint only when it
                // starts and ends with double support (known bounds).
                let bounded = start > 0
                    && state[start - 1] == Some((true, true))
                    && k < n
                    && state[k] == Some((true, true));
                if bounded {
                    let mid = 0.5 * (c.t[start] + c.t[k]);
                    for (j, o) in out.iter_mut().enumerate().take(k).skip(start) {
                        *o = Some(if c.t[j] < mid {
                            GaitPhase::Ss2
                        } else {
                            GaitPhase::Ss1
                        });
                    }
                }
            }
            _ => k += 1,
        }
    }
    out
}

/// Compares a gait-events estimate with its trial's contact and speed references.
pub fn evaluate_gait_event_files(
    trial: &Path,
    estimate: &Path,
    allow_trial_mismatch: bool,
) -> Result<GaitEventEvaluation, EvalError> {
    evaluate_gait_event_files_in(
        trial,
        estimate,
        allow_trial_mismatch,
        &TimeWindow::default(),
    )
}

/// As [`evaluate_gait_event_files`], over the rows inside `window` only
/// (`evaluate --window`): the references outside it count as unknown, so
/// that the events, contacts and strides scored are those inside it.
pub fn evaluate_gait_event_files_in(
    trial: &Path,
    estimate: &Path,
    allow_trial_mismatch: bool,
    window: &TimeWindow,
) -> Result<GaitEventEvaluation, EvalError> {
    evaluate_with_strides(Some(trial), estimate, allow_trial_mismatch, window).map(|(ev, _)| ev)
}

/// The evaluation and the strides it scores ([`crate::stride_table`]);
/// without a trial every reference is unknown (nothing is scored) and the
/// sides are those the estimate has events for.
pub(crate) fn evaluate_with_strides(
    trial: Option<&Path>,
    estimate: &Path,
    allow_trial_mismatch: bool,
    window: &TimeWindow,
) -> Result<(GaitEventEvaluation, Vec<StrideRow>), EvalError> {
    let mut er = EstimateReader::open(estimate)?;
    let method = er.method().to_string();
    let mut ev = GaitEventEvaluation::default();
    let (c, has_event_columns, with_imu, cut_lines) = match trial {
        Some(trial) => {
            let hash = limbfuse_io::TrialFingerprint::of_file(trial)?.hash;
            let mut tr = TrialReader::open(trial)?;
            ev.trial_check =
                crate::trial_check::check_trial(trial, hash, &er, allow_trial_mismatch)?;
            let with_imu = crate::scored_feet::legs_with_imu(tr.layout());
            ev.contact_ref_columns = tr.layout().contact_ref;
            let (c, has) = read_columns(Some((trial, &mut tr)), estimate, &mut er, window)?;
            let cut = crate::evaluation::cut_lines(Some(&tr), &er);
            (c, has, with_imu, cut)
        }
        None => {
            let (c, has) = read_columns(None, estimate, &mut er, window)?;
            let cut = crate::evaluation::cut_lines(None, &er);
            (c, has, [false; 2], cut)
        }
    };
    // (an audit: `--diagnostics none` changed the scores silently: 14
    // strides became 0, the events moved to the causal contact switches)
    ev.warnings = (matches!(
        limbfuse_methods::MethodName::parse(&method),
        Ok(limbfuse_methods::MethodName::GaitEvents)
    ) && !has_event_columns)
        .then(|| {
            format!(
                "{}: the estimate has no `diag_ic_*` / `diag_fc_*` / `diag_stride_*` columns \
                 (written with `--diagnostics none` or a list without them): events are scored \
                 at the causal contact switches and strides not at all; estimate with the \
                 default diagnostics to score them as documented",
                estimate.display()
            )
        })
        .into_iter()
        .chain(cut_lines)
        .collect();
    ev.method = method;
    ev.n_samples = c.n_inside;
    ev.speed_from_com = c.speed_from_com;
    let mut ic_sides = Vec::new();
    let mut fc_sides = Vec::new();
    let pooled = !has_event_columns && !c.ic_any.is_empty();
    ev.per_foot = !pooled;
    if pooled {
        let mut ref_ic: Vec<f64> = (0..2)
            .flat_map(|s| steps(&c.t, &c.reference[s], true))
            .collect();
        ref_ic.sort_by(f64::total_cmp);
        let est = c.ic_any.clone();
        let unscored = (0..2)
            .flat_map(|s| edge_steps(&c.t, &c.reference[s], true))
            .collect();
        let se = SideEvents {
            unscored,
            pairs: pair(&ref_ic, &est),
            reference: ref_ic,
            estimated: est,
        };
        ev.initial_contact = timing(core::slice::from_ref(&se), &c, &[None]);
        ev.contact_sides =
            crate::contact_sides::ContactSides::score(&c, &se.reference, &se.estimated, &se.pairs);
        accuracies(&c, &mut ev);
        let track = se.track();
        let rows = track_strides(StrideFoot::Unknown, &c.strides_any, &track, None, &c);
        score_strides(&rows, &c, &mut ev);
        let rows = unknown_foot_strides(rows, &track, &c);
        ev.n_withheld = withheld_with_reference(&rows);
        return Ok((ev, rows));
    }
    let estimated = [0, 1].map(|s| {
        c.contact[s].iter().any(Option::is_some) || !c.ic[s].is_empty() || !c.fc[s].is_empty()
    });
    let sides = crate::scored_feet::scored_sides(with_imu, estimated);
    for &s in &sides {
        let (est_ic, est_fc) = if has_event_columns {
            (c.ic[s].clone(), c.fc[s].clone())
        } else {
            (
                steps(&c.t, &c.contact[s], true),
                steps(&c.t, &c.contact[s], false),
            )
        };
        let ref_ic = steps(&c.t, &c.reference[s], true);
        let ref_fc = steps(&c.t, &c.reference[s], false);
        ic_sides.push(SideEvents {
            unscored: edge_steps(&c.t, &c.reference[s], true),
            pairs: pair(&ref_ic, &est_ic),
            reference: ref_ic,
            estimated: est_ic,
        });
        fc_sides.push(SideEvents {
            unscored: edge_steps(&c.t, &c.reference[s], false),
            pairs: pair(&ref_fc, &est_fc),
            reference: ref_fc,
            estimated: est_fc,
        });
    }
    let side_of: Vec<Option<usize>> = sides.iter().map(|&s| Some(s)).collect();
    ev.initial_contact = timing(&ic_sides, &c, &side_of);
    ev.final_contact = Some(timing(&fc_sides, &c, &side_of));
    accuracies(&c, &mut ev);
    let mut rows = Vec::new();
    for ((&s, se), fe) in sides.iter().zip(&ic_sides).zip(&fc_sides) {
        let foot = StrideFoot::of_side(s);
        rows.extend(track_strides(
            foot,
            &c.strides[s],
            &se.track(),
            Some(&fe.track()),
            &c,
        ));
    }
    score_strides(&rows, &c, &mut ev);
    ev.stance_swing = StanceSwingFigures::of_strides(&rows);
    ev.n_withheld = withheld_with_reference(&rows);
    Ok((ev, rows))
}

/// How many of `rows` have a speed reference but no speed from the method.
fn withheld_with_reference(rows: &[StrideRow]) -> u64 {
    rows.iter()
        .filter(|r| r.speed_withheld.is_some() && r.speed_ref_m_s.is_some())
        .count() as u64
}

fn accuracies(c: &Columns, ev: &mut GaitEventEvaluation) {
    let (mut ok, mut n) = (0u64, 0u64);
    for s in 0..2 {
        for (a, b) in c.reference[s].iter().zip(&c.contact[s]) {
            if let (Some(a), Some(b)) = (a, b) {
                n += 1;
                ok += u64::from(a == b);
            }
        }
    }
    ev.contact_accuracy_pct = (n > 0).then(|| 100.0 * ok as f64 / n as f64);
    let (mut ok, mut n) = (0u64, 0u64);
    for (a, b) in reference_phase(c).iter().zip(&c.phase) {
        if let (Some(a), Some(b)) = (a, b) {
            n += 1;
            ok += u64::from(a == b);
        }
    }
    ev.phase_accuracy_pct = (n > 0).then(|| 100.0 * ok as f64 / n as f64);
}

/// The per-stride and blended figures of the strides `rows` (every track;
/// the withheld strides of `lowback-speed`, without a length, are not among them).
fn score_strides(rows: &[StrideRow], c: &Columns, ev: &mut GaitEventEvaluation) {
    let (mut speed, mut length, mut strides) = (Vec::new(), Vec::new(), Vec::new());
    for r in rows {
        let (Some(l), Some(v)) = (r.stride_length_m, r.speed_m_s) else {
            continue;
        };
        strides.push(TrackStride {
            start: r.ic_s,
            end: r.end_s,
            length: l,
            reference_time: r.stride_time_ref_s,
        });
        let Some(v_ref) = r.speed_ref_m_s else {
            continue;
        };
        speed.push(v - v_ref);
        if let Some(l_ref) = r.stride_length_ref_m.filter(|&x| x > 0.0) {
            length.push((l - l_ref, l_ref));
        }
    }
    ev.per_stride = StrideFigures::from_errors(&speed, &length);
    if !c.speed_from_com {
        ev.blended = blended_stride_speed(&c.t, &c.speed_ref, &strides);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairing_is_one_to_one_and_nearest_first() {
        // 1.01 pairs with 1.0 (the closest pair first), 1.12 with 1.3; 3.0 is beyond the tolerance.
        let p = pair(&[1.0, 1.3], &[1.01, 1.12, 3.0]);
        assert_eq!(p, vec![(0, 0), (1, 1)]);
        assert!(pair(&[1.0], &[1.3]).is_empty());
    }

    #[test]
    fn reference_phase_splits_single_support_at_its_midpoint() {
        let t: Vec<f64> = (0..10).map(f64::from).collect();
        let both = Some(true);
        let mut c = Columns {
            t,
            ..Default::default()
        };
        // rows: DS DS | left swing 2..6 (4 rows) | DS DS DS DS
        c.reference[0] = vec![
            both,
            both,
            Some(false),
            Some(false),
            Some(false),
            Some(false),
            both,
            both,
            both,
            both,
        ];
        c.reference[1] = vec![both; 10];
        let ph = reference_phase(&c);
        use GaitPhase::*;
        assert_eq!(
            ph,
            vec![
                Some(Ds),
                Some(Ds),
                Some(Ss2),
                Some(Ss2),
                Some(Ss1),
                Some(Ss1),
                Some(Ds),
                Some(Ds),
                Some(Ds),
                Some(Ds)
            ]
        );
    }

    #[test]
    fn contact_steps_and_edges() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let v = [None, Some(true), Some(false), Some(true), Some(true), None];
        assert_eq!(steps(&t, &v, true), vec![3.0]);
        assert_eq!(steps(&t, &v, false), vec![2.0]);
        assert_eq!(edge_steps(&t, &v, true), vec![1.0]);
        assert_eq!(edge_steps(&t, &v, false), vec![5.0]);
    }
}
