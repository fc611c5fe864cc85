//! The pipeline of one leg with a shank IMU only (no foot IMU): events
//! from the shank's sagittal rate ([`super::shank_events`]), no strides.

use limbfuse_core::ImuSample;

use super::confirmed_events::ConfirmedEvents;
use super::reading_gap::ReadingGap;
use super::shank_events::{ShankAxis, ShankEvents};
use super::sign_replay::{LateEvents, Reading, UndecidedReadings};
use super::{FootOutput, GaitEventsParams, SwingTimes};

/// The pipeline of one leg with a shank IMU only: events, no strides.
#[derive(Debug, Clone)]
pub(super) struct ShankTracker {
    axis: ShankAxis,
    pub(super) events: ConfirmedEvents<ShankEvents>,
    sign: i32,
    pub(super) swing: SwingTimes,
    gap: ReadingGap,
    undecided: UndecidedReadings,
    late: LateEvents,
}

impl ShankTracker {
    pub(super) fn new(p: &GaitEventsParams) -> Self {
        ShankTracker::with_buffer(p, UndecidedReadings::default())
    }

    /// A tracker in its starting state with `undecided` (emptied) as its
    /// buffer of undecided readings.
    fn with_buffer(p: &GaitEventsParams, mut undecided: UndecidedReadings) -> Self {
        undecided.clear();
        ShankTracker {
            axis: ShankAxis::new(p.axis_time_constant),
            events: ConfirmedEvents::new(
                ShankEvents::new(p.swing_rate, p.min_swing_time, p.shank_contact),
                p.swing_rate,
            ),
            sign: 0,
            swing: SwingTimes::default(),
            gap: ReadingGap::default(),
            undecided,
            late: LateEvents::default(),
        }
    }

    /// Back to the starting state, keeping the buffer (no allocation).
    pub(super) fn reset(&mut self, p: &GaitEventsParams) {
        let undecided = core::mem::replace(&mut self.undecided, UndecidedReadings::empty());
        *self = ShankTracker::with_buffer(p, undecided);
    }

    /// The sign was just decided: the readings kept since the start (or the
    /// last restart) go through the event detector ([`sign_replay`]).
    fn replay_undecided(&mut self) {
        for i in 0..self.undecided.len() {
            let r = self.undecided.get(i);
            if let Some(w) = self.axis.sagittal_rate(&r.gyr) {
                let e = self.events.update(w, |d| d.update(r.t, w));
                self.swing.record(e);
                self.late.push(e);
            }
        }
    }

    pub(super) fn step(
        &mut self,
        p: &GaitEventsParams,
        t: f64,
        dt: f64,
        imu: &ImuSample,
    ) -> FootOutput {
        let Some(gyr) = imu.gyr else {
            return FootOutput::default();
        };
        let dt = self
            .gap
            .reading(t, dt, p.min_swing_time)
            .unwrap_or_else(|| {
                self.events.reset();
                self.undecided.clear();
                dt
            });
        let mut out = FootOutput::default();
        self.axis.update(&gyr, dt);
        let sign = self.axis.sign();
        if sign != self.sign {
            let decided = self.sign == 0;
            self.sign = sign;
            self.events.reset();
            if decided {
                self.replay_undecided();
            }
            self.undecided.clear();
        }
        if self.sign == 0 {
            self.undecided.push(Reading {
                t,
                dt,
                gyr,
                rest: false,
            });
        }
        if let Some(w) = self.axis.sagittal_rate(&gyr) {
            out.rate = Some(w);
            let e = self.events.update(w, |d| d.update(t, w));
            self.swing.record(e);
            self.late.push(e);
        }
        let written = self.late.pop();
        out.initial_contact = written.initial_contact;
        out.final_contact = written.final_contact;
        out.contact = self.events.contact();
        out
    }
}
