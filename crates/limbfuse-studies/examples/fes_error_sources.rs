//! knee-FES on limbfuse's own simulator: which sensor error or plant
//! feature makes the model-based filters of paper 004 carry a mean error
//! (docs/RESULTS.md, "knee-FES: our simulator vs the model-based filters").
//!
//! 6 legs x 4 seeds (960-983, a different seed per trial), 30 s `simulate knee-fes` trials as the CLI
//! writes them (activation dynamics on, shank IMU 0.2 m below the knee,
//! consumer-MEMS errors of `ImuSpec::default()`); one error source is
//! switched off at a time (the IMUs draw the same random numbers whatever
//! is switched off, so every row has the same bias, misalignment and noise
//! draws as the first), then each source alone, then the independent
//! simulator's error figures (its `# noise` header). Knee RMSE and mean
//! error (estimate minus reference) after 1 s; per variant the mean and
//! median RMSE and the mean of the absolute mean error over the 24 trials, for
//!
//! * `rmx` (Mahony on thigh and shank, default gains);
//! * `sdre` / `ekf` of the thesis (what `limbfuse estimate` runs on the
//!   trial's own metadata: `a_ke = u_ke`, `h = [x2, g sin x1]`);
//! * `sdre` / `ekf` of the thesis plus gyro and accelerometer bias states
//!   (`[states] gyro_bias = true, acc_bias = true`, lever arm 0);
//! * `sdre` / `ekf` with the plant as stated (what a parameter file with
//!   `[model] t_a` and no `[states]` runs: activation, gyro and
//!   accelerometer bias states, lever arm 0.2 m).
//!
//! `cargo run --release -p limbfuse-studies --example fes_error_sources`.

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{
    ExtendedKneeFilter, KneeFesFilter, Linearisation, RotationMatrixKnee,
};
use limbfuse_models::{
    ExtendedKneeModel, KneeFesModel, KneeFesParams, KneeStateOptions, KneeSubject,
};
use limbfuse_sim::config::{ImuSpec, TriadSpec};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_studies::example_args::NoArgs;
use rayon::prelude::*;

/// Trials per leg; leg `l` (Table-2 order, 0-5) gets seeds
/// `960 + 4 l ... 960 + 4 l + 3`, so that the 24 trials have 24 different
/// sensor draws (the IMU errors depend on the seed alone).
const TRIALS_PER_LEG: u64 = 4;
const NAMES: [&str; 7] = [
    "rmx",
    "sdre",
    "ekf",
    "sdre+bias",
    "ekf+bias",
    "sdre+plant",
    "ekf+plant",
];

/// Knee (RMSE, mean error) in deg after t = 1 s; NaN when the filter errs.
fn knee_error(e: &mut dyn Estimator, recs: &[Record]) -> (f64, f64) {
    let (mut s2, mut s1, mut n) = (0.0, 0.0, 0usize);
    for r in recs {
        let Ok(est) = e.step(&r.sample) else {
            return (f64::NAN, f64::NAN);
        };
        if r.sample.t < 1.0 {
            continue;
        }
        if let (Some(a), Some(b)) = (est.joint[1], r.reference.joint[1]) {
            s2 += (a - b) * (a - b);
            s1 += a - b;
            n += 1;
        }
    }
    let n = n.max(1) as f64;
    ((s2 / n).sqrt().to_degrees(), (s1 / n).to_degrees())
}

fn filters(m: KneeFesModel, r: f64) -> Vec<Box<dyn Estimator>> {
    let plant = KneeStateOptions {
        activation: true,
        disturbance: false,
        gyro_bias: true,
        acc_bias: true,
    };
    let ext = |lin| -> Box<dyn Estimator> {
        Box::new(ExtendedKneeFilter::with_default_tuning(
            ExtendedKneeModel::<5>::new(m, plant, r).expect("five states"),
            lin,
        ))
    };
    let biases = KneeStateOptions {
        activation: false,
        ..plant
    };
    let bias = |lin| -> Box<dyn Estimator> {
        Box::new(ExtendedKneeFilter::with_default_tuning(
            ExtendedKneeModel::<4>::new(m, biases, 0.0).expect("four states"),
            lin,
        ))
    };
    vec![
        Box::new(RotationMatrixKnee::new()),
        Box::new(KneeFesFilter::sdre(m)),
        Box::new(KneeFesFilter::ekf(m)),
        bias(Linearisation::Sdc),
        bias(Linearisation::Jacobian),
        ext(Linearisation::Sdc),
        ext(Linearisation::Jacobian),
    ]
}

