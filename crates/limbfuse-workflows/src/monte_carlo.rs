//! Monte Carlo under parametric uncertainty (paper 000, section 4, Fig. 9):
//! the filters' model parameters are perturbed by up to ±L % while the
//! simulated truth is not, and the mean estimation error is reported per
//! filter and uncertainty level L.
//!
//! Run `r` simulates one walking trial with seed `seed + r` (the same trial
//! for every level and filter: common random numbers). At level `L` every
//! noise parameter of the model — per segment `sigma_g` (gyro noise),
//! `sigma_bg` (bias drive), `sigma_a` (accelerometer-angle noise), `tau_g`
//! when finite — and the encoder noise is multiplied by `1 + L u` with `u`
//! uniform in [-1, 1], drawn independently per parameter from a ChaCha8
//! stream keyed by (seed, run, level); the three filters of a run and level
//! share the same perturbed parameters. Runs execute in parallel (rayon) and
//! are reduced in run order, so results are bit-identical for a seed
//! whatever the number of threads.

use std::convert::Infallible;
use std::io::Write;

use limbfuse_core::runner::{run, Observer};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{
    CommonParams, GlobalKf, GlobalKfParams, LocalKf, LocalKfParams, MarkovJumpKf,
    MarkovJumpKfParams,
};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use limbfuse_methods::MethodName;

use crate::parallel_cancellation::{run_with_stop_flag, StopFlag};

use limbfuse_eval::AngleMetrics;
use limbfuse_eval::EvalOptions;

/// The filters compared, in output order.
pub const METHODS: [MethodName; 3] = [MethodName::Local, MethodName::Mjls, MethodName::Global];

/// What to run.
#[derive(Debug, Clone, PartialEq)]
pub struct MonteCarloConfig {
    /// Runs per level (paper: 100).
    pub runs: usize,
    /// Uncertainty levels as fractions (paper: 0 to 0.20).
    pub levels: Vec<f64>,
    /// Base seed.
    pub seed: u64,
    /// The simulated trial (its `seed` is replaced by `seed + run`).
    pub trial: WalkingConfig,
}

impl Default for MonteCarloConfig {
    fn default() -> Self {
        MonteCarloConfig {
            runs: 100,
            levels: (0..=10).map(|k| k as f64 * 0.02).collect(),
            seed: 1,
            trial: WalkingConfig {
                duration_s: 30.0,
                ..WalkingConfig::default()
            },
        }
    }
}

/// Mean error of one filter at one level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonteCarloRow {
    /// Filter name.
    pub method: &'static str,
    /// Uncertainty level (fraction).
    pub level: f64,
    /// Mean over runs of the 4-segment mean RMSE (deg).
    pub mean_rmse_deg: f64,
    /// Standard deviation over runs (deg).
    pub std_rmse_deg: f64,
    /// Number of runs.
    pub runs: usize,
}

impl MonteCarloRow {
    /// The level in percent, rounded to 1e-9 % (a level of 0.14 printed
    /// `14.000000000000002`; levels are given in percent to a few decimals).
    pub fn level_pct(&self) -> f64 {
        (self.level * 100.0 * 1e9).round() / 1e9
    }
}

