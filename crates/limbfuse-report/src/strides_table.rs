//! The per-stride table of each `gait-events` / `lowback-speed` estimate in
//! the gait-events panel: the rows of `limbfuse evaluate TRIAL ESTIMATE
//! --strides FILE` (built by [`limbfuse_eval::stride_table`], not here), one
//! HTML table per estimate in a collapsible `<details>`.

use std::fmt::Write as _;
use std::path::Path;

use limbfuse_eval::evaluation::TimeWindow;
use limbfuse_eval::gait_events_evaluation::GaitEventEvaluation;
use limbfuse_eval::stride_table::{
    evaluation_and_stride_table, SpeedWithheld, StrideFoot, StrideRow, StrideTable,
};
use limbfuse_eval::EvalError;

use crate::svg::esc;

/// The strides of one estimate, or why it has none (`evaluate`'s message:
/// an estimate written with `--diagnostics none`, say).
#[derive(Debug, Clone)]
pub struct EstimateStrides {
    /// Index of the estimate in the report.
    pub estimate: usize,
    /// The table, or the message of [`EvalError::NoStrides`].
    pub table: Result<StrideTable, String>,
    /// Whether the table has the trial's references (`contact_*_ref`,
    /// `speed_ref` or the CoM velocity `evaluate` takes for it).
    pub with_reference: bool,
}

impl EstimateStrides {
    /// The strides of `estimate` (index `k` in the report) as `evaluate
    /// --strides` gives them, against `trial` when given (the trial has a
    /// reference for them), over `window`, with the evaluation they were
    /// scored in (the events table's, when `trial` is given). Any error but
    /// "no stride columns" is returned.
    pub fn read(
        k: usize,
        trial: Option<&Path>,
        estimate: &Path,
        allow_trial_mismatch: bool,
        window: &TimeWindow,
    ) -> Result<(GaitEventEvaluation, Self), EvalError> {
        let (ev, table) =
            evaluation_and_stride_table(trial, estimate, allow_trial_mismatch, window)?;
        let strides = EstimateStrides {
            estimate: k,
            table,
            with_reference: trial.is_some(),
        };
        Ok((ev, strides))
    }
}

/// A number with `p` decimals, as the events table prints its numbers; an
/// unknown is an empty cell (as in the CSV of `evaluate --strides`).
fn cell(v: Option<f64>, p: usize) -> String {
    v.map_or_else(String::new, |v| format!("{v:.p$}"))
}

/// Estimated minus reference stride speed (m/s), when both are known.
fn speed_error(r: &StrideRow) -> Option<f64> {
    Some(r.speed_m_s? - r.speed_ref_m_s?)
}

/// Estimated minus reference stance and swing time (ms), each when both
/// are known (`evaluate` scores the strides that have both).
fn stance_swing_errors_ms(r: &StrideRow) -> [Option<f64>; 2] {
    let error = |e: Option<f64>, x: Option<f64>| Some(1e3 * (e? - x?));
    [
        error(r.stance_time_s, r.stance_time_ref_s),
        error(r.swing_time_s, r.swing_time_ref_s),
    ]
}