/// A triad spec with every error zero.
const NO_ERRORS: TriadSpec = TriadSpec {
    noise_density: 0.0,
    turn_on_bias: 0.0,
    bias_instability: 0.0,
    bias_tau_s: 200.0,
    scale_error: 0.0,
    cross_axis: 0.0,
};

type Edit = fn(&mut KneeFesConfig);
/// One run: variant index, leg, seed, (RMSE, mean error) per filter.
type Run = (usize, KneeSubject, u64, Vec<(f64, f64)>);

/// The sensor error sources of `ImuSpec`, switched one at a time.
#[derive(Clone, Copy)]
enum Source {
    Misalignment,
    GyroBias,
    AccBias,
    Scale,
    CrossAxis,
    White,
}

impl Source {
    /// Copies this source's figures from `from` into `to`.
    fn copy(self, to: &mut ImuSpec, from: &ImuSpec) {
        let triad = |t: &mut TriadSpec, f: &TriadSpec, gyro: bool| match self {
            Source::Misalignment => {}
            Source::GyroBias | Source::AccBias => {
                if gyro == matches!(self, Source::GyroBias) {
                    t.turn_on_bias = f.turn_on_bias;
                    t.bias_instability = f.bias_instability;
                }
            }
            Source::Scale => t.scale_error = f.scale_error,
            Source::CrossAxis => t.cross_axis = f.cross_axis,
            Source::White => t.noise_density = f.noise_density,
        };
        triad(&mut to.gyro, &from.gyro, true);
        triad(&mut to.acc, &from.acc, false);
        if let Source::Misalignment = self {
            to.misalignment_rad = from.misalignment_rad;
        }
    }
}

/// Every sensor error zero.
const IDEAL: ImuSpec = ImuSpec {
    gyro: NO_ERRORS,
    acc: NO_ERRORS,
    misalignment_rad: 0.0,
};

/// `sources` switched off, the rest as `ImuSpec::default()`.
fn without(c: &mut KneeFesConfig, sources: &[Source]) {
    for s in sources {
        s.copy(&mut c.imu, &IDEAL);
    }
}

/// Only white noise and `sources`, at `ImuSpec::default()`'s figures.
fn only(c: &mut KneeFesConfig, sources: &[Source]) {
    c.imu = IDEAL;
    for s in [Source::White].iter().chain(sources) {
        s.copy(&mut c.imu, &ImuSpec::default());
    }
}

fn imu_at_knee(c: &mut KneeFesConfig) {
    c.shank_imu_m = 0.0;
}
fn no_activation(c: &mut KneeFesConfig) {
    c.activation_dynamics = false;
}
/// The plant the thesis filters assume: `a_ke = u_ke`, accelerometer at
/// the knee (`h = [x2, g sin x1]`).
fn thesis_plant(c: &mut KneeFesConfig) {
    imu_at_knee(c);
    no_activation(c);
}
/// The independent simulator's `# noise` header: white 0.005 rad/s and
/// 0.03 m/s^2 per sample, constant biases of 0.005 rad/s and 0.05 m/s^2
/// (1 sigma, per axis), no misalignment, scale or cross-axis error; at
/// 100 Hz a white sigma per sample is `density * sqrt(50)`.
fn independent_figures(c: &mut KneeFesConfig) {
    c.imu = IDEAL;
    let per_sample = (c.rate_hz / 2.0).sqrt();
    c.imu.gyro.noise_density = 0.005 / per_sample;
    c.imu.acc.noise_density = 0.03 / per_sample;
    c.imu.gyro.turn_on_bias = 0.005;
    c.imu.acc.turn_on_bias = 0.05;
}

