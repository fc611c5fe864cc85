//! `strides`: the per-stride table of a `gait-events` / `lowback-speed`
//! estimate (`limbfuse evaluate --strides`, docs/GAIT_EVENTS.md "Stride
//! table"), built by `limbfuse-eval::stride_table` over the estimate (and
//! the trial, when given) written to temporary files.

use limbfuse_eval::stride_table::{
    stride_table_of_files, SpeedWithheld, StrideTable, STRIDE_COLUMNS,
};
use limbfuse_eval::TimeWindow;
use pyo3::prelude::*;

use crate::estimate::EstimateArgs;
use crate::evaluate::{check_same_trial, write_estimate, write_trial};
use crate::trial::TrialArgs;
use crate::{guarded, user_error, user_msg};

/// The table's columns: `foot`, `speed_withheld` (`""` when not withheld)
/// and the numeric columns by name (NaN: not known).
type StrideColumns = (Vec<String>, Vec<String>, Vec<(String, Vec<f64>)>);

/// The strides of `estimate`, with the references of `trial` when given.
#[pyfunction]
#[pyo3(signature = (estimate, trial=None, allow_trial_mismatch=false, window=None))]
fn strides(
    estimate: EstimateArgs<'_>,
    trial: Option<TrialArgs<'_>>,
    allow_trial_mismatch: bool,
    window: Option<&str>,
) -> PyResult<StrideColumns> {
    guarded(|| {
        let window = match window {
            Some(w) => TimeWindow::parse(w).map_err(|m| user_msg(format!("window: {m}")))?,
            None => TimeWindow::default(),
        };
        let view = estimate.view()?;
        let dir = tempfile::tempdir().map_err(|e| user_msg(format!("temporary files: {e}")))?;
        let ep = write_estimate(dir.path(), &estimate, &view)?;
        let tp = match &trial {
            Some(trial) => {
                check_same_trial(trial, &estimate, allow_trial_mismatch)?;
                let cols = trial.columns()?;
                Some(write_trial(dir.path(), trial, &cols)?)
            }
            None => None,
        };
        let table =
            stride_table_of_files(tp.as_deref(), &ep, true, &window).map_err(|e| user_error(&e))?;
        Ok(columns(&table))
    })
}

fn columns(table: &StrideTable) -> StrideColumns {
    let foot = table
        .rows
        .iter()
        .map(|r| r.foot.name().to_string())
        .collect();
    let withheld = table
        .rows
        .iter()
        .map(|r| r.speed_withheld.map_or("", SpeedWithheld::name).to_string())
        .collect();
    // (every column, also for a table without rows)
    let mut numbers: Vec<(String, Vec<f64>)> = STRIDE_COLUMNS
        .iter()
        .filter(|&&c| c != "foot" && c != "speed_withheld")
        .map(|c| (c.to_string(), Vec::with_capacity(table.rows.len())))
        .collect();
    for r in &table.rows {
        for (column, (_, v)) in numbers.iter_mut().zip(r.numbers()) {
            column.1.push(v.unwrap_or(f64::NAN));
        }
    }
    (foot, withheld, numbers)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(strides, m)?)?;
    Ok(())
}
