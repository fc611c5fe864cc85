//! Segment inclination from a static accelerometer (SPEC section 1).

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

#[cfg(test)]
mod tests {
    use super::*;

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
