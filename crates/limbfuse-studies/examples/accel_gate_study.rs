//! Accelerometer-gate study (issue 3):
//! `cargo run --release -p limbfuse-studies --example accel_gate_study -- [FIRST] [LAST] [VARIANT ...] [--ideal] [--rate HZ]`
//!
//! 60 s simulated walking trials (default sensors, aligned mounting) at 0.4,
//! 1.0 and 1.6 m/s, seeds FIRST..=LAST; for each acceptance variant
//! (`AccelGate`, see `limbfuse_estimators::segment_kf::criteria`) the mean
//! 4-segment RMSE (deg) of local / mjls / global over the seeds and the
//! share of runs ordered mjls < global < local. A variant is `base` or
//! `+`-joined parts `holdMS` (`AccelGate::hold_s`, milliseconds) and
//! `gyroW` (`AccelGate::max_rate`, rad/s), e.g. `hold20+gyro1`; a suffix
//! `@mjls` applies the gate to mjls only (local and global keep the papers'
//! test). Default: the list `ALL`. `--ideal` switches every sensor error
//! off (`WalkingConfig::noise = false`); `--rate HZ` sets the IMU rate
//! (default 100).

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{
    CommonParams, GlobalKf, GlobalKfParams, LocalKf, LocalKfParams, MarkovJumpKf,
    MarkovJumpKfParams,
};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_studies::baseline_study::mean_rmse_deg;
use limbfuse_studies::example_args::{accel_gate, AccelGateStudyArgs};
use rayon::prelude::*;

const ALL: [&str; 10] = [
    "base",
    "hold10",
    "hold20",
    "hold30",
    "hold50",
    "gyro0.5",
    "gyro1",
    "gyro2",
    "hold20+gyro1",
    "hold10@mjls",
];

/// Mean 4-segment RMSE (deg), plain and offset-free.
fn mean_rmse(est: &mut dyn Estimator, records: &[Record]) -> [f64; 2] {
    mean_rmse_deg(est, records).expect("runs")
}

fn main() {
    let args = AccelGateStudyArgs::parse();
    let (a, b, ideal, rate_hz) = (args.first, args.last, args.ideal, args.rate);
    let named = args.variants;
    let variants: Vec<String> = if !named.is_empty() {
        named
    } else {
        ALL.iter().map(|s| s.to_string()).collect()
    };
    println!("seeds {a}..={b}, ideal sensors: {ideal}, IMU {rate_hz} Hz");
    println!("| variant | speed m/s | local | mjls | global | mjls<global<local | mjls max | mjls offset-free |");
    println!("|---|---|---|---|---|---|---|---|");
    for v in &variants {
        let gated = CommonParams {
            accel_gate: accel_gate(v).expect("checked by the parser"),
            ..CommonParams::default()
        };
        let common = if v.ends_with("@mjls") {
            CommonParams::default()
        } else {
            gated
        };
        for speed in [0.4, 1.0, 1.6] {
            let per: Vec<[f64; 4]> = (a..=b)
                .into_par_iter()
                .map(|seed| {
                    let cfg = WalkingConfig {
                        speed_mps: speed,
                        seed,
                        noise: !ideal,
                        imu_rate_hz: rate_hz,
                        ..WalkingConfig::default()
                    };
                    let records: Vec<Record> =
                        WalkingSimulator::new(cfg).expect("valid config").collect();
                    let l = mean_rmse(
                        &mut LocalKf::new(LocalKfParams {
                            common,
                            ..LocalKfParams::default()
                        })
                        .expect("valid"),
                        &records,
                    );
                    let m = mean_rmse(
                        &mut MarkovJumpKf::new(MarkovJumpKfParams {
                            common: gated,
                            ..MarkovJumpKfParams::default()
                        })
                        .expect("valid"),
                        &records,
                    );
                    let g = mean_rmse(
                        &mut GlobalKf::new(GlobalKfParams {
                            common,
                            ..GlobalKfParams::default()
                        })
                        .expect("valid"),
                        &records,
                    );
                    [l[0], m[0], g[0], m[1]]
                })
                .collect();
            let n = per.len() as f64;
            let avg = |k: usize| per.iter().map(|r| r[k]).sum::<f64>() / n;
            let ord = per.iter().filter(|r| r[1] < r[2] && r[2] < r[0]).count();
            let mx = per.iter().map(|r| r[1]).fold(0.0, f64::max);
            println!(
                "| {v} | {speed} | {:.2} | {:.2} | {:.2} | {ord}/{} | {:.2} | {:.2} |",
                avg(0),
                avg(1),
                avg(2),
                per.len(),
                mx,
                avg(3)
            );
        }
    }
}
