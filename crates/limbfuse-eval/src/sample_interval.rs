//! What `estimate` says when a trial's time column does not look like
//! seconds (SPEC section 2: `t` in seconds).
//!
//! Loggers often write milliseconds or microseconds. Read as seconds, a
//! 100 Hz recording in milliseconds steps by 10 s: every estimator then
//! sees a long gap at every sample and restarts (measured on a simulated
//! walk with `t` x 1000: `mjls` restarted at 299 of 300 samples and the
//! only warning was the restart count). [`SampleIntervalWatch`] takes the
//! median step of the first [`FIRST_INTERVALS`] samples (a median, so
//! jitter and a few dropouts do not count) and compares it with the
//! trial's `# sample_rate_hz:` when it has one, else with the slowest rate
//! a body-worn IMU records gait at ([`SLOWEST_PLAUSIBLE_HZ`]). The CLI
//! prints what it finds as a warning; the estimate is still written.

use std::fmt;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Record, ShownNumber};

/// Steps looked at: the first 64 (0.64 s at 100 Hz; enough for a median
/// that one dropout or a jittered clock does not move).
pub const FIRST_INTERVALS: usize = 64;

/// Below this rate no trial is taken to be sampled (Hz) when its metadata
/// states none: gait IMUs sample at 50-1000 Hz, and a step of a second or
/// more cannot follow a stride of about one second.
pub const SLOWEST_PLAUSIBLE_HZ: f64 = 2.0;

/// How far the median step may lie from the stated rate's (ratio): 25 %
/// covers a stated nominal rate against a device's actual clock; a unit
/// error is a factor of 1000.
const STATED_TOLERANCE: f64 = 1.25;

/// A time column whose steps contradict its stated rate, or are slower
/// than any gait recording.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntervalMismatch {
    /// Median step of the first samples (in the file's units, read as s).
    pub median_step: f64,
    /// Steps the median was taken over.
    pub steps: usize,
    /// The trial's `# sample_rate_hz:`, if any.
    pub stated_hz: Option<f64>,
}

impl IntervalMismatch {
    /// The unit the steps look like: the expected step (the stated rate's,
    /// else 10 ms) times 1000 is milliseconds, times 10^6 microseconds.
    pub fn unit_hint(&self) -> Option<(&'static str, f64)> {
        let expected = self.stated_hz.map_or(0.01, |hz| 1.0 / hz);
        let ratio = self.median_step / expected;
        [("milliseconds", 1e3), ("microseconds", 1e6)]
            .into_iter()
            .find(|(_, f)| {
                let r = ratio / f;
                if self.stated_hz.is_some() {
                    (1.0 / STATED_TOLERANCE..=STATED_TOLERANCE).contains(&r)
                } else {
                    // no stated rate: any rate of 10-1000 Hz in that unit
                    (0.1..=10.0).contains(&r)
                }
            })
    }
}

impl fmt::Display for IntervalMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let step = self.median_step;
        write!(
            f,
            "the time column `t` steps by a median {} over its first {} samples, i.e. {} Hz if `t` is in seconds",
            ShownNumber(step),
            self.steps + 1,
            ShownNumber(1.0 / step)
        )?;
        match self.stated_hz {
            Some(hz) => write!(
                f,
                ", but the trial's `# sample_rate_hz: {}` means steps of {} s",
                ShownNumber(hz),
                ShownNumber(1.0 / hz)
            )?,
            None => write!(
                f,
                ", slower than any gait recording ({SLOWEST_PLAUSIBLE_HZ} Hz)"
            )?,
        }
        write!(f, "; `t` must be in seconds (SPEC section 2)")?;
        if let Some((unit, factor)) = self.unit_hint() {
            write!(f, ": it looks like {unit} (divide `t` by {factor})")?;
        }
        Ok(())
    }
}

/// Follows the first steps of a run's time column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleIntervalWatch {
    stated_hz: Option<f64>,
    last_t: Option<f64>,
    steps: [f64; FIRST_INTERVALS],
    n: usize,
}

impl SampleIntervalWatch {
    /// A watch for a trial whose metadata states `stated_hz` (its
    /// `# sample_rate_hz:`; a value that is not a positive finite rate is
    /// taken as none).
    pub fn new(stated_hz: Option<f64>) -> Self {
        SampleIntervalWatch {
            stated_hz: stated_hz.filter(|hz| hz.is_finite() && *hz > 0.0),
            last_t: None,
            steps: [0.0; FIRST_INTERVALS],
            n: 0,
        }
    }

    /// A watch for a trial with this metadata (its `# sample_rate_hz:`,
    /// when that is a number).
    pub fn for_trial(meta: &limbfuse_io::TrialMeta) -> Self {
        Self::new(
            meta.get("sample_rate_hz")
                .and_then(|v| v.trim().parse().ok()),
        )
    }

