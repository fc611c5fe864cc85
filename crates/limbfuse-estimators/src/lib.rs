//! # limbfuse-estimators
//!
//! The estimators of the papers limbfuse implements, and ours, each a
//! module with its parameters struct and documented defaults, all
//! implementing [`limbfuse_core::Estimator`]. `no_std`; no estimator does
//! I/O or allocates per sample (construction may allocate a fixed buffer:
//! `chain`'s start-up window, the knee estimators' identification window,
//! `gait-events`' readings before a foot's axis sign is known, so the crate
//! needs `alloc`).
//!
//! | module | paper | estimators (`limbfuse estimate --method`) |
//! |---|---|---|
//! | [`segment_kf`] | 000, 001 | local, Markov-jump (MJLS) and global segment-angle Kalman filters (`local`, `mjls`, `global`) |
//! | [`chain_ekf`] | ours | kinematic-chain EKF of the four segment angles, accelerometers modelled (`chain`); `chain_ekf::smoother`: its offline RTS smoother |
//! | [`knee_selfalign`] | 002 | self-aligning knee angle, joint axes and positions identified online (`knee-selfalign`) |
//! | [`knee_gyro_axis`] | ours | knee angle from the relative gyro rate about the identified axes, a cross-check of 002 (`knee-gyro-axis`) |
//! | [`fes`] | 004 | SDRE, EKF and rotation-matrix (RMX) estimators on the FES knee and fixed-hip models (`sdre`, `ekf`, `rmx`, ...) |
//! | [`imm_bslip`] | 003 | interacting multiple models over a B-SLIP gait library: gait phase, speed (`imm-bslip`) |
//! | [`gait_events`] | ours | gait events, stance/swing, phase, stride length and speed from foot (or shank) IMUs (`gait-events`) |
//! | [`lowback_speed`] | ours | walking speed from a lower-back IMU (`lowback-speed`) |
//! | [`baseline`] | - | honest baselines: [`baseline::GyroIntegration`], [`baseline::AccelInclination`] |
//! | [`hinge_axis`] | 002 | the hinge-axis solver shared by the knee estimators and sensor alignment |
//! | [`inclination`] | 000 | the accelerometer inclination angle |
//! | [`cell_hold`] | ours | an empty cell among present ones takes that axis's last value (`gait-events`, `lowback-speed`) |
//! | [`stamp_grid`] | ours | a sensor's sampling clock from jittered stamps with lost rows (`knee-selfalign`, `knee-gyro-axis`, `lowback-speed`) |
//!
//! ## In a controller's loop
//!
//! Build the estimator from its parameters (no file, nothing read from a
//! trial), put it behind the sensor gate as `limbfuse estimate` puts every
//! method ([`limbfuse_core::Gated`]: a reading out of its sensor's range,
//! not finite, clipped at the gyroscope's full scale, jumping faster than a
//! segment can accelerate or stuck becomes missing and is counted), and step
//! it once per sample into an [`Estimate`](limbfuse_core::Estimate) the
//! loop owns. The estimates are `limbfuse estimate`'s bit for bit.
//!
//! - Units and frames (SPEC section 1): time in s, specific force in
//!   m/s^2, angular rate in rad/s, encoders and angles in rad. The segment
//!   filters and `chain` read IMU frames aligned to the segment: z to the
//!   subject's right, x and y in the sagittal plane such that the
//!   accelerometer reads (0, +g, 0) in upright quiet standing, so `gyr.z`
//!   is the segment's angular rate and a still segment's angle is
//!   `atan2(acc_x, acc_y)`; the knee estimators and `gait-events` read raw
//!   (arbitrarily mounted) frames. Angles are positive counter-clockwise
//!   seen from the subject's right (the distal end moving forward and up),
//!   zero in upright quiet standing; `hip = trunk - thigh`, `knee = thigh -
//!   shank`, `ankle = shank - foot`, and the encoders measure the same
//!   joint angles.
//! - A reading the drivers did not deliver is `None` (never NaN): the
//!   estimator predicts without it. A NaN or a glitch is made missing by the
//!   gate.
//! - `dt` is the difference of successive timestamps: a late sample is a
//!   longer step. A sample whose time is not after the last accepted one
//!   (or not finite) is refused with an error and changes nothing: the
//!   loop goes on with the next. After a fault, `reset` starts afresh.
//! - Parameters counted in samples follow the loop's rate where a method
//!   defines them in seconds: [`knee_selfalign::KneeSelfAlignParams::at_rate`].
//!
//! A segment filter at 500 Hz with a dropped thigh IMU packet and a
//! driver's NaN:
//!
//! ```
//! use limbfuse_core::nalgebra::Vector3;
//! use limbfuse_core::{Estimate, Estimator, Gated, Joint, Sample, Segment, SensorRanges};
//! use limbfuse_estimators::segment_kf::{MarkovJumpKf, MarkovJumpKfParams};
//!
//! let mjls = MarkovJumpKf::new(MarkovJumpKfParams::default())?;
//! let mut filter = Gated::new(mjls, SensorRanges::default());
//! let mut estimate = Estimate::empty(0.0);
//! let dt = 0.002;
//! for k in 0..1000 {
//!     // what the drivers read: a subject standing still (with the sensors'
//!     // noise: a vector repeated exactly for 0.1 s is a stuck sensor)
//!     let noise = 1e-3 * ((k * 7919 % 13) as f64 - 6.0);
//!     let mut sample = Sample::empty(k as f64 * dt);
//!     for imu in sample.imu.iter_mut() {
//!         imu.acc = Some(Vector3::new(noise, 9.81, -noise));
//!         imu.gyr = Some(Vector3::new(noise, -noise, noise));
//!     }
//!     sample.encoder = [Some(0.0); 3]; // hip, knee, ankle
//!     if k == 500 {
//!         sample.imu[Segment::Thigh.index()] = Default::default(); // no packet
//!     }
//!     if k == 600 {
//!         sample.encoder[Joint::Knee.index()] = Some(f64::NAN); // a driver's NaN
//!     }
//!     filter.step_into(&sample, &mut estimate)?;
//!     // the controller reads estimate.joint[Joint::Knee.index()] (rad)
//! }
//! let knee = estimate.joint[Joint::Knee.index()].expect("estimated");
//! assert!(knee.abs() < 0.01);
//! assert_eq!(filter.rejected_readings(), [0, 0, 1]); // [gyro, acc, encoder]
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Gait events from the right foot's IMU (here the walking simulator
//! stands in for the drivers), with a dropped foot packet. A foot's
//! gyroscope reaches its full scale in swing: `gait-events` keeps clipped
//! gyroscope readings (a rate at the full scale still says the foot swings),
//! as `limbfuse estimate` does, by a gate without the clipping check:
//!
//! ```
//! use limbfuse_core::{Estimate, Estimator, Gated, Segment, SensorRanges};
//! use limbfuse_estimators::gait_events::{FootSource, GaitDiag, GaitEvents, GaitEventsParams};
//! # use limbfuse_core::DiagnosticSet;
//! # let walk = limbfuse_sim::WalkingConfig { duration_s: 12.0, ..Default::default() };
//! # let drivers = limbfuse_sim::WalkingSimulator::new(walk)?;
//!
//! let params = GaitEventsParams { gravity: 9.81, ..GaitEventsParams::default() };
//! // [left, right]: the instrumented leg's foot IMU is the right one
//! let events = GaitEvents::new(params, [None, Some(FootSource::OwnLeg)])?;
//! // (gait-events keeps a clipped foot rate: `Gated` drops the clipping test)
//! let mut filter = Gated::new(events, SensorRanges::default());
//! let mut estimate = Estimate::empty(0.0);
//! let mut contacts = 0;
//! for (k, record) in drivers.enumerate() {
//!     let mut sample = record.sample;
//!     if k == 300 {
//!         sample.imu[Segment::Foot.index()].gyr = None; // no packet
//!     }
//!     filter.step_into(&sample, &mut estimate)?;
//!     // a right initial contact decided now: its time (s), back-dated
//!     if let Some(_t_ic) = estimate.diag[GaitDiag::IcRight.index()] {
//!         contacts += 1;
//!     }
//!     // the controller reads estimate.contact[1] (right foot on the ground),
//!     // estimate.phase and estimate.speed (m/s, the last stride's)
//! }
//! assert!(contacts >= 8, "{contacts}");
//! assert!(estimate.speed.is_some());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `crates/limbfuse-estimators/examples/controller_loop.rs` runs `mjls`,
//! `global`, `chain`, `knee-selfalign` and `gait-events` this way through a
//! driver's faults (docs/STREAMING.md, "Embedding an estimator in a
//! controller").
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

extern crate alloc;

pub mod baseline;
pub mod cell_hold;
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
pub mod stamp_grid;

#[cfg(test)]
mod tests {
    /// The crate documentation's table names every public module (it once
    /// left out `chain_ekf`, `gait_events` and `lowback_speed`).
    #[test]
    fn crate_table_lists_every_public_module() {
        let source = include_str!("lib.rs");
        let table: Vec<&str> = source
            .lines()
            .filter(|l| l.starts_with("//! | [`"))
            .collect();
        let modules = source
            .lines()
            .filter_map(|l| l.strip_prefix("pub mod ")?.strip_suffix(';'));
        for m in modules {
            let cell = format!("//! | [`{m}`] |");
            assert!(
                table.iter().any(|l| l.starts_with(&cell)),
                "module {m} is missing from the crate table"
            );
        }
    }
}
