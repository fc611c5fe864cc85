//! Mahony's nonlinear complementary orientation filter (R. Mahony, T. Hamel,
//! J.-M. Pflimlin, "Nonlinear complementary filters on the special
//! orthogonal group", IEEE Trans. Automatic Control 53(5), 2008), in the
//! explicit form with gyro-bias integral:
//!
//! `e = a_hat x v_hat`, `b_dot = -k_i e`, `q_dot = 1/2 q (x) (omega - b + k_p e)`,
//!
//! with `a_hat` the normalised specific force (points up when static) and
//! `v_hat = R^T y_world` the estimated up direction in the sensor frame
//! (world y up, SPEC section 1). No magnetometer: heading is unobserved.
//! Default gains `k_p = 0.5`, `k_i = 0` are those of the widely used
//! reference implementation (S. Madgwick, `MahonyAHRS.c`, x-io
//! Technologies, 2011: `twoKp = 2 * 0.5`, `twoKi = 0`).
//!
//! Step size (ours, not the paper's, which is continuous-time): one explicit
//! Euler step turns a small tilt error `x` into `(1 - k_p dt) x`, and with
//! the bias integral the error follows `z^2 - (2 - a) z + (1 - a + b)`,
//! `a = k_p dt`, `b = k_i dt^2`, stable only for `a < 2` and `b < a` (Jury).
//! So per step `k_p dt` is capped at 1 (a step corrects at most the whole
//! error: the accelerometer's tilt) and `k_i dt^2` at `k_p dt / 2`; gains
//! within those bounds are used as given (an audit: `kp = 1e6` at 100 Hz
//! gave a 40 deg knee error, `ki = 1000` 93 deg).

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// Gains of the filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MahonyGains {
    /// Proportional gain `k_p` (rad/s per unit error).
    pub kp: f64,
    /// Integral gain `k_i` (rad/s^2 per unit error).
    pub ki: f64,
}

impl MahonyGains {
    /// The gains one step of `dt` uses: `k_p dt` at most 1 and `k_i dt^2` at
    /// most `k_p dt / 2` (module doc); within them, the gains as given.
    pub fn for_step(&self, dt: f64) -> (f64, f64) {
        let kp = if self.kp * dt > 1.0 {
            1.0 / dt
        } else {
            self.kp
        };
        let ki = if self.ki * dt * dt > 0.5 * kp * dt {
            0.5 * kp / dt
        } else {
            self.ki
        };
        (kp, ki)
    }
}

impl Default for MahonyGains {
    fn default() -> Self {
        MahonyGains { kp: 0.5, ki: 0.0 }
    }
}

/// One IMU's orientation (sensor to world) and gyro-bias estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mahony {
    /// Orientation, sensor frame to world frame.
    pub q: UnitQuaternion<f64>,
    /// Gyro bias estimate (rad/s).
    pub bias: Vector3<f64>,
}

impl Mahony {
    /// Starts level: the rotation taking the measured up direction to world
    /// up with no heading (shortest arc).
    pub fn from_accel(acc: &Vector3<f64>) -> Self {
        let q = UnitQuaternion::rotation_between(acc, &Vector3::y()).unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), core::f64::consts::PI)
        });
        Mahony {
            q,
            bias: Vector3::zeros(),
        }
    }

    /// Advances by `dt` with gyro `gyr` (rad/s) and, when present and not
    /// degenerate, accelerometer `acc`; RK1 on the quaternion then
    /// renormalisation (as the reference implementation).
    pub fn update(
        &mut self,
        gyr: &Vector3<f64>,
        acc: Option<&Vector3<f64>>,
        dt: f64,
        gains: &MahonyGains,
    ) {
        let mut omega = gyr - self.bias;
        if let Some(a) = acc {
            let n = a.norm();
            if n > 1e-6 {
                let up_est = self.q.inverse_transform_vector(&Vector3::y());
                let e = (a / n).cross(&up_est);
                let (kp, ki) = gains.for_step(dt);
                self.bias -= e * (ki * dt);
                omega += e * kp;
            }
        }
        let dq = self.q.quaternion() * Quaternion::from_imag(omega * 0.5);
        let q = self.q.quaternion() + dq * dt;
        self.q = UnitQuaternion::from_quaternion(q);
    }
}

