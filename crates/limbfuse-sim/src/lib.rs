//! # limbfuse-sim
//!
//! Seeded simulators that produce trials with ground truth.
#![deny(missing_docs)]
