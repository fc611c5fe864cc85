//! The knee angle from the identified axes and positions (paper 002
//! section 2.2.3 and 2.3): the gyro angle rate (integrand of eq 4), the
//! accelerometer angle (eqs 5-7, with a signed `atan2`: SPEC section 6), and
//! the one-state complementary Kalman filter that fuses them (Algorithm 1).

use nalgebra::Vector3;

/// Integrand of eq 4: `g_T . j_T - g_S . j_S`, the knee angle rate (rad/s)
/// when both axes point to the same side.
pub fn gyro_angle_rate(
    g_t: &Vector3<f64>,
    g_s: &Vector3<f64>,
    j_t: &Vector3<f64>,
    j_s: &Vector3<f64>,
) -> f64 {
    g_t.dot(j_t) - g_s.dot(j_s)
}

/// An orthonormal basis `(x_i, y_i)` of the joint plane of one sensor
/// (eq 6), with `x_i x y_i = j_i`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneBasis {
    /// First in-plane direction.
    pub x: Vector3<f64>,
    /// Second in-plane direction, `j x x`.
    pub y: Vector3<f64>,
}

impl PlaneBasis {
    /// The paper's basis (eq 6): `x = j x c`, `y = j x x`, normalised; `c`
    /// must not be parallel to `j`. `None` when it (nearly) is.
    pub fn from_cross(j: &Vector3<f64>, c: &Vector3<f64>) -> Option<Self> {
        let x = j.cross(c);
        let n = x.norm();
        if n < 1e-6 {
            return None;
        }
        let x = x / n;
        Some(PlaneBasis { x, y: j.cross(&x) })
    }

    /// The basis whose `x` is the direction of `reference` in the joint plane
    /// (`reference` minus its component along `j`). This is eq 6 with `c =
    /// reference x j`. `None` when `reference` is (nearly) along `j`.
    pub fn from_reference(j: &Vector3<f64>, reference: &Vector3<f64>) -> Option<Self> {
        Self::from_cross(j, &reference.cross(j))
    }

    /// Coordinates `u = (v . x, v . y)` of a vector in this basis (eq 6).
    pub fn project(&self, v: &Vector3<f64>) -> (f64, f64) {
        (v.dot(&self.x), v.dot(&self.y))
    }
}

/// The accelerometer angle (eq 5 with a signed `atan2`): the angle from
/// `u_T` to `u_S` about the joint axis, `atan2(u_T x u_S, u_T . u_S)`, in
/// `(-pi, pi]`. `a_t`, `a_s` are the joint-centre accelerations of eq 7.
/// With axes along the segments' `+z` (SPEC section 1) this is the knee angle
/// `theta_thigh - theta_shank` up to the offset between the two bases.
/// `None` when either projection is (nearly) zero.
pub fn accel_angle(
    a_t: &Vector3<f64>,
    a_s: &Vector3<f64>,
    basis_t: &PlaneBasis,
    basis_s: &PlaneBasis,
) -> Option<f64> {
    let (tx, ty) = basis_t.project(a_t);
    let (sx, sy) = basis_s.project(a_s);
    if libm::hypot(tx, ty) < 1e-6 || libm::hypot(sx, sy) < 1e-6 {
        return None;
    }
    Some(libm::atan2(tx * sy - ty * sx, tx * sx + ty * sy))
}

/// Wraps an angle into `(-pi, pi]`.
pub fn wrap(a: f64) -> f64 {
    let tau = core::f64::consts::TAU;
    let mut w = libm::remainder(a, tau);
    if w <= -core::f64::consts::PI {
        w += tau;
    }
    w
}

/// The sample interval at which paper 002 gives Algorithm 1's `Q` and `R`
/// (its recordings and simulations are at 100 Hz) (s).
pub const PAPER_DT: f64 = 0.01;

/// The complementary Kalman filter of Algorithm 1: one state, the
/// difference `dalpha` between the accelerometer and gyro angles, with `A =
/// B = H = 1`. The fused angle is `alpha_gyro + x`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComplementaryKf {
    /// State estimate `x` (rad).
    pub x: f64,
    /// Its variance `P` (rad^2).
    pub p: f64,
    /// Process noise `Q` per sample (paper: 5e-6 rad^2).
    pub q: f64,
    /// Measurement noise `R` (paper: 0.2 rad^2).
    pub r: f64,
}

impl ComplementaryKf {
    /// `x0 = 0`, `P0 = 1` (Algorithm 1).
    pub fn new(q: f64, r: f64) -> Self {
        ComplementaryKf {
            x: 0.0,
            p: 1.0,
            q,
            r,
        }
    }

    /// Prediction: `x <- x`, `P <- P + Q`.
    pub fn predict(&mut self) {
        self.p += self.q;
    }

