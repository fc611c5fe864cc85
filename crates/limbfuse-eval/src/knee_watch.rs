//! What `limbfuse estimate` and Python's `limbfuse.estimate` say about a knee-axis method (`knee-selfalign`,
//! `knee-gyro-axis`; issue 15 item 5): the one-line summary ("knee axis
//! identified at t = 3.2 s, sign confidence 0.97") and the errors for a
//! trial on which the knee axis was never identified (no gyroscope samples,
//! a window longer than the trial, no knee motion).

use limbfuse_core::runner::{self, Observer};
use limbfuse_core::{Estimate, Joint, Record, Sample, Segment};

/// Watches a knee-axis method's estimates.
#[derive(Debug, Default)]
pub struct KneeWatch {
    /// Column of `sign_confidence` in the estimates' diagnostics.
    confidence: Option<usize>,
    committed: Option<usize>,
    /// Column of the "accelerometer angle used" flag (`acc_trusted` or
    /// `inclination_used`).
    acc_used: Option<usize>,
    windows: Option<usize>,
    samples: u64,
    gyro_samples: u64,
    /// Samples with both IMUs complete (accelerometer and gyroscope).
    complete_samples: u64,
    first: Option<f64>,
    last_confidence: Option<f64>,
    last_committed: Option<f64>,
    last_windows: Option<f64>,
    after_first: u64,
    acc_used_samples: u64,
    /// The `identified` diagnostic: an estimate with a knee angle before the
    /// axes were identified (`estimate --backfill`) does not count.
    identified: Option<usize>,
    /// Column of `position_outliers` (samples left out of the position
    /// fits so far) and its last value.
    outliers: Option<usize>,
    last_outliers: Option<f64>,
}

impl KneeWatch {
    /// A watch for an estimator whose diagnostics are `names`; `None` when
    /// it is not a knee-axis method (no `sign_confidence` diagnostic).
    pub fn for_diagnostics(names: &[&str]) -> Option<Self> {
        let col = |n: &str| names.iter().position(|x| *x == n);
        Some(KneeWatch {
            confidence: Some(col("sign_confidence")?),
            committed: col("sign_committed"),
            acc_used: col("acc_trusted").or_else(|| col("inclination_used")),
            windows: col("windows"),
            identified: col("identified"),
            outliers: col("position_outliers"),
            ..Default::default()
        })
    }

    /// The one-line summary, or the error when the axis was never
    /// identified. `window` is the identification window (samples).
    pub fn verdict(&self, window: usize) -> Result<String, String> {
        let Some(t) = self.first else {
            return Err(if self.gyro_samples == 0 {
                "the trial has no sample with both the thigh and the shank gyroscope \
                 (the knee axis comes from the two gyroscopes)"
                    .to_string()
            } else if self.last_windows.unwrap_or(0.0) < 1.0 && (self.samples as usize) < window {
                format!(
                    "the identification window ({window} samples, --window) is longer than the trial \
                     ({} samples): no window was completed; give `--window N` with N at most {} \
                     (a shorter window identifies the axis from less motion) or a longer trial",
                    self.samples, self.samples
                )
            } else if 2 * self.complete_samples < self.samples {
                format!(
                    "the knee axis is unidentifiable: only {} of the {} samples ({:.0} %) have both \
                     IMUs complete (the thigh's and the shank's accelerometer and gyroscope, every \
                     axis), and a window is used only when at least half of its samples are \
                     (empty cells or missing readings: `limbfuse inspect` shows what each input \
                     misses)",
                    self.complete_samples,
                    self.samples,
                    100.0 * self.complete_samples as f64 / self.samples as f64
                )
            } else {
                format!(
                    "the knee axis is unidentifiable: no knee motion in any of the {} windows \
                     ({} samples; every window was unobservable or had too few complete samples; \
                     each IMU's axis needs that segment to turn: a still thigh, as on a seat or \
                     a leg-extension machine, leaves the thigh's unidentifiable)",
                    self.last_windows.unwrap_or(0.0),
                    self.samples
                )
            });
        };
        let mut line = format!("knee axis identified at t = {t:.1} s");
        if let Some(c) = self.last_confidence {
            line += &format!(", sign confidence {c:.2}");
            if self.last_committed == Some(1.0) {
                line += " (committed)";
            } else if self.committed.is_some() {
                line += " (not committed: weak evidence)";
            }
        }
        if self.acc_used.is_some() && self.after_first > 0 {
            let pct = 100.0 * self.acc_used_samples as f64 / self.after_first as f64;
            line += &format!(", accelerometer angle corrects the drift in {pct:.0} % of the samples after it (high-pass otherwise)");
        }
        if let Some(n) = self.last_outliers.filter(|&n| n > 0.0) {
            line += &format!(
                "; {n} samples left out of the sensor-position fits as gross outliers of eq 3 \
                 (a gyroscope spike; docs/KNEE_SELFALIGN.md \"Gyroscope spikes\")"
            );
        }
        Ok(line)
    }
}

impl KneeWatch {
    /// Adds one sample and its estimate.
    pub fn push(&mut self, s: &Sample, e: &Estimate) {
        self.samples += 1;
        if s.imu(Segment::Thigh).gyr.is_some() && s.imu(Segment::Shank).gyr.is_some() {
            self.gyro_samples += 1;
            if s.imu(Segment::Thigh).acc.is_some() && s.imu(Segment::Shank).acc.is_some() {
                self.complete_samples += 1;
            }
        }
        let get = |c: Option<usize>| c.and_then(|c| e.diag.get(c).copied().flatten());
        if let Some(w) = get(self.windows) {
            self.last_windows = Some(w);
        }
        if let Some(n) = get(self.outliers) {
            self.last_outliers = Some(n);
        }
        let identified = match self.identified {
            Some(c) => get(Some(c)) == Some(1.0),
            None => true,
        };
        if identified && e.joint[Joint::Knee.index()].is_some() {
            self.first.get_or_insert(e.t);
            self.after_first += 1;
            self.acc_used_samples += u64::from(get(self.acc_used) == Some(1.0));
            self.last_confidence = get(self.confidence).or(self.last_confidence);
            self.last_committed = get(self.committed).or(self.last_committed);
        }
    }
}

impl Observer for KneeWatch {
    fn observe(&mut self, record: &Record, e: &Estimate) -> Result<(), runner::BoxError> {
        self.push(&record.sample, e);
        Ok(())
    }
}
