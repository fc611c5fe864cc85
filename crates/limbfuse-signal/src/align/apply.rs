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
        imu.quat = imu.quat.map(|[w, x, y, z]| {
            let q = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
            let q = q * UnitQuaternion::from_rotation_matrix(&r.inverse());
            [q.w, q.i, q.j, q.k]
        });
    }
    out
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

    /// Adds [`Alignment::metadata`] to `meta` (replacing earlier values).
    pub fn annotate(&self, meta: &mut TrialMeta) {
        for (k, v) in self.metadata() {
            meta.set(k, v);
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
