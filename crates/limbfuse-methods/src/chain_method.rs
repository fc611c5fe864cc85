//! `chain` (kinematic-chain EKF, beyond the papers; docs/CHAIN.md) as a
//! method: its parameter file and where its geometry comes from.
//!
//! ```toml
//! method = "chain"        # optional
//! acc_noise = 0.3         # any ChainParams field by name
//! [geometry]              # optional; the trial's metadata wins over it
//! height_m = 1.75
//! thigh_length = 0.43
//! imu_thigh = [0.0, -0.215, 0.08]
//! ```
//!
//! Geometry, per quantity: the trial's metadata (`imu_mounts_m`,
//! `segment_lengths_m`, `height_m`; `limbfuse_io::body_meta`), else the
//! parameter file's `[geometry]`, else Winter's proportions for the height
//! (`ChainGeometry::from_height`; when no height is known, the default body
//! of every method, `limbfuse_models::DEFAULT_BODY_HEIGHT_M`, 1.75 m).

use std::path::Path;

use limbfuse_core::Estimator;
use limbfuse_estimators::chain_ekf::{
    ChainEkf, ChainGeometry, ChainParams, WALKING_MEAN_ANGLE_DEG,
};
use limbfuse_io::{TrialLayout, TrialMeta};
use limbfuse_models::DEFAULT_BODY_HEIGHT_M;
use serde::Deserialize;

use crate::method_def::{read_file, MethodDef, MethodFile, MethodInfo};
use crate::segment_params::ParamsFileError;
use crate::{ChannelNeeds, MethodError, MethodFlags};

/// The `[geometry]` table of a `chain` parameter file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometryFile {
    /// Body height (m) for the anthropometric defaults.
    pub height_m: Option<f64>,
    /// Hip-knee distance (m).
    pub thigh_length: Option<f64>,
    /// Knee-ankle distance (m).
    pub shank_length: Option<f64>,
    /// Trunk IMU position (m), trunk frame from the hip joint.
    #[serde(default, deserialize_with = "exactly")]
    pub imu_trunk: Option<[f64; 3]>,
    /// Thigh IMU position (m), thigh frame from the hip joint.
    #[serde(default, deserialize_with = "exactly")]
    pub imu_thigh: Option<[f64; 3]>,
    /// Shank IMU position (m), shank frame from the knee.
    #[serde(default, deserialize_with = "exactly")]
    pub imu_shank: Option<[f64; 3]>,
    /// Foot IMU position (m), foot frame from the ankle.
    #[serde(default, deserialize_with = "exactly")]
    pub imu_foot: Option<[f64; 3]>,
    /// Sensor-frame angle relative to the anatomical frame per segment
    /// (trunk, thigh, shank, foot), deg (`ChainGeometry::frame_offset`).
    #[serde(default, deserialize_with = "exactly")]
    pub frame_offset_deg: Option<[f64; 4]>,
}

/// An array of exactly `N` numbers (an audit: serde read the first 3 of
/// `imu_trunk = [-0.1, 0.08, 0, 42]` and dropped the 4th without a word).
fn exactly<'de, D, const N: usize>(d: D) -> Result<Option<[f64; N]>, D::Error>
where
    D: serde::Deserializer<'de>,
{
    use serde::de::Error;
    let Some(v) = Option::<Vec<f64>>::deserialize(d)? else {
        return Ok(None);
    };
    <[f64; N]>::try_from(v.as_slice())
        .map(Some)
        .map_err(|_| D::Error::custom(format!("expected {N} numbers, found {}", v.len())))
}

/// A `chain` parameter file.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChainFile {
    method: Option<String>,
    gyro_noise: Option<f64>,
    acc_noise: Option<f64>,
    encoder_noise: Option<f64>,
    trunk_jerk: Option<f64>,
    leg_jerk: Option<f64>,
    hip_acc_sd: Option<f64>,
    hip_acc_tau: Option<f64>,
    gyro_bias_walk: Option<f64>,
    gyro_bias_initial: Option<f64>,
    hip_vertical_velocity: Option<f64>,
    hip_forward_velocity: Option<f64>,
    mean_speed_walk: Option<f64>,
    stance_velocity: Option<f64>,
    stance_acceleration: Option<f64>,
    stance_gyro: Option<f64>,
    stance_acc: Option<f64>,
    stance_min_s: Option<f64>,
    startup_s: Option<f64>,
    acc_gate: Option<f64>,
    encoder_gate: Option<f64>,
    gyro_gate: Option<f64>,
    use_encoders: Option<bool>,
    out_of_plane: Option<bool>,
    turn_tau_s: Option<f64>,
    turn_rate_min: Option<f64>,
    turn_angle_noise: Option<f64>,
    device_orientation: Option<bool>,
    device_angle_noise: Option<f64>,
    geometry: Option<GeometryFile>,
}

