//! The integration tests of limbfuse-methods, one module per former
//! `tests/NAME.rs` (one test binary per package: each binary linked the whole
//! dependency graph again).

mod adding_a_method;
mod embedded_gate;
mod method_names_parsed_once;
mod segment_params;
mod smoothed_chain;
