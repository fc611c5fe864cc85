//! Trunk (pelvis) medio-lateral axis from gravity and the walking direction,
//! the latter found through the hip joint that pelvis and thigh share.
//!
//! The pelvis has no hinge partner (the hip is a ball joint) and its rates
//! about the vertical (pelvic rotation) and forward (obliquity) axes are as
//! large as its sagittal tilt rate, so neither the principal gyro axis nor a
//! hinge fit finds its medio-lateral axis. Instead:
//! * up `u` = direction of the mean specific force (the mean acceleration of
//!   a walking body is ~0);
//! * forward: the hip joint centre is a point of both the pelvis and the
//!   thigh. Once the thigh is aligned, its sensor's specific force turned
//!   into the world sagittal frame by the thigh angle `phi`, minus the
//!   rotational terms of its unknown lever arm `r` to the hip, is the hip's
//!   forward specific force:
//!   `f_hip = [Rz(phi) a]_x + r_x (alpha sin phi + w^2 cos phi) + r_y (alpha cos phi - w^2 sin phi)`.
//!   The pelvis sensor, close to the hip and rotating little, sees about the
//!   same acceleration, so `f_hip = b1 h1 + b2 h2` with `h1, h2` its
//!   specific force along two horizontal axes. A linear least-squares fit of
//!   `(b1, b2, r, offset, thigh-zero error)` gives the forward direction
//!   `b1 e1 + b2 e2` in the pelvis sensor, sign included (`|b|` ~ 1 and the
//!   fit correlation are the quality figures). A small ridge on `(b1, b2)`
//!   keeps a horizontal direction without acceleration (no lateral sway in
//!   a planar simulation) from taking an arbitrary coefficient;
//! * `z = forward x up` (x forward, y up, z right).

use limbfuse_core::{Record, Segment};
use limbfuse_estimators::hinge_axis::chain_fit::tangent_basis;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::series::{acc, correlation, gyr};

/// Trunk axis estimate.
pub(crate) struct TrunkAxis {
    /// Medio-lateral axis (sensor coordinates, pointing right).
    pub z: Vector3<f64>,
    /// Up direction (sensor coordinates).
    pub up: Vector3<f64>,
    /// Correlation of the fitted hip forward acceleration (thigh side) with
    /// the pelvis forward acceleration.
    pub corr: f64,
    /// Gain `|b|` of the pelvis acceleration in the fit (~1 expected).
    pub gain: f64,
}

/// Estimates the trunk axis from the samples `idx`, given the thigh's
/// rotation (raw to aligned) and its gyro-aided angle `(k, phi)` series.
/// `None` when there are too few usable samples or the fit is degenerate.
pub(crate) fn trunk_axis(
    records: &[Record],
    idx: &[usize],
    thigh_rot: &Matrix3<f64>,
    thigh_phi: &[(usize, f64)],
) -> Option<TrunkAxis> {
    let (tr, th) = (Segment::Trunk, Segment::Thigh);
    let n = records.len();
    let mean: Vector3<f64> = idx.iter().filter_map(|&k| acc(records, tr, k)).sum();
    let up = mean.try_normalize(1e-9)?;
    let (e1, e2) = tangent_basis(&up);
    let mut phi = vec![None; n];
    for &(k, p) in thigh_phi {
        phi[k] = Some(p);
    }
    let rate = |k: usize| gyr(records, th, k).map(|w| thigh_rot.row(2).dot(&w.transpose()));
    // Rows: regressors (h1, h2, 1, vertical, -X1, -X2) and target y.
    let mut rows: Vec<([f64; 6], f64)> = Vec::with_capacity(idx.len());
    for &k in idx {
        if k == 0 || k + 1 >= n {
            continue;
        }
        let (Some(p), Some(at), Some(a), Some(w)) =
            (phi[k], acc(records, tr, k), acc(records, th, k), rate(k))
        else {
            continue;
        };
        // Angular acceleration: central difference, one-sided next to a gap.
        let (lo, wl) = rate(k - 1).map_or((k, w), |x| (k - 1, x));
        let (hi, wh) = rate(k + 1).map_or((k, w), |x| (k + 1, x));
        if lo == hi {
            continue;
        }
        let alpha = (wh - wl) / (records[hi].sample.t - records[lo].sample.t);
        let a = thigh_rot * a;
        let (s, c) = p.sin_cos();
        let y = c * a.x - s * a.y;
        let vert = s * a.x + c * a.y;
        let x1 = alpha * s + w * w * c;
        let x2 = alpha * c - w * w * s;
        rows.push(([at.dot(&e1), at.dot(&e2), 1.0, vert, -x1, -x2], y));
    }
    if rows.len() < 50 {
        return None;
    }
    let mut ata = SMatrix::<f64, 6, 6>::zeros();
    let mut aty = SVector::<f64, 6>::zeros();
    for (x, y) in &rows {
        let x = SVector::<f64, 6>::from_column_slice(x);
        ata += x * x.transpose();
        aty += x * *y;
    }
    // Ridge on the two pelvis coefficients (1 % of their mean diagonal): a
    // horizontal direction without acceleration (no sway) gets a coefficient
    // near 0 instead of an arbitrary one.
    let ridge = 0.01 * 0.5 * (ata[(0, 0)] + ata[(1, 1)]);
    ata[(0, 0)] += ridge;
    ata[(1, 1)] += ridge;
    let b = ata.cholesky()?.solve(&aty);
    let fwd_vec = e1 * b[0] + e2 * b[1];
    let gain = fwd_vec.norm();
    let fwd = fwd_vec.try_normalize(1e-12)?;
    let (hip, pelvis): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .map(|(x, y)| {
            let hip = y - b[2] - b[3] * x[3] - b[4] * x[4] - b[5] * x[5];
            (hip, x[0] * fwd.dot(&e1) + x[1] * fwd.dot(&e2))
        })
        .unzip();
    Some(TrunkAxis {
        z: fwd.cross(&up).normalize(),
        up,
        corr: correlation(&hip, &pelvis),
        gain,
    })
}