/// Why a Monte Carlo study failed.
#[derive(Debug, thiserror::Error)]
pub enum MonteCarloError {
    /// Bad configuration.
    #[error("{0}")]
    Config(String),
    /// The simulator rejected the trial configuration.
    #[error(transparent)]
    Sim(#[from] limbfuse_sim::SimError),
    /// A filter failed.
    #[error("{0}")]
    Filter(String),
    /// The caller's cancellation hook stopped the study.
    #[error("stopped before the end")]
    Cancelled,
}

/// Uncertainty levels written `START:END:STEP` in percent (the CLI's
/// `--levels`, e.g. `0:20:2`), as fractions; the error says what was
/// expected (without the flag or option's name, which the caller adds).
pub fn levels_from_spec(text: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let bad = || format!("expected START:END:STEP in percent (e.g. 0:20:2), found `{text}`");
    if parts.len() != 3 {
        return Err(bad());
    }
    let v: Vec<f64> = parts
        .iter()
        .map(|p| p.trim().parse::<f64>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    levels_from_range(v[0], v[1], v[2]).map_err(|m| format!("`{text}`: {m}"))
}

/// Levels `start`, `start + step`, ..., `end` in percent, as fractions
/// ([`level_from_percent`]).
pub fn levels_from_range(start: f64, end: f64, step: f64) -> Result<Vec<f64>, String> {
    let (a, b) = (start, end);
    if !(a.is_finite() && b.is_finite() && step.is_finite())
        || step <= 0.0
        || b < a
        || a < 0.0
        || b >= 100.0
    {
        return Err("need 0 <= START <= END < 100 and STEP > 0".into());
    }
    let n = ((b - a) / step + 1e-9).floor() as usize;
    let last = a + n as f64 * step;
    if (b - last).abs() > 1e-6 * step.max(1e-3) {
        return Err(format!(
            "END is not START + k STEP (the last level would be {}); give an END on that grid",
            (last * 1e9).round() / 1e9
        ));
    }
    if n > 1000 {
        return Err(format!("{} levels is too many (at most 1000)", n + 1));
    }
    Ok((0..=n)
        .map(|k| level_from_percent(a + k as f64 * step))
        .collect())
}

/// A level given in percent as a fraction, the percent rounded to 1e-9
/// (`0:1:0.1` gave 0.30000000000000004 %): every way of giving levels
/// (the CLI's `START:END:STEP`, Python's list) gives the same fractions.
pub fn level_from_percent(pct: f64) -> f64 {
    (pct * 1e9).round() / 1e9 / 100.0
}

/// Multiplies every model noise parameter by `1 + level u`, `u ~ U[-1, 1]`.
pub fn perturb(
    common: &CommonParams,
    encoder_sigma: &[f64; 3],
    level: f64,
    rng: &mut ChaCha8Rng,
) -> (CommonParams, [f64; 3]) {
    let mut c = *common;
    let mut f = |v: f64| v * (1.0 + level * rng.random_range(-1.0..=1.0));
    for s in c.segments.iter_mut() {
        s.gyro_noise = f(s.gyro_noise);
        s.bias_drive = f(s.bias_drive);
        s.accel_angle_sigma = f(s.accel_angle_sigma);
        if s.bias_tau.is_finite() {
            s.bias_tau = f(s.bias_tau);
        }
    }
    let enc = encoder_sigma.map(&mut f);
    (c, enc)
}

fn stream_seed(seed: u64, run: usize, level: usize) -> u64 {
    // SplitMix64 of the key, so neighbouring keys give unrelated streams.
    let mut z = seed ^ ((run as u64) << 20) ^ level as u64 ^ 0x9E37_79B9_7F4A_7C15;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn mean_rmse_deg(est: &mut dyn Estimator, records: &[Record]) -> Result<f64, MonteCarloError> {
    let mut m = AngleMetrics::new(est.name(), EvalOptions::default());
    let obs: &mut [&mut dyn Observer] = &mut [&mut m];
    run(est, records.iter().map(|r| Ok::<_, Infallible>(*r)), obs)
        .map_err(|e| MonteCarloError::Filter(e.to_string()))?;
    m.evaluation()
        .mean_rmse()
        .map(f64::to_degrees)
        .ok_or_else(|| MonteCarloError::Filter("no segment angle evaluated".into()))
}

/// One run: errors `[method][level]` in degrees.
fn one_run(
    cfg: &MonteCarloConfig,
    r: usize,
    stop: &StopFlag,
) -> Result<Vec<[f64; 3]>, MonteCarloError> {
    let trial = WalkingConfig {
        seed: cfg.seed.wrapping_add(r as u64),
        ..cfg.trial
    };
    let records: Vec<Record> = WalkingSimulator::new(trial)?.collect();
    let base = CommonParams::default();
    let enc0 = MarkovJumpKfParams::default().encoder_sigma;
    let mut out = Vec::with_capacity(cfg.levels.len());
    for (li, &level) in cfg.levels.iter().enumerate() {
        if stop.raised() {
            return Err(MonteCarloError::Cancelled);
        }
        let mut rng = ChaCha8Rng::seed_from_u64(stream_seed(cfg.seed, r, li));
        let (common, enc) = perturb(&base, &enc0, level, &mut rng);
        let bad =
            |e: limbfuse_estimators::segment_kf::ParamError| MonteCarloError::Filter(e.to_string());
        let mut local = LocalKf::new(LocalKfParams {
            common,
            ..LocalKfParams::default()
        })
        .map_err(bad)?;
        let mut mjls = MarkovJumpKf::new(MarkovJumpKfParams {
            common,
            encoder_sigma: enc,
            ..MarkovJumpKfParams::default()
        })
        .map_err(bad)?;
        let mut global = GlobalKf::new(GlobalKfParams {
            common,
            ..GlobalKfParams::default()
        })
        .map_err(bad)?;
        out.push([
            mean_rmse_deg(&mut local, &records)?,
            mean_rmse_deg(&mut mjls, &records)?,
            mean_rmse_deg(&mut global, &records)?,
        ]);
    }
    Ok(out)
}

/// Most runs per level (paper 000 Fig. 9 uses 100): the results of every run
/// are kept in memory, so the count is bounded (issue 18 item 7).
pub const MAX_RUNS: usize = 100_000;

/// Runs the study; `on_run_done` is called after each run (progress).
pub fn monte_carlo(
    cfg: &MonteCarloConfig,
    on_run_done: &(dyn Fn() + Sync),
) -> Result<Vec<MonteCarloRow>, MonteCarloError> {
    monte_carlo_cancellable(cfg, on_run_done, None)
}

/// [`monte_carlo`] that stops when `cancel` says so
/// ([`MonteCarloError::Cancelled`]). `cancel` is called on the calling
/// thread (so it may read that thread's state: the Python binding's Ctrl-C
/// check) about every 50 ms while the runs go on in rayon's pool
/// ([`crate::parallel_cancellation`]); each run looks at the verdict
/// before each level. The rows are those of
/// [`monte_carlo`]: runs are reduced in run order.
pub fn monte_carlo_cancellable(
    cfg: &MonteCarloConfig,
    on_run_done: &(dyn Fn() + Sync),
    cancel: Option<&dyn Fn() -> bool>,
) -> Result<Vec<MonteCarloRow>, MonteCarloError> {
    if !(1..=MAX_RUNS).contains(&cfg.runs) {
        return Err(MonteCarloError::Config(format!(
            "runs: expected 1 to {MAX_RUNS} runs per level, found {}",
            cfg.runs
        )));
    }
    if cfg.levels.is_empty() || cfg.levels.iter().any(|l| !(0.0..1.0).contains(l)) {
        return Err(MonteCarloError::Config(
            "levels: expected fractions in [0, 1), e.g. 0, 0.02, ..., 0.2".into(),
        ));
    }
    let per_run = run_with_stop_flag(
        |stop: &StopFlag| -> Result<Vec<Vec<[f64; 3]>>, MonteCarloError> {
            (0..cfg.runs)
                .into_par_iter()
                .map(|r| {
                    let res = one_run(cfg, r, stop);
                    on_run_done();
                    res
                })
                .collect()
        },
        cancel,
    )?;
    let n = cfg.runs as f64;
    let mut rows = Vec::new();
    for (m, method) in METHODS.iter().enumerate() {
        for (li, &level) in cfg.levels.iter().enumerate() {
            let mean = per_run.iter().map(|r| r[li][m]).sum::<f64>() / n;
            let var = per_run
                .iter()
                .map(|r| (r[li][m] - mean).powi(2))
                .sum::<f64>()
                / (n - 1.0).max(1.0);
            rows.push(MonteCarloRow {
                method: method.name(),
                level,
                mean_rmse_deg: mean,
                std_rmse_deg: var.sqrt(),
                runs: cfg.runs,
            });
        }
    }
    Ok(rows)
}

/// Writes `method,level_pct,mean_rmse_deg,std_rmse_deg,runs` rows after
/// the `provenance` lines (`# key: value` comments,
/// `limbfuse_io::provenance`: the limbfuse version, command and seeds that
/// made the file; none: the file as before them).
pub fn write_csv(
    rows: &[MonteCarloRow],
    provenance: &[(&str, String)],
    mut w: impl Write,
) -> std::io::Result<()> {
    w.write_all(limbfuse_io::provenance::comment_lines(provenance).as_bytes())?;
    writeln!(w, "method,level_pct,mean_rmse_deg,std_rmse_deg,runs")?;
    for r in rows {
        writeln!(
            w,
            "{},{},{},{},{}",
            r.method,
            r.level_pct(),
            r.mean_rmse_deg,
            r.std_rmse_deg,
            r.runs
        )?;
    }
    Ok(())
}