impl MethodFile for ChainFile {
    fn method(&self) -> Option<&str> {
        self.method.as_deref()
    }
}

/// Every setting of `chain`: the filter's parameters and the parameter
/// file's geometry (combined with the trial's metadata when built).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ChainSettings {
    /// Noise levels, anchors, switches.
    pub params: ChainParams,
    /// The file's `[geometry]`.
    pub geometry: GeometryFile,
}

fn invalid(path: &Path, message: String) -> MethodError {
    MethodError::ParamsFile(ParamsFileError::Invalid {
        path: path.to_path_buf(),
        message,
    })
}

/// The settings of a parameter file's text (`None`: defaults), validated.
pub fn chain_settings(file: Option<(&str, &Path)>) -> Result<ChainSettings, MethodError> {
    let f: ChainFile = read_file::<ChainMethod, _>(file)?;
    let d = ChainParams::default();
    let params = ChainParams {
        gyro_noise: f.gyro_noise.unwrap_or(d.gyro_noise),
        acc_noise: f.acc_noise.unwrap_or(d.acc_noise),
        encoder_noise: f.encoder_noise.unwrap_or(d.encoder_noise),
        trunk_jerk: f.trunk_jerk.unwrap_or(d.trunk_jerk),
        leg_jerk: f.leg_jerk.unwrap_or(d.leg_jerk),
        hip_acc_sd: f.hip_acc_sd.unwrap_or(d.hip_acc_sd),
        hip_acc_tau: f.hip_acc_tau.unwrap_or(d.hip_acc_tau),
        gyro_bias_walk: f.gyro_bias_walk.unwrap_or(d.gyro_bias_walk),
        gyro_bias_initial: f.gyro_bias_initial.unwrap_or(d.gyro_bias_initial),
        hip_vertical_velocity: f.hip_vertical_velocity.unwrap_or(d.hip_vertical_velocity),
        hip_forward_velocity: f.hip_forward_velocity.unwrap_or(d.hip_forward_velocity),
        mean_speed_walk: f.mean_speed_walk.unwrap_or(d.mean_speed_walk),
        stance_velocity: f.stance_velocity.unwrap_or(d.stance_velocity),
        stance_acceleration: f.stance_acceleration.unwrap_or(d.stance_acceleration),
        stance_gyro: f.stance_gyro.unwrap_or(d.stance_gyro),
        stance_acc: f.stance_acc.unwrap_or(d.stance_acc),
        stance_min_s: f.stance_min_s.unwrap_or(d.stance_min_s),
        startup_s: f.startup_s.unwrap_or(d.startup_s),
        acc_gate: f.acc_gate.unwrap_or(d.acc_gate),
        encoder_gate: f.encoder_gate.unwrap_or(d.encoder_gate),
        gyro_gate: f.gyro_gate.unwrap_or(d.gyro_gate),
        use_encoders: f.use_encoders.unwrap_or(d.use_encoders),
        out_of_plane: f.out_of_plane.unwrap_or(d.out_of_plane),
        turn_tau_s: f.turn_tau_s.unwrap_or(d.turn_tau_s),
        turn_rate_min: f.turn_rate_min.unwrap_or(d.turn_rate_min),
        turn_angle_noise: f.turn_angle_noise.unwrap_or(d.turn_angle_noise),
        device_orientation: f.device_orientation.unwrap_or(d.device_orientation),
        device_angle_noise: f.device_angle_noise.unwrap_or(d.device_angle_noise),
    };
    let path = file.map_or(Path::new("(defaults)"), |(_, p)| p);
    params
        .validate()
        .map_err(|e| invalid(path, e.to_string()))?;
    let geometry = f.geometry.unwrap_or_default();
    resolve_geometry(&TrialMeta::new(), &geometry)
        .map_err(|e| invalid(path, format!("[geometry]: {e}")))?;
    Ok(ChainSettings { params, geometry })
}

