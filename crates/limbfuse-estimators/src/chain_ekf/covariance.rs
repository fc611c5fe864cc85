//! Time and measurement updates of the chain EKF that exploit its structure
//! (docs/CHAIN.md, "Prediction" and "Sequential scalar updates").
//!
//! * The transition `Phi` is the identity except for the per-segment
//!   constant-angular-acceleration blocks `(theta, omega, alpha)` and the
//!   hip's `(v, a)` pairs, so `Phi P Phi^T` is computed as row and column
//!   operations in `O(n^2)` instead of two dense products.
//! * Each measurement is a scalar with a sparse row `H`: `h = P H^T` costs
//!   `O(n m)` for `m` non-zeros, and the Joseph form
//!   `(I - K H) P (I - K H)^T + K r K^T` is expanded to the rank-two update
//!   `P - K h^T - h K^T + (H P H^T + r) K K^T` (exact for any gain `K`).
#![allow(non_snake_case)]

use nalgebra::{SMatrix, SVector};

use super::state::{alpha, hip_acceleration, hip_velocity, omega, theta, SparseRow, N};

/// State vector.
pub type StateVector = SVector<f64, N>;
/// State covariance.
pub type Covariance = SMatrix<f64, N, N>;

/// Continuous-time white-noise intensities of the process model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcessNoise {
    /// Angular jerk `d alpha / dt` per segment, rad^2/s^5.
    pub angular_jerk: [f64; 4],
    /// Gyro bias random walk, rad^2/s^3.
    pub gyro_bias: f64,
    /// Hip acceleration: white-noise intensity per world axis, m^2/s^5.
    pub hip_jerk: f64,
    /// Hip acceleration: mean-reversion rate `beta = 1 / tau` (1/s) of its
    /// Gauss-Markov model `a_h' = -beta a_h + w`.
    pub hip_acc_rate: f64,
    /// Mean forward speed random walk, m^2/s^3.
    pub mean_speed: f64,
    /// Encoder offset random walk, rad^2/s.
    pub encoder_offset: f64,
}

/// The hip pair's transition `[[1, c], [0, e]]`: `e = exp(-beta T)`,
/// `c = (1 - e) / beta` (`T` when `beta = 0`).
fn hip_transition(dt: f64, beta: f64) -> (f64, f64) {
    let e = libm::exp(-beta * dt);
    let c = if beta * dt > 1e-9 {
        (1.0 - e) / beta
    } else {
        dt
    };
    (c, e)
}

/// `x <- Phi x` (constant angular acceleration per segment over the step;
/// Gauss-Markov hip acceleration).
pub fn predict_state(x: &mut StateVector, dt: f64, q: &ProcessNoise) {
    let h2 = 0.5 * dt * dt;
    for i in 0..4 {
        x[theta(i)] += dt * x[omega(i)] + h2 * x[alpha(i)];
        x[omega(i)] += dt * x[alpha(i)];
    }
    let (c, e) = hip_transition(dt, q.hip_acc_rate);
    for k in 0..2 {
        x[hip_velocity(k)] += c * x[hip_acceleration(k)];
        x[hip_acceleration(k)] *= e;
    }
}

/// Applies `Phi` to the rows of `P` (`P <- Phi P`), one column slice at a
/// time (column-major storage).
fn phi_rows(P: &mut Covariance, dt: f64, beta: f64) {
    let h2 = 0.5 * dt * dt;
    let (hc, he) = hip_transition(dt, beta);
    for col in P.as_mut_slice().chunks_exact_mut(N) {
        for i in 0..4 {
            let (t, w, a) = (col[theta(i)], col[omega(i)], col[alpha(i)]);
            col[theta(i)] = t + dt * w + h2 * a;
            col[omega(i)] = w + dt * a;
        }
        for k in 0..2 {
            let a = col[hip_acceleration(k)];
            col[hip_velocity(k)] += hc * a;
            col[hip_acceleration(k)] = he * a;
        }
    }
}

/// `column(target) += f * column(source)` of a column-major `N x N` slice.
#[inline]
fn add_column(p: &mut [f64], target: usize, source: usize, f: f64) {
    let (src, dst) = if source < target {
        let (lo, hi) = p.split_at_mut(target * N);
        (&lo[source * N..source * N + N], &mut hi[..N])
    } else {
        let (lo, hi) = p.split_at_mut(source * N);
        (&hi[..N], &mut lo[target * N..target * N + N])
    };
    for (d, s) in dst.iter_mut().zip(src.iter()) {
        *d += f * s;
    }
}

