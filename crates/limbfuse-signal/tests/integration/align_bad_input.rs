//! Alignment of bad input: typed errors that name the segment, never a panic.

use limbfuse_core::{Record, Segment};
use limbfuse_io::TrialMeta;
use limbfuse_signal::align::{
    estimate_alignment, rotations_from_metadata, AlignError, AlignOptions,
};
use limbfuse_sim::{Motion, Mounting, WalkingConfig, WalkingSimulator};
use nalgebra::Vector3;

fn walk(seconds: f64) -> Vec<Record> {
    let cfg = WalkingConfig {
        duration_s: seconds,
        mounting: Mounting::Random,
        seed: 11,
        ..Default::default()
    };
    WalkingSimulator::new(cfg).unwrap().collect()
}

fn opts() -> AlignOptions {
    AlignOptions::default()
}

#[test]
fn empty_and_imu_free_trials() {
    assert_eq!(estimate_alignment(&[], &opts()), Err(AlignError::NoSamples));
    let mut rec = walk(5.0);
    for r in &mut rec {
        r.sample.imu = Default::default();
    }
    let e = estimate_alignment(&rec, &opts()).unwrap_err();
    assert_eq!(e, AlignError::NoImu);
    assert!(e.to_string().contains("no IMU data"), "{e}");
}

#[test]
fn standing_still_is_not_walking() {
    let cfg = WalkingConfig {
        duration_s: 5.0,
        motion: Motion::Stand,
        mounting: Mounting::Random,
        ..Default::default()
    };
    let rec: Vec<Record> = WalkingSimulator::new(cfg).unwrap().collect();
    let e = estimate_alignment(&rec, &opts()).unwrap_err();
    assert!(
        matches!(e, AlignError::NoWalking { walking_s, needed_s } if walking_s == 0.0 && needed_s == 3.0),
        "{e:?}"
    );
    let msg = e.to_string();
    println!("{msg}");
    assert!(
        msg.starts_with("no walking found: 0.0 s of stride-periodic leg motion"),
        "{msg}"
    );
    // Nothing to align, `partial` or not.
    let e = estimate_alignment(
        &rec,
        &AlignOptions {
            partial: true,
            ..opts()
        },
    )
    .unwrap_err();
    assert!(matches!(e, AlignError::NoWalking { .. }), "{e:?}");
}

/// Walking, but the thigh sensor never rotates (a sensor left on the table):
/// the walking comes from the shank and foot, the thigh is refused by name.
#[test]
fn a_sensor_that_never_rotates_is_named() {
    let mut rec = walk(10.0);
    let still: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        duration_s: 10.0,
        motion: Motion::Stand,
        mounting: Mounting::Random,
        ..Default::default()
    })
    .unwrap()
    .collect();
    let th = Segment::Thigh.index();
    for (r, s) in rec.iter_mut().zip(&still) {
        r.sample.imu[th] = s.sample.imu[th];
    }
    let e = estimate_alignment(&rec, &opts()).unwrap_err();
    assert!(
        matches!(e, AlignError::TooLittleMotion { segment: Segment::Thigh, gyro_rms, .. } if gyro_rms > 0.0 && gyro_rms < 0.05),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.starts_with("thigh: not enough motion to identify the axis: gyro RMS"),
        "{msg}"
    );
    // Partial: the thigh and the trunk (which needs the thigh) are listed,
    // shank and foot aligned.
    let a = estimate_alignment(
        &rec,
        &AlignOptions {
            partial: true,
            ..opts()
        },
    )
    .unwrap();
    let skipped: Vec<Segment> = a.skipped.iter().map(|(s, _)| *s).collect();
    assert_eq!(skipped, [Segment::Thigh, Segment::Trunk]);
    assert!(a.per_segment[Segment::Shank.index()].is_some());
    assert!(a.per_segment[Segment::Foot.index()].is_some());
    assert!(a.skipped[1]
        .1
        .to_string()
        .contains("needs an aligned thigh sensor (thigh: not enough motion"));
}

