//! Issue 16 (fesbias): the knee `ekf` after seconds without shank
//! readings. `limbfuse simulate knee-fes --no-noise` writes still sensors
//! that repeat their readings bit for bit, so the sample gate rejects the
//! shank gyro and accelerometer as stuck from 0.1 s until the first
//! extension (3 s); during the gap `P_22` grows to ~90 (rad/s)^2, and the
//! first interval with readings again was far stiffer than the capped RK4
//! sub-steps could follow. The state ended finite but ~1e9 rad off, with a
//! negative variance, and stayed there: `limbfuse evaluate` gave knee RMSE
//! 17-153 deg on every leg (`ekf`; `sdre` went non-finite and restarted).
//! A negative variance now counts as a divergence and restarts the filter,
//! as a non-finite state did.
//!
//! Fails without the fix (checked: `ekf` knee RMSE after the gap 1.6e6 to
//! 1.2e11 deg, unwrapped, on five legs with no restart; P3-R restarted).

use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_estimators::fes::KneeFesFilter;
use limbfuse_models::{KneeFesModel, KneeFesParams, KneeSubject};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};

/// Knee RMSE (deg) from `from` s on, and the filter's restart count.
fn knee_rmse(e: &mut dyn Estimator, recs: &[Record], from: f64) -> (f64, f64) {
    let col = e.diagnostic_names().iter().position(|n| *n == "resets");
    let (mut s, mut n, mut resets) = (0.0, 0usize, 0.0);
    for r in recs {
        let est = e.step(&r.sample).expect("step");
        if let Some(v) = col.and_then(|c| est.diag[c]) {
            resets = v;
        }
        if r.sample.t < from {
            continue;
        }
        let (Some(a), Some(b)) = (est.joint[1], r.reference.joint[1]) else {
            continue;
        };
        s += (a - b) * (a - b);
        n += 1;
    }
    ((s / n.max(1) as f64).sqrt().to_degrees(), resets)
}

#[test]
fn issue_16_knee_ekf_recovers_after_a_shank_gap() {
    let mut failures = Vec::new();
    for subject in KneeSubject::ALL {
        let cfg = KneeFesConfig {
            subject,
            seed: 960,
            noise: false,
            duration_s: 12.0,
            ..KneeFesConfig::default()
        };
        let mut recs = simulate_knee_fes(&cfg).expect("trial").records;
        // What the sample gate leaves of the still shank sensors.
        for r in recs.iter_mut().filter(|r| (0.1..3.0).contains(&r.sample.t)) {
            let imu = &mut r.sample.imu[Segment::Shank.index()];
            imu.gyr = None;
            imu.acc = None;
        }
        let m = KneeFesModel::new(KneeFesParams::subject(subject)).expect("preset");
        for (name, mut f) in [
            ("sdre", KneeFesFilter::sdre(m)),
            ("ekf", KneeFesFilter::ekf(m)),
        ] {
            // From 4 s: one second after the readings are back.
            let (rmse, resets) = knee_rmse(&mut f, &recs, 4.0);
            println!(
                "{} {name}: knee RMSE {rmse:.3} deg after the gap, {resets} restarts",
                subject.label()
            );
            if rmse.is_nan() || rmse >= 2.0 {
                failures.push(format!("{} {name}: {rmse:.1} deg", subject.label()));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
