//! Soak runs (issue 18 item 4): one real-time estimator over a long
//! simulated 100 Hz stream with glitches and gaps injected on a fixed
//! schedule, checking that its error stays bounded, that its memory does
//! not grow and that its per-step time does not drift.
//!
//! The stream comes from limbfuse's simulators (walking for the segment
//! filters and `chain`, the knee scenario for `knee-selfalign`), generated
//! sample by sample and never held in memory; the estimator is built by the
//! method layer exactly as `limbfuse estimate` builds it (sensor-range gate
//! included). Every `glitch_every_s` seconds one glitch is injected, cycling
//! through the configured kinds ([`Glitch::ALL`] by default). Per chunk of `chunk_s` seconds the run records
//! the error against the simulator's truth, the thread's CPU time per step
//! and the process's resident memory.

use std::error::Error;

use limbfuse_core::{Estimator, Record, Segment};
use limbfuse_methods::{build, MethodName, MethodSpec};
use limbfuse_sim::{KneeScenario, WalkingConfig};
use limbfuse_workflows::simulated_trials;

/// Gyro full scale of the simulated sensors (2000 deg/s, rad/s): what a
/// saturated reading shows.
const GYRO_FULL_SCALE: f64 = 2000.0 * core::f64::consts::PI / 180.0;

/// One kind of injected fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Glitch {
    /// One thigh gyro cell at `1e300` (a bit flip in the exponent).
    GyroHuge,
    /// One shank accelerometer cell at `-1e308`.
    AccHuge,
    /// 50 samples of the foot gyro stuck at full scale on all axes
    /// (saturation).
    SaturatedBurst,
    /// 1 s with every IMU reading missing (dropped packets).
    Gap,
    /// One knee encoder reading at `1e9` rad.
    EncoderHuge,
}

impl Glitch {
    /// The schedule's cycle.
    pub const ALL: [Glitch; 5] = [
        Glitch::GyroHuge,
        Glitch::AccHuge,
        Glitch::SaturatedBurst,
        Glitch::Gap,
        Glitch::EncoderHuge,
    ];

    /// The glitch's name (`gyro-huge`, `acc-huge`, `saturated-burst`,
    /// `gap`, `encoder-huge`).
    pub fn name(self) -> &'static str {
        match self {
            Glitch::GyroHuge => "gyro-huge",
            Glitch::AccHuge => "acc-huge",
            Glitch::SaturatedBurst => "saturated-burst",
            Glitch::Gap => "gap",
            Glitch::EncoderHuge => "encoder-huge",
        }
    }

    /// Parses [`Glitch::name`].
    pub fn parse(text: &str) -> Result<Glitch, String> {
        Glitch::ALL
            .into_iter()
            .find(|g| g.name() == text)
            .ok_or_else(|| {
                let names: Vec<&str> = Glitch::ALL.iter().map(|g| g.name()).collect();
                format!(
                    "unknown glitch `{text}` (expected one of {})",
                    names.join(", ")
                )
            })
    }

    /// How many samples the glitch lasts at 100 Hz.
    fn samples(self) -> usize {
        match self {
            Glitch::SaturatedBurst => 50,
            Glitch::Gap => 100,
            _ => 1,
        }
    }

    /// Applies the glitch to one record.
    fn apply(self, r: &mut Record) {
        let s = &mut r.sample;
        match self {
            Glitch::GyroHuge => {
                if let Some(w) = &mut s.imu[Segment::Thigh.index()].gyr {
                    w.z = 1e300;
                }
            }
            Glitch::AccHuge => {
                if let Some(a) = &mut s.imu[Segment::Shank.index()].acc {
                    a.x = -1e308;
                }
            }
            Glitch::SaturatedBurst => {
                if let Some(w) = &mut s.imu[Segment::Foot.index()].gyr {
                    w.fill(GYRO_FULL_SCALE);
                }
            }
            Glitch::Gap => {
                for imu in s.imu.iter_mut() {
                    imu.acc = None;
                    imu.gyr = None;
                }
            }
            Glitch::EncoderHuge => {
                s.encoder[1] = Some(1e9);
            }
        }
    }
}

/// What to soak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoakConfig {
    /// The estimator (`local`, `mjls`, `global`, `chain` on the walking
    /// simulator; `knee-selfalign` on the knee scenario).
    pub method: MethodName,
    /// Simulated duration (s).
    pub duration_s: f64,
    /// Simulator seed.
    pub seed: u64,
    /// Length of one reporting chunk (s).
    pub chunk_s: f64,
    /// One glitch every this many seconds (infinity: none).
    pub glitch_every_s: f64,
    /// The glitches injected, in turn.
    pub glitches: &'static [Glitch],
}

