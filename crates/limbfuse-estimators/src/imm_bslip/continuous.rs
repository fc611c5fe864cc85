//! `imm-bslip`, configuration `continuous` (issue 19 items 1-2; not in
//! paper 003): the IMM over the three phase models of ONE gait of the
//! continuous gait family, re-targeted to the walking speed measured step
//! by step, with feet and phase placed by evidence from the data instead of
//! the template's touchdown timing. docs/GAIT_IMM.md, "Configuration
//! `continuous`".
//!
//! - **Feet from the data.** A periodic B-SLIP step is symmetric in time
//!   about mid-stance (MS), where the CoM is over the stance foot; so the
//!   stance foot is the midpoint of where the CoM rises through and falls
//!   back through its mid height (`height_crossings`), located in SS1 just
//!   after MS, and the next foot is one measured step length ahead (the
//!   located feet's spacing; the family's step length before two are
//!   located) and one step width to the side. MS is the CoM passing over
//!   the leading foot (or the leading foot's location, if that comes
//!   first). The first downward zero crossing of the ensemble's `vy`, used
//!   before, is ill-conditioned: flat-topped slow gaits and the flat DS of
//!   fast ones let noise fire it early, and an early MS put the next feet,
//!   hence the next MS, earlier still (issue 19, 10 s trials).
//! - **Phase from the leg lengths.** Feet land and lift at rest length
//!   (B-SLIP), so with the feet known the phase is the set of legs shorter
//!   than `l0` on the ensemble CoM: SS1 -> DS when the leading leg is
//!   shorter than `l0` (touchdown), DS -> SS2 when the trailing leg is no
//!   longer (lift-off), SS2 -> SS1 at MS. This is eq 14's physical
//!   likelihood taken to its limit (`kappa -> infinity`) and does not use
//!   the template's `t_touchdown` or touchdown height.
//! - **Speed as a continuous quantity.** The walking speed is the advance
//!   of the located feet over their MS times across the last stride (two
//!   steps; one step until three feet are located; before that the mean
//!   ensemble `vx` since the start), and at every MS the filters' gait is
//!   re-targeted to the family's gait at that speed ([`gait_at_speed`]):
//!   lateral offset, step width, and the stiffness until the legs' own is
//!   measured.
//! - **Leg stiffness from the weight support** (`super::weight_support`).
//!   The legs' vertical impulse over a step equals the weight's, so with
//!   the feet located the stiffness of the legs the trial walks on is
//!   measured step by step (mean over the last stride) and replaces the
//!   family's: the family's stiffness at a speed depends on the gait branch
//!   its search landed on (8 or 16 kN/m at 0.8 m/s for 70 kg / 0.95 m),
//!   and a walker on another branch is tracked with the wrong dynamics.

extern crate alloc;

use alloc::vec::Vec;
use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{Estimate, Estimator, EstimatorError, GaitPhase, Sample};
use limbfuse_models::bslip::family::{gait_at_speed, speed_at_mid_stance_velocity};
use limbfuse_models::bslip::{leg_length, GaitTemplate, Side, State};

use super::height_crossings::{FootFix, HeightCrossings};
use super::start_phase::{
    locate_in_step, mid_double_support, ms_worse_than_trough, vy_slope, Placement, StepPoint,
    StepProfile, MS_REJECTED, MS_SNAP_STEPS, NOISE_VY, START_WINDOW_S, TROUGH_EVIDENCE,
    VY_EVIDENCE, WINDOW_CAPACITY,
};
use super::weight_support::WeightSupport;
use super::{ImmBslip, ImmBslipError, ImmBslipParams};

