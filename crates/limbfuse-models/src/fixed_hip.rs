//! 2-DOF fixed-hip model of a swinging leg driven by FES and motors
//! (paper 004 section 4.2, eqs 4.18-4.25).
//!
//! The trunk is fixed upright; thigh and lower leg (shank + foot) swing in the
//! sagittal plane. State `x = [x1, x2, x3, x4] = [q1, q2, q1_dot, q2_dot]`
//! with `q1` the thigh's and `q2` the lower leg's absolute angle from hanging
//! vertically, positive counter-clockwise seen from the right (distal end
//! forward) — the SPEC absolute angles `thigh` and `shank`. Then SPEC
//! `hip = -q1` (trunk upright) and `knee = q1 - q2`.
//!
//! Dynamics (eq 4.18, absolute angles of a double pendulum):
//! `M(q) q_ddot + V(q, q_dot) + G(q) = T_pa + T`, with
//! `M = [[M11, a1 cos(q1-q2)], [a1 cos(q1-q2), M22]]`,
//! `V = [a1 q2_dot^2 sin(q1-q2), -a1 q1_dot^2 sin(q1-q2)]`,
//! `G = [b2 sin q1, b3 sin q2]`, where `M11 = I1 + m1 lc1^2 + m2 L1^2`,
//! `M22 = I2 + m2 lc2^2`, `a1 = m2 L1 lc2`, `b2 = (m1 lc1 + m2 L1) g`,
//! `b3 = m2 lc2 g` (I1, I2 about the segment centres of mass).
//!
//! Joint torques: `tau_h` acts on the thigh about +z (reaction on the
//! trunk), `tau_k` acts on the lower leg about +z (reaction on the thigh);
//! their generalised forces on `(q1, q2)` are `(tau_h - tau_k, tau_k)`.
//! `tau_h = T_hf psi_hf u_hf - T_he psi_he u_he + tau_h,passive + tau_hip_motor`,
//! `tau_k = T_ke psi_ke u_ke - T_kf psi_kf u_kf + tau_k,passive + tau_knee_motor`
//! (eq 4.19-4.20 with the motor gain folded into the torque input), with the
//! force-velocity factors `psi = 1 -/+ c_v * (joint speed in the muscle's
//! shortening direction)` (the linear form of eq 4.3). Input order
//! `u = [u_hf, u_he, u_kf, u_ke, tau_hip_motor, tau_knee_motor]` (eq 4.20).
//!
//! Measurements (eq 4.24), order used here:
//! `y = [thigh gyr_z, shank gyr_z, thigh acc_x, shank acc_x]
//!    = [x3, x4, g sin x1, g sin x2]` (SPEC sensor frame; the thesis's
//! sentence after eq 4.24 lists the gyro and accelerometer rows in a
//! different order and its IMU x axis points backwards).
//!
//! SDC factorisation (derived from eq 4.23, SPEC section 6; `w = M^-1`,
//! `s = sin(x1 - x2)`): rows 1-2 `[0 0 1 0; 0 0 0 1]`,
//! `A31 = -w11 b2 sinc x1`, `A32 = -w12 b3 sinc x2`, `A33 = w12 a1 x3 s`,
//! `A34 = -w11 a1 x4 s`, `A41 = -w21 b2 sinc x1`, `A42 = -w22 b3 sinc x2`,
//! `A43 = w22 a1 x3 s`, `A44 = -w21 a1 x4 s`; `B(x) u = [0, 0, M^-1 (T_pa + T)]`;
//! `C = [0 0 1 0; 0 0 0 1; g sinc x1 0 0 0; 0 g sinc x2 0 0]`.
//!
//! Segment data: D. A. Winter, *Biomechanics and Motor Control of Human
//! Movement*, 4th ed., Wiley 2009, Table 4.1 (thigh: 0.100 M, centre of mass
//! 0.433 L from the hip, radius of gyration about it 0.323 L, L = 0.245 H;
//! foot and leg: 0.061 M, 0.606 L, 0.416 L, L = 0.246 H) for 75 kg, 1.75 m.
//! The knee's passive torque is eq 4.2 with Table 1's P1-L values. The hip's
//! passive torque (linear spring-damper) and the peak muscle torques are
//! illustrative values of plausible magnitude, not identified from a source.

use nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector4};

use crate::default_body::{DEFAULT_BODY_HEIGHT_M, DEFAULT_BODY_MASS_KG};
use crate::error::{finite, limits, positive, within_limit, ModelError};
use crate::fes_knee::{KneeFesParams, KneeSubject};
use crate::sdc::{sinc, SdcModel};

