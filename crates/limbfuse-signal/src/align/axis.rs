//! Medio-lateral axis of a sensor from its gyro signal: the principal axis
//! (largest eigenvector of `sum w w^T`) and the hinge-pair refinement of
//! Seel et al. (paper 002 eq 2): for two segments joined by a hinge with axis
//! `j1` (sensor 1 coordinates) and `j2` (sensor 2), the angular rates
//! projected on the plane normal to the axis agree,
//! `e(k) = ||w1(k) x j1|| - ||w2(k) x j2|| = 0`. The axes of all segments in
//! a chain of hinges (thigh-shank knee, shank-foot ankle) are fitted together
//! by Levenberg-Marquardt on two tangent-plane coordinates per axis.

use limbfuse_core::{Record, Segment};
use nalgebra::{DMatrix, DVector, Matrix3, SymmetricEigen, Vector3};

use super::series::{acc, gyr};

/// Principal axis of the gyro samples: the unit eigenvector of `sum w w^T`
/// with the largest eigenvalue, the fraction of the gyro energy about it and
/// the gyro RMS (rad/s). `None` when there is no sample.
pub(crate) fn principal_axis(
    ws: impl Iterator<Item = Vector3<f64>>,
) -> Option<(Vector3<f64>, f64, f64)> {
    let mut c = Matrix3::zeros();
    let mut n = 0usize;
    for w in ws {
        c += w * w.transpose();
        n += 1;
    }
    if n == 0 {
        return None;
    }
    let tr = c.trace();
    let rms = (tr / n as f64).sqrt();
    let eig = SymmetricEigen::new(c);
    let i = eig.eigenvalues.imax();
    let v: Vector3<f64> = eig.eigenvectors.column(i).into();
    let frac = if tr > 0.0 {
        eig.eigenvalues[i] / tr
    } else {
        0.0
    };
    Some((v.normalize(), frac, rms))
}

