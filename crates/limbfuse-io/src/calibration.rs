//! IMU calibration files (`limbfuse calibrate -o cal.toml`, read by
//! `import`, `align` and `estimate --calibration`), and applying a
//! calibration to records. Model, fit and format: `docs/CALIBRATION.md`.
//!
//! Per sensor, in the **raw sensor frame** the calibration recording was
//! made in:
//! `a_cal = C (a_raw - b_a)`, `w_cal = w_raw - b_w`,
//! with `b_a` the accelerometer bias (m/s^2), `C` the 3x3 scale and
//! cross-axis correction (symmetric when fitted by `limbfuse calibrate`) and
//! `b_w` the gyroscope bias (rad/s). Device quaternions are left alone.
//!
//! ```toml
//! format = "limbfuse-imu-calibration/1"
//! model = "full"                  # full | scale | bias: what the fit estimated
//! gravity = 9.81                  # m/s^2, |C (a - b_a)| on a static sensor
//! source = "poses.csv"            # the pose recording (provenance)
//!
//! [sensors.thigh]                 # trunk | thigh | shank | foot
//! acc_bias = [0.12, -0.05, 0.2]   # b_a, m/s^2
//! acc_matrix = [[1.004, 0.001, -0.002], [0.001, 0.996, 0.0], [-0.002, 0.0, 1.001]]  # C, rows
//! gyro_bias = [0.004, -0.009, 0.002]  # b_w, rad/s (absent: no gyro correction)
//! poses = 14                      # fit summary (informative)
//! residual_rms = 0.0011           # m/s^2
//! pose_spans_s = [[0.0, 4.0], [6.0, 10.0]]
//! rejected_poses = ["12.00-16.00 s: not static: ..."]  # holds left out
//! ```

use std::path::{Path, PathBuf};

use limbfuse_core::{Record, Segment};
use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};

use crate::layout::TrialLayout;
use crate::meta::TrialMeta;

/// The `format` line of a calibration file.
pub const FORMAT: &str = "limbfuse-imu-calibration/1";

/// Metadata key a calibrated trial carries (its value names the file and
/// the frame the calibration was applied in); a second calibration of the
/// same trial is refused.
pub const META_KEY: &str = "imu_calibration";

/// What a fit estimated per sensor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum CalibrationModel {
    /// Bias and a symmetric `C` (3 scales + 3 cross-axis terms): 9 unknowns.
    #[default]
    Full,
    /// Bias and a diagonal `C` (3 scales): 6 unknowns.
    Scale,
    /// Bias only (`C = I`): 3 unknowns.
    Bias,
}

impl CalibrationModel {
    /// Number of accelerometer unknowns per sensor.
    pub fn unknowns(self) -> usize {
        match self {
            CalibrationModel::Full => 9,
            CalibrationModel::Scale => 6,
            CalibrationModel::Bias => 3,
        }
    }

    /// The name used in files and flags.
    pub fn name(self) -> &'static str {
        match self {
            CalibrationModel::Full => "full",
            CalibrationModel::Scale => "scale",
            CalibrationModel::Bias => "bias",
        }
    }
}

/// How the fit went for one sensor (informative; not used when applying).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FitSummary {
    /// Static poses used.
    pub poses: usize,
    /// RMS of `|C (a_k - b_a)| - g` over the poses (m/s^2).
    pub residual_rms: f64,
    /// The time spans (s) of the poses used.
    pub pose_spans_s: Vec<[f64; 2]>,
    /// Holds that were not static and were left out, one message each.
    pub rejected: Vec<String>,
}

/// The calibration of one IMU.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuCalibration {
    /// Accelerometer bias `b_a` (m/s^2, raw sensor frame).
    pub acc_bias: Vector3<f64>,
    /// Scale and cross-axis correction `C`.
    pub acc_matrix: Matrix3<f64>,
    /// Gyroscope bias `b_w` (rad/s); `None`: gyro left as it is.
    pub gyro_bias: Option<Vector3<f64>>,
    /// Fit summary, when the calibration came from a fit.
    pub fit: Option<FitSummary>,
}

impl ImuCalibration {
    /// Calibrated accelerometer reading `C (a - b_a)`.
    pub fn acc(&self, a: &Vector3<f64>) -> Vector3<f64> {
        self.acc_matrix * (a - self.acc_bias)
    }

    /// Calibrated gyro reading `w - b_w`.
    pub fn gyr(&self, w: &Vector3<f64>) -> Vector3<f64> {
        match &self.gyro_bias {
            Some(b) => w - b,
            None => *w,
        }
    }

