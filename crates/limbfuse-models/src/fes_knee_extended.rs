//! The knee model of [`crate::fes_knee`] extended beyond the thesis (issue
//! 16; derivation in docs/FES_ESTIMATION.md, "Extended knee model"):
//! optional states for muscle activation, an unknown knee torque and the
//! shank IMU's gyro and accelerometer biases, and the accelerometer's lever
//! arm.
//!
//! State `x = [x1, x2, a_ke?, d?, b_g?, b_a?]` (the optional states in this
//! order, each present when enabled; [`KneeStateLayout`]):
//!
//! * `x1' = x2`
//! * `x2' = -beta sin x1 + alpha (T_p(phi, phi') + T_ke(phi, phi', a) + d)`
//!   with `a = a_ke` when the activation is a state, else `a = u_ke` (eqs
//!   4.1-4.3, 4.6);
//! * `a_ke' = (u_ke - a_ke) / T_a` (first-order activation dynamics; the
//!   thesis's Table 1 gives `T_a`, its estimators take `a_ke = u_ke`);
//! * `d' = 0`, `b_g' = 0`, `b_a' = 0` (random walks: their process noise
//!   enters through `Q`);
//! * `y = [x2 + b_g, g sin x1 + r x2' + b_a]` (eq 4.7 plus the biases and the
//!   tangential acceleration `r x2'` of a shank accelerometer `r` metres below
//!   the knee; `r = 0` is the thesis's measurement).
//!
//! SDC factorisation, with `F = FL(phi) FV(phi')` the force-length-velocity
//! product of eq 4.3 (`T_ke = F a`), `T_p0 = T_p(pi/2, 0)` and the secant
//! `k_p(x1) = (T_p(pi/2 - x1, 0) - T_p0) / x1` of the static passive torque:
//!
//! ```text
//! A[1,2] = 1
//! A[2,1] = -beta sinc x1 + alpha k_p(x1), A[2,2] = -alpha d2
//! A[2,a] = alpha F, A[2,d] = alpha
//! A[a,a] = -1/T_a
//! B(x)u  = [0, alpha (T_p0 + T_ke(u_ke) if a is no state), u_ke/T_a, 0, 0, 0]
//! C[1,2] = 1, C[1,b_g] = 1
//! C[2,1] = g sinc x1 + r A[2,1], C[2,a] = r A[2,a], C[2,d] = r A[2,d], C[2,b_a] = 1
//! D(x,u) = [0, r (B(x)u)_2]            (h = C(x) x + D(x, u))
//! ```

use nalgebra::{SMatrix, SVector};

use crate::error::{finite, ModelError};
use crate::fes_knee::KneeFesModel;
use crate::sdc::{sinc, Linearised, SdcModel};

/// Which optional states the extended knee model carries.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KneeStateOptions {
    /// Muscle activation `a_ke` with `a_ke' = (u_ke - a_ke) / T_a`.
    pub activation: bool,
    /// Unknown knee torque `d` (N m), a random walk.
    pub disturbance: bool,
    /// Shank gyro z bias `b_g` (rad/s), a random walk.
    pub gyro_bias: bool,
    /// Shank accelerometer x bias `b_a` (m/s^2), a random walk.
    pub acc_bias: bool,
}

impl KneeStateOptions {
    /// Number of states: 2 plus one per enabled option.
    pub const fn states(&self) -> usize {
        2 + self.activation as usize
            + self.disturbance as usize
            + self.gyro_bias as usize
            + self.acc_bias as usize
    }
}

/// Where each optional state sits in the state vector.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KneeStateLayout {
    /// Index of `a_ke`.
    pub activation: Option<usize>,
    /// Index of the unknown torque `d`.
    pub disturbance: Option<usize>,
    /// Index of the gyro bias.
    pub gyro_bias: Option<usize>,
    /// Index of the accelerometer bias.
    pub acc_bias: Option<usize>,
}

impl KneeStateLayout {
    /// The layout of `opts`: the enabled states after `x1, x2`, in the order
    /// activation, disturbance, gyro bias, accelerometer bias.
    pub fn new(opts: KneeStateOptions) -> Self {
        let mut next = 2;
        let mut take = |on: bool| {
            if on {
                next += 1;
                Some(next - 1)
            } else {
                None
            }
        };
        KneeStateLayout {
            activation: take(opts.activation),
            disturbance: take(opts.disturbance),
            gyro_bias: take(opts.gyro_bias),
            acc_bias: take(opts.acc_bias),
        }
    }
}

