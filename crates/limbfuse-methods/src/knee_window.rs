//! How long the identification window of `knee-selfalign` and
//! `knee-gyro-axis` is.
//!
//! Paper 002 gives the window `s_w` in samples (500, section 3.5) for its
//! exoskeleton's 100 Hz IMUs: five seconds of motion. The window must span
//! enough motion to identify the joint axes and positions, and motion is
//! measured in seconds, not samples: the same 500 samples are two seconds at
//! the knee rig's 250 Hz, where the slow rig motion then left three of the
//! five shared trials with windows the identification could not resolve
//! (knee RMSE 24-36 deg, correlation 0.09-0.42; with five-second windows
//! 9.5 deg and 0.98 on all five, docs/RESULTS.md "knee-selfalign: the window
//! in seconds"). So unless a parameter file (`window`) or `--window` gives
//! `s_w` in samples, the window is [`DEFAULT_WINDOW_S`] seconds at the
//! trial's `# sample_rate_hz:`, which is the paper's 500 samples at 100 Hz
//! (a trial without the key is taken at the paper's 100 Hz).

use limbfuse_estimators::knee_selfalign::params::WINDOW_SAMPLES;
use limbfuse_io::TrialMeta;

use crate::{MethodError, MethodName, MethodSpec};

/// The identification window (samples) `spec` uses on a trial with `meta`:
/// `knee-selfalign`'s and `knee-gyro-axis`'s; 0 for other methods.
pub fn identification_window(spec: &MethodSpec, meta: &TrialMeta) -> Result<usize, MethodError> {
    match spec {
        MethodSpec::KneeSelfAlign(s) => s.for_trial(meta).map(|p| p.window),
        MethodSpec::KneeGyroAxis(s) => s.for_trial(meta).map(|p| p.axes.window),
        _ => Ok(0),
    }
}

/// Paper 002's window, `s_w = 500` samples at its 100 Hz, as a duration (s)
/// (the estimators' constant: a controller builds the same window with
/// `KneeSelfAlignParams::at_rate`).
pub use limbfuse_estimators::knee_selfalign::params::DEFAULT_WINDOW_S;

/// The rate a trial without `# sample_rate_hz:` is taken at: paper 002's
/// 100 Hz, so that such a trial gets the paper's `s_w = 500`.
const PAPER_RATE_HZ: f64 = 100.0;

/// The window as a parameter file or a flag gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WindowLength {
    /// `s_w` in samples (`window` key, `--window`): used as given.
    Samples(usize),
    /// A duration (s; `window_s` key): samples at the trial's rate.
    Seconds(f64),
}

impl Default for WindowLength {
    fn default() -> Self {
        WindowLength::Seconds(DEFAULT_WINDOW_S)
    }
}

impl WindowLength {
    /// The window from the `--window` flag and the file's `window` /
    /// `window_s` keys (the flag first; a file with both keys is an error).
    pub fn resolve(
        method: MethodName,
        flag: Option<usize>,
        samples: Option<usize>,
        seconds: Option<f64>,
    ) -> Result<Self, MethodError> {
        if let (Some(_), Some(_)) = (samples, seconds) {
            return Err(MethodError::KneeWindow {
                method,
                message: "the parameter file gives both `window` (samples) and `window_s` \
                          (seconds): keep one"
                    .into(),
            });
        }
        if let Some(s) = seconds.filter(|s| !(s.is_finite() && (0.2..=1000.0).contains(s))) {
            return Err(MethodError::KneeWindow {
                method,
                message: format!("`window_s = {s}`: expected a duration of 0.2 to 1000 s"),
            });
        }
        Ok(match (flag.or(samples), seconds) {
            (Some(n), _) => WindowLength::Samples(n),
            (None, Some(s)) => WindowLength::Seconds(s),
            (None, None) => WindowLength::default(),
        })
    }

    /// `s_w` in samples for a trial with this metadata.
    pub fn samples(self, method: MethodName, meta: &TrialMeta) -> Result<usize, MethodError> {
        match self {
            WindowLength::Samples(n) => Ok(n),
            WindowLength::Seconds(s) => {
                let rate = trial_rate(meta, method, &format!("the window of {s} s"))?;
                let n = (s * rate).round();
                let (lo, hi) = WINDOW_SAMPLES;
                if !(lo as f64..=hi as f64).contains(&n) {
                    // (an audit: `# sample_rate_hz: 1e308` blamed `--window`)
                    return Err(MethodError::KneeWindow {
                        method,
                        message: format!(
                            "the window of {s} s is {} samples at the trial's rate of {} Hz{}: \
                             expected {lo} to {hi} samples (check the rate, or give the window \
                             in samples with --window N)",
                            crate::error::shown(n),
                            crate::error::shown(rate),
                            if meta.get("sample_rate_hz").is_some() {
                                " (`# sample_rate_hz:`)"
                            } else {
                                ""
                            }
                        ),
                    });
                }
                Ok(n as usize)
            }
        }
    }

