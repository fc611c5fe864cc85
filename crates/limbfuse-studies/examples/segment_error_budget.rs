//! Error budget of the segment filters (issue 3, for docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example segment_error_budget -- [SEEDS]`
//!
//! Which sensor error sources set the floor of the mean 4-segment RMSE?
//! The same walking trials (seeds 1..=N, default 10, 60 s, aligned
//! mounting) are simulated with the default consumer-MEMS sensors and with
//! groups of error sources switched off, one at a time cumulatively:
//!
//! 1. `default`: every error source of `ImuSpec`/`EncoderSpec` defaults;
//! 2. `- static accel`: no accelerometer turn-on bias, in-run bias drift,
//!    scale-factor or cross-axis error and no mounting misalignment (what a
//!    per-sensor static calibration would remove);
//! 3. `- encoder offset`: additionally no encoder zeroing offset;
//! 4. `- gyro bias`: additionally no gyro turn-on bias or drift;
//! 5. `ideal sensors`: no sensor error at all (`noise = false`): what is left
//!    comes from the motion alone (dynamic accelerations admitted by the
//!    reliability test, out-of-plane motion).
//!
//! The motion (and so the dynamic accelerations) is identical across the
//! rows of one seed: only the sensor errors change.
//!
//! A second table runs the same seeds as 60 s of quiet standing
//! (`Motion::Stand`: every sensor static, no dynamic acceleration at all),
//! default sensors and without the static accelerometer errors: with no
//! motion, the error left is what the sensors' static errors alone cost, a
//! floor under the walking figures for filters whose absolute reference is
//! the accelerometer inclination.

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{Motion, WalkingConfig, WalkingSimulator};
use limbfuse_studies::baseline_study::mean_rmse_deg;
use limbfuse_studies::example_args::SegmentErrorBudgetArgs;
use rayon::prelude::*;

/// Mean 4-segment RMSE (deg), plain and offset-free.
fn mean_rmse(est: &mut dyn Estimator, records: &[Record]) -> [f64; 2] {
    mean_rmse_deg(est, records).expect("runs")
}

/// Means over seeds 1..=n of local, mjls, global and offset-free mjls RMSE
/// for the trial `base` with sensor variant `k`.
fn seed_means(n: u64, base: WalkingConfig, k: usize) -> [f64; 4] {
    let per_seed: Vec<[f64; 4]> = (1..=n)
        .into_par_iter()
        .map(|seed| {
            let mut cfg = WalkingConfig { seed, ..base };
            variant(k, &mut cfg);
            let records: Vec<Record> = WalkingSimulator::new(cfg).expect("valid config").collect();
            let l = mean_rmse(&mut LocalKf::default(), &records);
            let m = mean_rmse(&mut MarkovJumpKf::default(), &records);
            let g = mean_rmse(&mut GlobalKf::default(), &records);
            [l[0], m[0], g[0], m[1]]
        })
        .collect();
    core::array::from_fn(|i| per_seed.iter().map(|r| r[i]).sum::<f64>() / per_seed.len() as f64)
}

fn variant(k: usize, cfg: &mut WalkingConfig) {
    if k >= 1 {
        cfg.imu.acc.turn_on_bias = 0.0;
        cfg.imu.acc.bias_instability = 0.0;
        cfg.imu.acc.scale_error = 0.0;
        cfg.imu.acc.cross_axis = 0.0;
        cfg.imu.misalignment_rad = 0.0;
    }
    if k >= 2 {
        cfg.encoder.offset_rad = 0.0;
    }
    if k >= 3 {
        cfg.imu.gyro.turn_on_bias = 0.0;
        cfg.imu.gyro.bias_instability = 0.0;
    }
    if k >= 4 {
        cfg.noise = false;
    }
}

const VARIANTS: [&str; 5] = [
    "default",
    "- static accel",
    "- encoder offset",
    "- gyro bias",
    "ideal sensors",
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n = SegmentErrorBudgetArgs::parse().seeds;
    println!("| speed m/s | sensors | local | mjls | global | mjls offset-free |");
    println!("|---|---|---|---|---|---|");
    for speed in [0.4, 1.0, 1.6] {
        for (k, name) in VARIANTS.iter().enumerate() {
            let base = WalkingConfig {
                speed_mps: speed,
                ..WalkingConfig::default()
            };
            let [l, m, g, f] = seed_means(n, base, k);
            println!("| {speed} | {name} | {l:.2} | {m:.2} | {g:.2} | {f:.2} |");
        }
    }
    println!();
    println!("Quiet standing (no motion), 60 s, same seeds:");
    println!();
    println!("| sensors | local | mjls | global | mjls offset-free |");
    println!("|---|---|---|---|---|");
    for (k, name) in VARIANTS.iter().enumerate().take(2) {
        let base = WalkingConfig {
            motion: Motion::Stand,
            ..WalkingConfig::default()
        };
        let [l, m, g, f] = seed_means(n, base, k);
        println!("| {name} | {l:.2} | {m:.2} | {g:.2} | {f:.2} |");
    }
    Ok(())
}
