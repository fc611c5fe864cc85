//! The leg-extension plant (paper 004 section 4.1): the FES knee model fed by
//! the aligned shank IMU and the `u_ke` stimulation channel.

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Sample, Segment};
use limbfuse_models::KneeFesModel;
use nalgebra::{SVector, Vector1, Vector2};

use super::continuous::{ContinuousTuning, Linearisation};
use super::filter::{FesFilter, Plant};

/// The knee-FES model plus the (fixed) thigh angle of the machine seat.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneePlant {
    /// The model (eqs 4.1-4.7).
    pub model: KneeFesModel,
    /// Absolute thigh angle (rad); the seat holds the thigh horizontal: pi/2.
    pub thigh_angle: f64,
}

impl KneePlant {
    /// A plant with the thigh horizontal.
    pub fn new(model: KneeFesModel) -> Self {
        KneePlant {
            model,
            thigh_angle: core::f64::consts::FRAC_PI_2,
        }
    }
}

/// `sdre` / `ekf` on the leg-extension model.
pub type KneeFesFilter = FesFilter<KneePlant, 2, 2, 1>;

/// Default tuning of the knee filters: the values the tuning protocol of
/// docs/FES_ESTIMATION.md picks on three pre-trials (P1-L, seeds 1000-1002,
/// `limbfuse-studies::fes_study`) for both `sdre` and `ekf`:
/// `S = diag(1e-5, 1e-2)` (gyro, accelerometer), `Q = diag(1e-4, 1e3)`.
/// The large `Q` on the rate row and small `S` make the estimate follow the
/// measurements closely (the muscle model is uncertain: activation
/// dynamics, eq 4.3's simplification).
pub fn knee_default_tuning(lin: Linearisation) -> ContinuousTuning<2, 2> {
    ContinuousTuning {
        q: Vector2::new(1e-4, 1e3),
        s: Vector2::new(1e-5, 1e-2),
        a: match lin {
            Linearisation::Sdc => 1.0,
            Linearisation::Jacobian => 0.0,
        },
        p0: Vector2::new(1e-2, 1e-2),
        max_substep: 1e-2,
        a_states: None,
    }
}

impl KneeFesFilter {
    /// The SDRE estimator (eqs 4.14-4.16, `a = 1`) with the default tuning.
    pub fn sdre(model: KneeFesModel) -> Self {
        FesFilter::new(
            KneePlant::new(model),
            Linearisation::Sdc,
            knee_default_tuning(Linearisation::Sdc),
        )
    }

    /// The extended Kalman-Bucy filter with the default tuning.
    pub fn ekf(model: KneeFesModel) -> Self {
        FesFilter::new(
            KneePlant::new(model),
            Linearisation::Jacobian,
            knee_default_tuning(Linearisation::Jacobian),
        )
    }
}

diagnostic_set! {
    /// Diagnostics of the knee-FES `sdre` / `ekf` ([`KneePlant`]).
    pub enum KneeFesDiag {
        /// Shank angular rate state `x_2` (rad/s, paper 004 eq 4.1).
        ShankRate = "shank_rate",
        /// `P_11` of the Riccati solution (eq 4.16), shank angle (rad^2).
        P11 = "p11",
        /// `P_22`, shank rate ((rad/s)^2).
        P22 = "p22",
        /// Restarts after a non-finite state.
        Resets = "resets",
        /// Samples whose input was missing and held (cumulative; at most
        /// `MAX_INPUT_HOLD_S` = 0.1 s per gap, docs/FES_ESTIMATION.md).
        HeldInputs = "held_inputs",
    }
}

impl Plant<2, 2, 1> for KneePlant {
    type Model = KneeFesModel;
    type Diag = KneeFesDiag;
    const RATE_DIAG: &'static [KneeFesDiag] = &[KneeFesDiag::ShankRate];
    const COVARIANCE_DIAG: &'static [KneeFesDiag] = &[KneeFesDiag::P11, KneeFesDiag::P22];
    const RESETS_DIAG: KneeFesDiag = KneeFesDiag::Resets;
    const HELD_INPUTS_DIAG: Option<KneeFesDiag> = Some(KneeFesDiag::HeldInputs);

