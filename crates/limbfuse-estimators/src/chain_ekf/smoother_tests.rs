//! The RTS smoother against an independent batch solution, and its
//! covariance properties.

use super::*;
use crate::chain_ekf::covariance::scalar_update;
use crate::chain_ekf::state::SparseRow;
use nalgebra::DMatrix;
use proptest::prelude::*;

fn noise() -> ProcessNoise {
    ProcessNoise {
        angular_jerk: [2.0, 5.0, 8.0, 10.0],
        gyro_bias: 1e-2,
        hip_jerk: 3.0,
        hip_acc_rate: 2.0,
        mean_speed: 1e-2,
        encoder_offset: 1e-2,
    }
}

/// A seeded pseudo-random stream in [-0.5, 0.5).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    }
}

/// One step of a linear-Gaussian test problem.
struct StepData {
    dt: f64,
    widening: f64,
    rows: Vec<(SparseRow, f64, f64)>,
}

fn problem(seed: u64, steps: usize) -> (StateVector, Covariance, Vec<StepData>) {
    let mut r = Lcg(seed);
    let m0 = StateVector::from_fn(|_, _| r.next());
    let l = Covariance::from_fn(|_, _| r.next());
    let p0 = l * l.transpose() * 0.2 + Covariance::identity() * 0.05;
    let data = (0..steps)
        .map(|k| {
            let rows = (0..6)
                .map(|_| {
                    let mut row = SparseRow::new();
                    for _ in 0..3 {
                        let i = ((r.next() + 0.5) * N as f64) as usize % N;
                        row.add(i, 2.0 * r.next());
                    }
                    (row, 2.0 * r.next(), 0.01 + (r.next() + 0.5) * 0.1)
                })
                .collect();
            StepData {
                dt: 0.02 + 0.05 * (r.next() + 0.5),
                widening: if k % 3 == 1 { 0.01 } else { 0.0 },
                rows,
            }
        })
        .collect();
    (m0, p0, data)
}

/// Sequential filter, then the smoother's backward pass; per step x_s.
/// Filters `data` from (`m0`, `p0`) with the chain's own prediction and
/// scalar updates, pushing every step (time `k * step_s`) into a smoother
/// with `settings`; returns everything it emits, in order. With
/// `max_held`, also checks that the smoother never holds more steps.
fn filter_through_smoother(
    m0: &StateVector,
    p0: &Covariance,
    data: &[StepData],
    settings: SmootherSettings,
    step_s: f64,
    max_held: Option<usize>,
) -> Vec<(usize, Option<Smoothed>)> {
    let q = noise();
    let mut smoother = RtsSmoother::new(q, settings);
    let (mut x, mut p) = (*m0, *p0);
    let mut out = Vec::new();
    for (k, d) in data.iter().enumerate() {
        let link = if k == 0 {
            Link::Start
        } else {
            (x, p) = predict(&x, &p, d.dt, d.widening, &q);
            Link::Continue {
                dt: d.dt,
                widening: d.widening,
            }
        };
        for (row, z, r) in &d.rows {
            let nu = z - row.entries().map(|(i, v)| v * x[i]).sum::<f64>();
            scalar_update(&mut x, &mut p, row, nu, *r, f64::INFINITY);
        }
        smoother.push(k as f64 * step_s, link, &x, &p, k);
        if let Some(max) = max_held {
            assert!(smoother.held() <= max);
        }
        out.extend(core::iter::from_fn(|| smoother.pop()));
    }
    smoother.finish();
    out.extend(core::iter::from_fn(|| smoother.pop()));
    out
}

fn filter_and_smooth(m0: &StateVector, p0: &Covariance, data: &[StepData]) -> Vec<StateVector> {
    filter_through_smoother(m0, p0, data, SmootherSettings::WHOLE_TRIAL, 0.01, None)
        .into_iter()
        .map(|(_, s)| s.unwrap().x)
        .collect()
}

