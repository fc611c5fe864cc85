//! Resampling a trial onto a uniform time base (`limbfuse resample`).
//!
//! Paper 001 resamples every stream (IMUs at 50 Hz, potentiometers at 1 kHz,
//! markers at 100 Hz) to 50 Hz before estimation. [`resample_trial`] does the
//! same for a trial file: the output grid is `t_k = t_first + k / rate`, `k =
//! 0, 1, ...` up to the last input time, and each channel is resampled from
//! its own *present* samples (a trial that merges a 1 kHz encoder with a 100
//! Hz IMU has empty IMU cells between IMU samples; those are not zeros).
//!
//! Per channel kind ([`ChannelMethod`]):
//! - **IMU accelerometer and gyro** (decimation, input rate above the output
//!   rate): anti-alias low-pass, by default a Blackman-windowed sinc evaluated
//!   at each output time over the input samples within `+-W`
//!   ([`AntiAlias::WindowedSinc`]): cut-off `fc = 0.35 x` output rate (17.5 Hz
//!   at 50 Hz), half-width `W = 10` output periods (0.2 s at 50 Hz). The
//!   weights are normalised by their sum, so a constant is reproduced exactly
//!   and irregular input spacing is handled. The kernel is symmetric: no
//!   phase shift (no delay). Where the kernel does not fit inside a gap-free
//!   stretch of the channel (the first and last `W` seconds, next to a
//!   dropout) the output falls back to the mean over one output period
//!   (`[t - T/2, t + T/2]`, end points weighted 1/2); with no sample in that
//!   period the output is missing. Measured response: `docs/TUNING.md` and
//!   the tests in `tests/integration/resample.rs`.
//!   The other leg's IMU channels (two-leg recordings) are IMU channels.
//! - **Gait contact references** (`contact_left_ref`, `contact_right_ref`):
//!   the nearest present sample (as gait phase labels below), so they stay 0
//!   or 1; empty cells (unknown) stay empty under the gap rules.
//! - **Everything else** (encoders, references, model inputs, CoM; IMU
//!   channels when the input rate is not above the output rate): linear
//!   interpolation between the two present samples around `t`, unless they
//!   are separated by a gap (more than 1.5 nominal input periods); the first
//!   and last present samples (of the channel, or next to a gap) extend by
//!   half a period (the longer of the input and output periods). Quaternions:
//!   normalised linear interpolation (sign-aligned). Gait phase labels:
//!   nearest present sample under the same rules. Angles are interpolated as
//!   numbers (no wrap at +-pi: sagittal limb angles stay far from it).
//!
//! Readings no sensor can produce (outside the sensors' range or not
//! finite: [`limbfuse_core::SampleGate`] with the trial's
//! `gyro_range_rad_s` / `acc_range_m_s2`, as every estimator screens them;
//! not its plausibility checks, under which a static recording's exactly
//! repeated readings would go, nor its clipping tests) are left out before
//! resampling: interpolated, one 1e308 gyro cell became a 0.4 s burst of
//! values around 1e306. They are counted ([`ResampledTrial::rejections`])
//! and named in the output's `# resampled:` line. Clipped accelerometer
//! readings are resampled with the rest (what the sensor recorded); a
//! clipped gyroscope cell is carried through at the rail to the output
//! sample nearest to it (`clip_marks`; [`ResampledTrial::clipped_gyro`]).
//!
//! Not streaming: the present samples of every channel are held in memory,
//! 16 bytes per present cell (a 10 min trial at 1 kHz with 4 IMUs, 3
//! encoders and 7 references, a 408 MB CSV file, peaks at 370 MB of RSS and
//! takes 12.6 s to 50 Hz in release). Gaps, dropouts and a channel with a
//! single sample never panic: missing stays missing.

use limbfuse_io::FileError;

mod anti_alias;
mod clip_marks;
mod interpolation;
mod short_runs;
mod trial;

