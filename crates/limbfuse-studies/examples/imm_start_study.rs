//! `imm-bslip` on the shared independent B-SLIP trials
//! (`DATA/independent-sim/bslip-*.csv`, a 0.4-1.0 m/s library built for the
//! body in their metadata) started, or ended, anywhere in the stride: the
//! trial's first rows removed up to a start every `--every` % of a stride
//! over two strides (the stride from the trial's `phase_ref`: its
//! mid-stances are the SS2 -> SS1 changes), and, separately, its last rows
//! removed in the same steps. Estimators as the CLI builds them (the sway
//! restart, `SwayRestart`, around `continuous` and `paper`) and the bare
//! continuous one. Per start: phase accuracy over the whole cut trial, over
//! its first stride and over the rest, and the median speed estimate.
//! `cargo run --release -p limbfuse-studies --example imm_start_study -- [--every PCT] [--data DIR]`

use clap::Parser;
use limbfuse_core::{Estimator, GaitPhase, Record};
use limbfuse_estimators::imm_bslip::{
    ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights, SwayRestart,
};
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_studies::bslip_trials::{independent_trials, library};
use limbfuse_studies::example_args::ImmStartStudyArgs;

const SPEEDS: [f64; 7] = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// The estimators compared: (label, estimator).
fn estimators(lib: &[GaitTemplate]) -> Vec<(&'static str, Box<dyn Estimator>)> {
    let continuous = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    };
    let c = || ImmContinuous::new(lib, continuous).unwrap();
    vec![
        ("continuous", Box::new(SwayRestart::new(c()))),
        ("continuous bare", Box::new(c())),
        (
            "paper",
            Box::new(SwayRestart::new(
                ImmBslip::new(lib, ImmBslipParams::full_com()).unwrap(),
            )),
        ),
    ]
}

/// Phase accuracy (%) over all rows, the first `stride` s and the rest;
/// the median speed estimate.
struct Score {
    all: f64,
    first: f64,
    rest: f64,
    speed: f64,
}

fn run(est: &mut dyn Estimator, records: &[Record], stride: f64) -> Score {
    let t0 = records.first().map_or(0.0, |r| r.sample.t);
    let mut n = [[0usize; 2]; 2];
    let mut speeds = Vec::new();
    for r in records {
        let e = est.step(&r.sample).unwrap();
        if let Some(v) = e.speed {
            speeds.push(v);
        }
        let Some(truth) = r.reference.phase else {
            continue;
        };
        let late = usize::from(r.sample.t - t0 >= stride);
        n[late][1] += 1;
        n[late][0] += usize::from(e.phase == Some(truth));
    }
    speeds.sort_by(f64::total_cmp);
    let pct = |ok: usize, all: usize| 100.0 * ok as f64 / all.max(1) as f64;
    Score {
        all: pct(n[0][0] + n[1][0], n[0][1] + n[1][1]),
        first: pct(n[0][0], n[0][1]),
        rest: pct(n[1][0], n[1][1]),
        speed: speeds.get(speeds.len() / 2).copied().unwrap_or(f64::NAN),
    }
}

/// Mid-stance times of the reference (SS2 -> SS1).
fn mid_stances(records: &[Record]) -> Vec<f64> {
    records
        .windows(2)
        .filter(|w| {
            w[0].reference.phase == Some(GaitPhase::Ss2)
                && w[1].reference.phase == Some(GaitPhase::Ss1)
        })
        .map(|w| w[1].sample.t)
        .collect()
}

fn phase_name(p: Option<GaitPhase>) -> &'static str {
    match p {
        Some(GaitPhase::Ss1) => "SS1",
        Some(GaitPhase::Ds) => "DS",
        Some(GaitPhase::Ss2) => "SS2",
        None => "-",
    }
}

fn summary(label: &str, what: &str, scores: &[f64], digits: usize) {
    let mut s = scores.to_vec();
    s.sort_by(f64::total_cmp);
    let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
    println!(
        "    {label:<16} {what:<14}: min {:.d$}, median {:.d$}, mean {:.d$}, max {:.d$}",
        s[0],
        s[s.len() / 2],
        mean,
        s[s.len() - 1],
        d = digits
    );
}

fn main() {
    let args = ImmStartStudyArgs::parse();
    let Some(trials) = independent_trials(std::path::Path::new(&args.data), BslipParams::default())
    else {
        println!("skipped: {}/independent-sim not found", args.data);
        return;
    };
    for t in trials {
        let lib = library(&t.body, &SPEEDS);
        let ms = mid_stances(&t.records);
        let step = (ms[ms.len() - 1] - ms[0]) / (ms.len() - 1) as f64;
        let stride = 2.0 * step;
        println!(
            "{}: step {step:.3} s (reference mid-stances), stride {stride:.3} s",
            t.path.display()
        );
        let names: Vec<_> = estimators(&lib).iter().map(|e| e.0).collect();
        let n_cuts = (200.0 / args.every).round() as usize;
        for ends in [false, true] {
            println!(
                "  {}: % of a stride | t (s) | phase_ref there | per estimator: all / first stride / rest %, median speed",
                if ends { "end cut" } else { "start cut" }
            );
            let mut all: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
            let mut speeds: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
            for k in 0..=n_cuts {
                let frac = k as f64 * args.every / 100.0;
                let end = t.records.last().unwrap().sample.t;
                let at = if ends {
                    end - frac * stride
                } else {
                    frac * stride
                };
                let records: Vec<_> = t
                    .records
                    .iter()
                    .filter(|r| {
                        if ends {
                            r.sample.t <= at + 1e-9
                        } else {
                            r.sample.t >= at - 1e-9
                        }
                    })
                    .cloned()
                    .collect();
                let there = if ends {
                    records.last()
                } else {
                    records.first()
                }
                .and_then(|r| r.reference.phase);
                let mut line = format!(
                    "    {:5.1} {:6.2} {:<3}",
                    100.0 * frac,
                    at,
                    phase_name(there)
                );
                for (i, (_, mut est)) in estimators(&lib).into_iter().enumerate() {
                    let s = run(est.as_mut(), &records, stride);
                    all[i].push(s.all);
                    speeds[i].push(s.speed);
                    line += &format!(
                        " | {:5.1} {:5.1} {:5.1} {:.3}",
                        s.all, s.first, s.rest, s.speed
                    );
                }
                println!("{line}");
            }
            for (i, name) in names.iter().enumerate() {
                summary(name, "phase %", &all[i], 1);
                summary(name, "median speed", &speeds[i], 3);
            }
        }
    }
}
