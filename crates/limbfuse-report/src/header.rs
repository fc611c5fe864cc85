//! The page's header: the summary line, the warnings, the plots' time
//! origin and the time window controls.

use std::fmt::Write as _;

use crate::data::{EstimateData, TrialData};
use crate::svg::esc;
use crate::time_base::TimeBase;

/// The page's header: the summary line (samples, duration, rate, gaps, the
/// estimates), the warnings, the plots' time origin and the time window
/// controls.
pub(crate) fn header(
    s: &mut String,
    (trial, time_base): (&TrialData, &TimeBase),
    estimates: &[EstimateData],
    (rate, buckets): (f64, usize),
    checks: &[String],
) {
    let dur = time_base.relative.last().copied().unwrap_or(0.0);
    let _ = write!(
        s,
        r##"<header><h1>limbfuse report</h1><p id="summary">Trial <code>{}</code>: {} samples, {:.1} s, {:.1} Hz{}. {} estimate{}: {}.</p>{}<p class="note">Plots show at most 2 x {} points per line (min/max per run of samples, docs/REPORT.md); tables use every sample.</p></header><nav><a href="#angles">angles</a> <a href="#gait-cycle">gait cycle</a> <a href="#errors">errors</a> <a href="#methods">method panels</a> <a href="#commands">commands</a></nav>"##,
        esc(&trial.name()),
        trial.t.len(),
        dur,
        rate,
        gap_summary(time_base),
        estimates.len(),
        if estimates.len() == 1 { "" } else { "s" },
        estimates
            .iter()
            .map(|e| format!("<code>{}</code> ({})", esc(&e.label), esc(&e.method)))
            .collect::<Vec<_>>()
            .join(", "),
        time_origin_note(time_base),
        buckets
    );
    // The trial checks' warnings, as `evaluate` prints them (an audit: an
    // estimate of another trial, evaluated as asked, left no trace here).
    for w in trial.unit_warnings.iter().chain(checks) {
        let _ = write!(s, r#"<p class="warning">warning: {}</p>"#, esc(w));
    }
    // `estimate`'s raw-frame warning, for the estimates it applied to.
    for e in estimates {
        let note = limbfuse_methods::MethodName::parse(&e.method)
            .ok()
            .and_then(|m| limbfuse_methods::raw_frame_note(m, &trial.meta, &trial.name()));
        if let Some(w) = note {
            let w = w.strip_prefix("warning: ").unwrap_or(&w);
            let _ = write!(
                s,
                r#"<p class="warning">warning ({}): {}</p>"#,
                esc(&e.label),
                esc(w)
            );
        }
    }
    window_controls(s, time_base);
}

/// `, N gaps in time (longest ...)` for the summary line, empty without gaps
/// (audit 2026-12-05: a 3 s gap was not mentioned and drawn across).
fn gap_summary(time_base: &TimeBase) -> String {
    let Some(longest) = time_base.longest_gap() else {
        return String::new();
    };
    let n = time_base.gaps.len();
    format!(
        r#", <span id="time-gaps" data-gaps="{n}" data-longest-s="{:.3}">{n} gap{} in time (a step over {} median steps; longest {:.3} s, after t = {:.3} s): the lines break there</span>"#,
        longest.length(),
        if n == 1 { "" } else { "s" },
        limbfuse_eval::trial_summary::GAP_STEPS,
        longest.length(),
        longest.start
    )
}

/// Where the plots' time 0 is in the trial, when not at 0 s.
fn time_origin_note(time_base: &TimeBase) -> String {
    if time_base.origin == 0.0 {
        return String::new();
    }
    format!(
        r#"<p class="note" id="time-origin" data-origin-s="{0}">Times on this page are from the first sample: t = 0 is {0:.3} s in the trial.</p>"#,
        time_base.origin
    )
}

/// The time window shared by every time plot (the page's script acts on
/// it), in seconds since the first sample.
fn window_controls(s: &mut String, time_base: &TimeBase) {
    let end = time_base.relative.last().copied().unwrap_or(0.0);
    let _ = write!(
        s,
        r#"<div class="controls" id="window-controls">window <input id="win-start" type="number" step="any" value="0"> to <input id="win-end" type="number" step="any" value="{end:.3}"> s <button id="win-apply">show</button> <button id="win-in">zoom in</button> <button id="win-out">zoom out</button> <button id="win-left">&larr;</button> <button id="win-right">&rarr;</button> <button id="win-all">whole trial</button> <span class="note">(or scroll on a plot to zoom, drag to pan; click a legend entry to hide a line)</span></div>"#
    );
}