/// Why the geometry cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// The trial's metadata does not parse.
    #[error(transparent)]
    Meta(#[from] limbfuse_io::body_meta::BodyMetaError),
    /// A value out of range.
    #[error(transparent)]
    Range(#[from] limbfuse_estimators::chain_ekf::ChainParamsError),
    /// The height is not 1-2.5 m.
    #[error("height_m = {}: expected a body height of 1 to 2.5 m", crate::shown(*.0))]
    Height(f64),
}

/// The geometry for a trial: its metadata, else the file's `[geometry]`,
/// else Winter's proportions for the height (module documentation).
pub fn resolve_geometry(
    meta: &TrialMeta,
    file: &GeometryFile,
) -> Result<ChainGeometry, GeometryError> {
    let body = meta.body()?;
    let height = body
        .height
        .or(file.height_m)
        .unwrap_or(DEFAULT_BODY_HEIGHT_M);
    if crate::body_ranges::within(height, crate::body_ranges::BODY_HEIGHT_M).is_none() {
        return Err(GeometryError::Height(height));
    }
    let mut g = ChainGeometry::from_height(height);
    if let Some(l) = body.thigh_length.or(file.thigh_length) {
        g.thigh_length = l;
    }
    if let Some(l) = body.shank_length.or(file.shank_length) {
        g.shank_length = l;
    }
    // Mid-segment defaults follow the lengths actually used.
    g.imu_position[1][1] = -0.5 * g.thigh_length;
    g.imu_position[2][1] = -0.5 * g.shank_length;
    let from_file = [
        file.imu_trunk,
        file.imu_thigh,
        file.imu_shank,
        file.imu_foot,
    ];
    for ((r, meta_r), file_r) in g
        .imu_position
        .iter_mut()
        .zip(body.imu_position)
        .zip(from_file)
    {
        if let Some(v) = meta_r.or(file_r) {
            *r = v;
        }
    }
    g.frame_offset = match file.frame_offset_deg {
        Some(d) => d.map(f64::to_radians),
        None => frame_offset_from_alignment(meta),
    };
    g.validate()?;
    Ok(g)
}

/// Each sensor frame's angle to its segment's anatomical frame implied by
/// the trial's alignment metadata (`<seg>_align_zero`, written by `limbfuse
/// align`): `mean-inclination target X deg` puts the frame at the walking
/// mean, so `psi = X - WALKING_MEAN_ANGLE_DEG` (issue 14: on the real
/// gaittoolbox trial the shank frame is 16 deg from the knee-ankle line);
/// a quiet-standing zero, no metadata or an unreadable value: 0.
pub fn frame_offset_from_alignment(meta: &TrialMeta) -> [f64; 4] {
    core::array::from_fn(|i| {
        let key = format!("{}_align_zero", ["trunk", "thigh", "shank", "foot"][i]);
        meta.get(&key)
            .and_then(|v| v.strip_prefix("mean-inclination target "))
            .and_then(|v| v.strip_suffix(" deg"))
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|x| x.is_finite())
            .map_or(0.0, |target| {
                (target - WALKING_MEAN_ANGLE_DEG[i]).to_radians()
            })
    })
}

/// `chain`.
#[derive(Debug, Clone, Copy)]
pub struct ChainMethod;

impl MethodDef for ChainMethod {
    const INFO: MethodInfo = MethodInfo {
        in_walking_demo: true,
        ..MethodInfo::new(
            "chain",
            "beyond the papers: planar kinematic-chain EKF; accelerometers modelled (hip acceleration, rates, angular accelerations, mount positions), not gated",
            "aligned trunk, thigh, shank and foot IMUs; hip/knee/ankle encoders when present; geometry from the trial metadata (imu_mounts_m, segment_lengths_m, height_m)",
            "noise levels, anchors, start-up, innovation gates (encoder_gate, gyro_gate), [geometry] (parameter file; docs/CHAIN.md)",
        )
        .needing(
            ChannelNeeds::FOUR_IMUS,
            "models the four segments' accelerometers and gyroscopes together",
        )
        .reading_aligned_frames()
    };
    type Settings = ChainSettings;

    fn resolve(
        file: Option<(&str, &Path)>,
        _flags: &MethodFlags,
    ) -> Result<ChainSettings, MethodError> {
        chain_settings(file)
    }

    fn build(
        s: &ChainSettings,
        meta: &TrialMeta,
        _: &TrialLayout,
    ) -> Result<Box<dyn Estimator + Send>, MethodError> {
        let geometry =
            resolve_geometry(meta, &s.geometry).map_err(|e| MethodError::Chain(e.to_string()))?;
        let g = meta.gravity().map_err(MethodError::Metadata)?;
        let ekf =
            ChainEkf::new(s.params, geometry, g).map_err(|e| MethodError::Chain(e.to_string()))?;
        Ok(Box::new(ekf))
    }

