//! The knee angle over the first identification window, offline
//! (`limbfuse estimate --backfill`; ours, beyond paper 002).
//!
//! `knee-selfalign` and `knee-gyro-axis` output nothing until their first
//! window has identified the knee axes (`s_w` samples, 5 s by default): on a
//! 10 s recording that is half of it. Offline, the samples of that window
//! are known once the axes are, so their knee angle can be computed after
//! the fact. The backfill is the relative gyro angle about the first
//! identified axes (paper 002 eq 4, `g_T . j_T - g_S . j_S`, trapezoidal)
//! integrated *backwards* from the first estimate: at the first sample `J`
//! with a knee output `alpha_J`,
//!
//! `alpha_k = alpha_(k+1) - (r_k + r_(k+1)) / 2 (t_(k+1) - t_k)`, `k = J-1 .. 0`,
//!
//! anchored on the estimator's own output: `alpha_k = c + g_k`, with `g`
//! the relative gyro angle about the first identified axes (paper 002 eq 4,
//! `g_T . j_T - g_S . j_S`, trapezoidal), 0 at the first knee estimate's
//! sample `J` and integrated backwards from there, and `c` the circular mean
//! of `alpha_k - g_k` over the estimator's outputs in [`ANCHOR_S`] from `J`
//! on. The mean, not the value at `J`: the estimators' fusion starts afresh
//! at `J` and takes a few samples to converge (on the independent
//! simulator's 0.7 m/s walk `knee-selfalign`'s first output is 9.4 deg off,
//! 0.9 deg after 5 samples, 0.03 after 10), so anchoring on the first
//! output alone put the whole backfill 10 deg off. A gap in the rates up to [`MAX_BRIDGE_S`] is
//! bridged linearly; a longer one ends the backfill (the rows before it
//! keep no knee angle: the angle change across the gap is not known).
//! The backfill carries the estimator's zero and sign, but not its
//! accelerometer drift correction: a relative gyro bias `b` accumulates as
//! `b (t_J - t_k)` going back (0.1 deg/s over a 5 s window: 0.5 deg at
//! the start). Every estimate from `J` on is the real-time estimator's, bit
//! for bit, and so are the diagnostics of the backfilled samples
//! (`diag_identified` stays 0 there).
//!
//! The estimates are held until `J` + [`ANCHOR_S`] (memory: one estimate
//! and two gyro readings per sample); a backfill reaches back at most
//! [`MAX_BACKFILL_S`]: older estimates are released without a knee angle,
//! as the real-time estimator gave them.

use std::collections::VecDeque;
use std::fmt;

use limbfuse_core::{
    Estimate, Estimator, EstimatorError, Joint, OfflineEstimator, Outputs, Sample, Segment,
};
use limbfuse_estimators::knee_gyro_axis::KneeGyroAxis;
use limbfuse_estimators::knee_selfalign::angle::{gyro_angle_rate, wrap};
use limbfuse_estimators::knee_selfalign::KneeSelfAlign;
use limbfuse_io::{TrialLayout, TrialMeta};
use nalgebra::Vector3;

use crate::gated::GatedEstimator;
use crate::knee_params::out_of_range;
use crate::{MethodError, MethodName, MethodSpec};

/// How far back (s) a backfill reaches from the first knee estimate: twelve
/// default windows. Further back the estimates keep no knee angle (a
/// recording that starts with minutes of rest need not be held in memory).
pub const MAX_BACKFILL_S: f64 = 60.0;

/// Span (s) of the estimator's outputs from the first one on over which the
/// backfill's offset is averaged: about one stride of walking at a normal
/// cadence (~1.1 s, Perry, *Gait Analysis*, 1992, ch. 1), as the one-stride
/// smoothing of `knee-gyro-axis`; the fusions converge within 0.1 s of it.
pub const ANCHOR_S: f64 = 1.0;

/// A knee estimator whose axes the backfill reads.
pub trait KneeAxes: Estimator + Send {
    /// The identified thigh and shank axes `j_T`, `j_S` (sensor frames,
    /// signs included) the knee output uses; `None` before the first
    /// identification.
    fn knee_axes(&self) -> Option<[Vector3<f64>; 2]>;
}

impl KneeAxes for KneeSelfAlign {
    fn knee_axes(&self) -> Option<[Vector3<f64>; 2]> {
        self.geometry().map(|g| g.axis)
    }
}

