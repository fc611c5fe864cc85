//! `chain --smooth` (issue 14, offline RTS smoother) on limbfuse's walking
//! simulator: smoothed RMSE below filtered, blocks with overlap against the
//! whole-trial smoother, same seed bit for bit, bounded memory.

use limbfuse_core::{Estimate, OfflineEstimator, Record};
use limbfuse_estimators::chain_ekf::smoother::SmootherSettings;
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_methods::smoothed_chain::build_smoothed;
use limbfuse_methods::{MethodName, MethodSpec};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

fn trial(speed: f64, seed: u64, duration: f64) -> (TrialMeta, Vec<Record>) {
    let cfg = WalkingConfig {
        speed_mps: speed,
        seed,
        duration_s: duration,
        ..WalkingConfig::default()
    };
    let sim = WalkingSimulator::new(cfg).unwrap();
    let mut meta = TrialMeta::trial_v1();
    for (k, v) in sim.metadata() {
        meta.set(&k, &v);
    }
    (meta, sim.collect())
}

/// Filtered and smoothed estimates of every record.
fn run(meta: &TrialMeta, recs: &[Record], s: SmootherSettings) -> (Vec<Estimate>, Vec<Estimate>) {
    let spec = MethodSpec::defaults(MethodName::Chain).unwrap();
    let mut sm = build_smoothed(&spec, meta, &TrialLayout::walking(), s).unwrap();
    let mut filtered = Vec::new();
    let mut smoothed = Vec::new();
    for r in recs {
        sm.push(&r.sample).unwrap();
        smoothed.extend(core::iter::from_fn(|| sm.pop()));
    }
    sm.finish();
    smoothed.extend(core::iter::from_fn(|| sm.pop()));
    let mut f = limbfuse_methods::build(&spec, meta, &TrialLayout::walking()).unwrap();
    for r in recs {
        filtered.push(f.step(&r.sample).unwrap());
    }
    (filtered, smoothed)
}

/// Offset-free RMSE (deg) of the four segments, mean, over estimated samples.
fn offset_free(recs: &[Record], est: &[Estimate]) -> f64 {
    let mut total = 0.0;
    for i in 0..4 {
        let e: Vec<f64> = recs
            .iter()
            .zip(est)
            .filter_map(|(r, e)| Some(e.segment[i]? - r.reference.segment[i]?))
            .collect();
        let m = e.iter().sum::<f64>() / e.len() as f64;
        total += (e.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / e.len() as f64).sqrt();
    }
    (total / 4.0).to_degrees()
}

#[test]
fn smoothed_is_better_than_filtered_and_blocks_match_the_whole_trial() {
    for (speed, seed) in [(0.7, 1), (1.4, 2)] {
        let (meta, recs) = trial(speed, seed, 60.0);
        let (filtered, blocks) = run(&meta, &recs, SmootherSettings::default());
        let (_, whole) = run(&meta, &recs, SmootherSettings::WHOLE_TRIAL);
        assert_eq!(blocks.len(), recs.len());
        let (f, b, w) = (
            offset_free(&recs, &filtered),
            offset_free(&recs, &blocks),
            offset_free(&recs, &whole),
        );
        let (max_diff, rms_diff) = difference(&blocks, &whole);
        println!(
            "speed {speed} seed {seed}: offset-free mean 4 segments filtered {f:.4} / blocks 10+2 s {b:.4} / whole {w:.4} deg; blocks vs whole max {max_diff:.2e} rms {rms_diff:.2e} deg"
        );
        for overlap in [4.0, 8.0] {
            let (_, o) = run(
                &meta,
                &recs,
                SmootherSettings {
                    block_s: 10.0,
                    overlap_s: overlap,
                },
            );
            let (m, r) = difference(&o, &whole);
            println!("  overlap {overlap} s: blocks vs whole max {m:.2e} rms {r:.2e} deg, offset-free {:.4}", offset_free(&recs, &o));
        }
        assert!(b < f, "smoothed {b} not below filtered {f}");
        assert!(
            max_diff < 0.15 && rms_diff < 0.05 && (b - w).abs() < 0.005,
            "{max_diff} {rms_diff}"
        );
        // Same samples estimated as the filter, and smoothed sd <= filtered sd.
        for (a, b) in filtered.iter().zip(&blocks) {
            assert_eq!(a.segment[0].is_some(), b.segment[0].is_some());
        }
    }
}

/// Max and RMS difference (deg) of the segment angles of two runs.
fn difference(a: &[Estimate], b: &[Estimate]) -> (f64, f64) {
    let (mut max, mut sq, mut n) = (0.0f64, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.t, y.t);
        for i in 0..4 {
            assert_eq!(x.segment[i].is_some(), y.segment[i].is_some());
            if let (Some(p), Some(q)) = (x.segment[i], y.segment[i]) {
                let d = (p - q).to_degrees();
                max = max.max(d.abs());
                sq += d * d;
                n += 1.0;
            }
        }
    }
    (max, (sq / n).sqrt())
}

#[test]
fn same_seed_same_output_bit_for_bit() {
    let (meta, recs) = trial(1.0, 5, 15.0);
    let (_, a) = run(&meta, &recs, SmootherSettings::default());
    let (_, b) = run(&meta, &recs, SmootherSettings::default());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            x.segment.map(|v| v.map(f64::to_bits)),
            y.segment.map(|v| v.map(f64::to_bits))
        );
        assert_eq!(
            x.diag.map(|v| v.map(f64::to_bits)),
            y.diag.map(|v| v.map(f64::to_bits))
        );
    }
}

#[test]
fn smoothing_other_methods_is_refused() {
    let spec = MethodSpec::defaults(MethodName::Global).unwrap();
    let e = build_smoothed(
        &spec,
        &TrialMeta::trial_v1(),
        &TrialLayout::walking(),
        SmootherSettings::default(),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("global") && e.contains("--smooth"), "{e}");
}

#[test]
fn the_smoother_does_not_cross_a_gap_that_restarts_the_filter() {
    // 20 s of walking with 3 s removed at 8-11 s: the filter restarts
    // (start-up window again) after the gap.
    let (meta, recs) = trial(1.0, 3, 20.0);
    let recs: Vec<Record> = recs
        .into_iter()
        .filter(|r| !(8.0..11.0).contains(&r.sample.t))
        .collect();
    let (filtered, smoothed) = run(&meta, &recs, SmootherSettings::default());
    assert_eq!(filtered.len(), smoothed.len());
    let last_before = recs.iter().rposition(|r| r.sample.t < 8.0).unwrap();
    for (k, (f, s)) in filtered.iter().zip(&smoothed).enumerate() {
        // Estimated exactly where the filter estimated.
        assert_eq!(f.segment[1].is_some(), s.segment[1].is_some(), "row {k}");
    }
    // The last step before the gap ends a backward pass: filtered = smoothed.
    assert_eq!(filtered[last_before].segment, smoothed[last_before].segment);
    // Earlier steps are smoothed, and so are steps after the restart.
    assert_ne!(
        filtered[last_before - 50].segment,
        smoothed[last_before - 50].segment
    );
    let after = recs.iter().position(|r| r.sample.t > 13.0).unwrap();
    assert!(smoothed[after].segment[1].is_some());
    assert_ne!(filtered[after].segment, smoothed[after].segment);
    // Nothing estimated in the restarted start-up window.
    let first_after = last_before + 1;
    assert!(smoothed[first_after].segment[1].is_none());
}
