//! Tests of [`super::SampleGate`].

use super::*;
use nalgebra::Vector3;

/// All four IMUs and the encoders reading plausible walking values.
pub(crate) fn walking_sample() -> Sample {
    let mut s = Sample::empty(1.0);
    for imu in s.imu.iter_mut() {
        imu.gyr = Some(Vector3::new(0.1, -0.2, 3.0));
        imu.acc = Some(Vector3::new(2.0, 9.5, -0.3));
    }
    s.encoder = [Some(0.3), Some(1.2), Some(-0.2)];
    s.other_leg_imu = s.imu;
    s
}

#[test]
fn issue_18_incomplete_vectors_are_screened_per_cell() {
    let mut g = SampleGate::new(SensorRanges::default());
    let s = walking_sample();
    assert_eq!(g.screen(&s), s);
    let mut p = walking_sample();
    p.t = 1.01;
    p.imu[0].gyr = None;
    p.imu[0].gyr_partial = [None, None, Some(3.1)];
    p.imu[1].acc = None;
    p.imu[1].acc_partial = [Some(2.0), Some(9.4), None];
    // plausible partial vectors pass unchanged
    assert_eq!(g.screen(&p), p);
    assert_eq!(g.rejections().total(), 0);
    p.t = 1.02;
    p.imu[0].gyr_partial = [Some(0.1), None, Some(1e300)];
    p.imu[1].acc_partial = [Some(f64::NAN), Some(9.4), None];
    p.imu[2].gyr = None;
    p.imu[2].gyr_partial = [None, None, Some(34.9)]; // clipped
    p.imu[3].gyr = None;
    p.imu[3].gyr_partial = [None, Some(-0.2), Some(3.0 + 15.0)]; // a jump (foot: 101 rad/s allowed)
    let out = g.screen(&p);
    assert_eq!(out.imu[0].gyr_partial, [None; 3]);
    assert_eq!(out.imu[1].acc_partial, [None; 3]);
    assert_eq!(out.imu[2].gyr_partial, [None; 3]);
    assert_eq!(out.imu[3].gyr_partial, p.imu[3].gyr_partial);
    let r = *g.rejections();
    assert_eq!((r.gyro, r.acc, r.clipped, r.jumps), (2, 1, 1, 0));
    p.t = 1.03;
    p.imu[1].gyr = None;
    p.imu[1].gyr_partial = [None, None, Some(3.0 + 25.0)]; // thigh: beyond 21 rad/s in 10 ms
    let out = g.screen(&p);
    assert_eq!(out.imu[1].gyr_partial, [None; 3]);
    assert_eq!(g.rejections().jumps, 1);
}

#[test]
fn readings_within_range_pass_unchanged() {
    let mut g = SampleGate::new(SensorRanges::default());
    let s = walking_sample();
    assert_eq!(g.screen(&s), s);
    assert_eq!(g.rejections().total(), 0);
    assert_eq!(g.rejections().first_t, None);
}

#[test]
fn a_glitch_on_one_axis_drops_that_sensor_only_and_is_counted() {
    let mut g = SampleGate::new(SensorRanges::default());
    let mut s = walking_sample();
    s.imu[1].gyr = Some(Vector3::new(0.1, 1e300, 3.0));
    s.imu[2].acc = Some(Vector3::new(-1e308, 9.5, 0.0));
    s.encoder[1] = Some(f64::INFINITY);
    let out = g.screen(&s);
    assert_eq!(out.imu[1].gyr, None);
    assert_eq!(out.imu[1].acc, s.imu[1].acc);
    assert_eq!(out.imu[2].acc, None);
    assert_eq!(out.imu[2].gyr, s.imu[2].gyr);
    assert_eq!(out.encoder, [Some(0.3), None, Some(-0.2)]);
    let r = g.rejections();
    assert_eq!((r.gyro, r.acc, r.encoder, r.first_t), (1, 1, 1, Some(1.0)));
    // The other leg's IMUs (two-leg gait-event trials) are screened too.
    let mut two = walking_sample();
    two.other_leg_imu[3].gyr = Some(Vector3::new(0.0, 0.0, -1e300));
    let out = g.screen(&two);
    assert_eq!(out.other_leg_imu[3].gyr, None);
    assert_eq!(out.imu[3].gyr, two.imu[3].gyr);
    assert_eq!(g.rejections().gyro, 2);
    // The first time stays the first.
    let mut later = s;
    later.t = 2.0;
    g.screen(&later);
    assert_eq!(g.rejections().first_t, Some(1.0));
    assert_eq!(g.rejections().total(), 7);
}

