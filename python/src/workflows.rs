//! `simulate`, `align`, `calibrate` and `gait_library`: the CLI's workflows
//! as functions (`limbfuse-workflows`, `limbfuse-signal`, `limbfuse-sim`).

use std::path::PathBuf;

use limbfuse_core::{Record, Segment};
use limbfuse_io::calibration::CalibrationModel;
use limbfuse_models::bslip::BslipParams;
use limbfuse_models::KneeSubject;
use limbfuse_signal::align::{apply_alignment, estimate_alignment, AlignOptions};
use limbfuse_signal::calibration::CalibrationParams;
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_sim::fixed_hip::FixedHipConfig;
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_sim::{KneeScenario, Mounting, PoseRecordingConfig, WalkingConfig};
use limbfuse_workflows::gait_library::gait_library_file;
use limbfuse_workflows::simulated_trials::{self, SimulatedTrial};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::columns::OwnedColumns;
use crate::options::Options;
use crate::trial::{trial_tuple, TrialArgs, TrialTuple};
use crate::{chain_message, guarded, user_error, user_msg};

/// The most samples `simulate` makes in memory (24 h at 1 kHz, the CLI's
/// cap on a simulated trial).
const MAX_SAMPLES: f64 = 86_400_000.0;

fn rate_and_duration(
    o: &mut Options<'_>,
    rate_key: &'static str,
    d: (f64, f64),
) -> PyResult<(f64, f64)> {
    let duration = o.f64("duration")?.unwrap_or(d.0);
    let rate = o.f64(rate_key)?.unwrap_or(d.1);
    if duration <= 0.0 {
        return Err(user_msg(format!(
            "simulate: option `duration`: expected a positive number of seconds, found {duration}"
        )));
    }
    if rate <= 0.0 {
        return Err(user_msg(format!(
            "simulate: option `{rate_key}`: expected a positive number of Hz, found {rate}"
        )));
    }
    if duration * rate > MAX_SAMPLES {
        return Err(user_msg(format!(
            "simulate: {duration} s at {rate} Hz is {:.3e} samples, more than the cap of {MAX_SAMPLES:.3e}",
            duration * rate
        )));
    }
    Ok((duration, rate))
}

fn mounting(o: &mut Options<'_>) -> PyResult<Option<Mounting>> {
    match o.string("mounting")?.as_deref() {
        None => Ok(None),
        Some("aligned") => Ok(Some(Mounting::Aligned)),
        Some("random") => Ok(Some(Mounting::Random)),
        Some(other) => Err(user_msg(format!(
            "simulate: option `mounting`: expected \"aligned\" or \"random\", found \"{other}\""
        ))),
    }
}

fn collect<R: IntoIterator<Item = Record>>(
    tr: SimulatedTrial<R>,
) -> (limbfuse_io::TrialMeta, OwnedColumns) {
    let (mut cols, channels) = OwnedColumns::new(&tr.layout, 1024);
    for r in tr.records {
        cols.push(&channels, &r);
    }
    (tr.meta, cols)
}

/// Simulates a trial: `kind` is `walking`, `knee`, `knee-fes` or
/// `fixed-hip` (the `limbfuse simulate` subcommands), with their options.
/// The seed `limbfuse simulate` uses without `--seed` (the Python defaults
/// are the CLI's; an audit found walking, knee and calibration at 0).
const CLI_DEFAULT_SEED: u64 = 1;

