//! The self-aligning knee estimator (paper 002) on simulated walking with
//! random sensor mountings: the axis sign convention (SPEC section 6), the
//! knee angle against the simulator's truth, and bad input (missing samples,
//! a motionless recording, a saturated gyro).
#![allow(clippy::needless_range_loop)] // axis i of thigh (0) and shank (1) in parallel arrays

use limbfuse_core::{Estimate, Estimator, Joint, Record, Segment};
use limbfuse_estimators::knee_selfalign::{
    KneeDiag, KneeSelfAlign, KneeSelfAlignParams, WindowStatus,
};
use limbfuse_sim::{Motion, Mounting, WalkingConfig, WalkingSimulator};
use nalgebra::Vector3;

fn config(seed: u64, duration_s: f64) -> WalkingConfig {
    WalkingConfig {
        duration_s,
        seed,
        mounting: Mounting::Random,
        ..WalkingConfig::default()
    }
}

/// Segment z axes (the sagittal joint axes) in the thigh and shank sensor frames.
fn true_axes(sim: &WalkingSimulator) -> [Vector3<f64>; 2] {
    [Segment::Thigh, Segment::Shank].map(|s| sim.imus()[s.index()].mount.transpose() * Vector3::z())
}

fn diag(e: &Estimate, name: &str) -> Option<f64> {
    let i = KneeDiag::NAMES.iter().position(|n| *n == name).unwrap();
    e.diag[i]
}

