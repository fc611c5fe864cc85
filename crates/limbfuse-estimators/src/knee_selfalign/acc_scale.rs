//! Ours (issue 15 item 3, beyond paper 002): a relative scale between the two
//! accelerometers in eq 3.
//!
//! Eq 3 (`||a_T - Gamma_T(o_T)|| = ||a_S - Gamma_S(o_S)||`) assumes both
//! accelerometers read the same specific force at the joint centre. With
//! scale errors `s_T`, `s_S` (readings `s a`), dividing by `s_T`:
//! `||a_T - Gamma_T(s_T o_T)|| = ||r a_S - Gamma_S(s_T o_S)||` with
//! `r = s_T / s_S`. A common scale (`r = 1`) is absorbed by the positions
//! (scaled by `s_T`; eq 5 uses their directions only); a relative one is
//! the unknown `r`, identified with the positions: Algorithm 2 on
//! `Psi = [o_T, o_S, r]`, started from the lifted least-squares problem of
//! `super::position::lifted_row` with `r^2` and `r o_S` as unknowns.
//! The accelerometer angle (eqs 5-7) then uses `r a_S - Gamma_S(o_S)`.
//!
//! `r` is applied only when the window identifies it
//! ([`significant_scale`]); otherwise `r = 1` (the paper's eq 3, so a
//! recording whose accelerometers agree is processed exactly as before).

use nalgebra::{SMatrix, SVector, Vector3, Vector6};

use super::param_ekf::WindowResiduals;
use super::position::{lifted_row, Kinematics};
use super::window::Ring;

/// State of the scaled position problem: `[o_T, o_S, r]`.
pub type ScaledState = SVector<f64, 7>;

/// The shank kinematics with its specific force multiplied by `r`.
pub fn scaled(k: &Kinematics, r: f64) -> Kinematics {
    Kinematics {
        acc: k.acc * r,
        ..*k
    }
}

/// Eq 3 with the relative scale: `e = ||a_T - Gamma_T(o_T)|| - ||r a_S -
/// Gamma_S(o_S)||` and its gradient with respect to `[o_T, o_S, r]`.
pub fn scaled_position_residual(
    thigh: &Kinematics,
    shank: &Kinematics,
    x: &ScaledState,
) -> Option<(f64, ScaledState)> {
    let o_t = x.fixed_rows::<3>(0).into_owned();
    let o_s = x.fixed_rows::<3>(3).into_owned();
    let r = x[6];
    let (n_t, d_t) = thigh.norm_gradient(&o_t)?;
    let s = scaled(shank, r);
    let (n_s, d_s) = s.norm_gradient(&o_s)?;
    // d ||r a - M o|| / dr = (r a - M o) . a / ||r a - M o||
    let d_r = s.joint_acceleration(&o_s).dot(&shank.acc) / n_s;
    let mut h = ScaledState::zeros();
    for k in 0..3 {
        h[k] = d_t[k];
        h[3 + k] = -d_s[k];
    }
    h[6] = -d_r;
    Some((n_t - n_s, h))
}

/// The window's residuals of [`scaled_position_residual`].
pub struct ScaledPositionResiduals<'a>(pub &'a Ring);

impl WindowResiduals<7> for ScaledPositionResiduals<'_> {
    fn visit(&self, x: &ScaledState, f: &mut dyn FnMut(f64, &ScaledState)) {
        for i in 0..self.0.len() {
            if let Some([t, s]) = self.0.kinematics(i) {
                if let Some((e, h)) = scaled_position_residual(&t, &s, x) {
                    f(e, &h);
                }
            }
        }
    }
}

/// The lifted start with the relative scale: eq 3 squared,
/// `-2 a_T^T M_T o_T + <M_T^T M_T, o_T o_T^T> + 2 a_S^T M_S (r o_S) -
/// <M_S^T M_S, o_S o_S^T> - r^2 ||a_S||^2 = -||a_T||^2`, linear in 19
/// unknowns (`o_T`, `r o_S`, the two `o o^T`, `r^2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftedScaledStart {
    ata: SMatrix<f64, 19, 19>,
    atb: SVector<f64, 19>,
    n: usize,
}

impl Default for LiftedScaledStart {
    fn default() -> Self {
        LiftedScaledStart {
            ata: SMatrix::zeros(),
            atb: SVector::zeros(),
            n: 0,
        }
    }
}

impl LiftedScaledStart {
    /// Adds one sample's thigh and shank kinematics.
    pub fn add(&mut self, thigh: &Kinematics, shank: &Kinematics) {
        let (r18, y18) = lifted_row(thigh, shank);
        let a_s2 = shank.acc.norm_squared();
        let mut row = SVector::<f64, 19>::zeros();
        row.fixed_rows_mut::<18>(0).copy_from(&r18);
        row[18] = -a_s2;
        let y = y18 - a_s2;
        if row.iter().all(|v| v.is_finite()) && y.is_finite() {
            self.ata.ger(1.0, &row, &row, 1.0);
            self.atb.axpy(y, &row, 1.0);
            self.n += 1;
        }
    }