    /// Prediction over a step of `dt` seconds (ours, issue 15 item 3):
    /// `P <- P + Q (dt / PAPER_DT)^2`. The paper gives `Q` and `R` per
    /// sample at 100 Hz, where the steady-state gain `K ~ sqrt(Q / R)` =
    /// 0.005 makes the accelerometer angle correct the gyro angle with a
    /// time constant of ~200 samples = 2 s. Per sample at another rate, the
    /// same `Q` keeps 200 *samples* (5 s at 40 Hz, 0.8 s at 250 Hz), and the
    /// lag of the gyro angle's drift (relative gyro bias `b`: `b tau`) grows
    /// with it: the mean error of the shared 1.2 m/s walk was -1.09 deg at
    /// 100 Hz, -2.35 at 40 Hz and -0.48 at 250 Hz, in proportion to the time
    /// constant in seconds. Scaling `Q` with `dt^2` keeps `K / dt`, and so
    /// the time constant, in seconds (a complementary filter is specified by
    /// its crossover frequency). Within 0.1 % of 100 Hz, and for a step of
    /// unknown length, `Q` is the paper's exactly ([`Self::predict`]).
    pub fn predict_over(&mut self, dt: f64) {
        let s = dt / PAPER_DT;
        if !(s > 0.0 && s.is_finite()) || (s - 1.0).abs() <= 1e-3 {
            self.predict();
        } else {
            self.p += self.q * s * s;
        }
    }

    /// Correction with `z = alpha_acc - alpha_gyro`. The innovation is
    /// wrapped into `(-pi, pi]` so an angle crossing +-pi does not jump.
    pub fn update(&mut self, z: f64) {
        let k = self.p / (self.p + self.r);
        self.x += k * wrap(z - self.x);
        self.p *= 1.0 - k;
    }
}

/// An extension of Algorithm 1 (not in paper 002): a second state for the
/// rate bias of `alpha_gyro' = g_T . j_T - g_S . j_S`, so that a constant
/// gyro-bias difference does not leave a lag of `b / (gain / dt)`.
///
/// State `[x, b]`: `x` the correction added to `alpha_gyro` (as in
/// Algorithm 1), `b` the rate bias; `x_{k+1} = x_k - b dt`, `b_{k+1} = b_k`;
/// `z = alpha_acc - alpha_gyro = x + v`. `Q = diag(q, q_b)` per sample,
/// `R = r`, `P0 = diag(1, p_b0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RateBiasKf {
    /// Correction `x` (rad) and rate bias `b` (rad/s).
    pub x: [f64; 2],
    /// Covariance.
    pub p: [[f64; 2]; 2],
    /// Process noise of `x` per sample (rad^2).
    pub q: f64,
    /// Process noise of `b` per sample ((rad/s)^2).
    pub q_b: f64,
    /// Measurement noise (rad^2).
    pub r: f64,
}

impl RateBiasKf {
    /// `x0 = 0`, `P0 = diag(1, p_b0)`.
    pub fn new(q: f64, q_b: f64, r: f64, p_b0: f64) -> Self {
        RateBiasKf {
            x: [0.0; 2],
            p: [[1.0, 0.0], [0.0, p_b0]],
            q,
            q_b,
            r,
        }
    }

    /// Prediction over `dt` seconds.
    pub fn predict(&mut self, dt: f64) {
        let [x, b] = self.x;
        self.x = [x - b * dt, b];
        let p = self.p;
        // P <- F P F^T + Q with F = [[1, -dt], [0, 1]].
        let p00 = p[0][0] - dt * (p[1][0] + p[0][1]) + dt * dt * p[1][1] + self.q;
        let p01 = p[0][1] - dt * p[1][1];
        let p11 = p[1][1] + self.q_b;
        self.p = [[p00, p01], [p01, p11]];
    }

