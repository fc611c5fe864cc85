//! `align`, `calibrate`, `gait_library` and `report`: the CLI's workflows
//! as functions (`limbfuse-workflows`, `limbfuse-signal`, `limbfuse-sim`).

use std::path::PathBuf;

use limbfuse_core::{Record, Segment};
use limbfuse_io::calibration::CalibrationModel;
use limbfuse_io::provenance::{LIMBFUSE_VERSION, VERSION_KEY};
use limbfuse_models::bslip::BslipParams;
use limbfuse_signal::align::{apply_alignment, apply_rotations, AlignOptions};
use limbfuse_signal::calibration::CalibrationParams;
use limbfuse_sim::bslip::library::build_library;
use limbfuse_sim::bslip::search::SearchSettings;
use limbfuse_workflows::gait_library::gait_library_file;
use limbfuse_workflows::trial_alignment::{
    align_static_rotation, align_walking, TrialAlignmentError,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::columns::OwnedColumns;
use crate::estimate::calibration_and_frame;
use crate::interrupt::detach;
use crate::options::Options;
use crate::trial::{trial_tuple, TrialArgs, TrialTuple};
use crate::{chain_message, guarded, user_error, user_msg};

/// Sensor-to-segment alignment (`limbfuse align`): the aligned trial, its
/// metadata annotated with the rotations, and the CLI's warnings (readings
/// left out, a detected leg replacing the declared one).
#[pyfunction]
#[pyo3(signature = (trial, options=None))]
fn align<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<(TrialTuple<'py>, Vec<String>)> {
    guarded(|| {
        let mut o = Options::new("align", options);
        let static_rotation = match o.string("procedure")?.as_deref() {
            None | Some("walking") => false,
            Some("static-rotation") => true,
            Some(other) => {
                return Err(user_msg(format!(
                    "align: option `procedure`: expected \"walking\" or \"static-rotation\", found \"{other}\""
                )))
            }
        };
        let mut opts = AlignOptions {
            hinge: o.bool("hinge")?.unwrap_or(false),
            partial: o.bool("partial")?.unwrap_or(false),
            ..AlignOptions::default()
        };
        if let Some(m) = o.any("mean_angle")? {
            opts.mean_angle_rad = mean_angles(&m)?;
        }
        let imu_calibration = match (
            o.string("imu_calibration")?,
            o.string("imu_calibration_toml")?,
        ) {
            (Some(path), None) => Some((
                std::fs::read_to_string(&path)
                    .map_err(|e| user_msg(format!("imu_calibration: cannot read {path}: {e}")))?,
                path,
            )),
            (None, Some(text)) => Some((text, "<Calibration>".to_string())),
            (None, None) => None,
            (Some(_), Some(_)) => {
                return Err(user_msg(
                    "align: give `imu_calibration` (a file) or `imu_calibration_toml`, not both",
                ))
            }
        };
        let recording = o.any("calibration_trial")?;
        o.finish()?;
        if !static_rotation && recording.is_some() {
            return Err(user_msg(
                "align: `calibration` (the recording of quiet standing and rotations) is for \
                 procedure=\"static-rotation\"",
            ));
        }
        let cols = trial.columns()?;
        let layout = *cols.layout();
        let label = trial.label();
        let mut meta = trial.meta();
        // (Ctrl-C, session 30: an hour took 5 s of CPU, 30 s on a loaded
        // machine, and nothing stopped it; each step below polls it)
        let mut records: Vec<Record> = detach(py, || polled(cols.records()))?;
        let mut said = Vec::new();
        let cal = match &imu_calibration {
            Some((text, name)) => {
                let (cal, frame) = calibration_and_frame(py, text, name, &label, &meta, &layout)?;
                records.iter_mut().for_each(|r| cal.apply(r));
                // (the file's name, as `limbfuse align --imu-calibration` writes it)
                let file = std::path::Path::new(name)
                    .file_name()
                    .map_or(name.clone(), |n| n.to_string_lossy().into_owned());
                cal.annotate(&mut meta, &file, frame);
                Some(cal)
            }
            None => None,
        };
        let out = if static_rotation {
            let (cal_records, cal_name) = match &recording {
                Some(r) => {
                    let r: TrialArgs<'_> = r.extract().map_err(|_| {
                        user_msg("align: `calibration`: expected a limbfuse.Trial (the recording of quiet standing and rotations)")
                    })?;
                    let r_cols = r.columns()?;
                    let mut rec: Vec<Record> = detach(py, || polled(r_cols.records()))?;
                    if let Some(c) = &cal {
                        rec.iter_mut().for_each(|x| c.apply(x));
                    }
                    (rec, r.label())
                }
                None => (records.clone(), label.clone()),
            };
            let al = detach(py, || {
                align_static_rotation(&cal_records, &cal_name, &layout, &mut meta)
            })?
            .map_err(|e| {
                user_msg(format!(
                    "{cal_name}: static-rotation alignment: {}",
                    chain_message(&e)
                ))
            })?;
            detach(py, || {
                let aligned = polled(records.iter().map(|r| apply_rotations(r, &al.rotations)));
                OwnedColumns::of_records(&layout, &aligned)
            })?
        } else {
            opts.cancel = Some(crate::interrupt::cancelled);
            let (w, out) = detach(py, || {
                let w = align_walking(&records, &layout, &mut meta, &opts)?;
                let aligned = polled(records.iter().map(|r| apply_alignment(r, &w.alignment)));
                Ok::<_, TrialAlignmentError>((w, OwnedColumns::of_records(&layout, &aligned)))
            })?
            .map_err(|e| user_msg(format!("aligning {label}: {}", chain_message(&e))))?;
            if let Some((gyro, acc, first_t)) = w.left_out {
                said.push(format!(
                    "{label}: {gyro} gyroscope and {acc} accelerometer readings out of the sensors' \
                     range or implausible (first at t = {first_t} s) left out of the alignment, as \
                     `estimate` leaves them out (the aligned trial keeps them)"
                ));
            }
            if w.leg_replaced {
                said.push(format!("{label}: {}", w.leg_line));
            }
            if let Some(note) = &w.other_leg_raw {
                said.push(format!("{label}: {note}"));
            }
            out
        };
        Ok((trial_tuple(py, &meta, out, None), said))
    })
}

