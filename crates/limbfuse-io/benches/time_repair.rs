//! `limbfuse repair-time` throughput (`limbfuse_io::time_repair`), in CPU
//! time of one core (`support/cpu_time.rs`): a 10-minute 100 Hz trial
//! (60 000 rows, deterministic cells as `trial_csv` writes them) with one
//! time-stamp glitch every 500 rows, in turn a row written twice, two rows in
//! the wrong order and a stamp 0.5 s late; repaired by dropping and by
//! sorting (two passes over the mapped file, the copy written to a file).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

#[path = "support/cpu_time.rs"]
mod cpu_time;
use limbfuse_io::time_repair::{repair_time, TimeOrder};

/// The rows of a 60 000-row trial with its glitches, as CSV text.
fn glitched_trial() -> String {
    let mut text = String::from("# format: limbfuse-trial/1\n# sample_rate_hz: 100\nt");
    for s in ["trunk", "thigh", "shank", "foot"] {
        for q in ["acc", "gyr"] {
            for a in ["x", "y", "z"] {
                text += &format!(",{s}_{q}_{a}");
            }
        }
    }
    text += ",hip_enc,knee_enc,ankle_enc\n";
    let row = |k: usize, t: f64| {
        let mut r = format!("{t}");
        for i in 0..4 {
            let x = (k as f64 * 0.01 * (1.0 + i as f64) * std::f64::consts::SQRT_2).sin();
            for v in [x * 3.1, 9.81 + x, x * 0.7, x * 0.1, -x * 0.2, x * 2.3] {
                r += &format!(",{v}");
            }
        }
        let t0 = k as f64 * 0.01;
        r += &format!(",{},{},{}\n", t0.sin(), t0.cos(), -t0.sin());
        r
    };
    let mut rows: Vec<String> = (0..60_000).map(|k| row(k, k as f64 * 0.01)).collect();
    for (g, k) in (250..60_000 - 2).step_by(500).enumerate() {
        match g % 3 {
            0 => rows[k + 1] = rows[k].clone(),
            1 => rows.swap(k, k + 1),
            _ => rows[k] = row(k, k as f64 * 0.01 + 0.5),
        }
    }
    text + &rows.concat()
}

fn bench(c: &mut Criterion<cpu_time::ThreadCpuTime>) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let input = dir.path().join("glitched.csv");
    let text = glitched_trial();
    std::fs::write(&input, &text).expect("a temporary file");
    let output = dir.path().join("repaired.csv");
    let mut g = c.benchmark_group("time_repair");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(text.len() as u64));
    for (name, order) in [
        ("drop_60k_rows", TimeOrder::Drop),
        ("sort_60k_rows", TimeOrder::Sort),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| {
                black_box(
                    repair_time(&input, &output, order)
                        .expect("valid")
                        .rows_kept,
                )
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().with_measurement(cpu_time::ThreadCpuTime);
    targets = bench
}
criterion_main!(benches);
