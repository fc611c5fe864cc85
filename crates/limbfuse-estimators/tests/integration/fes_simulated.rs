//! Paper 004 estimators with their default tuning on simulated trials:
//! knee accuracy, the fixed-hip accuracy target of the thesis (<= 0.3 deg),
//! and a missing stimulation.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{FixedHipFilter, KneeFesFilter, RotationMatrixKnee};
use limbfuse_models::{FixedHipModel, FixedHipParams, KneeFesModel, KneeFesParams, KneeSubject};
use limbfuse_sim::fixed_hip::{simulate_fixed_hip, FixedHipConfig};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};

/// RMSE (deg) of joint `j` over the records.
fn rmse(e: &mut dyn Estimator, recs: &[Record], j: usize) -> f64 {
    let mut s = 0.0;
    for r in recs {
        let est = e.step(&r.sample).unwrap();
        let d = est.joint[j].unwrap() - r.reference.joint[j].unwrap();
        s += d * d;
    }
    (s / recs.len() as f64).sqrt().to_degrees()
}

/// The knee filters track the simulated knee to within 1 deg. Before
/// issue 16 item 0 this test also asserted `sdre < rmx && ekf < rmx`; that
/// held only because both filters restarted from the accelerometer
/// inclination at every sample. With the filters actually running, the
/// default tuning (a model without activation dynamics, q = (1e-4, 1e3))
/// does not beat `rmx` (P1-L seed 3: sdre 0.68, ekf 0.59, rmx 0.52 deg);
/// making the model earn its place is items 1-4 of issue 16.
#[test]
fn knee_filters_track_simulated_trials() {
    for subject in [KneeSubject::P1L, KneeSubject::P2R] {
        let tr = simulate_knee_fes(&KneeFesConfig {
            subject,
            seed: 3,
            ..KneeFesConfig::default()
        })
        .unwrap();
        let m = KneeFesModel::new(KneeFesParams::subject(subject)).unwrap();
        let sdre = rmse(&mut KneeFesFilter::sdre(m), &tr.records, 1);
        let ekf = rmse(&mut KneeFesFilter::ekf(m), &tr.records, 1);
        let rmx = rmse(&mut RotationMatrixKnee::new(), &tr.records, 1);
        eprintln!(
            "{}: sdre {sdre:.6} deg, ekf {ekf:.6} deg, rmx {rmx:.6} deg",
            subject.label()
        );
        assert!(sdre < 1.0 && ekf < 1.0 && rmx < 1.0, "{sdre} {ekf} {rmx}");
    }
}

/// Regression (twenty-seventh session's audit of left-alone items): Mahony
/// gains beyond the explicit Euler step's stability bound (`k_p dt > 2` or
/// `k_i dt^2 > k_p dt`) gave a 40 deg (`kp = 1e6`) or 93 deg (`ki = 1000`)
/// knee on this trial without a word; per step they are now capped at the
/// bound (`MahonyGains::for_step`), which leaves the default gains as given.
#[test]
fn rmx_gains_beyond_the_stable_step_are_capped() {
    use limbfuse_estimators::fes::mahony::MahonyGains;
    let tr = simulate_knee_fes(&KneeFesConfig {
        seed: 3,
        ..KneeFesConfig::default()
    })
    .unwrap();
    let default = rmse(&mut RotationMatrixKnee::new(), &tr.records, 1);
    for (kp, ki) in [(1e6, 0.0), (0.5, 1e3), (1e300, 1e300)] {
        let e = rmse(
            &mut RotationMatrixKnee::with_gains(MahonyGains { kp, ki }),
            &tr.records,
            1,
        );
        eprintln!("kp {kp:e} ki {ki:e}: {e:.3} deg (default gains {default:.3})");
        assert!(e < 3.0 * default.max(1.0), "kp {kp} ki {ki}: {e} deg");
    }
}

#[test]
fn fixed_hip_sdre_meets_the_thesis_accuracy() {
    let m = FixedHipModel::new(FixedHipParams::default()).unwrap();
    let mut worst: f64 = 0.0;
    for seed in 1..=3 {
        let tr = simulate_fixed_hip(&FixedHipConfig {
            seed,
            ..FixedHipConfig::default()
        })
        .unwrap();
        let hip = rmse(&mut FixedHipFilter::sdre(m), &tr.records, 0);
        let knee = rmse(&mut FixedHipFilter::sdre(m), &tr.records, 1);
        eprintln!("seed {seed}: sdre hip {hip:.3} knee {knee:.3} deg");
        worst = worst.max(hip).max(knee);
    }
    assert!(worst <= 0.3, "worst {worst} deg");
}

