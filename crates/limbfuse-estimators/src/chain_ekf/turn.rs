//! Turning (docs/CHAIN.md, "Turns"): the planar model does not hold while
//! the body turns, so the angles' covariance widens.

use limbfuse_core::Sample;

use super::state::theta;
use super::ChainEkf;

impl ChainEkf {
    /// Turning (docs/CHAIN.md, "Turns"): updates `Omega`, the mean over the
    /// sensors of the rate about the vertical, `w_x sin theta_i + w_y cos
    /// theta_i` (the world's up in sensor `i`'s frame is `R(theta_i)^T (0,
    /// 1)`), low-passed with `turn_tau_s` (the stride-periodic yaw of pelvis
    /// and legs averages out, a turn does not). Beyond `turn_rate_min` the
    /// planar model does not hold: every angle's variance grows by
    /// `turn_angle_noise^2 (|Omega| - turn_rate_min) dt`, so that the
    /// accelerometers re-anchor the angles quickly once the turn ends.
    pub(super) fn turning(&mut self, sample: &Sample, dt: f64) {
        let p = self.params;
        let (mut sum, mut n) = (0.0, 0.0);
        for i in 0..4 {
            let imu = &sample.imu[i];
            if let (Some(wx), Some(wy)) = (imu.gyr_axis(0), imu.gyr_axis(1)) {
                if !(wx.is_finite() && wy.is_finite()) {
                    continue;
                }
                let (s, c) = (libm::sin(self.x[theta(i)]), libm::cos(self.x[theta(i)]));
                sum += wx * s + wy * c;
                n += 1.0;
            }
        }
        if n > 0.0 {
            let a = (dt / p.turn_tau_s).min(1.0);
            self.turn_rate += a * (sum / n - self.turn_rate);
        }
        let excess = libm::fabs(self.turn_rate) - p.turn_rate_min;
        self.widening = 0.0;
        if excess > 0.0 && p.turn_angle_noise > 0.0 {
            let q = p.turn_angle_noise * p.turn_angle_noise * excess * dt;
            self.widening = q;
            for i in 0..4 {
                self.p[(theta(i), theta(i))] += q;
            }
        }
    }
}
