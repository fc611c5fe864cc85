//! Tests of the whole filter on the walking simulator.

use super::*;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use nalgebra::Vector3;

/// Per segment: (RMSE, mean error, offset-free RMSE), degrees, after 5 s.
fn run(cfg: WalkingConfig, params: ChainParams) -> [[f64; 3]; 4] {
    run_turned(cfg, params, [0.0; 4], ChainGeometry::default())
}

/// As [`run`], with each sensor frame turned by `psi_i` about z from its
/// segment's frame (what `align`'s mean-inclination zero does): readings
/// `R(-psi) v`, reference `theta + psi`; the filter gets `geometry`.
fn run_turned(
    cfg: WalkingConfig,
    params: ChainParams,
    psi: [f64; 4],
    geometry: ChainGeometry,
) -> [[f64; 3]; 4] {
    let sim = WalkingSimulator::new(cfg).unwrap().map(move |mut r| {
        for (i, imu) in r.sample.imu.iter_mut().enumerate() {
            let (s, c) = psi[i].sin_cos();
            let turn = |v: Vector3<f64>| Vector3::new(c * v.x + s * v.y, -s * v.x + c * v.y, v.z);
            imu.acc = imu.acc.map(turn);
            imu.gyr = imu.gyr.map(turn);
            if let Some(t) = r.reference.segment[i].as_mut() {
                *t += psi[i];
            }
        }
        r
    });
    let mut ekf = ChainEkf::new(params, geometry, cfg.g).unwrap();
    let mut sq = [0.0; 4];
    let mut sum = [0.0; 4];
    let mut n = 0.0;
    for r in sim {
        let e = ekf.step(&r.sample).unwrap();
        if r.sample.t < 5.0 {
            assert_eq!(
                e.segment[0].is_some(),
                r.sample.t >= 1.0 - 1e-9,
                "t {}",
                r.sample.t
            );
            continue;
        }
        n += 1.0;
        for i in 0..4 {
            let err = e.segment[i].unwrap() - r.reference.segment[i].unwrap();
            sq[i] += err * err;
            sum[i] += err;
        }
    }
    core::array::from_fn(|i| {
        let mean = sum[i] / n;
        let ms = sq[i] / n;
        [
            ms.sqrt().to_degrees(),
            mean.to_degrees(),
            (ms - mean * mean).max(0.0).sqrt().to_degrees(),
        ]
    })
}

#[test]
fn ideal_sensors_walking_tracks_the_truth() {
    let cfg = WalkingConfig {
        duration_s: 15.0,
        speed_mps: 1.2,
        noise: false,
        out_of_plane: false,
        ..Default::default()
    };
    let rmse = run(cfg, ChainParams::default());
    // Measured 0.05-0.15 deg per segment (offset-free 0.04).
    assert!(rmse.iter().all(|r| r[0] < 0.25 && r[2] < 0.08), "{rmse:?}");
}

#[test]
fn default_sensors_fast_walking_offset_free_error_is_small() {
    let cfg = WalkingConfig {
        duration_s: 15.0,
        speed_mps: 1.6,
        seed: 5,
        ..Default::default()
    };
    let rmse = run(cfg, ChainParams::default());
    // Offset-free (the static accelerometer biases and mounting errors are
    // constant): measured ~0.1-0.15 deg; the issue-14 target is 0.6 deg.
    assert!(rmse.iter().all(|r| r[2] < 0.3), "{rmse:?}");
}

#[test]
fn reset_starts_a_new_recording() {
    let cfg = WalkingConfig {
        duration_s: 3.0,
        ..Default::default()
    };
    let recs: Vec<_> = WalkingSimulator::new(cfg).unwrap().collect();
    let mut ekf = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), cfg.g).unwrap();
    let first: Vec<_> = recs.iter().map(|r| ekf.step(&r.sample).unwrap()).collect();
    ekf.reset();
    let second: Vec<_> = recs.iter().map(|r| ekf.step(&r.sample).unwrap()).collect();
    assert_eq!(first, second);
    assert!(first[50].segment[0].is_none() && first[150].segment[0].is_some());
}

/// Mean over the four segments of the offset-free RMSE (deg).
fn mean_offset_free(r: &[[f64; 3]; 4]) -> f64 {
    r.iter().map(|s| s[2]).sum::<f64>() / 4.0
}

#[test]
fn issue_14_frame_offsets_of_a_mean_inclination_zero_are_modelled() {
    let cfg = WalkingConfig {
        duration_s: 20.0,
        speed_mps: 1.2,
        seed: 3,
        ..Default::default()
    };
    let p = ChainParams::default();
    let psi = WALKING_MEAN_ANGLE_DEG.map(|m| -m.to_radians());
    let plain = mean_offset_free(&run(cfg, p));
    let known = ChainGeometry {
        frame_offset: psi,
        ..Default::default()
    };
    let modelled = mean_offset_free(&run_turned(cfg, p, psi, known));
    let ignored = mean_offset_free(&run_turned(cfg, p, psi, ChainGeometry::default()));
    std::println!(
        "frame offsets: plain {plain:.3}, modelled {modelled:.3}, ignored {ignored:.3} deg"
    );
    // The turned frames with their offsets are the same model as the plain
    // run; without them the shank's link points 16 deg off.
    assert!((modelled - plain).abs() < 0.01, "{modelled} vs {plain}");
    assert!(
        ignored > 1.5 * modelled,
        "ignored {ignored} modelled {modelled}"
    );
}

