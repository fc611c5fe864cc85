//! The integration tests of limbfuse-studies, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again). `tests/soak_ten_minutes.rs` stays its own binary:
//! its resident-memory figures must not be those of other tests running
//! beside it.

mod baseline_physics;
mod calibrated_segment_filters;
mod issue_16_perturbed_model;
mod knee_remount;
mod results_commands;
