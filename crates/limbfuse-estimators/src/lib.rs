//! # limbfuse-estimators
//!
//! The estimators of the papers limbfuse implements, each a module with its
//! parameters struct and documented defaults, all implementing
//! [`limbfuse_core::Estimator`]. `no_std`; no estimator allocates per sample
//! or does I/O.
//!
//! | module | paper | estimators |
//! |---|---|---|
//! | [`segment_kf`] | 000, 001 | local, Markov-jump (MJLS) and global segment-angle Kalman filters |
//! | [`knee_selfalign`] | 002 | self-aligning knee angle (joint axes and positions identified online) |
//! | [`fes`] | 004 | SDRE, EKF and rotation-matrix (RMX) estimators on the FES knee and fixed-hip models |
//! | [`imm_bslip`] | 003 | interacting multiple models over a B-SLIP gait library (gait phase, speed) |
//! | [`knee_gyro_axis`] | - | knee angle from the relative gyro rate about the identified axes (cross-check of 002) |
//! | [`baseline`] | - | honest baselines: [`baseline::GyroIntegration`], [`baseline::AccelInclination`] |
//!
//! [`hinge_axis`] is the hinge-axis solver shared by the knee estimator and
//! sensor alignment; [`inclination`] the accelerometer inclination angle.
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

extern crate alloc;

pub mod baseline;
pub mod chain_ekf;
pub mod fes;
pub mod gait_events;
pub mod hinge_axis;
pub mod imm_bslip;
pub mod inclination;
pub mod knee_gyro_axis;
pub mod knee_selfalign;
pub mod lowback_speed;
pub mod segment_kf;
