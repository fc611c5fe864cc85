//! Restarting the IMM at the next mid-stance, on the side the CoM sways
//! to, after a gap or a mid-stride start (ours, not in paper 003;
//! docs/GAIT_IMM.md, "Restart after a gap or a mid-stride start").
//!
//! The bank starts at mid-stance (MS) of SS1 on `first_side` (paper 003's
//! simulated trials start there). That holds at such a trial's start, and
//! only by chance after a gap or in a recording that starts anywhere in the
//! stride: the bank then tracks the wrong foot and never re-synchronises
//! (shared 0.85 m/s B-SLIP trial, one second of empty CoM cells: 97 % ->
//! 57 % phase accuracy; its first 0.9 s removed: 36 %). [`SwayRestart`]
//! wraps either configuration and keeps the recent measured positions.
//! At each lateral sway extremum (`sway_extremum`) found in them it
//! restarts the bank there, on that side, replaying the positions since
//! then, unless the bank's own last MS agrees with it
//! ([`MS_AGREEMENT_STEPS`]; without CoM velocity measurements the side
//! only). A bank that keeps its own MS (the continuous
//! configuration's step tracker) is checked so all along: from the start
//! (a recording may start anywhere in the stride) and while it tracks (its
//! MS can drift: limbfuse's 0.4 m/s trial, 0.1-0.25 s late after a few
//! steps). The lateral drift over the last stride (walking off the x axis,
//! `lateral_drift`) is taken out of the positions first. The paper's
//! bank is restarted at the first extremum after a gap
//! only: a gap is successive samples more than `max_gap` apart, or no
//! measured CoM position for longer than `max_gap`. Until a restart the
//! output is the bare estimator's (it predicts through a run of empty cells
//! and restarts on `first_side` after a gap in time), so no row loses its
//! estimate; with no extremum in [`MAX_WAIT_S`] after a gap (a walker who
//! does not sway) the bare estimator goes on.

extern crate alloc;

use alloc::collections::VecDeque;
use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{ComMeasurement, Estimate, Estimator, EstimatorError, Sample, TimeStep};
use limbfuse_models::bslip::Side;

use super::sway_extremum::{mid_stance_in, window_for_step, WINDOW_RANGE_S};
use super::{ImmBslip, ImmContinuous};

/// Longest wait for a sway extremum after a gap (s): more than a stride of
/// a slow (0.4 m/s) walk, which has two extremes.
pub const MAX_WAIT_S: f64 = 2.5;

/// How far the bare bank's last mid-stance may lie from the sway
/// extremum's, on the same side, for the bank to go on without a restart:
/// this fraction of the step time. The bare continuous bank's MS lies 2-6 %
/// of a step after the true one on the shared B-SLIP trials (its MS is the
/// CoM passing over the located foot); a bank started at the wrong instant
/// is off by the offset of its start. A restart is not free: the tracker
/// measures step length and leg stiffness anew.
pub const MS_AGREEMENT_STEPS: f64 = 0.15;

/// Most positions kept: [`KEPT_S`] up to 1.5 kHz.
const BUFFER: usize = 4096;

/// An IMM that can restart at MS of SS1 on a given side.
pub trait RestartOnSide: Estimator {
    /// Forgets all state: the next sample with a CoM position starts the
    /// bank at MS of SS1 with `side` the stance (trailing) foot.
    fn restart_on(&mut self, side: Side);
    /// A gap longer than this (s) restarts the bank.
    fn max_gap(&self) -> f64;
    /// The side the bank starts on by default.
    fn first_side(&self) -> Side;
    /// The step time (s) of the gait the bank tracks.
    fn step_time(&self) -> f64;
    /// Whether the bank keeps its own mid-stance ([`Self::last_mid_stance`]):
    /// then it is checked against the sway all along (from the start, and
    /// while tracking), else only restarted after a gap.
    fn keeps_mid_stance(&self) -> bool {
        false
    }
    /// The time of the bank's last mid-stance and its stance side.
    fn last_mid_stance(&self) -> Option<(f64, Side)> {
        None
    }
}

