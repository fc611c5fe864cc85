//! The constrained EKF parameter estimator of paper 002 (Algorithm 2,
//! after Walker 2006): the parameters are the state (`F = I`), each sample of
//! a window contributes a pseudo-measurement `0 = z - h(x) + v` with `z = 0`
//! and `h = e(k)`, so the innovation is `r = -e(k)` and the observation row
//! is `H(k) = de(k)/dx` (eq 9).
//!
//! One iteration (of `order`) is: predict `P <- P + Q`; linearise every
//! residual of the window at the current `x`; correct with all of them. The
//! paper's correction stacks the window into an `N x N` innovation
//! covariance `H P H^T + R` (`R = r I_N`). limbfuse uses the equivalent
//! information form, which needs only the `n x n` sums over the window:
//!
//! `P+ = (P^-1 + H^T H / r)^-1`, `x+ = x + P+ H^T (-e) / r`.
//!
//! This is algebraically the same update (matrix inversion lemma), and the
//! same as `N` sequential scalar updates with the rows linearised at one
//! point; the cost is `O(N n^2)` per iteration, linear in the window length.

use nalgebra::{SMatrix, SVector};

/// Noise settings of Algorithm 2 (paper 002 after eq 13).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamEkfNoise {
    /// Process noise `Q = q I` added per iteration (paper: 1e-3).
    pub q: f64,
    /// Pseudo-measurement noise `R = r I_N` (paper: 1e-3).
    pub r: f64,
    /// Initial covariance `P0 = p0 I` of each window (paper: 1).
    pub p0: f64,
}

impl Default for ParamEkfNoise {
    fn default() -> Self {
        ParamEkfNoise {
            q: 1e-3,
            r: 1e-3,
            p0: 1.0,
        }
    }
}

/// What one run of Algorithm 2 over a window produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamEkfResult<const N: usize> {
    /// Parameters after the last iteration.
    pub x: SVector<f64, N>,
    /// Covariance after the last iteration. (The batch form `(I - K H) P`
    /// of the paper agrees to about 1e-8 relative; its `N x N` inverse is the
    /// less accurate of the two.)
    pub p: SMatrix<f64, N, N>,
    /// Residuals used in the last iteration.
    pub n_used: usize,
    /// Root-mean-square residual at the starting point.
    pub rms_before: f64,
    /// Root-mean-square residual at the final parameters.
    pub rms_after: f64,
    /// Smallest eigenvalue of `H^T H / n_used` of the last linearisation
    /// (how well the window pins the parameters down; units of `H`^2).
    pub min_information: f64,
}

/// Why Algorithm 2 could not run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamEkfError {
    /// The window held no usable residual.
    NoResiduals,
    /// A covariance lost positive definiteness.
    Numerical,
}

/// Visits every residual of a window at parameters `x`: calls `f(e, H)` with
/// the residual `e(k)` and its gradient row `H(k)` for each usable sample.
pub trait WindowResiduals<const N: usize> {
    /// Calls `f` once per usable sample of the window.
    fn visit(&self, x: &SVector<f64, N>, f: &mut dyn FnMut(f64, &SVector<f64, N>));
}

/// Sum of squared residuals and their count at `x`.
pub fn residual_sum<const N: usize, W: WindowResiduals<N>>(
    w: &W,
    x: &SVector<f64, N>,
) -> (f64, usize) {
    let mut sum = 0.0;
    let mut n = 0usize;
    w.visit(x, &mut |e, _| {
        sum += e * e;
        n += 1;
    });
    (sum, n)
}

fn rms(sum: f64, n: usize) -> f64 {
    if n == 0 {
        0.0
    } else {
        libm::sqrt(sum / n as f64)
    }
}

/// Runs `iterations` iterations of Algorithm 2 from `x0` and `P0 = p0 I`.
/// `normalise` maps the state back into its canonical ranges after each
/// correction (the spherical angles of eq 1).
pub fn estimate_parameters<const N: usize, W: WindowResiduals<N>>(
    w: &W,
    x0: SVector<f64, N>,
    iterations: usize,
    noise: &ParamEkfNoise,
    normalise: fn(SVector<f64, N>) -> SVector<f64, N>,
) -> Result<ParamEkfResult<N>, ParamEkfError> {
    let (s0, n0) = residual_sum(w, &x0);
    if n0 == 0 {
        return Err(ParamEkfError::NoResiduals);
    }
    let mut x = x0;
    let mut p = SMatrix::<f64, N, N>::identity() * noise.p0;
    let mut n_used = n0;
    let mut min_information = 0.0;
    for _ in 0..iterations {
        // Prediction: F = I.
        p += SMatrix::<f64, N, N>::identity() * noise.q;
        // Error and Jacobian over the window, accumulated as H^T H and H^T e.
        let mut hth = SMatrix::<f64, N, N>::zeros();
        let mut hte = SVector::<f64, N>::zeros();
        let mut n = 0usize;
        w.visit(&x, &mut |e, h| {
            hth.ger(1.0, h, h, 1.0);
            hte.axpy(e, h, 1.0);
            n += 1;
        });
        if n == 0 {
            break;
        }
        n_used = n;
        // Correction in information form.
        let p_inv = p.cholesky().ok_or(ParamEkfError::Numerical)?.inverse();
        let info = p_inv + hth / noise.r;
        let p_post = info.cholesky().ok_or(ParamEkfError::Numerical)?.inverse();
        x = normalise(x - p_post * hte / noise.r);
        p = (p_post + p_post.transpose()) * 0.5;
        min_information = smallest_eigenvalue(&(hth / n as f64));
    }
    let (s1, n1) = residual_sum(w, &x);
    Ok(ParamEkfResult {
        x,
        p,
        n_used,
        rms_before: rms(s0, n0),
        rms_after: rms(s1, n1.max(1)),
        min_information,
    })
}

