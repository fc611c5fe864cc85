//! Tuning the noise parameters of a segment filter on a recorded window
//! (`limbfuse tune`), paper 001's "filter parameters were optimized using a
//! genetic algorithm".
//!
//! **Search space** ([`SearchSpace`]), in log10 units: per segment
//! `gyro_noise`, `bias_drive`, `accel_angle_sigma` (within +-2 decades of
//! the starting value) and `zeta` (+-1 decade): 16 coordinates; `mjls` adds
//! one `encoder_sigma` shared by the three joints, `global` one
//! `relative_sigma` shared by the three relative rows (+-2 decades). Every
//! other parameter (`bias_tau`, `P0`, numerics, `min_reliable`, ...) keeps
//! its starting value.
//!
//! **Objective**: the mean RMSE of the four segment angles (degrees),
//! averaged over the starting points of [`crate::protocol`] (paper 001 uses
//! 50 starting points in the optimisation stage too), on the samples the
//! starting parameters score: a candidate that scores fewer samples of a
//! channel in some run than the start did (a filter that keeps restarting
//! and so keeps restarting its run-in `startup_s`) has failed, cost `inf`,
//! instead of being averaged over the few samples it did estimate
//! ([`crate::coverage`], issue 14).
//!
//! **Optimiser**: particle swarm optimisation from the `argmin` crate
//! (argmin-rs, maintained, pure Rust; `ParticleSwarm` with the standard
//! SPSO inertia 1/(2 ln 2) and acceleration 0.5 + ln 2),
//! chosen because (a) the objective is a black box, not differentiable and
//! piecewise constant in `zeta` (a threshold that switches updates on and
//! off), which rules out gradient and quasi-Newton methods; (b) a
//! population method is the closest well-kept relative of the paper's
//! genetic algorithm; (c) argmin evaluates each generation in parallel
//! (`rayon` feature) and is deterministic for a seeded RNG, since the swarm's
//! random draws happen on one thread and the costs come back in order. The
//! `cmaes` crate was the alternative (CMA-ES is stronger on smooth
//! problems) but pulls a second nalgebra and rand generation into the build.
//! The starting point is particle 0 of the swarm, so the result is never
//! worse on the tuning window than the start.

use std::sync::{Arc, Mutex};

use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use limbfuse_core::Record;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::coverage::ScoredFloor;
use crate::protocol::{multi_start, MultiStartResult};
use limbfuse_methods::segment_params::FilterParams;

/// Half-width (decades) of the search range of the noise parameters.
pub const NOISE_DECADES: f64 = 2.0;
/// Half-width (decades) of the search range of the thresholds zeta.
pub const ZETA_DECADES: f64 = 1.0;
/// Smallest value a zero starting value is replaced by (log scale needs > 0).
pub const LOG_FLOOR: f64 = 1e-12;

/// One coordinate of the search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Knob {
    /// `gyro_noise` of segment i.
    GyroNoise(usize),
    /// `bias_drive` of segment i.
    BiasDrive(usize),
    /// `accel_angle_sigma` of segment i.
    AccelSigma(usize),
    /// `zeta` of segment i.
    Zeta(usize),
    /// `encoder_sigma` of the three joints (mjls).
    EncoderSigma,
    /// `relative_sigma` of the three relative rows (global).
    RelativeSigma,
}

impl Knob {
    /// The parameter-file key.
    pub fn key(self) -> String {
        let seg = |i: usize| limbfuse_core::Segment::ALL[i].name();
        match self {
            Knob::GyroNoise(i) => format!("segments.{}.gyro_noise", seg(i)),
            Knob::BiasDrive(i) => format!("segments.{}.bias_drive", seg(i)),
            Knob::AccelSigma(i) => format!("segments.{}.accel_angle_sigma", seg(i)),
            Knob::Zeta(i) => format!("segments.{}.zeta", seg(i)),
            Knob::EncoderSigma => "encoder_sigma".into(),
            Knob::RelativeSigma => "relative_sigma".into(),
        }
    }