impl KneeAxes for KneeGyroAxis {
    fn knee_axes(&self) -> Option<[Vector3<f64>; 2]> {
        self.axes_estimator().knee_axes()
    }
}

/// The thigh and shank gyro readings of a held sample, as the estimator saw
/// them (after the sensor gate).
#[derive(Debug, Clone, Copy)]
struct Gyros {
    t: f64,
    thigh: Option<Vector3<f64>>,
    shank: Option<Vector3<f64>>,
}

/// Where the backfill stands.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// No knee estimate yet.
    Waiting,
    /// The first knee estimate is `held[first]`, made with `axes`; the
    /// estimates up to [`ANCHOR_S`] after it are being collected.
    Anchoring {
        first: usize,
        axes: [Vector3<f64>; 2],
    },
    /// Backfilled (or the run finished): the held estimates are final.
    Done,
}

/// A knee estimator behind the sensor gate, backfilled offline.
pub struct KneeBackfill {
    filter: GatedEstimator<dyn KneeAxes>,
    /// Estimates not yet released, oldest first.
    held: VecDeque<Estimate>,
    /// The gyro readings of the held estimates, until the backfill.
    gyros: VecDeque<Gyros>,
    phase: Phase,
    /// Time span (s) the backfill filled.
    filled: Option<(f64, f64)>,
    seen: Sample,
}

/// The backfilled `knee-selfalign` or `knee-gyro-axis` for a trial; an
/// error for any other method.
pub fn build_backfilled(
    spec: &MethodSpec,
    meta: &TrialMeta,
    layout: &TrialLayout,
) -> Result<KneeBackfill, MethodError> {
    let inner: Box<dyn KneeAxes> = match spec {
        MethodSpec::KneeSelfAlign(s) => Box::new(
            KneeSelfAlign::new(s.for_trial(meta)?)
                .map_err(out_of_range(MethodName::KneeSelfAlign))?,
        ),
        MethodSpec::KneeGyroAxis(s) => Box::new(
            KneeGyroAxis::new(s.for_trial(meta)?)
                .map_err(out_of_range(MethodName::KneeGyroAxis))?,
        ),
        _ => return Err(MethodError::NoBackfill(spec.method().name())),
    };
    crate::build::check_channels(spec.method(), layout)?;
    let ranges = crate::gated::sensor_ranges(meta)?;
    Ok(KneeBackfill::new(GatedEstimator::new(inner, ranges)))
}

impl KneeBackfill {
    /// `filter` backfilled.
    pub fn new(filter: GatedEstimator<dyn KneeAxes>) -> Self {
        KneeBackfill {
            filter,
            held: VecDeque::new(),
            gyros: VecDeque::new(),
            phase: Phase::Waiting,
            filled: None,
            seen: Sample::empty(0.0),
        }
    }

    /// The time span (s, first and last backfilled sample) the backfill
    /// filled; `None` before the first knee estimate or when there was
    /// nothing to fill.
    pub fn filled(&self) -> Option<(f64, f64)> {
        self.filled
    }

    /// Fills the knee angle of the held estimates before `first` (module
    /// documentation): the gyro angle about `axes`, 0 at `first`, plus the
    /// circular mean of the estimator's outputs minus it from `first` on.
    fn fill(&mut self, first: usize, axes: &[Vector3<f64>; 2]) {
        let n = self.gyros.len().min(self.held.len());
        if first >= n {
            return;
        }
        let g = gyro_angles(self.gyros.iter().take(n), first, axes);
        let knee = Joint::Knee.index();
        let outputs = self.held.iter().map(|e| e.joint[knee]);
        let Some(offset) = anchor(outputs.zip(&g).skip(first)) else {
            return;
        };
        let mut from = None;
        for (k, gk) in g.iter().enumerate().take(first) {
            if let Some(gk) = gk {
                self.held[k].joint[knee] = Some(wrap(offset + gk));
                from.get_or_insert(k);
            }
        }
        if let Some(k) = from {
            self.filled = Some((self.gyros[k].t, self.gyros[first - 1].t));
        }
    }

    /// Ends the anchoring: backfills and releases the held estimates.
    fn end_anchoring(&mut self) {
        if let Phase::Anchoring { first, axes } = self.phase {
            self.fill(first, &axes);
        }
        self.phase = Phase::Done;
        self.gyros = VecDeque::new();
    }
}