/// Parameters of the fixed-hip leg (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedHipParams {
    /// Thigh mass `m1` (kg).
    pub thigh_mass: f64,
    /// Thigh length hip-knee `L1` (m).
    pub thigh_length: f64,
    /// Hip to thigh centre of mass `lc1` (m).
    pub thigh_com: f64,
    /// Thigh inertia about its centre of mass `I1` (kg m^2).
    pub thigh_inertia: f64,
    /// Lower-leg (shank + foot) mass `m2` (kg).
    pub leg_mass: f64,
    /// Knee to lower-leg centre of mass `lc2` (m).
    pub leg_com: f64,
    /// Lower-leg inertia about its centre of mass `I2` (kg m^2).
    pub leg_inertia: f64,
    /// Gravity (m/s^2).
    pub g: f64,
    /// Hip passive stiffness (N m/rad) about the hanging pose.
    pub hip_stiffness: f64,
    /// Hip passive damping (N m s/rad).
    pub hip_damping: f64,
    /// Knee passive torque rest angle `phi0` (rad), eq 4.2.
    pub knee_phi0: f64,
    /// Knee passive torque coefficients `d1 ... d6`, eq 4.2.
    pub knee_d: [f64; 6],
    /// Peak FES torques `[T_hf, T_he, T_kf, T_ke]` (N m) at full stimulation.
    pub muscle_peak: [f64; 4],
    /// Force-velocity coefficient `c_v` (s/rad).
    pub force_velocity: f64,
}

impl Default for FixedHipParams {
    fn default() -> Self {
        let (bm, h) = (DEFAULT_BODY_MASS_KG, DEFAULT_BODY_HEIGHT_M);
        let l1 = 0.245 * h;
        let l2 = 0.246 * h;
        let m1 = 0.100 * bm;
        let m2 = 0.061 * bm;
        let knee = KneeFesParams::subject(KneeSubject::P1L);
        FixedHipParams {
            thigh_mass: m1,
            thigh_length: l1,
            thigh_com: 0.433 * l1,
            thigh_inertia: m1 * (0.323 * l1) * (0.323 * l1),
            leg_mass: m2,
            leg_com: 0.606 * l2,
            leg_inertia: m2 * (0.416 * l2) * (0.416 * l2),
            g: 9.81,
            hip_stiffness: 2.0,
            hip_damping: 1.0,
            knee_phi0: knee.phi0,
            knee_d: knee.d,
            muscle_peak: [40.0, 40.0, 30.0, 50.0],
            force_velocity: 0.2,
        }
    }
}

impl FixedHipParams {
    /// Rejects unphysical parameters: non-finite values, non-positive masses,
    /// lengths, inertias or `g`, a centre of mass outside the thigh, negative
    /// damping or negative peak torques.
    pub fn validate(&self) -> Result<(), ModelError> {
        positive("thigh_mass", self.thigh_mass)?;
        positive("thigh_length", self.thigh_length)?;
        positive("thigh_com", self.thigh_com)?;
        positive("thigh_inertia", self.thigh_inertia)?;
        positive("leg_mass", self.leg_mass)?;
        positive("leg_com", self.leg_com)?;
        positive("leg_inertia", self.leg_inertia)?;
        positive("g", self.g)?;
        for (name, v, limit) in [
            ("thigh_mass", self.thigh_mass, limits::MASS),
            ("thigh_length", self.thigh_length, limits::LENGTH),
            ("thigh_com", self.thigh_com, limits::LENGTH),
            ("thigh_inertia", self.thigh_inertia, limits::INERTIA),
            ("leg_mass", self.leg_mass, limits::MASS),
            ("leg_com", self.leg_com, limits::LENGTH),
            ("leg_inertia", self.leg_inertia, limits::INERTIA),
            ("g", self.g, limits::G),
        ] {
            within_limit(name, v, limit)?;
        }
        if self.thigh_com >= self.thigh_length {
            return Err(ModelError::OutOfRange {
                name: "thigh_com",
                value: self.thigh_com,
                range: "(0, thigh_length)",
            });
        }
        finite("hip_stiffness", self.hip_stiffness)?;
        finite("knee_phi0", self.knee_phi0)?;
        for v in self.knee_d {
            finite("knee_d", v)?;
        }
        finite("force_velocity", self.force_velocity)?;
        for (name, v) in [
            ("hip_damping", self.hip_damping),
            ("knee_d2", self.knee_d[1]),
        ] {
            finite(name, v)?;
            if v < 0.0 {
                return Err(ModelError::OutOfRange {
                    name,
                    value: v,
                    range: "[0, inf) (negative damping adds energy)",
                });
            }
        }
        for v in self.muscle_peak {
            finite("muscle_peak", v)?;
            if v < 0.0 {
                return Err(ModelError::OutOfRange {
                    name: "muscle_peak",
                    value: v,
                    range: "[0, inf)",
                });
            }
        }
        Ok(())
    }
}

