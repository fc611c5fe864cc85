//! # limbfuse-core
//!
//! The `no_std` foundation of limbfuse: the sample and estimate types every
//! estimator exchanges, the streaming [`Estimator`] trait, linear Kalman
//! predict/update steps on `nalgebra` fixed-size matrices, exact (matrix
//! exponential + Van Loan) and Euler discretisation, the sensor gate
//! ([`SampleGate`]) and an estimator behind it as `limbfuse estimate` runs
//! every method ([`Gated`], for a controller's loop: `no_std`, no
//! allocation), and (with the `std` feature) the [`runner`] that drives an
//! estimator over a sample source and pushes results to observers.
//!
//! [`nalgebra`] is re-exported: a [`Sample`]'s vectors are its `Vector3`,
//! so a user fills one without depending on the same nalgebra release.
//!
//! Conventions (SPEC section 1): SI units, sagittal angles about the world
//! z axis (to the subject's right), positive counter-clockwise seen from the
//! right side; `hip = theta_trunk - theta_thigh`, `knee = theta_thigh -
//! theta_shank`, `ankle = theta_shank - theta_foot`.
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

extern crate alloc;

pub mod diagnostics;
pub mod discretize;
pub mod estimate;
pub mod estimator;
pub mod expm;
pub mod gated;
pub mod kalman;
pub mod limb;
pub mod plausibility;
pub mod sample;
pub mod sample_gate;
pub mod screening;
pub mod shown_number;

#[cfg(feature = "std")]
pub mod runner;

/// The linear-algebra crate of [`Sample`] and [`Estimate`] (`Vector3`), at
/// the version limbfuse is built with.
pub use nalgebra;

pub use diagnostics::{DiagnosticSet, DiagnosticWriter};
pub use estimate::{Estimate, MAX_DIAG};
pub use estimator::{Estimator, EstimatorError, OfflineEstimator, Outputs, TimeStep};
pub use gated::{EstimatorGate, Gated, REJECTION_DIAGNOSTICS};
pub use limb::{Joint, Leg, Segment, Side};
pub use plausibility::{Implausible, PlausibilityLimits, VectorTrack};
pub use sample::{ComMeasurement, GaitPhase, ImuSample, Record, Reference, Sample};
pub use sample_gate::{Rejections, SampleGate, SensorRanges};
pub use screening::Screening;
pub use shown_number::ShownNumber;

/// Standard gravity used when a trial does not say otherwise (m/s^2), SPEC section 1.
pub const STANDARD_GRAVITY: f64 = 9.81;
