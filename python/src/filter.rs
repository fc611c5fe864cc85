//! `Filter`: one estimator kept between calls, for real-time use: `step`
//! takes one sample (a dict of channel values) and returns one estimate;
//! `run` takes arrays and releases the GIL.

use std::collections::HashMap;
use std::sync::Mutex;

use limbfuse_core::{Estimator, Sample, Side};
use limbfuse_eval::{FixedThighWatch, SampleIntervalWatch, SensorUnitsWatch};
use limbfuse_io::{Calibration, TrialMeta};
use limbfuse_methods::MethodName;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat};

use crate::column_run::{run_columns, RunWatches};
use crate::column_samples::SampleColumns;
use crate::columns::{leg_of, Channel, TrialColumns};
use crate::estimate::EstimateTuple;
use crate::estimate_columns::EstimateColumns;
use crate::interrupt::Interrupt;
use crate::trial::slice;
use crate::{chain_message, guarded, user_msg};

/// A method's estimator for a set of channels, stepped from Python.
#[pyclass(module = "limbfuse._native")]
pub struct NativeFilter {
    /// In a mutex only to make the class `Sync` (PyO3 needs it); the
    /// methods take `&mut self` and use `get_mut`, which never locks.
    est: Mutex<Box<dyn Estimator + Send>>,
    method: String,
    channels: Vec<String>,
    /// The channel of each name of `channels`, in order.
    slots: Vec<Channel>,
    /// The position of each name in `channels`.
    index: HashMap<String, usize>,
    /// The side of the single-leg channels (the `leg` metadata).
    leg: Side,
    template: EstimateColumns,
    /// The IMU calibration applied to every sample (`calibration=`).
    calibration: Option<Calibration>,
    /// The unit checks of `estimate`, over the samples stepped or run.
    units: StreamUnits,
    /// `estimate`'s warning for a method reading aligned frames given a
    /// trial that declares raw ones (`raw_frame_note`).
    frame_note: Option<String>,
    /// `numpy.ma.masked`, a missing value in a sample as in arrays.
    masked: Py<PyAny>,
    /// `estimate`'s watches, kept between `run`s: the sensor gate's
    /// rejection counts (warned once per `run`, and once per stream of
    /// `step`s until `reset`).
    watches: RunWatches,
    /// Whether the rejections of the `step`s were warned of.
    step_rejections_said: bool,
}

/// The `LimbfuseWarning` of `text`.
pub(crate) fn warn_user(py: Python<'_>, text: String) -> PyResult<()> {
    let category = py
        .import("limbfuse._estimate")?
        .getattr("LimbfuseWarning")?;
    let text = std::ffi::CString::new(text).unwrap_or_default();
    PyErr::warn(py, &category, &text, 2)
}

/// The unit checks of `estimate` (`limbfuse_eval::unit_warnings`) over a
/// stream, and for `knee-kinematic` its fixed-thigh check
/// (`limbfuse_eval::FixedThighWatch`): each said once, as a
/// `LimbfuseWarning`, when it finds something.
struct StreamUnits {
    intervals: SampleIntervalWatch,
    units: SensorUnitsWatch,
    thigh: Option<FixedThighWatch>,
    samples: u64,
    said: bool,
    thigh_said: bool,
}

impl StreamUnits {
    /// Samples after which the checks stop (the first 64 steps decide the
    /// time column; the IMU shares settle long before).
    const LAST_CHECK: u64 = 8192;

    fn new(meta: &TrialMeta, method: MethodName) -> Self {
        StreamUnits {
            intervals: SampleIntervalWatch::for_trial(meta),
            units: SensorUnitsWatch::default(),
            thigh: method
                .info()
                .assumes_fixed_thigh
                .then(FixedThighWatch::default),
            samples: 0,
            said: false,
            thigh_said: false,
        }
    }

    /// Whether every check has spoken or stopped looking.
    fn done(&self) -> bool {
        (self.said && (self.thigh.is_none() || self.thigh_said)) || self.samples > Self::LAST_CHECK
    }

