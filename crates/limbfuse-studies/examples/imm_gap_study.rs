//! `imm-bslip` after a gap in the CoM measurements: the bank restarted at
//! the next lateral sway extremum on its side ([`SwayRestart`], the CLI's
//! and Python's `imm-bslip`) against the bare estimators (a run of empty
//! cells is predicted through; a gap in time restarts at the next position
//! on `first_side`). Trials: the shared independent B-SLIP trials
//! (`DATA/independent-sim/bslip-*.csv`, a 0.4-1.0 m/s library built for the
//! body in their metadata) and 10 s trials of limbfuse's simulator at 0.5,
//! 0.7 and 0.9 m/s (0.4-1.0 m/s library, default body, that gait held out
//! for the paper configuration). Gaps of `--gap` s start at five instants
//! 0.3 s apart from 3 s (different phases of the stride), as emptied
//! `com_meas_*` cells and as removed rows. Reported over the rows after the
//! gap: phase accuracy over the rows with an estimate, the share of rows
//! with one, and the accuracy counting rows without one as wrong. And the
//! whole trial started mid-stride (its first 0.15-0.9 s removed): the
//! continuous configuration is also restarted at the first sway extremum
//! after the start (`SwayRestart`, as the CLI builds it),
//! the paper configuration keeps the paper's start. And the whole trial
//! walked 1, 2 and 5 deg off the x axis (CoM measurements turned about the
//! vertical).
//! `cargo run --release -p limbfuse-studies --example imm_gap_study -- [--gap S] [--data DIR]`

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::imm_bslip::{
    ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights, SwayRestart,
};
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};
use limbfuse_studies::bslip_trials::{independent_trials, library};
use limbfuse_studies::example_args::ImmGapStudyArgs;

const SPEEDS: [f64; 7] = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// `(config, restart, estimator)` for every configuration, bare and with
/// the sway restart.
fn estimators(
    lib: &[GaitTemplate],
    held_out: &[GaitTemplate],
) -> Vec<(String, Box<dyn Estimator>)> {
    let continuous = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    };
    let paper = ImmBslipParams::full_com();
    let c = || ImmContinuous::new(lib, continuous).unwrap();
    let p = || ImmBslip::new(held_out, paper).unwrap();
    vec![
        ("continuous, bare".into(), Box::new(c())),
        (
            "continuous, sway restart".into(),
            Box::new(SwayRestart::new(c())),
        ),
        ("paper, bare".into(), Box::new(p())),
        (
            "paper, sway restart".into(),
            Box::new(SwayRestart::new(p())),
        ),
    ]
}

/// The rows of `[a, b)` emptied of CoM measurements, or removed.
fn gapped(records: &[Record], a: f64, b: f64, rows: bool) -> Vec<Record> {
    let mut out = records.to_vec();
    if rows {
        out.retain(|r| !(a..b).contains(&r.sample.t));
    } else {
        for r in &mut out {
            if (a..b).contains(&r.sample.t) {
                r.sample.com = Default::default();
            }
        }
    }
    out
}

/// `records` walking `deg` degrees off the x axis (CoM measurements turned
/// about the vertical; the unmeasured lateral velocity stays unmeasured).
fn turned(records: &[Record], deg: f64) -> Vec<Record> {
    let (s, c) = deg.to_radians().sin_cos();
    let mut out = records.to_vec();
    for r in &mut out {
        let com = &mut r.sample.com;
        if let (Some(x), Some(z)) = (com.pos[0], com.pos[2]) {
            com.pos[0] = Some(x * c - z * s);
            com.pos[2] = Some(x * s + z * c);
        }
        match (com.vel[0], com.vel[2]) {
            (Some(vx), Some(vz)) => {
                com.vel[0] = Some(vx * c - vz * s);
                com.vel[2] = Some(vx * s + vz * c);
            }
            (Some(vx), None) => com.vel[0] = Some(vx * c),
            _ => {}
        }
    }
    out
}

/// Over the rows from `from` s: (correct, with an estimate, all).
fn score(est: &mut dyn Estimator, records: &[Record], from: f64) -> [usize; 3] {
    let mut n = [0; 3];
    for r in records {
        let e = est.step(&r.sample).unwrap();
        if r.sample.t >= from && r.reference.phase.is_some() {
            n[2] += 1;
            if e.phase.is_some() {
                n[1] += 1;
                n[0] += usize::from(e.phase == r.reference.phase);
            }
        }
    }
    n
}

