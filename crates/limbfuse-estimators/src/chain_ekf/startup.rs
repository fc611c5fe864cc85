//! Start-up: each segment's initial angle from the circular mean of
//! (accelerometer inclination - integrated gyro) over the first seconds
//! (docs/CHAIN.md, "Start-up").
//!
//! Over a few strides the dynamic accelerations average out of the
//! inclination far better than at any single instant, while the integrated
//! gyro carries the shape of the motion; their difference is the constant
//! offset of the integral, `theta_i(t) = m_i + I_i(t)`. The circular mean
//! (mean of unit vectors) is used because inclinations may wrap at +-pi
//! (a foot or shank held far from upright). The encoder offsets start from
//! the circular mean of `enc_j - (theta_a - theta_b)` the same way.

use limbfuse_core::Sample;

use crate::inclination::{accel_inclination, sagittal_specific_force};
use crate::segment_kf::robust::borrow_rates;

/// Running sums of the start-up window.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Startup {
    start: Option<f64>,
    integral: [f64; 4],
    last_rate: [Option<f64>; 4],
    /// Sum of `(sin, cos)` of `inclination - integral`, per segment.
    segment_sum: [[f64; 2]; 4],
    /// Sum of `(sin, cos)` of `enc_j - (I_a - I_b)`, per joint.
    encoder_sum: [[f64; 2]; 3],
    /// The previous sample's encoders (rates borrowed through them).
    last_encoder: [Option<f64>; 3],
}

fn add(sum: &mut [f64; 2], angle: f64) {
    sum[0] += libm::sin(angle);
    sum[1] += libm::cos(angle);
}

fn mean(sum: &[f64; 2]) -> Option<f64> {
    (sum[0] != 0.0 || sum[1] != 0.0).then(|| libm::atan2(sum[0], sum[1]))
}

impl Startup {
    /// Adds one sample (`dt` = `None` for the first).
    ///
    /// A missing gyro rate is borrowed from a neighbour's rate and the
    /// encoder between them (`omega_(j+1) = omega_j - d enc_j / dt`, as the
    /// segment filters do, docs/ROBUST_INPUT.md; ours, issue 18 item 2);
    /// failing that the last rate is held. Holding it alone over random
    /// dropouts made the integral, and so the started angles, wrong by up
    /// to a degree with 20 % of the IMU cells missing.
    pub fn observe(&mut self, sample: &Sample, dt: Option<f64>) {
        if self.start.is_none() {
            self.start = Some(sample.t);
        }
        let mut rate: [Option<f64>; 4] =
            core::array::from_fn(|i| sample.imu[i].gyr_axis(2).filter(|r| r.is_finite()));
        let encoder = sample.encoder.map(|e| e.filter(|v| v.is_finite()));
        if let Some(dt) = dt {
            borrow_rates(&mut rate, &encoder, &self.last_encoder, dt);
        }
        self.last_encoder = encoder;
        for (i, rate) in rate.into_iter().enumerate() {
            let imu = &sample.imu[i];
            if let Some(dt) = dt {
                let r1 = rate.or(self.last_rate[i]);
                let r0 = self.last_rate[i].or(r1);
                if let (Some(r0), Some(r1)) = (r0, r1) {
                    self.integral[i] += 0.5 * (r0 + r1) * dt;
                }
            }
            if rate.is_some() {
                self.last_rate[i] = rate;
            }
            if let Some(acc) = sagittal_specific_force(imu) {
                add(
                    &mut self.segment_sum[i],
                    accel_inclination(&acc) - self.integral[i],
                );
            }
        }
        for j in 0..3 {
            if let Some(e) = sample.encoder[j] {
                add(
                    &mut self.encoder_sum[j],
                    e - (self.integral[j] - self.integral[j + 1]),
                );
            }
        }
    }

    /// Seconds since the first sample (0 before any).
    pub fn elapsed(&self, t: f64) -> f64 {
        self.start.map_or(0.0, |s| t - s)
    }

    /// Segment `i`'s angle now, `m_i + I_i` (`None` before its first accelerometer reading).
    pub fn angle(&self, i: usize) -> Option<f64> {
        mean(&self.segment_sum[i]).map(|m| m + self.integral[i])
    }

    /// Segment `i`'s offset `m_i`: its angle at the first sample.
    pub fn offset(&self, i: usize) -> Option<f64> {
        mean(&self.segment_sum[i])
    }

    /// Encoder `j`'s offset `enc_j - (theta_j - theta_{j+1})` (`None` without
    /// readings of it or accelerometer readings of both segments).
    pub fn encoder_offset(&self, j: usize) -> Option<f64> {
        let m = mean(&self.encoder_sum[j])?;
        let (a, b) = (mean(&self.segment_sum[j])?, mean(&self.segment_sum[j + 1])?);
        let d = m - (a - b);
        Some(libm::atan2(libm::sin(d), libm::cos(d)))
    }
}

/// Initial 1-sigma of the state after the start-up window.
pub mod initial {
    /// Segment angles (rad): the start-up mean is good to a few degrees.
    pub const ANGLE: f64 = 0.5;
    /// Rates (rad/s) about the latest gyro reading.
    pub const RATE: f64 = 0.1;
    /// Angular accelerations (rad/s^2).
    pub const ANGULAR_ACCELERATION: f64 = 20.0;
    /// Hip velocity and mean speed (m/s): walking speed is unknown.
    pub const VELOCITY: f64 = 1.0;
    /// Hip acceleration (m/s^2).
    pub const ACCELERATION: f64 = 3.0;
    /// Encoder offsets about the start-up estimate (rad).
    pub const ENCODER_OFFSET: f64 = 0.05;
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// Segment angle `c + 0.4 sin(2 pi t)` with an accelerometer reading
    /// gravity plus a zero-mean disturbance of the inclination.
    fn sample(t: f64, c: [f64; 4]) -> Sample {
        let mut s = Sample::empty(t);
        let w = core::f64::consts::TAU;
        for (i, imu) in s.imu.iter_mut().enumerate() {
            let th = c[i] + 0.4 * (w * t).sin();
            let disturbed = th + 0.2 * (3.0 * w * t + i as f64).sin();
            imu.acc = Some(Vector3::new(
                9.81 * disturbed.sin(),
                9.81 * disturbed.cos(),
                0.0,
            ));
            imu.gyr = Some(Vector3::new(0.0, 0.0, 0.4 * w * (w * t).cos()));
        }
        for j in 0..3 {
            s.encoder[j] = Some(c[j] - c[j + 1] + 0.01 * (j as f64 + 1.0));
        }
        s
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn the_circular_mean_recovers_offsets_also_across_pi() {
        let c = [0.05, 0.3, -3.0, 3.1];
        let mut st = Startup::default();
        let dt = 0.01;
        let mut prev = None;
        for k in 0..200 {
            let t = k as f64 * dt;
            st.observe(&sample(t, c), prev.map(|p| t - p));
            prev = Some(t);
        }
        let t = 1.99;
        let wrap = |a: f64| libm::atan2(libm::sin(a), libm::cos(a));
        for i in 0..4 {
            let truth = c[i] + 0.4 * (core::f64::consts::TAU * t).sin();
            let err = wrap(st.angle(i).unwrap() - truth);
            assert!(err.abs() < 2e-3, "segment {i}: error {err}");
        }
        for j in 0..3 {
            let err = wrap(st.encoder_offset(j).unwrap() - 0.01 * (j as f64 + 1.0));
            assert!(err.abs() < 3e-3, "encoder {j}: error {err}");
        }
    }
}
