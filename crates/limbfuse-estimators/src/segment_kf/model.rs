//! The state-space matrices of papers 000/001 and their discretisation.
//!
//! State (000 eq 16, 001 eq 4): `x = [dtheta_B, db_B, dtheta_T, db_T,
//! dtheta_S, db_S, dtheta_F, db_F]`, where `dtheta_i = theta_i -
//! theta_g,i` is the error of the gyro-integrated angle and `db_i = b_i -
//! b_hat_i` the error of the gyro-bias estimate, in the papers' bias
//! convention (000 eq 1: true rate = gyro reading + b). Segment `i`
//! (0 = trunk .. 3 = foot) owns states `2i` (angle) and `2i + 1` (bias).
#![allow(non_snake_case)]

use limbfuse_core::discretize::{discretize, Discretization};
use limbfuse_core::Segment;
use nalgebra::{Matrix2, SMatrix};

use super::params::SegmentNoise;
use super::structured::{dense_output_matrix, ChainRow};

/// 8x8 matrix of the stacked segment model.
pub type Mat8 = SMatrix<f64, 8, 8>;

/// Index of the angle-error state of a segment.
#[inline]
pub const fn angle_state(s: usize) -> usize {
    2 * s
}

/// Index of the bias-error state of a segment.
#[inline]
pub const fn bias_state(s: usize) -> usize {
    2 * s + 1
}

/// One segment's `A = [[0, 1], [0, -1/tau_g]]` (000 eq 8, 001 eq 1).
pub fn segment_a(tau: f64) -> Matrix2<f64> {
    Matrix2::new(0.0, 1.0, 0.0, -1.0 / tau)
}

/// One segment's continuous noise intensity `B Q B^T = diag(sigma_g^2,
/// sigma_bg^2)` with `B = I` (000 eqs 8, 26).
pub fn segment_qc(noise: &SegmentNoise) -> Matrix2<f64> {
    Matrix2::new(
        noise.gyro_noise * noise.gyro_noise,
        0.0,
        0.0,
        noise.bias_drive * noise.bias_drive,
    )
}

/// The block-diagonal `A-bar` of the four segments (000 eq 18, 001 eq 4).
pub fn chain_a(segments: &[SegmentNoise; 4]) -> Mat8 {
    let mut a = Mat8::zeros();
    for (i, s) in segments.iter().enumerate() {
        a.fixed_view_mut::<2, 2>(2 * i, 2 * i)
            .copy_from(&segment_a(s.bias_tau));
    }
    a
}

/// The block-diagonal continuous noise intensity `Q` (000 eq 26).
pub fn chain_qc(segments: &[SegmentNoise; 4]) -> Mat8 {
    let mut q = Mat8::zeros();
    for (i, s) in segments.iter().enumerate() {
        q.fixed_view_mut::<2, 2>(2 * i, 2 * i)
            .copy_from(&segment_qc(s));
    }
    q
}

/// Rows of the matricial local model, 001 eq 6: row `i` picks the angle
/// error of segment `i`.
pub const LOCAL_ROWS: [ChainRow; 4] = [
    ChainRow::segment(0),
    ChainRow::segment(1),
    ChainRow::segment(2),
    ChainRow::segment(3),
];

/// Rows of the matricial global model, 001 eq 22: rows 0-3 the segment
/// angle errors, rows 4-6 the hip, knee and ankle differences (001 eqs
/// 23-25).
pub const GLOBAL_ROWS: [ChainRow; 7] = [
    ChainRow::segment(0),
    ChainRow::segment(1),
    ChainRow::segment(2),
    ChainRow::segment(3),
    ChainRow::joint(0),
    ChainRow::joint(1),
    ChainRow::joint(2),
];

/// Rows of the MJLS model `C-bar(Xi)`, 000 eq 18 / 001 eq 10, with `M_i`
/// from 000 Table 1: row 0 the angle error of the selected segment (for
/// `None` the trunk row as a placeholder: the filter never activates it),
/// rows 1-3 the hip, knee and ankle differences `dtheta_i - dtheta_{i+1}`.
pub fn mjls_rows(mode: Option<Segment>) -> [ChainRow; 4] {
    [
        ChainRow::segment(mode.map_or(0, |s| s.index())),
        ChainRow::joint(0),
        ChainRow::joint(1),
        ChainRow::joint(2),
    ]
}

/// Output matrix of the matricial local model, 001 eq 6 ([`LOCAL_ROWS`]).
pub fn local_output_matrix() -> SMatrix<f64, 4, 8> {
    dense_output_matrix(&LOCAL_ROWS)
}

