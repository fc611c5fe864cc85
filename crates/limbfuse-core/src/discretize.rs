//! Continuous-to-discrete conversion of `dx = A x dt + B dw`.
//!
//! SPEC section 6: paper 000 eq 19 (`G = A^-1 (Phi - I) B`) is undefined
//! because `A` is singular, so limbfuse uses the exact discretisation
//! `Phi = expm(A T)` with `Qd` by Van Loan's method (C. F. Van Loan,
//! "Computing integrals involving the matrix exponential", IEEE TAC 23(3),
//! 1978) by default, and offers the papers' first-order form
//! `Phi = I + A T`, `Qd = B Q B^T T` as [`Discretization::Euler`].
#![allow(non_snake_case)]

use nalgebra::SMatrix;

/// Discretisation method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Discretization {
    /// `Phi = expm(A T)`, `Qd = int_0^T expm(A s) Qc expm(A^T s) ds` (Van Loan).
    #[default]
    Exact,
    /// `Phi = I + A T`, `Qd = Qc T` (first order).
    Euler,
}

/// Discretises `A` and the continuous noise intensity `Qc = B Q B^T` over `T` seconds.
///
/// `N2` must be `2 * N` (the size of Van Loan's block matrix); this is checked
/// at compile time. Returns `(Phi, Qd)`, `Qd` symmetrised. Non-finite `A`,
/// `Qc` or `T` yield non-finite outputs rather than a panic.
pub fn discretize<const N: usize, const N2: usize>(
    A: &SMatrix<f64, N, N>,
    Qc: &SMatrix<f64, N, N>,
    T: f64,
    method: Discretization,
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    const { assert!(N2 == 2 * N, "discretize: N2 must equal 2 * N") };
    match method {
        Discretization::Euler => (SMatrix::identity() + A * T, Qc * T),
        Discretization::Exact => {
            // Van Loan: M = [[-A, Qc], [0, A^T]] T, expm(M) = [[., Phi^-1 Qd], [0, Phi^T]].
            let mut M = SMatrix::<f64, N2, N2>::zeros();
            M.fixed_view_mut::<N, N>(0, 0).copy_from(&(-A * T));
            M.fixed_view_mut::<N, N>(0, N).copy_from(&(Qc * T));
            M.fixed_view_mut::<N, N>(N, N)
                .copy_from(&(A.transpose() * T));
            let E = crate::expm::expm(&M).unwrap_or_else(SMatrix::identity);
            let Phi: SMatrix<f64, N, N> = E.fixed_view::<N, N>(N, N).transpose();
            let Qd = Phi * E.fixed_view::<N, N>(0, N);
            (Phi, crate::kalman::symmetrize(&Qd))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    /// Paper 000 eq 8 model: x = [dtheta, db], A = [[0, 1], [0, -1/tau]],
    /// Qc = diag(q_g, q_b). Closed forms (hand-derived, a = 1/tau, e = exp(-a T)):
    /// Phi = [[1, (1 - e)/a], [0, e]];
    /// Qd_22 = q_b (1 - e^2) / (2 a);
    /// Qd_12 = q_b / a * [ (1 - e)/a - (1 - e^2)/(2a) ];
    /// Qd_11 = q_g T + q_b / a^2 * [ T - 2 (1 - e)/a + (1 - e^2)/(2a) ].
    #[test]
    fn van_loan_matches_closed_form_for_gyro_bias_model() {
        let (tau, qg, qb, T) = (30.0_f64, 3e-4, 2e-6, 0.01);
        let a = 1.0 / tau;
        let A = Matrix2::new(0.0, 1.0, 0.0, -a);
        let Qc = Matrix2::new(qg, 0.0, 0.0, qb);
        let (Phi, Qd) = discretize::<2, 4>(&A, &Qc, T, Discretization::Exact);
        let e = (-a * T).exp();
        let phi12 = (1.0 - e) / a;
        assert!((Phi[(0, 0)] - 1.0).abs() < 1e-14);
        assert!((Phi[(0, 1)] - phi12).abs() < 1e-14);
        assert!((Phi[(1, 1)] - e).abs() < 1e-14);
        assert!(Phi[(1, 0)].abs() < 1e-14);
        let q22 = qb * (1.0 - e * e) / (2.0 * a);
        let q12 = qb / a * ((1.0 - e) / a - (1.0 - e * e) / (2.0 * a));
        let q11 = qg * T + qb / (a * a) * (T - 2.0 * (1.0 - e) / a + (1.0 - e * e) / (2.0 * a));
        assert!(
            (Qd[(1, 1)] - q22).abs() < 1e-18,
            "{} vs {}",
            Qd[(1, 1)],
            q22
        );
        assert!((Qd[(0, 1)] - q12).abs() < 1e-18);
        assert!((Qd[(0, 0)] - q11).abs() < 1e-16);
        assert_eq!(Qd[(0, 1)], Qd[(1, 0)]);
    }

    #[test]
    fn euler_is_first_order_form() {
        let A = Matrix2::new(0.0, 1.0, 0.0, -0.5);
        let Qc = Matrix2::new(1.0, 0.0, 0.0, 2.0);
        let (Phi, Qd) = discretize::<2, 4>(&A, &Qc, 0.1, Discretization::Euler);
        assert_eq!(Phi, Matrix2::new(1.0, 0.1, 0.0, 0.95));
        assert_eq!(Qd, Matrix2::new(0.1, 0.0, 0.0, 0.2));
    }

    #[test]
    fn exact_and_euler_converge_for_small_steps() {
        let A = Matrix2::new(0.0, 1.0, 0.0, -0.5);
        let Qc = Matrix2::new(1.0, 0.0, 0.0, 2.0);
        let (p1, q1) = discretize::<2, 4>(&A, &Qc, 1e-4, Discretization::Exact);
        let (p2, q2) = discretize::<2, 4>(&A, &Qc, 1e-4, Discretization::Euler);
        assert!((p1 - p2).norm() < 1e-8);
        assert!((q1 - q2).norm() < 1e-7);
    }
}
