//! Time base (docs/RESULTS.md, "Invariance audit", "Time base"): a trial's
//! clock moved by a constant (default a Unix time, 1.7e9 s, where the
//! stamps' resolution is 2.4e-7 s) must give the same estimates.
//! `cargo run --release -p limbfuse-studies --example time_base_study -- [TRIAL] [--offset S]
//! [--methods M,...] [--from S] [-o SHIFTED]`
//!
//! Each method (default: knee-selfalign, mjls, chain), built as `limbfuse
//! estimate` builds it with its defaults, runs on the recorded and on the
//! shifted clock (`limbfuse_signal::recording_variants::shift_time`); per
//! method the largest and the RMS difference of the seven angle channels
//! between the two runs (and when the largest occurs, in seconds from the
//! first sample), the largest speed difference, the rows whose foot
//! contacts or gait phase differ, and the RMSE against the reference on both clocks (knee,
//! and the mean over the channels the method estimates), scored from
//! `--from` seconds after the first sample. `-o` also writes the shifted
//! trial, for `limbfuse estimate` and `limbfuse evaluate`.

use std::io::BufWriter;
use std::path::Path;

use clap::Parser;
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimate, Joint, Record};
use limbfuse_eval::{AngleMetrics, EvalOptions, TimeWindow};
use limbfuse_io::{TrialLayout, TrialMeta, TrialWriter};
use limbfuse_methods::MethodName;
use limbfuse_signal::recording_variants::shift_time;
use limbfuse_studies::example_args::TimeBaseStudyArgs;
use limbfuse_studies::recorded_trial::{run_defaults, RecordedTrial};

/// The estimates of `method` over `records`, and its knee RMSE and mean
/// RMSE (deg) from `start` (absolute time).
fn run_method(
    method: MethodName,
    meta: &TrialMeta,
    layout: &TrialLayout,
    records: &[Record],
    start: f64,
) -> (Vec<Estimate>, Option<f64>, Option<f64>) {
    let options = EvalOptions {
        window: TimeWindow {
            start: Some(start),
            end: None,
        },
        ..EvalOptions::default()
    };
    let mut metrics = AngleMetrics::new(method.name(), options);
    let all = run_defaults(method, meta, layout, records, &mut [&mut metrics])
        .unwrap_or_else(|e| panic!("{}: {e}", method.name()));
    let ev = metrics.evaluation();
    let knee = ev
        .rmse(AngleChannel::Joint(Joint::Knee))
        .map(f64::to_degrees);
    let mean = ev.mean_rmse().map(f64::to_degrees);
    (all, knee, mean)
}

fn angles(e: &Estimate) -> impl Iterator<Item = Option<f64>> + '_ {
    e.segment.iter().chain(e.joint.iter()).copied()
}

fn deg(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

fn main() {
    let args = TimeBaseStudyArgs::parse();
    let path = Path::new(&args.trial);
    let RecordedTrial {
        meta,
        layout,
        records,
    } = RecordedTrial::read(path).unwrap_or_else(|e| panic!("{e} (run from the repository root)"));
    let t0 = records.first().map_or(0.0, |r| r.sample.t);
    let mut shifted = records.clone();
    shift_time(&mut shifted, args.offset);
    if let Some(out) = &args.output {
        let file = std::fs::File::create(out).unwrap_or_else(|e| panic!("{out}: {e}"));
        let mut w = TrialWriter::for_path(Path::new(out), BufWriter::new(file), &meta, layout)
            .unwrap_or_else(|e| panic!("{out}: {e}"));
        for r in &shifted {
            w.write(r).unwrap_or_else(|e| panic!("{out}: {e}"));
        }
        w.finish().unwrap_or_else(|e| panic!("{out}: {e}"));
        eprintln!("wrote {out} (clock + {} s)", args.offset);
    }
    let methods = if args.methods.is_empty() {
        vec![
            MethodName::KneeSelfAlign,
            MethodName::Mjls,
            MethodName::Chain,
        ]
    } else {
        args.methods.clone()
    };
    println!(
        "{}: clock + {} s, {} samples, scored from {} s",
        path.display(),
        args.offset,
        records.len(),
        args.from
    );
    println!("| method | angles: max difference rad (at s) | RMS difference deg | speed: max difference m/s | rows whose contacts or phase differ | knee RMSE deg recorded / shifted | mean RMSE deg recorded / shifted |");
    println!("|---|---|---|---|---|---|---|");
    for method in methods {
        let (a, knee_a, mean_a) = run_method(method, &meta, &layout, &records, t0 + args.from);
        let (b, knee_b, mean_b) = run_method(
            method,
            &meta,
            &layout,
            &shifted,
            t0 + args.offset + args.from,
        );
        let (mut max, mut at, mut sq, mut n) = (0.0f64, 0.0, 0.0, 0usize);
        for (ea, eb) in a.iter().zip(&b) {
            for (x, y) in angles(ea).zip(angles(eb)) {
                if let (Some(x), Some(y)) = (x, y) {
                    let d = (x - y).abs();
                    if d > max {
                        (max, at) = (d, ea.t - t0);
                    }
                    sq += d * d;
                    n += 1;
                }
            }
        }
        let rms = (sq / n.max(1) as f64).sqrt().to_degrees();
        // Speed and foot contacts (gait methods).
        let (mut speed_max, mut contacts) = (0.0f64, 0usize);
        for (ea, eb) in a.iter().zip(&b) {
            if let (Some(x), Some(y)) = (ea.speed, eb.speed) {
                speed_max = speed_max.max((x - y).abs());
            }
            contacts += usize::from(ea.contact != eb.contact || ea.phase != eb.phase);
        }
        println!(
            "| {} | {max:.2e} ({at:.2}) | {rms:.4} | {speed_max:.2e} | {contacts} | {} / {} | {} / {} |",
            method.name(),
            deg(knee_a),
            deg(knee_b),
            deg(mean_a),
            deg(mean_b)
        );
    }
}
