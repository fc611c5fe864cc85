//! The fixed-hip plant (paper 004 section 4.2): thigh and shank IMUs, four
//! stimulation channels and two motor torques.

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Sample, Segment};
use limbfuse_models::FixedHipModel;
use nalgebra::{SVector, Vector4};

use super::continuous::{ContinuousTuning, Linearisation};
use super::filter::{FesFilter, Plant};

/// The fixed-hip model as an estimator plant (trunk upright and fixed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedHipPlant {
    /// The model (eqs 4.18-4.25).
    pub model: FixedHipModel,
}

/// `sdre` / `ekf` on the fixed-hip model.
pub type FixedHipFilter = FesFilter<FixedHipPlant, 4, 4, 6>;

/// Default tuning of the fixed-hip filters: the values the tuning protocol
/// of docs/FES_ESTIMATION.md picks on three pre-trials (seeds 1000-1002)
/// for both `sdre` and `ekf`: `S = diag(1e-6, 1e-6, 1e4, 1e4)`,
/// `Q = diag(1e-4, 1e-4, 1e-3, 1e-3)`: trust the model and the gyros, use
/// the accelerometers only very weakly (their motion acceleration is not
/// in the measurement model).
pub fn fixed_hip_default_tuning(lin: Linearisation) -> ContinuousTuning<4, 4> {
    ContinuousTuning {
        q: Vector4::new(1e-4, 1e-4, 1e-3, 1e-3),
        s: Vector4::new(1e-6, 1e-6, 1e4, 1e4),
        a: match lin {
            Linearisation::Sdc => 1.0,
            Linearisation::Jacobian => 0.0,
        },
        p0: Vector4::new(1e-2, 1e-2, 1e-2, 1e-2),
        max_substep: 2e-3,
        a_states: None,
    }
}

impl FixedHipFilter {
    /// The SDRE estimator with the default tuning.
    pub fn sdre(model: FixedHipModel) -> Self {
        FesFilter::new(
            FixedHipPlant { model },
            Linearisation::Sdc,
            fixed_hip_default_tuning(Linearisation::Sdc),
        )
    }

    /// The extended Kalman-Bucy filter with the default tuning.
    pub fn ekf(model: FixedHipModel) -> Self {
        FesFilter::new(
            FixedHipPlant { model },
            Linearisation::Jacobian,
            fixed_hip_default_tuning(Linearisation::Jacobian),
        )
    }
}

diagnostic_set! {
    /// Diagnostics of the fixed-hip `sdre` / `ekf` ([`FixedHipPlant`]).
    pub enum FixedHipDiag {
        /// Thigh angular rate state `x_3` (rad/s, paper 004 eq 4.18).
        ThighRate = "thigh_rate",
        /// Shank angular rate state `x_4` (rad/s).
        ShankRate = "shank_rate",
        /// `P_11` of the Riccati solution (eq 4.16), thigh angle (rad^2).
        P11 = "p11",
        /// `P_22`, shank angle (rad^2).
        P22 = "p22",
        /// `P_33`, thigh rate ((rad/s)^2).
        P33 = "p33",
        /// `P_44`, shank rate ((rad/s)^2).
        P44 = "p44",
        /// Restarts after a non-finite state.
        Resets = "resets",
        /// Samples whose input was missing and held (cumulative; at most
        /// `MAX_INPUT_HOLD_S` = 0.1 s per gap, docs/FES_ESTIMATION.md).
        HeldInputs = "held_inputs",
    }
}

