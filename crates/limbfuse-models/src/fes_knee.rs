//! Single-joint leg-extension model driven by FES of the quadriceps
//! (paper 004 section 4.1.1, eqs 4.1-4.7).
//!
//! The subject sits with the thigh horizontal; the lower leg (shank + foot)
//! swings about the knee. State `x = [x1, x2] = [theta + theta_eq, theta_dot]`:
//! `x1` is the lower leg's angle from hanging vertically, positive when the
//! foot moves forward/up, which is exactly the SPEC absolute shank angle when
//! the thigh is horizontal. The anatomical knee angle is
//! `phi = pi/2 - x1` (flexion positive, 0 = straight), `phi_dot = -x2`.
//!
//! * eq 4.1: `J theta_ddot + m g l_c sin(x1) = T_p + T_ke`
//! * eq 4.2: `T_p = d1 (phi - phi0) + d2 phi_dot + d3 e^(d4 phi) - d5 e^(d6 phi)`
//! * eq 4.3: `T_ke = (c2 phi^2 + c1 phi + c0)(1 + c3 phi_dot) a_ke`, `a_ke = u_ke`
//! * eq 4.4: stimulation current `I = I_t + u_ke (I_s - I_t)`
//! * eq 4.6: `f(x, u) = [x2, -beta sin(x1) + alpha (T_p + T_ke)]`, `alpha = 1/J`,
//!   `beta = m g l_c / J`
//! * eq 4.7: measurements `[gyro_z, acc_x]` of the aligned shank IMU. In the
//!   SPEC sensor frame a static segment at angle `x1` reads
//!   `acc_x = g sin(x1)`, so `h(x) = [x2, g sin(x1)]`; the thesis prints
//!   `-g sin(x1)` because its IMU x axis points backwards. Measurement order:
//!   `y = [shank gyr_z, shank acc_x]`.
//!
//! SDC factorisation (eqs 4.11-4.13): `A = [[0, 1], [-beta sinc(x1), 0]]`,
//! `B(x) u = [0, alpha (T_p + T_ke)]`, `C = [[0, 1], [g sinc(x1), 0]]`.
//!
//! Table 1 of the thesis gives the muscle and passive parameters of six legs
//! (P1-L ... P3-R) but not the lower leg's mass, inertia or centre of mass;
//! those come from D. A. Winter, *Biomechanics and Motor Control of Human
//! Movement*, 4th ed., Wiley 2009, Table 4.1, segment "foot and leg"
//! (femoral condyles to medial malleolus, length 0.246 H): mass 0.061 M,
//! centre of mass 0.606 L from the knee, radius of gyration about the knee
//! 0.735 L, for a 75 kg, 1.75 m subject (the thesis does not report body
//! size). The machine's lever arm is neglected.

use nalgebra::{SMatrix, SVector, Vector2};

use crate::default_body::{DEFAULT_BODY_HEIGHT_M, DEFAULT_BODY_MASS_KG};
use crate::error::{finite, limits, positive, within_limit, ModelError};
use crate::sdc::{sinc, SdcModel};

/// Parameters of one leg in the leg-extension machine (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeFesParams {
    /// Lower-leg moment of inertia about the knee `J` (kg m^2).
    pub inertia: f64,
    /// Lower-leg mass `m` (kg).
    pub mass: f64,
    /// Knee to lower-leg centre of mass `l_c` (m).
    pub l_c: f64,
    /// Gravity (m/s^2).
    pub g: f64,
    /// Passive torque rest angle `phi0` (rad).
    pub phi0: f64,
    /// Passive torque coefficients `d1 ... d6` (eq 4.2).
    pub d: [f64; 6],
    /// Force-length / force-velocity coefficients `c0 ... c3` (eq 4.3).
    pub c: [f64; 4],
    /// Equilibrium angle from vertical `theta_eq` (rad).
    pub theta_eq: f64,
    /// Muscle activation time constant `T_a` (s), Table 1 (the estimators
    /// follow the thesis and take `a_ke = u_ke`; the simulator may use it).
    pub t_a: f64,
    /// Threshold current `I_t` (mA).
    pub i_threshold_ma: f64,
    /// Saturation current `I_s` (mA).
    pub i_saturation_ma: f64,
}

