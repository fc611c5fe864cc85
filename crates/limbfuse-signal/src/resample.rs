//! Resampling a trial onto a uniform time base (`limbfuse resample`).
//!
//! Paper 001 resamples every stream (IMUs at 50 Hz, potentiometers at 1 kHz,
//! markers at 100 Hz) to 50 Hz before estimation. [`resample_trial`] does the
//! same for a trial file: the output grid is `t_k = t_first + k / rate`, `k =
//! 0, 1, ...` up to the last input time, and each channel is resampled from
//! its own *present* samples (a trial that merges a 1 kHz encoder with a 100
//! Hz IMU has empty IMU cells between IMU samples; those are not zeros).
//!
//! Per channel kind ([`ChannelMethod`]):
//! - **IMU accelerometer and gyro** (decimation, input rate above the output
//!   rate): anti-alias low-pass, by default a Blackman-windowed sinc evaluated
//!   at each output time over the input samples within `+-W`
//!   ([`AntiAlias::WindowedSinc`]): cut-off `fc = 0.35 x` output rate (17.5 Hz
//!   at 50 Hz), half-width `W = 10` output periods (0.2 s at 50 Hz). The
//!   weights are normalised by their sum, so a constant is reproduced exactly
//!   and irregular input spacing is handled. The kernel is symmetric: no
//!   phase shift (no delay). Where the kernel does not fit inside a gap-free
//!   stretch of the channel (the first and last `W` seconds, next to a
//!   dropout) the output falls back to the mean over one output period
//!   (`[t - T/2, t + T/2]`, end points weighted 1/2); with no sample in that
//!   period the output is missing. Measured response: `docs/TUNING.md` and
//!   the tests in `tests/resample.rs`.
//! - **Everything else** (encoders, references, model inputs, CoM; IMU
//!   channels when the input rate is not above the output rate): linear
//!   interpolation between the two present samples around `t`, unless they
//!   are separated by a gap (more than 1.5 nominal input periods); the first
//!   and last present samples (of the channel, or next to a gap) extend by
//!   half a period (the longer of the input and output periods). Quaternions:
//!   normalised linear interpolation (sign-aligned). Gait phase labels:
//!   nearest present sample under the same rules. Angles are interpolated as
//!   numbers (no wrap at +-pi: sagittal limb angles stay far from it).
//!
//! Not streaming: the present samples of every channel are held in memory,
//! 16 bytes per present cell (a 10 min trial at 1 kHz with 4 IMUs, 3
//! encoders and 7 references, a 408 MB CSV file, peaks at 370 MB of RSS and
//! takes 12.6 s to 50 Hz in release). Gaps, dropouts and a channel with a
//! single sample never panic: missing stays missing.

use std::io::Write;
use std::path::{Path, PathBuf};

use limbfuse_core::sample::GaitPhase;
use limbfuse_core::Record;
use nalgebra::Vector3;

use limbfuse_io::FileError;
use limbfuse_io::TrialLayout;
use limbfuse_io::TrialMeta;
use limbfuse_io::TrialReader;
use limbfuse_io::TrialWriter;

/// Cut-off of the windowed-sinc anti-alias filter as a fraction of the
/// output rate: 0.35 (17.5 Hz at 50 Hz, 0.7 of the output Nyquist frequency).
pub const SINC_CUTOFF_FRACTION: f64 = 0.35;
/// Half-width of the windowed-sinc kernel in output periods: 10 (0.2 s at 50 Hz).
pub const SINC_HALF_WIDTH_PERIODS: f64 = 10.0;
/// Two successive present samples further apart than this many nominal
/// input periods are separated by a gap (no interpolation across it).
pub const GAP_FACTOR: f64 = 1.5;
/// Largest number of output samples [`resample_trial`] produces.
pub const MAX_OUTPUT_SAMPLES: usize = 100_000_000;

