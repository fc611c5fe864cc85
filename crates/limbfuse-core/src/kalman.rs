//! Linear Kalman filter steps as pure functions on fixed-size matrices.
//!
//! State and covariance go in, state and covariance come out (the style of
//! adskalman-rs). The covariance update is selectable; the Joseph form is the
//! default because it keeps `P` symmetric positive semi-definite under
//! round-off and with sub-optimal gains.
//!
//! Notation (paper 000, eqs 21-25): `x` state, `P` covariance, `Phi`
//! transition, `Qd` discrete process noise, `z` measurement, `H` output
//! matrix, `R` measurement noise, `K` gain.
#![allow(non_snake_case)]

use nalgebra::{SMatrix, SVector};

/// How the posterior covariance is formed after an update.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CovarianceUpdate {
    /// `P+ = (I - K H) P (I - K H)^T + K R K^T` (Joseph form, default).
    #[default]
    Joseph,
    /// `P+ = (I - K H) P` (the papers' textbook form, paper 000 eq 25).
    Standard,
}

/// A numerical failure of a Kalman step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum KalmanError {
    /// The innovation covariance `S = H P H^T + R` is not positive definite.
    #[error("innovation covariance is not positive definite")]
    InnovationNotPositiveDefinite,
}

/// Result of a measurement update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Update<const N: usize, const M: usize> {
    /// Posterior state.
    pub x: SVector<f64, N>,
    /// Posterior covariance.
    pub P: SMatrix<f64, N, N>,
    /// Kalman gain `K = P H^T S^-1`.
    pub K: SMatrix<f64, N, M>,
    /// Innovation `z - H x`.
    pub innovation: SVector<f64, M>,
}

/// Time update (paper 000 eqs 21-22): `x- = Phi x`, `P- = Phi P Phi^T + Qd`.
pub fn predict<const N: usize>(
    x: &SVector<f64, N>,
    P: &SMatrix<f64, N, N>,
    Phi: &SMatrix<f64, N, N>,
    Qd: &SMatrix<f64, N, N>,
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    let x_next = Phi * x;
    let P_next = symmetrize(&(Phi * P * Phi.transpose() + Qd));
    (x_next, P_next)
}

/// Measurement update (paper 000 eqs 23-25) with the chosen covariance form.
pub fn update<const N: usize, const M: usize>(
    x: &SVector<f64, N>,
    P: &SMatrix<f64, N, N>,
    z: &SVector<f64, M>,
    H: &SMatrix<f64, M, N>,
    R: &SMatrix<f64, M, M>,
    form: CovarianceUpdate,
) -> Result<Update<N, M>, KalmanError> {
    let HP = H * P;
    let S = symmetrize(&(HP * H.transpose() + R));
    let chol = S
        .cholesky()
        .ok_or(KalmanError::InnovationNotPositiveDefinite)?;
    // K^T = S^-1 H P (S and P symmetric).
    let K: SMatrix<f64, N, M> = chol.solve(&HP).transpose();
    let innovation = z - H * x;
    let x_post = x + K * innovation;
    let I_KH = SMatrix::<f64, N, N>::identity() - K * H;
    let P_post = match form {
        CovarianceUpdate::Joseph => I_KH * P * I_KH.transpose() + K * R * K.transpose(),
        CovarianceUpdate::Standard => I_KH * P,
    };
    Ok(Update {
        x: x_post,
        P: symmetrize(&P_post),
        K,
        innovation,
    })
}

/// Measurement update using only the rows of `z`/`H` whose `active` flag is set.
///
/// Inactive rows are removed exactly (not down-weighted): their `H` rows and
/// innovations are zeroed and their rows/columns of `R` replaced by the
/// identity, so their gain columns are exactly zero and the active rows see
/// the same update as a reduced-size filter. Cross-covariances in `R` between
/// an active and an inactive row are dropped. With no active row the prior is
/// returned unchanged.
pub fn update_rows<const N: usize, const M: usize>(
    x: &SVector<f64, N>,
    P: &SMatrix<f64, N, N>,
    z: &SVector<f64, M>,
    H: &SMatrix<f64, M, N>,
    R: &SMatrix<f64, M, M>,
    active: &[bool; M],
    form: CovarianceUpdate,
) -> Result<Update<N, M>, KalmanError> {
    if !active.iter().any(|&a| a) {
        return Ok(Update {
            x: *x,
            P: *P,
            K: SMatrix::zeros(),
            innovation: SVector::zeros(),
        });
    }
    let mut Hm = *H;
    let mut zm = *z;
    let mut Rm = *R;
    for (i, &on) in active.iter().enumerate() {
        if !on {
            Hm.row_mut(i).fill(0.0);
            zm[i] = 0.0;
            Rm.row_mut(i).fill(0.0);
            Rm.column_mut(i).fill(0.0);
            Rm[(i, i)] = 1.0;
        }
    }
    update(x, P, &zm, &Hm, &Rm, form)
}

