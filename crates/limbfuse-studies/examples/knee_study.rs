//! Self-aligning knee study of issue 4 (paper 002), for docs/RESULTS.md:
//!
//! ```text
//! cargo run --release -p limbfuse-studies --example knee_study -- seeds [N] [AP_SD_CM] [paper|rate-bias]
//! cargo run --release -p limbfuse-studies --example knee_study -- table1 [N]
//! cargo run --release -p limbfuse-studies --example knee_study -- remount [N]
//! cargo run --release -p limbfuse-studies --example knee_study -- real [DATA_DIR]
//! cargo run --release -p limbfuse-studies --example knee_study -- floor [N]
//! ```
//!
//! * `seeds`: 60 s simulated walking (1 m/s, default sensors, random IMU
//!   orientations and positions), seeds 1..=N (default 30), s_w = 500,
//!   order = 6: knee RMSE, offset-free RMSE, mean error, correlation.
//! * `table1`: the order x s_w grid of 002 Table 1 (mean over seeds 1..=N,
//!   default 10) with the processing time of a 60 s trial.
//! * `remount`: thigh sensor turned 50 deg about the thigh's long axis at
//!   t = 30 s; recovery time of the 2 s sliding RMSE below 2 deg for
//!   s_w = 200 and 400 (order 6), seeds 1..=N (default 10).
//! * `real`: the shared gaittoolbox trial (right knee vs Vicon, straight
//!   parts) and the five knee-rig trials (vs the stepper angle).
//! * `floor`: the error left with the TRUE geometry fixed (no
//!   identification), seeds 1..=N (default 30), while sensor error sources
//!   are switched off cumulatively (static accelerometer errors, then gyro
//!   bias, then everything): what the fusion of Algorithm 1 alone costs.

use clap::Parser;
use limbfuse_estimators::knee_selfalign::{Fusion, KneeSelfAlignParams};
use limbfuse_sim::Remount;
use limbfuse_studies::example_args::{KneeStudyArgs, KneeStudyMode};
use limbfuse_studies::knee_study::{
    mean_error, recovery_time, run, simulate, simulate_with_truth, simulate_with_truth_and,
    sliding_rmse,
};
use rayon::prelude::*;

fn params(window: usize, order: usize) -> KneeSelfAlignParams {
    KneeSelfAlignParams {
        window,
        order,
        ..KneeSelfAlignParams::default()
    }
}