/// The six legs of Table 1 (paper 004), in the order of Table 2.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KneeSubject {
    /// Participant 1, left leg.
    P1L,
    /// Participant 1, right leg.
    P1R,
    /// Participant 2, left leg.
    P2L,
    /// Participant 2, right leg.
    P2R,
    /// Participant 3, left leg.
    P3L,
    /// Participant 3, right leg.
    P3R,
}

impl KneeSubject {
    /// All six legs in Table 2 order.
    pub const ALL: [KneeSubject; 6] = [
        KneeSubject::P1L,
        KneeSubject::P1R,
        KneeSubject::P2L,
        KneeSubject::P2R,
        KneeSubject::P3L,
        KneeSubject::P3R,
    ];

    /// Label as in the thesis (`P1-L` ...).
    pub const fn label(self) -> &'static str {
        match self {
            KneeSubject::P1L => "P1-L",
            KneeSubject::P1R => "P1-R",
            KneeSubject::P2L => "P2-L",
            KneeSubject::P2R => "P2-R",
            KneeSubject::P3L => "P3-L",
            KneeSubject::P3R => "P3-R",
        }
    }

    /// Parses `P1-L`, `p1l`, or `1` ... `6` (Table 2 order).
    pub fn parse(s: &str) -> Option<Self> {
        KneeSubject::ALL.iter().enumerate().find_map(|(i, k)| {
            let lab = k.label().as_bytes();
            let compact = [lab[0], lab[1], lab[3]];
            let ok = s.as_bytes().eq_ignore_ascii_case(lab)
                || s.as_bytes().eq_ignore_ascii_case(&compact)
                || s.as_bytes() == [b'1' + i as u8];
            ok.then_some(*k)
        })
    }

    /// Index in [`KneeSubject::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Table 1 of paper 004, one array per row, columns P1-L, P1-R, P2-L, P2-R, P3-L, P3-R.
#[allow(clippy::approx_constant)] // 3.14 is a measured damping (Table 1), not pi
mod table1 {
    pub const PHI0: [f64; 6] = [0.40, 8.34e-11, 0.78, 2.22e-14, 0.30, 1.50];
    pub const D1: [f64; 6] = [4.05, 2.27, 5.86, 4.12, 2.22e-14, 4.41];
    pub const D2: [f64; 6] = [3.05, 3.30, 3.56, 2.54, 2.54, 3.14];
    pub const D3: [f64; 6] = [1.48e-9, 3.96e-8, 1.54e-5, 2.38e-5, 6.1984, 3.39e-4];
    pub const D4: [f64; 6] = [14.10, 11.20, 8.70, 8.33, 0.84, 6.70];
    pub const D5: [f64; 6] = [8.90, 15.30, 3.05, 5.41, 0.04, 0.16];
    pub const D6: [f64; 6] = [-1.76, -1.77, -3.45, -3.45, -0.41, -1.26e-8];
    pub const C0: [f64; 6] = [76.71, 61.00, 27.74, -28.29, -17.88, 5.63];
    pub const C1: [f64; 6] = [3.12, -0.57, 296.32, 402.07, 299.41, 159.39];
    pub const C2: [f64; 6] = [-15.36, -8.47, -186.11, -231.19, -183.75, -85.94];
    pub const C3: [f64; 6] = [0.28, 0.47, 1.93e-4, 0.88, 1.52, 1.75];
    pub const THETA_EQ: [f64; 6] = [0.13, 0.08, 0.19, 0.17, 0.17, 0.14];
    pub const TA: [f64; 6] = [0.25, 0.19, 0.14, 1.0, 0.72, 0.18];
    pub const IT: [f64; 6] = [33.90, 38.60, 33.50, 38.80, 38.20, 32.90];
    pub const IS: [f64; 6] = [60.40, 68.20, 66.60, 64.90, 68.10, 63.20];
}

impl KneeFesParams {
    /// Table 1 values of one leg with Winter's lower-leg anthropometry.
    pub fn subject(s: KneeSubject) -> Self {
        use table1::*;
        let i = s.index();
        let (mass, inertia, l_c) =
            lower_leg_anthropometry(DEFAULT_BODY_MASS_KG, DEFAULT_BODY_HEIGHT_M);
        KneeFesParams {
            inertia,
            mass,
            l_c,
            g: 9.81,
            phi0: PHI0[i],
            d: [D1[i], D2[i], D3[i], D4[i], D5[i], D6[i]],
            c: [C0[i], C1[i], C2[i], C3[i]],
            theta_eq: THETA_EQ[i],
            t_a: TA[i],
            i_threshold_ma: IT[i],
            i_saturation_ma: IS[i],
        }
    }

