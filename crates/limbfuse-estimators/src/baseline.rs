//! Two honest baselines every paper estimator must beat.
//!
//! * [`GyroIntegration`]: each segment angle is the trapezoidal integral of
//!   its aligned gyro's z rate from an initial accelerometer inclination. It
//!   is smooth but drifts with the gyro bias (paper 000 eq 1).
//! * [`AccelInclination`]: each segment angle is `atan2(acc_x, acc_y)`
//!   (SPEC section 1). It does not drift but carries every dynamic
//!   acceleration of the segment as angle error (paper 000 eq 9 assumes none).
//!
//! Both expect aligned sensors (SPEC section 1). Joint angles are the
//! differences of the segment angles.

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{Estimate, Estimator, EstimatorError, Sample, TimeStep};

use crate::inclination::accel_inclination;
use crate::segment_kf::robust::LONG_GAP_S;

/// Gyro integration from the first accelerometer inclination.
///
/// A segment starts when it first has both an accelerometer and a gyro
/// reading: its angle is then the accelerometer inclination. A missing gyro
/// sample is bridged by holding the last rate (zero-order hold), so a
/// dropout of `n` samples adds at most `n dt |rate change|` of error. A
/// time step over [`LONG_GAP_S`] (a gap in the recording) starts every
/// segment again from its inclination.
#[derive(Debug, Clone, Default)]
pub struct GyroIntegration {
    time: TimeStep,
    angle: [Option<f64>; 4],
    last_rate: [Option<f64>; 4],
}

impl GyroIntegration {
    /// A fresh integrator.
    pub fn new() -> Self {
        Self::default()
    }
}

impl Estimator for GyroIntegration {
    fn name(&self) -> &'static str {
        "gyro-integration"
    }

    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(
            out,
            "integration: trapezoidal on gyr_z, zero-order hold over gyro dropouts"
        )?;
        writeln!(
            out,
            "initial_angle: atan2(acc_x, acc_y) of the first sample with acc and gyr (again after a time gap over {LONG_GAP_S} s)"
        )
    }

    fn reset(&mut self) {
        *self = Self::default();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let mut dt = self.time.advance(sample.t)?;
        if dt.is_some_and(|d| d > LONG_GAP_S) {
            // A gap in the recording: no rate held over it means anything
            // (an audit: a 1000 s gap integrated the last rate into a knee
            // of -2090 rad). Start again from the inclination, as at first.
            self.angle = [None; 4];
            self.last_rate = [None; 4];
            dt = None;
        }
        let mut est = Estimate::empty(sample.t);
        for i in 0..4 {
            let imu = &sample.imu[i];
            let rate = imu.gyr_axis(2);
            match (self.angle[i], dt) {
                (Some(a), Some(dt)) => {
                    let r1 = rate.or(self.last_rate[i]);
                    let r0 = self.last_rate[i].or(r1);
                    if let (Some(r0), Some(r1)) = (r0, r1) {
                        self.angle[i] = Some(a + 0.5 * (r0 + r1) * dt);
                    }
                }
                _ => {
                    if let (Some(acc), Some(_)) = (imu.acc, rate) {
                        self.angle[i] = Some(accel_inclination(&acc));
                    }
                }
            }
            if rate.is_some() {
                self.last_rate[i] = rate;
            }
            est.segment[i] = self.angle[i];
        }
        est.fill_joints_from_segments();
        Ok(est)
    }
}

/// Accelerometer inclination, sample by sample.
#[derive(Debug, Clone, Default)]
pub struct AccelInclination {
    time: TimeStep,
}

impl AccelInclination {
    /// A fresh estimator.
    pub fn new() -> Self {
        Self::default()
    }
}

