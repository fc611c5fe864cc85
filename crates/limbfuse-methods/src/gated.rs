//! Every estimator [`crate::build`] makes sees its samples through a
//! [`SampleGate`](limbfuse_core::SampleGate) (issue 18 item 1): readings outside the sensors' physical
//! range become missing readings, counted in three cumulative diagnostics
//! appended to the estimator's own, `rejected_gyro`, `rejected_acc` and
//! `rejected_encoder` (`diag_rejected_*` columns). The gate also rejects
//! non-physical jumps, saturated bursts and stuck sensors
//! ([`limbfuse_core::plausibility`]); the counts include the readings the
//! estimator's own innovation gate refused
//! ([`Estimator::rejected_readings`]).
//!
//! The gate is also the last line of the "finite or missing" contract: an
//! output the estimator left non-finite (a divergence its own checks did not
//! catch, e.g. `rmx` with a Mahony gain of 1e308) is written missing and the
//! estimator is reset, so that it starts afresh from the next sample
//! (docs/ROBUST_INPUT.md). The gate is [`limbfuse_core::EstimatorGate`], the
//! same code a `no_std` controller runs through [`limbfuse_core::Gated`].

use limbfuse_core::{Estimator, Gated, SensorRanges};
use limbfuse_io::TrialMeta;

use crate::MethodError;

pub use limbfuse_core::gated::REJECTION_DIAGNOSTICS;

pub use limbfuse_io::meta::{ACC_RANGE_KEY, GYRO_RANGE_KEY};

/// The sensor ranges of a trial ([`TrialMeta::sensor_ranges`]): its
/// metadata's `gyro_range_rad_s` and `acc_range_m_s2` where given, the
/// datasheet defaults of [`SensorRanges::default`] otherwise.
pub fn sensor_ranges(meta: &TrialMeta) -> Result<SensorRanges, MethodError> {
    meta.sensor_ranges().map_err(|e| MethodError::SensorRange {
        key: e.key,
        found: e.found,
    })
}

/// An estimator behind the sensor gate, boxed (a trait object: any
/// method): core's [`Gated`] over a [`Box`], the gate a `no_std`
/// controller runs over an owned estimator.
pub type GatedEstimator<E = dyn Estimator + Send> = Gated<Box<E>>;

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::{EstimatorError, Sample};
    use limbfuse_estimators::baseline::GyroIntegration;
    use nalgebra::Vector3;

    fn sample(t: f64, rate: f64) -> Sample {
        let mut s = Sample {
            t,
            ..Sample::default()
        };
        s.imu[1].gyr = Some(Vector3::new(0.0, 0.0, rate));
        s
    }

    /// A sample refused for its time (Python's `Filter` goes on after the
    /// error) left its out-of-range reading in the gate's count:
    /// `diag_rejected_gyro` stayed raised on every later step. It is now
    /// refused before the gate sees it, and the run goes on as if it had
    /// never been given.
    #[test]
    fn a_sample_refused_for_its_time_leaves_no_trace() {
        let gated = || {
            GatedEstimator::new(
                Box::new(GyroIntegration::new()) as Box<dyn Estimator + Send>,
                SensorRanges::default(),
            )
        };
        let (mut a, mut b) = (gated(), gated());
        for k in 0..50 {
            let s = sample(k as f64 * 0.01, (0.3 * k as f64).sin());
            a.step(&s).unwrap();
            b.step(&s).unwrap();
        }
        // backwards in time, with a gyro reading far beyond the range
        let bad = sample(0.1, 1e4);
        assert!(matches!(
            a.step(&bad),
            Err(EstimatorError::NonIncreasingTime { .. })
        ));
        assert!(matches!(
            a.step(&sample(f64::NAN, 1e4)),
            Err(EstimatorError::NonFinite { channel: "t" })
        ));
        assert_eq!(a.rejected_readings(), b.rejected_readings());
        let next = sample(0.5, 0.7);
        assert_eq!(a.step(&next).unwrap(), b.step(&next).unwrap());
        // after a reset any time starts a new run
        a.reset();
        assert!(a.step(&sample(0.0, 0.5)).is_ok());
    }
}
