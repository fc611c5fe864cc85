//! Issue 16 item 4 (a)-(c): does the knee model earn its place? On
//! limbfuse's knee-FES simulator with muscle activation dynamics in the
//! plant (Table 1's `T_a`), shank IMU 0.2 m below the knee, consumer-MEMS
//! sensor errors: 6 legs x 3 trials (seeds `10 (leg + 1) + trial`, those of
//! study (a)), knee RMSE after the first second, every filter with its
//! default tuning (no tuning on these trials):
//!
//! * `rmx`, `knee-kinematic` (model-free, gyro/acc bias states, lever arm);
//! * `sdre` / `ekf` of the thesis (no activation, `a_ke = u_ke`);
//! * `sdre` / `ekf` with the activation state only ((b) inverted: the
//!   estimator gets the plant's activation dynamics);
//! * `ekf` with activation + biases + lever arm, and with every state
//!   (+ unknown torque), and `sdre` with every state and with activation
//!   + biases + lever arm.
//!
//! (c): every model parameter of the estimator perturbed by a uniform
//! factor in `1 +- e` (e = 10 %, 30 %; 24 seeded draws each, leg = draw mod
//! 6), the plant exact. A run diverges when the filter restarts, the knee is
//! non-finite or its RMSE exceeds 20 deg.
//!
//! Paired statistics: Wilcoxon signed-rank against `rmx`, Shapiro-Wilk of
//! each column. `cargo run --release -p limbfuse-studies --example fes_model_study`.

use clap::Parser;
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{
    ExtendedKneeFilter, KinematicKneeFilter, KneeFesFilter, Linearisation, RotationMatrixKnee,
};
use limbfuse_eval::stats::{shapiro_wilk, wilcoxon_signed_rank};
use limbfuse_models::{
    ExtendedKneeModel, KinematicKneeModel, KneeFesModel, KneeFesParams, KneeStateOptions,
    KneeSubject,
};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_studies::example_args::NoArgs;
use limbfuse_studies::fes_pulse_cv::perturbed;
use rayon::prelude::*;

const R: f64 = 0.2;
const NAMES: [&str; 11] = [
    "rmx",
    "knee-kinematic",
    "sdre",
    "ekf",
    "sdre+act",
    "ekf+act",
    "ekf+act+r",
    "ekf+act+bias+r",
    "ekf+all+r",
    "sdre+all+r",
    "sdre+act+bias+r",
];

/// Knee RMSE (deg) after t = 1 s; infinity on a restart, an error or a
/// non-finite or > 20 deg result (divergence).
fn rmse(e: &mut dyn Estimator, recs: &[Record]) -> f64 {
    let resets = e.diagnostic_names().iter().position(|n| *n == "resets");
    let (mut s, mut n) = (0.0, 0usize);
    for r in recs {
        let Ok(est) = e.step(&r.sample) else {
            return f64::INFINITY;
        };
        if resets.and_then(|c| est.diag[c]).is_some_and(|v| v > 0.0) {
            return f64::INFINITY;
        }
        if r.sample.t < 1.0 {
            continue;
        }
        if let (Some(a), Some(b)) = (est.joint[1], r.reference.joint[1]) {
            s += (a - b) * (a - b);
            n += 1;
        }
    }
    let v = (s / n.max(1) as f64).sqrt().to_degrees();
    if v.is_finite() && v <= 20.0 {
        v
    } else {
        f64::INFINITY
    }
}

fn opts(act: bool, dist: bool, bias: bool) -> KneeStateOptions {
    KneeStateOptions {
        activation: act,
        disturbance: dist,
        gyro_bias: bias,
        acc_bias: bias,
    }
}

fn ext<const N: usize>(
    m: KneeFesModel,
    o: KneeStateOptions,
    r: f64,
    lin: Linearisation,
) -> Box<dyn Estimator> {
    Box::new(ExtendedKneeFilter::with_default_tuning(
        ExtendedKneeModel::<N>::new(m, o, r).expect("options match N"),
        lin,
    ))
}

