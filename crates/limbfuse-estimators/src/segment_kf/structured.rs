//! The Kalman time and measurement updates of the segment chain, exploiting
//! the structure of papers 000/001's model instead of dense 8x8 products.
//!
//! * The transition `Phi-bar` and process noise `Q_d` are block-diagonal
//!   with one 2x2 block per segment (000 eqs 16-19, 001 eq 4), so
//!   `P- = Phi P Phi^T + Q_d` (000 eq 22) needs only the pairs of columns
//!   (then rows) of each block mixed by that block's `Phi_i`: 2 x 4 x 8 x 4
//!   multiplications instead of 2 x 8^3, and half of that for the segment
//!   model's `Phi_i = [[1, c], [0, d]]`, which both discretisations produce.
//! * Every output row of the three models (000 eqs 17-18, 001 eqs 6, 10,
//!   22) is either `e_a` (one segment's angle error) or `e_a - e_b` (a joint:
//!   the difference of two angle errors), and `R` is diagonal (000 eq 27,
//!   001 eq 22). `P H^T` is then a selection or difference of columns of
//!   `P`, `S = H P H^T + R` a selection of its rows, and the Joseph form
//!   `(I - K H) P (I - K H)^T + K R K^T` (000 eq 25 in Joseph form) is
//!   evaluated as `A = P - K (H P)`, `P+ = A - (A H^T) K^T + K R K^T`: the
//!   same products, with the multiplications by `H` done as column
//!   selections. Only the active rows enter (`m <= M`, compacted into a
//!   kernel of exactly `m` rows); inactive rows get a zero gain column,
//!   exactly as [`limbfuse_core::kalman::update_rows`].
//!
//! The results equal the dense [`limbfuse_core::kalman`] functions to
//! round-off (tests below). Nothing allocates.
#![allow(non_snake_case)]
// Index loops mirror the matrix algebra (rows, columns, blocks) one to one.
#![allow(clippy::needless_range_loop)]

use limbfuse_core::kalman::{CovarianceUpdate, KalmanError};
use nalgebra::{Matrix2, SMatrix, SVector};

use super::model::{angle_state, Mat8};

/// One measurement row of the chain models: the angle error of segment
/// `plus`, minus that of segment `minus` when present (a joint row).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ChainRow {
    /// Segment whose angle error enters with `+1`.
    pub plus: usize,
    /// Segment whose angle error enters with `-1` (joint rows).
    pub minus: Option<usize>,
}

impl ChainRow {
    /// Row `e_i`: the angle error of segment `i`.
    pub const fn segment(i: usize) -> Self {
        ChainRow {
            plus: i,
            minus: None,
        }
    }

    /// Row `e_j - e_(j+1)`: joint `j` (0 hip, 1 knee, 2 ankle).
    pub const fn joint(j: usize) -> Self {
        ChainRow {
            plus: j,
            minus: Some(j + 1),
        }
    }

    /// `(v[plus] - v[minus])` over the angle-state entries of `v`, read
    /// through `at(state_index)`.
    #[inline(always)]
    fn apply(&self, at: impl Fn(usize) -> f64) -> f64 {
        let p = at(angle_state(self.plus));
        match self.minus {
            Some(m) => p - at(angle_state(m)),
            None => p,
        }
    }

    /// The dense row of `H` (8 entries).
    pub fn dense(&self) -> SMatrix<f64, 1, 8> {
        let mut h = SMatrix::<f64, 1, 8>::zeros();
        h[angle_state(self.plus)] = 1.0;
        if let Some(m) = self.minus {
            h[angle_state(m)] = -1.0;
        }
        h
    }
}

/// The dense output matrix of a list of rows.
pub fn dense_output_matrix<const M: usize>(rows: &[ChainRow; M]) -> SMatrix<f64, M, 8> {
    let mut c = SMatrix::<f64, M, 8>::zeros();
    for (r, row) in rows.iter().enumerate() {
        c.row_mut(r).copy_from(&row.dense());
    }
    c
}

