//! Plants beyond the thesis (issue 16): the extended knee model (activation,
//! unknown torque, sensor biases, accelerometer lever arm) for `sdre` /
//! `ekf`, and the model-free kinematic shank model of `knee-kinematic`.
//! Derivations and the defaults' physics: docs/FES_ESTIMATION.md.

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Sample, Segment};
use limbfuse_models::{ExtendedKneeModel, KinematicKneeModel, KneeStateLayout};
use nalgebra::SVector;

use super::continuous::{ContinuousTuning, FilterState, Linearisation};
use super::filter::{FesFilter, Plant};
use super::knee::{describe_knee_params, knee_default_tuning};

diagnostic_set! {
    /// Diagnostics of the extended knee `sdre` / `ekf`
    /// ([`ExtendedKneePlant`]); a state that is not enabled is empty.
    pub enum ExtendedKneeDiag {
        /// Shank angular rate `x_2` (rad/s).
        ShankRate = "shank_rate",
        /// Activation state `a_ke`.
        Activation = "activation",
        /// Unknown knee torque `d` (N m).
        Disturbance = "torque_disturbance",
        /// Shank gyro z bias (rad/s).
        GyroBias = "gyro_bias",
        /// Shank accelerometer x bias (m/s^2).
        AccBias = "acc_bias",
        /// `P_11`, shank angle (rad^2).
        P11 = "p11",
        /// `P_22`, shank rate ((rad/s)^2).
        P22 = "p22",
        /// `P` of the activation.
        PActivation = "p_activation",
        /// `P` of the unknown torque ((N m)^2).
        PDisturbance = "p_torque_disturbance",
        /// `P` of the gyro bias.
        PGyroBias = "p_gyro_bias",
        /// `P` of the accelerometer bias.
        PAccBias = "p_acc_bias",
        /// Restarts after a non-finite state.
        Resets = "resets",
        /// Samples whose input was missing and held (cumulative; at most
        /// `MAX_INPUT_HOLD_S` = 0.1 s per gap, docs/FES_ESTIMATION.md).
        HeldInputs = "held_inputs",
        /// The model's share of the update of the shank rate at the sample
        /// time, `|f_2| / (|f_2| + |(K (y - h))_2|)` with `f_2` the model's
        /// angular acceleration and `(K (y - h))_2` the measurement
        /// correction of eq 4.14: 1 = the rate moves as the model predicts,
        /// 0 = the measurements alone move it (empty when both are 0).
        ModelShare = "model_share",
        /// The model's weight in the shank rate over one sample,
        /// `exp(-(K C)_22 dt)`: the fraction of the model's rate prediction
        /// that survives one sample interval `dt` of measurement updates
        /// (1 = the model's prediction stands, 0 = the gyro replaces it;
        /// `1 / (K C)_22` is the time constant with which the measurements
        /// pull the rate). The thesis default tuning gives about `e^-100`.
        ModelWeight = "model_weight",
    }
}

/// The extended knee model plus the seat's thigh angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtendedKneePlant<const N: usize> {
    /// The model.
    pub model: ExtendedKneeModel<N>,
    /// Absolute thigh angle (rad); the seat holds the thigh horizontal: pi/2.
    pub thigh_angle: f64,
    /// Where the lever arm `model.imu_radius` came from (written to the
    /// estimate's header as `shank_imu_m_source` when not empty).
    pub imu_radius_source: &'static str,
}

/// `sdre` / `ekf` on the extended knee model with `N` states.
pub type ExtendedKneeFilter<const N: usize> = FesFilter<ExtendedKneePlant<N>, N, 2, 1>;

