//! `repair_time`: a copy of a trial file whose time increases (`limbfuse
//! repair-time`, `limbfuse_io::time_repair`).

use std::path::PathBuf;

use limbfuse_io::time_repair::{repair_time as repair, TimeOrder};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{guarded, user_error, user_msg};

/// Repairs the time column of the trial file `path` into the CSV file
/// `output`; returns the report as a dict.
#[pyfunction]
#[pyo3(signature = (path, output, out_of_order="drop"))]
fn repair_time<'py>(
    py: Python<'py>,
    path: PathBuf,
    output: PathBuf,
    out_of_order: &str,
) -> PyResult<Bound<'py, PyDict>> {
    guarded(|| {
        let order = match out_of_order {
            "drop" => TimeOrder::Drop,
            "sort" => TimeOrder::Sort,
            other => {
                return Err(user_msg(format!(
                    "repair_time: out_of_order: expected \"drop\" or \"sort\", found {other:?}"
                )))
            }
        };
        if limbfuse_io::arrow_file::is_arrow_path(&output) {
            return Err(user_msg(format!(
                "repair_time: output {}: writes a CSV trial file; name the output `.csv`",
                output.display()
            )));
        }
        let same = match (std::fs::canonicalize(&path), std::fs::canonicalize(&output)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if same {
            return Err(user_msg(format!(
                "repair_time: output {} is the input; write the copy to another file",
                output.display()
            )));
        }
        let r = repair(&path, &output, order).map_err(|e| user_error(&e))?;
        let d = PyDict::new(py);
        d.set_item("rows_read", r.rows_read)?;
        d.set_item("rows_kept", r.rows_kept)?;
        d.set_item("moved", r.moved)?;
        d.set_item("sorted_onto_a_taken_time", r.sorted_onto_a_taken_time)?;
        d.set_item("largest_step_back_s", r.largest_step_back_s)?;
        d.set_item("median_step_s", r.median_step_s)?;
        let dropped = r
            .dropped
            .iter()
            .map(|x| {
                let row = PyDict::new(py);
                row.set_item("line", x.line)?;
                row.set_item("t", x.t)?;
                row.set_item("reason", x.reason.name())?;
                row.set_item("kept_line", x.kept_line)?;
                Ok(row)
            })
            .collect::<PyResult<Vec<_>>>()?;
        d.set_item("dropped", dropped)?;
        // (the CLI's warning: a last line cut off while the file was written)
        if let Some(c) = r.cut_last_line {
            crate::filter::warn_user(py, c.message(&path))?;
        }
        Ok(d)
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(repair_time, m)?)?;
    Ok(())
}
