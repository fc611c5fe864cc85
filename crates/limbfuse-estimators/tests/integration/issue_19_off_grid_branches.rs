//! Issue 19, off-grid speeds and other gait branches: the gait search can
//! land on different branches at the same speed (70 kg / 0.95 m at
//! 0.8 m/s: the library's gait has k ~8.2 kN/m and 34 % double support;
//! continued up from the 0.7 m/s gait it has k ~15.5 kN/m and 18 %, like
//! the independent simulator's gaits). The continuous configuration took
//! its filters' leg stiffness from the family, so a walker on the other
//! branch was tracked with the wrong dynamics: phase 88 % (human-like walker,
//! the body's own library) and 82-84 % (the library's odd gait, default-body
//! library rescaled). Now the stiffness is measured from the weight support
//! over each step. Both cases, two noise seeds, 10 s each.

use crate::imm_continuous_support::run;
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::{build_library, continue_to, LibraryGait};
use limbfuse_sim::bslip::periodic::Corrected;
use limbfuse_sim::bslip::search::{FoundGait, SearchSettings};
use limbfuse_sim::bslip::step::StepSimulator;

/// Library speeds: the neighbours of 0.8 m/s, as in `gait-library build
/// --speeds 0.4:1.0:0.1` (the homotopy from 1.0 m/s walks the same path).
const SPEEDS: [f64; 3] = [0.7, 0.8, 0.9];

fn library(body: &BslipParams) -> Vec<LibraryGait> {
    build_library(body, &SPEEDS, &SearchSettings::default(), |_, _| {}).unwrap()
}

#[test]
fn issue_19_off_grid_gait_branch_other_than_the_library() {
    let body = BslipParams {
        mass: 70.0,
        rest_length: 0.95,
        ..BslipParams::default()
    };
    let default_body = BslipParams::default();
    let (own, default_lib) = std::thread::scope(|s| {
        let a = s.spawn(|| library(&body));
        let b = s.spawn(|| library(&default_body));
        (a.join().unwrap(), b.join().unwrap())
    });
    // The human-like 0.8 m/s gait: continued up from the library's 0.7.
    let from = own[0];
    let found = FoundGait {
        speed: from.speed,
        solution: Corrected {
            gait: from.gait,
            outcome: from.step,
            residual: from.residual,
            iterations: 0,
        },
        objective: from.objective,
    };
    let sim = StepSimulator::new(body);
    let human: LibraryGait = continue_to(&sim, &found, 0.8, &SearchSettings::default())
        .unwrap()
        .into();
    let odd = own[1];
    // Precondition: the two 0.8 m/s gaits are on different branches.
    let (k_human, k_odd) = (human.gait.stiffness, odd.gait.stiffness);
    assert!(k_human > 1.5 * k_odd, "k {k_human} vs {k_odd}");
    let own: Vec<GaitTemplate> = own.iter().map(|g| g.template(&body)).collect();
    let rescaled: Vec<GaitTemplate> = default_lib
        .iter()
        .map(|g| g.template(&default_body).rescaled_to_body(&body).unwrap())
        .collect();
    let mut report = Vec::new();
    let mut failed = false;
    for (name, walker, family) in [
        ("human-like gait, own library", human.template(&body), &own),
        (
            "library's gait, default library rescaled",
            odd.template(&body),
            &rescaled,
        ),
    ] {
        for seed in [1, 2] {
            let (acc, speed) = run(&walker, family, seed);
            let bad = acc < 0.90 || (speed - 0.8).abs() > 0.01;
            failed |= bad;
            report.push(format!(
                "{name}, k {:.0} N/m, seed {seed}: phase {:.1} %, median speed {speed:.3}{}",
                walker.body.stiffness,
                100.0 * acc,
                if bad { "  <-- FAIL" } else { "" }
            ));
        }
    }
    assert!(!failed, "\n{}", report.join("\n"));
}
