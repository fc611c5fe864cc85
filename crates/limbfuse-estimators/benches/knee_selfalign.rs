//! Processing a 60 s, 100 Hz trial with the self-aligning knee estimator
//! (paper 002; s_w = 500, order = 6; 12 window re-estimates), on the seeded
//! knee scenario (random IMU orientations and positions), one core.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_sim::{KneeScenario, KneeSimulator, WalkingConfig};

fn bench(c: &mut Criterion) {
    let d = KneeScenario::default();
    let sc = KneeScenario {
        walking: WalkingConfig {
            seed: 42,
            ..d.walking
        },
        ..d
    };
    let records: Vec<Record> = KneeSimulator::new(sc).expect("valid scenario").collect();
    let mut g = c.benchmark_group("knee_selfalign_60s_100hz");
    g.throughput(Throughput::Elements(records.len() as u64));
    g.sample_size(20);
    for (window, order) in [(500, 6), (200, 6)] {
        g.bench_function(format!("s_w={window} order={order}"), |b| {
            b.iter(|| {
                let mut e = KneeSelfAlign::new(KneeSelfAlignParams {
                    window,
                    order,
                    ..KneeSelfAlignParams::default()
                })
                .expect("valid parameters");
                let mut acc = 0.0;
                for r in &records {
                    acc += e.step(&r.sample).expect("valid sample").joint[1].unwrap_or(0.0);
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