#[pyfunction]
#[pyo3(signature = (kind, options=None))]
fn simulate<'py>(
    py: Python<'py>,
    kind: &str,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<TrialTuple<'py>> {
    guarded(|| {
        let mut o = Options::new("simulate", options);
        let (meta, cols) = match kind {
            "walking" | "knee" => {
                let d = WalkingConfig::default();
                let (duration, rate) =
                    rate_and_duration(&mut o, "imu_rate", (d.duration_s, d.imu_rate_hz))?;
                let walking = WalkingConfig {
                    speed_mps: o.f64("speed")?.unwrap_or(d.speed_mps),
                    duration_s: duration,
                    imu_rate_hz: rate,
                    seed: o.u64("seed")?.unwrap_or(CLI_DEFAULT_SEED),
                    noise: o.bool("noise")?.unwrap_or(d.noise),
                    out_of_plane: o.bool("out_of_plane")?.unwrap_or(d.out_of_plane),
                    ..d
                };
                if kind == "walking" {
                    let walking = WalkingConfig {
                        mounting: mounting(&mut o)?.unwrap_or(d.mounting),
                        variability: if o.bool("variability")?.unwrap_or(true) {
                            d.variability
                        } else {
                            None
                        },
                        ..walking
                    };
                    let gait_reference = o.bool("gait_reference")?.unwrap_or(false);
                    o.finish()?;
                    let tr = py.detach(|| {
                        simulated_trials::walking(walking).map(|t| match gait_reference {
                            true => collect(simulated_trials::with_gait_reference(t)),
                            false => collect(t),
                        })
                    });
                    tr.map_err(|e| user_error(&e))?
                } else {
                    o.finish()?;
                    let sc = KneeScenario {
                        walking,
                        ..KneeScenario::default()
                    };
                    let tr = py.detach(|| simulated_trials::knee(sc).map(collect));
                    tr.map_err(|e| user_error(&e))?
                }
            }
            "knee-fes" => {
                let d = KneeFesConfig::default();
                let (duration, rate) =
                    rate_and_duration(&mut o, "rate", (d.duration_s, d.rate_hz))?;
                let subject = match o.string("subject")? {
                    None => d.subject,
                    Some(s) => KneeSubject::parse(&s).ok_or_else(|| {
                        user_msg(format!("simulate knee-fes: option `subject`: unknown leg `{s}`; use P1-L, P1-R, P2-L, P2-R, P3-L, P3-R or 1-6"))
                    })?,
                };
                let cfg = KneeFesConfig {
                    subject,
                    duration_s: duration,
                    rate_hz: rate,
                    seed: o.u64("seed")?.unwrap_or(d.seed),
                    noise: o.bool("noise")?.unwrap_or(d.noise),
                    mounting: mounting(&mut o)?.unwrap_or(d.mounting),
                    ..d
                };
                o.finish()?;
                let tr = py.detach(|| {
                    simulated_trials::knee_fes(&cfg, "limbfuse simulate knee-fes").map(collect)
                });
                tr.map_err(|e| user_error(&e))? // (its message names the simulator)
            }
            "fixed-hip" => {
                let d = FixedHipConfig::default();
                let (duration, rate) =
                    rate_and_duration(&mut o, "rate", (d.duration_s, d.rate_hz))?;
                let cfg = FixedHipConfig {
                    duration_s: duration,
                    rate_hz: rate,
                    seed: o.u64("seed")?.unwrap_or(d.seed),
                    noise: o.bool("noise")?.unwrap_or(d.noise),
                    ..d
                };
                o.finish()?;
                let tr = py.detach(|| simulated_trials::fixed_hip(&cfg).map(collect));
                tr.map_err(|e| user_error(&e))? // (its message names the simulator)
            }
            "calibration" => {
                // `limbfuse simulate calibration`: the sensors of `simulate
                // walking --seed N` held still in poses on a board.
                let d = PoseRecordingConfig::default();
                let rate = o.f64("imu_rate")?.unwrap_or(d.sensors.imu_rate_hz);
                if !(rate.is_finite() && rate > 0.0) {
                    return Err(user_msg(format!(
                        "simulate calibration: option `imu_rate`: expected a positive number of Hz, found {rate}"
                    )));
                }
                let cfg = PoseRecordingConfig {
                    sensors: WalkingConfig {
                        seed: o.u64("seed")?.unwrap_or(CLI_DEFAULT_SEED),
                        imu_rate_hz: rate,
                        noise: o.bool("noise")?.unwrap_or(d.sensors.noise),
                        ..d.sensors
                    },
                    poses: o.u64("poses")?.map_or(d.poses, |v| v as usize),
                    hold_s: o.f64("hold")?.unwrap_or(d.hold_s),
                    transition_s: o.f64("transition")?.unwrap_or(d.transition_s),
                    ..d
                };
                o.finish()?;
                if cfg.duration_s() * rate > MAX_SAMPLES {
                    return Err(user_msg(format!(
                        "simulate calibration: {:.0} s at {rate} Hz is more than the cap of {MAX_SAMPLES:.3e} samples",
                        cfg.duration_s()
                    )));
                }
                let tr = py.detach(|| simulated_trials::calibration_poses(cfg).map(collect));
                tr.map_err(|e| user_error(&e))? // (its message names the simulator)
            }
            other => {
                return Err(user_msg(format!(
                "simulate: unknown kind `{other}` (expected walking, knee, knee-fes, fixed-hip or calibration)"
            )))
            }
        };
        Ok(trial_tuple(py, &meta, cols, None))
    })
}

