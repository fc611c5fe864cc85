//! `limbfuse estimate --method NAME TRIAL -o OUT`: flags -> method spec ->
//! estimator -> runner -> estimate file.

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::Estimator;
use limbfuse_eval::ResetWatch;
use limbfuse_io::{EstimateWriter, TrialReader};

use crate::cli::EstimateArgs;
use crate::methods;
use crate::progress::Progress;

/// Runs one estimator over a trial file, streaming.
pub fn run(a: &EstimateArgs) -> Result<()> {
    let spec = methods::resolve(&a.method, a.params.as_deref(), &methods::flags(a))?;
    let reader = TrialReader::open(&a.trial)?;
    let mut est = methods::build_for(&spec, &reader)?;
    let n = run_to_file(est.as_mut(), reader, &a.output, spec.method().name())?;
    eprintln!("{}: {n} samples -> {}", spec.method(), a.output.display());
    Ok(())
}

/// Runs an estimator over an opened trial into an estimate file, with a
/// progress bar; warns on stderr when the estimator restarted during the
/// run (issue 16); returns the number of samples.
pub fn run_to_file(
    est: &mut dyn Estimator,
    reader: TrialReader,
    output: &Path,
    label: &str,
) -> Result<u64> {
    let trial = reader.path().to_path_buf();
    let mut writer = EstimateWriter::new(super::create_file(output)?);
    let mut progress = Progress::new(label);
    let mut resets = ResetWatch::default();
    let observers: &mut [&mut dyn Observer] = &mut [&mut writer, &mut progress, &mut resets];
    let summary = runner::run(est, reader, observers)
        .with_context(|| format!("estimating {} with {label}", trial.display()))?;
    super::warn_resets(
        &format!("{label} on {}", trial.display()),
        resets.resets().as_ref(),
    );
    Ok(summary.n_samples)
}
