//! # limbfuse-workflows
//!
//! What a study or a command does with estimators, above the method layer
//! and the metrics, so that the CLI and the Python package call the same
//! code: paper 001's multi-start protocol ([`protocol`]) and which samples
//! it scored ([`coverage`]), noise tuning
//! ([`tuning`]) and the tune-then-validate loop of `limbfuse tune`
//! ([`tune_validate`]), paper 000's Monte Carlo ([`monte_carlo`], plot in
//! [`monte_carlo_plot`]), simulated trials with their metadata and columns
//! ([`simulated_trials`]), a built gait library as its file
//! ([`gait_library`]), the gait a simulated B-SLIP trial walks on
//! ([`bslip_gait`]), a trial's sensor alignment by either procedure
//! ([`trial_alignment`]), and `imm-bslip`'s library extended to a trial's
//! speeds ([`imm_library_extension`]).
#![deny(missing_docs)]

pub mod align_verdict;
pub mod bslip_gait;
pub mod coverage;
pub mod fes_pulse_cv;
pub mod fes_torque_tuning;
pub mod gait_library;
pub mod imm_library_extension;
pub mod monte_carlo;
pub mod monte_carlo_plot;
pub mod parallel_cancellation;
pub mod protocol;
pub mod simulated_trials;
pub mod simulator_options;
pub mod trial_alignment;
pub mod tune_validate;
pub mod tuning;
