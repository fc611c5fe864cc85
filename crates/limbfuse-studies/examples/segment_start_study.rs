//! The paper segment filters (`local`, `mjls`, `global`, defaults as the CLI
//! builds them) started, or restarted, anywhere in the stride (for
//! docs/RESULTS.md, "The paper filters started mid-walk").
//!
//! Trials: the shared independent walks (`DATA/independent-sim/walk-*.csv`,
//! skipped when absent) and our simulator's walks (30 s, seed `--seed`, 0.4
//! to 1.6 m/s). Per trial and filter, starts every `--every` s over two
//! strides (stride period from the autocorrelation of the reference thigh
//! angle over 5-25 s): a *cut* (the trial's rows before the start removed,
//! as `recording_variant --drop-rows 0:C` does) and a *reset* (`reset()` at
//! 10 s plus the same offset, the filter running from the trial's start).
//!
//! Error of segment `i` = estimate - reference - the filter's own steady
//! offset (mean error over t >= 10 s of the uncut run: the paper filters
//! have constant offsets on the independent walks). Per start: the start
//! error (first estimate), the peak |error| over the first 3 s (max over the
//! segments), the time to steady (from the start until the error stays
//! within 2 deg of the uncut run's steady band, the 99th percentile of
//! |error| over t >= 10 s, up to 10 s after the start; max over the
//! segments), the delay to the first estimate, the peak |estimate -
//! reference| over the first 3 s without the offset removed, and the
//! offsets themselves. Tables: min / median / max
//! over the starts; the start error against the start sample's `rho` and
//! `|gyro rate|` (cuts, all segments).
//! `cargo run --release -p limbfuse-studies --example segment_start_study -- [--every S] [--seed N] [--data DIR]`

use std::path::Path;

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{
    CommonParams, GlobalKf, GlobalKfParams, LocalKf, LocalKfParams, MarkovJumpKf,
    MarkovJumpKfParams,
};
use limbfuse_io::TrialReader;
use limbfuse_methods::MethodName;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_studies::example_args::SegmentStartStudyArgs;
use rayon::prelude::*;

const METHODS: [MethodName; 3] = [MethodName::Mjls, MethodName::Global, MethodName::Local];
const SIM_SPEEDS: [f64; 5] = [0.4, 0.7, 1.0, 1.3, 1.6];
/// Peak window after a start (s).
const PEAK_S: f64 = 3.0;
/// How long after a start the time to steady is looked for (s).
const HORIZON_S: f64 = 10.0;
/// Steady from here on in the uncut run (s).
const STEADY_FROM_S: f64 = 10.0;
/// Margin over the steady band (deg).
const MARGIN_DEG: f64 = 2.0;

fn filter(method: MethodName, first_sample_start: bool) -> Box<dyn Estimator> {
    let common = CommonParams {
        first_sample_start,
        ..CommonParams::default()
    };
    match method {
        MethodName::Mjls => Box::new(
            MarkovJumpKf::new(MarkovJumpKfParams {
                common,
                ..MarkovJumpKfParams::default()
            })
            .expect("defaults"),
        ),
        MethodName::Global => Box::new(
            GlobalKf::new(GlobalKfParams {
                common,
                ..GlobalKfParams::default()
            })
            .expect("defaults"),
        ),
        _ => Box::new(
            LocalKf::new(LocalKfParams {
                common,
                ..LocalKfParams::default()
            })
            .expect("defaults"),
        ),
    }
}

/// Segment estimates per record; `reset_at` resets the filter before that record.
fn run(
    (method, old): (MethodName, bool),
    records: &[Record],
    reset_at: Option<usize>,
) -> Vec<[Option<f64>; 4]> {
    let mut f = filter(method, old);
    records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            if reset_at == Some(k) {
                f.reset();
            }
            f.step(&r.sample).expect("runs").segment
        })
        .collect()
}

fn err_deg(est: Option<f64>, truth: Option<f64>, offset: f64) -> Option<f64> {
    Some((est? - truth? - offset).to_degrees())
}

