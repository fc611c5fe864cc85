//! What `estimate` says when `knee-kinematic` is given a trial whose thigh
//! moves. The method models the seated FES leg of paper 004: the thigh
//! fixed at `# thigh_angle_rad:` (default horizontal), the knee the thigh's
//! angle minus the shank's. On a walking trial it runs and writes a knee
//! that is not the knee (limbfuse's simulated 20 s walk: 110 deg RMSE),
//! with exit 0 and nothing said.
//!
//! [`FixedThighWatch`] counts the thigh gyroscope's readings turning faster
//! than [`TURNING_THIGH`] (1 rad/s, 57 deg/s): a thigh on a seat, even one
//! shaken by a stimulated kick, stays far below it; a walking thigh swings
//! at 2-4 rad/s through most of each stride. Flagged when a tenth of the
//! readings turn that fast, on at least [`MIN_READINGS`] readings (every
//! [`FixedThighWatch::STRIDE`]-th sample, as the unit checks).

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::{Estimate, Record, Sample};
use nalgebra::Vector3;

use crate::sensor_units::MIN_READINGS;

/// A thigh rate (rad/s) a seated leg does not reach.
pub const TURNING_THIGH: f64 = 1.0;
/// Share of thigh gyroscope readings beyond [`TURNING_THIGH`] that says
/// the thigh moves.
const MOVING_SHARE: f64 = 0.10;

/// Counts the thigh gyroscope readings of a run (see the module).
#[derive(Debug, Clone, Default)]
pub struct FixedThighWatch {
    records: u64,
    readings: u64,
    turning: u64,
}

impl FixedThighWatch {
    /// Every how many samples one is counted.
    pub const STRIDE: usize = 8;

    /// Adds a sample's thigh gyroscope reading (the leg the trial names).
    pub fn push_sample(&mut self, s: &Sample) {
        if let Some(w) = &s.imu[1].gyr {
            self.push_gyr(w);
        }
    }

    /// Adds one thigh gyroscope reading (rad/s).
    pub fn push_gyr(&mut self, w: &Vector3<f64>) {
        self.readings += 1;
        if w.norm() > TURNING_THIGH {
            self.turning += 1;
        }
    }

    /// The share (0-1) of the thigh's readings turning faster than
    /// [`TURNING_THIGH`], when the thigh moves by that measure.
    pub fn moving_share(&self) -> Option<f64> {
        if self.readings < MIN_READINGS {
            return None;
        }
        let share = self.turning as f64 / self.readings as f64;
        (share >= MOVING_SHARE).then_some(share)
    }

    /// The warning for `method` on `trial`, when the thigh moves.
    pub fn warning(&self, method: &str, trial: &str) -> Option<String> {
        self.moving_share().map(|share| {
            format!(
                "{method} on {trial}: the method models a fixed thigh (a seated FES leg, \
                 `# thigh_angle_rad:`), but the thigh IMU turns faster than {TURNING_THIGH} rad/s \
                 in {:.0} % of its readings: the knee it gives is not this trial's knee \
                 (`rmx`, `knee-selfalign` and `knee-gyro-axis` follow a moving thigh)",
                100.0 * share
            )
        })
    }
}

impl Observer for FixedThighWatch {
    /// Counts every [`FixedThighWatch::STRIDE`]-th record.
    fn observe(&mut self, record: &Record, _estimate: &Estimate) -> Result<(), BoxError> {
        if self.records.is_multiple_of(Self::STRIDE as u64) {
            self.push_sample(&record.sample);
        }
        self.records += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::ImuSample;

    fn with_thigh_rate(rate: f64) -> Sample {
        let mut s = Sample::default();
        s.imu[1] = ImuSample {
            gyr: Some(Vector3::new(0.0, 0.0, rate)),
            ..ImuSample::default()
        };
        s
    }

    /// A seated thigh (noise, a kick's jolt) says nothing; a swinging one
    /// does, with its share; too few readings say nothing.
    #[test]
    fn a_swinging_thigh_is_named_a_seated_one_is_not() {
        let mut seated = FixedThighWatch::default();
        for k in 0..400 {
            seated.push_sample(&with_thigh_rate(if k % 50 == 0 { 1.5 } else { 0.01 }));
        }
        assert_eq!(seated.moving_share(), None);
        assert!(seated.warning("knee-kinematic", "t.csv").is_none());
        let mut walking = FixedThighWatch::default();
        for k in 0..400 {
            let phase = k as f64 * 0.0628;
            walking.push_sample(&with_thigh_rate(3.0 * phase.sin()));
        }
        let share = walking.moving_share().unwrap();
        assert!((0.6..0.8).contains(&share), "{share}");
        let w = walking.warning("knee-kinematic", "t.csv").unwrap();
        assert!(w.contains("t.csv") && w.contains("fixed thigh"), "{w}");
        let mut short = FixedThighWatch::default();
        for _ in 0..(MIN_READINGS - 1) {
            short.push_sample(&with_thigh_rate(3.0));
        }
        assert_eq!(short.moving_share(), None);
    }
}
