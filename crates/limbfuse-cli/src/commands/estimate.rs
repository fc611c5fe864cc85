//! `limbfuse estimate --method NAME TRIAL -o OUT`: flags -> method spec ->
//! estimator -> runner -> estimate file.

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::Estimator;
use limbfuse_eval::ResetWatch;
use limbfuse_io::{Calibration, EstimateWriter, TrialReader};

use crate::cli::EstimateArgs;
use crate::exit::Internal;
use crate::methods;
use crate::progress::Progress;

/// Runs one estimator over a trial file, streaming.
pub fn run(a: &EstimateArgs) -> Result<()> {
    let spec = methods::resolve(&a.method, a.params.as_deref(), &methods::flags(a))?;
    let reader = TrialReader::open(&a.trial)?;
    let mut est = methods::build_for(&spec, &reader)?;
    let calibration = match &a.calibration {
        Some(path) => Some(
            super::calibrate::load_for_trial(path, &a.trial, reader.meta(), reader.layout())?.0,
        ),
        None => None,
    };
    let n = run_to_file_calibrated(
        est.as_mut(),
        reader,
        &a.output,
        spec.method().name(),
        &mut [],
        calibration.as_ref(),
    )?;
    eprintln!("{}: {n} samples -> {}", spec.method(), a.output.display());
    Ok(())
}

/// Runs an estimator over an opened trial into an estimate file, with a
/// progress bar and the `extra` observers; warns on stderr when the
/// estimator restarted during the run (issue 16); returns the number of
/// samples.
///
/// The estimate file records its trial (`# trial:`, `# trial_hash:`; the
/// trial is hashed as it is read) and appears only if the whole run succeeds.
pub fn run_to_file(
    est: &mut dyn Estimator,
    reader: TrialReader,
    output: &Path,
    label: &str,
    extra: &mut [&mut dyn Observer],
) -> Result<u64> {
    run_to_file_calibrated(est, reader, output, label, extra, None)
}

/// [`run_to_file`] with an IMU calibration applied to every record read
/// (docs/CALIBRATION.md).
pub fn run_to_file_calibrated(
    est: &mut dyn Estimator,
    mut reader: TrialReader,
    output: &Path,
    label: &str,
    extra: &mut [&mut dyn Observer],
    calibration: Option<&Calibration>,
) -> Result<u64> {
    let trial = reader.path().to_path_buf();
    let trial_name = trial.file_name().map_or_else(
        || trial.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let mut writer = EstimateWriter::new(super::create_file(output)?).recording_trial(trial_name);
    let mut progress = Progress::new(label);
    let mut resets = ResetWatch::default();
    let summary = {
        let mut observers: Vec<&mut dyn Observer> = Vec::with_capacity(3 + extra.len());
        observers.push(&mut writer);
        observers.push(&mut progress);
        observers.push(&mut resets);
        for o in extra.iter_mut() {
            observers.push(&mut **o);
        }
        let source = reader.by_ref().map(|r| {
            r.map(|mut rec| {
                if let Some(c) = calibration {
                    c.apply(&mut rec);
                }
                rec
            })
        });
        runner::run(est, source, &mut observers)
            .with_context(|| format!("estimating {} with {label}", trial.display()))?
    };
    let hash = reader.content_hash().ok_or_else(|| {
        Internal(format!(
            "{}: the trial was not read to its end",
            trial.display()
        ))
    })?;
    let write_err = || format!("{}: cannot write the output file", output.display());
    writer.stamp_trial_hash(hash).with_context(write_err)?;
    super::commit(writer.into_inner().with_context(write_err)?)?;
    super::warn_resets(
        &format!("{label} on {}", trial.display()),
        resets.resets().as_ref(),
    );
    Ok(summary.n_samples)
}
