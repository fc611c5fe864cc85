//! The data window of Algorithm 3: a fixed-capacity ring buffer of both
//! IMUs' readings, allocated once, the kinematics (with the rate
//! derivative) of its samples, and, ours (2026-12-07), the samples left out
//! of the position fit as outliers ([`super::position_outliers`]).

use alloc::vec::Vec;

use nalgebra::Vector3;

use super::position::{
    central_derivative, central_difference, rate_derivative, rate_derivative3, Kinematics,
};
use super::stamp_clock::StampClock;

/// Both IMUs' readings at one sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Slot {
    /// Time (s).
    pub t: f64,
    /// Thigh and shank angular rates (rad/s).
    pub gyr: [Vector3<f64>; 2],
    /// Thigh and shank specific forces (m/s^2).
    pub acc: [Vector3<f64>; 2],
    /// Both gyros present and unsaturated.
    pub gyr_ok: bool,
    /// Both accelerometers present.
    pub acc_ok: bool,
}

/// The last `capacity` samples, oldest first, and the time base of their
/// rate derivatives ([`StampClock`], which sees every sample pushed).
#[derive(Debug, Clone)]
pub struct Ring {
    slots: Vec<Slot>,
    /// Per slot: left out of [`Ring::kinematics`] as an outlier of the
    /// position fit ([`super::position_outliers`]); cleared when the slot is
    /// written.
    excluded: Vec<bool>,
    /// Room for one indexed value and one value per sample
    /// ([`Ring::take_scratch`]).
    scratch: (Vec<(usize, f64)>, Vec<f64>),
    head: usize,
    len: usize,
    clock: StampClock,
}

impl Ring {
    /// An empty ring; the only allocations.
    pub fn new(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Ring {
            slots: alloc::vec![Slot::default(); capacity],
            excluded: alloc::vec![false; capacity],
            scratch: (Vec::with_capacity(capacity), Vec::with_capacity(capacity)),
            head: 0,
            len: 0,
            clock: StampClock::default(),
        }
    }

    /// Appends a sample, dropping the oldest when full.
    pub fn push(&mut self, s: Slot) {
        self.clock.observe(&s);
        let cap = self.slots.len();
        let idx = (self.head + self.len) % cap;
        self.slots[idx] = s;
        self.excluded[idx] = false;
        if self.len < cap {
            self.len += 1;
        } else {
            self.head = (self.head + 1) % cap;
        }
    }

