//! `simulate`: the `limbfuse simulate` subcommands as one function, with
//! their options as keywords (`limbfuse-workflows`' simulated trials).

use std::path::Path;

use limbfuse_core::{Leg, Record};
use limbfuse_models::bslip::BslipParams;
use limbfuse_models::KneeSubject;
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_sim::bslip::trial::{BslipTrialConfig, ComChannels};
use limbfuse_sim::fixed_hip::FixedHipConfig;
use limbfuse_sim::knee_fes::KneeFesConfig;
use limbfuse_sim::{KneeScenario, Mounting, PoseRecordingConfig, Remount, Turns, WalkingConfig};
use limbfuse_workflows::bslip_gait::{bslip_gait, bslip_gait_with, BslipGaitError, GaitSource};
use limbfuse_workflows::simulated_trials::{self, SimulatedTrial};
use limbfuse_workflows::simulator_options;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::columns::OwnedColumns;
use crate::interrupt::detach;
use crate::options::Options;
use crate::trial::{trial_tuple, TrialTuple};
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
        // (Ctrl-C: `detach` raises; the part made is dropped)
        if crate::interrupt::poll_current() {
            break;
        }
    }
    (tr.meta, cols)
}

/// `simulate knee-fes --calibration PATH`: the calibration recording (quiet
/// standing + 4 hip rotations) of the same sensors, written to `path` (the
/// CLI's bytes; an audit: Python had no way to make it).
fn write_knee_fes_calibration(cfg: &KneeFesConfig, path: &Path) -> PyResult<()> {
    use std::io::Write;
    let rec = simulated_trials::knee_fes_calibration(cfg).map_err(|e| user_error(&e))?;
    let io = |e: std::io::Error| {
        user_msg(format!(
            "simulate knee-fes: option `calibration`: {}: {e}",
            path.display()
        ))
    };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
    simulated_trials::write_trial(&mut out, rec, path).map_err(|e| user_error(&e))?;
    out.flush().map_err(io)
}

/// An out-of-range option, named as the Python keyword.
fn option_error(scenario: &'static str, option: simulator_options::OptionOutOfRange) -> PyErr {
    user_error(&simulated_trials::SimulatedTrialError::Option { scenario, option })
}

/// `gyro_drift` (deg/s) of `knee-fes` / `fixed-hip`, in rad/s.
fn gyro_drift(o: &mut Options<'_>, scenario: &'static str) -> PyResult<Option<f64>> {
    o.f64("gyro_drift")?
        .map(|deg_s| {
            simulator_options::gyro_drift_rad_s(deg_s).map_err(|e| option_error(scenario, e))
        })
        .transpose()
}

/// The options only `simulate("walking")` has (`limbfuse simulate walking`'s
/// flags): mounting, variability, leg, turns, misalignment.
fn walking_options(o: &mut Options<'_>, w: WalkingConfig) -> PyResult<WalkingConfig> {
    let d = WalkingConfig::default();
    let leg = match o.string("leg")?.as_deref() {
        None => d.leg,
        Some("right") => Leg::Right,
        Some("left") => Leg::Left,
        Some(other) => {
            return Err(user_msg(format!(
                "simulate: option `leg`: expected \"right\" or \"left\", found \"{other}\""
            )))
        }
    };
    let (every, deg, dur) = (o.f64("turn_every")?, o.f64("turn_deg")?, o.f64("turn_s")?);
    if every.is_none() && (deg.is_some() || dur.is_some()) {
        return Err(user_msg(
            "simulate: options `turn_deg` and `turn_s` describe the turns of `turn_every` \
             (seconds between turn starts): give it too",
        ));
    }
    let mut imu = w.imu;
    if !o.bool("misalignment")?.unwrap_or(true) {
        imu.misalignment_rad = 0.0;
    }
    Ok(WalkingConfig {
        imu,
        mounting: mounting(o)?.unwrap_or(d.mounting),
        variability: if o.bool("variability")?.unwrap_or(true) {
            d.variability
        } else {
            None
        },
        leg,
        turns: every.map(|every_s| Turns {
            every_s,
            duration_s: dur.unwrap_or(simulator_options::DEFAULT_TURN_S),
            angle_rad: deg
                .unwrap_or(simulator_options::DEFAULT_TURN_DEG)
                .to_radians(),
        }),
        ..w
    })
}

