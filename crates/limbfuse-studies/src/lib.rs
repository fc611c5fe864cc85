//! # limbfuse-studies
//!
//! The studies and experiments behind `docs/RESULTS.md`: the code the study
//! examples (`examples/*.rs`) share, their argument parsers, and the list of
//! commands written in `docs/RESULTS.md`. Not part of the limbfuse library
//! API (`publish = false`): the libraries (`limbfuse-eval` for metrics and
//! statistics) never depend on it.
#![deny(missing_docs)]

pub mod baseline_study;
pub mod bslip_trials;
pub mod calibration_study;
pub mod example_args;
pub mod fes_plot;
pub mod fes_pulse_cv;
pub mod fes_study;
pub mod knee_study;
pub mod recorded_trial;
pub mod recorded_trial_args;
pub mod results_commands;
pub mod soak;
