//! Gait events, stance/swing, gait phase, stride length and walking speed
//! from foot-mounted IMUs in raw (unaligned) sensor frames, one or both feet
//! (`--method gait-events`, docs/GAIT_EVENTS.md).
//!
//! Per foot, each sample:
//! 1. [`zero_velocity`]: is the foot at rest (SHOE, Skog et al. 2010)?
//! 2. [`foot_axis`]: the medio-lateral axis (principal component of the
//!    gyro while moving), signed by the walking direction that
//!    [`strapdown`] found, so `w = d theta / dt` is positive toe-up.
//! 3. [`foot_events`]: initial contact (end-of-swing zero crossing of `w`)
//!    and final contact (push-off extremum of `w`), hence stance/swing.
//! 4. [`strapdown`]: zero-velocity-update integration of each moving period;
//!    a period that contains an initial contact is a stride, its length the
//!    horizontal displacement, its time the interval between this and the
//!    previous initial contact, its speed their ratio.
//!
//! Outputs: `contact_left`, `contact_right`, `phase` (SS1/DS/SS2 from both
//! contacts: double support when both feet are down; single support is
//! split at its predicted midpoint, the first half SS2 (after the other
//! foot's lift-off), the second SS1 (before its touchdown), as in paper
//! 003's B-SLIP), `speed` (the last stride's, held for `speed_hold`).
//! Back-dated event times and per-stride values go to `diag_*` columns.
//!
//! Latency: an initial contact is decided one sample after it; a final
//! contact when the foot's rate exceeds `swing_rate` (tens of ms, reported
//! in docs/RESULTS.md); a stride length when the foot is flat again. The
//! contact columns are causal (they switch when the event is decided). A
//! leg's event (foot or shank) is written one sample after its decision,
//! when the next reading has confirmed it ([`confirmed_events`]: a
//! single-sample gyroscope spike reverses its own).
//! The events before a leg's axis sign was decided are replayed then and
//! written late ([`sign_replay`]). Allocation-free per sample.

pub mod confirmed_events;
pub mod foot_axis;
pub mod foot_events;
mod foot_tracker;
pub mod reading_gap;
pub mod shank_events;
mod shank_tracker;
pub mod sign_replay;
pub mod strapdown;
pub mod trough_time;
pub mod zero_velocity;

use core::fmt;

use limbfuse_core::estimator::Outputs;
use limbfuse_core::{
    diagnostic_set, Estimate, Estimator, EstimatorError, GaitPhase, ImuSample, Sample, Segment,
    Side, TimeStep,
};

use foot_tracker::FootTracker;
use shank_events::ShankContact;
use shank_tracker::ShankTracker;
use zero_velocity::ShoeParams;

diagnostic_set! {
    /// Diagnostics of [`GaitEvents`].
    pub enum GaitDiag {
        /// Time (s) of a left initial contact decided at this sample.
        IcLeft = "ic_left",
        /// Time (s) of a left final contact (toe off) decided at this sample.
        FcLeft = "fc_left",
        /// Time (s) of a right initial contact decided at this sample.
        IcRight = "ic_right",
        /// Time (s) of a right final contact decided at this sample.
        FcRight = "fc_right",
        /// Left stride length (m), at the sample the stride is finished.
        StrideLengthLeft = "stride_length_left",
        /// Right stride length (m).
        StrideLengthRight = "stride_length_right",
        /// Left stride time (s, initial contact to initial contact).
        StrideTimeLeft = "stride_time_left",
        /// Right stride time (s).
        StrideTimeRight = "stride_time_right",
        /// Time (s) the left foot's accelerometer was at its full scale in
        /// the stride just finished (at the sample of its length): a heel
        /// strike clips for up to [`strapdown::IMPACT_CLIP_TIME`], a clipped
        /// swing longer (its stride comes out short).
        StrideClippedLeft = "stride_clipped_left",
        /// The same for the right foot (s).
        StrideClippedRight = "stride_clipped_right",
        /// Mean heading rate (rad/s, signed, counter-clockwise seen from
        /// above) of the left stride just finished, turning or not (a
        /// stride faster than `turn_rate` has no length: it turns).
        StrideTurnRateLeft = "stride_turn_rate_left",
        /// The same for the right foot (rad/s).
        StrideTurnRateRight = "stride_turn_rate_right",
        /// 1 while the left foot is at rest (zero-velocity detector), else 0
        /// (a stride ends only at a rest that lasted `min_rest_time`).
        RestLeft = "rest_left",
        /// 1 while the right foot is at rest, else 0.
        RestRight = "rest_right",
        /// Left foot sagittal rate `d theta / dt` (rad/s), once its axis sign is known.
        RateLeft = "rate_left",
        /// Right foot sagittal rate (rad/s).
        RateRight = "rate_right",
    }
}

