//! Per-sample cost of `imm-bslip` with 18 filters (the 0.4-0.9 m/s library
//! minus nothing: 6 gaits x 3 phases) on a seeded 0.7 m/s B-SLIP trial
//! (60 s at 100 Hz, full CoM channels), one core; the `continuous`
//! configuration (issue 19: 3 filters of one family gait re-targeted at
//! every mid-stance, feet and phase from the data) over the same library
//! with the walker's 0.7 m/s gait held out; and the library build.
//! `cargo bench -p limbfuse-estimators --bench imm_bslip`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::Estimator;
use limbfuse_estimators::imm_bslip::{
    ImmBslip, ImmBslipParams, ImmContinuous, ImmWeights, SwayRestart,
};
use limbfuse_models::bslip::BslipParams;
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_sim::bslip::trial::{simulate_trial, BslipTrialConfig};

fn bench(c: &mut Criterion) {
    let body = BslipParams::default();
    let speeds = [0.4, 0.5, 0.6, 0.7, 0.8, 0.9];
    let lib = build_library(&body, &speeds, &SearchSettings::default(), |_, _| {}).unwrap();
    let templates: Vec<_> = lib.iter().map(|g| g.template(&body)).collect();
    let records = simulate_trial(
        &templates[3],
        &BslipTrialConfig {
            duration: 60.0,
            seed: 42,
            ..Default::default()
        },
    );
    let mut g = c.benchmark_group("imm_bslip_60s_100hz");
    g.throughput(Throughput::Elements(records.len() as u64));
    g.sample_size(10);
    g.bench_function("18_filters", |b| {
        b.iter(|| {
            let mut e = ImmBslip::new(&templates, ImmBslipParams::full_com()).unwrap();
            let mut acc = 0.0;
            for r in &records {
                acc += e.step(&r.sample).unwrap().speed.unwrap_or(0.0);
            }
            black_box(acc)
        })
    });
    let held_out: Vec<_> = templates
        .iter()
        .filter(|t| (t.speed - 0.7).abs() > 1e-9)
        .copied()
        .collect();
    let continuous = ImmBslipParams {
        weights: ImmWeights::Recursive,
        ..ImmBslipParams::full_com()
    };
    g.bench_function("continuous", |b| {
        b.iter(|| {
            let mut e = ImmContinuous::new(&held_out, continuous).unwrap();
            let mut acc = 0.0;
            for r in &records {
                acc += e.step(&r.sample).unwrap().speed.unwrap_or(0.0);
            }
            black_box(acc)
        })
    });
    // As the CLI builds it: restarted at the first sway extremum after the
    // start (the fit runs on every sample until then) and after gaps.
    g.bench_function("continuous_sway_restart", |b| {
        b.iter(|| {
            let mut e = SwayRestart::new(ImmContinuous::new(&held_out, continuous).unwrap());
            let mut acc = 0.0;
            for r in &records {
                acc += e.step(&r.sample).unwrap().speed.unwrap_or(0.0);
            }
            black_box(acc)
        })
    });
    g.finish();
    let mut g = c.benchmark_group("gait_library_build");
    g.sample_size(10);
    g.bench_function("0.4-0.9_step_0.1", |b| {
        b.iter(|| {
            black_box(build_library(&body, &speeds, &SearchSettings::default(), |_, _| {}).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
