//! Segment-filter study of issue 3 (for docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example segment_study -- [SEEDS]`
//!
//! 60 s simulated walking trials (default sensors, aligned mounting) at 0.4,
//! 1.0 and 1.6 m/s, seeds 1..=N (default 30); per speed: per-segment RMSE of
//! local / mjls / global (mean over seeds), accelerometer reliability AR %
//! (share of samples with rho < zeta, 001 Table 2), and the share of runs
//! ordered mjls < global < local on the mean 4-segment RMSE.

use clap::Parser;
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_estimators::segment_kf::{CommonParams, GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_studies::baseline_study::evaluate_records;
use limbfuse_studies::example_args::SegmentStudyArgs;
use rayon::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n = SegmentStudyArgs::parse().seeds;
    let zeta = CommonParams::default().zetas();
    println!("| speed m/s | method | trunk | thigh | shank | foot | mean | hip | knee | ankle |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut summary = Vec::new();
    for speed in [0.4, 1.0, 1.6] {
        // per seed: [method][channel 0..7 + mean], AR per segment
        let per_seed: Vec<([[f64; 8]; 3], [f64; 4])> = (1..=n)
            .into_par_iter()
            .map(|seed| {
                let cfg = WalkingConfig {
                    speed_mps: speed,
                    seed,
                    ..WalkingConfig::default()
                };
                let records: Vec<Record> =
                    WalkingSimulator::new(cfg).expect("valid config").collect();
                let mut ar = [0.0; 4];
                for r in &records {
                    for s in Segment::ALL {
                        if let Some(a) = r.sample.imu[s.index()].acc {
                            if (a.norm() - cfg.g).abs() < zeta[s.index()] {
                                ar[s.index()] += 100.0 / records.len() as f64;
                            }
                        }
                    }
                }
                let mut out = [[0.0; 8]; 3];
                let evs = [
                    evaluate_records(&mut LocalKf::default(), &records)
                        .expect("runs")
                        .0,
                    evaluate_records(&mut MarkovJumpKf::default(), &records)
                        .expect("runs")
                        .0,
                    evaluate_records(&mut GlobalKf::default(), &records)
                        .expect("runs")
                        .0,
                ];
                for (m, ev) in evs.iter().enumerate() {
                    for (k, c) in AngleChannel::ALL.iter().enumerate() {
                        out[m][k] = ev.rmse(*c).unwrap_or(f64::NAN).to_degrees();
                    }
                    out[m][7] = ev.mean_rmse().unwrap_or(f64::NAN).to_degrees();
                }
                (out, ar)
            })
            .collect();
        let nn = per_seed.len() as f64;
        let names = [
            LocalKf::default().name(),
            MarkovJumpKf::default().name(),
            GlobalKf::default().name(),
        ];
        for (m, name) in names.iter().enumerate() {
            let mean = |k: usize| per_seed.iter().map(|(o, _)| o[m][k]).sum::<f64>() / nn;
            println!(
                "| {speed} | {name} | {:.2} | {:.2} | {:.2} | {:.2} | **{:.2}** | {:.2} | {:.2} | {:.2} |",
                mean(0), mean(1), mean(2), mean(3), mean(7), mean(4), mean(5), mean(6)
            );
        }
        let ar: Vec<String> = (0..4)
            .map(|s| {
                format!(
                    "{:.1}",
                    per_seed.iter().map(|(_, a)| a[s]).sum::<f64>() / nn
                )
            })
            .collect();
        println!(
            "| {speed} | AR % (rho < zeta) | {} | | | | |",
            ar.join(" | ")
        );
        let ordered = per_seed
            .iter()
            .filter(|(o, _)| o[1][7] < o[2][7] && o[2][7] < o[0][7])
            .count();
        let max_m = |m: usize| per_seed.iter().map(|(o, _)| o[m][7]).fold(0.0, f64::max);
        summary.push(format!(
            "{speed} m/s: mjls < global < local in {ordered}/{} runs; worst-run mean RMSE local {:.2}, mjls {:.2}, global {:.2} deg",
            per_seed.len(), max_m(0), max_m(1), max_m(2)
        ));
    }
    println!();
    for s in summary {
        println!("- {s}");
    }
    Ok(())
}
