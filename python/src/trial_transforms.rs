//! `resample` and `mirror`: a trial in, a new trial out, as `limbfuse
//! resample` and `limbfuse mirror` write it (`limbfuse_signal::resample`,
//! `limbfuse_signal::align::mirror_trial`).

use std::path::Path;

use limbfuse_signal::align::mirror_trial::{mirror_trial, mirrored_leg};
use limbfuse_signal::resample::{resample_notes, resample_records, AntiAlias, ResampleOptions};
use pyo3::prelude::*;

use crate::columns::OwnedColumns;
use crate::interrupt::detach;
use crate::trial::{trial_tuple, TrialArgs, TrialTuple};
use crate::workflows::polled;
use crate::{chain_message, guarded, user_msg};

/// The trial on a uniform time base at `rate_hz` (`limbfuse resample`), and
/// the CLI's warnings (readings out of the sensors' range left out, clipped
/// gyroscope cells carried at the rail).
#[pyfunction]
#[pyo3(signature = (trial, rate_hz, anti_alias="sinc"))]
fn resample<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    rate_hz: f64,
    anti_alias: &str,
) -> PyResult<(TrialTuple<'py>, Vec<String>)> {
    guarded(|| {
        let anti_alias = match anti_alias {
            "sinc" => AntiAlias::WindowedSinc,
            "boxcar" => AntiAlias::Boxcar,
            "none" => AntiAlias::None,
            other => return Err(user_msg(anti_alias_expected(other))),
        };
        let opts = ResampleOptions {
            rate_hz,
            anti_alias,
        };
        let cols = trial.columns()?;
        let layout = *cols.layout();
        let (label, meta) = (trial.label(), trial.meta());
        let records = detach(py, || polled(cols.records()))?;
        let out = detach(py, || {
            resample_records(
                &records,
                &meta,
                layout,
                Path::new(&label),
                &opts,
                Some(crate::interrupt::cancelled),
            )
        })?
        .map_err(|e| {
            user_msg(format!(
                "resampling {label} to {} Hz: {}",
                limbfuse_core::ShownNumber(rate_hz),
                chain_message(&e)
            ))
        })?;
        let (rejected, clipped) =
            resample_notes(Path::new(&label), &out.rejections, out.clipped_gyro);
        let said = rejected.into_iter().chain(clipped).collect();
        let cols = detach(py, || OwnedColumns::of_records(&out.layout, &out.records))?;
        Ok((trial_tuple(py, &out.meta, cols, None), said))
    })
}

/// The message for an unknown `anti_alias`.
fn anti_alias_expected(found: &str) -> String {
    format!("resample: anti_alias: expected \"sinc\", \"boxcar\" or \"none\", found {found:?}")
}

/// The trial as the mirror-image leg's sensors would read it (`limbfuse
/// mirror`), re-mounted at random with `remount_seed`, and the CLI's
/// warning (metadata lines that could not be mirrored).
#[pyfunction]
#[pyo3(signature = (trial, remount_seed=None))]
fn mirror<'py>(
    py: Python<'py>,
    trial: TrialArgs<'py>,
    remount_seed: Option<u64>,
) -> PyResult<(TrialTuple<'py>, Vec<String>)> {
    guarded(|| {
        let cols = trial.columns()?;
        let layout = *cols.layout();
        let (label, meta) = (trial.label(), trial.meta());
        // (the channels checked before the records are built)
        mirrored_leg(&meta, &layout, &label).map_err(|e| user_msg(e.to_string()))?;
        let records = detach(py, || polled(cols.records()))?;
        let m = detach(py, || {
            mirror_trial(&records, &meta, layout, &label, remount_seed)
        })?
        .map_err(|e| user_msg(e.to_string()))?;
        let mut said = Vec::new();
        if !m.dropped_meta.is_empty() {
            said.push(format!(
                "{label}: left out metadata lines that could not be mirrored: {}",
                m.dropped_meta.join(", ")
            ));
        }
        let cols = detach(py, || OwnedColumns::of_records(&m.layout, &m.records))?;
        Ok((trial_tuple(py, &m.meta, cols, None), said))
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(resample, m)?)?;
    m.add_function(wrap_pyfunction!(mirror, m)?)?;
    Ok(())
}
