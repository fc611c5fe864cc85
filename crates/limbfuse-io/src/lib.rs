//! # limbfuse-io
//!
//! Trial files (SPEC section 2) and estimate files (SPEC section 3): streaming
//! readers and writers with precise errors (file, line, column, what was
//! expected), and importers that turn real recordings into trial files.
#![deny(missing_docs)]

pub mod align;
mod cell_format;
pub mod conditioning;
pub mod error;
pub mod estimate_file;
pub mod gait_library;
pub mod import;
pub mod layout;
pub mod meta;
pub mod resample;
pub mod table;
pub mod trial_reader;
pub mod trial_writer;

pub use error::FileError;
pub use estimate_file::{EstimateReader, EstimateWriter};
pub use layout::TrialLayout;
pub use meta::TrialMeta;
pub use trial_reader::TrialReader;
pub use trial_writer::TrialWriter;
