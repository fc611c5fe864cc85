//! # limbfuse-models
//!
//! Physical models shared by the simulators (`limbfuse-sim`) and the
//! model-based estimators (`limbfuse-estimators`): the FES-driven
//! musculoskeletal knee and fixed-hip models of paper 004 and the bipedal
//! spring-loaded inverted pendulum (B-SLIP) of paper 003. `no_std`; each
//! model is a module with its parameter struct, its dynamics `f(x, u)` and
//! its measurement function, so a simulator integrates exactly the equations
//! an estimator linearises.
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

pub mod default_body;
pub mod error;
pub mod fes_knee;
pub mod fes_knee_extended;
pub mod fixed_hip;
pub mod fixed_hip_activation;
pub mod kinematic_knee;
pub mod sdc;

pub use default_body::{DEFAULT_BODY_HEIGHT_M, DEFAULT_BODY_MASS_KG};
pub use error::ModelError;
pub use fes_knee::{KneeFesModel, KneeFesParams, KneeSubject};
pub use fes_knee_extended::{
    ExtendedKneeError, ExtendedKneeModel, KneeStateLayout, KneeStateOptions,
};
pub use fixed_hip::{FixedHipModel, FixedHipParams};
pub use fixed_hip_activation::{FixedHipActivationModel, FIXED_HIP_T_A};
pub use kinematic_knee::KinematicKneeModel;
pub use sdc::{Linearised, SdcModel};
pub mod bslip;
