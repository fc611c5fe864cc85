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
//! `atan2(d . f, -d . up)` for the forward direction `f` and up `up` of the
//! device's world. Neither is given:
//! - `up` is the long-run mean of the specific force turned into the world
//!   (`R a`; gravity, the walking accelerations average out);
//! - `f` is the principal direction of the long axis's horizontal motion
//!   over the last seconds (the leg swings along the walking direction),
//!   its sign the one that makes the projected angle turn with the
//!   segment's `z` gyro. Each sensor gets its own `f`: a magnetometer-based
//!   heading differs between the sensors (docs/RESULTS.md).
//!
//! The angle enters the filter as a row on the segment angle minus an
//! offset of its own (the device's zero need not be the chain's), the
//! offset following the mean difference. Not while turning (the walking
//! direction moves), not before the direction is established.

use limbfuse_core::Sample;
use nalgebra::{Matrix2, Quaternion, UnitQuaternion, Vector2, Vector3};

use super::covariance::scalar_update;
use super::state::{theta, SparseRow};
use super::ChainEkf;

/// Time constant (s) of the device world's up (a long mean of `R a`).
const UP_TAU_S: f64 = 10.0;
/// Time constant (s) of the mean and covariance of the long axis's
/// horizontal motion (a few strides).
const DIRECTION_TAU_S: f64 = 2.0;
/// Time constant (s) of the sign test (about a tenth of a stride).
const SIGN_TAU_S: f64 = 0.1;
/// Time constant (s) of the offset between the device's angle and the
/// chain's.
const OFFSET_TAU_S: f64 = 10.0;
/// The direction is established after this long (s) ...
const READY_S: f64 = 1.0;
/// ... and when the principal variance exceeds the other this many times.
const ANISOTROPY: f64 = 4.0;

/// One sensor's walking direction and offset.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct DeviceAngle {
    up: Option<Vector3<f64>>,
    mean: Vector2<f64>,
    cov: Matrix2<f64>,
    dir: Option<Vector2<f64>>,
    last: Option<Vector2<f64>>,
    sign: f64,
    tracked_s: f64,
    offset: Option<f64>,
    /// Rows since the offset started (its first ones are a plain mean).
    offset_n: f64,
}

fn wrap(a: f64) -> f64 {
    libm::atan2(libm::sin(a), libm::cos(a))
}

/// Unit eigenvector of the larger eigenvalue of a symmetric 2x2 matrix, and
/// the two eigenvalues (larger first).
fn principal(c: &Matrix2<f64>) -> (Vector2<f64>, f64, f64) {
    let (a, b, d) = (c[(0, 0)], c[(0, 1)], c[(1, 1)]);
    let mean = 0.5 * (a + d);
    let r = libm::sqrt(0.25 * (a - d) * (a - d) + b * b);
    let (l1, l2) = (mean + r, mean - r);
    let v = if libm::fabs(b) > 1e-12 {
        Vector2::new(l1 - d, b)
    } else if a >= d {
        Vector2::new(1.0, 0.0)
    } else {
        Vector2::new(0.0, 1.0)
    };
    (v.normalize(), l1, l2)
}

impl DeviceAngle {
    /// Tracks one sample; the device's angle (rad) once the walking
    /// direction is established.
    pub(super) fn observe(
        &mut self,
        quat: [f64; 4],
        acc: Option<Vector3<f64>>,
        rate_z: Option<f64>,
        dt: f64,
    ) -> Option<f64> {
        let q = Quaternion::new(quat[0], quat[1], quat[2], quat[3]);
        if !(q.norm() > 1e-9 && q.coords.iter().all(|c| c.is_finite())) {
            return None;
        }
        let r = UnitQuaternion::from_quaternion(q);
        if let Some(a) = acc.map(|a| r * a).and_then(|a| a.try_normalize(1e-9)) {
            let up = match self.up {
                None => a,
                Some(u) => u + (a - u) * (dt / UP_TAU_S).min(1.0),
            };
            self.up = up.try_normalize(1e-9);
        }
        let up = self.up?;
        let e1 = if libm::fabs(up.x) < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = (e1 - up * up.dot(&e1)).normalize();
        let e2 = up.cross(&e1);
        let d = r * Vector3::new(0.0, -1.0, 0.0);
        let h = Vector2::new(d.dot(&e1), d.dot(&e2));
        let k = (dt / DIRECTION_TAU_S).min(1.0);
        if self.tracked_s == 0.0 {
            self.mean = h;
        }
        self.mean += (h - self.mean) * k;
        let x = h - self.mean;
        self.cov += (x * x.transpose() - self.cov) * k;
        self.tracked_s += dt;
        let (mut v, l1, l2) = principal(&self.cov);
        if self.dir.is_some_and(|p| p.dot(&v) < 0.0) {
            v = -v;
        }
        self.dir = Some(v);
        if let (Some(last), Some(w)) = (self.last, rate_z) {
            if dt > 0.0 {
                let rate = (h - last).dot(&v) / dt;
                self.sign += (rate * w - self.sign) * (dt / SIGN_TAU_S).min(1.0);
            }
        }
        self.last = Some(h);
        if self.tracked_s < READY_S || l1 < ANISOTROPY * l2.max(0.0) || self.sign == 0.0 {
            return None;
        }
        let v = if self.sign < 0.0 { -v } else { v };
        let f = e1 * v.x + e2 * v.y;
        Some(libm::atan2(d.dot(&f), -d.dot(&up)))
    }

    /// Starts the walking direction and the offset again (the up stays:
    /// after a turn the direction's sign, and so the offset, may differ).
    fn forget_direction(&mut self) {
        *self = DeviceAngle {
            up: self.up,
            ..DeviceAngle::default()
        };
    }

    /// The offset between the device's angle `device` and the chain's
    /// `angle`, updated with this sample.
    fn offset(&mut self, device: f64, angle: f64, dt: f64) -> f64 {
        let diff = wrap(device - angle);
        let o = match self.offset {
            None => diff,
            Some(o) => o + wrap(diff - o) * (dt / OFFSET_TAU_S).clamp(1.0 / self.offset_n, 1.0),
        };
        self.offset_n += 1.0;
        self.offset = Some(o);
        o
    }
}

impl ChainEkf {
    /// The device orientation rows (module docs), one per sensor with a
    /// quaternion, skipped while turning.
    pub(super) fn device_rows(&mut self, sample: &Sample, dt: f64) {
        let p = self.params;
        if !p.device_orientation {
            return;
        }
        let turning = libm::fabs(self.turn_rate) > p.turn_rate_min;
        for i in 0..4 {
            let imu = &sample.imu[i];
            let Some(q) = imu.quat else { continue };
            let rate = imu.gyr_axis(2).filter(|w| w.is_finite());
            let acc = imu.acc.filter(|a| a.iter().all(|c| c.is_finite()));
            let angle = self.device[i].observe(q, acc, rate, dt);
            if turning {
                // The horizontal motion is the turn's: start the walking
                // direction again once it ends.
                self.device[i].forget_direction();
                continue;
            }
            let Some(angle) = angle else { continue };
            let offset = self.device[i].offset(angle, self.x[theta(i)], dt);
            let mut row = SparseRow::new();
            row.add(theta(i), 1.0);
            let nu = wrap(angle - offset - self.x[theta(i)]);
            let r = p.device_angle_noise * p.device_angle_noise * self.variance_scale;
            scalar_update(&mut self.x, &mut self.p, &row, nu, r, f64::INFINITY);
        }
    }
}
