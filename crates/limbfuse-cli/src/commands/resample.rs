//! `limbfuse resample TRIAL --rate HZ -o OUT`.

use anyhow::{Context, Result};
use limbfuse_signal::resample::{anti_alias_said, resample_file, AntiAlias, ResampleOptions};

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
    let rej = s.rejections;
    if rej.total() > 0 {
        eprintln!(
            "warning: {}: {} gyroscope, {} accelerometer and {} encoder readings out of the \
             sensors' range (first at t = {} s) left out, as `estimate` leaves them out \
             (interpolated, they would spread into their neighbours)",
            a.trial.display(),
            rej.gyro,
            rej.acc,
            rej.encoder,
            limbfuse_methods::shown(rej.first_t.unwrap_or(f64::NAN))
        );
    }
    if s.clipped_gyro > 0 {
        eprintln!(
            "{}: {} gyroscope cells at the full scale (clipped) carried through at the rail, not \
             low-passed: `estimate` rejects them as it does at the trial's own rate, `gait-events` \
             keeps them (docs/RESULTS.md \"Clipped accelerometers\")",
            a.trial.display(),
            s.clipped_gyro
        );
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
