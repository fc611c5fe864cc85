//! Every estimator [`crate::build`] makes sees its samples through a
//! [`SampleGate`] (issue 18 item 1): readings outside the sensors' physical
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
//! (docs/ROBUST_INPUT.md).

use std::fmt;

use limbfuse_core::{
    Estimate, Estimator, EstimatorError, Outputs, Sample, SampleGate, SensorRanges, TimeStep,
    MAX_DIAG,
};
use limbfuse_io::TrialMeta;

use crate::MethodError;

/// Names of the gate's diagnostics, in the order they follow the
/// estimator's own.
pub const REJECTION_DIAGNOSTICS: [&str; 3] = ["rejected_gyro", "rejected_acc", "rejected_encoder"];

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

/// An estimator behind a [`SampleGate`].
pub struct GatedEstimator<E: Estimator + ?Sized = dyn Estimator + Send> {
    inner: Box<E>,
    gate: SampleGate,
    /// The inner estimator's diagnostic names, then [`REJECTION_DIAGNOSTICS`]
    /// (when they fit in [`MAX_DIAG`]).
    names: Vec<&'static str>,
    /// Index of `rejected_gyro` in [`Estimate::diag`], if written.
    first: Option<usize>,
    /// The times of the samples stepped without error.
    time: TimeStep,
}

impl<E: Estimator + ?Sized> GatedEstimator<E> {
    /// `inner` behind a gate with `ranges`.
    pub fn new(inner: Box<E>, ranges: SensorRanges) -> Self {
        let mut names: Vec<&'static str> = inner.diagnostic_names().to_vec();
        let first = (names.len() + REJECTION_DIAGNOSTICS.len() <= MAX_DIAG).then_some(names.len());
        if first.is_some() {
            names.extend_from_slice(&REJECTION_DIAGNOSTICS);
        }
        GatedEstimator {
            inner,
            gate: SampleGate::new(ranges),
            names,
            first,
            time: TimeStep::new(),
        }
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
        let r = self.gate.ranges();
        writeln!(
            out,
            "sensor_range: gyro {} rad/s, acc {} m/s2, encoder {} rad (readings beyond are treated as missing)",
            r.gyro_rad_s, r.acc_m_s2, r.encoder_rad
        )
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &self.names
    }

    fn rejected_readings(&self) -> [u64; 3] {
        let r = self.gate.rejections();
        let [g, a, n] = self.inner.rejected_readings();
        [r.gyro + g, r.acc + a, r.encoder + n]
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.gate.reset();
        self.time.reset();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        self.step_into(sample, &mut e)?;
        Ok(e)
    }

    fn step_into(&mut self, sample: &Sample, e: &mut Estimate) -> Result<(), EstimatorError> {
        self.step_gated(sample, e, None)
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
        self.step_gated(sample, e, Some(seen))
    }

    #[inline]
    fn step_gated(
        &mut self,
        sample: &Sample,
        e: &mut Estimate,
        seen: Option<&mut Sample>,
    ) -> Result<(), EstimatorError> {
        // A sample the estimator would refuse for its time is refused
        // before the gate sees it: a refused sample leaves no trace in the
        // gate's counts and tests (Python's `Filter` goes on after an error).
        self.time.check(sample.t)?;
        // Most samples pass the gate unchanged: no copy of the sample then.
        let screening = self.gate.check(sample);
        if screening.is_clean() {
            self.inner.step_into(sample, e)?;
            if let Some(s) = seen {
                *s = *sample;
            }
        } else {
            let mut screened = *sample;
            screening.apply(&mut screened);
            self.inner.step_into(&screened, e)?;
            if let Some(s) = seen {
                *s = screened;
            }
        }
        if !outputs_finite(e) {
            blank_non_finite(e);
            self.inner.reset();
        }
        // (checked above)
        let _ = self.time.advance(sample.t);
        if let Some(i) = self.first {
            let [g, a, n] = self.rejected_readings();
            e.diag[i] = Some(g as f64);
            e.diag[i + 1] = Some(a as f64);
            e.diag[i + 2] = Some(n as f64);
        }
        Ok(())
    }
}

/// Whether every angle, speed and centre-of-mass output is finite or missing.
fn outputs_finite(e: &Estimate) -> bool {
    let ok = |v: &Option<f64>| v.is_none_or(f64::is_finite);
    let ok3 =
        |v: &Option<nalgebra::Vector3<f64>>| v.is_none_or(|v| v.iter().all(|x| x.is_finite()));
    e.segment.iter().all(ok)
        && e.joint.iter().all(ok)
        && ok(&e.speed)
        && ok3(&e.com_pos)
        && ok3(&e.com_vel)
}

/// Makes every non-finite output and diagnostic missing.
fn blank_non_finite(e: &mut Estimate) {
    let blank = |v: &mut Option<f64>| {
        if v.is_some_and(|x| !x.is_finite()) {
            *v = None;
        }
    };
    e.segment
        .iter_mut()
        .chain(e.joint.iter_mut())
        .chain(e.diag.iter_mut())
        .for_each(blank);
    blank(&mut e.speed);
    for v in [&mut e.com_pos, &mut e.com_vel] {
        if v.is_some_and(|v| v.iter().any(|x| !x.is_finite())) {
            *v = None;
        }
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
