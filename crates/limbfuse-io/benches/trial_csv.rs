//! Trial CSV reading and writing throughput (issue 2: reading >= 50 MB/s;
//! issue 18: >= 400 MB/s), in CPU time of one core (`support/cpu_time.rs`).
//!
//! The file is deterministic (no RNG): 4 IMUs + 3 encoders + 7 references,
//! values from smooth signals plus an irrational perturbation so every cell
//! has the full 17 significant digits a simulator writes. The records are
//! built once; `write_60k_rows` times only the writing.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

#[path = "support/cpu_time.rs"]
mod cpu_time;
use limbfuse_core::Record;
use limbfuse_io::{TrialLayout, TrialMeta, TrialReader, TrialWriter};
use nalgebra::Vector3;

fn records(n: usize) -> Vec<Record> {
    let mut out = Vec::with_capacity(n);
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
        out.push(r);
    }
    out
}

/// Writes `records` into `out` (cleared; reused between iterations so that
/// the kernel's page faults of a fresh 38 MB buffer are not timed).
fn trial_bytes<'a>(records: &[Record], out: &'a mut Vec<u8>) -> &'a mut Vec<u8> {
    out.clear();
    let mut w = TrialWriter::new(out, &TrialMeta::trial_v1(), TrialLayout::walking())
        .expect("in-memory write");
    for r in records {
        w.write(r).expect("in-memory write");
    }
    w.finish().expect("in-memory write")
}

fn bench(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    let n = 60_000; // 10 minutes at 100 Hz
    let records = records(n);
    // Leaked so that each read borrows the bytes instead of copying them.
    let mut out = Vec::new();
    trial_bytes(&records, &mut out);
    let bytes: &'static [u8] = Vec::leak(out.clone());
    let mut g = c.benchmark_group("trial_csv");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("read_60k_rows", |b| {
        b.iter(|| {
            let r =
                TrialReader::from_reader(Path::new("bench.csv"), Box::new(bytes)).expect("valid");
            let mut acc = 0.0;
            for rec in r {
                acc += rec.expect("valid").sample.t;
            }
            black_box(acc)
        })
    });
    // The runner's path (issue 18): every row parsed into one record.
    g.bench_function("read_into_60k_rows", |b| {
        b.iter(|| {
            let mut r =
                TrialReader::from_reader(Path::new("bench.csv"), Box::new(bytes)).expect("valid");
            let mut rec = Record::default();
            let mut acc = 0.0;
            while r.read_into(&mut rec).expect("valid") {
                acc += rec.sample.t;
            }
            black_box(acc)
        })
    });
    g.bench_function("write_60k_rows", |b| {
        b.iter(|| black_box(trial_bytes(&records, &mut out).len()))
    });
    // The runner's path from a file (issue 18 item 6, `iopath`): the file
    // mapped and read in place; it is in the page cache, as a trial just
    // written or read before is.
    let dir = tempfile::tempdir().expect("a temporary directory");
    let csv = dir.path().join("bench.csv");
    std::fs::write(&csv, bytes).expect("a temporary file");
    g.bench_function("read_into_60k_rows_mapped_file", |b| {
        b.iter(|| black_box(read_into_all(&csv)))
    });
    g.finish();
    // The same trial as an Arrow file, read the same way (throughput in the
    // CSV's bytes, so that the two compare as time per row).
    let arrow = dir.path().join("bench.arrow");
    let mut file = std::fs::File::create(&arrow).expect("a temporary file");
    let mut w = TrialWriter::for_path(
        &arrow,
        &mut file,
        &TrialMeta::trial_v1(),
        TrialLayout::walking(),
    )
    .expect("a temporary file");
    for r in &records {
        w.write(r).expect("a temporary file");
    }
    w.finish().expect("a temporary file");
    drop(file);
    let mut g = c.benchmark_group("trial_arrow");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("read_into_60k_rows_mapped_file", |b| {
        b.iter(|| black_box(read_into_all(&arrow)))
    });
    g.finish();
}

/// Every row of the trial file at `path` parsed into one record.
fn read_into_all(path: &Path) -> f64 {
    let mut r = TrialReader::open(path).expect("valid");
    let mut rec = Record::default();
    let mut acc = 0.0;
    while r.read_into(&mut rec).expect("valid") {
        acc += rec.sample.t;
    }
    acc
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(cpu_time::ThreadCpuTime);
    targets = bench
}
criterion_main!(benches);
