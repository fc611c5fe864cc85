//! Model-based knee and hip estimation for FES (paper 004, Zhong 2016).
//!
//! * [`continuous`]: the continuous-time estimator of eqs 4.14-4.16 (state
//!   and Riccati equation integrated together by RK4 between samples), with
//!   SDC matrices (`sdre`) or Jacobians (`ekf`); [`propagation`]: its RK4
//!   sub-stepping between samples and the stiffness bound that sizes it.
//! * [`filter`]: [`filter::FesFilter`], the [`limbfuse_core::Estimator`]
//!   over a [`filter::Plant`] (a model plus the channel mapping).
//! * [`knee`]: the leg-extension plant (2 states), [`fixed_hip`]: the
//!   fixed-hip plant (4 states); [`fixed_hip_activation`]: the fixed hip
//!   with the four muscle activations as states (8, issue 16).
//! * [`knee_extended`]: the knee model with optional activation,
//!   unknown-torque and sensor-bias states (issue 16), and the model-free
//!   kinematic shank plant of `knee-kinematic`.
//! * [`rmx`]: the rotation-matrix baseline (relative orientation of the two
//!   IMUs, each from a Mahony complementary filter or device quaternions).
//!
//! Design notes and measured results: docs/FES_ESTIMATION.md.

pub mod continuous;
pub mod filter;
pub mod fixed_hip;
pub mod fixed_hip_activation;
mod gyro_spikes;
pub mod knee;
pub mod knee_extended;
pub mod mahony;
pub mod propagation;
pub mod rmx;

pub use continuous::{ContinuousTuning, Linearisation};
pub use filter::{FesFilter, Plant};
pub use fixed_hip::{FixedHipDiag, FixedHipFilter, FixedHipPlant};
pub use fixed_hip_activation::{
    FixedHipActivationDiag, FixedHipActivationFilter, FixedHipActivationPlant,
};
pub use knee::{KneeFesDiag, KneeFesFilter, KneePlant};
pub use knee_extended::{
    ExtendedKneeDiag, ExtendedKneeFilter, ExtendedKneePlant, KinematicKneeDiag,
    KinematicKneeFilter, KinematicKneePlant,
};
pub use rmx::{OrientationSource, RmxDiag, RotationMatrixKnee};