/// The `<details>` element holding the stride table of one estimate
/// (`label`), or the note saying why it has none.
pub fn strides_details(label: &str, s: &EstimateStrides) -> String {
    let k = s.estimate;
    let table = match &s.table {
        Ok(t) => t,
        Err(why) => {
            return format!(
                r#"<p class="note" id="strides-none-{k}" data-estimate="{}">{}: no stride table ({}).</p>"#,
                esc(label),
                esc(label),
                esc(why)
            )
        }
    };
    // (`lowback-speed`'s strides, their two step lengths given: a speed it
    // may withhold, and a foot it may not know)
    let withheld_column = table
        .rows
        .iter()
        .any(|r| r.foot == StrideFoot::Unknown || r.step_length_2_m.is_some());
    // (stance and swing: strides with a final contact, `gait-events`')
    let phase_columns = table.rows.iter().any(|r| r.fc_s.is_some());
    let mut out = format!(
        r#"<details class="strides" id="strides-{k}" data-estimate="{}" data-strides="{}"><summary>Strides of {}: {} (the rows of <code>limbfuse evaluate TRIAL ESTIMATE --strides FILE</code>; times in the trial's own <code>t</code>)</summary><table class="numbers" id="strides-table-{k}"><thead><tr><th>foot</th><th>IC s</th><th>FC s</th><th>stride time s</th>"#,
        esc(label),
        table.rows.len(),
        esc(label),
        table.rows.len()
    );
    if phase_columns {
        out.push_str("<th>stance s</th><th>swing s</th>");
    }
    out.push_str("<th>stride length m</th><th>speed m/s</th>");
    if s.with_reference {
        out.push_str("<th>reference speed m/s</th><th>speed error m/s</th>");
    }
    if s.with_reference && phase_columns {
        out.push_str("<th>stance error ms</th><th>swing error ms</th>");
    }
    if withheld_column {
        out.push_str("<th>speed withheld</th>");
    }
    out.push_str("</tr></thead><tbody>");
    for r in &table.rows {
        let _ = write!(
            out,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td>",
            r.foot.name(),
            cell(Some(r.ic_s), 3),
            cell(r.fc_s, 3),
            cell(r.stride_time_s, 3),
        );
        if phase_columns {
            let (stance, swing) = (cell(r.stance_time_s, 3), cell(r.swing_time_s, 3));
            let _ = write!(out, "<td>{stance}</td><td>{swing}</td>");
        }
        let _ = write!(
            out,
            "<td>{}</td><td>{}</td>",
            cell(r.stride_length_m, 3),
            cell(r.speed_m_s, 3),
        );
        if s.with_reference {
            let _ = write!(
                out,
                "<td>{}</td><td>{}</td>",
                cell(r.speed_ref_m_s, 3),
                cell(speed_error(r), 3)
            );
        }
        if s.with_reference && phase_columns {
            let [stance, swing] = stance_swing_errors_ms(r).map(|e| cell(e, 1));
            let _ = write!(out, "<td>{stance}</td><td>{swing}</td>");
        }
        if withheld_column {
            let _ = write!(
                out,
                "<td>{}</td>",
                r.speed_withheld.map_or("", SpeedWithheld::name)
            );
        }
        out.push_str("</tr>");
    }
    out.push_str("</tbody></table></details>");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // (the rows themselves come from `limbfuse_eval::stride_table`, which
    // builds them; the CLI test `report_strides_table` checks them against
    // `evaluate --strides`)
    #[test]
    fn unknown_cells_are_empty_and_numbers_have_three_decimals() {
        assert_eq!(cell(None, 3), "");
        assert_eq!(cell(Some(1.23456), 3), "1.235");
        let none = EstimateStrides {
            estimate: 0,
            table: Err("e.csv: no stride columns".into()),
            with_reference: false,
        };
        let html = strides_details("g<1>.csv", &none);
        assert!(html.contains(r#"id="strides-none-0""#), "{html}");
        assert!(html.contains("g&lt;1&gt;.csv"), "{html}");
    }

    #[test]
    fn an_empty_table_is_a_details_element_with_no_row() {
        let s = EstimateStrides {
            estimate: 3,
            table: Ok(StrideTable::default()),
            with_reference: true,
        };
        let html = strides_details("g.csv", &s);
        assert!(html.starts_with(r#"<details class="strides" id="strides-3""#));
        assert!(html.contains(r#"data-strides="0""#));
        assert!(html.contains("<th>speed error m/s</th>"));
        assert!(!html.contains("<th>speed withheld</th>"));
        // (no stride with a final contact: no stance or swing column)
        assert!(!html.contains("<th>stance s</th>"), "{html}");
        assert!(html.ends_with("<tbody></tbody></table></details>"));
    }
}
