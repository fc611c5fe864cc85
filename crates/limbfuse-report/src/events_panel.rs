//! The gait-events panel and table (issue 19 methods `gait-events`,
//! `lowback-speed`): each foot's contact and the walking speed over time
//! against the trial's `contact_*_ref` / `speed_ref`, and the numbers of
//! `limbfuse evaluate` for such estimates (event timing, contact accuracy,
//! stride speed and length; `limbfuse_eval::gait_events_evaluation`).

use std::fmt::Write as _;

use limbfuse_core::Side;
use limbfuse_eval::gait_events_evaluation::{EventTiming, GaitEventEvaluation};

use crate::data::{Column, EstimateData, TrialData, COM_SPEED};
use crate::panels::{color, Panel, TimePlot};
use crate::strides_table::{strides_details, EstimateStrides};
use crate::svg::esc;

/// Whether an estimate carries gait events or a walking speed of its own
/// (a contact column, or a speed without a gait phase: the `imm-bslip`
/// speed is drawn by its own panel).
pub fn is_event_estimate(e: &EstimateData) -> bool {
    e.contact.iter().any(Option::is_some) || (e.speed.is_some() && e.phase.is_none())
}

/// Whether the trial has a reference these estimates can be scored against:
/// `contact_*_ref`, `speed_ref`, or a CoM velocity that `evaluate` takes as
/// the speed reference ([`TrialData::speed_from_com`]; an audit 2026-12-05:
/// the independent walks' events and speeds went unscored in the report).
pub fn has_event_reference(trial: &TrialData) -> bool {
    trial.speed_from_com
        || ["contact_left_ref", "contact_right_ref", "speed_ref"]
            .iter()
            .any(|k| trial.columns.contains_key(*k))
}

/// The panel, when some estimate carries events or a speed
/// ([`is_event_estimate`]), with the stride table of each such estimate
/// (`strides`, [`crate::strides_table`]) under its plots.
pub fn events_panel(
    trial: &TrialData,
    estimates: &[EstimateData],
    tp: &TimePlot,
    strides: &[EstimateStrides],
) -> Option<Panel> {
    let shown: Vec<(usize, &EstimateData)> = estimates
        .iter()
        .enumerate()
        .filter(|(_, e)| is_event_estimate(e))
        .collect();
    if shown.is_empty() {
        return None;
    }
    let mut plots = Vec::new();
    for (k, side) in Side::BOTH.into_iter().enumerate() {
        let reference = trial.columns.get(&format!("contact_{}_ref", side.name()));
        let mut lines = Vec::new();
        if let Some(r) = reference {
            lines.push((
                "ref".to_string(),
                "reference".to_string(),
                "#000000".to_string(),
                r,
                true,
            ));
        }
        for (i, e) in &shown {
            if let Some(c) = &e.contact[k] {
                lines.push((format!("e{i}"), e.label.clone(), color(*i), c, false));
            }
        }
        if lines.iter().any(|l| l.0 != "ref") {
            plots.push(tp.plot(
                format!("plot-contact-{}", side.name()),
                "contact",
                format!("{} foot contact (1 on the ground, 0 in swing)", side.name()),
                "contact",
                lines,
            ));
        }
    }
    plots.extend(initial_contacts_plot(trial, &shown, tp));
    let mut lines = Vec::new();
    let speed_ref = trial
        .columns
        .get("speed_ref")
        .map(|r| ("speed_ref", r))
        .or_else(|| {
            let r = trial
                .columns
                .get(COM_SPEED)
                .filter(|_| trial.speed_from_com)?;
            Some(("horizontal CoM speed hypot(com_vx, com_vz) (reference)", r))
        });
    if let Some((label, r)) = speed_ref {
        lines.push((
            "ref".to_string(),
            label.to_string(),
            "#000000".to_string(),
            r,
            true,
        ));
    }
    for (i, e) in &shown {
        if let Some(v) = &e.speed {
            lines.push((format!("e{i}"), e.label.clone(), color(*i), v, false));
        }
    }
    if lines.iter().any(|l| l.0 != "ref") {
        plots.push(
            tp.plot(
                "plot-speed".into(),
                "speed",
                "walking speed (m/s; an estimate holds each stride's speed from the stride's end)"
                    .into(),
                "m/s",
                lines,
            ),
        );
    }
    Some(Panel {
        id: "panel-events".into(),
        kind: "events".into(),
        title: "Gait events and walking speed".into(),
        note: "Each foot's contact and the walking speed of the estimates that carry them, against the trial's <code>contact_*_ref</code> and <code>speed_ref</code> (dashed; without <code>speed_ref</code>, its horizontal CoM speed when <code>evaluate</code> scores against it) where it has them; the initial contacts of estimates that pool both feet (<code>diag_ic</code>: <code>lowback-speed</code>, which tells a contact's foot 2 s later, in the stride tables' foot column) as spikes, down, under the reference ones, up. The numbers are in the errors section; each estimate's strides, one row per stride as <code>limbfuse evaluate --strides</code> writes them, are in the tables under the plots (click to open).".into(),
        plots,
        table: strides
            .iter()
            .filter_map(|s| Some(strides_details(&estimates.get(s.estimate)?.label, s)))
            .collect(),
    })
}

