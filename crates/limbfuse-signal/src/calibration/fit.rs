//! The accelerometer fit: bias `b` and correction `C` such that every static
//! pose's mean reading `m_k` satisfies `|C (m_k - b)| = g` (an ellipsoid fit,
//! solved by Levenberg-Marquardt-damped Gauss-Newton).
//!
//! Residual `r_k(p) = |v_k| - g`, `v_k = C u_k`, `u_k = m_k - b`, and with
//! `n_k = v_k / |v_k|` its gradient (docs/CALIBRATION.md, eqs 3-5):
//! * `dr_k/db = -n_k^T C`;
//! * `dr_k/dC_ii = n_ki u_ki`; `dr_k/dC_ij = n_ki u_kj + n_kj u_ki` for the
//!   symmetric pair `C_ij = C_ji` (`i < j`).
//!
//! `C` is symmetric because `|Q C u| = |C u|` for every rotation `Q`: gravity
//! magnitudes alone determine `C` only up to a rotation, and the symmetric
//! factor (polar decomposition) is the one that turns the raw frame least.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use limbfuse_io::calibration::CalibrationModel;

/// Parameter vector: `b` (3), then `C_00, C_11, C_22, C_01, C_02, C_12`.
pub type Params = SVector<f64, 9>;

/// `C` from the parameters of `model` (entries a model does not estimate
/// are held at their starting value).
pub fn matrix(p: &Params) -> Matrix3<f64> {
    Matrix3::new(p[3], p[6], p[7], p[6], p[4], p[8], p[7], p[8], p[5])
}

/// Bias from the parameters.
pub fn bias(p: &Params) -> Vector3<f64> {
    Vector3::new(p[0], p[1], p[2])
}

/// Indices of the parameters `model` estimates.
fn free(model: CalibrationModel) -> &'static [usize] {
    match model {
        CalibrationModel::Full => &[0, 1, 2, 3, 4, 5, 6, 7, 8],
        CalibrationModel::Scale => &[0, 1, 2, 3, 4, 5],
        CalibrationModel::Bias => &[0, 1, 2],
    }
}

/// Residual `|C (m - b)| - g`.
pub fn residual(p: &Params, m: &Vector3<f64>, g: f64) -> f64 {
    (matrix(p) * (m - bias(p))).norm() - g
}

/// Gradient of [`residual`] with respect to all nine parameters.
pub fn gradient(p: &Params, m: &Vector3<f64>) -> Params {
    let c = matrix(p);
    let u = m - bias(p);
    let v = c * u;
    let n = v / v.norm();
    let db = -(c.transpose() * n);
    Params::from_column_slice(&[
        db.x,
        db.y,
        db.z,
        n.x * u.x,
        n.y * u.y,
        n.z * u.z,
        n.x * u.y + n.y * u.x,
        n.x * u.z + n.z * u.x,
        n.y * u.z + n.z * u.y,
    ])
}

/// What the fit found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitResult {
    /// The parameters.
    pub params: Params,
    /// RMS residual (m/s^2).
    pub residual_rms: f64,
    /// Smallest eigenvalue of the column-normalised normal matrix `J^T J`
    /// over the free parameters (1 = orthogonal columns, 0 = undetermined).
    pub min_normalised_eigenvalue: f64,
    /// Iterations made.
    pub iterations: usize,
}

fn normal_equations(
    p: &Params,
    poses: &[Vector3<f64>],
    g: f64,
    idx: &[usize],
) -> (SMatrix<f64, 9, 9>, Params, f64) {
    let mut jtj = SMatrix::<f64, 9, 9>::zeros();
    let mut jtr = Params::zeros();
    let mut cost = 0.0;
    for m in poses {
        let r = residual(p, m, g);
        let full = gradient(p, m);
        let mut j = Params::zeros();
        for &i in idx {
            j[i] = full[i];
        }
        jtj += j * j.transpose();
        jtr += j * r;
        cost += r * r;
    }
    (jtj, jtr, cost)
}

/// Smallest eigenvalue of the normalised `J^T J` restricted to `idx` (the
/// held parameters get a unit diagonal: the normalised matrix has trace
/// `k` over `k` free parameters, so its smallest eigenvalue is <= 1 and the
/// added ones never are the minimum).
fn min_normalised_eigenvalue(jtj: &SMatrix<f64, 9, 9>, idx: &[usize]) -> f64 {
    let mut a = SMatrix::<f64, 9, 9>::identity();
    for &i in idx {
        for &j in idx {
            let d = (jtj[(i, i)] * jtj[(j, j)]).sqrt();
            a[(i, j)] = if d > 0.0 { jtj[(i, j)] / d } else { 0.0 };
        }
    }
    a.symmetric_eigenvalues().min()
}

