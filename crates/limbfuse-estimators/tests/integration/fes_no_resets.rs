//! Issue 16 item 0: the paper-004 filters must never restart on nominal
//! data. A restart (`diag_resets`) happens only when the state or the
//! Riccati solution goes non-finite, so any restart on a simulated trial of
//! the filter's own model is a divergence, not a feature of the data.
//!
//! Before the fix the knee `sdre` / `ekf` restarted at every sample (the
//! RK4 sub-step was chosen from the Riccati solution at the start of each
//! interval, `P_22 = p0 = 0.01`, while `P_22` rises to its steady value
//! `sqrt(q_2 s_1) = 0.1` within 1e-4 s, ten times stiffer than the step
//! allowed for).

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{
    FixedHipActivationFilter, FixedHipFilter, KneeFesFilter, Linearisation, RotationMatrixKnee,
};
use limbfuse_models::{
    FixedHipActivationModel, FixedHipModel, FixedHipParams, KneeFesModel, KneeFesParams,
    KneeSubject,
};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};

/// Runs `e` over `recs`; returns the restart count at the end and the
/// first time a restart was counted, or an error text on a non-finite angle
/// or an estimator error.
fn resets(e: &mut dyn Estimator, recs: &[Record]) -> Result<(u32, Option<f64>), String> {
    let col = e.diagnostic_names().iter().position(|n| *n == "resets");
    let mut first = None;
    let mut last = 0.0;
    for r in recs {
        let est = e
            .step(&r.sample)
            .map_err(|err| format!("t = {}: {err}", r.sample.t))?;
        if let Some(j) = est.joint.iter().flatten().find(|v| !v.is_finite()) {
            return Err(format!("t = {}: non-finite knee {j}", r.sample.t));
        }
        if let Some(n) = col.and_then(|c| est.diag[c]) {
            if n > 0.0 && first.is_none() {
                first = Some(r.sample.t);
            }
            last = n;
        }
    }
    Ok((last as u32, first))
}