/// The model with its derived constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedHipModel {
    /// The parameters.
    pub p: FixedHipParams,
    m11: f64,
    m22: f64,
    a1: f64,
    b2: f64,
    b3: f64,
}

/// Partial derivatives of the generalised torque `Q(x, u)` with respect to `x`.
type TorqueJacobian = SMatrix<f64, 2, 4>;

impl FixedHipModel {
    /// Validates the parameters and derives `M11, M22, a1, b2, b3`.
    pub fn new(p: FixedHipParams) -> Result<Self, ModelError> {
        p.validate()?;
        let a1 = p.leg_mass * p.thigh_length * p.leg_com;
        Ok(FixedHipModel {
            p,
            m11: p.thigh_inertia
                + p.thigh_mass * p.thigh_com * p.thigh_com
                + p.leg_mass * p.thigh_length * p.thigh_length,
            m22: p.leg_inertia + p.leg_mass * p.leg_com * p.leg_com,
            a1,
            b2: (p.thigh_mass * p.thigh_com + p.leg_mass * p.thigh_length) * p.g,
            b3: p.leg_mass * p.leg_com * p.g,
        })
    }

    /// `(a1, b2, b3)` of eq 4.23.
    pub fn constants(&self) -> (f64, f64, f64) {
        (self.a1, self.b2, self.b3)
    }

    /// Mass matrix `M(x)`.
    pub fn mass_matrix(&self, x: &Vector4<f64>) -> Matrix2<f64> {
        let m12 = self.a1 * libm::cos(x[0] - x[1]);
        Matrix2::new(self.m11, m12, m12, self.m22)
    }

    /// `M(x)^-1` (always invertible: `det = M11 M22 - a1^2 cos^2 > 0` for positive inertias).
    pub fn inverse_mass(&self, x: &Vector4<f64>) -> Matrix2<f64> {
        let m12 = self.a1 * libm::cos(x[0] - x[1]);
        let det = self.m11 * self.m22 - m12 * m12;
        Matrix2::new(self.m22, -m12, -m12, self.m11) / det
    }

    /// Joint torques `(tau_h, tau_k)` (see module docs).
    pub fn joint_torques(&self, x: &Vector4<f64>, u: &SVector<f64, 6>) -> (f64, f64) {
        let p = &self.p;
        let cv = p.force_velocity;
        let [t_hf, t_he, t_kf, t_ke] = p.muscle_peak;
        let v_k = x[3] - x[2];
        let tau_h = t_hf * (1.0 - cv * x[2]) * u[0]
            - t_he * (1.0 + cv * x[2]) * u[1]
            - p.hip_stiffness * x[0]
            - p.hip_damping * x[2]
            + u[4];
        let (tp, _, _) = self.knee_passive(x);
        let tau_k = t_ke * (1.0 - cv * v_k) * u[3] - t_kf * (1.0 + cv * v_k) * u[2] + tp + u[5];
        (tau_h, tau_k)
    }

    /// Knee passive torque (eq 4.2 at knee flexion `phi = x1 - x2`) and its
    /// derivatives with respect to `phi` and `phi_dot`.
    fn knee_passive(&self, x: &Vector4<f64>) -> (f64, f64, f64) {
        let d = &self.p.knee_d;
        let phi = x[0] - x[1];
        let rate = x[2] - x[3];
        let e4 = libm::exp(d[3] * phi);
        let e6 = libm::exp(d[5] * phi);
        (
            d[0] * (phi - self.p.knee_phi0) + d[1] * rate + d[2] * e4 - d[4] * e6,
            d[0] + d[2] * d[3] * e4 - d[4] * d[5] * e6,
            d[1],
        )
    }