/// Tuning defaults of the extended knee and kinematic filters, each from a
/// stated physical error (docs/FES_ESTIMATION.md, "Defaults from physics").
/// Sensor figures: the consumer-MEMS budget of docs/SIMULATOR.md (Bosch
/// BMI270 / TDK ICM-42688-P data sheets).
pub mod extended_defaults {
    /// Relative error of the identified muscle and passive torques the
    /// filter is sized for (issue 16: identified parameters are off by
    /// 10-30 %; the lower end, the higher ones are the stress test).
    pub const TORQUE_ERROR: f64 = 0.1;
    /// Time over which a persistent torque error builds up (s): the 1.5 s
    /// ramps of a stimulation pulse, rounded to 1 s.
    pub const TORQUE_ERROR_TIME_S: f64 = 1.0;
    /// Correlation time of the torque error left as white noise on the rate
    /// row (s): one 100 Hz sample.
    pub const WHITE_TORQUE_TIME_S: f64 = 0.01;
    /// Gyro turn-on bias, 1 sigma (rad/s): 0.5 deg/s.
    pub const GYRO_BIAS_SIGMA: f64 = 0.5 * core::f64::consts::PI / 180.0;
    /// Accelerometer turn-on bias, 1 sigma (m/s^2): 20 mg.
    pub const ACC_BIAS_SIGMA: f64 = 0.02 * 9.81;
    /// Bias instability as a random-walk intensity, gyro ((rad/s)^2/s): the
    /// bias may wander by `sqrt(q t)` = 1e-3 rad/s in 100 s (the budget's
    /// 0.03 deg/s in-run drift is 5e-4 rad/s).
    pub const GYRO_BIAS_Q: f64 = 1e-8;
    /// Accelerometer bias random walk ((m/s^2)^2/s): 1e-2 m/s^2 (1 mg) in 100 s.
    pub const ACC_BIAS_Q: f64 = 1e-6;
    /// Activation process noise (1/s): recruitment varies by about 1 % of
    /// full activation per second.
    pub const ACTIVATION_Q: f64 = 1e-4;
    /// Gyro measurement intensity `S_g` ((rad/s)^2 s): the budget's
    /// scale-factor and cross-axis errors (about 1 % of a 1 rad/s rate, 0.01
    /// rad/s) taken as white over one 10 ms sample: `0.01^2 * 0.01`. (The
    /// white noise alone, 0.007 deg/s/sqrt(Hz), is 1.5e-8.)
    pub const S_GYRO: f64 = 1e-6;
    /// Accelerometer measurement intensity `S_a` ((m/s^2)^2 s): 1 deg of
    /// mounting misalignment (0.17 m/s^2 of g) plus 1 % cross-axis (0.1
    /// m/s^2), about 0.3 m/s^2, white over one 10 ms sample: `0.3^2 * 0.01`.
    pub const S_ACC: f64 = 1e-3;
}

/// The prescribed-stability shift of each state of the extended knee model
/// ([`ContinuousTuning::a_states`], ours). With the leg at rest (`u_ke = 0`,
/// `x2 = 0`) the torque balance and the accelerometer are two equations for
/// the angle, the activation, the unknown torque `d` and the accelerometer
/// bias. A shift `a` on a mode that is unobservable and decays slower than
/// `a` makes `(A + a I, C)` undetectable, and its `P` grows as
/// `e^{2 (a - rate) t}` (issue 16: `sdre` with these states diverged, `P`
/// of `d` 1.4 -> 170 N^2 m^2 in the first 3 s of rest). Hence:
/// * `a` on `x1, x2` and the gyro bias (observable at rest);
/// * on the activation, which decays on its own at `1 / T_a`, at most half
///   that rate: `min(a, 1 / (2 T_a))`;
/// * on the accelerometer bias `a` when there is no `d` (the torque balance
///   then fixes the angle, the accelerometer the bias);
/// * with `d`: 0 on `d`, `x1` and the accelerometer bias (the torque balance
///   only fixes `d`, and angle and bias share one measurement).
pub fn extended_shift<const N: usize>(model: &ExtendedKneeModel<N>, a: f64) -> SVector<f64, N> {
    let mut l = SVector::<f64, N>::repeat(a);
    if let Some(i) = model.layout.activation {
        l[i] = a.min(0.5 / model.base.p.t_a);
    }
    if let Some(i) = model.layout.disturbance {
        l[i] = 0.0;
        l[0] = 0.0;
        if let Some(b) = model.layout.acc_bias {
            l[b] = 0.0;
        }
    }
    l
}

