//! `imm-bslip`, configuration `continuous` (issue 19 items 1-2): with the
//! walker's gait held out of a small family, the speed is estimated between
//! the family's gaits and the phase from the leg lengths follows the
//! reference; gaps restart it without NaN.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::imm_bslip::{ImmBslipParams, ImmContinuous, ImmWeights};
use limbfuse_models::bslip::{BslipParams, GaitTemplate};
use limbfuse_sim::bslip::library::{start_seed, LibraryGait, START_SPEED};
use limbfuse_sim::bslip::search::{optimise_gait, SearchSettings};
use limbfuse_sim::bslip::step::StepSimulator;
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};

/// One optimised gait (the walker) and a family of two dynamically similar
/// gaits around it (CoM heights x0.9 and x1.1: speeds x0.95 and x1.05),
/// so the test costs one gait search.
fn walker_and_family() -> (GaitTemplate, Vec<GaitTemplate>) {
    let body = BslipParams::default();
    let sim = StepSimulator::new(body);
    let g: LibraryGait = optimise_gait(
        &sim,
        &start_seed(1.0),
        START_SPEED,
        &SearchSettings::default(),
    )
    .unwrap()
    .into();
    let t = g.template(&body);
    let family = vec![
        t.rescaled_to_height(t.gait.height * 0.9).unwrap(),
        t.rescaled_to_height(t.gait.height * 1.1).unwrap(),
    ];
    (t, family)
}

fn params() -> ImmBslipParams {
    ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    }
}

#[test]
fn speed_between_the_family_gaits_and_phase_from_the_leg_lengths() {
    let (walker, family) = walker_and_family();
    let records: Vec<Record> = simulate_trial(
        &walker,
        &BslipTrialConfig {
            duration: 4.0,
            ..Default::default()
        },
    );
    let mut imm = ImmContinuous::new(&family, params()).unwrap();
    let (mut ok, mut speeds) = (0, Vec::new());
    for r in &records {
        let e = imm.step(&r.sample).unwrap();
        ok += usize::from(e.phase == r.reference.phase);
        speeds.push(e.speed.unwrap());
    }
    let acc = ok as f64 / records.len() as f64;
    speeds.sort_by(f64::total_cmp);
    let median = speeds[speeds.len() / 2];
    // The family's gaits are 5 % slower and faster than the walker: a grid
    // estimate would be off by ~0.05 m/s.
    let grid = (family[0].speed - walker.speed).abs();
    assert!(grid > 0.04, "family spacing {grid}");
    assert!(
        (median - walker.speed).abs() < 0.02,
        "median speed {median}, walker {}",
        walker.speed
    );
    assert!(acc > 0.9, "phase accuracy {acc}");
    // Re-targeted between the two family gaits.
    let g = imm.current_gait();
    assert!(g.speed > family[0].speed && g.speed < family[1].speed);
}

#[test]
fn a_gap_restarts_the_continuous_configuration_without_nan() {
    let (walker, family) = walker_and_family();
    let records = simulate_trial(
        &walker,
        &BslipTrialConfig {
            duration: 2.0,
            ..Default::default()
        },
    );
    let mut imm = ImmContinuous::new(&family, params()).unwrap();
    for (k, r) in records.iter().enumerate() {
        if (80..120).contains(&k) {
            continue; // a 0.4 s gap
        }
        let e = imm.step(&r.sample).unwrap();
        assert!(e.speed.is_some_and(f64::is_finite));
        assert!(e.com_pos.is_some_and(|p| p.iter().all(|v| v.is_finite())));
    }
    assert!(ImmContinuous::new(&[], params()).is_err());
}
