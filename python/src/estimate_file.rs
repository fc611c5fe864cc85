//! Estimate files from Python: `read_estimate`, `write_estimate` (the
//! estimate writer's format, byte for byte) and `check_estimate`.

use std::io::Write;
use std::path::PathBuf;

use limbfuse_core::sample::AngleChannel;
use limbfuse_io::estimate_file::COM_COLUMNS;
use limbfuse_io::table::TableReader;
use limbfuse_io::{AtomicFile, EstimateReader};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::estimate::{file_order, EstimateArgs, EstimateTuple};
use crate::estimate_columns::PHASE;
use crate::{guarded, user_error, user_msg};

/// Reads an estimate file.
#[pyfunction]
fn read_estimate(py: Python<'_>, path: PathBuf) -> PyResult<EstimateTuple<'_>> {
    guarded(|| {
        let table = TableReader::open(&path).map_err(|e| user_error(&e))?;
        let header_names = table.header().to_vec();
        // An Arrow file's `# key: value` lines are its metadata (docs/ARROW.md;
        // an audit: reading one as text failed with "stream did not contain
        // valid UTF-8").
        let header = match limbfuse_io::arrow_file::is_arrow_path(&path) {
            true => table
                .meta()
                .entries()
                .iter()
                .map(|(k, v)| format!("{k}: {v}"))
                .collect(),
            false => comment_lines(&path)?,
        };
        drop(table);
        let mut reader = EstimateReader::open(&path).map_err(|e| user_error(&e))?;
        let known = |n: &str| {
            n == "t"
                || n == "speed"
                || n.starts_with("diag_")
                || AngleChannel::ALL.iter().any(|c| c.name() == n)
                || COM_COLUMNS.contains(&n)
                || n == "contact_left"
                || n == "contact_right"
        };
        let names: Vec<String> = header_names.iter().filter(|n| known(n)).cloned().collect();
        let has_phase = header_names.iter().any(|n| n == PHASE);
        let mut values: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        let mut phase = has_phase.then(Vec::new);
        let diag_names: Vec<String> = reader.diagnostic_names().map(str::to_string).collect();
        while let Some((_, e)) = reader.next_estimate().map_err(|e| user_error(&e))? {
            for (n, col) in names.iter().zip(values.iter_mut()) {
                let v = if n == "t" {
                    Some(e.t)
                } else if n == "speed" {
                    e.speed
                } else if let Some(d) = n.strip_prefix("diag_") {
                    diag_names
                        .iter()
                        .position(|m| m == d)
                        .and_then(|k| e.diag[k])
                } else if n == "contact_left" || n == "contact_right" {
                    e.contact[usize::from(n == "contact_right")].map(|c| if c { 1.0 } else { 0.0 })
                } else if let Some(k) = COM_COLUMNS.iter().position(|c| c == n) {
                    if k < 3 {
                        e.com_pos.map(|p| p[k])
                    } else {
                        e.com_vel.map(|p| p[k - 3])
                    }
                } else {
                    AngleChannel::ALL
                        .iter()
                        .find(|c| c.name() == n)
                        .and_then(|c| e.angle(*c))
                };
                col.push(v.unwrap_or(f64::NAN));
            }
            if let Some(p) = &mut phase {
                p.push(e.phase.map(limbfuse_core::GaitPhase::label));
            }
        }
        let mut order: Vec<String> = names.clone();
        if has_phase {
            order = file_order(&names, true);
        }
        let mut values = values.into_iter();
        let t = values.next().unwrap_or_default();
        Ok((
            header,
            order,
            PyArray1::from_vec(py, t),
            names[1..].to_vec(),
            values.map(|v| PyArray1::from_vec(py, v)).collect(),
            phase,
            None,
            None,
            None,
        ))
    })
}

/// The leading `# ...` lines of a file, without `# ` (kept as written, so
/// that writing the estimate back gives the same header).
fn comment_lines(path: &std::path::Path) -> PyResult<Vec<String>> {
    use std::io::BufRead;
    let f = std::fs::File::open(path).map_err(|e| user_msg(format!("{}: {e}", path.display())))?;
    let mut out = Vec::new();
    for line in std::io::BufReader::new(f).lines() {
        let line = line.map_err(|e| user_msg(format!("{}: {e}", path.display())))?;
        let Some(body) = line.strip_prefix('#') else {
            break;
        };
        out.push(body.strip_prefix(' ').unwrap_or(body).to_string());
    }
    Ok(out)
}

/// Writes an estimate file (the estimate writer's format, byte for byte).
#[pyfunction]
fn write_estimate(py: Python<'_>, path: PathBuf, estimate: EstimateArgs<'_>) -> PyResult<()> {
    guarded(|| {
        let view = estimate.view()?;
        let header = &estimate.0;
        let err = |e: std::io::Error| user_msg(format!("{}: cannot write: {e}", path.display()));
        crate::interrupt::detach(py, || {
            let mut file = AtomicFile::create(&path).map_err(err)?;
            let mut head = String::new();
            for l in header {
                head.push_str(&format!("# {}\n", l.replace(['\n', '\r'], " ")));
            }
            head.push_str(&view.file_columns().join(","));
            head.push('\n');
            file.write_all(head.as_bytes()).map_err(err)?;
            let mut line = Vec::with_capacity(512);
            let mut buf = ryu::Buffer::new();
            for i in 0..view.len() {
                line.clear();
                view.write_row(i, &mut line, &mut buf);
                file.write_all(&line).map_err(err)?;
                // (Ctrl-C: nothing written, `detach` raises)
                if crate::interrupt::poll_current() {
                    return Ok(());
                }
            }
            file.commit().map_err(err)
        })?
    })
}

/// Checks an estimate's columns (names, lengths, time, phase cells).
#[pyfunction]
fn check_estimate(estimate: EstimateArgs<'_>) -> PyResult<()> {
    guarded(|| estimate.view().map(|_| ()))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_estimate, m)?)?;
    m.add_function(wrap_pyfunction!(read_estimate, m)?)?;
    m.add_function(wrap_pyfunction!(write_estimate, m)?)?;
    Ok(())
}
