//! Applying an alignment to records, and describing it in trial metadata.

use limbfuse_core::{Record, Segment};
use nalgebra::{Quaternion, Rotation3, UnitQuaternion};

use super::{AlignError, Alignment, ZeroMethod};
use limbfuse_io::TrialMeta;

/// The record with every aligned sensor's readings turned into its aligned
/// frame: `acc` and `gyr` become `R v`. A device quaternion `q` (sensor to
/// world) becomes `q R^-1` (aligned frame to world). Sensors without an
/// alignment, encoders, inputs and the reference are unchanged.
pub fn apply_alignment(record: &Record, alignment: &Alignment) -> Record {
    apply_rotations(record, &alignment.rotations())
}

/// [`apply_alignment`] with bare rotations (raw to aligned), e.g. read back
/// by [`rotations_from_metadata`] from another trial of the same session.
pub fn apply_rotations(record: &Record, rotations: &[Option<Rotation3<f64>>; 4]) -> Record {
    let mut out = *record;
    for (imu, r) in out.sample.imu.iter_mut().zip(rotations) {
        let Some(r) = r else { continue };
        imu.acc = imu.acc.map(|v| r * v);
        imu.gyr = imu.gyr.map(|v| r * v);
        if imu.acc.is_none() {
            imu.set_acc_axes(rotate_cells(r, &imu.acc_partial));
        }
        if imu.gyr.is_none() {
            imu.set_gyr_axes(rotate_cells(r, &imu.gyr_partial));
        }
        imu.quat = imu.quat.map(|[w, x, y, z]| {
            let q = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
            let q = q * UnitQuaternion::from_rotation_matrix(&r.inverse());
            [q.w, q.i, q.j, q.k]
        });
    }
    out
}

/// A rotation entry at or below this magnitude is an exact zero that
/// round-off left behind (an axis permutation built from a quaternion
/// leaves ~1e-16): the input axis it weights may be missing. Its term is at
/// most 1e-6 times the input's range, 2e-4 m/s^2 at 16 g and 4e-5 rad/s at
/// 2000 deg/s, below any MEMS IMU's per-sample noise (~1e-2 m/s^2, ~5e-3
/// rad/s at 100 Hz).
pub const NEGLIGIBLE_WEIGHT: f64 = 1e-6;

/// `R v` of an incomplete vector (issue 18 item 2): output axis `k` is
/// there only when every input axis it depends on with a weight beyond
/// [`NEGLIGIBLE_WEIGHT`] is there (a rotation that mixes axes needs them
/// all); its value is the sum over those axes.
pub fn rotate_cells(r: &Rotation3<f64>, cells: &[Option<f64>; 3]) -> [Option<f64>; 3] {
    let m = r.matrix();
    core::array::from_fn(|k| {
        (0..3).try_fold(0.0, |sum, j| {
            let w = m[(k, j)];
            if w.abs() <= NEGLIGIBLE_WEIGHT {
                Some(sum + cells[j].map_or(0.0, |v| w * v))
            } else {
                cells[j].map(|v| sum + w * v)
            }
        })
    })
}

/// `w x y z` of a rotation (w first, w >= 0).
fn quat_text(r: &Rotation3<f64>) -> String {
    let q = UnitQuaternion::from_rotation_matrix(r);
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    format!(
        "{:.9} {:.9} {:.9} {:.9}",
        s * q.w,
        s * q.i,
        s * q.j,
        s * q.k
    )
}

/// The metadata key importers use to declare the IMU frames.
pub const IMU_FRAME_KEY: &str = "imu_frame";

/// What `imu_frame` says after [`Alignment::annotate`].
pub const ALIGNED_FRAME: &str = "aligned to the segments by limbfuse align (SPEC section 1)";

impl Alignment {
    /// The rotations (raw to aligned) per segment.
    pub fn rotations(&self) -> [Option<Rotation3<f64>>; 4] {
        self.per_segment.map(|a| a.map(|a| a.rotation))
    }

