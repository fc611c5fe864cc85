//! Trials across the boundary: the tuple the Python `Trial` hands in
//! ([`TrialArgs`]), the tuple handed back ([`trial_tuple`]), and
//! `read_trial` / `write_trial` over `limbfuse-io`'s reader and writer.

use std::path::PathBuf;

use limbfuse_io::{AtomicFile, TrialMeta, TrialReader, TrialWriter};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::columns::{check_names, leg_of, OwnedColumns, TrialColumns};
use crate::{guarded, user_error, user_msg};

/// What the Python `Trial._native()` returns: metadata items, `t`, channel
/// names and arrays (float64, NaN = missing), `phase_ref` cells, and the
/// source file's name and content hash when the trial was read from a file.
#[derive(FromPyObject)]
pub struct TrialArgs<'py>(
    pub Vec<(String, String)>,
    pub PyReadonlyArray1<'py, f64>,
    pub Vec<String>,
    pub Vec<PyReadonlyArray1<'py, f64>>,
    pub Option<Vec<Option<String>>>,
    pub Option<(String, String)>,
);

impl<'py> TrialArgs<'py> {
    /// The metadata.
    pub fn meta(&self) -> TrialMeta {
        let mut m = TrialMeta::new();
        for (k, v) in &self.0 {
            m.set(k.clone(), v);
        }
        m
    }

    /// The columns, checked (names, lengths, time, contact cells; the
    /// other leg's IMU columns named after the `leg` metadata).
    pub fn columns(&self) -> PyResult<TrialColumns<'_>> {
        let leg = leg_of(&self.meta()).map_err(user_msg)?;
        if self.2.len() != self.3.len() {
            return Err(user_msg(
                "trial: as many channel names as arrays are needed",
            ));
        }
        let t = slice(&self.1, "t")?;
        let mut named = Vec::with_capacity(self.2.len());
        for (n, a) in self.2.iter().zip(&self.3) {
            named.push((n.clone(), slice(a, n)?));
        }
        TrialColumns::new(t, named, self.4.clone(), leg).map_err(user_msg)
    }

    /// The source file name and its hash text, if read from a file.
    pub fn source(&self) -> Option<&(String, String)> {
        self.5.as_ref()
    }

    /// The name of the trial in messages.
    pub fn label(&self) -> String {
        self.5
            .as_ref()
            .map_or_else(|| "<in-memory trial>".to_string(), |s| s.0.clone())
    }
}

/// A contiguous float64 array as a slice.
pub fn slice<'a>(a: &'a PyReadonlyArray1<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    a.as_slice().map_err(|_| {
        user_msg(format!(
            "channel `{name}`: expected a contiguous 1-D float64 array"
        ))
    })
}

/// The tuple the Python layer builds a `Trial` from (the layout of
/// [`TrialArgs`]).
pub type TrialTuple<'py> = (
    Vec<(String, String)>,
    Bound<'py, PyArray1<f64>>,
    Vec<String>,
    Vec<Bound<'py, PyArray1<f64>>>,
    Option<Vec<Option<&'static str>>>,
    Option<(String, String)>,
);

/// Hands owned columns to Python without copying the arrays.
pub fn trial_tuple<'py>(
    py: Python<'py>,
    meta: &TrialMeta,
    cols: OwnedColumns,
    source: Option<(String, String)>,
) -> TrialTuple<'py> {
    let (names, arrays): (Vec<String>, Vec<_>) = cols
        .columns
        .into_iter()
        .map(|(n, v)| (n, PyArray1::from_vec(py, v)))
        .unzip();
    (
        meta.entries().to_vec(),
        PyArray1::from_vec(py, cols.t),
        names,
        arrays,
        cols.phase,
        source,
    )
}

/// Reads a trial file (SPEC section 2).
#[pyfunction]
fn read_trial(py: Python<'_>, path: PathBuf) -> PyResult<TrialTuple<'_>> {
    guarded(|| {
        let (meta, cols, hash, cut) =
            crate::interrupt::detach(py, || -> Result<_, limbfuse_io::FileError> {
                let mut reader = TrialReader::open(&path)?;
                let meta = reader.meta().clone();
                let (mut cols, channels) = OwnedColumns::new(reader.layout(), 1024);
                while let Some(r) = reader.next_record()? {
                    cols.push(&channels, &r);
                    if crate::interrupt::poll_current() {
                        break;
                    }
                }
                let cut = reader.cut_last_line().map(|c| c.message(&path));
                Ok((meta, cols, reader.content_hash(), cut))
            })?
            .map_err(|e| user_error(&e))?;
        // (the CLI's warning: a recording cut off mid-line, its last line left out)
        if let Some(cut) = cut {
            crate::filter::warn_user(py, cut)?;
        }
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let source = hash.map(|h| (name, h.to_string()));
        Ok(trial_tuple(py, &meta, cols, source))
    })
}

/// Writes a trial file (the CLI's writer: same bytes as `limbfuse` writes).
#[pyfunction]
fn write_trial(py: Python<'_>, path: PathBuf, trial: TrialArgs<'_>) -> PyResult<()> {
    guarded(|| {
        let meta = trial.meta();
        let cols = trial.columns()?;
        let err = |e: std::io::Error| user_msg(format!("{}: cannot write: {e}", path.display()));
        crate::interrupt::detach(py, || {
            let mut file = AtomicFile::create(&path).map_err(err)?;
            {
                let mut w =
                    TrialWriter::for_path(&path, &mut file, &meta, *cols.layout()).map_err(err)?;
                for r in cols.records() {
                    w.write(&r).map_err(err)?;
                    // (Ctrl-C: nothing written, `detach` raises)
                    if crate::interrupt::poll_current() {
                        return Ok(());
                    }
                }
                w.finish().map_err(err)?;
            }
            file.commit().map_err(err)
        })?
    })
}

/// Checks a trial's arrays (names, lengths, time, phase cells).
#[pyfunction]
fn check_trial(trial: TrialArgs<'_>) -> PyResult<()> {
    guarded(|| trial.columns().map(|_| ()))
}

/// Checks the channel names of a trial with metadata `meta` (before its
/// arrays are converted: a misspelt name is reported before a NaN in it).
#[pyfunction]
fn check_channel_names(meta: Vec<(String, String)>, names: Vec<String>) -> PyResult<()> {
    guarded(|| {
        let mut m = TrialMeta::new();
        for (k, v) in &meta {
            m.set(k.clone(), v);
        }
        let leg = leg_of(&m).map_err(user_msg)?;
        check_names(names.iter().map(String::as_str), leg).map_err(user_msg)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_channel_names, m)?)?;
    m.add_function(wrap_pyfunction!(read_trial, m)?)?;
    m.add_function(wrap_pyfunction!(write_trial, m)?)?;
    m.add_function(wrap_pyfunction!(check_trial, m)?)?;
    Ok(())
}
