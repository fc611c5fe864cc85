//! Paper 003 sec IV-A reproduction: measurements simulated from the 0.7 m/s
//! gait, that gait removed from a 0.4-0.9 m/s library; IMM with kappa > 0
//! and kappa = 0; also the true gait included and alone (the exact-model
//! ceiling). `cargo run --release -p limbfuse-studies --example imm_bslip_study -- [SEEDS]`
//! (prints the tables of docs/RESULTS.md). Options: `--truth 0.5` simulates
//! (and holds out) another library gait, `--weights recursive`,
//! `--touchdown step-clock|mixed`, `--p-next P`, `--p-gait P` (Markov
//! probabilities), `--rate HZ` (measurement rate, default 100), `--kappa K`
//! (only this kappa), `--ms-guard L` (MS at the apex within L x l0 of the
//! leading foot; the estimator's is 0.1) or `--ms-past-foot` (MS once the
//! CoM is past the leading foot and its apex). Besides the phase marginal
//! (the estimator's phase), it scores two other phase readouts: the phase of
//! the most likely model, and the most likely phase of the most likely gait.

use clap::Parser;
use limbfuse_core::{Estimator, GaitPhase};
use limbfuse_estimators::imm_bslip::{ImmBslip, ImmBslipParams, MidStanceEvent};
use limbfuse_models::bslip::BslipParams;
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};
use limbfuse_studies::example_args::{ImmBslipStudyArgs, IMM_STUDY_SPEEDS};

fn main() {
    let args = ImmBslipStudyArgs::parse();
    let body = BslipParams::default();
    let speeds = IMM_STUDY_SPEEDS;
    let lib = build_library(&body, &speeds, &SearchSettings::default(), |_, _| {}).unwrap();
    // --truth 0.5 etc.: simulate another library gait (held out in turn).
    let truth_speed = args.truth;
    let templates: Vec<_> = lib.iter().map(|g| g.template(&body)).collect();
    let truth = templates
        .iter()
        .find(|t| (t.speed - truth_speed).abs() < 1e-9)
        .copied()
        .unwrap();
    let held_out: Vec<_> = templates
        .iter()
        .filter(|t| (t.speed - truth_speed).abs() > 1e-9)
        .copied()
        .collect();
    let seeds: Vec<u64> = (1..=args.seeds).collect();
    println!(
        "step time of the 0.7 m/s gait: {:.3} s (stride {:.3} s)",
        truth.step_time,
        2.0 * truth.step_time
    );
    let kappas = match args.kappa {
        Some(k) => vec![k],
        None => vec![1e5, 1e4, 1e3, 0.0],
    };
    let mid_stance = match (args.ms_past_foot, args.ms_guard) {
        (true, _) => MidStanceEvent::PastFootAndApex,
        (false, Some(within)) => MidStanceEvent::ApexNearFoot { within },
        (false, None) => MidStanceEvent::default(),
    };
    println!("MS event: {mid_stance:?}");
    for kappa in kappas {
        let only = vec![truth];
        for (label, lib) in [
            ("held out", &held_out),
            ("included", &templates),
            ("truth only", &only),
        ] {
            let mut acc = Vec::new();
            // Phase readouts other than the marginal: most likely model,
            // most likely phase of the most likely gait.
            let mut acc_model = Vec::new();
            let mut acc_gait = Vec::new();
            let mut pos_rms = Vec::new();
            let mut neighbour = Vec::new();
            let mut speed_hist = std::collections::BTreeMap::new();
            let mut conf = [[0usize; 3]; 3];
            for &seed in &seeds {
                let cfg = BslipTrialConfig {
                    duration: 4.0 * truth.step_time,
                    sample_rate: args.rate,
                    seed,
                    ..Default::default()
                };
                let trial = simulate_trial(&truth, &cfg);
                // --p-next / --p-gait override the Markov probabilities (sweeps).
                let base = ImmBslipParams::full_com();
                // --weights recursive: the standard IMM mode probability.
                // --touchdown step-clock: each gait's foot lands on its own
                // step clock instead of at its touchdown height (default);
                // --touchdown mixed: foot placement mixed by the IMM.
                let params = ImmBslipParams {
                    touchdown: args.touchdown,
                    kappa,
                    p_next_phase: args.p_next.unwrap_or(base.p_next_phase),
                    p_other_gait: args.p_gait.unwrap_or(base.p_other_gait),
                    weights: args.weights,
                    mid_stance,
                    ..base
                };
                let mut imm = ImmBslip::new(lib, params).unwrap();
                let (mut ok, mut n, mut se, mut nb, mut n2) = (0, 0, 0.0, 0, 0);
                let (mut ok_model, mut ok_gait) = (0, 0);
                for r in &trial {
                    let e = imm.step(&r.sample).unwrap();
                    let w: f64 = imm.weights().sum();
                    assert!((w - 1.0).abs() < 1e-9);
                    // Models are gait-major, phases SS1, DS, SS2.
                    let ws: Vec<f64> = imm.weights().collect();
                    let argmax =
                        |v: &[f64]| (0..v.len()).fold(0, |b, i| if v[i] > v[b] { i } else { b });
                    let phases = [GaitPhase::Ss1, GaitPhase::Ds, GaitPhase::Ss2];
                    if Some(phases[argmax(&ws) % 3]) == r.reference.phase {
                        ok_model += 1;
                    }
                    let per_gait: Vec<f64> = ws.chunks(3).map(|c| c.iter().sum()).collect();
                    let g = argmax(&per_gait);
                    if Some(phases[argmax(&ws[3 * g..3 * g + 3])]) == r.reference.phase {
                        ok_gait += 1;
                    }
                    if e.phase == r.reference.phase {
                        ok += 1;
                    }
                    let pi = |p: Option<GaitPhase>| match p {
                        Some(GaitPhase::Ss1) => 0,
                        Some(GaitPhase::Ds) => 1,
                        _ => 2,
                    };
                    conf[pi(r.reference.phase)][pi(e.phase)] += 1;
                    n += 1;
                    let d = e.com_pos.unwrap() - r.reference.com_pos.unwrap();
                    se += d.norm_squared();
                    // second gait cycle: steps 3 and 4
                    if r.sample.t >= 2.0 * truth.step_time {
                        n2 += 1;
                        let s = e.speed.unwrap();
                        *speed_hist.entry(format!("{s:.1}")).or_insert(0) += 1;
                        if ((s - truth_speed).abs() - 0.1).abs() < 1e-9 {
                            nb += 1;
                        }
                    }
                    let _ = GaitPhase::Ss1;
                }
                acc.push(ok as f64 / n as f64 * 100.0);
                acc_model.push(ok_model as f64 / n as f64 * 100.0);
                acc_gait.push(ok_gait as f64 / n as f64 * 100.0);
                pos_rms.push((se / n as f64).sqrt() * 100.0);
                neighbour.push(nb as f64 / n2 as f64 * 100.0);
            }
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
            let min = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min);
            println!("kappa {kappa:>8} {truth_speed} {label}: phase acc mean {:.1} % (min {:.1}), CoM pos RMS {:.2} cm (max {:.2}), neighbour-most-likely in cycle 2 {:.1} % ; speeds {:?}",
                mean(&acc), min(&acc), mean(&pos_rms), pos_rms.iter().cloned().fold(0.0, f64::max), mean(&neighbour), speed_hist);
            println!("   confusion (rows true SS1/DS/SS2, cols est): {conf:?}");
            println!(
                "   phase acc of other readouts: most likely model {:.1} %, most likely phase of the most likely gait {:.1} %",
                mean(&acc_model),
                mean(&acc_gait)
            );
        }
    }
}