    /// Rejects parameters that make the model unphysical: non-finite values,
    /// non-positive inertia, mass, `l_c` or `g`, a non-positive activation
    /// time constant, or a saturation current not above the threshold.
    pub fn validate(&self) -> Result<(), ModelError> {
        positive("inertia", self.inertia)?;
        positive("mass", self.mass)?;
        positive("l_c", self.l_c)?;
        positive("g", self.g)?;
        within_limit("inertia", self.inertia, limits::INERTIA)?;
        within_limit("mass", self.mass, limits::MASS)?;
        within_limit("l_c", self.l_c, limits::LENGTH)?;
        within_limit("g", self.g, limits::G)?;
        positive("t_a", self.t_a)?;
        within_limit("phi0", self.phi0, limits::ANGLE)?;
        within_limit("theta_eq", self.theta_eq, limits::ANGLE)?;
        const D: [&str; 6] = ["d1", "d2", "d3", "d4", "d5", "d6"];
        for (n, v) in D.iter().zip(self.d) {
            finite(n, v)?;
        }
        const C: [&str; 4] = ["c0", "c1", "c2", "c3"];
        for (n, v) in C.iter().zip(self.c) {
            finite(n, v)?;
        }
        if self.d[1] < 0.0 {
            return Err(ModelError::OutOfRange {
                name: "d2",
                value: self.d[1],
                range: "[0, inf) (negative damping adds energy)",
            });
        }
        positive("i_threshold_ma", self.i_threshold_ma)?;
        finite("i_saturation_ma", self.i_saturation_ma)?;
        if self.i_saturation_ma <= self.i_threshold_ma {
            return Err(ModelError::OutOfRange {
                name: "i_saturation_ma",
                value: self.i_saturation_ma,
                range: "(i_threshold_ma, inf)",
            });
        }
        Ok(())
    }
}

/// Mass (kg), inertia about the knee (kg m^2) and knee-to-COM distance (m) of
/// the lower leg (shank + foot) from Winter's Table 4.1 (see module docs).
pub fn lower_leg_anthropometry(body_mass: f64, height: f64) -> (f64, f64, f64) {
    let len = 0.246 * height;
    let m = 0.061 * body_mass;
    let rg = 0.735 * len;
    (m, m * rg * rg, 0.606 * len)
}

/// The model with derived constants `alpha = 1/J`, `beta = m g l_c / J`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeFesModel {
    /// The parameters.
    pub p: KneeFesParams,
    alpha: f64,
    beta: f64,
}

impl KneeFesModel {
    /// Validates the parameters and builds the model.
    pub fn new(p: KneeFesParams) -> Result<Self, ModelError> {
        p.validate()?;
        Ok(KneeFesModel {
            p,
            alpha: 1.0 / p.inertia,
            beta: p.mass * p.g * p.l_c / p.inertia,
        })
    }

    /// `alpha = 1 / J`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// `beta = m g l_c / J`.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Anatomical knee angle `phi = pi/2 - x1` (rad).
    pub fn phi(x1: f64) -> f64 {
        core::f64::consts::FRAC_PI_2 - x1
    }

    /// Passive torque `T_p` (eq 4.2) and its derivatives `(dT/dphi, dT/dphi_dot)`.
    pub fn passive_torque(&self, phi: f64, phi_dot: f64) -> (f64, f64, f64) {
        let d = &self.p.d;
        let e4 = libm::exp(d[3] * phi);
        let e6 = libm::exp(d[5] * phi);
        let t = d[0] * (phi - self.p.phi0) + d[1] * phi_dot + d[2] * e4 - d[4] * e6;
        let dphi = d[0] + d[2] * d[3] * e4 - d[4] * d[5] * e6;
        (t, dphi, d[1])
    }

    /// Force-length polynomial `c2 phi^2 + c1 phi + c0` (eq 4.3).
    pub fn force_length(&self, phi: f64) -> f64 {
        let c = &self.p.c;
        (c[2] * phi + c[1]) * phi + c[0]
    }

