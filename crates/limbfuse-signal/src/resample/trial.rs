//! The trial-level resampler: every channel of a trial file onto one
//! uniform grid ([`resample_trial`], [`resample_file`]).

use std::path::{Path, PathBuf};

use limbfuse_core::sample::GaitPhase;
use limbfuse_core::{PlausibilityLimits, Record, Rejections, SampleGate};
use limbfuse_io::{FileError, TrialLayout, TrialMeta, TrialReader, TrialWriter};
use nalgebra::Vector3;

use super::interpolation::{nominal_period, resample_phase, resample_quat};
use super::{
    check_rate, resample_series, uniform_grid, AntiAlias, ChannelMethod, ResampleError,
    ResampleOptions, Series,
};

/// A resampled trial, held in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct ResampledTrial {
    /// Input metadata with `sample_rate_hz` and `resampled` set.
    pub meta: TrialMeta,
    /// Same channels as the input.
    pub layout: TrialLayout,
    /// One record per output time.
    pub records: Vec<Record>,
    /// The input readings left out as [`SampleGate`] leaves them out of
    /// every estimator for being out of the sensors' range or not
    /// finite (not for the plausibility checks, [`PlausibilityLimits::off`]):
    /// interpolated, one such reading would spread into its neighbours.
    pub rejections: Rejections,
    /// Whether an IMU channel was low-pass filtered (`opts.anti_alias` on
    /// a channel whose input rate is above the output rate); interpolated
    /// only otherwise (an audit: upsampling said "windowed-sinc
    /// anti-alias").
    pub imu_filtered: bool,
    /// Gyroscope cells at the full scale, carried through as the rail
    /// ([`super::clip_marks`]).
    pub clipped_gyro: u64,
    /// The input's last line, left out: cut off mid-line
    /// ([`TrialReader::cut_last_line`]).
    pub cut_last_line: Option<limbfuse_io::table::CutLine>,
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
    OtherAcc(usize, usize),
    OtherGyr(usize, usize),
    ContactRef(usize),
    SpeedRef,
    ComMeas(usize),
}

impl Slot {
    fn get(self, r: &Record) -> Option<f64> {
        let (s, re) = (&r.sample, &r.reference);
        match self {
            Slot::Acc(i, k) => s.imu[i].acc_axis(k),
            Slot::Gyr(i, k) => s.imu[i].gyr_axis(k),
            Slot::Encoder(j) => s.encoder[j],
            Slot::Stim(k) => s.inputs.stim[k],
            Slot::Motor(j) => s.inputs.motor_torque[j],
            Slot::SegmentRef(i) => re.segment[i],
            Slot::JointRef(j) => re.joint[j],
            Slot::ComPos(k) => re.com_pos.map(|v| v[k]),
            Slot::ComVel(k) => re.com_vel.map(|v| v[k]),
            Slot::OtherAcc(i, k) => s.other_leg_imu[i].acc_axis(k),
            Slot::OtherGyr(i, k) => s.other_leg_imu[i].gyr_axis(k),
            Slot::ContactRef(side) => re.contact[side].map(|c| if c { 1.0 } else { 0.0 }),
            Slot::SpeedRef => re.speed,
            Slot::ComMeas(k) => s.com.values()[k],
        }
    }