pub use trial::{
    anti_alias_said, bytes_per_output_sample, resample_file, resample_notes, resample_records,
    resample_trial, ResampleSummary, ResampledTrial, MAX_RESAMPLE_BYTES,
};

/// Cut-off of the windowed-sinc anti-alias filter as a fraction of the
/// output rate: 0.35 (17.5 Hz at 50 Hz, 0.7 of the output Nyquist frequency).
pub const SINC_CUTOFF_FRACTION: f64 = 0.35;
/// Half-width of the windowed-sinc kernel in output periods: 10 (0.2 s at 50 Hz).
pub const SINC_HALF_WIDTH_PERIODS: f64 = 10.0;
/// Two successive present samples further apart than this many nominal
/// input periods are separated by a gap (no interpolation across it).
pub const GAP_FACTOR: f64 = 1.5;
/// Largest number of output times [`uniform_grid`] produces (a grid of
/// times only; [`resample_trial`] is bounded further by the memory of its
/// records, [`MAX_RESAMPLE_BYTES`]).
pub const MAX_OUTPUT_SAMPLES: usize = 100_000_000;

/// How IMU accelerometer and gyro channels are low-passed before decimation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AntiAlias {
    /// Blackman-windowed sinc, cut-off [`SINC_CUTOFF_FRACTION`] of the
    /// output rate, half-width [`SINC_HALF_WIDTH_PERIODS`] output periods
    /// (default).
    #[default]
    WindowedSinc,
    /// Mean over one output period centred on the output time.
    Boxcar,
    /// No low-pass: linear interpolation (aliases whatever is above the
    /// output Nyquist frequency).
    None,
}

impl AntiAlias {
    /// `windowed-sinc`, `boxcar` or `none`.
    pub const fn label(self) -> &'static str {
        match self {
            AntiAlias::WindowedSinc => "windowed-sinc",
            AntiAlias::Boxcar => "boxcar",
            AntiAlias::None => "none",
        }
    }
}

/// How one scalar channel is resampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelMethod {
    /// Anti-alias low-pass when the channel's input rate is above the output
    /// rate, linear interpolation otherwise.
    Decimate(AntiAlias),
    /// Linear interpolation.
    Linear,
    /// The nearest present sample (labels and 0/1 flags, such as the gait
    /// contact references: an interpolated 0.5 is no contact state).
    Nearest,
}

/// Options of [`resample_trial`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResampleOptions {
    /// Output rate (Hz), finite, > 0 and at most 100 kHz.
    pub rate_hz: f64,
    /// Low-pass of the IMU channels.
    pub anti_alias: AntiAlias,
}

impl ResampleOptions {
    /// Resampling to `rate_hz` with the default windowed-sinc anti-alias filter.
    pub fn new(rate_hz: f64) -> Self {
        ResampleOptions {
            rate_hz,
            anti_alias: AntiAlias::WindowedSinc,
        }
    }
}

/// Why resampling failed.
#[derive(Debug, thiserror::Error)]
pub enum ResampleError {
    /// The input could not be read or the output written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A bad option or an input that cannot be resampled.
    #[error("{0}")]
    Invalid(String),
    /// The caller's cancellation hook asked to stop ([`resample_records`]).
    #[error("cancelled")]
    Cancelled,
}

/// The present samples of one scalar channel, in time order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    /// Times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Values.
    pub v: Vec<f64>,
}

impl Series {
    pub(super) fn push(&mut self, t: f64, v: Option<f64>) {
        if let Some(v) = v {
            self.t.push(t);
            self.v.push(v);
        }
    }
}

