//! Missing data, time gaps, bad timestamps, reset, angle wrapping, options,
//! and the structural properties (block-diagonal local gain, symmetric
//! positive-definite covariances over long runs) of the segment filters.
#![allow(clippy::needless_range_loop)]

use crate::segment_kf_support::{is_spd, Rng, StaticLimb, G};
use limbfuse_core::{Estimate, Estimator, Sample};
use limbfuse_estimators::segment_kf::params::CommonParams;
use limbfuse_estimators::segment_kf::{
    GlobalDiag, GlobalKf, GlobalKfParams, LocalDiag, LocalKf, LocalKfParams, MarkovJumpKf,
    MarkovJumpKfParams, MjlsDiag, WhenUnreliable,
};
use nalgebra::{SMatrix, Vector3};
use proptest::prelude::*;

/// The three filters behind one interface, with their covariance.
#[allow(clippy::large_enum_variant)]
pub(crate) enum AnyKf {
    Local(LocalKf),
    Mjls(MarkovJumpKf),
    Global(GlobalKf),
}

impl AnyKf {
    pub(crate) fn all(common: CommonParams) -> [AnyKf; 3] {
        [
            AnyKf::Local(
                LocalKf::new(LocalKfParams {
                    common,
                    min_reliable: 2,
                })
                .unwrap(),
            ),
            AnyKf::Mjls(
                MarkovJumpKf::new(MarkovJumpKfParams {
                    common,
                    ..Default::default()
                })
                .unwrap(),
            ),
            AnyKf::Global(
                GlobalKf::new(GlobalKfParams {
                    common,
                    ..Default::default()
                })
                .unwrap(),
            ),
        ]
    }

    pub(crate) fn est(&mut self) -> &mut dyn Estimator {
        match self {
            AnyKf::Local(f) => f,
            AnyKf::Mjls(f) => f,
            AnyKf::Global(f) => f,
        }
    }

    pub(crate) fn p(&self) -> SMatrix<f64, 8, 8> {
        match self {
            AnyKf::Local(f) => *f.covariance(),
            AnyKf::Mjls(f) => *f.covariance(),
            AnyKf::Global(f) => *f.covariance(),
        }
    }

    pub(crate) fn name(&self) -> &'static str {
        match self {
            AnyKf::Local(_) => "local",
            AnyKf::Mjls(_) => "mjls",
            AnyKf::Global(_) => "global",
        }
    }

    pub(crate) fn diag_names(&self) -> &'static [&'static str] {
        match self {
            AnyKf::Local(_) => &LocalDiag::NAMES,
            AnyKf::Mjls(_) => &MjlsDiag::NAMES,
            AnyKf::Global(_) => &GlobalDiag::NAMES,
        }
    }
}

pub(crate) fn diag(e: &Estimate, names: &[&str], name: &str) -> Option<f64> {
    e.diag[names.iter().position(|n| *n == name).unwrap()]
}

fn all_finite(e: &Estimate) -> bool {
    e.segment
        .iter()
        .chain(e.joint.iter())
        .flatten()
        .all(|v| v.is_finite())
        && e.diag.iter().flatten().all(|v| v.is_finite())
}

pub(crate) fn limb(seed: u64) -> StaticLimb {
    StaticLimb {
        theta: [0.1, -0.2, 0.3, -0.1],
        gyro_bias: [0.01, -0.005, 0.002, 0.008],
        gyro_density: 1.2e-4,
        acc_sigma: 0.02,
        enc_sigma: 1e-4,
        dt: 0.01,
        rng: Rng::new(seed),
    }
}