/// Output matrix `C-bar(Xi)` of the MJLS model, 000 eq 18 / 001 eq 10
/// ([`mjls_rows`]); row 0 is all zeros for `None`.
pub fn mjls_output_matrix(mode: Option<Segment>) -> SMatrix<f64, 4, 8> {
    let mut c = dense_output_matrix(&mjls_rows(mode));
    if mode.is_none() {
        c.row_mut(0).fill(0.0);
    }
    c
}

/// Coupled output matrix `C-bar_c` of the matricial global model, 001 eq 22
/// ([`GLOBAL_ROWS`]).
pub fn global_output_matrix() -> SMatrix<f64, 7, 8> {
    dense_output_matrix(&GLOBAL_ROWS)
}

/// Discretises the block-diagonal model segment by segment and caches the
/// result while the step length repeats.
///
/// `Phi = expm(A T)` and `Qd` by Van Loan (default) or `Phi = I + A T`,
/// `Qd = Q T` (SPEC section 6; 000 eq 19 is undefined as printed). Each
/// 2x2 block is discretised on its own (the model is block-diagonal, so this
/// equals discretising the 8x8 model). Steps that differ from the cached one
/// by less than 1e-9 relative reuse it: timestamps such as `k * 0.01` give
/// differences that vary in the last bits, and the resulting change of
/// `Phi`/`Qd` is below 1e-9 relative.
#[derive(Debug, Clone, Copy)]
pub struct Discretizer {
    a: [Matrix2<f64>; 4],
    qc: [Matrix2<f64>; 4],
    method: Discretization,
    cached_dt: f64,
    cached: Blocks,
}

impl Discretizer {
    /// A discretiser for the four segments' noise models.
    pub fn new(segments: &[SegmentNoise; 4], method: Discretization) -> Self {
        let mut a = [Matrix2::zeros(); 4];
        let mut qc = [Matrix2::zeros(); 4];
        for i in 0..4 {
            a[i] = segment_a(segments[i].bias_tau);
            qc[i] = segment_qc(&segments[i]);
        }
        Discretizer {
            a,
            qc,
            method,
            cached_dt: f64::NAN,
            cached: Blocks {
                phi: [Matrix2::zeros(); 4],
                qd: [Matrix2::zeros(); 4],
            },
        }
    }

    /// Per-segment blocks `(Phi_i, Qd_i)` for a step of `dt` seconds.
    pub fn blocks(&mut self, dt: f64) -> &Blocks {
        // `cached_dt` starts as NaN, which never compares within tolerance.
        let reuse = libm::fabs(dt - self.cached_dt) <= 1e-9 * self.cached_dt;
        if !reuse {
            for i in 0..4 {
                let (p, q) = discretize::<2, 4>(&self.a[i], &self.qc[i], dt, self.method);
                self.cached.phi[i] = p;
                self.cached.qd[i] = q;
            }
            self.cached_dt = dt;
        }
        &self.cached
    }

    /// `(Phi, Qd)` (8x8, block-diagonal) for a step of `dt` seconds.
    pub fn get(&mut self, dt: f64) -> (Mat8, Mat8) {
        let b = *self.blocks(dt);
        let mut phi = Mat8::zeros();
        let mut qd = Mat8::zeros();
        for i in 0..4 {
            phi.fixed_view_mut::<2, 2>(2 * i, 2 * i)
                .copy_from(&b.phi[i]);
            qd.fixed_view_mut::<2, 2>(2 * i, 2 * i).copy_from(&b.qd[i]);
        }
        (phi, qd)
    }
}

/// The per-segment 2x2 blocks of the discretised model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blocks {
    /// `Phi_i = expm(A_i T)` (or `I + A_i T`).
    pub phi: [Matrix2<f64>; 4],
    /// `Qd_i` (Van Loan, or `Q_i T`).
    pub qd: [Matrix2<f64>; 4],
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::discretize::discretize;

    #[test]
    fn blockwise_equals_full_discretisation() {
        let mut segs = [super::super::params::SegmentNoise::consumer_mems(9.81); 4];
        segs[1].bias_tau = 30.0;
        segs[3].gyro_noise = 0.3;
        let a = chain_a(&segs);
        let q = chain_qc(&segs);
        let (p_full, q_full) = discretize::<8, 16>(&a, &q, 0.013, Discretization::Exact);
        let (p, qd) = Discretizer::new(&segs, Discretization::Exact).get(0.013);
        assert!((p - p_full).norm() < 1e-13);
        assert!((qd - q_full).norm() < 1e-15);
    }
}