impl Plant<4, 4, 6> for FixedHipPlant {
    type Model = FixedHipModel;
    type Diag = FixedHipDiag;
    const RATE_DIAG: &'static [FixedHipDiag] = &[FixedHipDiag::ThighRate, FixedHipDiag::ShankRate];
    const COVARIANCE_DIAG: &'static [FixedHipDiag] = &[
        FixedHipDiag::P11,
        FixedHipDiag::P22,
        FixedHipDiag::P33,
        FixedHipDiag::P44,
    ];
    const RESETS_DIAG: FixedHipDiag = FixedHipDiag::Resets;
    const HELD_INPUTS_DIAG: Option<FixedHipDiag> = Some(FixedHipDiag::HeldInputs);

    fn model(&self) -> &FixedHipModel {
        &self.model
    }

    fn model_name(&self) -> &'static str {
        "fixed-hip"
    }

    fn measurement_names(&self) -> [&'static str; 4] {
        HIP_MEASUREMENT_NAMES
    }

    fn input_names(&self) -> [&'static str; 6] {
        HIP_INPUT_NAMES
    }

    fn measurement(&self, s: &Sample) -> [Option<f64>; 4] {
        hip_measurement(s)
    }

    fn input(&self, s: &Sample) -> [Option<f64>; 6] {
        hip_input(s)
    }

    fn initial_state(&self, s: &Sample) -> SVector<f64, 4> {
        hip_initial_state(s)
    }

    fn outputs(&self) -> Outputs {
        HIP_OUTPUTS
    }

    fn fill(&self, x: &SVector<f64, 4>, e: &mut Estimate) {
        hip_fill(x[0], x[1], e);
    }

    fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        describe_hip(&self.model, out)
    }
}

/// The fixed hip's measurement rows of a sample (thigh and shank `gyr_z`,
/// `acc_x`).
/// The fixed-hip filters' measurement channels, in the order of
/// [`hip_measurement`].
pub(crate) const HIP_MEASUREMENT_NAMES: [&str; 4] =
    ["thigh_gyr_z", "shank_gyr_z", "thigh_acc_x", "shank_acc_x"];

/// The fixed-hip filters' input channels, in the order of [`hip_input`].
pub(crate) const HIP_INPUT_NAMES: [&str; 6] = [
    "u_hf",
    "u_he",
    "u_kf",
    "u_ke",
    "tau_hip_motor",
    "tau_knee_motor",
];

pub(crate) fn hip_measurement(s: &Sample) -> [Option<f64>; 4] {
    let th = s.imu(Segment::Thigh);
    let sh = s.imu(Segment::Shank);
    [
        th.gyr_axis(2),
        sh.gyr_axis(2),
        th.acc_axis(0),
        sh.acc_axis(0),
    ]
}

/// The fixed hip's inputs `[u_hf, u_he, u_kf, u_ke, tau_hip, tau_knee]`.
pub(crate) fn hip_input(s: &Sample) -> [Option<f64>; 6] {
    // ModelInputs::stim order is [u_ke, u_kf, u_he, u_hf].
    let st = &s.inputs.stim;
    let m = &s.inputs.motor_torque;
    [st[3], st[2], st[1], st[0], m[0], m[1]]
}

/// Thigh and shank angle and rate from the first sample.
pub(crate) fn hip_initial_state(s: &Sample) -> SVector<f64, 4> {
    let incl = |seg: Segment| {
        let imu = s.imu(seg);
        (
            imu.acc.map(|a| libm::atan2(a.x, a.y)).unwrap_or(0.0),
            imu.gyr_axis(2).unwrap_or(0.0),
        )
    };
    let (t, tr) = incl(Segment::Thigh);
    let (sh, sr) = incl(Segment::Shank);
    Vector4::new(t, sh, tr, sr)
}

/// What the fixed-hip plants fill: thigh, shank, hip, knee.
pub(crate) const HIP_OUTPUTS: Outputs = Outputs {
    segment: [false, true, true, false],
    joint: [true, true, false],
    phase: false,
    speed: false,
    com: false,
    contact: false,
};

/// Writes thigh `q1` and shank `q2` (absolute) and hip `-q1`, knee `q1 - q2`.
pub(crate) fn hip_fill(q1: f64, q2: f64, e: &mut Estimate) {
    e.set_segment(Segment::Thigh, q1);
    e.set_segment(Segment::Shank, q2);
    e.joint[0] = Some(-q1);
    e.joint[1] = Some(q1 - q2);
}

/// The fixed-hip parameters of the estimate header.
pub(crate) fn describe_hip(m: &FixedHipModel, out: &mut dyn fmt::Write) -> fmt::Result {
    let p = &m.p;
    writeln!(out, "trunk: fixed upright (hip = -thigh)")?;
    writeln!(out, "thigh_mass: {}", p.thigh_mass)?;
    writeln!(out, "thigh_length: {}", p.thigh_length)?;
    writeln!(out, "leg_mass: {}", p.leg_mass)?;
    writeln!(out, "g: {}", p.g)?;
    writeln!(out, "muscle_peak_hf_he_kf_ke: {:?}", p.muscle_peak)
}