/// `(A + A^T) / 2`: removes the asymmetry round-off adds to a covariance.
pub fn symmetrize<const N: usize>(A: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    (A + A.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix1, Matrix2, Vector1, Vector2};

    #[test]
    fn scalar_update_matches_hand_computation() {
        // x = 1, P = 4, z = 3, H = 1, R = 1: S = 5, K = 0.8, x+ = 1 + 0.8*2 = 2.6,
        // P+ (Joseph) = 0.2*4*0.2 + 0.8*1*0.8 = 0.16 + 0.64 = 0.8.
        let u = update(
            &Vector1::new(1.0),
            &Matrix1::new(4.0),
            &Vector1::new(3.0),
            &Matrix1::new(1.0),
            &Matrix1::new(1.0),
            CovarianceUpdate::Joseph,
        )
        .unwrap();
        assert!((u.K[0] - 0.8).abs() < 1e-15);
        assert!((u.x[0] - 2.6).abs() < 1e-15);
        assert!((u.P[(0, 0)] - 0.8).abs() < 1e-15);
    }

    #[test]
    fn joseph_and_standard_agree_for_optimal_gain() {
        let x = Vector2::new(0.1, -0.2);
        let P = Matrix2::new(2.0, 0.3, 0.3, 0.5);
        let H = nalgebra::Matrix1x2::new(1.0, 0.0);
        let R = Matrix1::new(0.04);
        let z = Vector1::new(0.3);
        let a = update(&x, &P, &z, &H, &R, CovarianceUpdate::Joseph).unwrap();
        let b = update(&x, &P, &z, &H, &R, CovarianceUpdate::Standard).unwrap();
        assert!((a.P - b.P).norm() < 1e-14);
        assert_eq!(a.x, b.x);
    }

    #[test]
    fn masked_rows_equal_reduced_filter() {
        let x = Vector2::new(0.1, -0.2);
        let P = Matrix2::new(2.0, 0.3, 0.3, 0.5);
        let H = Matrix2::new(1.0, 0.0, 1.0, 1.0);
        let R = Matrix2::new(0.04, 0.0, 0.0, 0.09);
        let z = Vector2::new(0.3, 5.0);
        let masked =
            update_rows(&x, &P, &z, &H, &R, &[true, false], CovarianceUpdate::Joseph).unwrap();
        let reduced = update(
            &x,
            &P,
            &Vector1::new(0.3),
            &nalgebra::Matrix1x2::new(1.0, 0.0),
            &Matrix1::new(0.04),
            CovarianceUpdate::Joseph,
        )
        .unwrap();
        assert!((masked.x - reduced.x).norm() < 1e-15);
        assert!((masked.P - reduced.P).norm() < 1e-15);
        assert_eq!(masked.K.column(1).norm(), 0.0);
        let none = update_rows(
            &x,
            &P,
            &z,
            &H,
            &R,
            &[false, false],
            CovarianceUpdate::Joseph,
        )
        .unwrap();
        assert_eq!(none.x, x);
        assert_eq!(none.P, P);
    }

    #[test]
    fn indefinite_innovation_is_an_error_not_a_panic() {
        let r = update(
            &Vector1::new(0.0),
            &Matrix1::new(-1.0),
            &Vector1::new(0.0),
            &Matrix1::new(1.0),
            &Matrix1::new(0.0),
            CovarianceUpdate::Joseph,
        );
        assert_eq!(r.unwrap_err(), KalmanError::InnovationNotPositiveDefinite);
    }
}
