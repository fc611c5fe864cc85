//! Simulated trials as files: each simulator's records with the metadata
//! and columns its trial file carries (SPEC section 3), in one place for
//! the CLI, the demo and the Python package.

use std::io::Write;
use std::path::{Path, PathBuf};

use limbfuse_core::Record;
use limbfuse_core::Side;
use limbfuse_io::{TrialLayout, TrialMeta, TrialWriter};
use limbfuse_models::bslip::GaitTemplate;
use limbfuse_sim::bslip::trial::{trial_records, BslipTrialConfig, ComChannels};
use limbfuse_sim::fixed_hip::{fixed_hip_stream, FixedHipConfig};
use limbfuse_sim::gait_truth::GaitTruth;
use limbfuse_sim::knee_fes::{knee_fes_stream, simulate_calibration, FesTrial, KneeFesConfig};
use limbfuse_sim::{
    KneeScenario, KneeSimulator, PoseRecording, PoseRecordingConfig, WalkingConfig,
    WalkingSimulator,
};

/// A simulated trial: metadata, columns and the records (a stream for the
/// walking simulators, which never hold a trial in memory).
#[derive(Debug, Clone)]
pub struct SimulatedTrial<R> {
    /// The `# key: value` header.
    pub meta: TrialMeta,
    /// The columns written.
    pub layout: TrialLayout,
    /// The records.
    pub records: R,
}

/// Why a simulated trial could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum SimulatedTrialError {
    /// The simulator rejected its configuration or failed.
    #[error("simulate {scenario}: {message}")]
    Simulator {
        /// Which simulator.
        scenario: &'static str,
        /// Why.
        message: String,
    },
    /// A setting of `simulate walking`, `knee` or `calibration` out of range,
    /// named as the option (`crate::simulator_options`).
    #[error("simulate {scenario}: option `{}` = {}: outside the allowed range {}", option.option, limbfuse_methods::shown(option.value), option.range)]
    Option {
        /// Which simulator.
        scenario: &'static str,
        /// The option.
        option: crate::simulator_options::OptionOutOfRange,
    },
    /// The output file.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// File path.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
}

/// A simulator's configuration error, as the option when it is one
/// ([`SimulatedTrialError::Option`]).
pub fn config_error(scenario: &'static str, e: limbfuse_sim::SimError) -> SimulatedTrialError {
    match crate::simulator_options::OptionOutOfRange::of(&e) {
        Some(option) => SimulatedTrialError::Option { scenario, option },
        None => sim_err(scenario)(&e),
    }
}

fn config_err(scenario: &'static str) -> impl Fn(limbfuse_sim::SimError) -> SimulatedTrialError {
    move |e| config_error(scenario, e)
}

/// An FES simulator's error, a setting the user gave named as its option.
fn fes_err(
    scenario: &'static str,
) -> impl Fn(limbfuse_sim::fes_error::FesSimError) -> SimulatedTrialError {
    move |e| match crate::simulator_options::OptionOutOfRange::of_fes(&e) {
        Some(option) => SimulatedTrialError::Option { scenario, option },
        None => sim_err(scenario)(&e),
    }
}

fn sim_err(scenario: &'static str) -> impl Fn(&dyn std::fmt::Display) -> SimulatedTrialError {
    move |e| SimulatedTrialError::Simulator {
        scenario,
        message: e.to_string(),
    }
}

/// The header every simulated trial starts with.
fn meta(source: &str, rate_hz: f64) -> TrialMeta {
    let mut meta = TrialMeta::trial_v1();
    meta.set("source", source);
    meta.set("sample_rate_hz", rate_hz);
    meta
}

/// Level walking (`simulate walking`, `demo`).
pub fn walking(
    cfg: WalkingConfig,
) -> Result<SimulatedTrial<WalkingSimulator>, SimulatedTrialError> {
    let sim = WalkingSimulator::new(cfg).map_err(config_err("walking"))?;
    let mut m = meta("limbfuse simulate walking", cfg.imu_rate_hz);
    m.set("leg", "right");
    m.set("g", cfg.g);
    for (k, v) in sim.metadata() {
        m.set(k, v);
    }
    Ok(SimulatedTrial {
        meta: m,
        layout: TrialLayout::walking(),
        records: sim,
    })
}

