//! A left-leg trial from a right-leg one (and back): the mirror image of the
//! recording across the sagittal plane, for checking alignment on both legs
//! with one recording (`limbfuse mirror`).
//!
//! Mirroring is `S = diag(1, 1, -1)` in the sensor's own coordinates (any
//! reflection is the sagittal reflection followed by a rotation, so the
//! result is what *some* mounting of a sensor on the mirror-image leg
//! reads). The accelerometer measures a polar vector, `f -> S f`; the
//! gyroscope an axial one, `w -> -S w` (`[w]x = R^T dR/dt` and
//! `S [w]x S = -[S w]x`); a device orientation `R` (sensor to world) becomes
//! `S R S`, i.e. the quaternion `(w, x, y, z) -> (w, -x, -y, z)`. The
//! sagittal angles (rotations about the medio-lateral axis), the joint
//! angles, encoders and references are unchanged. Derivation with the
//! simulator's left leg: `limbfuse_sim::body_path`.
//!
//! [`remount_rotations`] draws seeded uniformly random rotations (Shoemake's
//! quaternion method, SplitMix64 numbers) to re-mount the mirrored sensors
//! with [`super::apply_rotations`].

use limbfuse_core::{ImuSample, Record};
use nalgebra::{Quaternion, Rotation3, UnitQuaternion, Vector3};

/// The record as the mirror-image (other) leg's sensors read it.
///
/// Two-leg recordings: both legs' sensors are mirrored (the other leg's
/// IMUs too), and the foot-contact references swap sides, since the
/// mirror image of the right foot is a left foot (`contact_right_ref`
/// becomes `contact_left_ref`). The trial's `# leg:` and its column names
/// follow (`limbfuse mirror`). Until issue 19's invariance audit the other
/// leg was left as recorded and the references unswapped, so a mirrored
/// two-foot walk lost every event (`issue_19_mirror_two_leg_recording`).
pub fn mirror_record(r: &Record) -> Record {
    mirror_record_in(r, WorldReflection::Z)
}

/// The world axis a mirrored device orientation (`S_quat_*`) is reflected
/// along. The mirror image of a world must stay a world with the same
/// vertical: SPEC's frame (y up, z medio-lateral) is reflected along z; a
/// device world with z up (Xsens: the shared gaittoolbox recording) along y
/// (an audit: reflecting its z turned gravity upside down, `R f` from
/// +9.90 to -9.90 m/s^2 on the trunk). Any horizontal axis gives a valid
/// mirror-image world; [`world_reflection`] picks it from the data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorldReflection {
    /// Reflect the world's z: quaternion `(w, -x, -y, z)`.
    Z,
    /// Reflect the world's y (a z-up world): `S_y R S_z`, i.e. the
    /// quaternion `(x, w, -z, -y)` (a half turn about x after the z
    /// reflection).
    Y,
}

impl WorldReflection {
    /// How the quaternion changes, for the trial's metadata.
    pub const fn formula(self) -> &'static str {
        match self {
            WorldReflection::Z => "quat (w, -x, -y, z): world z reflected",
            WorldReflection::Y => {
                "quat (x, w, -z, -y): world y reflected (the device world has z up)"
            }
        }
    }
}

/// The reflection that keeps the device world's vertical: the world axis
/// along which the accelerometers' specific force, rotated by the device
/// orientation (`R f`, gravity's reaction when still), has the largest mean
/// is vertical; y is reflected when that is z, else z. Without a sample
/// holding both an orientation and an accelerometer reading: z (SPEC).
pub fn world_reflection(records: &[Record]) -> WorldReflection {
    let mut sum = Vector3::zeros();
    for r in records {
        for imu in r.sample.imu.iter().chain(r.sample.other_leg_imu.iter()) {
            if let (Some(q), Some(f)) = (imu.quat, imu.acc) {
                let q = UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]));
                let rf = q * f;
                if rf.iter().all(|v| v.is_finite()) {
                    sum += rf;
                }
            }
        }
    }
    let vertical = sum.iamax();
    match (vertical, sum[vertical] != 0.0) {
        (2, true) => WorldReflection::Y,
        _ => WorldReflection::Z,
    }
}

/// [`mirror_record`] with the device orientations reflected along `world`
/// ([`world_reflection`]).
pub fn mirror_record_in(r: &Record, world: WorldReflection) -> Record {
    let mut out = *r;
    for imu in out
        .sample
        .imu
        .iter_mut()
        .chain(out.sample.other_leg_imu.iter_mut())
    {
        mirror_imu(imu, world);
    }
    out.reference.contact.swap(0, 1);
    out
}

fn mirror_imu(imu: &mut ImuSample, world: WorldReflection) {
    imu.acc = imu.acc.map(|a| Vector3::new(a.x, a.y, -a.z));
    imu.gyr = imu.gyr.map(|w| Vector3::new(-w.x, -w.y, w.z));
    // incomplete vectors: each axis maps to itself (issue 18 item 2)
    let [ax, ay, az] = imu.acc_partial;
    imu.acc_partial = [ax, ay, az.map(|z| -z)];
    let [wx, wy, wz] = imu.gyr_partial;
    imu.gyr_partial = [wx.map(|x| -x), wy.map(|y| -y), wz];
    imu.quat = imu.quat.map(|[w, x, y, z]| match world {
        WorldReflection::Z => [w, -x, -y, z],
        WorldReflection::Y => [x, w, -z, -y],
    });
}

/// A uniformly distributed number in `[0, 1)` from the SplitMix64 stream.
pub(crate) fn uniform01(state: &mut u64) -> f64 {
    (splitmix(state) >> 11) as f64 / (1u64 << 53) as f64
}

