//! The fixed-hip model with first-order muscle activation (issue 16 item
//! 1, beyond the thesis): the four stimulated muscle groups' activations
//! `a = [a_hf, a_he, a_kf, a_ke]` become states,
//! `a_i' = (u_i - a_i) / T_a`, and drive the muscle torques in place of
//! the stimulation (the thesis sets `a = u`, eq 4.20).
//!
//! State `x = [q1, q2, q1', q2', a_hf, a_he, a_kf, a_ke]`, input and
//! measurements as [`FixedHipModel`]. With `G(x)` the generalised torque per
//! unit activation ([`FixedHipModel::muscle_torque_matrix`]), `w = M^-1`
//! and `Q0(x, u)` the generalised torque without the muscles (passive
//! tissues and motors):
//!
//! ```text
//! f = [q1', q2', w (Q0 + G a - V - G_g), (u_m - a) / T_a]
//! A(x) = [A_4(x)  [0; w G(x)];  0  -I/T_a]     (A_4: the fixed-hip SDC of
//!                                               FixedHipModel, top left)
//! B(x)u = [0, 0, w Q0(x, u), u_m / T_a]
//! C(x) = [C_4(x)  0]
//! ```
//!
//! so `A(x) x + B(x) u = f(x, u)` (`A_4 x + [0, 0, w Q] = f_4` with the
//! muscle part `G a` of `Q` moved into `A`). Jacobian: the fixed hip's
//! `df/dx` at the input with `a` for the muscle inputs, the columns
//! `d(acc)/da = w G(x)`, and `-I/T_a`. Derivation and tests:
//! docs/FES_ESTIMATION.md "Fixed hip with activation".

use nalgebra::{SMatrix, SVector, Vector4};

use crate::error::{positive, ModelError};
use crate::fixed_hip::FixedHipModel;
use crate::sdc::SdcModel;

/// The activation time constant of the fixed hip when none is given (s):
/// Table 1's `T_a` of leg P1-L, whose passive knee torque the fixed-hip
/// model uses ([`crate::FixedHipParams`]).
pub const FIXED_HIP_T_A: f64 = 0.25;

/// [`FixedHipModel`] with the four muscle activations as states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedHipActivationModel {
    /// The fixed-hip model.
    pub base: FixedHipModel,
    /// Activation time constant `T_a` (s), the same for the four muscles.
    pub t_a: f64,
}

impl FixedHipActivationModel {
    /// The model; `t_a` must be finite and > 0.
    pub fn new(base: FixedHipModel, t_a: f64) -> Result<Self, ModelError> {
        positive("t_a", t_a)?;
        Ok(FixedHipActivationModel { base, t_a })
    }

    fn split(x: &SVector<f64, 8>) -> (Vector4<f64>, Vector4<f64>) {
        (
            Vector4::new(x[0], x[1], x[2], x[3]),
            Vector4::new(x[4], x[5], x[6], x[7]),
        )
    }

    /// The fixed hip's input with the activations in place of the stimulation.
    fn activated_input(a: &Vector4<f64>, u: &SVector<f64, 6>) -> SVector<f64, 6> {
        SVector::<f64, 6>::from_row_slice(&[a[0], a[1], a[2], a[3], u[4], u[5]])
    }

    fn activation_rate(&self, a: &Vector4<f64>, u: &SVector<f64, 6>) -> Vector4<f64> {
        (Vector4::new(u[0], u[1], u[2], u[3]) - a) / self.t_a
    }

    fn stack(top: &Vector4<f64>, bottom: &Vector4<f64>) -> SVector<f64, 8> {
        SVector::<f64, 8>::from_row_slice(&[
            top[0], top[1], top[2], top[3], bottom[0], bottom[1], bottom[2], bottom[3],
        ])
    }
}

impl SdcModel<8, 4, 6> for FixedHipActivationModel {
    fn f(&self, x: &SVector<f64, 8>, u: &SVector<f64, 6>) -> SVector<f64, 8> {
        let (q, a) = Self::split(x);
        let top = self.base.f(&q, &Self::activated_input(&a, u));
        Self::stack(&top, &self.activation_rate(&a, u))
    }

    fn h(&self, x: &SVector<f64, 8>) -> SVector<f64, 4> {
        self.base.h(&Self::split(x).0)
    }

    fn sdc_a(&self, x: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
        let (q, _) = Self::split(x);
        let mut m = SMatrix::<f64, 8, 8>::zeros();
        m.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.base.sdc_a(&q));
        let wg = self.base.inverse_mass(&q) * self.base.muscle_torque_matrix(&q);
        m.fixed_view_mut::<2, 4>(2, 4).copy_from(&wg);
        for i in 4..8 {
            m[(i, i)] = -1.0 / self.t_a;
        }
        m
    }

    fn input_term(&self, x: &SVector<f64, 8>, u: &SVector<f64, 6>) -> SVector<f64, 8> {
        let (q, _) = Self::split(x);
        let motors_only = Self::activated_input(&Vector4::zeros(), u);
        let top = self.base.input_term(&q, &motors_only);
        let bottom = Vector4::new(u[0], u[1], u[2], u[3]) / self.t_a;
        Self::stack(&top, &bottom)
    }

    fn sdc_c(&self, x: &SVector<f64, 8>) -> SMatrix<f64, 4, 8> {
        let mut c = SMatrix::<f64, 4, 8>::zeros();
        c.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.base.sdc_c(&Self::split(x).0));
        c
    }

    fn jacobian_f(&self, x: &SVector<f64, 8>, u: &SVector<f64, 6>) -> SMatrix<f64, 8, 8> {
        let (q, a) = Self::split(x);
        let mut j = SMatrix::<f64, 8, 8>::zeros();
        j.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.base.jacobian_f(&q, &Self::activated_input(&a, u)));
        let wg = self.base.inverse_mass(&q) * self.base.muscle_torque_matrix(&q);
        j.fixed_view_mut::<2, 4>(2, 4).copy_from(&wg);
        for i in 4..8 {
            j[(i, i)] = -1.0 / self.t_a;
        }
        j
    }

    fn jacobian_h(&self, x: &SVector<f64, 8>) -> SMatrix<f64, 4, 8> {
        let mut c = SMatrix::<f64, 4, 8>::zeros();
        c.fixed_view_mut::<4, 4>(0, 0)
            .copy_from(&self.base.jacobian_h(&Self::split(x).0));
        c
    }
}