/// Where a side's IMU is in a [`Sample`]: a foot IMU (events, stride
/// length, speed) or, for a leg without one, a shank IMU (events only,
/// [`shank_events`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FootSource {
    /// `sample.imu[Foot]` (the trial's `# leg:`).
    OwnLeg,
    /// `sample.other_leg_imu[Foot]`.
    OtherLeg,
    /// `sample.imu[Shank]` (the trial's leg, no foot IMU).
    OwnShank,
    /// `sample.other_leg_imu[Shank]`.
    OtherShank,
}

impl FootSource {
    /// The IMU this source names.
    fn imu(self, sample: &Sample) -> &ImuSample {
        match self {
            FootSource::OwnLeg => &sample.imu[Segment::Foot.index()],
            FootSource::OtherLeg => &sample.other_leg_imu[Segment::Foot.index()],
            FootSource::OwnShank => &sample.imu[Segment::Shank.index()],
            FootSource::OtherShank => &sample.other_leg_imu[Segment::Shank.index()],
        }
    }

    /// How `describe_parameters` names it.
    fn describe(self) -> &'static str {
        match self {
            FootSource::OwnLeg => "foot_ (the trial's leg)",
            FootSource::OtherLeg => "foot_<other side>_",
            FootSource::OwnShank => "shank_ (the trial's leg; events only)",
            FootSource::OtherShank => "shank_<other side>_ (events only)",
        }
    }
}

/// Parameters (defaults and their sources: docs/GAIT_EVENTS.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaitEventsParams {
    /// Zero-velocity detector (Skog et al. 2010 OpenShoe values).
    pub shoe: ShoeParams,
    /// Sagittal rate (rad/s) above which the foot is in swing: 1.0, well
    /// below the mid-swing foot rate of walking (4-8 rad/s at 0.5-1.5 m/s).
    pub swing_rate: f64,
    /// Shortest swing (s) before an initial contact is accepted: 0.15
    /// (walking swings last 0.35-0.5 s).
    pub min_swing_time: f64,
    /// Shortest rest (s) that ends a moving period (the stride integration's
    /// zero-velocity update): 0.05. A walking foot-flat lasts 0.13 s or more
    /// at up to 1.8 m/s (the walking simulator; a median 0.25 s per stance
    /// on the shared real walk), while a slow swing can hold still in
    /// rotation and acceleration for 0.02 s, which the detector calls a rest
    /// (docs/GAIT_EVENTS.md, "Rest of the foot"). 0 ends a moving period at
    /// the first rest sample (the behaviour before 2026-12-04). The same
    /// rest is the stance's foot flat, after which the push-off lobe is
    /// looked for ([`foot_events`]).
    pub min_rest_time: f64,
    /// Averaging time constant (s) of the medio-lateral axis: 10.
    pub axis_time_constant: f64,
    /// Longest moving period (s) integrated: 3.0 (a longer one is not a stride).
    pub max_moving_time: f64,
    /// Shortest horizontal displacement (m) that votes for the axis sign: 0.2.
    pub min_vote_length: f64,
    /// Shortest stride time (s): 0.4.
    pub min_stride_time: f64,
    /// Longest stride time (s): 3.0 (longer: not continuous walking).
    pub max_stride_time: f64,
    /// How long (s) a stride's speed is held as the `speed` output: 3.0.
    pub speed_hold: f64,
    /// Mean heading rate (rad/s) above which a stride turns and has no
    /// length or speed: 15 deg/s, the turn threshold of El-Gohary et al.
    /// 2014 that `lowback-speed` uses (docs/GAIT_EVENTS.md "Turning
    /// strides": in a turn the foot's displacement depends on the point of
    /// the foot it is taken at, by up to `2 r sin(dpsi / 2)`, and is not
    /// the walking distance).
    pub turn_rate: f64,
    /// Gravity (m/s^2), from the trial's metadata.
    pub gravity: f64,
    /// Accelerometer full scale (m/s^2): the trial's `acc_range_m_s2`
    /// metadata when given, else 16 g (the widest full scale of the IMUs
    /// used in gait work, the sensor gate's default). An axis at or beyond
    /// [`strapdown::ACC_CLIP_FRACTION`] of it is clipped, and the stride
    /// integration attributes the lost velocity change to it
    /// ([`strapdown`], docs/GAIT_EVENTS.md "Clipped impacts").
    pub acc_full_scale: f64,
    /// Initial-contact landmark of a shank IMU ([`shank_events`]).
    pub shank_contact: ShankContact,
}

