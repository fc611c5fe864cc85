//! In-plane zero: where x and y point within the sagittal plane once z is
//! known. A provisional frame has y along the mean specific force projected
//! normal to z; the aligned frame is that frame turned about z by `delta`,
//! chosen so that the segment angle is 0 in quiet standing, or so that its
//! mean over the walking data equals a target (0 by default).
//!
//! The walking mean is *gyro-aided*: within windows of `zero_window_s` the
//! provisional angle is `phi(k) = psi(k) + c`, with `psi` the integrated gyro
//! z and `c` chosen so that the mean specific force turned into the world
//! frame, `mean Rz(phi) a`, points straight up. Dynamic accelerations
//! average out in the world frame (their mean is the change of velocity over
//! the window divided by its length), so the mean angle is not biased by the
//! correlation of posture and acceleration that averaging `atan2(a_x, a_y)`
//! or the raw accelerometer (or a least-squares fit weighted by the vertical
//! force) suffers from. A gyro bias `b` tilts `phi` by `b (t - t_mid)`
//! within a window (about +-2.5 deg at 0.5 deg/s over 10 s), which averages
//! out of the mean; no drift is fitted (the velocity change at the window
//! ends makes a drift fit much worse than the drift itself).

use limbfuse_core::{Record, Segment};
use nalgebra::{Matrix3, Rotation3, Vector3};

use super::series::{acc, gyr};

/// Rows `(x0, y0, z)` of the provisional frame: `y0` = `up` projected normal
/// to `z`, `x0 = y0 x z`. `None` when `up` is (nearly) parallel to `z`.
pub(crate) fn provisional(z: &Vector3<f64>, up: &Vector3<f64>) -> Option<Matrix3<f64>> {
    let y = up - z * z.dot(up);
    if y.norm() < 0.1 * up.norm() {
        return None;
    }
    let y = y.normalize();
    let x = y.cross(z);
    Some(Matrix3::from_rows(&[
        x.transpose(),
        y.transpose(),
        z.transpose(),
    ]))
}

/// Rotation about z by `delta` (acts on aligned coordinates).
pub(crate) fn rot_z(delta: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), delta).into_inner()
}

/// Angle of the mean specific force over `idx` in `frame` (`atan2(x, y)`):
/// the segment angle in that frame when the samples are static.
pub(crate) fn static_angle(
    records: &[Record],
    seg: Segment,
    frame: &Matrix3<f64>,
    idx: impl Iterator<Item = usize>,
) -> Option<f64> {
    let mut m = Vector3::zeros();
    let mut n = 0;
    for k in idx {
        if let Some(a) = acc(records, seg, k) {
            m += frame * a;
            n += 1;
        }
    }
    (n > 0).then(|| m.x.atan2(m.y))
}

/// Gyro-aided angle of `seg` in `frame` at the samples `idx` (increasing),
/// processed in equal windows of about `window_s`: `(k, phi(k))` for every
/// sample with an accelerometer reading.
pub(crate) fn angle_series(
    records: &[Record],
    seg: Segment,
    frame: &Matrix3<f64>,
    idx: &[usize],
    window_s: f64,
) -> Vec<(usize, f64)> {
    let mut out = Vec::with_capacity(idx.len());
    // Runs of consecutive records (the gyro is not integrated over gaps);
    // runs shorter than 2 s are left out unless no run is longer.
    let mut runs: Vec<&[usize]> = Vec::new();
    let mut start = 0;
    for i in 1..=idx.len() {
        if i == idx.len() || idx[i] != idx[i - 1] + 1 {
            runs.push(&idx[start..i]);
            start = i;
        }
    }
    let dur = |r: &[usize]| records[r[r.len() - 1]].sample.t - records[r[0]].sample.t;
    let longest = runs.iter().map(|r| dur(r)).fold(0.0, f64::max);
    for run in runs {
        if dur(run) < 2.0_f64.min(longest) {
            continue;
        }
        // Equal windows of about `window_s` (no short remainder).
        let t0 = records[run[0]].sample.t;
        let len = dur(run) / (dur(run) / window_s).round().max(1.0) + 1e-9;
        let mut start = 0;
        while start < run.len() {
            let w = ((records[run[start]].sample.t - t0) / len).floor();
            let mut end = start + 1;
            while end < run.len() && ((records[run[end]].sample.t - t0) / len).floor() == w {
                end += 1;
            }
            window(records, seg, frame, &run[start..end], &mut out);
            start = end;
        }
    }
    out
}

fn window(
    records: &[Record],
    seg: Segment,
    frame: &Matrix3<f64>,
    idx: &[usize],
    out: &mut Vec<(usize, f64)>,
) {
    // Integrated gyro z (trapezoid; a missing reading holds the last rate).
    let mut psi = 0.0;
    let mut rate_prev: Option<f64> = None;
    let mut t_prev = records[idx[0]].sample.t;
    let mut pts: Vec<(usize, f64, f64, f64)> = Vec::with_capacity(idx.len());
    for &k in idx {
        let t = records[k].sample.t;
        let rate = gyr(records, seg, k).map(|w| frame.row(2).dot(&w.transpose()));
        let r = rate.or(rate_prev).unwrap_or(0.0);
        psi += 0.5 * (rate_prev.unwrap_or(r) + r) * (t - t_prev);
        rate_prev = Some(r);
        t_prev = t;
        if let Some(a) = acc(records, seg, k) {
            let p = frame * a;
            pts.push((k, psi, p.x, p.y));
        }
    }
    if pts.is_empty() {
        return;
    }
    // Offset c: the mean world specific force over the window, sum of
    // Rz(psi + c) a, points straight up (unweighted, so dynamic
    // accelerations cancel whatever their correlation with posture).
    let (mut sx, mut sy) = (0.0, 0.0);
    for &(_, ps, ax, ay) in &pts {
        let (s, c) = ps.sin_cos();
        sx += c * ax - s * ay;
        sy += s * ax + c * ay;
    }
    let c0 = sx.atan2(sy);
    out.extend(pts.iter().map(|&(k, ps, _, _)| (k, ps + c0)));
}