    fn method(self, anti_alias: AntiAlias) -> ChannelMethod {
        match self {
            Slot::Acc(..) | Slot::Gyr(..) | Slot::OtherAcc(..) | Slot::OtherGyr(..) => {
                ChannelMethod::Decimate(anti_alias)
            }
            Slot::ContactRef(_) => ChannelMethod::Nearest,
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
        if l.other_acc[i] {
            v.extend((0..3).map(|k| Slot::OtherAcc(i, k)));
        }
        if l.other_gyr[i] {
            v.extend((0..3).map(|k| Slot::OtherGyr(i, k)));
        }
    }
    for side in 0..2 {
        if l.contact_ref[side] {
            v.push(Slot::ContactRef(side));
        }
    }
    if l.speed_ref {
        v.push(Slot::SpeedRef);
    }
    for k in 0..6 {
        if l.com_meas[k] {
            v.push(Slot::ComMeas(k));
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
    let (meta, layout) = (reader.meta().clone(), *reader.layout());
    let path = reader.path().to_path_buf();
    let rows = std::iter::from_fn(|| reader.next_record().transpose());
    let mut trial = resample_rows(rows, &meta, layout, &path, opts, None)?;
    trial.cut_last_line = reader.cut_last_line();
    note_resampling(&mut trial, &path, opts);
    Ok(trial)
}

/// Resamples a trial held in memory (its `records` in time order, as a
/// [`TrialReader`] would give them; `source` names it in messages and in the
/// `# resampled:` line): what [`resample_trial`] does with a file. `cancel`
/// is polled every 4096 rows read and before each channel (a fraction of a
/// second each on an hour): once it returns true the call ends with
/// [`ResampleError::Cancelled`] (Python's Ctrl-C).
pub fn resample_records(
    records: &[Record],
    meta: &TrialMeta,
    layout: TrialLayout,
    source: &Path,
    opts: &ResampleOptions,
    cancel: Option<fn() -> bool>,
) -> Result<ResampledTrial, ResampleError> {
    let rows = records.iter().map(|r| Ok(*r));
    let mut trial = resample_rows(rows, meta, layout, source, opts, cancel)?;
    note_resampling(&mut trial, source, opts);
    Ok(trial)
}

/// Sets the `# resampled:` line: where from, how, and what was left out.
fn note_resampling(trial: &mut ResampledTrial, source: &Path, opts: &ResampleOptions) {
    let (rejections, clipped_gyro) = (trial.rejections, trial.clipped_gyro);
    let mut left_out = String::new();
    if rejections.total() > 0 {
        left_out = format!(
            "; {} gyroscope, {} accelerometer and {} encoder readings out of the \
             sensors' range left out",
            rejections.gyro, rejections.acc, rejections.encoder
        );
    }
    if clipped_gyro > 0 {
        left_out =
            format!("{left_out}; {clipped_gyro} clipped gyroscope cells carried at the rail");
    }
    if let Some(c) = trial.cut_last_line {
        left_out = format!("{left_out}; its line {} left out, cut off mid-line", c.line);
    }
    trial.meta.set(
        "resampled",
        format!(
            "from {} by limbfuse resample (IMU anti-alias: {}; other channels linear{left_out})",
            source.display(),
            anti_alias_said(opts.anti_alias, trial.imu_filtered)
        ),
    );
}

/// The resampler over a trial's rows: everything but the `# resampled:`
/// line and the cut last line, which its callers know.
fn resample_rows(
    rows: impl Iterator<Item = Result<Record, FileError>>,
    meta: &TrialMeta,
    layout: TrialLayout,
    source: &Path,
    opts: &ResampleOptions,
    cancel: Option<fn() -> bool>,
) -> Result<ResampledTrial, ResampleError> {
    check_rate(opts.rate_hz)?;
    let ranges = meta.sensor_ranges().map_err(|e| {
        ResampleError::Invalid(format!(
            "{}: trial metadata `# {}: {}`: expected the sensor's full-scale range as a positive \
             number",
            source.display(),
            e.key,
            e.found
        ))
    })?;
    // Readings no sensor can produce are left out (an audit found one 1e308
    // gyro cell spread over its neighbours). Not the plausibility checks: a
    // static recording's exactly repeated readings are data here.
    // Nor the accelerometer clipping test: a clipped specific force is what
    // the sensor recorded (`gait-events` models its clipped impacts), and the
    // methods that reject it do so when they read the resampled trial.
    // Clipped gyroscope cells are taken out of their series and carried
    // through as the rail ([`super::clip_marks`]); the vector's other axes
    // stay.
    let gyro_clip = ranges
        .gyro_full_scale_rad_s
        .map(|fs| limbfuse_core::sample_gate::CLIPPED_FRACTION * fs);
    let ranges = limbfuse_core::SensorRanges {
        gyro_full_scale_rad_s: None,
        acc_full_scale_m_s2: None,
        ..ranges
    };
    let mut gate = SampleGate::with_limits(ranges, PlausibilityLimits::off());
    let slots = slots(&layout);
    let mut series = vec![Series::default(); slots.len()];
    let mut clipped: Vec<Vec<(f64, f64)>> = vec![Vec::new(); slots.len()];
    let mut quat: [(Vec<f64>, Vec<[f64; 4]>); 4] = Default::default();
    let mut phase: (Vec<f64>, Vec<GaitPhase>) = Default::default();
    let (mut t_first, mut t_last) = (None, 0.0);
    for (k, r) in rows.enumerate() {
        if k % 4096 == 4095 && cancel.is_some_and(|c| c()) {
            return Err(ResampleError::Cancelled);
        }
        let mut r = r?;
        let screening = gate.check(&r.sample);
        if !screening.is_clean() {
            screening.apply(&mut r.sample);
        }
        let t = r.sample.t;
        t_first.get_or_insert(t);
        t_last = t;
        for ((s, c), slot) in series.iter_mut().zip(&mut clipped).zip(&slots) {
            let v = slot.get(&r);
            match (slot, v, gyro_clip) {
                (Slot::Gyr(..) | Slot::OtherGyr(..), Some(x), Some(level)) if x.abs() >= level => {
                    c.push((t, x));
                }
                _ => s.push(t, v),
            }
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
    let Some(t_first) = t_first else {
        return Err(ResampleError::Invalid(format!(
            "{}: no rows to resample",
            source.display()
        )));
    };
    check_memory(source, t_first, t_last, opts.rate_hz)?;
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
    // (IMU axes are set one at a time in the records, each keeping the
    // vector partial until its last axis arrives: no per-sample buffer)
    let mut com = vec![[[None; 3]; 2]; grid.len()];
    let mut imu_filtered = false;
    for ((s, c), &slot) in series.iter().zip(&clipped).zip(&slots) {
        if cancel.is_some_and(|c| c()) {
            return Err(ResampleError::Cancelled);
        }
        if let ChannelMethod::Decimate(a) = slot.method(opts.anti_alias) {
            imu_filtered |= a != AntiAlias::None
                && nominal_period(&s.t).is_some_and(|p| p < (1.0 - 1e-9) / opts.rate_hz);
        }
        let mut out = resample_series(s, &grid, opts.rate_hz, slot.method(opts.anti_alias));
        if !c.is_empty() {
            let period = super::interpolation::nominal_period(&s.t).unwrap_or(1.0 / opts.rate_hz);
            super::clip_marks::mark_clipped(c, &grid, 0.5 * period, &mut out);
        }
        for (k, v) in out.into_iter().enumerate() {
            let r = &mut records[k];
            match slot {
                Slot::Acc(i, a) => set_axis(&mut r.sample.imu[i], Axis::Acc, a, v),
                Slot::Gyr(i, a) => set_axis(&mut r.sample.imu[i], Axis::Gyr, a, v),
                Slot::Encoder(j) => r.sample.encoder[j] = v,
                Slot::Stim(j) => r.sample.inputs.stim[j] = v,
                Slot::Motor(j) => r.sample.inputs.motor_torque[j] = v,
                Slot::SegmentRef(i) => r.reference.segment[i] = v,
                Slot::JointRef(j) => r.reference.joint[j] = v,
                Slot::ComPos(a) => com[k][0][a] = v,
                Slot::ComVel(a) => com[k][1][a] = v,
                Slot::OtherAcc(i, a) => set_axis(&mut r.sample.other_leg_imu[i], Axis::Acc, a, v),
                Slot::OtherGyr(i, a) => set_axis(&mut r.sample.other_leg_imu[i], Axis::Gyr, a, v),
                Slot::ContactRef(side) => r.reference.contact[side] = v.map(|c| c >= 0.5),
                Slot::SpeedRef => r.reference.speed = v,
                Slot::ComMeas(a) => r.sample.com.set(a, v),
            }
        }
    }
    let vec3 = |v: [Option<f64>; 3]| Some(Vector3::new(v[0]?, v[1]?, v[2]?));
    for (k, r) in records.iter_mut().enumerate() {
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
    let rejections = *gate.rejections();
    let clipped_gyro: u64 = clipped.iter().map(|c| c.len() as u64).sum();
    let mut meta = meta.clone();
    meta.set("sample_rate_hz", opts.rate_hz);
    Ok(ResampledTrial {
        meta,
        layout,
        records,
        rejections,
        imu_filtered,
        clipped_gyro,
        cut_last_line: None,
    })
}

/// Which vector of an IMU sample [`set_axis`] sets.
#[derive(Clone, Copy)]
enum Axis {
    Acc,
    Gyr,
}

/// Sets axis `a` of `imu`'s specific force or angular rate; the vector is
/// complete once all three axes are present, else partial (per axis: an
/// incomplete vector keeps its axes, issue 18).
fn set_axis(imu: &mut limbfuse_core::ImuSample, which: Axis, a: usize, v: Option<f64>) {
    match which {
        Axis::Acc => {
            let mut cells = imu.acc_axes();
            cells[a] = v;
            imu.set_acc_axes(cells);
        }
        Axis::Gyr => {
            let mut cells = imu.gyr_axes();
            cells[a] = v;
            imu.set_gyr_axes(cells);
        }
    }
}

/// Memory [`resample_trial`] may take for its output (10 GiB): the records
/// and their working buffers, [`bytes_per_output_sample`] each (about
/// 2.2 KB). An hour at 1 kHz (3.6 million samples, the longest real
/// recording resampled, ~7.5 GiB) fits; an audit's trial with a 1e6 s jump
/// in `t` asked for 103 GB at 50 Hz and was killed by the allocator. The
/// records are held whole (the filters look ahead), so the output is
/// bounded here rather than streamed.
pub const MAX_RESAMPLE_BYTES: u64 = 10 << 30;

/// Memory one output sample of [`resample_trial`] takes at most (bytes):
/// its record, its grid time, its CoM buffer, one channel's resampled
/// value and one quaternion.
pub fn bytes_per_output_sample() -> u64 {
    (std::mem::size_of::<Record>()
        + std::mem::size_of::<f64>()
        + std::mem::size_of::<[[Option<f64>; 3]; 2]>()
        + std::mem::size_of::<Option<f64>>()
        + std::mem::size_of::<Option<[f64; 4]>>()) as u64
}

/// Refuses, before anything is allocated, an output grid from `t_first` to
/// `t_last` s at `rate_hz` whose records would take more than
/// [`MAX_RESAMPLE_BYTES`]; `input` names the trial.
fn check_memory(
    input: &Path,
    t_first: f64,
    t_last: f64,
    rate_hz: f64,
) -> Result<(), ResampleError> {
    let n = ((t_last - t_first) * rate_hz).floor() + 1.0;
    let per = bytes_per_output_sample();
    let max_samples = MAX_RESAMPLE_BYTES / per;
    // (times that give no grid at all are said by `uniform_grid`)
    if !n.is_finite() || n <= max_samples as f64 {
        return Ok(());
    }
    let shown = limbfuse_core::ShownNumber;
    Err(ResampleError::Invalid(format!(
        "{}: its times run from {} s to {} s: at --rate {} Hz that is {} output samples, \
         {} GB in memory ({per} bytes each), more than the limit of {} GiB \
         ({max_samples} samples); is there a jump in its `t` column, or resample at a lower --rate",
        input.display(),
        shown(t_first),
        shown(t_last),
        shown(rate_hz),
        shown(n),
        shown((n * per as f64 / 1e9 * 10.0).round() / 10.0),
        MAX_RESAMPLE_BYTES >> 30
    )))
}

/// What [`resample_file`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResampleSummary {
    /// Number of output samples.
    pub n_samples: usize,
    /// First and last output time (s).
    pub span: (f64, f64),
    /// The input readings left out ([`ResampledTrial::rejections`]).
    pub rejections: Rejections,
    /// [`ResampledTrial::imu_filtered`].
    pub imu_filtered: bool,
    /// [`ResampledTrial::clipped_gyro`].
    pub clipped_gyro: u64,
    /// [`ResampledTrial::cut_last_line`].
    pub cut_last_line: Option<limbfuse_io::table::CutLine>,
}

/// How the IMU channels were treated, in words: the filter's name, or that
/// none was needed.
pub fn anti_alias_said(anti_alias: AntiAlias, imu_filtered: bool) -> &'static str {
    match (imu_filtered, anti_alias) {
        (true, a) => a.label(),
        (false, AntiAlias::None) => AntiAlias::None.label(),
        (false, _) => "none needed (no IMU channel downsampled: interpolated)",
    }
}

/// What the user is told about readings a resampling left out or carried
/// at the rail (`source` names the trial): the warning on out-of-range
/// readings, and the note on clipped gyroscope cells; the CLI's words, and
/// Python's.
pub fn resample_notes(
    source: &Path,
    rejections: &Rejections,
    clipped_gyro: u64,
) -> (Option<String>, Option<String>) {
    let rejected = (rejections.total() > 0).then(|| {
        format!(
            "{}: {} gyroscope, {} accelerometer and {} encoder readings out of the \
             sensors' range (first at t = {} s) left out, as `estimate` leaves them out \
             (interpolated, they would spread into their neighbours)",
            source.display(),
            rejections.gyro,
            rejections.acc,
            rejections.encoder,
            limbfuse_core::ShownNumber(rejections.first_t.unwrap_or(f64::NAN))
        )
    });
    let clipped = (clipped_gyro > 0).then(|| {
        format!(
            "{}: {} gyroscope cells at the full scale (clipped) carried through at the rail, not \
             low-passed: `estimate` rejects them as it does at the trial's own rate, `gait-events` \
             keeps them (docs/RESULTS.md \"Clipped accelerometers\")",
            source.display(),
            clipped_gyro
        )
    });
    (rejected, clipped)
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
    let mut file = limbfuse_io::AtomicFile::create(output).map_err(io_err)?;
    let mut w =
        TrialWriter::for_path(output, &mut file, &trial.meta, trial.layout).map_err(io_err)?;
    for r in &trial.records {
        w.write(r).map_err(io_err)?;
    }
    w.finish().map_err(io_err)?;
    file.commit().map_err(io_err)?;
    Ok(ResampleSummary {
        n_samples: trial.records.len(),
        span: (
            trial.records.first().map_or(0.0, |r| r.sample.t),
            trial.records.last().map_or(0.0, |r| r.sample.t),
        ),
        rejections: trial.rejections,
        imu_filtered: trial.imu_filtered,
        clipped_gyro: trial.clipped_gyro,
        cut_last_line: trial.cut_last_line,
    })
}