    /// [`Self::for_trial`] for a command that uses the stated rate: a
    /// `# sample_rate_hz:` that is not a positive number is an error naming
    /// the line ([`limbfuse_io::TrialMeta::sample_rate_hz`]).
    pub fn checked_for_trial(meta: &limbfuse_io::TrialMeta) -> Result<Self, String> {
        Ok(Self::new(meta.sample_rate_hz()?))
    }

    /// The rate the trial states, if it is a positive finite number.
    pub fn stated_hz(&self) -> Option<f64> {
        self.stated_hz
    }

    /// Adds a sample time.
    pub fn push(&mut self, t: f64) {
        if self.n < FIRST_INTERVALS {
            if let Some(last) = self.last_t {
                self.steps[self.n] = t - last;
                self.n += 1;
            }
            self.last_t = Some(t);
        }
    }

    /// The median step of the samples seen (`None` before two samples).
    pub fn median_step(&self) -> Option<f64> {
        let mut s = self.steps;
        let s = &mut s[..self.n];
        s.sort_by(f64::total_cmp);
        let n = s.len();
        match n {
            0 => None,
            _ if n % 2 == 1 => Some(s[n / 2]),
            _ => Some(0.5 * (s[n / 2 - 1] + s[n / 2])),
        }
    }

    /// The mismatch, if the median step contradicts the stated rate by
    /// more than 25 %, or (no stated rate) is slower than
    /// [`SLOWEST_PLAUSIBLE_HZ`].
    pub fn mismatch(&self) -> Option<IntervalMismatch> {
        let median_step = self.median_step()?;
        let off = match self.stated_hz {
            Some(hz) => {
                let r = median_step * hz;
                !(1.0 / STATED_TOLERANCE..=STATED_TOLERANCE).contains(&r)
            }
            None => median_step > 1.0 / SLOWEST_PLAUSIBLE_HZ,
        };
        off.then_some(IntervalMismatch {
            median_step,
            steps: self.n,
            stated_hz: self.stated_hz,
        })
    }
}

impl Observer for SampleIntervalWatch {
    fn observe(&mut self, record: &Record, _estimate: &Estimate) -> Result<(), BoxError> {
        self.push(record.sample.t);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn watch(stated: Option<f64>, times: impl IntoIterator<Item = f64>) -> SampleIntervalWatch {
        let mut w = SampleIntervalWatch::new(stated);
        for t in times {
            w.push(t);
        }
        w
    }

    #[test]
    fn seconds_at_the_stated_rate_pass() {
        let w = watch(Some(100.0), (0..300).map(|k| k as f64 * 0.01));
        assert!((w.median_step().unwrap() - 0.01).abs() < 1e-12);
        assert_eq!(w.mismatch(), None);
        // jitter and a dropout do not move the median
        let w = watch(
            Some(250.0),
            (0..100).map(|k| {
                k as f64 * 0.004 + if k > 50 { 0.02 } else { 0.0 } + 1e-6 * (k % 3) as f64
            }),
        );
        assert_eq!(w.mismatch(), None);
        // the shared gaitmap walk's rate: t = row / 204.8
        let w = watch(Some(204.8), (0..100).map(|k| k as f64 / 204.8));
        assert_eq!(w.mismatch(), None);
    }

    #[test]
    fn milliseconds_are_named() {
        let w = watch(Some(100.0), (0..300).map(|k| k as f64 * 10.0));
        let m = w.mismatch().expect("10 s steps at a stated 100 Hz");
        assert_eq!(m.steps, FIRST_INTERVALS);
        assert_eq!(m.unit_hint(), Some(("milliseconds", 1e3)));
        let text = m.to_string();
        assert!(text.contains("`# sample_rate_hz: 100`"), "{text}");
        assert!(text.contains("divide `t` by 1000"), "{text}");
        // microseconds, no stated rate (250 Hz: 4000 us)
        let m = watch(None, (0..10).map(|k| k as f64 * 4000.0))
            .mismatch()
            .unwrap();
        assert_eq!(m.unit_hint(), Some(("microseconds", 1e6)));
        assert!(m.to_string().contains("slower than any gait recording"));
    }

    #[test]
    fn a_wrong_stated_rate_is_a_mismatch_without_a_unit() {
        let m = watch(Some(100.0), (0..50).map(|k| k as f64 * 0.02))
            .mismatch()
            .expect("50 Hz steps against a stated 100 Hz");
        assert_eq!(m.unit_hint(), None);
        assert!(!m.to_string().contains("looks like"));
    }

    #[test]
    fn few_samples_or_none_stated_and_plausible() {
        assert_eq!(watch(Some(100.0), [0.0]).mismatch(), None);
        assert_eq!(
            watch(None, (0..10).map(|k| k as f64 * 0.4)).mismatch(),
            None
        );
        assert!(watch(None, (0..10).map(|k| k as f64 * 0.6))
            .mismatch()
            .is_some());
        // a stated rate that is no rate is ignored
        assert_eq!(
            watch(Some(0.0), (0..10).map(|k| k as f64 * 0.01)).mismatch(),
            None
        );
    }
}