/// The options only `simulate("knee")` has (`limbfuse simulate knee`'s
/// flags): the sensors' position spread and a thigh-sensor re-mounting.
fn knee_options(o: &mut Options<'_>, walking: WalkingConfig) -> PyResult<KneeScenario> {
    let d = KneeScenario::default();
    let remount_at = o.f64("remount_at")?;
    let remount_deg = o.f64("remount_deg")?;
    // (as the CLI: a re-mounting outside the trial would be reported but
    // never happen)
    if let Some(t) = remount_at.filter(|t| !(*t > 0.0 && *t < walking.duration_s)) {
        return Err(user_msg(format!(
            "simulate knee: option `remount_at` = {}: expected a time within the trial, after 0 \
             and before `duration` {} s",
            limbfuse_methods::shown(t),
            walking.duration_s
        )));
    }
    if remount_at.is_none() && remount_deg.is_some() {
        return Err(user_msg(
            "simulate knee: option `remount_deg` is the re-mounting of `remount_at` (s): give it too",
        ));
    }
    Ok(KneeScenario {
        walking,
        ap_offset_sd_m: o
            .f64("ap_offset_sd_cm")?
            .map_or(d.ap_offset_sd_m, |cm| cm / 100.0),
        remount: remount_at.map(|t_s| Remount {
            t_s,
            angle_rad: remount_deg
                .unwrap_or(simulator_options::DEFAULT_REMOUNT_DEG)
                .to_radians(),
        }),
        ..d
    })
}

/// The seed `limbfuse simulate` uses without `--seed` (the Python defaults
/// are the CLI's; an audit found walking, knee and calibration at 0).
const CLI_DEFAULT_SEED: u64 = 1;

