//! `import_recording`: a real recording's own format converted into a trial
//! (`limbfuse import`, `limbfuse_io::import`; docs/IMPORTERS.md).

use std::path::PathBuf;

use limbfuse_core::Side;
use limbfuse_io::import::{import_gaittoolbox_with, import_knee_rig, GaittoolboxOptions};
use pyo3::prelude::*;

use crate::columns::OwnedColumns;
use crate::estimate::calibration_and_frame;
use crate::interrupt::detach;
use crate::trial::{trial_tuple, TrialTuple};
use crate::{guarded, user_error, user_msg};

/// Converts the recording at `path` (`format` "gaittoolbox": a sample
/// folder; "knee-rig": a rig log) into a trial; `leg` picks the
/// gaittoolbox leg, and `calibration` (the calibration file's text and its
/// name) is applied to the raw channels, as `limbfuse import --calibration`.
#[pyfunction]
#[pyo3(signature = (path, format, leg=None, calibration=None))]
fn import_recording<'py>(
    py: Python<'py>,
    path: PathBuf,
    format: &str,
    leg: Option<&str>,
    calibration: Option<(String, String)>,
) -> PyResult<TrialTuple<'py>> {
    guarded(|| {
        let leg = match leg {
            None => None,
            Some(l) => Some(Side::parse(l).ok_or_else(|| {
                user_msg(format!(
                    "import_recording: leg: expected \"left\" or \"right\", found {l:?}"
                ))
            })?),
        };
        let imported = match format {
            "gaittoolbox" => {
                let opts = GaittoolboxOptions {
                    leg,
                    ..GaittoolboxOptions::default()
                };
                detach(py, || import_gaittoolbox_with(&path, &opts))?
            }
            "knee-rig" => {
                if leg.is_some() {
                    return Err(user_msg(
                        "import_recording: leg applies to format=\"gaittoolbox\" only (a knee-rig \
                         log has one knee)",
                    ));
                }
                detach(py, || import_knee_rig(&path))?
            }
            other => {
                return Err(user_msg(format!(
                    "import_recording: format: expected \"gaittoolbox\" or \"knee-rig\", found \
                     {other:?}"
                )))
            }
        };
        let mut trial = imported.map_err(|e| user_error(&e))?;
        if let Some((text, name)) = &calibration {
            let label = path.display().to_string();
            let (cal, frame) =
                calibration_and_frame(py, text, name, &label, &trial.meta, &trial.layout)?;
            trial.records.iter_mut().for_each(|r| cal.apply(r));
            // (the file's name, as `limbfuse import --calibration` writes it)
            let file = std::path::Path::new(name)
                .file_name()
                .map_or(name.clone(), |n| n.to_string_lossy().into_owned());
            cal.annotate(&mut trial.meta, &file, frame);
        }
        let cols = detach(py, || {
            OwnedColumns::of_records(&trial.layout, &trial.records)
        })?;
        Ok(trial_tuple(py, &trial.meta, cols, None))
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(import_recording, m)?)?;
    Ok(())
}
