//! Segment filters on calibrated accelerometers, paper-001 protocol
//! (issue 14 item 3; docs/CALIBRATION.md, docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example calibration_study -- [SEEDS] [--speed S] [--tune] [--startup S]`
//!
//! Per seed and speed, for each sensor variant of
//! [`limbfuse_studies::calibration_study::Sensors`]: the walking trial (60 s)
//! resampled to 50 Hz, `mjls` and `global` on the validation block 30-50 s
//! from 50 starts, default parameters (or tuned on 10-30 s with `--tune`).
//! Prints the mean over seeds of the mean 4-segment RMSE and the worst seed.

use clap::Parser;
use limbfuse_methods::segment_params::FilterMethod;
use limbfuse_studies::calibration_study::{
    resample_to_50_hz, trial, validation_figure, whole_trial_rmse_deg, Sensors,
};
use limbfuse_studies::example_args::CalibrationStudyArgs;
use limbfuse_workflows::tuning::TuneConfig;
use rayon::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = CalibrationStudyArgs::parse();
    let tune = a.tune.then(|| TuneConfig {
        budget: a.budget,
        ..TuneConfig::default()
    });
    println!(
        "paper-001 protocol (50 Hz, validation 30-50 s, 50 starts), {} parameters, seeds 1-{}",
        if a.tune {
            "tuned on 10-30 s"
        } else {
            "default"
        },
        a.seeds
    );
    if a.startup > 0.0 {
        println!(
            "run-in startup_s = {} s: the first {} s of each run are not estimated",
            a.startup, a.startup
        );
    }
    println!();
    println!("Columns: paper-001 protocol (mjls, global: mean over seeds / worst seed), then the whole 100 Hz trial with default parameters (issue-3 protocol), then the share of segment samples the 001 figures scored (lowest seed; a run-in of W s scores 100 - 10 W %).");
    println!();
    println!("| speed m/s | sensors | 001 mjls | 001 mjls worst | 001 global | 001 global worst | whole mjls | whole global | scored % mjls | scored % global |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for &speed in &a.speeds {
        for sensors in Sensors::ALL {
            let per_seed: Vec<[f64; 6]> = (1..=a.seeds)
                .into_par_iter()
                .map(|seed| {
                    let err = |e: Box<dyn std::error::Error>| e.to_string();
                    let full = trial(seed, speed, sensors).map_err(err)?;
                    let [wm, wg] = whole_trial_rmse_deg(&full).map_err(err)?;
                    let r = resample_to_50_hz(&full).map_err(err)?;
                    let m = validation_figure(&r, FilterMethod::Mjls, tune, a.startup)
                        .map_err(|e| format!("seed {seed}, mjls: {e}"))?;
                    let g = validation_figure(&r, FilterMethod::Global, tune, a.startup)
                        .map_err(|e| format!("seed {seed}, global: {e}"))?;
                    Ok([m.rmse_deg, g.rmse_deg, wm, wg, m.coverage, g.coverage])
                })
                .collect::<Result<_, String>>()?;
            let n = per_seed.len() as f64;
            let mean = |i: usize| per_seed.iter().map(|r| r[i]).sum::<f64>() / n;
            let worst = |i: usize| per_seed.iter().map(|r| r[i]).fold(0.0, f64::max);
            let lowest = |i: usize| per_seed.iter().map(|r| 100.0 * r[i]).fold(100.0, f64::min);
            println!(
                "| {speed} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.1} | {:.1} |",
                sensors.label(),
                mean(0),
                worst(0),
                mean(1),
                worst(1),
                mean(2),
                mean(3),
                lowest(4),
                lowest(5)
            );
        }
    }
    Ok(())
}
