//! Estimate-file writing throughput (issue 18 item 6: >= 300 MB/s), in CPU
//! time of one core (`support/cpu_time.rs`).
//!
//! The estimates have the shape of an `mjls` run (7 angles, 37 diagnostics:
//! 16 exact small numbers such as flags and counts, 12 empty cells, the rest
//! full-precision values), from smooth signals plus an irrational
//! perturbation so every value has the 16-17 significant digits a filter
//! writes. Deterministic (no RNG); 60 000 rows (10 min at 100 Hz).

use std::fmt;
use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

#[path = "support/cpu_time.rs"]
mod cpu_time;
use limbfuse_core::estimator::Outputs;
use limbfuse_core::runner::Observer;
use limbfuse_core::{Estimate, Estimator, EstimatorError, Record, Sample};
use limbfuse_io::EstimateWriter;

const DIAG_NAMES: [&str; 37] = [
    "mode",
    "rho_min",
    "upd_trunk",
    "upd_thigh",
    "upd_shank",
    "upd_foot",
    "upd_hip",
    "upd_knee",
    "upd_ankle",
    "missing_inputs",
    "rho_trunk",
    "rho_thigh",
    "rho_shank",
    "rho_foot",
    "bias_trunk",
    "bias_thigh",
    "bias_shank",
    "bias_foot",
    "sd_trunk",
    "sd_thigh",
    "sd_shank",
    "sd_foot",
    "share_own_trunk",
    "share_own_thigh",
    "share_own_shank",
    "share_own_foot",
    "share_other_trunk",
    "share_other_thigh",
    "share_other_shank",
    "share_other_foot",
    "share_joint_trunk",
    "share_joint_thigh",
    "share_joint_shank",
    "share_joint_foot",
    "rejected_gyro",
    "rejected_acc",
    "rejected_encoder",
];

/// Stands in for the estimator in the header (name, outputs, diagnostics).
struct MjlsShape;

impl Estimator for MjlsShape {
    fn name(&self) -> &'static str {
        "mjls"
    }
    fn outputs(&self) -> Outputs {
        Outputs {
            segment: [true; 4],
            joint: [true; 3],
            ..Outputs::default()
        }
    }
    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        writeln!(out, "sigma_gyro: 0.01")
    }
    fn diagnostic_names(&self) -> &[&'static str] {
        &DIAG_NAMES
    }
    fn reset(&mut self) {}
    fn step(&mut self, _sample: &Sample) -> Result<Estimate, EstimatorError> {
        unreachable!("the bench only writes")
    }
}

fn estimates(n: usize) -> Vec<Estimate> {
    (0..n)
        .map(|k| {
            let t = k as f64 * 0.01;
            let x = |i: usize| (t * (1.0 + i as f64) * std::f64::consts::SQRT_2).sin();
            let mut e = Estimate::empty(t);
            for (i, s) in e.segment.iter_mut().enumerate() {
                *s = Some(0.4 * x(i));
            }
            for (i, j) in e.joint.iter_mut().enumerate() {
                *j = Some(0.3 * x(i + 4));
            }
            e.diag[0] = Some(-1.0);
            e.diag[1] = Some(1.0 + x(7).abs());
            for d in &mut e.diag[2..10] {
                *d = Some(0.0);
            }
            for (i, d) in e.diag[10..14].iter_mut().enumerate() {
                *d = Some(2.0 + x(i + 8));
            }
            for d in &mut e.diag[14..18] {
                *d = Some(-0.0);
            }
            for (i, d) in e.diag[18..22].iter_mut().enumerate() {
                *d = Some(0.28 + 1e-3 * x(i + 12));
            }
            for d in &mut e.diag[34..37] {
                *d = Some(0.0);
            }
            e
        })
        .collect()
}

/// How the estimates are written.
#[derive(Clone, Copy)]
enum Form {
    /// CSV, one write per row (a stream).
    Rows,
    /// CSV, rows written in 64 KiB blocks (a file: `EstimateWriter::for_path`).
    Blocks,
    /// An Arrow IPC file.
    Arrow,
}

/// Writes every estimate into `out` (cleared; reused between iterations so
/// that the kernel's page faults of a fresh 24 MB buffer are not timed).
fn write_all(est: &[Estimate], out: &mut Vec<u8>, form: Form) -> usize {
    out.clear();
    let mut w = match form {
        Form::Rows => EstimateWriter::new(out),
        Form::Blocks => EstimateWriter::new(out).in_blocks(),
        Form::Arrow => EstimateWriter::arrow(out),
    };
    w.start(&MjlsShape).expect("in-memory write");
    let r = Record::default();
    for e in est {
        w.observe(&r, e).expect("in-memory write");
    }
    w.finish().expect("in-memory write");
    w.into_inner().expect("in-memory write").len()
}

fn bench(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    let est = estimates(60_000);
    let mut out = Vec::new();
    let bytes = write_all(&est, &mut out, Form::Rows);
    let mut g = c.benchmark_group("estimate_csv");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes as u64));
    g.bench_function("write_60k_rows", |b| {
        b.iter(|| black_box(write_all(&est, &mut out, Form::Rows)))
    });
    // The file path of `estimate` (issue 18 item 6, `iopath`).
    g.bench_function("write_60k_rows_in_blocks", |b| {
        b.iter(|| black_box(write_all(&est, &mut out, Form::Blocks)))
    });
    g.finish();
    // The same estimates as an Arrow file (throughput in the CSV's bytes,
    // so that the two compare as time per row).
    let mut g = c.benchmark_group("estimate_arrow");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes as u64));
    g.bench_function("write_60k_rows", |b| {
        b.iter(|| black_box(write_all(&est, &mut out, Form::Arrow)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(cpu_time::ThreadCpuTime);
    targets = bench
}
criterion_main!(benches);