#[test]
fn a_missing_gyro_channel_names_the_segment() {
    let mut rec = walk(10.0);
    for r in &mut rec {
        r.sample.imu[Segment::Shank.index()].gyr = None;
    }
    let e = estimate_alignment(&rec, &opts()).unwrap_err();
    assert_eq!(
        e,
        AlignError::NoGyro {
            segment: Segment::Shank
        }
    );
    assert_eq!(
        e.to_string(),
        "shank: no gyro samples (the axis is found from the angular rate)"
    );
    // With `partial`, the others are still aligned.
    let a = estimate_alignment(
        &rec,
        &AlignOptions {
            partial: true,
            ..opts()
        },
    )
    .unwrap();
    assert!(a.per_segment[Segment::Shank.index()].is_none());
    assert!(a.per_segment[Segment::Thigh.index()].is_some());
    assert!(a.per_segment[Segment::Foot.index()].is_some());
    assert!(a.per_segment[Segment::Trunk.index()].is_some());
    let meta = a.metadata();
    assert!(meta
        .iter()
        .any(|(k, v)| k == "shank_align_skipped" && v.starts_with("shank: no gyro")));
}

#[test]
fn missing_accelerometer_and_trunk_without_thigh() {
    let mut rec = walk(10.0);
    for r in &mut rec {
        r.sample.imu[Segment::Foot.index()].acc = None;
    }
    let e = estimate_alignment(&rec, &opts()).unwrap_err();
    assert_eq!(
        e,
        AlignError::NoAcc {
            segment: Segment::Foot
        }
    );
    let mut rec = walk(10.0);
    for r in &mut rec {
        r.sample.imu[Segment::Thigh.index()] = Default::default();
    }
    let e = estimate_alignment(&rec, &opts()).unwrap_err();
    assert_eq!(e, AlignError::TrunkNeedsThigh { thigh: None });
}

#[test]
fn dropouts_nan_and_bad_time_do_not_panic() {
    let mut rec = walk(15.0);
    // Every third sample missing, a few NaN readings (treated as missing).
    for (k, r) in rec.iter_mut().enumerate() {
        if k % 3 == 0 {
            r.sample.imu = Default::default();
        }
        if k % 97 == 1 {
            r.sample.imu[1].gyr = Some(Vector3::new(f64::NAN, 0.0, 0.0));
            r.sample.imu[2].acc = Some(Vector3::new(0.0, f64::INFINITY, 0.0));
        }
    }
    let a = estimate_alignment(&rec, &opts()).unwrap();
    assert!(a.per_segment.iter().all(Option::is_some));
    let mut bad = walk(2.0);
    bad[10].sample.t = bad[9].sample.t;
    assert_eq!(estimate_alignment(&bad, &opts()), Err(AlignError::BadTime));
    bad[10].sample.t = f64::NAN;
    assert_eq!(estimate_alignment(&bad, &opts()), Err(AlignError::BadTime));
    // Very short trials: an error, not a panic.
    for n in [1, 2, 5, 50] {
        let short = walk(1.0);
        assert!(estimate_alignment(&short[..n], &opts()).is_err(), "{n}");
    }
}

#[test]
fn bad_options_and_metadata() {
    let e = estimate_alignment(
        &walk(1.0),
        &AlignOptions {
            quiet_min_s: -1.0,
            ..opts()
        },
    );
    assert!(
        matches!(
            e,
            Err(AlignError::BadOption {
                name: "quiet_min_s",
                ..
            })
        ),
        "{e:?}"
    );
    let e = estimate_alignment(
        &walk(1.0),
        &AlignOptions {
            mean_angle_rad: [0.0, f64::NAN, 0.0, 0.0],
            ..opts()
        },
    );
    assert!(
        matches!(
            e,
            Err(AlignError::BadOption {
                name: "mean_angle_rad[1]",
                ..
            })
        ),
        "{e:?}"
    );
    for bad in [-0.01, f64::NAN, 1.0] {
        let e = estimate_alignment(
            &walk(1.0),
            &AlignOptions {
                gyro_axis_max_tilt_rad: bad,
                ..opts()
            },
        );
        assert!(
            matches!(
                e,
                Err(AlignError::BadOption {
                    name: "gyro_axis_max_tilt_rad",
                    ..
                })
            ),
            "{bad}: {e:?}"
        );
    }
    let mut meta = TrialMeta::new();
    meta.set("thigh_align_quat", "1 0 0");
    let e = rotations_from_metadata(&meta).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("metadata `thigh_align_quat`: expected four finite numbers"),
        "{e}"
    );
    meta.set("thigh_align_quat", "2 0 0 0");
    assert!(rotations_from_metadata(&meta).is_err());
    meta.set("thigh_align_quat", "1 0 0 0");
    let r = rotations_from_metadata(&meta).unwrap();
    assert!(r[1].is_some() && r[0].is_none());
}

