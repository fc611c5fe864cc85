//! Per-sample cost of `chain` (kinematic-chain EKF) on a seeded simulated
//! walking trial: 60 s at 100 Hz, 4 IMUs + 3 encoders, default sensors, one
//! core (issue 14: >= 200 k samples/s). Two groups: wall time, and the
//! thread's CPU time (`chain_60s_100hz_cpu`), which a loaded shared machine
//! does not inflate by time-slicing.

use std::hint::black_box;

use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainGeometry, ChainParams};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

// One measurement for every crate's benches (it lives with limbfuse-io's).
#[path = "../../limbfuse-io/benches/support/cpu_time.rs"]
mod cpu_time;
use cpu_time::ThreadCpuTime;

fn bench_wall(c: &mut Criterion) {
    bench(c, "chain_60s_100hz");
}

fn bench_cpu(c: &mut Criterion<ThreadCpuTime>) {
    bench(c, "chain_60s_100hz_cpu");
}

fn bench<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let cfg = WalkingConfig {
        seed: 42,
        ..WalkingConfig::default()
    };
    let records: Vec<Record> = WalkingSimulator::new(cfg).expect("valid config").collect();
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(records.len() as u64));
    g.sample_size(10);
    g.bench_function("chain", |b| {
        b.iter(|| {
            let mut e = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), cfg.g)
                .expect("valid parameters");
            let mut acc = 0.0;
            for r in &records {
                let est = e.step(&r.sample).expect("valid sample");
                acc += est.segment[1].unwrap_or(0.0);
            }
            black_box(acc)
        })
    });
    g.finish();
}

criterion_group!(wall, bench_wall);
criterion_group! {
    name = cpu;
    config = Criterion::default().with_measurement(ThreadCpuTime);
    targets = bench_cpu
}
criterion_main!(wall, cpu);