/// Applies `Phi^T` to the columns of `P` (`P <- P Phi^T`).
fn phi_columns(P: &mut Covariance, dt: f64, beta: f64) {
    let h2 = 0.5 * dt * dt;
    let (hc, he) = hip_transition(dt, beta);
    let p = P.as_mut_slice();
    for i in 0..4 {
        // theta uses the old omega column: update it before omega.
        add_column(p, theta(i), omega(i), dt);
        add_column(p, theta(i), alpha(i), h2);
        add_column(p, omega(i), alpha(i), dt);
    }
    for k in 0..2 {
        add_column(p, hip_velocity(k), hip_acceleration(k), hc);
        let a = hip_acceleration(k) * N;
        for v in p[a..a + N].iter_mut() {
            *v *= he;
        }
    }
}

/// Discrete noise of the Gauss-Markov pair `v' = a`, `a' = -beta a + w`
/// (intensity `q`), by integrating `Phi(s) [0, 1]^T q [0, 1] Phi(s)^T`:
/// `Q22 = q (1 - e^2) / (2 beta)`, `Q12 = q (1 - e)^2 / (2 beta^2)`,
/// `Q11 = q / beta^2 (T - 2 (1 - e) / beta + (1 - e^2) / (2 beta))`,
/// `e = exp(-beta T)`; the white-jerk block of
/// [`triple_integrator_noise`] when `beta T < 1e-4` (relative error
/// `O(beta T)`; the closed form cancels there).
pub fn gauss_markov_pair_noise(q: f64, dt: f64, beta: f64) -> [[f64; 2]; 2] {
    if beta * dt < 1e-4 {
        let b = triple_integrator_noise(q, dt);
        return [[b[1][1], b[1][2]], [b[2][1], b[2][2]]];
    }
    let e = libm::exp(-beta * dt);
    let b2 = beta * beta;
    let q22 = q * (1.0 - e * e) / (2.0 * beta);
    let q12 = q * (1.0 - e) * (1.0 - e) / (2.0 * b2);
    let q11 = q / b2 * (dt - 2.0 * (1.0 - e) / beta + (1.0 - e * e) / (2.0 * beta));
    [[q11, q12], [q12, q22]]
}

/// Discrete process noise of one integrator chain driven by white noise of
/// intensity `q` on its last state: for `(p, v, a)` with `a' = w`,
/// `Qd = q [[T^5/20, T^4/8, T^3/6], [T^4/8, T^3/3, T^2/2], [T^3/6, T^2/2, T]]`
/// (Bar-Shalom, Li, Kirubarajan, *Estimation with Applications to Tracking
/// and Navigation*, Wiley 2001, eq 6.2.3-8); for `(v, a)` its lower-right
/// 2x2 block.
pub fn triple_integrator_noise(q: f64, dt: f64) -> [[f64; 3]; 3] {
    let t2 = dt * dt;
    let t3 = t2 * dt;
    let t4 = t3 * dt;
    let t5 = t4 * dt;
    [
        [q * t5 / 20.0, q * t4 / 8.0, q * t3 / 6.0],
        [q * t4 / 8.0, q * t3 / 3.0, q * t2 / 2.0],
        [q * t3 / 6.0, q * t2 / 2.0, q * dt],
    ]
}

/// `P <- Phi P Phi^T + Qd` for a step of `dt` seconds.
pub fn predict_covariance(P: &mut Covariance, dt: f64, q: &ProcessNoise) {
    phi_rows(P, dt, q.hip_acc_rate);
    phi_columns(P, dt, q.hip_acc_rate);
    for i in 0..4 {
        let b = triple_integrator_noise(q.angular_jerk[i], dt);
        let ix = [theta(i), omega(i), alpha(i)];
        for r in 0..3 {
            for c in 0..3 {
                P[(ix[r], ix[c])] += b[r][c];
            }
        }
        let g = super::state::gyro_bias(i);
        P[(g, g)] += q.gyro_bias * dt;
    }
    let b = gauss_markov_pair_noise(q.hip_jerk, dt, q.hip_acc_rate);
    for k in 0..2 {
        let ix = [hip_velocity(k), hip_acceleration(k)];
        for r in 0..2 {
            for c in 0..2 {
                P[(ix[r], ix[c])] += b[r][c];
            }
        }
    }
    let m = super::state::MEAN_SPEED;
    P[(m, m)] += q.mean_speed * dt;
    for j in 0..3 {
        let o = super::state::encoder_offset(j);
        P[(o, o)] += q.encoder_offset * dt;
    }
    // The row and column passes round differently: mirror the lower
    // triangle so that P is exactly symmetric for [`scalar_update`].
    symmetrise(P);
}

