//! The integration tests of limbfuse-sim, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again).

mod bslip;
mod determinism;
mod light_body_library;
mod physics;
