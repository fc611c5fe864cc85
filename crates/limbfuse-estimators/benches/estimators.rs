//! Per-sample cost of every segment-angle estimator on a seeded simulated
//! walking trial (60 s at 100 Hz, default sensors), one core: `step` alone
//! (group `estimator_60s_100hz`), and the segment filters the way
//! `limbfuse estimate` runs them (group `gated_60s_100hz`): behind the
//! sensor gate ([`SampleGate`], as `limbfuse_methods::gated` does), each
//! estimate built in place in one reused [`Estimate`] (`step_into`).
//! Measured in CPU time of the benchmark thread (`cpu_time.rs`, shared with
//! the I/O benches): on the shared machine wall time counts the waits.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimate, Estimator, Record, SampleGate, SensorRanges};
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

#[path = "../../limbfuse-io/benches/support/cpu_time.rs"]
mod cpu_time;

/// A method name and a constructor of a fresh estimator.
type Maker = (&'static str, fn() -> Box<dyn Estimator>);

fn bench(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    let sim = WalkingSimulator::new(WalkingConfig {
        seed: 42,
        ..WalkingConfig::default()
    })
    .expect("valid config");
    let records: Vec<Record> = sim.collect();
    let mut g = c.benchmark_group("estimator_60s_100hz");
    g.throughput(Throughput::Elements(records.len() as u64));
    g.sample_size(20);
    let makers: [Maker; 5] = [
        ("gyro-integration", || Box::new(GyroIntegration::new())),
        ("accel-inclination", || Box::new(AccelInclination::new())),
        ("local", || Box::new(LocalKf::default())),
        ("mjls", || Box::new(MarkovJumpKf::default())),
        ("global", || Box::new(GlobalKf::default())),
    ];
    for (name, make) in makers {
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut e = make();
                let mut acc = 0.0;
                for r in &records {
                    let est = e.step(&r.sample).expect("valid sample");
                    acc += est.segment[1].unwrap_or(0.0);
                }
                black_box(acc)
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("gated_60s_100hz");
    g.throughput(Throughput::Elements(records.len() as u64));
    g.sample_size(20);
    for (name, make) in &makers[2..] {
        g.bench_function(*name, |b| {
            b.iter(|| {
                let mut e = make();
                let mut gate = SampleGate::new(SensorRanges::default());
                let mut est = Estimate::empty(0.0);
                let mut acc = 0.0;
                for r in &records {
                    gated_step(&mut gate, e.as_mut(), &r.sample, &mut est);
                    acc += est.segment[1].unwrap_or(0.0);
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

/// One step behind the sensor gate, as `GatedEstimator::step_into`.
fn gated_step(
    gate: &mut SampleGate,
    e: &mut dyn Estimator,
    sample: &limbfuse_core::Sample,
    est: &mut Estimate,
) {
    let screening = gate.check(sample);
    if screening.is_clean() {
        e.step_into(sample, est).expect("valid sample");
    } else {
        let mut s = *sample;
        screening.apply(&mut s);
        e.step_into(&s, est).expect("valid sample");
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(cpu_time::ThreadCpuTime);
    targets = bench
}
criterion_main!(benches);
