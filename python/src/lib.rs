//! `limbfuse._native`: the Rust side of the `limbfuse` Python package.
//!
//! It calls the limbfuse crates as the CLI does (`limbfuse-methods` to
//! resolve and build a method, `limbfuse-core`'s runner, `limbfuse-io` for
//! files, `limbfuse-eval` for metrics, `limbfuse-workflows` and
//! `limbfuse-signal` for simulation and alignment); the pure-Python layer
//! (`python/limbfuse/`) wraps these functions in the `Trial`, `Estimate` and
//! `Filter` classes of the public API. Trials cross the boundary as columns
//! (numpy arrays, NaN = missing inside this crate: see the `columns` module).
//!
//! Every entry point runs inside `guarded`: a user error becomes a
//! `limbfuse.LimbfuseError` (a `ValueError`) with the CLI's message, a panic
//! a `limbfuse.InternalError`; no panic unwinds into Python.

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

mod cache_hints;
mod column_block;
mod column_records;
mod column_run;
mod column_samples;
mod columns;
mod estimate;
mod estimate_columns;
mod estimate_file;
mod evaluate;
mod filter;
mod interrupt;
mod monte_carlo;
mod options;
mod recording_import;
mod simulate;
mod strides;
mod time_repair;
mod trial;
mod trial_transforms;
mod tune;
mod tune_fes;
mod workflows;

create_exception!(
    limbfuse,
    LimbfuseError,
    PyValueError,
    "A user error: a bad file, array, method name or parameter (the message names it)."
);
create_exception!(
    limbfuse,
    InternalError,
    PyRuntimeError,
    "A limbfuse bug (a Rust panic caught at the boundary); please report it."
);

/// The message of an error and its sources, as the CLI prints it (a source
/// already contained in the message is not repeated).
pub(crate) fn chain_message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut msg = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let text = s.to_string();
        if !msg.contains(&text) {
            msg.push_str(": ");
            msg.push_str(&text);
        }
        source = s.source();
    }
    msg
}

/// A user error from a typed error.
pub(crate) fn user_error(e: &(dyn std::error::Error + 'static)) -> PyErr {
    LimbfuseError::new_err(chain_message(e))
}

/// A user error from a message.
pub(crate) fn user_msg(msg: impl Into<String>) -> PyErr {
    LimbfuseError::new_err(msg.into())
}

/// Runs `f`, turning a panic into `InternalError`.
pub(crate) fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let text = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(InternalError::new_err(format!(
                "internal error: {text} (this is a limbfuse bug; please report it)"
            )))
        }
    }
}

/// Every method's name and one-line summary, in `limbfuse methods` order.
#[pyfunction]
fn methods() -> Vec<(&'static str, &'static str)> {
    limbfuse_methods::MethodName::ALL
        .iter()
        .map(|m| (m.name(), m.info().summary))
        .collect()
}

/// Every method with what `limbfuse methods` says of it: (name, summary,
/// what it reads, its settings).
#[pyfunction]
fn method_details() -> Vec<(&'static str, &'static str, &'static str, &'static str)> {
    limbfuse_methods::MethodName::ALL
        .iter()
        .map(|m| {
            let i = m.info();
            (m.name(), i.summary, i.inputs, i.settings)
        })
        .collect()
}

/// A method's default parameter file, commented (`limbfuse params`).
#[pyfunction]
fn default_params(method: &str) -> PyResult<String> {
    guarded(|| {
        let m = limbfuse_methods::MethodName::parse(method).map_err(|e| user_error(&e))?;
        Ok(limbfuse_methods::default_params_file(m))
    })
}