    /// Correction with `z = alpha_acc - alpha_gyro` (innovation wrapped).
    pub fn update(&mut self, z: f64) {
        let s = self.p[0][0] + self.r;
        let k = [self.p[0][0] / s, self.p[1][0] / s];
        let nu = wrap(z - self.x[0]);
        self.x = [self.x[0] + k[0] * nu, self.x[1] + k[1] * nu];
        let p = self.p;
        let p00 = (1.0 - k[0]) * p[0][0];
        let p01 = (1.0 - k[0]) * p[0][1];
        let p11 = p[1][1] - k[1] * p[0][1];
        self.p = [[p00, p01], [p01, p11]];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_atan2_recovers_the_relative_rotation() {
        // Both sensors with j = z; the shank frame turned by -knee about z.
        let j = Vector3::z();
        let b = PlaneBasis::from_cross(&j, &Vector3::x()).unwrap();
        for knee in [-0.3f64, 0.0, 0.4, 1.2, 3.0] {
            let v_world = Vector3::new(0.3, 9.7, 0.0);
            let r = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), -knee);
            let v_s = r.inverse() * v_world;
            let a = accel_angle(&v_world, &v_s, &b, &b).unwrap();
            assert!((a - knee).abs() < 1e-12, "{a} vs {knee}");
        }
    }

    #[test]
    fn eq6_basis_hand_values() {
        // j = z, c = x: x = z cross x = y, y = z cross y = -x.
        let b = PlaneBasis::from_cross(&Vector3::z(), &Vector3::x()).unwrap();
        assert!((b.x - Vector3::y()).norm() < 1e-15);
        assert!((b.y + Vector3::x()).norm() < 1e-15);
        let r = PlaneBasis::from_reference(&Vector3::z(), &Vector3::new(0.0, 2.0, 5.0)).unwrap();
        assert!((r.x - Vector3::y()).norm() < 1e-15);
        assert!(PlaneBasis::from_cross(&Vector3::z(), &Vector3::z()).is_none());
    }

    #[test]
    fn algorithm1_first_steps_by_hand() {
        let mut kf = ComplementaryKf::new(5e-6, 0.2);
        kf.predict();
        kf.update(0.5);
        let p1 = 1.0 + 5e-6;
        let k1 = p1 / (p1 + 0.2);
        assert!((kf.x - k1 * 0.5).abs() < 1e-15);
        assert!((kf.p - (1.0 - k1) * p1).abs() < 1e-15);
        // The steady-state gain is about sqrt(Q / R) = 0.005.
        for _ in 0..20_000 {
            kf.predict();
            kf.update(0.5);
        }
        let k = kf.p / (kf.p + kf.r);
        assert!((kf.x - 0.5).abs() < 1e-9);
        assert!((k - 0.005).abs() < 2e-4, "{k}");
    }

    #[test]
    fn rate_bias_state_removes_the_ramp_lag() {
        // alpha_gyro carries a 0.01 rad/s bias: z = -0.01 t. Algorithm 1
        // lags it by about b dt / K; the two-state filter does not.
        let dt = 0.01;
        let mut one = ComplementaryKf::new(5e-6, 0.2);
        let mut two = RateBiasKf::new(5e-6, 1e-10, 0.2, 1e-4);
        for k in 1..=20_000 {
            let z = -0.01 * k as f64 * dt;
            one.predict();
            one.update(z);
            two.predict(dt);
            two.update(z);
        }
        let z = -0.01 * 20_000.0 * dt;
        let lag_one = (one.x - z).abs();
        let lag_two = (two.x[0] - z).abs();
        // Steady-state lag of Algorithm 1: b dt / K = 1e-4 / 0.0050 = 0.02 rad.
        assert!((lag_one - 0.02).abs() < 0.002, "{lag_one}");
        assert!(lag_two < 0.002, "{lag_two}");
        assert!((two.x[1] - 0.01).abs() < 1e-3, "{}", two.x[1]);
    }

    /// Issue 15 item 3: the paper's `Q` per sample made Algorithm 1's time
    /// constant 200 samples at every rate, so the lag of a drifting gyro
    /// angle was 2.5 times longer at 40 Hz than at 100 Hz (the shared 1.2 m/s
    /// walk: mean error -2.35 deg at 40 Hz, -1.09 at 100 Hz). With `Q`
    /// scaled by `(dt / 0.01 s)^2` the lag is the same in seconds.
    #[test]
    fn issue_15_time_constant_in_seconds_at_any_rate() {
        let bias = 0.01; // rad/s
        let lag = |rate: f64| {
            let dt = 1.0 / rate;
            let mut kf = ComplementaryKf::new(5e-6, 0.2);
            let n = (200.0 * rate) as usize;
            for k in 1..=n {
                kf.predict_over(dt);
                kf.update(-bias * k as f64 * dt);
            }
            (kf.x + bias * n as f64 * dt).abs()
        };
        let (l40, l100, l250) = (lag(40.0), lag(100.0), lag(250.0));
        // 100 Hz: the paper's filter, lag b dt / K = 0.02 rad.
        assert!((l100 - 0.02).abs() < 0.002, "{l100}");
        assert!(
            (l40 / l100 - 1.0).abs() < 0.1,
            "40 Hz {l40} vs 100 Hz {l100}"
        );
        assert!(
            (l250 / l100 - 1.0).abs() < 0.1,
            "250 Hz {l250} vs 100 Hz {l100}"
        );
        // At 100 Hz, predict_over is the paper's predict exactly.
        let (mut a, mut b) = (
            ComplementaryKf::new(5e-6, 0.2),
            ComplementaryKf::new(5e-6, 0.2),
        );
        a.predict();
        b.predict_over(0.01);
        assert_eq!(a, b);
    }

    #[test]
    fn wrap_range() {
        assert!((wrap(3.0 * core::f64::consts::PI) - core::f64::consts::PI).abs() < 1e-12);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-15);
        assert!((wrap(7.0) - (7.0 - core::f64::consts::TAU)).abs() < 1e-12);
    }

    #[test]
    fn gyro_rate_is_the_difference_of_projections() {
        let r = gyro_angle_rate(
            &Vector3::new(1.0, 2.0, 3.0),
            &Vector3::new(0.5, 0.0, 1.0),
            &Vector3::z(),
            &Vector3::x(),
        );
        assert!((r - 2.5).abs() < 1e-15);
    }
}