/// Simulates a trial in memory: `kind` is `walking`, `knee`, `knee-fes`,
/// `fixed-hip`, `bslip` or `calibration` (the `limbfuse simulate`
/// subcommands), with their options.
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
                    let walking = walking_options(&mut o, walking)?;
                    let gait_reference = o.bool("gait_reference")?.unwrap_or(false);
                    o.finish()?;
                    let tr = detach(py, || {
                        simulated_trials::walking(walking).map(|t| match gait_reference {
                            true => collect(simulated_trials::with_gait_reference(t)),
                            false => collect(t),
                        })
                    })?;
                    tr.map_err(|e| user_error(&e))?
                } else {
                    let sc = knee_options(&mut o, walking)?;
                    o.finish()?;
                    let tr = detach(py, || simulated_trials::knee(sc).map(collect))?;
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
                    gyro_drift: gyro_drift(&mut o, "knee-fes")?.unwrap_or(d.gyro_drift),
                    activation_dynamics: o
                        .bool("activation_dynamics")?
                        .unwrap_or(d.activation_dynamics),
                    cycles: match o.u64("cycles")? {
                        None => d.cycles,
                        // (beyond u32: the simulator's own range check names it)
                        Some(n) => u32::try_from(n).map_err(|_| {
                            option_error(
                                "knee-fes",
                                simulator_options::OptionOutOfRange {
                                    option: "cycles",
                                    value: n as f64,
                                    range: "[0, 600] (6 s each)",
                                },
                            )
                        })?,
                    },
                    ..d
                };
                let calibration = o.string("calibration")?;
                o.finish()?;
                let tr = detach(py, || {
                    simulated_trials::knee_fes(&cfg, "limbfuse simulate knee-fes").map(collect)
                })?;
                let tr = tr.map_err(|e| user_error(&e))?; // (its message names the simulator)
                if let Some(note) = simulated_trials::knee_fes_rest_note(&cfg, "option `cycles`") {
                    crate::filter::warn_user(py, note)?;
                }
                if let Some(path) = calibration {
                    detach(py, || write_knee_fes_calibration(&cfg, Path::new(&path)))??;
                }
                tr
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
                    gyro_drift: gyro_drift(&mut o, "fixed-hip")?.unwrap_or(d.gyro_drift),
                    activation_t_a: match o.f64("activation_t_a")? {
                        None => d.activation_t_a,
                        Some(t) => Some(
                            simulator_options::activation_t_a_s(t)
                                .map_err(|e| option_error("fixed-hip", e))?,
                        ),
                    },
                    ..d
                };
                o.finish()?;
                let tr = detach(py, || simulated_trials::fixed_hip(&cfg).map(collect))?;
                tr.map_err(|e| user_error(&e))? // (its message names the simulator)
            }
            "bslip" => {
                // `limbfuse simulate bslip` (paper 003): a gait of `library`
                // at `speed`, or one searched now for the body.
                let d = BslipTrialConfig::default();
                let (duration, rate) =
                    rate_and_duration(&mut o, "rate", (d.duration, d.sample_rate))?;
                let speed = o.f64("speed")?.unwrap_or(0.7);
                let library = o.string("library")?;
                let mass = o.f64("mass")?;
                let leg_length = o.f64("leg_length")?;
                let cfg = BslipTrialConfig {
                    duration,
                    sample_rate: rate,
                    channels: match o.bool("position_only")?.unwrap_or(false) {
                        true => ComChannels::Position,
                        false => ComChannels::Full,
                    },
                    seed: o.u64("seed")?.unwrap_or(d.seed),
                    ..d
                };
                o.finish()?;
                let body = match (&library, mass, leg_length) {
                    (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                        return Err(user_msg(
                            "simulate bslip: options `mass` and `leg_length` describe the body of a \
                             searched gait; the gait of `library` has its own body: give one or the other",
                        ))
                    }
                    _ => {
                        use limbfuse_methods::body_ranges::{leg_length_m, mass_kg};
                        let b = BslipParams::default();
                        BslipParams {
                            mass: mass_kg("simulate bslip: option `mass`", mass.unwrap_or(b.mass))
                                .map_err(user_msg)?,
                            rest_length: leg_length_m(
                                "simulate bslip: option `leg_length`",
                                leg_length.unwrap_or(b.rest_length),
                            )
                            .map_err(user_msg)?,
                            ..b
                        }
                    }
                };
                // (the search: seconds; Ctrl-C stops it, `SearchSettings::cancel`)
                let search = SearchSettings {
                    cancel: Some(crate::interrupt::cancelled),
                    ..SearchSettings::default()
                };
                let template = detach(py, || match &library {
                    Some(p) => bslip_gait(speed, GaitSource::Library(Path::new(p))),
                    None => bslip_gait_with(speed, GaitSource::Search(&body), &search),
                })?
                .map_err(|e| match e {
                        BslipGaitError::Speed(_) => {
                            user_msg(format!("simulate bslip: option `speed`: {e}"))
                        }
                        e => user_msg(format!("simulate bslip: {}", chain_message(&e))),
                    })?;
                detach(py, || {
                    collect(simulated_trials::bslip(
                        &template,
                        &cfg,
                        "limbfuse simulate bslip",
                    ))
                })?
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
                    lever_arm_m: o.f64("lever_arm")?.unwrap_or(d.lever_arm_m),
                    wobble_pose: match o.u64("wobble_pose")? {
                        None => d.wobble_pose,
                        Some(0) => {
                            return Err(user_msg(
                                "simulate calibration: option `wobble_pose`: poses are numbered from 1, found 0",
                            ))
                        }
                        Some(k) => Some(k as usize - 1),
                    },
                };
                if let Some(k) = cfg.wobble_pose.filter(|k| *k >= cfg.poses) {
                    return Err(user_msg(format!(
                        "simulate calibration: option `wobble_pose` = {}: expected a pose from 1 to {} \
                         (`poses`; numbered from 1)",
                        k + 1,
                        cfg.poses
                    )));
                }
                o.finish()?;
                if cfg.duration_s() * rate > MAX_SAMPLES {
                    return Err(user_msg(format!(
                        "simulate calibration: {:.0} s at {rate} Hz is more than the cap of {MAX_SAMPLES:.3e} samples",
                        cfg.duration_s()
                    )));
                }
                let tr = detach(py, || simulated_trials::calibration_poses(cfg).map(collect))?;
                tr.map_err(|e| user_error(&e))? // (its message names the simulator)
            }
            other => {
                return Err(user_msg(format!(
                "simulate: unknown kind `{other}` (expected walking, knee, knee-fes, fixed-hip, bslip or calibration)"
            )))
            }
        };
        Ok(trial_tuple(py, &meta, cols, None))
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    Ok(())
}
