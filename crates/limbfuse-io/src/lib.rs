//! # limbfuse-io
//!
//! Trial files (SPEC section 2) and estimate files (SPEC section 3): streaming
//! readers and writers with precise errors (file, line, column, what was
//! expected), importers that turn real recordings into trial files, and the
//! gait-library file. Signal processing on trials (alignment, resampling,
//! conditioning) lives in `limbfuse-signal`.
#![deny(missing_docs)]

pub mod arrow_file;
mod arrow_source;
pub mod atomic_file;
pub mod body_meta;
pub mod bounded_text;
pub mod calibration;
pub mod calibration_bounds;
mod cell_format;
mod cell_sink;
mod column_spelling;
pub mod content_hash;
mod csv_lines;
pub mod diagnostic_columns;
pub mod error;
pub mod estimate_file;
pub mod file_identity;
pub mod gait_library;
pub mod import;
pub mod late_rows;
pub mod layout;
mod mapped_file;
pub mod meta;
pub mod provenance;
pub mod table;
pub mod time_repair;
mod trial_hints;
pub mod trial_reader;
pub mod trial_writer;

pub use atomic_file::AtomicFile;
pub use calibration::{Calibration, CalibrationFileError, ImuCalibration};
pub use content_hash::{ContentHash, TrialFingerprint};
pub use diagnostic_columns::DiagnosticColumns;
pub use error::FileError;
pub use estimate_file::{EstimateReader, EstimateWriter, CONTACT_COLUMNS};
pub use late_rows::{LateRowLog, LateRows};
pub use layout::{contact_ref_column, TrialLayout};
pub use meta::TrialMeta;
pub use trial_reader::TrialReader;
pub use trial_writer::TrialWriter;
