//! # limbfuse-sim
//!
//! Seeded simulators that produce trials with ground truth.
//!
//! [`WalkingSimulator`] streams [`limbfuse_core::Record`]s of a walking leg:
//! a sagittal trunk-thigh-shank-foot chain driven by normative gait curves
//! (speed 0.4-1.8 m/s), a prescribed realistic hip path with the stance leg
//! made consistent with it by inverse kinematics, analytic
//! angular rates and specific forces at four IMUs, consumer-MEMS sensor
//! errors (paper 000 eqs 1-4) and 1 kHz joint encoders. Model, defaults,
//! sources and measured checks: `docs/SIMULATOR.md`.
#![deny(missing_docs)]

pub mod anthropometry;
pub mod body_path;
pub mod calibration_poses;
pub mod chain;
pub mod config;
pub mod encoder_model;
pub mod fes_error;
pub mod fixed_hip;
pub mod fourier;
pub mod gait_curves;
pub mod gait_model;
pub mod gait_truth;
pub mod hip_path;
pub mod imu_model;
pub mod knee_fes;
pub mod knee_scenario;
pub mod planar_imu;
pub mod stance;
pub mod turn_schedule;
pub mod variability;
pub mod walking;

pub use body_path::Turns;
pub use calibration_poses::{PoseRecording, PoseRecordingConfig};
pub use config::{
    EncoderResample, EncoderSpec, ImuSpec, Motion, Mounting, SimError, TriadSpec, Variability,
    WalkingConfig,
};
pub use knee_scenario::{KneeScenario, KneeSimulator, Remount};
pub use walking::{walking_sensors, Truth, WalkingSimulator};
pub mod bslip;