/// Copies the lower triangle of `P` into the upper one.
fn symmetrise(P: &mut Covariance) {
    let p = P.as_mut_slice();
    for c in 0..N {
        for r in c + 1..N {
            p[r * N + c] = p[c * N + r];
        }
    }
}

/// `P += s K K^T - (K h^T + h K^T)` on whole columns of a column-major
/// `N x N` slice. Every product and sum of entry `(r, c)` is symmetric in
/// `(r, c)`, so a symmetric `P` stays exactly symmetric without mirroring,
/// and the column loops vectorise.
#[inline(always)]
fn rank_two_columns(p: &mut [f64], K: &[f64; N], h: &[f64; N], s: f64) {
    for (c, col) in p.chunks_exact_mut(N).enumerate() {
        let (kc, hc) = (K[c], h[c]);
        for ((v, kr), hr) in col.iter_mut().zip(K).zip(h) {
            *v += s * (kr * kc) - (kr * hc + hr * kc);
        }
    }
}

/// What one scalar update did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarUpdate {
    /// Innovation `z - z_hat`.
    pub innovation: f64,
    /// Innovation variance `H P H^T + r`.
    pub variance: f64,
    /// Whether the update was applied (false: rejected by the gate).
    pub applied: bool,
}

/// Scalar measurement update with a sparse row: innovation `nu`, row `H`,
/// noise variance `r`. Rows with `nu^2 > gate^2 (H P H^T + r)` are not
/// applied (`gate` = infinity: never rejected). Joseph form, expanded for a
/// rank-one `H` (module documentation); `P` must be exactly symmetric on
/// entry (as [`predict_covariance`] leaves it) and stays so.
///
/// Nearly all of the chain filter's time is spent here (24 x 24 entries per
/// scalar row, about 20 rows per sample), so the same code is compiled for
/// AVX-512 and AVX2 and the widest unit the CPU has is picked at run time
/// (with `std`). Rust never contracts `a * b + c` into a fused
/// multiply-add, so every version gives bit-identical results (tested).
pub fn scalar_update(
    x: &mut StateVector,
    P: &mut Covariance,
    H: &SparseRow,
    nu: f64,
    r: f64,
    gate: f64,
) -> ScalarUpdate {
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    {
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: AVX-512F support was just checked.
            return unsafe { wide::scalar_update_avx512(x, P, H, nu, r, gate) };
        }
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: AVX2 support was just checked.
            return unsafe { wide::scalar_update_avx2(x, P, H, nu, r, gate) };
        }
    }
    scalar_update_portable(x, P, H, nu, r, gate)
}

/// Copies of [`scalar_update_portable`] compiled for wider vector units.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
mod wide {
    use super::*;

    /// # Safety
    /// The CPU must support AVX-512F.
    #[target_feature(enable = "avx512f")]
    pub(super) unsafe fn scalar_update_avx512(
        x: &mut StateVector,
        P: &mut Covariance,
        H: &SparseRow,
        nu: f64,
        r: f64,
        gate: f64,
    ) -> ScalarUpdate {
        scalar_update_portable(x, P, H, nu, r, gate)
    }

    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn scalar_update_avx2(
        x: &mut StateVector,
        P: &mut Covariance,
        H: &SparseRow,
        nu: f64,
        r: f64,
        gate: f64,
    ) -> ScalarUpdate {
        scalar_update_portable(x, P, H, nu, r, gate)
    }
}

