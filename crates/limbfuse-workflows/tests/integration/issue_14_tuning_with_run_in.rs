//! Issue 14: `calibration_study -- 5 --tune --startup 2` stopped with "no
//! segment could be evaluated". The PSO had found parameters with which the
//! filter keeps restarting (`encoder_sigma` at its lower bound: the encoder
//! rows are refused, and after `GATE_LOCKOUT_S` the chain restarts), each
//! restart restarting the run-in `startup_s`; the objective, a mean over
//! the samples that were scored, rewarded them (0.23 deg on 40 of 20002
//! samples against 0.81 deg on all), and on the validation window they
//! scored nothing. The objective must count a candidate that scores fewer
//! samples than the start as a failure, and the protocol reports coverage.

use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Record, Segment};
use limbfuse_eval::TimeWindow;
use limbfuse_methods::segment_params::{FilterMethod, FilterParams, Preset};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use limbfuse_workflows::coverage::ScoredFloor;
use limbfuse_workflows::protocol::{plan_intervals, StartPlan};
use limbfuse_workflows::tuning::{measure_params, objective_deg, tune, TuneConfig};

const RUN_IN_S: f64 = 1.0;

fn trial() -> Vec<Record> {
    WalkingSimulator::new(WalkingConfig {
        duration_s: 12.0,
        imu_rate_hz: 50.0,
        seed: 2,
        speed_mps: 0.4,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect()
}

fn intervals(records: &[Record]) -> Vec<(f64, f64)> {
    plan_intervals(
        records,
        &StartPlan {
            window: TimeWindow::parse("0:12").unwrap(),
            starts: 4,
            length_s: Some(6.0),
        },
    )
    .unwrap()
}

fn start() -> FilterParams {
    let mut p = FilterParams::preset(FilterMethod::Mjls, Preset::Default);
    p.common_mut().startup_s = RUN_IN_S;
    p
}

/// The start with `encoder_sigma` at the lower end of the search range
/// (two decades down), where the tuned parameters of issue 14 ended.
fn restarting() -> FilterParams {
    let mut p = start();
    if let FilterParams::Mjls(m) = &mut p {
        m.encoder_sigma = m.encoder_sigma.map(|s| s * 1e-2);
    }
    p
}

#[test]
fn issue_14_a_candidate_that_scores_fewer_samples_than_the_start_fails() {
    let records = trial();
    let iv = intervals(&records);
    let s = measure_params(&start(), &records, &iv).unwrap().unwrap();
    let r = measure_params(&restarting(), &records, &iv)
        .unwrap()
        .unwrap();
    let seg = |m: &limbfuse_workflows::protocol::MultiStartResult| {
        (
            m.mean_rmse().unwrap().to_degrees(),
            m.segment_coverage().unwrap(),
            m.runs
                .iter()
                .map(|e| e.resets.map_or(0, |x| x.count))
                .sum::<u64>(),
        )
    };
    let (s_deg, s_cov, s_resets) = seg(&s);
    let (r_deg, r_cov, r_resets) = seg(&r);
    println!("start: {s_deg:.3} deg, coverage {s_cov:.3}, {s_resets} restarts");
    println!("restarting: {r_deg:.3} deg, coverage {r_cov:.3}, {r_resets} restarts");
    // The run-in leaves out RUN_IN_S of each 6 s run and nothing else.
    assert!((s_cov - (1.0 - RUN_IN_S / 6.0)).abs() < 0.01, "{s_cov}");
    assert_eq!(s_resets, 0);
    // The restarting filter estimates less...
    assert!(r_resets > 0 && r_cov < s_cov, "{r_cov} {r_resets}");
    let thigh = AngleChannel::Segment(Segment::Thigh);
    assert!(r.coverage(thigh).unwrap() < s.coverage(thigh).unwrap());
    // ...and the objective must not compare it on its smaller set.
    let floor = ScoredFloor::of(&s);
    assert!(floor.first_shortfall(&r).is_some());
    let start_cost = objective_deg(&start(), &records, &iv, &floor).unwrap();
    let cost = objective_deg(&restarting(), &records, &iv, &floor).unwrap();
    assert!((start_cost - s_deg).abs() < 1e-12);
    assert_eq!(
        cost,
        f64::INFINITY,
        "restarting candidate scored {cost} deg"
    );
}

#[test]
fn issue_14_tuned_parameters_with_a_run_in_score_every_sample_the_start_scores() {
    let records = trial();
    let iv = intervals(&records);
    // Without the fix this swarm ends on parameters that restart and score
    // 5 % of the segment samples (0.320 deg on those; checked); tuning
    // seeds 1-11 happen to end on fully scored ones.
    let cfg = TuneConfig {
        seed: 12,
        budget: 120,
        particles: 12,
        cancel: None,
    };
    let r = tune(&start(), &records, &iv, &cfg, &|| {}).unwrap();
    let s = measure_params(&start(), &records, &iv).unwrap().unwrap();
    let t = measure_params(&r.params, &records, &iv).unwrap().unwrap();
    println!(
        "start {:.3} deg ({:.3} scored), tuned {:.3} deg ({:.3} scored)",
        r.start_cost_deg,
        s.segment_coverage().unwrap(),
        r.best_cost_deg,
        t.segment_coverage().unwrap()
    );
    assert_eq!(ScoredFloor::of(&s).first_shortfall(&t), None);
    for c in AngleChannel::ALL {
        assert_eq!(t.unscored_runs(c), 0, "{}", c.name());
    }
    assert!(r.best_cost_deg <= r.start_cost_deg);
}
