//! Per-sample cost of `gait-events` (both feet; both shanks) and `lowback-speed` on a
//! seeded simulated walk (60 s at 100 Hz, the right foot's IMU also fed as
//! the left one), one core. Two groups: wall time, and the thread's CPU
//! time (`..._cpu`), which time-slicing on a shared machine does not inflate.
//! `cargo bench -p limbfuse-estimators --bench gait_events`

use std::hint::black_box;

use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_estimators::gait_events::{FootSource, GaitEvents, GaitEventsParams};
use limbfuse_estimators::lowback_speed::{LowbackParams, LowbackSpeed};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

// One measurement for every crate's benches (it lives with limbfuse-io's).
#[path = "../../limbfuse-io/benches/support/cpu_time.rs"]
mod cpu_time;
use cpu_time::ThreadCpuTime;

fn bench_wall(c: &mut Criterion) {
    bench(c, "gait_events_60s_100hz");
}

fn bench_cpu(c: &mut Criterion<ThreadCpuTime>) {
    bench(c, "gait_events_60s_100hz_cpu");
}

fn bench<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let cfg = WalkingConfig {
        duration_s: 60.0,
        seed: 42,
        ..WalkingConfig::default()
    };
    let foot = Segment::Foot.index();
    let records: Vec<Record> = WalkingSimulator::new(cfg)
        .unwrap()
        .map(|mut r| {
            r.sample.other_leg_imu[foot] = r.sample.imu[foot];
            r
        })
        .collect();
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(records.len() as u64));
    g.bench_function("two_feet", |b| {
        b.iter(|| {
            let mut e = GaitEvents::new(
                GaitEventsParams::default(),
                [Some(FootSource::OtherLeg), Some(FootSource::OwnLeg)],
            )
            .unwrap();
            let mut acc = 0.0;
            for r in &records {
                acc += e.step(&r.sample).unwrap().speed.unwrap_or(0.0);
            }
            black_box(acc)
        })
    });
    // Issue 19 item 3: both legs from shank IMUs (events only).
    let shank = Segment::Shank.index();
    let shank_records: Vec<Record> = records
        .iter()
        .map(|r| {
            let mut r = *r;
            r.sample.other_leg_imu[shank] = r.sample.imu[shank];
            r
        })
        .collect();
    g.bench_function("two_shanks", |b| {
        b.iter(|| {
            let mut e = GaitEvents::new(
                GaitEventsParams::default(),
                [Some(FootSource::OtherShank), Some(FootSource::OwnShank)],
            )
            .unwrap();
            let mut n = 0usize;
            for r in &shank_records {
                n += usize::from(e.step(&r.sample).unwrap().contact[1].is_some());
            }
            black_box(n)
        })
    });
    g.bench_function("lowback_speed", |b| {
        b.iter(|| {
            let mut e = LowbackSpeed::new(LowbackParams::default());
            let mut acc = 0.0;
            for r in &records {
                acc += e.step(&r.sample).unwrap().speed.unwrap_or(0.0);
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