impl RestartOnSide for ImmBslip {
    fn restart_on(&mut self, side: Side) {
        self.reset();
        for f in &mut self.feet {
            f.side = side;
        }
    }

    fn max_gap(&self) -> f64 {
        self.params.max_gap
    }

    fn first_side(&self) -> Side {
        self.params.first_side
    }

    // No `last_mid_stance`: the paper's bank is always restarted at the
    // extremum. Its feet's MS agreeing with the sway says little about its
    // weights (limbfuse's own trial after a 1 s gap: kept, 0.682; restarted,
    // 0.861; no gap, 0.695), and a restart costs it nothing it learned.

    fn step_time(&self) -> f64 {
        self.dominant_gait().step_time
    }
}

impl RestartOnSide for ImmContinuous {
    fn restart_on(&mut self, side: Side) {
        self.reset();
        self.start_side = side;
        self.start_at_mid_stance = true;
    }

    fn max_gap(&self) -> f64 {
        self.inner.params.max_gap
    }

    fn first_side(&self) -> Side {
        self.inner.params.first_side
    }

    fn keeps_mid_stance(&self) -> bool {
        true
    }

    fn last_mid_stance(&self) -> Option<(f64, Side)> {
        self.last_mid_stance()
    }

    fn step_time(&self) -> f64 {
        self.current_gait().step_time
    }
}

/// `E`, restarted at a sway extremum (module docs).
#[derive(Debug, Clone)]
pub struct SwayRestart<E> {
    inner: E,
    time: TimeStep,
    /// Time of the last sample.
    last_t: Option<f64>,
    /// Time of the last measured CoM position before now.
    last_position: Option<f64>,
    /// Since when the bank has been stopped (a gap), if it is.
    lost_since: Option<f64>,
    /// Recent measured positions (time, CoM), oldest first: at most
    /// [`KEPT_S`].
    buffer: VecDeque<(f64, ComMeasurement)>,
    /// The last extremum looked at: time (s) and side.
    last_extremum: Option<(f64, Side)>,
    /// The one before it.
    earlier_extremum: Option<(f64, Side)>,
    /// The step time over the last three extremes (s), when plausible.
    measured_step: Option<f64>,
    /// Whether a sample carried a CoM velocity measurement.
    velocity_seen: bool,
}

/// Plausible step times (s): a fast run-walk to a very slow walk.
const STEP_RANGE_S: (f64, f64) = (0.25, 2.0);

/// Positions older than this before the newest are dropped (s): a stride of
/// the longest fit window (the lateral drift) and a margin.
const KEPT_S: f64 = 2.0 * WINDOW_RANGE_S.1 + 0.2;

/// Each end of the stride over which the lateral drift is measured is the
/// mean position over this long (s).
const DRIFT_END_S: f64 = 0.05;

/// The lateral drift (m/s) of `buffer` (time, CoM; oldest first) over the
/// stride `stride` (s) before `now`: the CoM's mean lateral velocity, which
/// walking off the x axis makes non-zero (1 m/s at 2 deg: 0.035 m/s) and
/// which would move the sway's vertex by `drift / z''` (0.07 s at a
/// curvature of 0.5 m/s^2). Over one stride the sway itself returns.
/// `None` until a stride is kept.
fn lateral_drift(buffer: &VecDeque<(f64, ComMeasurement)>, now: f64, stride: f64) -> Option<f64> {
    let mean = |a: f64, b: f64| {
        let from = buffer.partition_point(|&(t, _)| t < a);
        let to = buffer.partition_point(|&(t, _)| t <= b);
        let (sum, n) = buffer
            .range(from..to.max(from))
            .fold((0.0, 0usize), |(s, n), (_, c)| {
                (s + c.pos[2].unwrap_or(0.0), n + 1)
            });
        (n > 0).then(|| sum / n as f64)
    };
    let covered = buffer
        .front()
        .is_some_and(|&(t, _)| t <= now - stride - DRIFT_END_S);
    match (
        covered,
        mean(now - DRIFT_END_S, now),
        mean(now - stride - DRIFT_END_S, now - stride),
    ) {
        (true, Some(z1), Some(z0)) => Some((z1 - z0) / stride),
        _ => None,
    }
}