/// A stimulation not yet seen: no estimate (not an error, since
/// 2026-12-06: a recording whose stimulation log starts late is estimated
/// from its first value on; a trial without the column is refused by the
/// method layer before any step).
#[test]
fn stimulation_not_yet_seen_gives_no_estimate_until_it_comes() {
    let tr = simulate_knee_fes(&KneeFesConfig {
        duration_s: 2.0,
        ..KneeFesConfig::default()
    })
    .unwrap();
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    for (mut f, mut fresh) in [
        (KneeFesFilter::sdre(m), KneeFesFilter::sdre(m)),
        (KneeFesFilter::ekf(m), KneeFesFilter::ekf(m)),
    ] {
        for (k, r) in tr.records.iter().enumerate() {
            let mut s = r.sample;
            if k < 20 {
                s.inputs.stim[0] = None;
                let e = f.step(&s).unwrap();
                assert_eq!(e.joint, [None; 3], "sample {k}");
                assert_eq!(e.segment, [None; 4], "sample {k}");
            } else {
                // from its first input on, the run of a filter started there
                let e = f.step(&s).unwrap();
                let want = fresh.step(&s).unwrap();
                assert_eq!(e.joint, want.joint, "sample {k}");
                assert!(e.joint[1].is_some());
                let resets = f.diagnostic_names().iter().position(|n| *n == "resets");
                assert_eq!(e.diag[resets.unwrap()], Some(0.0), "a start, not a restart");
            }
        }
    }
}

/// Issue 16 item 5 (brief fes2): a missing stimulation value is held for
/// at most `MAX_INPUT_HOLD_S` (0.1 s) and counted in `held_inputs`. Past
/// the hold (since 2026-12-06; until then an `InputGap` error ended the
/// run) the filter gives no estimate until the stimulation is back, then
/// restarts there, as a filter started at that sample, and counts the
/// restart in `resets`. P1-L, 100 Hz: `u_ke` blank on samples 100-104
/// (held, counted 5, estimates equal to those of a trial whose cells hold
/// the last value), then blank on samples 200-239: 200-209 are within 0.1
/// s of sample 199's value (held), 210-239 have no estimate, 240 restarts.
#[test]
fn issue_16_missing_stimulation_is_held_then_restarted() {
    use limbfuse_estimators::fes::filter::MAX_INPUT_HOLD_S;
    assert_eq!(MAX_INPUT_HOLD_S, 0.1);
    let tr = simulate_knee_fes(&KneeFesConfig {
        duration_s: 3.0,
        ..KneeFesConfig::default()
    })
    .unwrap();
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    for (mut f, mut held_copy, mut fresh) in [
        (
            KneeFesFilter::sdre(m),
            KneeFesFilter::sdre(m),
            KneeFesFilter::sdre(m),
        ),
        (
            KneeFesFilter::ekf(m),
            KneeFesFilter::ekf(m),
            KneeFesFilter::ekf(m),
        ),
    ] {
        let names = f.diagnostic_names();
        let held_col = names.iter().position(|n| *n == "held_inputs").unwrap();
        let resets_col = names.iter().position(|n| *n == "resets").unwrap();
        let mut last_u = None;
        for (k, r) in tr.records.iter().enumerate() {
            let mut s = r.sample;
            let mut filled = r.sample;
            if (100..105).contains(&k) || (200..240).contains(&k) {
                s.inputs.stim[0] = None;
                filled.inputs.stim[0] = last_u;
            } else {
                last_u = s.inputs.stim[0];
            }
            let e = f.step(&s).unwrap();
            let held = e.diag[held_col].unwrap();
            let resets = e.diag[resets_col].unwrap();
            match k {
                0..=209 => {
                    let want = held_copy.step(&filled).unwrap();
                    assert_eq!(e.joint, want.joint, "sample {k}");
                    let expect = match k {
                        0..=99 => 0.0,
                        100..=104 => (k - 99) as f64,
                        105..=199 => 5.0,
                        _ => (k - 194) as f64,
                    };
                    assert_eq!(held, expect, "sample {k}");
                    assert_eq!(resets, 0.0, "sample {k}");
                    assert!(e.joint[1].unwrap().is_finite());
                }
                210..=239 => {
                    assert_eq!(e.joint, [None; 3], "sample {k}: no input, no estimate");
                    assert_eq!(e.segment, [None; 4], "sample {k}");
                    assert_eq!((held, resets), (15.0, 0.0), "sample {k}");
                }
                _ => {
                    let want = fresh.step(&s).unwrap();
                    assert_eq!(e.joint, want.joint, "sample {k}: a start at sample 240");
                    assert_eq!((held, resets), (15.0, 1.0), "sample {k}");
                }
            }
        }
    }
}

