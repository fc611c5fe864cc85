//! # limbfuse-io
//!
//! Trial files (SPEC section 2) and estimate files (SPEC section 3): streaming
//! readers and writers with precise errors, and importers that turn real
//! recordings into trial files.
#![deny(missing_docs)]

pub mod layout;
pub mod meta;

pub use layout::TrialLayout;
pub use meta::TrialMeta;
