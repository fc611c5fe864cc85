//! Matrix exponential by scaling and squaring with a diagonal Padé(6,6)
//! approximant (Golub & Van Loan, *Matrix Computations*, 4th ed., Alg. 9.3.1).
//!
//! Written here because `nalgebra`'s `Matrix::exp` needs its `std` feature and
//! cannot be used from this `no_std` crate. With `||A||_inf / 2^s <= 1/2` and
//! q = 6 the Padé error bound is about 3.4e-16 relative.
#![allow(non_snake_case)]

use nalgebra::SMatrix;

/// `expm(A)` for a fixed-size square matrix. Returns `None` only if `A` holds
/// non-finite values (the Padé denominator is then not invertible).
pub fn expm<const N: usize>(A: &SMatrix<f64, N, N>) -> Option<SMatrix<f64, N, N>> {
    const Q: usize = 6;
    let norm = A
        .row_iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    if !norm.is_finite() {
        return None;
    }
    // Smallest s >= 0 with norm / 2^s <= 1/2.
    let mut s: i32 = 0;
    let mut scaled_norm = norm;
    while scaled_norm > 0.5 {
        scaled_norm *= 0.5;
        s += 1;
    }
    let As = A * libm::ldexp(1.0, -s);
    let I = SMatrix::<f64, N, N>::identity();
    let mut X = I;
    let mut Nm = I;
    let mut D = I;
    let mut c = 1.0;
    for k in 1..=Q {
        c = c * (Q - k + 1) as f64 / (k * (2 * Q - k + 1)) as f64;
        X = As * X;
        let cX = X * c;
        Nm += cX;
        if k % 2 == 0 {
            D += cX;
        } else {
            D -= cX;
        }
    }
    let mut F = solve(D, Nm)?;
    for _ in 0..s {
        F = F * F;
    }
    Some(F)
}

/// Solves `D F = B` by Gaussian elimination with partial pivoting (nalgebra's
/// LU needs type-level dimensions that generic `const N` code cannot name).
fn solve<const N: usize>(
    mut D: SMatrix<f64, N, N>,
    mut B: SMatrix<f64, N, N>,
) -> Option<SMatrix<f64, N, N>> {
    for col in 0..N {
        let (pivot, max) = (col..N)
            .map(|r| (r, D[(r, col)].abs()))
            .fold((col, -1.0), |acc, v| if v.1 > acc.1 { v } else { acc });
        if !max.is_finite() || max <= 0.0 {
            return None;
        }
        D.swap_rows(col, pivot);
        B.swap_rows(col, pivot);
        for r in (col + 1)..N {
            let f = D[(r, col)] / D[(col, col)];
            if f != 0.0 {
                for c in col..N {
                    D[(r, c)] -= f * D[(col, c)];
                }
                for c in 0..N {
                    B[(r, c)] -= f * B[(col, c)];
                }
            }
        }
    }
    for col in (0..N).rev() {
        for c in 0..N {
            let mut v = B[(col, c)];
            for k in (col + 1)..N {
                v -= D[(col, k)] * B[(k, c)];
            }
            B[(col, c)] = v / D[(col, col)];
        }
    }
    Some(B)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Matrix3};

    #[test]
    fn rotation_generator_gives_rotation() {
        // expm([[0, -w], [w, 0]]) = [[cos w, -sin w], [sin w, cos w]].
        let w = 2.3_f64;
        let E = expm(&Matrix2::new(0.0, -w, w, 0.0)).unwrap();
        let R = Matrix2::new(w.cos(), -w.sin(), w.sin(), w.cos());
        assert!((E - R).norm() < 1e-14, "{E}");
    }

    #[test]
    fn nilpotent_and_diagonal_cases() {
        // Nilpotent: expm([[0,1,0],[0,0,1],[0,0,0]] t) = [[1, t, t^2/2], [0, 1, t], [0, 0, 1]].
        let t = 3.0;
        let E = expm(&Matrix3::new(0.0, t, 0.0, 0.0, 0.0, t, 0.0, 0.0, 0.0)).unwrap();
        let want = Matrix3::new(1.0, t, t * t / 2.0, 0.0, 1.0, t, 0.0, 0.0, 1.0);
        assert!((E - want).norm() < 1e-13);
        let E = expm(&Matrix2::new(-20.0, 0.0, 0.0, 1.5)).unwrap();
        assert!(((E[(0, 0)] - (-20.0f64).exp()) / (-20.0f64).exp()).abs() < 1e-12);
        assert!(((E[(1, 1)] - 1.5f64.exp()) / 1.5f64.exp()).abs() < 1e-13);
        assert!(expm(&Matrix2::new(f64::NAN, 0.0, 0.0, 0.0)).is_none());
    }
}