/// The same problem solved as one Gaussian conditioning of all states at
/// once (covariance form): prior mean and covariance of the stacked states
/// from the model, then `mu + Sigma H^T (H Sigma H^T + R)^-1 (z - H mu)`.
fn batch(m0: &StateVector, p0: &Covariance, data: &[StepData]) -> (DMatrix<f64>, DMatrix<f64>) {
    let q = noise();
    let n = data.len();
    let dim = n * N;
    let mut mu = DMatrix::zeros(dim, 1);
    let mut sigma = DMatrix::zeros(dim, dim);
    let mut phis = Vec::new();
    let (mut m, mut p) = (*m0, *p0);
    for (k, d) in data.iter().enumerate() {
        if k > 0 {
            let f = transition(d.dt, &q);
            // Q from the structured prediction of a zero covariance.
            let mut qd = Covariance::zeros();
            predict_covariance(&mut qd, d.dt, &q);
            for i in 0..4 {
                qd[(theta(i), theta(i))] += d.widening;
            }
            m = f * m;
            p = f * p * f.transpose() + qd;
            phis.push(f);
        }
        mu.view_mut((k * N, 0), (N, 1)).copy_from(&m);
        sigma.view_mut((k * N, k * N), (N, N)).copy_from(&p);
        // Cross terms Cov(x_k, x_j) = Phi_{k-1} ... Phi_j Cov(x_j, x_j).
        let mut a = Covariance::identity();
        for j in (0..k).rev() {
            a *= phis[j];
            let pj: Covariance = Covariance::from_fn(|r, c| sigma[(j * N + r, j * N + c)]);
            let c = a * pj;
            sigma.view_mut((k * N, j * N), (N, N)).copy_from(&c);
            sigma
                .view_mut((j * N, k * N), (N, N))
                .copy_from(&c.transpose());
        }
    }
    let rows: Vec<(usize, &SparseRow, f64, f64)> = data
        .iter()
        .enumerate()
        .flat_map(|(k, d)| d.rows.iter().map(move |(row, z, r)| (k, row, *z, *r)))
        .collect();
    let m_rows = rows.len();
    let mut h = DMatrix::zeros(m_rows, dim);
    let mut z = DMatrix::zeros(m_rows, 1);
    let mut r = DMatrix::zeros(m_rows, m_rows);
    for (i, (k, row, zi, ri)) in rows.iter().enumerate() {
        for (j, v) in row.entries() {
            h[(i, k * N + j)] += v;
        }
        z[(i, 0)] = *zi;
        r[(i, i)] = *ri;
    }
    let s = &h * &sigma * h.transpose() + r;
    let gain_t = s.cholesky().unwrap().solve(&(&h * &sigma));
    let mean = &mu + gain_t.transpose() * (z - &h * &mu);
    let cov = &sigma - gain_t.transpose() * &h * &sigma;
    (mean, cov)
}

#[test]
fn rts_equals_the_batch_solution_of_a_linear_gaussian_model() {
    let (m0, p0, data) = problem(7, 14);
    let (mean, cov) = batch(&m0, &p0, &data);
    let out = filter_and_smooth(&m0, &p0, &data);
    assert_eq!(out.len(), data.len());
    let mut worst = (0.0f64, 0.0f64);
    for (k, x_s) in out.iter().enumerate() {
        for i in 0..N {
            worst.0 = worst.0.max((x_s[i] - mean[(k * N + i, 0)]).abs());
        }
    }
    // Covariances: the whole recursion, by hand, against the batch blocks.
    let q = noise();
    let (mut x, mut p) = (m0, p0);
    let mut fil = Vec::new();
    for (k, d) in data.iter().enumerate() {
        if k > 0 {
            (x, p) = predict(&x, &p, d.dt, d.widening, &q);
        }
        for (row, z, r) in &d.rows {
            let nu = z - row.entries().map(|(i, v)| v * x[i]).sum::<f64>();
            scalar_update(&mut x, &mut p, row, nu, *r, f64::INFINITY);
        }
        fil.push((x, p));
    }
    let mut next = fil[data.len() - 1];
    for k in (0..data.len()).rev() {
        if k + 1 < data.len() {
            let d = &data[k + 1];
            next = rts_step(
                &fil[k].0,
                &fil[k].1,
                d.dt,
                d.widening,
                &q,
                (&next.0, &next.1),
            )
            .unwrap();
        }
        for r in 0..N {
            for c in 0..N {
                worst.1 = worst
                    .1
                    .max((next.1[(r, c)] - cov[(k * N + r, k * N + c)]).abs());
            }
        }
        assert!((next.0 - out[k]).amax() == 0.0, "step {k}");
    }
    println!(
        "batch vs RTS: max mean difference {:.1e}, max covariance difference {:.1e}",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-9 && worst.1 < 1e-9, "{worst:?}");
}