    /// Metadata entries describing the alignment: `align_method`,
    /// `align_quiet`, and per aligned segment `<seg>_align_quat` (raw to
    /// aligned, `w x y z`), `<seg>_align_axis`, `<seg>_align_zero`,
    /// `<seg>_align_quality`; `<seg>_align_skipped` for skipped ones.
    pub fn metadata(&self) -> Vec<(String, String)> {
        let mut m = vec![
            (
                "align_method".to_string(),
                "limbfuse-align/1 (axis: hinge fit or principal gyro axis, trunk: gravity + walking direction; sign: gait; zero: quiet standing or mean inclination); docs/ALIGNMENT.md".to_string(),
            ),
            (
                "align_quiet".to_string(),
                match self.quiet {
                    Some((a, b)) => format!("{a:.3}..{b:.3} s"),
                    None => "none".into(),
                },
            ),
        ];
        for s in Segment::ALL {
            let name = s.name();
            if let Some(a) = &self.per_segment[s.index()] {
                m.push((format!("{name}_align_quat"), quat_text(&a.rotation)));
                m.push((format!("{name}_align_axis"), a.axis_method.label()));
                let zero = match a.zero_method {
                    ZeroMethod::QuietStanding { start_s, end_s } => {
                        format!("quiet-standing {start_s:.3}..{end_s:.3} s")
                    }
                    ZeroMethod::MeanInclination { target_rad } => {
                        format!("mean-inclination target {:.3} deg", target_rad.to_degrees())
                    }
                };
                m.push((format!("{name}_align_zero"), zero));
                let hinge = a
                    .hinge_residual
                    .map_or("none".to_string(), |h| format!("{h:.4}"));
                let ratio = a
                    .axis_ratio
                    .map_or("none".to_string(), |r| format!("{r:.4}"));
                m.push((
                    format!("{name}_align_quality"),
                    format!(
                        "axis_energy_fraction={:.4} axis_ratio={ratio} axis_vs_principal_deg={:.2} hinge_residual_rad_s={hinge} sign_margin={:.3} walking_mean_deg={:.2} gyro_only_weight={:.2}",
                        a.axis_energy_fraction,
                        a.axis_vs_principal_rad.to_degrees(),
                        a.sign_margin,
                        a.walking_mean_angle_rad.to_degrees(),
                        a.gyro_only_weight
                    ),
                ));
            }
        }
        m.push((
            "align_walking".to_string(),
            format!(
                "walking_samples={} turning_samples={} not_walking_samples={}",
                self.walking_samples, self.turning_samples, self.not_walking_samples
            ),
        ));
        if let Some(l) = &self.leg {
            let seg =
                |s: Segment| l.per_segment[s.index()].map_or("none".into(), |v| format!("{v:+.3}"));
            m.push((
                "align_leg".to_string(),
                format!(
                    "{} score={:+.3} thigh={} shank={}",
                    l.leg.map_or("undetermined", |g| g.name()),
                    l.score,
                    seg(Segment::Thigh),
                    seg(Segment::Shank)
                ),
            ));
        }
        for (s, e) in &self.skipped {
            m.push((format!("{}_align_skipped", s.name()), e.to_string()));
        }
        m
    }

    /// Adds [`Alignment::metadata`] to `meta` (replacing earlier values),
    /// and restates an importer's `imu_frame` declaration of raw frames as
    /// aligned (keeping what it said after `before:`).
    pub fn annotate(&self, meta: &mut TrialMeta) {
        for (k, v) in self.metadata() {
            meta.set(k, v);
        }
        if let Some(before) = meta.get(IMU_FRAME_KEY).map(str::to_string) {
            if !before.starts_with(ALIGNED_FRAME) {
                meta.set(
                    IMU_FRAME_KEY,
                    format!(
                        "{ALIGNED_FRAME} (segments with a `<seg>_align_quat`); before: {before}"
                    ),
                );
            }
        }
    }
}

/// Reads the `<seg>_align_quat` entries written by [`Alignment::metadata`]
/// (`None` for a segment without one).
pub fn rotations_from_metadata(
    meta: &TrialMeta,
) -> Result<[Option<Rotation3<f64>>; 4], AlignError> {
    let mut out = [None; 4];
    for s in Segment::ALL {
        let key = format!("{}_align_quat", s.name());
        let Some(text) = meta.get(&key) else { continue };
        let bad = || AlignError::BadMetadata {
            key: key.clone(),
            expected: "four finite numbers `w x y z` of a unit quaternion",
            found: text.to_string(),
        };
        let v: Vec<f64> = text
            .split_whitespace()
            .map(|x| x.parse::<f64>().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        if v.len() != 4 || !v.iter().all(|x| x.is_finite()) {
            return Err(bad());
        }
        let q = Quaternion::new(v[0], v[1], v[2], v[3]);
        if (q.norm() - 1.0).abs() > 1e-3 {
            return Err(bad());
        }
        out[s.index()] = Some(UnitQuaternion::from_quaternion(q).to_rotation_matrix());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn issue_18_a_rotated_incomplete_vector_keeps_the_axes_it_can() {
        // 90 deg about z: x' = -y, y' = x, z' = z (entries ~1e-16 elsewhere)
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), core::f64::consts::FRAC_PI_2);
        let out = rotate_cells(&r, &[Some(1.0), None, Some(3.0)]);
        assert_eq!(out[0], None);
        assert!((out[1].unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(out[2], Some(3.0));
        // 30 deg about z mixes x and y: without y, neither x' nor y'
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.5);
        assert_eq!(
            rotate_cells(&r, &[Some(1.0), None, Some(3.0)]),
            [None, None, Some(3.0)]
        );
        // applied to a record: a complete vector as before, an incomplete one per axis
        let mut rec = Record::default();
        rec.sample.imu[1].set_gyr_axes([None, Some(2.0), Some(0.5)]);
        rec.sample.imu[2].acc = Some(Vector3::new(1.0, 2.0, 3.0));
        let rot = [None, Some(r), Some(r), None];
        let out = apply_rotations(&rec, &rot);
        assert_eq!(out.sample.imu[1].gyr_axes(), [None, None, Some(0.5)]);
        assert_eq!(out.sample.imu[2].acc, Some(r * Vector3::new(1.0, 2.0, 3.0)));
    }
}