    /// Counts one sample (every [`SensorUnitsWatch::STRIDE`]-th one's IMUs
    /// and encoders, as `estimate` counts).
    fn observe(&mut self, s: &Sample) {
        if self.done() {
            return;
        }
        self.intervals.push(s.t);
        if self.samples.is_multiple_of(SensorUnitsWatch::STRIDE as u64) {
            self.units.push_sample(s);
            if let Some(w) = self.thigh.as_mut() {
                w.push_sample(s);
            }
        }
        self.samples += 1;
    }

    /// Warns once per check, when it has found something (looked at every
    /// 64 samples and at the end of a `run`).
    fn warn(&mut self, py: Python<'_>, method: &str, now: bool) -> PyResult<()> {
        if !(now || self.samples.is_multiple_of(64)) {
            return Ok(());
        }
        let mut texts = Vec::new();
        if !self.said {
            let said: Vec<String> =
                limbfuse_eval::unit_warnings(&self.intervals, &self.units).collect();
            if !said.is_empty() {
                self.said = true;
                texts.push(format!(
                    "{method}: the filter's samples: {}",
                    said.join("; ")
                ));
            }
        }
        if !self.thigh_said {
            if let Some(w) = self
                .thigh
                .as_ref()
                .and_then(|w| w.warning(method, "the filter's samples"))
            {
                self.thigh_said = true;
                texts.push(w);
            }
        }
        for text in texts {
            warn_user(py, text)?;
        }
        Ok(())
    }
}

/// Whether `v` is pandas' missing marker `pd.NA` (pandas not imported).
fn is_pandas_na(v: &Bound<'_, PyAny>) -> bool {
    let ty = v.get_type();
    ty.name().is_ok_and(|n| n == "NAType")
        && ty
            .module()
            .is_ok_and(|m| m.to_string().starts_with("pandas"))
}

fn step_error(method: &str, t: f64, e: &dyn std::error::Error) -> PyErr {
    user_msg(format!("{method}: sample at t = {t} s: {e}"))
}

impl NativeFilter {
    fn estimator(&mut self) -> &mut (dyn Estimator + Send) {
        match self.est.get_mut() {
            Ok(e) => e.as_mut(),
            Err(poisoned) => poisoned.into_inner().as_mut(),
        }
    }
}