/// The initial contacts of the estimates that pool both feet (`diag_ic`,
/// the back-dated contact times of `lowback-speed`) against the reference
/// ones (the 0 -> 1 steps of `contact_*_ref`), as spikes: the reference's
/// up (dashed), each estimate's down, so a detected contact sits under its
/// reference one; the spike's height tells the foot: a right contact 1, a
/// left one [`LEFT_SPIKE`], an estimated contact whose foot the method did
/// not tell (`diag_ic_right` / `diag_ic_left`) [`UNTOLD_SPIKE`]. Before
/// (review 27), a `lowback-speed` estimate showed only its speed: its
/// contacts, scored in the events table, were not drawn; before session 48
/// every spike was of height 1.
/// Height of a left contact's spike in the initial-contacts plot.
const LEFT_SPIKE: f64 = 0.6;
/// Height of an estimated contact whose foot was not told.
const UNTOLD_SPIKE: f64 = 0.3;

fn initial_contacts_plot(
    trial: &TrialData,
    shown: &[(usize, &EstimateData)],
    tp: &TimePlot,
) -> Option<crate::svg::Plot> {
    let detected: Vec<(usize, &EstimateData, &Column)> = shown
        .iter()
        .filter_map(|(i, e)| Some((*i, *e, e.diag.get("ic")?)))
        .collect();
    if detected.is_empty() {
        return None;
    }
    let n = trial.t.len();
    let refs: Vec<(Side, &Column)> = Side::BOTH
        .iter()
        .filter_map(|s| Some((*s, trial.columns.get(&format!("contact_{}_ref", s.name()))?)))
        .collect();
    let mut columns: Vec<(String, String, String, Column, bool)> = Vec::new();
    if !refs.is_empty() {
        let mut r: Column = (0..n)
            .map(|k| refs.iter().any(|(_, c)| c[k].is_some()).then_some(0.0))
            .collect();
        for (side, c) in &refs {
            let height = if *side == Side::Right {
                1.0
            } else {
                LEFT_SPIKE
            };
            for k in 1..n {
                if let (Some(a), Some(b)) = (c[k - 1], c[k]) {
                    if a < 0.5 && b >= 0.5 {
                        r[k] = Some(height);
                    }
                }
            }
        }
        columns.push((
            "ref".into(),
            "reference initial contacts (contact_*_ref 0 -> 1; right 1, left 0.6)".into(),
            "#000000".into(),
            r,
            true,
        ));
    }
    for (i, e, ic) in detected {
        let mut c: Column = vec![Some(0.0); n];
        let [right, left] = ["ic_right", "ic_left"].map(|name| {
            e.diag
                .get(name)
                .map(|col| col.iter().flatten().copied().collect::<Vec<f64>>())
                .unwrap_or_default()
        });
        let told = |side: &[f64], t: f64| side.iter().any(|x| (x - t).abs() <= 1e-9);
        for t_ic in ic.iter().flatten() {
            if let Some(k) = nearest_sample(&trial.t, *t_ic) {
                let height = if told(&right, *t_ic) {
                    1.0
                } else if told(&left, *t_ic) {
                    LEFT_SPIKE
                } else {
                    UNTOLD_SPIKE
                };
                c[k] = Some(-height);
            }
        }
        columns.push((
            format!("e{i}"),
            format!("{}: initial contacts", e.label),
            color(i),
            c,
            false,
        ));
    }
    Some(
        tp.plot(
            "plot-initial-contacts".into(),
            "initial-contacts",
            // (an audit 2026-12-05: the title spoke of a reference on
            // trials without one)
            if refs.is_empty() {
                "initial contacts (estimated, down; right foot 1, left 0.6, foot not told 0.3; the trial has no contact_*_ref)"
                    .into()
            } else {
                "initial contacts (reference up, estimated down; right foot 1, left 0.6, foot not told 0.3)".into()
            },
            "contact",
            columns
                .iter()
                .map(|(k, l, c, col, d)| (k.clone(), l.clone(), c.clone(), col, *d))
                .collect(),
        ),
    )
}