    /// The generalised torque per unit muscle input: column `i` of the
    /// returned matrix is `dQ/du_i` for `u = [u_hf, u_he, u_kf, u_ke]`
    /// (the force-velocity-scaled peak torques; `Q` is affine in them).
    pub fn muscle_torque_matrix(&self, x: &Vector4<f64>) -> SMatrix<f64, 2, 4> {
        let p = &self.p;
        let cv = p.force_velocity;
        let [t_hf, t_he, t_kf, t_ke] = p.muscle_peak;
        let v_k = x[3] - x[2];
        let hf = t_hf * (1.0 - cv * x[2]);
        let he = -t_he * (1.0 + cv * x[2]);
        let kf = -t_kf * (1.0 + cv * v_k);
        let ke = t_ke * (1.0 - cv * v_k);
        // Q = (tau_h - tau_k, tau_k).
        SMatrix::<f64, 2, 4>::new(hf, he, -kf, -ke, 0.0, 0.0, kf, ke)
    }

    /// Generalised torque `Q = T_pa + T = (tau_h - tau_k, tau_k)`.
    pub fn generalised_torque(&self, x: &Vector4<f64>, u: &SVector<f64, 6>) -> Vector2<f64> {
        let (th, tk) = self.joint_torques(x, u);
        Vector2::new(th - tk, tk)
    }

    fn generalised_torque_jacobian(&self, x: &Vector4<f64>, u: &SVector<f64, 6>) -> TorqueJacobian {
        let p = &self.p;
        let cv = p.force_velocity;
        let [t_hf, t_he, t_kf, t_ke] = p.muscle_peak;
        let dth_dx1 = -p.hip_stiffness;
        let dth_dx3 = -p.hip_damping - cv * (t_hf * u[0] + t_he * u[1]);
        let (_, dphi, drate) = self.knee_passive(x);
        let dtk_dv = -cv * (t_ke * u[3] + t_kf * u[2]);
        let dtk = [dphi, -dphi, drate - dtk_dv, -drate + dtk_dv];
        let dth = [dth_dx1, 0.0, dth_dx3, 0.0];
        let mut j = TorqueJacobian::zeros();
        for k in 0..4 {
            j[(0, k)] = dth[k] - dtk[k];
            j[(1, k)] = dtk[k];
        }
        j
    }

    /// `r = Q - V - G` (the right-hand side before `M^-1`).
    fn rhs(&self, x: &Vector4<f64>, u: &SVector<f64, 6>) -> Vector2<f64> {
        let s = libm::sin(x[0] - x[1]);
        let q = self.generalised_torque(x, u);
        Vector2::new(
            q[0] - self.a1 * x[3] * x[3] * s - self.b2 * libm::sin(x[0]),
            q[1] + self.a1 * x[2] * x[2] * s - self.b3 * libm::sin(x[1]),
        )
    }

    /// Joint angular accelerations `q_ddot = M^-1 (Q - V - G)`.
    pub fn accelerations(&self, x: &Vector4<f64>, u: &SVector<f64, 6>) -> Vector2<f64> {
        self.inverse_mass(x) * self.rhs(x, u)
    }
}

impl SdcModel<4, 4, 6> for FixedHipModel {
    fn f(&self, x: &SVector<f64, 4>, u: &SVector<f64, 6>) -> SVector<f64, 4> {
        let acc = self.accelerations(x, u);
        Vector4::new(x[2], x[3], acc[0], acc[1])
    }

    fn h(&self, x: &SVector<f64, 4>) -> SVector<f64, 4> {
        let g = self.p.g;
        Vector4::new(x[2], x[3], g * libm::sin(x[0]), g * libm::sin(x[1]))
    }

    fn sdc_a(&self, x: &SVector<f64, 4>) -> SMatrix<f64, 4, 4> {
        let w = self.inverse_mass(x);
        let s = libm::sin(x[0] - x[1]);
        let (a1, b2, b3) = (self.a1, self.b2, self.b3);
        let (s1, s2) = (sinc(x[0]), sinc(x[1]));
        #[rustfmt::skip]
        let a = SMatrix::<f64, 4, 4>::new(
            0.0, 0.0, 1.0, 0.0,
            0.0, 0.0, 0.0, 1.0,
            -w[(0, 0)] * b2 * s1, -w[(0, 1)] * b3 * s2, w[(0, 1)] * a1 * x[2] * s, -w[(0, 0)] * a1 * x[3] * s,
            -w[(1, 0)] * b2 * s1, -w[(1, 1)] * b3 * s2, w[(1, 1)] * a1 * x[2] * s, -w[(1, 0)] * a1 * x[3] * s,
        );
        a
    }

