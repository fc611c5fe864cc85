//! # limbfuse-methods
//!
//! The method layer: every estimation method limbfuse can run, configured
//! and built the same way.
//!
//! ```text
//! name ──MethodName::parse──► MethodName ─┐
//! --params FILE.toml ─────────────────────┼─MethodSpec::resolve─► MethodSpec ─build(meta, layout)─► Box<dyn Estimator>
//! flags (MethodFlags) ────────────────────┘
//! ```
//!
//! - [`MethodName`] is the one place a method name is parsed;
//!   [`MethodName::info`] documents it (`limbfuse methods`) and
//!   [`MethodName::required_channels`] says which columns it reads.
//! - [`MethodSpec`] holds every setting resolved and validated, typed per
//!   method. Every parameter file is TOML with an optional
//!   `method = "NAME"`, read into the method's typed struct with unknown
//!   keys rejected (file, line, column); [`default_params_file`] writes the
//!   defaults, commented (`limbfuse params --method NAME`).
//! - [`build`] turns a spec and a trial's metadata and columns into an
//!   estimator; it does no I/O.
//!
//! Adding a method: write its estimator in `limbfuse-estimators`, implement
//! [`MethodDef`] for it (name and documentation, settings from a typed
//! parameter file and flags, build for a trial, default file) and add one
//! line to the registry ([`registry`]); [`MethodName`], [`MethodSpec`] and
//! every dispatch follow from that line.
//! `tests/integration/adding_a_method.rs` does it for a trivial method.
#![deny(missing_docs)]

pub mod availability;
mod baseline_methods;
pub mod body_ranges;
mod build;
pub mod chain_method;
pub mod channels;
mod error;
pub mod fes_default_file;
pub mod fes_extended;
pub mod fes_fixed_hip;
pub mod fes_methods;
pub mod fes_param_lines;
pub mod fes_params;
pub mod gait_methods;
pub mod gated;
pub mod imm_body;
pub mod imm_params;
pub mod knee_backfill;
pub mod knee_params;
pub mod knee_window;
pub mod leg_length_keys;
pub mod lowback_method;
pub mod metadata_settings;
pub mod method_def;
mod name;
pub mod params_toml;
pub mod raw_frames;
pub mod registry;
pub mod segment_methods;
pub mod segment_params;
pub mod smoothed_chain;
mod spec;

pub use availability::{availability, Availability};
pub use baseline_methods::{AccelInclinationMethod, GyroIntegrationMethod};
pub use build::{build, check_channels, gate};
pub use channels::ChannelNeeds;
pub use error::{clip_echoes, shown, MethodError};
pub use metadata_settings::metadata_settings;
pub use method_def::{build_with, read_file, resolve_with, MethodDef, MethodFile, MethodInfo};
pub use name::{check_file_method, UnknownMethod};
pub use raw_frames::raw_frame_note;
pub use registry::{default_params_file, MethodName, MethodSpec};
pub use spec::MethodFlags;
