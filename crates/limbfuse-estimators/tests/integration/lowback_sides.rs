//! `lowback-speed`'s contact sides (`lowback_speed::sides`) on a synthetic
//! lower-back signal whose truth is known: the vertical acceleration peaks
//! at every contact (step period 0.55 s) and the trunk turns about the
//! vertical at the stride frequency, counter-clockwise (seen from above)
//! through the right contacts, the sign McCamley's rule reads as right.

use limbfuse_core::{Estimator, Sample, Segment};
use limbfuse_estimators::lowback_speed::{LowbackDiag, LowbackParams, LowbackSpeed};
use nalgebra::{Rotation3, Vector3};

const STEP_S: f64 = 0.55;
const T0: f64 = 0.3;
const DURATION_S: f64 = 30.0;

/// (right contacts, left contacts) decided by `lowback-speed` on the
/// synthetic walk with yaw-rate amplitude `yaw` (rad/s), the sensor mounted
/// at `mount` (sensor frame = `mount^T` world frame, z up).
fn sides(yaw: f64, mount: Rotation3<f64>) -> (Vec<f64>, Vec<f64>) {
    let mut e = LowbackSpeed::new(LowbackParams::default());
    let up = Vector3::z();
    let (mut right, mut left) = (vec![], vec![]);
    let n = (DURATION_S * 100.0) as usize;
    for k in 0..n {
        let t = k as f64 * 0.01;
        let phase = core::f64::consts::PI * (t - T0) / STEP_S;
        let a_v = 2.0 * (2.0 * phase).cos();
        let w_up = yaw * phase.cos();
        let mut s = Sample::empty(t);
        let imu = &mut s.imu[Segment::Trunk.index()];
        imu.acc = Some(mount.inverse() * (up * (9.81 + a_v)));
        imu.gyr = Some(mount.inverse() * (up * w_up));
        let est = e.step(&s).unwrap();
        right.extend(est.diagnostic(LowbackDiag::IcRight));
        left.extend(est.diagnostic(LowbackDiag::IcLeft));
    }
    (right, left)
}

/// Contact number of time `t` (`T0 + k STEP_S`); the even ones are right.
fn contact_number(t: f64) -> i64 {
    let x = (t - T0) / STEP_S;
    assert!((x - x.round()).abs() < 0.05, "{t} s is not a contact");
    x.round() as i64
}

#[test]
fn lowback_sides_follow_the_trunk_rotation_at_any_mounting() {
    let upright = Rotation3::identity();
    let tilted = Rotation3::from_euler_angles(0.7, -1.9, 2.6);
    let (right, left) = sides(0.4, upright);
    // Every contact from the window's 2 s to 2 s before the end has a side.
    let expected = ((DURATION_S - 4.0) / STEP_S) as usize;
    assert!(
        right.len() + left.len() + 2 >= expected,
        "{right:?} {left:?}"
    );
    assert!(
        right.iter().all(|&t| contact_number(t) % 2 == 0),
        "{right:?}"
    );
    assert!(left.iter().all(|&t| contact_number(t) % 2 != 0), "{left:?}");
    // The rate is taken about gravity, not about a sensor axis.
    assert_eq!(sides(0.4, tilted), (right.clone(), left.clone()));
    // The opposite rotation: the other feet.
    assert_eq!(sides(-0.4, upright), (left, right));
}

#[test]
fn lowback_sides_unknown_without_a_turning_trunk() {
    // 2 deg/s (0.035 rad/s) is below `side_min_rate`, 3 deg/s.
    for yaw in [0.0, 0.035] {
        let (right, left) = sides(yaw, Rotation3::identity());
        assert!(
            right.is_empty() && left.is_empty(),
            "{yaw}: {right:?} {left:?}"
        );
    }
}
