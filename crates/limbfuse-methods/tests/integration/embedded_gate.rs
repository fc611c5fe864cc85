//! A controller without `std` builds an estimator from its parameters and
//! puts it behind `limbfuse_core::Gated`: its estimates must be `limbfuse
//! estimate`'s ([`limbfuse_methods::build`]) bit for bit, glitches included
//! (the two share `limbfuse_core::EstimatorGate`).

use limbfuse_core::{Estimator, Gated, Record, SensorRanges};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainGeometry, ChainParams};
use limbfuse_estimators::segment_kf::{GlobalKf, GlobalKfParams, MarkovJumpKf, MarkovJumpKfParams};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_methods::{MethodName, MethodSpec};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

/// 8 s of simulated walking with a driver's faults: a NaN gyro cell, a
/// knee encoder 2 pi off, a saturated shank gyro, a dropped thigh IMU and
/// a repeated time stamp.
fn glitched_walk() -> (TrialMeta, Vec<Record>) {
    let cfg = WalkingConfig {
        seed: 33,
        duration_s: 8.0,
        ..WalkingConfig::default()
    };
    let sim = WalkingSimulator::new(cfg).unwrap();
    let mut meta = TrialMeta::trial_v1();
    for (k, v) in sim.metadata() {
        meta.set(&k, &v);
    }
    let mut recs: Vec<Record> = sim.collect();
    if let Some(g) = recs[300].sample.imu[1].gyr.as_mut() {
        g.z = f64::NAN;
    }
    recs[350].sample.encoder[1] = recs[350].sample.encoder[1].map(|x| x + std::f64::consts::TAU);
    for r in &mut recs[400..405] {
        if let Some(g) = r.sample.imu[2].gyr.as_mut() {
            g.z = 2000f64.to_radians();
        }
    }
    recs[450].sample.imu[1] = Default::default();
    let repeated = recs[500];
    recs.insert(501, repeated);
    (meta, recs)
}

/// Steps both over `recs`: equal results (estimates bit for bit, the same
/// refusals), equal diagnostic names and header lines, at least
/// `min_rejected` readings rejected.
fn same_as_build(
    method: MethodName,
    mut ours: impl Estimator,
    meta: &TrialMeta,
    recs: &[Record],
    min_rejected: u64,
) {
    let spec = MethodSpec::defaults(method).unwrap();
    let mut cli = limbfuse_methods::build(&spec, meta, &TrialLayout::walking()).unwrap();
    assert_eq!(ours.diagnostic_names(), cli.diagnostic_names());
    let (mut a, mut b) = (String::new(), String::new());
    ours.describe_parameters(&mut a).unwrap();
    cli.describe_parameters(&mut b).unwrap();
    assert_eq!(a, b);
    let mut refused = 0;
    for r in recs {
        let (x, y) = (ours.step(&r.sample), cli.step(&r.sample));
        refused += usize::from(x.is_err());
        assert_eq!(x, y, "{} at t = {}", method.name(), r.sample.t);
    }
    assert_eq!(refused, 1);
    assert_eq!(ours.rejected_readings(), cli.rejected_readings());
    assert!(ours.rejected_readings().iter().sum::<u64>() >= min_rejected);
}

#[test]
fn gated_estimators_built_from_params_equal_the_method_layer() {
    let (meta, recs) = glitched_walk();
    let r = SensorRanges::default();
    let mjls = MarkovJumpKf::new(MarkovJumpKfParams::default()).unwrap();
    same_as_build(MethodName::Mjls, Gated::new(mjls, r), &meta, &recs, 4);
    let global = GlobalKf::new(GlobalKfParams::default()).unwrap();
    same_as_build(MethodName::Global, Gated::new(global, r), &meta, &recs, 4);
    // the walking simulator's body: its segment lengths and IMU mounts
    let body = meta.body().unwrap();
    let mut geometry = ChainGeometry::from_height(body.height.unwrap());
    geometry.thigh_length = body.thigh_length.unwrap();
    geometry.shank_length = body.shank_length.unwrap();
    for (p, m) in geometry.imu_position.iter_mut().zip(body.imu_position) {
        *p = m.unwrap();
    }
    let chain = ChainEkf::new(ChainParams::default(), geometry, 9.81).unwrap();
    same_as_build(MethodName::Chain, Gated::new(chain, r), &meta, &recs, 4);
}

/// `gait-events` keeps a foot gyroscope clipped at its full scale (the
/// estimator says so, `Estimator::keeps_clipped_gyro`, and `Gated` drops
/// the clipping test): a controller that puts it behind its IMUs' ranges
/// gets `limbfuse estimate`'s events. Before, only the method layer knew;
/// the same gate made every clipped swing reading missing (embedding audit,
/// session 33: the estimates differed from the 1st clipped swing on).
#[test]
fn gait_events_behind_the_gate_keeps_a_clipped_foot_gyro() {
    let (mut meta, mut recs) = glitched_walk();
    // a 250 deg/s gyroscope, its range stated (as the clipped-gyro CLI test)
    let full_scale = 250f64.to_radians();
    meta.set(
        limbfuse_methods::gated::GYRO_RANGE_KEY,
        full_scale.to_string(),
    );
    let foot = limbfuse_core::Segment::Foot.index();
    let mut clipped = 0;
    for r in &mut recs {
        for imu in &mut r.sample.imu {
            if let Some(g) = imu.gyr.as_mut() {
                for v in g.iter_mut() {
                    if v.abs() > full_scale {
                        *v = v.signum() * full_scale;
                        clipped += 1;
                    }
                }
            }
        }
    }
    assert!(clipped > 20, "{clipped} clipped readings");
    let ranges = limbfuse_methods::gated::sensor_ranges(&meta).unwrap();
    assert_eq!(ranges.gyro_full_scale_rad_s, Some(full_scale));
    use limbfuse_estimators::gait_events::{FootSource, GaitEvents, GaitEventsParams};
    let events = GaitEvents::new(
        GaitEventsParams::default(),
        [None, Some(FootSource::OwnLeg)],
    );
    let gated = Gated::new(events.unwrap(), ranges);
    assert!(recs.iter().any(|r| r.sample.imu[foot].gyr.is_some()));
    same_as_build(MethodName::GaitEvents, gated, &meta, &recs, 0);
}