#[test]
fn issue_14_turns_widen_the_angles_so_the_accelerometers_reanchor_them() {
    let cfg = WalkingConfig {
        duration_s: 30.0,
        speed_mps: 1.2,
        seed: 2,
        turns: Some(limbfuse_sim::body_path::Turns {
            every_s: 10.0,
            duration_s: 2.5,
            angle_rad: core::f64::consts::PI,
        }),
        ..Default::default()
    };
    // The simulated body's lengths and sensor positions, as `limbfuse
    // estimate` reads them from the trial's metadata: under the turns'
    // rates a wrong lever arm makes the accelerometers pull the angles off.
    let body = WalkingSimulator::new(cfg).unwrap().model().body;
    let geometry = ChainGeometry {
        thigh_length: body.thigh,
        shank_length: body.shank,
        imu_position: body.imu.map(|r| [r.x, r.y, r.z]),
        ..ChainGeometry::from_height(body.height)
    };
    let with = mean_offset_free(&run_turned(cfg, ChainParams::default(), [0.0; 4], geometry));
    let without = mean_offset_free(&run_turned(
        cfg,
        ChainParams {
            turn_angle_noise: 0.0,
            ..Default::default()
        },
        [0.0; 4],
        geometry,
    ));
    std::println!("turns: offset-free mean {with:.3} deg (without the turn noise {without:.3})");
    assert!(with < 0.9 * without, "with {with} without {without}");
}

/// Issue 18 item 3: a segment rate beyond any gyroscope's range is a
/// divergence: the start-up window begins again, the covariance is zeroed
/// (no estimate, `diag_running` 0) and the filter starts afresh.
#[test]
fn issue_18_a_rate_beyond_any_gyroscope_restarts_the_startup() {
    let cfg = WalkingConfig {
        duration_s: 3.0,
        ..Default::default()
    };
    let records: Vec<_> = WalkingSimulator::new(cfg).unwrap().collect();
    let mut ekf = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), cfg.g).unwrap();
    let mut k = 0;
    while !ekf.running {
        ekf.step(&records[k].sample).unwrap();
        k += 1;
    }
    // a sample without readings (rows would pull the rate back)
    let next = Sample::empty(records[k].sample.t);
    ekf.x[omega(2)] = 1.5 * DIVERGED_RATE_RAD_S;
    let e = ekf.step(&next).unwrap();
    assert!(e.segment.iter().all(|s| s.is_none()));
    assert_eq!(ekf.covariance(), &Covariance::zeros());
    // just below the bound: an estimate, not a restart
    let mut ekf2 = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), cfg.g).unwrap();
    for r in &records[..k] {
        ekf2.step(&r.sample).unwrap();
    }
    ekf2.x[omega(2)] = 0.5 * DIVERGED_RATE_RAD_S;
    assert!(ekf2.step(&next).unwrap().segment[2].is_some());
    // the window closes again after `startup_s`
    let restarted = records[k + 1..]
        .iter()
        .map(|r| ekf.step(&r.sample).unwrap())
        .position(|e| e.segment[0].is_some());
    assert!(restarted.is_some());
}

/// Twenty-seventh session's audit: every IMU cell empty for 1.2 s of a walk
/// without encoders. The chain predicted the leg angles through it
/// (quadratic extrapolation, whole turns within 0.8 s of a real walk) and
/// re-locked after it wrong (the independent simulator's 1.2 m/s walk:
/// foot 158 deg off for the remaining 28 s). Past
/// [`missing_data::blind_limit_s`] it now gives no estimate and starts
/// again from the readings after the gap, as after a time gap.
#[test]
fn a_run_without_any_reading_restarts_the_startup() {
    let cfg = WalkingConfig {
        duration_s: 12.0,
        speed_mps: 1.2,
        seed: 4,
        ..Default::default()
    };
    let params = ChainParams::default();
    let limit = missing_data::blind_limit_s(params.leg_jerk, initial::ANGLE);
    assert!((limit - 0.2187).abs() < 1e-3, "{limit}"); // (20 * 0.25 / 1e4)^(1/5)
    let (t0, t1) = (5.0, 6.2);
    let mut ekf = ChainEkf::new(params, ChainGeometry::default(), cfg.g).unwrap();
    let mut resumed = None;
    for mut r in WalkingSimulator::new(cfg).unwrap() {
        let t = r.sample.t;
        if (t0..t1).contains(&t) {
            r.sample.imu = Default::default();
            r.sample.encoder = [None; 3];
        }
        let e = ekf.step(&r.sample).unwrap();
        if t > t0 + limit + 0.011 && t < t1 {
            assert!(e.segment.iter().all(Option::is_none), "estimate at {t}");
        }
        if t >= t1 && resumed.is_none() && e.segment[0].is_some() {
            resumed = Some(t);
        }
        if t >= t1 + 1.5 {
            for i in 0..4 {
                let err = (e.segment[i].unwrap() - r.reference.segment[i].unwrap()).to_degrees();
                assert!(err.abs() < 10.0, "segment {i} at {t}: {err} deg");
            }
        }
    }
    // The start-up window (1 s) opens at the first reading after the gap.
    let resumed = resumed.expect("no estimate after the gap");
    assert!((resumed - (t1 + 1.0)).abs() < 0.02, "resumed at {resumed}");
}
