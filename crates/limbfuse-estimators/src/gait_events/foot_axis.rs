//! The foot's medio-lateral (pitch) axis in the raw sensor frame: the
//! principal component of the angular rate while the foot moves (walking
//! rotates the foot mostly about that axis), signed to point to the
//! subject's right with the walking direction found by the stride
//! integration, so that the signed rate is SPEC section 1's `d theta / dt`
//! (positive toe-up: the swing).
//!
//! The second moment `M = E[w w^T]` is averaged exponentially over the
//! moving samples (time constant `tau`); its dominant eigenvector is
//! followed by one power-iteration step per sample, `u <- M u / ||M u||`,
//! which never reverses `u` (`u^T M u >= 0`), so the sign evidence stays
//! valid while the axis is refined. Sign: after each stride, the right
//! direction in the sensor frame is `forward x up` (SPEC axes: z = x cross
//! y); its dot product with `u` votes for the sign.

use nalgebra::{Matrix3, Vector3};

/// Streaming principal axis with its sign.
#[derive(Debug, Clone)]
pub struct FootAxis {
    moment: Matrix3<f64>,
    axis: Vector3<f64>,
    time_constant: f64,
    weight: f64,
    sign_score: i32,
}

/// Votes beyond which the score stops growing (a later, consistently
/// opposite evidence can still reverse the sign after this many strides).
const MAX_SCORE: i32 = 5;

impl FootAxis {
    /// An axis tracker with averaging time constant `time_constant` (s).
    pub fn new(time_constant: f64) -> Self {
        FootAxis {
            moment: Matrix3::zeros(),
            axis: Vector3::new(1.0, 1.0, 1.0).normalize(),
            time_constant,
            weight: 0.0,
            sign_score: 0,
        }
    }

    /// Adds one moving sample.
    pub fn update(&mut self, gyr: &Vector3<f64>, dt: f64) {
        self.weight = (self.weight + dt).min(self.time_constant);
        let alpha = dt / self.weight.max(dt);
        self.moment += (gyr * gyr.transpose() - self.moment) * alpha;
        let next = self.moment * self.axis;
        let n = next.norm();
        if n > 1e-12 {
            self.axis = next / n;
        }
    }

    /// Records the evidence of one stride: the subject's right in the sensor frame.
    pub fn vote(&mut self, right_in_sensor: &Vector3<f64>) {
        let d = right_in_sensor.dot(&self.axis);
        if d > 0.0 {
            self.sign_score = (self.sign_score + 1).min(MAX_SCORE);
        } else if d < 0.0 {
            self.sign_score = (self.sign_score - 1).max(-MAX_SCORE);
        }
    }

    /// The sign decision: +1 or -1 (the axis as tracked, or reversed), 0 while undecided.
    pub fn sign(&self) -> i32 {
        self.sign_score.signum()
    }

    /// The tracked axis before signing (unit; its sign is arbitrary but
    /// never reversed by the tracking).
    pub fn unsigned_axis(&self) -> Vector3<f64> {
        self.axis
    }

    /// The signed axis (pointing right), once a stride has decided it.
    pub fn right_axis(&self) -> Option<Vector3<f64>> {
        match self.sign_score.signum() {
            0 => None,
            s => Some(self.axis * f64::from(s)),
        }
    }

    /// The sagittal angular rate `d theta / dt` (rad/s), once the sign is known.
    pub fn sagittal_rate(&self, gyr: &Vector3<f64>) -> Option<f64> {
        self.right_axis().map(|a| a.dot(gyr))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_dominant_rotation_axis_and_its_sign() {
        let true_axis = Vector3::new(0.2, -0.4, 0.9).normalize();
        let other = true_axis.cross(&Vector3::x()).normalize();
        let mut f = FootAxis::new(10.0);
        for k in 0..4000 {
            let t = k as f64 * 0.005;
            let w = true_axis * (5.0 * libm::sin(6.0 * t)) + other * (0.8 * libm::cos(11.0 * t));
            f.update(&w, 0.005);
        }
        assert!(f.right_axis().is_none());
        f.vote(&(-true_axis + other * 0.3));
        let a = f.right_axis().unwrap();
        assert!((a + true_axis).norm() < 5e-3, "{a:?}");
        assert!((f.sagittal_rate(&true_axis).unwrap() + 1.0).abs() < 5e-3);
    }
}