/// Sensor-to-segment alignment from walking data (`limbfuse align`):
/// returns the aligned trial, its metadata annotated with the rotations.
#[pyfunction]
#[pyo3(signature = (trial, options=None))]
fn align<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<TrialTuple<'py>> {
    guarded(|| {
        let mut o = Options::new("align", options);
        let mut opts = AlignOptions {
            hinge: o.bool("hinge")?.unwrap_or(false),
            partial: o.bool("partial")?.unwrap_or(false),
            ..AlignOptions::default()
        };
        if let Some(m) = o.any("mean_angle")? {
            let d = m.downcast::<PyDict>().map_err(|_| {
                user_msg("align: option `mean_angle`: expected a dict {segment: degrees}, e.g. {\"thigh\": 7}")
            })?;
            for (k, v) in d.iter() {
                let seg: String = k.extract()?;
                let s = Segment::ALL.into_iter().find(|s| s.name() == seg).ok_or_else(|| {
                    user_msg(format!("align: option `mean_angle`: unknown segment `{seg}` (expected trunk, thigh, shank or foot)"))
                })?;
                let deg: f64 = v
                    .extract()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| {
                        user_msg(format!(
                            "align: option `mean_angle`: expected a number of degrees for `{seg}`"
                        ))
                    })?;
                opts.mean_angle_rad[s.index()] = deg.to_radians();
            }
        }
        o.finish()?;
        let cols = trial.columns()?;
        let layout = *cols.layout();
        let label = trial.label();
        if !layout.gyr.iter().any(|&g| g) {
            return Err(user_msg(format!(
                "{label}: the trial has no gyroscope channels (`<segment>_gyr_x` ...), which alignment needs"
            )));
        }
        let mut meta = trial.meta();
        let records: Vec<Record> = cols.records().collect();
        let (meta, out) = py
            .detach(|| {
                let alignment = estimate_alignment(&records, &opts)?;
                alignment.annotate(&mut meta);
                let aligned: Vec<Record> = records
                    .iter()
                    .map(|r| apply_alignment(r, &alignment))
                    .collect();
                Ok::<_, limbfuse_signal::align::AlignError>((
                    meta,
                    OwnedColumns::of_records(&layout, &aligned),
                ))
            })
            .map_err(|e| user_msg(format!("aligning {label}: {}", chain_message(&e))))?;
        Ok(trial_tuple(py, &meta, out, None))
    })
}

/// The calibration of every IMU of a pose recording (`limbfuse calibrate`):
/// the calibration file's text (TOML, as `limbfuse calibrate -o` writes it)
/// and one summary dict per calibrated sensor.
#[pyfunction]
#[pyo3(signature = (trial, options=None))]
fn calibrate<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<(String, Vec<Bound<'py, PyDict>>)> {
    guarded(|| {
        let mut o = Options::new("calibrate", options);
        let d = CalibrationParams::default();
        let model = match o.string("model")?.as_deref() {
            None | Some("full") => CalibrationModel::Full,
            Some("scale") => CalibrationModel::Scale,
            Some("bias") => CalibrationModel::Bias,
            Some(other) => {
                return Err(user_msg(format!(
                    "calibrate: option `model`: expected \"full\", \"scale\" or \"bias\", found \"{other}\""
                )))
            }
        };
        let meta = trial.meta();
        let params = CalibrationParams {
            model,
            gravity: match o.f64("gravity")? {
                Some(g) => g,
                None => meta.gravity().map_err(user_msg)?,
            },
            acc_std_max: o.f64("acc_std_max")?.unwrap_or(d.acc_std_max),
            gyro_std_max: o.f64("gyro_std_max")?.unwrap_or(d.gyro_std_max),
            min_pose_s: o.f64("min_pose")?.unwrap_or(d.min_pose_s),
            ..d
        };
        o.finish()?;
        let label = trial.label();
        let records: Vec<Record> = trial.columns()?.records().collect();
        let mut cal = py
            .detach(|| limbfuse_signal::calibration::calibrate(&records, &params))
            .map_err(|e| user_msg(format!("calibrating from {label}: {}", chain_message(&e))))?;
        cal.source = trial.source().map(|(name, _)| name.clone());
        let g = params.gravity;
        let mut sensors = Vec::new();
        for (seg, c) in Segment::ALL.iter().zip(&cal.sensors) {
            let Some(c) = c else { continue };
            let dict = PyDict::new(py);
            dict.set_item("segment", seg.name())?;
            let b = c.acc_bias * (1000.0 / g);
            dict.set_item("acc_bias_mg", [b.x, b.y, b.z])?;
            let scale = [
                c.acc_matrix[(0, 0)],
                c.acc_matrix[(1, 1)],
                c.acc_matrix[(2, 2)],
            ];
            dict.set_item("acc_scale", scale)?;
            dict.set_item("gyro_bias_rad_s", c.gyro_bias.map(|b| [b.x, b.y, b.z]))?;
            if let Some(f) = &c.fit {
                dict.set_item("poses", f.poses)?;
                dict.set_item("residual_mg", f.residual_rms * 1000.0 / g)?;
                dict.set_item("rejected", f.rejected.clone())?;
            }
            sensors.push(dict);
        }
        Ok((cal.to_toml(), sensors))
    })
}