    fn get(self, p: &FilterParams) -> f64 {
        let c = p.common();
        let geo =
            |v: [f64; 3]| (v[0].max(LOG_FLOOR) * v[1].max(LOG_FLOOR) * v[2].max(LOG_FLOOR)).cbrt();
        match self {
            Knob::GyroNoise(i) => c.segments[i].gyro_noise,
            Knob::BiasDrive(i) => c.segments[i].bias_drive,
            Knob::AccelSigma(i) => c.segments[i].accel_angle_sigma,
            Knob::Zeta(i) => c.segments[i].zeta,
            Knob::EncoderSigma => match p {
                FilterParams::Mjls(m) => geo(m.encoder_sigma),
                _ => f64::NAN,
            },
            Knob::RelativeSigma => match p {
                FilterParams::Global(g) => geo(g.resolved_relative_sigma()),
                _ => f64::NAN,
            },
        }
    }

    fn set(self, p: &mut FilterParams, v: f64) {
        match self {
            Knob::GyroNoise(i) => p.common_mut().segments[i].gyro_noise = v,
            Knob::BiasDrive(i) => p.common_mut().segments[i].bias_drive = v,
            Knob::AccelSigma(i) => p.common_mut().segments[i].accel_angle_sigma = v,
            Knob::Zeta(i) => p.common_mut().segments[i].zeta = v,
            Knob::EncoderSigma => {
                if let FilterParams::Mjls(m) = p {
                    m.encoder_sigma = [v; 3];
                }
            }
            Knob::RelativeSigma => {
                if let FilterParams::Global(g) = p {
                    g.relative_sigma = [Some(v); 3];
                }
            }
        }
    }

    fn decades(self) -> f64 {
        match self {
            Knob::Zeta(_) => ZETA_DECADES,
            _ => NOISE_DECADES,
        }
    }
}

/// The coordinates searched and their log10 bounds around a starting point.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchSpace {
    /// The parameters every candidate starts from (non-searched values).
    pub base: FilterParams,
    /// The coordinates.
    pub knobs: Vec<Knob>,
    /// log10 of the starting values.
    pub x0: Vec<f64>,
    /// Lower bounds (log10).
    pub lower: Vec<f64>,
    /// Upper bounds (log10).
    pub upper: Vec<f64>,
}

impl SearchSpace {
    /// The search space around `start` (see the module docs).
    pub fn around(start: &FilterParams) -> Self {
        let mut knobs = Vec::new();
        for i in 0..4 {
            knobs.extend([
                Knob::GyroNoise(i),
                Knob::BiasDrive(i),
                Knob::AccelSigma(i),
                Knob::Zeta(i),
            ]);
        }
        match start {
            FilterParams::Mjls(_) => knobs.push(Knob::EncoderSigma),
            FilterParams::Global(_) => knobs.push(Knob::RelativeSigma),
            FilterParams::Local(_) => {}
        }
        let x0: Vec<f64> = knobs
            .iter()
            .map(|k| k.get(start).max(LOG_FLOOR).log10())
            .collect();
        let lower = knobs
            .iter()
            .zip(&x0)
            .map(|(k, x)| x - k.decades())
            .collect();
        let upper = knobs
            .iter()
            .zip(&x0)
            .map(|(k, x)| x + k.decades())
            .collect();
        SearchSpace {
            base: *start,
            knobs,
            x0,
            lower,
            upper,
        }
    }

    /// The parameters at log10 coordinates `x` (clamped to the bounds). A
    /// coordinate equal to its starting value keeps the starting parameter
    /// exactly (`10^log10(v)` need not be `v`), so `params_at(&x0)` is the start.
    pub fn params_at(&self, x: &[f64]) -> FilterParams {
        let mut p = self.base;
        for (d, (k, &xi)) in self.knobs.iter().zip(x).enumerate() {
            if xi == self.x0[d] {
                continue;
            }
            k.set(&mut p, 10f64.powf(xi.clamp(self.lower[d], self.upper[d])));
        }
        p
    }
}

/// How to tune.
#[derive(Debug, Clone, Copy)]
pub struct TuneConfig {
    /// Seed of the swarm's random draws: same seed, same result.
    pub seed: u64,
    /// Number of objective evaluations (>= 2 x particles).
    pub budget: usize,
    /// Swarm size (>= 2).
    pub particles: usize,
    /// A cancellation hook, polled after every generation of the swarm
    /// (`particles` evaluations) on the calling thread: once it returns
    /// true the tuning ends with [`TuneError::Cancelled`] (Python's Ctrl-C;
    /// `None`: never).
    pub cancel: Option<fn() -> bool>,
}

impl Default for TuneConfig {
    fn default() -> Self {
        TuneConfig {
            seed: 1,
            budget: 400,
            particles: 20,
            cancel: None,
        }
    }
}

