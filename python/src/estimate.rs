//! `estimate` (a method over an in-memory trial, the GIL released),
//! `read_estimate` and `write_estimate` (SPEC section 3 files).

use std::path::Path;

use limbfuse_core::sample::AngleChannel;
use limbfuse_core::{Estimator, OfflineEstimator};
use limbfuse_eval::sample_interval::FIRST_INTERVALS;
use limbfuse_eval::{SampleIntervalWatch, SensorUnitsWatch, SpeedRangeWatch};
use limbfuse_io::content_hash::{TRIAL_HASH_KEY, TRIAL_KEY};
use limbfuse_io::Calibration;
use limbfuse_methods::knee_backfill::build_backfilled;
use limbfuse_methods::smoothed_chain::build_smoothed;
use limbfuse_methods::MethodSpec;
use limbfuse_signal::calibration::trial_calibration::for_trial;
use limbfuse_workflows::imm_library_extension;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::column_run::{run_columns, run_columns_offline, RunWatches};
use crate::estimate_columns::{EstimateColumns, EstimateView, PHASE};
use crate::interrupt::Interrupt;
use crate::options::python_spelling;
use crate::trial::{slice, TrialArgs};
use crate::{chain_message, guarded, user_error, user_msg};

/// What the Python `Estimate._native()` returns: header lines, `t`, numeric
/// column names and arrays, `phase` cells.
#[derive(FromPyObject)]
pub struct EstimateArgs<'py>(
    pub Vec<String>,
    pub PyReadonlyArray1<'py, f64>,
    pub Vec<String>,
    pub Vec<PyReadonlyArray1<'py, f64>>,
    pub Option<Vec<Option<String>>>,
);

impl<'py> EstimateArgs<'py> {
    /// The columns, checked.
    pub fn view(&self) -> PyResult<EstimateView<'_>> {
        if self.2.len() != self.3.len() {
            return Err(user_msg(
                "estimate: as many column names as arrays are needed",
            ));
        }
        let t = slice(&self.1, "t")?;
        let mut named = Vec::with_capacity(self.2.len());
        for (n, a) in self.2.iter().zip(&self.3) {
            named.push((n.clone(), slice(a, n)?));
        }
        EstimateView::new(t, named, self.4.clone()).map_err(user_msg)
    }

    /// The header entry `key`, if present.
    pub fn header(&self, key: &str) -> Option<&str> {
        self.0.iter().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            (k.trim() == key).then(|| v.trim())
        })
    }
}

/// The tuple the Python layer builds an `Estimate` from: header lines,
/// file column order, `t`, numeric names and arrays, `phase` cells, a
/// restart warning (issue 16) when the estimator restarted, and whether
/// each numeric array holds a NaN (`None`: not known, the Python layer
/// looks), and the run's summary line (`Estimate.summary`: what `limbfuse
/// estimate` prints of a knee-axis method's identification; `None` for
/// other methods and for a file read back).
pub type EstimateTuple<'py> = (
    Vec<String>,
    Vec<String>,
    Bound<'py, PyArray1<f64>>,
    Vec<String>,
    Vec<Bound<'py, PyArray1<f64>>>,
    Option<Vec<Option<&'static str>>>,
    Option<String>,
    Option<Vec<bool>>,
    Option<String>,
);

pub(crate) fn file_order(names: &[String], has_phase: bool) -> Vec<String> {
    let mut order: Vec<String> = Vec::with_capacity(names.len() + 1);
    for n in names {
        let after_angles = !(n == "t" || AngleChannel::ALL.iter().any(|c| c.name() == n));
        if has_phase && after_angles && !order.iter().any(|o| o == PHASE) {
            order.push(PHASE.into());
        }
        order.push(n.clone());
    }
    if has_phase && !order.iter().any(|o| o == PHASE) {
        order.push(PHASE.into());
    }
    order
}

pub(crate) fn estimate_tuple(
    py: Python<'_>,
    cols: EstimateColumns,
    resets: Option<String>,
    summary: Option<String>,
) -> PyResult<EstimateTuple<'_>> {
    let order = file_order(&cols.names, cols.phase.is_some());
    let (mut arrays, mut nan) = cols.values.into_numpy(py)?;
    let t = if arrays.is_empty() {
        PyArray1::zeros(py, 0, false)
    } else {
        nan.remove(0);
        arrays.remove(0)
    };
    Ok((
        cols.header,
        order,
        t,
        cols.names[1..].to_vec(),
        arrays,
        cols.phase,
        resets,
        Some(nan),
        summary,
    ))
}