    /// The same calibration for readings rotated by `r` (`v' = R v`, e.g.
    /// an aligned trial): `C' = R C R^T`, `b_a' = R b_a`, `b_w' = R b_w`, so
    /// that `C' (R a - b_a') = R C (a - b_a)`.
    pub fn rotated(&self, r: &Rotation3<f64>) -> Self {
        let rm = r.matrix();
        ImuCalibration {
            acc_bias: rm * self.acc_bias,
            acc_matrix: rm * self.acc_matrix * rm.transpose(),
            gyro_bias: self.gyro_bias.map(|b| rm * b),
            fit: self.fit.clone(),
        }
    }
}

/// A calibration file: one entry per calibrated sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    /// Per segment's IMU (trunk, thigh, shank, foot).
    pub sensors: [Option<ImuCalibration>; 4],
    /// What the fit estimated.
    pub model: CalibrationModel,
    /// Gravity the fit used (m/s^2).
    pub gravity: f64,
    /// The pose recording it came from (provenance).
    pub source: Option<String>,
}

/// Why a calibration file could not be read, or does not fit a trial.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationFileError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// Bad TOML, unknown key, wrong type.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Syntax {
        /// File path.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A value that parses but cannot be a calibration.
    #[error("{}: `{key}`: {expected}", path.display())]
    Value {
        /// File path.
        path: PathBuf,
        /// The key.
        key: String,
        /// What was expected.
        expected: String,
    },
    /// The trial has IMUs the file does not calibrate.
    #[error("{}: calibrates the sensors {covered} but the trial {trial} also has {missing}: a calibration of other sensors cannot be applied (calibrate those sensors, or leave --calibration out)", path.display())]
    SensorsDoNotMatch {
        /// Calibration file.
        path: PathBuf,
        /// What the file covers.
        covered: String,
        /// The trial.
        trial: String,
        /// Trial IMUs without an entry.
        missing: String,
    },
    /// The trial was calibrated already.
    #[error("{}: already calibrated ({META_KEY}: {previous}); applying a calibration twice would distort it", trial.display())]
    AlreadyCalibrated {
        /// The trial.
        trial: PathBuf,
        /// The earlier calibration, as recorded.
        previous: String,
    },
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SensorToml {
    acc_bias: [f64; 3],
    acc_matrix: [[f64; 3]; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    gyro_bias: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    poses: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    residual_rms: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pose_spans_s: Option<Vec<[f64; 2]>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    rejected_poses: Vec<String>,
}

#[derive(Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct SensorsToml {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    trunk: Option<SensorToml>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    thigh: Option<SensorToml>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    shank: Option<SensorToml>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    foot: Option<SensorToml>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    format: String,
    model: CalibrationModel,
    gravity: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    source: Option<String>,
    sensors: SensorsToml,
}

/// 1-based line and column of byte `offset` in `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

fn to_sensor(c: &ImuCalibration) -> SensorToml {
    let m = &c.acc_matrix;
    SensorToml {
        acc_bias: c.acc_bias.into(),
        acc_matrix: [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]),
        gyro_bias: c.gyro_bias.map(Into::into),
        poses: c.fit.as_ref().map(|f| f.poses),
        residual_rms: c.fit.as_ref().map(|f| f.residual_rms),
        pose_spans_s: c.fit.as_ref().map(|f| f.pose_spans_s.clone()),
        rejected_poses: c.fit.as_ref().map_or_else(Vec::new, |f| f.rejected.clone()),
    }
}

impl Calibration {
    /// Names of the calibrated sensors, e.g. `thigh, shank`.
    pub fn sensor_names(&self) -> String {
        let names: Vec<&str> = Segment::ALL
            .into_iter()
            .filter(|s| self.sensors[s.index()].is_some())
            .map(|s| s.name())
            .collect();
        if names.is_empty() {
            "(none)".into()
        } else {
            names.join(", ")
        }
    }

    /// The file text (TOML, every number in its shortest round-trip form).
    pub fn to_toml(&self) -> String {
        self.to_toml_with_provenance(&[])
    }

    /// [`Calibration::to_toml`] with provenance lines (`# key: value`
    /// comments after the format comment, [`crate::provenance`]): the
    /// limbfuse version, the command, the fit's settings, the pose
    /// recording's hash. Comments, so every reader of the format reads the
    /// file as before, and a file without them reads as well.
    pub fn to_toml_with_provenance(&self, provenance: &[(&str, String)]) -> String {
        let [trunk, thigh, shank, foot] =
            self.sensors.each_ref().map(|s| s.as_ref().map(to_sensor));
        let file = FileToml {
            format: FORMAT.into(),
            model: self.model,
            gravity: self.gravity,
            source: self.source.clone(),
            sensors: SensorsToml {
                trunk,
                thigh,
                shank,
                foot,
            },
        };
        let body = toml::to_string(&file).unwrap_or_default();
        format!(
            "# limbfuse IMU calibration (docs/CALIBRATION.md), raw sensor frames:\n# a_cal = acc_matrix * (a_raw - acc_bias), w_cal = w_raw - gyro_bias\n{}{body}",
            crate::provenance::comment_lines(provenance)
        )
    }

