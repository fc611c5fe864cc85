//! The fixed-hip plant with the four muscle activations as states (issue
//! 16 item 1; `limbfuse_models::fixed_hip_activation`): same sensors,
//! inputs and outputs as [`super::fixed_hip::FixedHipPlant`].

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{diagnostic_set, Estimate, Sample};
use limbfuse_models::FixedHipActivationModel;
use nalgebra::SVector;

use super::continuous::{ContinuousTuning, FilterState, Linearisation};
use super::filter::{FesFilter, Plant};
use super::fixed_hip::{
    describe_hip, fixed_hip_default_tuning, hip_fill, hip_initial_state, hip_input,
    hip_measurement, HIP_INPUT_NAMES, HIP_MEASUREMENT_NAMES, HIP_OUTPUTS,
};
use super::knee_extended::extended_defaults::ACTIVATION_Q;

/// The fixed-hip model with activation states as an estimator plant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedHipActivationPlant {
    /// The model.
    pub model: FixedHipActivationModel,
}

/// `sdre` / `ekf` on the fixed-hip model with activation states.
pub type FixedHipActivationFilter = FesFilter<FixedHipActivationPlant, 8, 4, 6>;

impl FixedHipActivationFilter {
    /// `sdre` (`Linearisation::Sdc`) or `ekf` with
    /// [`fixed_hip_activation_tuning`].
    pub fn with_default_tuning(model: FixedHipActivationModel, lin: Linearisation) -> Self {
        let t = fixed_hip_activation_tuning(&model, lin);
        FesFilter::new(FixedHipActivationPlant { model }, lin, t)
    }
}

/// Default tuning: the fixed hip's for the mechanical states; for each
/// activation the knee model's (`extended_defaults::ACTIVATION_Q`, `p0 =
/// 1e-4`: the filter starts at the first sample's stimulation), and the SDRE's
/// prescribed-stability shift `min(a, 1 / (2 T_a))` on the activations (a
/// shift beyond its own decay rate would make the activation's `P` grow
/// while the muscle is off; docs/FES_ESTIMATION.md "Prescribed stability
/// per state").
pub fn fixed_hip_activation_tuning(
    model: &FixedHipActivationModel,
    lin: Linearisation,
) -> ContinuousTuning<8, 4> {
    let base = fixed_hip_default_tuning(lin);
    let mut q = SVector::<f64, 8>::repeat(ACTIVATION_Q);
    let mut p0 = SVector::<f64, 8>::repeat(1e-4);
    for i in 0..4 {
        q[i] = base.q[i];
        p0[i] = base.p0[i];
    }
    ContinuousTuning {
        q,
        s: base.s,
        a: base.a,
        p0,
        max_substep: base.max_substep,
        a_states: Some(fixed_hip_activation_shift(model, base.a)),
    }
}

/// The per-state shift of [`fixed_hip_activation_tuning`] for a gain `a`
/// (after a `[tuning] a` override).
pub fn fixed_hip_activation_shift(model: &FixedHipActivationModel, a: f64) -> SVector<f64, 8> {
    let mut l = SVector::<f64, 8>::repeat(a.min(0.5 / model.t_a));
    for v in l.iter_mut().take(4) {
        *v = a;
    }
    l
}

diagnostic_set! {
    /// Diagnostics of the fixed-hip `sdre` / `ekf` with activation states.
    pub enum FixedHipActivationDiag {
        /// Thigh angular rate state `x_3` (rad/s).
        ThighRate = "thigh_rate",
        /// Shank angular rate state `x_4` (rad/s).
        ShankRate = "shank_rate",
        /// `P_11`, thigh angle (rad^2).
        P11 = "p11",
        /// `P_22`, shank angle (rad^2).
        P22 = "p22",
        /// `P_33`, thigh rate ((rad/s)^2).
        P33 = "p33",
        /// `P_44`, shank rate ((rad/s)^2).
        P44 = "p44",
        /// Hip flexor activation state `a_hf`.
        ActivationHf = "activation_hf",
        /// Hip extensor activation state `a_he`.
        ActivationHe = "activation_he",
        /// Knee flexor activation state `a_kf`.
        ActivationKf = "activation_kf",
        /// Knee extensor activation state `a_ke`.
        ActivationKe = "activation_ke",
        /// Restarts after a non-finite state.
        Resets = "resets",
        /// Samples whose input was missing and held (cumulative).
        HeldInputs = "held_inputs",
    }
}