/// What tuning found.
#[derive(Debug, Clone, PartialEq)]
pub struct TuneResult {
    /// The tuned parameters.
    pub params: FilterParams,
    /// Objective at the starting point (mean segment RMSE, deg).
    pub start_cost_deg: f64,
    /// Objective at the result (deg).
    pub best_cost_deg: f64,
    /// Objective evaluations made.
    pub evaluations: usize,
    /// Best objective after each generation (deg), the initial one first.
    pub history_deg: Vec<f64>,
}

/// Why tuning failed.
#[derive(Debug, thiserror::Error)]
pub enum TuneError {
    /// A bad option.
    #[error("{0}")]
    Config(String),
    /// The objective could not be evaluated (filter error) or the optimiser failed.
    #[error("{0}")]
    Failed(String),
    /// [`TuneConfig::cancel`] asked to stop.
    #[error("cancelled")]
    Cancelled,
}

/// The multi-start result of `params` over the intervals; `None` when the
/// parameters are invalid.
pub fn measure_params(
    params: &FilterParams,
    records: &[Record],
    intervals: &[(f64, f64)],
) -> Result<Option<MultiStartResult>, TuneError> {
    if params.validate().is_err() {
        return Ok(None);
    }
    let make = || {
        params
            .build()
            .map(|f| f as Box<dyn limbfuse_core::Estimator>)
            .map_err(|e| e.to_string())
    };
    multi_start(&make, records, intervals, false)
        .map(Some)
        .map_err(|e| TuneError::Failed(e.to_string()))
}

/// Mean segment RMSE (deg) of `params` over the intervals; `inf` when no
/// segment could be evaluated, the parameters are invalid, or some run
/// scored fewer samples of a channel than `floor` asks (see the module docs).
pub fn objective_deg(
    params: &FilterParams,
    records: &[Record],
    intervals: &[(f64, f64)],
    floor: &ScoredFloor,
) -> Result<f64, TuneError> {
    let Some(r) = measure_params(params, records, intervals)? else {
        return Ok(f64::INFINITY);
    };
    Ok(cost_deg(&r, floor))
}

/// The objective of a measured result (see [`objective_deg`]).
fn cost_deg(r: &MultiStartResult, floor: &ScoredFloor) -> f64 {
    if floor.first_shortfall(r).is_some() {
        return f64::INFINITY;
    }
    r.mean_rmse()
        .map(f64::to_degrees)
        .filter(|v| v.is_finite())
        .unwrap_or(f64::INFINITY)
}

struct Problem<'a> {
    space: &'a SearchSpace,
    records: &'a [Record],
    intervals: &'a [(f64, f64)],
    floor: &'a ScoredFloor,
    on_eval: &'a (dyn Fn() + Sync),
}

impl CostFunction for Problem<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        let c = objective_deg(
            &self.space.params_at(x),
            self.records,
            self.intervals,
            self.floor,
        )
        .map_err(|e| ArgminError::msg(e.to_string()))?;
        (self.on_eval)();
        Ok(c)
    }
}