    fn input_term(&self, x: &SVector<f64, 4>, u: &SVector<f64, 6>) -> SVector<f64, 4> {
        let b = self.inverse_mass(x) * self.generalised_torque(x, u);
        Vector4::new(0.0, 0.0, b[0], b[1])
    }

    fn sdc_c(&self, x: &SVector<f64, 4>) -> SMatrix<f64, 4, 4> {
        let g = self.p.g;
        #[rustfmt::skip]
        let c = SMatrix::<f64, 4, 4>::new(
            0.0, 0.0, 1.0, 0.0,
            0.0, 0.0, 0.0, 1.0,
            g * sinc(x[0]), 0.0, 0.0, 0.0,
            0.0, g * sinc(x[1]), 0.0, 0.0,
        );
        c
    }

    fn jacobian_f(&self, x: &SVector<f64, 4>, u: &SVector<f64, 6>) -> SMatrix<f64, 4, 4> {
        let w = self.inverse_mass(x);
        let z = w * self.rhs(x, u);
        let (a1, b2, b3) = (self.a1, self.b2, self.b3);
        let d = x[0] - x[1];
        let (s, c) = (libm::sin(d), libm::cos(d));
        let mut dr = self.generalised_torque_jacobian(x, u);
        // -V and -G.
        dr[(0, 0)] += -a1 * x[3] * x[3] * c - b2 * libm::cos(x[0]);
        dr[(0, 1)] += a1 * x[3] * x[3] * c;
        dr[(0, 3)] += -2.0 * a1 * x[3] * s;
        dr[(1, 0)] += a1 * x[2] * x[2] * c;
        dr[(1, 1)] += -a1 * x[2] * x[2] * c - b3 * libm::cos(x[1]);
        dr[(1, 2)] += 2.0 * a1 * x[2] * s;
        // dM/dx1 = [[0, -a1 s], [-a1 s, 0]] = -dM/dx2: subtract (dM/dxk) z.
        let dmz = Vector2::new(-a1 * s * z[1], -a1 * s * z[0]);
        for r in 0..2 {
            dr[(r, 0)] -= dmz[r];
            dr[(r, 1)] += dmz[r];
        }
        let lower = w * dr;
        let mut j = SMatrix::<f64, 4, 4>::zeros();
        j[(0, 2)] = 1.0;
        j[(1, 3)] = 1.0;
        for k in 0..4 {
            j[(2, k)] = lower[(0, k)];
            j[(3, k)] = lower[(1, k)];
        }
        j
    }