/// Feet, phase and speed from the data (module docs).
#[derive(Debug, Clone, Copy)]
struct StepTracker {
    /// Trailing (SS1 stance) side.
    side: Side,
    /// Trailing foot `(x, z)`.
    stance: [f64; 2],
    /// Leading foot `(x, z)`.
    leading: [f64; 2],
    phase: GaitPhase,
    /// Steps since the start (one per MS).
    step: u32,
    /// The last three located stance feet (newest first) and their steps.
    fixes: [Option<(FootFix, u32)>; 3],
    /// MS and the stance foot from the CoM's mid-height crossings.
    crossings: HeightCrossings,
    /// Lowest and highest CoM height since the last MS.
    heights: (f64, f64),
    /// The detector's crossing count at the last MS.
    crossings_at_ms: u32,
    /// Walking speed (m/s).
    speed: f64,
    /// Whether `speed` is measured (two located feet).
    measured: bool,
    /// Sum of ensemble `vx` and samples since the start (the speed before a
    /// step is measured).
    vx_sum: (f64, usize),
    /// The family's gait the filters use.
    gait: GaitTemplate,
    /// The last MS: time and stance side.
    ms: Option<(f64, Side)>,
    /// The legs' stiffness from the weight support of the last stride.
    support: WeightSupport,
    /// Whether an apex (MS) has passed since the start: the crossing
    /// detector starts at the first lift-off after one.
    apex_seen: bool,
}

impl StepTracker {
    fn new(gait: GaitTemplate, side: Side) -> Self {
        StepTracker {
            side,
            stance: [0.0; 2],
            leading: [0.0; 2],
            phase: GaitPhase::Ss1,
            step: 0,
            fixes: [None; 3],
            crossings: HeightCrossings::new(),
            heights: (f64::INFINITY, f64::NEG_INFINITY),
            crossings_at_ms: 0,
            speed: gait.speed,
            measured: false,
            vx_sum: (0.0, 0),
            gait,
            ms: None,
            support: WeightSupport::new(),
            apex_seen: true,
        }
    }

    /// A step starting at MS on `self.side` with the stance foot at `foot`,
    /// the next foot one step length ahead and one step width to the side.
    fn place_feet(&mut self, foot: [f64; 2]) {
        let s = self.side.sign();
        self.stance = foot;
        self.leading = [
            foot[0] + self.step_length(),
            foot[1] + s * self.gait.step_width,
        ];
        self.phase = GaitPhase::Ss1;
    }

    /// The newest and the oldest located foot of different steps.
    fn span(&self) -> Option<((FootFix, u32), (FootFix, u32))> {
        let a = self.fixes[0]?;
        let b = self.fixes[2].or(self.fixes[1])?;
        (a.1 > b.1 && a.0.t > b.0.t).then_some((a, b))
    }

    /// The measured step length (located feet), else the family's.
    fn step_length(&self) -> f64 {
        match self.span() {
            Some((a, b)) => (a.0.x - b.0.x) / f64::from(a.1 - b.1),
            None => self.gait.step_length,
        }
    }

    /// Records the located stance foot of the current step.
    fn fix(&mut self, f: FootFix) {
        if self.fixes[0].is_some_and(|(_, s)| s == self.step) {
            self.fixes[0] = Some((f, self.step));
        } else {
            self.fixes = [Some((f, self.step)), self.fixes[0], self.fixes[1]];
        }
        self.stance[0] = f.x;
        self.leading[0] = f.x + self.step_length();
        if let Some((a, b)) = self.span() {
            self.speed = (a.0.x - b.0.x) / (a.0.t - b.0.t);
            self.measured = true;
        }
    }
}

/// `imm-bslip` with the continuous gait family and evidence-based phase
/// (module docs).
#[derive(Debug, Clone)]
pub struct ImmContinuous {
    pub(super) inner: ImmBslip,
    family: Vec<GaitTemplate>,
    steps: StepTracker,
    first_side: Side,
    /// The stance side of the next start ([`super::RestartOnSide`]).
    pub(super) start_side: Side,
    /// Whether the next start is known to be at MS (a restart at a sway
    /// extremum), else where in the step it is comes from the data.
    pub(super) start_at_mid_stance: bool,
    previous: Option<(f64, State)>,
    /// Since a start taken as MS for want of vertical velocity (while
    /// `window_open`): the samples since, until they span
    /// [`START_WINDOW_S`] (a buffer of [`WINDOW_CAPACITY`], allocated here
    /// once).
    window: Vec<Sample>,
    window_open: bool,
    /// The points of a gait's step, for placing a start.
    profile: StepProfile,
    /// The placement of the start being replayed from its window.
    replay_placement: Option<Placement>,
}

