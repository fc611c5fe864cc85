//! Issue 19 (lead's measurement 2026-12-03): `imm-bslip --imm-config
//! continuous` lost the phase on 10 s trials of its own simulator with the
//! true gait in the library (0.4 m/s 56 %, 0.5 53 %, 0.9 40-55 %; 70 kg /
//! 0.95 m library 0.8 m/s 55 %): MS was the ensemble's first downward `vy`
//! zero crossing in SS2, which noise fires early at the near-tangencies of
//! flat-topped (0.4-0.5 m/s) and DS-flat (0.9 m/s) gaits, and each early MS
//! put the next feet, hence the next MS, earlier still. Now the stance foot
//! is the midpoint of the CoM's mid-height crossings and MS the CoM passing
//! over it. Every library gait of both bodies, two noise seeds, 10 s each.

use crate::imm_continuous_support::run;
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;

const SPEEDS: [f64; 7] = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// The library `gait-library build --speeds 0.4:1.0:0.1` builds for `body`.
fn library(body: BslipParams) -> Vec<GaitTemplate> {
    build_library(&body, &SPEEDS, &SearchSettings::default(), |_, _| {})
        .unwrap()
        .iter()
        .map(|g| g.template(&body))
        .collect()
}

#[test]
fn issue_19_continuous_keeps_the_phase_on_10_s_trials_of_both_bodies() {
    let other = BslipParams {
        mass: 70.0,
        rest_length: 0.95,
        ..BslipParams::default()
    };
    let (default_lib, other_lib) = std::thread::scope(|s| {
        let a = s.spawn(|| library(BslipParams::default()));
        let b = s.spawn(|| library(other));
        (a.join().unwrap(), b.join().unwrap())
    });
    let mut report = Vec::new();
    let mut failed = false;
    for (name, lib) in [
        ("80 kg / 1 m", &default_lib),
        ("70 kg / 0.95 m", &other_lib),
    ] {
        for walker in lib.iter() {
            for seed in [1, 2] {
                let (acc, speed) = run(walker, lib, seed);
                let bad = acc < 0.90 || (speed - walker.speed).abs() > 0.01;
                failed |= bad;
                report.push(format!(
                    "{name} {:.1} m/s seed {seed}: phase {:.1} %, median speed {speed:.3}{}",
                    walker.speed,
                    100.0 * acc,
                    if bad { "  <-- FAIL" } else { "" }
                ));
            }
        }
    }
    assert!(!failed, "\n{}", report.join("\n"));
}
