//! Same seed -> bit-identical output; different seeds differ; bad configs are
//! typed errors; every record field the simulator promises is filled.

use limbfuse_core::Record;
use limbfuse_sim::{EncoderResample, Motion, Mounting, SimError, WalkingConfig, WalkingSimulator};

fn bits(r: &Record) -> Vec<u64> {
    let mut v = vec![r.sample.t.to_bits()];
    for imu in &r.sample.imu {
        v.extend(imu.acc.unwrap().iter().map(|x| x.to_bits()));
        v.extend(imu.gyr.unwrap().iter().map(|x| x.to_bits()));
    }
    v.extend(r.sample.encoder.iter().map(|x| x.unwrap().to_bits()));
    v.extend(r.reference.segment.iter().map(|x| x.unwrap().to_bits()));
    v.extend(r.reference.joint.iter().map(|x| x.unwrap().to_bits()));
    v
}

fn run(cfg: WalkingConfig) -> Vec<Vec<u64>> {
    WalkingSimulator::new(cfg)
        .unwrap()
        .map(|r| bits(&r))
        .collect()
}

#[test]
fn same_seed_gives_identical_output_bit_for_bit() {
    let cfg = WalkingConfig {
        duration_s: 20.0,
        seed: 42,
        mounting: Mounting::Random,
        ..Default::default()
    };
    let a = run(cfg);
    let b = run(cfg);
    assert_eq!(a.len(), 2000);
    assert_eq!(a, b);
    let m1 = WalkingSimulator::new(cfg).unwrap().metadata();
    let m2 = WalkingSimulator::new(cfg).unwrap().metadata();
    assert_eq!(m1, m2);
}

#[test]
fn different_seeds_differ() {
    let cfg = WalkingConfig {
        duration_s: 5.0,
        seed: 1,
        ..Default::default()
    };
    let a = run(cfg);
    let b = run(WalkingConfig { seed: 2, ..cfg });
    let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert!(differing > a.len() * 9 / 10, "{differing}");
}

#[test]
fn invalid_configs_are_typed_errors_naming_the_parameter() {
    let bad = |cfg: WalkingConfig, name: &str| match WalkingSimulator::new(cfg) {
        Err(SimError::OutOfRange { name: n, .. }) => assert_eq!(n, name),
        other => panic!("expected OutOfRange({name}), got {other:?}"),
    };
    let d = WalkingConfig::default();
    bad(
        WalkingConfig {
            speed_mps: 0.39,
            ..d
        },
        "speed_mps",
    );
    bad(
        WalkingConfig {
            speed_mps: 1.81,
            ..d
        },
        "speed_mps",
    );
    bad(
        WalkingConfig {
            speed_mps: f64::NAN,
            ..d
        },
        "speed_mps",
    );
    bad(
        WalkingConfig {
            duration_s: 0.0,
            ..d
        },
        "duration_s",
    );
    bad(
        WalkingConfig {
            imu_rate_hz: -100.0,
            ..d
        },
        "imu_rate_hz",
    );
    bad(
        WalkingConfig {
            encoder_rate_hz: 0.0,
            ..d
        },
        "encoder_rate_hz",
    );
    bad(WalkingConfig { height_m: 3.0, ..d }, "height_m");
    let msg = WalkingSimulator::new(WalkingConfig {
        speed_mps: 2.5,
        ..d
    })
    .unwrap_err()
    .to_string();
    assert!(
        msg.contains("speed_mps") && msg.contains("[0.4, 1.8]"),
        "{msg}"
    );
}

#[test]
fn records_are_complete_and_joint_refs_are_exact_differences() {
    let sim = WalkingSimulator::new(WalkingConfig {
        duration_s: 2.0,
        ..Default::default()
    })
    .unwrap();
    assert_eq!(sim.len(), 200);
    for (k, r) in sim.enumerate() {
        assert_eq!(r.sample.t, k as f64 / 100.0);
        let s = r.reference.segment.map(|x| x.unwrap());
        let j = r.reference.joint.map(|x| x.unwrap());
        assert_eq!(j, [s[0] - s[1], s[1] - s[2], s[2] - s[3]]);
        assert!(r
            .sample
            .imu
            .iter()
            .all(|i| i.acc.is_some() && i.gyr.is_some()));
        assert!(r.sample.encoder.iter().all(|e| e.is_some()));
    }
}