impl Default for GaitEventsParams {
    fn default() -> Self {
        GaitEventsParams {
            shoe: ShoeParams::default(),
            swing_rate: 1.0,
            min_swing_time: 0.15,
            min_rest_time: 0.05,
            axis_time_constant: 10.0,
            max_moving_time: 3.0,
            min_vote_length: 0.2,
            min_stride_time: 0.4,
            max_stride_time: 3.0,
            speed_hold: 3.0,
            turn_rate: 15.0 * core::f64::consts::PI / 180.0,
            gravity: limbfuse_core::STANDARD_GRAVITY,
            acc_full_scale: 16.0 * 9.80665,
            shank_contact: ShankContact::ZeroCrossing,
        }
    }
}

/// One finished stride of one foot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stride {
    /// Horizontal length (m).
    pub length: f64,
    /// Initial contact to initial contact (s).
    pub time: f64,
    /// Time (s) its accelerometer was at full scale while the foot moved
    /// ([`strapdown::Segment::clipped_time`]).
    pub clipped_time: f64,
    /// Mean heading rate (rad/s, signed, counter-clockwise seen from
    /// above): the foot's heading change from the rest before the stride's
    /// swing to the rest after it ([`strapdown::Segment::heading_change`])
    /// over the stride time.
    pub turn_rate: f64,
}

impl Stride {
    /// The stride turns faster than `turn_rate` (rad/s): its length and
    /// speed are withheld (docs/GAIT_EVENTS.md "Turning strides").
    pub fn turns(&self, turn_rate: f64) -> bool {
        libm::fabs(self.turn_rate) > turn_rate
    }
}

/// What one foot gave at one sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct FootOutput {
    contact: Option<bool>,
    initial_contact: Option<f64>,
    final_contact: Option<f64>,
    stride: Option<Stride>,
    rest: Option<bool>,
    rate: Option<f64>,
}

/// A leg's last toe off and last swing duration (for the phase).
#[derive(Debug, Clone, Copy, Default)]
struct SwingTimes {
    last_fc: Option<f64>,
    last_swing: Option<f64>,
}

impl SwingTimes {
    /// Last toe off and last swing duration had `e` been recorded too (a
    /// decision held for confirmation, [`confirmed_events`]).
    fn with(&self, e: foot_events::EventsAt) -> (Option<f64>, Option<f64>) {
        let mut times = *self;
        times.record(e);
        (times.last_fc, times.last_swing)
    }

    /// Records one sample's events (in time order: live, or replayed).
    fn record(&mut self, e: foot_events::EventsAt) {
        if let Some(t_fc) = e.final_contact {
            self.last_fc = Some(t_fc);
        }
        if let Some(t_ic) = e.initial_contact {
            if let Some(t_fc) = self.last_fc {
                self.last_swing = Some(t_ic - t_fc);
            }
        }
    }
}

/// One side's pipeline (two per estimator, made once with the estimator:
/// the foot variant's buffer of undecided readings is its only allocation,
/// and `reset` keeps it).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
enum LegTracker {
    Foot(FootTracker),
    Shank(ShankTracker),
}

impl LegTracker {
    fn new(p: &GaitEventsParams, source: Option<FootSource>) -> Self {
        match source {
            Some(FootSource::OwnShank | FootSource::OtherShank) => {
                LegTracker::Shank(ShankTracker::new(p))
            }
            _ => LegTracker::Foot(FootTracker::new(p)),
        }
    }

    /// Back to the starting state (no allocation).
    fn reset(&mut self, p: &GaitEventsParams) {
        match self {
            LegTracker::Foot(f) => f.reset(p),
            LegTracker::Shank(s) => s.reset(p),
        }
    }

