//! Planar chain kinematics: the specific force each accelerometer reads and
//! the ankle's velocity, as functions of the state, with their Jacobians
//! (docs/CHAIN.md, "Measurement model", eqs C1-C8).
//!
//! Frames (SPEC section 1): world x forward, y up; `R(theta)` rotates a
//! segment's frame into the world. Segment origins: trunk and thigh at the
//! hip joint, shank at the knee, foot at the ankle; the thigh's distal joint
//! is at `e_1 = R(theta_1) (0, -L_1)`, the shank's at `e_2 = R(theta_2) (0, -L_2)`.
// The x/y components index several arrays at once (textbook form).
#![allow(clippy::needless_range_loop)]

use super::covariance::StateVector;
use super::state::{alpha, hip_acceleration, hip_velocity, omega, theta, SparseRow};

/// Segment lengths and sensor positions (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainGeometry {
    /// Hip joint to knee joint, `L_1`.
    pub thigh_length: f64,
    /// Knee joint to ankle joint, `L_2`.
    pub shank_length: f64,
    /// Each IMU's position `r_i = (x, y, z)` in its segment frame, from the
    /// segment's origin (trunk and thigh: hip joint; shank: knee; foot: ankle).
    pub imu_position: [[f64; 3]; 4],
    /// Each sensor frame's angle `psi_i` (rad) relative to its segment's
    /// anatomical frame (the one whose -y axis is the link to the distal
    /// joint and in which `imu_position` is given): `theta_i` (the state, the
    /// sensor frame's angle) is `theta_anatomical + psi_i`. Zero for a
    /// quiet-standing zero or a known mounting; `align`'s mean-inclination
    /// zero puts the sensor frame at the segment's walking mean angle
    /// (docs/CHAIN.md, "Frame offsets").
    pub frame_offset: [f64; 4],
}

/// The non-sagittal rotation of one sensor, taken from its gyro's x and y
/// axes (known inputs, not states): rates `(w_x, w_y)` and their time
/// derivatives. Zero for a purely planar model.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OutOfPlane {
    /// `(w_x, w_y)`, rad/s.
    pub rate: [f64; 2],
    /// `(dw_x/dt, dw_y/dt)`, rad/s^2.
    pub rate_derivative: [f64; 2],
}

#[inline]
fn sin_cos(a: f64) -> (f64, f64) {
    (libm::sin(a), libm::cos(a))
}

/// `R(theta)^T u` for a world vector `u`.
#[inline]
fn to_segment(s: f64, c: f64, u: [f64; 2]) -> [f64; 2] {
    [c * u[0] + s * u[1], -s * u[0] + c * u[1]]
}

/// `e_j = R(theta_j - psi_j) (0, -L_j)` and `J e_j`, `J = [[0, -1], [1, 0]]`.
#[inline]
fn link(x: &StateVector, j: usize, length: f64, psi: f64) -> ([f64; 2], [f64; 2]) {
    let (s, c) = sin_cos(x[theta(j)] - psi);
    ([length * s, -length * c], [length * c, length * s])
}

impl ChainGeometry {
    /// Sensor `s`'s position in its sensor frame: `R(-psi_s) r_s` (z unchanged).
    #[inline]
    pub fn sensor_position(&self, s: usize) -> [f64; 3] {
        let r = self.imu_position[s];
        let psi = self.frame_offset[s];
        if psi == 0.0 {
            return r;
        }
        let (sn, cs) = sin_cos(psi);
        [cs * r[0] + sn * r[1], -sn * r[0] + cs * r[1], r[2]]
    }

    /// `L_j` of the links that carry a distal origin (1: thigh, 2: shank).
    fn link_length(&self, j: usize) -> f64 {
        if j == 1 {
            self.thigh_length
        } else {
            self.shank_length
        }
    }

