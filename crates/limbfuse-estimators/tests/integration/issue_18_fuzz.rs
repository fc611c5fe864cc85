//! Issue 18 item 3 (first part): fuzz-style property tests of the segment
//! filters' `step` and of the sample gate under arbitrary and adversarial
//! input: extreme, non-finite and missing readings, time steps from
//! microseconds to hours, and timestamps that go backwards. Never a panic;
//! a non-increasing time is a typed error; every output is finite or
//! missing; the covariance stays symmetric positive semi-definite.

use limbfuse_core::{Estimator, Sample, SampleGate, SensorRanges};
use limbfuse_estimators::segment_kf::{GlobalKf, LocalKf, MarkovJumpKf};
use nalgebra::{SMatrix, Vector3};
use proptest::prelude::*;

/// Adversarial cell values: ordinary readings mixed with the values that
/// broke filters before (1e300, -1e308, NaN, infinities, subnormals).
fn cell() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![
        4 => (-20.0..20.0f64).prop_map(Some),
        1 => prop::sample::select(vec![
            1e300, -1e308, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 5e-324, -0.0, 9.81, 34.906585,
            156.9, 1e9,
        ])
        .prop_map(Some),
        1 => Just(None),
    ]
}

fn vec3() -> impl Strategy<Value = Option<Vector3<f64>>> {
    (cell(), cell(), cell()).prop_map(|(x, y, z)| Some(Vector3::new(x?, y?, z?)))
}

/// Time steps: tiny, ordinary, long gaps, zero and backwards.
fn step() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => Just(0.01),
        1 => 1e-6..0.5f64,
        1 => prop::sample::select(vec![0.0, -0.01, 2.0, 3600.0, 1e-9]),
    ]
}

/// One fuzzed row: time step, four accelerometers then four gyroscopes,
/// three encoders.
type Row = (f64, [Option<Vector3<f64>>; 8], [Option<f64>; 3]);

fn sample() -> impl Strategy<Value = Row> {
    (
        step(),
        prop::array::uniform8(vec3()),
        prop::array::uniform3(cell()),
    )
}

/// Symmetric, and `P + 1e-9 I` has a Cholesky factor (PSD to round-off).
fn symmetric_psd(p: &SMatrix<f64, 8, 8>) -> bool {
    let sym = (0..8).all(|r| {
        (0..8).all(|c| {
            p[(r, c)] == p[(c, r)]
                || (p[(r, c)] - p[(c, r)]).abs() <= 1e-12 * p[(r, r)].abs().max(1.0)
        })
    });
    sym && (p + SMatrix::<f64, 8, 8>::identity() * 1e-9)
        .cholesky()
        .is_some()
}

fn run_filter<F: Estimator>(
    f: &mut F,
    cov: impl Fn(&F) -> SMatrix<f64, 8, 8>,
    rows: &[Row],
    gate: bool,
) -> Result<(), TestCaseError> {
    let mut g = SampleGate::new(SensorRanges::default());
    let mut t = 0.0;
    let mut last_ok: Option<f64> = None;
    for (dt, imus, enc) in rows {
        t += dt;
        let mut s = Sample::empty(t);
        for i in 0..4 {
            s.imu[i].acc = imus[i];
            s.imu[i].gyr = imus[4 + i];
        }
        s.encoder = *enc;
        let s = if gate { g.screen(&s) } else { s };
        match f.step(&s) {
            Ok(e) => {
                prop_assert!(last_ok.is_none_or(|l| t > l));
                last_ok = Some(t);
                for v in e.segment.iter().chain(e.joint.iter()).flatten() {
                    prop_assert!(v.is_finite(), "output {v}");
                }
                for v in e.diag.iter().flatten() {
                    prop_assert!(v.is_finite(), "diagnostic {v}");
                }
                prop_assert!(symmetric_psd(&cov(f)), "P = {}", cov(f));
            }
            // the only error: time that does not increase
            Err(_) => prop_assert!(last_ok.is_some_and(|l| t <= l)),
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn issue_18_segment_filters_survive_arbitrary_input(
        rows in prop::collection::vec(sample(), 1..120),
        gate in any::<bool>(),
    ) {
        run_filter(&mut LocalKf::default(), |f| *f.covariance(), &rows, gate)?;
        run_filter(&mut MarkovJumpKf::default(), |f| *f.covariance(), &rows, gate)?;
        run_filter(&mut GlobalKf::default(), |f| *f.covariance(), &rows, gate)?;
    }

    /// Whatever goes in, what the gate lets through is finite and in range.
    #[test]
    fn issue_18_the_gate_passes_only_finite_in_range_readings(
        rows in prop::collection::vec(sample(), 1..60),
    ) {
        let r = SensorRanges::default();
        let mut g = SampleGate::new(r);
        let mut t = 0.0;
        for (dt, imus, enc) in &rows {
            t += dt;
            let mut s = Sample::empty(t);
            for i in 0..4 {
                s.imu[i].acc = imus[i];
                s.imu[i].gyr = imus[4 + i];
            }
            s.encoder = *enc;
            let out = g.screen(&s);
            for imu in &out.imu {
                for v in imu.acc.iter().flat_map(|a| a.iter()) {
                    prop_assert!(v.is_finite() && v.abs() <= r.acc_m_s2);
                }
                for v in imu.gyr.iter().flat_map(|a| a.iter()) {
                    prop_assert!(v.is_finite() && v.abs() <= r.gyro_rad_s);
                }
            }
            for v in out.encoder.iter().flatten() {
                prop_assert!(v.is_finite() && v.abs() <= r.encoder_rad);
            }
        }
    }
}

/// Corpus: the case the fuzz test found. An accelerometer axis of 1e300 is
/// finite, but its norm overflows: `rho` was an infinite diagnostic. Such a
/// reading now counts as missing inside the segment filters too.
#[test]
fn issue_18_corpus_an_overflowing_accelerometer_norm_is_no_reading() {
    let mut f = MarkovJumpKf::default();
    let mut s = Sample::empty(0.0);
    for imu in s.imu.iter_mut() {
        imu.acc = Some(Vector3::new(0.0, 9.81, 0.0));
        imu.gyr = Some(Vector3::zeros());
    }
    s.encoder = [Some(0.0); 3];
    f.step(&s).unwrap();
    s.t = 0.01;
    s.imu[2].acc = Some(Vector3::new(1e300, 1e300, 0.0));
    let e = f.step(&s).unwrap();
    assert!(e.diag.iter().flatten().all(|v| v.is_finite()));
    assert!(e.segment.iter().flatten().all(|v| v.is_finite()));
}

/// Corpus: encoders of -1e308 at the first sample started the MJLS chain
/// at an infinite angle (the sample gate removes them first; the filter
/// alone must not fail either).
#[test]
fn issue_18_corpus_huge_encoders_do_not_start_the_chain_at_infinity() {
    let mut f = MarkovJumpKf::default();
    let mut s = Sample::empty(0.0);
    for imu in s.imu.iter_mut() {
        imu.acc = Some(Vector3::zeros());
        imu.gyr = Some(Vector3::zeros());
    }
    s.imu[2].acc = Some(Vector3::new(0.0, 34.906585, 0.0));
    s.encoder = [Some(0.0), Some(-1e308), Some(-1e308)];
    let e = f.step(&s).unwrap();
    assert!(e
        .segment
        .iter()
        .chain(e.joint.iter())
        .flatten()
        .all(|v| v.is_finite()));
}
