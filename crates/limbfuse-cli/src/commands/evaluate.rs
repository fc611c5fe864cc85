//! `limbfuse evaluate TRIAL ESTIMATE [--json] [--window A:B] [--offset-free] [--max-lag N]`.

use anyhow::{anyhow, Result};
use limbfuse_eval::{
    evaluate_files_scored, EvalError, EvalOptions, EvaluationKind, TimeWindow, TrialCheck,
};

use limbfuse_eval::stride_table::{evaluation_and_stride_table, StrideTable};

use crate::cli::EvaluateArgs;

/// Prints a gait evaluation (JSON or text) after the trial-check warning.
fn print_gait(
    json: bool,
    check: &TrialCheck,
    value: serde_json::Value,
    text: impl FnOnce() -> String,
) {
    warn(check);
    if json {
        println!("{value}");
    } else {
        print!("{}", text());
    }
}

/// Writes the stride table of `estimate` with the references of `trial`
/// (`--strides`; docs/GAIT_EVENTS.md "Stride table") atomically.
fn write_strides(path: &std::path::Path, table: &StrideTable) -> Result<()> {
    let mut file = super::create_file(path)?;
    let mut w = std::io::BufWriter::new(&mut file);
    table
        .write_csv(&mut w)
        .and_then(|()| std::io::Write::flush(&mut w))
        .map_err(|e| anyhow!("{}: cannot write the output file: {e}", path.display()))?;
    drop(w);
    super::commit(file)
}

/// `--strides` with an estimate scored for `what` (no strides): refused.
fn strides_refused(a: &EvaluateArgs, what: &str) -> Result<()> {
    if a.strides.is_some() {
        anyhow::bail!(
            "--strides: the estimate is scored for {what} and has no strides (a stride table is \
             made from `gait-events` and `lowback-speed` estimates)"
        );
    }
    Ok(())
}

/// Prints the errors of an estimate against its trial's reference.
pub fn run(a: &EvaluateArgs) -> Result<()> {
    if a.method.is_some() || a.starts.is_some() {
        strides_refused(a, "the joint angles of --method")?;
        return super::protocol::run(a);
    }
    let Some(estimate) = &a.estimate else {
        anyhow::bail!(
            "evaluate needs an ESTIMATE file, or --method NAME [--params FILE] [--starts N] to run the method on the trial"
        );
    };
    super::refuse_read_twice_from_a_stream("evaluate", &[&a.trial, estimate])?;
    super::refuse_overwrites(
        &[("", Some(&a.trial)), ("", Some(estimate))],
        &[("--strides", a.strides.as_deref())],
    )?;
    let window = match &a.window {
        Some(w) => TimeWindow::parse(w).map_err(|m| anyhow!("--window: {m}"))?,
        None => TimeWindow::default(),
    };
    // Options of the angle evaluation that an event or gait evaluation
    // cannot honour: refused rather than silently ignored.
    let angle_only = |what: &str, window_too: bool| -> Result<()> {
        let mut given = Vec::new();
        if window_too && a.window.is_some() {
            given.push("--window");
        }
        if a.offset_free {
            given.push("--offset-free");
        }
        if a.max_lag > 0 {
            given.push("--max-lag");
        }
        if given.is_empty() {
            return Ok(());
        }
        anyhow::bail!(
            "{}: {} to angle errors only; {} is scored for {what}",
            given.join(", "),
            if given.len() == 1 { "applies" } else { "apply" },
            estimate.display()
        )
    };
    let assumed_zero = {
        let reader = limbfuse_io::TrialReader::open(&a.trial)?;
        let layout = *reader.layout();
        let (trial, mismatch) = (&a.trial, a.allow_trial_mismatch);
        let content =
            limbfuse_eval::EstimateContent::of_file(&limbfuse_io::EstimateReader::open(estimate)?);
        match limbfuse_eval::evaluation_kind(&layout, content) {
            EvaluationKind::GaitEvents => {
                // Gait events, contacts, phase and stride speed (docs/GAIT_EVENTS.md).
                angle_only("gait events and walking speed", false)?;
                let ev = match &a.strides {
                    // One scoring for both (the table holds the strides it scores).
                    Some(path) => {
                        let (ev, table) =
                            evaluation_and_stride_table(Some(trial), estimate, mismatch, &window)?;
                        write_strides(path, &table.map_err(EvalError::NoStrides)?)?;
                        ev
                    }
                    None => limbfuse_eval::gait_events_evaluation::evaluate_gait_event_files_in(
                        trial, estimate, mismatch, &window,
                    )?,
                };
                for w in &ev.warnings {
                    eprintln!("warning: {w}");
                }
                print_gait(a.json, &ev.trial_check, ev.to_json(), || ev.to_text());
                return Ok(());
            }
            EvaluationKind::Gait => {
                // A gait trial (paper 003): phase, CoM and speed errors.
                angle_only("gait phase, CoM and speed (paper 003)", true)?;
                strides_refused(a, "gait phase, CoM and speed (paper 003)")?;
                let ev =
                    limbfuse_eval::gait_evaluation::evaluate_gait_files(trial, estimate, mismatch)?;
                for w in &ev.cut_lines {
                    eprintln!("warning: {w}");
                }
                print_gait(a.json, &ev.trial_check, ev.to_json(), || ev.to_text());
                return Ok(());
            }
            EvaluationKind::Angles => {}
        }
        if content.events_or_speed && !content.angles && a.strides.is_some() {
            // An event estimate on a trial with no reference of its events:
            // "scored for its joint angles" would name the wrong cause.
            anyhow::bail!(
                "--strides: {} has no reference of the events and speed of {} \
                 (`contact_left_ref` / `contact_right_ref`, `speed_ref`, or `com_vx`..`com_vz`), \
                 so `evaluate` has nothing to score; the stride table without references: \
                 `limbfuse report {} {} -o report.html` (gait-events panel) or, in Python, \
                 `limbfuse.read_estimate(...).strides()`",
                trial.display(),
                estimate.display(),
                trial.display(),
                estimate.display()
            );
        }
        strides_refused(a, "its joint angles")?;
        limbfuse_eval::notes::assumed_zero_note(reader.meta(), a.offset_free)
    };
    let ev = evaluate_files_scored(
        &a.trial,
        estimate,
        EvalOptions {
            window,
            offset_free: a.offset_free,
            max_lag: a.max_lag,
            allow_trial_mismatch: a.allow_trial_mismatch,
        },
    )
    .map_err(|e| match e {
        EvalError::MaxLagTooLong { .. } => anyhow!(e).context(format!("--max-lag {}", a.max_lag)),
        EvalError::TrialMismatch(_) => anyhow!(e).context(
            "refusing to evaluate an estimate made from another trial \
             (--allow-trial-mismatch evaluates it anyway)",
        ),
        e => e.into(),
    })?;
    warn(&ev.trial_check);
    for w in &ev.cut_lines {
        eprintln!("warning: {w}");
    }
    super::warn_resets(&estimate.display().to_string(), ev.resets.as_ref());
    if let Some(w) = &ev.reference_units {
        eprintln!("warning: {}: {w}", a.trial.display());
    }
    if a.json {
        println!("{}", ev.to_json());
    } else {
        print!("{}", ev.to_text());
        if let Some(note) = &assumed_zero {
            println!("note: {note}");
        }
        if a.diagnostics {
            print!("{}", ev.diagnostics_text());
        }
    }
    Ok(())
}

/// Prints the trial check's warning, if any.
fn warn(check: &TrialCheck) {
    if let Some(w) = check.warning() {
        eprintln!("warning: {w}");
    }
}
