//! Segment inclination from a static accelerometer (SPEC section 1).

use limbfuse_core::sample::ImuSample;
use nalgebra::Vector3;

/// Sagittal angle `theta = atan2(acc_x, acc_y)` of an aligned sensor.
///
/// Exact when the segment is static (the accelerometer then reads gravity
/// only: `(g sin theta, g cos theta, 0)` for a rotation `theta` about z of
/// the upright pose, which reads `(0, g, 0)`); dynamic accelerations enter
/// it unfiltered.
#[inline]
pub fn accel_inclination(acc: &Vector3<f64>) -> f64 {
    libm::atan2(acc.x, acc.y)
}

/// The specific force a sagittal-plane filter reads from an aligned IMU:
/// the complete vector, or, when only the lateral axis `z` is missing, `(x,
/// y, 0)` (ours, issue 18 item 2); `None` without `x` and `y`.
///
/// The inclination `atan2(x, y)` needs only the in-plane axes. The norm
/// test `| ||a|| - g |` takes the missing lateral component at its prior
/// mean, 0: in the planar model the segment moves in the sagittal plane,
/// and an aligned sensor's `z` reads lateral accelerations only (the
/// shared independent trials: noise only). A true lateral specific force
/// `a_z` enters the norm to second order, `||a|| - ||a_xy|| ~ a_z^2 / (2
/// ||a_xy||)`: 0.05 m/s^2 for a 1 m/s^2 lateral sway at `g`, an eighth of
/// the smallest default threshold `zeta` (0.4 m/s^2). Only aligned frames:
/// a sensor whose `z` mixes in-plane motion is aligned first, and the
/// alignment keeps an output axis only where every input axis it depends on
/// is present (`limbfuse_signal::align::apply_rotations`).
#[inline]
pub fn sagittal_specific_force(imu: &ImuSample) -> Option<Vector3<f64>> {
    match (imu.acc, imu.acc_partial) {
        (Some(a), _) => Some(a),
        (None, [Some(x), Some(y), _]) => Some(Vector3::new(x, y, 0.0)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn issue_18_the_in_plane_axes_suffice_without_the_lateral_one() {
        let mut imu = ImuSample::default();
        imu.set_acc_axes([Some(1.0), Some(9.0), None]);
        assert_eq!(
            sagittal_specific_force(&imu),
            Some(Vector3::new(1.0, 9.0, 0.0))
        );
        imu.set_acc_axes([None, Some(9.0), Some(0.1)]);
        assert_eq!(sagittal_specific_force(&imu), None);
        imu.set_acc_axes([Some(1.0), Some(9.0), Some(0.1)]);
        assert_eq!(
            sagittal_specific_force(&imu),
            Some(Vector3::new(1.0, 9.0, 0.1))
        );
    }

    #[test]
    fn rotated_gravity_gives_its_angle() {
        let g = 9.81;
        for deg in [-170.0f64, -45.0, -1.0, 0.0, 10.0, 90.0, 135.0] {
            let th = deg.to_radians();
            // Specific force of a static sensor rotated by th about z, in the sensor frame:
            // R(th)^T (0, g, 0) = (g sin th, g cos th, 0).
            let f = Vector3::new(g * th.sin(), g * th.cos(), 0.0);
            assert!((accel_inclination(&f) - th).abs() < 1e-12, "{deg}");
        }
    }
}
