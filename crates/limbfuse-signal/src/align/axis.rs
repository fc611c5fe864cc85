//! Medio-lateral axis of a sensor from its gyro signal: the principal axis
//! (largest eigenvector of `sum w w^T`) and the hinge-pair refinement of
//! Seel et al. (paper 002 eq 2): for two segments joined by a hinge with axis
//! `j1` (sensor 1 coordinates) and `j2` (sensor 2), the angular rates
//! projected on the plane normal to the axis agree,
//! `e(k) = ||w1(k) x j1|| - ||w2(k) x j2|| = 0`. The axes of all segments in
//! a chain of hinges (thigh-shank knee, shank-foot ankle) are fitted together
//! by the hinge-axis solver shared with `knee-selfalign`
//! (`limbfuse_estimators::hinge_axis::chain_fit`); this module picks the
//! samples and maps segments to axes.

use limbfuse_core::{Record, Segment};
use limbfuse_estimators::hinge_axis::chain_fit::{fit_hinge_chain, Hinge};
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use super::series::{acc, gyr};

/// Principal axis of the gyro samples: the unit eigenvector of `sum w w^T`
/// with the largest eigenvalue, the fraction of the gyro energy about it,
/// the gyro RMS (rad/s) and the ratio of the second to the largest
/// eigenvalue (0: one clear axis, 1: two axes equally energetic, the axis
/// undetermined). `None` when there is no sample.
pub(crate) fn principal_axis(
    ws: impl Iterator<Item = Vector3<f64>>,
) -> Option<(Vector3<f64>, f64, f64, f64)> {
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
    let mut ev: Vec<f64> = eig.eigenvalues.iter().copied().collect();
    ev.sort_by(|a, b| b.total_cmp(a));
    let ratio = if ev[0] > 0.0 {
        ev[1].max(0.0) / ev[0]
    } else {
        1.0
    };
    Some((v.normalize(), frac, rms, ratio))
}

/// Combines the principal axis of the horizontal gyro `z_h` (the rate about
/// the accelerometer-tracked vertical removed) with the principal axis of
/// the full gyro signal `z_g` (no accelerometer involved).
///
/// The two err in different ways. `z_h` inherits the accelerometer bias:
/// a bias `b_z` along the medio-lateral axis tilts the tracked vertical
/// toward it by `b_z / g`, and the projection turns that into the same tilt
/// of the axis (it cannot be told from a tilted axis by any accelerometer
/// reading). `z_g` is free of it but is pulled toward the vertical by a rate
/// about the vertical that correlates with the sagittal rate (real legs:
/// RMS 1.1 rad/s about the vertical on straight walking, `z_g` 8-38 deg
/// from `z_h` on the gaittoolbox trial). When the two agree within the
/// largest tilt an accelerometer bias can cause (`d0`), the difference can
/// be the bias alone and `z_g` is taken; beyond `2 d0` it cannot, and `z_h`
/// is taken; in between the weight of `z_g` falls linearly (continuous in
/// the data). Returns the unit axis (with the sign of `z_h`) and the weight
/// of `z_g`. `d0 = 0` gives `z_h`.
pub(crate) fn gyro_only_blend(
    z_h: &Vector3<f64>,
    z_g: &Vector3<f64>,
    d0: f64,
) -> (Vector3<f64>, f64) {
    let z_g = if z_g.dot(z_h) < 0.0 { -z_g } else { *z_g };
    let d = z_g.dot(z_h).min(1.0).acos();
    let weight = if d0 > 0.0 {
        (2.0 - d / d0).clamp(0.0, 1.0)
    } else {
        0.0
    };
    if weight == 0.0 {
        return (*z_h, 0.0);
    }
    match (z_h * (1.0 - weight) + z_g * weight).try_normalize(1e-12) {
        Some(z) => (z, weight),
        None => (*z_h, 0.0),
    }
}

/// Result of a hinge-chain fit.
pub(crate) struct HingeFit {
    /// Fitted axis per segment (only segments in a pair are `Some`).
    pub axes: [Option<Vector3<f64>>; 4],
    /// RMS of `e(k)` per pair (rad/s), in the order of the pairs given.
    pub rms: Vec<f64>,
}

/// Fits the axes of the segments joined by `pairs` (proximal, distal),
/// starting from `init` (e.g. principal axes), with the shared hinge-axis
/// solver [`fit_hinge_chain`]. Samples where either gyro is missing are
/// skipped; at most `max_samples` samples per pair are used (evenly strided).
pub(crate) fn hinge_fit(
    records: &[Record],
    pairs: &[(Segment, Segment)],
    init: &[Option<Vector3<f64>>; 4],
    max_samples: usize,
) -> Option<HingeFit> {
    // slot[segment] = index of its axis in the solver's axis list.
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
    let mut axes: Vec<Vector3<f64>> = vec![Vector3::zeros(); m];
    for s in Segment::ALL {
        if slot[s.index()] != usize::MAX {
            axes[slot[s.index()]] = init[s.index()]?;
        }
    }
    let hinges: Vec<Hinge<'_>> = pairs
        .iter()
        .zip(&data)
        .map(|(&(a, b), rates)| Hinge {
            proximal: slot[a.index()],
            distal: slot[b.index()],
            rates,
        })
        .collect();
    let fit = fit_hinge_chain(&hinges, &axes)?;
    let mut out = [None; 4];
    for s in Segment::ALL {
        if slot[s.index()] != usize::MAX {
            out[s.index()] = Some(fit.axes[slot[s.index()]]);
        }
    }
    Some(HingeFit {
        axes: out,
        rms: fit.rms,
    })
}

