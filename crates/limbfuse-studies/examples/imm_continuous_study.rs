//! Issue 19 items 1-2: `imm-bslip --imm-config continuous` (continuous gait
//! family, speed measured and re-targeted, phase from the leg lengths).
//! (1) Paper 003 sec IV-A: the `--truth` gait (default 0.7 m/s) simulated
//! and held out of the 0.4-0.9 m/s library (default body), SEEDS noise
//! seeds at `--rate` Hz: phase accuracy, median speed, CoM RMS, with the
//! paper configuration beside it. (2) The shared independent B-SLIP trials
//! (`DATA/independent-sim/bslip-*.csv`): a 0.4-1.0 m/s library built for
//! the body in the trial's metadata, and one built for the default body
//! rescaled automatically (Froude similarity); phase accuracy and median
//! speed against `# speed_true`. (3) With `--long N`: 10 s trials (`--long-duration`; 100 Hz,
//! noise seeds 1..=N) of every gait of the 0.4-1.0 m/s library of each
//! body (default 80 kg / 1 m; 70 kg / 0.95 m), the gait in the library:
//! continuous configuration's phase accuracy and median speed (issue 19,
//! long trials).
//! `cargo run --release -p limbfuse-studies --example imm_continuous_study -- [SEEDS] [--truth V] [--rate HZ] [--data DIR] [--long N] [--long-duration S]`

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::imm_bslip::{ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights};
use limbfuse_methods::imm_body::fit_library;
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};
use limbfuse_studies::bslip_trials::{independent_trials, library};
use limbfuse_studies::example_args::{ImmContinuousStudyArgs, IMM_STUDY_SPEEDS};

/// Phase accuracy (%), median speed (m/s) and CoM position RMS (cm).
fn run(est: &mut dyn Estimator, trial: &[Record]) -> (f64, f64, f64) {
    let (mut ok, mut n, mut se) = (0usize, 0usize, 0.0);
    let mut speeds = Vec::new();
    for r in trial {
        let e = est.step(&r.sample).unwrap();
        if r.reference.phase.is_some() {
            n += 1;
            ok += usize::from(e.phase == r.reference.phase);
        }
        if let Some(s) = e.speed {
            speeds.push(s);
        }
        if let (Some(a), Some(b)) = (e.com_pos, r.reference.com_pos) {
            se += (a - b).norm_squared();
        }
    }
    speeds.sort_by(f64::total_cmp);
    let median = speeds.get(speeds.len() / 2).copied().unwrap_or(f64::NAN);
    (
        100.0 * ok as f64 / n.max(1) as f64,
        median,
        100.0 * (se / trial.len() as f64).sqrt(),
    )
}

fn estimators(lib: &[GaitTemplate]) -> [(&'static str, Box<dyn Estimator>); 2] {
    let continuous = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    };
    [
        (
            "continuous",
            Box::new(ImmContinuous::new(lib, continuous).unwrap()),
        ),
        (
            "paper",
            Box::new(ImmBslip::new(lib, ImmBslipParams::full_com()).unwrap()),
        ),
    ]
}

fn main() {
    let args = ImmContinuousStudyArgs::parse();
    let body = BslipParams::default();
    let templates = library(&body, &IMM_STUDY_SPEEDS);
    let truth = *templates
        .iter()
        .find(|t| (t.speed - args.truth).abs() < 1e-9)
        .unwrap();
    let held_out: Vec<_> = templates
        .iter()
        .filter(|t| (t.speed - args.truth).abs() > 1e-9)
        .copied()
        .collect();
    println!(
        "(1) sec IV-A: {} m/s held out of {:?}, {} Hz, {} seeds",
        args.truth, IMM_STUDY_SPEEDS, args.rate, args.seeds
    );
    for (label, _) in estimators(&held_out) {
        let mut acc = Vec::new();
        let mut speed_err = Vec::new();
        let mut rms = Vec::new();
        for seed in 1..=args.seeds {
            let cfg = BslipTrialConfig {
                duration: 4.0 * truth.step_time,
                sample_rate: args.rate,
                seed,
                ..Default::default()
            };
            let trial = simulate_trial(&truth, &cfg);
            let mut est = estimators(&held_out)
                .into_iter()
                .find(|(l, _)| *l == label)
                .unwrap()
                .1;
            let (a, s, r) = run(est.as_mut(), &trial);
            acc.push(a);
            speed_err.push((s - truth.speed).abs());
            rms.push(r);
        }
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        println!(
            "  {label:<10}: phase accuracy mean {:.1} % (min {:.1}), |median speed - truth| mean {:.3} m/s (max {:.3}), CoM RMS {:.2} cm",
            mean(&acc),
            min(&acc),
            mean(&speed_err),
            max(&speed_err),
            mean(&rms)
        );
    }
    let speeds = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];
    let default_lib = library(&body, &speeds);
    if args.long > 0 {
        long_trials(&default_lib, &speeds, args.long, args.long_duration);
    }
    let Some(trials) = independent_trials(std::path::Path::new(&args.data), body) else {
        println!("(2) skipped: {}/independent-sim not found", args.data);
        return;
    };
    println!("(2) independent B-SLIP trials, library {speeds:?} m/s");
    for t in trials {
        let (path, meta, trial, tb, own_body) =
            (&t.path, &t.meta, &t.records, &t.body_source, t.body);
        let truth: f64 = meta.get("speed_true").unwrap().trim().parse().unwrap();
        let own = library(&own_body, &speeds);
        let (rescaled, note) = fit_library(default_lib.clone(), tb).unwrap();
        println!(
            "  {}: true speed {truth} m/s; body from {}: {} kg, l0 {} m",
            path.display(),
            tb.source,
            own_body.mass,
            own_body.rest_length
        );
        println!("    {}", note.unwrap_or_default());
        for (lib_label, lib) in [
            ("built for the trial body", &own),
            ("default body, rescaled", &rescaled),
        ] {
            for (label, mut est) in estimators(lib) {
                let (a, s, _) = run(est.as_mut(), trial);
                println!(
                    "    {lib_label:<25} {label:<10}: phase accuracy {a:.1} %, median speed {s:.3} m/s (error {:+.3})",
                    s - truth
                );
            }
        }
    }
}

/// Part (3): `duration` s trials of every library gait, both bodies, `seeds` seeds.
fn long_trials(default_lib: &[GaitTemplate], speeds: &[f64], seeds: u64, duration: f64) {
    let other = BslipParams {
        mass: 70.0,
        rest_length: 0.95,
        ..BslipParams::default()
    };
    let other_lib = library(&other, speeds);
    println!(
        "(3) {duration} s trials of the library's own gaits, library {speeds:?} m/s, seeds 1..={seeds}"
    );
    for (name, lib) in [
        ("80 kg / 1 m", default_lib),
        ("70 kg / 0.95 m", &other_lib[..]),
    ] {
        for walker in lib {
            let mut acc = Vec::new();
            let mut speed = Vec::new();
            for seed in 1..=seeds {
                let cfg = BslipTrialConfig {
                    duration,
                    seed,
                    ..Default::default()
                };
                let trial = simulate_trial(walker, &cfg);
                let [(_, mut est), _] = estimators(lib);
                let (a, s, _) = run(est.as_mut(), &trial);
                acc.push(format!("{a:.1}"));
                speed.push(format!("{s:.3}"));
            }
            println!(
                "  {name:<15} {:.1} m/s: phase accuracy {} %, median speed {} m/s",
                walker.speed,
                acc.join(" / "),
                speed.join(" / ")
            );
        }
    }
}
