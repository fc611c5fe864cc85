//! Batch fit of the axes of a chain of hinges (e.g. thigh-shank knee and
//! shank-foot ankle share the shank axis): Levenberg-Marquardt on the sum of
//! the squared residuals of eq 2 over all hinges and samples, each axis
//! moved by two coordinates in the plane tangent to it and re-normalised
//! after each step (no singularity at the poles of eq 1's spherical
//! coordinates, which a batch fit from arbitrary starting axes would meet).

use alloc::vec::Vec;

use nalgebra::{DMatrix, DVector, Vector3};

use super::{hinge_residual, MIN_PERPENDICULAR_RATE};

/// Two unit vectors `(e_1, e_2)` spanning the plane normal to the unit axis
/// `j`, with `e_2 = j x e_1`: the tangent coordinates of the chain fit.
pub fn tangent_basis(j: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
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

/// `||g x j||` and its gradient (eq 11) along the tangent directions
/// `basis = (e_1, e_2)` of the unit axis `j`.
///
/// As `e_i` is normal to `j`, eq 11 projected on it is
/// `((g x j) x g) . e_i / ||g x j|| = -(g . j)(g . e_i) / ||g x j||`, which
/// is what is evaluated, with `||g x j|| = sqrt(|g|^2 - (g . j)^2)` floored
/// at [`MIN_PERPENDICULAR_RATE`] (a rate along the axis then contributes a
/// zero gradient instead of being dropped).
#[inline]
pub fn perpendicular_rate_tangent(
    g: &Vector3<f64>,
    j: &Vector3<f64>,
    basis: &(Vector3<f64>, Vector3<f64>),
) -> (f64, f64, f64) {
    let gj = g.dot(j);
    let f = libm::sqrt((g.norm_squared() - gj * gj).max(0.0)).max(MIN_PERPENDICULAR_RATE);
    (f, -gj * g.dot(&basis.0) / f, -gj * g.dot(&basis.1) / f)
}

/// One hinge of the chain.
#[derive(Debug, Clone, Copy)]
pub struct Hinge<'a> {
    /// Index (into the axes given to [`fit_hinge_chain`]) of the axis in the
    /// proximal sensor's frame (`j_1` of eq 2).
    pub proximal: usize,
    /// Index of the axis in the distal sensor's frame (`j_2` of eq 2).
    pub distal: usize,
    /// Simultaneous angular rates `(g_1(k), g_2(k))` (rad/s), each in its
    /// sensor's frame.
    pub rates: &'a [(Vector3<f64>, Vector3<f64>)],
}

/// Result of [`fit_hinge_chain`].
#[derive(Debug, Clone, PartialEq)]
pub struct HingeChainFit {
    /// The fitted unit axes, in the order of the initial axes.
    pub axes: Vec<Vector3<f64>>,
    /// RMS of `e_j(k)` (eq 2) per hinge (rad/s), in the order of the hinges.
    pub rms: Vec<f64>,
}

/// Largest number of Levenberg-Marquardt iterations.
const MAX_ITERATIONS: usize = 100;
/// Largest number of damping increases (x10) tried per iteration.
const MAX_DAMPING_TRIES: usize = 10;