/// Every configuration's phase accuracy over each of the whole `variants`.
fn whole_trials(
    variants: &[Vec<Record>],
    kind: &str,
    what: &str,
    lib: &[GaitTemplate],
    held_out: &[GaitTemplate],
) {
    for (k, (label, _)) in estimators(lib, held_out).into_iter().enumerate() {
        let acc: Vec<_> = variants
            .iter()
            .map(|records| {
                let mut est = estimators(lib, held_out).swap_remove(k).1;
                let n = score(est.as_mut(), records, 0.0);
                format!("{:.1}", 100.0 * n[0] as f64 / n[2].max(1) as f64)
            })
            .collect();
        println!("    {kind:<13} {label:<25}: {} % ({what})", acc.join(" / "));
    }
}

fn study(name: &str, trial: &[Record], lib: &[GaitTemplate], held_out: &[GaitTemplate], gap: f64) {
    println!("  {name}");
    for (k, (label, _)) in estimators(lib, held_out).into_iter().enumerate() {
        let (mut ok, mut n) = (0, 0);
        for start in [3.0, 3.3, 3.6, 3.9, 4.2] {
            let mut est = estimators(lib, held_out).swap_remove(k).1;
            let s = score(est.as_mut(), trial, start + gap);
            ok += s[0];
            n += s[2];
        }
        println!(
            "    {:<13} {label:<25}: {:.1} %",
            "no gap",
            100.0 * ok as f64 / n.max(1) as f64
        );
    }
    // Started mid-stride: the first 0.15-0.9 s removed (no gap).
    let cuts: Vec<_> = [0.15, 0.3, 0.45, 0.6, 0.75, 0.9]
        .iter()
        .map(|&cut| gapped(trial, 0.0, cut, true))
        .collect();
    whole_trials(
        &cuts,
        "mid-stride",
        "first 0.15, 0.3, ..., 0.9 s removed",
        lib,
        held_out,
    );
    // Walking off the x axis: the whole trial turned by 1, 2, 5 deg.
    let turns: Vec<_> = [1.0, 2.0, 5.0].iter().map(|&d| turned(trial, d)).collect();
    whole_trials(&turns, "heading", "turned 1, 2, 5 deg", lib, held_out);
    for rows in [false, true] {
        for (k, (label, _)) in estimators(lib, held_out).into_iter().enumerate() {
            let mut sum = [0usize; 3];
            for start in [3.0, 3.3, 3.6, 3.9, 4.2] {
                let records = gapped(trial, start, start + gap, rows);
                let mut est = estimators(lib, held_out).swap_remove(k).1;
                let n = score(est.as_mut(), &records, start + gap);
                sum.iter_mut().zip(n).for_each(|(s, n)| *s += n);
            }
            let pct = |a: usize, b: usize| 100.0 * a as f64 / b.max(1) as f64;
            println!(
                "    {:<13} {label:<25}: {:.1} % of rows with an estimate ({:.1} % of rows have one; {:.1} % counting the others wrong)",
                if rows { "rows removed" } else { "cells emptied" },
                pct(sum[0], sum[1]),
                pct(sum[1], sum[2]),
                pct(sum[0], sum[2]),
            );
        }
    }
}

fn main() {
    let args = ImmGapStudyArgs::parse();
    println!(
        "imm-bslip after a {} s gap (five starts 3.0-4.2 s), rows after the gap",
        args.gap
    );
    let body = BslipParams::default();
    let default_lib = library(&body, &SPEEDS);
    for speed in [0.5, 0.7, 0.9] {
        let walker = *default_lib
            .iter()
            .find(|t| (t.speed - speed).abs() < 1e-9)
            .unwrap();
        let held_out: Vec<_> = default_lib
            .iter()
            .filter(|t| (t.speed - speed).abs() > 1e-9)
            .copied()
            .collect();
        let cfg = BslipTrialConfig {
            duration: 10.0,
            ..Default::default()
        };
        let trial = simulate_trial(&walker, &cfg);
        study(
            &format!("limbfuse simulator, {speed} m/s, 80 kg / 1 m (paper: gait held out)"),
            &trial,
            &default_lib,
            &held_out,
            args.gap,
        );
    }
    let Some(trials) = independent_trials(std::path::Path::new(&args.data), body) else {
        println!(
            "  skipped the shared trials: {}/independent-sim not found",
            args.data
        );
        return;
    };
    for t in trials {
        let own = library(&t.body, &SPEEDS);
        study(
            &t.path.display().to_string(),
            &t.records,
            &own,
            &own,
            args.gap,
        );
    }
}
