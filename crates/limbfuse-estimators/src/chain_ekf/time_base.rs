//! The chain EKF's time base (ours, 2026-12-07): the step between two
//! samples on the sensor's own sampling grid when the stamps are jittered,
//! and the out-of-plane rate derivative taken on that time base.
//!
//! A wireless IMU samples on its own regular clock; a receiver stamps the
//! readings later, by a varying amount. Taken at their word, jittered stamps
//! put the jitter into every prediction step and into the derivative of the
//! out-of-plane rates (a difference over the stamps' step): the shared
//! independent walks with +-30 % stamp jitter cost `chain` 0.22 -> 0.38 deg
//! on the 1.2 m/s walk (docs/CHAIN.md, "Jittered stamps"). Whether the stamps
//! are jittered or the samples truly uneven is the knee methods' stamp clock
//! verdict ([`crate::knee_selfalign::stamp_clock::StampClock`]: the thigh and
//! shank rates are smooth on the right time base), on the sensor's grid of
//! [`crate::stamp_grid`]; on the grid verdict a step is whole grid steps.
//! Evenly stamped recordings are never scored and keep their stamps (bit for
//! bit as before).

use limbfuse_core::sample::ImuSample;
use limbfuse_core::Sample;

use super::kinematics::OutOfPlane;
use super::ChainEkf;
use crate::knee_selfalign::stamp_clock::StampClock;

/// The stamp clock of a chain's thigh and shank readings and the time of
/// the last sample on the sensor's grid.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StampTime {
    clock: StampClock,
    t: f64,
}

impl StampTime {
    /// Observes `sample` (its step `dt` from the stamps, `None` for the
    /// first or after a gap); returns the step to predict over and the
    /// sample's time: whole grid steps from the last sample when the stamps
    /// are jittered, else the stamps' own.
    pub fn step(&mut self, sample: &Sample, dt: Option<f64>) -> (Option<f64>, f64) {
        let (thigh, shank) = (sample.imu[1].gyr, sample.imu[2].gyr);
        self.clock
            .observe_rates(sample.t, thigh.zip(shank).map(|(a, b)| [a, b]));
        match (dt, self.clock.last_grid_step()) {
            (Some(_), Some(g)) => {
                self.t += g;
                (Some(g), self.t)
            }
            _ => {
                self.t = sample.t;
                (dt, sample.t)
            }
        }
    }
}

impl ChainEkf {
    /// Records the gyro x/y rates of every sensor (for their derivative).
    pub(super) fn out_of_plane_rates(&mut self, sample: &Sample) {
        for i in 0..4 {
            self.out_of_plane(i, &sample.imu[i], sample.t);
        }
    }

    /// The non-sagittal rotation of segment `i`'s sensor (zero when off or
    /// without gyro x and y readings, which an incomplete vector without z
    /// may still hold); remembers the reading for the next derivative.
    pub(super) fn out_of_plane(&mut self, i: usize, imu: &ImuSample, t: f64) -> OutOfPlane {
        let (Some(x), Some(y)) = (imu.gyr_axis(0), imu.gyr_axis(1)) else {
            return OutOfPlane::default();
        };
        let rate = [x, y];
        let derivative = match self.last_xy_rate[i] {
            Some((prev, tp)) if t > tp => [
                (rate[0] - prev[0]) / (t - tp),
                (rate[1] - prev[1]) / (t - tp),
            ],
            _ => [0.0, 0.0],
        };
        self.last_xy_rate[i] = Some((rate, t));
        if self.params.out_of_plane {
            OutOfPlane {
                rate,
                rate_derivative: derivative,
            }
        } else {
            OutOfPlane::default()
        }
    }
}
