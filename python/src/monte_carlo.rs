//! `montecarlo`: paper 000 Fig. 9 on simulated walking (`limbfuse
//! montecarlo`, `limbfuse_workflows::monte_carlo`): the three segment
//! filters' mean RMSE against the uncertainty of their noise parameters.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use limbfuse_io::provenance::{comment_lines, COMMAND_KEY, LIMBFUSE_VERSION, VERSION_KEY};
use limbfuse_sim::WalkingConfig;
use limbfuse_workflows::monte_carlo::{
    level_from_percent, levels_from_range, levels_from_spec, monte_carlo_cancellable, write_csv,
    MonteCarloConfig, MonteCarloError, MAX_RUNS,
};
use limbfuse_workflows::monte_carlo_plot::render_svg;
use limbfuse_workflows::simulator_options::OptionOutOfRange;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::interrupt::detach;
use crate::{guarded, user_msg};

/// The most samples of one run's trial (24 h at the walking simulator's
/// 100 Hz IMU rate: the CLI's cap without `--force`).
const MAX_TRIAL_S: f64 = 86_400.0;

/// `levels`: `"START:END:STEP"` in percent, or a sequence of percents.
fn levels(levels: Option<&Bound<'_, PyAny>>) -> PyResult<(Vec<f64>, String)> {
    let bad = |m: String| user_msg(format!("montecarlo: levels: {m}"));
    let Some(l) = levels.filter(|l| !l.is_none()) else {
        return Ok((
            levels_from_range(0.0, 20.0, 2.0).map_err(bad)?,
            "\"0:20:2\"".into(),
        ));
    };
    if l.is_instance_of::<PyString>() {
        let text: String = l.extract()?;
        return Ok((levels_from_spec(&text).map_err(bad)?, format!("{text:?}")));
    }
    let pct: Vec<f64> =
        l.extract().map_err(|_| {
            bad("expected \"START:END:STEP\" in percent (e.g. \"0:20:2\") or a sequence of percents"
            .into())
        })?;
    if pct.is_empty() || pct.len() > 1001 {
        return Err(bad(format!(
            "expected 1 to 1001 levels, found {}",
            pct.len()
        )));
    }
    if let Some(p) = pct.iter().find(|p| !(0.0..100.0).contains(*p)) {
        return Err(bad(format!("expected percents in [0, 100), found {p}")));
    }
    let shown: Vec<String> = pct.iter().map(|p| p.to_string()).collect();
    let fractions = pct.iter().map(|&p| level_from_percent(p)).collect();
    Ok((fractions, format!("[{}]", shown.join(", "))))
}

/// The trial of each run, checked as `simulate("walking")` checks it.
fn trial(speed: f64, duration: f64) -> PyResult<WalkingConfig> {
    if !(duration > 0.0 && duration <= MAX_TRIAL_S) {
        return Err(user_msg(format!(
            "montecarlo: duration = {duration}: expected 0 < duration <= {MAX_TRIAL_S} s"
        )));
    }
    let cfg = WalkingConfig {
        speed_mps: speed,
        duration_s: duration,
        ..WalkingConfig::default()
    };
    if (duration * cfg.imu_rate_hz).round() < 1.0 {
        return Err(user_msg(format!(
            "montecarlo: duration = {}: less than one sample at the simulator's {} Hz",
            limbfuse_methods::shown(duration),
            cfg.imu_rate_hz
        )));
    }
    if let Err(e) = cfg.validate() {
        let msg = match OptionOutOfRange::of(&e) {
            Some(o) => format!(
                "montecarlo: {} = {}: outside the allowed range {}",
                o.option,
                limbfuse_methods::shown(o.value),
                o.range
            ),
            None => format!("montecarlo: the simulated trial: {e}"),
        };
        return Err(user_msg(msg));
    }
    Ok(cfg)
}