#[test]
fn ideal_encoders_equal_the_joint_reference_and_noisy_ones_are_close() {
    let ideal = WalkingConfig {
        duration_s: 5.0,
        noise: false,
        ..Default::default()
    };
    for r in WalkingSimulator::new(ideal).unwrap() {
        assert_eq!(r.sample.encoder, r.reference.joint);
    }
    for mode in [EncoderResample::Latest, EncoderResample::Mean] {
        let sim = WalkingSimulator::new(WalkingConfig {
            duration_s: 10.0,
            encoder_resample: mode,
            ..Default::default()
        })
        .unwrap();
        let offs = sim.encoders().offset;
        let mut worst: f64 = 0.0;
        for r in sim {
            for (i, off) in offs.iter().enumerate() {
                let e = r.sample.encoder[i].unwrap() - r.reference.joint[i].unwrap() - off;
                worst = worst.max(e.abs());
            }
        }
        // Latest: noise + half a quantum; Mean: plus the 4.5 ms box-filter lag.
        let bound = if mode == EncoderResample::Latest {
            0.002
        } else {
            0.03
        };
        assert!(worst < bound, "{mode:?}: {worst}");
    }
}

#[test]
fn noisy_static_imu_shows_the_specified_noise_and_bias() {
    let cfg = WalkingConfig {
        motion: Motion::Stand,
        duration_s: 60.0,
        ..Default::default()
    };
    let sim = WalkingSimulator::new(cfg).unwrap();
    let b0 = sim.imus()[1].gyro.turn_on + sim.imus()[1].gyro.gm;
    let sigma = sim.imus()[1].gyro.white_sigma();
    let xs: Vec<f64> = sim.map(|r| r.sample.imu[1].gyr.unwrap().z).collect();
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    let sd = (xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / xs.len() as f64).sqrt();
    // white sigma = 0.007 deg/s/sqrt(Hz) * sqrt(50 Hz) ~ 8.6e-4 rad/s
    assert!((sd / sigma - 1.0).abs() < 0.1, "{sd} vs {sigma}");
    assert!((mean - b0.z).abs() < 1e-3);
}

/// The FES simulators stream their records (an audit: `simulate knee-fes`
/// and `fixed-hip` held every record in memory, 2 KB each: 409 MB for
/// 200 s at 1 kHz, 14 GB at their 3600 s x 2 kHz limit). The longest trial
/// gives its first records at once, equal to a short trial's, and the
/// in-memory functions are the streams collected.
#[test]
fn fes_trials_stream_and_equal_the_in_memory_ones() {
    use limbfuse_sim::fixed_hip::{fixed_hip_stream, simulate_fixed_hip, FixedHipConfig};
    use limbfuse_sim::knee_fes::{knee_fes_stream, simulate_knee_fes, KneeFesConfig};
    let short = KneeFesConfig {
        duration_s: 1.0,
        ..KneeFesConfig::default()
    };
    let long = KneeFesConfig {
        duration_s: 3600.0,
        rate_hz: 2000.0,
        ..short
    };
    let head: Vec<Record> = knee_fes_stream(&long).unwrap().records.take(5).collect();
    let short_2k = simulate_knee_fes(&KneeFesConfig {
        rate_hz: 2000.0,
        ..short
    })
    .unwrap();
    assert_eq!(head, short_2k.records[..5]);
    let a = simulate_knee_fes(&short).unwrap();
    let b = knee_fes_stream(&short).unwrap().collect();
    assert_eq!((a.records, a.metadata), (b.records, b.metadata));
    for t_a in [None, Some(0.1)] {
        let short = FixedHipConfig {
            duration_s: 1.0,
            activation_t_a: t_a,
            ..FixedHipConfig::default()
        };
        let long = FixedHipConfig {
            duration_s: 3600.0,
            ..short
        };
        let head: Vec<Record> = fixed_hip_stream(&long).unwrap().records.take(5).collect();
        let a = simulate_fixed_hip(&short).unwrap();
        assert_eq!(head, a.records[..5]);
        assert_eq!(a.records.len(), 100);
    }
}
