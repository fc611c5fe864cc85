//! B-SLIP model, events, gait search and trial simulation (paper 003 sec II).

use limbfuse_core::GaitPhase;
use limbfuse_models::bslip::{
    derivative, energy, leg_force, leg_length, touchdown_function, BslipParams, GaitParameters,
    Stance, State,
};
use limbfuse_sim::bslip::integrator::{advance, Stop, Tolerances};
use limbfuse_sim::bslip::library::{start_seed, LibraryGait, START_SPEED};
use limbfuse_sim::bslip::periodic::periodicity_error;
use limbfuse_sim::bslip::search::{optimise_gait, SearchSettings};
use limbfuse_sim::bslip::step::StepSimulator;
use limbfuse_sim::bslip::trial::{simulate_trial, trial_records, BslipTrialConfig};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

fn body() -> BslipParams {
    BslipParams::default()
}

/// One gait found from the start seed (shared by the tests below).
fn gait_at_start_speed() -> LibraryGait {
    let sim = StepSimulator::new(body());
    optimise_gait(
        &sim,
        &start_seed(1.0),
        START_SPEED,
        &SearchSettings::default(),
    )
    .expect("a periodic gait at the start speed")
    .into()
}

/// Vertical leg under the CoM: y'' = k/m (l0 - y) - g, simple harmonic about
/// y_eq = l0 - m g / k with omega = sqrt(k/m). Released at rest from
/// y_eq + A, the CoM crosses y_eq downwards at t = pi / (2 omega): the
/// touchdown event (height y_eq) must fire exactly then.
#[test]
fn touchdown_event_fires_at_the_quarter_period_of_a_vertical_bounce() {
    let p = body();
    let y_eq = p.rest_length - p.mass * p.gravity / p.stiffness;
    let omega = (p.stiffness / p.mass).sqrt();
    let gait = GaitParameters {
        phi: (y_eq / p.rest_length).asin(),
        theta: 0.0,
        stiffness: p.stiffness,
        height: y_eq + 0.02,
        lateral: 0.0,
        forward_speed: 0.0,
    };
    let stance = Stance {
        trailing: Some([0.0, 0.0]),
        leading: None,
    };
    let f = |s: &State| derivative(&p, s, &stance);
    let g = |s: &State| touchdown_function(&p, &gait, s);
    let mut x = State::new(0.0, y_eq + 0.02, 0.0, 0.0, 0.0, 0.0);
    let (mut t, mut h) = (0.0, 0.0);
    let stop = advance(
        &f,
        Some(&g),
        &Tolerances::default(),
        &mut t,
        &mut x,
        1.0,
        &mut h,
    );
    assert_eq!(stop, Stop::Event);
    let expected = std::f64::consts::FRAC_PI_2 / omega;
    assert!((t - expected).abs() < 1e-9, "t = {t}, expected {expected}");
    // Speed at the equilibrium: A omega.
    assert!((x[4] + 0.02 * omega).abs() < 1e-8);
}

#[test]
fn a_step_conserves_energy_and_its_events_sit_where_they_belong() {
    let g = gait_at_start_speed();
    let p = g.gait.model(&body());
    let o = g.step;
    let trailing = [0.0, 0.0];
    let ss1 = Stance {
        trailing: Some(trailing),
        leading: None,
    };
    let ds = Stance {
        trailing: Some(trailing),
        leading: Some(o.leading_foot),
    };
    let ss2 = Stance {
        trailing: None,
        leading: Some(o.leading_foot),
    };
    let x0 = limbfuse_sim::bslip::step::initial_state(&g.gait, limbfuse_models::bslip::Side::Left);
    let e0 = energy(&p, &x0, &ss1);
    // Touchdown: the CoM at the touchdown height, the new leg at rest length
    // (so the energy is the same counted with one or two legs).
    assert!((o.x_touchdown[1] - g.gait.touchdown_height(p.rest_length)).abs() < 1e-9);
    assert!((leg_length(&o.x_touchdown, o.leading_foot) - p.rest_length).abs() < 1e-9);
    let e_td = energy(&p, &o.x_touchdown, &ds);
    assert!((e_td - e0).abs() < 1e-6 * e0, "SS1 energy {e0} -> {e_td}");
    // Lift-off: the trailing leg at rest length, its force zero.
    assert!(leg_force(&p, &o.x_lift_off, trailing).norm() < 1e-6);
    let e_lo = energy(&p, &o.x_lift_off, &ss2);
    assert!((e_lo - e0).abs() < 1e-6 * e0, "DS energy {e0} -> {e_lo}");
    // MS: zero vertical velocity.
    assert!(o.x_end[4].abs() < 1e-9);
    let e_end = energy(&p, &o.x_end, &ss2);
    assert!((e_end - e0).abs() < 1e-6 * e0, "SS2 energy {e0} -> {e_end}");
    assert!(0.0 < o.t_touchdown && o.t_touchdown < o.t_lift_off && o.t_lift_off < o.t_end);
}