/// Why an extended knee model could not be built.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ExtendedKneeError {
    /// The parameters are unphysical.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The state dimension does not match the options.
    #[error("the extended knee model with these options has {needed} states, not {given}")]
    Dimension {
        /// States the options need.
        needed: usize,
        /// The `N` asked for.
        given: usize,
    },
}

/// The extended knee model with `N = 2 + enabled options` states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtendedKneeModel<const N: usize> {
    /// The thesis model (eqs 4.1-4.7).
    pub base: KneeFesModel,
    /// Which states are present.
    pub options: KneeStateOptions,
    /// Their indices.
    pub layout: KneeStateLayout,
    /// Shank accelerometer distance below the knee `r` (m); 0: thesis.
    pub imu_radius: f64,
    /// `(T_p, dT_p/dphi)` at `(pi/2, 0)` (eq 4.2), derived once from
    /// `base` (the constant of `B(x) u` and the secant's limit).
    rest_passive: (f64, f64),
}

impl<const N: usize> ExtendedKneeModel<N> {
    /// The model; `N` must equal `options.states()`, `imu_radius` finite.
    pub fn new(
        base: KneeFesModel,
        options: KneeStateOptions,
        imu_radius: f64,
    ) -> Result<Self, ExtendedKneeError> {
        if options.states() != N {
            return Err(ExtendedKneeError::Dimension {
                needed: options.states(),
                given: N,
            });
        }
        finite("imu_radius", imu_radius)?;
        let rest = base.passive_torque(core::f64::consts::FRAC_PI_2, 0.0);
        Ok(ExtendedKneeModel {
            base,
            options,
            layout: KneeStateLayout::new(options),
            imu_radius,
            rest_passive: (rest.0, rest.1),
        })
    }