/// How IMU accelerometer and gyro channels are low-passed before decimation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AntiAlias {
    /// Blackman-windowed sinc, cut-off [`SINC_CUTOFF_FRACTION`] of the
    /// output rate, half-width [`SINC_HALF_WIDTH_PERIODS`] output periods
    /// (default).
    #[default]
    WindowedSinc,
    /// Mean over one output period centred on the output time.
    Boxcar,
    /// No low-pass: linear interpolation (aliases whatever is above the
    /// output Nyquist frequency).
    None,
}

impl AntiAlias {
    /// `windowed-sinc`, `boxcar` or `none`.
    pub const fn label(self) -> &'static str {
        match self {
            AntiAlias::WindowedSinc => "windowed-sinc",
            AntiAlias::Boxcar => "boxcar",
            AntiAlias::None => "none",
        }
    }
}

/// How one scalar channel is resampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelMethod {
    /// Anti-alias low-pass when the channel's input rate is above the output
    /// rate, linear interpolation otherwise.
    Decimate(AntiAlias),
    /// Linear interpolation.
    Linear,
}

/// Options of [`resample_trial`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResampleOptions {
    /// Output rate (Hz), finite, > 0 and at most 100 kHz.
    pub rate_hz: f64,
    /// Low-pass of the IMU channels.
    pub anti_alias: AntiAlias,
}

impl ResampleOptions {
    /// Resampling to `rate_hz` with the default windowed-sinc anti-alias filter.
    pub fn new(rate_hz: f64) -> Self {
        ResampleOptions {
            rate_hz,
            anti_alias: AntiAlias::WindowedSinc,
        }
    }
}

/// Why resampling failed.
#[derive(Debug, thiserror::Error)]
pub enum ResampleError {
    /// The input could not be read or the output written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A bad option or an input that cannot be resampled.
    #[error("{0}")]
    Invalid(String),
}

/// A resampled trial, held in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct ResampledTrial {
    /// Input metadata with `sample_rate_hz` and `resampled` set.
    pub meta: TrialMeta,
    /// Same channels as the input.
    pub layout: TrialLayout,
    /// One record per output time.
    pub records: Vec<Record>,
}

/// The present samples of one scalar channel, in time order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    /// Times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Values.
    pub v: Vec<f64>,
}

impl Series {
    fn push(&mut self, t: f64, v: Option<f64>) {
        if let Some(v) = v {
            self.t.push(t);
            self.v.push(v);
        }
    }
}

/// The uniform output grid `t_first + k / rate` up to `t_last` (inclusive,
/// with a 1e-9-period tolerance).
pub fn uniform_grid(t_first: f64, t_last: f64, rate_hz: f64) -> Result<Vec<f64>, ResampleError> {
    check_rate(rate_hz)?;
    if !(t_first.is_finite() && t_last.is_finite()) || t_last < t_first {
        return Err(ResampleError::Invalid(format!(
            "cannot build a time grid from {t_first} s to {t_last} s"
        )));
    }
    let n = ((t_last - t_first) * rate_hz + 1e-9).floor() + 1.0;
    if n > MAX_OUTPUT_SAMPLES as f64 {
        return Err(ResampleError::Invalid(format!(
            "{t_first} s to {t_last} s at {rate_hz} Hz is {n} samples, more than the limit of {MAX_OUTPUT_SAMPLES}"
        )));
    }
    Ok((0..n as usize)
        .map(|k| t_first + k as f64 / rate_hz)
        .collect())
}

fn check_rate(rate_hz: f64) -> Result<(), ResampleError> {
    if rate_hz.is_finite() && rate_hz > 0.0 && rate_hz <= 100_000.0 {
        Ok(())
    } else {
        Err(ResampleError::Invalid(format!(
            "rate: expected a rate in Hz above 0 and at most 100000, found {rate_hz}"
        )))
    }
}

