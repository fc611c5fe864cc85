//! Issue 19, off-grid speeds and other gait branches: `imm-bslip
//! --imm-config continuous` on 10 s B-SLIP trials (70 kg / 0.95 m body,
//! 100 Hz, eq 15 noise, noise seeds 1..=SEEDS) at speeds that are NOT
//! library speeds, walking gaits that are NOT in the library: (search) the
//! gait search at that speed alone (what `limbfuse simulate bslip --speed V
//! --mass 70 --leg-length 0.95` walks), and the homotopy continued to that
//! speed from the library's gait just below (below) and just above (above)
//! it, which can land on another branch. Each distinct gait (stiffness,
//! double-support fraction, vertical excursion printed) is estimated with
//! (lib095) the 0.4-1.0 m/s library built for the body and (lib100) the
//! default body's (80 kg / 1 m) rescaled automatically (Froude similarity):
//! phase accuracy and median speed per seed.
//! `cargo run --release -p limbfuse-studies --example imm_offgrid_study -- [SEEDS] [--speeds V,V,...] [--duration S]`

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::imm_bslip::{ImmBslipParams, ImmContinuous, ImmWeights};
use limbfuse_methods::imm_body::{fit_library, TrialBody};
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::{build_library, continue_to, LibraryGait};
use limbfuse_sim::bslip::periodic::Corrected;
use limbfuse_sim::bslip::search::{FoundGait, SearchSettings};
use limbfuse_sim::bslip::step::StepSimulator;
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};
use limbfuse_studies::example_args::ImmOffgridStudyArgs;

/// Library speeds (m/s) of both libraries.
const LIBRARY_SPEEDS: [f64; 7] = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// Phase accuracy (%) and median speed (m/s).
fn run(est: &mut dyn Estimator, trial: &[Record]) -> (f64, f64) {
    let (mut ok, mut n) = (0usize, 0usize);
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
    }
    speeds.sort_by(f64::total_cmp);
    let median = speeds.get(speeds.len() / 2).copied().unwrap_or(f64::NAN);
    (100.0 * ok as f64 / n.max(1) as f64, median)
}

fn found(g: &LibraryGait) -> FoundGait {
    FoundGait {
        speed: g.speed,
        solution: Corrected {
            gait: g.gait,
            outcome: g.step,
            residual: g.residual,
            iterations: 0,
        },
        objective: g.objective,
    }
}

fn continuous(lib: &[GaitTemplate]) -> ImmContinuous {
    let params = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    };
    ImmContinuous::new(lib, params).unwrap()
}

fn main() {
    let args = ImmOffgridStudyArgs::parse();
    let settings = SearchSettings::default();
    let body = BslipParams {
        mass: 70.0,
        rest_length: 0.95,
        ..BslipParams::default()
    };
    let default_body = BslipParams::default();
    let own = build_library(&body, &LIBRARY_SPEEDS, &settings, |_, _| {}).unwrap();
    let lib095: Vec<GaitTemplate> = own.iter().map(|g| g.template(&body)).collect();
    let lib100: Vec<GaitTemplate> =
        build_library(&default_body, &LIBRARY_SPEEDS, &settings, |_, _| {})
            .unwrap()
            .iter()
            .map(|g| g.template(&default_body))
            .collect();
    let trial_body = TrialBody {
        mass: Some(body.mass),
        leg_length: Some(body.rest_length),
        gravity: body.gravity,
        source: "study",
    };
    let (lib100, _) = fit_library(lib100, &trial_body).unwrap();
    let sim = StepSimulator::new(body);
    println!(
        "70 kg / 0.95 m body, {} s trials, seeds 1..={}, libraries {LIBRARY_SPEEDS:?} m/s",
        args.duration, args.seeds
    );
    for &v in &args.speeds {
        let mut walkers: Vec<(&str, LibraryGait)> = Vec::new();
        match build_library(&body, &[v], &settings, |_, _| {}) {
            Ok(g) => walkers.push(("search", g[0])),
            Err(e) => println!("  {v:.2} m/s search: {e}"),
        }
        let below = own.iter().rev().find(|g| g.speed < v - 1e-9);
        let above = own.iter().find(|g| g.speed > v + 1e-9);
        for (label, from) in [("below", below), ("above", above)] {
            let Some(from) = from else { continue };
            match continue_to(&sim, &found(from), v, &settings) {
                Ok(g) => walkers.push((label, g.into())),
                Err(e) => println!("  {v:.2} m/s from {:.2}: {e}", from.speed),
            }
        }
        let mut seen: Vec<f64> = Vec::new();
        for (label, walker) in walkers {
            let k = walker.gait.stiffness;
            if seen.iter().any(|s| (s - k).abs() < 0.01 * k) {
                continue;
            }
            seen.push(k);
            let step = walker.step;
            let ds = 100.0 * (step.t_lift_off - step.t_touchdown) / step.t_end;
            let template = walker.template(&body);
            // The walker's own mean speed (reference CoM advance over the
            // trial): a check on the simulated trial itself.
            let check = simulate_trial(
                &template,
                &BslipTrialConfig {
                    duration: args.duration,
                    ..Default::default()
                },
            );
            let walked = match (check.first(), check.last()) {
                (Some(a), Some(b)) => match (a.reference.com_pos, b.reference.com_pos) {
                    (Some(p), Some(q)) => (q[0] - p[0]) / (b.sample.t - a.sample.t),
                    _ => f64::NAN,
                },
                _ => f64::NAN,
            };
            for (lib_label, lib) in [("lib095", &lib095), ("lib100", &lib100)] {
                let mut acc = Vec::new();
                let mut speed = Vec::new();
                for seed in 1..=args.seeds {
                    let cfg = BslipTrialConfig {
                        duration: args.duration,
                        seed,
                        ..Default::default()
                    };
                    let trial = simulate_trial(&template, &cfg);
                    let (a, s) = run(&mut continuous(lib), &trial);
                    acc.push(format!("{a:.1}"));
                    speed.push(format!("{:+.3}", s - v));
                }
                println!(
                    "  {v:.2} m/s {label:<6} k {k:>6.0} N/m DS {ds:>2.0} % exc {:.1} cm walked {walked:.3} m/s  {lib_label}: phase {} %, median speed error {} m/s",
                    100.0 * walker.vertical_excursion(),
                    acc.join(" / "),
                    speed.join(" / ")
                );
            }
        }
    }
}
