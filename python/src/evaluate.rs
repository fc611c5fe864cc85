//! `evaluate`: an estimate against its trial's reference, the CLI's
//! `evaluate --json` object (SPEC section 4) computed by the same code
//! (`limbfuse-eval`'s `AngleMetrics`; for gait trials, the gait-event
//! evaluation (contacts, stride speed) or the gait evaluation (phase, CoM)
//! over the two written to temporary files, chosen as the CLI chooses).

use std::io::Write;

use std::path::{Path, PathBuf};

use limbfuse_eval::evaluation::nothing_scored;
use limbfuse_eval::gait_evaluation::evaluate_gait_files;
use limbfuse_eval::gait_events_evaluation::evaluate_gait_event_files_in;
use limbfuse_eval::{evaluation_kind, EvaluationKind};
use limbfuse_eval::{max_lag_bound, AngleMetrics, EvalOptions, TimeWindow};
use limbfuse_io::content_hash::TRIAL_HASH_KEY;
use limbfuse_io::TrialWriter;
use pyo3::prelude::*;

use crate::columns::TrialColumns;
use crate::estimate::EstimateArgs;
use crate::estimate_columns::EstimateView;
use crate::trial::TrialArgs;
use crate::{guarded, user_error, user_msg};

/// Evaluates; returns the JSON text of `limbfuse evaluate --json`.
#[pyfunction]
#[pyo3(signature = (trial, estimate, window=None, offset_free=false, max_lag=0, allow_trial_mismatch=false))]
fn evaluate(
    py: Python<'_>,
    trial: TrialArgs<'_>,
    estimate: EstimateArgs<'_>,
    window: Option<&str>,
    offset_free: bool,
    max_lag: usize,
    allow_trial_mismatch: bool,
) -> PyResult<String> {
    guarded(|| {
        let cols = trial.columns()?;
        let view = estimate.view()?;
        let label = trial.label();
        check_same_trial(&trial, &estimate, allow_trial_mismatch)?;
        let layout = *cols.layout();
        let window_text = window;
        let window = match window {
            Some(w) => TimeWindow::parse(w).map_err(|m| user_msg(format!("window: {m}")))?,
            None => TimeWindow::default(),
        };
        // As `limbfuse evaluate`: options of the angle evaluation that an
        // event or gait evaluation cannot honour are refused.
        let angle_only = |what: &str, window_too: bool| -> PyResult<()> {
            let mut given = Vec::new();
            if window_too && window_text.is_some() {
                given.push("window");
            }
            if offset_free {
                given.push("offset_free");
            }
            if max_lag > 0 {
                given.push("max_lag");
            }
            if given.is_empty() {
                return Ok(());
            }
            Err(user_msg(format!(
                "{}: {} to angle errors only; the estimate is scored for {what}",
                given.join(", "),
                if given.len() == 1 { "applies" } else { "apply" }
            )))
        };
        match evaluation_kind(&layout, view.content()) {
            EvaluationKind::GaitEvents => {
                // Gait events, contacts and stride speed (docs/GAIT_EVENTS.md).
                angle_only("gait events and walking speed", false)?;
                return gait(&trial, &cols, &estimate, &view, |tp, ep| {
                    let ev = evaluate_gait_event_files_in(tp, ep, true, &window)
                        .map_err(|e| user_error(&e))?;
                    Ok(ev.to_json().to_string())
                });
            }
            EvaluationKind::Gait => {
                angle_only("gait phase, CoM and speed (paper 003)", true)?;
                return gait(&trial, &cols, &estimate, &view, |tp, ep| {
                    let ev = evaluate_gait_files(tp, ep, true).map_err(|e| user_error(&e))?;
                    Ok(ev.to_json().to_string())
                });
            }
            EvaluationKind::Angles => {}
        }
        if !layout.has_angle_reference() {
            return Err(user_msg(format!(
                "{label}: the trial has no reference angle column (`thigh_ref`, `knee_ref`, ...), so there is nothing to evaluate against"
            )));
        }
        let bound = max_lag_bound(cols.len() as u64);
        if max_lag as u64 > bound {
            return Err(user_msg(format!(
                "max_lag {max_lag}: a maximum lag of {max_lag} samples is longer than half the trial {label} ({} samples): at most {bound}, so that every lag searched compares at least half the trial",
                cols.len()
            )));
        }
        if view.len() != cols.len() {
            return Err(user_msg(format!(
                "the estimate has {} samples but the trial {label} has {} (an estimate must have its trial's time base)",
                view.len(),
                cols.len()
            )));
        }
        let method = estimate.header("method").unwrap_or("unknown").to_string();
        let options = EvalOptions {
            window,
            offset_free,
            max_lag,
            allow_trial_mismatch,
        };
        crate::interrupt::detach(py, || {
            let mut metrics = AngleMetrics::new(method, options);
            metrics.set_carried_channels(view.carried_angles());
            metrics.set_diagnostic_names(view.diag.iter().map(|(n, _)| n.as_str()));
            for (i, r) in cols.records().enumerate() {
                let e = view.estimate(i);
                let tol = 1e-9 * r.sample.t.abs().max(1.0);
                if (r.sample.t - e.t).abs() > tol {
                    return Err(user_msg(format!(
                        "estimate time {} s does not match the trial's sample {i} time {} s (an estimate must have its trial's time base)",
                        e.t, r.sample.t
                    )));
                }
                metrics.push(&r, &e);
                // (Ctrl-C: `detach` raises)
                if crate::interrupt::poll_current() {
                    return Ok(String::new());
                }
            }
            let ev = metrics.evaluation();
            let angles = view.content().angles;
            if let Some(why) = nothing_scored(&ev, angles, &window, &label, "the estimate") {
                return Err(user_msg(why));
            }
            Ok(ev.to_json().to_string())
        })?
    })
}