    fn default_file() -> String {
        default_file()
    }
}

/// The default file, commented (`limbfuse params --method chain`).
pub fn default_file() -> String {
    let d = ChainParams::default();
    let g = ChainGeometry::default();
    let v = |r: [f64; 3]| format!("[{}, {}, {}]", r[0], r[1], r[2]);
    format!(
        "# limbfuse chain parameters (kinematic-chain EKF; docs/CHAIN.md).\n\
         # Measurement and anchor sigmas are per sample at 100 Hz; their variances scale with the\n\
         # sample period (docs/CHAIN.md, \"Sample rate\").\n\
         method = \"chain\"\n\
         gyro_noise = {}  # gyro z noise + model error per sample, 1 sigma (rad/s)\n\
         acc_noise = {}  # accelerometer x/y noise + model error per sample, 1 sigma (m/s^2)\n\
         encoder_noise = {}  # encoder noise + quantisation, 1 sigma (rad)\n\
         trunk_jerk = {}  # trunk angular jerk intensity (rad^2/s^5)\n\
         leg_jerk = {}  # thigh/shank/foot angular jerk intensity (rad^2/s^5)\n\
         hip_acc_sd = {}  # hip acceleration per axis, stationary 1 sigma of its Gauss-Markov model (m/s^2)\n\
         hip_acc_tau = {}  # hip acceleration correlation time (s)\n\
         gyro_bias_walk = {:e}  # gyro bias random walk (rad^2/s^3)\n\
         gyro_bias_initial = {}  # initial gyro bias, 1 sigma (rad/s)\n\
         hip_vertical_velocity = {}  # anchor: vertical hip velocity about 0, 1 sigma (m/s)\n\
         hip_forward_velocity = {}  # anchor: forward hip velocity about the mean speed, 1 sigma (m/s)\n\
         mean_speed_walk = {:e}  # mean forward speed random walk (m^2/s^3)\n\
         stance_velocity = {}  # anchor: ankle velocity while the foot is still, 1 sigma (m/s)\n\
         stance_acceleration = {}  # anchor: ankle acceleration while the foot is still, 1 sigma (m/s^2)\n\
         stance_gyro = {}  # foot still: |gyro| below (rad/s)\n\
         stance_acc = {}  # foot still: | |acc| - g | below (m/s^2)\n\
         stance_min_s = {}  # foot still for at least (s)\n\
         startup_s = {}  # start-up window (s)\n\
         acc_gate = inf  # skip accelerometer rows beyond this many sigmas (inf: never)\n\
         encoder_gate = {}  # refuse encoder rows beyond this many sigmas (chi-square 1-1e-6; inf: never); refused for 0.5 s: re-adopted\n\
         gyro_gate = {}  # refuse a segment's gyro row beyond this many sigmas while one of its joints' encoders reads (inf: never)\n\
         use_encoders = {}  # use hip/knee/ankle encoders when present\n\
         out_of_plane = {}  # correct for non-sagittal gyro components\n\
         turn_tau_s = {}  # turning: low-pass time constant of the rate about the vertical (s)\n\
         turn_rate_min = {}  # turning: low-passed rate about the vertical above this is a turn (rad/s)\n\
         turn_angle_noise = {}  # turning: angle 1-sigma added per sqrt(rad) turned (rad; 0: off)\n\
         device_orientation = {}  # use the trial's device orientation (<seg>_quat_*) as an angle row\n\
         device_angle_noise = {}  # that angle's 1 sigma per sample at 100 Hz (rad)\n\
         \n\
         # Geometry: the trial's metadata wins (imu_mounts_m, segment_lengths_m, height_m);\n\
         # these keys fill what it lacks; the rest comes from Winter's proportions.\n\
         [geometry]\n\
         # height_m = {DEFAULT_BODY_HEIGHT_M}\n\
         # thigh_length = {}\n\
         # shank_length = {}\n\
         # imu_trunk = {}\n\
         # imu_thigh = {}\n\
         # imu_shank = {}\n\
         # imu_foot = {}\n\
         # frame_offset_deg = [0, 0, 0, 0]  # sensor frame vs anatomical frame per segment; default: from align's metadata (docs/CHAIN.md)\n",
        d.gyro_noise,
        d.acc_noise,
        d.encoder_noise,
        d.trunk_jerk,
        d.leg_jerk,
        d.hip_acc_sd,
        d.hip_acc_tau,
        d.gyro_bias_walk,
        d.gyro_bias_initial,
        d.hip_vertical_velocity,
        d.hip_forward_velocity,
        d.mean_speed_walk,
        d.stance_velocity,
        d.stance_acceleration,
        d.stance_gyro,
        d.stance_acc,
        d.stance_min_s,
        d.startup_s,
        d.encoder_gate,
        d.gyro_gate,
        d.use_encoders,
        d.out_of_plane,
        d.turn_tau_s,
        d.turn_rate_min,
        d.turn_angle_noise,
        d.device_orientation,
        d.device_angle_noise,
        g.thigh_length,
        g.shank_length,
        v(g.imu_position[0]),
        v(g.imu_position[1]),
        v(g.imu_position[2]),
        v(g.imu_position[3]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_file_reads_back_to_the_defaults() {
        let s = chain_settings(Some((&default_file(), Path::new("d.toml")))).unwrap();
        assert_eq!(s.params, ChainParams::default());
        assert_eq!(s.geometry, GeometryFile::default());
    }

    #[test]
    fn unknown_keys_and_bad_values_are_errors() {
        let p = Path::new("c.toml");
        let e = chain_settings(Some(("acc_nois = 1\n", p)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("c.toml"), "{e}");
        let e = chain_settings(Some(("acc_noise = -1\n", p)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("acc_noise"), "{e}");
        let e = chain_settings(Some(("[geometry]\nthigh_length = 5.0\n", p)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("thigh_length"), "{e}");
    }

    #[test]
    fn metadata_wins_over_the_file_which_wins_over_anthropometry() {
        let file = GeometryFile {
            height_m: Some(1.6),
            thigh_length: Some(0.40),
            imu_shank: Some([0.01, -0.2, 0.05]),
            imu_foot: Some([0.05, 0.0, 0.0]),
            ..Default::default()
        };
        let mut meta = TrialMeta::new();
        meta.set("imu_mounts_m", "foot (0.08, -0.01)");
        meta.set("segment_lengths_m", "shank 0.41");
        let g = resolve_geometry(&meta, &file).unwrap();
        assert_eq!(g.thigh_length, 0.40);
        assert_eq!(g.shank_length, 0.41);
        assert_eq!(g.imu_position[3], [0.08, -0.01, 0.0]);
        assert_eq!(g.imu_position[2], [0.01, -0.2, 0.05]);
        assert_eq!(g.imu_position[1], [0.0, -0.20, 0.0]);
        let w = ChainGeometry::from_height(1.6);
        assert_eq!(g.imu_position[0], w.imu_position[0]);
        meta.set("imu_mounts_m", "foot (0.08)");
        assert!(resolve_geometry(&meta, &file)
            .unwrap_err()
            .to_string()
            .contains("imu_mounts_m"));
    }

    #[test]
    fn issue_14_frame_offsets_follow_the_alignment_zero() {
        let mut meta = TrialMeta::new();
        let none = resolve_geometry(&meta, &GeometryFile::default()).unwrap();
        assert_eq!(none.frame_offset, [0.0; 4]);
        meta.set("thigh_align_zero", "mean-inclination target 0.000 deg");
        meta.set("shank_align_zero", "mean-inclination target -10.000 deg");
        meta.set("foot_align_zero", "quiet-standing 1.000..2.990 s");
        let g = resolve_geometry(&meta, &GeometryFile::default()).unwrap();
        let deg = g.frame_offset.map(f64::to_degrees);
        assert!((deg[1] + 7.0).abs() < 1e-9, "{deg:?}");
        assert!((deg[2] - 6.0).abs() < 1e-9, "{deg:?}");
        assert_eq!((deg[0], deg[3]), (0.0, 0.0));
        let file = GeometryFile {
            frame_offset_deg: Some([0.0, 1.0, 2.0, 3.0]),
            ..Default::default()
        };
        let g = resolve_geometry(&meta, &file).unwrap();
        assert!((g.frame_offset[3].to_degrees() - 3.0).abs() < 1e-12);
        let bad = GeometryFile {
            frame_offset_deg: Some([0.0, 400.0, 0.0, 0.0]),
            ..Default::default()
        };
        let e = resolve_geometry(&meta, &bad).unwrap_err().to_string();
        assert!(e.contains("thigh frame offset"), "{e}");
    }
}
