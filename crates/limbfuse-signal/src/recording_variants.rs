//! Variants of a recording that a method claiming orientation, side or
//! time-origin independence must answer the same way (the invariance audit
//! of docs/RESULTS.md, "Invariance audit (unseen recordings)"): sensors
//! re-mounted by fixed rotations on both legs, the time base shifted, and
//! timestamps jittered. The other leg is [`crate::align::mirror`]; other
//! sample rates are [`crate::resample`].

use limbfuse_core::Record;
use nalgebra::{Rotation3, Vector3};

use crate::align::apply_rotations;
use crate::align::mirror::uniform01;

/// The record as sensors turned by fixed rotations read it: `own` for this
/// leg's trunk, thigh, shank and foot IMUs, `other` for the other leg's
/// (two-leg recordings). Readings become `R v` (see
/// [`crate::align::apply_rotations`]).
pub fn remount_both_legs(
    r: &Record,
    own: &[Rotation3<f64>; 4],
    other: &[Rotation3<f64>; 4],
) -> Record {
    let mut out = apply_rotations(r, &own.map(Some));
    let mut other_leg = *r;
    other_leg.sample.imu = r.sample.other_leg_imu;
    out.sample.other_leg_imu = apply_rotations(&other_leg, &other.map(Some)).sample.imu;
    out
}

/// The six quarter and half turns about the sensor's x, y and z axes (the
/// mountings a user gets by clipping a sensor on the wrong way round).
pub fn axis_turns() -> [Rotation3<f64>; 6] {
    let half_pi = core::f64::consts::FRAC_PI_2;
    let pi = core::f64::consts::PI;
    [
        Rotation3::from_axis_angle(&Vector3::x_axis(), half_pi),
        Rotation3::from_axis_angle(&Vector3::x_axis(), pi),
        Rotation3::from_axis_angle(&Vector3::y_axis(), half_pi),
        Rotation3::from_axis_angle(&Vector3::y_axis(), pi),
        Rotation3::from_axis_angle(&Vector3::z_axis(), half_pi),
        Rotation3::from_axis_angle(&Vector3::z_axis(), pi),
    ]
}

/// Adds `offset` seconds to every time stamp (a trial whose clock starts at
/// 1000 s, or at a Unix time).
pub fn shift_time(records: &mut [Record], offset: f64) {
    for r in records {
        r.sample.t += offset;
    }
}

/// Moves every time stamp by a seeded uniformly random amount in
/// `[-max_s, max_s]` (clock jitter of a wireless or USB-polled sensor). Only
/// the stamps move, not the readings: a check that a method tolerates
/// irregular stamps (no sample refused, no collapse), not that it is
/// unchanged. `max_s` below half the sample period keeps the order.
pub fn jitter_times(records: &mut [Record], max_s: f64, seed: u64) {
    let mut state = seed;
    for r in records {
        r.sample.t += max_s * (2.0 * uniform01(&mut state) - 1.0);
    }
}