/// Default tuning of the extended knee filter, every entry from a stated
/// physical error ([`extended_defaults`]; `e` =
/// [`extended_defaults::TORQUE_ERROR`], `T_g = m g l_c` the largest gravity
/// torque the muscle has to hold, `alpha = 1/J`):
/// * `q_1 = 1e-8`: `x1' = x2` is exact (a floor keeps `P` positive);
/// * `q_2 = (alpha e T_g)^2 t_w`: the torque error as white noise over one
///   sample `t_w`;
/// * unknown torque `q_d = (e T_g)^2 / t_e`, `p0_d = (e T_g)^2`: a random
///   walk reaching that torque error within one pulse ramp `t_e`;
/// * activation and sensor biases: the constants of [`extended_defaults`];
/// * `S` from the sensor error budget, `a` as the thesis filters (1 for
///   `sdre`, 0 for `ekf`), per state as [`extended_shift`] says.
pub fn extended_knee_default_tuning<const N: usize>(
    model: &ExtendedKneeModel<N>,
    lin: Linearisation,
) -> ContinuousTuning<N, 2> {
    extended_knee_tuning(model, lin, extended_defaults::TORQUE_ERROR)
}

/// [`extended_knee_default_tuning`] for a relative torque error `e` other
/// than the default's: `q_2`, `q_d` and `p0_d` scale with `e^2`, the rest
/// stays. `e` is the one knob "how much I trust my model": the filter
/// admits a torque error of `e m g l_c` (docs/FES_ESTIMATION.md).
pub fn extended_knee_tuning<const N: usize>(
    model: &ExtendedKneeModel<N>,
    lin: Linearisation,
    torque_error: f64,
) -> ContinuousTuning<N, 2> {
    use extended_defaults::*;
    let base = knee_default_tuning(lin);
    let p = &model.base.p;
    let torque = torque_error * p.mass * p.g * p.l_c;
    let rate = torque / p.inertia;
    let mut q = SVector::<f64, N>::zeros();
    let mut p0 = SVector::<f64, N>::zeros();
    q[0] = 1e-8;
    q[1] = rate * rate * WHITE_TORQUE_TIME_S;
    p0[0] = base.p0[0];
    p0[1] = base.p0[1];
    let l = &model.layout;
    let mut set = |i: Option<usize>, qi: f64, pi: f64| {
        if let Some(i) = i {
            q[i] = qi;
            p0[i] = pi;
        }
    };
    set(l.activation, ACTIVATION_Q, 1e-4);
    set(
        l.disturbance,
        torque * torque / TORQUE_ERROR_TIME_S,
        torque * torque,
    );
    set(l.gyro_bias, GYRO_BIAS_Q, GYRO_BIAS_SIGMA * GYRO_BIAS_SIGMA);
    set(l.acc_bias, ACC_BIAS_Q, ACC_BIAS_SIGMA * ACC_BIAS_SIGMA);
    let shift = extended_shift(model, base.a);
    ContinuousTuning {
        q,
        s: SVector::<f64, 2>::new(S_GYRO, S_ACC),
        a: base.a,
        p0,
        max_substep: base.max_substep,
        a_states: Some(shift),
    }
}

/// The stimulation at the first sample (0 when missing).
fn start_stimulation(s: &Sample) -> f64 {
    s.inputs.stim[0]
        .filter(|u| u.is_finite())
        .unwrap_or(0.0)
        .max(0.0)
}

fn shank_start(s: &Sample, fallback: f64) -> (f64, f64) {
    let imu = s.imu(Segment::Shank);
    let x1 = imu.acc.map(|a| libm::atan2(a.x, a.y)).unwrap_or(fallback);
    (x1, imu.gyr_axis(2).unwrap_or(0.0))
}

fn shank_measurement(s: &Sample) -> [Option<f64>; 2] {
    let imu = s.imu(Segment::Shank);
    [imu.gyr_axis(2), imu.acc_axis(0)]
}