#[test]
fn the_found_gait_is_periodic_and_has_the_human_step() {
    let g = gait_at_start_speed();
    let tol = SearchSettings::default().periodic_tol;
    assert!(g.residual <= tol);
    let sim = StepSimulator::new(body());
    let o = sim.step(&g.gait).unwrap();
    assert!(periodicity_error(&g.gait, &o) <= tol);
    assert!((o.mean_speed() - START_SPEED).abs() <= tol);
    let l_des = limbfuse_sim::bslip::step_law::step_length(START_SPEED, 1.0);
    assert!((o.step_length() - l_des).abs() < 1e-6);
}

/// `trial_records` yields records one at a time: a trial of 1e11 samples
/// (about 200 TB as records in memory) gives its first ones at once, equal
/// to a short trial's. `simulate bslip --rate 1e7` (4e7 samples, within the
/// cap) aborted asking for 82 GB before the records were streamed.
#[test]
fn trial_records_stream_without_holding_the_trial() {
    let g = gait_at_start_speed();
    let tpl = g.template(&body());
    let short = BslipTrialConfig {
        duration: 0.05,
        ..Default::default()
    };
    let huge = BslipTrialConfig {
        duration: 1e9,
        ..Default::default()
    };
    let first: Vec<_> = trial_records(&tpl, &huge).take(5).collect();
    assert_eq!(first, simulate_trial(&tpl, &short));
}

/// `simulate bslip`'s end sample: a trial of `duration` s at `rate` Hz held
/// `floor(duration x rate) + 1` samples (401 for 4 s at 100 Hz, the last at
/// t = 4 s), one more than `simulate walking` (and `knee`, `knee-fes`,
/// `fixed-hip`, and the shared independent trials: 10 s at 100 Hz are
/// 1000 rows to 9.99 s) for the same duration and rate. Expected: the
/// same `round(duration x rate)` samples at `k / rate`.
#[test]
fn a_trial_holds_duration_times_rate_samples_as_the_walking_simulator() {
    let tpl = gait_at_start_speed().template(&body());
    for (duration, rate) in [(4.0, 100.0), (3.0, 250.0), (2.5, 60.0), (1.0, 1.0)] {
        let trial = simulate_trial(
            &tpl,
            &BslipTrialConfig {
                duration,
                sample_rate: rate,
                ..Default::default()
            },
        );
        let walking = WalkingSimulator::new(WalkingConfig {
            duration_s: duration,
            imu_rate_hz: rate,
            ..Default::default()
        })
        .unwrap();
        let n = (duration * rate).round() as usize;
        assert_eq!(
            (trial.len(), walking.sample_count() as usize),
            (n, n),
            "{duration} s at {rate} Hz"
        );
        let last = walking.last().unwrap().sample.t;
        assert_eq!(trial.last().unwrap().sample.t, last);
        assert!((last - (n - 1) as f64 / rate).abs() < 1e-12);
    }
}

