//! The static-rotation IMU-to-segment alignment of paper 004 section 3.3
//! (Fig. 9): quiet standing gives each segment's up axis (gravity), then 3-5
//! hip flexion/extension rotations give the medio-lateral axis (integrated
//! gyro of the positive rotations); the third axis is their cross product.
//!
//! In SPEC frames (section 1) the thesis's body Z (gravity) is our `y` and
//! its X (rotation axis) our `z`. Steps:
//! 1. quiet standing: the first run of at least `min_quiet_s` where every
//!    used sensor's gyro norm is below `quiet_gyro` and its specific force
//!    within `quiet_acc` of `g`; mean specific force -> `y`;
//! 2. rotations: after the quiet run, bursts where the gyro norm exceeds
//!    `moving_gyro`; each burst's integrated gyro `v_i`; the first burst is
//!    taken as a flexion (distal end forward, SPEC +z), bursts with
//!    `v_i . v_1 > 0` are the positive rotations; `z = sum v_i / |.|`;
//! 3. `x = y x z`; the matrix `[x y z]` is replaced by the nearest rotation
//!    (polar decomposition via SVD, eq 3.3's orthonormality conditions);
//! 4. Z-rotation correction (eqs 3.4-3.5): the frame is turned about its up
//!    axis by the mean signed angle between the positive rotations' axes
//!    (projected on the horizontal plane) and `z`, with the axis-angle
//!    matrix of eq 3.5. The thesis averages unsigned angles of X and Y to a
//!    reference and subtracts 45 deg, which equals this signed mean when the
//!    axes are orthogonal; the signed form is used so that deviations to
//!    either side do not add up.
//!
//! Without a quiet period or without rotations the procedure fails with a
//! typed error naming what is missing.

use limbfuse_core::{Record, Segment};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

/// Thresholds of the procedure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticRotationOptions {
    /// Shortest quiet-standing run (s); the thesis asks for 10 s.
    pub min_quiet_s: f64,
    /// Gyro norm below which a sample is quiet (rad/s).
    pub quiet_gyro: f64,
    /// Largest `| |a| - g |` of a quiet sample (m/s^2).
    pub quiet_acc: f64,
    /// Gyro norm above which a sample is part of a rotation (rad/s).
    pub moving_gyro: f64,
    /// Gravity (m/s^2).
    pub g: f64,
}

impl Default for StaticRotationOptions {
    fn default() -> Self {
        StaticRotationOptions {
            min_quiet_s: 5.0,
            quiet_gyro: 0.1,
            quiet_acc: 0.5,
            moving_gyro: 0.3,
            g: 9.81,
        }
    }
}

/// Why the procedure failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StaticRotationError {
    /// A segment has no accelerometer or gyro in the trial.
    #[error("the static-rotation procedure needs the {0} IMU (acc and gyr), which the trial does not have")]
    MissingSensor(&'static str),
    /// No quiet-standing period.
    #[error("no calibration segment: no quiet standing of at least {min_s} s (gyro below {gyro} rad/s, |acc| within {acc} m/s^2 of g) was found; record quiet standing then 3-5 hip flexion/extension rotations (`limbfuse simulate knee-fes --calibration FILE` writes one)")]
    NoQuietStanding {
        /// Required duration (s).
        min_s: f64,
        /// Gyro threshold.
        gyro: f64,
        /// Accelerometer threshold.
        acc: f64,
    },
    /// No rotations after the quiet period.
    #[error("no flexion/extension rotations after the quiet standing ending at {quiet_end} s for the {segment} IMU (gyro never above {gyro} rad/s)")]
    NoRotations {
        /// Segment.
        segment: &'static str,
        /// End of the quiet run (s).
        quiet_end: f64,
        /// Threshold.
        gyro: f64,
    },
    /// The rotation axis is parallel to gravity.
    #[error("the {0} IMU's rotation axis is parallel to gravity: the rotations must be flexion/extension, not about the vertical")]
    DegenerateAxis(&'static str),
}

/// The result: raw-to-aligned rotations and what was used.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticRotationAlignment {
    /// Raw-to-aligned rotation per segment (`v_aligned = R v_raw`).
    pub rotations: [Option<Rotation3<f64>>; 4],
    /// Quiet-standing run (s).
    pub quiet: (f64, f64),
    /// Number of positive rotations per segment.
    pub positive_rotations: [usize; 4],
    /// Z-rotation correction (rad) per segment (eq 3.4).
    pub z_correction: [f64; 4],
}

/// Eq 3.5: rotation by `theta` about the unit axis `z` (Rodrigues).
pub fn axis_rotation(z: &Vector3<f64>, theta: f64) -> Matrix3<f64> {
    let (c, s) = (theta.cos(), theta.sin());
    let w = 1.0 - c;
    Matrix3::new(
        z.x * z.x * w + c,
        z.x * z.y * w - z.z * s,
        z.x * z.z * w + z.y * s,
        z.x * z.y * w + z.z * s,
        z.y * z.y * w + c,
        z.y * z.z * w - z.x * s,
        z.x * z.z * w - z.y * s,
        z.y * z.z * w + z.x * s,
        z.z * z.z * w + c,
    )
}

/// Nearest rotation to `m` in the Frobenius norm (polar decomposition by SVD).
pub fn nearest_rotation(m: &Matrix3<f64>) -> Matrix3<f64> {
    let svd = m.svd(true, true);
    let (u, vt) = (svd.u.expect("computed"), svd.v_t.expect("computed"));
    let mut d = Matrix3::identity();
    if (u * vt).determinant() < 0.0 {
        d[(2, 2)] = -1.0;
    }
    u * d * vt
}