    /// `[o_T, o_S, r]` from the least-squares solution (ridge `1e-9` of
    /// the mean diagonal); `None` without enough samples, when the solve
    /// fails or `r^2` is not positive.
    pub fn solve(&self) -> Option<ScaledState> {
        if self.n < 19 {
            return None;
        }
        let z = ridge_solve(&self.ata, &self.atb)?;
        if !(z[18].is_finite() && z[18] > 0.0) {
            return None;
        }
        let r = libm::sqrt(z[18]);
        let x =
            ScaledState::from_column_slice(&[z[0], z[1], z[2], z[3] / r, z[4] / r, z[5] / r, r]);
        x.iter().all(|v| v.is_finite()).then_some(x)
    }

    /// The lifted solution of the paper's eq 3 (`r = 1`:
    /// `super::position::lifted_row`) from the same sums: with `r^2 = 1`
    /// known, its column moves to the right-hand side. `[o_T, o_S]`.
    pub fn solve_unit_scale(&self) -> Option<Vector6<f64>> {
        if self.n < 18 {
            return None;
        }
        let a: SMatrix<f64, 18, 18> = self.ata.fixed_view::<18, 18>(0, 0).into_owned();
        let b: SVector<f64, 18> =
            self.atb.fixed_rows::<18>(0) - self.ata.fixed_view::<18, 1>(0, 18);
        let z = ridge_solve(&a, &b)?;
        let o = Vector6::new(z[0], z[1], z[2], z[3], z[4], z[5]);
        o.iter().all(|v| v.is_finite()).then_some(o)
    }
}

/// The least-squares solution of the normal equations `A z = b` with a
/// ridge of `1e-9` times the mean diagonal of `A` (directions the window does
/// not excite, such as the positions along the axis in planar motion, come
/// out zero); `None` when the ridge is not positive and finite or the
/// Cholesky factorisation fails.
fn ridge_solve<const N: usize>(
    a: &SMatrix<f64, N, N>,
    b: &SVector<f64, N>,
) -> Option<SVector<f64, N>> {
    let ridge = 1e-9 * a.trace() / N as f64;
    if !(ridge.is_finite() && ridge > 0.0) {
        return None;
    }
    let regularised = a + SMatrix::<f64, N, N>::identity() * ridge;
    Some(regularised.cholesky()?.solve(b))
}

/// Standard deviations of `r - 1` the estimate must lie from 1 to be
/// applied (the standard deviation from the residuals:
/// `s^2 (H^T H)^-1`, `s^2 = sum e^2 / (N - 7)`).
pub const SCALE_SIGMAS: f64 = 3.0;

/// The relative scale `r` when the window identifies it: `r` differs from
/// 1 by more than [`SCALE_SIGMAS`] standard deviations (`var` its variance,
/// from the residuals); else `None` (the window cannot tell it from 1, and
/// eq 3 is the paper's).
pub fn significant_scale(r: f64, var: f64) -> Option<f64> {
    let ok = r.is_finite() && r > 0.0 && var.is_finite() && var >= 0.0;
    (ok && (r - 1.0).abs() > SCALE_SIGMAS * libm::sqrt(var)).then_some(r)
}

/// The positions of a scaled state.
pub fn positions(x: &ScaledState) -> Vector6<f64> {
    Vector6::new(x[0], x[1], x[2], x[3], x[4], x[5])
}

/// `[a_T - Gamma_T(o_T), r a_S - Gamma_S(o_S)]`: the joint-centre
/// accelerations of eq 7 with the relative scale.
pub fn joint_accelerations(
    kin: &[Kinematics; 2],
    position: &[Vector3<f64>; 2],
    r: f64,
) -> [Vector3<f64>; 2] {
    [
        kin[0].joint_acceleration(&position[0]),
        scaled(&kin[1], r).joint_acceleration(&position[1]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_matches_central_differences() {
        let t = Kinematics {
            acc: Vector3::new(1.0, 9.5, -0.4),
            gyr: Vector3::new(0.4, -0.3, 2.2),
            gyr_dot: Vector3::new(3.0, -1.0, 6.0),
        };
        let s = Kinematics {
            acc: Vector3::new(-2.0, 8.1, 1.3),
            gyr: Vector3::new(-0.2, 0.6, -3.1),
            gyr_dot: Vector3::new(-4.0, 2.0, 1.0),
        };
        let x = ScaledState::from_column_slice(&[0.02, 0.21, 0.08, -0.01, -0.2, 0.05, 1.2]);
        let (_, h) = scaled_position_residual(&t, &s, &x).unwrap();
        for i in 0..7 {
            let step = 1e-6;
            let (mut p, mut m) = (x, x);
            p[i] += step;
            m[i] -= step;
            let fd = (scaled_position_residual(&t, &s, &p).unwrap().0
                - scaled_position_residual(&t, &s, &m).unwrap().0)
                / (2.0 * step);
            assert!((fd - h[i]).abs() < 1e-7, "d/dx{i}: {fd} vs {}", h[i]);
        }
    }
}
