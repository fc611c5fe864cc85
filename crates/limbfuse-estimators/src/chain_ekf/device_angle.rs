//! The device's own orientation as an angle row (docs/CHAIN.md, "Device
//! orientation"; ours, beyond the papers).
//!
//! Inertial units such as the Xsens MTx report their orientation
//! (`<seg>_quat_*`: sensor to the device's world; after `align`, segment to
//! world). A planar model turns each segment about one fixed axis, but a
//! recorded segment angle is the segment's long axis projected on the
//! walking plane (docs/RESULTS.md, "the attitude floor"). With the device's
//! orientation `R`, the long axis in the world is `d = R (0, -1, 0)` (align's
//! frame: `y` up along the segment), and the angle is
//! `atan2(d . f, -d . up)` for a forward direction `f` and the up `up` of the
//! device's world:
//! - `up` is the axis of the device's world (gravity-aligned by
//!   construction: ENU `z` up, NED `z` down, some `y` up) nearest the mean
//!   specific force turned into the world (`R a`; gravity, as the walking
//!   accelerations average out), decided after 1 s (a plain mean, then over
//!   the last 10 s) when it is within 20 deg of an axis: the mean itself
//!   is 5-10 deg off gravity over a second of walking on S02, the axis
//!   exact;
//! - `f` is the segment's own forward: up x (its `z`, the medio-lateral
//!   axis after `align`, made horizontal). It turns with the segment, so it
//!   needs no heading (a magnetometer's heading differs between sensors:
//!   docs/RESULTS.md), and a turn does not move it. (A walking direction
//!   learned per sensor as the principal direction of the long axis's
//!   horizontal motion was tried: within 4 deg of this forward on S02 and no
//!   better.)
//!
//! The orientation is used only while it turns as the gyroscope says (its
//! rate, from one sample to the next, against the gyro's): an orientation
//! in another convention (world to sensor, another axis order) or of
//! another sensor is not used.
//!
//! The angle enters the filter as a row on the segment angle: `theta_i` is
//! the angle of the aligned sensor frame (docs/CHAIN.md, "Frame offsets"),
//! and so is the projection of that frame's `-y`, with no offset between
//! them. (An offset learned from the first rows was tried: a start in a
//! turn learned the chain's start-up error into it.)

use limbfuse_core::Sample;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use super::covariance::scalar_update;
use super::state::{theta, SparseRow};
use super::ChainEkf;

/// Time constant (s) of the device world's up (a long mean of `R a`).
const UP_TAU_S: f64 = 10.0;
/// The device's up is decided after this long (s) ...
const UP_READY_S: f64 = 1.0;
/// ... as the world axis within this angle (deg) of the mean specific
/// force (a second's mean while walking is within 10 deg of it on S02).
const UP_AXIS_DEG: f64 = 20.0;
/// Time constant (s) of the comparison of the orientation's rate with the
/// gyroscope's.
const RATE_TAU_S: f64 = 1.0;
/// The comparison decides only while the gyro's RMS rate exceeds this
/// (rad/s) ...
const MOVING_RATE: f64 = 0.3;
/// ... and passes when the mean square difference is below this fraction
/// of the gyro's mean square (a quarter: an RMS difference of half the
/// rate; an orientation of another convention, or of another sensor,
/// differs by more than the rate itself).
const RATE_AGREEMENT: f64 = 0.25;

/// One sensor's up and orientation check.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct DeviceAngle {
    /// Mean of the specific force turned into the world (m/s^2).
    up_mean: Option<Vector3<f64>>,
    /// Time (s) over which `up_mean` was formed, and its samples.
    tracked_s: f64,
    up_n: f64,
    /// The previous orientation (for its rate).
    last: Option<UnitQuaternion<f64>>,
    /// Mean square of the orientation's rate minus the gyro's, and of the
    /// gyro's rate ((rad/s)^2).
    rate_error: f64,
    rate_power: f64,
    /// The orientation turns as the gyroscope says (decided while moving).
    consistent: bool,
}

fn wrap(a: f64) -> f64 {
    libm::atan2(libm::sin(a), libm::cos(a))
}