/// The filter's own steady offset (rad) and band (deg) per segment.
fn steady(records: &[Record], est: &[[Option<f64>; 4]]) -> ([f64; 4], [f64; 4]) {
    let mut off = [0.0; 4];
    let mut band = [0.0; 4];
    for i in 0..4 {
        let e: Vec<f64> = records
            .iter()
            .zip(est)
            .filter(|(r, _)| r.sample.t >= STEADY_FROM_S)
            .filter_map(|(r, e)| Some(e[i]? - r.reference.segment[i]?))
            .collect();
        off[i] = e.iter().sum::<f64>() / e.len().max(1) as f64;
        let mut a: Vec<f64> = e.iter().map(|x| (x - off[i]).abs().to_degrees()).collect();
        a.sort_by(f64::total_cmp);
        band[i] = a.get(a.len() * 99 / 100).copied().unwrap_or(0.0);
    }
    (off, band)
}

/// One start's figures.
#[derive(Clone, Copy)]
struct Start {
    /// Start error per segment (deg), rho and |rate| of the start sample.
    seg: [(f64, f64, f64); 4],
    peak: f64,
    /// Peak |estimate - reference| (deg) over the first 3 s, no offset removed.
    peak_truth: f64,
    to_steady: f64,
    first: f64,
}

fn score(
    records: &[Record],
    est: &[[Option<f64>; 4]],
    k0: usize,
    off: &[f64; 4],
    band: &[f64; 4],
    g: f64,
) -> Start {
    let t0 = records[k0].sample.t;
    let mut s = Start {
        seg: [(f64::NAN, 0.0, 0.0); 4],
        peak: 0.0,
        peak_truth: 0.0,
        to_steady: 0.0,
        first: f64::NAN,
    };
    for i in 0..4 {
        let imu = &records[k0].sample.imu[i];
        let rho = imu.acc.map_or(f64::NAN, |a| (a.norm() - g).abs());
        let rate = imu.gyr.map_or(f64::NAN, |w| w[2].abs());
        let mut start_err = f64::NAN;
        let mut last_bad = t0;
        for k in k0..records.len() {
            let t = records[k].sample.t;
            if t - t0 > HORIZON_S {
                break;
            }
            let Some(e) = err_deg(est[k][i], records[k].reference.segment[i], off[i]) else {
                last_bad = t;
                continue;
            };
            if start_err.is_nan() {
                start_err = e;
                s.first = if s.first.is_nan() {
                    t - t0
                } else {
                    s.first.max(t - t0)
                };
            }
            if t - t0 <= PEAK_S {
                s.peak = s.peak.max(e.abs());
                s.peak_truth = s.peak_truth.max((e + off[i].to_degrees()).abs());
            }
            if e.abs() > band[i] + MARGIN_DEG {
                last_bad = t;
            }
        }
        s.to_steady = s.to_steady.max(last_bad - t0);
        s.seg[i] = (start_err, rho, rate);
    }
    s
}

/// Stride period (s) from the autocorrelation of the reference thigh angle.
fn stride_period(records: &[Record]) -> f64 {
    let dt = records[1].sample.t - records[0].sample.t;
    let x: Vec<f64> = records
        .iter()
        .filter(|r| (5.0..25.0).contains(&r.sample.t))
        .filter_map(|r| r.reference.segment[1])
        .collect();
    let m = x.iter().sum::<f64>() / x.len() as f64;
    let (lo, hi) = ((0.6 / dt) as usize, (2.5 / dt) as usize);
    let best = (lo..hi.min(x.len() / 2))
        .max_by(|&a, &b| {
            let c = |l: usize| -> f64 { (l..x.len()).map(|j| (x[j] - m) * (x[j - l] - m)).sum() };
            c(a).total_cmp(&c(b))
        })
        .unwrap_or(lo);
    best as f64 * dt
}

fn stats(v: &mut [f64]) -> String {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return "-".into();
    }
    format!(
        "{:.1} / {:.1} / {:.1}",
        v[0],
        v[v.len() / 2],
        v[v.len() - 1]
    )
}

fn trials(data: &Path, seed: u64) -> Vec<(String, Vec<Record>, f64)> {
    let mut out = Vec::new();
    for v in ["0.7-s300", "1.2-s301", "1.6-s302"] {
        let path = data.join(format!("independent-sim/walk-v{v}.csv"));
        match TrialReader::open(&path) {
            Ok(reader) => {
                let g = reader.meta().gravity().unwrap_or(9.81);
                let records = reader.map(|r| r.expect("valid trial")).collect();
                out.push((format!("independent {v}"), records, g));
            }
            Err(e) => eprintln!("skipped {}: {e}", path.display()),
        }
    }
    for speed in SIM_SPEEDS {
        let cfg = WalkingConfig {
            speed_mps: speed,
            duration_s: 30.0,
            seed,
            ..WalkingConfig::default()
        };
        let records = WalkingSimulator::new(cfg).expect("valid config").collect();
        out.push((format!("ours {speed} s{seed}"), records, cfg.g));
    }
    out
}