/// Time update `x- = Phi x`, `P- = Phi P Phi^T + Q_d` (000 eqs 21-22) for a
/// block-diagonal `Phi` and `Q_d` given as per-segment 2x2 blocks, in place.
pub fn predict_blocks(
    x: &mut SVector<f64, 8>,
    P: &mut Mat8,
    phi: &[Matrix2<f64>; 4],
    qd: &[Matrix2<f64>; 4],
) {
    for i in 0..4 {
        let (a, b) = (2 * i, 2 * i + 1);
        let f = &phi[i];
        let (xa, xb) = (x[a], x[b]);
        x[a] = f[(0, 0)] * xa + f[(0, 1)] * xb;
        x[b] = f[(1, 0)] * xa + f[(1, 1)] * xb;
    }
    // Column-major storage: p[col][row]. First P Phi^T (the two columns of
    // block j mixed by Phi_j), then Phi (P Phi^T) (the two rows of block i
    // mixed by Phi_i).
    let p = &mut P.data.0;
    // The segment model's Phi_i = [[1, c_i], [0, d_i]] (000 eq 8: the angle
    // integrates the bias, the bias decays) has half the products of a
    // general 2x2 block; both discretisations give these exact 1 and 0.
    if phi.iter().all(|f| f[(0, 0)] == 1.0 && f[(1, 0)] == 0.0) {
        for j in 0..4 {
            let (c, d) = (phi[j][(0, 1)], phi[j][(1, 1)]);
            let (lo, hi) = p.split_at_mut(2 * j + 1);
            let (c0, c1) = (&mut lo[2 * j], &mut hi[0]);
            for s in 0..8 {
                c0[s] += c * c1[s];
                c1[s] *= d;
            }
        }
        for col in p.iter_mut() {
            for i in 0..4 {
                let (c, d) = (phi[i][(0, 1)], phi[i][(1, 1)]);
                col[2 * i] += c * col[2 * i + 1];
                col[2 * i + 1] *= d;
            }
        }
    } else {
        predict_general(p, phi);
    }
    for i in 0..4 {
        let q = &qd[i];
        let (a, b) = (2 * i, 2 * i + 1);
        p[a][a] += q[(0, 0)];
        p[b][b] += q[(1, 1)];
        p[b][a] += q[(0, 1)];
        p[a][b] += q[(1, 0)];
    }
    for a in 0..8 {
        for b in a + 1..8 {
            let v = 0.5 * (p[a][b] + p[b][a]);
            p[a][b] = v;
            p[b][a] = v;
        }
    }
}

/// `p <- Phi p Phi^T` for general 2x2 blocks `Phi_i` (column-major `p`).
fn predict_general(p: &mut [[f64; 8]; 8], phi: &[Matrix2<f64>; 4]) {
    for j in 0..4 {
        let f = &phi[j];
        let (c0, c1) = (p[2 * j], p[2 * j + 1]);
        for s in 0..8 {
            p[2 * j][s] = c0[s] * f[(0, 0)] + c1[s] * f[(0, 1)];
            p[2 * j + 1][s] = c0[s] * f[(1, 0)] + c1[s] * f[(1, 1)];
        }
    }
    for col in p.iter_mut() {
        for i in 0..4 {
            let f = &phi[i];
            let (r0, r1) = (col[2 * i], col[2 * i + 1]);
            col[2 * i] = f[(0, 0)] * r0 + f[(0, 1)] * r1;
            col[2 * i + 1] = f[(1, 0)] * r0 + f[(1, 1)] * r1;
        }
    }
}

/// Gain and innovation of a measurement update (the state and covariance
/// are updated in place).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gain<const M: usize> {
    /// Kalman gain `K = P H^T S^-1` (8xM); zero columns for inactive rows.
    pub K: SMatrix<f64, 8, M>,
    /// Innovation `z - H x` of the active rows (zero for inactive rows).
    pub innovation: SVector<f64, M>,
}

impl<const M: usize> Gain<M> {
    /// A zero gain and innovation (no update).
    pub fn zero() -> Self {
        Gain {
            K: SMatrix::zeros(),
            innovation: SVector::zeros(),
        }
    }
}

