//! Issue 16 item 1, fixed hip: the model with the four muscle activations
//! as states. Its SDC factorisation reproduces `f` and `h` (`A(x) x + B(x)
//! u = f(x, u)`, `C(x) x = h(x)`), its analytic Jacobians match central
//! differences, the activation rows are `(u - a) / T_a`, and with `a = u`
//! the mechanics are the fixed-hip model's.

use limbfuse_models::{
    FixedHipActivationModel, FixedHipModel, FixedHipParams, ModelError, SdcModel, FIXED_HIP_T_A,
};
use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;

fn model(t_a: f64) -> FixedHipActivationModel {
    FixedHipActivationModel::new(FixedHipModel::new(FixedHipParams::default()).unwrap(), t_a)
        .unwrap()
}

fn fd_jacobian<const N: usize, const M: usize>(
    g: impl Fn(&SVector<f64, N>) -> SVector<f64, M>,
    x: &SVector<f64, N>,
) -> SMatrix<f64, M, N> {
    let mut j = SMatrix::<f64, M, N>::zeros();
    for k in 0..N {
        let h = 1e-6 * (1.0 + x[k].abs());
        let (mut xp, mut xm) = (*x, *x);
        xp[k] += h;
        xm[k] -= h;
        j.set_column(k, &((g(&xp) - g(&xm)) / (2.0 * h)));
    }
    j
}

fn close<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    tol: f64,
) -> bool {
    (a - b).iter().all(|d| d.abs() <= tol * (1.0 + b.amax()))
}

fn angle() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), -1e-5..1e-5f64, -1e-3..1e-3f64, -1.6..1.6f64]
}

fn state(q: [f64; 4], a: [f64; 4]) -> SVector<f64, 8> {
    SVector::<f64, 8>::from_row_slice(&[q[0], q[1], q[2], q[3], a[0], a[1], a[2], a[3]])
}

fn input(u: [f64; 4], tau: [f64; 2]) -> SVector<f64, 6> {
    SVector::<f64, 6>::from_row_slice(&[u[0], u[1], u[2], u[3], tau[0], tau[1]])
}

proptest! {
    #[test]
    fn sdc_reproduces_f_and_h(
        x1 in angle(), x2 in angle(), x3 in -5.0..5.0f64, x4 in -8.0..8.0f64,
        a in proptest::array::uniform4(0.0..1.0f64), u in proptest::array::uniform4(0.0..1.0f64),
        tau in proptest::array::uniform2(-30.0..30.0f64), t_a in 0.05..1.5f64,
    ) {
        let m = model(t_a);
        let x = state([x1, x2, x3, x4], a);
        let u = input(u, tau);
        let f = m.f(&x, &u);
        let sdc = m.sdc_a(&x) * x + m.input_term(&x, &u);
        prop_assert!(close(&sdc, &f, 1e-12), "A x + B u = {sdc:?}, f = {f:?}");
        prop_assert!(close(&(m.sdc_c(&x) * x), &m.h(&x), 1e-14));
    }

    #[test]
    fn jacobians_match_finite_differences(
        x1 in -1.0..1.0f64, x2 in -1.5..1.0f64, x3 in -4.0..4.0f64, x4 in -6.0..6.0f64,
        a in proptest::array::uniform4(0.0..1.0f64), u in proptest::array::uniform4(0.0..1.0f64),
        tau in proptest::array::uniform2(-30.0..30.0f64), t_a in 0.05..1.5f64,
    ) {
        let m = model(t_a);
        let x = state([x1, x2, x3, x4], a);
        let u = input(u, tau);
        let fd = fd_jacobian(|x| m.f(x, &u), &x);
        let an = m.jacobian_f(&x, &u);
        prop_assert!(close(&an, &fd, 1e-6), "{an:?} vs {fd:?}");
        prop_assert!(close(&m.jacobian_h(&x), &fd_jacobian(|x| m.h(x), &x), 1e-7));
    }
}

#[test]
fn activation_rows_and_mechanics_at_a_equal_u() {
    let m = model(0.2);
    let u = input([0.1, 0.2, 0.3, 0.4], [5.0, -3.0]);
    let x = state([0.3, -0.2, 1.0, -2.0], [0.5, 0.0, 0.3, 0.9]);
    let f = m.f(&x, &u);
    for (i, want) in [(0.1 - 0.5) / 0.2, 0.2 / 0.2, 0.0, (0.4 - 0.9) / 0.2]
        .into_iter()
        .enumerate()
    {
        assert!((f[4 + i] - want).abs() < 1e-15, "a'_{i} = {}", f[4 + i]);
    }
    // With a = u the joint accelerations are the thesis model's.
    let q = SVector::<f64, 4>::new(0.3, -0.2, 1.0, -2.0);
    let x = state([0.3, -0.2, 1.0, -2.0], [0.1, 0.2, 0.3, 0.4]);
    let f4 = m.base.f(&q, &u);
    let f8 = m.f(&x, &u);
    for i in 0..4 {
        assert!((f8[i] - f4[i]).abs() < 1e-12, "{i}: {} vs {}", f8[i], f4[i]);
    }
    assert_eq!(FIXED_HIP_T_A, 0.25);
}

#[test]
fn non_positive_t_a_is_refused() {
    let base = FixedHipModel::new(FixedHipParams::default()).unwrap();
    for t in [0.0, -0.1, f64::NAN] {
        let e = FixedHipActivationModel::new(base, t).unwrap_err();
        assert!(
            matches!(
                e,
                ModelError::NotPositive { name: "t_a", .. }
                    | ModelError::NonFinite { name: "t_a", .. }
            ),
            "{e}"
        );
    }
}