/// Fits `model` to the pose means `poses` (at least as many as unknowns).
/// Starts from `b = 0`, `C = (g / mean |m_k|) I` (`C = I` for the bias
/// model, which holds it).
pub fn fit(poses: &[Vector3<f64>], g: f64, model: CalibrationModel) -> FitResult {
    let idx = free(model);
    let mean_norm = poses.iter().map(|m| m.norm()).sum::<f64>() / poses.len().max(1) as f64;
    let s = if mean_norm > 0.0 && model != CalibrationModel::Bias {
        g / mean_norm
    } else {
        1.0
    };
    let mut p = Params::from_column_slice(&[0.0, 0.0, 0.0, s, s, s, 0.0, 0.0, 0.0]);
    let mut lambda = 1e-3;
    let (mut jtj, mut jtr, mut cost) = normal_equations(&p, poses, g, idx);
    let mut iterations = 0;
    for it in 0..200 {
        iterations = it + 1;
        let mut a = jtj;
        for &i in idx {
            a[(i, i)] += lambda * jtj[(i, i)].max(1e-12);
        }
        for i in 0..9 {
            if !idx.contains(&i) {
                a[(i, i)] = 1.0;
            }
        }
        let Some(step) = a.cholesky().map(|ch| ch.solve(&(-jtr))) else {
            lambda *= 10.0;
            continue;
        };
        let trial = p + step;
        let (tj, tr, tc) = normal_equations(&trial, poses, g, idx);
        if tc.is_finite() && tc < cost {
            let done = cost - tc <= 1e-15 * cost.max(1e-300) || step.norm() < 1e-13;
            p = trial;
            (jtj, jtr, cost) = (tj, tr, tc);
            lambda = (lambda / 10.0).max(1e-12);
            if done {
                break;
            }
        } else {
            lambda *= 10.0;
            if lambda > 1e12 {
                break;
            }
        }
    }
    FitResult {
        params: p,
        residual_rms: (cost / poses.len().max(1) as f64).sqrt(),
        min_normalised_eigenvalue: min_normalised_eigenvalue(&jtj, idx),
        iterations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directions() -> Vec<Vector3<f64>> {
        let c = 1.0 / 3f64.sqrt();
        let mut d = vec![
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
        ];
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    d.push(Vector3::new(sx * c, sy * c, sz * c));
                }
            }
        }
        d
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let p = Params::from_column_slice(&[0.1, -0.2, 0.3, 1.01, 0.98, 1.02, 0.01, -0.02, 0.015]);
        let m = Vector3::new(3.0, 8.0, -4.0);
        let g = gradient(&p, &m);
        for i in 0..9 {
            let h = 1e-6;
            let mut a = p;
            let mut b = p;
            a[i] += h;
            b[i] -= h;
            let fd = (residual(&a, &m, 9.81) - residual(&b, &m, 9.81)) / (2.0 * h);
            assert!((fd - g[i]).abs() < 1e-7, "{i}: {fd} vs {}", g[i]);
        }
    }

    #[test]
    fn recovers_a_symmetric_sensor_exactly() {
        // Sensor y = S f + b0 with S symmetric: the fit returns C = S^-1, b = b0.
        let s = Matrix3::new(
            1.01, 0.008, -0.004, 0.008, 0.995, 0.006, -0.004, 0.006, 1.004,
        );
        let b0 = Vector3::new(0.2, -0.15, 0.3);
        let poses: Vec<Vector3<f64>> = directions().iter().map(|d| s * (d * 9.81) + b0).collect();
        let r = fit(&poses, 9.81, CalibrationModel::Full);
        let c_true = s.try_inverse().unwrap();
        assert!((bias(&r.params) - b0).norm() < 1e-10, "{}", bias(&r.params));
        assert!((matrix(&r.params) - c_true).norm() < 1e-10);
        assert!(r.residual_rms < 1e-10);
        assert!(
            r.min_normalised_eigenvalue > 0.05,
            "{}",
            r.min_normalised_eigenvalue
        );
    }

    #[test]
    fn poses_in_one_plane_leave_the_model_undetermined() {
        let poses: Vec<Vector3<f64>> = (0..12)
            .map(|k| {
                let a = k as f64 * 0.5;
                Vector3::new(a.cos(), a.sin(), 0.0) * 9.81
            })
            .collect();
        let r = fit(&poses, 9.81, CalibrationModel::Full);
        assert!(
            r.min_normalised_eigenvalue < 1e-6,
            "{}",
            r.min_normalised_eigenvalue
        );
    }

    #[test]
    fn reduced_models_hold_the_other_entries() {
        let b0 = Vector3::new(0.1, 0.2, -0.1);
        let poses: Vec<Vector3<f64>> = directions().iter().map(|d| d * 9.81 + b0).collect();
        let r = fit(&poses, 9.81, CalibrationModel::Bias);
        assert!((bias(&r.params) - b0).norm() < 1e-10);
        assert_eq!(matrix(&r.params), Matrix3::identity());
    }
}
