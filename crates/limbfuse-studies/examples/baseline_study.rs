//! Baseline study for docs/RESULTS.md:
//! `cargo run --release -p limbfuse-studies --example baseline_study`
//!
//! 60 s simulated walking trials (default sensors, aligned mounting) at
//! 0.4, 1.0 and 1.6 m/s, seeds 1..=10; per segment the mean over seeds of
//! the dynamic acceleration, the baselines' RMSE and the gyro drift vs bias.

use clap::Parser;
use limbfuse_sim::WalkingConfig;
use limbfuse_studies::baseline_study::baseline_trial;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    limbfuse_studies::example_args::NoArgs::parse();
    let seeds = 1..=10u64;
    let names = ["trunk", "thigh", "shank", "foot"];
    println!("| speed m/s | segment | RMS dyn. acc m/s^2 | mean rho m/s^2 | accel-inclination RMSE deg | gyro-integration RMSE deg | gyro drift deg/s | mean gyro z bias deg/s |");
    println!("|---|---|---|---|---|---|---|---|");
    for speed in [0.4, 1.0, 1.6] {
        let mut acc = [[0.0f64; 6]; 4];
        let mut drift_err = 0.0f64;
        let n = seeds.clone().count() as f64;
        for seed in seeds.clone() {
            let cfg = WalkingConfig {
                speed_mps: speed,
                seed,
                ..WalkingConfig::default()
            };
            let tr = baseline_trial(cfg)?;
            for (i, f) in tr.segments.iter().enumerate() {
                let v = [
                    f.rms_dynamic_acc,
                    f.mean_rho,
                    f.accel_rmse.to_degrees(),
                    f.gyro_rmse.to_degrees(),
                    f.gyro_drift.to_degrees(),
                    f.gyro_bias.to_degrees(),
                ];
                for k in 0..6 {
                    acc[i][k] += if k >= 4 { v[k].abs() } else { v[k] } / n;
                }
                drift_err = drift_err.max((f.gyro_drift - f.gyro_bias).abs().to_degrees());
            }
        }
        for (i, a) in acc.iter().enumerate() {
            println!(
                "| {speed} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} | {:.3} |",
                names[i], a[0], a[1], a[2], a[3], a[4], a[5]
            );
        }
        println!("| {speed} | max over seeds and segments of abs(drift - bias) | | | | | {drift_err:.4} | |");
    }
    println!();
    println!("Ideal sensors (no noise, no bias), out-of-plane motion on: gyro-integration drift from coning alone (deg/s)");
    println!();
    println!("| speed m/s | trunk | thigh | shank | foot |");
    println!("|---|---|---|---|---|");
    for speed in [0.4, 1.0, 1.6] {
        let cfg = WalkingConfig {
            speed_mps: speed,
            seed: 1,
            noise: false,
            ..WalkingConfig::default()
        };
        let tr = baseline_trial(cfg)?;
        let d = tr.segments.map(|f| f.gyro_drift.to_degrees());
        println!(
            "| {speed} | {:.3} | {:.3} | {:.3} | {:.3} |",
            d[0], d[1], d[2], d[3]
        );
    }
    Ok(())
}