/// The sample nearest to time `t` (s, the trial's clock), when `t` is
/// within the trial.
fn nearest_sample(times: &[f64], t: f64) -> Option<usize> {
    let (first, last) = (*times.first()?, *times.last()?);
    if !t.is_finite() || t < first || t > last {
        return None;
    }
    let k = times.partition_point(|x| *x < t);
    if k == 0 {
        return Some(0);
    }
    if k == times.len() || t - times[k - 1] <= times[k] - t {
        Some(k - 1)
    } else {
        Some(k)
    }
}

/// The numbers of `limbfuse evaluate` for gait-event and speed estimates.
pub fn events_table(labels: &[String], evals: &[(usize, GaitEventEvaluation)]) -> String {
    let mut s = String::from(
        r#"<table class="numbers" id="events-table"><thead><tr><th>estimate</th><th>initial contacts found / reference (missed, extra)</th><th>IC |error| median / p95 ms</th><th>final contacts found / reference (missed, extra)</th><th>FC |error| median / p95 ms</th><th>stance / swing time MAE (bias) ms (strides)</th><th>contact accuracy %</th><th>phase accuracy %</th><th>stride speed MAE (bias) m/s</th><th>strides</th><th>stride length error % (strides)</th></tr></thead><tbody>"#,
    );
    let f = |v: Option<f64>, p: usize| v.map_or("-".to_string(), |v| format!("{v:.p$}"));
    // (an audit: "0 / 0 (0, 0)" where `evaluate` says there is no
    // reference event to score against)
    let count = |e: &EventTiming| {
        if e.n_reference == 0 {
            "no reference event".to_string()
        } else {
            format!(
                "{} / {} ({}, {})",
                e.n_matched, e.n_reference, e.missed, e.extra
            )
        }
    };
    let timing = |e: &EventTiming| format!("{} / {}", f(e.median_abs_ms, 1), f(e.p95_abs_ms, 1));
    for (i, e) in evals {
        let (fc_count, fc_timing) = e
            .final_contact
            .as_ref()
            .map_or(("not estimated".to_string(), "-".to_string()), |fc| {
                (count(fc), timing(fc))
            });
        let st = &e.per_stride;
        // (`evaluate`'s stance / swing lines; "-" where no stride has both
        // its reference stance and swing: `lowback-speed`, no reference)
        let ss = &e.stance_swing;
        let stance_swing = if ss.n_strides == 0 {
            "-".to_string()
        } else {
            format!(
                "{} ({}) / {} ({}) ({})",
                f(ss.stance_time_mae_ms, 1),
                f(ss.stance_time_bias_ms, 1),
                f(ss.swing_time_mae_ms, 1),
                f(ss.swing_time_bias_ms, 1),
                ss.n_strides
            )
        };
        // (`evaluate`'s "not scored" line: strides withheld for a turn)
        let strides = match e.n_withheld {
            0 => st.n_strides.to_string(),
            n => format!("{} ({n} more withheld: turning)", st.n_strides),
        };
        let _ = write!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td><td>{}</td><td>{} ({})</td></tr>",
            esc(&labels[*i]),
            count(&e.initial_contact),
            timing(&e.initial_contact),
            fc_count,
            fc_timing,
            stance_swing,
            f(e.contact_accuracy_pct, 1),
            f(e.phase_accuracy_pct, 1),
            f(st.speed_mae_mps, 3),
            f(st.speed_bias_mps, 3),
            strides,
            f(st.stride_length_error_pct, 2),
            st.n_lengths,
        );
    }
    s.push_str("</tbody></table>");
    s
}

#[cfg(test)]
mod tests {
    use super::nearest_sample;

    #[test]
    fn nearest_sample_of_a_time() {
        let t = [10.0, 10.01, 10.02, 10.03];
        assert_eq!(nearest_sample(&t, 10.0), Some(0));
        assert_eq!(nearest_sample(&t, 10.014), Some(1));
        assert_eq!(nearest_sample(&t, 10.016), Some(2));
        assert_eq!(nearest_sample(&t, 10.03), Some(3));
        assert_eq!(nearest_sample(&t, 9.99), None);
        assert_eq!(nearest_sample(&t, f64::NAN), None);
    }
}
