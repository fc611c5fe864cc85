//! Issue 18 item 2: the planar filters read the axes they need from an
//! incomplete IMU vector (`ImuSample::acc_partial` / `gyr_partial`): the
//! sagittal gyro axis `z`, the in-plane accelerometer axes `x` and `y`
//! (docs/ROBUST_INPUT.md, "Incomplete vectors"). Each test fails without
//! the fix: before it, an incomplete vector was no reading at all.
//! Short runs on limbfuse's walking simulator (aligned sensors).

use limbfuse_core::{Estimate, Estimator, Record};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainGeometry, ChainParams};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

fn walking(duration_s: f64, seed: u64) -> Vec<Record> {
    WalkingSimulator::new(WalkingConfig {
        duration_s,
        seed,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect()
}

fn run(est: &mut dyn Estimator, records: &[Record]) -> Vec<Estimate> {
    records
        .iter()
        .map(|r| est.step(&r.sample).unwrap())
        .collect()
}

/// The records with the listed gyro and accelerometer axes missing on
/// every IMU, the other axes kept (as the trial reader keeps them).
fn without_axes(records: &[Record], gyr: [bool; 3], acc: [bool; 3]) -> Vec<Record> {
    records
        .iter()
        .map(|r| {
            let mut r = *r;
            for imu in r.sample.imu.iter_mut() {
                let (w, a) = (imu.gyr_axes(), imu.acc_axes());
                imu.set_gyr_axes(core::array::from_fn(|k| w[k].filter(|_| !gyr[k])));
                imu.set_acc_axes(core::array::from_fn(|k| a[k].filter(|_| !acc[k])));
            }
            r
        })
        .collect()
}

/// Segment RMSE (deg), mean over the four segments, after `from_s`.
fn mean_rmse(out: &[Estimate], records: &[Record], from_s: f64) -> f64 {
    let mut total = 0.0;
    for i in 0..4 {
        let (mut sq, mut n) = (0.0, 0.0);
        for (e, r) in out.iter().zip(records) {
            if r.sample.t < from_s {
                continue;
            }
            if let (Some(a), Some(b)) = (e.segment[i], r.reference.segment[i]) {
                let d = libm::remainder(a - b, core::f64::consts::TAU);
                sq += d * d;
                n += 1.0;
            }
        }
        assert!(n > 0.0, "segment {i}: nothing estimated");
        total += (sq / n).sqrt().to_degrees();
    }
    total / 4.0
}

fn estimators() -> [(&'static str, Box<dyn Estimator>); 3] {
    [
        ("mjls", Box::new(MarkovJumpKf::default())),
        ("local", Box::new(LocalKf::default())),
        ("global", Box::new(GlobalKf::default())),
    ]
}

/// Gyro x and y missing everywhere: the segment filters use only the
/// sagittal rate z, so their angles are those of the complete trial, bit
/// for bit. Before the fix every rate was missing.
#[test]
fn issue_18_segment_filters_need_only_the_sagittal_gyro_axis() {
    let clean = walking(10.0, 7);
    let partial = without_axes(&clean, [true, true, false], [false; 3]);
    assert!(partial.iter().all(|r| r.sample.imu[1].gyr.is_none()));
    for ((name, mut a), (_, mut b)) in estimators().into_iter().zip(estimators()) {
        let (ea, eb) = (run(a.as_mut(), &clean), run(b.as_mut(), &partial));
        for (k, (x, y)) in ea.iter().zip(&eb).enumerate() {
            assert_eq!(x.segment, y.segment, "{name}, sample {k}");
            assert_eq!(x.joint, y.joint, "{name}, sample {k}");
        }
    }
}

/// Accelerometer z missing everywhere: the segment filters take the
/// inclination from x and y and the norm test with the lateral axis at its
/// prior 0; the chain feeds x and y as its rows. Before the fix no
/// accelerometer reading was left (the segment filters never started).
#[test]
fn issue_18_the_in_plane_accelerometer_axes_are_used_without_the_lateral_one() {
    let clean = walking(12.0, 8);
    let partial = without_axes(&clean, [false; 3], [false, false, true]);
    for ((name, mut a), (_, mut b)) in estimators().into_iter().zip(estimators()) {
        let c = mean_rmse(&run(a.as_mut(), &clean), &clean, 2.0);
        let p = mean_rmse(&run(b.as_mut(), &partial), &partial, 2.0);
        println!("{name}: {c:.3} deg complete, {p:.3} deg without acc z");
        assert!((p - c).abs() < 0.05 * c + 0.02, "{name}: {p:.3} vs {c:.3}");
    }
    // the chain never reads acc z: identical estimates
    let chain = || ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
    let (ea, eb) = (run(&mut chain(), &clean), run(&mut chain(), &partial));
    assert!(ea.iter().any(|e| e.segment[0].is_some()));
    for (k, (x, y)) in ea.iter().zip(&eb).enumerate() {
        assert_eq!(x.segment, y.segment, "chain, sample {k}");
    }
}

/// The chain with only gyro z and accelerometer x, y on even samples and
/// only accelerometer y on odd ones: each present axis is its own row, so
/// the estimate stays close to the complete trial's. Before the fix no
/// sample had an IMU reading at all.
#[test]
fn issue_18_chain_uses_each_present_axis() {
    let clean = walking(12.0, 9);
    let mut partial = clean.clone();
    for (k, r) in partial.iter_mut().enumerate() {
        for imu in r.sample.imu.iter_mut() {
            let (w, a) = (imu.gyr_axes(), imu.acc_axes());
            if k.is_multiple_of(2) {
                imu.set_gyr_axes([None, None, w[2]]);
                imu.set_acc_axes([a[0], a[1], None]);
            } else {
                imu.set_gyr_axes([None, None, None]);
                imu.set_acc_axes([None, a[1], None]);
            }
        }
    }
    let chain = || ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
    let c = mean_rmse(&run(&mut chain(), &clean), &clean, 3.0);
    let p = mean_rmse(&run(&mut chain(), &partial), &partial, 3.0);
    println!("chain: {c:.3} deg complete, {p:.3} deg with partial vectors");
    assert!(p < 2.0 * c + 0.1, "{p:.3} vs {c:.3}");
}