/// The uniform output grid `t_first + k / rate` up to `t_last` (inclusive,
/// with a 1e-9-period tolerance).
pub fn uniform_grid(t_first: f64, t_last: f64, rate_hz: f64) -> Result<Vec<f64>, ResampleError> {
    check_rate(rate_hz)?;
    if !(t_first.is_finite() && t_last.is_finite()) || t_last < t_first {
        return Err(ResampleError::Invalid(format!(
            "cannot build a time grid from {} s to {} s",
            limbfuse_core::ShownNumber(t_first),
            limbfuse_core::ShownNumber(t_last)
        )));
    }
    let n = ((t_last - t_first) * rate_hz + 1e-9).floor() + 1.0;
    if n < 2.0 && t_last > t_first {
        // (an audit: `--rate 1e-300` wrote a one-sample trial, exit 0)
        return Err(ResampleError::Invalid(format!(
            "rate {} Hz: the trial's {} s give one sample at it; expected at least {} Hz (two samples)",
            limbfuse_core::ShownNumber(rate_hz),
            t_last - t_first,
            limbfuse_core::ShownNumber(1.0 / (t_last - t_first))
        )));
    }
    if n > MAX_OUTPUT_SAMPLES as f64 {
        return Err(ResampleError::Invalid(format!(
            "{} s to {} s at {} Hz is {} samples, more than the limit of {MAX_OUTPUT_SAMPLES}",
            limbfuse_core::ShownNumber(t_first),
            limbfuse_core::ShownNumber(t_last),
            limbfuse_core::ShownNumber(rate_hz),
            limbfuse_core::ShownNumber(n)
        )));
    }
    Ok((0..n as usize)
        .map(|k| t_first + k as f64 / rate_hz)
        .collect())
}

/// `Ok` for a finite rate above 0 and at most 100 kHz.
pub(super) fn check_rate(rate_hz: f64) -> Result<(), ResampleError> {
    if rate_hz.is_finite() && rate_hz > 0.0 && rate_hz <= 100_000.0 {
        Ok(())
    } else {
        Err(ResampleError::Invalid(format!(
            "rate: expected a rate in Hz above 0 and at most 100000, found {}",
            limbfuse_core::ShownNumber(rate_hz)
        )))
    }
}

/// Resamples one scalar channel onto `grid` (output rate `rate_hz`).
///
/// `s.t` must be strictly increasing (as a trial file's times are).
pub fn resample_series(
    s: &Series,
    grid: &[f64],
    rate_hz: f64,
    method: ChannelMethod,
) -> Vec<Option<f64>> {
    let period_out = 1.0 / rate_hz;
    let anti_alias = match method {
        ChannelMethod::Decimate(a) => a,
        ChannelMethod::Linear => AntiAlias::None,
        ChannelMethod::Nearest => {
            return short_runs::nearest_keeping_runs(&s.t, &s.v, grid, period_out)
        }
    };
    let Some(p_in) = interpolation::nominal_period(&s.t) else {
        return interpolation::linear(s, grid, period_out);
    };
    // Not a decimation (input rate not above the output rate): interpolate.
    if anti_alias == AntiAlias::None || p_in >= period_out * (1.0 - 1e-9) {
        return interpolation::linear(s, grid, period_out);
    }
    if anti_alias == AntiAlias::Boxcar {
        return grid
            .iter()
            .map(|&tg| anti_alias::boxcar_at(s, tg, period_out))
            .collect();
    }
    anti_alias::windowed_sinc(s, grid, rate_hz, p_in)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_uniform_and_inclusive() {
        let g = uniform_grid(0.0, 1.0, 50.0).unwrap();
        assert_eq!(g.len(), 51);
        assert_eq!(g[50], 1.0);
        assert!(uniform_grid(0.0, 1.0, 0.0).is_err());
        assert!(uniform_grid(0.0, 1e12, 1000.0).is_err());
    }

    #[test]
    fn single_sample_and_empty_series_do_not_panic() {
        let grid = uniform_grid(0.0, 1.0, 10.0).unwrap();
        let one = Series {
            t: vec![0.5],
            v: vec![2.0],
        };
        let out = resample_series(
            &one,
            &grid,
            10.0,
            ChannelMethod::Decimate(AntiAlias::WindowedSinc),
        );
        assert_eq!(out[5], Some(2.0));
        assert_eq!(out[0], None);
        let none = resample_series(&Series::default(), &grid, 10.0, ChannelMethod::Linear);
        assert!(none.iter().all(Option::is_none));
    }
}