fn stats(x: &[f64]) -> (f64, f64, f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let sd = (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (m, sd, lo, hi)
}

fn seeds(n: u64, ap_sd_cm: f64, fusion: &str) {
    let fusion = match fusion {
        "rate-bias" => Fusion::RATE_BIAS,
        _ => Fusion::Paper,
    };
    let params = |w, o| KneeSelfAlignParams {
        fusion,
        ..params(w, o)
    };
    let runs: Vec<_> = (1..=n)
        .into_par_iter()
        .map(|seed| {
            let (recs, truth) =
                simulate_with_truth(seed, 60.0, ap_sd_cm / 100.0).expect("valid scenario");
            let fixed =
                limbfuse_studies::knee_study::run_fixed(&recs, truth, &[(500, recs.len())], fusion)
                    .expect("runs");
            (seed, run(&recs, params(500, 6)).expect("runs"), fixed)
        })
        .collect();
    println!("seeds 1..={n}, A/P offset sd {ap_sd_cm} cm, s_w = 500, order = 6, fusion {fusion:?} (angles from sample 500 on)");
    println!("| seed | RMSE deg | offset-free RMSE deg | mean error deg | corr | true geometry: RMSE / mean deg |");
    println!("|---|---|---|---|---|---|");
    for (seed, r, f) in &runs {
        println!(
            "| {seed} | {:.3} | {:.3} | {:+.3} | {:.5} | {:.3} / {:+.3} |",
            r.rmse.to_degrees(),
            r.rmse_offset_free.to_degrees(),
            r.mean.to_degrees(),
            r.corr,
            f.rmse.to_degrees(),
            f.mean.to_degrees()
        );
    }
    let col = |f: &dyn Fn(&limbfuse_studies::knee_study::KneeRun) -> f64| {
        stats(&runs.iter().map(|(_, r, _)| f(r)).collect::<Vec<_>>())
    };
    let colf = |f: &dyn Fn(&limbfuse_studies::knee_study::KneeRun) -> f64| {
        stats(&runs.iter().map(|(_, _, r)| f(r)).collect::<Vec<_>>())
    };
    for (name, s) in [
        ("RMSE deg", col(&|r| r.rmse.to_degrees())),
        (
            "offset-free RMSE deg",
            col(&|r| r.rmse_offset_free.to_degrees()),
        ),
        ("|mean error| deg", col(&|r| r.mean.abs().to_degrees())),
        ("corr", col(&|r| r.corr)),
        (
            "true geometry (fixed): RMSE deg",
            colf(&|r| r.rmse.to_degrees()),
        ),
        (
            "true geometry (fixed): offset-free RMSE deg",
            colf(&|r| r.rmse_offset_free.to_degrees()),
        ),
        (
            "true geometry (fixed): |mean error| deg",
            colf(&|r| r.mean.abs().to_degrees()),
        ),
    ] {
        println!(
            "{name}: mean {:.4}, sd {:.4}, min {:.4}, max {:.4}",
            s.0, s.1, s.2, s.3
        );
    }
}

fn floor(n: u64) {
    type Adjust = fn(&mut limbfuse_sim::WalkingConfig);
    let variants: [(&str, Adjust); 4] = [
        ("default sensors", |_| {}),
        (
            "- static accel (bias, drift, scale, cross-axis, misalignment)",
            |c| {
                c.imu.acc.turn_on_bias = 0.0;
                c.imu.acc.bias_instability = 0.0;
                c.imu.acc.scale_error = 0.0;
                c.imu.acc.cross_axis = 0.0;
                c.imu.misalignment_rad = 0.0;
            },
        ),
        ("- static accel - gyro bias", |c| {
            c.imu.acc.turn_on_bias = 0.0;
            c.imu.acc.bias_instability = 0.0;
            c.imu.acc.scale_error = 0.0;
            c.imu.acc.cross_axis = 0.0;
            c.imu.misalignment_rad = 0.0;
            c.imu.gyro.turn_on_bias = 0.0;
            c.imu.gyro.bias_instability = 0.0;
        }),
        ("ideal sensors", |c| c.noise = false),
    ];
    println!("true geometry fixed, seeds 1..={n}, 60 s walking at 1 m/s, random mountings, angles from sample 500 on");
    println!("| sensors | fusion | RMSE deg | offset-free RMSE deg | mean abs(mean error) deg | max RMSE deg |");
    println!("|---|---|---|---|---|---|");
    for (name, adjust) in variants {
        for fusion in [Fusion::Paper, Fusion::RATE_BIAS] {
            let runs: Vec<_> = (1..=n)
                .into_par_iter()
                .map(|seed| {
                    let (recs, truth) =
                        simulate_with_truth_and(seed, 60.0, 0.0, adjust).expect("valid scenario");
                    limbfuse_studies::knee_study::run_fixed(
                        &recs,
                        truth,
                        &[(500, recs.len())],
                        fusion,
                    )
                    .expect("runs")
                })
                .collect();
            let m = |f: &dyn Fn(&limbfuse_studies::knee_study::KneeRun) -> f64| {
                runs.iter().map(f).sum::<f64>() / runs.len() as f64
            };
            let max = runs.iter().map(|r| r.rmse.to_degrees()).fold(0.0, f64::max);
            println!(
                "| {name} | {fusion:?} | {:.3} | {:.3} | {:.3} | {:.3} |",
                m(&|r| r.rmse.to_degrees()),
                m(&|r| r.rmse_offset_free.to_degrees()),
                m(&|r| r.mean.abs().to_degrees()),
                max
            );
        }
    }
}

fn table1(n: u64) {
    let grid: Vec<(usize, usize)> = [2usize, 4, 6, 8]
        .iter()
        .flat_map(|&o| [50usize, 100, 200, 400, 500, 600].map(|w| (o, w)))
        .collect();
    let trials: Vec<_> = (1..=n)
        .map(|seed| simulate(seed, 60.0, 0.0, None).expect("valid scenario"))
        .collect();
    println!("mean over seeds 1..={n} (60 s, 100 Hz); time = estimator wall time per 60 s trial, one core");
    println!("| order | s_w | corr | RMSE deg | offset-free RMSE deg | time ms |");
    println!("|---|---|---|---|---|---|");
    for (order, window) in grid {
        // Sequential so the timings are not disturbed by other runs.
        let runs: Vec<_> = trials
            .iter()
            .map(|t| run(t, params(window, order)).expect("runs"))
            .collect();
        let m = |f: &dyn Fn(&limbfuse_studies::knee_study::KneeRun) -> f64| {
            runs.iter().map(f).sum::<f64>() / runs.len() as f64
        };
        println!(
            "| {order} | {window} | {:.4} | {:.3} | {:.3} | {:.2} |",
            m(&|r| r.corr),
            m(&|r| r.rmse.to_degrees()),
            m(&|r| r.rmse_offset_free.to_degrees()),
            m(&|r| r.seconds * 1e3)
        );
    }
}

fn remount(n: u64) {
    let event = 30.0;
    let threshold = 2f64.to_radians();
    println!("thigh sensor turned 50 deg about the thigh long axis at t = {event} s; 60 s trials; order 6");
    println!("recovery = time after the event from which the 2 s sliding RMSE stays <= 2 deg;");
    println!("'raw' uses the error itself, 'own zero' the error minus its mean over 10-30 s (the estimator's pre-event offset)");
    println!("| s_w | seed | peak sliding RMSE deg (own zero) | recovery raw s | recovery own zero s | offset before deg | offset after (50-60 s) deg |");
    println!("|---|---|---|---|---|---|---|");
    for window in [200usize, 400] {
        let rows: Vec<_> = (1..=n)
            .into_par_iter()
            .map(|seed| {
                let recs = simulate(
                    seed,
                    60.0,
                    0.0,
                    Some(Remount {
                        t_s: event,
                        angle_rad: 50f64.to_radians(),
                    }),
                )
                .expect("valid scenario");
                let r = run(&recs, params(window, 6)).expect("runs");
                let before = mean_error(&r.errors, 10.0, event);
                let after = mean_error(&r.errors, 50.0, 60.0);
                let raw = sliding_rmse(&r.errors, 2.0, 0.0);
                let own = sliding_rmse(&r.errors, 2.0, before);
                let peak = own
                    .iter()
                    .filter(|(t, _)| *t >= event)
                    .map(|x| x.1)
                    .fold(0.0, f64::max);
                (
                    seed,
                    peak,
                    recovery_time(&raw, event, 2.0, threshold),
                    recovery_time(&own, event, 2.0, threshold),
                    before,
                    after,
                )
            })
            .collect();
        let fmt = |x: Option<f64>| x.map_or("never".into(), |v| format!("{v:.2}"));
        let mut rec = Vec::new();
        for (seed, peak, raw, own, before, after) in &rows {
            println!(
                "| {window} | {seed} | {:.2} | {} | {} | {:+.2} | {:+.2} |",
                peak.to_degrees(),
                fmt(*raw),
                fmt(*own),
                before.to_degrees(),
                after.to_degrees()
            );
            if let Some(v) = own {
                rec.push(*v);
            }
        }
        let s = stats(&rec);
        println!(
            "s_w = {window}: own-zero recovery in {}/{} seeds, mean {:.2} s, min {:.2}, max {:.2}",
            rec.len(),
            rows.len(),
            s.0,
            s.2,
            s.3
        );
    }
}

fn show(label: &str, r: &limbfuse_studies::knee_study::KneeRun) {
    println!(
        "| {label} | {} | {:.2} | {:.2} | {:+.2} | {:.4} |",
        r.errors.len(),
        r.rmse.to_degrees(),
        r.rmse_offset_free.to_degrees(),
        r.mean.to_degrees(),
        r.corr
    );
}

/// The gyro part alone: correlation and slope of `g_T.j_T - g_S.j_S` (eq 4's
/// integrand) at the identified axes against the reference knee rate
/// (central differences), on the given sample ranges.
fn gyro_check(
    recs: &[limbfuse_core::Record],
    g: &limbfuse_estimators::knee_selfalign::Geometry,
    ranges: &[(usize, usize)],
    shift: i32,
) {
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for &(a, b) in ranges {
        for k in a.max(1)..b.min(recs.len() - 1) {
            let (Some(gt), Some(gs)) = (recs[k].sample.imu[1].gyr, recs[k].sample.imu[2].gyr)
            else {
                continue;
            };
            let (Some(r0), Some(r1)) = (
                recs[k - 1].reference.joint[1],
                recs[k + 1].reference.joint[1],
            ) else {
                continue;
            };
            let dt = recs[k + 1].sample.t - recs[k - 1].sample.t;
            x.push((r1 - r0) / dt);
            y.push(gt.dot(&g.axis[0]) - gs.dot(&g.axis[1]));
        }
    }
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    println!(
        "gyro check (IMU shift {shift}): eq 4 rate at the axes identified on straight part 1 vs reference knee rate: corr {:.3}, slope {:.3} ({} samples)",
        limbfuse_studies::knee_study::pearson(&x, &y),
        sxy / sxx,
        x.len()
    );
}

fn real(data: &str) {
    use limbfuse_io::import::{import_gaittoolbox_with, import_knee_rig, GaittoolboxOptions};
    let dir = std::path::Path::new(data);
    let straight = [(45usize, 355usize), (440, 872)];
    println!("gaittoolbox right knee, evaluated on the straight parts (samples 45..355, 440..872)");
    println!("| variant | n | RMSE deg | offset-free RMSE deg | mean error deg | corr |");
    println!("|---|---|---|---|---|---|");
    for shift in [0, 2] {
        let trial = match import_gaittoolbox_with(
            &dir.join("gaittoolbox-s02-walk"),
            &GaittoolboxOptions {
                shift_imu_samples: shift,
                ..GaittoolboxOptions::default()
            },
        ) {
            Ok(t) => t,
            Err(e) => {
                println!("skipped: {e}");
                return;
            }
        };
        let recs = &trial.records;
        for window in [300usize, 500] {
            let r = limbfuse_studies::knee_study::run_on(recs, params(window, 6), &straight)
                .expect("runs");
            show(
                &format!("online s_w={window}, order 6, IMU shift {shift}"),
                &r,
            );
        }
        let g = limbfuse_studies::knee_study::identify_offline(&recs[45..355], 6);
        if let Some(g) = g {
            gyro_check(recs, &g, &straight, shift);
        }
        match g {
            Some(g) => {
                let r = limbfuse_studies::knee_study::run_fixed(recs, g, &straight, Fusion::Paper)
                    .expect("runs");
                show(
                    &format!("geometry from straight part 1, IMU shift {shift}"),
                    &r,
                );
                let r =
                    limbfuse_studies::knee_study::run_fixed(recs, g, &straight[1..], Fusion::Paper)
                        .expect("runs");
                show(
                    &format!("  same, straight part 2 only (held out), IMU shift {shift}"),
                    &r,
                );
            }
            None => println!("| offline identification failed (shift {shift}) | | | | | |"),
        }
    }
    println!();
    println!(
        "knee rig (250 Hz), whole trial after the first window; corr with the stepper reference"
    );
    println!("| variant | n | RMSE deg | offset-free RMSE deg | mean error deg | corr |");
    println!("|---|---|---|---|---|---|");
    for i in 1..=5 {
        let path = dir.join(format!("knee-rig/Trial_0{i}.csv"));
        let trial = match import_knee_rig(&path) {
            Ok(t) => t,
            Err(e) => {
                println!("skipped: {e}");
                return;
            }
        };
        for window in [500usize, 1250] {
            let r = run(&trial.records, params(window, 6)).expect("runs");
            show(&format!("Trial_0{i} online s_w={window}"), &r);
        }
    }
}

fn main() {
    match KneeStudyArgs::parse().mode {
        KneeStudyMode::Seeds {
            n,
            ap_sd_cm,
            fusion,
        } => seeds(n, ap_sd_cm, &fusion),
        KneeStudyMode::Table1 { n } => table1(n),
        KneeStudyMode::Remount { n } => remount(n),
        KneeStudyMode::Real { data_dir } => real(&data_dir),
        KneeStudyMode::Floor { n } => floor(n),
    }
}
