//! Per-sample cost of every segment-angle estimator on a seeded simulated
//! walking trial (60 s at 100 Hz, default sensors), one core.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::baseline::{AccelInclination, GyroIntegration};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

/// A method name and a constructor of a fresh estimator.
type Maker = (&'static str, fn() -> Box<dyn Estimator>);

fn bench(c: &mut Criterion) {
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
}

criterion_group!(benches, bench);
criterion_main!(benches);