impl<E: RestartOnSide> SwayRestart<E> {
    /// Wraps `inner`.
    pub fn new(inner: E) -> Self {
        SwayRestart {
            inner,
            time: TimeStep::new(),
            last_t: None,
            last_position: None,
            lost_since: None,
            buffer: VecDeque::with_capacity(BUFFER),
            last_extremum: None,
            earlier_extremum: None,
            measured_step: None,
            velocity_seen: false,
        }
    }

    /// The wrapped estimator.
    pub fn inner(&self) -> &E {
        &self.inner
    }

    /// A gap: the kept positions and the extremes found in them are gone.
    fn forget_positions(&mut self) {
        self.buffer.clear();
        self.last_extremum = None;
        self.earlier_extremum = None;
        self.measured_step = None;
    }

    /// Keeps the position of `sample` (with the bank's output `bare` for
    /// it) and looks for a sway extremum: the bank goes on if its own MS
    /// agrees, else it is restarted there. While lost, after [`MAX_WAIT_S`]
    /// without an extremum the bare estimator goes on.
    fn observe(&mut self, sample: &Sample, bare: Estimate) -> Result<Estimate, EstimatorError> {
        if self
            .buffer
            .back()
            .is_some_and(|&(t, _)| sample.t - t > self.inner.max_gap())
        {
            self.forget_positions();
        }
        while self.buffer.len() == BUFFER
            || self
                .buffer
                .front()
                .is_some_and(|&(t, _)| sample.t - t > KEPT_S)
        {
            self.buffer.pop_front();
        }
        self.buffer.push_back((sample.t, sample.com));
        self.velocity_seen |= sample.com.vel.iter().any(Option::is_some);
        // The step time measured over the last three extremes, else the
        // tracked gait's: the gait's can be far off (0.81 s
        // against 0.96 s on limbfuse's position-only 0.5 m/s trial), and a
        // stride of the wrong length leaves sway in the drift.
        let step = self.measured_step.unwrap_or_else(|| self.inner.step_time());
        let now = sample.t;
        // Until a stride is kept the drift is unknown and taken as zero: a
        // looser agreement then (tried: 0.35 of a step) or no check at all
        // keeps a bank started mid-stride for a stride longer, which costs
        // more on mid-stride starts than the rare false restart of a bank
        // walking 5 deg off the x axis (docs/RESULTS.md).
        let drift = lateral_drift(&self.buffer, now, 2.0 * step).unwrap_or(0.0);
        let window = window_for_step(step);
        // The fit looks at the last window (and, centred on a vertex found
        // there, at most half a window before it).
        let first = self
            .buffer
            .partition_point(|&(t, _)| t < now - 1.5 * window);
        let sway = self
            .buffer
            .range(first..)
            .map(|&(t, c)| (t, c.pos[2].unwrap_or(0.0) - drift * (t - now)));
        let found = mid_stance_in(sway, window).filter(|ms| {
            !self
                .last_extremum
                .is_some_and(|(e, _)| ms.t - e < 0.5 * step)
        });
        if let Some(ms) = found {
            // Half the last stride (two steps, the same side again): a
            // drift left in the positions moves minima and maxima opposite
            // ways, so single steps alternate long and short.
            self.measured_step = match (self.last_extremum, self.earlier_extremum) {
                (Some((t1, s1)), Some((t0, s0))) if s1 != ms.side && s0 == ms.side => {
                    Some(0.5 * (ms.t - t0)).filter(|&dt| {
                        (STEP_RANGE_S.0..=STEP_RANGE_S.1).contains(&dt)
                            && (STEP_RANGE_S.0..=STEP_RANGE_S.1).contains(&(ms.t - t1))
                    })
                }
                _ => None,
            };
            self.earlier_extremum = self.last_extremum;
            self.last_extremum = Some((ms.t, ms.side));
            let last = self.buffer.len() - 1;
            let from = self.buffer.partition_point(|&(t, _)| t < ms.t).min(last);
            // The buffered sample nearer to the extremum.
            let from = match from.checked_sub(1) {
                Some(before) if ms.t - self.buffer[before].0 < self.buffer[from].0 - ms.t => before,
                _ => from,
            };
            // Without velocity measurements the bank's own MS scatters by
            // up to a third of a step while it tracks (limbfuse's
            // position-only 0.5 m/s trial: 0.03-0.3 s early, 80 % phase
            // accuracy), and a restart does not do better: only the side
            // is checked then.
            let tolerance = if self.velocity_seen {
                MS_AGREEMENT_STEPS
            } else {
                0.5
            };
            let agrees = self
                .inner
                .last_mid_stance()
                .is_some_and(|(t, side)| side == ms.side && (t - ms.t).abs() <= tolerance * step);
            self.lost_since = None;
            if agrees {
                // The bank is in step with the sway: it goes on.
                return Ok(bare);
            }
            return self.resume(ms.side, from);
        }
        if self
            .lost_since
            .is_some_and(|since| sample.t - since > MAX_WAIT_S)
        {
            // No sway: the bare estimator goes on.
            self.buffer.clear();
            self.lost_since = None;
        }
        Ok(bare)
    }

