//! `limbfuse report TRIAL EST... -o report.html` (docs/REPORT.md).

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Result};
use limbfuse_eval::TimeWindow;
use limbfuse_report::{render, ReportInput, Scoring};

use crate::cli::ReportArgs;

/// Writes the HTML report.
pub fn run(a: &ReportArgs) -> Result<()> {
    let mut inputs = vec![("", Some(a.trial.as_path()))];
    inputs.extend(a.estimates.iter().map(|e| ("", Some(e.as_path()))));
    super::refuse_overwrites(&inputs, &[("-o", Some(&a.output))])?;
    let read: Vec<&Path> = inputs.iter().filter_map(|(_, p)| *p).collect();
    super::refuse_read_twice_from_a_stream("report", &read)?;
    if a.buckets == 0 {
        bail!("--buckets: expected a positive number of display buckets, found 0");
    }
    let scoring = Scoring {
        window: match &a.window {
            Some(w) => TimeWindow::parse(w).map_err(|m| anyhow!("--window: {m}"))?,
            None => TimeWindow::default(),
        },
        offset_free: a.offset_free,
        max_lag: a.max_lag,
    };
    let mut command = command_line(&a.trial, &a.estimates, &a.output, a.buckets);
    if a.allow_trial_mismatch {
        command.push_str(" --allow-trial-mismatch");
    }
    command.push_str(&scoring.flags());
    let input = ReportInput {
        buckets: a.buckets,
        allow_trial_mismatch: a.allow_trial_mismatch,
        scoring,
        ..ReportInput::new(&a.trial, &a.estimates, command)
    };
    let n = write(&input, &a.output)?;
    eprintln!(
        "report: {} estimate(s) of {} -> {} ({:.2} MB)",
        a.estimates.len(),
        a.trial.display(),
        a.output.display(),
        n as f64 / 1e6
    );
    Ok(())
}

/// Renders `input` into `output` (atomically); returns its size in bytes.
pub fn write(input: &ReportInput, output: &Path) -> Result<usize> {
    let html = render(input).map_err(|e| match e {
        limbfuse_report::ReportError::Eval(limbfuse_eval::EvalError::TrialMismatch(_)) => {
            anyhow::anyhow!(e).context(
                "refusing to report an estimate made from another trial \
                 (--allow-trial-mismatch reports it anyway, with a warning)",
            )
        }
        limbfuse_report::ReportError::Eval(limbfuse_eval::EvalError::MaxLagTooLong { .. }) => {
            anyhow::anyhow!(e).context(format!("--max-lag {}", input.scoring.max_lag))
        }
        e => e.into(),
    })?;
    super::write_file(output, &html)?;
    Ok(html.len())
}

/// The command as the report records it (paths as given).
pub fn command_line(trial: &Path, estimates: &[PathBuf], output: &Path, buckets: usize) -> String {
    let word = |p: &Path| super::shell_word(&p.display().to_string()).into_owned();
    let mut c = format!("limbfuse report {}", word(trial));
    for e in estimates {
        c.push(' ');
        c.push_str(&word(e));
    }
    c.push_str(&format!(" -o {}", word(output)));
    if buckets != limbfuse_report::DEFAULT_BUCKETS {
        c.push_str(&format!(" --buckets {buckets}"));
    }
    c
}
