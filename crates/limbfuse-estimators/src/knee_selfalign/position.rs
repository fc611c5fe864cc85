//! Joint-position identification (paper 002 section 2.2.2): the radial and
//! tangential acceleration model `Gamma` (equation before eq 3), the position
//! cost `e_o` (eq 3, as a difference: SPEC section 6), its Jacobian
//! (eqs 12-13), the correction of the positions along the axes, and the
//! symmetric finite-difference derivative of the gyro rate.
//!
//! `o_i` is the position of sensor `i` relative to the joint centre,
//! expressed in the sensor's frame (m). The specific force of the joint
//! centre seen from sensor `i` is `a_i - Gamma_{g_i}(o_i)` (eq 7); both
//! sensors see the same joint centre, so the norms agree at the true
//! positions: `e_o = ||a_T - Gamma_T(o_T)|| - ||a_S - Gamma_S(o_S)||`.

use nalgebra::{Matrix3, SVector, Vector3, Vector6};

/// Accelerations whose joint-centre part is below this norm (m/s^2) give no
/// usable gradient (eq 13 divides by it); such samples are left out.
pub const MIN_JOINT_ACCELERATION: f64 = 1e-6;

/// Cross-product matrix `[v]x` (`[v]x w = v x w`).
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// `M = [g]x^2 + [gdot]x`, so that `Gamma_g(o) = M o`.
pub fn gamma_matrix(g: &Vector3<f64>, gdot: &Vector3<f64>) -> Matrix3<f64> {
    let gx = skew(g);
    gx * gx + skew(gdot)
}

/// `Gamma_g(o) = g x (g x o) + gdot x o` (radial + tangential acceleration
/// of a point at `o` rotating with rate `g`).
pub fn gamma(g: &Vector3<f64>, gdot: &Vector3<f64>, o: &Vector3<f64>) -> Vector3<f64> {
    g.cross(&g.cross(o)) + gdot.cross(o)
}

/// One sensor's readings at one sample, with the rate derivative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Specific force (m/s^2).
    pub acc: Vector3<f64>,
    /// Angular rate (rad/s).
    pub gyr: Vector3<f64>,
    /// Angular acceleration (rad/s^2), from [`central_derivative`] (or [`rate_derivative3`]).
    pub gyr_dot: Vector3<f64>,
}

impl Kinematics {
    /// `a~ = a - Gamma(o)` (eq 7): the joint centre's specific force in this
    /// sensor's frame.
    pub fn joint_acceleration(&self, o: &Vector3<f64>) -> Vector3<f64> {
        self.acc - gamma(&self.gyr, &self.gyr_dot, o)
    }

    /// Gradient of `||a - Gamma(o)||` with respect to `o` (eq 13 with its
    /// sign): `-(([g]x^2 - [gdot]x) a~ / ||a~||)^T`, since `M^T = [g]x^2 -
    /// [gdot]x`. The paper prints it without the leading minus; with `r =
    /// -e` in Algorithm 2 the minus is needed for the update to descend.
    /// `None` when `||a~||` is below [`MIN_JOINT_ACCELERATION`].
    pub fn norm_gradient(&self, o: &Vector3<f64>) -> Option<(f64, Vector3<f64>)> {
        let at = self.joint_acceleration(o);
        let n = at.norm();
        if n < MIN_JOINT_ACCELERATION {
            return None;
        }
        let m = gamma_matrix(&self.gyr, &self.gyr_dot);
        Some((n, -(m.transpose() * at) / n))
    }
}

/// The position residual `e_o(k)` (eq 3, a difference) and its gradient with
/// respect to `Psi_o = [o_T, o_S]` (eqs 12-13).
pub fn position_residual(
    thigh: &Kinematics,
    shank: &Kinematics,
    psi: &Vector6<f64>,
) -> Option<(f64, Vector6<f64>)> {
    let o_t = psi.fixed_rows::<3>(0).into_owned();
    let o_s = psi.fixed_rows::<3>(3).into_owned();
    let (n_t, d_t) = thigh.norm_gradient(&o_t)?;
    let (n_s, d_s) = shank.norm_gradient(&o_s)?;
    Some((
        n_t - n_s,
        Vector6::new(d_t.x, d_t.y, d_t.z, -d_s.x, -d_s.y, -d_s.z),
    ))
}

