//! Paper 004 single-joint study (a) under the thesis's own noise protocol
//! (section 4.1.1): `S` is not tuned but "calculated by taking the sample
//! standard deviation of the filtered IMU measurement data in the
//! initialization stage when the IMUs were stationary" (here: the variance
//! of each measurement row over the trial's rest period, per trial), and
//! only `Q = diag(n1, n2)` is tuned, per estimator, on the pre-trials.
//! The fixed hip (study b) has no rest period; there `S` is the variance a
//! stationary recording of the simulated IMUs has, `noise_density^2 fs / 2`
//! per row; it runs with the simulator's accelerometers and with
//! gravity-only ones, as in the thesis's simulation.
//! `cargo run --release -p limbfuse-studies --example fes_thesis_protocol`.

use clap::Parser;
use limbfuse_core::Record;
use limbfuse_estimators::fes::{
    ContinuousTuning, FesFilter, FixedHipPlant, KneePlant, Linearisation, Plant, RotationMatrixKnee,
};
use limbfuse_eval::stats::{shapiro_wilk, wilcoxon_signed_rank};
use limbfuse_models::{FixedHipModel, KneeFesModel, KneeFesParams, KneeSubject};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_studies::fes_study::{
    joint_rmse, knee_pre_trials, stability_gain, tune_rmx, PRE_TRIAL_SEEDS,
};
use nalgebra::{Vector2, Vector4};
use rayon::prelude::*;

/// Angle-row process noise of the grid.
const ANGLE_Q: [f64; 7] = [1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 1.0];
/// Rate-row process noise of the grid.
const RATE_Q: [f64; 17] = [
    1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 0.01, 0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5,
    1e6,
];

/// Every `(n1, n2)` of the process-noise grid.
fn q_grid() -> Vec<(f64, f64)> {
    ANGLE_Q
        .iter()
        .flat_map(|&n1| RATE_Q.iter().map(move |&n2| (n1, n2)))
        .collect()
}

/// Sample variance of each measurement row over `t < rest_s - 0.1`.
fn rest_variance(plant: &KneePlant, recs: &[Record], rest_s: f64) -> Vector2<f64> {
    let t0 = recs.first().map_or(0.0, |r| r.sample.t);
    let rows: Vec<[f64; 2]> = recs
        .iter()
        .take_while(|r| r.sample.t - t0 < rest_s - 0.1)
        .filter_map(|r| match plant.measurement(&r.sample) {
            [Some(a), Some(b)] => Some([a, b]),
            _ => None,
        })
        .collect();
    let n = rows.len() as f64;
    let mut v = Vector2::zeros();
    for k in 0..2 {
        let mean = rows.iter().map(|r| r[k]).sum::<f64>() / n;
        v[k] = rows.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (n - 1.0);
    }
    v
}

fn filter(
    model: KneeFesModel,
    lin: Linearisation,
    s: Vector2<f64>,
    q: (f64, f64),
) -> FesFilter<KneePlant, 2, 2, 1> {
    FesFilter::new(
        KneePlant::new(model),
        lin,
        ContinuousTuning {
            q: Vector2::new(q.0, q.1),
            s,
            a: stability_gain(lin),
            p0: Vector2::new(1e-2, 1e-2),
            max_substep: 2e-3,
            a_states: None,
        },
    )
}