impl ImmContinuous {
    /// The estimator over `family` (one body; sorted here by speed).
    pub fn new(family: &[GaitTemplate], params: ImmBslipParams) -> Result<Self, ImmBslipError> {
        let mut family = family.to_vec();
        family.sort_by(|a, b| a.speed.total_cmp(&b.speed));
        let middle = *family
            .get(family.len() / 2)
            .ok_or(ImmBslipError::EmptyLibrary)?;
        let mut inner = ImmBslip::new(core::slice::from_ref(&middle), params)?;
        inner.external_feet = true;
        Ok(ImmContinuous {
            inner,
            family,
            steps: StepTracker::new(middle, params.first_side),
            first_side: params.first_side,
            start_side: params.first_side,
            start_at_mid_stance: false,
            previous: None,
            window: Vec::with_capacity(WINDOW_CAPACITY),
            window_open: false,
            profile: StepProfile::new(),
            replay_placement: None,
        })
    }

    /// The last mid-stance (MS): its time and the stance foot's side.
    pub fn last_mid_stance(&self) -> Option<(f64, Side)> {
        self.steps.ms
    }

    /// The family's gait the filters use now.
    pub fn current_gait(&self) -> &GaitTemplate {
        &self.steps.gait
    }

    /// The family's gait at `speed`, with the measured leg stiffness when
    /// there is one.
    fn retarget(&mut self, speed: f64) {
        if let Some(mut g) = gait_at_speed(&self.family, speed) {
            if let Some(k) = self.steps.support.stiffness() {
                g.body.stiffness = k;
                g.gait.stiffness = k;
            }
            self.steps.gait = g;
            self.inner.templates[0] = g;
        }
    }

    /// `sum_legs (l0 - l_i) y / l_i` over the legs loaded in the current
    /// phase, on the CoM `x` (m).
    fn support(&self, x: &State) -> f64 {
        let st = &self.steps;
        let l0 = st.gait.body.rest_length;
        let leg = |foot: [f64; 2]| {
            let l = leg_length(x, foot);
            (l0 - l) * x[1] / l
        };
        match st.phase {
            GaitPhase::Ss1 => leg(st.stance),
            GaitPhase::Ds => leg(st.stance) + leg(st.leading),
            GaitPhase::Ss2 => leg(st.leading),
        }
    }

    /// The family's gait at the speed whose MS forward velocity is the
    /// measured `vx` (the family's middle speed without one).
    fn speed_guess(&self, vx: Option<f64>) -> (f64, GaitTemplate) {
        let middle = self.family[self.family.len() / 2].speed;
        let speed = vx
            .and_then(|vx| speed_at_mid_stance_velocity(&self.family, vx))
            .unwrap_or(middle);
        let gait = gait_at_speed(&self.family, speed).unwrap_or(self.steps.gait);
        (speed, gait)
    }

    /// `p` on `gait` as a start, the speed from the forward velocity `vx`
    /// measured there scaled to MS by the gait's own ratio.
    fn located(&self, p: StepPoint, gait: &GaitTemplate, vx: Option<f64>, speed: f64) -> Placement {
        let vx_ms = vx.map(|vx| vx * gait.gait.forward_speed / p.vx);
        Placement {
            located: Some((p, gait.step_time, gait.step_length)),
            speed: vx_ms
                .and_then(|v| speed_at_mid_stance_velocity(&self.family, v))
                .unwrap_or(speed),
        }
    }