/// Number of samples the rate derivative looks ahead (its latency).
pub const DERIVATIVE_LATENCY: usize = 2;

/// Symmetric five-point ("third-order", Seel et al. 2014) derivative at the
/// middle of five equally spaced rates `g[0..5]` (spacing `dt`):
/// `(g[0] - 8 g[1] + 8 g[3] - g[4]) / (12 dt)`. Exact for polynomials up to
/// degree 4; the estimate for sample `k` needs sample `k + 2`, a latency of
/// [`DERIVATIVE_LATENCY`] samples.
#[inline]
pub fn central_derivative(g: &[Vector3<f64>; 5], dt: f64) -> Vector3<f64> {
    (g[0] - g[1] * 8.0 + g[3] * 8.0 - g[4]) / (12.0 * dt)
}

/// Whether five sample times are equally spaced (within 1 % of the mean
/// step), as [`central_derivative`] assumes; returns the mean step.
#[inline]
pub fn uniform_step(t: &[f64; 5]) -> Option<f64> {
    let dt = (t[4] - t[0]) / 4.0;
    if dt.is_nan() || dt <= 0.0 {
        return None;
    }
    let ok = (0..4).all(|i| ((t[i + 1] - t[i]) - dt).abs() <= 0.01 * dt);
    ok.then_some(dt)
}

/// Largest step, as a multiple of the mean step of the five samples, that
/// [`rate_derivative`] takes as timestamp jitter rather than a gap: 1.5, the
/// gap rule of the resampler (`limbfuse_signal::resample::GAP_FACTOR`). One
/// dropped sample among four regular steps is 1.6 mean steps: a gap.
pub const MAX_STEP_RATIO: f64 = 1.5;

/// The rate derivative at the middle of five samples at times `t` taken at
/// their word (the stamp clock's verdict is not the grid: for a regular
/// clock with jittered stamps the caller uses [`central_derivative`] with
/// the grid's step once the clock counts the five consecutive,
/// `window::Ring::kinematics`): the five-point formula
/// ([`central_derivative`]) when the times are equally spaced (within 1 %);
/// otherwise, as long as every step lies within `[1 / MAX_STEP_RATIO,
/// MAX_STEP_RATIO]` mean steps (uneven sampling, not a gap), the derivative
/// of the degree-4 interpolating polynomial through the five samples
/// (Lagrange weights: exact for polynomials up to degree 4, as the
/// five-point formula is). `None` across a gap or out-of-order times. Until
/// issue 15's invariance audit a step more than 1 % off the mean refused
/// the sample, so timestamps with 1 ms of jitter at 100 Hz left the
/// estimator without any window (`issue_15_knee_jittered_timestamps`).
#[inline]
pub fn rate_derivative(t: &[f64; 5], g: &[Vector3<f64>; 5]) -> Option<Vector3<f64>> {
    if let Some(dt) = uniform_step(t) {
        return Some(central_derivative(g, dt));
    }
    let mean = (t[4] - t[0]) / 4.0;
    if mean.is_nan() || mean <= 0.0 {
        return None;
    }
    let regular = (0..4).all(|i| {
        let step = t[i + 1] - t[i];
        step >= mean / MAX_STEP_RATIO && step <= mean * MAX_STEP_RATIO
    });
    if !regular {
        return None;
    }
    // d/dt of the Lagrange basis at the middle node x = t[2]:
    // L_j'(t2) = prod_{m != j, 2} (t2 - t_m) / prod_{m != j} (t_j - t_m)
    // for j != 2, and L_2'(t2) = sum_{m != 2} 1 / (t2 - t_m).
    let x = t[2];
    let mut d = Vector3::zeros();
    for j in 0..5 {
        let w = if j == 2 {
            (0..5).filter(|&m| m != 2).map(|m| 1.0 / (x - t[m])).sum()
        } else {
            let num: f64 = (0..5)
                .filter(|&m| m != j && m != 2)
                .map(|m| x - t[m])
                .product();
            let den: f64 = (0..5).filter(|&m| m != j).map(|m| t[j] - t[m]).product();
            num / den
        };
        d += g[j] * w;
    }
    Some(d)
}

/// The central difference `(g_2 - g_0) / (2 dt)` of three samples `dt`
/// apart: exact for a quadratic rate.
pub fn central_difference(g: &[Vector3<f64>; 3], dt: f64) -> Vector3<f64> {
    (g[2] - g[0]) / (2.0 * dt)
}

