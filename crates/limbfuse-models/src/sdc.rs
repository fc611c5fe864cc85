//! The interface the continuous-time estimators of paper 004 need from a
//! model: dynamics `f(x, u)`, measurement `h(x)`, a state-dependent
//! coefficient (SDC) factorisation and the analytic Jacobians.
//!
//! The SDC factorisation (paper 004 eq 4.8) must be exact:
//! `A(x) x + B(x) u = f(x, u)` and `C(x) x = h(x)` for every state,
//! including `x_i -> 0` (sinc terms). `B(x) u` is returned as one vector
//! ([`SdcModel::input_term`]) because it also carries the passive torques,
//! which the thesis lumps into it (eqs 4.12 and 4.25).

use nalgebra::{SMatrix, SVector};

/// A model with `N` states, `M` measurements and `U` inputs.
pub trait SdcModel<const N: usize, const M: usize, const U: usize> {
    /// Dynamics `f(x, u)` (eqs 4.6, 4.23).
    fn f(&self, x: &SVector<f64, N>, u: &SVector<f64, U>) -> SVector<f64, N>;
    /// Measurement `h(x)` (eqs 4.7, 4.24).
    fn h(&self, x: &SVector<f64, N>) -> SVector<f64, M>;
    /// SDC state matrix `A(x)` (eqs 4.11, 4.25).
    fn sdc_a(&self, x: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// The input term `B(x) u` (eqs 4.12, 4.25), with `f = A(x) x + B(x) u`.
    fn input_term(&self, x: &SVector<f64, N>, u: &SVector<f64, U>) -> SVector<f64, N>;
    /// SDC measurement matrix `C(x)` (eqs 4.13, 4.25), with `h = C(x) x`.
    fn sdc_c(&self, x: &SVector<f64, N>) -> SMatrix<f64, M, N>;
    /// Jacobian `df/dx` (for the EKF).
    fn jacobian_f(&self, x: &SVector<f64, N>, u: &SVector<f64, U>) -> SMatrix<f64, N, N>;
    /// Jacobian `dh/dx` (for the EKF).
    fn jacobian_h(&self, x: &SVector<f64, N>) -> SMatrix<f64, M, N>;

    /// The measurement when it also depends on the input, `h(x, u)` (an
    /// accelerometer away from the joint feels the angular acceleration,
    /// which the input drives). Default: `h(x)`.
    fn h_with_input(&self, x: &SVector<f64, N>, _u: &SVector<f64, U>) -> SVector<f64, M> {
        self.h(x)
    }

    /// The input-dependent part `D(x, u)` of the SDC measurement form
    /// `h(x, u) = C(x) x + D(x, u)` (the measurement analogue of
    /// [`SdcModel::input_term`]). Default: zero (`h = C(x) x`).
    fn sdc_measurement_input(&self, _x: &SVector<f64, N>, _u: &SVector<f64, U>) -> SVector<f64, M> {
        SVector::zeros()
    }

    /// Jacobian `dh(x, u)/dx` of [`SdcModel::h_with_input`]. Default:
    /// [`SdcModel::jacobian_h`].
    fn jacobian_h_with_input(
        &self,
        x: &SVector<f64, N>,
        _u: &SVector<f64, U>,
    ) -> SMatrix<f64, M, N> {
        self.jacobian_h(x)
    }

    /// The SDC form at `(x, u)` in one evaluation: `A(x)`, `C(x)`,
    /// `A(x) x + B(x) u` and `C(x) x + D(x, u)` (what eqs 4.14-4.16 need at
    /// one instant). Default: the four methods above; a model whose
    /// coefficients share work overrides it with the same arithmetic.
    fn sdc_terms(&self, x: &SVector<f64, N>, u: &SVector<f64, U>) -> Linearised<N, M> {
        let a = self.sdc_a(x);
        let c = self.sdc_c(x);
        Linearised {
            drift: a * x + self.input_term(x, u),
            y_hat: c * x + self.sdc_measurement_input(x, u),
            a,
            c,
        }
    }

    /// The Jacobian form at `(x, u)` in one evaluation: `df/dx`,
    /// `dh(x, u)/dx`, `f(x, u)` and `h(x, u)`. Default: the methods above.
    fn jacobian_terms(&self, x: &SVector<f64, N>, u: &SVector<f64, U>) -> Linearised<N, M> {
        Linearised {
            a: self.jacobian_f(x, u),
            c: self.jacobian_h_with_input(x, u),
            drift: self.f(x, u),
            y_hat: self.h_with_input(x, u),
        }
    }
}

/// A model linearised at one instant ([`SdcModel::sdc_terms`],
/// [`SdcModel::jacobian_terms`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linearised<const N: usize, const M: usize> {
    /// State matrix: `A(x)` or `df/dx`.
    pub a: SMatrix<f64, N, N>,
    /// Measurement matrix: `C(x)` or `dh/dx`.
    pub c: SMatrix<f64, M, N>,
    /// The model's state derivative `f(x, u)` (SDC: `A(x) x + B(x) u`).
    pub drift: SVector<f64, N>,
    /// The predicted measurement `h(x, u)` (SDC: `C(x) x + D(x, u)`).
    pub y_hat: SVector<f64, M>,
}

/// `sin(x) / x`, equal to 1 at 0 and accurate near it (Taylor series below 1e-4).
#[inline]
pub fn sinc(x: f64) -> f64 {
    if libm::fabs(x) < 1e-4 {
        let x2 = x * x;
        1.0 - x2 / 6.0 + x2 * x2 / 120.0
    } else {
        libm::sin(x) / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinc_is_continuous_through_zero() {
        assert_eq!(sinc(0.0), 1.0);
        for x in [1e-12, 1e-6, 9.9e-5, 1.01e-4, 1e-3, 0.5, -2.0] {
            let direct = if x == 0.0 { 1.0 } else { libm::sin(x) / x };
            assert!((sinc(x) - direct).abs() < 1e-15, "x = {x}");
        }
    }
}
