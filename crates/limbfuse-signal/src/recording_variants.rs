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

/// Adds `count` single-sample spikes of `+-amplitude` rad/s (seeded random
/// sign) to the z axis of this leg's thigh, shank or foot gyroscope (seeded
/// random choice) at seeded random rows with `t >= from` that have that
/// gyroscope: a sensor's bus or conversion glitch that stays within the
/// range and below a jump bound (docs/RESULTS.md, "Single-sample gyroscope
/// spikes"). Returns the rows changed; a row is drawn at most once.
pub fn add_gyro_spikes(
    records: &mut [Record],
    count: usize,
    amplitude: f64,
    from: f64,
    seed: u64,
) -> std::vec::Vec<usize> {
    let candidates: std::vec::Vec<usize> = (0..records.len())
        .filter(|&i| records[i].sample.t >= from)
        .collect();
    let mut state = seed;
    let mut rows = std::vec::Vec::with_capacity(count);
    let mut tries = 0;
    while rows.len() < count.min(candidates.len()) && tries < 100 * count.max(1) {
        tries += 1;
        let pick = candidates[((uniform01(&mut state) * candidates.len() as f64) as usize)
            .min(candidates.len() - 1)];
        let segment = 1 + ((uniform01(&mut state) * 3.0) as usize).min(2);
        let sign = if uniform01(&mut state) < 0.5 {
            -1.0
        } else {
            1.0
        };
        if rows.contains(&pick) {
            continue;
        }
        if let Some(g) = records[pick].sample.imu[segment].gyr.as_mut() {
            g.z += sign * amplitude;
            rows.push(pick);
        }
    }
    rows.sort_unstable();
    rows
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::ImuSample;

    #[test]
    fn gyro_spikes_change_one_axis_of_the_drawn_rows_only() {
        let mut records: std::vec::Vec<Record> = (0..500)
            .map(|k| {
                let mut r = Record::default();
                r.sample.t = k as f64 * 0.01;
                for imu in &mut r.sample.imu {
                    *imu = ImuSample {
                        gyr: Some(Vector3::new(0.1, 0.2, 0.3)),
                        ..ImuSample::default()
                    };
                }
                r
            })
            .collect();
        let before = records.clone();
        let rows = add_gyro_spikes(&mut records, 20, 3.0, 2.0, 5);
        assert_eq!(rows.len(), 20);
        assert_eq!(rows, add_gyro_spikes(&mut before.clone(), 20, 3.0, 2.0, 5));
        for (i, (a, b)) in records.iter().zip(&before).enumerate() {
            let changed: std::vec::Vec<usize> = (0..4)
                .filter(|&s| a.sample.imu[s].gyr != b.sample.imu[s].gyr)
                .collect();
            if rows.contains(&i) {
                assert!(a.sample.t >= 2.0);
                assert_eq!(changed.len(), 1, "row {i}");
                let s = changed[0];
                assert!((1..4).contains(&s));
                let d = a.sample.imu[s].gyr.unwrap() - b.sample.imu[s].gyr.unwrap();
                assert_eq!((d.x, d.y), (0.0, 0.0));
                assert!((d.z.abs() - 3.0).abs() < 1e-12);
            } else {
                assert!(changed.is_empty(), "row {i}");
            }
        }
    }
}
