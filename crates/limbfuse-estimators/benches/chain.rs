//! Per-sample cost of `chain` (kinematic-chain EKF) on a seeded simulated
//! walking trial: 60 s at 100 Hz, 4 IMUs + 3 encoders, default sensors, one
//! core (issue 14: >= 200 k samples/s).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainGeometry, ChainParams};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

fn bench(c: &mut Criterion) {
    let cfg = WalkingConfig {
        seed: 42,
        ..WalkingConfig::default()
    };
    let records: Vec<Record> = WalkingSimulator::new(cfg).expect("valid config").collect();
    let mut g = c.benchmark_group("chain_60s_100hz");
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

criterion_group!(benches, bench);
criterion_main!(benches);
