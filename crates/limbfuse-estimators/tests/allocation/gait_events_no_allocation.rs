//! `gait-events` and `lowback-speed` allocate nothing per step (the
//! counting-allocator pattern of `no_allocation.rs`, in their own binary so
//! the global counter sees no other test's allocations).

use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_estimators::gait_events::{FootSource, GaitEvents, GaitEventsParams};
use limbfuse_estimators::lowback_speed::{LowbackParams, LowbackSpeed};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

use crate::counting_alloc::allocations;

#[test]
fn gait_estimators_step_without_allocating() {
    let cfg = WalkingConfig {
        duration_s: 8.0,
        seed: 9,
        ..WalkingConfig::default()
    };
    let mut records: Vec<Record> = WalkingSimulator::new(cfg).unwrap().collect();
    let foot = Segment::Foot.index();
    for (k, r) in records.iter_mut().enumerate() {
        r.sample.other_leg_imu[foot] = r.sample.imu[foot];
        if k % 19 == 4 {
            r.sample.imu[foot].gyr = None;
            r.sample.imu[0].acc = None;
        }
    }
    let mut cases: Vec<Box<dyn Estimator>> = vec![
        Box::new(
            GaitEvents::new(
                GaitEventsParams::default(),
                [Some(FootSource::OtherLeg), Some(FootSource::OwnLeg)],
            )
            .unwrap(),
        ),
        // A foot IMU on the left, a shank IMU on the right (issue 19 item 3).
        Box::new(
            GaitEvents::new(
                GaitEventsParams::default(),
                [Some(FootSource::OtherLeg), Some(FootSource::OwnShank)],
            )
            .unwrap(),
        ),
        Box::new(LowbackSpeed::new(LowbackParams::default())),
    ];
    for e in cases.iter_mut() {
        let before = allocations();
        let mut n = 0usize;
        for r in &records {
            n += usize::from(e.step(&r.sample).unwrap().speed.is_some());
        }
        let after = allocations();
        assert!(n > 0, "{} estimated no speed", e.name());
        assert_eq!(
            after - before,
            0,
            "{} allocated {} times",
            e.name(),
            after - before
        );
    }
}