/// Issue 16 ("show the model's share of the update"): the extended knee
/// filter's `model_weight` (`exp(-(K C)_22 dt)`, the part of the model's
/// rate prediction left after one sample of measurement updates) tells a
/// tuning that switches the model off from one that uses it, and
/// `model_share` is a fraction. Same model (no optional state, no lever
/// arm), P1-L seed 3: with the thesis default `Q = diag(1e-4, 1e3)`,
/// `S = diag(1e-5, 1e-2)` the median weight is about `e^-100` (measured
/// 4e-44 on the 18 trials of docs/RESULTS.md); with the physics default
/// (`q_2` from a 10 % torque error) about 0.08.
#[test]
fn issue_16_model_weight_separates_model_trusting_tunings() {
    use limbfuse_estimators::fes::{
        ContinuousTuning, ExtendedKneeFilter, ExtendedKneePlant, FesFilter, Linearisation,
    };
    use limbfuse_models::{ExtendedKneeModel, KneeStateOptions};
    use nalgebra::Vector2;
    let tr = simulate_knee_fes(&KneeFesConfig {
        subject: KneeSubject::P1L,
        seed: 3,
        duration_s: 6.0,
        cycles: 1,
        ..KneeFesConfig::default()
    })
    .unwrap();
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    let model = ExtendedKneeModel::<2>::new(m, KneeStateOptions::default(), 0.0).unwrap();
    let thesis = ContinuousTuning {
        q: Vector2::new(1e-4, 1e3),
        s: Vector2::new(1e-5, 1e-2),
        a: 0.0,
        p0: Vector2::new(1e-2, 1e-2),
        max_substep: 1e-2,
        a_states: None,
    };
    let median_weight = |f: &mut dyn Estimator| {
        let names = f.diagnostic_names();
        let (w, s) = (
            names.iter().position(|n| *n == "model_weight").unwrap(),
            names.iter().position(|n| *n == "model_share").unwrap(),
        );
        let mut v = Vec::new();
        for r in &tr.records {
            let est = f.step(&r.sample).unwrap();
            if let Some(share) = est.diag[s] {
                assert!((0.0..=1.0).contains(&share), "model_share {share}");
            }
            if r.sample.t >= 1.0 {
                v.push(est.diag[w].unwrap());
            }
        }
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let off = median_weight(&mut FesFilter::new(
        ExtendedKneePlant::new(model),
        Linearisation::Jacobian,
        thesis,
    ));
    let on = median_weight(&mut ExtendedKneeFilter::with_default_tuning(
        model,
        Linearisation::Jacobian,
    ));
    assert!(off < 1e-20, "thesis tuning: median model_weight {off:e}");
    assert!(
        on > 0.02 && on < 0.5,
        "physics tuning: median model_weight {on}"
    );
}

/// Issue 16 item 1 (brief fes2): the sub-steps sized by the
/// Collatz-Wielandt stiffness bound and the Riccati relative-rate limit
/// stay accurate. The 5-state `sdre` and `ekf` (activation, gyro and
/// accelerometer bias, 0.2 m lever arm, physics tuning) with the default
/// sub-steps against the same filter with `max_substep` 0.1 ms (100
/// sub-steps per sample; 4e-6 deg from 25 microseconds): measured max
/// |delta knee| 2.2e-5 (sdre) and 2.9e-5 deg (ekf), P1-L seed 42, 4 s.
/// Without the relative-rate limit the first interval's transient from
/// `p0` alone left 1.3e-3 deg.
#[test]
fn issue_16_bounded_substeps_match_a_converged_solution() {
    use limbfuse_estimators::fes::{ExtendedKneeFilter, ExtendedKneePlant, FesFilter};
    use limbfuse_models::{ExtendedKneeModel, KneeStateOptions};
    let tr = simulate_knee_fes(&KneeFesConfig {
        seed: 42,
        duration_s: 4.0,
        ..KneeFesConfig::default()
    })
    .unwrap();
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    let opts = KneeStateOptions {
        activation: true,
        disturbance: false,
        gyro_bias: true,
        acc_bias: true,
    };
    let model = ExtendedKneeModel::<5>::new(m, opts, 0.2).unwrap();
    for lin in [
        limbfuse_estimators::fes::Linearisation::Sdc,
        limbfuse_estimators::fes::Linearisation::Jacobian,
    ] {
        let mut fast = ExtendedKneeFilter::with_default_tuning(model, lin);
        let mut fine_tuning = *fast.tuning();
        fine_tuning.max_substep = 1e-4;
        let mut fine = FesFilter::new(ExtendedKneePlant::new(model), lin, fine_tuning);
        let mut worst: f64 = 0.0;
        for r in &tr.records {
            let a = fast.step(&r.sample).unwrap().joint[1].unwrap();
            let b = fine.step(&r.sample).unwrap().joint[1].unwrap();
            worst = worst.max((a - b).abs().to_degrees());
        }
        eprintln!("{lin:?}: max |delta knee| {worst:e} deg");
        assert!(worst < 5e-5, "{lin:?}: {worst} deg");
    }
}
