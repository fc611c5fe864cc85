//! The optional refinements of the accelerometer acceptance test
//! (`AccelGate`: quasi-static hold, angular-rate bound) in the three
//! segment filters (moved from segment_kf_robustness.rs, which had grown
//! over 600 lines).

use crate::segment_kf_robustness::{diag, first_sample_start, limb, AnyKf};
use limbfuse_core::Estimator;
use limbfuse_estimators::segment_kf::params::CommonParams;
use limbfuse_estimators::segment_kf::{AccelGate, MarkovJumpKf, MarkovJumpKfParams, MjlsDiag};
use nalgebra::Vector3;

#[test]
fn accel_hold_gate_waits_for_a_quasi_static_run_of_the_given_duration() {
    // 100 Hz; rho < zeta on samples 0, 2, 3, 4, ...; sample 1 breaks the run.
    // With hold_s = 0.02 the accelerometer rows may enter again at sample 4
    // (20 ms after the run restarted at sample 2), not at 2 or 3.
    let gate = AccelGate {
        hold_s: 0.02,
        ..AccelGate::OFF
    };
    for (hold, first) in [(AccelGate::OFF, 2usize), (gate, 4)] {
        let common = CommonParams {
            accel_gate: hold,
            ..first_sample_start()
        };
        for mut kf in AnyKf::all(common) {
            let mut l = limb(23);
            let names = kf.diag_names();
            kf.est().step(&l.sample(0)).unwrap();
            let mut s = l.sample(1);
            for imu in s.imu.iter_mut() {
                imu.acc = imu.acc.map(|a| a * 1.2); // rho ~ 2 m/s^2
            }
            kf.est().step(&s).unwrap();
            for k in 2..=5 {
                let e = kf.est().step(&l.sample(k)).unwrap();
                let upd: f64 = ["upd_trunk", "upd_thigh", "upd_shank", "upd_foot"]
                    .iter()
                    .map(|n| diag(&e, names, n).unwrap())
                    .sum();
                assert_eq!(upd > 0.0, k >= first, "{} k={k} {hold:?}", kf.name());
            }
        }
    }
}

#[test]
fn accel_rate_gate_drops_a_rotating_segment() {
    let common = CommonParams {
        accel_gate: AccelGate {
            max_rate: 1.0,
            ..AccelGate::OFF
        },
        ..first_sample_start()
    };
    for mut kf in AnyKf::all(common) {
        if kf.name() == "mjls" {
            continue; // one row only; checked below
        }
        let mut l = limb(29);
        let names = kf.diag_names();
        kf.est().step(&l.sample(0)).unwrap();
        let mut s = l.sample(1);
        s.imu[0].gyr = Some(Vector3::new(0.0, 0.3, 2.0)); // trunk turns at 2 rad/s
        s.imu[2].gyr = None; // a missing gyro fails the test
        let e = kf.est().step(&s).unwrap();
        assert_eq!(diag(&e, names, "upd_trunk"), Some(0.0), "{}", kf.name());
        assert_eq!(diag(&e, names, "upd_thigh"), Some(1.0), "{}", kf.name());
        assert_eq!(diag(&e, names, "upd_shank"), Some(0.0), "{}", kf.name());
        assert_eq!(diag(&e, names, "upd_foot"), Some(1.0), "{}", kf.name());
    }
    // MJLS picks the most reliable among the segments that pass: make the
    // trunk the argmin of rho but rotating, and check the mode skips it.
    let mut f = MarkovJumpKf::new(MarkovJumpKfParams {
        common,
        ..Default::default()
    })
    .unwrap();
    let mut l = limb(31);
    l.acc_sigma = 0.0;
    f.step(&l.sample(0)).unwrap();
    let mut s = l.sample(1);
    for (i, imu) in s.imu.iter_mut().enumerate() {
        imu.acc = imu.acc.map(|a| a * (1.0 + 0.005 * i as f64)); // trunk best
    }
    let e = f.step(&s).unwrap();
    assert_eq!(e.diagnostic(MjlsDiag::Mode), Some(0.0));
    let mut s = l.sample(2);
    for (i, imu) in s.imu.iter_mut().enumerate() {
        imu.acc = imu.acc.map(|a| a * (1.0 + 0.005 * i as f64));
    }
    s.imu[0].gyr = Some(Vector3::new(0.0, 0.0, -1.5));
    let e = f.step(&s).unwrap();
    assert_eq!(e.diagnostic(MjlsDiag::Mode), Some(1.0));
}