/// Runs the procedure on `segments` of `records`.
pub fn static_rotation_alignment(
    records: &[Record],
    segments: &[Segment],
    opts: &StaticRotationOptions,
) -> Result<StaticRotationAlignment, StaticRotationError> {
    for s in segments {
        let i = s.index();
        if !records
            .iter()
            .any(|r| r.sample.imu[i].acc.is_some() && r.sample.imu[i].gyr.is_some())
        {
            return Err(StaticRotationError::MissingSensor(s.name()));
        }
    }
    let quiet = |r: &Record| {
        segments.iter().all(|s| {
            let imu = &r.sample.imu[s.index()];
            match (imu.acc, imu.gyr) {
                (Some(a), Some(g)) => {
                    g.norm() < opts.quiet_gyro && (a.norm() - opts.g).abs() < opts.quiet_acc
                }
                _ => false,
            }
        })
    };
    // First quiet run long enough.
    let mut start = None;
    let mut found = None;
    for (k, r) in records.iter().enumerate() {
        if quiet(r) {
            let s = *start.get_or_insert(k);
            if r.sample.t - records[s].sample.t >= opts.min_quiet_s {
                // Extend to the end of this run.
                let mut e = k;
                while e + 1 < records.len() && quiet(&records[e + 1]) {
                    e += 1;
                }
                found = Some((s, e));
                break;
            }
        } else {
            start = None;
        }
    }
    let (qs, qe) = found.ok_or(StaticRotationError::NoQuietStanding {
        min_s: opts.min_quiet_s,
        gyro: opts.quiet_gyro,
        acc: opts.quiet_acc,
    })?;
    let mut out = StaticRotationAlignment {
        rotations: [None; 4],
        quiet: (records[qs].sample.t, records[qe].sample.t),
        positive_rotations: [0; 4],
        z_correction: [0.0; 4],
    };
    for s in segments {
        let i = s.index();
        let up: Vector3<f64> = records[qs..=qe]
            .iter()
            .filter_map(|r| r.sample.imu[i].acc)
            .sum::<Vector3<f64>>()
            .normalize();
        // Bursts of rotation after the quiet run.
        let mut bursts: Vec<Vector3<f64>> = Vec::new();
        let mut current: Option<Vector3<f64>> = None;
        for w in records[qe..].windows(2) {
            let dt = w[1].sample.t - w[0].sample.t;
            match w[1].sample.imu[i].gyr {
                Some(g) if g.norm() > opts.moving_gyro => {
                    *current.get_or_insert_with(Vector3::zeros) += g * dt;
                }
                _ => {
                    if let Some(v) = current.take() {
                        bursts.push(v);
                    }
                }
            }
        }
        if let Some(v) = current {
            bursts.push(v);
        }
        let Some(first) = bursts.first().copied() else {
            return Err(StaticRotationError::NoRotations {
                segment: s.name(),
                quiet_end: out.quiet.1,
                gyro: opts.moving_gyro,
            });
        };
        let positive: Vec<Vector3<f64>> =
            bursts.into_iter().filter(|v| v.dot(&first) > 0.0).collect();
        let horizontal = |v: &Vector3<f64>| v - up * v.dot(&up);
        let sum: Vector3<f64> = positive.iter().sum();
        let z = horizontal(&sum);
        if z.norm() < 1e-6 * sum.norm().max(1e-12) {
            return Err(StaticRotationError::DegenerateAxis(s.name()));
        }
        let z = z.normalize();
        let x = up.cross(&z);
        // Columns: the segment's x, y, z axes in sensor coordinates.
        let m = Matrix3::from_columns(&[x, up, z]);
        let r0 = nearest_rotation(&m);
        // Eq 3.4 (signed form): mean angle of the rotations' axes from z about up.
        let (y_axis, z_axis) = (r0.column(1).into_owned(), r0.column(2).into_owned());
        let theta = positive
            .iter()
            .map(|v| {
                let h = horizontal(v).normalize();
                z_axis.cross(&h).dot(&y_axis).atan2(z_axis.dot(&h))
            })
            .sum::<f64>()
            / positive.len() as f64;
        let corrected = axis_rotation(&Unit::new_normalize(y_axis).into_inner(), theta) * r0;
        out.rotations[i] = Some(Rotation3::from_matrix_unchecked(corrected.transpose()));
        out.positive_rotations[i] = positive.len();
        out.z_correction[i] = theta;
    }
    Ok(out)
}

/// `[w, x, y, z]` of a rotation (w >= 0), for metadata.
pub fn quat_wxyz(r: &Rotation3<f64>) -> [f64; 4] {
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(r);
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [s * q.w, s * q.i, s * q.j, s * q.k]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq_3_5_is_a_rotation_about_the_axis() {
        let z = Vector3::new(1.0, 2.0, 2.0) / 3.0;
        let r = axis_rotation(&z, 0.7);
        let want = Rotation3::from_axis_angle(&Unit::new_normalize(z), 0.7);
        assert!((r - want.matrix()).amax() < 1e-15);
    }

    #[test]
    fn nearest_rotation_recovers_a_perturbed_rotation() {
        let r = Rotation3::from_euler_angles(0.3, -0.5, 1.1).into_inner();
        let m = r + Matrix3::new(1e-3, -2e-3, 0.0, 0.0, 1e-3, 3e-3, -1e-3, 0.0, 2e-3);
        let n = nearest_rotation(&m);
        assert!((n.transpose() * n - Matrix3::identity()).amax() < 1e-12);
        assert!((n.determinant() - 1.0).abs() < 1e-12);
        assert!((n - r).amax() < 5e-3);
    }
}
