//! The measurement update of the segment chain (000 eqs 23-25) as a
//! sequence of scalar updates, one per active row.
//!
//! `R` is diagonal in all three models (000 eq 27, 001 eq 22), so the rows
//! are independent measurements and processing them one after the other is
//! exact (the batch update's `S^-1` factors into the scalar pivots of its
//! Cholesky factorisation). Per row `h` (a segment's angle error `e_a` or a
//! joint's `e_a - e_b`, see [`ChainRow`]), with `v = P h` a column of `P` or
//! the difference of two, `s = h v + r`, the gain `k = v / s`:
//!
//! * innovation `e' = e - h dx` (`e = z - H x` of the batch update, `dx` the
//!   correction so far), correction `dx += k e'`;
//! * covariance `P <- P - w w^T` with `w = v / sqrt(s)`: the Joseph form
//!   `(I - k h) P (I - k h)^T + k r k^T` expands to `P - k v^T - v k^T + s
//!   k k^T`, which for the optimal gain `k = v / s` is `P - v v^T / s`
//!   (algebraically identical). Written as `w w^T` every entry `(a, b)`
//!   is the same product `w_a w_b` as `(b, a)`, so `P` stays exactly
//!   symmetric with no symmetrising pass; it is a rank-1 downdate of 64
//!   multiply-subtracts instead of the batch form's products with the
//!   `8 x m` gain. (Updating the upper triangle only and mirroring it was
//!   measured slower: its loops do not vectorise.)
//!
//! The batch gain, which [`Gain::K`] reports (the gain-share diagnostics of
//! 001 Fig. 6 are defined on it, [`super::gain_shares`]), is recovered from
//! the updated covariance: `K = P+ H^T R^-1` (000 eq 24 with eq 25:
//! `P+ = (I - K H) P-` and `K = P- H^T S^-1` give `P+ H^T R^-1 = P- H^T
//! (I - S^-1 H P- H^T) R^-1 = P- H^T S^-1 (S - H P- H^T) R^-1 = K`), a
//! column of `P+` or the difference of two, divided by `r`.
//!
//! Equal to the dense Joseph-form batch update of
//! [`limbfuse_core::kalman::update_rows`] to round-off (property tests
//! below). Nothing allocates.
#![allow(non_snake_case)]
// Index loops mirror the matrix algebra (rows, columns) one to one.
#![allow(clippy::needless_range_loop)]

use limbfuse_core::kalman::KalmanError;
use nalgebra::SVector;

use super::model::{angle_state, Mat8};
use super::structured::{all_finite, ChainRow, Gain};