    fn model(&self) -> &KneeFesModel {
        &self.model
    }

    fn model_name(&self) -> &'static str {
        "knee-fes"
    }

    fn measurement_names(&self) -> [&'static str; 2] {
        ["shank_gyr_z", "shank_acc_x"]
    }

    fn input_names(&self) -> [&'static str; 1] {
        ["u_ke"]
    }

    fn measurement(&self, s: &Sample) -> [Option<f64>; 2] {
        let imu = s.imu(Segment::Shank);
        [imu.gyr_axis(2), imu.acc_axis(0)]
    }

    fn input(&self, s: &Sample) -> [Option<f64>; 1] {
        [s.inputs.stim[0]]
    }

    fn initial_state(&self, s: &Sample) -> SVector<f64, 2> {
        let imu = s.imu(Segment::Shank);
        let x1 = imu
            .acc
            .map(|a| libm::atan2(a.x, a.y))
            .unwrap_or(self.model.p.theta_eq);
        let x2 = imu.gyr_axis(2).unwrap_or(0.0);
        Vector2::new(x1, x2)
    }

    fn outputs(&self) -> Outputs {
        Outputs {
            segment: [false, true, true, false],
            joint: [false, true, false],
            ..Outputs::default()
        }
    }

    fn fill(&self, x: &SVector<f64, 2>, e: &mut Estimate) {
        e.set_segment(Segment::Thigh, self.thigh_angle);
        e.set_segment(Segment::Shank, x[0]);
        e.joint[1] = Some(self.thigh_angle - x[0]);
    }

    fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        describe_knee_params(&self.model.p, self.thigh_angle, out)?;
        writeln!(out, "activation: a_ke = u_ke (thesis section 4.1.1)")
    }
}

/// Writes the seat's thigh angle and the knee model's parameters as
/// `key: value` lines (shared by the thesis and the extended knee plants).
pub fn describe_knee_params(
    p: &limbfuse_models::KneeFesParams,
    thigh_angle: f64,
    out: &mut dyn fmt::Write,
) -> fmt::Result {
    writeln!(out, "thigh_angle_rad: {thigh_angle}")?;
    writeln!(out, "inertia: {}", p.inertia)?;
    writeln!(out, "mass: {}", p.mass)?;
    writeln!(out, "l_c: {}", p.l_c)?;
    writeln!(out, "g: {}", p.g)?;
    writeln!(out, "phi0: {}", p.phi0)?;
    writeln!(out, "d: {:?}", p.d)?;
    writeln!(out, "c: {:?}", p.c)
}

/// Input vector of the knee model.
pub fn knee_input(u_ke: f64) -> SVector<f64, 1> {
    Vector1::new(u_ke)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fes::filter::Plant;

    /// The knee filters measure the shank's gyro z and accelerometer x only
    /// (paper 004); a sample whose vectors are incomplete but hold those
    /// two axes was no measurement (found 2026-12-06: the shared P2-R trial
    /// with 5 % of its IMU cells empty, `sdre` 0.085-0.099 deg over three
    /// masks, now 0.076-0.078; 0.080 clean).
    #[test]
    fn an_incomplete_vector_still_gives_its_measured_axes() {
        let params = limbfuse_models::KneeFesParams::subject(limbfuse_models::KneeSubject::P2R);
        let plant = KneePlant::new(KneeFesModel::new(params).unwrap());
        let mut s = Sample::empty(0.0);
        let shank = Segment::Shank.index();
        s.imu[shank].gyr_partial = [None, Some(0.1), Some(0.3)];
        s.imu[shank].acc_partial = [Some(1.5), None, Some(9.0)];
        assert_eq!(plant.measurement(&s), [Some(0.3), Some(1.5)]);
        // and not the axes it does not measure
        s.imu[shank].gyr_partial = [Some(0.1), Some(0.2), None];
        s.imu[shank].acc_partial = [None, Some(9.7), Some(0.2)];
        assert_eq!(plant.measurement(&s), [None, None]);
    }
}