#[test]
fn the_backward_pass_does_not_cross_a_restart() {
    let (m0, p0, data) = problem(3, 8);
    let q = noise();
    let mut smoother = RtsSmoother::new(q, SmootherSettings::WHOLE_TRIAL);
    let (mut x, mut p) = (m0, p0);
    let mut filtered = Vec::new();
    for (k, d) in data.iter().enumerate() {
        let link = match k {
            0 | 4 => Link::Start,
            3 => Link::None,
            _ => {
                (x, p) = predict(&x, &p, d.dt, d.widening, &q);
                Link::Continue {
                    dt: d.dt,
                    widening: d.widening,
                }
            }
        };
        if k != 3 {
            for (row, z, r) in &d.rows {
                let nu = z - row.entries().map(|(i, v)| v * x[i]).sum::<f64>();
                scalar_update(&mut x, &mut p, row, nu, *r, f64::INFINITY);
            }
        }
        filtered.push(x);
        smoother.push(k as f64, link, &x, &p, k);
    }
    smoother.finish();
    let out: Vec<_> = core::iter::from_fn(|| smoother.pop()).collect();
    assert_eq!(out.len(), 8);
    assert!(out[3].1.is_none());
    // The last step of each segment keeps its filtered state; the others move.
    assert_eq!(out[2].1.unwrap().x, filtered[2]);
    assert_eq!(out[7].1.unwrap().x, filtered[7]);
    assert_ne!(out[1].1.unwrap().x, filtered[1]);
    assert_ne!(out[5].1.unwrap().x, filtered[5]);
}

#[test]
fn blocks_with_an_overlap_longer_than_the_trial_equal_the_whole_trial() {
    let (m0, p0, data) = problem(11, 30);
    let run = |settings: SmootherSettings| {
        filter_through_smoother(&m0, &p0, &data, settings, 1.0, Some(30))
    };
    let whole = run(SmootherSettings::WHOLE_TRIAL);
    let blocks = run(SmootherSettings {
        block_s: 5.0,
        overlap_s: 40.0,
    });
    assert_eq!(whole.len(), 30);
    assert_eq!(blocks.len(), 30);
    for (a, b) in whole.iter().zip(&blocks) {
        assert_eq!(a.0, b.0);
        assert_eq!(a.1, b.1);
    }
    // A short overlap emits earlier: blocks of 5 steps after 8 held.
    let short = run(SmootherSettings {
        block_s: 5.0,
        overlap_s: 3.0,
    });
    assert_eq!(short.len(), 30);
    assert_eq!(short[29].1, whole[29].1);
}

#[test]
fn pack_and_unpack_round_trip() {
    let (_, p0, _) = problem(5, 1);
    assert_eq!(unpack(&pack(&p0)), p0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The smoothed covariance is never larger than the filtered one
    /// (`P_f - P_s` positive semi-definite) and stays positive
    /// semi-definite and symmetric.
    #[test]
    fn smoothed_covariance_is_psd_and_never_larger_than_filtered(seed in 0u64..10_000, steps in 2usize..12) {
        let (m0, p0, data) = problem(seed, steps);
        let q = noise();
        let (mut x, mut p) = (m0, p0);
        let mut fil = Vec::new();
        for (k, d) in data.iter().enumerate() {
            if k > 0 {
                (x, p) = predict(&x, &p, d.dt, d.widening, &q);
            }
            for (row, z, r) in &d.rows {
                let nu = z - row.entries().map(|(i, v)| v * x[i]).sum::<f64>();
                scalar_update(&mut x, &mut p, row, nu, *r, f64::INFINITY);
            }
            fil.push((x, p));
        }
        let mut next = fil[steps - 1];
        for k in (0..steps - 1).rev() {
            let d = &data[k + 1];
            next = rts_step(&fil[k].0, &fil[k].1, d.dt, d.widening, &q, (&next.0, &next.1)).unwrap();
            let ps = next.1;
            prop_assert_eq!(ps, ps.transpose());
            let scale = fil[k].1.amax();
            let min_s = ps.symmetric_eigen().eigenvalues.min();
            prop_assert!(min_s > -1e-10 * scale, "P_s eigenvalue {}", min_s);
            let diff = fil[k].1 - ps;
            let diff = (diff + diff.transpose()) * 0.5;
            let min_d = diff.symmetric_eigen().eigenvalues.min();
            prop_assert!(min_d > -1e-10 * scale, "P_f - P_s eigenvalue {}", min_d);
        }
    }
}