/// One chunk of a soak run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoakChunk {
    /// End of the chunk (s).
    pub t_end: f64,
    /// RMSE (deg) over the chunk: the mean of the four segments' RMSEs for
    /// the segment filters, the knee angle's for `knee-selfalign`.
    pub rmse_deg: f64,
    /// Samples of the chunk with no estimate of a scored angle.
    pub missing: u64,
    /// Non-finite values among the outputs (must stay 0).
    pub non_finite: u64,
    /// Thread CPU time per step (ns), estimator `step` only.
    pub step_ns: f64,
    /// Resident set size of the process at the chunk's end (kB), from
    /// `/proc/self/status` (`None` where that is not readable).
    pub rss_kb: Option<u64>,
}

/// Per-step CPU times of a run, in 10 ns bins up to 1 ms (longer steps
/// land in the last bin).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StepTimes {
    bins: Vec<u64>,
    n: u64,
}

impl StepTimes {
    const BIN_NS: u64 = 10;
    const BINS: usize = 100_000;

    fn new() -> Self {
        StepTimes {
            bins: vec![0; Self::BINS],
            n: 0,
        }
    }

    fn push(&mut self, ns: u64) {
        let k = ((ns / Self::BIN_NS) as usize).min(Self::BINS - 1);
        self.bins[k] += 1;
        self.n += 1;
    }

    /// The `q`-quantile (0..1) of the per-step CPU time (ns, upper edge of
    /// its 10 ns bin); `None` without steps.
    pub fn quantile_ns(&self, q: f64) -> Option<f64> {
        if self.n == 0 {
            return None;
        }
        let target = (q * self.n as f64).ceil().max(1.0) as u64;
        let mut seen = 0;
        for (k, c) in self.bins.iter().enumerate() {
            seen += c;
            if seen >= target {
                return Some(((k as u64 + 1) * Self::BIN_NS) as f64);
            }
        }
        None
    }
}

/// A whole soak run.
#[derive(Debug, Clone, PartialEq)]
pub struct SoakReport {
    /// Per chunk, in time order.
    pub chunks: Vec<SoakChunk>,
    /// Per-step CPU times over the whole run (each includes one read of the
    /// thread clock, some tens of ns).
    pub step_times: StepTimes,
    /// Glitches injected.
    pub glitches: u64,
    /// Samples processed.
    pub samples: u64,
    /// Where the error is made, over the whole run: per [`Phase`] and
    /// scored channel (segments trunk..foot, or the knee), the RMSE (deg).
    pub phase_rmse_deg: [[Option<f64>; 4]; 3],
}

/// When a sample lies relative to the glitches (for [`SoakReport::phase_rmse_deg`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// While a glitch is applied (a gap: the missing second).
    During = 0,
    /// Within [`AFTER_S`] after a glitch ends (the recovery).
    After = 1,
    /// Everything else.
    Elsewhere = 2,
}

/// The recovery span after a glitch scored as [`Phase::After`] (s).
pub const AFTER_S: f64 = 5.0;

/// Running squared errors per phase and channel.
#[derive(Default)]
struct PhaseAccumulator {
    sq: [[f64; 4]; 3],
    n: [[u64; 4]; 3],
}

impl PhaseAccumulator {
    fn push(&mut self, phase: Phase, k: usize, est: Option<f64>, truth: Option<f64>) {
        if let (Some(e), Some(t)) = (est, truth) {
            if e.is_finite() {
                let d = wrap(e - t);
                self.sq[phase as usize][k] += d * d;
                self.n[phase as usize][k] += 1;
            }
        }
    }

    fn rmse_deg(&self) -> [[Option<f64>; 4]; 3] {
        core::array::from_fn(|p| {
            core::array::from_fn(|k| {
                (self.n[p][k] > 0)
                    .then(|| (self.sq[p][k] / self.n[p][k] as f64).sqrt().to_degrees())
            })
        })
    }
}

impl SoakReport {
    /// The largest chunk RMSE (deg).
    pub fn max_rmse_deg(&self) -> f64 {
        self.chunks.iter().map(|c| c.rmse_deg).fold(0.0, f64::max)
    }

    /// The median chunk RMSE (deg).
    pub fn median_rmse_deg(&self) -> f64 {
        let mut v: Vec<f64> = self.chunks.iter().map(|c| c.rmse_deg).collect();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    }
}

/// CPU time consumed by the calling thread (ns).
fn thread_cpu_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return 0;
    }
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// The process's resident set size (kB), Linux only.
fn rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// `x` wrapped to [-pi, pi).
fn wrap(x: f64) -> f64 {
    use core::f64::consts::PI;
    (x + PI).rem_euclid(2.0 * PI) - PI
}

/// Running squared errors of one chunk.
#[derive(Default)]
struct ChunkAccumulator {
    sq: [f64; 4],
    n: [u64; 4],
    missing: u64,
    non_finite: u64,
    cpu_ns: u64,
    steps: u64,
}