/// The walking trial with its gait truth (`simulate walking
/// --gait-reference`): both legs' `contact_*_ref` (the other leg's half a
/// stride later) and `speed_ref` per stride ([`limbfuse_sim::gait_truth`]).
pub fn with_gait_reference(
    trial: SimulatedTrial<WalkingSimulator>,
) -> SimulatedTrial<Box<dyn Iterator<Item = Record>>> {
    let mut truth = GaitTruth::new(trial.records.clone());
    let side = match trial.meta.get("leg") {
        Some("left") => Side::Left,
        _ => Side::Right,
    };
    let mut layout = trial.layout;
    layout.contact_ref = [true; 2];
    layout.speed_ref = true;
    let records = trial.records.map(move |mut r| {
        let ([own, other], speed) = truth.at(r.sample.t);
        r.reference.contact[side.index()] = Some(own);
        r.reference.contact[side.other().index()] = Some(other);
        r.reference.speed = Some(speed);
        r
    });
    SimulatedTrial {
        meta: trial.meta,
        layout,
        records: Box::new(records),
    }
}

/// A calibration recording of the walking simulator's sensors (`simulate
/// calibration`): raw sensor channels of the four IMUs, no reference.
pub fn calibration_poses(
    cfg: PoseRecordingConfig,
) -> Result<SimulatedTrial<PoseRecording>, SimulatedTrialError> {
    let rec = PoseRecording::new(cfg).map_err(config_err("calibration"))?;
    let mut m = meta("limbfuse simulate calibration", cfg.sensors.imu_rate_hz);
    for (k, v) in rec.metadata() {
        m.set(k, v);
    }
    Ok(SimulatedTrial {
        meta: m,
        layout: TrialLayout {
            acc: [true; 4],
            gyr: [true; 4],
            ..TrialLayout::default()
        },
        records: rec,
    })
}

/// The paper-002 knee scenario (`simulate knee`).
pub fn knee(sc: KneeScenario) -> Result<SimulatedTrial<KneeSimulator>, SimulatedTrialError> {
    let sim = KneeSimulator::new(sc).map_err(config_err("knee"))?;
    let mut m = meta("limbfuse simulate knee", sc.walking.imu_rate_hz);
    m.set("leg", "right");
    m.set("g", sc.walking.g);
    for (k, v) in sim.metadata() {
        m.set(k, v);
    }
    Ok(SimulatedTrial {
        meta: m,
        layout: TrialLayout::walking(),
        records: sim,
    })
}

/// Columns the FES simulators write (`hip`: the fixed-hip model).
pub fn fes_layout(hip: bool) -> TrialLayout {
    let mut l = TrialLayout::default();
    for i in [1, 2] {
        l.acc[i] = true;
        l.gyr[i] = true;
        l.segment_ref[i] = true;
    }
    l.encoder[1] = true;
    l.joint_ref[1] = true;
    l.stim[0] = true;
    if hip {
        l.encoder[0] = true;
        l.joint_ref[0] = true;
        l.segment_ref[0] = true;
        l.stim = [true; 4];
        l.motor_torque = [true, true, false];
    }
    l
}

fn fes_trial<R>(source: &str, rate: f64, tr: FesTrial<R>, hip: bool) -> SimulatedTrial<R> {
    let mut m = meta(source, rate);
    m.set("leg", "right");
    for (k, v) in &tr.metadata {
        m.set(k.clone(), v);
    }
    if let Some(g) = tr.metadata.iter().find(|(k, _)| k == "param.g") {
        m.set("g", &g.1);
    }
    SimulatedTrial {
        meta: m,
        layout: fes_layout(hip),
        records: tr.records,
    }
}

