//! Continuous-discrete extended Kalman filter of one (gait, phase) model
//! (paper 003 Table I), on the B-SLIP dynamics of `limbfuse-models`.
//!
//! Propagation: `x' = f(x)`, `P' = F P + P F^T + G Q G^T` with `G = I`
//! (process noise enters every state; Q is zero on the positions, eq 16),
//! integrated by fixed-step RK4 with sub-steps no longer than
//! `max_substep` (SPEC section 6). Update: the measurement is a subset of
//! the state (`h(x) = H x`, H rows of the identity); with a diagonal R the
//! rows are processed one at a time, which gives exactly the joint update of
//! Table I and the joint likelihood of eq 7: `det(2 pi E)^-1/2 exp(lambda_r)`
//! factorises into the product of the scalar innovations' densities (chain
//! rule of Gaussian conditionals).
#![allow(non_snake_case)]

use limbfuse_models::bslip::{derivative, jacobian, BslipParams, Stance, State};
use nalgebra::Matrix6;

/// 6x6 covariance.
pub type Cov = Matrix6<f64>;

/// ln(2 pi).
const LN_2PI: f64 = 1.837_877_066_409_345_5;

/// `(f(x), F P + P F^T + Q)`. `F = [[0, I], [A, 0]]` (A = da/dc), so
/// `M = F P = [[P21, P22], [A P11, A P12]]` and `F P + P F^T = M + M^T`
/// for symmetric P: two 3x3 products instead of two 6x6 ones.
fn riccati(p: &BslipParams, stance: &Stance, x: &State, P: &Cov, Q: &Cov) -> (State, Cov) {
    let F = jacobian(p, x, stance);
    let A = F.fixed_view::<3, 3>(3, 0);
    let mut M = Cov::zeros();
    M.fixed_view_mut::<3, 6>(0, 0)
        .copy_from(&P.fixed_view::<3, 6>(3, 0));
    M.fixed_view_mut::<3, 6>(3, 0)
        .copy_from(&(A * P.fixed_view::<3, 6>(0, 0)));
    (derivative(p, x, stance), M + M.transpose() + Q)
}

/// Propagates `(x, P)` over `dt` by RK4 with `n` equal sub-steps.
pub fn propagate(
    p: &BslipParams,
    stance: &Stance,
    x: &mut State,
    P: &mut Cov,
    Q: &Cov,
    dt: f64,
    max_substep: f64,
) {
    if dt <= 0.0 {
        return;
    }
    let n = libm::ceil(dt / max_substep).max(1.0) as usize;
    let h = dt / n as f64;
    for _ in 0..n {
        let (k1x, k1p) = riccati(p, stance, x, P, Q);
        let (k2x, k2p) = riccati(
            p,
            stance,
            &(*x + k1x * (h / 2.0)),
            &(*P + k1p * (h / 2.0)),
            Q,
        );
        let (k3x, k3p) = riccati(
            p,
            stance,
            &(*x + k2x * (h / 2.0)),
            &(*P + k2p * (h / 2.0)),
            Q,
        );
        let (k4x, k4p) = riccati(p, stance, &(*x + k3x * h), &(*P + k3p * h), Q);
        *x += (k1x + k2x * 2.0 + k3x * 2.0 + k4x) * (h / 6.0);
        *P += (k1p + k2p * 2.0 + k3p * 2.0 + k4p) * (h / 6.0);
    }
    *P = (*P + P.transpose()) * 0.5;
}