    fn step(&mut self, p: &GaitEventsParams, t: f64, dt: f64, imu: &ImuSample) -> FootOutput {
        match self {
            LegTracker::Foot(f) => f.step(p, t, dt, imu),
            LegTracker::Shank(s) => s.step(p, t, dt, imu),
        }
    }

    /// Last toe off and last swing duration (s).
    fn swing(&self) -> (Option<f64>, Option<f64>) {
        match self {
            LegTracker::Foot(f) => f.swing.with(f.events.held_events()),
            LegTracker::Shank(s) => s.swing.with(s.events.held_events()),
        }
    }
}

/// The gait-events estimator.
#[derive(Debug, Clone)]
pub struct GaitEvents {
    params: GaitEventsParams,
    sources: [Option<FootSource>; 2],
    feet: [LegTracker; 2],
    time: TimeStep,
    speed: Option<(f64, f64)>,
    strides: u64,
}

impl GaitEvents {
    /// An estimator for the feet in `sources` (indexed by [`Side::index`]);
    /// at least one must be present.
    pub fn new(
        params: GaitEventsParams,
        sources: [Option<FootSource>; 2],
    ) -> Result<Self, EstimatorError> {
        if sources.iter().all(Option::is_none) {
            return Err(EstimatorError::MissingChannel {
                channel: "foot_acc_* and foot_gyr_* (or foot_left_*, or shank_gyr_*): gait-events needs a foot or shank IMU",
            });
        }
        Ok(GaitEvents {
            params,
            sources,
            feet: [
                LegTracker::new(&params, sources[0]),
                LegTracker::new(&params, sources[1]),
            ],
            time: TimeStep::new(),
            speed: None,
            strides: 0,
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &GaitEventsParams {
        &self.params
    }

    /// Strides found so far (both feet).
    pub fn strides_found(&self) -> u64 {
        self.strides
    }

    fn phase(&self, t: f64, contact: [Option<bool>; 2]) -> Option<GaitPhase> {
        let (Some(l), Some(r)) = (contact[0], contact[1]) else {
            return None;
        };
        let swing_side = match (l, r) {
            (true, true) => return Some(GaitPhase::Ds),
            (false, false) => return None,
            (true, false) => Side::Right,
            (false, true) => Side::Left,
        };
        let (lift_off, last_swing) = self.feet[swing_side.index()].swing();
        let lift_off = lift_off?;
        // Predicted single support = the swing foot's last swing duration.
        let predicted = last_swing.unwrap_or(0.4);
        Some(if t - lift_off < 0.5 * predicted {
            GaitPhase::Ss2
        } else {
            GaitPhase::Ss1
        })
    }
}

impl Estimator for GaitEvents {
    fn name(&self) -> &'static str {
        "gait-events"
    }

    /// A foot's rate clipped at the gyroscope's full scale still says the
    /// foot swings, and a swing of missing readings loses the stride (a
    /// gyroscope clipped at 250 deg/s, its range stated, lost every swing
    /// to the gate: "no gait found" on a simulated walk, 22 of 56 contacts
    /// and 0.53 m/s on the gaitmap walk; passed on, 0.14 m/s).
    fn keeps_clipped_gyro(&self) -> bool {
        true
    }

    /// Clipped accelerometer readings are kept too: the stride integration
    /// needs every sample of the swing, and models a clipped impact
    /// ([`strapdown`] step 4).
    fn keeps_clipped_acc(&self) -> bool {
        true
    }

    fn outputs(&self) -> Outputs {
        Outputs {
            phase: true,
            speed: true,
            contact: true,
            ..Outputs::default()
        }
    }

    fn describe_parameters(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let p = &self.params;
        for side in Side::BOTH {
            let src = self.sources[side.index()].map_or("none", FootSource::describe);
            writeln!(out, "foot_{}: {src}", side.name())?;
        }
        writeln!(
            out,
            "shoe: window {} samples, sigma_acc {} m/s^2, sigma_gyr {} rad/s, gamma {}",
            p.shoe.window, p.shoe.sigma_acc, p.shoe.sigma_gyr, p.shoe.gamma
        )?;
        writeln!(out, "swing_rate: {} rad/s", p.swing_rate)?;
        writeln!(out, "min_swing_time: {} s", p.min_swing_time)?;
        writeln!(out, "min_rest_time: {} s", p.min_rest_time)?;
        writeln!(out, "axis_time_constant: {} s", p.axis_time_constant)?;
        writeln!(out, "max_moving_time: {} s", p.max_moving_time)?;
        writeln!(out, "min_vote_length: {} m", p.min_vote_length)?;
        writeln!(
            out,
            "stride_time: {} - {} s",
            p.min_stride_time, p.max_stride_time
        )?;
        writeln!(out, "speed_hold: {} s", p.speed_hold)?;
        writeln!(
            out,
            "turn_rate: {:.6} deg/s (a stride turning faster has no length or speed)",
            p.turn_rate.to_degrees()
        )?;
        writeln!(
            out,
            "acc_full_scale: {} m/s^2 (clipped from {} of it)",
            p.acc_full_scale,
            strapdown::ACC_CLIP_FRACTION
        )?;
        if self
            .sources
            .iter()
            .flatten()
            .any(|s| matches!(s, FootSource::OwnShank | FootSource::OtherShank))
        {
            writeln!(out, "shank_contact: {:?}", p.shank_contact)?;
        }
        writeln!(out, "gravity: {} m/s^2", p.gravity)
    }

    fn diagnostic_names(&self) -> &[&'static str] {
        &GaitDiag::NAMES
    }

    fn reset(&mut self) {
        for foot in &mut self.feet {
            foot.reset(&self.params);
        }
        self.time = TimeStep::new();
        self.speed = None;
        self.strides = 0;
    }

    fn step(&mut self, sample: &Sample) -> Result<Estimate, EstimatorError> {
        let t = sample.t;
        let dt = self.time.advance(t)?;
        let mut e = Estimate::empty(t);
        let Some(dt) = dt else {
            return Ok(e);
        };
        let mut outs = [FootOutput::default(); 2];
        for side in Side::BOTH {
            let Some(source) = self.sources[side.index()] else {
                continue;
            };
            let imu = source.imu(sample);
            if imu.acc.is_some_and(|a| !a.iter().all(|v| v.is_finite()))
                || imu.gyr.is_some_and(|g| !g.iter().all(|v| v.is_finite()))
            {
                return Err(EstimatorError::NonFinite {
                    channel: "foot or shank IMU",
                });
            }
            outs[side.index()] = self.feet[side.index()].step(&self.params, t, dt, imu);
        }
        for (side, o) in outs.iter().enumerate() {
            e.contact[side] = o.contact;
            if let Some(s) = o.stride {
                self.strides += 1;
                if !s.turns(self.params.turn_rate) {
                    self.speed = Some((s.length / s.time, t));
                }
            }
        }
        e.phase = self.phase(t, e.contact);
        e.speed = self
            .speed
            .filter(|(_, at)| t - at <= self.params.speed_hold)
            .map(|(v, _)| v);
        let mut d = e.diagnostics_mut::<GaitDiag>();
        let keys = [
            (
                GaitDiag::IcLeft,
                GaitDiag::FcLeft,
                GaitDiag::StrideLengthLeft,
                GaitDiag::StrideTimeLeft,
                GaitDiag::StrideClippedLeft,
                GaitDiag::StrideTurnRateLeft,
                GaitDiag::RestLeft,
                GaitDiag::RateLeft,
            ),
            (
                GaitDiag::IcRight,
                GaitDiag::FcRight,
                GaitDiag::StrideLengthRight,
                GaitDiag::StrideTimeRight,
                GaitDiag::StrideClippedRight,
                GaitDiag::StrideTurnRateRight,
                GaitDiag::RestRight,
                GaitDiag::RateRight,
            ),
        ];
        let turn_rate = self.params.turn_rate;
        for (o, (ic, fc, len, time, clipped, turn, rest, rate)) in outs.iter().zip(keys) {
            d.set(ic, o.initial_contact);
            d.set(fc, o.final_contact);
            d.set(
                len,
                o.stride.filter(|s| !s.turns(turn_rate)).map(|s| s.length),
            );
            d.set(time, o.stride.map(|s| s.time));
            d.set(clipped, o.stride.map(|s| s.clipped_time));
            d.set(turn, o.stride.map(|s| s.turn_rate));
            d.set(rest, o.rest.map(|r| if r { 1.0 } else { 0.0 }));
            d.set(rate, o.rate);
        }
        Ok(e)
    }
}