    /// Specific force `f_s` (sensor frame x, y) of segment `s`'s aligned
    /// accelerometer and its two Jacobian rows (eqs C1-C5):
    ///
    /// `f_s = R_s^T (a_h + sum_{j<s, j>=1} d_j + (0, g)) + alpha_s J r_s
    ///  - omega_s^2 r_s + f_oop`,
    /// `d_j = alpha_j J e_j - omega_j^2 e_j`.
    pub fn specific_force(
        &self,
        x: &StateVector,
        s: usize,
        g: f64,
        oop: &OutOfPlane,
    ) -> ([f64; 2], [SparseRow; 2]) {
        let mut rows = [SparseRow::new(), SparseRow::new()];
        let mut u = [x[hip_acceleration(0)], x[hip_acceleration(1)] + g];
        let (sn, cs) = sin_cos(x[theta(s)]);
        for j in 1..s {
            let (e, je) = link(x, j, self.link_length(j), self.frame_offset[j]);
            let (w, a) = (x[omega(j)], x[alpha(j)]);
            u[0] += a * je[0] - w * w * e[0];
            u[1] += a * je[1] - w * w * e[1];
            let d_theta = to_segment(
                sn,
                cs,
                [-a * e[0] - w * w * je[0], -a * e[1] - w * w * je[1]],
            );
            let d_omega = to_segment(sn, cs, [-2.0 * w * e[0], -2.0 * w * e[1]]);
            let d_alpha = to_segment(sn, cs, je);
            for k in 0..2 {
                rows[k].add(theta(j), d_theta[k]);
                rows[k].add(omega(j), d_omega[k]);
                rows[k].add(alpha(j), d_alpha[k]);
            }
        }
        let v = to_segment(sn, cs, u);
        let r = self.sensor_position(s);
        let (w, a) = (x[omega(s)], x[alpha(s)]);
        let [gx, gy] = oop.rate;
        let [dgx, dgy] = oop.rate_derivative;
        // Out-of-plane terms of alpha x r + omega x (omega x r) (eq C5).
        let extra = [
            gx * gy * r[1] + gx * w * r[2] - r[0] * gy * gy + dgy * r[2],
            gy * gx * r[0] + gy * w * r[2] - r[1] * gx * gx - dgx * r[2],
        ];
        let f = [
            v[0] - a * r[1] - w * w * r[0] + extra[0],
            v[1] + a * r[0] - w * w * r[1] + extra[1],
        ];
        // d(R^T u)/d theta_s = -J R^T u = (v_1, -v_0).
        let d_theta = [v[1], -v[0]];
        let d_omega = [-2.0 * w * r[0] + gx * r[2], -2.0 * w * r[1] + gy * r[2]];
        let d_alpha = [-r[1], r[0]];
        let d_ax = [cs, -sn];
        let d_ay = [sn, cs];
        for k in 0..2 {
            rows[k].add(theta(s), d_theta[k]);
            rows[k].add(omega(s), d_omega[k]);
            rows[k].add(alpha(s), d_alpha[k]);
            rows[k].add(hip_acceleration(0), d_ax[k]);
            rows[k].add(hip_acceleration(1), d_ay[k]);
        }
        (f, rows)
    }

    /// World velocity of the ankle joint and its Jacobian rows (eq C6):
    /// `v_A = v_h + omega_1 J e_1 + omega_2 J e_2`.
    pub fn ankle_velocity(&self, x: &StateVector) -> ([f64; 2], [SparseRow; 2]) {
        let mut rows = [SparseRow::new(), SparseRow::new()];
        let mut v = [x[hip_velocity(0)], x[hip_velocity(1)]];
        for k in 0..2 {
            rows[k].add(hip_velocity(k), 1.0);
        }
        for j in 1..3 {
            let (e, je) = link(x, j, self.link_length(j), self.frame_offset[j]);
            let w = x[omega(j)];
            for k in 0..2 {
                v[k] += w * je[k];
                rows[k].add(theta(j), -w * e[k]);
                rows[k].add(omega(j), je[k]);
            }
        }
        (v, rows)
    }
}