/// Longest run of missing rates (s, from the reading before it to the one
/// after it) the backfill bridges, linearly: a few samples' dropout (0.1 s
/// is under a tenth of a stride; the knee rate changes little across it).
/// A longer gap ends the backfill there: the angle change across it is not
/// known, so the rows before it keep no knee angle, as in real time.
pub const MAX_BRIDGE_S: f64 = 0.1;

/// The relative gyro angle about `axes` (paper 002 eq 4, trapezoidal) at
/// each of the readings, 0 at reading `first`, integrated forwards after it
/// and backwards before it, up to the first gap in the rates longer than
/// [`MAX_BRIDGE_S`] either way (`None` beyond it); shorter gaps are
/// bridged by linear interpolation between their neighbours.
fn gyro_angles<'a>(
    gyros: impl Iterator<Item = &'a Gyros>,
    first: usize,
    axes: &[Vector3<f64>; 2],
) -> Vec<Option<f64>> {
    let (t, mut rate): (Vec<f64>, Vec<Option<f64>>) = gyros
        .map(|g| {
            let r = match (g.thigh, g.shank) {
                (Some(t), Some(s)) => Some(gyro_angle_rate(&t, &s, &axes[0], &axes[1])),
                _ => None,
            };
            (g.t, r)
        })
        .unzip();
    bridge_short_gaps(&t, &mut rate);
    let n = t.len();
    let step = |k: usize| match (rate[k], rate[k + 1]) {
        (Some(r0), Some(r1)) => Some(0.5 * (r0 + r1) * (t[k + 1] - t[k])),
        _ => None,
    };
    let mut g = vec![None; n];
    if first >= n || rate[first].is_none() {
        return g;
    }
    g[first] = Some(0.0);
    for k in first + 1..n {
        g[k] = g[k - 1].zip(step(k - 1)).map(|(a, d)| a + d);
    }
    for k in (0..first).rev() {
        g[k] = g[k + 1].zip(step(k)).map(|(a, d)| a - d);
    }
    g
}

/// Fills each run of missing rates no longer than [`MAX_BRIDGE_S`] between
/// two known ones by linear interpolation.
fn bridge_short_gaps(t: &[f64], rate: &mut [Option<f64>]) {
    let mut last: Option<usize> = None;
    for k in 0..rate.len() {
        let Some(r1) = rate[k] else { continue };
        if let Some(i) = last {
            if k > i + 1 && t[k] - t[i] <= MAX_BRIDGE_S {
                let r0 = rate[i].unwrap_or(r1);
                for j in i + 1..k {
                    let w = (t[j] - t[i]) / (t[k] - t[i]);
                    rate[j] = Some(r0 + w * (r1 - r0));
                }
            }
        }
        last = Some(k);
    }
}

/// The circular mean of `alpha - g` over the pairs (estimator output,
/// gyro angle) that have both: the backfill's offset (`None` without any).
fn anchor<'a>(pairs: impl Iterator<Item = (Option<f64>, &'a Option<f64>)>) -> Option<f64> {
    let (mut sin, mut cos, mut n) = (0.0, 0.0, 0);
    for (a, g) in pairs {
        if let (Some(a), Some(g)) = (a, g) {
            let (s, c) = libm::sincos(a - g);
            sin += s;
            cos += c;
            n += 1;
        }
    }
    (n > 0).then(|| libm::atan2(sin, cos))
}

impl Estimator for KneeBackfill {
    fn name(&self) -> &'static str {
        self.filter.name()
    }

    fn outputs(&self) -> Outputs {
        self.filter.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        self.filter.describe_parameters(out)?;
        writeln!(
            out,
            "backfill: offline; before the first knee estimate, the relative gyro angle about the first identified axes integrated backwards from it (at most {MAX_BACKFILL_S} s)"
        )
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        self.filter.diagnostic_names()
    }

    fn rejected_readings(&self) -> [u64; 3] {
        self.filter.rejected_readings()
    }

    fn reset(&mut self) {
        self.filter.reset();
        self.held.clear();
        self.gyros.clear();
        self.phase = Phase::Waiting;
        self.filled = None;
    }

    /// The real-time estimate; [`OfflineEstimator::push`] runs the backfill.
    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        self.filter.step(sample)
    }
}