#[test]
fn nan_is_rejected_and_the_limit_itself_is_accepted() {
    let ranges = SensorRanges {
        gyro_rad_s: 10.0,
        acc_m_s2: 50.0,
        encoder_rad: 1.0,
        gyro_full_scale_rad_s: None,
        acc_full_scale_m_s2: None,
    };
    let mut g = SampleGate::new(ranges);
    let mut s = walking_sample();
    s.imu[0].gyr = Some(Vector3::new(10.0, -10.0, 0.0));
    s.imu[0].acc = Some(Vector3::new(f64::NAN, 0.0, 0.0));
    s.encoder = [Some(1.0), Some(-1.0), Some(1.0000001)];
    let out = g.screen(&s);
    assert!(out.imu[0].gyr.is_some());
    assert!(out.imu[0].acc.is_none());
    assert_eq!(out.encoder, [Some(1.0), Some(-1.0), None]);
}

#[test]
fn issue_18_a_clipped_reading_is_rejected_from_its_first_sample() {
    let mut g = SampleGate::new(SensorRanges::default());
    let fs = 2000f64.to_radians();
    // A foot gyroscope saturating at full scale: within the range (and
    // within the foot's jump bound), but clipped.
    let mut s = walking_sample();
    s.imu[3].gyr = Some(Vector3::new(fs, 3.0, -fs));
    let out = g.screen(&s);
    assert_eq!(out.imu[3].gyr, None);
    assert_eq!(out.imu[2].gyr, s.imu[2].gyr);
    let r = *g.rejections();
    assert_eq!((r.gyro, r.clipped), (1, 1));
    // Just below 99.9 % of full scale passes; a clipped accelerometer (a
    // heel strike at 16 g) is rejected too since 2026-12-06, from 97 % of
    // its full scale (module documentation), on one axis or on a cell of an
    // incomplete vector.
    let mut t = walking_sample();
    t.t = 2.0;
    t.imu[0].gyr = Some(Vector3::new(0.998 * fs, 0.0, 0.0));
    t.imu[0].acc = Some(Vector3::new(0.0, 16.0 * 9.80665, 0.0));
    t.imu[1].acc = Some(Vector3::new(0.0, 0.969 * 16.0 * 9.80665, 0.0));
    t.imu[2].acc = None;
    t.imu[2].acc_partial = [None, Some(-0.97 * 16.0 * 9.80665), Some(1.0)];
    let out = g.screen(&t);
    assert_eq!(out.imu[0].gyr, t.imu[0].gyr);
    assert_eq!(out.imu[0].acc, None);
    assert_eq!(out.imu[1].acc, t.imu[1].acc);
    assert_eq!(out.imu[2].acc_partial, [None; 3]);
    let r = *g.rejections();
    assert_eq!((r.acc, r.clipped), (2, 3));
}

#[test]
fn default_ranges_are_the_datasheet_full_scales_with_margin() {
    let r = SensorRanges::default();
    // 2000 deg/s = 34.9 rad/s; 16 g = 156.9 m/s^2; each + 15 %.
    assert!((r.gyro_rad_s - 40.142).abs() < 1e-3, "{}", r.gyro_rad_s);
    assert!((r.acc_m_s2 - 180.442).abs() < 1e-3, "{}", r.acc_m_s2);
}

