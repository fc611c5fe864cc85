//! Issue 16 "done when": with every estimator model parameter perturbed by
//! +-30 % (`J, m, l_c, phi0, theta_eq, T_a, d1-d6, c0-c3` each scaled by
//! `1 + 0.3 u`, `u` uniform in [-1, 1), seeded: `fes_pulse_cv::perturbed`,
//! the study's draw), the disturbance-state configuration (`ekf` with the
//! activation, unknown-torque, gyro- and accelerometer-bias states and the
//! 0.2 m lever arm, default physics tuning) never diverges over 24 draws
//! (no restart, `diag_resets` 0; finite knee) and its mean knee RMSE is at
//! most 1.2 x `rmx`'s on the same trials. The study example
//! (`fes_model_study`, part (c)) uses 30 s trials; here 14 s with two
//! extensions keep the debug-profile run short.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{ExtendedKneeFilter, Linearisation, RotationMatrixKnee};
use limbfuse_models::{
    ExtendedKneeModel, KneeFesModel, KneeFesParams, KneeStateOptions, KneeSubject,
};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};
use limbfuse_studies::fes_pulse_cv::perturbed;

const DRAWS: u64 = 24;

/// Knee RMSE (deg) after 1 s; `Err` on an estimator error, a restart or a
/// non-finite knee.
fn knee_rmse(e: &mut dyn Estimator, recs: &[Record]) -> Result<f64, String> {
    let resets = e.diagnostic_names().iter().position(|n| *n == "resets");
    let (mut s, mut n) = (0.0, 0usize);
    for r in recs {
        let est = e
            .step(&r.sample)
            .map_err(|err| format!("t = {}: {err}", r.sample.t))?;
        if let Some(v) = resets.and_then(|c| est.diag[c]).filter(|v| *v > 0.0) {
            return Err(format!("t = {}: {v} restarts", r.sample.t));
        }
        let knee = est.joint[1].ok_or("no knee estimate")?;
        if !knee.is_finite() {
            return Err(format!("t = {}: knee {knee}", r.sample.t));
        }
        if r.sample.t >= 1.0 {
            if let Some(truth) = r.reference.joint[1] {
                s += (knee - truth) * (knee - truth);
                n += 1;
            }
        }
    }
    Ok((s / n.max(1) as f64).sqrt().to_degrees())
}

/// Runs `states` (with `N` states, the 0.2 m lever arm, default physics
/// tuning) and `rmx` on the 24 perturbed draws: the mean knee RMSE of each
/// over the draws that ran, and the draws that failed.
fn perturbed_draws<const N: usize>(
    states: KneeStateOptions,
    label: &str,
) -> (f64, f64, Vec<String>) {
    let (mut ekf_sum, mut rmx_sum, mut ran) = (0.0, 0.0, 0usize);
    let mut failures = Vec::new();
    for draw in 0..DRAWS {
        let subject = KneeSubject::ALL[(draw % 6) as usize];
        let recs = simulate_knee_fes(&KneeFesConfig {
            subject,
            seed: 500 + draw,
            duration_s: 14.0,
            cycles: 2,
            ..KneeFesConfig::default()
        })
        .expect("valid config")
        .records;
        let p = perturbed(KneeFesParams::subject(subject), 0.3, draw);
        let m = KneeFesModel::new(p).expect("a +-30 % draw stays physical");
        let mut ekf = ExtendedKneeFilter::with_default_tuning(
            ExtendedKneeModel::<N>::new(m, states, 0.2).expect("state count"),
            Linearisation::Jacobian,
        );
        let rmx = knee_rmse(&mut RotationMatrixKnee::new(), &recs).expect("rmx runs");
        match knee_rmse(&mut ekf, &recs) {
            Ok(v) => {
                eprintln!(
                    "draw {draw} {}: {label} {v:.3} deg, rmx {rmx:.3}",
                    subject.label()
                );
                ekf_sum += v;
                rmx_sum += rmx;
                ran += 1;
            }
            Err(e) => failures.push(format!("draw {draw} {}: {e}", subject.label())),
        }
    }
    let n = ran.max(1) as f64;
    (ekf_sum / n, rmx_sum / n, failures)
}

#[test]
fn issue_16_disturbance_state_survives_30_percent_parameter_error() {
    let all = KneeStateOptions {
        activation: true,
        disturbance: true,
        gyro_bias: true,
        acc_bias: true,
    };
    let (ekf, rmx, failures) = perturbed_draws::<6>(all, "ekf+all+r");
    assert!(failures.is_empty(), "diverged:\n{}", failures.join("\n"));
    let ratio = ekf / rmx;
    eprintln!("mean knee RMSE: ekf+all+r {ekf:.3}, rmx {rmx:.3} deg, ratio {ratio:.2}");
    assert!(ratio <= 1.2, "ekf+all+r / rmx = {ratio:.2} > 1.2");
}

/// The bound above can fail: without the unknown-torque state the same
/// draws miss it (docs/RESULTS.md, issue 16 section).
#[test]
fn issue_16_without_the_unknown_torque_state_the_bound_is_missed() {
    let no_torque = KneeStateOptions {
        activation: true,
        disturbance: false,
        gyro_bias: true,
        acc_bias: true,
    };
    let (ekf, rmx, failures) = perturbed_draws::<5>(no_torque, "ekf+act+bias+r");
    let ratio = ekf / rmx;
    eprintln!(
        "mean knee RMSE: ekf+act+bias+r {ekf:.3}, rmx {rmx:.3} deg, ratio {ratio:.2}, {} diverged",
        failures.len()
    );
    assert!(
        !failures.is_empty() || ratio > 1.2,
        "ekf+act+bias+r / rmx = {ratio:.2} <= 1.2 on every draw"
    );
}