/// The rate derivative at the middle of three samples at times `t` taken
/// at their word (ours, 2026-12-06): the fallback of [`rate_derivative`]
/// when an outer sample of its five lacks a gyro reading (empty cells).
/// [`central_difference`] with the mean step; `None` when the two steps
/// differ by more than [`MAX_STEP_RATIO`] (a gap).
pub fn rate_derivative3(t: &[f64; 3], g: &[Vector3<f64>; 3]) -> Option<Vector3<f64>> {
    let (h1, h2) = (t[1] - t[0], t[2] - t[1]);
    let mean = 0.5 * (t[2] - t[0]);
    let within = |h: f64| h >= mean / MAX_STEP_RATIO && h <= mean * MAX_STEP_RATIO;
    if mean.is_nan() || mean <= 0.0 || !within(h1) || !within(h2) {
        return None;
    }
    Some(central_difference(g, mean))
}

/// Moves both positions along their axes to the points of the axis midway
/// between the sensors (paper 002 after eq 3; Seel et al. 2014):
/// `o_i <- o_i - j_i (o_T . j_T + o_S . j_S) / 2`. The axes must point to
/// the same side (SPEC section 6): then shifting the joint centre by `s`
/// along the axis adds `s` to both projections, and the correction puts it
/// where they cancel.
pub fn correct_along_axes(
    o_t: &Vector3<f64>,
    o_s: &Vector3<f64>,
    j_t: &Vector3<f64>,
    j_s: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let m = 0.5 * (o_t.dot(j_t) + o_s.dot(j_s));
    (o_t - j_t * m, o_s - j_s * m)
}

/// The six distinct entries of a symmetric matrix, off-diagonals doubled, so
/// that `<N, o o^T> = sym(N) . [o_x^2, o_y^2, o_z^2, o_x o_y, o_x o_z, o_y o_z]`.
fn sym6(n: &Matrix3<f64>) -> [f64; 6] {
    [
        n[(0, 0)],
        n[(1, 1)],
        n[(2, 2)],
        2.0 * n[(0, 1)],
        2.0 * n[(0, 2)],
        2.0 * n[(1, 2)],
    ]
}