    /// How a parameter file writes it (`window = N` or `window_s = S`).
    pub fn file_line(self) -> String {
        match self {
            WindowLength::Samples(n) => format!("window = {n}"),
            WindowLength::Seconds(s) => format!("window_s = {s:?}"),
        }
    }
}

/// `max_sensor_delay_s` (the largest thigh-shank time offset the knee
/// methods search) in samples at the trial's rate, rounded (a trial
/// without `# sample_rate_hz:` at the paper's 100 Hz); 0 s is 0 (the
/// search off).
pub fn delay_samples(
    seconds: f64,
    method: MethodName,
    meta: &TrialMeta,
) -> Result<usize, MethodError> {
    if seconds == 0.0 {
        return Ok(0);
    }
    let rate = trial_rate(meta, method, &format!("max_sensor_delay_s = {seconds}"))?;
    // (beyond any window: the estimator's check names `max_delay`)
    Ok((seconds * rate).round().min(1e9) as usize)
}

/// The trial's `# sample_rate_hz:` (the paper's 100 Hz without it), which
/// `what` (a duration in seconds) is counted in samples at.
fn trial_rate(meta: &TrialMeta, method: MethodName, what: &str) -> Result<f64, MethodError> {
    match meta.get("sample_rate_hz") {
        None => Ok(PAPER_RATE_HZ),
        Some(v) => v
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|r| r.is_finite() && *r > 0.0)
            .ok_or_else(|| MethodError::KneeWindow {
                method,
                message: format!(
                    "trial metadata `# sample_rate_hz: {v}`: expected a positive rate in Hz \
                     ({what} is counted in samples at it)"
                ),
            }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta(rate: Option<&str>) -> TrialMeta {
        let mut m = TrialMeta::new();
        if let Some(r) = rate {
            m.set("sample_rate_hz", r);
        }
        m
    }

    const M: MethodName = MethodName::KneeSelfAlign;

    #[test]
    fn the_default_is_the_papers_500_samples_at_100_hz_and_five_seconds_elsewhere() {
        let w = WindowLength::resolve(M, None, None, None).unwrap();
        assert_eq!(w.samples(M, &meta(Some("100"))).unwrap(), 500);
        assert_eq!(w.samples(M, &meta(None)).unwrap(), 500);
        assert_eq!(w.samples(M, &meta(Some("250"))).unwrap(), 1250);
        assert_eq!(w.samples(M, &meta(Some("204.8"))).unwrap(), 1024);
        assert_eq!(w.samples(M, &meta(Some("40"))).unwrap(), 200);
    }

    #[test]
    fn samples_given_are_used_as_given_at_any_rate() {
        let w = WindowLength::resolve(M, None, Some(300), None).unwrap();
        assert_eq!(w.samples(M, &meta(Some("250"))).unwrap(), 300);
        // the flag over the file's seconds
        let w = WindowLength::resolve(M, Some(700), None, Some(2.0)).unwrap();
        assert_eq!(w.samples(M, &meta(Some("250"))).unwrap(), 700);
        let w = WindowLength::resolve(M, None, None, Some(2.0)).unwrap();
        assert_eq!(w.samples(M, &meta(Some("250"))).unwrap(), 500);
    }

    #[test]
    fn bad_windows_and_rates_are_errors_that_name_them() {
        let e = WindowLength::resolve(M, None, Some(500), Some(5.0)).unwrap_err();
        assert!(e.to_string().contains("both `window`"), "{e}");
        for bad in [0.0, -1.0, f64::NAN, 1e9] {
            let e = WindowLength::resolve(M, None, None, Some(bad)).unwrap_err();
            assert!(e.to_string().contains("window_s"), "{e}");
        }
        let w = WindowLength::default();
        for bad in ["fast", "0", "-100", "inf"] {
            let e = w.samples(M, &meta(Some(bad))).unwrap_err();
            assert!(e.to_string().contains("sample_rate_hz"), "{e}");
        }
        // A rate that makes the window absurd names the rate, not `--window`
        // (an audit: `# sample_rate_hz: 1e308` blamed the flag and
        // `knee-selfalign` under `knee-gyro-axis`).
        for (rate, n) in [("1e308", "inf"), ("1", "5"), ("1e6", "5000000")] {
            let e = w
                .samples(MethodName::KneeGyroAxis, &meta(Some(rate)))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("method `knee-gyro-axis`")
                    && e.contains(&format!("is {n} samples"))
                    && e.contains("`# sample_rate_hz:`"),
                "{e}"
            );
        }
    }
}
