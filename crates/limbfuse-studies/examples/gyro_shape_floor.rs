//! The gyroscopes' own shape floor on a real recording (docs/RESULTS.md,
//! "Real data: gaittoolbox S02, after `align`", issue 14): plain gyro
//! integration (`gyro-integration`, built as `limbfuse estimate` builds it)
//! scored per window with the *ideal* offset and linear drift removed, i.e.
//! the RMS of the error's residual after a least-squares line in time,
//! minimised over lags of +-`--max-lag` samples per segment. No real-time
//! or offline estimator that only integrates these gyros can do better
//! than this on the window's shape; what remains is the gyro signal's own
//! disagreement with the reference.
//! `cargo run --release -p limbfuse-studies --example gyro_shape_floor -- TRIAL --window A:B [--window C:D] [--max-lag N]`

use std::path::Path;

use clap::Parser;
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::Segment;
use limbfuse_methods::MethodName;
use limbfuse_studies::example_args::GyroShapeFloorArgs;
use limbfuse_studies::recorded_trial::{run_defaults, RecordedTrial};

/// RMS of `e - (a + b t)` for the least-squares line; `None` under 3 points.
fn detrended_rms(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    if points.len() < 3 {
        return None;
    }
    let (mt, me) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (t, e)| (a + t / n, b + e / n));
    let (mut stt, mut ste, mut see) = (0.0, 0.0, 0.0);
    for (t, e) in points {
        let (dt, de) = (t - mt, e - me);
        stt += dt * dt;
        ste += dt * de;
        see += de * de;
    }
    let residual = if stt > 0.0 {
        see - ste * ste / stt
    } else {
        see
    };
    Some((residual.max(0.0) / n).sqrt())
}

fn main() {
    let args = GyroShapeFloorArgs::parse();
    let path = Path::new(&args.trial);
    let trial =
        RecordedTrial::read(path).unwrap_or_else(|e| panic!("{e} (run from the repository root)"));
    let records = &trial.records;
    let estimates = run_defaults(
        MethodName::GyroIntegration,
        &trial.meta,
        &trial.layout,
        records,
        &mut [],
    )
    .unwrap_or_else(|e| panic!("gyro-integration on {}: {e}", path.display()));
    let segments = [Segment::Thigh, Segment::Shank, Segment::Foot];
    let lag = args.max_lag as i64;
    println!(
        "{}: gyro-integration, offset and linear drift removed per window, lag within +-{} samples",
        path.display(),
        args.max_lag
    );
    println!("| window (s) | thigh | shank | foot | mean | lags thigh / shank / foot |");
    println!("|---|---|---|---|---|---|");
    for w in &args.windows {
        let (start, end) = *w;
        let mut row = Vec::new();
        let mut lags = Vec::new();
        for s in segments {
            let c = AngleChannel::Segment(s);
            let best = (-lag..=lag)
                .filter_map(|l| {
                    // Estimate at row k against the reference at row k - l
                    // (l > 0: the estimate trails the reference).
                    let points: Vec<(f64, f64)> = (0..records.len() as i64)
                        .filter_map(|k| {
                            let r = records.get(usize::try_from(k - l).ok()?)?;
                            let e = &estimates[k as usize];
                            let t = records[k as usize].sample.t;
                            if t < start || t > end {
                                return None;
                            }
                            Some((t, e.angle(c)? - r.reference.angle(c)?))
                        })
                        .collect();
                    detrended_rms(&points).map(|v| (v, l))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let (v, l) = best.unwrap_or((f64::NAN, 0));
            row.push(v.to_degrees());
            lags.push(l);
        }
        let mean = row.iter().sum::<f64>() / row.len() as f64;
        println!(
            "| {start}-{end} | {:.2} | {:.2} | {:.2} | **{mean:.2}** | {} / {} / {} |",
            row[0], row[1], row[2], lags[0], lags[1], lags[2]
        );
    }
}