/// What a trial file holds and which methods run on it (`limbfuse
/// inspect`): a tuple the Python layer turns into a dict.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn inspect(
    py: Python<'_>,
    path: std::path::PathBuf,
) -> PyResult<(
    u64,
    Option<(f64, f64)>,
    Option<f64>,
    Option<f64>,
    u64,
    Option<(f64, f64)>,
    Vec<(String, u64)>,
    Vec<String>,
    Vec<(&'static str, &'static str, String)>,
    Vec<String>,
    Option<f64>,
    // the data notes and `limbfuse align`'s verdict (needed, possible, reason)
    (Vec<String>, (bool, Option<bool>, Option<String>)),
)> {
    guarded(|| {
        // (Ctrl-C, session 30: it ran holding the GIL; the alignment check
        // of a raw-frame trial under 200 000 rows took 2 s of CPU)
        let (s, methods, read, motion, align) = interrupt::detach(py, || {
            let mut reader = limbfuse_io::TrialReader::open(&path)?;
            let meta = reader.meta().clone();
            let layout = *reader.layout();
            let s = limbfuse_eval::summarise(&mut reader)?;
            let mut available = limbfuse_methods::availability(&meta, &layout);
            limbfuse_eval::data_limits::limit_by_data(&mut available, &s, &meta);
            let read = limbfuse_methods::metadata_settings(&meta, &available);
            let motion =
                limbfuse_eval::fixed_thigh::thigh_motion_notes(s.thigh_spread_deg, &available);
            // Whether `limbfuse align` can align it (`inspect`'s line, the JSON's `align`).
            let align = limbfuse_workflows::align_verdict::align_verdict(
                &path,
                &meta,
                &layout,
                s.rows,
                &available,
                Some(interrupt::cancelled),
            );
            // (the reasons with the model file's hint, as `inspect --json`'s)
            let why = limbfuse_methods::availability::inspect_reasons(&available, &path);
            let methods: Vec<_> = available
                .into_iter()
                .zip(why)
                .map(|((m, a), why)| (m.name(), a.kind(), why))
                .collect();
            Ok::<_, limbfuse_io::FileError>((s, methods, read, motion, align))
        })?
        .map_err(|e| time_order_error(&path, e))?;
        Ok((
            s.rows,
            s.span,
            s.median_step,
            s.stated_hz,
            s.gaps,
            s.longest_step,
            s.inputs
                .into_iter()
                .map(|g| (g.name, g.missing_rows))
                .collect(),
            s.warnings,
            methods,
            read,
            s.thigh_spread_deg,
            (motion, (align.needed, align.possible, align.reason)),
        ))
    })
}

/// A file error; one about the time's order gets what `repair_time` would
/// drop over the whole file (as `limbfuse inspect` says it).
fn time_order_error(path: &std::path::Path, e: limbfuse_io::FileError) -> PyErr {
    if !matches!(e, limbfuse_io::FileError::TimeNotIncreasing { .. }) {
        return user_error(&e);
    }
    match limbfuse_io::time_repair::time_problems(path) {
        Ok(r) => user_msg(format!(
            "{}: its time does not increase on every row: {}: {}",
            path.display(),
            r.would_drop("limbfuse.repair_time(path, output)", 8),
            chain_message(&e)
        )),
        Err(_) => user_error(&e),
    }
}

/// Raises `InternalError` from inside Rust (tests the panic boundary).
#[pyfunction]
fn _panic_for_test() -> PyResult<()> {
    guarded(|| panic!("a test panic"))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("LimbfuseError", py.get_type::<LimbfuseError>())?;
    m.add("InternalError", py.get_type::<InternalError>())?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(method_details, m)?)?;
    m.add_function(wrap_pyfunction!(default_params, m)?)?;
    m.add_function(wrap_pyfunction!(inspect, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    trial::register(m)?;
    estimate::register(m)?;
    estimate_file::register(m)?;
    evaluate::register(m)?;
    strides::register(m)?;
    time_repair::register(m)?;
    trial_transforms::register(m)?;
    recording_import::register(m)?;
    tune::register(m)?;
    monte_carlo::register(m)?;
    simulate::register(m)?;
    workflows::register(m)?;
    m.add_class::<filter::NativeFilter>()?;
    Ok(())
}
