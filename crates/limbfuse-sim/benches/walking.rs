//! Throughput of the walking simulator: 4 IMUs at 1 kHz (encoders at 1 kHz),
//! all sensor errors on, random mountings, out-of-plane motion and
//! variability on.
//!
//! * criterion (10 samples) times one simulated minute (60 000 records);
//! * before that, one full simulated hour (3.6 M records) is timed once and
//!   printed, so the one-hour figure is measured, not extrapolated.
//!
//! `CARGO_TARGET_DIR=/work/target-sim cargo bench -p limbfuse-sim --bench walking`

use std::hint::black_box;
use std::time::Instant;

use criterion::{criterion_group, Criterion};
use limbfuse_sim::{Mounting, WalkingConfig, WalkingSimulator};

fn config(duration_s: f64) -> WalkingConfig {
    WalkingConfig {
        duration_s,
        imu_rate_hz: 1000.0,
        encoder_rate_hz: 1000.0,
        mounting: Mounting::Random,
        speed_mps: 1.2,
        seed: 7,
        ..Default::default()
    }
}

/// Consumes a simulator, folding every reading into a checksum.
fn drain(sim: WalkingSimulator) -> (u64, f64) {
    let mut n = 0u64;
    let mut acc = 0.0;
    for r in sim {
        n += 1;
        acc += r.sample.imu[3].acc.map_or(0.0, |a| a.x) + r.sample.encoder[1].unwrap_or(0.0);
    }
    (n, acc)
}

fn one_minute(c: &mut Criterion) {
    let mut g = c.benchmark_group("walking");
    g.sample_size(10);
    g.bench_function("1 min, 4 IMUs @ 1 kHz (60k records)", |b| {
        b.iter(|| {
            let sim = WalkingSimulator::new(black_box(config(60.0))).unwrap();
            black_box(drain(sim))
        })
    });
    g.finish();
}

fn one_hour_once() {
    let t0 = Instant::now();
    let sim = WalkingSimulator::new(config(3600.0)).unwrap();
    let (n, sum) = drain(sim);
    let dt = t0.elapsed().as_secs_f64();
    println!(
        "walking: one simulated hour, {n} records (4 IMUs + 3 encoders @ 1 kHz) in {dt:.2} s ({:.0} ns/record) [checksum {sum:.3}]",
        1e9 * dt / n as f64
    );
}

criterion_group!(benches, one_minute);

fn main() {
    one_hour_once();
    benches();
    criterion::Criterion::default()
        .configure_from_args()
        .final_summary();
}
