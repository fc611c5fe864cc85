//! The integration tests of limbfuse-models, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again).

mod fixed_hip_activation;
mod sdc_factorisations;