/// Issue 14 (leg detection, `leg_side.rs`): the leg is detected from the
/// aligned thigh and shank gyros sample by sample; a trial whose thigh gyro
/// has missing cells, or that has no shank sensor, or whose thigh could not
/// be aligned, must give a detection (or "undetermined"), never a panic.
#[test]
fn issue_14_leg_side_with_missing_gyro_cells_and_an_absent_sensor() {
    let (th, sh) = (Segment::Thigh.index(), Segment::Shank.index());
    // Thigh gyro missing in two samples of five, shank gyro in every seventh.
    let mut rec = walk(15.0);
    for (k, r) in rec.iter_mut().enumerate() {
        if k % 5 < 2 {
            r.sample.imu[th].gyr = None;
        }
        if k % 7 == 3 {
            r.sample.imu[sh].gyr = None;
        }
    }
    let a = estimate_alignment(&rec, &opts()).unwrap();
    let leg = a.leg.unwrap();
    println!("missing gyro cells: leg {:?} ({:+.2})", leg.leg, leg.score);
    assert_eq!(leg.leg, Some(limbfuse_core::Leg::Right));
    // No shank sensor at all: detected from the thigh alone.
    let mut no_shank = walk(15.0);
    for r in &mut no_shank {
        r.sample.imu[sh] = Default::default();
    }
    let a = estimate_alignment(&no_shank, &opts()).unwrap();
    assert!(a.per_segment[sh].is_none());
    let leg = a.leg.unwrap();
    println!("no shank: leg {:?} ({:+.2})", leg.leg, leg.score);
    assert!(leg.per_segment[sh].is_none() && leg.per_segment[th].is_some());
    // A thigh that never rotates is skipped (`partial`); the shank alone
    // decides, and the thigh's readings are not used.
    let mut still_thigh = walk(15.0);
    let g = still_thigh[0].sample.imu[th].acc;
    for r in &mut still_thigh {
        r.sample.imu[th].gyr = Some(Vector3::zeros());
        r.sample.imu[th].acc = g;
    }
    let a = estimate_alignment(
        &still_thigh,
        &AlignOptions {
            partial: true,
            ..opts()
        },
    )
    .unwrap();
    assert!(a.per_segment[th].is_none());
    let leg = a.leg.unwrap();
    println!("thigh skipped: leg {:?} ({:+.2})", leg.leg, leg.score);
    assert!(leg.per_segment[th].is_none() && leg.per_segment[sh].is_some());
}

/// Session 30: nothing stopped an alignment before its end (Python's Ctrl-C
/// waited 5 s of CPU per hour). With a cancellation hook that says stop,
/// it ends with `Cancelled`, without one (the CLI) it aligns as before.
#[test]
fn a_cancellation_hook_stops_the_alignment() {
    let rec = walk(30.0);
    let stop = AlignOptions {
        cancel: Some(|| true),
        ..opts()
    };
    assert_eq!(estimate_alignment(&rec, &stop), Err(AlignError::Cancelled));
    let go = AlignOptions {
        cancel: Some(|| false),
        ..opts()
    };
    assert_eq!(
        estimate_alignment(&rec, &go),
        estimate_alignment(&rec, &opts())
    );
    assert!(estimate_alignment(&rec, &go).is_ok());
}