/// Smallest eigenvalue of a symmetric positive semi-definite matrix, by
/// inverse iteration (0 when the matrix is numerically singular).
fn smallest_eigenvalue<const N: usize>(m: &SMatrix<f64, N, N>) -> f64 {
    let scale = m.trace().abs().max(f64::MIN_POSITIVE);
    let Some(ch) = (m + SMatrix::<f64, N, N>::identity() * (1e-12 * scale)).cholesky() else {
        return 0.0;
    };
    let mut v = SVector::<f64, N>::repeat(1.0).normalize();
    let mut lambda = 0.0;
    for _ in 0..100 {
        let w = ch.solve(&v);
        let n = w.norm();
        if n.is_nan() || n <= 0.0 || !n.is_finite() {
            return 0.0;
        }
        v = w / n;
        let next = v.dot(&(m * v));
        if (next - lambda).abs() <= 1e-12 * scale {
            return next.max(0.0);
        }
        lambda = next;
    }
    lambda.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector, Vector2};

    /// Linear residuals e(k) = a_k . x - b_k.
    struct Linear(std::vec::Vec<(Vector2<f64>, f64)>);

    impl WindowResiduals<2> for Linear {
        fn visit(&self, x: &Vector2<f64>, f: &mut dyn FnMut(f64, &Vector2<f64>)) {
            for (a, b) in &self.0 {
                f(a.dot(x) - b, a);
            }
        }
    }

    fn rows() -> Linear {
        Linear(
            (0..40)
                .map(|k| {
                    let t = k as f64 * 0.1;
                    let a = Vector2::new(libm::sin(t), 1.0 + 0.3 * libm::cos(2.0 * t));
                    let b = a.dot(&Vector2::new(0.7, -1.3)) + 0.01 * libm::sin(7.0 * t);
                    (a, b)
                })
                .collect(),
        )
    }

    #[test]
    fn information_form_equals_the_papers_batch_update() {
        // One iteration, computed the paper's way with the N x N innovation
        // covariance, and with estimate_parameters.
        let w = rows();
        let noise = ParamEkfNoise::default();
        let x0 = Vector2::new(0.1, 0.2);
        let n = w.0.len();
        let h = DMatrix::from_fn(n, 2, |i, j| w.0[i].0[j]);
        let e = DVector::from_fn(n, |i, _| w.0[i].0.dot(&x0) - w.0[i].1);
        let p = DMatrix::<f64>::identity(2, 2) * (noise.p0 + noise.q);
        let s = &h * &p * h.transpose() + DMatrix::<f64>::identity(n, n) * noise.r;
        let k = &p * h.transpose() * s.try_inverse().unwrap();
        let x_batch = DVector::from_column_slice(x0.as_slice()) - &k * &e;
        let p_batch = (DMatrix::<f64>::identity(2, 2) - &k * &h) * &p;
        let out = estimate_parameters(&w, x0, 1, &noise, |x| x).unwrap();
        for i in 0..2 {
            assert!((out.x[i] - x_batch[i]).abs() < 1e-10);
            for j in 0..2 {
                assert!(
                    (out.p[(i, j)] - p_batch[(i, j)]).abs() < 1e-6 * p_batch.amax(),
                    "{} vs {}",
                    out.p,
                    p_batch
                );
            }
        }
    }

    #[test]
    fn iterations_converge_to_least_squares() {
        let w = rows();
        let out =
            estimate_parameters(&w, Vector2::zeros(), 6, &ParamEkfNoise::default(), |x| x).unwrap();
        assert!((out.x - Vector2::new(0.7, -1.3)).norm() < 2e-3, "{}", out.x);
        assert!(out.rms_after < out.rms_before);
        assert!(out.min_information > 0.1);
    }

    #[test]
    fn empty_window_is_an_error() {
        let w = Linear(std::vec::Vec::new());
        assert_eq!(
            estimate_parameters(&w, Vector2::zeros(), 3, &ParamEkfNoise::default(), |x| x),
            Err(ParamEkfError::NoResiduals)
        );
    }
}