const KNEE_OUTPUTS: Outputs = Outputs {
    segment: [false, true, true, false],
    joint: [false, true, false],
    phase: false,
    speed: false,
    com: false,
    contact: false,
};

fn fill_knee(thigh: f64, shank: f64, e: &mut Estimate) {
    e.set_segment(Segment::Thigh, thigh);
    e.set_segment(Segment::Shank, shank);
    e.joint[1] = Some(thigh - shank);
}

impl<const N: usize> Plant<N, 2, 1> for ExtendedKneePlant<N> {
    type Model = ExtendedKneeModel<N>;
    type Diag = ExtendedKneeDiag;
    const RATE_DIAG: &'static [ExtendedKneeDiag] = &[];
    const COVARIANCE_DIAG: &'static [ExtendedKneeDiag] = &[];
    const RESETS_DIAG: ExtendedKneeDiag = ExtendedKneeDiag::Resets;
    const HELD_INPUTS_DIAG: Option<ExtendedKneeDiag> = Some(ExtendedKneeDiag::HeldInputs);

    fn model(&self) -> &ExtendedKneeModel<N> {
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
        shank_measurement(s)
    }

    fn input(&self, s: &Sample) -> [Option<f64>; 1] {
        [s.inputs.stim[0]]
    }

    fn initial_state(&self, s: &Sample) -> SVector<f64, N> {
        let (x1, x2) = shank_start(s, self.model.base.p.theta_eq);
        let mut x = SVector::<f64, N>::zeros();
        x[0] = x1;
        x[1] = x2;
        if let Some(i) = self.model.layout.activation {
            // Without stimulation, activation at rest is 0. A start during a
            // pulse (stimulation on at the first sample) knows only that the
            // activation lies between 0 and the stimulation (it rises towards
            // it with T_a): the middle, with the variance of a uniform over
            // that range ([`Plant::initial_covariance`]). A generalisation
            // audit started the shared FES trials 3.5 s in, during a pulse:
            // with activation = u and p0 = 1e-4 the ekf carried the start's
            // error into its bias states, 0.28 deg off 25 s later (0.06 from
            // the trial's start).
            x[i] = 0.5 * start_stimulation(s);
        }
        x
    }

    fn initial_covariance(&self, s: &Sample, p0: &SVector<f64, N>) -> SVector<f64, N> {
        let mut p = *p0;
        if let Some(i) = self.model.layout.activation {
            let u = start_stimulation(s);
            p[i] = p[i].max(u * u / 12.0);
        }
        p
    }

    fn outputs(&self) -> Outputs {
        KNEE_OUTPUTS
    }

    fn fill(&self, x: &SVector<f64, N>, e: &mut Estimate) {
        fill_knee(self.thigh_angle, x[0], e);
    }

    fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let m = &self.model;
        let p = &m.base.p;
        describe_knee_params(p, self.thigh_angle, out)?;
        let o = &m.options;
        if o.activation {
            writeln!(
                out,
                "activation: state, a_ke' = (u_ke - a_ke) / T_a, T_a = {} s",
                p.t_a
            )?;
        } else {
            writeln!(out, "activation: a_ke = u_ke (thesis section 4.1.1)")?;
        }
        writeln!(out, "torque_disturbance_state: {}", o.disturbance)?;
        writeln!(out, "gyro_bias_state: {}", o.gyro_bias)?;
        writeln!(out, "acc_bias_state: {}", o.acc_bias)?;
        writeln!(out, "shank_imu_m: {}", m.imu_radius)?;
        if !self.imu_radius_source.is_empty() {
            writeln!(out, "shank_imu_m_source: {}", self.imu_radius_source)?;
        }
        Ok(())
    }

    fn write_diagnostics(&self, st: &FilterState<N>, resets: u32, e: &mut Estimate) {
        use ExtendedKneeDiag as D;
        let l = &self.model.layout;
        let mut d = e.diagnostics_mut::<D>();
        d.value(D::ShankRate, st.x[1]);
        d.value(D::P11, st.p[(0, 0)]);
        d.value(D::P22, st.p[(1, 1)]);
        for (i, state, cov) in [
            (l.activation, D::Activation, D::PActivation),
            (l.disturbance, D::Disturbance, D::PDisturbance),
            (l.gyro_bias, D::GyroBias, D::PGyroBias),
            (l.acc_bias, D::AccBias, D::PAccBias),
        ] {
            d.set(state, i.map(|i| st.x[i]));
            d.set(cov, i.map(|i| st.p[(i, i)]));
        }
        d.value(D::Resets, f64::from(resets));
    }

    const UPDATE_PARTS: bool = true;

    fn write_update_parts(
        &self,
        (prediction, correction, pull): (&SVector<f64, N>, &SVector<f64, N>, &SVector<f64, N>),
        dt: Option<f64>,
        e: &mut Estimate,
    ) {
        let (m, c) = (libm::fabs(prediction[1]), libm::fabs(correction[1]));
        let share = (m + c > 0.0).then(|| m / (m + c));
        let mut d = e.diagnostics_mut::<ExtendedKneeDiag>();
        d.set(ExtendedKneeDiag::ModelShare, share);
        d.set(
            ExtendedKneeDiag::ModelWeight,
            dt.map(|dt| libm::exp(-pull[1] * dt)),
        );
    }
}

impl<const N: usize> ExtendedKneeFilter<N> {
    /// `sdre` (`Linearisation::Sdc`) or `ekf` on `model` with the default
    /// tuning ([`extended_knee_default_tuning`]), thigh horizontal.
    pub fn with_default_tuning(model: ExtendedKneeModel<N>, lin: Linearisation) -> Self {
        FesFilter::new(
            ExtendedKneePlant::new(model),
            lin,
            extended_knee_default_tuning(&model, lin),
        )
    }
}

impl<const N: usize> ExtendedKneePlant<N> {
    /// The plant with the thigh horizontal.
    pub fn new(model: ExtendedKneeModel<N>) -> Self {
        ExtendedKneePlant {
            model,
            thigh_angle: core::f64::consts::FRAC_PI_2,
            imu_radius_source: "",
        }
    }

    /// Where the optional states are.
    pub fn layout(&self) -> KneeStateLayout {
        self.model.layout
    }
}

diagnostic_set! {
    /// Diagnostics of `knee-kinematic` ([`KinematicKneePlant`]).
    pub enum KinematicKneeDiag {
        /// Shank angular rate (rad/s).
        ShankRate = "shank_rate",
        /// Shank angular acceleration (rad/s^2).
        ShankAccel = "shank_accel",
        /// Shank gyro z bias (rad/s).
        GyroBias = "gyro_bias",
        /// Shank accelerometer x bias (m/s^2).
        AccBias = "acc_bias",
        /// `P_11`, shank angle (rad^2).
        P11 = "p11",
        /// Restarts after a non-finite state.
        Resets = "resets",
    }
}

/// The kinematic shank model as a plant: the shank IMU only, no input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicKneePlant {
    /// The model.
    pub model: KinematicKneeModel,
    /// Absolute thigh angle (rad).
    pub thigh_angle: f64,
}

/// `knee-kinematic`: the extended Kalman-Bucy filter on the kinematic model.
pub type KinematicKneeFilter = FesFilter<KinematicKneePlant, 5, 2, 0>;

/// The method name `knee-kinematic` reports ([`Plant::method_name`]).
pub const KINEMATIC_METHOD: &str = "knee-kinematic";

/// Largest angular jerk of the shank the default tuning allows for
/// (rad/s^3): a 60 deg extension over a 1.5 s cosine ramp has peak jerk
/// `(pi/3)/2 (pi/1.5)^3` = 4.8 rad/s^3 (the limbfuse and independent
/// simulators' pulses; a faster voluntary kick is several times more).
pub const KINEMATIC_JERK: f64 = 5.0;

