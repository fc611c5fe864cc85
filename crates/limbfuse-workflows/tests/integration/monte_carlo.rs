//! Monte Carlo: deterministic per seed (whatever the thread count), one row
//! per filter and level, perturbation that really changes the parameters.

use limbfuse_estimators::segment_kf::CommonParams;
use limbfuse_sim::WalkingConfig;
use limbfuse_workflows::monte_carlo::{monte_carlo, perturb, write_csv, MonteCarloConfig};
use rand::SeedableRng;

fn small() -> MonteCarloConfig {
    MonteCarloConfig {
        runs: 3,
        levels: vec![0.0, 0.2],
        seed: 11,
        trial: WalkingConfig {
            duration_s: 8.0,
            ..WalkingConfig::default()
        },
    }
}

#[test]
fn same_seed_same_result_bit_for_bit() {
    let a = monte_carlo(&small(), &|| {}).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let b = pool.install(|| monte_carlo(&small(), &|| {})).unwrap();
    assert_eq!(a, b);
    assert_eq!(a.len(), 3 * 2);
    let mut csv = Vec::new();
    write_csv(&a, &[], &mut csv).unwrap();
    assert_eq!(String::from_utf8(csv).unwrap().lines().count(), 7);
    let c = monte_carlo(
        &MonteCarloConfig {
            seed: 12,
            ..small()
        },
        &|| {},
    )
    .unwrap();
    assert_ne!(a, c);
}

#[test]
fn perturbation_stays_within_the_level_and_zero_level_is_identity() {
    let base = CommonParams::default();
    let enc = [0.01, 0.01, 0.01];
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let (same, e0) = perturb(&base, &enc, 0.0, &mut rng);
    assert_eq!(same, base);
    assert_eq!(e0, enc);
    let (p, e) = perturb(&base, &enc, 0.2, &mut rng);
    assert_ne!(p, base);
    for (s, b) in p.segments.iter().zip(base.segments.iter()) {
        for (x, y) in [
            (s.gyro_noise, b.gyro_noise),
            (s.bias_drive, b.bias_drive),
            (s.accel_angle_sigma, b.accel_angle_sigma),
        ] {
            assert!((x / y - 1.0).abs() <= 0.2 + 1e-12);
        }
    }
    assert!(e.iter().all(|v| (v / 0.01 - 1.0).abs() <= 0.2 + 1e-12));
}

#[test]
fn bad_configuration_is_an_error() {
    assert!(monte_carlo(&MonteCarloConfig { runs: 0, ..small() }, &|| {}).is_err());
    assert!(monte_carlo(
        &MonteCarloConfig {
            levels: vec![1.5],
            ..small()
        },
        &|| {}
    )
    .is_err());
}
