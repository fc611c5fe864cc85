//! Error budget of the segment filters (issue 3, for docs/RESULTS.md):
//! `cargo run --release -p limbfuse-eval --example segment_error_budget [seeds]`
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

use std::convert::Infallible;

use limbfuse_core::runner::{run, Observer};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_eval::{AngleMetrics, EvalOptions};
use limbfuse_sim::{Motion, WalkingConfig, WalkingSimulator};
use rayon::prelude::*;

/// Mean 4-segment RMSE (deg), plain and offset-free.
fn mean_rmse(est: &mut dyn Estimator, records: &[Record]) -> [f64; 2] {
    let mut plain = AngleMetrics::new(est.name(), EvalOptions::default());
    let mut free = AngleMetrics::new(
        est.name(),
        EvalOptions {
            offset_free: true,
            ..EvalOptions::default()
        },
    );
    let observers: &mut [&mut dyn Observer] = &mut [&mut plain, &mut free];
    run(
        est,
        records.iter().map(|r| Ok::<_, Infallible>(*r)),
        observers,
    )
    .expect("runs");
    let deg = |m: &AngleMetrics| m.evaluation().mean_rmse().unwrap_or(f64::NAN).to_degrees();
    [deg(&plain), deg(&free)]
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
    let n: u64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(10);
    println!("| speed m/s | sensors | local | mjls | global | mjls offset-free |");
    println!("|---|---|---|---|---|---|");
    for speed in [0.4, 1.0, 1.6] {
        for (k, name) in VARIANTS.iter().enumerate() {
            let per_seed: Vec<[f64; 4]> = (1..=n)
                .into_par_iter()
                .map(|seed| {
                    let mut cfg = WalkingConfig {
                        speed_mps: speed,
                        seed,
                        ..WalkingConfig::default()
                    };
                    variant(k, &mut cfg);
                    let records: Vec<Record> =
                        WalkingSimulator::new(cfg).expect("valid config").collect();
                    let l = mean_rmse(&mut LocalKf::default(), &records);
                    let m = mean_rmse(&mut MarkovJumpKf::default(), &records);
                    let g = mean_rmse(&mut GlobalKf::default(), &records);
                    [l[0], m[0], g[0], m[1]]
                })
                .collect();
            let avg = |i: usize| per_seed.iter().map(|r| r[i]).sum::<f64>() / per_seed.len() as f64;
            println!(
                "| {speed} | {name} | {:.2} | {:.2} | {:.2} | {:.2} |",
                avg(0),
                avg(1),
                avg(2),
                avg(3)
            );
        }
    }
    println!();
    println!("Quiet standing (no motion), 60 s, same seeds:");
    println!();
    println!("| sensors | local | mjls | global | mjls offset-free |");
    println!("|---|---|---|---|---|");
    for (k, name) in VARIANTS.iter().enumerate().take(2) {
        let per_seed: Vec<[f64; 4]> = (1..=n)
            .into_par_iter()
            .map(|seed| {
                let mut cfg = WalkingConfig {
                    motion: Motion::Stand,
                    seed,
                    ..WalkingConfig::default()
                };
                variant(k, &mut cfg);
                let records: Vec<Record> =
                    WalkingSimulator::new(cfg).expect("valid config").collect();
                let l = mean_rmse(&mut LocalKf::default(), &records);
                let m = mean_rmse(&mut MarkovJumpKf::default(), &records);
                let g = mean_rmse(&mut GlobalKf::default(), &records);
                [l[0], m[0], g[0], m[1]]
            })
            .collect();
        let avg = |i: usize| per_seed.iter().map(|r| r[i]).sum::<f64>() / per_seed.len() as f64;
        println!(
            "| {name} | {:.2} | {:.2} | {:.2} | {:.2} |",
            avg(0),
            avg(1),
            avg(2),
            avg(3)
        );
    }
    Ok(())
}
