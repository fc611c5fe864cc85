//! # limbfuse-sim
//!
//! Seeded simulators that produce trials with ground truth.
#![deny(missing_docs)]

pub mod anthropometry;
pub mod chain;
pub mod config;
pub mod encoder_model;
pub mod fourier;
pub mod gait_curves;
pub mod gait_model;
pub mod hip_path;
pub mod imu_model;
pub mod variability;
pub mod walking;

pub use config::{
    EncoderResample, EncoderSpec, ImuSpec, Motion, Mounting, SimError, TriadSpec, Variability,
    WalkingConfig,
};
pub use walking::{Truth, WalkingSimulator};