impl ChainGeometry {
    /// World acceleration of the ankle joint and its Jacobian rows (eq C8):
    /// `a_A = a_h + d_1 + d_2` (C1); a still foot has `a_A = 0`.
    pub fn ankle_acceleration(&self, x: &StateVector) -> ([f64; 2], [SparseRow; 2]) {
        let mut rows = [SparseRow::new(), SparseRow::new()];
        let mut a = [x[hip_acceleration(0)], x[hip_acceleration(1)]];
        for k in 0..2 {
            rows[k].add(hip_acceleration(k), 1.0);
        }
        for j in 1..3 {
            let (e, je) = link(x, j, self.link_length(j), self.frame_offset[j]);
            let (w, al) = (x[omega(j)], x[alpha(j)]);
            for k in 0..2 {
                a[k] += al * je[k] - w * w * e[k];
                rows[k].add(theta(j), -al * e[k] - w * w * je[k]);
                rows[k].add(omega(j), -2.0 * w * e[k]);
                rows[k].add(alpha(j), je[k]);
            }
        }
        (a, rows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn geometry() -> ChainGeometry {
        ChainGeometry {
            thigh_length: 0.43,
            shank_length: 0.42,
            imu_position: [
                [-0.10, 0.08, -0.09],
                [0.01, -0.21, 0.08],
                [0.02, -0.2, 0.05],
                [0.07, -0.005, 0.01],
            ],
            frame_offset: [0.03, -0.05, 0.2, 0.15],
        }
    }

    fn state() -> StateVector {
        let mut x = StateVector::zeros();
        let vals = [
            (theta(0), 0.05),
            (theta(1), 0.4),
            (theta(2), -0.3),
            (theta(3), -0.2),
            (omega(0), 0.2),
            (omega(1), 2.1),
            (omega(2), -3.0),
            (omega(3), 4.2),
            (alpha(0), 1.0),
            (alpha(1), -12.0),
            (alpha(2), 25.0),
            (alpha(3), -40.0),
            (hip_velocity(0), 1.2),
            (hip_velocity(1), -0.1),
            (hip_acceleration(0), 0.7),
            (hip_acceleration(1), -1.3),
        ];
        for (i, v) in vals {
            x[i] = v;
        }
        x
    }

    fn check_jacobian(f: impl Fn(&StateVector) -> ([f64; 2], [SparseRow; 2]), x: &StateVector) {
        let (_, rows) = f(x);
        let h = 1e-6;
        for i in 0..x.len() {
            let (mut xp, mut xm) = (*x, *x);
            xp[i] += h;
            xm[i] -= h;
            let (fp, _) = f(&xp);
            let (fm, _) = f(&xm);
            for k in 0..2 {
                let fd = (fp[k] - fm[k]) / (2.0 * h);
                let an = rows[k].dense()[i];
                assert!(
                    (fd - an).abs() < 1e-6 * (1.0 + fd.abs()),
                    "row {k} state {i}: fd {fd} analytic {an}"
                );
            }
        }
    }

    #[test]
    fn specific_force_jacobians_match_finite_differences() {
        let geo = geometry();
        let oop = OutOfPlane {
            rate: [0.4, -0.7],
            rate_derivative: [3.0, -5.0],
        };
        for s in 0..4 {
            check_jacobian(|x| geo.specific_force(x, s, 9.81, &oop), &state());
        }
    }

    #[test]
    fn ankle_velocity_jacobian_matches_finite_differences() {
        let geo = geometry();
        check_jacobian(|x| geo.ankle_velocity(x), &state());
        check_jacobian(|x| geo.ankle_acceleration(x), &state());
    }

    /// A planar motion with closed-form angles: `theta_i(t) = A_i sin(w_i t + p_i)`,
    /// hip `p_h(t) = (v t + b sin(2 t), c cos(3 t))`.
    struct Motion;
    impl Motion {
        const A: [f64; 4] = [0.05, 0.5, 0.6, 0.4];
        const W: [f64; 4] = [5.0, 5.5, 6.0, 7.0];
        const P: [f64; 4] = [0.1, 0.7, -0.4, 1.1];
        fn angles(t: f64) -> [[f64; 3]; 4] {
            core::array::from_fn(|i| {
                let (a, w, p) = (Self::A[i], Self::W[i], Self::P[i]);
                let ph = w * t + p;
                [a * ph.sin(), a * w * ph.cos(), -a * w * w * ph.sin()]
            })
        }
        fn hip(t: f64) -> [[f64; 2]; 3] {
            let (b, c) = (0.03, 0.02);
            [
                [1.2 * t + b * (2.0 * t).sin(), c * (3.0 * t).cos()],
                [1.2 + 2.0 * b * (2.0 * t).cos(), -3.0 * c * (3.0 * t).sin()],
                [-4.0 * b * (2.0 * t).sin(), -9.0 * c * (3.0 * t).cos()],
            ]
        }
        fn state(t: f64) -> StateVector {
            let mut x = StateVector::zeros();
            let a = Self::angles(t);
            for i in 0..4 {
                x[theta(i)] = a[i][0];
                x[omega(i)] = a[i][1];
                x[alpha(i)] = a[i][2];
            }
            let h = Self::hip(t);
            for k in 0..2 {
                x[hip_velocity(k)] = h[1][k];
                x[hip_acceleration(k)] = h[2][k];
            }
            x
        }
        /// World position of segment `s`'s sensor (or of the ankle for `s = 4`):
        /// links and positions in the anatomical frames, at `theta_i - psi_i`.
        fn point(geo: &ChainGeometry, t: f64, s: usize) -> [f64; 2] {
            let th: [f64; 4] = core::array::from_fn(|i| Self::angles(t)[i][0]);
            let rot = |a: f64, v: [f64; 2]| {
                [
                    a.cos() * v[0] - a.sin() * v[1],
                    a.sin() * v[0] + a.cos() * v[1],
                ]
            };
            let mut o = Self::hip(t)[0];
            let lengths = [0.0, geo.thigh_length, geo.shank_length];
            for j in 1..s.min(3) {
                let e = rot(th[j] - geo.frame_offset[j], [0.0, -lengths[j]]);
                o = [o[0] + e[0], o[1] + e[1]];
            }
            if s == 4 {
                return o;
            }
            let r = geo.imu_position[s];
            let p = rot(th[s] - geo.frame_offset[s], [r[0], r[1]]);
            [o[0] + p[0], o[1] + p[1]]
        }
    }

    #[test]
    fn planar_specific_force_equals_the_second_difference_of_the_sensor_position() {
        let mut geo = geometry();
        for r in geo.imu_position.iter_mut() {
            r[2] = 0.0;
        }
        let g = 9.81;
        let h = 1e-4;
        for t in [0.3, 1.1, 2.7] {
            let x = Motion::state(t);
            for s in 0..4 {
                let p = |t| Motion::point(&geo, t, s);
                let (pp, p0, pm) = (p(t + h), p(t), p(t - h));
                let acc = [
                    (pp[0] - 2.0 * p0[0] + pm[0]) / (h * h),
                    (pp[1] - 2.0 * p0[1] + pm[1]) / (h * h) + g,
                ];
                let th = x[theta(s)];
                let expected = [
                    th.cos() * acc[0] + th.sin() * acc[1],
                    -th.sin() * acc[0] + th.cos() * acc[1],
                ];
                let (f, _) = geo.specific_force(&x, s, g, &OutOfPlane::default());
                for k in 0..2 {
                    assert!(
                        (f[k] - expected[k]).abs() < 1e-4,
                        "t {t} s {s} k {k}: {f:?} vs {expected:?}"
                    );
                }
            }
            let (v, _) = geo.ankle_velocity(&x);
            let (a, _) = geo.ankle_acceleration(&x);
            let (pp, p0, pm) = (
                Motion::point(&geo, t + h, 4),
                Motion::point(&geo, t, 4),
                Motion::point(&geo, t - h, 4),
            );
            for k in 0..2 {
                let fd = (pp[k] - pm[k]) / (2.0 * h);
                assert!((v[k] - fd).abs() < 1e-6, "ankle velocity {v:?} vs fd {fd}");
                let fd2 = (pp[k] - 2.0 * p0[k] + pm[k]) / (h * h);
                assert!(
                    (a[k] - fd2).abs() < 1e-4,
                    "ankle acceleration {a:?} vs fd {fd2}"
                );
            }
        }
    }

    #[test]
    fn out_of_plane_terms_equal_the_three_dimensional_cross_products() {
        // A sensor rotating with omega = (gx, gy, w) about its (fixed) origin,
        // alpha = (dgx, dgy, a): alpha x r + omega x (omega x r) in the segment frame.
        let geo = geometry();
        let mut x = StateVector::zeros();
        x[hip_acceleration(1)] = -9.81; // cancel gravity: only the rotation is left
        let (w, a) = (2.3, -17.0);
        let s = 0;
        x[omega(s)] = w;
        x[alpha(s)] = a;
        let oop = OutOfPlane {
            rate: [0.8, -1.1],
            rate_derivative: [6.0, 9.0],
        };
        let (f, _) = geo.specific_force(&x, s, 9.81, &oop);
        let r = Vector3::from(geo.sensor_position(s));
        let om = Vector3::new(oop.rate[0], oop.rate[1], w);
        let al = Vector3::new(oop.rate_derivative[0], oop.rate_derivative[1], a);
        let expected = al.cross(&r) + om.cross(&om.cross(&r));
        assert!(
            (f[0] - expected.x).abs() < 1e-12 && (f[1] - expected.y).abs() < 1e-12,
            "{f:?} {expected}"
        );
    }
}
