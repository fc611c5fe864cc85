//! The report's "Errors" section: `evaluate`'s tables and notes, scored
//! with `evaluate`'s options ([`crate::scoring`]).

use std::fmt::Write as _;

use limbfuse_eval::evaluation::nothing_scored;
use limbfuse_eval::gait_evaluation::GaitEvaluation;
use limbfuse_eval::gait_events_evaluation::GaitEventEvaluation;
use limbfuse_eval::{EvalError, Evaluation};
use limbfuse_io::TrialMeta;

use crate::data::EstimateData;
use crate::events_panel::{events_table, is_event_estimate};
use crate::scoring::Scoring;
use crate::svg::esc;
use crate::{tables, ReportError, ReportInput};

/// Refuses scoring options that apply to no estimate of the report, as
/// `evaluate` refuses them for an estimate they do not apply to
/// (`--offset-free` and `--max-lag` score angles; `--window` angles and
/// gait events; the paper-003 gait evaluation takes none), and a window
/// without a sample of the trial (`evaluate`'s error).
pub(crate) fn check_scoring(
    input: &ReportInput,
    evals: &[Evaluation],
    estimates: &[EstimateData],
    events: &[(usize, GaitEventEvaluation)],
    gait_trial: bool,
) -> Result<(), ReportError> {
    let scoring = &input.scoring;
    let angles = evals
        .iter()
        .zip(estimates)
        .any(|(_, e)| !is_event_estimate(e));
    let why = if gait_trial {
        "the trial is a gait trial (paper 003), scored for gait phase, CoM and speed"
    } else if !estimates.is_empty() && estimates.iter().all(is_event_estimate) {
        if events.is_empty() {
            "the estimates are of gait events and walking speed, and the trial has no contact or speed reference"
        } else {
            "the estimates are scored for gait events and walking speed"
        }
    } else {
        "the trial has no reference angle to score against"
    };
    if !angles {
        let options: Vec<_> = scoring
            .given()
            .into_iter()
            .filter(|o| events.is_empty() || *o != crate::ScoringOption::Window)
            .collect();
        if !options.is_empty() {
            return Err(ReportError::ScoringNotApplicable {
                why: format!(
                    "to angle errors only{}; {why}",
                    if events.is_empty() {
                        ""
                    } else {
                        " (--window to gait events too)"
                    }
                ),
                options,
            });
        }
    }
    if scoring.has_window() && !evals.is_empty() && evals.iter().all(|ev| ev.n_samples == 0) {
        let why = nothing_scored(
            &evals[0],
            true,
            &scoring.window,
            &input.trial.display().to_string(),
            &estimates[0].path.display().to_string(),
        );
        return Err(EvalError::NothingScored(why.unwrap_or_default()).into());
    }
    Ok(())
}

