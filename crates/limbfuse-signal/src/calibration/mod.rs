//! Accelerometer calibration from static poses, and gyro bias from rest
//! (`limbfuse calibrate`). Model, equations, minimum poses and file format:
//! `docs/CALIBRATION.md`; the file is [`limbfuse_io::Calibration`].
//!
//! Per sensor: find the static poses ([`static_poses`]), fit `b_a` and a
//! symmetric `C` so that `|C (m_k - b_a)| = g` for every pose mean `m_k`
//! ([`fit`]), check that the poses determine the unknowns and fit one
//! ellipsoid, and take the gyro bias `b_w` as the mean gyro reading over
//! the poses (the sensor is at rest there).

use limbfuse_core::{Record, Segment, STANDARD_GRAVITY};
use limbfuse_io::calibration::{CalibrationModel, FitSummary};
use limbfuse_io::{Calibration, ImuCalibration};
use nalgebra::Vector3;

pub mod fit;
pub mod static_poses;
pub mod trial_calibration;

use static_poses::{find_poses, RejectedHold, StaticPose};

/// Settings of [`calibrate`]. `Default` gives the documented values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrationParams {
    /// What to estimate per accelerometer.
    pub model: CalibrationModel,
    /// Local gravity (m/s^2), the norm every calibrated static reading gets.
    pub gravity: f64,
    /// Window (s) of the moving statistics of the static test.
    pub window_s: f64,
    /// Static: accelerometer spread `sqrt(sum var)` below this (m/s^2).
    pub acc_std_max: f64,
    /// Static: gyro spread below this (rad/s).
    pub gyro_std_max: f64,
    /// Hold: mean gyro rate below this (rad/s): the sensor is not being turned.
    pub hold_rate_max: f64,
    /// Shortest pose (s).
    pub min_pose_s: f64,
    /// Poses whose gravity directions are closer than this (rad) count as one
    /// distinct pose for the minimum (they all enter the fit).
    pub distinct_rad: f64,
    /// The poses must determine the unknowns: smallest eigenvalue of the
    /// column-normalised `J^T J` at least this.
    pub min_eigenvalue: f64,
    /// Largest RMS residual `|C (m_k - b)| - g` accepted (m/s^2).
    pub max_residual: f64,
}

impl CalibrationParams {
    /// Every setting as `name=value` words (the `# fit_settings:` line of a
    /// calibration file, docs/CALIBRATION.md: what thresholds made it).
    pub fn settings(&self) -> String {
        format!(
            "model={} gravity={} window_s={} acc_std_max={} gyro_std_max={} hold_rate_max={} \
             min_pose_s={} distinct_rad={} min_eigenvalue={} max_residual={}",
            self.model.name(),
            self.gravity,
            self.window_s,
            self.acc_std_max,
            self.gyro_std_max,
            self.hold_rate_max,
            self.min_pose_s,
            self.distinct_rad,
            self.min_eigenvalue,
            self.max_residual
        )
    }
}

impl Default for CalibrationParams {
    fn default() -> Self {
        CalibrationParams {
            model: CalibrationModel::Full,
            gravity: STANDARD_GRAVITY,
            window_s: 0.5,
            acc_std_max: 0.05,
            gyro_std_max: 0.03,
            hold_rate_max: 0.3,
            min_pose_s: 1.0,
            distinct_rad: 15f64.to_radians(),
            min_eigenvalue: 1e-3,
            max_residual: 0.05,
        }
    }
}

