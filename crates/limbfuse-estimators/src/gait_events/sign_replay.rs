//! The events before a leg's axis sign was known, replayed and reported
//! late.
//!
//! A leg's events need the sign of its medio-lateral axis: a foot's comes
//! from its first stride's walking direction ([`super::foot_axis`]), a
//! shank's from 2 s of data ([`super::shank_events`]). A causal detector
//! has no events until then. Before 2026-12-04 they were lost, so a
//! recording that starts mid-walk (or with the first steps) missed each
//! foot's first initial and final contact (a shank's first two strides).
//! Instead, the readings of a leg whose sign is undecided are kept
//! ([`UndecidedReadings`]), and once the sign is decided they are replayed
//! through a fresh event detector with the signed axis. The replayed events
//! carry their own (back-dated) times and are written on the rows after the
//! decision, one per row and kind ([`LateEvents`]), as every event is
//! written on the row where it is decided. The contact columns stay causal:
//! they start at the decision.
//!
//! [`CAPACITY`] readings are kept (the latest ones): 10 s at 204.8 Hz,
//! 2 s at 1 kHz, more than a foot's stride (about 1.1 s) with the rest
//! before it, or a shank's 2 s, at any usual rate. Nothing allocates per
//! sample: the buffer is made with the tracker.

use alloc::boxed::Box;

use nalgebra::Vector3;

use super::foot_events::EventsAt;

/// Readings kept while a foot's axis sign is undecided.
pub const CAPACITY: usize = 2048;

/// Most events of one kind waiting for their row ([`LateEvents`]).
pub const LATE_CAPACITY: usize = 8;

/// One reading of a foot, as the event detector takes it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Reading {
    /// Time (s).
    pub t: f64,
    /// Step (s) since the foot's previous reading.
    pub dt: f64,
    /// Gyroscope (rad/s, sensor frame).
    pub gyr: Vector3<f64>,
    /// The zero-velocity detector's verdict.
    pub rest: bool,
}

/// The latest [`CAPACITY`] readings of a foot whose axis sign is undecided
/// (a ring buffer: a full one forgets its oldest reading).
#[derive(Debug, Clone)]
pub struct UndecidedReadings {
    ring: Box<[Reading]>,
    start: usize,
    len: usize,
}

impl Default for UndecidedReadings {
    fn default() -> Self {
        UndecidedReadings {
            ring: alloc::vec![Reading::default(); CAPACITY].into_boxed_slice(),
            start: 0,
            len: 0,
        }
    }
}

impl UndecidedReadings {
    /// A buffer of no capacity (allocates nothing): a placeholder while the
    /// real one is borrowed; it keeps nothing.
    pub fn empty() -> Self {
        UndecidedReadings {
            ring: Box::default(),
            start: 0,
            len: 0,
        }
    }

    /// Forgets every reading (keeps the buffer).
    pub fn clear(&mut self) {
        self.start = 0;
        self.len = 0;
    }

    /// Keeps `r`, forgetting the oldest reading when full (nothing for
    /// [`UndecidedReadings::empty`]).
    pub fn push(&mut self, r: Reading) {
        let cap = self.ring.len();
        if cap == 0 {
            return;
        }
        if self.len < cap {
            self.ring[(self.start + self.len) % cap] = r;
            self.len += 1;
        } else {
            self.ring[self.start] = r;
            self.start = (self.start + 1) % cap;
        }
    }

    /// Readings kept.
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` when none is kept.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The `i`-th reading kept, oldest first (`i < len()`).
    pub fn get(&self, i: usize) -> Reading {
        self.ring[(self.start + i) % self.ring.len()]
    }
}

/// Event times of one kind waiting to be written, one per row, oldest
/// first (at most [`LATE_CAPACITY`]; a full queue forgets its oldest).
#[derive(Debug, Clone, Copy, Default)]
pub struct TimeQueue {
    times: [f64; LATE_CAPACITY],
    start: usize,
    len: usize,
}

impl TimeQueue {
    /// Queues an event at `t` (s).
    pub fn push(&mut self, t: f64) {
        if self.len < LATE_CAPACITY {
            self.times[(self.start + self.len) % LATE_CAPACITY] = t;
            self.len += 1;
        } else {
            self.times[self.start] = t;
            self.start = (self.start + 1) % LATE_CAPACITY;
        }
    }

    /// The oldest queued event, removed.
    pub fn pop(&mut self) -> Option<f64> {
        if self.len == 0 {
            return None;
        }
        let t = self.times[self.start];
        self.start = (self.start + 1) % LATE_CAPACITY;
        self.len -= 1;
        Some(t)
    }
}

/// A leg's initial and final contacts waiting for their rows: with no
/// replay each is written on the row where it is decided, as before.
#[derive(Debug, Clone, Copy, Default)]
pub struct LateEvents {
    initial: TimeQueue,
    last: TimeQueue,
}

impl LateEvents {
    /// Queues the events decided at one sample (live or replayed).
    pub fn push(&mut self, e: EventsAt) {
        if let Some(t) = e.final_contact {
            self.last.push(t);
        }
        if let Some(t) = e.initial_contact {
            self.initial.push(t);
        }
    }

    /// The events to write on this row: the oldest queued of each kind.
    pub fn pop(&mut self) -> EventsAt {
        EventsAt {
            initial_contact: self.initial.pop(),
            final_contact: self.last.pop(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(t: f64) -> Reading {
        Reading {
            t,
            dt: 0.01,
            gyr: Vector3::new(t, 0.0, 0.0),
            rest: false,
        }
    }

    #[test]
    fn a_full_ring_keeps_the_latest_readings_in_order() {
        let mut r = UndecidedReadings::default();
        for i in 0..CAPACITY + 5 {
            r.push(reading(i as f64));
        }
        assert_eq!(r.len(), CAPACITY);
        let times: alloc::vec::Vec<f64> = (0..r.len()).map(|i| r.get(i).t).collect();
        assert_eq!(times[0], 5.0);
        assert_eq!(*times.last().unwrap(), (CAPACITY + 4) as f64);
        assert!(times.windows(2).all(|w| w[1] == w[0] + 1.0));
        r.clear();
        assert!(r.is_empty());
        r.push(reading(7.0));
        assert_eq!(
            (0..r.len())
                .map(|i| r.get(i).t)
                .collect::<alloc::vec::Vec<_>>(),
            vec![7.0]
        );
    }

    #[test]
    fn queued_times_come_out_oldest_first_and_a_full_queue_drops_the_oldest() {
        let mut q = TimeQueue::default();
        assert_eq!(q.pop(), None);
        q.push(1.0);
        q.push(2.0);
        assert_eq!(q.pop(), Some(1.0));
        q.push(3.0);
        assert_eq!(q.pop(), Some(2.0));
        assert_eq!(q.pop(), Some(3.0));
        assert_eq!(q.pop(), None);
        for i in 0..LATE_CAPACITY + 2 {
            q.push(i as f64);
        }
        let out: alloc::vec::Vec<f64> = core::iter::from_fn(|| q.pop()).collect();
        assert_eq!(out.len(), LATE_CAPACITY);
        assert_eq!(out[0], 2.0);
        assert_eq!(*out.last().unwrap(), (LATE_CAPACITY + 1) as f64);
    }
}