impl OfflineEstimator for KneeBackfill {
    fn header(&self) -> &dyn Estimator {
        self
    }

    fn push(&mut self, sample: &Sample) -> Result<(), EstimatorError> {
        let mut e = Estimate::empty(sample.t);
        if self.phase == Phase::Done {
            self.filter.step_into(sample, &mut e)?;
            self.held.push_back(e);
            return Ok(());
        }
        self.filter.step_seen(sample, &mut e, &mut self.seen)?;
        self.gyros.push_back(Gyros {
            t: self.seen.t,
            thigh: self.seen.imu(Segment::Thigh).gyr,
            shank: self.seen.imu(Segment::Shank).gyr,
        });
        let knee = e.joint[Joint::Knee.index()].is_some();
        self.held.push_back(e);
        match self.phase {
            Phase::Waiting => {
                if let (true, Some(axes)) = (knee, self.filter.inner().knee_axes()) {
                    self.phase = Phase::Anchoring {
                        first: self.held.len() - 1,
                        axes,
                    };
                }
            }
            Phase::Anchoring { first, .. } => {
                if sample.t - self.held[first].t >= ANCHOR_S {
                    self.end_anchoring();
                }
            }
            Phase::Done => {}
        }
        Ok(())
    }

    fn pop(&mut self) -> Option<Estimate> {
        match self.phase {
            Phase::Done => self.held.pop_front(),
            Phase::Anchoring { .. } => None,
            Phase::Waiting => {
                // Too old to be backfilled: released as the estimator gave it.
                let newest = self.held.back()?.t;
                if self.held.front()?.t >= newest - MAX_BACKFILL_S {
                    return None;
                }
                self.gyros.pop_front();
                self.held.pop_front()
            }
        }
    }

    fn finish(&mut self) {
        self.end_anchoring();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> [Vector3<f64>; 2] {
        [Vector3::z(), -Vector3::z()]
    }

    /// Thigh rate `w_t`, shank rate `w_s` about z: knee rate `w_t + w_s`
    /// with the shank axis pointing the other way.
    fn reading(t: f64, w: Option<(f64, f64)>) -> Gyros {
        Gyros {
            t,
            thigh: w.map(|w| Vector3::new(0.3, -0.2, w.0)),
            shank: w.map(|w| Vector3::new(-0.1, 0.5, w.1)),
        }
    }

    #[test]
    fn gyro_angles_integrate_both_ways_from_the_first_estimate() {
        // Knee rate 2 t rad/s (linear: the trapezoid is exact), uneven steps.
        let times = [0.0, 0.01, 0.025, 0.03, 0.05, 0.06];
        let gyros: Vec<Gyros> = times
            .iter()
            .map(|&t| reading(t, Some((0.5 * t, 1.5 * t))))
            .collect();
        let g = gyro_angles(gyros.iter(), 3, &axes());
        for (k, &t) in times.iter().enumerate() {
            // integral of 2 s ds from 0.03 to t
            let want = t * t - 0.03 * 0.03;
            let got = g[k].unwrap();
            assert!((got - want).abs() < 1e-15, "{k}: {got} vs {want}");
        }
    }

    #[test]
    fn a_short_gap_is_bridged_and_a_long_one_ends_the_backfill() {
        // 100 Hz; rate 1 rad/s, missing at 0.05 s (bridged: 0.02 s between
        // its neighbours), missing over 0.10-0.25 s (0.16 s: not bridged).
        let gyros: Vec<Gyros> = (0..40)
            .map(|k| {
                let t = f64::from(k) * 0.01;
                let missing = k == 5 || (10..=24).contains(&k);
                reading(t, (!missing).then_some((1.0, 0.0)))
            })
            .collect();
        let g = gyro_angles(gyros.iter(), 30, &axes());
        for (k, gk) in g.iter().enumerate().skip(25) {
            let want = (k as f64 - 30.0) * 0.01;
            assert!((gk.unwrap() - want).abs() < 1e-12, "{k}: {gk:?}");
        }
        assert!(g[..25].iter().all(Option::is_none), "{g:?}");
        // Backwards from 0.08 s: across the short gap, to the start.
        let g = gyro_angles(gyros.iter(), 8, &axes());
        for (k, gk) in g.iter().enumerate().take(9) {
            let want = (k as f64 - 8.0) * 0.01;
            assert!((gk.unwrap() - want).abs() < 1e-12, "{k}: {gk:?}");
        }
        assert!(g[9].is_some() && g[10].is_none());
    }

    /// A knee estimator that outputs `0.5 + 0.2 (t - t_first)` rad from
    /// time `t_first` on, with axes z / -z (the rate the samples carry).
    struct FakeKnee {
        t_first: f64,
        identified: bool,
    }

    impl Estimator for FakeKnee {
        fn name(&self) -> &'static str {
            "knee-selfalign"
        }
        fn outputs(&self) -> Outputs {
            Outputs {
                joint: [false, true, false],
                ..Outputs::default()
            }
        }
        fn describe_parameters(&self, _: &mut dyn fmt::Write) -> fmt::Result {
            Ok(())
        }
        fn diagnostic_names(&self) -> &[&'static str] {
            &[]
        }
        fn reset(&mut self) {}
        fn step(&mut self, s: &Sample) -> Result<Estimate, EstimatorError> {
            let mut e = Estimate::empty(s.t);
            self.identified |= s.t >= self.t_first;
            if self.identified {
                e.joint[1] = Some(0.5 + 0.2 * (s.t - self.t_first));
            }
            Ok(e)
        }
    }

