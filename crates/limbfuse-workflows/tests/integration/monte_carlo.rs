//! Monte Carlo: deterministic per seed (whatever the thread count), one row
//! per filter and level, perturbation that really changes the parameters.

use limbfuse_estimators::segment_kf::CommonParams;
use limbfuse_sim::WalkingConfig;
use limbfuse_workflows::monte_carlo::{
    levels_from_spec, monte_carlo, monte_carlo_cancellable, perturb, write_csv, MonteCarloConfig,
    MonteCarloError,
};
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

/// The Python binding's Ctrl-C hook (session 45): a study told to stop
/// stops with `Cancelled`, and one never told gives `monte_carlo`'s rows.
#[test]
fn a_cancelled_study_stops_and_an_uncancelled_one_gives_the_same_rows() {
    let never = || false;
    let a = monte_carlo(&small(), &|| {}).unwrap();
    let b = monte_carlo_cancellable(&small(), &|| {}, Some(&never)).unwrap();
    assert_eq!(a, b);
    let long = MonteCarloConfig {
        runs: 1000,
        levels: (0..=10).map(|k| k as f64 * 0.02).collect(),
        ..small()
    };
    let done = std::sync::atomic::AtomicUsize::new(0);
    let count = || {
        done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    };
    let now = || true;
    let r = monte_carlo_cancellable(&long, &count, Some(&now));
    assert!(matches!(r, Err(MonteCarloError::Cancelled)), "{r:?}");
    // (the hook is first asked 50 ms in: a few runs of 11 levels at most,
    // of the 1000 that take minutes)
    assert!(done.into_inner() < 100);
}

#[test]
fn levels_are_read_in_percent_and_bad_ones_are_named() {
    assert_eq!(
        levels_from_spec("0:20:5").unwrap(),
        vec![0.0, 0.05, 0.1, 0.15, 0.2]
    );
    assert_eq!(levels_from_spec("0:1:0.1").unwrap()[3], 0.003);
    for (bad, says) in [
        ("0:20", "expected START:END:STEP"),
        ("a:b:c", "expected START:END:STEP"),
        ("0:20:0", "STEP > 0"),
        ("5:1:1", "START <= END"),
        ("0:100:10", "END < 100"),
        (
            "0:10:3",
            "END is not START + k STEP (the last level would be 9)",
        ),
        ("0:99:0.01", "9901 levels is too many"),
    ] {
        let e = levels_from_spec(bad).unwrap_err();
        assert!(e.contains(says), "{bad}: {e}");
    }
}
