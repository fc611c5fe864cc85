//! The integration tests of limbfuse-workflows, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again).

mod fes_torque_tuning;
mod issue_14_tuning_with_run_in;
mod monte_carlo;
mod protocol;
mod tuning;