/// Builds a B-SLIP gait library (`limbfuse gait-library build`) and writes
/// it to `path`; returns one summary dict per gait.
#[pyfunction]
#[pyo3(signature = (path, speeds, mass=80.0, leg_length=1.0))]
fn gait_library<'py>(
    py: Python<'py>,
    path: PathBuf,
    speeds: Vec<f64>,
    mass: f64,
    leg_length: f64,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    guarded(|| {
        if speeds.is_empty()
            || speeds
                .iter()
                .any(|s| !(s.is_finite() && *s > 0.0 && *s <= 2.0))
        {
            return Err(user_msg(
                "gait_library: speeds: expected one or more speeds in (0, 2] m/s",
            ));
        }
        // (an audit: a repeated speed was searched for and written, and the
        // library then refused at read)
        let mut sorted = speeds.clone();
        sorted.sort_by(f64::total_cmp);
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(user_msg(format!(
                "gait_library: speeds: {} m/s given twice; each speed once",
                w[0]
            )));
        }
        let max = limbfuse_estimators::imm_bslip::MAX_GAITS;
        if speeds.len() > max {
            return Err(user_msg(format!(
                "gait_library: {} speeds; at most {max} gaits are supported",
                speeds.len()
            )));
        }
        use limbfuse_methods::body_ranges::{leg_length_m, mass_kg};
        // A human's, as the CLI's `gait-library build` checks.
        let mass = mass_kg("gait_library: mass", mass).map_err(user_msg)?;
        let leg_length = leg_length_m("gait_library: leg_length", leg_length).map_err(user_msg)?;
        let body = BslipParams {
            mass,
            rest_length: leg_length,
            ..BslipParams::default()
        };
        let lib = py
            .detach(|| build_library(&body, &speeds, &SearchSettings::default(), |_, _| {}))
            .map_err(|e| user_msg(format!("gait library search: {}", chain_message(&e))))?;
        let file = gait_library_file(&body, &lib);
        file.write(&path).map_err(|e| user_error(&e))?;
        file.gaits
            .iter()
            .map(|g| {
                let d = PyDict::new(py);
                d.set_item("speed", g.speed)?;
                d.set_item("step_length", g.step_length)?;
                d.set_item("step_width", g.step_width)?;
                d.set_item("step_time", g.step_time)?;
                d.set_item("stiffness", g.xi.stiffness)?;
                d.set_item("periodicity_residual", g.periodicity_residual)?;
                Ok(d)
            })
            .collect()
    })
}

/// Writes the HTML report of a trial file and estimate files (`limbfuse
/// report`) to `path`; returns its size in bytes.
#[pyfunction]
#[pyo3(signature = (trial, estimates, path, buckets, allow_trial_mismatch, command))]
fn report(
    py: Python<'_>,
    trial: PathBuf,
    estimates: Vec<PathBuf>,
    path: PathBuf,
    buckets: usize,
    allow_trial_mismatch: bool,
    command: String,
) -> PyResult<usize> {
    guarded(|| {
        if buckets == 0 {
            return Err(user_msg(
                "report: buckets: expected a positive number of display buckets, found 0",
            ));
        }
        // As the CLI: an output naming an input would replace it (an audit:
        // `report("c.csv", ["e.csv"], "c.csv")` wrote the HTML over the trial).
        for input in std::iter::once(&trial).chain(&estimates) {
            if limbfuse_io::file_identity::same_file(input, &path) {
                return Err(user_msg(format!(
                    "report: path {}: that is the input file {}; writing would replace it: give \
                     the report another name",
                    path.display(),
                    input.display()
                )));
            }
        }
        let input = limbfuse_report::ReportInput {
            buckets,
            allow_trial_mismatch,
            ..limbfuse_report::ReportInput::new(&trial, &estimates, command)
        };
        let html = py
            .detach(|| limbfuse_report::render(&input))
            .map_err(|e| user_error(&e))?;
        limbfuse_io::AtomicFile::write(&path, &html)
            .map_err(|e| user_msg(format!("{}: cannot write: {e}", path.display())))?;
        Ok(html.len())
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(align, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(gait_library, m)?)?;
    Ok(())
}
