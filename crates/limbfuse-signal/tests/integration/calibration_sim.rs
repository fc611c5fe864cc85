//! `calibrate` on simulated calibration recordings of the walking
//! simulator's sensors, against the drawn sensor errors (issue 14 item 3:
//! biases to <= 2 mg, scales to <= 0.2 %).

use limbfuse_core::Record;
use limbfuse_io::calibration::CalibrationModel;
use limbfuse_signal::calibration::{calibrate, CalibrationError, CalibrationParams};
use limbfuse_sim::{PoseRecording, PoseRecordingConfig, WalkingConfig, WalkingSimulator};
use nalgebra::{Matrix3, Vector3};

const MG: f64 = 9.81e-3;

fn config(seed: u64) -> PoseRecordingConfig {
    PoseRecordingConfig {
        sensors: WalkingConfig {
            seed,
            ..WalkingConfig::default()
        },
        ..PoseRecordingConfig::default()
    }
}

/// The records and, per sensor, the mean accelerometer and gyro bias over
/// the recording (turn-on + Gauss-Markov: what the sensor really had).
fn record(cfg: PoseRecordingConfig) -> (Vec<Record>, [Vector3<f64>; 4], [Vector3<f64>; 4]) {
    let mut rec = PoseRecording::new(cfg).unwrap();
    let mut records = Vec::new();
    let mut acc = [Vector3::zeros(); 4];
    let mut gyr = [Vector3::zeros(); 4];
    while let Some(r) = rec.next() {
        for i in 0..4 {
            acc[i] += rec.imus()[i].acc.turn_on + rec.imus()[i].acc.gm;
            gyr[i] += rec.imus()[i].gyro.turn_on + rec.imus()[i].gyro.gm;
        }
        records.push(r);
    }
    let n = records.len() as f64;
    (records, acc.map(|v| v / n), gyr.map(|v| v / n))
}

/// Sensitivity of each axis: the norm of row `i` of the sensor matrix
/// (`a = S f + b`): invariant to the rotation no static calibration sees.
fn sensitivities(s: &Matrix3<f64>) -> [f64; 3] {
    [0, 1, 2].map(|i| s.row(i).norm())
}

#[test]
fn recovers_the_simulated_biases_and_scales() {
    let mut worst_bias: f64 = 0.0;
    let mut worst_scale: f64 = 0.0;
    let mut worst_gyro: f64 = 0.0;
    for seed in 1..=3 {
        let (records, acc_bias, gyro_bias) = record(config(seed));
        let cal = calibrate(&records, &CalibrationParams::default()).unwrap();
        let truth = limbfuse_sim::walking_sensors(&config(seed).sensors).unwrap();
        for i in 0..4 {
            let c = cal.sensors[i].as_ref().expect("every sensor calibrated");
            let fit = c.fit.as_ref().unwrap();
            assert_eq!(fit.poses, 14, "seed {seed} sensor {i}: {fit:?}");
            assert!(fit.rejected.is_empty(), "{fit:?}");
            let e = (c.acc_bias - acc_bias[i]).amax();
            worst_bias = worst_bias.max(e);
            let s_est = sensitivities(&c.acc_matrix.try_inverse().unwrap());
            let s_true = sensitivities(&truth[i].acc.m);
            for k in 0..3 {
                worst_scale = worst_scale.max((s_est[k] / s_true[k] - 1.0).abs());
            }
            let gb = c.gyro_bias.unwrap();
            worst_gyro = worst_gyro.max((gb - gyro_bias[i]).amax());
            // The error is far below the bias it removes (20 mg turn-on sigma).
            assert!(
                truth[i].acc.turn_on.amax() > 5.0 * e,
                "seed {seed} sensor {i}"
            );
        }
    }
    println!(
        "worst over seeds 1-3, 4 sensors: bias {:.3} mg, scale {:.4} %, gyro bias {:.5} deg/s",
        worst_bias / MG,
        worst_scale * 100.0,
        worst_gyro.to_degrees()
    );
    assert!(worst_bias <= 2.0 * MG, "bias error {} mg", worst_bias / MG);
    assert!(
        worst_scale <= 0.002,
        "scale error {} %",
        worst_scale * 100.0
    );
    // Gyro bias: the mean of ~5000 samples of 0.05 deg/s white noise per
    // axis (and coning-free rest): well under 0.01 deg/s.
    assert!(
        worst_gyro.to_degrees() <= 0.01,
        "gyro bias error {} deg/s",
        worst_gyro.to_degrees()
    );
}