/// Two unit vectors spanning the plane normal to unit `j`.
pub(crate) fn tangent_basis(j: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let a = if j.x.abs() < 0.6 {
        Vector3::x()
    } else if j.y.abs() < 0.6 {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let e1 = j.cross(&a).normalize();
    (e1, j.cross(&e1))
}

/// Result of a hinge-chain fit.
pub(crate) struct HingeFit {
    /// Fitted axis per segment (only segments in a pair are `Some`).
    pub axes: [Option<Vector3<f64>>; 4],
    /// RMS of `e(k)` per pair (rad/s), in the order of the pairs given.
    pub rms: Vec<f64>,
}

const EPS: f64 = 1e-6;

/// `||w x j||` (smoothed at 0) and its tangent-plane gradient.
#[inline]
fn perp(w: &Vector3<f64>, j: &Vector3<f64>, e: &(Vector3<f64>, Vector3<f64>)) -> (f64, f64, f64) {
    let wj = w.dot(j);
    let f = (w.norm_squared() - wj * wj).max(0.0).sqrt().max(EPS);
    (f, -wj * w.dot(&e.0) / f, -wj * w.dot(&e.1) / f)
}

/// Fits the axes of the segments joined by `pairs` (proximal, distal),
/// starting from `init` (e.g. principal axes). Samples where either gyro is
/// missing are skipped; at most `max_samples` samples per pair are used
/// (evenly strided).
pub(crate) fn hinge_fit(
    records: &[Record],
    pairs: &[(Segment, Segment)],
    init: &[Option<Vector3<f64>>; 4],
    max_samples: usize,
) -> Option<HingeFit> {
    let mut slot = [usize::MAX; 4];
    let mut m = 0;
    for &(a, b) in pairs {
        for s in [a, b] {
            if slot[s.index()] == usize::MAX {
                init[s.index()]?;
                slot[s.index()] = m;
                m += 1;
            }
        }
    }
    let data: Vec<Vec<(Vector3<f64>, Vector3<f64>)>> = pairs
        .iter()
        .map(|&(a, b)| {
            let all: Vec<_> = (0..records.len())
                .filter_map(|k| Some((gyr(records, a, k)?, gyr(records, b, k)?)))
                .collect();
            let stride = all.len().div_ceil(max_samples.max(1)).max(1);
            all.into_iter().step_by(stride).collect()
        })
        .collect();
    let n_res: usize = data.iter().map(Vec::len).sum();
    if m == 0 || n_res < 4 * m {
        return None;
    }
    let mut axes: Vec<Vector3<f64>> = vec![Vector3::zeros(); m];
    for s in Segment::ALL {
        if slot[s.index()] != usize::MAX {
            axes[slot[s.index()]] = init[s.index()]?.normalize();
        }
    }
    let cost = |axes: &[Vector3<f64>]| -> f64 {
        let mut c = 0.0;
        for (p, &(a, b)) in pairs.iter().enumerate() {
            let (ja, jb) = (axes[slot[a.index()]], axes[slot[b.index()]]);
            for (w1, w2) in &data[p] {
                let r = w1.cross(&ja).norm() - w2.cross(&jb).norm();
                c += r * r;
            }
        }
        c
    };
    let mut c0 = cost(&axes);
    let mut lambda = 1e-3;
    for _ in 0..100 {
        let basis: Vec<_> = axes.iter().map(tangent_basis).collect();
        let mut jtj = DMatrix::<f64>::zeros(2 * m, 2 * m);
        let mut jtr = DVector::<f64>::zeros(2 * m);
        for (p, &(a, b)) in pairs.iter().enumerate() {
            let (ia, ib) = (slot[a.index()], slot[b.index()]);
            for (w1, w2) in &data[p] {
                let (f1, g1a, g1b) = perp(w1, &axes[ia], &basis[ia]);
                let (f2, g2a, g2b) = perp(w2, &axes[ib], &basis[ib]);
                let r = f1 - f2;
                let idx = [2 * ia, 2 * ia + 1, 2 * ib, 2 * ib + 1];
                let g = [g1a, g1b, -g2a, -g2b];
                for u in 0..4 {
                    jtr[idx[u]] += g[u] * r;
                    for v in 0..4 {
                        jtj[(idx[u], idx[v])] += g[u] * g[v];
                    }
                }
            }
        }
        let mut improved = false;
        for _ in 0..10 {
            let mut h = jtj.clone();
            for d in 0..2 * m {
                h[(d, d)] += lambda * (jtj[(d, d)] + 1e-9);
            }
            let Some(step) = h.cholesky().map(|ch| ch.solve(&(-&jtr))) else {
                lambda *= 10.0;
                continue;
            };
            let trial: Vec<Vector3<f64>> = (0..m)
                .map(|i| {
                    (axes[i] + basis[i].0 * step[2 * i] + basis[i].1 * step[2 * i + 1]).normalize()
                })
                .collect();
            let c1 = cost(&trial);
            if c1 < c0 {
                let small = step.norm() < 1e-10;
                axes = trial;
                c0 = c1;
                lambda = (lambda * 0.3).max(1e-12);
                improved = !small;
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    let mut out = [None; 4];
    for s in Segment::ALL {
        if slot[s.index()] != usize::MAX {
            out[s.index()] = Some(axes[slot[s.index()]]);
        }
    }
    let rms = pairs
        .iter()
        .enumerate()
        .map(|(p, &(a, b))| {
            let (ja, jb) = (axes[slot[a.index()]], axes[slot[b.index()]]);
            let s: f64 = data[p]
                .iter()
                .map(|(w1, w2)| (w1.cross(&ja).norm() - w2.cross(&jb).norm()).powi(2))
                .sum();
            (s / data[p].len().max(1) as f64).sqrt()
        })
        .collect();
    Some(HingeFit { axes: out, rms })
}

/// Unit "up" direction (the direction of `-gravity`, i.e. of the static
/// specific force) in the sensor frame at every record, from a
/// complementary filter: the vector is carried along by the gyro
/// (`dv/dt = -w x v`) and pulled toward the normalised accelerometer with
/// time constant `tau` (s); accelerometer readings further than 30 % from
/// their median norm are not used. `None` before the first reading.
pub(crate) fn up_track(records: &[Record], seg: Segment, tau: f64) -> Vec<Option<Vector3<f64>>> {
    let mut norms: Vec<f64> = (0..records.len())
        .filter_map(|k| acc(records, seg, k).map(|a| a.norm()))
        .collect();
    let g = super::series::median(&mut norms).unwrap_or(0.0);
    let mut v: Option<Vector3<f64>> = None;
    let mut t_prev = records.first().map_or(0.0, |r| r.sample.t);
    records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let dt = r.sample.t - t_prev;
            t_prev = r.sample.t;
            if let (Some(cur), Some(w)) = (v, gyr(records, seg, k)) {
                v = (cur - w.cross(&cur) * dt).try_normalize(1e-12);
            }
            if let Some(a) = acc(records, seg, k) {
                let trusted = g > 0.0 && (a.norm() - g).abs() < 0.3 * g;
                v = match (v, a.try_normalize(1e-9)) {
                    (None, an) => an,
                    (Some(cur), Some(an)) if trusted => {
                        (cur + (an - cur) * (dt / tau).clamp(0.0, 1.0)).try_normalize(1e-12)
                    }
                    (cur, _) => cur,
                };
            }
            v
        })
        .collect()
}
