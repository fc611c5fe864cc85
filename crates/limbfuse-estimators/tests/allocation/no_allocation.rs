//! Per-sample updates allocate nothing (house rule for real-time use): a
//! counting global allocator watches `Estimator::step` of every estimator
//! over a simulated walking trial with dropouts.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_estimators::imm_bslip::{
    ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights, SwayRestart, TouchdownRule,
};
use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_estimators::segment_kf::{
    AccelGate, CommonParams, GlobalKf, GlobalKfParams, LocalKf, LocalKfParams, MarkovJumpKf,
    MarkovJumpKfParams,
};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

use crate::counting_alloc::allocations;

#[test]
fn step_never_allocates() {
    let cfg = WalkingConfig {
        duration_s: 10.0,
        seed: 5,
        ..WalkingConfig::default()
    };
    let mut records: Vec<Record> = WalkingSimulator::new(cfg).unwrap().collect();
    for (k, r) in records.iter_mut().enumerate() {
        if k % 17 == 3 {
            r.sample.imu[2].acc = None;
            r.sample.imu[0].gyr = None;
            r.sample.encoder[1] = None;
        }
    }
    // A B-SLIP IMM over 6 gaits x 3 phases (18 filters): one searched gait
    // and five dynamically similar rescalings (no library search needed).
    let body = limbfuse_models::bslip::BslipParams::default();
    let sim = limbfuse_sim::bslip::step::StepSimulator::new(body);
    let gait: limbfuse_sim::bslip::library::LibraryGait =
        limbfuse_sim::bslip::search::optimise_gait(
            &sim,
            &limbfuse_sim::bslip::library::start_seed(1.0),
            1.0,
            &Default::default(),
        )
        .unwrap()
        .into();
    let tpl = gait.template(&body);
    let library: Vec<_> = [0.85, 0.9, 0.95, 1.0, 1.05, 1.1]
        .iter()
        .map(|s| tpl.rescaled_to_height(tpl.gait.height * s).unwrap())
        .collect();
    let bslip = limbfuse_sim::bslip::trial::simulate_trial(
        &tpl,
        &limbfuse_sim::bslip::trial::BslipTrialConfig::default(),
    );
    for (k, r) in records.iter_mut().enumerate() {
        if let Some(b) = bslip.get(k) {
            // Single dropouts, and a 0.5 s run that stops the bank and
            // restarts it at a sway extremum (`SwayRestart`).
            r.sample.com = if k % 13 == 5 || (150..200).contains(&k) {
                Default::default()
            } else {
                b.sample.com
            };
        }
    }
    // The refined accelerometer test (duration + angular rate) keeps state.
    let gated = CommonParams {
        accel_gate: AccelGate {
            hold_s: 0.01,
            max_rate: 2.0,
        },
        ..CommonParams::default()
    };
    // The IMM with each weight rule and touchdown rule.
    let imm_variants = [
        ImmBslipParams::default(),
        ImmBslipParams {
            weights: ImmWeights::Recursive,
            ..Default::default()
        },
        ImmBslipParams {
            touchdown: TouchdownRule::StepClock,
            ..Default::default()
        },
        ImmBslipParams {
            touchdown: TouchdownRule::Mixed,
            ..Default::default()
        },
    ];
    let mut estimators: Vec<Box<dyn Estimator>> = imm_variants
        .iter()
        .map(|p| Box::new(ImmBslip::new(&library, *p).unwrap()) as Box<dyn Estimator>)
        .collect();
    // The continuous configuration (issue 19): re-targeting at every MS.
    estimators.push(Box::new(
        ImmContinuous::new(&library, ImmBslipParams::default()).unwrap(),
    ));
    // Both, restarted after the gap at a sway extremum.
    estimators.push(Box::new(SwayRestart::new(
        ImmBslip::new(&library, ImmBslipParams::default()).unwrap(),
    )));
    estimators.push(Box::new(SwayRestart::new(
        ImmContinuous::new(&library, ImmBslipParams::default()).unwrap(),
    )));
    estimators.extend::<[Box<dyn Estimator>; 10]>([
        Box::new(GyroIntegration::new()),
        Box::new(AccelInclination::new()),
        Box::new(LocalKf::default()),
        Box::new(MarkovJumpKf::default()),
        Box::new(GlobalKf::default()),
        Box::new(
            LocalKf::new(LocalKfParams {
                common: gated,
                ..LocalKfParams::default()
            })
            .unwrap(),
        ),
        Box::new(
            MarkovJumpKf::new(MarkovJumpKfParams {
                common: gated,
                ..MarkovJumpKfParams::default()
            })
            .unwrap(),
        ),
        Box::new(
            GlobalKf::new(GlobalKfParams {
                common: gated,
                ..GlobalKfParams::default()
            })
            .unwrap(),
        ),
        // Window re-estimates (every 500 samples) run inside `step` too.
        Box::new(KneeSelfAlign::default()),
        Box::new(KneeGyroAxis::new(KneeGyroAxisParams::default()).unwrap()),
    ]);
    for e in estimators.iter_mut() {
        let before = allocations();
        let mut sum = 0.0;
        for r in &records {
            let est = e.step(&r.sample).unwrap();
            sum += est.segment[1].unwrap_or(0.0)
                + est.joint[1].unwrap_or(0.0)
                + est.speed.unwrap_or(0.0);
        }
        let after = allocations();
        assert!(sum.is_finite());
        assert_eq!(
            after - before,
            0,
            "{} allocated {} times over {} steps",
            e.name(),
            after - before,
            records.len()
        );
    }
    // The delay search (session 28) runs at each window's end and, with the
    // shank's readings two rows late, re-pairs the window inside `step`.
    let mut late = records.clone();
    for k in (2..late.len()).rev() {
        let shank = limbfuse_core::Segment::Shank.index();
        late[k].sample.imu[shank] = late[k - 2].sample.imu[shank];
    }
    let delay = KneeSelfAlignParams {
        max_delay: 5,
        ..KneeSelfAlignParams::default()
    };
    let mut gyro_axis = KneeGyroAxisParams::default();
    gyro_axis.axes.max_delay = 5;
    let delayed: [Box<dyn Estimator>; 2] = [
        Box::new(KneeSelfAlign::new(delay).unwrap()),
        Box::new(KneeGyroAxis::new(gyro_axis).unwrap()),
    ];
    for mut e in delayed {
        let before = allocations();
        let mut sum = 0.0;
        for r in &late {
            sum += e.step(&r.sample).unwrap().joint[1].unwrap_or(0.0);
        }
        assert!(sum.is_finite());
        assert_eq!(
            allocations() - before,
            0,
            "{} with the delay search allocated",
            e.name()
        );
    }
}

