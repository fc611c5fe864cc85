//! The report's tables: the numbers of `limbfuse evaluate` (computed by
//! `limbfuse-eval` on every sample, never on the decimated display data).

use std::fmt::Write as _;

use limbfuse_core::sample::AngleChannel;
use limbfuse_eval::gait_evaluation::GaitEvaluation;
use limbfuse_eval::Evaluation;

use crate::svg::esc;

/// `{:.3}` of an angle in degrees, `-` when absent (as `evaluate` prints).
fn deg(v: Option<f64>) -> String {
    v.map_or("-".to_string(), |v| format!("{:.3}", v.to_degrees()))
}

/// RMSE (deg) per channel (rows) and estimate (columns), then the mean RMSE.
pub fn rmse_matrix(labels: &[String], evals: &[Evaluation]) -> String {
    let mut s =
        String::from(r#"<table class="numbers" id="rmse-table"><thead><tr><th>RMSE (deg)</th>"#);
    for l in labels {
        let _ = write!(s, "<th>{}</th>", esc(l));
    }
    s.push_str("</tr></thead><tbody>");
    for c in AngleChannel::ALL {
        if evals.iter().all(|e| e.rmse(c).is_none()) {
            continue;
        }
        let _ = write!(s, r#"<tr data-channel="{0}"><td>{0}</td>"#, c.name());
        for e in evals {
            let _ = write!(s, "<td>{}</td>", deg(e.rmse(c)));
        }
        s.push_str("</tr>");
    }
    s.push_str(r#"<tr class="mean" data-channel="mean"><td>mean RMSE</td>"#);
    for e in evals {
        let _ = write!(s, "<td>{}</td>", deg(e.mean_rmse()));
    }
    s.push_str("</tr></tbody></table>");
    s
}

/// Every column of `evaluate`'s table, one block of rows per estimate.
pub fn error_details(labels: &[String], evals: &[Evaluation]) -> String {
    let mut s = String::from(
        r#"<table class="numbers" id="error-table"><thead><tr><th>estimate</th><th>channel</th><th>RMSE deg</th><th>max|e| deg</th><th>mean e deg</th><th>corr</th><th>n</th></tr></thead><tbody>"#,
    );
    for (l, e) in labels.iter().zip(evals) {
        for (c, st) in &e.channels {
            if st.n() == 0 {
                continue;
            }
            let _ = write!(
                s,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(l),
                c.name(),
                deg(e.rmse(*c)),
                deg(st.max_abs_error()),
                deg(st.mean_error()),
                st.correlation().map_or("-".to_string(), |r| format!("{r:.4}")),
                st.n()
            );
        }
    }
    s.push_str("</tbody></table>");
    s
}

/// Gait estimates (paper 003): phase accuracy, CoM and speed, as `evaluate` prints them.
pub fn gait_table(labels: &[String], evals: &[GaitEvaluation]) -> String {
    let mut s = String::from(
        r#"<table class="numbers" id="gait-table"><thead><tr><th>estimate</th><th>phase accuracy %</th><th>CoM position RMS cm</th><th>CoM max cm</th><th>speed m/s</th><th>reference speed m/s</th><th>n</th></tr></thead><tbody>"#,
    );
    let f =
        |v: Option<f64>, k: f64, p: usize| v.map_or("-".to_string(), |v| format!("{:.p$}", v * k));
    for (l, e) in labels.iter().zip(evals) {
        let _ = write!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(l),
            f(e.phase_accuracy_pct, 1.0, 1),
            f(e.com_pos_rmse_m, 100.0, 3),
            f(e.com_pos_max_m, 100.0, 3),
            f(e.speed_mean_mps, 1.0, 3),
            f(e.speed_ref_mps, 1.0, 3),
            e.n_samples
        );
    }
    s.push_str("</tbody></table>");
    s
}
