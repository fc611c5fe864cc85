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

/// A time-stamp glitch of [`add_time_glitches`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeGlitch {
    /// The row is written twice (a logger that wrote a packet again).
    Duplicate,
    /// The row and the next are written in the wrong order (each with its
    /// own stamp: packets that arrived out of order).
    Swap,
    /// The row's stamp is [`LATE_STAMP_S`] late (a clock read glitch).
    Late,
}

/// How late a [`TimeGlitch::Late`] stamp is (s).
pub const LATE_STAMP_S: f64 = 0.5;

/// Adds `count` time-stamp glitches at seeded random rows (at least three
/// rows apart, none in the first or last row), cycling through
/// [`TimeGlitch::Duplicate`], [`TimeGlitch::Swap`] and [`TimeGlitch::Late`]:
/// a recording whose time does not increase (the readers refuse it; `limbfuse
/// repair-time` repairs it). Returns each glitch's row (in the output, the
/// first of the two rows of a duplicate or a swap) and kind, in row order.
pub fn add_time_glitches(
    records: &mut std::vec::Vec<Record>,
    count: usize,
    seed: u64,
) -> std::vec::Vec<(usize, TimeGlitch)> {
    let n = records.len();
    let mut state = seed;
    let mut rows: std::vec::Vec<usize> = std::vec::Vec::with_capacity(count);
    let mut tries = 0;
    while rows.len() < count && n > 8 && tries < 100 * count.max(1) {
        tries += 1;
        let pick = 1 + ((uniform01(&mut state) * (n - 3) as f64) as usize).min(n - 4);
        if rows.iter().all(|&r| r.abs_diff(pick) >= 3) {
            rows.push(pick);
        }
    }
    let kinds = [TimeGlitch::Duplicate, TimeGlitch::Swap, TimeGlitch::Late];
    let mut glitches: std::vec::Vec<(usize, TimeGlitch)> = rows
        .iter()
        .enumerate()
        .map(|(k, &r)| (r, kinds[k % 3]))
        .collect();
    glitches.sort_unstable_by_key(|g| g.0);
    // from the last row back, so that an inserted row moves no later pick
    for &(r, kind) in glitches.iter().rev() {
        match kind {
            TimeGlitch::Duplicate => records.insert(r + 1, records[r]),
            TimeGlitch::Swap => records.swap(r, r + 1),
            TimeGlitch::Late => records[r].sample.t += LATE_STAMP_S,
        }
    }
    // rows in the output: every duplicate before a glitch shifts it by one
    let mut shift = 0;
    for g in &mut glitches {
        g.0 += shift;
        if g.1 == TimeGlitch::Duplicate {
            shift += 1;
        }
    }
    glitches
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::ImuSample;

    #[test]
    fn time_glitches_are_one_duplicate_one_swap_and_one_late_stamp_in_turn() {
        let records: std::vec::Vec<Record> = (0..300)
            .map(|k| {
                let mut r = Record::default();
                r.sample.t = k as f64 * 0.01;
                r.sample.encoder[1] = Some(k as f64);
                r
            })
            .collect();
        let mut out = records.clone();
        let g = add_time_glitches(&mut out, 6, 3);
        assert_eq!(g.len(), 6);
        assert_eq!(out.len(), 302);
        let mut again = records.clone();
        assert_eq!(add_time_glitches(&mut again, 6, 3), g);
        for &(r, kind) in &g {
            let (a, b) = (&out[r].sample, &out[r + 1].sample);
            match kind {
                TimeGlitch::Duplicate => assert_eq!((a.t, a.encoder), (b.t, b.encoder)),
                TimeGlitch::Swap => {
                    assert!(a.t > b.t);
                    assert_eq!(a.encoder[1].unwrap(), b.encoder[1].unwrap() + 1.0);
                    assert!((a.t - 0.01 * a.encoder[1].unwrap()).abs() < 1e-9);
                }
                TimeGlitch::Late => {
                    let k = a.encoder[1].unwrap();
                    assert!((a.t - (0.01 * k + LATE_STAMP_S)).abs() < 1e-9);
                }
            }
        }
        // every row but the late ones keeps its own stamp
        let late: std::vec::Vec<usize> = g
            .iter()
            .filter(|x| x.1 == TimeGlitch::Late)
            .map(|x| x.0)
            .collect();
        let unchanged = (0..out.len()).filter(|i| !late.contains(i)).all(|i| {
            let k = out[i].sample.encoder[1].unwrap();
            (out[i].sample.t - 0.01 * k).abs() < 1e-9
        });
        assert!(unchanged);
        for kind in [TimeGlitch::Duplicate, TimeGlitch::Swap, TimeGlitch::Late] {
            assert_eq!(g.iter().filter(|x| x.1 == kind).count(), 2);
        }
    }

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
