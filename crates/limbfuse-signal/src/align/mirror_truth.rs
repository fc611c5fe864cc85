//! The simulator's ground-truth metadata of a mirrored (and re-mounted)
//! trial: the lines that describe each sensor in its own or its segment's
//! frame change as its readings do (`limbfuse mirror`).
//!
//! An audit found `mirror` copying them unchanged: `<seg>_mount_quat`, which
//! docs/ALIGNMENT.md gives as the ideal answer of `align`, no longer
//! described the mirrored sensors, nor did the lateral offsets of
//! `imu_mounts_m` or the turn-on biases.
//!
//! With `S = diag(1, 1, -1)` (segment and sensor frames reflected along
//! their medio-lateral z, [`super::mirror`]) and a re-mounting `Q` (readings
//! `v -> Q v`):
//! * `M` (`<seg>_mount_quat`, sensor to segment: `sensor = M^T segment`)
//!   becomes `S M S Q^T`: the quaternion `(w, -x, -y, z)` times `Q`'s
//!   conjugate;
//! * a gyroscope bias (axial, sensor frame) `b -> Q (-S b)`, an
//!   accelerometer bias (polar) `b -> Q (S b)`;
//! * a mounting position in the segment frame (`imu_mounts_m`) `p -> S p`.

use limbfuse_core::Segment;
use limbfuse_io::TrialMeta;
use nalgebra::{Quaternion, Rotation3, UnitQuaternion, Vector3};

/// Rewrites the truth lines of `meta` for the mirrored sensors of this leg,
/// re-mounted by `remount` when given. A line that does not parse is
/// removed (a wrong truth is worse than none), and the list of removed keys
/// returned.
pub fn mirror_truth_lines(
    meta: &mut TrialMeta,
    remount: Option<&[Rotation3<f64>; 4]>,
) -> Vec<String> {
    let mut removed = Vec::new();
    for seg in Segment::ALL {
        let q = remount.map(|r| UnitQuaternion::from_rotation_matrix(&r[seg.index()]));
        let key = format!("{}_mount_quat", seg.name());
        if let Some(text) = meta.get(&key).map(str::to_string) {
            match numbers::<4>(&text) {
                Some([w, x, y, z]) => {
                    let m = UnitQuaternion::from_quaternion(Quaternion::new(w, -x, -y, z));
                    let m = match q {
                        Some(q) => m * q.inverse(),
                        None => m,
                    };
                    meta.set(key, format!("{:.9} {:.9} {:.9} {:.9}", m.w, m.i, m.j, m.k));
                }
                None => removed.push(key),
            }
        }
        for (kind, sign) in [("gyro", -1.0), ("acc", 1.0)] {
            let key = format!("{}_{kind}_turn_on_bias", seg.name());
            if let Some(text) = meta.get(&key).map(str::to_string) {
                match numbers::<3>(&text) {
                    Some([x, y, z]) => {
                        let b = Vector3::new(x, y, -z) * sign;
                        let b = q.map_or(b, |q| q * b);
                        meta.set(key, format!("{:e} {:e} {:e}", b.x, b.y, b.z));
                    }
                    None => removed.push(key),
                }
            }
        }
    }
    if let Some(text) = meta.get("imu_mounts_m").map(str::to_string) {
        meta.set("imu_mounts_m", mirrored_positions(&text));
    }
    if !removed.is_empty() {
        let kept: Vec<(String, String)> = meta
            .entries()
            .iter()
            .filter(|(k, _)| !removed.contains(k))
            .cloned()
            .collect();
        let mut fresh = TrialMeta::new();
        for (k, v) in kept {
            fresh.set(k, v);
        }
        *meta = fresh;
    }
    removed
}

/// `N` whitespace-separated finite numbers.
fn numbers<const N: usize>(text: &str) -> Option<[f64; N]> {
    let mut out = [0.0; N];
    let mut it = text.split_whitespace();
    for o in out.iter_mut() {
        *o = it.next()?.parse::<f64>().ok().filter(|v| v.is_finite())?;
    }
    it.next().is_none().then_some(out)
}