    fn jacobian_h(&self, x: &SVector<f64, 4>) -> SMatrix<f64, 4, 4> {
        let g = self.p.g;
        #[rustfmt::skip]
        let c = SMatrix::<f64, 4, 4>::new(
            0.0, 0.0, 1.0, 0.0,
            0.0, 0.0, 0.0, 1.0,
            g * libm::cos(x[0]), 0.0, 0.0, 0.0,
            0.0, g * libm::cos(x[1]), 0.0, 0.0,
        );
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Default leg with the passive terms off (hip spring-damper and eq 4.2
    /// knee torque zero); muscles are off whenever `u[0..4] = 0`.
    fn unpowered() -> FixedHipModel {
        FixedHipModel::new(FixedHipParams {
            hip_stiffness: 0.0,
            hip_damping: 0.0,
            knee_d: [0.0; 6],
            ..FixedHipParams::default()
        })
        .unwrap()
    }

    /// Statics of eq 4.18/4.23 (`q_dot = 0`, so `V = 0`): the motors hold the
    /// leg when the generalised torques `(tau_h - tau_k, tau_k)` equal
    /// `G = (b2 sin q1, b3 sin q2)`. By hand from Winter's segments
    /// (75 kg, 1.75 m: `m1` 7.5, `L1` 0.42875, `lc1` 0.18564875, `m2` 4.575,
    /// `lc2` 0.260883, g 9.81): `b2 = (m1 lc1 + m2 L1) g` = 32.90172834,
    /// `b3 = m2 lc2 g` = 11.70862470; at `q = (0.3, -0.2)`:
    /// `tau_k = b3 sin q2` = -2.32614463, `tau_h = b2 sin q1 + b3 sin q2`
    /// = 7.39698093 N m, and `f` must vanish. Half the torque must let the
    /// leg fall back towards hanging (`q1_ddot < 0` at `q1 > 0`).
    #[test]
    fn motor_torques_balancing_gravity_give_zero_acceleration() {
        let m = unpowered();
        let (_, b2, b3) = m.constants();
        assert!((b2 - 32.901_728_343_75).abs() < 1e-9);
        assert!((b3 - 11.708_624_702_25).abs() < 1e-9);
        let x = Vector4::new(0.3, -0.2, 0.0, 0.0);
        let u = SVector::<f64, 6>::from_column_slice(&[
            0.0,
            0.0,
            0.0,
            0.0,
            7.396_980_925_533_724,
            -2.326_144_634_126_531,
        ]);
        let f = m.f(&x, &u);
        assert!(f.amax() < 1e-12, "{f}");
        let acc = m.f(&x, &(u * 0.5));
        assert!(acc[2] < 0.0 && acc[3] > 0.0, "{acc}");
    }

    /// The mass matrix of eq 4.18 against the Lagrangian of two rigid
    /// segments: kinetic energy `1/2 m1 |v1|^2 + 1/2 I1 q1_dot^2 +
    /// 1/2 m2 |v2|^2 + 1/2 I2 q2_dot^2` with the centres of mass at
    /// `lc1 (sin q1, -cos q1)` and `L1 (sin q1, -cos q1) + lc2 (sin q2,
    /// -cos q2)` gives `M11 = I1 + m1 lc1^2 + m2 L1^2` = 1.24333577,
    /// `M12 = m2 L1 lc2 cos(q1 - q2)` = 0.44908546 at `q = (0.3, -0.2)`,
    /// `M22 = I2 + m2 lc2^2` = 0.45810597 (`I1 = m1 (0.323 L1)^2`,
    /// `I2 = m2 (0.416 l2)^2`); numpy's polarisation of the kinetic energy
    /// with finite-difference velocities agrees to 1e-11.
    #[test]
    fn mass_matrix_matches_the_lagrangian_entries() {
        let m = unpowered();
        let mm = m.mass_matrix(&Vector4::new(0.3, -0.2, 0.0, 0.0));
        let want = Matrix2::new(
            1.243_335_772_054_687_4,
            0.449_085_462_258_895_95,
            0.449_085_462_258_895_95,
            0.458_105_965_305_974_9,
        );
        assert!((mm - want).amax() < 1e-12, "{mm}");
    }

    /// Conservation of the independently written mechanical energy
    /// (kinetic energy as above, potential `-m1 g lc1 cos q1 - m2 g
    /// (L1 cos q1 + lc2 cos q2)`) along an unpowered swing integrated with a
    /// plain RK4 (0.1 ms, 2 s) from `q = (0.5, -0.3)`, `q_dot = (1, -2)`:
    /// checks `V`'s signs and its consistency with `M` and `G`, which the
    /// statics above cannot see.
    #[test]
    fn unpowered_swing_conserves_mechanical_energy() {
        let m = unpowered();
        let p = m.p;
        let energy = |x: &Vector4<f64>| {
            let (s1, c1, s2, c2) = (
                libm::sin(x[0]),
                libm::cos(x[0]),
                libm::sin(x[1]),
                libm::cos(x[1]),
            );
            let v1 = Vector2::new(c1, s1) * (p.thigh_com * x[2]);
            let v2 = Vector2::new(c1, s1) * (p.thigh_length * x[2])
                + Vector2::new(c2, s2) * (p.leg_com * x[3]);
            let kinetic = 0.5 * p.thigh_mass * v1.norm_squared()
                + 0.5 * p.thigh_inertia * x[2] * x[2]
                + 0.5 * p.leg_mass * v2.norm_squared()
                + 0.5 * p.leg_inertia * x[3] * x[3];
            let potential = -p.thigh_mass * p.g * p.thigh_com * c1
                - p.leg_mass * p.g * (p.thigh_length * c1 + p.leg_com * c2);
            kinetic + potential
        };
        let u = SVector::<f64, 6>::zeros();
        let mut x = Vector4::new(0.5, -0.3, 1.0, -2.0);
        let e0 = energy(&x);
        let h = 1e-4;
        let mut swing = 0.0_f64;
        for _ in 0..20_000 {
            let k1 = m.f(&x, &u);
            let k2 = m.f(&(x + k1 * (h / 2.0)), &u);
            let k3 = m.f(&(x + k2 * (h / 2.0)), &u);
            let k4 = m.f(&(x + k3 * h), &u);
            x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            swing = swing.max((x[0] - x[1]).abs());
        }
        assert!(swing > 1.0, "the knee must move: {swing}");
        assert!((energy(&x) - e0).abs() < 1e-8, "{} vs {e0}", energy(&x));
    }
}
