//! # limbfuse-estimators
//!
//! The estimators of the papers limbfuse implements, each a module with its
//! parameters struct and documented defaults, all implementing
//! [`limbfuse_core::Estimator`]. `no_std`; no estimator allocates per sample
//! or does I/O.
//!
//! Until the paper estimators land, two honest baselines are provided:
//! [`baseline::GyroIntegration`] and [`baseline::AccelInclination`].
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

extern crate alloc;

pub mod baseline;
pub mod fes;
pub mod gait_events;
pub mod hinge_axis;
pub mod imm_bslip;
pub mod inclination;
pub mod knee_selfalign;
pub mod lowback_speed;
pub mod segment_kf;