#[pymethods]
impl NativeFilter {
    #[new]
    #[pyo3(signature = (method, channels, meta, params=None, options=None))]
    fn new(
        py: Python<'_>,
        method: &str,
        channels: Vec<String>,
        meta: Vec<(String, String)>,
        params: Option<&Bound<'_, PyAny>>,
        options: Option<Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        guarded(|| {
            let calibration = match &options {
                Some(d) => crate::options::take_calibration(d)?,
                None => None,
            };
            let spec = crate::options::method_spec(method, params, options)?;
            let mut m = TrialMeta::new();
            for (k, v) in meta {
                m.set(k, v);
            }
            // The layout of the declared channels (checked as a trial's).
            let t = [0.0];
            let empty: Vec<(String, &[f64])> =
                channels.iter().map(|c| (c.clone(), &t[..])).collect();
            let leg = leg_of(&m).map_err(user_msg)?;
            let cols = TrialColumns::new(&t, empty, None, leg).map_err(user_msg)?;
            let est = limbfuse_methods::build(&spec, &m, cols.layout())
                .map_err(|e| user_msg(chain_message(&e)))?;
            let calibration = match calibration {
                Some((text, name)) => Some(crate::estimate::calibration_for_trial(
                    py,
                    &text,
                    &name,
                    "the filter's input",
                    &m,
                    cols.layout(),
                )?),
                None => None,
            };
            let template = EstimateColumns::for_estimator(est.as_ref(), 0)
                .map_err(|_| user_msg("cannot describe the estimator's parameters"))?;
            let slots = channels
                .iter()
                .map(|c| Channel::parse(c, leg.other()))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| user_msg("unknown channel"))?;
            let index = channels
                .iter()
                .enumerate()
                .map(|(k, c)| (c.clone(), k))
                .collect();
            let watches = RunWatches::for_estimator(est.as_ref());
            Ok(NativeFilter {
                est: Mutex::new(est),
                method: spec.method().to_string(),
                channels,
                slots,
                index,
                leg,
                template,
                calibration,
                units: StreamUnits::new(&m, spec.method()),
                frame_note: limbfuse_methods::raw_frame_note(
                    spec.method(),
                    &m,
                    "the filter's metadata",
                ),
                masked: py.import("numpy.ma")?.getattr("masked")?.unbind(),
                watches,
                step_rejections_said: false,
            })
        })
    }

    /// The channels the filter was made for.
    #[getter]
    fn channels(&self) -> Vec<String> {
        self.channels.clone()
    }

    /// The estimate file header lines (method and parameters).
    #[getter]
    fn header(&self) -> Vec<String> {
        self.template.header.clone()
    }

    /// `estimate`'s raw-frame warning for this method and metadata, if any.
    #[getter]
    fn frame_note(&self) -> Option<String> {
        self.frame_note.clone()
    }

    /// Forgets the state (the next sample starts a new run).
    fn reset(&mut self) -> PyResult<()> {
        guarded(|| {
            self.estimator().reset();
            self.watches = RunWatches::for_estimator(self.estimator());
            self.step_rejections_said = false;
            Ok(())
        })
    }

    /// One sample in (`t` and channel values, `None` or absent = missing),
    /// one estimate out (a dict, `None` = not estimated).
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        sample: &Bound<'py, PyDict>,
    ) -> PyResult<Bound<'py, PyDict>> {
        guarded(|| {
            // NaN = missing (an absent channel too), as in trial columns.
            let mut values = vec![f64::NAN; self.slots.len()];
            let mut t = None;
            for (k, v) in sample.iter() {
                let key: String = k
                    .extract()
                    .map_err(|_| user_msg("sample: every key must be a channel name (str)"))?;
                let value: Option<f64> = if v.is_none() || v.is(self.masked.bind(py)) {
                    None
                } else if v.is_exact_instance_of::<PyFloat>() {
                    // (the common case first: no look at the type's name)
                    Some(v.extract::<f64>()?)
                } else if crate::options::is_bool(&v) {
                    // (a `TypeError`, as for a string: an audit found a bool
                    // raising `LimbfuseError` against the docs)
                    return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                        "sample `{key}`: expected a number or None, found a bool"
                    )));
                } else if let Ok(x) = v.extract::<f64>() {
                    Some(x)
                } else if is_pandas_na(&v) {
                    // (pandas' missing marker, as in a row of a `Float64`
                    // DataFrame, `df.iloc[i].to_dict()`; an audit found it
                    // refused as "not a number")
                    None
                } else {
                    return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                        "sample `{key}`: expected a number or None, found {}",
                        crate::options::shown(&v)
                    )));
                };
                if let Some(x) = value {
                    if !x.is_finite() {
                        return Err(user_msg(format!(
                            "sample `{key}`: {x} is not a value (pass None for a missing sample)"
                        )));
                    }
                }
                if key == "t" {
                    t = value;
                    continue;
                }
                let Some(&k) = self.index.get(&key) else {
                    return Err(user_msg(format!(
                        "sample: `{key}` is not one of the filter's channels ({})",
                        self.channels.join(", ")
                    )));
                };
                values[k] = value.unwrap_or(f64::NAN);
            }
            let t = t.ok_or_else(|| user_msg("sample: `t` (time in s) is required"))?;
            let time = [t];
            let columns: Vec<(Channel, &[f64])> = self
                .slots
                .iter()
                .zip(&values)
                .map(|(c, v)| (*c, std::slice::from_ref(v)))
                .collect();
            let mut sample = Sample::default();
            SampleColumns::new(&time, &columns).fill(0, &mut sample);
            // (the units of the samples as given, before a calibration)
            self.units.observe(&sample);
            self.units.warn(py, &self.method, false)?;
            if let Some(c) = &self.calibration {
                c.apply_sample(&mut sample);
            }
            let e = self
                .estimator()
                .step(&sample)
                .map_err(|e| step_error(&self.method, t, &e))?;
            // `estimate`'s warning of rejected readings, once per stream.
            self.watches.rejections.push(&e);
            if !self.step_rejections_said {
                if let Some(r) = self.watches.rejections.rejected() {
                    self.step_rejections_said = true;
                    warn_user(py, format!("{}: the filter's samples: {r}", self.method))?;
                }
            }
            // ... and of the first stride clipped past an impact.
            let before = self.watches.clipped_swings.clipped();
            self.watches.clipped_swings.push(&e);
            if let (None, Some(c)) = (before, self.watches.clipped_swings.clipped()) {
                warn_user(py, format!("{}: the filter's samples: {c}", self.method))?;
            }
            let out = PyDict::new(py);
            for (name, v) in self.template.row(&e) {
                out.set_item(name, v)?;
            }
            if self.template.phase.is_some() {
                out.set_item(
                    crate::estimate_columns::PHASE,
                    e.phase.map(limbfuse_core::GaitPhase::label),
                )?;
            }
            Ok(out)
        })
    }

    /// Runs the filter over arrays (`t` and the channels), continuing from
    /// its state, with the GIL released.
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        t: PyReadonlyArray1<'py, f64>,
        names: Vec<String>,
        arrays: Vec<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<EstimateTuple<'py>> {
        guarded(|| {
            if names.len() != arrays.len() {
                return Err(user_msg("run: as many channel names as arrays are needed"));
            }
            for n in &names {
                if !self.channels.contains(n) {
                    return Err(user_msg(format!(
                        "run: `{n}` is not one of the filter's channels ({})",
                        self.channels.join(", ")
                    )));
                }
            }
            let t = slice(&t, "t")?;
            let mut named = Vec::with_capacity(names.len());
            for (n, a) in names.iter().zip(&arrays) {
                named.push((n.clone(), slice(a, n)?));
            }
            let cols = TrialColumns::new(t, named, None, self.leg).map_err(user_msg)?;
            let mut out = EstimateColumns::for_estimator(self.estimator(), cols.len())
                .map_err(|_| user_msg("cannot describe the estimator's parameters"))?;
            let method = self.method.clone();
            let calibration = self.calibration.clone();
            let inputs = cols.inputs();
            if !self.units.done() {
                let mut sample = Sample::default();
                for i in 0..inputs.len().min(StreamUnits::LAST_CHECK as usize) {
                    inputs.fill(i, &mut sample);
                    self.units.observe(&sample);
                }
                self.units.warn(py, &method, true)?;
            }
            let mut watches = std::mem::take(&mut self.watches);
            let mut interrupt = Interrupt::new(py)?;
            let est = self.estimator();
            let run = py.detach(|| {
                run_columns(
                    est,
                    &inputs,
                    &mut out,
                    Some(&mut watches),
                    calibration.as_ref(),
                    &mut interrupt,
                )
            });
            // (the counts carry on, also past an error)
            let rejected = watches.rejections.rejected();
            let clipped = watches.clipped_swings.clipped();
            let counts = watches.rejections.counts();
            watches.rejections.carry(counts);
            self.watches = watches;
            // Ctrl-C stops the run, the filter part-way through it.
            if let Some(e) = interrupt.raised() {
                return Err(e);
            }
            run.map_err(|e| user_msg(format!("{method}: {}", chain_message(&e))))?;
            // `estimate`'s warning of rejected readings, once per run.
            if let Some(r) = rejected {
                warn_user(py, format!("{method}: the filter's samples: {r}"))?;
            }
            // ... and of strides clipped past an impact (`gait-events`).
            if let Some(c) = clipped {
                warn_user(py, format!("{method}: the filter's samples: {c}"))?;
            }
            crate::estimate::estimate_tuple(py, out, None, None)
        })
    }
}