    /// FES torque `T_ke` (eq 4.3, `a_ke = activation`) and its derivatives
    /// `(dT/dphi, dT/dphi_dot)`.
    pub fn fes_torque(&self, phi: f64, phi_dot: f64, activation: f64) -> (f64, f64, f64) {
        let c = &self.p.c;
        let fl = self.force_length(phi);
        let fv = 1.0 + c[3] * phi_dot;
        (
            fl * fv * activation,
            (2.0 * c[2] * phi + c[1]) * fv * activation,
            fl * c[3] * activation,
        )
    }

    /// Stimulation current (mA) for normalised stimulation `u` (eq 4.4).
    pub fn current_ma(&self, u: f64) -> f64 {
        self.p.i_threshold_ma + u * (self.p.i_saturation_ma - self.p.i_threshold_ma)
    }

    /// Net joint torque `T_p + T_ke` at state `x` with activation `a`.
    pub fn joint_torque(&self, x: &Vector2<f64>, a: f64) -> f64 {
        let phi = Self::phi(x[0]);
        self.passive_torque(phi, -x[1]).0 + self.fes_torque(phi, -x[1], a).0
    }

    /// Gravity torque `m g l_c sin(x1)` (N m).
    pub fn gravity_torque(&self, x1: f64) -> f64 {
        self.p.mass * self.p.g * self.p.l_c * libm::sin(x1)
    }

    /// Static activation that holds the leg at `x1` (rad), if one in [0, 1] exists.
    pub fn holding_activation(&self, x1: f64) -> Option<f64> {
        let phi = Self::phi(x1);
        let need = self.gravity_torque(x1) - self.passive_torque(phi, 0.0).0;
        let fl = self.force_length(phi);
        if fl.abs() < 1e-9 {
            return None;
        }
        let a = need / fl;
        (0.0..=1.0).contains(&a).then_some(a)
    }

    /// Passive equilibrium angle `x1` with no stimulation (Newton from `theta_eq`).
    pub fn passive_equilibrium(&self) -> f64 {
        let mut x1 = self.p.theta_eq;
        for _ in 0..50 {
            let phi = Self::phi(x1);
            let (tp, dtp, _) = self.passive_torque(phi, 0.0);
            let r = tp - self.gravity_torque(x1);
            let dr = -dtp - self.p.mass * self.p.g * self.p.l_c * libm::cos(x1);
            if dr.abs() < 1e-12 {
                break;
            }
            let step = (r / dr).clamp(-0.2, 0.2);
            x1 -= step;
            if step.abs() < 1e-13 {
                break;
            }
        }
        x1
    }
}

impl SdcModel<2, 2, 1> for KneeFesModel {
    fn f(&self, x: &SVector<f64, 2>, u: &SVector<f64, 1>) -> SVector<f64, 2> {
        Vector2::new(
            x[1],
            -self.beta * libm::sin(x[0]) + self.alpha * self.joint_torque(x, u[0]),
        )
    }

    fn h(&self, x: &SVector<f64, 2>) -> SVector<f64, 2> {
        Vector2::new(x[1], self.p.g * libm::sin(x[0]))
    }

