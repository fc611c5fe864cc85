//! The self-aligning knee estimator (paper 002) on the shared recordings
//! of `../shared/data` (skipped with a message when that folder is absent;
//! `LIMBFUSE_DATA` overrides the path): one test per failure cause found on
//! them (issue 15), each of which failed before its fix.
//!
//! Figures: `cargo test --release -p limbfuse-estimators --test integration
//! -- knee_selfalign_shared:: --nocapture`.

use crate::shared_data_support::{data_dir, read};
use limbfuse_core::{Estimator, Joint, Record};
use limbfuse_estimators::knee_selfalign::window::{identify, Ring, Slot};
use limbfuse_estimators::knee_selfalign::{KneeDiag, KneeSelfAlign, KneeSelfAlignParams};

fn slot(r: &Record) -> Slot {
    let (t, s) = (r.sample.imu[1], r.sample.imu[2]);
    Slot {
        t: r.sample.t,
        gyr: [t.gyr.unwrap(), s.gyr.unwrap()],
        acc: [t.acc.unwrap(), s.acc.unwrap()],
        gyr_ok: true,
        acc_ok: true,
    }
}

/// RMSE (deg) of the knee estimate against `knee_ref` from `from_s` on.
fn knee_rmse(records: &[Record], params: KneeSelfAlignParams, from_s: f64) -> f64 {
    let mut est = KneeSelfAlign::new(params).unwrap();
    let (mut s, mut n) = (0.0, 0usize);
    for r in records {
        let e = est.step(&r.sample).unwrap();
        if r.sample.t < from_s {
            continue;
        }
        let k = Joint::Knee.index();
        if let (Some(a), Some(b)) = (e.joint[k], r.reference.joint[k]) {
            let d = limbfuse_estimators::knee_selfalign::angle::wrap(a - b);
            s += d * d;
            n += 1;
        }
    }
    assert!(n > 0, "no knee estimate after {from_s} s");
    (s / n as f64).sqrt().to_degrees()
}

const WALKS: [&str; 3] = ["walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"];

/// Cause 1: Algorithm 2 for the positions started from `o = 0` and, on the
/// 1.2 m/s walk, converged to a wrong local minimum (`o_T` 0.28 m *below*
/// the thigh sensor's true place, RMS `e_o` 1.18 m/s^2 against 0.08 at the
/// truth); the wrong positions spoilt the accelerometer angle, the sign rule
/// took the wrong pair and the angle wandered over +-180 deg. The sensors sit
/// 0.215 m above and below the knee on the segments' y axes
/// (`# imu_mounts_m`).
#[test]
fn first_window_positions_are_the_true_ones() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    for name in WALKS {
        let records = read(&dir.join(format!("independent-sim/{name}.csv")));
        let p = KneeSelfAlignParams::default();
        let mut ring = Ring::new(p.window);
        for r in &records[..p.window] {
            ring.push(slot(r));
        }
        let g = match identify(&mut ring, None, None, false, false, &p) {
            limbfuse_estimators::knee_selfalign::window::WindowOutcome::Identified {
                geometry,
                ..
            } => geometry,
            other => panic!("{name}: {other:?}"),
        };
        // Compare the components off the axis (along the axis the positions
        // are only fixed by the correction of paper 002 after eq 3).
        let off = |o: nalgebra::Vector3<f64>, j: nalgebra::Vector3<f64>| o - j * o.dot(&j);
        let e_t = (off(g.position[0], g.axis[0]) - nalgebra::Vector3::new(0.0, 0.215, 0.0)).norm();
        let e_s = (off(g.position[1], g.axis[1]) - nalgebra::Vector3::new(0.0, -0.215, 0.0)).norm();
        println!("{name}: position errors thigh {e_t:.4} m, shank {e_s:.4} m");
        assert!(e_t < 0.02 && e_s < 0.02, "{name}: {g:?}");
    }
}

/// The issue-15 target on the shared independent-simulator walks: knee
/// RMSE <= 2 deg after 10 s, not offset-free, with the defaults.
#[test]
fn independent_walks_meet_the_target() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    for name in WALKS {
        let records = read(&dir.join(format!("independent-sim/{name}.csv")));
        let rmse = knee_rmse(&records, KneeSelfAlignParams::default(), 10.0);
        println!("{name}: knee RMSE after 10 s {rmse:.3} deg");
        assert!(rmse <= 2.0, "{name}: {rmse} deg");
    }
    let _ = KneeDiag::NAMES;
}

/// Cause 2: the relative axis sign was chosen once, in the first
/// identified window, with no margin, and kept for good by the continuity
/// rule, so one window with misleading evidence (here: the accelerometers of
/// the first 5 s desynchronised from the gyros by 0.37 to 2.51 s) fixed the
/// wrong pair for the whole trial. Now the pair stays uncommitted until a
/// window's sign confidence reaches `sign_commit`. The run with
/// `sign_commit = 0`, `acc_max_spread = 1`, `acc_min_motion = 0` (every
/// accelerometer angle trusted, the default before the gaittoolbox/knee-rig causes) is the old
/// behaviour: it kept the wrong pair on the 0.7 m/s walk with a 2.51 s
/// shift (knee RMSE 55 deg) until issue 15 item 3 (see the end of the test).
#[test]
fn a_misleading_first_window_does_not_fix_the_sign() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    let mut old_wrong = 0;
    for name in WALKS {
        let records = read(&dir.join(format!("independent-sim/{name}.csv")));
        for shift in [37usize, 137, 251] {
            let mut rec = records.clone();
            for i in 0..500 {
                for seg in [1, 2] {
                    rec[i].sample.imu[seg].acc = records[i + shift].sample.imu[seg].acc;
                }
            }
            let same_side = |params: KneeSelfAlignParams| {
                let mut est = KneeSelfAlign::new(params).unwrap();
                let mut conf = Vec::new();
                for r in &rec {
                    let e = est.step(&r.sample).unwrap();
                    conf.push(e.diag[KneeDiag::SignConfidence as usize]);
                }
                let g = est.geometry().unwrap();
                (
                    g.axis[0].z > 0.5 && g.axis[1].z > 0.5,
                    conf.last().copied().flatten(),
                )
            };
            let (new, c) = same_side(KneeSelfAlignParams::default());
            let (old, _) = same_side(KneeSelfAlignParams {
                sign_commit: 0.0,
                acc_max_spread: 1.0,
                acc_min_motion: 0.0,
                ..Default::default()
            });
            let rmse = knee_rmse(&rec, KneeSelfAlignParams::default(), 20.0);
            println!(
                "{name}, accelerometers shifted {shift} samples: right pair now {new} \
                 (confidence {c:?}), with the old rule {old}; RMSE after 20 s {rmse:.2} deg"
            );
            assert!(new, "{name} shift {shift}");
            assert!(rmse < 2.0, "{name} shift {shift}: {rmse}");
            old_wrong += usize::from(!old);
        }
    }
    // Until issue 15 item 3 the old rule kept the wrong pair on the 0.7 m/s
    // walk with a 2.51 s shift (asserted here, so the scenario was shown to
    // discriminate). Since the relative accelerometer scale of eq 3 and the
    // fused positions (`acc_scale`, `position_fusion`), the old rule's
    // settings find the right pair on all 9 cases too: printed, no longer
    // asserted.
    println!("old rule wrong on {old_wrong} of 9 cases");
}