/// Measurement update with the channels present in `z` (state index i has
/// measurement `z[i]` with variance `r[i]`). Returns the log of eq 7's
/// measurement likelihood (with the SPEC section 6 sign fix), i.e.
/// `-1/2 ln det(2 pi E) + lambda_r`, `lambda_r = -1/2 e^T E^-1 e`, evaluated
/// at the prior; 0 when nothing is measured.
pub fn update(x: &mut State, P: &mut Cov, z: &[Option<f64>; 6], r: &[f64; 6]) -> f64 {
    let mut log_l = 0.0;
    for i in 0..6 {
        let Some(zi) = z[i] else { continue };
        let s = P[(i, i)] + r[i];
        if s.is_nan() || s <= 0.0 || !s.is_finite() {
            continue;
        }
        let e = zi - x[i];
        log_l += -0.5 * (LN_2PI + libm::log(s) + e * e / s);
        let k = P.column(i) / s;
        *x += k * e;
        let row = P.row(i).into_owned();
        *P -= k * row;
    }
    *P = (*P + P.transpose()) * 0.5;
    log_l
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SMatrix, SVector};

    /// Sequential scalar updates equal the joint Table I update and eq 7's
    /// joint likelihood, computed directly with the 5x5 innovation covariance.
    #[test]
    fn sequential_update_equals_the_joint_update_and_eq7() {
        let mut P = Cov::from_fn(|i, j| {
            if i == j {
                0.01 + 0.001 * i as f64
            } else {
                0.002
            }
        });
        P = P * P.transpose();
        let x0 = State::new(0.1, 0.95, 0.03, 0.7, -0.05, 0.02);
        let z = [
            Some(0.105),
            Some(0.948),
            Some(0.031),
            Some(0.72),
            Some(-0.04),
            None,
        ];
        let r = [5e-5, 5e-5, 5e-5, 5e-4, 5e-4, 5e-4];
        // Joint.
        let H = SMatrix::<f64, 5, 6>::from_fn(|i, j| if i == j { 1.0 } else { 0.0 });
        let R = SMatrix::<f64, 5, 5>::from_diagonal(&SVector::<f64, 5>::from_column_slice(&r[..5]));
        let zv = SVector::<f64, 5>::from_fn(|i, _| z[i].unwrap());
        let e = zv - H * x0;
        let E = H * P * H.transpose() + R;
        let Einv = E.try_inverse().unwrap();
        let K = P * H.transpose() * Einv;
        let x_joint = x0 + K * e;
        let P_joint = (Cov::identity() - K * H) * P;
        let lambda_r = -0.5 * (e.transpose() * Einv * e)[(0, 0)];
        let det = (E * (2.0 * core::f64::consts::PI)).determinant();
        let log_l_joint = -0.5 * det.ln() + lambda_r;
        // Sequential.
        let mut x = x0;
        let mut Ps = P;
        let log_l = update(&mut x, &mut Ps, &z, &r);
        assert!((x - x_joint).amax() < 1e-12);
        assert!((Ps - P_joint).amax() < 1e-12);
        assert!(
            (log_l - log_l_joint).abs() < 1e-9,
            "{log_l} vs {log_l_joint}"
        );
    }

    /// Free fall (no stance leg): RK4 is exact for the quadratic position,
    /// and with Q = 0, F = [[0, I], [0, 0]] the covariance follows
    /// `P(t) = Phi P0 Phi^T`, `Phi = [[I, tI], [0, I]]`.
    #[test]
    fn propagation_of_free_fall_matches_the_closed_form() {
        let p = BslipParams::default();
        let stance = Stance::default();
        let mut x = State::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0);
        let mut P = Cov::identity() * 1e-3;
        let P0 = P;
        propagate(&p, &stance, &mut x, &mut P, &Cov::zeros(), 0.3, 0.01);
        assert!((x[1] - (1.0 - 0.5 * 9.81 * 0.09)).abs() < 1e-12);
        assert!((x[0] - 0.3).abs() < 1e-12);
        let mut phi = Cov::identity();
        for i in 0..3 {
            phi[(i, i + 3)] = 0.3;
        }
        assert!((P - phi * P0 * phi.transpose()).amax() < 1e-12);
    }

    /// Table I's covariance propagation with process noise, `P_dot = F P +
    /// P F^T + G Q G^T` (continuous white noise of spectral density `q_i`
    /// on velocity `i`, G = I, Q zero on positions as in eqs 16 and 18), in
    /// free fall: the closed form is `P(t) = Phi P0 Phi^T + int_0^t Phi(s)
    /// Q Phi(s)^T ds`, per axis `[[q t^3/3, q t^2/2], [q t^2/2, q t]]` added
    /// to the Q = 0 solution. By hand for eq 18's vertical density q = 0.1,
    /// t = 0.3 s, P0 = 1e-3 I: position 1e-3 (1 + 0.09) + 0.1 * 0.009 =
    /// 1.99e-3, cross 3e-4 + 4.5e-3 = 4.8e-3, velocity 1e-3 + 0.03 = 0.031.
    #[test]
    fn propagation_of_free_fall_with_process_noise_matches_the_closed_form() {
        let p = BslipParams::default();
        let stance = Stance::default();
        let mut x = State::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0);
        let P0 = Cov::identity() * 1e-3;
        let mut P = P0;
        let q = [1e-2, 1e-1, 1e-2];
        let mut Q = Cov::zeros();
        for (i, qi) in q.iter().enumerate() {
            Q[(i + 3, i + 3)] = *qi;
        }
        let t = 0.3;
        propagate(&p, &stance, &mut x, &mut P, &Q, t, 0.01);
        let mut want = Cov::zeros();
        for (a, qa) in q.iter().enumerate() {
            let v = a + 3;
            want[(a, a)] = 1e-3 * (1.0 + t * t) + qa * t * t * t / 3.0;
            want[(a, v)] = 1e-3 * t + qa * t * t / 2.0;
            want[(v, a)] = want[(a, v)];
            want[(v, v)] = 1e-3 + qa * t;
        }
        assert!((want[(1, 1)] - 1.99e-3).abs() < 1e-15);
        assert!((want[(1, 4)] - 4.8e-3).abs() < 1e-15);
        assert!((want[(4, 4)] - 0.031).abs() < 1e-15);
        assert!((P - want).amax() < 1e-12, "{P}");
    }
}