/// A controller's loop: estimators behind `limbfuse_core::Gated` (the gate
/// `limbfuse estimate` uses), stepped with `step_into` through glitches the
/// gate removes (a NaN, an encoder 2 pi off, a saturated gyro, a refused
/// repeated time), allocate nothing per sample.
#[test]
fn gated_controller_loop_never_allocates() {
    use limbfuse_core::{Estimate, Gated, SensorRanges};
    let cfg = WalkingConfig {
        duration_s: 8.0,
        seed: 6,
        ..WalkingConfig::default()
    };
    let mut records: Vec<Record> = WalkingSimulator::new(cfg).unwrap().collect();
    for (k, r) in records.iter_mut().enumerate() {
        match k % 97 {
            5 => r.sample.imu[1].gyr = r.sample.imu[1].gyr.map(|g| g * f64::NAN),
            6 => r.sample.encoder[1] = r.sample.encoder[1].map(|x| x + std::f64::consts::TAU),
            7 => {
                if let Some(g) = r.sample.imu[2].gyr.as_mut() {
                    g.z = 2000f64.to_radians();
                }
            }
            8 => r.sample.imu[3] = Default::default(),
            _ => {}
        }
    }
    let repeated = records[400];
    records.insert(401, repeated);
    let r = SensorRanges::default();
    let mut loops: [Box<dyn Estimator>; 3] = [
        Box::new(Gated::new(MarkovJumpKf::default(), r)),
        Box::new(Gated::new(GlobalKf::default(), r)),
        Box::new(Gated::new(KneeSelfAlign::default(), r)),
    ];
    for filter in loops.iter_mut() {
        let mut out = Estimate::empty(0.0);
        let before = allocations();
        let mut refused = 0;
        for rec in &records {
            refused += usize::from(filter.step_into(&rec.sample, &mut out).is_err());
        }
        assert_eq!(refused, 1);
        assert!(filter.rejected_readings().iter().sum::<u64>() > 0);
        assert_eq!(
            allocations() - before,
            0,
            "{} behind the gate allocated",
            filter.name()
        );
    }
}