fn run(records: &[Record], params: KneeSelfAlignParams) -> (KneeSelfAlign, Vec<Estimate>) {
    let mut est = KneeSelfAlign::new(params).unwrap();
    let out = records
        .iter()
        .map(|r| est.step(&r.sample).unwrap())
        .collect();
    (est, out)
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn both_axes_point_to_the_subjects_right_for_random_mountings() {
    // Flexion positive (SPEC section 1) with eq 4 needs both axes along the
    // segments' +z; a wrong relative sign would make eq 4 the sum of the
    // segment rates. Eight random mountings, default (noisy) sensors.
    let params = KneeSelfAlignParams {
        window: 400,
        ..KneeSelfAlignParams::default()
    };
    for seed in 0..8 {
        let sim = WalkingSimulator::new(config(seed, 12.0)).unwrap();
        let truth = true_axes(&sim);
        let records: Vec<Record> = sim.collect();
        let (est, out) = run(&records, params);
        let g = est
            .geometry()
            .unwrap_or_else(|| panic!("seed {seed}: {:?}", est.last_window()));
        for i in 0..2 {
            let cos = g.axis[i].dot(&truth[i]);
            assert!(
                cos > 10f64.to_radians().cos(),
                "seed {seed} axis {i}: cos {cos}"
            );
        }
        // The angle follows the truth (correlation is offset-free).
        let (mut e, mut r) = (Vec::new(), Vec::new());
        for (o, rec) in out.iter().zip(&records).skip(800) {
            e.push(o.joint[Joint::Knee.index()].unwrap());
            r.push(rec.reference.joint[Joint::Knee.index()].unwrap());
        }
        let c = correlation(&e, &r);
        assert!(c > 0.99, "seed {seed}: correlation {c}");
        // The accelerometer angle follows the gyro angle (0 = exactly).
        let spread = diag(out.last().unwrap(), "acc_gyro_spread").unwrap();
        assert!(spread < 0.01, "seed {seed}: spread {spread}");
    }
}

#[test]
fn no_angle_before_the_first_window_and_diagnostics_after() {
    let records: Vec<Record> = WalkingSimulator::new(config(11, 7.0)).unwrap().collect();
    let (_, out) = run(&records, KneeSelfAlignParams::default());
    for (k, e) in out.iter().enumerate() {
        let has = e.joint[Joint::Knee.index()].is_some();
        assert_eq!(has, k >= 499, "sample {k}");
        assert_eq!(
            diag(e, "identified"),
            Some(if k >= 499 { 1.0 } else { 0.0 })
        );
    }
    let last = out.last().unwrap();
    assert_eq!(
        diag(last, "window_status"),
        Some(WindowStatus::Identified.code())
    );
    assert_eq!(diag(last, "windows"), Some(1.0));
    let j = Vector3::new(
        diag(last, "j_thigh_x").unwrap(),
        diag(last, "j_thigh_y").unwrap(),
        diag(last, "j_thigh_z").unwrap(),
    );
    assert!((j.norm() - 1.0).abs() < 1e-12);
}

#[test]
fn motionless_recording_is_reported_unobservable() {
    let cfg = WalkingConfig {
        motion: Motion::Stand,
        ..config(4, 12.0)
    };
    let records: Vec<Record> = WalkingSimulator::new(cfg).unwrap().collect();
    let (est, out) = run(&records, KneeSelfAlignParams::default());
    assert!(est.geometry().is_none());
    for e in &out {
        assert_eq!(e.joint[Joint::Knee.index()], None);
    }
    let last = out.last().unwrap();
    assert_eq!(diag(last, "unobservable"), Some(1.0));
    assert_eq!(
        diag(last, "window_status"),
        Some(WindowStatus::Unobservable.code())
    );
    assert!(diag(last, "information").unwrap() < 0.01);
}

#[test]
fn windows_with_missing_samples() {
    let sim = WalkingSimulator::new(config(6, 15.0)).unwrap();
    let truth = true_axes(&sim);
    let mut records: Vec<Record> = sim.collect();
    // Window 1 (samples 0..500): 70 % of the shank gyro missing -> skipped.
    // Windows 2 and 3: every fifth thigh accelerometer sample missing.
    for (k, r) in records.iter_mut().enumerate() {
        if k < 500 && k % 10 < 7 {
            r.sample.imu[Segment::Shank.index()].gyr = None;
        }
        if k >= 500 && k % 5 == 0 {
            r.sample.imu[Segment::Thigh.index()].acc = None;
        }
    }
    let (est, out) = run(&records, KneeSelfAlignParams::default());
    assert_eq!(
        diag(&out[499], "window_status"),
        Some(WindowStatus::TooFewSamples.code())
    );
    assert_eq!(diag(&out[499], "window_usable"), Some(150.0));
    assert_eq!(out[700].joint[Joint::Knee.index()], None);
    assert_eq!(
        diag(&out[999], "window_status"),
        Some(WindowStatus::Identified.code())
    );
    let g = est.geometry().unwrap();
    for i in 0..2 {
        assert!(g.axis[i].dot(&truth[i]) > 10f64.to_radians().cos());
    }
    assert!(out[1499].joint[Joint::Knee.index()].unwrap().is_finite());
}

#[test]
fn saturated_gyro_samples_are_flagged_and_left_out() {
    // A 250 deg/s gyro range: the shank's swing rates (up to ~400 deg/s)
    // clip. The clipped samples are flagged and kept out of the
    // identification; the axes are still found.
    let range = 250f64.to_radians();
    let sim = WalkingSimulator::new(config(8, 15.0)).unwrap();
    let truth = true_axes(&sim);
    let mut records: Vec<Record> = sim.collect();
    let mut clipped = 0;
    for r in records.iter_mut() {
        for imu in r.sample.imu.iter_mut() {
            if let Some(g) = imu.gyr.as_mut() {
                for c in g.iter_mut() {
                    if c.abs() > range {
                        *c = c.signum() * range;
                        clipped += 1;
                    }
                }
            }
        }
    }
    assert!(clipped > 50, "{clipped}");
    let params = KneeSelfAlignParams {
        gyro_range: range,
        ..KneeSelfAlignParams::default()
    };
    let (est, out) = run(&records, params);
    let flagged = out
        .iter()
        .filter(|e| diag(e, "saturated") == Some(1.0))
        .count();
    assert!(flagged > 20, "{flagged}");
    let g = est
        .geometry()
        .expect("identified from the unsaturated samples");
    for i in 0..2 {
        assert!(g.axis[i].dot(&truth[i]) > 10f64.to_radians().cos());
    }
    assert!(out.iter().all(|e| e.joint[1].is_none_or(f64::is_finite)));
}

#[test]
fn reset_gives_the_same_output_bit_for_bit() {
    let records: Vec<Record> = WalkingSimulator::new(config(12, 8.0)).unwrap().collect();
    let mut est = KneeSelfAlign::new(KneeSelfAlignParams {
        window: 300,
        ..KneeSelfAlignParams::default()
    })
    .unwrap();
    let first: Vec<Estimate> = records
        .iter()
        .map(|r| est.step(&r.sample).unwrap())
        .collect();
    est.reset();
    let second: Vec<Estimate> = records
        .iter()
        .map(|r| est.step(&r.sample).unwrap())
        .collect();
    assert!(first[400].joint[Joint::Knee.index()].is_some());
    for (a, b) in first.iter().zip(&second) {
        assert_eq!(a.joint[1].map(f64::to_bits), b.joint[1].map(f64::to_bits));
        assert_eq!(
            a.diag.map(|d| d.map(f64::to_bits)),
            b.diag.map(|d| d.map(f64::to_bits))
        );
    }
}
