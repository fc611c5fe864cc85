//! `sdre`, `ekf` (both plants) and `rmx` allocate nothing per step (same
//! counting-allocator pattern as `no_allocation.rs`, in its own binary so
//! the global counter sees no other test's allocations).

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{
    ExtendedKneeFilter, FixedHipActivationFilter, FixedHipFilter, KinematicKneeFilter,
    KneeFesFilter, Linearisation, RotationMatrixKnee,
};
use limbfuse_models::{
    ExtendedKneeModel, FixedHipActivationModel, FixedHipModel, FixedHipParams, KinematicKneeModel,
    KneeFesModel, KneeFesParams, KneeStateOptions, KneeSubject,
};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};

use crate::counting_alloc::allocations;

fn with_dropouts(mut recs: Vec<Record>) -> Vec<Record> {
    for (k, r) in recs.iter_mut().enumerate() {
        if k % 13 == 5 {
            r.sample.imu[2].acc = None;
            r.sample.imu[1].gyr = None;
            r.sample.inputs.stim[0] = None;
        }
    }
    recs
}

#[test]
fn fes_estimators_step_without_allocating() {
    let knee = with_dropouts(
        simulate_knee_fes(&KneeFesConfig {
            duration_s: 5.0,
            ..KneeFesConfig::default()
        })
        .unwrap()
        .records,
    );
    let hip = with_dropouts(
        simulate_fixed_hip(&FixedHipConfig {
            duration_s: 5.0,
            ..FixedHipConfig::default()
        })
        .unwrap()
        .records,
    );
    let km = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    let hm = FixedHipModel::new(FixedHipParams::default()).unwrap();
    let all = KneeStateOptions {
        activation: true,
        disturbance: true,
        gyro_bias: true,
        acc_bias: true,
    };
    let mut cases: Vec<(Box<dyn Estimator>, &[Record])> = vec![
        (Box::new(KneeFesFilter::sdre(km)), &knee),
        (Box::new(KneeFesFilter::ekf(km)), &knee),
        (Box::new(RotationMatrixKnee::new()), &knee),
        (Box::new(FixedHipFilter::sdre(hm)), &hip),
        (Box::new(FixedHipFilter::ekf(hm)), &hip),
        // Issue 16: the fixed hip with its four activation states.
        (
            Box::new(FixedHipActivationFilter::with_default_tuning(
                FixedHipActivationModel::new(hm, 0.25).unwrap(),
                Linearisation::Sdc,
            )),
            &hip,
        ),
        (
            Box::new(FixedHipActivationFilter::with_default_tuning(
                FixedHipActivationModel::new(hm, 0.25).unwrap(),
                Linearisation::Jacobian,
            )),
            &hip,
        ),
        // Issue 16: every optional state and the lever arm; the kinematic baseline.
        (
            Box::new(ExtendedKneeFilter::with_default_tuning(
                ExtendedKneeModel::<6>::new(km, all, 0.2).unwrap(),
                Linearisation::Sdc,
            )),
            &knee,
        ),
        (
            Box::new(ExtendedKneeFilter::with_default_tuning(
                ExtendedKneeModel::<6>::new(km, all, 0.2).unwrap(),
                Linearisation::Jacobian,
            )),
            &knee,
        ),
        (
            Box::new(KinematicKneeFilter::kinematic(
                KinematicKneeModel::new(9.81, 0.2).unwrap(),
                core::f64::consts::FRAC_PI_2,
            )),
            &knee,
        ),
    ];
    for (e, recs) in cases.iter_mut() {
        let before = allocations();
        let mut sum = 0.0;
        for r in recs.iter() {
            sum += e.step(&r.sample).unwrap().joint[1].unwrap_or(0.0);
        }
        let after = allocations();
        assert!(sum.is_finite());
        assert_eq!(
            after - before,
            0,
            "{} allocated {} times",
            e.name(),
            after - before
        );
    }
}
