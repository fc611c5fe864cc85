//! The spherical parametrisation of a joint axis (paper 002 eq 1) and the
//! axis residual with its Jacobian in those coordinates (eqs 2, 10-11):
//! the form the knee EKF (`knee_selfalign`, Algorithm 2) identifies
//! `Psi_j = [phi_T, theta_T, phi_S, theta_S]` in.

use nalgebra::{Matrix3x2, Vector3, Vector4};

use super::{hinge_residual, perpendicular_rate_gradient};

/// Unit axis from spherical coordinates (eq 1):
/// `j = [cos(phi) cos(theta), cos(phi) sin(theta), sin(phi)]`.
pub fn axis_from_spherical(phi: f64, theta: f64) -> Vector3<f64> {
    let (sp, cp) = libm::sincos(phi);
    let (st, ct) = libm::sincos(theta);
    Vector3::new(cp * ct, cp * st, sp)
}

/// Spherical coordinates `(phi, theta)` of a non-zero vector, with
/// `phi` in `[-pi/2, pi/2]` and `theta` in `[0, 2 pi)` (the ranges of eq 1).
pub fn spherical_from_axis(j: &Vector3<f64>) -> (f64, f64) {
    let n = j.norm();
    let phi = libm::asin((j.z / n).clamp(-1.0, 1.0));
    let mut theta = libm::atan2(j.y, j.x);
    if theta < 0.0 {
        theta += core::f64::consts::TAU;
    }
    (phi, theta)
}

/// `dj / d(phi, theta)`: the columns are the partial derivatives of eq 1
/// with respect to `phi` and `theta`.
pub fn axis_partials(phi: f64, theta: f64) -> Matrix3x2<f64> {
    let (sp, cp) = libm::sincos(phi);
    let (st, ct) = libm::sincos(theta);
    Matrix3x2::new(-sp * ct, -cp * st, -sp * st, cp * ct, cp, 0.0)
}

/// The axis residual `e_j(k)` (eq 2) and its gradient with respect to
/// `Psi_j = [phi_T, theta_T, phi_S, theta_S]` (eqs 10-11), at one sample.
///
/// `None` when either rate is (nearly) parallel to its axis, where the
/// gradient of eq 11 is undefined.
pub fn axis_residual(
    g_t: &Vector3<f64>,
    g_s: &Vector3<f64>,
    psi: &Vector4<f64>,
) -> Option<(f64, Vector4<f64>)> {
    let j_t = axis_from_spherical(psi[0], psi[1]);
    let j_s = axis_from_spherical(psi[2], psi[3]);
    let e = hinge_residual(g_t, &j_t, g_s, &j_s);
    let d_t = perpendicular_rate_gradient(g_t, &j_t)?;
    let d_s = perpendicular_rate_gradient(g_s, &j_s)?;
    let h_t = axis_partials(psi[0], psi[1]).transpose() * d_t;
    let h_s = axis_partials(psi[2], psi[3]).transpose() * d_s;
    Some((e, Vector4::new(h_t[0], h_t[1], -h_s[0], -h_s[1])))
}

/// `Psi_j` of two axes.
pub fn axis_state(j_t: &Vector3<f64>, j_s: &Vector3<f64>) -> Vector4<f64> {
    let (pt, tt) = spherical_from_axis(j_t);
    let (ps, ts) = spherical_from_axis(j_s);
    Vector4::new(pt, tt, ps, ts)
}

/// The two unit axes of `Psi_j`, re-expressed in the canonical ranges of eq 1.
pub fn axes_of_state(psi: &Vector4<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (
        axis_from_spherical(psi[0], psi[1]),
        axis_from_spherical(psi[2], psi[3]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq1_hand_values() {
        // phi = 0, theta = pi/2 -> y axis; phi = pi/2 -> z axis.
        let j = axis_from_spherical(0.0, core::f64::consts::FRAC_PI_2);
        assert!((j - Vector3::y()).norm() < 1e-15);
        let j = axis_from_spherical(core::f64::consts::FRAC_PI_2, 1.0);
        assert!((j - Vector3::z()).norm() < 1e-15);
        // phi = 30 deg, theta = 60 deg: (cos30 cos60, cos30 sin60, sin30).
        let (p, t) = (30f64.to_radians(), 60f64.to_radians());
        let j = axis_from_spherical(p, t);
        let want = Vector3::new(0.75f64.sqrt() * 0.5, 0.75, 0.5);
        assert!((j - want).norm() < 1e-15);
        let (p2, t2) = spherical_from_axis(&(j * 3.0));
        assert!((p2 - p).abs() < 1e-14 && (t2 - t).abs() < 1e-14);
    }

    #[test]
    fn eq2_hand_value() {
        // g_T = (1, 2, 3) about j_T = z: |g x z| = |(2, -1, 0)| = sqrt 5.
        // g_S = (0, 0, 4) about j_S = x: |(0, 4, 0)| = 4.
        let psi = Vector4::new(core::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0);
        let (e, _) = axis_residual(
            &Vector3::new(1.0, 2.0, 3.0),
            &Vector3::new(0.0, 0.0, 4.0),
            &psi,
        )
        .unwrap();
        assert!((e - (5f64.sqrt() - 4.0)).abs() < 1e-12);
    }

    #[test]
    fn jacobian_matches_central_differences() {
        let g_t = Vector3::new(0.3, -1.2, 2.5);
        let g_s = Vector3::new(-0.7, 0.4, 1.9);
        for psi in [
            Vector4::new(0.3, 1.1, -0.4, 4.0),
            Vector4::new(-1.2, 5.5, 0.9, 0.2),
            Vector4::new(0.0, 3.0, 0.1, 2.0),
        ] {
            let (_, h) = axis_residual(&g_t, &g_s, &psi).unwrap();
            for i in 0..4 {
                let step = 1e-6;
                let mut p = psi;
                p[i] += step;
                let mut m = psi;
                m[i] -= step;
                let fd = (axis_residual(&g_t, &g_s, &p).unwrap().0
                    - axis_residual(&g_t, &g_s, &m).unwrap().0)
                    / (2.0 * step);
                assert!((fd - h[i]).abs() < 1e-7, "d/dpsi{i}: {fd} vs {}", h[i]);
            }
        }
    }

    #[test]
    fn residual_vanishes_for_a_hinge() {
        // Two frames differing by a rotation R; rates w and w + rate j share
        // the perpendicular norm.
        let j_world = Vector3::new(0.0, 0.0, 1.0);
        let w_t = Vector3::new(0.4, -0.8, 1.3);
        let w_s = w_t + j_world * 2.1;
        // Sensor frames: thigh = identity, shank rotated 0.7 rad about x.
        let r = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), 0.7);
        let g_s = r.inverse() * w_s;
        let j_s = r.inverse() * j_world;
        let psi = axis_state(&j_world, &j_s);
        let (e, _) = axis_residual(&w_t, &g_s, &psi).unwrap();
        assert!(e.abs() < 1e-12, "{e}");
    }
}