/// Measurement update (000 eqs 23-25) on the active `rows`, with diagonal
/// measurement noise `r` (variances) and innovations `innovation = z - H x`
/// (already formed by the caller, e.g. with angle wrapping), applied to `x`
/// and `P` in place. Inactive rows are removed exactly (zero `H` row, unit
/// noise, zero innovation: their gain columns are exactly zero), as in
/// [`limbfuse_core::kalman::update_rows`]; the loops keep the fixed size `M`
/// so that they unroll. With no active row nothing changes and the gain is
/// zero.
///
/// Fails, leaving `x` and `P` untouched, when `S = H P H^T + R` is not
/// positive definite or the result is not finite.
pub fn update_rows<const M: usize>(
    x: &mut SVector<f64, 8>,
    P: &mut Mat8,
    innovation: &SVector<f64, M>,
    rows: &[ChainRow; M],
    r: &[f64; M],
    active: &[bool; M],
    form: CovarianceUpdate,
) -> Result<Gain<M>, KalmanError> {
    let m = active.iter().filter(|&&a| a).count();
    if m == M {
        return update_masked(x, P, innovation, rows, r, &[true; M], form);
    }
    if m > 6 {
        return update_masked(x, P, innovation, rows, r, active, form);
    }
    if m == 0 {
        return Ok(Gain {
            K: SMatrix::zeros(),
            innovation: SVector::zeros(),
        });
    }
    // Compact the active rows and run the kernel at their exact count, so
    // that every loop has a fixed trip count and no row is padding.
    let mut idx = [0usize; M];
    let mut n = 0;
    for (k, &on) in active.iter().enumerate() {
        if on {
            idx[n] = k;
            n += 1;
        }
    }
    macro_rules! compact {
        ($n:literal) => {{
            let rows_c: [ChainRow; $n] = core::array::from_fn(|c| rows[idx[c]]);
            let r_c: [f64; $n] = core::array::from_fn(|c| r[idx[c]]);
            let e_c = SVector::<f64, $n>::from_fn(|c, _| innovation[idx[c]]);
            let g = update_masked(x, P, &e_c, &rows_c, &r_c, &[true; $n], form)?;
            let mut out = Gain {
                K: SMatrix::<f64, 8, M>::zeros(),
                innovation: SVector::<f64, M>::zeros(),
            };
            for c in 0..$n {
                out.K.set_column(idx[c], &g.K.column(c));
                out.innovation[idx[c]] = g.innovation[c];
            }
            Ok(out)
        }};
    }
    match m {
        1 => compact!(1),
        2 => compact!(2),
        3 => compact!(3),
        4 => compact!(4),
        5 => compact!(5),
        _ => compact!(6),
    }
}

/// [`update_rows`] on a fixed-size row set with a mask (inactive rows
/// padded).
#[inline(always)]
fn update_masked<const M: usize>(
    x: &mut SVector<f64, 8>,
    P: &mut Mat8,
    innovation: &SVector<f64, M>,
    rows: &[ChainRow; M],
    r: &[f64; M],
    active: &[bool; M],
    form: CovarianceUpdate,
) -> Result<Gain<M>, KalmanError> {
    let mut gain = Gain {
        K: SMatrix::<f64, 8, M>::zeros(),
        innovation: SVector::<f64, M>::zeros(),
    };
    if !active.iter().any(|&a| a) {
        return Ok(gain);
    }
    // Columns of the symmetric P (column j of P is also its row j).
    let p: &[[f64; 8]; 8] = &P.data.0;
    // ph[c] = column c of P H^T: a column of P, or the difference of two
    // (zero for inactive rows).
    let mut ph = [[0.0f64; 8]; M];
    for c in 0..M {
        if active[c] {
            let row = rows[c];
            let a = &p[angle_state(row.plus)];
            ph[c] = *a;
            if let Some(m) = row.minus {
                let b = &p[angle_state(m)];
                for s in 0..8 {
                    ph[c][s] = a[s] - b[s];
                }
            }
            gain.innovation[c] = innovation[c];
        }
    }
    // S = H P H^T + R (identity for inactive rows), symmetrised, then its
    // Cholesky factor (lower triangle of L).
    let mut L = [[0.0f64; M]; M];
    for a in 0..M {
        for b in 0..=a {
            L[a][b] = if active[a] && active[b] {
                let sab = rows[a].apply(|t| ph[b][t]);
                let sba = rows[b].apply(|t| ph[a][t]);
                0.5 * (sab + sba)
            } else {
                0.0
            };
        }
        L[a][a] += if active[a] { r[a] } else { 1.0 };
    }
    for j in 0..M {
        let mut d = L[j][j];
        for k in 0..j {
            d -= L[j][k] * L[j][k];
        }
        if !(d.is_finite() && d > 0.0) {
            return Err(KalmanError::InnovationNotPositiveDefinite);
        }
        let d = libm::sqrt(d);
        L[j][j] = d;
        for i in j + 1..M {
            let mut v = L[i][j];
            for k in 0..j {
                v -= L[i][k] * L[j][k];
            }
            L[i][j] = v / d;
        }
    }
    // k[c] = column c of K: S [k_0 .. k_M-1]^T = [ph_0 .. ph_M-1]^T, solved
    // with 8-vector entries (forward, then backward substitution).
    let mut k = ph;
    for i in 0..M {
        for j in 0..i {
            let l = L[i][j];
            let kj = k[j];
            for s in 0..8 {
                k[i][s] -= l * kj[s];
            }
        }
        let inv = 1.0 / L[i][i];
        for v in k[i].iter_mut() {
            *v *= inv;
        }
    }
    for i in (0..M).rev() {
        for j in i + 1..M {
            let l = L[j][i];
            let kj = k[j];
            for s in 0..8 {
                k[i][s] -= l * kj[s];
            }
        }
        let inv = 1.0 / L[i][i];
        for v in k[i].iter_mut() {
            *v *= inv;
        }
    }
    let mut xp = *x;
    for c in 0..M {
        let e = gain.innovation[c];
        for s in 0..8 {
            xp[s] += k[c][s] * e;
        }
    }
    // A = (I - K H) P = P - K (H P): column t is p[t] - sum_c ph[c][t] k[c].
    let mut A = *p;
    for (t, col) in A.iter_mut().enumerate() {
        for c in 0..M {
            let f = ph[c][t];
            for s in 0..8 {
                col[s] -= f * k[c][s];
            }
        }
    }
    if form == CovarianceUpdate::Joseph {
        // (I - K H) P (I - K H)^T + K R K^T = A + sum_c w_c k_c^T with
        // w_c = r_c k_c - (A H^T)_c, accumulated into A in place.
        let mut w = [[0.0f64; 8]; M];
        for c in 0..M {
            if active[c] {
                let row = rows[c];
                for s in 0..8 {
                    let ah = row.apply(|t| A[t][s]);
                    w[c][s] = r[c] * k[c][s] - ah;
                }
            }
        }
        for (t, col) in A.iter_mut().enumerate() {
            for c in 0..M {
                let f = k[c][t];
                for s in 0..8 {
                    col[s] += f * w[c][s];
                }
            }
        }
    }
    for a in 0..8 {
        for b in a + 1..8 {
            let v = 0.5 * (A[a][b] + A[b][a]);
            A[a][b] = v;
            A[b][a] = v;
        }
    }
    for c in 0..M {
        for s in 0..8 {
            gain.K[(s, c)] = k[c][s];
        }
    }
    if !(all_finite(xp.as_slice()) && all_finite(A.as_flattened()) && all_finite(gain.K.as_slice()))
    {
        return Err(KalmanError::InnovationNotPositiveDefinite);
    }
    *x = xp;
    P.data.0 = A;
    Ok(gain)
}