/// Why a calibration could not be made. Each names the sensor and the problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrationError {
    /// A setting out of range.
    #[error("calibration setting `{name}` = {}: must be {expected}", limbfuse_core::ShownNumber(*value))]
    BadParam {
        /// Setting name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        expected: &'static str,
    },
    /// No accelerometer channel in the recording.
    #[error("the recording has no accelerometer channels (`<segment>_acc_x`, ...): nothing to calibrate")]
    NoAccelerometer,
    /// No static pose at all.
    #[error("{sensor}: no static pose in the recording (a pose: at least {} s with accelerometer std below {} m/s^2 and gyro std below {} rad/s); the sensor moves throughout{rejected}", limbfuse_core::ShownNumber(*.min_pose_s), limbfuse_core::ShownNumber(*.acc_std_max), limbfuse_core::ShownNumber(*.gyro_std_max))]
    NoStaticPose {
        /// Sensor (segment name).
        sensor: &'static str,
        /// Settings quoted in the message.
        min_pose_s: f64,
        /// Settings quoted in the message.
        acc_std_max: f64,
        /// Settings quoted in the message.
        gyro_std_max: f64,
        /// Rejected holds, one per line (or empty).
        rejected: String,
    },
    /// Too few (distinct) poses for the model's unknowns.
    #[error("{sensor}: {distinct} distinct static poses ({found} found), but the {model} model has {needed} unknowns and needs at least {needed} distinct, well-spread poses (gravity along +x, -x, +y, -y, +z, -z and in between; or a reduced model: --model scale needs 6, bias 3){rejected}")]
    TooFewPoses {
        /// Sensor.
        sensor: &'static str,
        /// Poses found.
        found: usize,
        /// Distinct ones.
        distinct: usize,
        /// Unknowns of the model.
        needed: usize,
        /// Model name.
        model: &'static str,
        /// Rejected holds, one per line (or empty).
        rejected: String,
    },
    /// The poses do not determine the unknowns (e.g. all in one plane).
    #[error("{sensor}: the {poses} poses do not determine the {model} model (smallest normalised eigenvalue {eigenvalue:.2e} < {limit:.0e}): spread gravity over every direction of the sensor (+-x, +-y, +-z and the corners), or use a reduced model")]
    NotSpread {
        /// Sensor.
        sensor: &'static str,
        /// Poses used.
        poses: usize,
        /// Model name.
        model: &'static str,
        /// The eigenvalue.
        eigenvalue: f64,
        /// The limit.
        limit: f64,
    },
    /// The poses do not fit one ellipsoid (a moving or mislabelled pose).
    #[error("{sensor}: the poses do not fit one calibration: RMS residual {rms:.4} m/s^2 > {} m/s^2; worst pose {start:.2}-{end:.2} s ({worst:+.4} m/s^2): was the sensor moving or saturated, or is the {model} model too small for it?", limbfuse_core::ShownNumber(*.limit))]
    Residual {
        /// Sensor.
        sensor: &'static str,
        /// RMS residual.
        rms: f64,
        /// Limit.
        limit: f64,
        /// Worst pose span start (s).
        start: f64,
        /// Worst pose span end (s).
        end: f64,
        /// Its residual.
        worst: f64,
        /// Model name.
        model: &'static str,
    },
}

fn check(p: &CalibrationParams) -> Result<(), CalibrationError> {
    let pos = |name, value: f64, expected| {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(CalibrationError::BadParam {
                name,
                value,
                expected,
            })
        }
    };
    // The accelerometers are fitted to it: a value off the Earth's gave
    // scales of 0.51 (`--gravity 5`) without a word (an audit).
    if !(9.7..=9.9).contains(&p.gravity) {
        return Err(CalibrationError::BadParam {
            name: "gravity",
            value: p.gravity,
            expected: "9.7 to 9.9 m/s^2 (gravity at the Earth's surface is 9.78-9.83, which the static poses measure)",
        });
    }
    pos("window_s", p.window_s, "finite and > 0 (s)")?;
    pos("acc_std_max", p.acc_std_max, "finite and > 0 (m/s^2)")?;
    pos("gyro_std_max", p.gyro_std_max, "finite and > 0 (rad/s)")?;
    pos("hold_rate_max", p.hold_rate_max, "finite and > 0 (rad/s)")?;
    pos("min_pose_s", p.min_pose_s, "finite and > 0 (s)")?;
    pos("distinct_rad", p.distinct_rad, "finite and > 0 (rad)")?;
    pos("min_eigenvalue", p.min_eigenvalue, "finite and > 0")?;
    pos("max_residual", p.max_residual, "finite and > 0 (m/s^2)")
}

