//! `limbfuse estimate --method NAME TRIAL -o OUT`.

use anyhow::{bail, Context, Result};
use limbfuse_core::runner::{self, Observer};
use limbfuse_io::{EstimateWriter, TrialReader};

use crate::cli::EstimateArgs;
use crate::methods;
use crate::progress::Progress;

/// Runs one estimator over a trial file, streaming.
pub fn run(a: &EstimateArgs) -> Result<()> {
    let knee = methods::KneeOptions {
        window: a.window,
        order: a.order,
    };
    if a.method != "knee-selfalign" && knee != methods::KneeOptions::default() {
        bail!(
            "--window and --order apply to method knee-selfalign only, not to `{}`",
            a.method
        );
    }
    if a.method == "imm-bslip" {
        let options = super::gait::ImmOptions {
            library: a.library.as_deref(),
            kappa: a.kappa,
            rescale_height: a.rescale_height,
            weights: a.imm_weights.as_deref(),
            touchdown: a.imm_touchdown.as_deref(),
        };
        let mut est = super::gait::imm_estimator(&a.trial, &options)?;
        let n = super::gait::run_estimator(est.as_mut(), &a.trial, &a.output, &a.method)?;
        eprintln!("{}: {n} samples -> {}", a.method, a.output.display());
        return Ok(());
    }
    if a.library.is_some()
        || a.kappa.is_some()
        || a.rescale_height.is_some()
        || a.imm_weights.is_some()
        || a.imm_touchdown.is_some()
    {
        anyhow::bail!(
            "--library, --kappa, --rescale-height, --imm-weights and --imm-touchdown apply to --method imm-bslip only"
        );
    }
    let reader = TrialReader::open(&a.trial)?;
    methods::check_trial_channels(&a.method, reader.layout(), &a.trial)?;
    let mut est = if a.method == "knee-selfalign" {
        methods::knee_selfalign(&knee, a.params.as_deref())?
    } else if methods::FROM_TRIAL.contains(&a.method.as_str()) {
        super::fes::build(&a.method, a.params.as_deref(), &reader)?
    } else {
        methods::build(&a.method, a.params.as_deref())?
    };
    let mut writer = EstimateWriter::new(super::create_file(&a.output)?);
    let mut progress = Progress::new(&a.method);
    let observers: &mut [&mut dyn Observer] = &mut [&mut writer, &mut progress];
    let summary = runner::run(est.as_mut(), reader, observers)
        .with_context(|| format!("estimating {} with {}", a.trial.display(), a.method))?;
    eprintln!(
        "{}: {} samples -> {}",
        a.method,
        summary.n_samples,
        a.output.display()
    );
    Ok(())
}
