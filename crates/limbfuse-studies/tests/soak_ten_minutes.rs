//! The 10-minute soak of issue 18 item 4 (the 24-hour one is the `soak`
//! example, figures in docs/RESULTS.md): every real-time segment and knee
//! estimator over 10 simulated minutes at 100 Hz with a glitch every 30 s,
//! against the same stream without glitches. The glitches of the issue's
//! criterion (a 1e300 gyro cell, a -1e308 accelerometer cell, a saturated
//! burst) and a 1e9 encoder reading must cost at most 0.5 deg of mean RMSE;
//! 1 s gaps of every IMU (issue 18 item 2, docs/RESULTS.md) are run too and
//! must leave every output finite; for `mjls` and `knee-selfalign`, whose
//! gap handling was fixed, their cost is bounded as measured (`GAP_COST`).
//! One test, so that the resident-memory figures are not those of other
//! tests running beside it.

use limbfuse_methods::MethodName;
use limbfuse_studies::soak::{soak, Glitch, SoakConfig, SoakReport};

/// The glitches whose cost is bounded.
const BOUNDED: [Glitch; 4] = [
    Glitch::GyroHuge,
    Glitch::AccHuge,
    Glitch::SaturatedBurst,
    Glitch::EncoderHuge,
];

/// Largest cost (deg of mean RMSE) of a 1 s gap of every IMU every 30 s,
/// per method with a bound: measured 2026-12-02 (seed 1) mjls 2.174 ->
/// 2.488 (+0.31; before the fix 5.797) and knee-selfalign 0.797 -> 6.067
/// (+5.27; before 18.602); branch `missing2`: mjls 2.505 (+0.33), chain
/// 2.253 -> 2.279 (+0.03; before its trunk hold 3.702). local/global are
/// not bounded (not fixed: +3.7).
fn gap_cost(m: MethodName) -> Option<f64> {
    match m {
        MethodName::Mjls => Some(0.5),
        MethodName::Chain => Some(0.3),
        MethodName::KneeSelfAlign => Some(6.0),
        _ => None,
    }
}

/// 10 minutes, reported per minute.
fn run(method: MethodName, glitches: &'static [Glitch], every: f64) -> SoakReport {
    soak(&SoakConfig {
        method,
        duration_s: 600.0,
        seed: 1,
        chunk_s: 60.0,
        glitch_every_s: every,
        glitches,
    })
    .expect("soak runs")
}

/// Mean of the per-minute RMSEs (deg).
fn mean_rmse(r: &SoakReport) -> f64 {
    r.chunks.iter().map(|c| c.rmse_deg).sum::<f64>() / r.chunks.len() as f64
}

#[test]
fn issue_18_soak_ten_minutes_with_glitches_and_gaps() {
    let methods = [
        MethodName::Local,
        MethodName::Mjls,
        MethodName::Global,
        MethodName::Chain,
        MethodName::KneeSelfAlign,
    ];
    let mut failures = Vec::new();
    for m in methods {
        let clean = run(m, &[], f64::INFINITY);
        let glitchy = run(m, &BOUNDED, 30.0);
        let gaps = run(m, &[Glitch::Gap], 30.0);
        assert_eq!(clean.samples, 60_000, "{m}");
        assert_eq!(
            glitchy.glitches, 19,
            "{m}: a glitch every 30 s from t = 30 s"
        );
        let (c, g) = (mean_rmse(&clean), mean_rmse(&glitchy));
        let worst = glitchy.max_rmse_deg();
        let non_finite: u64 = glitchy
            .chunks
            .iter()
            .chain(&gaps.chunks)
            .map(|c| c.non_finite)
            .sum();
        // Memory: the estimator allocates nothing per step, so the process
        // does not grow between the first and the last minute.
        let rss = |r: &SoakReport, k: usize| r.chunks[k].rss_kb;
        let growth = match (rss(&glitchy, 1), rss(&glitchy, glitchy.chunks.len() - 1)) {
            (Some(a), Some(b)) => b.saturating_sub(a),
            _ => 0,
        };
        println!(
            "{m}: clean {c:.3} deg, glitches {g:.3} deg (worst minute {worst:.3}), 1 s gaps {:.3} deg, non-finite {non_finite}, RSS growth {growth} kB",
            mean_rmse(&gaps)
        );
        if non_finite > 0 {
            failures.push(format!("{m}: {non_finite} non-finite outputs"));
        }
        if growth > 512 {
            failures.push(format!("{m}: resident memory grew by {growth} kB"));
        }
        // Bounded error: the glitches may cost at most 0.5 deg of mean
        // RMSE (issue 18's glitch criterion), and no minute may be lost.
        if g > c + 0.5 {
            failures.push(format!("{m}: mean RMSE {c:.3} -> {g:.3} deg with glitches"));
        }
        if let Some(bound) = gap_cost(m) {
            let gap = mean_rmse(&gaps);
            if gap > c + bound {
                failures.push(format!(
                    "{m}: mean RMSE {c:.3} -> {gap:.3} deg with 1 s gaps (bound +{bound})"
                ));
            }
        }
        let clean_worst = clean.max_rmse_deg();
        if worst > 2.0 * clean_worst + 1.0 {
            failures.push(format!(
                "{m}: worst minute {worst:.3} deg with glitches (clean {clean_worst:.3})"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