impl Plant<8, 4, 6> for FixedHipActivationPlant {
    type Model = FixedHipActivationModel;
    type Diag = FixedHipActivationDiag;
    const RATE_DIAG: &'static [FixedHipActivationDiag] = &[
        FixedHipActivationDiag::ThighRate,
        FixedHipActivationDiag::ShankRate,
    ];
    const COVARIANCE_DIAG: &'static [FixedHipActivationDiag] = &[
        FixedHipActivationDiag::P11,
        FixedHipActivationDiag::P22,
        FixedHipActivationDiag::P33,
        FixedHipActivationDiag::P44,
    ];
    const RESETS_DIAG: FixedHipActivationDiag = FixedHipActivationDiag::Resets;
    const HELD_INPUTS_DIAG: Option<FixedHipActivationDiag> =
        Some(FixedHipActivationDiag::HeldInputs);

    fn model(&self) -> &FixedHipActivationModel {
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

    /// Angles and rates as the fixed hip; each activation half the first
    /// sample's stimulation, with the variance of a uniform between 0 and it
    /// ([`Plant::initial_covariance`]): a start during a pulse knows only
    /// that the activation is on its way there (as the knee's,
    /// `knee_extended`); 0 without stimulation or when missing.
    fn initial_state(&self, s: &Sample) -> SVector<f64, 8> {
        let q = hip_initial_state(s);
        let u = start_stimulation(s);
        SVector::<f64, 8>::from_row_slice(&[
            q[0],
            q[1],
            q[2],
            q[3],
            0.5 * u[0],
            0.5 * u[1],
            0.5 * u[2],
            0.5 * u[3],
        ])
    }

    fn initial_covariance(&self, s: &Sample, p0: &SVector<f64, 8>) -> SVector<f64, 8> {
        let mut p = *p0;
        for (k, u) in start_stimulation(s).iter().enumerate() {
            p[4 + k] = p[4 + k].max(u * u / 12.0);
        }
        p
    }

    fn outputs(&self) -> Outputs {
        HIP_OUTPUTS
    }

    fn fill(&self, x: &SVector<f64, 8>, e: &mut Estimate) {
        hip_fill(x[0], x[1], e);
    }

    fn describe(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        describe_hip(&self.model.base, out)?;
        writeln!(
            out,
            "activation: states a_hf, a_he, a_kf, a_ke, a' = (u - a) / T_a, T_a = {} s",
            self.model.t_a
        )
    }

    fn write_diagnostics(&self, st: &FilterState<8>, resets: u32, e: &mut Estimate) {
        use FixedHipActivationDiag as D;
        let mut d = e.diagnostics_mut::<D>();
        d.value(D::ThighRate, st.x[2]);
        d.value(D::ShankRate, st.x[3]);
        for (i, key) in [D::P11, D::P22, D::P33, D::P44].into_iter().enumerate() {
            d.value(key, st.p[(i, i)]);
        }
        for (i, key) in [
            D::ActivationHf,
            D::ActivationHe,
            D::ActivationKf,
            D::ActivationKe,
        ]
        .into_iter()
        .enumerate()
        {
            d.value(key, st.x[4 + i]);
        }
        d.value(D::Resets, f64::from(resets));
    }
}

/// Each muscle's stimulation at the first sample (the first four inputs;
/// 0 when missing).
fn start_stimulation(s: &Sample) -> [f64; 4] {
    let u = hip_input(s);
    core::array::from_fn(|k| u[k].filter(|v| v.is_finite()).unwrap_or(0.0).max(0.0))
}