    /// The activation the torque uses: the state, or the input.
    fn activation(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> f64 {
        self.layout.activation.map_or(u[0], |i| x[i])
    }

    fn state(&self, x: &SVector<f64, N>, i: Option<usize>) -> f64 {
        i.map_or(0.0, |i| x[i])
    }

    /// `x2'` (rad/s^2).
    fn accel(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> f64 {
        let joint = SVector::<f64, 2>::new(x[0], x[1]);
        -self.base.beta() * libm::sin(x[0])
            + self.base.alpha()
                * (self.base.joint_torque(&joint, self.activation(x, u))
                    + self.state(x, self.layout.disturbance))
    }

    /// Row 2 of `df/dx`.
    fn accel_jacobian(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> SMatrix<f64, 1, N> {
        self.accel_with_jacobian(x, u).1
    }

    /// `x2'` and row 2 of `df/dx` from one evaluation of the torques
    /// (the same arithmetic as [`Self::accel`] and [`Self::accel_jacobian`]).
    fn accel_with_jacobian(
        &self,
        x: &SVector<f64, N>,
        u: &SVector<f64, 1>,
    ) -> (f64, SMatrix<f64, 1, N>) {
        let m = &self.base;
        let phi = KneeFesModel::phi(x[0]);
        let a = self.activation(x, u);
        let (tp, p_phi, p_rate) = m.passive_torque(phi, -x[1]);
        let (tke, f_phi, f_rate) = m.fes_torque(phi, -x[1], a);
        let accel = -m.beta() * libm::sin(x[0])
            + m.alpha() * ((tp + tke) + self.state(x, self.layout.disturbance));
        let mut row = SMatrix::<f64, 1, N>::zeros();
        row[0] = -m.beta() * libm::cos(x[0]) - m.alpha() * (p_phi + f_phi);
        row[1] = -m.alpha() * (p_rate + f_rate);
        if let Some(i) = self.layout.activation {
            row[i] = m.alpha() * m.fes_torque(phi, -x[1], 1.0).0;
        }
        if let Some(i) = self.layout.disturbance {
            row[i] = m.alpha();
        }
        (accel, row)
    }

    /// Secant slope of the static passive torque about `x1 = 0`:
    /// `(T_p(pi/2 - x1, 0) - T_p(pi/2, 0)) / x1`, its limit
    /// `-dT_p/dphi (pi/2)` below `|x1| < 1e-8`.
    pub fn passive_secant(&self, x1: f64) -> f64 {
        if libm::fabs(x1) < 1e-8 {
            return -self.rest_passive.1;
        }
        let half_pi = core::f64::consts::FRAC_PI_2;
        (self.base.passive_torque(half_pi - x1, 0.0).0 - self.rest_passive.0) / x1
    }

    /// Row 2 of the SDC `A(x)` and of `B(x) u`. Unlike the thesis's eq 4.12,
    /// which leaves the passive torque in `B(x) u`, its state dependence is
    /// in `A`: stiffness as the secant [`Self::passive_secant`], damping
    /// `-alpha d2` on `x2`; `B` keeps the constant `alpha T_p(pi/2, 0)`.
    /// With a lever arm the measurement matrix `C` (= `r` times this row)
    /// then sees the passive stiffness too.
    fn accel_sdc(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> (SMatrix<f64, 1, N>, f64) {
        let m = &self.base;
        let phi = KneeFesModel::phi(x[0]);
        let mut row = SMatrix::<f64, 1, N>::zeros();
        row[0] = -m.beta() * sinc(x[0]) + m.alpha() * self.passive_secant(x[0]);
        row[1] = -m.alpha() * m.p.d[1];
        let mut input = self.rest_passive.0;
        match self.layout.activation {
            Some(i) => row[i] = m.alpha() * m.fes_torque(phi, -x[1], 1.0).0,
            None => input += m.fes_torque(phi, -x[1], u[0]).0,
        }
        if let Some(i) = self.layout.disturbance {
            row[i] = m.alpha();
        }
        (row, m.alpha() * input)
    }
}

impl<const N: usize> SdcModel<N, 2, 1> for ExtendedKneeModel<N> {
    fn f(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> SVector<f64, N> {
        let mut f = SVector::<f64, N>::zeros();
        f[0] = x[1];
        f[1] = self.accel(x, u);
        if let Some(i) = self.layout.activation {
            f[i] = (u[0] - x[i]) / self.base.p.t_a;
        }
        f
    }

    /// The measurement without the lever-arm term (`r = 0`).
    fn h(&self, x: &SVector<f64, N>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(
            x[1] + self.state(x, self.layout.gyro_bias),
            self.base.p.g * libm::sin(x[0]) + self.state(x, self.layout.acc_bias),
        )
    }

    fn sdc_a(&self, x: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let mut a = SMatrix::<f64, N, N>::zeros();
        a[(0, 1)] = 1.0;
        // Row 2 does not depend on u (the input part goes to B(x)u).
        let (row, _) = self.accel_sdc(x, &SVector::<f64, 1>::zeros());
        a.set_row(1, &row);
        if let Some(i) = self.layout.activation {
            a[(i, i)] = -1.0 / self.base.p.t_a;
        }
        a
    }

    fn input_term(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> SVector<f64, N> {
        let mut b = SVector::<f64, N>::zeros();
        b[1] = self.accel_sdc(x, u).1;
        if let Some(i) = self.layout.activation {
            b[i] = u[0] / self.base.p.t_a;
        }
        b
    }

    fn sdc_c(&self, x: &SVector<f64, N>) -> SMatrix<f64, 2, N> {
        let mut c = SMatrix::<f64, 2, N>::zeros();
        c[(0, 1)] = 1.0;
        let (row, _) = self.accel_sdc(x, &SVector::<f64, 1>::zeros());
        c.set_row(1, &(row * self.imu_radius));
        c[(1, 0)] += self.base.p.g * sinc(x[0]);
        if let Some(i) = self.layout.gyro_bias {
            c[(0, i)] = 1.0;
        }
        if let Some(i) = self.layout.acc_bias {
            c[(1, i)] = 1.0;
        }
        c
    }

    fn jacobian_f(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> SMatrix<f64, N, N> {
        let mut j = SMatrix::<f64, N, N>::zeros();
        j[(0, 1)] = 1.0;
        j.set_row(1, &self.accel_jacobian(x, u));
        if let Some(i) = self.layout.activation {
            j[(i, i)] = -1.0 / self.base.p.t_a;
        }
        j
    }

    fn jacobian_h(&self, x: &SVector<f64, N>) -> SMatrix<f64, 2, N> {
        let mut j = SMatrix::<f64, 2, N>::zeros();
        j[(0, 1)] = 1.0;
        j[(1, 0)] = self.base.p.g * libm::cos(x[0]);
        if let Some(i) = self.layout.gyro_bias {
            j[(0, i)] = 1.0;
        }
        if let Some(i) = self.layout.acc_bias {
            j[(1, i)] = 1.0;
        }
        j
    }

    fn h_with_input(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> SVector<f64, 2> {
        let mut y = self.h(x);
        if self.imu_radius != 0.0 {
            y[1] += self.imu_radius * self.accel(x, u);
        }
        y
    }

    fn sdc_measurement_input(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(0.0, self.imu_radius * self.accel_sdc(x, u).1)
    }

    fn jacobian_h_with_input(
        &self,
        x: &SVector<f64, N>,
        u: &SVector<f64, 1>,
    ) -> SMatrix<f64, 2, N> {
        let mut j = self.jacobian_h(x);
        if self.imu_radius != 0.0 {
            let row = self.accel_jacobian(x, u) * self.imu_radius;
            for k in 0..N {
                j[(1, k)] += row[k];
            }
        }
        j
    }

    /// [`Self::sdc_a`], [`Self::sdc_c`], [`Self::input_term`] and
    /// [`Self::sdc_measurement_input`] from one evaluation of row 2.
    fn sdc_terms(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> Linearised<N, 2> {
        let (row, input) = self.accel_sdc(x, u);
        let mut a = SMatrix::<f64, N, N>::zeros();
        a[(0, 1)] = 1.0;
        a.set_row(1, &row);
        let mut b = SVector::<f64, N>::zeros();
        b[1] = input;
        if let Some(i) = self.layout.activation {
            a[(i, i)] = -1.0 / self.base.p.t_a;
            b[i] = u[0] / self.base.p.t_a;
        }
        let mut c = SMatrix::<f64, 2, N>::zeros();
        c[(0, 1)] = 1.0;
        c.set_row(1, &(row * self.imu_radius));
        c[(1, 0)] += self.base.p.g * sinc(x[0]);
        if let Some(i) = self.layout.gyro_bias {
            c[(0, i)] = 1.0;
        }
        if let Some(i) = self.layout.acc_bias {
            c[(1, i)] = 1.0;
        }
        let d = SVector::<f64, 2>::new(0.0, self.imu_radius * input);
        Linearised {
            drift: a * x + b,
            y_hat: c * x + d,
            a,
            c,
        }
    }

    /// [`Self::jacobian_f`], [`Self::jacobian_h_with_input`], [`Self::f`]
    /// and [`Self::h_with_input`] from one evaluation of the torques.
    fn jacobian_terms(&self, x: &SVector<f64, N>, u: &SVector<f64, 1>) -> Linearised<N, 2> {
        let (accel, row) = self.accel_with_jacobian(x, u);
        let mut a = SMatrix::<f64, N, N>::zeros();
        a[(0, 1)] = 1.0;
        a.set_row(1, &row);
        let mut drift = SVector::<f64, N>::zeros();
        drift[0] = x[1];
        drift[1] = accel;
        if let Some(i) = self.layout.activation {
            a[(i, i)] = -1.0 / self.base.p.t_a;
            drift[i] = (u[0] - x[i]) / self.base.p.t_a;
        }
        let mut c = self.jacobian_h(x);
        let mut y_hat = self.h(x);
        if self.imu_radius != 0.0 {
            let r_row = row * self.imu_radius;
            for k in 0..N {
                c[(1, k)] += r_row[k];
            }
            y_hat[1] += self.imu_radius * accel;
        }
        Linearised { a, c, drift, y_hat }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{KneeFesParams, KneeSubject};

    #[test]
    fn layout_orders_the_enabled_states() {
        let l = KneeStateLayout::new(KneeStateOptions {
            activation: true,
            disturbance: false,
            gyro_bias: true,
            acc_bias: true,
        });
        assert_eq!(
            (l.activation, l.disturbance, l.gyro_bias, l.acc_bias),
            (Some(2), None, Some(3), Some(4))
        );
    }

    #[test]
    fn dimension_must_match_the_options() {
        let base = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
        let opts = KneeStateOptions {
            activation: true,
            ..Default::default()
        };
        assert!(ExtendedKneeModel::<3>::new(base, opts, 0.2).is_ok());
        assert_eq!(
            ExtendedKneeModel::<4>::new(base, opts, 0.2).unwrap_err(),
            ExtendedKneeError::Dimension {
                needed: 3,
                given: 4
            }
        );
    }
}