impl ChunkAccumulator {
    fn push(&mut self, k: usize, est: Option<f64>, truth: Option<f64>) {
        match (est, truth) {
            (Some(e), Some(t)) if e.is_finite() => {
                let d = wrap(e - t);
                self.sq[k] += d * d;
                self.n[k] += 1;
            }
            (Some(_), _) => self.non_finite += 1,
            (None, _) => self.missing += 1,
        }
    }

    fn close(&self, t_end: f64, channels: usize) -> SoakChunk {
        let rmse = (0..channels)
            .map(|k| (self.sq[k] / self.n[k].max(1) as f64).sqrt().to_degrees())
            .sum::<f64>()
            / channels as f64;
        SoakChunk {
            t_end,
            rmse_deg: rmse,
            missing: self.missing,
            non_finite: self.non_finite,
            step_ns: self.cpu_ns as f64 / self.steps.max(1) as f64,
            rss_kb: rss_kb(),
        }
    }
}

/// Runs one soak.
pub fn soak(cfg: &SoakConfig) -> Result<SoakReport, Box<dyn Error>> {
    let spec = MethodSpec::defaults(cfg.method)?;
    let knee = cfg.method == MethodName::KneeSelfAlign;
    let walking = WalkingConfig {
        duration_s: cfg.duration_s,
        seed: cfg.seed,
        ..WalkingConfig::default()
    };
    let (meta, layout, records): (_, _, Box<dyn Iterator<Item = Record>>) = if knee {
        let t = simulated_trials::knee(KneeScenario {
            walking: WalkingConfig {
                mounting: limbfuse_sim::Mounting::Random,
                ..walking
            },
            ..KneeScenario::default()
        })?;
        (t.meta, t.layout, Box::new(t.records))
    } else {
        let t = simulated_trials::walking(walking)?;
        (t.meta, t.layout, Box::new(t.records))
    };
    let mut est: Box<dyn Estimator + Send> = build(&spec, &meta, &layout)?;
    let channels = if knee { 1 } else { 4 };
    let mut report = SoakReport {
        chunks: Vec::new(),
        step_times: StepTimes::new(),
        glitches: 0,
        samples: 0,
        phase_rmse_deg: [[None; 4]; 3],
    };
    let mut phases = PhaseAccumulator::default();
    let mut glitch_ended: Option<f64> = None;
    let mut acc = ChunkAccumulator::default();
    let mut chunk_end = cfg.chunk_s;
    let mut next_glitch = cfg.glitch_every_s;
    let mut active: Option<(Glitch, usize)> = None;
    let mut last_t = 0.0;
    for mut r in records {
        let t = r.sample.t;
        if t >= next_glitch && !cfg.glitches.is_empty() {
            let g = cfg.glitches[(report.glitches % cfg.glitches.len() as u64) as usize];
            active = Some((g, g.samples()));
            report.glitches += 1;
            next_glitch += cfg.glitch_every_s;
        }
        let phase = if let Some((g, left)) = active {
            g.apply(&mut r);
            active = (left > 1).then_some((g, left - 1));
            if active.is_none() {
                glitch_ended = Some(t);
            }
            Phase::During
        } else if glitch_ended.is_some_and(|e| t - e <= AFTER_S) {
            Phase::After
        } else {
            Phase::Elsewhere
        };
        let c0 = thread_cpu_ns();
        let e = est.step(&r.sample)?;
        let dt_ns = thread_cpu_ns().saturating_sub(c0);
        acc.cpu_ns += dt_ns;
        report.step_times.push(dt_ns);
        acc.steps += 1;
        report.samples += 1;
        if knee {
            acc.push(0, e.joint[1], r.reference.joint[1]);
            phases.push(phase, 0, e.joint[1], r.reference.joint[1]);
        } else {
            for k in 0..4 {
                acc.push(k, e.segment[k], r.reference.segment[k]);
                phases.push(phase, k, e.segment[k], r.reference.segment[k]);
            }
        }
        last_t = t;
        if t >= chunk_end {
            report.chunks.push(acc.close(t, channels));
            acc = ChunkAccumulator::default();
            chunk_end += cfg.chunk_s;
        }
    }
    if acc.steps > 0 {
        report.chunks.push(acc.close(last_t, channels));
    }
    report.phase_rmse_deg = phases.rmse_deg();
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_of_the_step_time_histogram() {
        let mut h = StepTimes::new();
        assert_eq!(h.quantile_ns(0.99), None);
        // 1..=100 x 100 ns: the 99th percentile is 9900 ns, its bin's upper
        // edge 9910; the median 5000 -> 5010.
        for k in 1..=100 {
            h.push(k * 100);
        }
        assert_eq!(h.quantile_ns(0.99), Some(9910.0));
        assert_eq!(h.quantile_ns(0.5), Some(5010.0));
        h.push(10_000_000);
        assert_eq!(h.quantile_ns(1.0), Some(1_000_000.0));
    }
}
