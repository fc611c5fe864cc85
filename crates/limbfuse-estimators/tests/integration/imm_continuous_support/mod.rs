//! What the issue-19 tests of `imm-bslip --imm-config continuous` share:
//! one 10 s simulated trial of a walker gait, scored.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::imm_bslip::{ImmBslipParams, ImmContinuous, ImmWeights};
use limbfuse_models::bslip::GaitTemplate;
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};

/// Phase accuracy and median speed of the continuous configuration on a
/// 10 s trial of `walker`.
pub fn run(walker: &GaitTemplate, family: &[GaitTemplate], seed: u64) -> (f64, f64) {
    let records: Vec<Record> = simulate_trial(
        walker,
        &BslipTrialConfig {
            duration: 10.0,
            seed,
            ..Default::default()
        },
    );
    let params = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    };
    let mut imm = ImmContinuous::new(family, params).unwrap();
    let (mut ok, mut speeds) = (0, Vec::new());
    for r in &records {
        let e = imm.step(&r.sample).unwrap();
        ok += usize::from(e.phase == r.reference.phase);
        speeds.push(e.speed.unwrap());
    }
    speeds.sort_by(f64::total_cmp);
    (ok as f64 / records.len() as f64, speeds[speeds.len() / 2])
}