    /// Where the first sample of a run lies from itself alone: its measured
    /// height and vertical velocity against the gait's step
    /// (`start_phase`), unless it is `known` to be MS; a start within
    /// [`MS_SNAP_STEPS`] of MS is taken as MS.
    fn place(&mut self, known: bool, measured: &[Option<f64>; 6]) -> Placement {
        let (speed, gait) = self.speed_guess(measured[3]);
        match (known, measured[1], measured[4]) {
            (false, Some(y), Some(vy)) if vy.abs() > VY_EVIDENCE => {
                let (p, worse_at_ms) = locate_in_step(&gait, y, vy, &mut self.profile);
                let from_ms = p.t.min(gait.step_time - p.t);
                let off_ms = from_ms > MS_SNAP_STEPS * gait.step_time;
                if off_ms && worse_at_ms > MS_REJECTED {
                    return self.located(p, &gait, measured[3], speed);
                }
            }
            _ => {}
        }
        Placement {
            located: None,
            speed,
        }
    }

    /// A start taken as MS for want of vertical velocity (`vy` near zero:
    /// MS or the middle of DS) placed again from the first
    /// [`START_WINDOW_S`] of samples: in the middle of DS when `vy` rises
    /// over them, its slope over [`TROUGH_EVIDENCE`] standard deviations
    /// above zero, and the gait's step followed from the middle of DS fits
    /// them better than followed from MS (by [`MS_REJECTED`],
    /// [`ms_worse_than_trough`]), else `None` (MS stays).
    fn place_from_window(&mut self, samples: &[Sample]) -> Option<Placement> {
        let first = samples.first()?;
        let measured = first.com.values();
        let seen = samples
            .iter()
            .filter_map(|s| Some((s.t - first.t, s.com.values()[4]?)));
        let (slope, sd) = vy_slope(seen.clone(), NOISE_VY)?;
        if slope <= TROUGH_EVIDENCE * sd {
            return None;
        }
        let (speed, gait) = self.speed_guess(measured[3]);
        if ms_worse_than_trough(&gait, seen, &mut self.profile) <= MS_REJECTED {
            return None;
        }
        let p = mid_double_support(&gait, &mut self.profile);
        Some(self.located(p, &gait, measured[3], speed))
    }

    /// The first sample of a run: placed in the step ([`Self::place`];
    /// the replay's placement from the window, if there is one) and, unless
    /// it is known to be MS, the window of samples opened that places it
    /// again. The feet, the phase and the last MS follow.
    fn start(&mut self, now: f64, x: &State, measured: &[Option<f64>; 6]) {
        let placement = match self.replay_placement.take() {
            Some(p) => p,
            None => {
                let known = core::mem::replace(&mut self.start_at_mid_stance, false);
                let p = self.place(known, measured);
                let flat = measured[4].is_some_and(|vy| vy.abs() <= VY_EVIDENCE);
                if !known && p.located.is_none() && flat {
                    self.window.clear();
                    self.window_open = true;
                }
                p
            }
        };
        let Placement { located, speed } = placement;
        // `start_side` is the stance side of the MS nearest to the start:
        // past the middle of the step that is the coming MS, whose stance
        // foot is the leading one (so that a start just before MS keeps
        // the side a start at MS takes).
        let trailing = match located {
            Some((p, step_time, _)) if p.t > 0.5 * step_time => self.start_side.other(),
            _ => self.start_side,
        };
        let gait = gait_at_speed(&self.family, speed).unwrap_or(self.steps.gait);
        self.steps = StepTracker::new(gait, trailing);
        self.retarget(speed);
        let s = trailing.sign();
        let g = self.steps.gait;
        match located {
            None => {
                self.steps.place_feet([x[0], x[2] - s * g.gait.lateral]);
                self.steps.ms = Some((now, trailing));
            }
            Some((p, step_time, step_length)) => {
                // The point's share of the step, on this gait's step.
                let share = p.t / step_time;
                let advance = p.x / step_length * self.steps.step_length();
                // Laterally the CoM moves from `lateral` off the trailing
                // foot at MS to `width - lateral` at the next MS.
                let off = g.gait.lateral + share * (g.step_width - 2.0 * g.gait.lateral);
                self.steps.place_feet([x[0] - advance, x[2] - s * off]);
                let t_td = g.t_touchdown / g.step_time;
                let t_lo = g.t_lift_off / g.step_time;
                self.steps.phase = if share < t_td {
                    GaitPhase::Ss1
                } else if share < t_lo {
                    GaitPhase::Ds
                } else {
                    GaitPhase::Ss2
                };
                // The crossing detector needs an apex before its first
                // lift-off.
                self.steps.apex_seen = self.steps.phase == GaitPhase::Ss1;
                self.steps.ms = Some((now - share * g.step_time, trailing));
            }
        }
    }