/// Nominal input period of a channel: the median spacing of its present
/// samples (`None` with fewer than two).
fn nominal_period(t: &[f64]) -> Option<f64> {
    if t.len() < 2 {
        return None;
    }
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let mid = d.len() / 2;
    let (_, m, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}

/// Where `tg` falls among the samples `t`: the bracketing pair (both
/// indices, not separated by a gap) or the single nearby sample at an edge.
enum Bracket {
    Pair(usize, usize, f64),
    One(usize),
    Nothing,
}

fn bracket(t: &[f64], tg: f64, period: Option<f64>, period_out: f64) -> Bracket {
    if t.is_empty() {
        return Bracket::Nothing;
    }
    let tol = 1e-9 * tg.abs().max(1.0);
    let j = t.partition_point(|&x| x <= tg);
    // Exact hit.
    if j > 0 && (tg - t[j - 1]).abs() <= tol {
        return Bracket::One(j - 1);
    }
    if j < t.len() && (t[j] - tg).abs() <= tol {
        return Bracket::One(j);
    }
    // A lone sample stands for half an output period each side.
    let p = period.unwrap_or(period_out);
    if j > 0 && j < t.len() {
        let (a, b) = (j - 1, j);
        if t[b] - t[a] <= GAP_FACTOR * p {
            return Bracket::Pair(a, b, (tg - t[a]) / (t[b] - t[a]));
        }
    }
    // Edge of the data or of a gap: the nearest sample within half a period
    // (the longer of the input and output periods).
    let near = [j.checked_sub(1), (j < t.len()).then_some(j)]
        .into_iter()
        .flatten()
        .min_by(|&a, &b| (t[a] - tg).abs().total_cmp(&(t[b] - tg).abs()));
    match near {
        Some(k) if (t[k] - tg).abs() <= 0.5 * p.max(period_out) + tol => Bracket::One(k),
        _ => Bracket::Nothing,
    }
}

fn linear(s: &Series, grid: &[f64], period_out: f64) -> Vec<Option<f64>> {
    let p = nominal_period(&s.t);
    grid.iter()
        .map(|&tg| match bracket(&s.t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => Some(s.v[a] + w * (s.v[b] - s.v[a])),
            Bracket::One(k) => Some(s.v[k]),
            Bracket::Nothing => None,
        })
        .collect()
}

/// Blackman window on [-1, 1].
fn blackman(x: f64) -> f64 {
    use std::f64::consts::PI;
    if x.abs() >= 1.0 {
        return 0.0;
    }
    0.42 + 0.5 * (PI * x).cos() + 0.08 * (2.0 * PI * x).cos()
}

fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-12 {
        1.0
    } else {
        let y = std::f64::consts::PI * x;
        y.sin() / y
    }
}

/// Mean over `[tg - T/2, tg + T/2]`, the end points weighted 1/2.
fn boxcar_at(s: &Series, tg: f64, period_out: f64) -> Option<f64> {
    let half = 0.5 * period_out;
    let tol = 1e-9 * period_out;
    let lo = s.t.partition_point(|&x| x < tg - half - tol);
    let hi = s.t.partition_point(|&x| x <= tg + half + tol);
    let (mut sw, mut sv) = (0.0, 0.0);
    for k in lo..hi {
        let edge = (s.t[k] - tg).abs() >= half - tol;
        let w = if edge { 0.5 } else { 1.0 };
        sw += w;
        sv += w * s.v[k];
    }
    (sw > 0.0).then(|| sv / sw)
}