/// Whether every value is finite. Tests the exponent bits (all ones for
/// infinities and NaN) with integer operations, which, unlike a
/// floating-point reduction, the compiler may reorder and vectorise: the
/// exponent field plus one unit of it reaches the sign bit only when the
/// field is all ones, so an OR of these sums has the sign bit set exactly
/// when some value is not finite (a 64-bit add, AND and OR per value, which
/// SSE2 has; a 64-bit equality test, the form before, it has not).
#[inline]
pub fn all_finite(v: &[f64]) -> bool {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    const EXP_UNIT: u64 = 1 << 52;
    const SIGN: u64 = 1 << 63;
    v.iter()
        .fold(0u64, |acc, v| acc | ((v.to_bits() & EXP) + EXP_UNIT))
        & SIGN
        == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::kalman;
    use proptest::prelude::*;

    use crate::segment_kf::model::GLOBAL_ROWS;
    use crate::segment_kf::sequential::tests::{global_case, global_inputs, spd};

    proptest! {
        /// The structured update equals the dense `kalman::update_rows` for
        /// every row mask, both covariance forms, random SPD `P`.
        #[test]
        fn structured_update_equals_dense(
            (seed, extra, r, e, x, mask) in global_inputs(),
            joseph in any::<bool>(),
        ) {
            let (P, x, active, innov, H, R, z) = global_case(&seed, &extra, &r, &e, &x, mask);
            let form = if joseph { CovarianceUpdate::Joseph } else { CovarianceUpdate::Standard };
            let dense = kalman::update_rows(&x, &P, &z, &H, &R, &active, form).unwrap();
            let (mut xf, mut Pf) = (x, P);
            let fast = update_rows(&mut xf, &mut Pf, &innov, &GLOBAL_ROWS, &r, &active, form).unwrap();
            let scale = 1.0 + P.norm();
            prop_assert!((dense.K - fast.K).norm() < 1e-12 * scale);
            prop_assert!((dense.x - xf).norm() < 1e-12 * scale);
            prop_assert!((dense.P - Pf).norm() < 1e-11 * scale);
            prop_assert!((dense.innovation - fast.innovation).norm() < 1e-15);
            prop_assert_eq!(Pf, Pf.transpose());
        }

        /// The blockwise time update equals `Phi P Phi^T + Q_d` with the
        /// assembled 8x8 matrices.
        #[test]
        fn blockwise_predict_equals_dense(
            seed in prop::array::uniform32(-1.0f64..1.0),
            f in prop::array::uniform16(-1.5f64..1.5),
            q in prop::array::uniform8(0.0f64..0.1),
            x in prop::array::uniform8(-0.3f64..0.3),
        ) {
            let mut s36 = [0.5; 36];
            s36[..32].copy_from_slice(&seed);
            let P = spd(&s36);
            let x = SVector::<f64, 8>::from_column_slice(&x);
            let phi: [Matrix2<f64>; 4] = core::array::from_fn(|i| {
                Matrix2::new(f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3])
            });
            let qd: [Matrix2<f64>; 4] = core::array::from_fn(|i| {
                Matrix2::new(q[2 * i], 0.1 * q[2 * i], 0.1 * q[2 * i], q[2 * i + 1])
            });
            let mut Phi = Mat8::zeros();
            let mut Qd = Mat8::zeros();
            for i in 0..4 {
                Phi.fixed_view_mut::<2, 2>(2 * i, 2 * i).copy_from(&phi[i]);
                Qd.fixed_view_mut::<2, 2>(2 * i, 2 * i).copy_from(&qd[i]);
            }
            let (xd, Pd) = kalman::predict(&x, &P, &Phi, &Qd);
            let (mut xf, mut Pf) = (x, P);
            predict_blocks(&mut xf, &mut Pf, &phi, &qd);
            prop_assert!((xd - xf).norm() < 1e-14);
            prop_assert!((Pd - Pf).norm() < 1e-12 * (1.0 + P.norm()));
            prop_assert_eq!(Pf, Pf.transpose());
        }
    }

    /// The fast path for the segment model's `Phi_i = [[1, c], [0, d]]`
    /// (taken by the real discretisations) equals the dense time update.
    #[test]
    fn triangular_predict_equals_dense() {
        use crate::segment_kf::model::Discretizer;
        use crate::segment_kf::params::SegmentNoise;
        use limbfuse_core::discretize::Discretization;
        let mut segs = [SegmentNoise::consumer_mems(9.81); 4];
        segs[2].bias_tau = 7.0;
        for method in [Discretization::Exact, Discretization::Euler] {
            let mut disc = Discretizer::new(&segs, method);
            let b = *disc.blocks(0.013);
            assert!(b.phi.iter().all(|f| f[(0, 0)] == 1.0 && f[(1, 0)] == 0.0));
            let (Phi, Qd) = disc.get(0.013);
            let mut seed = [0.0; 36];
            for (k, v) in seed.iter_mut().enumerate() {
                *v = ((k * 37 % 11) as f64 - 5.0) / 7.0;
            }
            let P = spd(&seed);
            let x = SVector::<f64, 8>::from_fn(|i, _| 0.1 * i as f64 - 0.3);
            let (xd, Pd) = kalman::predict(&x, &P, &Phi, &Qd);
            let (mut xf, mut Pf) = (x, P);
            predict_blocks(&mut xf, &mut Pf, &b.phi, &b.qd);
            assert!((xd - xf).norm() < 1e-14);
            assert!((Pd - Pf).norm() < 1e-12 * (1.0 + P.norm()), "{method:?}");
        }
    }

    #[test]
    fn indefinite_innovation_is_an_error() {
        let mut P = -Mat8::identity();
        let r = [1e-3; 1];
        let u = update_rows(
            &mut SVector::zeros(),
            &mut P,
            &SVector::<f64, 1>::new(0.1),
            &[ChainRow::segment(2)],
            &r,
            &[true],
            CovarianceUpdate::Joseph,
        );
        assert_eq!(u.unwrap_err(), KalmanError::InnovationNotPositiveDefinite);
        assert_eq!(P, -Mat8::identity());
    }

    #[test]
    fn all_finite_spots_nan_and_infinity() {
        assert!(all_finite(&[0.0, -1e300, 1e300, 5.0]));
        assert!(!all_finite(&[0.0, f64::NAN]));
        assert!(!all_finite(&[f64::INFINITY, 1.0]));
        assert!(!all_finite(&[1.0, f64::NEG_INFINITY]));
        // the extremes of the finite range, negative NaN, an empty slice
        assert!(all_finite(&[
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            5e-324,
            -0.0
        ]));
        assert!(!all_finite(&[-f64::NAN, 1.0, 2.0, 3.0, 4.0]));
        assert!(all_finite(&[]));
        // every position of a longer slice (the vectorised fold)
        for k in 0..72 {
            let mut v = [1.5f64; 72];
            v[k] = f64::INFINITY;
            assert!(!all_finite(&v), "{k}");
            v[k] = f64::NAN;
            assert!(!all_finite(&v), "{k}");
        }
    }
}