    /// Keeps `sample` in the start's window; once the window spans
    /// [`START_WINDOW_S`], the start is placed from it and, if that differs
    /// from where it was placed, the run is started again there and the
    /// window replayed: the last sample's estimate.
    fn keep_in_window(&mut self, sample: &Sample) -> Option<Result<Estimate, EstimatorError>> {
        if !self.window_open {
            return None;
        }
        self.window.push(*sample);
        let span = sample.t - self.window[0].t;
        if span < START_WINDOW_S - 1e-9 && self.window.len() < WINDOW_CAPACITY {
            return None;
        }
        self.window_open = false;
        // The buffer is lent out while it is read and replayed (nothing
        // opens a window during the replay) and put back, cleared.
        let mut samples = core::mem::take(&mut self.window);
        let replayed = self.replay_from(&samples);
        samples.clear();
        self.window = samples;
        replayed
    }

    /// Places the start again from the window's `samples` and, if that
    /// differs from MS, starts the run again there and replays them.
    fn replay_from(&mut self, samples: &[Sample]) -> Option<Result<Estimate, EstimatorError>> {
        let placement = self.place_from_window(samples)?;
        let side = self.start_side;
        self.reset();
        self.start_side = side;
        self.replay_placement = Some(placement);
        let mut last = None;
        for s in samples {
            match self.step(s) {
                Ok(e) => last = Some(e),
                Err(e) => return Some(Err(e)),
            }
        }
        last.map(Ok)
    }

    /// After the ensemble update: the stance foot located by the mid-height
    /// crossings, phase by the leg lengths, MS when the CoM passes over the
    /// leading foot, then the next step's feet, speed and re-targeting.
    fn advance(&mut self, now: f64, x: &State) {
        let l0 = self.steps.gait.body.rest_length;
        let st = &mut self.steps;
        st.vx_sum.0 += x[3];
        st.vx_sum.1 += 1;
        st.heights = (st.heights.0.min(x[1]), st.heights.1.max(x[1]));
        if let Some(f) = st.crossings.push(now, x[0], x[1]) {
            // The located foot is the nearer of the two: the leading one if
            // the CoM has not yet passed over it (MS is overdue).
            if (f.x - st.leading[0]).abs() < (f.x - st.stance[0]).abs() {
                self.mid_stance(now, x, Some(f));
            } else {
                self.steps.fix(f);
            }
        }
        let st = &mut self.steps;
        let trailing = leg_length(x, st.stance);
        let leading = leg_length(x, st.leading);
        if st.phase == GaitPhase::Ss1 && leading < l0 {
            st.phase = GaitPhase::Ds;
        }
        if st.phase == GaitPhase::Ds && trailing >= l0 {
            st.phase = GaitPhase::Ss2;
            if !st.crossings.started() && st.apex_seen {
                // The first lift-off after an apex (the start at MS, or
                // a tracked MS): an apex and a trough have passed.
                st.crossings.restart(st.heights.0, st.heights.1, x[1]);
            }
        }
        let support = self.support(x);
        self.steps.support.push(now, support);
        if self.steps.phase == GaitPhase::Ss2 && x[0] >= self.steps.leading[0] {
            self.mid_stance(now, x, None);
        }
    }