/// A 1 kHz pose recording (the walking simulator's sensors) gave "no
/// static pose": the accelerometer's white noise spreads 0.061 m/s^2 over
/// three axes at 1 kHz (160 ug/sqrt(Hz)), above the 0.05 limit set for 100
/// Hz. The static test now reads 10 ms means above 100 Hz: every pose is
/// found and the fit meets the 100 Hz test's bounds; a rocking pose is
/// still rejected.
#[test]
fn a_1_khz_recording_calibrates_as_at_100_hz() {
    let fast = |seed| {
        let mut c = config(seed);
        c.sensors.imu_rate_hz = 1000.0;
        c
    };
    let (records, acc_bias, _) = record(fast(1));
    let cal = calibrate(&records, &CalibrationParams::default()).unwrap();
    let truth = limbfuse_sim::walking_sensors(&fast(1).sensors).unwrap();
    for i in 0..4 {
        let c = cal.sensors[i].as_ref().expect("every sensor calibrated");
        let fit = c.fit.as_ref().unwrap();
        assert_eq!(fit.poses, 14, "sensor {i}: {fit:?}");
        assert!((c.acc_bias - acc_bias[i]).amax() <= 2.0 * MG, "sensor {i}");
        let s_est = sensitivities(&c.acc_matrix.try_inverse().unwrap());
        let s_true = sensitivities(&truth[i].acc.m);
        for k in 0..3 {
            assert!((s_est[k] / s_true[k] - 1.0).abs() <= 0.002, "sensor {i}");
        }
    }
    let (records, _, _) = record(PoseRecordingConfig {
        wobble_pose: Some(3),
        ..fast(4)
    });
    let cal = calibrate(&records, &CalibrationParams::default()).unwrap();
    for c in cal.sensors.iter().flatten() {
        let fit = c.fit.as_ref().unwrap();
        assert_eq!((fit.poses, fit.rejected.len()), (13, 1), "{fit:?}");
    }
}

#[test]
fn a_pose_that_is_not_held_still_is_rejected_by_its_time_span() {
    let cfg = PoseRecordingConfig {
        wobble_pose: Some(3),
        ..config(4)
    };
    let (records, _, _) = record(cfg);
    let cal = calibrate(&records, &CalibrationParams::default()).unwrap();
    let (a, b) = cfg.hold_span(3);
    for c in cal.sensors.iter().flatten() {
        let fit = c.fit.as_ref().unwrap();
        assert_eq!(fit.poses, 13, "{fit:?}");
        assert_eq!(fit.rejected.len(), 1, "{fit:?}");
        let msg = &fit.rejected[0];
        let start: f64 = msg.split('-').next().unwrap().parse().unwrap();
        assert!(start <= a + 0.5 && start >= a - 1.0, "{msg} vs {a}..{b}");
        assert!(msg.contains("not static"), "{msg}");
    }
}

#[test]
fn too_few_poses_and_a_moving_recording_are_refused() {
    let (records, _, _) = record(PoseRecordingConfig {
        poses: 6,
        ..config(5)
    });
    let e = calibrate(&records, &CalibrationParams::default()).unwrap_err();
    assert!(
        matches!(
            e,
            CalibrationError::TooFewPoses {
                found: 6,
                distinct: 6,
                needed: 9,
                ..
            }
        ),
        "{e}"
    );
    // Six faces are enough for the 6-unknown model.
    let scale = CalibrationParams {
        model: CalibrationModel::Scale,
        ..CalibrationParams::default()
    };
    assert!(calibrate(&records, &scale).is_ok());
    // Walking: the sensors never rest.
    let walk: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        duration_s: 10.0,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect();
    let e = calibrate(&walk, &CalibrationParams::default()).unwrap_err();
    assert!(matches!(e, CalibrationError::NoStaticPose { .. }), "{e}");
    assert!(e.to_string().contains("no static pose"), "{e}");
}