impl DeviceAngle {
    /// Tracks one sample; the device's angle (rad).
    pub(super) fn observe(
        &mut self,
        quat: [f64; 4],
        acc: Option<Vector3<f64>>,
        gyr: Option<Vector3<f64>>,
        dt: f64,
    ) -> Option<f64> {
        let q = Quaternion::new(quat[0], quat[1], quat[2], quat[3]);
        if !(q.norm() > 1e-9 && q.coords.iter().all(|c| c.is_finite())) {
            return None;
        }
        let r = UnitQuaternion::from_quaternion(q);
        if let (Some(last), Some(w), true) = (self.last, gyr, dt > 0.0) {
            // The body rate of the orientation, `2 vec(q_prev^-1 q) / dt`.
            let e = (last.inverse() * r).scaled_axis() / dt - w;
            let k = (dt / RATE_TAU_S).min(1.0);
            self.rate_error += (e.norm_squared() - self.rate_error) * k;
            self.rate_power += (w.norm_squared() - self.rate_power) * k;
            if self.rate_power > MOVING_RATE * MOVING_RATE {
                self.consistent = self.rate_error < RATE_AGREEMENT * self.rate_power;
            }
        }
        self.last = Some(r);
        if let Some(a) = acc.map(|a| r * a) {
            // A plain mean until it spans `UP_TAU_S`, then exponential (one
            // sample's specific force is off by the walking accelerations).
            self.up_n += 1.0;
            let k = (dt / UP_TAU_S).max(1.0 / self.up_n).min(1.0);
            self.up_mean = Some(self.up_mean.map_or(a, |u| u + (a - u) * k));
            self.tracked_s += dt;
        }
        let mean = self.up_mean?;
        if !self.consistent || self.tracked_s < UP_READY_S {
            return None;
        }
        // A device's world is gravity-aligned with one of its axes up (ENU
        // z up, NED z down, some y up): the axis nearest the mean, when it
        // is within `UP_AXIS_DEG` of it.
        let mean = mean.try_normalize(1e-9)?;
        let k = mean.iamax();
        if libm::fabs(mean[k]) < libm::cos(UP_AXIS_DEG.to_radians()) {
            return None;
        }
        let mut up = Vector3::zeros();
        up[k] = libm::copysign(1.0, mean[k]);
        let z = r * Vector3::z();
        let lateral = (z - up * up.dot(&z)).try_normalize(1e-6)?;
        let forward = up.cross(&lateral);
        let d = r * Vector3::new(0.0, -1.0, 0.0);
        Some(libm::atan2(d.dot(&forward), -d.dot(&up)))
    }
}

impl ChainEkf {
    /// The device orientation rows (module docs), one per sensor with a
    /// quaternion, turns included.
    pub(super) fn device_rows(&mut self, sample: &Sample, dt: f64) {
        let p = self.params;
        if !p.device_orientation {
            return;
        }
        for i in 0..4 {
            let imu = &sample.imu[i];
            let Some(q) = imu.quat else { continue };
            let acc = imu.acc.filter(|a| a.iter().all(|c| c.is_finite()));
            let gyr = imu.gyr.filter(|w| w.iter().all(|c| c.is_finite()));
            let Some(angle) = self.device[i].observe(q, acc, gyr, dt) else {
                continue;
            };
            let mut row = SparseRow::new();
            row.add(theta(i), 1.0);
            let nu = wrap(angle - self.x[theta(i)]);
            let r = p.device_angle_noise * p.device_angle_noise * self.variance_scale;
            scalar_update(&mut self.x, &mut self.p, &row, nu, r, f64::INFINITY);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::TAU;

    /// A segment swinging `theta(t) = 0.5 sin(2 pi t)` about its `z` in a
    /// vertical plane whose heading is `psi` (world `y` up): its
    /// orientation, gravity's specific force and its gyro, per sample.
    fn swing(psi: f64, k: usize) -> (f64, UnitQuaternion<f64>, Vector3<f64>, Vector3<f64>) {
        let t = k as f64 * 0.01;
        let theta = 0.5 * libm::sin(TAU * t);
        let rate = 0.5 * TAU * libm::cos(TAU * t);
        let r = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), psi)
            * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta);
        let acc = r.inverse() * Vector3::new(0.0, 9.81, 0.0);
        (theta, r, acc, Vector3::new(0.0, 0.0, rate))
    }

    fn wxyz(q: &UnitQuaternion<f64>) -> [f64; 4] {
        [q.w, q.i, q.j, q.k]
    }

    #[test]
    fn the_device_angle_is_the_planar_angle_whatever_the_heading() {
        for psi in [0.0, 1.0, 2.5, -2.0] {
            let mut d = DeviceAngle::default();
            let mut checked = 0;
            for k in 0..300 {
                let (theta, r, acc, gyr) = swing(psi, k);
                if let Some(a) = d.observe(wxyz(&r), Some(acc), Some(gyr), 0.01) {
                    assert!((a - theta).abs() < 1e-9, "psi {psi}: {a} against {theta}");
                    checked += 1;
                }
            }
            assert!(checked > 150, "psi {psi}: only {checked} angles");
        }
    }

    #[test]
    fn an_orientation_in_another_convention_is_not_used() {
        // World to sensor instead of sensor to world: the conjugate.
        let mut d = DeviceAngle::default();
        for k in 0..300 {
            let (_, r, acc, gyr) = swing(0.7, k);
            let a = d.observe(wxyz(&r.inverse()), Some(acc), Some(gyr), 0.01);
            assert_eq!(a, None, "sample {k}");
        }
    }
}