#[test]
fn missing_samples_nan_cells_and_a_time_gap_never_give_nan() {
    for mut f in AnyKf::all(first_sample_start()) {
        let mut l = limb(11);
        let mut t_offset = 0.0;
        for k in 0..1500 {
            let mut s = l.sample(k);
            if k == 700 {
                t_offset = 5.0; // a 5 s gap in the recording
            }
            s.t += t_offset;
            match k % 13 {
                1 => s.imu[0].gyr = None,
                2 => s.imu[1].acc = None,
                3 => s.encoder = [None; 3],
                4 => s = Sample::empty(s.t),
                5 => s.imu[2].acc = Some(Vector3::new(f64::NAN, 9.81, 0.0)),
                6 => s.encoder[1] = Some(f64::INFINITY),
                7 => s.imu[3].gyr = Some(Vector3::new(0.0, 0.0, f64::NAN)),
                _ => {}
            }
            let e = f.est().step(&s).unwrap();
            assert!(all_finite(&e), "{} step {k}", f.est().name());
            // Missing inputs are counted: 4 acc + 4 gyro (+ 3 encoders for mjls).
            let mjls = f.est().name() == "mjls";
            let expected = match k % 13 {
                1 | 2 | 5 | 7 => 1.0,
                3 => 3.0 * f64::from(u8::from(mjls)),
                4 => 8.0 + 3.0 * f64::from(u8::from(mjls)),
                6 => f64::from(u8::from(mjls)),
                _ => 0.0,
            };
            assert_eq!(
                diag(&e, f.diag_names(), "missing_inputs"),
                Some(expected),
                "{} step {k}",
                f.est().name()
            );
            assert!(e.segment.iter().all(|v| v.is_some()));
            assert!(e.joint.iter().all(|v| v.is_some()));
            assert!(is_spd(&f.p(), 0.0), "{} step {k}", f.est().name());
        }
        // Still on the right angles after the gap (the gap let the angles
        // drift by at most bias * 5 s = 0.05 rad, then the updates resume).
        let mut s = l.sample(1500);
        s.t += t_offset;
        let e = f.est().step(&s).unwrap();
        for i in 0..4 {
            assert!((e.segment[i].unwrap() - l.theta[i]).abs() < 0.06);
        }
    }
}

#[test]
fn a_segment_without_accelerometer_is_not_estimated() {
    // mjls starts the chain from the encoders (next test), so a segment
    // without an accelerometer is estimated there; local and global only.
    for mut f in AnyKf::all(first_sample_start()) {
        if f.est().name() == "mjls" {
            continue;
        }
        let mut l = limb(12);
        for k in 0..200 {
            let mut s = l.sample(k);
            s.imu[3].acc = None;
            let e = f.est().step(&s).unwrap();
            assert_eq!(e.segment[3], None);
            assert_eq!(e.joint[2], None);
            assert!(e.segment[..3].iter().all(|v| v.is_some()));
            assert!(e.joint[..2].iter().all(|v| v.is_some()));
            assert!(all_finite(&e));
        }
        // The foot accelerometer appears: the foot starts at its inclination.
        let s = l.sample(200);
        let th = s.imu[3].acc.map(|a| libm::atan2(a.x, a.y)).unwrap();
        let e = f.est().step(&s).unwrap();
        assert_eq!(e.segment[3], Some(th));
    }
}

#[test]
fn mjls_without_a_foot_accelerometer_estimates_the_foot_through_the_ankle_encoder() {
    let mut f = MarkovJumpKf::new(MarkovJumpKfParams {
        common: first_sample_start(),
        ..Default::default()
    })
    .unwrap();
    let mut l = limb(12);
    for k in 0..200 {
        let mut s = l.sample(k);
        s.imu[3].acc = None;
        let e = f.step(&s).unwrap();
        assert!(all_finite(&e));
        let (shank, foot) = (e.segment[2].unwrap(), e.segment[3].unwrap());
        // the ankle encoder row keeps shank - foot on the encoder
        assert!(
            (shank - foot - l.theta[2] + l.theta[3]).abs() < 0.01,
            "step {k}"
        );
    }
}

#[test]
fn mjls_starts_the_chain_from_the_most_reliable_accelerometer_and_the_encoders() {
    let mut f = MarkovJumpKf::new(MarkovJumpKfParams {
        common: first_sample_start(),
        ..Default::default()
    })
    .unwrap();
    let mut l = limb(13);
    let s = l.sample(0);
    let g = first_sample_start().gravity;
    let rho: Vec<f64> = s
        .imu
        .iter()
        .map(|m| (m.acc.unwrap().norm() - g).abs())
        .collect();
    let k = (0..4).min_by(|a, b| rho[*a].total_cmp(&rho[*b])).unwrap();
    let e = f.step(&s).unwrap();
    let a = s.imu[k].acc.unwrap();
    assert_eq!(e.segment[k], Some(libm::atan2(a.x, a.y)));
    for j in 0..3 {
        let enc = s.encoder[j].unwrap();
        let (p, d) = (e.segment[j].unwrap(), e.segment[j + 1].unwrap());
        assert!((p - d - enc).abs() < 1e-12, "joint {j}");
    }
    let names = f.diagnostic_names();
    for upd in ["upd_trunk", "upd_thigh", "upd_shank", "upd_foot"] {
        assert_eq!(diag(&e, names, upd), Some(0.0));
    }
}