/// The records of `it` until Ctrl-C (in a run of [`detach`], which then
/// raises `KeyboardInterrupt`).
pub(crate) fn polled(it: impl Iterator<Item = Record>) -> Vec<Record> {
    let mut out = Vec::with_capacity(it.size_hint().0);
    for r in it {
        out.push(r);
        if crate::interrupt::poll_current() {
            break;
        }
    }
    out
}

/// `mean_angle={segment: degrees}`.
fn mean_angles(m: &Bound<'_, PyAny>) -> PyResult<[f64; 4]> {
    let d = m.downcast::<PyDict>().map_err(|_| {
        user_msg(
            "align: option `mean_angle`: expected a dict {segment: degrees}, e.g. {\"thigh\": 7}",
        )
    })?;
    let mut out = [0.0; 4];
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
        out[s.index()] = deg.to_radians();
    }
    Ok(out)
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
        // The CLI's provenance lines but `# command:` (docs/OUTPUTS.md
        // section 3): the hash when the recording came from a file.
        let mut provenance = vec![
            (VERSION_KEY, LIMBFUSE_VERSION.to_string()),
            ("fit_settings", params.settings()),
        ];
        if let Some((_, hash)) = trial.source() {
            provenance.push(("source_hash", hash.clone()));
        }
        Ok((cal.to_toml_with_provenance(&provenance), sensors))
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
        // (minutes for many speeds; Ctrl-C stops the search)
        let search = SearchSettings {
            cancel: Some(crate::interrupt::cancelled),
            ..SearchSettings::default()
        };
        let lib = detach(py, || build_library(&body, &speeds, &search, |_, _| {}))?
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
#[pyo3(signature = (trial, estimates, path, buckets, allow_trial_mismatch, command, window=None, offset_free=false, max_lag=0))]
#[allow(clippy::too_many_arguments)]
fn report(
    py: Python<'_>,
    trial: PathBuf,
    estimates: Vec<PathBuf>,
    path: PathBuf,
    buckets: usize,
    allow_trial_mismatch: bool,
    command: String,
    window: Option<&str>,
    offset_free: bool,
    max_lag: usize,
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
        // `evaluate`'s options, parsed and named as Python's `evaluate` does
        let scoring = limbfuse_report::Scoring {
            window: match window {
                Some(w) => limbfuse_eval::TimeWindow::parse(w)
                    .map_err(|m| user_msg(format!("report: window: {m}")))?,
                None => limbfuse_eval::TimeWindow::default(),
            },
            offset_free,
            max_lag,
        };
        let input = limbfuse_report::ReportInput {
            buckets,
            allow_trial_mismatch,
            scoring,
            // (Ctrl-C, session 30: 2 s of CPU per estimate of an hour)
            cancel: Some(crate::interrupt::cancelled),
            ..limbfuse_report::ReportInput::new(&trial, &estimates, command)
        };
        let html = detach(py, || limbfuse_report::render(&input))?.map_err(|e| match &e {
            limbfuse_report::ReportError::ScoringNotApplicable { options, why } => {
                user_msg(format!(
                    "report: {}: {} {}",
                    options
                        .iter()
                        .map(|o| o.keyword())
                        .collect::<Vec<_>>()
                        .join(", "),
                    if options.len() == 1 {
                        "applies"
                    } else {
                        "apply"
                    },
                    why.replace("--window", "window")
                ))
            }
            limbfuse_report::ReportError::Eval(limbfuse_eval::EvalError::MaxLagTooLong {
                ..
            }) => user_msg(format!("report: max_lag {max_lag}: {e}")),
            _ => user_error(&e),
        })?;
        limbfuse_io::AtomicFile::write(&path, &html)
            .map_err(|e| user_msg(format!("{}: cannot write: {e}", path.display())))?;
        Ok(html.len())
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(align, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(gait_library, m)?)?;
    Ok(())
}
