//! The rest check of `knee-selfalign` (ours, issue knee31b,
//! `knee_selfalign::rest_gravity`) on the shared knee rig: its
//! accelerometers read 1.00-1.01 g in the start pose and 1.10-1.24 g in the
//! rests from 2-7 s on, so they are not gravity sensors, and at
//! `--window 500` Trials 03-05 had a window near 102-104 s whose
//! accelerometer angle followed the gyro angle by chance and pulled the knee
//! off (RMSE 24.2 / 28.2 / 36.4 deg, r 0.42 / 0.37 / 0.09). Skipped with a
//! message without ../shared/data.
//!
//! Figures: `cargo test --release -p limbfuse-estimators --test integration
//! -- knee_rest_gravity:: --nocapture`.

use limbfuse_core::{Estimator, Joint, Record};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};

use super::knee_selfalign_real::{data_dir, paired, rig};

/// `--window 500` (2 s at 250 Hz), where the chance-trusted windows were.
fn params() -> KneeSelfAlignParams {
    KneeSelfAlignParams {
        window: 500,
        ..Default::default()
    }
}

/// Offset-free knee RMSE (deg) over the trial, as `evaluate --offset-free`.
fn offset_free_rmse(records: &[Record], p: KneeSelfAlignParams) -> f64 {
    let (e, r) = paired(records, p, (0.0, f64::INFINITY), 0);
    let d: Vec<f64> = e.iter().zip(&r).map(|(a, b)| a - b).collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / d.len() as f64)
        .sqrt()
        .to_degrees()
}

/// Trial_03 at `--window 500`: a rest reads a norm off g by more than the
/// tolerance within the first 10 s, no window is trusted after it, and the
/// knee follows the rig as on Trials 01-02 (offset-free RMSE 2.24 / 2.20
/// deg there, unaffected by the check: within 25 % of the worse of them is
/// the shape the rig's gyro angle gives; 24.2 deg without the check).
#[test]
fn rig_trial_3_trusts_no_window_after_a_rest_off_one_g() {
    let Some(dir) = data_dir() else { return };
    let records = rig(&dir, 3);
    let mut est = KneeSelfAlign::new(params()).unwrap();
    let mut first_bad = None;
    let mut trusted_after = Vec::new();
    for r in &records {
        let out = est.step(&r.sample).unwrap();
        if first_bad.is_none() && est.rest_check().miscalibrated() {
            first_bad = Some((r.sample.t, est.rest_check().last_error().unwrap()));
        }
        if first_bad.is_some() && est.acc_trusted() && out.joint[Joint::Knee.index()].is_some() {
            trusted_after.push(r.sample.t);
        }
    }
    let (t_bad, error) = first_bad.expect("a rest off 1 g on Trial_03");
    let bound = 1.25
        * offset_free_rmse(&rig(&dir, 1), params()).max(offset_free_rmse(&rig(&dir, 2), params()));
    let rmse = offset_free_rmse(&records, params());
    println!(
        "Trial_03 --window 500: first rest off 1 g at {t_bad:.2} s (|norm/g - 1| {error:.3}); \
         trusted samples after it {}; offset-free RMSE {rmse:.3} deg (bound {bound:.3})",
        trusted_after.len()
    );
    assert!(t_bad < 10.0, "{t_bad}");
    assert!(
        trusted_after.is_empty(),
        "trusted from {:?} s on",
        trusted_after.first()
    );
    assert!(rmse < bound, "{rmse} >= {bound}");
}

/// The rest check against limbfuse's simulator's sensor errors (20 mg
/// zero-g offset, 0.5 % scale, 1 % cross-axis, 1 sigma; docs/SIMULATOR.md):
/// standing, every seed's thigh and shank read g within the tolerance;
/// walking from 0.4 to 1.8 m/s never marks them miscalibrated: heel
/// strikes and the segments' rate reversals are not rests, and where a slow
/// walk does hold one (a segment still for 0.2 s in a 0.4 m/s stance) it
/// reads g as a standing rest does.
#[test]
fn simulated_standing_and_walking_read_one_g_at_rest() {
    use limbfuse_estimators::knee_selfalign::rest_gravity::{
        RestGravityCheck, ACC_REST_TOLERANCE_G,
    };
    use limbfuse_sim::{Motion, Mounting, WalkingConfig, WalkingSimulator};
    let run = |motion, speed_mps, seed| {
        let mut c = RestGravityCheck::new(ACC_REST_TOLERANCE_G, limbfuse_core::STANDARD_GRAVITY);
        let sim = WalkingSimulator::new(WalkingConfig {
            duration_s: 20.0,
            speed_mps,
            seed,
            motion,
            mounting: Mounting::Random,
            ..WalkingConfig::default()
        })
        .unwrap();
        for r in sim {
            c.step(r.sample.t, &[r.sample.imu[1], r.sample.imu[2]]);
        }
        c
    };
    let (mut worst, mut walk_worst, mut walks_with_rest): (f64, f64, Vec<_>) = (0.0, 0.0, vec![]);
    for seed in 1..=10 {
        let c = run(Motion::Stand, 1.0, seed);
        let e = c.last_error().expect("standing is a rest");
        worst = worst.max(e);
        assert!(!c.miscalibrated(), "seed {seed}: {e}");
        for speed in [0.4, 1.0, 1.8] {
            let c = run(Motion::Walk, speed, seed);
            assert!(
                !c.miscalibrated(),
                "seed {seed}, {speed} m/s: {:?}",
                c.last_error()
            );
            if let Some(e) = c.last_error() {
                walk_worst = walk_worst.max(e);
                walks_with_rest.push((seed, speed));
            }
        }
    }
    println!(
        "standing, 10 seeds: largest |norm/g - 1| {worst:.4} (tolerance {ACC_REST_TOLERANCE_G}); \
         walks with a rest (seed, m/s): {walks_with_rest:?}, largest |norm/g - 1| {walk_worst:.4}"
    );
}