/// One sample's row of the lifted linear least-squares problem that gives
/// Algorithm 2 its starting positions, and its right-hand side
/// `||a_S||^2 - ||a_T||^2` (a limbfuse decision: paper 002 does not say
/// where the position search starts; the sums and solves are
/// [`super::acc_scale::LiftedScaledStart`]).
///
/// Eq 3 holds when `||a_T - M_T o_T||^2 = ||a_S - M_S o_S||^2` (`M` of
/// [`gamma_matrix`]). Expanded, this is linear in `o_T`, `o_S` and the six
/// distinct entries of each `o o^T`:
///
/// `-2 a_T^T M_T o_T + 2 a_S^T M_S o_S + <M_T^T M_T, o_T o_T^T> -
/// <M_S^T M_S, o_S o_S^T> = ||a_S||^2 - ||a_T||^2`.
///
/// Treating the 18 terms as independent unknowns gives a linear least-squares
/// problem with one global solution, whose first six entries are a start
/// near the true positions. Starting Algorithm 2 (Gauss-Newton on the norms)
/// from `o = 0` instead can end in a wrong local minimum: on the shared
/// independent-simulator walk at 1.2 m/s the first window converged to
/// `o_T = (-0.03, -0.28, -0.01)` m (RMS `e_o` 1.18 m/s^2) instead of the true
/// `(0, 0.215, 0)` (0.08 m/s^2); from the lifted start it reaches the truth.
pub(crate) fn lifted_row(thigh: &Kinematics, shank: &Kinematics) -> (SVector<f64, 18>, f64) {
    let mt = gamma_matrix(&thigh.gyr, &thigh.gyr_dot);
    let ms = gamma_matrix(&shank.gyr, &shank.gyr_dot);
    let lt = mt.transpose() * thigh.acc * -2.0;
    let ls = ms.transpose() * shank.acc * 2.0;
    let qt = sym6(&(mt.transpose() * mt));
    let qs = sym6(&(ms.transpose() * ms));
    let mut row = SVector::<f64, 18>::zeros();
    for k in 0..3 {
        row[k] = lt[k];
        row[3 + k] = ls[k];
    }
    for k in 0..6 {
        row[6 + k] = qt[k];
        row[12 + k] = -qs[k];
    }
    (row, shank.acc.norm_squared() - thigh.acc.norm_squared())
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_three_point_derivative_is_exact_for_a_quadratic_rate() {
        let rate = |t: f64| Vector3::new(1.0 + 2.0 * t - 3.0 * t * t, -t * t, 0.5 * t);
        let slope = |t: f64| Vector3::new(2.0 - 6.0 * t, -2.0 * t, 0.5);
        let t = [0.99, 1.0, 1.01];
        let d = rate_derivative3(&t, &t.map(rate)).unwrap();
        assert!((d - slope(1.0)).norm() < 1e-9, "{d}");
        // the samples of a regular grid (jittered stamps): the grid step
        let d = central_difference(&[0.99, 1.0, 1.01].map(rate), 0.01);
        assert!((d - slope(1.0)).norm() < 1e-9, "{d}");
        // a gap: no derivative
        assert!(rate_derivative3(&[0.97, 1.0, 1.01], &t.map(rate)).is_none());
    }

    use super::*;

    fn kin(a: [f64; 3], g: [f64; 3], gd: [f64; 3]) -> Kinematics {
        Kinematics {
            acc: a.into(),
            gyr: g.into(),
            gyr_dot: gd.into(),
        }
    }

    #[test]
    fn gamma_hand_value() {
        // g = (0, 0, 2), o = (1, 0, 0): radial g x (g x o) = (-4, 0, 0);
        // gdot = (0, 0, 3): tangential (0, 3, 0).
        let v = gamma(
            &Vector3::new(0.0, 0.0, 2.0),
            &Vector3::new(0.0, 0.0, 3.0),
            &Vector3::new(1.0, 0.0, 0.0),
        );
        assert!((v - Vector3::new(-4.0, 3.0, 0.0)).norm() < 1e-15);
        let g = Vector3::new(0.3, -0.2, 1.1);
        let gd = Vector3::new(-2.0, 0.5, 0.7);
        let o = Vector3::new(0.1, 0.25, -0.04);
        assert!((gamma_matrix(&g, &gd) * o - gamma(&g, &gd, &o)).norm() < 1e-15);
    }

    #[test]
    fn eq3_is_a_difference() {
        // o = 0: e_o = ||a_T|| - ||a_S||.
        let t = kin([3.0, 4.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]);
        let s = kin([0.0, 0.0, 2.0], [0.0, 1.0, 0.0], [0.0; 3]);
        let (e, _) = position_residual(&t, &s, &Vector6::zeros()).unwrap();
        assert!((e - 3.0).abs() < 1e-15);
    }

    #[test]
    fn jacobian_matches_central_differences() {
        let t = kin([1.0, 9.5, -0.4], [0.4, -0.3, 2.2], [3.0, -1.0, 6.0]);
        let s = kin([-2.0, 8.1, 1.3], [-0.2, 0.6, -3.1], [-4.0, 2.0, 1.0]);
        let psi = Vector6::new(0.02, 0.21, 0.08, -0.01, -0.2, 0.05);
        let (_, h) = position_residual(&t, &s, &psi).unwrap();
        for i in 0..6 {
            let step = 1e-6;
            let mut p = psi;
            p[i] += step;
            let mut m = psi;
            m[i] -= step;
            let fd = (position_residual(&t, &s, &p).unwrap().0
                - position_residual(&t, &s, &m).unwrap().0)
                / (2.0 * step);
            assert!((fd - h[i]).abs() < 1e-7, "d/do{i}: {fd} vs {}", h[i]);
        }
    }

    #[test]
    fn five_point_derivative_is_exact_on_quartics() {
        let f = |t: f64| Vector3::new(t.powi(4), 2.0 * t.powi(3) - t, 5.0);
        let df = |t: f64| Vector3::new(4.0 * t.powi(3), 6.0 * t * t - 1.0, 0.0);
        let (t0, dt) = (0.7, 0.01);
        let g = [-2.0, -1.0, 0.0, 1.0, 2.0].map(|k| f(t0 + k * dt));
        assert!((central_derivative(&g, dt) - df(t0)).norm() < 1e-9);
        assert_eq!(uniform_step(&[0.0, 0.01, 0.02, 0.03, 0.04]), Some(0.01));
        assert_eq!(uniform_step(&[0.0, 0.01, 0.02, 0.05, 0.06]), None);
        // Jittered times: exact for a degree-4 polynomial; a gap: none.
        let p = |t: f64| Vector3::new(t.powi(4), 2.0 * t.powi(3) - t, 3.0 * t * t);
        let dp = |t: f64| Vector3::new(4.0 * t.powi(3), 6.0 * t * t - 1.0, 6.0 * t);
        let tj = [0.7, 0.7108, 0.7193, 0.7301, 0.7395];
        let d = rate_derivative(&tj, &tj.map(p)).unwrap();
        assert!((d - dp(tj[2])).norm() < 1e-9, "{d} vs {}", dp(tj[2]));
        let tu = [0.7, 0.71, 0.72, 0.73, 0.74];
        assert_eq!(
            rate_derivative(&tu, &tu.map(p)),
            Some(central_derivative(&tu.map(p), uniform_step(&tu).unwrap()))
        );
        assert_eq!(
            rate_derivative(&[0.0, 0.01, 0.02, 0.04, 0.05], &tu.map(p)),
            None
        );
    }

    #[test]
    fn correction_makes_the_projections_cancel() {
        let j_t = Vector3::new(0.0, 0.6, 0.8);
        let j_s = Vector3::new(1.0, 0.0, 0.0);
        let (o_t, o_s) = correct_along_axes(
            &Vector3::new(0.1, 0.2, 0.3),
            &Vector3::new(0.4, -0.1, 0.0),
            &j_t,
            &j_s,
        );
        assert!((o_t.dot(&j_t) + o_s.dot(&j_s)).abs() < 1e-15);
        // The perpendicular parts are untouched.
        assert!(
            (o_t - j_t * o_t.dot(&j_t) - Vector3::new(0.1, 0.2, 0.3)
                + j_t * Vector3::new(0.1, 0.2, 0.3).dot(&j_t))
            .norm()
                < 1e-15
        );
    }

    #[test]
    fn lifted_start_recovers_positions_of_a_rigid_pair() {
        // Thigh and shank sensors at known positions from a common point,
        // both frames turning with varied rates: the joint-centre acceleration
        // a_J (in the world frame) is the same for both, so eq 3 is exact
        // and the lifted problem recovers both positions (to 1 mm: the ridge biases it slightly).
        let o_t = Vector3::new(0.03, 0.21, -0.05);
        let o_s = Vector3::new(-0.02, -0.18, 0.06);
        let mut lifted = super::super::acc_scale::LiftedScaledStart::default();
        for k in 0..400 {
            let t = k as f64 * 0.01;
            let a_j = Vector3::new(1.5 * (2.0 * t).sin(), 9.81 + (3.1 * t).cos(), 0.4 * t.sin());
            let rot = |w: f64, phase: f64| {
                nalgebra::Rotation3::from_euler_angles(
                    0.3 * (w * t).sin(),
                    0.5 * (0.7 * w * t + phase).cos(),
                    w * t,
                )
            };
            let (rt, rs) = (rot(1.3, 0.2), rot(2.1, 1.0));
            let g = |w: f64| {
                Vector3::new(
                    2.0 * (w * t).cos(),
                    -1.5 * (1.7 * w * t).sin(),
                    3.0 * (0.9 * w * t).cos(),
                )
            };
            let gd = |w: f64| {
                Vector3::new(
                    -2.0 * w * (w * t).sin(),
                    -2.55 * w * (1.7 * w * t).cos(),
                    -2.7 * w * (0.9 * w * t).sin(),
                )
            };
            let kin = |r: &nalgebra::Rotation3<f64>, w: f64, o: &Vector3<f64>| {
                let (g, gd) = (g(w), gd(w));
                Kinematics {
                    acc: r.inverse() * a_j + gamma(&g, &gd, o),
                    gyr: g,
                    gyr_dot: gd,
                }
            };
            lifted.add(&kin(&rt, 1.3, &o_t), &kin(&rs, 2.1, &o_s));
        }
        let o = lifted.solve_unit_scale().unwrap();
        assert!((o.fixed_rows::<3>(0) - o_t).norm() < 1e-3, "{o}");
        assert!((o.fixed_rows::<3>(3) - o_s).norm() < 1e-3, "{o}");
        assert_eq!(
            super::super::acc_scale::LiftedScaledStart::default().solve_unit_scale(),
            None
        );
    }
}