    /// Parses a calibration file's text (`path` names it in errors).
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, CalibrationFileError> {
        let file: FileToml = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map_or((1, 1), |s| line_col(text, s.start));
            CalibrationFileError::Syntax {
                path: path.to_path_buf(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        })?;
        let value = |key: String, expected: &str| CalibrationFileError::Value {
            path: path.to_path_buf(),
            key,
            expected: expected.to_string(),
        };
        if file.format != FORMAT {
            return Err(value(
                "format".into(),
                &format!("`{FORMAT}`, found `{}`", file.format),
            ));
        }
        // (an audit: any finite positive number was accepted, 1e300 too)
        if let Some(expected) = crate::calibration_bounds::check_gravity(file.gravity) {
            return Err(value("gravity".into(), &expected));
        }
        let SensorsToml {
            trunk,
            thigh,
            shank,
            foot,
        } = file.sensors;
        let mut sensors: [Option<ImuCalibration>; 4] = Default::default();
        for (seg, entry) in Segment::ALL.into_iter().zip([trunk, thigh, shank, foot]) {
            let Some(e) = entry else { continue };
            let key = |k: &str| format!("sensors.{}.{k}", seg.name());
            if !e.acc_bias.iter().all(|v| v.is_finite()) {
                return Err(value(key("acc_bias"), "three finite numbers (m/s^2)"));
            }
            let m = Matrix3::from_fn(|i, j| e.acc_matrix[i][j]);
            if !m.iter().all(|v| v.is_finite()) || m.determinant() <= 1e-6 {
                return Err(value(
                    key("acc_matrix"),
                    "three rows of three finite numbers with a positive determinant (an invertible correction without reflection)",
                ));
            }
            if let Some(g) = e.gyro_bias {
                if !g.iter().all(|v| v.is_finite()) {
                    return Err(value(key("gyro_bias"), "three finite numbers (rad/s)"));
                }
            }
            crate::calibration_bounds::check(&e.acc_bias, &m, e.gyro_bias)
                .map_err(|(k, expected)| value(key(k), &expected))?;
            let fit = e.poses.map(|poses| FitSummary {
                poses,
                residual_rms: e.residual_rms.unwrap_or(f64::NAN),
                pose_spans_s: e.pose_spans_s.clone().unwrap_or_default(),
                rejected: e.rejected_poses.clone(),
            });
            sensors[seg.index()] = Some(ImuCalibration {
                acc_bias: Vector3::from(e.acc_bias),
                acc_matrix: m,
                gyro_bias: e.gyro_bias.map(Vector3::from),
                fit,
            });
        }
        if sensors.iter().all(Option::is_none) {
            return Err(value(
                "sensors".into(),
                "at least one of [sensors.trunk], [sensors.thigh], [sensors.shank], [sensors.foot]",
            ));
        }
        Ok(Calibration {
            sensors,
            model: file.model,
            gravity: file.gravity,
            source: file.source,
        })
    }