    /// MS: the leading foot becomes the stance foot (at `fix` if it was
    /// located, else where it was predicted, laterally at the gait's MS
    /// offset from the CoM), the gait is re-targeted to the speed.
    fn mid_stance(&mut self, now: f64, x: &State, fix: Option<FootFix>) {
        let support = self.support(x);
        let st = &mut self.steps;
        let located = st.fixes[0].is_some_and(|(_, s)| s == st.step);
        let body = st.gait.body;
        st.support
            .end_step(now, x[4], support, body.mass, body.gravity, located);
        if st.crossings.started() && st.crossings.crossings() == st.crossings_at_ms {
            // A step without a crossing: the level from its extremes.
            st.crossings.restart(st.heights.0, st.heights.1, x[1]);
        } else {
            st.crossings.set_excursion(st.heights.0, st.heights.1);
        }
        st.heights = (x[1], x[1]);
        st.apex_seen = true;
        st.crossings_at_ms = st.crossings.crossings();
        st.side = st.side.other();
        st.ms = Some((now, st.side));
        st.step += 1;
        let mut foot = [st.leading[0], x[2] - st.side.sign() * st.gait.gait.lateral];
        if fix.is_some() {
            // Located after MS: the CoM has moved on laterally.
            foot[1] = st.leading[1];
        }
        let speed = st.speed;
        self.retarget(speed);
        let st = &mut self.steps;
        st.place_feet(foot);
        if let Some(f) = fix {
            st.fix(f);
        }
    }
}

impl Estimator for ImmContinuous {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn outputs(&self) -> Outputs {
        self.inner.outputs()
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let p = &self.inner.params;
        writeln!(
            out,
            "configuration: continuous (gait family + leg-length phase)"
        )?;
        writeln!(out, "r: {:?}", p.r)?;
        writeln!(out, "q: {:?}", p.q)?;
        writeln!(out, "kappa: {}", p.kappa)?;
        writeln!(out, "weights: {}", p.weights.label())?;
        writeln!(out, "p_next_phase: {}", p.p_next_phase)?;
        writeln!(out, "max_substep: {}", p.max_substep)?;
        writeln!(out, "max_gap: {}", p.max_gap)?;
        for (g, t) in self.family.iter().enumerate() {
            writeln!(
                out,
                "family gait {g:02}: speed {:.3} m/s, step {:.3} x {:.3} m, l0 {:.3} m, m {:.1} kg, k {:.0} N/m",
                t.speed,
                t.step_length,
                t.step_width,
                t.body.rest_length,
                t.body.mass,
                t.body.stiffness
            )?;
        }
        Ok(())
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        self.inner.diagnostic_names()
    }

    fn reset(&mut self) {
        // As `new` left it: the filters' gait is the family's middle one
        // again (an audit: the inner filter restarted on the last run's
        // re-targeted gait, so a reset filter's estimates differed from a
        // new one's from the first sample).
        let middle = self.family[self.family.len() / 2];
        self.inner.templates[0] = middle;
        self.inner.reset();
        self.steps = StepTracker::new(middle, self.first_side);
        self.start_side = self.first_side;
        self.start_at_mid_stance = false;
        self.previous = None;
        self.window.clear();
        self.window_open = false;
        self.replay_placement = None;
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let was_running = self.inner.running;
        let gap = self
            .previous
            .is_some_and(|(t, _)| sample.t - t > self.inner.params.max_gap);
        let mut e = self.inner.step(sample)?;
        if !self.inner.running {
            self.previous = None;
            self.window_open = false;
            return Ok(e);
        }
        let x = self.inner.ensemble.0;
        if !was_running || gap {
            self.previous = None;
            self.window_open = false;
            self.start(sample.t, &x, &sample.com.values());
        }
        self.advance(sample.t, &x);
        self.previous = Some((sample.t, x));
        if let Some(replayed) = self.keep_in_window(sample) {
            return replayed;
        }
        let st = &self.steps;
        self.inner.set_feet(st.stance, st.leading);
        e.phase = Some(st.phase);
        e.speed = Some(if st.measured {
            st.speed
        } else {
            st.vx_sum.0 / st.vx_sum.1.max(1) as f64
        });
        Ok(e)
    }
}
