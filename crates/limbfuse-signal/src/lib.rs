//! # limbfuse-signal
//!
//! Signal processing on recorded or simulated trials that is not file I/O:
//! sensor-to-segment alignment ([`align`]), resampling onto a uniform time
//! base ([`resample`]), the signal conditioning of paper 004
//! ([`conditioning`]) and IMU calibration from static poses
//! ([`calibration`]), and the variants of a recording (re-mounted
//! sensors, shifted or jittered clocks) used to audit that methods answer
//! them the same way ([`recording_variants`]). Files are read and written
//! by `limbfuse-io`; this crate works on its records and metadata.
#![deny(missing_docs)]

pub mod align;
pub mod calibration;
pub mod conditioning;
pub mod recording_variants;
pub mod resample;
