//! Trial CSV reading and writing throughput (issue 2: reading >= 50 MB/s).
//!
//! The file is deterministic (no RNG): 4 IMUs + 3 encoders + 7 references,
//! values from smooth signals plus an irrational perturbation so every cell
//! has the full 17 significant digits a simulator writes.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::Record;
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader, TrialWriter};
use nalgebra::Vector3;

fn trial_bytes(n: usize) -> Vec<u8> {
    let mut w = TrialWriter::new(Vec::new(), &TrialMeta::trial_v1(), TrialLayout::walking())
        .expect("in-memory write");
    for k in 0..n {
        let t = k as f64 * 0.01;
        let mut r = Record::default();
        r.sample.t = t;
        for (i, imu) in r.sample.imu.iter_mut().enumerate() {
            let x = (t * (1.0 + i as f64) * std::f64::consts::SQRT_2).sin();
            imu.acc = Some(Vector3::new(x * 3.1, 9.81 + x, x * 0.7));
            imu.gyr = Some(Vector3::new(x * 0.1, -x * 0.2, x * 2.3));
        }
        r.sample.encoder = [Some(t.sin()), Some(t.cos()), Some(-t.sin())];
        r.reference.segment = [
            Some(0.01 * t.sin()),
            Some(t.sin()),
            Some(t.cos()),
            Some(0.3 * t.sin()),
        ];
        r.reference.joint = [Some(t.cos()), Some(-t.sin()), Some(0.2 * t.cos())];
        w.write(&r).expect("in-memory write");
    }
    w.finish().expect("in-memory write")
}

fn bench(c: &mut Criterion) {
    let n = 60_000; // 10 minutes at 100 Hz
    let bytes = trial_bytes(n);
    let mut g = c.benchmark_group("trial_csv");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("read_60k_rows", |b| {
        b.iter(|| {
            let r = TrialReader::from_reader(
                Path::new("bench.csv"),
                Box::new(std::io::Cursor::new(bytes.clone())),
            )
            .expect("valid");
            let mut acc = 0.0;
            for rec in r {
                acc += rec.expect("valid").sample.t;
            }
            black_box(acc)
        })
    });
    g.bench_function("write_60k_rows", |b| {
        b.iter(|| black_box(trial_bytes(n).len()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
