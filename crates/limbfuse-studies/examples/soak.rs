//! Soak run of the real-time estimators (issue 18 item 4, for
//! docs/RESULTS.md):
//! `cargo run --release -p limbfuse-studies --example soak -- [--hours H] [--methods LIST] [--glitches LIST] [--glitch-every S] [--chunk-s S]`
//!
//! Each estimator over H hours (default 24: 8.64 M samples) of simulated
//! 100 Hz data with one glitch every 30 s (cycling: a 1e300 gyro cell, a
//! -1e308 accelerometer cell, 50 saturated foot-gyro samples, a 1 s gap of
//! every IMU, a 1e9 encoder reading; `limbfuse_studies::soak`). Prints one
//! row per hour (error, missing estimates, non-finite outputs, CPU time per
//! step, resident memory) and a summary line per estimator. Estimators run
//! one after the other (the per-step times are single-thread CPU times).

use clap::Parser;
use limbfuse_studies::example_args::SoakArgs;
use limbfuse_studies::soak::{soak, SoakConfig};

fn main() {
    let args = SoakArgs::parse();
    let glitches: &'static [_] = Vec::leak(args.glitches.clone());
    for method in &args.methods {
        let cfg = SoakConfig {
            method: *method,
            duration_s: args.hours * 3600.0,
            seed: 1,
            chunk_s: args.chunk_s.min(args.hours * 3600.0),
            glitch_every_s: args.glitch_every,
            glitches,
        };
        let report = match soak(&cfg) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{method}: {e}");
                std::process::exit(1);
            }
        };
        println!(
            "## {method}: {} samples, {} glitches",
            report.samples, report.glitches
        );
        println!("| chunk ends (s) | RMSE deg | missing | non-finite | CPU ns/step | RSS kB |");
        println!("|---|---|---|---|---|---|");
        for c in &report.chunks {
            println!(
                "| {:.0} | {:.3} | {} | {} | {:.0} | {} |",
                c.t_end,
                c.rmse_deg,
                c.missing,
                c.non_finite,
                c.step_ns,
                c.rss_kb.map_or("-".into(), |v| v.to_string())
            );
        }
        let phase = |p: usize| {
            report.phase_rmse_deg[p]
                .iter()
                .map(|v| v.map_or("-".into(), |v| format!("{v:.2}")))
                .collect::<Vec<_>>()
                .join(" / ")
        };
        println!(
            "RMSE deg per channel (segments trunk / thigh / shank / foot, or the knee): during glitches {}; first {} s after {}; elsewhere {}",
            phase(0),
            limbfuse_studies::soak::AFTER_S,
            phase(1),
            phase(2)
        );
        let first = report.chunks.first().expect("at least one chunk");
        let last = report.chunks.last().expect("at least one chunk");
        let q = |x: f64| report.step_times.quantile_ns(x).unwrap_or(f64::NAN);
        println!(
            "summary {method}: RMSE median {:.3} / max {:.3} deg; CPU per step first {:.0} / last {:.0} ns (p50 {:.0}, p99 {:.0}, p99.9 {:.0} ns); RSS first {} / last {} kB\n",
            report.median_rmse_deg(),
            report.max_rmse_deg(),
            first.step_ns,
            last.step_ns,
            q(0.5),
            q(0.99),
            q(0.999),
            first.rss_kb.map_or("-".into(), |v| v.to_string()),
            last.rss_kb.map_or("-".into(), |v| v.to_string()),
        );
    }
}
