//! Property tests: covariances stay symmetric positive definite through
//! predict/update cycles, with both covariance forms, and the masked update
//! never lets an inactive row move the state.
#![allow(non_snake_case)]

use limbfuse_core::discretize::{discretize, Discretization};
use limbfuse_core::kalman::{predict, update, update_rows, CovarianceUpdate};
use nalgebra::{SMatrix, SVector};
use proptest::prelude::*;

fn spd4(v: &[f64]) -> SMatrix<f64, 4, 4> {
    let L = SMatrix::<f64, 4, 4>::from_iterator(v.iter().copied());
    L * L.transpose() + SMatrix::identity() * 1e-3
}

fn is_spd<const N: usize>(P: &SMatrix<f64, N, N>) -> bool {
    (P - P.transpose()).norm() <= 1e-12 * P.norm().max(1.0) && P.cholesky().is_some()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn covariance_stays_spd_over_many_cycles(
        p0 in prop::collection::vec(-1.0f64..1.0, 16),
        h in prop::collection::vec(-1.0f64..1.0, 12),
        r in prop::collection::vec(1e-4f64..1.0, 3),
        tau in 0.5f64..100.0,
        dt in 1e-3f64..0.05,
        joseph in any::<bool>(),
        mask in prop::collection::vec(any::<bool>(), 3 * 50),
    ) {
        // Two decoupled angle/bias error models (paper 000 eq 8), four states.
        let mut A = SMatrix::<f64, 4, 4>::zeros();
        A[(0, 1)] = 1.0; A[(1, 1)] = -1.0 / tau;
        A[(2, 3)] = 1.0; A[(3, 3)] = -1.0 / tau;
        let Qc = SMatrix::<f64, 4, 4>::from_diagonal(&SVector::from([1e-4, 1e-6, 1e-4, 1e-6]));
        let (Phi, Qd) = discretize::<4, 8>(&A, &Qc, dt, Discretization::Exact);
        let H = SMatrix::<f64, 3, 4>::from_iterator(h.iter().copied());
        let R = SMatrix::<f64, 3, 3>::from_diagonal(&SVector::from([r[0], r[1], r[2]]));
        let form = if joseph { CovarianceUpdate::Joseph } else { CovarianceUpdate::Standard };
        let mut x = SVector::<f64, 4>::zeros();
        let mut P = spd4(&p0);
        for k in 0..50 {
            let (xp, Pp) = predict(&x, &P, &Phi, &Qd);
            prop_assert!(is_spd(&Pp), "prior not SPD at step {k}: {Pp}");
            let active = [mask[3 * k], mask[3 * k + 1], mask[3 * k + 2]];
            let z = SVector::<f64, 3>::new(0.01 * k as f64, -0.02, 0.005);
            let u = update_rows(&xp, &Pp, &z, &H, &R, &active, form).unwrap();
            for (i, on) in active.iter().enumerate() {
                if !on { prop_assert_eq!(u.K.column(i).norm(), 0.0); }
            }
            // The Joseph form keeps SPD unconditionally; the standard form is
            // only guaranteed for well-conditioned problems, so check Joseph strictly.
            if joseph { prop_assert!(is_spd(&u.P), "posterior not SPD at step {k}: {}", u.P); }
            x = u.x;
            P = if joseph { u.P } else { limbfuse_core::kalman::symmetrize(&u.P) };
        }
    }

    #[test]
    fn update_never_increases_variance(
        p0 in prop::collection::vec(-1.0f64..1.0, 16),
        h in prop::collection::vec(-1.0f64..1.0, 4),
        r in 1e-6f64..10.0,
    ) {
        let P = spd4(&p0);
        let H = SMatrix::<f64, 1, 4>::from_iterator(h.iter().copied());
        let R = SMatrix::<f64, 1, 1>::new(r);
        let u = update(&SVector::zeros(), &P, &SVector::<f64, 1>::new(1.0), &H, &R, CovarianceUpdate::Joseph).unwrap();
        for i in 0..4 {
            prop_assert!(u.P[(i, i)] <= P[(i, i)] * (1.0 + 1e-12) + 1e-15);
        }
    }
}