/// Every filter of [`NAMES`] with estimator model `m`.
fn filters(m: KneeFesModel) -> Vec<Box<dyn Estimator>> {
    use Linearisation::{Jacobian as J, Sdc as S};
    vec![
        Box::new(RotationMatrixKnee::new()),
        Box::new(KinematicKneeFilter::kinematic(
            KinematicKneeModel::new(9.81, R).expect("g"),
            core::f64::consts::FRAC_PI_2,
        )),
        Box::new(KneeFesFilter::sdre(m)),
        Box::new(KneeFesFilter::ekf(m)),
        ext::<3>(m, opts(true, false, false), 0.0, S),
        ext::<3>(m, opts(true, false, false), 0.0, J),
        ext::<3>(m, opts(true, false, false), R, J),
        ext::<5>(m, opts(true, false, true), R, J),
        ext::<6>(m, opts(true, true, true), R, J),
        ext::<6>(m, opts(true, true, true), R, S),
        ext::<5>(m, opts(true, false, true), R, S),
    ]
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn main() {
    let _ = NoArgs::parse();
    let base = KneeFesConfig::default();
    println!("knee RMSE after 1 s (deg), limbfuse knee-fes simulator, activation dynamics in the plant, shank IMU {R} m");
    let cases: Vec<(KneeSubject, u64)> = KneeSubject::ALL
        .iter()
        .flat_map(|s| (1..=3).map(move |k| (*s, k)))
        .collect();
    let rows: Vec<(KneeSubject, u64, Vec<f64>)> = cases
        .into_par_iter()
        .map(|(subject, trial)| {
            let cfg = KneeFesConfig {
                subject,
                seed: 10 * (subject.index() as u64 + 1) + trial,
                ..base
            };
            let recs = simulate_knee_fes(&cfg).expect("trial").records;
            let m = KneeFesModel::new(KneeFesParams::subject(subject)).expect("preset");
            let v = filters(m)
                .iter_mut()
                .map(|f| rmse(f.as_mut(), &recs))
                .collect();
            (subject, trial, v)
        })
        .collect();
    print!("{:<6} {:>2}", "leg", "k");
    for n in NAMES {
        print!(" {n:>14}");
    }
    println!();
    for (s, k, v) in &rows {
        print!("{:<6} {k:>2}", s.label());
        for x in v {
            print!(" {x:>14.3}");
        }
        println!();
    }
    let col = |j: usize| rows.iter().map(|r| r.2[j]).collect::<Vec<_>>();
    print!("{:<9}", "mean");
    for j in 0..NAMES.len() {
        print!(" {:>14.3}", mean(&col(j)));
    }
    println!();
    let rmx = col(0);
    let kin = col(1);
    for (j, n) in NAMES.iter().enumerate().skip(1) {
        let c = col(j);
        let sw = shapiro_wilk(&c).map_or("-".to_string(), |t| format!("{:.3}", t.p_value));
        let w = wilcoxon_signed_rank(&c, &rmx)
            .map_or("-".to_string(), |t| format!("{:.2e}", t.p_value));
        let wins = c.iter().zip(&rmx).filter(|(a, b)| a < b).count();
        println!(
            "{n:<16} mean {:.3} = {:.2} x rmx, {:.2} x knee-kinematic; below rmx in {wins}/18; Wilcoxon vs rmx p = {w}; Shapiro-Wilk p = {sw}",
            mean(&c),
            mean(&c) / mean(&rmx),
            mean(&c) / mean(&kin),
        );
    }

    println!("\n(c) estimator model parameters perturbed by U(1 - e, 1 + e), plant exact, 24 draws per e");
    let perturbed_names = [
        "rmx",
        "knee-kinematic",
        "ekf+act+bias+r",
        "ekf+all+r",
        "sdre+all+r",
        "sdre+act+bias+r",
    ];
    for e in [0.1, 0.3] {
        let runs: Vec<Vec<f64>> = (0..24u64)
            .into_par_iter()
            .map(|draw| {
                let subject = KneeSubject::ALL[(draw % 6) as usize];
                let cfg = KneeFesConfig {
                    subject,
                    seed: 500 + draw,
                    ..base
                };
                let recs = simulate_knee_fes(&cfg).expect("trial").records;
                let p = perturbed(KneeFesParams::subject(subject), e, draw);
                let Ok(m) = KneeFesModel::new(p) else {
                    return vec![f64::INFINITY; 6];
                };
                let mut fs = filters(m);
                [0usize, 1, 7, 8, 9, 10]
                    .iter()
                    .map(|&j| rmse(fs[j].as_mut(), &recs))
                    .collect()
            })
            .collect();
        for (j, n) in perturbed_names.iter().enumerate() {
            let c: Vec<f64> = runs.iter().map(|r| r[j]).collect();
            let ok: Vec<f64> = c.iter().copied().filter(|x| x.is_finite()).collect();
            let worst = ok.iter().copied().fold(0.0, f64::max);
            println!(
                "e = {:>2.0} %  {n:<16} diverged {}/24, mean of the rest {:.3} deg, worst {:.3} deg",
                e * 100.0,
                c.len() - ok.len(),
                mean(&ok),
                worst
            );
        }
        let rmx: Vec<f64> = runs.iter().map(|r| r[0]).collect();
        let all: Vec<f64> = runs.iter().map(|r| r[3]).collect();
        if all.iter().all(|x| x.is_finite()) {
            println!(
                "e = {:>2.0} %  ekf+all+r / rmx (means): {:.2}",
                e * 100.0,
                mean(&all) / mean(&rmx)
            );
        }
    }
}