/// Study (b) under the thesis protocol: 10 seeds, mean hip / knee RMSE (deg).
fn fixed_hip() {
    let base = FixedHipConfig::default();
    let model = FixedHipModel::new(base.params).unwrap();
    let white = |d: f64| d * d * base.rate_hz / 2.0;
    let (g, a) = (
        white(base.imu.gyro.noise_density),
        white(base.imu.acc.noise_density),
    );
    let s = Vector4::new(g, g, a, a);
    println!("fixed hip: S = {s:?}");
    // The thesis's simulation (section 4.2.1): "only gravitational
    // acceleration is considered because motion acceleration is
    // negligible". `gravity_only` replaces each accelerometer's x by
    // `g sin(theta)` plus the sensor's own errors (the noisy minus the ideal
    // reading of the same motion).
    let trials = |seeds: &[u64], gravity_only: bool| -> Vec<Vec<Record>> {
        seeds
            .iter()
            .map(|seed| {
                let cfg = FixedHipConfig {
                    seed: *seed,
                    ..base
                };
                let mut recs = simulate_fixed_hip(&cfg).unwrap().records;
                if gravity_only {
                    let ideal = simulate_fixed_hip(&FixedHipConfig {
                        noise: false,
                        ..cfg
                    })
                    .unwrap()
                    .records;
                    for (r, c) in recs.iter_mut().zip(&ideal) {
                        for seg in [1, 2] {
                            let theta = c.reference.segment[seg].unwrap();
                            if let (Some(a), Some(ac)) =
                                (r.sample.imu[seg].acc.as_mut(), c.sample.imu[seg].acc)
                            {
                                a.x += base.params.g * theta.sin() - ac.x;
                            }
                        }
                    }
                }
                recs
            })
            .collect()
    };
    let make = |lin: Linearisation, q: (f64, f64)| {
        FesFilter::new(
            FixedHipPlant { model },
            lin,
            ContinuousTuning {
                q: Vector4::new(q.0, q.0, q.1, q.1),
                s,
                a: stability_gain(lin),
                p0: Vector4::repeat(1e-2),
                max_substep: 2e-3,
                a_states: None,
            },
        )
    };
    let mean_rmse = |lin: Linearisation, q: (f64, f64), recs: &[Vec<Record>]| -> [f64; 2] {
        let mut m = [0.0; 2];
        for r in recs {
            let e = joint_rmse(&mut make(lin, q), r, &[0, 1]);
            m[0] += e[0].to_degrees() / recs.len() as f64;
            m[1] += e[1].to_degrees() / recs.len() as f64;
        }
        m
    };
    for gravity_only in [false, true] {
        let pre = trials(&PRE_TRIAL_SEEDS, gravity_only);
        let study = trials(&(1..=10).collect::<Vec<_>>(), gravity_only);
        for lin in [Linearisation::Sdc, Linearisation::Jacobian] {
            let (q, _) = q_grid()
                .into_par_iter()
                .map(|q| {
                    let m = mean_rmse(lin, q, &pre);
                    (q, m[0] + m[1])
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            let m = mean_rmse(lin, q, &study);
            println!(
                "fixed hip {lin:?} (gravity-only accelerometers: {gravity_only}): tuned Q {q:?}, hip / knee {:.3} / {:.3} deg",
                m[0], m[1]
            );
        }
    }
}

fn main() {
    limbfuse_studies::example_args::NoArgs::parse();
    fixed_hip();
    let base = KneeFesConfig::default();
    let pre = knee_pre_trials(&base);
    let pre_model = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    let plant = KneePlant::new(pre_model);
    let pre_s: Vec<Vector2<f64>> = pre
        .iter()
        .map(|p| rest_variance(&plant, p, base.rest_s))
        .collect();
    println!("measured S on the pre-trials: {pre_s:?}");
    let tune = |lin: Linearisation| {
        q_grid()
            .into_par_iter()
            .map(|q| {
                let m = pre
                    .iter()
                    .zip(&pre_s)
                    .map(|(p, s)| joint_rmse(&mut filter(pre_model, lin, *s, q), p, &[1])[0])
                    .sum::<f64>()
                    / pre.len() as f64;
                (q, m)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap()
    };
    let (q_sdre, m_sdre) = tune(Linearisation::Sdc);
    let (q_ekf, m_ekf) = tune(Linearisation::Jacobian);
    let (gains, _) = tune_rmx(&pre);
    println!(
        "tuned Q: sdre {q_sdre:?} (pre-trial {:.3} deg), ekf {q_ekf:?} ({:.3} deg)",
        m_sdre.to_degrees(),
        m_ekf.to_degrees()
    );
    let cases: Vec<(KneeSubject, u64)> = KneeSubject::ALL
        .iter()
        .flat_map(|s| (1..=3).map(move |k| (*s, k)))
        .collect();
    let rows: Vec<(KneeSubject, u64, [f64; 3])> = cases
        .into_par_iter()
        .map(|(subject, trial)| {
            let cfg = KneeFesConfig {
                subject,
                seed: 10 * (subject.index() as u64 + 1) + trial,
                ..base
            };
            let recs = simulate_knee_fes(&cfg).unwrap().records;
            let model = KneeFesModel::new(KneeFesParams::subject(subject)).unwrap();
            let s = rest_variance(&KneePlant::new(model), &recs, base.rest_s);
            let mut sd = filter(model, Linearisation::Sdc, s, q_sdre);
            let mut ek = filter(model, Linearisation::Jacobian, s, q_ekf);
            let mut rm = RotationMatrixKnee::with_gains(gains);
            (
                subject,
                trial,
                [
                    joint_rmse(&mut sd, &recs, &[1])[0].to_degrees(),
                    joint_rmse(&mut ek, &recs, &[1])[0].to_degrees(),
                    joint_rmse(&mut rm, &recs, &[1])[0].to_degrees(),
                ],
            )
        })
        .collect();
    println!("| leg | trial | SDRE | EKF | RMX |\n|---|---|---|---|---|");
    for (s, t, r) in &rows {
        println!(
            "| {} | {t} | {:.2} | {:.2} | {:.2} |",
            s.label(),
            r[0],
            r[1],
            r[2]
        );
    }
    let col = |k: usize| rows.iter().map(|r| r.2[k]).collect::<Vec<_>>();
    let (a, b, c) = (col(0), col(1), col(2));
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    println!(
        "| **mean** | | **{:.2}** | **{:.2}** | **{:.2}** |",
        mean(&a),
        mean(&b),
        mean(&c)
    );
    println!(
        "Shapiro-Wilk sdre {:?} ekf {:?} rmx {:?}",
        shapiro_wilk(&a),
        shapiro_wilk(&b),
        shapiro_wilk(&c)
    );
    println!(
        "Wilcoxon sdre-ekf {:?}, sdre-rmx {:?}",
        wilcoxon_signed_rank(&a, &b),
        wilcoxon_signed_rank(&a, &c)
    );
}