/// The thigh accelerometer's vector rejected at each of `n` samples at
/// 100 Hz: the accelerometer reads `acc(k)`, the gyroscope `gyr(k)`.
fn acc_rejected(
    n: usize,
    acc: impl Fn(usize) -> Vector3<f64>,
    gyr: impl Fn(usize) -> Option<Vector3<f64>>,
) -> Vec<bool> {
    let mut gate = SampleGate::new(SensorRanges::default());
    (0..n)
        .map(|k| {
            let mut s = Sample::empty(k as f64 * 0.01);
            s.imu[1].acc = Some(acc(k));
            s.imu[1].gyr = gyr(k);
            gate.screen(&s).imu[1].acc.is_none()
        })
        .collect()
}

/// A gyroscope reading with white noise of about 0.01 rad/s and a
/// 1.5 deg/s bias: a still segment.
fn still_gyro(k: usize) -> Option<Vector3<f64>> {
    let n = |j: usize| 0.01 * (((k * 7 + j * 13) % 11) as f64 / 5.0 - 1.0);
    Some(Vector3::new(0.026 + n(0), n(1), -0.02 + n(2)))
}

#[test]
fn issue_18_a_still_accelerometer_recorded_at_0_01_g_is_not_stuck() {
    // The knee rig's files: 0.01 g steps, a still segment repeats its
    // vector for seconds while its gyroscope shows noise and bias.
    let q = 0.0981;
    let rig = Vector3::new(12.0 * q, 100.0 * q, -3.0 * q);
    let r = acc_rejected(500, |_| rig, still_gyro);
    assert!(r.iter().all(|&x| !x), "{r:?}");
    // Turning about the specific force itself (about the vertical)
    // changes nothing it measures.
    let about_g = |k: usize| Some(rig.normalize() * (2.0 + (k as f64).sin()));
    assert!(acc_rejected(500, |_| rig, about_g).iter().all(|&x| !x));
}

#[test]
fn issue_18_a_frozen_accelerometer_on_a_turning_segment_is_stuck() {
    // Walking: the thigh turns at ~2 rad/s about z; its accelerometer
    // freezes from sample 100 on.
    let frozen = Vector3::new(2.0, 9.5, -0.3);
    let acc = |k: usize| {
        if k >= 100 {
            frozen
        } else {
            Vector3::new(2.0 + 0.01 * k as f64, 9.5, -0.3)
        }
    };
    let gyr = |k: usize| Some(Vector3::new(0.1, 0.0, 2.0 * (k as f64 * 0.06).sin() + 2.5));
    let r = acc_rejected(300, acc, gyr);
    let first = r.iter().position(|&x| x);
    // the repeat rule's 0.1 s (sample 110), the turn long exceeded
    assert_eq!(first, Some(110));
    assert!(r[110..].iter().all(|&x| x));
}

#[test]
fn issue_18_a_frozen_imu_and_an_imu_without_gyroscope_keep_the_repeat_rule() {
    let frozen = Vector3::new(2.0, 9.5, -0.3);
    // the whole IMU frozen: its gyroscope repeats too
    let w = Vector3::new(0.3, -0.1, 1.2);
    let r = acc_rejected(200, |_| frozen, |_| Some(w));
    assert_eq!(r.iter().position(|&x| x), Some(10));
    // no gyroscope: no evidence of stillness, the repeat alone decides
    let r = acc_rejected(200, |_| frozen, |_| None);
    assert_eq!(r.iter().position(|&x| x), Some(10));
    // a gyroscope that stays still, then turns: rejected once the turn
    // predicts 0.5 m/s^2 of change (0.5 rad/s across g: ~0.1 s)
    let gyr = |k: usize| {
        if k < 100 {
            still_gyro(k)
        } else {
            Some(Vector3::new(0.0, 0.0, 0.5))
        }
    };
    let r = acc_rejected(300, |_| frozen, gyr);
    let first = r.iter().position(|&x| x).expect("rejected once turning");
    assert!((105..=115).contains(&first), "{first}");
}
