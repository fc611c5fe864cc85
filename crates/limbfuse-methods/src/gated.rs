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

use std::fmt;

use limbfuse_core::{
    Estimate, Estimator, EstimatorError, EstimatorGate, Outputs, Sample, SensorRanges,
};
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

/// An estimator behind a [`SampleGate`](limbfuse_core::SampleGate), boxed
/// (a trait object: any method); the gate itself is
/// [`limbfuse_core::EstimatorGate`], which [`limbfuse_core::Gated`] puts in
/// front of an owned estimator without `std`.
pub struct GatedEstimator<E: Estimator + ?Sized = dyn Estimator + Send> {
    inner: Box<E>,
    gate: EstimatorGate,
    /// The inner estimator's diagnostic names, then [`REJECTION_DIAGNOSTICS`]
    /// (when they fit in [`limbfuse_core::MAX_DIAG`]).
    names: Vec<&'static str>,
}

impl<E: Estimator + ?Sized> GatedEstimator<E> {
    /// `inner` behind a gate with `ranges`.
    pub fn new(inner: Box<E>, ranges: SensorRanges) -> Self {
        let mut names: Vec<&'static str> = inner.diagnostic_names().to_vec();
        let gate = EstimatorGate::new(ranges, names.len());
        if gate.rejections_at().is_some() {
            names.extend_from_slice(&REJECTION_DIAGNOSTICS);
        }
        GatedEstimator { inner, gate, names }
    }

    /// The estimator behind the gate.
    pub fn inner(&self) -> &E {
        &self.inner
    }
}

impl<E: Estimator + ?Sized> Estimator for GatedEstimator<E> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn outputs(&self) -> Outputs {
        self.inner.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        self.inner.describe_parameters(out)?;
        self.gate.describe(out)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &self.names
    }

    fn rejected_readings(&self) -> [u64; 3] {
        self.gate.rejected_readings(&*self.inner)
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.gate.reset();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        self.step_into(sample, &mut e)?;
        Ok(e)
    }

    fn step_into(&mut self, sample: &Sample, e: &mut Estimate) -> Result<(), EstimatorError> {
        self.gate.step_into(&mut *self.inner, sample, e, None)
    }
}

impl<E: Estimator + ?Sized> GatedEstimator<E> {
    /// As [`Estimator::step_into`]; `seen` becomes the sample as the
    /// estimator saw it (the readings the gate rejected missing), for an
    /// offline pass that reuses the readings ([`crate::knee_backfill`]).
    pub fn step_seen(
        &mut self,
        sample: &Sample,
        e: &mut Estimate,
        seen: &mut Sample,
    ) -> Result<(), EstimatorError> {
        self.gate.step_into(&mut *self.inner, sample, e, Some(seen))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
