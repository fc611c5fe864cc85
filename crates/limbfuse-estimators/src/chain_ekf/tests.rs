//! Tests of the whole filter on the walking simulator.

use super::*;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

/// Per segment: (RMSE, mean error, offset-free RMSE), degrees, after 5 s.
fn run(cfg: WalkingConfig, params: ChainParams) -> [[f64; 3]; 4] {
    let sim = WalkingSimulator::new(cfg).unwrap();
    let mut ekf = ChainEkf::new(params, ChainGeometry::default(), cfg.g).unwrap();
    let mut sq = [0.0; 4];
    let mut sum = [0.0; 4];
    let mut n = 0.0;
    for r in sim {
        let e = ekf.step(&r.sample).unwrap();
        if r.sample.t < 5.0 {
            assert_eq!(e.segment[0].is_some(), r.sample.t >= 2.0 - 1e-9, "t {}", r.sample.t);
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
        [ms.sqrt().to_degrees(), mean.to_degrees(), (ms - mean * mean).max(0.0).sqrt().to_degrees()]
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
    eprintln!("rmse {rmse:?}");
    assert!(rmse.iter().all(|r| r[0] < 1.0), "{rmse:?}");
}

#[test]
#[ignore]
fn sweep() {
    let cfg = WalkingConfig {
        duration_s: 20.0,
        speed_mps: 1.2,
        noise: false,
        out_of_plane: false,
        ..Default::default()
    };
    let d = ChainParams::default();
    let cases = [
        ("default", d),
        ("acc 0.1", ChainParams { acc_noise: 0.1, ..d }),
        ("acc 1", ChainParams { acc_noise: 1.0, ..d }),
        ("leg jerk 1e5", ChainParams { leg_jerk: 1e5, ..d }),
        ("leg jerk 1e3", ChainParams { leg_jerk: 1e3, ..d }),
        ("hip tau 1", ChainParams { hip_acc_tau: 1.0, ..d }),
        ("no enc", ChainParams { use_encoders: false, ..d }),
        ("stance 1000", ChainParams { stance_velocity: 1000.0, ..d }),
        ("vy 1000", ChainParams { hip_vertical_velocity: 1000.0, ..d }),
        ("vx 1000", ChainParams { hip_forward_velocity: 1000.0, ..d }),
        ("gyro 0.002", ChainParams { gyro_noise: 0.002, ..d }),
    ];
    for (name, p) in cases {
        let r = run(cfg, p);
        let m: f64 = r.iter().map(|x| x[0]).sum::<f64>() / 4.0;
        let of: f64 = r.iter().map(|x| x[2]).sum::<f64>() / 4.0;
        eprintln!("{name:>14}: rmse {m:.3} offset-free {of:.3}  {:?}", r.map(|x| (x[1] * 100.0).round() / 100.0));
    }
}