#[test]
fn first_sample_initialises_from_the_accelerometer_without_update() {
    for mut f in AnyKf::all(first_sample_start()) {
        if f.est().name() == "mjls" {
            continue; // previous test
        }
        let mut l = limb(13);
        let s = l.sample(0);
        let e = f.est().step(&s).unwrap();
        let names = f.diag_names();
        for i in 0..4 {
            let a = s.imu[i].acc.unwrap();
            assert_eq!(e.segment[i], Some(libm::atan2(a.x, a.y)));
            let upd = ["upd_trunk", "upd_thigh", "upd_shank", "upd_foot"][i];
            assert_eq!(diag(&e, names, upd), Some(0.0));
            assert_eq!(
                diag(
                    &e,
                    names,
                    ["bias_trunk", "bias_thigh", "bias_shank", "bias_foot"][i]
                ),
                Some(0.0)
            );
        }
    }
}

#[test]
fn held_rate_over_gyro_dropouts_decays_as_a_second_order_process() {
    // No accelerometer update can happen (zeta tiny, rho = 0.5), so each
    // angle is the pure trapezoidal integral of the rate; over the dropout
    // the rate is predicted by a critically damped second-order model with
    // the correlation time HELD_RATE_CORRELATION_S
    // (issue 18, docs/ROBUST_INPUT.md; the papers hold it constant).
    let tau_c = limbfuse_estimators::segment_kf::robust::HELD_RATE_CORRELATION_S;
    let mut c = first_sample_start();
    for s in c.segments.iter_mut() {
        s.zeta = 1e-6;
    }
    for mut f in AnyKf::all(c) {
        let mut theta = 0.0;
        let mut prev = 0.2; // rate at the previous sample (held or measured)
        for k in 0..60 {
            let t = k as f64 * 0.01;
            let mut s = Sample::empty(t);
            // Rate 0.2 until k = 20, gyro missing for k = 20..40, then 0.5.
            let rate = if k < 20 {
                Some(0.2)
            } else if k < 40 {
                None
            } else {
                Some(0.5)
            };
            for imu in s.imu.iter_mut() {
                imu.acc = Some(Vector3::new(0.0, G + 0.5, 0.0));
                imu.gyr = rate.map(|r| Vector3::new(0.0, 0.0, r));
            }
            // the held value after tau = (k - 19) * 0.01 s without a reading
            // (critically damped second-order prediction, slope 0 before the
            // dropout, r e^(-tau / tau_c) (1 + tau / tau_c), up to tau_c / 4,
            // then a first-order decay)
            let tau = (k - 19) as f64 * 0.01;
            let second = |t: f64| 0.2 * (-t / tau_c).exp() * (1.0 + t / tau_c);
            let h = 0.25 * tau_c;
            let held = if tau <= h {
                second(tau)
            } else {
                second(h) * (-(tau - h) / tau_c).exp()
            };
            let r1 = rate.unwrap_or(held);
            if k > 0 {
                theta += 0.5 * (prev + r1) * 0.01;
            }
            prev = r1;
            let e = f.est().step(&s).unwrap();
            for i in 0..4 {
                assert!((e.segment[i].unwrap() - theta).abs() < 1e-12, "k {k}");
            }
        }
        // the held rate integrates to less than holding 0.2 would
        assert!(theta < 0.2 * 0.39 + 0.35 * 0.01 + 0.5 * 0.19);
    }
}

