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
//! Adding a method: write its estimator in `limbfuse-estimators`, add a
//! [`MethodName`] variant with its [`MethodInfo`], a [`MethodSpec`] variant
//! with its settings, and the arms the compiler then asks for.
#![deny(missing_docs)]

mod build;
pub mod channels;
mod error;
pub mod fes_params;
pub mod imm_params;
pub mod knee_params;
mod name;
pub mod params_toml;
pub mod segment_params;
mod spec;

pub use build::{build, check_channels};
pub use channels::ChannelNeeds;
pub use error::MethodError;
pub use name::{MethodInfo, MethodName, UnknownMethod};
pub use spec::{default_params_file, MethodFlags, MethodSpec};