    /// Restarts the bank on `side` at buffered sample `from` and replays
    /// the rest; the last sample's estimate.
    fn resume(&mut self, side: Side, from: usize) -> Result<Estimate, EstimatorError> {
        self.inner.restart_on(side);
        let mut last = None;
        for &(t, com) in self.buffer.iter().skip(from) {
            let sample = Sample {
                t,
                com,
                ..Sample::default()
            };
            last = Some(self.inner.step(&sample)?);
            self.last_position = Some(t);
        }
        last.ok_or(EstimatorError::NonFinite {
            channel: "com_meas_z",
        })
    }
}

fn has_position(sample: &Sample) -> bool {
    sample.com.pos.iter().all(Option::is_some)
}

impl<E: RestartOnSide> Estimator for SwayRestart<E> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn outputs(&self) -> Outputs {
        self.inner.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        self.inner.describe_parameters(out)?;
        writeln!(
            out,
            "sway restart: at a lateral sway extremum (fit over a step, {}-{} s) {}",
            WINDOW_RANGE_S.0,
            WINDOW_RANGE_S.1,
            if self.inner.keeps_mid_stance() {
                "where the bank's own mid-stance disagrees with it, from the start"
            } else {
                "after a gap"
            }
        )
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        self.inner.diagnostic_names()
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.time.reset();
        self.last_t = None;
        self.last_position = None;
        self.lost_since = None;
        self.forget_positions();
        self.velocity_seen = false;
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        self.time.advance(sample.t)?;
        let previous = self.last_t.replace(sample.t);
        for (v, name) in sample.com.values().iter().zip(ComMeasurement::NAMES) {
            if v.is_some_and(|v| !v.is_finite()) {
                return Err(EstimatorError::NonFinite { channel: name });
            }
        }
        let max_gap = self.inner.max_gap();
        let position = has_position(sample);
        if self.lost_since.is_none() && self.last_position.is_some() {
            let gap = previous.is_some_and(|p| sample.t - p > max_gap);
            let stale = !position && self.last_position.is_some_and(|p| sample.t - p > max_gap);
            if gap || stale {
                self.lost_since = Some(sample.t);
                self.forget_positions();
            }
        }
        let bare = self.inner.step(sample)?;
        if !position {
            return Ok(bare);
        }
        self.last_position = Some(sample.t);
        if self.lost_since.is_some() || self.inner.keeps_mid_stance() {
            self.observe(sample, bare)
        } else {
            Ok(bare)
        }
    }
}