/// Tunes `start` on `records` (the tuning window's records, sorted by time)
/// with the objective over `intervals`. `on_eval` is called after every
/// objective evaluation (progress).
pub fn tune(
    start: &FilterParams,
    records: &[Record],
    intervals: &[(f64, f64)],
    cfg: &TuneConfig,
    on_eval: &(dyn Fn() + Sync),
) -> Result<TuneResult, TuneError> {
    if cfg.particles < 2 || cfg.particles > 10_000 {
        return Err(TuneError::Config(format!(
            "particles: expected 2 to 10000, found {}",
            cfg.particles
        )));
    }
    if cfg.budget < 2 * cfg.particles || cfg.budget > 10_000_000 {
        return Err(TuneError::Config(format!(
            "budget: expected at least two generations of the swarm ({} evaluations) and at most 10000000, found {}",
            2 * cfg.particles,
            cfg.budget
        )));
    }
    start
        .validate()
        .map_err(|e| TuneError::Config(format!("starting parameters: {e}")))?;
    let space = SearchSpace::around(start);
    let history = Arc::new(Mutex::new(Vec::new()));
    // The start is measured first: what it scores is the floor every
    // candidate must score (module docs).
    let start_result = measure_params(&space.params_at(&space.x0), records, intervals)?
        .ok_or_else(|| TuneError::Config("starting parameters: invalid".into()))?;
    let floor = ScoredFloor::of(&start_result);
    let start_cost = cost_deg(&start_result, &floor);
    on_eval();
    let problem = Problem {
        space: &space,
        records,
        intervals,
        floor: &floor,
        on_eval,
    };
    // Initial swarm: the starting point and particles - 1 uniform draws.
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let dim = space.x0.len();
    let mut positions = vec![space.x0.clone()];
    let mut velocities = vec![vec![0.0; dim]];
    for _ in 1..cfg.particles {
        let (mut p, mut v) = (Vec::with_capacity(dim), Vec::with_capacity(dim));
        for d in 0..dim {
            let (lo, hi) = (space.lower[d], space.upper[d]);
            p.push(rng.random_range(lo..=hi));
            let half = 0.25 * (hi - lo);
            v.push(rng.random_range(-half..=half));
        }
        positions.push(p);
        velocities.push(v);
    }
    let mut costs = vec![start_cost];
    costs.extend(
        positions[1..]
            .par_iter()
            .map(|x| problem.cost(x))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| TuneError::Failed(e.to_string()))?,
    );
    if cfg.cancel.is_some_and(|c| c()) {
        return Err(TuneError::Cancelled);
    }
    if !start_cost.is_finite() {
        return Err(TuneError::Failed(
            "the trial window gives no segment-angle error to minimise (no reference or no estimate)".into(),
        ));
    }
    let swarm: Vec<Particle<Vec<f64>, f64>> = positions
        .into_iter()
        .zip(costs)
        .zip(velocities)
        .map(|((p, c), v)| Particle::new(p, c, v))
        .collect();
    let init_best = swarm.iter().map(|p| p.cost).fold(f64::INFINITY, f64::min);
    history.lock().map(|mut h| h.push(init_best)).ok();
    let iters = (cfg.budget / cfg.particles - 1) as u64;
    let solver = ParticleSwarm::new((space.lower.clone(), space.upper.clone()), cfg.particles)
        .with_rng_generator(ChaCha8Rng::seed_from_u64(cfg.seed ^ 0x5DEE_CE66_D1A4_F87D));
    let res = Executor::new(problem, solver)
        .configure(|s| s.population(swarm).max_iters(iters))
        .add_observer(
            HistoryObserver(Arc::clone(&history)),
            argmin::core::observers::ObserverMode::Always,
        )
        .add_observer(
            CancelObserver(cfg.cancel),
            argmin::core::observers::ObserverMode::Always,
        )
        .run()
        .map_err(|e| match cfg.cancel.is_some_and(|c| c()) {
            true => TuneError::Cancelled,
            false => TuneError::Failed(format!("optimiser: {e}")),
        })?;
    let state = res.state();
    let best = state
        .get_best_param()
        .ok_or_else(|| TuneError::Failed("optimiser returned no result".into()))?;
    let (x, cost) = if best.cost <= start_cost {
        (best.position.clone(), best.cost)
    } else {
        (space.x0.clone(), start_cost)
    };
    let history_deg = history.lock().map(|h| h.clone()).unwrap_or_default();
    Ok(TuneResult {
        params: space.params_at(&x),
        start_cost_deg: start_cost,
        best_cost_deg: cost,
        evaluations: cfg.particles * (iters as usize + 1),
        history_deg,
    })
}

/// Records the best cost after each generation.
/// Ends the run when [`TuneConfig::cancel`] says so (an observer's error
/// stops argmin's executor after the generation).
struct CancelObserver(Option<fn() -> bool>);

impl<I: State> argmin::core::observers::Observe<I> for CancelObserver {
    fn observe_iter(&mut self, _state: &I, _kv: &argmin::core::KV) -> Result<(), ArgminError> {
        match self.0.is_some_and(|c| c()) {
            true => Err(ArgminError::msg("cancelled")),
            false => Ok(()),
        }
    }
}

struct HistoryObserver(Arc<Mutex<Vec<f64>>>);

impl<I> argmin::core::observers::Observe<I> for HistoryObserver
where
    I: State<Float = f64>,
{
    fn observe_iter(&mut self, state: &I, _kv: &argmin::core::KV) -> Result<(), ArgminError> {
        if let Ok(mut h) = self.0.lock() {
            h.push(state.get_best_cost());
        }
        Ok(())
    }
}