/// SplitMix64 step: a well-mixed 64-bit number from the state.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Four uniformly random rotations (trunk, thigh, shank, foot) from `seed`
/// (Shoemake 1992, "Uniform random rotations", Graphics Gems III).
pub fn remount_rotations(seed: u64) -> [Rotation3<f64>; 4] {
    remount_rotations_both_legs(seed).0
}

/// Eight uniformly random rotations from `seed`: this leg's four (those of
/// [`remount_rotations`]) and the other leg's four (two-leg recordings),
/// drawn next from the same stream.
pub fn remount_rotations_both_legs(seed: u64) -> ([Rotation3<f64>; 4], [Rotation3<f64>; 4]) {
    let mut state = seed;
    let own = draw_rotations(&mut state);
    let other = draw_rotations(&mut state);
    (own, other)
}

fn draw_rotations(state: &mut u64) -> [Rotation3<f64>; 4] {
    let mut uniform = || uniform01(state);
    core::array::from_fn(|_| {
        let (u1, u2, u3) = (uniform(), uniform(), uniform());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let q = Quaternion::new(
            b * (tau * u3).cos(),
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
        );
        UnitQuaternion::from_quaternion(q).to_rotation_matrix()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::{ImuSample, Sample};
    use nalgebra::Matrix3;

    #[test]
    fn mirroring_matches_the_mirrored_motion() {
        // A sensor turning at w (sensor frame) with orientation R reads
        // (R^T f, w). Its mirror image has orientation S R S and angular rate
        // from d(S R S)/dt = S (dR/dt) S.
        let r = Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let w = Vector3::new(0.4, -1.2, 2.0);
        let f = Vector3::new(1.0, 9.0, -2.0);
        let h = 1e-6;
        let skew = |v: &Vector3<f64>| v.cross_matrix();
        let r_next = r * (Matrix3::identity() + skew(&w) * h);
        let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
        let (rl, rl_next) = (s * r * s, s * r_next * s);
        let wl_skew = rl.transpose() * (rl_next - rl) / h;
        let wl = Vector3::new(wl_skew[(2, 1)], wl_skew[(0, 2)], wl_skew[(1, 0)]);
        let fl = rl.transpose() * (s * (r * f));
        let mut rec = Record {
            sample: Sample::empty(0.0),
            reference: Default::default(),
        };
        let q = UnitQuaternion::from_matrix(&r);
        rec.sample.imu[1] = ImuSample {
            acc: Some(f),
            gyr: Some(w),
            quat: Some([q.w, q.i, q.j, q.k]),
            ..Default::default()
        };
        let m = mirror_record(&rec).sample.imu[1];
        assert!((m.gyr.unwrap() - wl).norm() < 1e-5);
        assert!((m.acc.unwrap() - fl).norm() < 1e-12);
        let [qw, qx, qy, qz] = m.quat.unwrap();
        let ql = UnitQuaternion::from_quaternion(Quaternion::new(qw, qx, qy, qz));
        assert!((ql.to_rotation_matrix().into_inner() - rl).norm() < 1e-12);
    }

    /// Issue: `mirror` of the shared gaittoolbox recording (Xsens, world z
    /// up) turned its world upside down. Reflecting the world's y keeps it
    /// up: `S_y R S_z`, detected from the data.
    #[test]
    fn a_z_up_device_world_keeps_its_vertical() {
        let r = Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let up = Vector3::new(0.0, 0.0, 9.81);
        let f = r.transpose() * up; // still: R f = gravity's reaction, up
        let q = UnitQuaternion::from_matrix(&r);
        let mut rec = Record {
            sample: Sample::empty(0.0),
            reference: Default::default(),
        };
        rec.sample.imu[0] = ImuSample {
            acc: Some(f),
            quat: Some([q.w, q.i, q.j, q.k]),
            ..Default::default()
        };
        let world = world_reflection(std::slice::from_ref(&rec));
        assert_eq!(world, WorldReflection::Y);
        let m = mirror_record_in(&rec, world).sample.imu[0];
        let [qw, qx, qy, qz] = m.quat.unwrap();
        let ql = UnitQuaternion::from_quaternion(Quaternion::new(qw, qx, qy, qz));
        let sy = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
        let sz = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
        assert!((ql.to_rotation_matrix().into_inner() - sy * r * sz).norm() < 1e-12);
        assert!((ql * m.acc.unwrap() - up).norm() < 1e-9, "still up");
        // The z reflection (SPEC's y-up world) would have turned it down.
        let [qw, qx, qy, qz] = mirror_record(&rec).sample.imu[0].quat.unwrap();
        let qz_refl = UnitQuaternion::from_quaternion(Quaternion::new(qw, qx, qy, qz));
        assert!((qz_refl * m.acc.unwrap() + up).norm() < 1e-9);
        // A y-up world (SPEC's) keeps the z reflection.
        let f_spec = r.transpose() * Vector3::new(0.0, 9.81, 0.0);
        rec.sample.imu[0].acc = Some(f_spec);
        assert_eq!(
            world_reflection(std::slice::from_ref(&rec)),
            WorldReflection::Z
        );
    }

    #[test]
    fn remount_rotations_are_seeded_and_spread() {
        let a = remount_rotations(3);
        assert_eq!(a, remount_rotations(3));
        assert_ne!(a, remount_rotations(4));
        // Mean of z axes over many draws ~ 0 (uniform on the sphere).
        let mut m = Vector3::zeros();
        for seed in 0..250 {
            for r in remount_rotations(seed) {
                m += r * Vector3::z();
            }
        }
        assert!((m / 1000.0).norm() < 0.1, "{m}");
    }
}
