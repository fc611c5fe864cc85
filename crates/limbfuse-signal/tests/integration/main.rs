//! The integration tests of limbfuse-signal, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again).

mod align_bad_input;
mod align_gaittoolbox;
mod align_legs;
mod align_sim;
mod calibration_sim;
mod invariance_unseen;
mod knee_stamp_jitter;
mod resample;
