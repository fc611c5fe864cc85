//! Missing IMU data (issue 18 item 2, for docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example robust_input_study -- [--seeds N] [--missing-pct P]
//! [--cells both|acc|gyr] [--per-segment] [--methods mjls,chain] [--whole-vectors]`
//!
//! On the three shared independent walking trials
//! (`independent-sim/walk-*.csv`), each IMU cell (the 24 accelerometer and
//! gyroscope columns) is made missing with probability `P` (default 20 %),
//! independently, with seeds 1..=N; the present axes of a vector with a
//! missing axis stay, as the trial reader keeps them (`--whole-vectors`: the
//! whole vector goes, as the reader made it before issue 18 item 2). Per method: the mean 4-segment
//! RMSE of the clean trial, the mean over seeds of the masked trials', and
//! the relative increase (of the mean, and of the worst seed). The estimators are built as `limbfuse estimate`
//! builds them (`limbfuse_methods::build`, behind the sensor gate).

use std::convert::Infallible;
use std::path::Path;

use clap::Parser;
use limbfuse_core::runner::{run, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Record, Segment};
use limbfuse_eval::{AngleMetrics, EvalOptions};
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader};
use limbfuse_methods::{build, MethodName, MethodSpec};
use limbfuse_studies::example_args::{MaskedCells, RobustInputStudyArgs};
use rayon::prelude::*;

/// SplitMix64: a small seeded generator (reproducible bit for bit).
struct SplitMix(u64);

impl SplitMix {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `records` with each IMU cell of the `cells` kind missing with
/// probability `p`. With `whole_vectors` a vector with any missing axis
/// becomes missing (as the trial reader made it before issue 18 item 2);
/// otherwise the present axes stay, as the trial reader keeps them.
fn mask(
    records: &[Record],
    p: f64,
    seed: u64,
    cells: MaskedCells,
    whole_vectors: bool,
) -> Vec<Record> {
    let mut rng = SplitMix(seed.wrapping_mul(0x2545_F491_4F6C_DD1D));
    let mut drop = |axes: [Option<f64>; 3], masked: bool| {
        // draw all three cells so the pattern does not depend on the data
        let gone: [bool; 3] = core::array::from_fn(|_| rng.uniform() < p);
        if !masked {
            return axes;
        }
        if whole_vectors && gone.iter().any(|&g| g) {
            return [None; 3];
        }
        core::array::from_fn(|k| axes[k].filter(|_| !gone[k]))
    };
    records
        .iter()
        .map(|r| {
            let mut r = *r;
            for imu in r.sample.imu.iter_mut() {
                let acc = drop(imu.acc_axes(), cells != MaskedCells::Gyr);
                let gyr = drop(imu.gyr_axes(), cells != MaskedCells::Acc);
                imu.set_acc_axes(acc);
                imu.set_gyr_axes(gyr);
            }
            r
        })
        .collect()
}

/// RMSE (deg) of each segment (trunk, thigh, shank, foot) of `method` over `records`.
fn segment_rmse(
    method: MethodName,
    meta: &TrialMeta,
    layout: &TrialLayout,
    records: &[Record],
) -> [f64; 4] {
    let spec = MethodSpec::defaults(method).expect("defaults");
    let mut est = build(&spec, meta, layout).expect("builds");
    let mut m = AngleMetrics::new(method.name(), EvalOptions::default());
    let observers: &mut [&mut dyn Observer] = &mut [&mut m];
    run(
        est.as_mut(),
        records.iter().map(|r| Ok::<_, Infallible>(*r)),
        observers,
    )
    .expect("runs");
    let ev = m.evaluation();
    Segment::ALL.map(|s| {
        ev.rmse(AngleChannel::Segment(s))
            .expect("scored")
            .to_degrees()
    })
}

fn mean4(v: &[f64; 4]) -> f64 {
    v.iter().sum::<f64>() / 4.0
}

fn segments(v: &[f64; 4]) -> String {
    format!("{:.2} / {:.2} / {:.2} / {:.2}", v[0], v[1], v[2], v[3])
}

fn main() {
    let args = RobustInputStudyArgs::parse();
    let p = args.missing_pct / 100.0;
    let dir = Path::new(&args.data).join("independent-sim");
    let trials = [
        "walk-v0.7-s300.csv",
        "walk-v1.2-s301.csv",
        "walk-v1.6-s302.csv",
    ];
    let methods = if args.methods.is_empty() {
        vec![
            MethodName::Mjls,
            MethodName::Chain,
            MethodName::Global,
            MethodName::Local,
        ]
    } else {
        args.methods.clone()
    };
    println!(
        "| trial | method | clean RMSE deg | {:.0} % IMU cells ({:?}) missing: mean over {} seeds (worst) | increase (worst seed) |{}",
        args.missing_pct,
        args.cells,
        args.seeds,
        if args.per_segment {
            " clean trunk / thigh / shank / foot | masked, mean over seeds |"
        } else {
            ""
        }
    );
    println!(
        "|---|---|---|---|---|{}",
        if args.per_segment { "---|---|" } else { "" }
    );
    for t in trials {
        let path = dir.join(t);
        let reader = TrialReader::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (run from the repository root)", path.display()));
        let meta = reader.meta().clone();
        let layout = *reader.layout();
        let records: Vec<Record> = reader.map(|r| r.expect("valid trial")).collect();
        for &method in &methods {
            let clean_seg = segment_rmse(method, &meta, &layout, &records);
            let clean = mean4(&clean_seg);
            let masked_seg: Vec<[f64; 4]> = (1..=args.seeds)
                .into_par_iter()
                .map(|seed| {
                    let masked = mask(&records, p, seed, args.cells, args.whole_vectors);
                    segment_rmse(method, &meta, &layout, &masked)
                })
                .collect();
            let masked: Vec<f64> = masked_seg.iter().map(mean4).collect();
            let mean = masked.iter().sum::<f64>() / masked.len() as f64;
            let worst = masked.iter().cloned().fold(f64::MIN, f64::max);
            let per_segment = if args.per_segment {
                let n = masked_seg.len() as f64;
                let m: [f64; 4] =
                    core::array::from_fn(|k| masked_seg.iter().map(|s| s[k]).sum::<f64>() / n);
                format!(" {} | {} |", segments(&clean_seg), segments(&m))
            } else {
                String::new()
            };
            println!(
                "| {t} | {} | {clean:.2} | {mean:.2} ({worst:.2}) | {:+.0} % ({:+.0} %) |{per_segment}",
                method.name(),
                100.0 * (mean / clean - 1.0),
                100.0 * (worst / clean - 1.0)
            );
        }
    }
}