/// Refuses an estimate whose header records another trial than this one
/// (both hashes known), unless allowed, as `limbfuse evaluate` does.
pub(crate) fn check_same_trial(
    trial: &TrialArgs<'_>,
    estimate: &EstimateArgs<'_>,
    allow: bool,
) -> PyResult<()> {
    let (Some((name, hash)), Some(recorded)) = (trial.source(), estimate.header(TRIAL_HASH_KEY))
    else {
        return Ok(());
    };
    if allow || recorded == hash {
        return Ok(());
    }
    let made_from = estimate.header("trial").unwrap_or("another trial");
    Err(user_msg(format!(
        "the estimate was made from `{made_from}` ({recorded}) but the trial is `{name}` ({hash}): refusing to evaluate an estimate made from another trial (allow_trial_mismatch=True evaluates it anyway)"
    )))
}

/// A gait evaluation (`evaluate_files(trial, estimate)`: the JSON text)
/// over the trial and the estimate written to temporary files.
fn gait(
    trial: &TrialArgs<'_>,
    cols: &TrialColumns<'_>,
    estimate: &EstimateArgs<'_>,
    view: &EstimateView<'_>,
    evaluate_files: impl FnOnce(&Path, &Path) -> PyResult<String>,
) -> PyResult<String> {
    let dir = tempfile::tempdir().map_err(temporary_files)?;
    let tp = write_trial(dir.path(), trial, cols)?;
    let ep = write_estimate(dir.path(), estimate, view)?;
    evaluate_files(&tp, &ep)
}

fn temporary_files(e: std::io::Error) -> PyErr {
    user_msg(format!("temporary files: {e}"))
}

/// Writes `trial` to a file in `dir` (named as its source when it has one); its path.
pub(crate) fn write_trial(
    dir: &Path,
    trial: &TrialArgs<'_>,
    cols: &TrialColumns<'_>,
) -> PyResult<PathBuf> {
    let io = temporary_files;
    let tp = dir.join(trial.source().map_or("trial.csv", |s| s.0.as_str()));
    let mut f = std::io::BufWriter::new(std::fs::File::create(&tp).map_err(io)?);
    let mut w = TrialWriter::for_path(&tp, &mut f, &trial.meta(), *cols.layout()).map_err(io)?;
    for r in cols.records() {
        w.write(&r).map_err(io)?;
    }
    w.finish().map_err(io)?;
    Ok(tp)
}

/// Writes `estimate` to `dir/estimate.csv` without its `trial` header
/// lines (the caller checks the trial); its path.
pub(crate) fn write_estimate(
    dir: &Path,
    estimate: &EstimateArgs<'_>,
    view: &EstimateView<'_>,
) -> PyResult<PathBuf> {
    let io = temporary_files;
    let ep = dir.join("estimate.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&ep).map_err(io)?);
    for l in &estimate.0 {
        // The temporary trial is not the file the estimate recorded:
        // the trial check was done by the caller.
        if l.starts_with("trial") {
            continue;
        }
        writeln!(f, "# {l}").map_err(io)?;
    }
    writeln!(f, "{}", view.file_columns().join(",")).map_err(io)?;
    let mut line = Vec::new();
    let mut buf = ryu::Buffer::new();
    for i in 0..view.len() {
        line.clear();
        view.write_row(i, &mut line, &mut buf);
        f.write_all(&line).map_err(io)?;
    }
    f.flush().map_err(io)?;
    Ok(ep)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    Ok(())
}
