//! `limbfuse resample TRIAL --rate HZ -o OUT`.

use anyhow::{Context, Result};
use limbfuse_signal::resample::{
    anti_alias_said, resample_file, resample_notes, AntiAlias, ResampleOptions,
};

use crate::cli::{AntiAliasArg, ResampleArgs};

/// Resamples a trial onto a uniform time base (not streaming: see
/// `limbfuse_signal::resample`).
pub fn run(a: &ResampleArgs) -> Result<()> {
    super::refuse_stdout(&a.output)?;
    super::refuse_input_as_output(&a.trial, &a.output)?;
    let opts = ResampleOptions {
        rate_hz: a.rate,
        anti_alias: match a.anti_alias {
            AntiAliasArg::Sinc => AntiAlias::WindowedSinc,
            AntiAliasArg::Boxcar => AntiAlias::Boxcar,
            AntiAliasArg::None => AntiAlias::None,
        },
    };
    let s = resample_file(&a.trial, &a.output, &opts).with_context(|| {
        format!(
            "resampling {} to {} Hz",
            a.trial.display(),
            limbfuse_methods::shown(a.rate)
        )
    })?;
    if let Some(cut) = s.cut_last_line {
        eprintln!("warning: {}", cut.message(&a.trial));
    }
    let (rejected, clipped) = resample_notes(&a.trial, &s.rejections, s.clipped_gyro);
    if let Some(w) = rejected {
        eprintln!("warning: {w}");
    }
    if let Some(n) = clipped {
        eprintln!("{n}");
    }
    eprintln!(
        "resampled {} to {} Hz (IMU anti-alias: {}): {} samples, {} s to {} s -> {}",
        a.trial.display(),
        a.rate,
        anti_alias_said(opts.anti_alias, s.imu_filtered),
        s.n_samples,
        s.span.0,
        s.span.1,
        a.output.display()
    );
    Ok(())
}