/// Unit "up" direction (the direction of `-gravity`, i.e. of the static
/// specific force) in the sensor frame at every record, from a
/// complementary filter: the vector is carried along by the gyro
/// (`dv/dt = -w x v`) and pulled toward the normalised accelerometer with
/// time constant `tau` (s); accelerometer readings further than 30 % from
/// their median norm are not used. `None` before the first reading.
///
/// The filter starts from the vertical that the same filter, run backward
/// over the whole recording, gives at the first reading (alignment is
/// offline): a recording that starts mid-stride would otherwise start from
/// one reading's direction, tens of degrees off the vertical in swing, and
/// carry that error for several `tau` into the axis (issue 14, audit
/// 2026-12-03: S02 cut 1 s into the walk).
pub(crate) fn up_track(records: &[Record], seg: Segment, tau: f64) -> Vec<Option<Vector3<f64>>> {
    let mut norms: Vec<f64> = (0..records.len())
        .filter_map(|k| acc(records, seg, k).map(|a| a.norm()))
        .collect();
    let g = super::series::median(&mut norms).unwrap_or(0.0);
    let backward = complementary(records, seg, tau, g, (0..records.len()).rev(), None);
    let start = backward.iter().rev().find_map(|v| *v);
    complementary(records, seg, tau, g, 0..records.len(), start)
}

/// One pass of [`up_track`]'s filter over the records in `order` (forward
/// or backward in time), from `init`; the vertical at each record, in the
/// order visited.
fn complementary(
    records: &[Record],
    seg: Segment,
    tau: f64,
    g: f64,
    order: impl Iterator<Item = usize>,
    init: Option<Vector3<f64>>,
) -> Vec<Option<Vector3<f64>>> {
    let mut v = init;
    let mut t_prev: Option<f64> = None;
    order
        .map(|k| {
            let t = records[k].sample.t;
            // Signed: negative on the backward pass, where the gyro carries
            // the vector back in time.
            let dt = t - t_prev.unwrap_or(t);
            t_prev = Some(t);
            if let (Some(cur), Some(w)) = (v, gyr(records, seg, k)) {
                v = (cur - w.cross(&cur) * dt).try_normalize(1e-12);
            }
            if let Some(a) = acc(records, seg, k) {
                let trusted = g > 0.0 && (a.norm() - g).abs() < 0.3 * g;
                v = match (v, a.try_normalize(1e-9)) {
                    (None, an) => an,
                    (Some(cur), Some(an)) if trusted => {
                        (cur + (an - cur) * (dt.abs() / tau).clamp(0.0, 1.0)).try_normalize(1e-12)
                    }
                    (cur, _) => cur,
                };
            }
            v
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::gyro_only_blend;
    use nalgebra::Vector3;

    /// Issue 14: the gyro-only axis is taken in full within `d0` of the
    /// horizontal one, not at all beyond `2 d0`, linearly in between, and
    /// its sign never matters.
    #[test]
    fn issue_14_gyro_only_blend_weights() {
        let d0 = 3f64.to_radians();
        let z_h = Vector3::z();
        let at = |deg: f64| Vector3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        let angle = |a: &Vector3<f64>, b: &Vector3<f64>| a.dot(b).min(1.0).acos().to_degrees();
        for (deg, weight) in [(0.0, 1.0), (2.9, 1.0), (4.5, 0.5), (6.1, 0.0), (40.0, 0.0)] {
            for sign in [1.0, -1.0] {
                let (z, w) = gyro_only_blend(&z_h, &(at(deg) * sign), d0);
                assert!((w - weight).abs() < 1e-9, "{deg} deg: weight {w}");
                assert!((z.norm() - 1.0).abs() < 1e-12 && z.dot(&z_h) > 0.0);
                if weight == 1.0 {
                    assert!(angle(&z, &at(deg)) < 1e-9, "{deg} deg");
                }
                if weight == 0.0 {
                    assert_eq!(z, z_h);
                }
            }
        }
        // Half weight: the axis lies half-way between the two.
        let (z, _) = gyro_only_blend(&z_h, &at(4.5), d0);
        assert!((angle(&z, &z_h) - 2.25).abs() < 1e-3);
        // d0 = 0: the horizontal axis alone.
        assert_eq!(gyro_only_blend(&z_h, &at(1.0), 0.0), (z_h, 0.0));
    }
}