/// [`scalar_update`] in portable code (the baseline vector unit).
#[inline(always)]
fn scalar_update_portable(
    x: &mut StateVector,
    P: &mut Covariance,
    H: &SparseRow,
    nu: f64,
    r: f64,
    gate: f64,
) -> ScalarUpdate {
    let mut h = [0.0; N];
    for (k, v) in H.entries() {
        // Column k of the symmetric P is its row k: h = P H^T.
        let col = &P.as_slice()[k * N..(k + 1) * N];
        for (hr, p) in h.iter_mut().zip(col) {
            *hr += p * v;
        }
    }
    let mut s = r;
    for (k, v) in H.entries() {
        s += v * h[k];
    }
    let out = ScalarUpdate {
        innovation: nu,
        variance: s,
        applied: false,
    };
    if s.is_nan() || s <= 0.0 || !nu.is_finite() || nu * nu > gate * gate * s {
        return out;
    }
    let mut K = [0.0; N];
    for (k, hr) in K.iter_mut().zip(h.iter()) {
        *k = hr / s;
    }
    for (xi, k) in x.iter_mut().zip(K.iter()) {
        *xi += k * nu;
    }
    rank_two_columns(P.as_mut_slice(), &K, &h, s);
    ScalarUpdate {
        applied: true,
        ..out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::discretize::{discretize, Discretization};
    use limbfuse_core::kalman::{update, CovarianceUpdate};

    fn noise() -> ProcessNoise {
        ProcessNoise {
            angular_jerk: [10.0, 200.0, 400.0, 900.0],
            gyro_bias: 1e-6,
            hip_jerk: 50.0,
            hip_acc_rate: 7.0,
            mean_speed: 1e-3,
            encoder_offset: 1e-8,
        }
    }

    /// A dense SPD covariance from a seeded pseudo-random factor.
    fn spd(seed: u64) -> Covariance {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let L = Covariance::from_fn(|_, _| next());
        L * L.transpose() + Covariance::identity() * 0.1
    }

    /// The continuous model `dx = A x dt + dw` of the whole state.
    fn continuous(q: &ProcessNoise) -> (Covariance, Covariance) {
        let mut A = Covariance::zeros();
        let mut Qc = Covariance::zeros();
        for i in 0..4 {
            A[(theta(i), omega(i))] = 1.0;
            A[(omega(i), alpha(i))] = 1.0;
            Qc[(alpha(i), alpha(i))] = q.angular_jerk[i];
            let g = crate::chain_ekf::state::gyro_bias(i);
            Qc[(g, g)] = q.gyro_bias;
        }
        for k in 0..2 {
            A[(hip_velocity(k), hip_acceleration(k))] = 1.0;
            A[(hip_acceleration(k), hip_acceleration(k))] = -q.hip_acc_rate;
            Qc[(hip_acceleration(k), hip_acceleration(k))] = q.hip_jerk;
        }
        let m = crate::chain_ekf::state::MEAN_SPEED;
        Qc[(m, m)] = q.mean_speed;
        for j in 0..3 {
            let o = crate::chain_ekf::state::encoder_offset(j);
            Qc[(o, o)] = q.encoder_offset;
        }
        (A, Qc)
    }

    #[test]
    fn structured_prediction_equals_van_loan_discretisation() {
        let q = noise();
        let dt = 0.01;
        let (A, Qc) = continuous(&q);
        let (Phi, Qd) = discretize::<N, { 2 * N }>(&A, &Qc, dt, Discretization::Exact);
        let P0 = spd(3);
        let dense = Phi * P0 * Phi.transpose() + Qd;
        let mut P = P0;
        predict_covariance(&mut P, dt, &q);
        let scale = dense.amax();
        assert!((P - dense).amax() < 1e-12 * scale, "{}", (P - dense).amax());
        let x0 = StateVector::from_fn(|i, _| 0.1 * i as f64 - 0.7);
        let mut x = x0;
        predict_state(&mut x, dt, &q);
        assert!((x - Phi * x0).amax() < 1e-14);
    }

    #[test]
    fn gauss_markov_noise_tends_to_the_white_jerk_block_and_its_stationary_variance() {
        let (q, dt) = (40.0, 0.01);
        // beta T = 1e-3: the closed form, within O(beta T) of white jerk.
        let gm = gauss_markov_pair_noise(q, dt, 0.1);
        let wj = triple_integrator_noise(q, dt);
        for r in 0..2 {
            for c in 0..2 {
                let rel = (gm[r][c] - wj[r + 1][c + 1]).abs() / wj[r + 1][c + 1].abs();
                assert!(rel < 2e-3 && rel > 0.0, "{r}{c}: {rel}");
            }
        }
        // Long steps: Q22 -> q / (2 beta), the stationary variance.
        let beta = 5.0;
        let long = gauss_markov_pair_noise(q, 100.0, beta);
        assert!((long[1][1] - q / (2.0 * beta)).abs() < 1e-12);
    }

    #[test]
    fn sparse_scalar_update_equals_the_dense_joseph_update() {
        let mut H = SparseRow::new();
        H.add(theta(2), 0.7);
        H.add(alpha(1), -0.3);
        H.add(hip_acceleration(0), 0.9);
        let Hd = SMatrix::<f64, 1, N>::from_row_slice(&H.dense());
        let P0 = spd(11);
        let x0 = StateVector::from_fn(|i, _| 0.05 * i as f64);
        let z = 0.4;
        let nu = z - (Hd * x0)[0];
        let r = 0.02;
        let dense = update(
            &x0,
            &P0,
            &SVector::<f64, 1>::new(z),
            &Hd,
            &SMatrix::<f64, 1, 1>::new(r),
            CovarianceUpdate::Joseph,
        )
        .unwrap();
        let (mut x, mut P) = (x0, P0);
        let u = scalar_update(&mut x, &mut P, &H, nu, r, f64::INFINITY);
        assert!(u.applied);
        assert!((x - dense.x).amax() < 1e-12);
        assert!((P - dense.P).amax() < 1e-12 * P0.amax());
        assert_eq!(P, P.transpose());
    }

    #[test]
    fn every_vector_unit_gives_the_portable_update_bit_for_bit() {
        let mut H = SparseRow::new();
        H.add(theta(1), 0.3);
        H.add(omega(1), -1.7);
        H.add(hip_acceleration(1), 0.25);
        let mut P0 = spd(5);
        P0 = (P0 + P0.transpose()) * 0.5;
        let x0 = StateVector::from_fn(|i, _| 0.01 * i as f64 - 0.1);
        let (mut x1, mut P1) = (x0, P0);
        let (mut x2, mut P2) = (x0, P0);
        let a = scalar_update(&mut x1, &mut P1, &H, 0.37, 0.003, f64::INFINITY);
        let b = scalar_update_portable(&mut x2, &mut P2, &H, 0.37, 0.003, f64::INFINITY);
        assert!(a.applied && b.applied);
        assert_eq!(
            (a, x1.as_slice(), P1.as_slice()),
            (b, x2.as_slice(), P2.as_slice())
        );
        assert_eq!(P1, P1.transpose());
        assert_ne!(P1, P0);
    }

    #[test]
    fn the_gate_rejects_outliers_and_leaves_the_state() {
        let mut H = SparseRow::new();
        H.add(0, 1.0);
        let mut P = Covariance::identity();
        let mut x = StateVector::zeros();
        // s = 1 + 1 = 2; nu = 10 > 3 sqrt(2).
        let u = scalar_update(&mut x, &mut P, &H, 10.0, 1.0, 3.0);
        assert!(!u.applied);
        assert_eq!((x, P), (StateVector::zeros(), Covariance::identity()));
        let u = scalar_update(&mut x, &mut P, &H, 4.0, 1.0, 3.0);
        assert!(u.applied && (x[0] - 2.0).abs() < 1e-15 && (P[(0, 0)] - 0.5).abs() < 1e-15);
    }
}

#[cfg(test)]
mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// Any sequence of predictions and scalar updates with random sparse
        /// rows keeps `P` exactly symmetric and positive definite.
        #[test]
        fn covariance_stays_symmetric_positive_definite(
            steps in proptest::collection::vec(
                (0.001f64..0.05, proptest::collection::vec((0usize..N, -3.0f64..3.0), 1..8), 1e-6f64..1.0, -1.0f64..1.0),
                1..40,
            )
        ) {
            let q = ProcessNoise {
                angular_jerk: [300.0, 1e4, 1e4, 1e4],
                gyro_bias: 1e-7,
                hip_jerk: 50.0,
                hip_acc_rate: 7.0,
                mean_speed: 1e-3,
                encoder_offset: 1e-10,
            };
            let mut P = Covariance::identity() * 0.01;
            let mut x = StateVector::zeros();
            for (dt, entries, r, nu) in steps {
                predict_covariance(&mut P, dt, &q);
                let mut H = SparseRow::new();
                for (i, v) in entries {
                    H.add(i, v);
                }
                scalar_update(&mut x, &mut P, &H, nu, r, f64::INFINITY);
                prop_assert_eq!(P, P.transpose());
                prop_assert!(P.cholesky().is_some(), "P lost positive definiteness");
            }
        }
    }
}