#[test]
fn non_increasing_time_is_rejected_and_leaves_the_state_alone() {
    for (mut f, mut g) in AnyKf::all(first_sample_start())
        .into_iter()
        .zip(AnyKf::all(first_sample_start()))
    {
        let mut l1 = limb(14);
        let mut l2 = limb(14);
        for k in 0..50 {
            let a = f.est().step(&l1.sample(k)).unwrap();
            let b = g.est().step(&l2.sample(k)).unwrap();
            assert_eq!(a, b);
        }
        let mut bad = Sample::empty(0.49);
        bad.imu[0].acc = Some(Vector3::new(5.0, 5.0, 0.0));
        assert!(f.est().step(&bad).is_err());
        bad.t = f64::NAN;
        assert!(f.est().step(&bad).is_err());
        for k in 50..100 {
            assert_eq!(
                f.est().step(&l1.sample(k)).unwrap(),
                g.est().step(&l2.sample(k)).unwrap()
            );
        }
        // reset = a fresh filter.
        f.est().reset();
        let mut h = AnyKf::all(first_sample_start());
        let name = f.name();
        let fresh = h.iter_mut().find(|x| x.name() == name).unwrap();
        let mut l3 = limb(15);
        let mut l4 = limb(15);
        for k in 0..30 {
            assert_eq!(
                f.est().step(&l3.sample(k)).unwrap(),
                fresh.est().step(&l4.sample(k)).unwrap()
            );
        }
    }
}

#[test]
fn angles_near_plus_minus_pi_do_not_jump() {
    // A segment upside down: the inclination flips between +pi and -pi
    // with the noise; the innovation is wrapped so the estimate does not.
    for mut f in AnyKf::all(first_sample_start()) {
        let mut l = limb(16);
        l.theta = [3.13, 3.13, 3.13, 3.13];
        l.gyro_bias = [0.0; 4];
        for k in 0..500 {
            let e = f.est().step(&l.sample(k)).unwrap();
            for i in 0..4 {
                let d = libm::remainder(e.segment[i].unwrap() - 3.13, core::f64::consts::TAU);
                assert!(
                    d.abs() < 0.05,
                    "{} k {k}: {}",
                    f.est().name(),
                    e.segment[i].unwrap()
                );
            }
        }
    }
}

#[test]
fn mjls_encoders_only_option_uses_the_encoders_when_no_imu_is_reliable() {
    for (opt, want) in [
        (WhenUnreliable::PredictOnly, 0.0),
        (WhenUnreliable::EncodersOnly, 1.0),
    ] {
        let mut f = MarkovJumpKf::new(MarkovJumpKfParams {
            when_unreliable: opt,
            common: first_sample_start(),
            ..Default::default()
        })
        .unwrap();
        let mut l = limb(17);
        f.step(&l.sample(0)).unwrap();
        let mut s = l.sample(1);
        for imu in s.imu.iter_mut() {
            imu.acc = imu.acc.map(|a| a * 1.2); // rho ~ 2 m/s^2: unreliable
        }
        let e = f.step(&s).unwrap();
        assert_eq!(e.diagnostic(MjlsDiag::Mode), Some(-1.0));
        for n in ["upd_hip", "upd_knee", "upd_ankle"] {
            assert_eq!(diag(&e, &MjlsDiag::NAMES, n), Some(want), "{opt:?}");
        }
        for n in ["upd_trunk", "upd_thigh", "upd_shank", "upd_foot"] {
            assert_eq!(diag(&e, &MjlsDiag::NAMES, n), Some(0.0));
        }
    }
}

#[test]
fn gain_shares_are_fractions_and_local_has_only_its_own_rows() {
    for mut f in AnyKf::all(first_sample_start()) {
        let names = f.diag_names();
        let mut l = limb(18);
        let mut seen = false;
        for k in 0..300 {
            let e = f.est().step(&l.sample(k)).unwrap();
            for seg in ["trunk", "thigh", "shank", "foot"] {
                let own = diag(&e, names, &format!("share_own_{seg}"));
                let other = diag(&e, names, &format!("share_other_{seg}"));
                let joint = diag(&e, names, &format!("share_joint_{seg}"));
                if let (Some(a), Some(b), Some(c)) = (own, other, joint) {
                    seen = true;
                    assert!((a + b + c - 1.0).abs() < 1e-12);
                    assert!(a >= 0.0 && b >= 0.0 && c >= 0.0);
                    if let AnyKf::Local(_) = f {
                        assert_eq!((a, b, c), (1.0, 0.0, 0.0));
                    }
                } else {
                    assert_eq!((own, other, joint), (None, None, None));
                }
            }
        }
        assert!(seen);
    }
}