/// `imu_mounts_m` with the medio-lateral coordinate of every `(x, y, z)`
/// negated; everything else as it was: sagittal `(x, y)` pairs (the
/// independent simulator's, which `chain` reads) and free text do not
/// change in the mirror image (an audit: such a line, dropped, cost `chain`
/// 0.22 -> 0.35 deg on the mirrored independent walks).
fn mirrored_positions(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(open) = rest.find('(') {
        out.push_str(&rest[..=open]);
        rest = &rest[open + 1..];
        let Some(close) = rest.find(')') else {
            break;
        };
        let inner = &rest[..close];
        let v: Option<Vec<f64>> = inner
            .split(',')
            .map(|c| c.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect();
        match v.as_deref() {
            Some([x, y, z]) => out.push_str(&format!("{x:+.4}, {y:+.4}, {:+.4}", -z)),
            _ => out.push_str(inner),
        }
        rest = &rest[close..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    /// The rewritten mounting maps the mirrored, re-mounted readings to the
    /// mirrored segment frame: `M'' (Q S f) = S (M f)`.
    #[test]
    fn the_mount_maps_mirrored_readings_to_the_mirrored_segment() {
        let m = UnitQuaternion::from_euler_angles(0.4, -1.1, 2.3);
        let q = Rotation3::from_euler_angles(-0.2, 0.9, 0.5);
        let mut meta = TrialMeta::new();
        meta.set(
            "thigh_mount_quat",
            format!("{:.9} {:.9} {:.9} {:.9}", m.w, m.i, m.j, m.k),
        );
        meta.set("thigh_gyro_turn_on_bias", "1e-3 2e-3 3e-3");
        meta.set(
            "imu_mounts_m",
            "trunk (-0.1000, +0.0800, -0.0900); thigh (+0.0000, -0.2144, +0.0800)",
        );
        let rot = [
            Rotation3::identity(),
            q,
            Rotation3::identity(),
            Rotation3::identity(),
        ];
        assert!(mirror_truth_lines(&mut meta, Some(&rot)).is_empty());
        let [w, x, y, z] = numbers::<4>(meta.get("thigh_mount_quat").unwrap()).unwrap();
        let m2 = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
        let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
        let f = Vector3::new(0.3, 9.7, -1.2); // a sensor-frame reading
        let reading = q * (s * f);
        let want = s * (m * f);
        assert!(
            (m2 * reading - want).norm() < 1e-7,
            "{}",
            (m2 * reading - want).norm()
        );
        let b = numbers::<3>(meta.get("thigh_gyro_turn_on_bias").unwrap()).unwrap();
        let want_b = q * Vector3::new(-1e-3, -2e-3, 3e-3);
        assert!((Vector3::from(b) - want_b).norm() < 1e-15);
        assert_eq!(
            meta.get("imu_mounts_m").unwrap(),
            "trunk (-0.1000, +0.0800, +0.0900); thigh (+0.0000, -0.2144, -0.0800)"
        );
    }

    /// Sagittal pairs and free text are the mirror image's too: kept.
    #[test]
    fn positions_in_the_plane_and_text_are_kept() {
        let ind = "trunk (-0.080, +0.100); thigh (+0.000, -0.215) in segment frames (trunk/thigh origin hip joint)";
        assert_eq!(mirrored_positions(ind), ind);
        let fes =
            "thigh: static; shank: on the shank axis 0.25 m distal (acc_x = r x1'' + g sin x1)";
        assert_eq!(mirrored_positions(fes), fes);
        assert_eq!(
            mirrored_positions("foot (+0.0700, -0.0050, +0.0100"),
            "foot (+0.0700, -0.0050, +0.0100"
        );
    }

    #[test]
    fn a_line_that_does_not_parse_is_removed() {
        let mut meta = TrialMeta::new();
        meta.set("foot_mount_quat", "1 0 0");
        meta.set("leg", "right");
        assert_eq!(mirror_truth_lines(&mut meta, None), vec!["foot_mount_quat"]);
        assert_eq!(meta.get("foot_mount_quat"), None);
        assert_eq!(meta.get("leg"), Some("right"));
    }
}
