//! `limbfuse evaluate TRIAL --method NAME [--params FILE] --starts N`: paper
//! 001's validation from N starting points (`limbfuse_workflows::protocol`).

use anyhow::{anyhow, bail, Context, Result};
use limbfuse_core::{Estimator, Record};
use limbfuse_eval::TimeWindow;
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader};
use limbfuse_methods::{build, check_channels, MethodFlags, MethodName};
use limbfuse_workflows::protocol::{multi_start, plan_intervals, StartPlan};

use crate::cli::EvaluateArgs;
use crate::methods;

/// A whole trial read into memory, with its metadata and columns.
pub struct TrialInMemory {
    /// Metadata.
    pub meta: TrialMeta,
    /// Columns.
    pub layout: TrialLayout,
    /// Every record.
    pub records: Vec<Record>,
}

/// Reads a whole trial; it must have a reference angle and the columns
/// `method` needs.
pub fn read_trial(path: &std::path::Path, method: MethodName) -> Result<TrialInMemory> {
    let mut reader = TrialReader::open(path)?;
    if !reader.layout().has_angle_reference() {
        bail!(
            "{}: the trial has no reference angle column (`thigh_ref`, `knee_ref`, ...), so there is nothing to evaluate against",
            path.display()
        );
    }
    check_channels(method, reader.layout()).with_context(|| path.display().to_string())?;
    let (meta, layout) = (reader.meta().clone(), *reader.layout());
    let records = super::read_records(&mut reader)?;
    // (`tune` and `evaluate --starts` run the method over these records)
    super::warn_input_units(path, &meta, &records)?;
    Ok(TrialInMemory {
        meta,
        layout,
        records,
    })
}

/// Re-runs `--method` from each starting point and prints the averaged errors.
pub fn run(a: &EvaluateArgs) -> Result<()> {
    let Some(method) = &a.method else {
        bail!("--starts needs --method NAME: the method is re-run from each starting point");
    };
    if let Some(e) = &a.estimate {
        bail!(
            "with --method, evaluate runs the method itself from each starting point: give the trial only, not the estimate file {}",
            e.display()
        );
    }
    let spec = methods::resolve(method, a.params.as_deref(), &MethodFlags::default())?;
    let window = match &a.window {
        Some(w) => TimeWindow::parse(w).map_err(|m| anyhow!("--window: {m}"))?,
        None => TimeWindow::default(),
    };
    check_starts(a.starts.unwrap_or(1))?;
    let trial = read_trial(&a.trial, spec.method())?;
    let records = &trial.records;
    let plan = StartPlan {
        window,
        starts: a.starts.unwrap_or(1),
        length_s: a.length,
    };
    let intervals = plan_intervals(records, &plan)
        .with_context(|| format!("{}: starting points", a.trial.display()))?;
    let make = || {
        build(&spec, &trial.meta, &trial.layout)
            .map(|e| e as Box<dyn Estimator>)
            .map_err(|e| e.to_string())
    };
    let r = multi_start(&make, records, &intervals, a.offset_free)
        .with_context(|| format!("evaluating {} on {}", method, a.trial.display()))?;
    if a.json {
        println!("{}", r.to_json());
    } else {
        print!("{}", r.to_text());
    }
    Ok(())
}

/// `--starts` of `evaluate --method` and `tune`: 1 to
/// [`limbfuse_workflows::protocol::MAX_STARTS`] (an audit: `--starts 0` was
/// reported as "starting points: starts: ...", naming no flag).
pub fn check_starts(starts: usize) -> Result<()> {
    let max = limbfuse_workflows::protocol::MAX_STARTS;
    if starts == 0 || starts > max {
        bail!("--starts {starts}: expected 1 to {max} starting points");
    }
    Ok(())
}