    impl KneeAxes for FakeKnee {
        fn knee_axes(&self) -> Option<[Vector3<f64>; 2]> {
            self.identified.then(axes)
        }
    }

    /// The backfilled knee angles of a 100 Hz run of `n` samples whose
    /// knee rate is 0.2 rad/s, the first estimate at `t_first`.
    fn run(n: usize, t_first: f64) -> Vec<Option<f64>> {
        let fake: Box<dyn KneeAxes> = Box::new(FakeKnee {
            t_first,
            identified: false,
        });
        let mut b = KneeBackfill::new(GatedEstimator::new(fake, Default::default()));
        let mut out = Vec::new();
        for k in 0..n {
            let mut s = Sample::empty(k as f64 * 0.01);
            // Readings that change (a constant one is a stuck sensor to the
            // gate) with a knee rate of 0.15 + 0.05 = 0.2 rad/s.
            let w = 0.01 * (k as f64).sin();
            s.imu[Segment::Thigh.index()].gyr = Some(Vector3::new(w, -w, 0.15 + w));
            s.imu[Segment::Shank.index()].gyr = Some(Vector3::new(w, w, 0.05 - w));
            b.push(&s).unwrap();
            while let Some(e) = b.pop() {
                out.push(e.joint[1]);
            }
        }
        b.finish();
        while let Some(e) = b.pop() {
            out.push(e.joint[1]);
        }
        out
    }

    #[test]
    fn the_backfill_continues_the_output_backwards() {
        let out = run(1000, 5.0);
        assert_eq!(out.len(), 1000);
        for (k, a) in out.iter().enumerate() {
            let want = wrap(0.5 + 0.2 * (k as f64 * 0.01 - 5.0));
            assert!((a.unwrap() - want).abs() < 1e-12, "{k}: {a:?} vs {want}");
        }
    }

    #[test]
    fn the_backfill_reaches_back_at_most_max_backfill_s() {
        let out = run(9000, 80.0);
        assert_eq!(out.len(), 9000);
        // released unfilled: older than 60 s before the newest held sample
        // while waiting, i.e. before t = 20 s
        let first_filled = out.iter().position(Option::is_some).unwrap();
        assert!((1999..=2001).contains(&first_filled), "{first_filled}");
        assert!(out[first_filled..].iter().all(Option::is_some));
    }

    #[test]
    fn the_anchor_is_the_circular_mean_across_the_wrap() {
        let g = [0.0, 0.0, 0.0];
        // outputs at +179 and -179 deg: the mean is 180 deg, not 0
        let out = [Some(179f64.to_radians()), None, Some(-179f64.to_radians())];
        let a = anchor(out.into_iter().zip(&g.map(Some))).unwrap();
        assert!((a.abs() - core::f64::consts::PI).abs() < 1e-12, "{a}");
        let out = [Some(0.2), Some(0.4), None];
        let a = anchor(out.into_iter().zip(&[Some(0.1), Some(0.1), Some(5.0)])).unwrap();
        assert!((a - 0.2).abs() < 1e-12, "{a}");
        assert_eq!(anchor(out.into_iter().zip(&[None, None, Some(0.0)])), None);
    }
}