/// A long run with random step lengths, dropouts and reliability patterns:
/// every covariance stays exactly symmetric and positive definite, for the
/// default and the paper-2014 parameters, Joseph and standard forms.
#[test]
fn covariances_stay_spd_over_a_long_random_run() {
    let mut paper_std = CommonParams::paper_2014();
    paper_std.covariance_update = limbfuse_core::kalman::CovarianceUpdate::Standard;
    for common in [first_sample_start(), CommonParams::paper_2014(), paper_std] {
        for mut f in AnyKf::all(common) {
            let mut rng = Rng::new(99);
            let mut t = 0.0;
            for k in 0..20_000 {
                t += [0.001, 0.01, 0.02, 0.5][(rng.next_u64() % 4) as usize];
                let s = random_sample(&mut rng, t);
                let e = f.est().step(&s).unwrap();
                assert!(all_finite(&e));
                assert!(is_spd(&f.p(), 0.0), "{} step {k}", f.est().name());
            }
        }
    }
}

fn random_sample(rng: &mut Rng, t: f64) -> Sample {
    let mut s = Sample::empty(t);
    for imu in s.imu.iter_mut() {
        let th = 0.5 * rng.normal();
        let dynamic = [0.0, 0.05, 0.3, 2.0][(rng.next_u64() % 4) as usize] * rng.normal();
        if rng.uniform() > 0.1 {
            imu.acc = Some(Vector3::new(
                G * th.sin(),
                (G + dynamic) * th.cos(),
                0.1 * rng.normal(),
            ));
        }
        if rng.uniform() > 0.1 {
            imu.gyr = Some(Vector3::new(0.0, 0.0, 2.0 * rng.normal()));
        }
    }
    for e in s.encoder.iter_mut() {
        if rng.uniform() > 0.1 {
            *e = Some(0.5 * rng.normal());
        }
    }
    s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// 001 after eq 29: in the matricial local model K (and P) stay block
    /// diagonal, exactly: no segment's row ever touches another segment.
    #[test]
    fn local_gain_stays_block_diagonal(seed in any::<u64>(), s in 1u8..=4, n in 1usize..400) {
        let mut f = LocalKf::new(LocalKfParams { min_reliable: s, ..Default::default() }).unwrap();
        let mut rng = Rng::new(seed);
        let mut t = 0.0;
        for _ in 0..n {
            t += 0.001 + 0.05 * rng.uniform();
            f.step(&random_sample(&mut rng, t)).unwrap();
            let k = f.last_gain();
            let p = f.covariance();
            for r in 0..8 {
                for c in 0..4 {
                    if r / 2 != c {
                        prop_assert_eq!(k[(r, c)], 0.0);
                    }
                }
                for c in 0..8 {
                    if r / 2 != c / 2 {
                        prop_assert_eq!(p[(r, c)], 0.0);
                    }
                }
            }
        }
    }

    /// Symmetric positive-definite covariances for all three filters under
    /// random data, step lengths, dropouts and reliability.
    #[test]
    fn covariances_stay_spd(seed in any::<u64>(), n in 1usize..600, euler in any::<bool>()) {
        let mut c = first_sample_start();
        if euler {
            c.discretization = limbfuse_core::discretize::Discretization::Euler;
        }
        for mut f in AnyKf::all(c) {
            let mut rng = Rng::new(seed);
            let mut t = 0.0;
            for _ in 0..n {
                t += 0.001 + 0.1 * rng.uniform();
                let e = f.est().step(&random_sample(&mut rng, t)).unwrap();
                prop_assert!(all_finite(&e));
                prop_assert!(is_spd(&f.p(), 0.0));
            }
        }
    }
}

/// The default parameters with the start of limbfuse before 2026-12-06 (each
/// segment at its first accelerometer sample): these tests check what
/// follows a start placed on their first sample
/// (the start itself: tests/integration/segment_kf_mid_walk_start.rs).
pub(crate) fn first_sample_start() -> CommonParams {
    CommonParams {
        first_sample_start: true,
        ..CommonParams::default()
    }
}