    /// Number of samples held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Forgets every sample; the time base stays (samples pushed again
    /// are not newer than the last one, and [`StampClock`] ignores them).
    pub fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
        self.clear_excluded();
    }

    /// Leaves sample `i` out of [`Ring::kinematics`] until it is
    /// overwritten or [`Ring::clear_excluded`].
    pub fn exclude(&mut self, i: usize) {
        let idx = (self.head + i) % self.slots.len();
        self.excluded[idx] = true;
    }

    /// Whether sample `i` is left out ([`Ring::exclude`]).
    pub fn is_excluded(&self, i: usize) -> bool {
        self.excluded[(self.head + i) % self.slots.len()]
    }

    /// Takes every sample back into [`Ring::kinematics`].
    pub fn clear_excluded(&mut self) {
        self.excluded.iter_mut().for_each(|x| *x = false);
    }

    /// The ring's buffers of one indexed value and one value per sample,
    /// emptied, for a pass over the window without allocating; give them
    /// back with [`Ring::put_scratch`].
    pub fn take_scratch(&mut self) -> (Vec<(usize, f64)>, Vec<f64>) {
        let (mut a, mut b) = core::mem::take(&mut self.scratch);
        a.clear();
        b.clear();
        (a, b)
    }

    /// Returns the buffers [`Ring::take_scratch`] gave.
    pub fn put_scratch(&mut self, v: (Vec<(usize, f64)>, Vec<f64>)) {
        self.scratch = v;
    }

    /// [`StampClock::last_grid_step`] of the samples pushed.
    pub fn last_grid_step(&self) -> Option<f64> {
        self.clock.last_grid_step()
    }

    /// Forgets every sample and the time base.
    pub fn reset(&mut self) {
        self.clear();
        self.clock.reset();
    }

    /// The `i`-th oldest sample.
    pub fn get(&self, i: usize) -> &Slot {
        &self.slots[(self.head + i) % self.slots.len()]
    }

    /// Thigh and shank kinematics (with the five-point rate derivative) at
    /// sample `i`, when samples `i-2..=i+2` have complete, unsaturated gyros
    /// (or the three-point one, [`rate_derivative3`], when only `i-1..=i+1`
    /// have),
    /// sample `i` complete accelerometers, and the times are equally spaced
    /// or jittered without a gap ([`rate_derivative`], on the time base of
    /// [`StampClock`]; with jittered stamps, no sample lost among them by
    /// the clock's count, [`StampClock::consecutive`]), and sample `i` is not
    /// left out ([`Ring::exclude`]).
    pub fn kinematics(&self, i: usize) -> Option<[Kinematics; 2]> {
        if i < 2 || i + 2 >= self.len || !self.get(i).acc_ok || self.is_excluded(i) {
            return None;
        }
        let w: [&Slot; 5] = core::array::from_fn(|k| self.get(i + k - 2));
        let grid = self.clock.grid_step();
        let gyr_dot = if w.iter().all(|s| s.gyr_ok) {
            let t = w.map(|s| s.t);
            let g = |seg: usize| w.map(|x| x.gyr[seg]);
            match grid {
                // Jittered stamps of a regular clock: the clock's count says
                // whether the five are consecutive samples, not their
                // stamps' steps (2026-12-07).
                Some(dt) => {
                    if !self.clock.consecutive(&t) {
                        return None;
                    }
                    [central_derivative(&g(0), dt), central_derivative(&g(1), dt)]
                }
                None => [rate_derivative(&t, &g(0))?, rate_derivative(&t, &g(1))?],
            }
        } else if w[1..4].iter().all(|s| s.gyr_ok) {
            // An outer sample without its gyro (empty cells): the
            // three-point difference of the inner three.
            let n: [&Slot; 3] = [w[1], w[2], w[3]];
            let t = n.map(|s| s.t);
            let g = |seg: usize| n.map(|x| x.gyr[seg]);
            match grid {
                Some(dt) => {
                    if !self.clock.consecutive(&t) {
                        return None;
                    }
                    [central_difference(&g(0), dt), central_difference(&g(1), dt)]
                }
                None => [rate_derivative3(&t, &g(0))?, rate_derivative3(&t, &g(1))?],
            }
        } else {
            return None;
        };
        let s = w[2];
        Some(core::array::from_fn(|seg| Kinematics {
            acc: s.acc[seg],
            gyr: s.gyr[seg],
            gyr_dot: gyr_dot[seg],
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slot(k: usize) -> Slot {
        let x = k as f64 * 0.01;
        Slot {
            t: x,
            gyr: [
                Vector3::new(x.sin(), 0.0, 1.0),
                Vector3::new(0.0, x.cos(), 1.0),
            ],
            acc: [Vector3::new(0.0, 9.81, 0.0); 2],
            gyr_ok: true,
            acc_ok: true,
        }
    }

    #[test]
    fn an_excluded_sample_has_no_kinematics_until_overwritten() {
        let mut ring = Ring::new(10);
        (0..10).for_each(|k| ring.push(slot(k)));
        assert!(ring.kinematics(4).is_some());
        ring.exclude(4);
        assert!(ring.is_excluded(4));
        assert!(ring.kinematics(4).is_none());
        assert!(ring.kinematics(5).is_some());
        // one more sample: the excluded one is now the 4th oldest (index 3)
        ring.push(slot(10));
        assert!(ring.is_excluded(3) && ring.kinematics(3).is_none());
        // wrapped round: its slot was written again, no longer excluded
        (11..20).for_each(|k| ring.push(slot(k)));
        assert!((0..10).all(|i| !ring.is_excluded(i)));
        ring.exclude(6);
        ring.clear_excluded();
        assert!(ring.kinematics(6).is_some());
    }

    #[test]
    fn the_scratch_buffers_come_back_without_allocating() {
        let mut ring = Ring::new(50);
        let (mut a, mut b) = ring.take_scratch();
        let caps = (a.capacity(), b.capacity());
        assert!(caps.0 >= 50 && caps.1 >= 50);
        a.extend((0..50).map(|i| (i, i as f64)));
        b.extend((0..50).map(f64::from));
        ring.put_scratch((a, b));
        let (a, b) = ring.take_scratch();
        assert!(a.is_empty() && b.is_empty());
        assert_eq!((a.capacity(), b.capacity()), caps);
        ring.put_scratch((a, b));
    }
}