/// Resamples one scalar channel onto `grid` (output rate `rate_hz`).
///
/// `s.t` must be strictly increasing (as a trial file's times are).
pub fn resample_series(
    s: &Series,
    grid: &[f64],
    rate_hz: f64,
    method: ChannelMethod,
) -> Vec<Option<f64>> {
    let period_out = 1.0 / rate_hz;
    let anti_alias = match method {
        ChannelMethod::Decimate(a) => a,
        ChannelMethod::Linear => AntiAlias::None,
    };
    let Some(p_in) = nominal_period(&s.t) else {
        return linear(s, grid, period_out);
    };
    // Not a decimation (input rate not above the output rate): interpolate.
    if anti_alias == AntiAlias::None || p_in >= period_out * (1.0 - 1e-9) {
        return linear(s, grid, period_out);
    }
    if anti_alias == AntiAlias::Boxcar {
        return grid
            .iter()
            .map(|&tg| boxcar_at(s, tg, period_out))
            .collect();
    }
    // Gap-free runs: run_end[k] = index of the last sample of k's run.
    let n = s.t.len();
    let mut run_start = vec![0usize; n];
    for k in 1..n {
        run_start[k] = if s.t[k] - s.t[k - 1] > GAP_FACTOR * p_in {
            k
        } else {
            run_start[k - 1]
        };
    }
    let mut run_end = vec![n - 1; n];
    for k in (0..n - 1).rev() {
        run_end[k] = if s.t[k + 1] - s.t[k] > GAP_FACTOR * p_in {
            k
        } else {
            run_end[k + 1]
        };
    }
    let half_width = SINC_HALF_WIDTH_PERIODS * period_out;
    let two_fc = 2.0 * SINC_CUTOFF_FRACTION * rate_hz;
    grid.iter()
        .map(|&tg| {
            let lo = s.t.partition_point(|&x| x <= tg - half_width);
            let hi = s.t.partition_point(|&x| x < tg + half_width);
            // The kernel must lie inside one gap-free run, within half an
            // input period of its ends.
            let inside = lo < hi
                && run_end[lo] >= hi - 1
                && s.t[run_start[lo]] <= tg - half_width + 0.5 * p_in
                && s.t[run_end[lo]] >= tg + half_width - 0.5 * p_in;
            if inside {
                let (mut sw, mut sv) = (0.0, 0.0);
                for k in lo..hi {
                    let tau = s.t[k] - tg;
                    let w = sinc(two_fc * tau) * blackman(tau / half_width);
                    sw += w;
                    sv += w * s.v[k];
                }
                // With the whole kernel covered the sum is about f_in / (2 fc)
                // > 1; anything tiny means something odd: fall back.
                if sw > 0.5 {
                    return Some(sv / sw);
                }
            }
            boxcar_at(s, tg, period_out)
        })
        .collect()
}

/// Quaternion series (sign-aligned normalised linear interpolation).
fn resample_quat(
    t: &[f64],
    q: &[[f64; 4]],
    grid: &[f64],
    period_out: f64,
) -> Vec<Option<[f64; 4]>> {
    let p = nominal_period(t);
    grid.iter()
        .map(|&tg| match bracket(t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => {
                let (qa, mut qb) = (q[a], q[b]);
                let dot: f64 = (0..4).map(|i| qa[i] * qb[i]).sum();
                if dot < 0.0 {
                    qb = qb.map(|x| -x);
                }
                let mut r = [0.0; 4];
                for i in 0..4 {
                    r[i] = qa[i] + w * (qb[i] - qa[i]);
                }
                let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
                (norm > 1e-12).then(|| r.map(|x| x / norm))
            }
            Bracket::One(k) => Some(q[k]),
            Bracket::Nothing => None,
        })
        .collect()
}

fn resample_phase(
    t: &[f64],
    ph: &[GaitPhase],
    grid: &[f64],
    period_out: f64,
) -> Vec<Option<GaitPhase>> {
    let p = nominal_period(t);
    grid.iter()
        .map(|&tg| match bracket(t, tg, p, period_out) {
            Bracket::Pair(a, b, w) => Some(if w <= 0.5 { ph[a] } else { ph[b] }),
            Bracket::One(k) => Some(ph[k]),
            Bracket::Nothing => None,
        })
        .collect()
}

/// A scalar cell of a record.
#[derive(Debug, Clone, Copy)]
enum Slot {
    Acc(usize, usize),
    Gyr(usize, usize),
    Encoder(usize),
    Stim(usize),
    Motor(usize),
    SegmentRef(usize),
    JointRef(usize),
    ComPos(usize),
    ComVel(usize),
}

