//! Caps on the flags that size a command's output or memory (issue 18 item
//! 7): a typo such as `--duration 1e8` must not start writing terabytes.
//!
//! A simulated trial is capped at [`MAX_DURATION_S`] (24 h) of simulated time
//! and [`MAX_SAMPLES`] samples unless `--force`: 24 h is the longest run the
//! project needs (the 24-hour soak of issue 18) and already a ~6 GB walking
//! trial at 100 Hz (~4 MB per simulated minute). Non-finite, zero or negative
//! values are refused whatever `--force` says.

use anyhow::{bail, Result};

/// Longest simulated trial without `--force` (s): 24 h.
pub const MAX_DURATION_S: f64 = 86_400.0;

/// Most samples in a simulated trial without `--force`: 24 h at 1 kHz.
pub const MAX_SAMPLES: f64 = 86_400_000.0;

/// `value` of `flag` must be a finite number > 0.
pub fn positive(flag: &str, value: f64, unit: &str) -> Result<()> {
    if !(value.is_finite() && value > 0.0) {
        bail!(
            "{flag} {}: expected a positive number of {unit}",
            limbfuse_methods::shown(value)
        );
    }
    Ok(())
}

/// Checks `--duration` and the sample rate flag `rate_flag` of a simulation:
/// positive, and within the caps unless `force`.
pub fn simulated_trial(duration_s: f64, rate_flag: &str, rate_hz: f64, force: bool) -> Result<()> {
    simulated_length("--duration", duration_s, rate_flag, rate_hz, force)
}

/// [`simulated_trial`] for a command whose length is not one flag:
/// `duration` names what makes it (`simulate calibration`: its poses, hold
/// and transition times; an audit found `--hold 1e9` reported as
/// `--duration`, a flag that command does not have).
pub fn simulated_length(
    duration: &str,
    duration_s: f64,
    rate_flag: &str,
    rate_hz: f64,
    force: bool,
) -> Result<()> {
    positive(duration, duration_s, "seconds")?;
    positive(rate_flag, rate_hz, "Hz")?;
    let d = limbfuse_methods::shown(duration_s);
    let r = limbfuse_methods::shown(rate_hz);
    // (an audit: `--duration 1e-300` was reported as the simulator's
    // `duration_s * imu_rate_hz = 0`, naming neither flag)
    if (duration_s * rate_hz).round() < 1.0 {
        bail!(
            "{duration} {d} at {rate_flag} {r}: less than one sample; expected at least one \
             sample period ({} s)",
            limbfuse_methods::shown(1.0 / rate_hz)
        );
    }
    if force {
        return Ok(());
    }
    if duration_s > MAX_DURATION_S {
        bail!(
            "{duration} {d}: longer than the cap of {MAX_DURATION_S} s (24 h of simulated time; \
             24 h of walking at 100 Hz is a ~6 GB trial file); pass --force to simulate it anyway"
        );
    }
    let samples = duration_s * rate_hz;
    if samples > MAX_SAMPLES {
        bail!(
            "{duration} {d} at {rate_flag} {r}: {samples:.3e} samples, more than the cap of \
             {MAX_SAMPLES:.3e} (24 h at 1 kHz); pass --force to simulate it anyway"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caps_hold_unless_forced_and_bad_numbers_never_pass() {
        assert!(simulated_trial(60.0, "--rate", 100.0, false).is_ok());
        assert!(simulated_trial(86_400.0, "--rate", 1000.0, false).is_ok());
        let e = simulated_trial(1e8, "--rate", 100.0, false)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--duration 100000000") && e.contains("--force"),
            "{e}"
        );
        assert!(simulated_trial(1e8, "--rate", 100.0, true).is_ok());
        let e = simulated_trial(60.0, "--imu-rate", 1e9, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--imu-rate"), "{e}");
        for bad in [f64::NAN, f64::INFINITY, -1.0, 0.0] {
            assert!(simulated_trial(bad, "--rate", 100.0, true).is_err());
            assert!(simulated_trial(60.0, "--rate", bad, true).is_err());
        }
    }
}