impl Estimator for AccelInclination {
    fn name(&self) -> &'static str {
        "accel-inclination"
    }

    fn outputs(&self) -> Outputs {
        Outputs::ALL_ANGLES
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "formula: theta = atan2(acc_x, acc_y), no filtering")
    }

    fn reset(&mut self) {
        self.time.reset();
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        self.time.advance(sample.t)?;
        let mut est = Estimate::empty(sample.t);
        for i in 0..4 {
            est.segment[i] = sample.imu[i].acc.as_ref().map(accel_inclination);
        }
        est.fill_joints_from_segments();
        Ok(est)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn sample(t: f64, theta: f64, rate: Option<f64>) -> Sample {
        let mut s = Sample::empty(t);
        for imu in s.imu.iter_mut() {
            imu.acc = Some(Vector3::new(
                9.81 * libm::sin(theta),
                9.81 * libm::cos(theta),
                0.0,
            ));
            imu.gyr = rate.map(|r| Vector3::new(0.0, 0.0, r));
        }
        s
    }

    #[test]
    fn integrates_a_linear_rate_exactly_with_trapezoid() {
        // rate = 2 t: angle(t) = 0.3 + t^2, trapezoid is exact for linear rates.
        let mut g = GyroIntegration::new();
        let mut last = None;
        for k in 0..=100 {
            let t = k as f64 * 0.01;
            let e = g.step(&sample(t, 0.3, Some(2.0 * t))).unwrap();
            last = e.segment[1];
        }
        assert!((last.unwrap() - 1.3).abs() < 1e-12);
    }

    #[test]
    fn holds_last_rate_over_a_dropout_and_rejects_time_going_back() {
        let mut g = GyroIntegration::new();
        g.step(&sample(0.0, 0.0, Some(1.0))).unwrap();
        g.step(&sample(0.1, 0.0, None)).unwrap();
        let e = g.step(&sample(0.2, 0.0, Some(1.0))).unwrap();
        assert!((e.segment[0].unwrap() - 0.2).abs() < 1e-12);
        assert_eq!(e.joint[0], Some(0.0));
        assert!(g.step(&sample(0.2, 0.0, Some(1.0))).is_err());
    }

    /// Gyro integration reads the sagittal rate `z` only: a vector with
    /// an empty `x` or `y` cell still gives it (2026-12-06; before, the
    /// rate was held from the previous sample). The rate jumps from 1 to 3
    /// rad/s at 0.1 s, read from an incomplete vector.
    #[test]
    fn an_incomplete_gyro_vector_still_gives_its_z_rate() {
        let mut g = GyroIntegration::new();
        g.step(&sample(0.0, 0.0, Some(1.0))).unwrap();
        let mut s = sample(0.1, 0.0, None);
        for imu in s.imu.iter_mut() {
            imu.gyr_partial = [None, Some(0.5), Some(3.0)];
        }
        let e = g.step(&s).unwrap();
        // trapezoid of 1 and 3 rad/s over 0.1 s (the held rate gave 0.1)
        assert!(
            (e.segment[0].unwrap() - 0.2).abs() < 1e-12,
            "{:?}",
            e.segment[0]
        );
    }

    /// An audit: a 1000 s gap integrated the last rate into a knee of
    /// -2090 rad. Over a step longer than `LONG_GAP_S` every segment starts
    /// again from its inclination; a shorter dropout still holds the rate.
    #[test]
    fn starts_again_from_the_inclination_after_a_time_gap() {
        let mut g = GyroIntegration::new();
        g.step(&sample(0.0, 0.1, Some(1.0))).unwrap();
        let e = g.step(&sample(0.5, 0.1, Some(1.0))).unwrap();
        assert!((e.segment[0].unwrap() - 0.6).abs() < 1e-12);
        let e = g.step(&sample(1000.0, 0.4, Some(1.0))).unwrap();
        assert!((e.segment[0].unwrap() - 0.4).abs() < 1e-12);
        let e = g.step(&sample(1000.01, 0.4, Some(1.0))).unwrap();
        assert!((e.segment[0].unwrap() - 0.41).abs() < 1e-12);
    }

    #[test]
    fn inclination_reads_static_angle_and_none_without_accel() {
        let mut a = AccelInclination::new();
        let e = a.step(&sample(0.0, 0.25, None)).unwrap();
        assert!((e.segment[2].unwrap() - 0.25).abs() < 1e-12);
        let e = a.step(&Sample::empty(0.01)).unwrap();
        assert_eq!(e.segment[2], None);
        assert_eq!(e.joint[1], None);
    }
}
