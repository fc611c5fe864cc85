//! `chain` on limbfuse's own walking simulator (issue 14, for docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example chain_study -- [SEEDS] [--calibrated]`
//!
//! 60 s trials with the default (uncalibrated) sensors at 0.4, 0.7, 1.0,
//! 1.3 and 1.6 m/s, seeds 1..=N (default 10); the geometry comes from the
//! trial metadata (`imu_mounts_m`, `segment_lengths_m`), as `limbfuse
//! estimate --method chain` reads it. Per speed: mean 4-segment RMSE,
//! absolute and offset-free (each segment's mean error removed), mean over
//! seeds and the worst seed. The filter gives no estimate during its 2 s
//! start-up window; those samples are not scored.
//!
//! `--calibrated`: the mounting misalignment is set to zero and each
//! trial's accelerometers are calibrated from the simulated pose recording
//! of the same sensors, as `limbfuse simulate walking --no-misalignment`,
//! `limbfuse simulate calibration`, `limbfuse calibrate` and
//! `--calibration` do (issue 14: <= 0.6 deg absolute).

use std::convert::Infallible;

use clap::Parser;
use limbfuse_core::runner::{run, Observer};
use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Record, Segment};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainParams};
use limbfuse_eval::{AngleMetrics, EvalOptions};
use limbfuse_io::TrialMeta;
use limbfuse_methods::chain_method::{resolve_geometry, GeometryFile};
use limbfuse_sim::WalkingSimulator;
use limbfuse_studies::calibration_study::{trial, walking_config, Sensors};
use limbfuse_studies::example_args::ChainStudyArgs;
use rayon::prelude::*;

/// Mean 4-segment RMSE (deg): absolute and offset-free.
fn one_trial(speed: f64, seed: u64, calibrated: bool) -> [f64; 2] {
    let sensors = if calibrated {
        Sensors::CalibratedNoMisalignment
    } else {
        Sensors::Raw
    };
    let cfg = walking_config(seed, speed, sensors);
    let sim = WalkingSimulator::new(cfg).expect("valid config");
    let mut meta = TrialMeta::new();
    for (k, v) in sim.metadata() {
        meta.set(k, v);
    }
    let records: Vec<Record> = trial(seed, speed, sensors).expect("simulated, calibrated");
    let geometry = resolve_geometry(&meta, &GeometryFile::default()).expect("simulator metadata");
    let mut ekf = ChainEkf::new(ChainParams::default(), geometry, meta.gravity().expect("g"))
        .expect("defaults");
    let mut abs = AngleMetrics::new("chain", EvalOptions::default());
    let mut off = AngleMetrics::new(
        "chain",
        EvalOptions {
            offset_free: true,
            ..EvalOptions::default()
        },
    );
    let observers: &mut [&mut dyn Observer] = &mut [&mut abs, &mut off];
    run(
        &mut ekf,
        records.iter().map(|r| Ok::<_, Infallible>(*r)),
        observers,
    )
    .expect("runs");
    let mean4 = |m: &AngleMetrics| {
        let ev = m.evaluation();
        Segment::ALL
            .iter()
            .map(|s| {
                ev.rmse(AngleChannel::Segment(*s))
                    .expect("scored")
                    .to_degrees()
            })
            .sum::<f64>()
            / 4.0
    };
    [mean4(&abs), mean4(&off)]
}

fn main() {
    let args = ChainStudyArgs::parse();
    let n = args.seeds;
    println!(
        "| speed m/s | seeds | absolute mean / worst | offset-free mean / worst (worst seed) |"
    );
    println!("|---|---|---|---|");
    for speed in [0.4, 0.7, 1.0, 1.3, 1.6] {
        let runs: Vec<(u64, [f64; 2])> = (1..=n)
            .into_par_iter()
            .map(|seed| (seed, one_trial(speed, seed, args.calibrated)))
            .collect();
        let mean = |k: usize| runs.iter().map(|(_, r)| r[k]).sum::<f64>() / runs.len() as f64;
        let worst = |k: usize| {
            runs.iter()
                .max_by(|a, b| a.1[k].total_cmp(&b.1[k]))
                .map(|(s, r)| (*s, r[k]))
                .expect("at least one seed")
        };
        let (wa, wo) = (worst(0), worst(1));
        println!(
            "| {speed} | {n} | {:.2} / {:.2} | **{:.3}** / {:.3} (seed {}) |",
            mean(0),
            wa.1,
            mean(1),
            wo.1,
            wo.0
        );
    }
}
