//! `limbfuse estimate --method NAME TRIAL -o OUT`: flags -> method spec ->
//! estimator -> runner -> estimate file.

use std::path::Path;

use anyhow::{Context, Result};
use limbfuse_core::runner::{self, Observer};
use limbfuse_core::Estimator;
use limbfuse_eval::ResetWatch;
use limbfuse_io::{EstimateWriter, TrialReader};

use crate::cli::EstimateArgs;
use crate::exit::Internal;
use crate::methods;
use crate::progress::Progress;

/// Whether any estimate carried a contact state or a walking speed.
#[derive(Debug, Default)]
struct GaitWatch {
    found: bool,
}

impl Observer for GaitWatch {
    fn observe(
        &mut self,
        _record: &limbfuse_core::Record,
        e: &limbfuse_core::Estimate,
    ) -> Result<(), runner::BoxError> {
        self.found |= e.speed.is_some() || e.contact.iter().any(Option::is_some);
        Ok(())
    }
}

/// Runs one estimator over a trial file, streaming.
pub fn run(a: &EstimateArgs) -> Result<()> {
    let spec = methods::resolve(&a.method, a.params.as_deref(), &methods::flags(a))?;
    let reader = TrialReader::open(&a.trial)?;
    let mut est = methods::build_for(&spec, &reader)?;
    let outputs = est.outputs();
    // Gait methods (contacts, or a speed without a CoM model): a recording
    // in which they find no gait is an error, not an empty estimate.
    let gait_method = outputs.contact || (outputs.speed && !outputs.com);
    let mut gait = GaitWatch::default();
    let n = run_to_file(
        est.as_mut(),
        reader,
        &a.output,
        spec.method().name(),
        &mut [&mut gait],
    )?;
    if gait_method && !gait.found {
        let _ = std::fs::remove_file(&a.output);
        anyhow::bail!(
            "no gait found in {}: `{}` detected no foot contact and no walking speed in {n} samples \
             (the recording has no walking, or the IMU is not where the method expects it); no estimate written",
            a.trial.display(),
            spec.method()
        );
    }
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
    mut reader: TrialReader,
    output: &Path,
    label: &str,
    extra: &mut [&mut dyn Observer],
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
        runner::run(est, &mut reader, &mut observers)
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