    fn sdc_a(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, -self.beta * sinc(x[0]), 0.0)
    }

    fn input_term(&self, x: &SVector<f64, 2>, u: &SVector<f64, 1>) -> SVector<f64, 2> {
        Vector2::new(0.0, self.alpha * self.joint_torque(x, u[0]))
    }

    fn sdc_c(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, self.p.g * sinc(x[0]), 0.0)
    }

    fn jacobian_f(&self, x: &SVector<f64, 2>, u: &SVector<f64, 1>) -> SMatrix<f64, 2, 2> {
        let phi = Self::phi(x[0]);
        let (_, p_phi, p_rate) = self.passive_torque(phi, -x[1]);
        let (_, f_phi, f_rate) = self.fes_torque(phi, -x[1], u[0]);
        // d phi / d x1 = -1, d phi_dot / d x2 = -1.
        SMatrix::<f64, 2, 2>::new(
            0.0,
            1.0,
            -self.beta * libm::cos(x[0]) - self.alpha * (p_phi + f_phi),
            -self.alpha * (p_rate + f_rate),
        )
    }

    fn jacobian_h(&self, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, self.p.g * libm::cos(x[0]), 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Paper 004 eqs 4.1-4.3 and 4.6 evaluated by hand (numpy, from the
    /// printed equations, not this code): P1-L of Table 1 (`phi0` 0.40,
    /// `d` = 4.05, 3.05, 1.48e-9, 14.10, 8.90, -1.76, `c` = 76.71, 3.12,
    /// -15.36, 0.28) with Winter's lower leg for 75 kg, 1.75 m
    /// (`J` = 0.458049, `m` = 4.575, `l_c` = 0.260883, g = 9.81), at
    /// `x = (0.5, 0.2)`, `u = 0.3`: `phi = pi/2 - x1` = 1.070796,
    /// `phi_dot = -x2`; `T_p` = 0.760245, `T_ke` = 17.682735,
    /// `G = m g l_c sin x1` = 5.613414 N m, so
    /// `x2_dot = (T_p + T_ke - G) / J` = 28.009148 rad/s^2.
    /// Second point, P3-L (large `d3`, negative `c0`), `x = (-0.2, -0.5)`,
    /// `u = 0.8`: `T_p` = 28.684016, `T_ke` = -89.935090, `G` = -2.326145,
    /// `x2_dot` = -128.643246.
    #[test]
    fn f_matches_hand_evaluation_of_eqs_4_1_to_4_6() {
        let p = KneeFesParams::subject(KneeSubject::P1L);
        assert!((p.inertia - 0.458_049_156_951).abs() < 1e-9);
        assert_eq!((p.mass, p.l_c), (4.575, 0.260_883));
        let m = KneeFesModel::new(p).unwrap();
        let f = m.f(&Vector2::new(0.5, 0.2), &SVector::<f64, 1>::new(0.3));
        assert_eq!(f[0], 0.2);
        assert!((f[1] - 28.009_147_791_254_85).abs() < 1e-9, "{}", f[1]);

        let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P3L)).unwrap();
        let f = m.f(&Vector2::new(-0.2, -0.5), &SVector::<f64, 1>::new(0.8));
        assert_eq!(f[0], -0.5);
        assert!((f[1] + 128.643_245_555_301_66).abs() < 1e-8, "{}", f[1]);
    }

    /// Physics check of eq 4.6's sign conventions: with the passive torque
    /// and stimulation off (`d = 0`, `u = 0`) the leg is a compound
    /// pendulum, whose small oscillations about hanging (`x1 = 0`) have
    /// period `T = 2 pi sqrt(J / (m g l_c))` (1.242748 s for Winter's lower
    /// leg). Integrated here by a plain RK4 (1 ms) from `x1 = 1e-3` rad;
    /// the period is the time between the first and third downward zero
    /// crossings (linear interpolation). A wrong gravity sign would diverge,
    /// a wrong `beta` would change `T`.
    #[test]
    fn small_oscillations_have_the_compound_pendulum_period() {
        let mut p = KneeFesParams::subject(KneeSubject::P1L);
        p.d = [0.0; 6];
        let model = KneeFesModel::new(p).unwrap();
        let u = SVector::<f64, 1>::zeros();
        let want = 2.0 * core::f64::consts::PI * libm::sqrt(p.inertia / (p.mass * p.g * p.l_c));
        assert!((want - 1.242_747_704_342).abs() < 1e-9);
        let h = 1e-3;
        let mut x = Vector2::new(1e-3, 0.0);
        let mut t = 0.0;
        let mut crossings = [0.0; 3];
        let mut n = 0;
        while n < 3 && t < 10.0 {
            let k1 = model.f(&x, &u);
            let k2 = model.f(&(x + k1 * (h / 2.0)), &u);
            let k3 = model.f(&(x + k2 * (h / 2.0)), &u);
            let k4 = model.f(&(x + k3 * h), &u);
            let next = x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
            assert!(next[0].abs() <= 1.0001e-3, "not a stable equilibrium");
            if x[0] > 0.0 && next[0] <= 0.0 {
                crossings[n] = t + h * x[0] / (x[0] - next[0]);
                n += 1;
            }
            x = next;
            t += h;
        }
        assert_eq!(n, 3);
        let period = (crossings[2] - crossings[0]) / 2.0;
        assert!((period - want).abs() < 1e-6 * want, "{period} vs {want}");
    }
}