/// Measurement update (000 eqs 23-25, Joseph form in its rank-1 equivalent,
/// module docs) on the active `rows`, with diagonal measurement noise `r`
/// (variances) and innovations `innovation = z - H x` (formed by the caller,
/// e.g. with angle wrapping), applied to `x` and `P` in place, one row after
/// the other. Inactive rows have a zero gain column and innovation. With no
/// active row nothing changes and the gain is zero.
///
/// Fails, leaving `x` and `P` untouched, when a pivot `s = h P h^T + r`
/// is not positive (exactly when the batch `S = H P H^T + R` is not
/// positive definite) or the result is not finite.
/// The gain is written into `gain` (no copy of it on the way out: the
/// filters keep it for their `last_gain`); after a failure `gain` holds no
/// meaningful value.
pub fn update_rows_into<const M: usize>(
    x: &mut SVector<f64, 8>,
    P: &mut Mat8,
    innovation: &SVector<f64, M>,
    rows: &[ChainRow; M],
    r: &[f64; M],
    active: &[bool; M],
    gain: &mut Gain<M>,
) -> Result<(), KalmanError> {
    gain.K.fill(0.0);
    gain.innovation.fill(0.0);
    if !active.iter().any(|&a| a) {
        return Ok(());
    }
    // Column-major and symmetric: p[t] is column t of P and also its row t.
    let mut p: [[f64; 8]; 8] = P.data.0;
    let mut dx = [0.0f64; 8];
    for c in 0..M {
        if !active[c] {
            continue;
        }
        let row = rows[c];
        let a = angle_state(row.plus);
        let mut v = p[a];
        let (hv, hdx) = match row.minus {
            Some(m) => {
                let b = angle_state(m);
                let pb = p[b];
                for t in 0..8 {
                    v[t] -= pb[t];
                }
                (v[a] - v[b], dx[a] - dx[b])
            }
            None => (v[a], dx[a]),
        };
        let s = hv + r[c];
        if !(s.is_finite() && s > 0.0) {
            return Err(KalmanError::InnovationNotPositiveDefinite);
        }
        let ke = (innovation[c] - hdx) / s;
        let inv_sqrt = 1.0 / libm::sqrt(s);
        let mut w = [0.0f64; 8];
        for t in 0..8 {
            dx[t] += v[t] * ke;
            w[t] = v[t] * inv_sqrt;
        }
        for (col, wb) in p.iter_mut().zip(w) {
            for t in 0..8 {
                col[t] -= w[t] * wb;
            }
        }
        gain.innovation[c] = innovation[c];
    }
    // K = P+ H^T R^-1, column by column.
    for c in 0..M {
        if !active[c] {
            continue;
        }
        let row = rows[c];
        let inv_r = 1.0 / r[c];
        let pa = &p[angle_state(row.plus)];
        let mut col = SVector::<f64, 8>::zeros();
        match row.minus {
            Some(m) => {
                let pb = &p[angle_state(m)];
                for t in 0..8 {
                    col[t] = (pa[t] - pb[t]) * inv_r;
                }
            }
            None => {
                for t in 0..8 {
                    col[t] = pa[t] * inv_r;
                }
            }
        }
        gain.K.set_column(c, &col);
    }
    if !(all_finite(&dx) && all_finite(p.as_flattened()) && all_finite(gain.K.as_slice())) {
        return Err(KalmanError::InnovationNotPositiveDefinite);
    }
    for t in 0..8 {
        x[t] += dx[t];
    }
    P.data.0 = p;
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::segment_kf::gain_shares::{gain_shares, RowKind};
    use crate::segment_kf::model::{GLOBAL_ROWS, LOCAL_ROWS};
    use crate::segment_kf::structured::dense_output_matrix;
    use limbfuse_core::kalman::{self, CovarianceUpdate};
    use nalgebra::SMatrix;
    use proptest::prelude::*;

    /// `B B^T + 0.1 I`, symmetric positive definite, from a lower-triangular
    /// `B` filled from the seed.
    pub(crate) fn spd(seed: &[f64; 36]) -> Mat8 {
        let mut B = Mat8::zeros();
        let mut k = 0;
        for i in 0..8 {
            for j in 0..=i {
                B[(i, j)] = seed[k % 36];
                k += 1;
            }
        }
        B * B.transpose() + Mat8::identity() * 0.1
    }

    /// A random update of the global rows: `P` (from `seed`, `extra`), `x`,
    /// the active rows (bits of `mask`), innovations `e`, `H`, `R = diag(r)`
    /// and `z = e + H x`.
    #[allow(clippy::type_complexity)]
    pub(crate) fn global_case(
        seed: &[f64; 32],
        extra: &[f64; 4],
        r: &[f64; 7],
        e: &[f64; 7],
        x: &[f64; 8],
        mask: u32,
    ) -> (
        Mat8,
        SVector<f64, 8>,
        [bool; 7],
        SVector<f64, 7>,
        SMatrix<f64, 7, 8>,
        SMatrix<f64, 7, 7>,
        SVector<f64, 7>,
    ) {
        let mut s36 = [0.0; 36];
        s36[..32].copy_from_slice(seed);
        s36[32..].copy_from_slice(extra);
        let x = SVector::<f64, 8>::from_column_slice(x);
        let innov = SVector::<f64, 7>::from_column_slice(e);
        let H = dense_output_matrix(&GLOBAL_ROWS);
        let R = SMatrix::<f64, 7, 7>::from_diagonal(&SVector::from_column_slice(r));
        let active = core::array::from_fn(|k| mask & (1 << k) != 0);
        (spd(&s36), x, active, innov, H, R, innov + H * x)
    }

    /// The inputs of [`global_case`] (and the row variances `r`): a seed and
    /// extra seed of `P`, `r`, innovations, state, row mask.
    #[allow(clippy::type_complexity)]
    pub(crate) fn global_inputs(
    ) -> impl Strategy<Value = ([f64; 32], [f64; 4], [f64; 7], [f64; 7], [f64; 8], u32)> {
        (
            prop::array::uniform32(-1.0f64..1.0),
            prop::array::uniform4(-1.0f64..1.0),
            prop::array::uniform7(0.01f64..2.0),
            prop::array::uniform7(-0.5f64..0.5),
            prop::array::uniform8(-0.3f64..0.3),
            0u32..128,
        )
    }

    /// Whether the symmetric `P` is positive semi-definite (eigenvalues of
    /// at least `-tol`).
    fn psd(P: &Mat8, tol: f64) -> bool {
        P.symmetric_eigenvalues().iter().all(|&l| l >= -tol)
    }

    proptest! {
        /// The sequential update equals the dense Joseph-form batch update
        /// (`kalman::update_rows`) for every row mask on random SPD `P`: the
        /// state, the covariance, the batch gain recovered as `P+ H^T R^-1`,
        /// and the gain shares of 001 Fig. 6 computed from that gain (to
        /// 1e-12). `P` stays exactly symmetric and positive semi-definite.
        #[test]
        fn sequential_update_equals_dense_joseph(
            (seed, extra, r, e, x, mask) in global_inputs(),
        ) {
            let (P, x, active, innov, _, R, z) = global_case(&seed, &extra, &r, &e, &x, mask);
            let H = dense_output_matrix(&GLOBAL_ROWS);
            let dense = kalman::update_rows(&x, &P, &z, &H, &R, &active, CovarianceUpdate::Joseph).unwrap();
            let (mut xf, mut Pf) = (x, P);
            let mut seq = Gain::zero();
            update_rows_into(&mut xf, &mut Pf, &innov, &GLOBAL_ROWS, &r, &active, &mut seq).unwrap();
            let scale = 1.0 + P.norm();
            prop_assert!((dense.K - seq.K).norm() < 1e-12 * scale);
            prop_assert!((dense.x - xf).norm() < 1e-12 * scale);
            prop_assert!((dense.P - Pf).norm() < 1e-12 * scale);
            prop_assert!((dense.innovation - seq.innovation).norm() < 1e-15);
            prop_assert_eq!(Pf, Pf.transpose());
            prop_assert!(psd(&Pf, 1e-12 * scale));
            let kinds = [
                RowKind::Imu(0), RowKind::Imu(1), RowKind::Imu(2), RowKind::Imu(3),
                RowKind::Joint, RowKind::Joint, RowKind::Joint,
            ];
            let sd = gain_shares(&dense.K, &dense.innovation, &kinds);
            let sq = gain_shares(&seq.K, &seq.innovation, &kinds);
            for (a, b) in sd.iter().flatten().zip(sq.iter().flatten()) {
                match (a, b) {
                    (Some(a), Some(b)) => prop_assert!((a - b).abs() < 1e-12, "{a} {b}"),
                    (a, b) => prop_assert_eq!(a.is_some(), b.is_some()),
                }
            }
        }

        /// The same with the mjls rows (one segment row, three joint rows).
        #[test]
        fn sequential_update_equals_dense_on_mjls_rows(
            seed in prop::array::uniform32(-1.0f64..1.0),
            r in prop::array::uniform4(1e-5f64..0.1),
            e in prop::array::uniform4(-0.5f64..0.5),
            mode in 0usize..4,
            mask in 0u32..16,
        ) {
            let mut s36 = [0.3; 36];
            s36[..32].copy_from_slice(&seed);
            let P = spd(&s36) * 1e-2;
            let rows = crate::segment_kf::model::mjls_rows(Some(limbfuse_core::Segment::ALL[mode]));
            let active: [bool; 4] = core::array::from_fn(|k| mask & (1 << k) != 0);
            let innov = SVector::<f64, 4>::from_column_slice(&e);
            let H = dense_output_matrix(&rows);
            let R = SMatrix::<f64, 4, 4>::from_diagonal(&SVector::from_column_slice(&r));
            let x = SVector::<f64, 8>::zeros();
            let dense = kalman::update_rows(&x, &P, &innov, &H, &R, &active, CovarianceUpdate::Joseph).unwrap();
            let (mut xf, mut Pf) = (x, P);
            let mut seq = Gain::zero();
            update_rows_into(&mut xf, &mut Pf, &innov, &rows, &r, &active, &mut seq).unwrap();
            prop_assert!((dense.x - xf).norm() < 1e-12);
            prop_assert!((dense.P - Pf).norm() < 1e-12);
            prop_assert!((dense.K - seq.K).norm() < 1e-12 * (1.0 + dense.K.norm()));
            prop_assert_eq!(Pf, Pf.transpose());
            prop_assert!(psd(&Pf, 1e-15));
        }
    }

    /// The local filter's rows (four segment rows) on a fixed `P`.
    #[test]
    fn local_rows_equal_dense() {
        let mut seed = [0.0; 36];
        for (k, v) in seed.iter_mut().enumerate() {
            *v = ((k * 37 % 11) as f64 - 5.0) / 7.0;
        }
        let P = spd(&seed);
        let r = [0.02, 0.5, 0.1, 1.0];
        let innov = SVector::<f64, 4>::new(0.1, -0.2, 0.05, 0.3);
        let H = dense_output_matrix(&LOCAL_ROWS);
        let R = SMatrix::<f64, 4, 4>::from_diagonal(&SVector::from_column_slice(&r));
        let x = SVector::<f64, 8>::zeros();
        let dense =
            kalman::update_rows(&x, &P, &innov, &H, &R, &[true; 4], CovarianceUpdate::Joseph)
                .unwrap();
        let (mut xf, mut Pf) = (x, P);
        let mut g = Gain::zero();
        update_rows_into(
            &mut xf,
            &mut Pf,
            &innov,
            &LOCAL_ROWS,
            &r,
            &[true; 4],
            &mut g,
        )
        .unwrap();
        assert!((dense.x - xf).norm() < 1e-13);
        assert!((dense.P - Pf).norm() < 1e-13);
    }

    #[test]
    fn indefinite_pivot_is_an_error_and_changes_nothing() {
        let mut P = -Mat8::identity();
        let mut x = SVector::<f64, 8>::zeros();
        let u = update_rows_into(
            &mut x,
            &mut P,
            &SVector::<f64, 1>::new(0.1),
            &[ChainRow::segment(2)],
            &[1e-3],
            &[true],
            &mut Gain::zero(),
        );
        assert_eq!(u.unwrap_err(), KalmanError::InnovationNotPositiveDefinite);
        assert_eq!(P, -Mat8::identity());
        assert_eq!(x, SVector::<f64, 8>::zeros());
    }
}