/// `evaluate`'s notes on the angle estimates of the table
/// ([`Evaluation::notes`], the restarts, the reference's units, `align`'s
/// assumed zero): a note every estimate has is given once, others name
/// their estimates.
fn evaluate_notes(
    s: &mut String,
    labels: &[String],
    evals: &[Evaluation],
    (scoring, trial_meta): (&Scoring, &TrialMeta),
) {
    // (text, warning?, the estimates it is about)
    let mut notes: Vec<(String, bool, Vec<usize>)> = Vec::new();
    let mut add = |text: String, warning: bool, label: usize| match notes
        .iter_mut()
        .find(|(t, _, _)| *t == text)
    {
        Some((_, _, l)) => l.push(label),
        None => notes.push((text, warning, vec![label])),
    };
    for (l, ev) in evals.iter().enumerate() {
        if let Some(r) = &ev.resets {
            add(format!("warning: {r}"), true, l);
        }
        if let Some(w) = &ev.reference_units {
            add(format!("warning: {w}"), true, l);
        }
        for n in ev.notes() {
            add(n, false, l);
        }
    }
    if let Some(n) = limbfuse_eval::notes::assumed_zero_note(trial_meta, scoring.offset_free) {
        notes.push((format!("note: {n}"), false, (0..labels.len()).collect()));
    }
    if notes.is_empty() {
        return;
    }
    s.push_str(r#"<ul class="notes" id="evaluate-notes">"#);
    for (text, warning, about) in notes {
        let about: Vec<&str> = about.iter().map(|&k| labels[k].as_str()).collect();
        // (a note of every estimate is said once, without names)
        let who = if about.len() == labels.len() {
            String::new()
        } else {
            let names: Vec<String> = about
                .iter()
                .map(|l| format!("<code>{}</code>", esc(l)))
                .collect();
            format!("{}: ", names.join(", "))
        };
        let _ = write!(
            s,
            r#"<li class="{}" data-estimates="{}">{who}{}</li>"#,
            if warning { "warning" } else { "note" },
            esc(&about.join(" ")),
            esc(&text)
        );
    }
    s.push_str("</ul>");
}

/// The error tables, with `evaluate`'s notes beside them.
pub(crate) fn error_section(
    s: &mut String,
    (labels, nothing_scored): (&[String], &[Option<String>]),
    (evals, scoring, trial_meta): (&[Evaluation], &Scoring, &TrialMeta),
    gait: &[GaitEvaluation],
    (is_event, events): (&[bool], &[(usize, GaitEventEvaluation)]),
    speed_from_com: bool,
) {
    s.push_str(r#"<section id="errors" data-section="errors"><h2>Errors</h2>"#);
    // Angle tables only for estimates of angles (a speed or event estimate
    // of a trial with angle references is scored below, if it can be), and
    // only for those that scored a sample: for the others, `evaluate`'s
    // sentence (audit 2026-12-05: an estimate of empty cells gave an empty
    // table, unexplained).
    let angle_estimates: Vec<usize> = (0..evals.len()).filter(|&i| !is_event[i]).collect();
    let unscored: Vec<(usize, &String)> = angle_estimates
        .iter()
        .filter_map(|&i| Some((i, nothing_scored.get(i)?.as_ref()?)))
        .collect();
    let angle_rows: Vec<usize> = angle_estimates
        .iter()
        .copied()
        .filter(|i| unscored.iter().all(|(k, _)| k != i))
        .collect();
    let (labels_a, evals_a): (Vec<String>, Vec<Evaluation>) = angle_rows
        .iter()
        .map(|&i| (labels[i].clone(), evals[i].clone()))
        .unzip();
    let labels_all = labels;
    let (labels, evals) = (&labels_a[..], &evals_a[..]);
    if !evals.is_empty() {
        let _ = write!(
            s,
            r#"<p class="note" id="scoring" data-window="{}" data-offset-free="{}" data-max-lag="{}">The numbers of <code>limbfuse evaluate TRIAL ESTIMATE{}</code>: {}.</p>"#,
            esc(&scoring.window.to_string()),
            scoring.offset_free,
            scoring.max_lag,
            esc(&scoring.flags()),
            scoring.describe()
        );
        s.push_str(r#"<p class="note">The mean RMSE is over the segment angles estimated (over the joint angles when no segment is), leaving out channels equal to their reference in every sample when another channel has an error (a value the method is given, not an estimate).</p>"#);
        s.push_str(&tables::rmse_matrix(labels, evals));
        evaluate_notes(s, labels, evals, (scoring, trial_meta));
        s.push_str("<details><summary>All columns of <code>evaluate</code></summary>");
        s.push_str(&tables::error_details(labels, evals));
        s.push_str("</details>");
    }
    for (i, why) in &unscored {
        let _ = write!(
            s,
            r#"<p class="warning" id="nothing-scored-{i}" data-estimate="{}">{}</p>"#,
            esc(&labels_all[*i]),
            esc(why)
        );
    }
    if !gait.is_empty() {
        s.push_str(r#"<p class="note">The numbers of <code>limbfuse evaluate</code> on a gait trial (paper 003).</p>"#);
        // (one evaluation per estimate given: every label, not only the
        // angle estimates' — an audit found the table empty for imm-bslip)
        s.push_str(&tables::gait_table(labels_all, gait));
    }
    if !events.is_empty() {
        s.push_str(r#"<p class="note" id="events-note">The numbers of <code>limbfuse evaluate TRIAL ESTIMATE</code> for gait events and walking speed (docs/GAIT_EVENTS.md): events paired within 0.25 s, each stride's speed against the mean <code>speed_ref</code> over its rows"#);
        if speed_from_com {
            s.push_str(r#" (the trial has no <code>speed_ref</code>: its horizontal CoM speed <code>hypot(com_vx, com_vz)</code> instead, as <code>evaluate</code> takes it)"#);
        }
        s.push('.');
        if scoring.has_window() {
            let _ = write!(
                s,
                " Window {} (<code>--window</code>).",
                esc(&scoring.window.to_string())
            );
        }
        if scoring.offset_free || scoring.max_lag > 0 {
            s.push_str(" <code>--offset-free</code> and <code>--max-lag</code> apply to angle errors only, not to this table.");
        }
        s.push_str("</p>");
        s.push_str(&events_table(labels_all, events));
    }
    if events.is_empty() && is_event.iter().any(|&e| e) {
        s.push_str(r#"<p class="note">The trial has no contact or speed reference (<code>contact_*_ref</code>, <code>speed_ref</code>, or a CoM velocity <code>com_vx</code> .. <code>com_vz</code> without <code>phase_ref</code>) to score the gait events and walking speed against.</p>"#);
    } else if evals.is_empty() && unscored.is_empty() && gait.is_empty() && events.is_empty() {
        s.push_str(r#"<p class="note">The trial has no reference to evaluate against.</p>"#);
    }
    s.push_str("</section>");
}