impl Slot {
    fn get(self, r: &Record) -> Option<f64> {
        let (s, re) = (&r.sample, &r.reference);
        match self {
            Slot::Acc(i, k) => s.imu[i].acc.map(|v| v[k]),
            Slot::Gyr(i, k) => s.imu[i].gyr.map(|v| v[k]),
            Slot::Encoder(j) => s.encoder[j],
            Slot::Stim(k) => s.inputs.stim[k],
            Slot::Motor(j) => s.inputs.motor_torque[j],
            Slot::SegmentRef(i) => re.segment[i],
            Slot::JointRef(j) => re.joint[j],
            Slot::ComPos(k) => re.com_pos.map(|v| v[k]),
            Slot::ComVel(k) => re.com_vel.map(|v| v[k]),
        }
    }

    fn method(self, anti_alias: AntiAlias) -> ChannelMethod {
        match self {
            Slot::Acc(..) | Slot::Gyr(..) => ChannelMethod::Decimate(anti_alias),
            _ => ChannelMethod::Linear,
        }
    }
}

fn slots(l: &TrialLayout) -> Vec<Slot> {
    let mut v = Vec::new();
    for i in 0..4 {
        if l.acc[i] {
            v.extend((0..3).map(|k| Slot::Acc(i, k)));
        }
        if l.gyr[i] {
            v.extend((0..3).map(|k| Slot::Gyr(i, k)));
        }
        if l.segment_ref[i] {
            v.push(Slot::SegmentRef(i));
        }
        if l.stim[i] {
            v.push(Slot::Stim(i));
        }
    }
    for j in 0..3 {
        if l.encoder[j] {
            v.push(Slot::Encoder(j));
        }
        if l.motor_torque[j] {
            v.push(Slot::Motor(j));
        }
        if l.joint_ref[j] {
            v.push(Slot::JointRef(j));
        }
        if l.com_pos {
            v.push(Slot::ComPos(j));
        }
        if l.com_vel {
            v.push(Slot::ComVel(j));
        }
    }
    v
}

/// Reads the whole trial and resamples it (see the module docs).
pub fn resample_trial(
    mut reader: TrialReader,
    opts: &ResampleOptions,
) -> Result<ResampledTrial, ResampleError> {
    check_rate(opts.rate_hz)?;
    let layout = *reader.layout();
    let slots = slots(&layout);
    let mut series = vec![Series::default(); slots.len()];
    let mut quat: [(Vec<f64>, Vec<[f64; 4]>); 4] = Default::default();
    let mut phase: (Vec<f64>, Vec<GaitPhase>) = Default::default();
    let (mut t_first, mut t_last) = (None, 0.0);
    while let Some(r) = reader.next_record()? {
        let t = r.sample.t;
        t_first.get_or_insert(t);
        t_last = t;
        for (s, slot) in series.iter_mut().zip(&slots) {
            s.push(t, slot.get(&r));
        }
        for (i, q) in quat.iter_mut().enumerate() {
            if let Some(v) = r.sample.imu[i].quat {
                q.0.push(t);
                q.1.push(v);
            }
        }
        if let Some(p) = r.reference.phase {
            phase.0.push(t);
            phase.1.push(p);
        }
    }
    // TrialReader errors on a file without rows, so t_first is set.
    let t_first = t_first.unwrap_or(t_last);
    let grid = uniform_grid(t_first, t_last, opts.rate_hz)?;
    let mut records: Vec<Record> = grid
        .iter()
        .map(|&t| {
            let mut r = Record::default();
            r.sample.t = t;
            r
        })
        .collect();
    // Scalars; vectors are assembled per axis, present when all axes are.
    let mut acc = vec![[[None; 3]; 4]; grid.len()];
    let mut gyr = vec![[[None; 3]; 4]; grid.len()];
    let mut com = vec![[[None; 3]; 2]; grid.len()];
    for (s, &slot) in series.iter().zip(&slots) {
        let out = resample_series(s, &grid, opts.rate_hz, slot.method(opts.anti_alias));
        for (k, v) in out.into_iter().enumerate() {
            let r = &mut records[k];
            match slot {
                Slot::Acc(i, a) => acc[k][i][a] = v,
                Slot::Gyr(i, a) => gyr[k][i][a] = v,
                Slot::Encoder(j) => r.sample.encoder[j] = v,
                Slot::Stim(j) => r.sample.inputs.stim[j] = v,
                Slot::Motor(j) => r.sample.inputs.motor_torque[j] = v,
                Slot::SegmentRef(i) => r.reference.segment[i] = v,
                Slot::JointRef(j) => r.reference.joint[j] = v,
                Slot::ComPos(a) => com[k][0][a] = v,
                Slot::ComVel(a) => com[k][1][a] = v,
            }
        }
    }
    let vec3 = |v: [Option<f64>; 3]| Some(Vector3::new(v[0]?, v[1]?, v[2]?));
    for (k, r) in records.iter_mut().enumerate() {
        for i in 0..4 {
            r.sample.imu[i].acc = vec3(acc[k][i]);
            r.sample.imu[i].gyr = vec3(gyr[k][i]);
        }
        r.reference.com_pos = vec3(com[k][0]);
        r.reference.com_vel = vec3(com[k][1]);
    }
    for (i, (t, q)) in quat.iter().enumerate() {
        if layout.quat[i] {
            for (k, v) in resample_quat(t, q, &grid, 1.0 / opts.rate_hz)
                .into_iter()
                .enumerate()
            {
                records[k].sample.imu[i].quat = v;
            }
        }
    }
    if layout.phase_ref {
        for (k, v) in resample_phase(&phase.0, &phase.1, &grid, 1.0 / opts.rate_hz)
            .into_iter()
            .enumerate()
        {
            records[k].reference.phase = v;
        }
    }
    let mut meta = reader.meta().clone();
    meta.set("sample_rate_hz", opts.rate_hz);
    meta.set(
        "resampled",
        format!(
            "from {} by limbfuse resample (IMU anti-alias: {}; other channels linear)",
            reader.path().display(),
            opts.anti_alias.label()
        ),
    );
    Ok(ResampledTrial {
        meta,
        layout,
        records,
    })
}