    /// Reads a calibration file.
    pub fn read(path: &Path) -> Result<Self, CalibrationFileError> {
        let text = crate::bounded_text::read_text_at_most(
            path,
            crate::bounded_text::MAX_SETTINGS_FILE_BYTES,
            "a calibration file (TOML, a few KB)",
        )
        .map_err(|source| CalibrationFileError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_toml(&text, path)
    }

    /// Checks that the calibration covers every IMU of a trial (`layout`:
    /// a segment with accelerometer or gyro columns); `path` and `trial`
    /// name the two files in the error. Returns the calibrated sensors the
    /// trial does not have (not an error: a calibration of four sensors
    /// serves a trial of two).
    pub fn check_covers(
        &self,
        layout: &TrialLayout,
        path: &Path,
        trial: &Path,
    ) -> Result<Vec<Segment>, CalibrationFileError> {
        let has = |s: Segment| layout.acc[s.index()] || layout.gyr[s.index()];
        let missing: Vec<&str> = Segment::ALL
            .into_iter()
            .filter(|&s| has(s) && self.sensors[s.index()].is_none())
            .map(|s| s.name())
            .collect();
        if !missing.is_empty() {
            return Err(CalibrationFileError::SensorsDoNotMatch {
                path: path.to_path_buf(),
                covered: self.sensor_names(),
                trial: trial.display().to_string(),
                missing: missing.join(", "),
            });
        }
        Ok(Segment::ALL
            .into_iter()
            .filter(|&s| !has(s) && self.sensors[s.index()].is_some())
            .collect())
    }

    /// Refuses a trial whose metadata says it was calibrated already.
    pub fn check_not_calibrated(
        meta: &TrialMeta,
        trial: &Path,
    ) -> Result<(), CalibrationFileError> {
        match meta.get(META_KEY) {
            Some(previous) => Err(CalibrationFileError::AlreadyCalibrated {
                trial: trial.to_path_buf(),
                previous: previous.to_string(),
            }),
            None => Ok(()),
        }
    }

    /// The calibration for readings rotated by `rotations[s]` (raw to the
    /// trial's frame; `None`: raw frame): see [`ImuCalibration::rotated`].
    pub fn rotated(&self, rotations: &[Option<Rotation3<f64>>; 4]) -> Self {
        let mut out = self.clone();
        for (c, r) in out.sensors.iter_mut().zip(rotations) {
            if let (Some(c), Some(r)) = (c.as_mut(), r) {
                *c = c.rotated(r);
            }
        }
        out
    }

    /// Applies the calibration to a record's accelerometer and gyro
    /// readings (sensors without an entry are left as they are).
    pub fn apply(&self, record: &mut Record) {
        self.apply_sample(&mut record.sample);
    }

    /// [`Calibration::apply`] on a sample.
    pub fn apply_sample(&self, sample: &mut limbfuse_core::Sample) {
        for (imu, c) in sample.imu.iter_mut().zip(&self.sensors) {
            if let Some(c) = c {
                imu.acc = imu.acc.map(|a| c.acc(&a));
                imu.gyr = imu.gyr.map(|w| c.gyr(&w));
            }
        }
    }

    /// Records in `meta` that this calibration (file `name`) was applied,
    /// in `frame` (e.g. `raw sensor frame`).
    pub fn annotate(&self, meta: &mut TrialMeta, name: &str, frame: &str) {
        meta.set(
            META_KEY,
            format!(
                "{name} ({} model, sensors {}; applied in the {frame})",
                self.model.name(),
                self.sensor_names()
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Calibration {
        let c = ImuCalibration {
            acc_bias: Vector3::new(0.1, -0.2, 0.3),
            acc_matrix: Matrix3::new(1.01, 0.002, -0.003, 0.002, 0.99, 0.001, -0.003, 0.001, 1.0),
            gyro_bias: Some(Vector3::new(0.01, 0.0, -0.02)),
            fit: Some(FitSummary {
                poses: 12,
                residual_rms: 0.001,
                pose_spans_s: vec![[0.0, 4.0], [6.0, 10.5]],
                rejected: vec!["12.00-16.00 s: not static".into()],
            }),
        };
        Calibration {
            sensors: [None, Some(c.clone()), Some(c), None],
            model: CalibrationModel::Full,
            gravity: 9.81,
            source: Some("poses.csv".into()),
        }
    }

    #[test]
    fn the_file_reads_back_bit_for_bit() {
        let c = sample();
        let text = c.to_toml();
        let back = Calibration::from_toml(&text, Path::new("c.toml")).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn unknown_keys_and_bad_values_name_the_place() {
        let text = sample()
            .to_toml()
            .replace("[sensors.thigh]", "[sensors.knee]");
        let e = Calibration::from_toml(&text, Path::new("c.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("c.toml:") && e.contains("knee"), "{e}");
        let text = sample()
            .to_toml()
            .replacen("acc_matrix = [[1.01", "acc_matrix = [[-1.01", 1);
        let e = Calibration::from_toml(&text, Path::new("c.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("sensors.thigh.acc_matrix"), "{e}");
        let text = sample().to_toml().replace(FORMAT, "other/1");
        let e = Calibration::from_toml(&text, Path::new("c.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("`format`"), "{e}");
    }

    #[test]
    fn rotated_calibration_commutes_with_the_rotation() {
        let c = sample().sensors[1].clone().unwrap();
        let r = Rotation3::from_euler_angles(0.3, -1.1, 2.0);
        let a = Vector3::new(1.0, 9.0, -2.0);
        let w = Vector3::new(0.5, -0.1, 0.2);
        let cr = c.rotated(&r);
        assert!((cr.acc(&(r * a)) - r * c.acc(&a)).norm() < 1e-12);
        assert!((cr.gyr(&(r * w)) - r * c.gyr(&w)).norm() < 1e-12);
    }

    #[test]
    fn coverage_names_the_missing_sensors() {
        let c = sample();
        let e = c
            .check_covers(
                &TrialLayout::walking(),
                Path::new("c.toml"),
                Path::new("t.csv"),
            )
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("thigh, shank") && e.contains("trunk, foot"),
            "{e}"
        );
        let mut layout = TrialLayout::default();
        layout.acc[1] = true;
        layout.gyr[1] = true;
        let unused = c
            .check_covers(&layout, Path::new("c.toml"), Path::new("t.csv"))
            .unwrap();
        assert_eq!(unused, vec![Segment::Shank]);
    }
}
