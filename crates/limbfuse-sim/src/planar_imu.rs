//! Inputs of [`crate::imu_model::Imu`] for a segment rotating in the
//! sagittal plane: its rotation, world angular rate and the world specific
//! force at a sensor on the segment axis (used by the FES simulators).

use nalgebra::{Matrix3, Vector2, Vector3};

/// Kinematics of one planar segment at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarSegment {
    /// Absolute angle (rad), SPEC convention (0 = hanging, CCW from the right).
    pub angle: f64,
    /// Angular rate (rad/s).
    pub rate: f64,
    /// Angular acceleration (rad/s^2).
    pub accel: f64,
    /// World acceleration of the segment's proximal joint (m/s^2, x forward, y up).
    pub pivot_accel: Vector2<f64>,
}

impl PlanarSegment {
    /// World acceleration of the point `r` metres distal of the proximal
    /// joint on the segment axis: `a_pivot + alpha x p - omega^2 p`, with
    /// `p = r (sin angle, -cos angle)`.
    pub fn point_accel(&self, r: f64) -> Vector2<f64> {
        let (s, c) = (self.angle.sin(), self.angle.cos());
        let p = Vector2::new(r * s, -r * c);
        self.pivot_accel + Vector2::new(-p.y, p.x) * self.accel - p * (self.rate * self.rate)
    }

    /// `(R_seg, world angular rate, world specific force)` of a sensor `r`
    /// metres distal of the proximal joint, for gravity `g`.
    pub fn imu_inputs(&self, r: f64, g: f64) -> (Matrix3<f64>, Vector3<f64>, Vector3<f64>) {
        let (s, c) = (self.angle.sin(), self.angle.cos());
        let rot = Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        let a = self.point_accel(r);
        (
            rot,
            Vector3::new(0.0, 0.0, self.rate),
            Vector3::new(a.x, a.y + g, 0.0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn static_segment_reads_g_sin_and_g_cos() {
        let seg = PlanarSegment {
            angle: 0.4,
            rate: 0.0,
            accel: 0.0,
            pivot_accel: Vector2::zeros(),
        };
        let (r, _, f) = seg.imu_inputs(0.2, 9.81);
        let body = r.transpose() * f;
        assert!((body.x - 9.81 * 0.4f64.sin()).abs() < 1e-12);
        assert!((body.y - 9.81 * 0.4f64.cos()).abs() < 1e-12);
    }

    #[test]
    fn rotating_segment_reads_tangential_and_centripetal_terms() {
        // Body frame: tangential r*alpha along x, centripetal r*omega^2 along +y.
        let seg = PlanarSegment {
            angle: -0.7,
            rate: 2.0,
            accel: 3.0,
            pivot_accel: Vector2::zeros(),
        };
        let (r, _, f) = seg.imu_inputs(0.25, 9.81);
        let body = r.transpose() * f;
        assert!((body.x - (9.81 * (-0.7f64).sin() + 0.25 * 3.0)).abs() < 1e-12);
        assert!((body.y - (9.81 * (-0.7f64).cos() + 0.25 * 4.0)).abs() < 1e-12);
    }
}
