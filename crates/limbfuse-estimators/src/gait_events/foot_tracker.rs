//! The pipeline of one foot IMU: rest detector, medio-lateral axis, events,
//! stride integration (docs/GAIT_EVENTS.md, `gait-events` steps 1-4), and
//! the late report of the events before the axis sign was known
//! ([`super::sign_replay`]).

use limbfuse_core::ImuSample;

use super::confirmed_events::ConfirmedEvents;
use super::foot_axis::FootAxis;
use super::foot_events::{EventsAt, FootEvents};
use super::reading_gap::ReadingGap;
use super::sign_replay::{LateEvents, Reading, UndecidedReadings};
use super::strapdown::StrideIntegrator;
use super::zero_velocity::Shoe;
use super::{FootOutput, GaitEventsParams, Stride, SwingTimes};
use crate::cell_hold::CellHold;

/// The pipeline of one foot.
#[derive(Debug, Clone)]
pub(super) struct FootTracker {
    shoe: Shoe,
    axis: FootAxis,
    pub(super) events: ConfirmedEvents<FootEvents>,
    integrator: StrideIntegrator,
    sign: i32,
    ics_in_segment: u32,
    last_ic: Option<f64>,
    ic_in_segment: Option<f64>,
    stride_start_ic: Option<f64>,
    pub(super) swing: SwingTimes,
    gap: ReadingGap,
    cells: CellHold,
    /// How long (s) the detector has said "rest" without a break.
    rest_time: f64,
    undecided: UndecidedReadings,
    late: LateEvents,
}

impl FootTracker {
    pub(super) fn new(p: &GaitEventsParams) -> Self {
        FootTracker::with_buffer(p, UndecidedReadings::default())
    }

    /// A tracker in its starting state with `undecided` (emptied) as its
    /// buffer of undecided readings.
    fn with_buffer(p: &GaitEventsParams, mut undecided: UndecidedReadings) -> Self {
        undecided.clear();
        FootTracker {
            shoe: Shoe::new(p.shoe),
            axis: FootAxis::new(p.axis_time_constant),
            events: ConfirmedEvents::new(
                FootEvents::new(p.swing_rate, p.min_swing_time, p.min_rest_time),
                p.swing_rate,
            ),
            integrator: StrideIntegrator::new(p.max_moving_time, p.acc_full_scale),
            sign: 0,
            ics_in_segment: 0,
            last_ic: None,
            ic_in_segment: None,
            stride_start_ic: None,
            swing: SwingTimes::default(),
            gap: ReadingGap::default(),
            cells: CellHold::default(),
            rest_time: 0.0,
            undecided,
            late: LateEvents::default(),
        }
    }

    /// Back to the state of [`FootTracker::new`], keeping the buffer of
    /// undecided readings (no allocation).
    pub(super) fn reset(&mut self, p: &GaitEventsParams) {
        let undecided = core::mem::replace(&mut self.undecided, UndecidedReadings::empty());
        *self = FootTracker::with_buffer(p, undecided);
    }

    fn dropout(&mut self) {
        self.shoe.reset();
        self.rest_time = 0.0;
        self.integrator.reset();
        self.events.reset();
        self.ic_in_segment = None;
        self.ics_in_segment = 0;
        self.last_ic = None;
        // A toe off before the gap does not start a swing after it (the
        // phase would split that swing from it).
        self.swing.last_fc = None;
        // (readings before a long gap are not replayed across it)
        self.undecided.clear();
    }

    /// The events of one sample: kept for the phase and the strides, and
    /// queued for output.
    fn record(&mut self, e: EventsAt) {
        self.swing.record(e);
        self.late.push(e);
        if let Some(t_ic) = e.initial_contact {
            self.stride_start_ic = self.last_ic;
            self.ic_in_segment = Some(t_ic);
            self.ics_in_segment += 1;
            self.last_ic = Some(t_ic);
        }
    }

    /// The axis sign was just decided: the readings kept since the start
    /// (or the last restart) go through the event detector with the signed
    /// axis ([`super::sign_replay`]). They end with the stride that
    /// decided the sign, whose moving period is over: its initial contact
    /// opens the next stride, and no contact is left in the current one.
    fn replay_undecided(&mut self) {
        let Some(axis) = self.axis.right_axis() else {
            return;
        };
        for i in 0..self.undecided.len() {
            let r = self.undecided.get(i);
            let w = axis.dot(&r.gyr);
            let e = self.events.update(w, |d| d.update(r.t, r.dt, w, r.rest));
            self.record(e);
        }
        self.ic_in_segment = None;
        self.ics_in_segment = 0;
    }

    pub(super) fn step(
        &mut self,
        p: &GaitEventsParams,
        t: f64,
        dt: f64,
        imu: &ImuSample,
    ) -> FootOutput {
        let (Some(acc), Some(gyr)) = self.cells.complete(t, imu, p.min_swing_time) else {
            // No reading: bridged, or the pipeline restarts, at the next one.
            return FootOutput::default();
        };
        let dt = self
            .gap
            .reading(t, dt, p.min_swing_time)
            .unwrap_or_else(|| {
                self.dropout();
                dt
            });
        let mut out = FootOutput::default();
        let rest = self.shoe.update(&acc, &gyr, p.gravity);
        out.rest = Some(rest);
        if !rest {
            self.axis.update(&gyr, dt);
        }
        let axis_sign = self.axis.sign();
        if axis_sign != self.sign {
            // The sign was decided or reversed: events from the other sign are void.
            let decided = self.sign == 0;
            self.sign = axis_sign;
            self.events.reset();
            self.last_ic = None;
            self.ic_in_segment = None;
            self.ics_in_segment = 0;
            if decided {
                self.replay_undecided();
            }
            self.undecided.clear();
        }
        if self.sign == 0 {
            self.undecided.push(Reading { t, dt, gyr, rest });
        }
        if let Some(w) = self.axis.sagittal_rate(&gyr) {
            out.rate = Some(w);
            let e = self.events.update(w, |d| d.update(t, dt, w, rest));
            self.record(e);
        }
        let written = self.late.pop();
        out.initial_contact = written.initial_contact;
        out.final_contact = written.final_contact;
        out.contact = self.events.contact();
        // The stride integration stops at a rest that has lasted
        // `min_rest_time` (this sample included), not at a moment of a
        // slow swing that holds still.
        self.rest_time = if rest { self.rest_time + dt } else { 0.0 };
        let settled = rest && self.rest_time >= p.min_rest_time - 1e-9;
        if let Some(seg) = self.integrator.update(settled, &acc, &gyr, dt) {
            let length = seg.horizontal_length();
            if length >= p.min_vote_length {
                self.axis
                    .vote(&seg.forward_in_sensor.cross(&seg.up_in_sensor));
            }
            let one_contact = core::mem::take(&mut self.ics_in_segment) == 1;
            if let (Some(end), Some(start)) = (self.ic_in_segment.take(), self.stride_start_ic) {
                let time = end - start;
                if one_contact && (p.min_stride_time..=p.max_stride_time).contains(&time) {
                    out.stride = Some(Stride {
                        length,
                        time,
                        clipped_time: seg.clipped_time,
                        turn_rate: seg.heading_change / time,
                    });
                }
            }
        }
        out
    }
}