/// Default tuning of `knee-kinematic`: angular jerk white noise of
/// intensity `q_3 = KINEMATIC_JERK^2 * 0.1 s` (a jerk of that size held for
/// 0.1 s), bias states and `S` as the extended knee model's
/// ([`extended_defaults`]: same sensors, same trust).
pub fn kinematic_default_tuning() -> ContinuousTuning<5, 2> {
    use extended_defaults::*;
    let base = knee_default_tuning(Linearisation::Jacobian);
    ContinuousTuning {
        q: SVector::<f64, 5>::from_row_slice(&[
            1e-8,
            1e-8,
            KINEMATIC_JERK * KINEMATIC_JERK * 0.1,
            GYRO_BIAS_Q,
            ACC_BIAS_Q,
        ]),
        s: SVector::<f64, 2>::new(S_GYRO, S_ACC),
        a: 0.0,
        p0: SVector::<f64, 5>::from_row_slice(&[
            1e-2,
            1e-2,
            1.0,
            GYRO_BIAS_SIGMA * GYRO_BIAS_SIGMA,
            ACC_BIAS_SIGMA * ACC_BIAS_SIGMA,
        ]),
        max_substep: base.max_substep,
        a_states: None,
    }
}

impl KinematicKneeFilter {
    /// `knee-kinematic` with the default tuning.
    pub fn kinematic(model: KinematicKneeModel, thigh_angle: f64) -> Self {
        FesFilter::new(
            KinematicKneePlant { model, thigh_angle },
            Linearisation::Jacobian,
            kinematic_default_tuning(),
        )
    }
}

impl Plant<5, 2, 0> for KinematicKneePlant {
    type Model = KinematicKneeModel;
    type Diag = KinematicKneeDiag;
    const RATE_DIAG: &'static [KinematicKneeDiag] = &[];
    const COVARIANCE_DIAG: &'static [KinematicKneeDiag] = &[];
    const RESETS_DIAG: KinematicKneeDiag = KinematicKneeDiag::Resets;

    fn model(&self) -> &KinematicKneeModel {
        &self.model
    }

    fn model_name(&self) -> &'static str {
        "kinematic shank (no dynamics)"
    }

    fn method_name(&self) -> Option<&'static str> {
        Some(KINEMATIC_METHOD)
    }

    fn measurement_names(&self) -> [&'static str; 2] {
        ["shank_gyr_z", "shank_acc_x"]
    }

    fn input_names(&self) -> [&'static str; 0] {
        []
    }

    fn measurement(&self, s: &Sample) -> [Option<f64>; 2] {
        shank_measurement(s)
    }

    fn input(&self, _: &Sample) -> [Option<f64>; 0] {
        []
    }

    fn initial_state(&self, s: &Sample) -> SVector<f64, 5> {
        let (x1, x2) = shank_start(s, 0.0);
        SVector::<f64, 5>::from_row_slice(&[x1, x2, 0.0, 0.0, 0.0])
    }

    fn outputs(&self) -> Outputs {
        KNEE_OUTPUTS
    }

    fn fill(&self, x: &SVector<f64, 5>, e: &mut Estimate) {
        fill_knee(self.thigh_angle, x[0], e);
    }

    fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "thigh_angle_rad: {}", self.thigh_angle)?;
        writeln!(out, "g: {}", self.model.g)?;
        writeln!(out, "shank_imu_m: {}", self.model.imu_radius)?;
        writeln!(
            out,
            "states: shank angle, rate, angular acceleration (jerk noise), gyro bias, accelerometer bias"
        )
    }

    fn write_diagnostics(&self, st: &FilterState<5>, resets: u32, e: &mut Estimate) {
        use KinematicKneeDiag as D;
        let mut d = e.diagnostics_mut::<D>();
        d.value(D::ShankRate, st.x[1]);
        d.value(D::ShankAccel, st.x[2]);
        d.value(D::GyroBias, st.x[3]);
        d.value(D::AccBias, st.x[4]);
        d.value(D::P11, st.p[(0, 0)]);
        d.value(D::Resets, f64::from(resets));
    }
}