/// FES leg extension, paper 004 (`simulate knee-fes`); `source` names the
/// producer in the header.
pub fn knee_fes(
    cfg: &KneeFesConfig,
    source: &str,
) -> Result<SimulatedTrial<impl Iterator<Item = Record>>, SimulatedTrialError> {
    let tr = knee_fes_stream(cfg).map_err(fes_err("knee-fes"))?;
    Ok(fes_trial(source, cfg.rate_hz, tr, false))
}

/// What a knee-FES trial much longer than its extension cycles should say:
/// the leg rests after the last cycle (`None` when the cycles fill the
/// trial to within one cycle, or none were asked for); `option` is how the
/// caller spells the setting (`--cycles`, `cycles`).
pub fn knee_fes_rest_note(cfg: &KneeFesConfig, option: &str) -> Option<String> {
    let end = cfg.cycles_end_s();
    let resting = cfg.duration_s - end;
    (cfg.cycles > 0 && resting >= limbfuse_sim::knee_fes::CYCLE_S).then(|| {
        format!(
            "the {} extension cycles end at {} s; the leg rests for the last {} s ({option}: more \
             extensions, 6 s each)",
            cfg.cycles,
            limbfuse_methods::shown(end),
            limbfuse_methods::shown(resting)
        )
    })
}

/// The calibration recording (quiet standing + 4 hip rotations) of the
/// knee-FES trial's sensors (`simulate knee-fes --calibration`).
pub fn knee_fes_calibration(
    cfg: &KneeFesConfig,
) -> Result<SimulatedTrial<Vec<Record>>, SimulatedTrialError> {
    let tr = simulate_calibration(cfg).map_err(fes_err("calibration"))?;
    let mut m = TrialMeta::trial_v1();
    m.set("sample_rate_hz", cfg.rate_hz);
    for (k, v) in &tr.metadata {
        m.set(k.clone(), v);
    }
    let mut layout = fes_layout(false);
    layout.encoder = [false; 3];
    layout.stim = [false; 4];
    Ok(SimulatedTrial {
        meta: m,
        layout,
        records: tr.records,
    })
}

/// Fixed-hip swing, paper 004 (`simulate fixed-hip`).
pub fn fixed_hip(
    cfg: &FixedHipConfig,
) -> Result<SimulatedTrial<impl Iterator<Item = Record>>, SimulatedTrialError> {
    let tr = fixed_hip_stream(cfg).map_err(fes_err("fixed-hip"))?;
    Ok(fes_trial(
        "limbfuse simulate fixed-hip",
        cfg.rate_hz,
        tr,
        true,
    ))
}

/// B-SLIP walking on one gait, paper 003 (`simulate bslip`, `demo`).
pub fn bslip(
    template: &GaitTemplate,
    cfg: &BslipTrialConfig,
    source: &str,
) -> SimulatedTrial<impl Iterator<Item = Record>> {
    let mut m = meta(source, cfg.sample_rate);
    m.set("bslip_speed_mps", template.speed);
    m.set("bslip_step_time_s", template.step_time);
    m.set("seed", cfg.seed);
    let velocity = cfg.channels == ComChannels::Full;
    let mut layout = TrialLayout {
        com_pos: true,
        com_vel: true,
        phase_ref: true,
        ..Default::default()
    };
    layout.com_meas = [true, true, true, velocity, velocity, false];
    SimulatedTrial {
        meta: m,
        layout,
        records: trial_records(template, cfg),
    }
}

/// Writes a trial to `out`; returns the number of records.
pub fn write_trial<W: Write, R: IntoIterator<Item = Record>>(
    out: W,
    trial: SimulatedTrial<R>,
    path: &Path,
) -> Result<u64, SimulatedTrialError> {
    let err = |source| SimulatedTrialError::Write {
        path: path.to_path_buf(),
        source,
    };
    let mut w = TrialWriter::for_path(path, out, &trial.meta, trial.layout).map_err(err)?;
    let mut n = 0;
    for r in trial.records {
        w.write(&r).map_err(err)?;
        n += 1;
    }
    w.finish().map_err(err)?;
    Ok(n)
}
