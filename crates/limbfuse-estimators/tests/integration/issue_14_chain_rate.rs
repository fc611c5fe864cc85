//! Issue 14 (generality): `chain` gives the same answer at any sample rate
//! (docs/CHAIN.md, "Sample rate"; docs/RESULTS.md, "Sample rate"). Before
//! the fix every measurement variance was per sample, so at 200 Hz the
//! sensors and anchors carried twice the information per second of 100 Hz:
//! the filter grew confident (shank 1-sigma x0.67) and the real trial S02's
//! second pass lost 0.5 deg on the shank. Short simulated walks (10 s) so
//! that the test stays fast in debug builds.

use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_estimators::chain_ekf::{ChainDiag, ChainEkf, ChainGeometry, ChainParams};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

/// Scored from this time (s): after the 1 s start-up and its transient.
const SCORED_FROM_S: f64 = 2.0;

/// Mean shank 1-sigma (rad) and offset-free shank RMSE (deg) of `chain` on
/// limbfuse's simulated walk at `rate` Hz.
fn shank_sd_and_rmse(rate: f64) -> (f64, f64) {
    let records: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        duration_s: 10.0,
        seed: 2,
        speed_mps: 1.2,
        imu_rate_hz: rate,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect();
    let mut chain = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
    let k = ChainDiag::SdShank.index();
    let (mut sd, mut errors) = (Vec::new(), Vec::new());
    for r in &records {
        let e = chain.step(&r.sample).unwrap();
        if r.sample.t < SCORED_FROM_S {
            continue;
        }
        sd.push(e.diag[k].unwrap());
        let truth = r.reference.segment[Segment::Shank.index()].unwrap();
        errors.push(e.segment[Segment::Shank.index()].unwrap() - truth);
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let bias = mean(&errors);
    let rmse = errors.iter().map(|e| (e - bias).powi(2)).sum::<f64>() / errors.len() as f64;
    (mean(&sd), rmse.sqrt().to_degrees())
}

/// At 200 Hz the filter's stated uncertainty stays within 25 % of 100 Hz
/// (before the fix: 0.67 times it; with the fix 0.83: the discrete filter
/// at 100 Hz is not at its continuous-time limit, docs/CHAIN.md), and the
/// offset-free shank error within 0.05 deg.
#[test]
fn issue_14_chain_rate_200_hz_as_confident_and_accurate_as_100_hz() {
    let (sd100, e100) = shank_sd_and_rmse(100.0);
    let (sd200, e200) = shank_sd_and_rmse(200.0);
    let ratio = sd200 / sd100;
    eprintln!("shank sd 100 Hz {sd100:.5} rad, 200 Hz {sd200:.5} rad (ratio {ratio:.3}); offset-free RMSE {e100:.3} / {e200:.3} deg");
    assert!(
        (0.75..=1.0 / 0.75).contains(&ratio),
        "shank 1-sigma at 200 Hz is {ratio:.3} times that at 100 Hz"
    );
    assert!(
        (e200 - e100).abs() < 0.05,
        "offset-free shank RMSE {e100:.3} deg at 100 Hz, {e200:.3} deg at 200 Hz"
    );
}