/// Fits the axes `init` (any non-zero length; normalised first) so that the
/// residuals of eq 2 of every hinge vanish in the least-squares sense.
///
/// Levenberg-Marquardt with damping `lambda` (start 1e-3, x10 on a rejected
/// step, x0.3 down to 1e-12 on an accepted one) on the diagonal of `J^T J`,
/// at most 100 iterations; stops when no step of up to ten damping
/// increases lowers the cost or when the accepted step is below 1e-10.
/// `None` when there is no axis, fewer than four residuals per axis in
/// total, or a hinge names an axis outside `init`.
pub fn fit_hinge_chain(hinges: &[Hinge<'_>], init: &[Vector3<f64>]) -> Option<HingeChainFit> {
    let m = init.len();
    let n_res: usize = hinges.iter().map(|h| h.rates.len()).sum();
    if m == 0 || n_res < 4 * m || hinges.iter().any(|h| h.proximal >= m || h.distal >= m) {
        return None;
    }
    let mut axes: Vec<Vector3<f64>> = init.iter().map(|j| j.normalize()).collect();
    let cost = |axes: &[Vector3<f64>]| -> f64 {
        let mut c = 0.0;
        for h in hinges {
            let (ja, jb) = (axes[h.proximal], axes[h.distal]);
            for (w1, w2) in h.rates {
                let r = hinge_residual(w1, &ja, w2, &jb);
                c += r * r;
            }
        }
        c
    };
    let mut c0 = cost(&axes);
    let mut lambda = 1e-3;
    for _ in 0..MAX_ITERATIONS {
        let basis: Vec<_> = axes.iter().map(tangent_basis).collect();
        let mut jtj = DMatrix::<f64>::zeros(2 * m, 2 * m);
        let mut jtr = DVector::<f64>::zeros(2 * m);
        for h in hinges {
            let (ia, ib) = (h.proximal, h.distal);
            for (w1, w2) in h.rates {
                let (f1, g1a, g1b) = perpendicular_rate_tangent(w1, &axes[ia], &basis[ia]);
                let (f2, g2a, g2b) = perpendicular_rate_tangent(w2, &axes[ib], &basis[ib]);
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
        for _ in 0..MAX_DAMPING_TRIES {
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
    let rms = hinges
        .iter()
        .map(|h| {
            let (ja, jb) = (axes[h.proximal], axes[h.distal]);
            let s: f64 = h
                .rates
                .iter()
                .map(|(w1, w2)| {
                    let r = hinge_residual(w1, &ja, w2, &jb);
                    r * r
                })
                .sum();
            libm::sqrt(s / h.rates.len().max(1) as f64)
        })
        .collect();
    Some(HingeChainFit { axes, rms })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_basis_is_orthonormal() {
        for j in [
            Vector3::x(),
            Vector3::y(),
            Vector3::z(),
            Vector3::new(0.3, -0.5, 0.8).normalize(),
        ] {
            let (e1, e2) = tangent_basis(&j);
            assert!(e1.dot(&j).abs() < 1e-15 && e2.dot(&j).abs() < 1e-15);
            assert!(e1.dot(&e2).abs() < 1e-15);
            assert!((e1.norm() - 1.0).abs() < 1e-15 && (e2.norm() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn tangent_gradient_is_eq11_projected() {
        let g = Vector3::new(0.3, -1.2, 2.5);
        let j = Vector3::new(0.2, 0.9, -0.4).normalize();
        let basis = tangent_basis(&j);
        let (f, d1, d2) = perpendicular_rate_tangent(&g, &j, &basis);
        let full = super::super::perpendicular_rate_gradient(&g, &j).unwrap();
        assert!((f - g.cross(&j).norm()).abs() < 1e-12);
        assert!((d1 - full.dot(&basis.0)).abs() < 1e-12);
        assert!((d2 - full.dot(&basis.1)).abs() < 1e-12);
    }

    #[test]
    fn recovers_the_axes_of_a_hinge() {
        // Thigh frame = world; shank frame rotated 0.7 rad about x; hinge
        // axis z in the world. Rates: thigh w(k), shank w(k) + rate(k) z.
        let r = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), 0.7);
        let j_world = Vector3::z();
        let rates: Vec<_> = (0..200)
            .map(|k| {
                let t = k as f64 * 0.01;
                let w = Vector3::new(libm::sin(3.0 * t), 0.5 * libm::cos(2.0 * t), libm::sin(t));
                let w_s = w + j_world * (2.0 * libm::sin(5.0 * t));
                (w, r.inverse() * w_s)
            })
            .collect();
        let hinges = [Hinge {
            proximal: 0,
            distal: 1,
            rates: &rates,
        }];
        let init = [
            Vector3::new(0.2, 0.1, 1.0),
            r.inverse() * Vector3::new(-0.1, 0.2, 1.0),
        ];
        let fit = fit_hinge_chain(&hinges, &init).unwrap();
        assert!((fit.axes[0] - j_world).norm() < 1e-6, "{}", fit.axes[0]);
        assert!((fit.axes[1] - r.inverse() * j_world).norm() < 1e-6);
        assert!(fit.rms[0] < 1e-8, "{}", fit.rms[0]);
        assert!(fit_hinge_chain(&hinges, &[]).is_none());
        assert!(fit_hinge_chain(&hinges[..0], &init).is_none());
    }
}