#[test]
fn issue_16_knee_fes_filters_never_reset_on_nominal_data() {
    let mut failures = Vec::new();
    for subject in KneeSubject::ALL {
        let m = KneeFesModel::new(KneeFesParams::subject(subject)).unwrap();
        for noise in [true, false] {
            let tr = simulate_knee_fes(&KneeFesConfig {
                subject,
                seed: 5,
                noise,
                duration_s: 8.0,
                cycles: 1,
                ..KneeFesConfig::default()
            })
            .unwrap();
            let filters: [(&str, Box<dyn Estimator>); 3] = [
                ("sdre", Box::new(KneeFesFilter::sdre(m))),
                ("ekf", Box::new(KneeFesFilter::ekf(m))),
                ("rmx", Box::new(RotationMatrixKnee::new())),
            ];
            for (name, mut f) in filters {
                match resets(f.as_mut(), &tr.records) {
                    Ok((0, _)) => {}
                    Ok((n, t)) => failures.push(format!(
                        "{} noise={noise} {name}: {n} resets, first at t = {t:?} s",
                        subject.label()
                    )),
                    Err(e) => failures.push(format!("{} {name}: {e}", subject.label())),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn issue_16_fixed_hip_filters_never_reset_on_nominal_data() {
    let m = FixedHipModel::new(FixedHipParams::default()).unwrap();
    let mut failures = Vec::new();
    for noise in [true, false] {
        let tr = simulate_fixed_hip(&FixedHipConfig {
            seed: 5,
            noise,
            duration_s: 6.0,
            ..FixedHipConfig::default()
        })
        .unwrap();
        let filters: [(&str, Box<dyn Estimator>); 3] = [
            ("sdre", Box::new(FixedHipFilter::sdre(m))),
            ("ekf", Box::new(FixedHipFilter::ekf(m))),
            ("rmx", Box::new(RotationMatrixKnee::new())),
        ];
        for (name, mut f) in filters {
            match resets(f.as_mut(), &tr.records) {
                Ok((0, _)) => {}
                Ok((n, t)) => failures.push(format!(
                    "fixed-hip noise={noise} {name}: {n} resets, first at t = {t:?} s"
                )),
                Err(e) => failures.push(format!("fixed-hip {name}: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Issue 16 item 1 (fixed hip): with activation dynamics in the plant
/// (`T_a` 0.25 s, Table 1's P1-L, and a slow 1 s), the fixed-hip filters
/// with and without the four activation states never restart, and with
/// them the knee follows (RMSE after 1 s below 1 deg; measured 0.01-0.40
/// here, the filter without them 16 deg on 20 s trials, docs/RESULTS.md).
#[test]
fn issue_16_fixed_hip_with_activation_never_resets() {
    let m = FixedHipModel::new(FixedHipParams::default()).unwrap();
    let mut failures = Vec::new();
    for (t_a, noise) in [(0.25, true), (0.25, false), (1.0, true)] {
        let tr = simulate_fixed_hip(&FixedHipConfig {
            seed: 5,
            noise,
            duration_s: 6.0,
            activation_t_a: Some(t_a),
            ..FixedHipConfig::default()
        })
        .unwrap();
        let am = FixedHipActivationModel::new(m, t_a).unwrap();
        let filters: [(&str, Box<dyn Estimator>); 4] = [
            ("sdre", Box::new(FixedHipFilter::sdre(m))),
            ("ekf", Box::new(FixedHipFilter::ekf(m))),
            (
                "sdre+act",
                Box::new(FixedHipActivationFilter::with_default_tuning(
                    am,
                    Linearisation::Sdc,
                )),
            ),
            (
                "ekf+act",
                Box::new(FixedHipActivationFilter::with_default_tuning(
                    am,
                    Linearisation::Jacobian,
                )),
            ),
        ];
        for (name, mut f) in filters {
            let label = format!("fixed-hip T_a={t_a} noise={noise} {name}");
            match resets(f.as_mut(), &tr.records) {
                Ok((0, _)) => {}
                Ok((n, t)) => failures.push(format!("{label}: {n} resets, first at {t:?} s")),
                Err(e) => failures.push(format!("{label}: {e}")),
            }
            if name.ends_with("+act") {
                let mut f = FixedHipActivationFilter::with_default_tuning(
                    am,
                    if name == "sdre+act" {
                        Linearisation::Sdc
                    } else {
                        Linearisation::Jacobian
                    },
                );
                let (mut se, mut n) = (0.0, 0.0);
                for r in &tr.records {
                    let e = f.step(&r.sample).unwrap();
                    if r.sample.t >= 1.0 {
                        se += (e.joint[1].unwrap() - r.reference.joint[1].unwrap()).powi(2);
                        n += 1.0;
                    }
                }
                let rmse = (se / n).sqrt().to_degrees();
                eprintln!("{label}: knee {rmse:.3} deg");
                if rmse > 1.0 {
                    failures.push(format!("{label}: knee RMSE {rmse:.2} deg > 1"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The knee filters with the sub-step bounds the issue tried
/// (`max_substep` 2 ms and 0.5 ms) must not restart either.
#[test]
fn issue_16_knee_filters_never_reset_with_shorter_max_substep() {
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    let tr = simulate_knee_fes(&KneeFesConfig {
        duration_s: 6.0,
        cycles: 1,
        ..KneeFesConfig::default()
    })
    .unwrap();
    for lin in [Linearisation::Sdc, Linearisation::Jacobian] {
        for max_substep in [2e-3, 5e-4] {
            let mut tuning = limbfuse_estimators::fes::knee::knee_default_tuning(lin);
            tuning.max_substep = max_substep;
            let plant = limbfuse_estimators::fes::KneePlant::new(m);
            let mut f = limbfuse_estimators::fes::FesFilter::new(plant, lin, tuning);
            let got = resets(&mut f, &tr.records).unwrap();
            assert_eq!(got.0, 0, "{lin:?} max_substep {max_substep}: {got:?}");
        }
    }
}

/// Issue 16 items 1-2: the extended knee filters (`sdre` and `ekf` with the
/// activation state; `ekf` with every optional state and the accelerometer
/// lever arm) and `knee-kinematic` never restart on any preset, with the
/// plant's activation dynamics on. (`sdre` with the bias states, lever arm
/// and unknown torque: the next test.)
#[test]
fn issue_16_extended_and_kinematic_knee_filters_never_reset() {
    use limbfuse_estimators::fes::{ExtendedKneeFilter, KinematicKneeFilter};
    use limbfuse_models::{ExtendedKneeModel, KinematicKneeModel, KneeStateOptions};
    let all = KneeStateOptions {
        activation: true,
        disturbance: true,
        gyro_bias: true,
        acc_bias: true,
    };
    let act = KneeStateOptions {
        activation: true,
        ..Default::default()
    };
    let mut failures = Vec::new();
    for subject in KneeSubject::ALL {
        let m = KneeFesModel::new(KneeFesParams::subject(subject)).unwrap();
        let tr = simulate_knee_fes(&KneeFesConfig {
            subject,
            seed: 5,
            duration_s: 8.0,
            cycles: 1,
            ..KneeFesConfig::default()
        })
        .unwrap();
        let m3 = ExtendedKneeModel::<3>::new(m, act, 0.0).unwrap();
        let m6 = ExtendedKneeModel::<6>::new(m, all, 0.2).unwrap();
        let filters: [(&str, Box<dyn Estimator>); 4] = [
            (
                "sdre+activation",
                Box::new(ExtendedKneeFilter::with_default_tuning(
                    m3,
                    Linearisation::Sdc,
                )),
            ),
            (
                "ekf+activation",
                Box::new(ExtendedKneeFilter::with_default_tuning(
                    m3,
                    Linearisation::Jacobian,
                )),
            ),
            (
                "ekf+all",
                Box::new(ExtendedKneeFilter::with_default_tuning(
                    m6,
                    Linearisation::Jacobian,
                )),
            ),
            (
                "knee-kinematic",
                Box::new(KinematicKneeFilter::kinematic(
                    KinematicKneeModel::new(9.81, 0.2).unwrap(),
                    core::f64::consts::FRAC_PI_2,
                )),
            ),
        ];
        for (name, mut f) in filters {
            match resets(f.as_mut(), &tr.records) {
                Ok((0, _)) => {}
                Ok((n, t)) => failures.push(format!(
                    "{} {name}: {n} resets, first at t = {t:?} s",
                    subject.label()
                )),
                Err(e) => failures.push(format!("{} {name}: {e}", subject.label())),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Issue 16: `sdre` with the sensor-bias states, the lever arm and (second
/// filter) the unknown torque diverged: the prescribed-stability term
/// `2 a P` of eq 4.16 acted on states that are not observable while the leg
/// rests (torque balance and accelerometer are two equations for the angle,
/// the activation, the unknown torque and the accelerometer bias), so their
/// `P` grew as `e^{2t}` during each rest and the next extension applied
/// gains from it (the unknown torque's `P` went from 1.4 to 170 N^2 m^2 in
/// the first 3 s). Now the shift acts per state
/// (`knee_extended::extended_shift`). On every preset, with the plant's
/// activation dynamics and sensor errors: no restart, the knee RMSE after
/// the first second below `LIMIT_DEG`, and the `P` of every state at most
/// `P_GROWTH` times its start value (measured: at most 1.4 deg and 7.8;
/// without the per-state shift `sdre+all+r` reached 11-25 deg or diverged,
/// with `P` growing 321-3268 times).
#[test]
fn issue_16_sdre_with_bias_and_torque_states_stays_bounded() {
    use limbfuse_estimators::fes::ExtendedKneeFilter;
    use limbfuse_models::{ExtendedKneeModel, KneeStateOptions};
    const LIMIT_DEG: f64 = 3.0;
    const P_GROWTH: f64 = 50.0;
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
    let mut failures = Vec::new();
    for subject in KneeSubject::ALL {
        let m = KneeFesModel::new(KneeFesParams::subject(subject)).unwrap();
        let tr = simulate_knee_fes(&KneeFesConfig {
            subject,
            seed: 5,
            duration_s: 8.0,
            cycles: 1,
            ..KneeFesConfig::default()
        })
        .unwrap();
        let filters: [(&str, Box<dyn Estimator>); 2] = [
            (
                "sdre+act+bias+r",
                Box::new(ExtendedKneeFilter::with_default_tuning(
                    ExtendedKneeModel::<5>::new(m, bias, 0.2).unwrap(),
                    Linearisation::Sdc,
                )),
            ),
            (
                "sdre+all+r",
                Box::new(ExtendedKneeFilter::with_default_tuning(
                    ExtendedKneeModel::<6>::new(m, all, 0.2).unwrap(),
                    Linearisation::Sdc,
                )),
            ),
        ];
        for (name, mut f) in filters {
            let names = f.diagnostic_names();
            let p_cols: Vec<usize> = (0..names.len())
                .filter(|&i| names[i].starts_with('p'))
                .collect();
            let resets = names.iter().position(|n| *n == "resets").unwrap();
            let (mut p_start, mut worst_growth) = (vec![None; names.len()], 0.0f64);
            let (mut s, mut n) = (0.0, 0usize);
            for r in &tr.records {
                let est = f.step(&r.sample).unwrap();
                if est.diag[resets].is_some_and(|v| v > 0.0) {
                    failures.push(format!(
                        "{} {name}: restart at t = {}",
                        subject.label(),
                        r.sample.t
                    ));
                    break;
                }
                for &c in &p_cols {
                    if let Some(v) = est.diag[c] {
                        let p0 = *p_start[c].get_or_insert(v);
                        worst_growth = worst_growth.max(v / p0);
                    }
                }
                if r.sample.t >= 1.0 {
                    let (a, b) = (est.joint[1].unwrap(), r.reference.joint[1].unwrap());
                    s += (a - b) * (a - b);
                    n += 1;
                }
            }
            let rmse = (s / n.max(1) as f64).sqrt().to_degrees();
            let ok = rmse.is_finite() && rmse <= LIMIT_DEG && worst_growth <= P_GROWTH;
            if !ok {
                failures.push(format!(
                    "{} {name}: knee RMSE {rmse:.3} deg, worst P growth {worst_growth:.1}",
                    subject.label()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