fn main() {
    let _ = NoArgs::parse();
    use Source::*;
    let rows: [(&str, Edit); 23] = [
        ("as the CLI writes it", |_| {}),
        ("no mounting misalignment", |c| without(c, &[Misalignment])),
        ("no gyro bias", |c| without(c, &[GyroBias])),
        ("no accelerometer bias", |c| without(c, &[AccBias])),
        ("no scale-factor errors", |c| without(c, &[Scale])),
        ("no cross-axis errors", |c| without(c, &[CrossAxis])),
        ("no white noise", |c| without(c, &[White])),
        ("shank IMU at the knee (r = 0)", imu_at_knee),
        ("no activation dynamics", no_activation),
        ("white noise only", |c| only(c, &[])),
        ("white + accelerometer bias", |c| only(c, &[AccBias])),
        ("white + gyro bias", |c| only(c, &[GyroBias])),
        ("white + misalignment", |c| only(c, &[Misalignment])),
        ("white + scale and cross-axis", |c| {
            only(c, &[Scale, CrossAxis])
        }),
        ("independent simulator's figures", independent_figures),
        ("thesis plant: ideal", |c| {
            thesis_plant(c);
            c.imu = IDEAL;
        }),
        ("thesis plant: white noise only", |c| {
            thesis_plant(c);
            only(c, &[]);
        }),
        ("thesis plant: white + acc bias", |c| {
            thesis_plant(c);
            only(c, &[AccBias]);
        }),
        ("thesis plant: white + gyro bias", |c| {
            thesis_plant(c);
            only(c, &[GyroBias]);
        }),
        ("thesis plant: white + misalignment", |c| {
            thesis_plant(c);
            only(c, &[Misalignment]);
        }),
        ("thesis plant: white + scale, cross", |c| {
            thesis_plant(c);
            only(c, &[Scale, CrossAxis]);
        }),
        ("thesis plant: every sensor error", thesis_plant),
        ("thesis plant: independent figures", |c| {
            thesis_plant(c);
            independent_figures(c);
        }),
    ];
    let cases: Vec<(usize, KneeSubject, u64)> = (0..rows.len())
        .flat_map(|v| {
            KneeSubject::ALL.iter().flat_map(move |s| {
                (0..TRIALS_PER_LEG).map(move |k| (v, *s, 960 + 4 * s.index() as u64 + k))
            })
        })
        .collect();
    let results: Vec<Run> = cases
        .into_par_iter()
        .map(|(v, subject, seed)| {
            let mut cfg = KneeFesConfig {
                subject,
                seed,
                ..KneeFesConfig::default()
            };
            (rows[v].1)(&mut cfg);
            let recs = simulate_knee_fes(&cfg).expect("trial").records;
            let m = KneeFesModel::new(KneeFesParams::subject(subject)).expect("preset");
            let errs = filters(m, 0.2)
                .iter_mut()
                .map(|f| knee_error(f.as_mut(), &recs))
                .collect();
            (v, subject, seed, errs)
        })
        .collect();
    println!(
        "knee RMSE / mean error after 1 s (deg), mean of 6 legs x {TRIALS_PER_LEG} seeds (960-983), limbfuse simulate knee-fes"
    );
    println!("per filter: mean RMSE, median RMSE, mean |mean error| over the trials");
    print!("{:<34}", "variant");
    for n in NAMES {
        print!(" {n:>20}");
    }
    println!();
    for (v, (label, _)) in rows.iter().enumerate() {
        print!("{label:<34}");
        let sel: Vec<&Vec<(f64, f64)>> =
            results.iter().filter(|r| r.0 == v).map(|r| &r.3).collect();
        let n = sel.len() as f64;
        for j in 0..NAMES.len() {
            let rmse = sel.iter().map(|e| e[j].0).sum::<f64>() / n;
            let bias = sel.iter().map(|e| e[j].1.abs()).sum::<f64>() / n;
            let mut r: Vec<f64> = sel.iter().map(|e| e[j].0).collect();
            r.sort_by(f64::total_cmp);
            let median = 0.5 * (r[(r.len() - 1) / 2] + r[r.len() / 2]);
            print!(" {rmse:>6.3} {median:>6.3} {bias:>6.3}");
        }
        let over: Vec<String> = (0..NAMES.len())
            .map(|j| {
                sel.iter()
                    .filter(|e| e[j].0.is_nan() || e[j].0 > 5.0)
                    .count()
                    .to_string()
            })
            .collect();
        println!("  (> 5 deg: {})", over.join("/"));
    }
    println!("\nper trial, as the CLI writes it");
    for (_, s, seed, e) in results.iter().filter(|r| r.0 == 0) {
        print!("{:<34}", format!("{} seed {seed}", s.label()));
        for x in e {
            print!(" {:>8.3} / {:>+6.3}", x.0, x.1);
        }
        println!();
    }
    println!("\nper leg, as the CLI writes it (mean of the seeds)");
    for s in KneeSubject::ALL {
        print!("{:<34}", s.label());
        let sel: Vec<&Vec<(f64, f64)>> = results
            .iter()
            .filter(|r| r.0 == 0 && r.1 == s)
            .map(|r| &r.3)
            .collect();
        for j in 0..NAMES.len() {
            let n = sel.len() as f64;
            let rmse = sel.iter().map(|e| e[j].0).sum::<f64>() / n;
            let bias = sel.iter().map(|e| e[j].1).sum::<f64>() / n;
            print!(" {:>8.3} / {:>+6.3}", rmse, bias);
        }
        println!();
    }
}