/// [`SpeedRangeWatch`] over the estimate's `speed` array (NaN: no speed)
/// against the imm-bslip library's speeds `lo..=hi`; `None` without a
/// `speed` column.
fn speed_watch(
    (lo, hi): (f64, f64),
    names: &[String],
    arrays: &[Bound<'_, PyArray1<f64>>],
) -> PyResult<Option<SpeedRangeWatch>> {
    let Some(i) = names.iter().position(|n| n == "speed") else {
        return Ok(None);
    };
    let mut watch = SpeedRangeWatch::new(lo, hi);
    let speeds = arrays[i].readonly();
    for &v in speeds.as_slice()? {
        watch.observe_speed(Some(v));
    }
    Ok(Some(watch))
}

/// The calibration `text` (file `name`) for the trial `label`, as
/// `limbfuse estimate --calibration` takes it: refused for a trial
/// calibrated already or one with an IMU it does not cover; rotated into
/// the aligned frames of a trial `align` wrote; the CLI's notes given as
/// `LimbfuseWarning`s.
pub(crate) fn calibration_for_trial(
    py: Python<'_>,
    text: &str,
    name: &str,
    label: &str,
    meta: &limbfuse_io::TrialMeta,
    layout: &limbfuse_io::TrialLayout,
) -> PyResult<Calibration> {
    calibration_and_frame(py, text, name, label, meta, layout).map(|(c, _)| c)
}

/// [`calibration_for_trial`] and the frame it applies in, for the metadata
/// (`Calibration::annotate`, as `limbfuse align --imu-calibration` writes it).
pub(crate) fn calibration_and_frame(
    py: Python<'_>,
    text: &str,
    name: &str,
    label: &str,
    meta: &limbfuse_io::TrialMeta,
    layout: &limbfuse_io::TrialLayout,
) -> PyResult<(Calibration, &'static str)> {
    let (path, trial) = (Path::new(name), Path::new(label));
    let cal = Calibration::from_toml(text, path).map_err(|e| user_error(&e))?;
    let prepared = for_trial(cal, path, trial, meta, layout).map_err(|e| user_error(&e))?;
    for note in prepared.notes {
        crate::filter::warn_user(py, note)?;
    }
    Ok((prepared.calibration, prepared.frame))
}

/// The estimator of an `estimate` call: real-time, or offline: a knee
/// method backfilled (`backfill=True`, `limbfuse estimate --backfill`) or
/// `chain` smoothed (`smooth=True`, `--smooth`).
enum Built {
    Online(Box<dyn Estimator + Send>),
    Offline(Box<dyn OfflineEstimator + Send>),
}

impl Built {
    /// The estimator as the estimate's header describes it.
    fn header(&self) -> &dyn Estimator {
        match self {
            Built::Online(e) => e.as_ref(),
            Built::Offline(e) => e.header(),
        }
    }
}

/// `Estimate.summary` of a knee-axis method: the line `limbfuse estimate`
/// prints ([`limbfuse_eval::KneeWatch::verdict`]), with the backfill said
/// in Python's spelling.
fn knee_summary(method: &str, verdict: &str, backfill: bool) -> String {
    let before = if backfill {
        "; knee backfilled before it (gyro angle)"
    } else {
        "; no knee angle before it (`backfill=True` fills it offline)"
    };
    format!("{method}: {verdict}{before}")
}

/// Runs `method` over the trial, in memory, with the GIL released.
/// `imm-bslip` in the continuous configuration on a trial walking outside
/// its library's speeds runs twice, as the CLI does: the missing gaits are
/// searched and the trial estimated again over the extended family
/// (`limbfuse_workflows::imm_library_extension`); the warning says so.
#[pyfunction]
#[pyo3(signature = (trial, method, params=None, options=None))]
fn estimate<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    method: &str,
    params: Option<&Bound<'py, PyAny>>,
    options: Option<Bound<'py, PyDict>>,
) -> PyResult<EstimateTuple<'py>> {
    guarded(|| {
        let crate::options::EstimateRun {
            spec,
            diagnostics,
            backfill,
            smooth,
            calibration,
        } = crate::options::estimate_spec(method, params, options)?;
        let meta = trial.meta();
        let cols = trial.columns()?;
        let label = trial.label();
        let calibration = match calibration {
            Some((text, name)) => Some(calibration_for_trial(
                py,
                &text,
                &name,
                &label,
                &meta,
                cols.layout(),
            )?),
            None => None,
        };
        let in_trial = |e: &limbfuse_methods::MethodError| {
            user_msg(format!("{label}: {}", python_spelling(&chain_message(e))))
        };
        let est = if backfill {
            Built::Offline(Box::new(
                build_backfilled(&spec, &meta, cols.layout()).map_err(|e| in_trial(&e))?,
            ))
        } else if smooth {
            Built::Offline(Box::new(
                build_smoothed(&spec, &meta, cols.layout(), Default::default())
                    .map_err(|e| in_trial(&e))?,
            ))
        } else {
            Built::Online(
                limbfuse_methods::build(&spec, &meta, cols.layout()).map_err(|e| in_trial(&e))?,
            )
        };
        let inputs = cols.inputs();
        let frame_note = limbfuse_methods::raw_frame_note(spec.method(), &meta, &label);
        // As `limbfuse estimate`: a trial stating both leg-length keys.
        let leg_note =
            limbfuse_methods::leg_length_keys::conflict_warning(spec.method(), &meta, &label);
        // As `limbfuse estimate`: a time column, IMU or encoder readings
        // that do not look like SPEC units.
        let unit_note = {
            let mut w = SampleIntervalWatch::for_trial(&meta);
            for &t in cols.t.iter().take(FIRST_INTERVALS + 1) {
                w.push(t);
            }
            let mut units = SensorUnitsWatch::default();
            inputs.count_units(&mut units);
            let said: Vec<String> = limbfuse_eval::unit_warnings(&w, &units)
                .map(|m| format!("{label}: {m}"))
                .collect();
            (!said.is_empty()).then(|| said.join("\n"))
        };
        // A method modelling a fixed thigh on a trial whose thigh moves (the CLI's warning).
        let thigh_note = spec
            .method()
            .info()
            .assumes_fixed_thigh
            .then(|| {
                let mut w = limbfuse_eval::FixedThighWatch::default();
                inputs.count_thigh(&mut w);
                w.warning(spec.method().name(), &label)
            })
            .flatten();
        // Accelerometer readings that repeat at their largest value below
        // the full scale assumed (the CLI's warning).
        let rail_note = {
            let ranges = limbfuse_methods::gated::sensor_ranges(&meta).map_err(|e| in_trial(&e))?;
            let mut w = limbfuse_eval::AccRailWatch::new(
                ranges.acc_full_scale_m_s2.unwrap_or(f64::INFINITY),
                meta.get(limbfuse_methods::gated::ACC_RANGE_KEY).is_some(),
            );
            inputs.count_rails(&mut w);
            w.rails()
                .map(|r| format!("{} on {label}: {r}", spec.method()))
        };
        let knee_window = limbfuse_methods::knee_window::identification_window(&spec, &meta)
            .map_err(|e| in_trial(&e))?;
        let run = |mut built: Built| -> PyResult<EstimateTuple<'py>> {
            let est = built.header();
            let chosen = diagnostics
                .resolve(est.name(), est.diagnostic_names())
                .map_err(|e| user_msg(format!("{label}: {}", python_spelling(&e.to_string()))))?;
            let mut out = EstimateColumns::with_diagnostics(est, cols.len(), &chosen)
                .map_err(|_| user_msg("cannot describe the estimator's parameters"))?;
            if let Some((name, hash)) = trial.source() {
                out.header.push(format!("{TRIAL_KEY}: {name}"));
                out.header.push(format!("{TRIAL_HASH_KEY}: {hash}"));
            }
            let mut watches = RunWatches::default();
            let gait_method = limbfuse_eval::gait_watch::is_gait_method(&est.outputs());
            let mut interrupt = Interrupt::new(py)?;
            let run = py.detach(|| match &mut built {
                Built::Online(est) => run_columns(
                    est.as_mut(),
                    &inputs,
                    &mut out,
                    Some(&mut watches),
                    calibration.as_ref(),
                    &mut interrupt,
                ),
                Built::Offline(est) => run_columns_offline(
                    est.as_mut(),
                    &inputs,
                    &mut out,
                    &mut watches,
                    calibration.as_ref(),
                    &mut interrupt,
                ),
            });
            // Ctrl-C (a signal handler's exception) stops the run.
            if let Some(e) = interrupt.raised() {
                return Err(e);
            }
            run.map_err(|e| {
                user_msg(format!(
                    "estimating {label} with {}: {}",
                    spec.method(),
                    chain_message(&e)
                ))
            })?;
            // The CLI's warning of readings the range gate rejected (an
            // audit: Python users never saw it, not even in the error when
            // every reading was rejected).
            let rejected = watches
                .rejections
                .rejected()
                .map(|r| format!("{} on {label}: {r}", spec.method()));
            // ... and the other warnings the CLI prints before that error: the
            // unit checks above all (an audit, session 31: foot IMUs in deg/s
            // and g, as peers' tools give them, were "no gait found" with
            // nothing about their units).
            let with_warnings = |message: String| {
                let said = [
                    rejected.clone(),
                    unit_note.clone(),
                    frame_note.clone(),
                    leg_note.clone(),
                    thigh_note.clone(),
                    rail_note.clone(),
                ];
                user_msg(
                    std::iter::once(message)
                        .chain(said.into_iter().flatten())
                        .collect::<Vec<_>>()
                        .join("\n"),
                )
            };
            // As `limbfuse estimate`: nothing estimated is an error.
            let mut summary = None;
            if let Some(k) = &watches.knee {
                match k.verdict(knee_window) {
                    Ok(line) => summary = Some(knee_summary(spec.method().name(), &line, backfill)),
                    Err(why) => {
                        return Err(with_warnings(format!(
                            "{label}: `{}`: {why}",
                            spec.method()
                        )))
                    }
                }
            }
            if gait_method && !watches.gait.found {
                return Err(with_warnings(watches.gait.no_gait_message(
                    &label,
                    spec.method().name(),
                    inputs.len() as u64,
                    "nothing to return",
                )));
            }
            if !watches.any_output.found {
                return Err(with_warnings(
                    limbfuse_eval::output_watch::no_output_message(
                        &label,
                        spec.method().name(),
                        inputs.len() as u64,
                        watches.any_output.span_s(),
                        "nothing to return",
                    ),
                ));
            }
            let resets = watches
                .resets
                .resets()
                .map(|r| format!("{} on {label}: {r}", spec.method()));
            let clipped = watches
                .clipped_swings
                .clipped()
                .map(|c| format!("{} on {label}: {c}", spec.method()));
            let warning = [
                frame_note.clone(),
                leg_note.clone(),
                resets,
                rejected,
                clipped,
                unit_note.clone(),
                thigh_note.clone(),
                rail_note.clone(),
            ]
            .into_iter()
            .flatten()
            .reduce(|a, b| format!("{a}\n{b}"));
            estimate_tuple(py, out, warning, summary)
        };
        let mut tuple = run(est)?;
        let MethodSpec::ImmBslip(s) = &spec else {
            return Ok(tuple);
        };
        let range = limbfuse_methods::imm_params::library_speed_range(s, &meta)
            .map_err(|e| in_trial(&e))?;
        let Some(mut watch) = speed_watch(range, &tuple.3, &tuple.4)? else {
            return Ok(tuple);
        };
        let mut said = Vec::new();
        // (the gait search: seconds to minutes; Ctrl-C stops it)
        let search = limbfuse_sim::bslip::search::SearchSettings {
            cancel: Some(crate::interrupt::cancelled),
            ..Default::default()
        };
        let extension = crate::interrupt::detach(py, || {
            imm_library_extension::extend_for_trial(&spec, &meta, cols.layout(), &watch, &search)
        })?;
        if let Some(ext) = extension.map_err(|e| in_trial(&e))? {
            said.push(format!("{} on {label}: {}", spec.method(), ext.message));
            if let Some(est) = ext.estimator {
                tuple = run(Built::Online(est))?;
                watch = speed_watch(ext.range, &tuple.3, &tuple.4)?.unwrap_or(watch);
            }
        }
        if let Some(note) = watch.note() {
            said.push(format!("{} on {label}: {note}", spec.method()));
        }
        if !said.is_empty() {
            // (the restart warning first, as before the extension)
            said.splice(0..0, tuple.6.take());
            tuple.6 = Some(said.join("; "));
        }
        Ok(tuple)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(estimate, m)?)?;
    Ok(())
}
