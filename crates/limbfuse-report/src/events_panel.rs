//! The gait-events panel and table (issue 19 methods `gait-events`,
//! `lowback-speed`): each foot's contact and the walking speed over time
//! against the trial's `contact_*_ref` / `speed_ref`, and the numbers of
//! `limbfuse evaluate` for such estimates (event timing, contact accuracy,
//! stride speed and length; `limbfuse_eval::gait_events_evaluation`).

use std::fmt::Write as _;

use limbfuse_core::Side;
use limbfuse_eval::gait_events_evaluation::{EventTiming, GaitEventEvaluation};

use crate::data::{EstimateData, TrialData};
use crate::panels::{color, Panel, TimePlot};
use crate::svg::esc;

/// Whether an estimate carries gait events or a walking speed of its own
/// (a contact column, or a speed without a gait phase: the `imm-bslip`
/// speed is drawn by its own panel).
pub fn is_event_estimate(e: &EstimateData) -> bool {
    e.contact.iter().any(Option::is_some) || (e.speed.is_some() && e.phase.is_none())
}

/// Whether the trial has a reference these estimates can be scored against.
pub fn has_event_reference(trial: &TrialData) -> bool {
    ["contact_left_ref", "contact_right_ref", "speed_ref"]
        .iter()
        .any(|k| trial.columns.contains_key(*k))
}

/// The panel, when some estimate carries events or a speed
/// ([`is_event_estimate`]).
pub fn events_panel(trial: &TrialData, estimates: &[EstimateData], tp: &TimePlot) -> Option<Panel> {
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
    let mut lines = Vec::new();
    if let Some(r) = trial.columns.get("speed_ref") {
        lines.push((
            "ref".to_string(),
            "speed_ref".to_string(),
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
        note: "Each foot's contact and the walking speed of the estimates that carry them, against the trial's <code>contact_*_ref</code> and <code>speed_ref</code> (dashed) where it has them. The numbers are in the errors section.".into(),
        plots,
        table: String::new(),
    })
}

/// The numbers of `limbfuse evaluate` for gait-event and speed estimates.
pub fn events_table(labels: &[String], evals: &[(usize, GaitEventEvaluation)]) -> String {
    let mut s = String::from(
        r#"<table class="numbers" id="events-table"><thead><tr><th>estimate</th><th>initial contacts found / reference (missed, extra)</th><th>IC |error| median / p95 ms</th><th>final contacts found / reference (missed, extra)</th><th>FC |error| median / p95 ms</th><th>contact accuracy %</th><th>phase accuracy %</th><th>stride speed MAE (bias) m/s</th><th>strides</th><th>stride length error % (strides)</th></tr></thead><tbody>"#,
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
        let _ = write!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td><td>{}</td><td>{} ({})</td></tr>",
            esc(&labels[*i]),
            count(&e.initial_contact),
            timing(&e.initial_contact),
            fc_count,
            fc_timing,
            f(e.contact_accuracy_pct, 1),
            f(e.phase_accuracy_pct, 1),
            f(st.speed_mae_mps, 3),
            f(st.speed_bias_mps, 3),
            st.n_strides,
            f(st.stride_length_error_pct, 2),
            st.n_lengths,
        );
    }
    s.push_str("</tbody></table>");
    s
}