/// Runs the study (`limbfuse montecarlo`); returns its rows as columns,
/// the CSV text and the provenance lines; `svg`: also draws the plot there;
/// `progress`: the runs done on `sys.stderr`.
#[pyfunction]
#[pyo3(signature = (runs=100, levels=None, seed=1, speed=1.0, duration=30.0, svg=None, progress=false))]
#[allow(clippy::too_many_arguments)]
fn montecarlo<'py>(
    py: Python<'py>,
    runs: usize,
    levels: Option<&Bound<'py, PyAny>>,
    seed: u64,
    speed: f64,
    duration: f64,
    svg: Option<PathBuf>,
    progress: bool,
) -> PyResult<Bound<'py, PyDict>> {
    guarded(|| {
        if !(1..=MAX_RUNS).contains(&runs) {
            return Err(user_msg(format!(
                "montecarlo: runs = {runs}: expected 1 to {MAX_RUNS} runs per level"
            )));
        }
        let (levels, levels_text) = self::levels(levels)?;
        let cfg = MonteCarloConfig {
            runs,
            levels,
            seed,
            trial: trial(speed, duration)?,
        };
        let done = AtomicUsize::new(0);
        let shown = AtomicUsize::new(usize::MAX);
        let count = || {
            done.fetch_add(1, Ordering::Relaxed);
        };
        // (asked on this thread every 50 ms while the runs go on)
        let check = || {
            if progress {
                show_progress(&done, &shown, runs, false);
            }
            crate::interrupt::cancelled()
        };
        let rows = detach(py, || monte_carlo_cancellable(&cfg, &count, Some(&check)));
        if progress {
            show_progress(&done, &shown, runs, true);
        }
        let rows = rows?.map_err(|e| match e {
            MonteCarloError::Cancelled => user_msg("montecarlo: stopped before the end"),
            e => user_msg(format!("montecarlo: {e}")),
        })?;
        let last = seed.wrapping_add(runs as u64 - 1);
        let provenance = vec![
            (VERSION_KEY, LIMBFUSE_VERSION.to_string()),
            (
                COMMAND_KEY,
                format!(
                    "limbfuse.montecarlo(runs={runs}, levels={levels_text}, seed={seed}, \
                     speed={speed}, duration={duration})"
                ),
            ),
            (
                "trial_seeds",
                format!(
                    "{seed} to {last} (run r: seed + r; its parameter errors from the stream \
                     keyed by (seed, r, level))"
                ),
            ),
        ];
        let mut csv = Vec::new();
        write_csv(&rows, &provenance, &mut csv).map_err(|e| user_msg(e.to_string()))?;
        if let Some(path) = &svg {
            let title = format!("{runs} runs per level, {speed} m/s, {duration} s trials");
            let text = render_svg(&rows, path, &title, &provenance).map_err(user_msg)?;
            std::fs::write(path, text)
                .map_err(|e| user_msg(format!("{}: cannot write the plot: {e}", path.display())))?;
        }
        let d = PyDict::new(py);
        d.set_item("method", rows.iter().map(|r| r.method).collect::<Vec<_>>())?;
        d.set_item(
            "level_pct",
            rows.iter().map(|r| r.level_pct()).collect::<Vec<_>>(),
        )?;
        d.set_item(
            "mean_rmse_deg",
            rows.iter().map(|r| r.mean_rmse_deg).collect::<Vec<_>>(),
        )?;
        d.set_item(
            "std_rmse_deg",
            rows.iter().map(|r| r.std_rmse_deg).collect::<Vec<_>>(),
        )?;
        d.set_item("runs", rows.iter().map(|r| r.runs).collect::<Vec<_>>())?;
        d.set_item(
            "csv",
            String::from_utf8(csv).map_err(|e| user_msg(e.to_string()))?,
        )?;
        d.set_item("provenance", comment_lines(&provenance))?;
        Ok(d)
    })
}

/// `montecarlo: N/M runs` on Python's `sys.stderr` (a notebook shows it),
/// rewritten in place when the count changed; `last`: end the line.
/// Errors writing it are ignored (a closed stderr does not stop the study).
fn show_progress(done: &AtomicUsize, shown: &AtomicUsize, runs: usize, last: bool) {
    let d = done.load(Ordering::Relaxed);
    if shown.swap(d, Ordering::Relaxed) == d && !last {
        return;
    }
    let line = format!(
        "\rmontecarlo: {d}/{runs} runs{}",
        if last { "\n" } else { "" }
    );
    let _ = Python::attach(|py| -> PyResult<()> {
        let err = py.import("sys")?.getattr("stderr")?;
        err.call_method1("write", (line,))?;
        err.call_method0("flush")?;
        Ok(())
    });
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(montecarlo, m)?)?;
    Ok(())
}