#[test]
fn trial_walks_through_phases_in_order_and_is_reproducible() {
    let g = gait_at_start_speed();
    let tpl = g.template(&body());
    let cfg = BslipTrialConfig {
        duration: 2.0,
        ..Default::default()
    };
    let a = simulate_trial(&tpl, &cfg);
    let b = simulate_trial(&tpl, &cfg);
    assert_eq!(a, b);
    let phases: Vec<GaitPhase> = a.iter().map(|r| r.reference.phase.unwrap()).collect();
    let mut changes = vec![phases[0]];
    for w in phases.windows(2) {
        if w[1] != w[0] {
            changes.push(w[1]);
        }
    }
    use GaitPhase::*;
    assert_eq!(&changes[..7], &[Ss1, Ds, Ss2, Ss1, Ds, Ss2, Ss1]);
    // Forward progress at the gait's speed; measurements are noisy truth.
    let last = a.last().unwrap();
    let x = last.reference.com_pos.unwrap()[0];
    assert!(
        (x / 2.0 - START_SPEED).abs() < 0.1,
        "mean speed {}",
        x / 2.0
    );
    let err = last.sample.com.pos[1].unwrap() - last.reference.com_pos.unwrap()[1];
    assert!(err.abs() < 0.04 && err != 0.0);
    assert!(last.sample.com.vel[2].is_none());
}

#[test]
fn rescaled_gait_is_still_periodic() {
    let g = gait_at_start_speed();
    let tpl = g.template(&body());
    let s = tpl.rescaled_to_height(0.85).unwrap();
    let sim = StepSimulator::new(s.body);
    let o = sim.step(&s.gait).unwrap();
    assert!(periodicity_error(&s.gait, &o) < 1e-7);
    let r = (0.85 / tpl.gait.height).sqrt();
    assert!((o.mean_speed() - tpl.speed * r).abs() < 1e-7);
    assert!((o.step_length() - tpl.step_length * r * r).abs() < 1e-7);
    assert!(tpl.rescaled_to_height(f64::NAN).is_none());
}

/// Froude scaling (docs/GAIT_IMM.md, "Continuous gait family"): a gait found
/// for the default body (80 kg, l0 1 m, g 9.81), rescaled to another body
/// (70 kg, l0 0.95 m; and a 0.9 m leg under Mars gravity), is a periodic
/// gait of that body's own dynamics, with the step's times, lengths and
/// mean speed scaled as the dimensionless groups say. Keeping the default
/// body's stiffness instead (what a library built for another body gives
/// without rescaling) is not periodic: the test can fail.
#[test]
fn a_gait_rescaled_by_froude_similarity_is_periodic_for_the_other_body() {
    let g = gait_at_start_speed();
    let t = g.template(&body());
    assert!(g.residual < 1e-8);
    for other in [
        BslipParams {
            mass: 70.0,
            rest_length: 0.95,
            ..body()
        },
        BslipParams {
            mass: 60.0,
            rest_length: 0.9,
            gravity: 3.71,
            ..body()
        },
    ] {
        let r = t.rescaled_to_body(&other).unwrap();
        let sim = StepSimulator::new(r.body);
        let o = sim.step(&r.gait).unwrap();
        let err = periodicity_error(&r.gait, &o);
        assert!(
            err < 1e-8,
            "rescaled to {other:?}: periodicity error {err:e}"
        );
        let s = other.rest_length / body().rest_length;
        let time = (s * body().gravity / other.gravity).sqrt();
        assert!((o.t_end - g.step.t_end * time).abs() < 1e-9);
        assert!((o.t_touchdown - g.step.t_touchdown * time).abs() < 1e-9);
        assert!((o.step_length() - g.step.step_length() * s).abs() < 1e-9);
        assert!((o.mean_speed() - r.speed).abs() < 1e-6);
        // The default body's stiffness with the other body's mass and leg.
        let unscaled = limbfuse_models::bslip::GaitParameters {
            stiffness: g.gait.stiffness,
            ..r.gait
        };
        let sim = StepSimulator::new(unscaled.model(&other));
        let bad = sim
            .step(&unscaled)
            .map(|o| periodicity_error(&unscaled, &o))
            .unwrap_or(f64::INFINITY);
        assert!(bad > 1e-4, "unscaled stiffness still periodic: {bad:e}");
    }
}
