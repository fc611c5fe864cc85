//! Per-sample cost of the paper 004 estimators on seeded simulated trials
//! (100 Hz, default sensors, default tuning), one core: `sdre`/`ekf` on the
//! 2-state knee model and the 4-state fixed-hip model, and `rmx`; issue 16:
//! the extended knee model (activation + gyro/acc bias states + lever arm,
//! 5 states; every state, 6) and `knee-kinematic` (5 states), default
//! physics tuning; the fixed hip with its four activation states (8).
//! Two groups: `fes_100hz` (wall time) and `fes_100hz_cpu`
//! (the benchmark thread's CPU time, `limbfuse-io/benches/support/cpu_time.rs`:
//! the figure to quote on a loaded machine).

use std::hint::black_box;

use criterion::measurement::Measurement;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{
    ExtendedKneeFilter, FixedHipActivationFilter, FixedHipFilter, KinematicKneeFilter,
    KneeFesFilter, Linearisation, RotationMatrixKnee,
};
use limbfuse_models::{
    ExtendedKneeModel, FixedHipActivationModel, FixedHipModel, FixedHipParams, KinematicKneeModel,
    KneeFesModel, KneeFesParams, KneeStateOptions, KneeSubject,
};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};

#[path = "../../limbfuse-io/benches/support/cpu_time.rs"]
mod cpu_time;
use cpu_time::ThreadCpuTime;

fn run<Ms: Measurement>(
    g: &mut criterion::BenchmarkGroup<'_, Ms>,
    name: &str,
    recs: &[Record],
    make: &dyn Fn() -> Box<dyn Estimator>,
) {
    g.throughput(Throughput::Elements(recs.len() as u64));
    g.bench_function(name, |b| {
        b.iter(|| {
            let mut e = make();
            let mut acc = 0.0;
            for r in recs {
                acc += e.step(&r.sample).expect("valid sample").joint[1].unwrap_or(0.0);
            }
            black_box(acc)
        })
    });
}

fn bench_wall(c: &mut Criterion) {
    bench(c, "fes_100hz");
}

fn bench_cpu(c: &mut Criterion<ThreadCpuTime>) {
    bench(c, "fes_100hz_cpu");
}

fn bench<Ms: Measurement>(c: &mut Criterion<Ms>, group: &str) {
    let knee = simulate_knee_fes(&KneeFesConfig {
        seed: 42,
        ..KneeFesConfig::default()
    })
    .expect("valid config")
    .records;
    let hip = simulate_fixed_hip(&FixedHipConfig {
        seed: 42,
        ..FixedHipConfig::default()
    })
    .expect("valid config")
    .records;
    let km = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).expect("preset");
    let hm = FixedHipModel::new(FixedHipParams::default()).expect("defaults");
    let mut g = c.benchmark_group(group);
    g.sample_size(20);
    run(&mut g, "sdre-knee-2state", &knee, &|| {
        Box::new(KneeFesFilter::sdre(km))
    });
    run(&mut g, "ekf-knee-2state", &knee, &|| {
        Box::new(KneeFesFilter::ekf(km))
    });
    run(&mut g, "rmx-knee", &knee, &|| {
        Box::new(RotationMatrixKnee::new())
    });
    run(&mut g, "sdre-fixed-hip-4state", &hip, &|| {
        Box::new(FixedHipFilter::sdre(hm))
    });
    run(&mut g, "ekf-fixed-hip-4state", &hip, &|| {
        Box::new(FixedHipFilter::ekf(hm))
    });
    // Issue 16: the fixed hip with its four activation states (8 states),
    // on a trial whose plant has activation dynamics (T_a = 0.25 s).
    let hip_act = simulate_fixed_hip(&FixedHipConfig {
        seed: 42,
        activation_t_a: Some(0.25),
        ..FixedHipConfig::default()
    })
    .expect("valid config")
    .records;
    let ha = FixedHipActivationModel::new(hm, 0.25).expect("T_a > 0");
    run(&mut g, "sdre-fixed-hip-act-8state", &hip_act, &|| {
        Box::new(FixedHipActivationFilter::with_default_tuning(
            ha,
            Linearisation::Sdc,
        ))
    });
    run(&mut g, "ekf-fixed-hip-act-8state", &hip_act, &|| {
        Box::new(FixedHipActivationFilter::with_default_tuning(
            ha,
            Linearisation::Jacobian,
        ))
    });
    let bias = KneeStateOptions {
        activation: true,
        disturbance: false,
        gyro_bias: true,
        acc_bias: true,
    };
    let all = KneeStateOptions {
        disturbance: true,
        ..bias
    };
    let m5 = ExtendedKneeModel::<5>::new(km, bias, 0.2).expect("5 states");
    let m6 = ExtendedKneeModel::<6>::new(km, all, 0.2).expect("6 states");
    run(&mut g, "sdre-knee-act-bias-5state", &knee, &|| {
        Box::new(ExtendedKneeFilter::with_default_tuning(
            m5,
            Linearisation::Sdc,
        ))
    });
    run(&mut g, "ekf-knee-act-bias-5state", &knee, &|| {
        Box::new(ExtendedKneeFilter::with_default_tuning(
            m5,
            Linearisation::Jacobian,
        ))
    });
    run(&mut g, "sdre-knee-all-6state", &knee, &|| {
        Box::new(ExtendedKneeFilter::with_default_tuning(
            m6,
            Linearisation::Sdc,
        ))
    });
    run(&mut g, "ekf-knee-all-6state", &knee, &|| {
        Box::new(ExtendedKneeFilter::with_default_tuning(
            m6,
            Linearisation::Jacobian,
        ))
    });
    run(&mut g, "knee-kinematic-5state", &knee, &|| {
        Box::new(KinematicKneeFilter::kinematic(
            KinematicKneeModel::new(9.81, 0.2).expect("g"),
            core::f64::consts::FRAC_PI_2,
        ))
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