/// What [`resample_file`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResampleSummary {
    /// Number of output samples.
    pub n_samples: usize,
    /// First and last output time (s).
    pub span: (f64, f64),
}

/// Resamples the trial file `input` into the trial file `output`.
pub fn resample_file(
    input: &Path,
    output: &Path,
    opts: &ResampleOptions,
) -> Result<ResampleSummary, ResampleError> {
    let trial = resample_trial(TrialReader::open(input)?, opts)?;
    let io_err = |e: std::io::Error| FileError::Io {
        path: PathBuf::from(output),
        source: e,
    };
    let file = std::fs::File::create(output).map_err(io_err)?;
    let mut w = TrialWriter::new(std::io::BufWriter::new(file), &trial.meta, trial.layout)
        .map_err(io_err)?;
    for r in &trial.records {
        w.write(r).map_err(io_err)?;
    }
    w.finish().map_err(io_err)?.flush().map_err(io_err)?;
    Ok(ResampleSummary {
        n_samples: trial.records.len(),
        span: (
            trial.records.first().map_or(0.0, |r| r.sample.t),
            trial.records.last().map_or(0.0, |r| r.sample.t),
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_uniform_and_inclusive() {
        let g = uniform_grid(0.0, 1.0, 50.0).unwrap();
        assert_eq!(g.len(), 51);
        assert_eq!(g[50], 1.0);
        assert!(uniform_grid(0.0, 1.0, 0.0).is_err());
        assert!(uniform_grid(0.0, 1e12, 1000.0).is_err());
    }

    #[test]
    fn single_sample_and_empty_series_do_not_panic() {
        let grid = uniform_grid(0.0, 1.0, 10.0).unwrap();
        let one = Series {
            t: vec![0.5],
            v: vec![2.0],
        };
        let out = resample_series(
            &one,
            &grid,
            10.0,
            ChannelMethod::Decimate(AntiAlias::WindowedSinc),
        );
        assert_eq!(out[5], Some(2.0));
        assert_eq!(out[0], None);
        let none = resample_series(&Series::default(), &grid, 10.0, ChannelMethod::Linear);
        assert!(none.iter().all(Option::is_none));
    }
}