/// Number of distinct gravity directions among the poses (greedy clusters
/// of angular radius `radius`).
fn distinct(poses: &[StaticPose], radius: f64) -> usize {
    let mut centres: Vec<Vector3<f64>> = Vec::new();
    for p in poses {
        let d = p.acc.normalize();
        if !centres.iter().any(|c| c.angle(&d) < radius) {
            centres.push(d);
        }
    }
    centres.len()
}

fn list(rejected: &[RejectedHold], p: &CalibrationParams) -> Vec<String> {
    rejected.iter().map(|r| r.describe(p)).collect()
}

fn lines(rejected: &[String]) -> String {
    if rejected.is_empty() {
        String::new()
    } else {
        format!("; rejected:\n  {}", rejected.join("\n  "))
    }
}

/// Calibrates one sensor.
fn calibrate_sensor(
    records: &[Record],
    seg: Segment,
    p: &CalibrationParams,
) -> Result<ImuCalibration, CalibrationError> {
    let sensor = seg.name();
    let (poses, rejected) = find_poses(records, seg.index(), p);
    let rejected = list(&rejected, p);
    if poses.is_empty() {
        return Err(CalibrationError::NoStaticPose {
            sensor,
            min_pose_s: p.min_pose_s,
            acc_std_max: p.acc_std_max,
            gyro_std_max: p.gyro_std_max,
            rejected: lines(&rejected),
        });
    }
    let needed = p.model.unknowns();
    let n_distinct = distinct(&poses, p.distinct_rad);
    if n_distinct < needed {
        return Err(CalibrationError::TooFewPoses {
            sensor,
            found: poses.len(),
            distinct: n_distinct,
            needed,
            model: p.model.name(),
            rejected: lines(&rejected),
        });
    }
    let means: Vec<Vector3<f64>> = poses.iter().map(|q| q.acc).collect();
    let r = fit::fit(&means, p.gravity, p.model);
    let eig = r.min_normalised_eigenvalue;
    if eig.is_nan() || eig < p.min_eigenvalue {
        return Err(CalibrationError::NotSpread {
            sensor,
            poses: poses.len(),
            model: p.model.name(),
            eigenvalue: r.min_normalised_eigenvalue,
            limit: p.min_eigenvalue,
        });
    }
    if r.residual_rms.is_nan() || r.residual_rms > p.max_residual {
        let (k, worst) = means
            .iter()
            .map(|m| fit::residual(&r.params, m, p.gravity))
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap_or((0, f64::NAN));
        return Err(CalibrationError::Residual {
            sensor,
            rms: r.residual_rms,
            limit: p.max_residual,
            start: poses[k].span.0,
            end: poses[k].span.1,
            worst,
            model: p.model.name(),
        });
    }
    let gyr_count: usize = poses.iter().map(|q| q.gyr_count).sum();
    let gyro_bias = (gyr_count > 0)
        .then(|| poses.iter().map(|q| q.gyr_sum).sum::<Vector3<f64>>() / gyr_count as f64);
    Ok(ImuCalibration {
        acc_bias: fit::bias(&r.params),
        acc_matrix: fit::matrix(&r.params),
        gyro_bias,
        fit: Some(FitSummary {
            poses: poses.len(),
            residual_rms: r.residual_rms,
            pose_spans_s: poses.iter().map(|q| [q.span.0, q.span.1]).collect(),
            rejected,
        }),
    })
}

/// Calibrates every sensor with accelerometer readings in `records` (a
/// recording of static poses, sorted by time). The result is in the raw
/// sensor frame of the recording. Holds that were not static are listed in
/// each sensor's [`FitSummary::rejected`].
pub fn calibrate(
    records: &[Record],
    params: &CalibrationParams,
) -> Result<Calibration, CalibrationError> {
    check(params)?;
    let mut sensors: [Option<ImuCalibration>; 4] = Default::default();
    for seg in Segment::ALL {
        if records
            .iter()
            .any(|r| r.sample.imu[seg.index()].acc.is_some())
        {
            sensors[seg.index()] = Some(calibrate_sensor(records, seg, params)?);
        }
    }
    if sensors.iter().all(Option::is_none) {
        return Err(CalibrationError::NoAccelerometer);
    }
    Ok(Calibration {
        sensors,
        model: params.model,
        gravity: params.gravity,
        source: None,
    })
}