fn main() {
    let args = SegmentStartStudyArgs::parse();
    let all = trials(Path::new(&args.data), args.seed);
    let bins_rho = [0.0, 0.4, 1.0, 3.0, f64::INFINITY];
    let bins_rate = [0.0, 0.5, 1.5, 3.0, f64::INFINITY];
    println!("| trial | stride s | method | kind | starts | peak |error| deg (min / median / max) | time to steady s | first estimate s | peak vs truth deg | steady offsets deg |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut table = vec![vec![Vec::new(); bins_rate.len() - 1]; bins_rho.len() - 1];
    for (name, records, g) in &all {
        let stride = stride_period(records);
        let dt = records[1].sample.t - records[0].sample.t;
        let n = (2.0 * stride / args.every).round() as usize;
        for (m, method) in METHODS.iter().enumerate() {
            let method = (*method, args.first_sample_start);
            let uncut = run(method, records, None);
            let (off, band) = steady(records, &uncut);
            for kind in ["cut", "reset"] {
                let starts: Vec<Start> = (0..n)
                    .into_par_iter()
                    .map(|j| {
                        let offset = j as f64 * args.every;
                        if kind == "cut" {
                            let k0 = (offset / dt).round() as usize;
                            let est = run(method, &records[k0..], None);
                            score(&records[k0..], &est, 0, &off, &band, *g)
                        } else {
                            let k0 = ((STEADY_FROM_S + offset) / dt).round() as usize;
                            let est = run(method, records, Some(k0));
                            score(records, &est, k0, &off, &band, *g)
                        }
                    })
                    .collect();
                if kind == "cut" {
                    for s in &starts {
                        for (e, rho, rate) in s.seg {
                            let b = |v: f64, bins: &[f64]| {
                                bins.windows(2).position(|w| v >= w[0] && v < w[1])
                            };
                            if let (Some(a), Some(b), false) =
                                (b(rho, &bins_rho), b(rate, &bins_rate), e.is_nan())
                            {
                                table[a][b].push((m, e.abs()));
                            }
                        }
                    }
                }
                let mut peak: Vec<f64> = starts.iter().map(|s| s.peak).collect();
                let mut steady: Vec<f64> = starts.iter().map(|s| s.to_steady).collect();
                let mut first: Vec<f64> = starts.iter().map(|s| s.first).collect();
                let mut truth: Vec<f64> = starts.iter().map(|s| s.peak_truth).collect();
                let offsets: Vec<String> = off
                    .iter()
                    .map(|o| format!("{:.1}", o.to_degrees()))
                    .collect();
                println!(
                    "| {name} | {stride:.2} | {} | {kind} | {n} | {} | {} | {} | {} | {} |",
                    method.0,
                    stats(&mut peak),
                    stats(&mut steady),
                    stats(&mut first),
                    stats(&mut truth),
                    offsets.join(" / ")
                );
            }
        }
    }
    println!();
    println!("Start error |deg| of each segment at a cut start (median / max, count) against the start sample's rho and |gyro rate|:");
    println!();
    println!("| rho m/s^2 | rate rad/s | mjls | global | local |");
    println!("|---|---|---|---|---|");
    for (a, row) in table.iter().enumerate() {
        for (b, cell) in row.iter().enumerate() {
            let cols: Vec<String> = (0..3)
                .map(|m| {
                    let mut v: Vec<f64> = cell.iter().filter(|c| c.0 == m).map(|c| c.1).collect();
                    v.sort_by(f64::total_cmp);
                    if v.is_empty() {
                        "-".into()
                    } else {
                        format!(
                            "{:.1} / {:.1} ({})",
                            v[v.len() / 2],
                            v[v.len() - 1],
                            v.len()
                        )
                    }
                })
                .collect();
            println!(
                "| {}-{} | {}-{} | {} |",
                bins_rho[a],
                bins_rho[a + 1],
                bins_rate[b],
                bins_rate[b + 1],
                cols.join(" | ")
            );
        }
    }
}