/// Sagittal joint angle `theta_proximal - theta_distal` from two sensor-to-world
/// orientations: minus the twist about z of the distal sensor's orientation
/// relative to the proximal one, wrapped to (-pi, pi].
pub fn sagittal_joint_angle(proximal: &UnitQuaternion<f64>, distal: &UnitQuaternion<f64>) -> f64 {
    let rel = proximal.inverse() * distal;
    let q = rel.quaternion();
    let twist = 2.0 * libm::atan2(q.k, q.w);
    let mut a = -twist;
    while a > core::f64::consts::PI {
        a -= core::f64::consts::TAU;
    }
    while a <= -core::f64::consts::PI {
        a += core::f64::consts::TAU;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn starts_at_the_accelerometer_inclination_and_follows_a_rotation() {
        let th: f64 = 0.3;
        let m = Mahony::from_accel(&Vector3::new(9.81 * th.sin(), 9.81 * th.cos(), 0.0));
        let (axis, angle) = m.q.axis_angle().unwrap();
        assert!((angle - th).abs() < 1e-12 && (axis.z - 1.0).abs() < 1e-12);
        // Pure gyro rotation about z at 1 rad/s for 0.5 s, consistent accel.
        let mut m = m;
        let g = MahonyGains::default();
        for k in 1..=500 {
            let t = th + k as f64 * 1e-3;
            let a = Vector3::new(9.81 * t.sin(), 9.81 * t.cos(), 0.0);
            m.update(&Vector3::new(0.0, 0.0, 1.0), Some(&a), 1e-3, &g);
        }
        let upright = UnitQuaternion::identity();
        let angle = -sagittal_joint_angle(&upright, &m.q);
        // The accelerometer leads the estimate by one step (1 mrad), which the
        // proportional term turns into k_p * dt * 1 mrad per step: 2.5e-4 rad.
        assert!((angle - (th + 0.5)).abs() < 3e-4, "{angle}");
    }

    #[test]
    fn gains_beyond_the_stable_step_are_capped() {
        let g = MahonyGains { kp: 0.5, ki: 0.1 };
        assert_eq!(g.for_step(0.01), (0.5, 0.1));
        // k_p dt = 1e4 -> 1 (k_p = 1/dt); k_i dt^2 = 0.1 < k_p dt / 2 = 0.5: kept.
        let g = MahonyGains { kp: 1e6, ki: 1e3 };
        assert_eq!(g.for_step(0.01), (100.0, 1e3));
        // k_i dt^2 = 1e4 > 0.5: k_i = (k_p dt / 2) / dt^2 = 5000.
        let g = MahonyGains { kp: 1e6, ki: 1e8 };
        assert_eq!(g.for_step(0.01), (100.0, 5000.0));
        // k_p dt = 0.005, k_i dt^2 = 0.1 > 0.0025: k_i = 0.0025 / dt^2 = 25.
        let g = MahonyGains { kp: 0.5, ki: 1e3 };
        assert_eq!(g.for_step(0.01), (0.5, 25.0));
        // One step at the cap lands on the accelerometer's tilt up to the
        // small-angle term: error x -> x - sin x.
        let x: f64 = 0.1;
        let mut m = Mahony::from_accel(&Vector3::new(0.0, 9.81, 0.0));
        let a = Vector3::new(9.81 * x.sin(), 9.81 * x.cos(), 0.0);
        m.update(
            &Vector3::zeros(),
            Some(&a),
            0.01,
            &MahonyGains { kp: 1e9, ki: 0.0 },
        );
        let angle = -sagittal_joint_angle(&UnitQuaternion::identity(), &m.q);
        let expected = (x.sin() * 0.5).atan() * 2.0; // RK1 on q, renormalised
        assert!((angle - expected).abs() < 1e-12, "{angle} {expected}");
        assert!((angle - x).abs() < 3e-4, "{angle}"); // x^3/6 + the atan term
    }

    #[test]
    fn accelerometer_corrects_a_wrong_start() {
        let mut m = Mahony::from_accel(&Vector3::new(0.0, 9.81, 0.0));
        let a = Vector3::new(9.81 * 0.2f64.sin(), 9.81 * 0.2f64.cos(), 0.0);
        for _ in 0..3000 {
            m.update(&Vector3::zeros(), Some(&a), 0.01, &MahonyGains::default());
        }
        let angle = -sagittal_joint_angle(&UnitQuaternion::identity(), &m.q);
        assert!((angle - 0.2).abs() < 1e-4, "{angle}");
    }
}
