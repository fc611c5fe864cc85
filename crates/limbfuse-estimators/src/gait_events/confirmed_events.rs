//! A leg's contact change confirmed by the next reading (ours, issue 18's
//! glitches applied to `gait-events`), for the foot detector
//! ([`FootEvents`]) and the shank detector ([`ShankEvents`]) alike.
//!
//! [`FootEvents`] decides a swing on the first sample whose rate `w`
//! exceeds `swing_rate`, and an initial contact on the first sample at or
//! below zero after a swing ([`ShankEvents`] the same, at its zero-crossing
//! landmark). A single-sample gyroscope spike does both: one
//! reading of +3 rad/s on the sagittal axis of a foot at rest is a "swing"
//! whose toe off is the rest's noise trough, and the real toe off of that
//! stance is then lost; one reading below zero in early or late swing is an
//! initial contact. Thirty 3 rad/s spikes on the right foot's z axis of the
//! shared gaitmap walk (`recording_variant --gyro-spikes 30 --spike-seed 1`)
//! gave 4 extra initial contacts, 7 extra and 3 missed final contacts
//! (docs/RESULTS.md, "Single-sample gyroscope spikes"; docs/ROBUST_INPUT.md
//! 2r); the damaging ones fell in stance.
//!
//! No test on one reading tells a spike from a real foot: the foot's rate
//! changes by up to 9.7 rad/s in one sample at heel strike (204.8 Hz) and
//! comes back the next. What a spike cannot do is *last*: so a change of
//! contact decided on one reading is held for one sample, and the next
//! reading reverses it when it gives back more than half of the step that
//! crossed the threshold *and* lies on the other side again:
//!
//! - a swing decided at `w_k > swing_rate` is reversed when
//!   `w_{k+1} <= swing_rate` and `w_k - w_{k+1} > (w_k - w_{k-1}) / 2`;
//! - an initial contact decided at `w_k <= 0` is reversed when
//!   `w_{k+1} > swing_rate` and `w_{k+1} - w_k > (w_{k-1} - w_k) / 2`.
//!
//! A reversed sample is taken out of the detector as if it had not come
//! (its state before that sample is restored), so the stride's real events
//! are found as without the spike. On every clean recording with foot IMUs
//! we have (the gaitmap walk at 204.8 and 50 Hz, the independent
//! simulator's three walks, the S02 foot, limbfuse's own walks at 0.4-1.8
//! m/s and 1 kHz), and on the same walks' shanks alone, no decision is
//! reversed: the nearest (feet) were a swing whose
//! rate fell from 1.14 to 0.75 rad/s at the next 50 Hz sample (it keeps
//! more than half of its step) and a real initial contact whose rate came
//! back to +0.27 rad/s (below `swing_rate`). A spike in late swing while
//! the rate is already below `swing_rate` is not reversed (its initial
//! contact comes early by the rest of that swing, a few samples).
//!
//! Cost: the events of a held decision are written one sample later (the
//! back-dated times are the same; a toe off that waited for the sample
//! after the decision anyway is written on it, as before), so an initial
//! contact is written two samples after its zero crossing instead of one; the contact columns
//! switch on the same sample as before, and for one sample only on a spike.
//! A decision held at a trial's last sample, or at the last before a gap
//! in the leg's readings (the detector restarts), is not written. Per sample of
//! two feet `GaitEvents::step` costs 2 343 instructions instead of 2 166
//! (callgrind, the shared gaitmap walk).

use super::foot_events::{EventsAt, FootEvents};
use super::shank_events::ShankEvents;

/// A per-leg contact detector whose changes between stance and swing
/// [`ConfirmedEvents`] holds for one sample.
pub trait ContactDetector: Copy {
    /// Contact state: `Some(true)` in stance, `Some(false)` in swing.
    fn contact(&self) -> Option<bool>;
    /// Whether a sample of rate `w` can change the contact between stance
    /// and swing (a cheap superset; the state is copied only then).
    fn may_change_contact(&self, w: f64) -> bool;
    /// Forgets the state.
    fn reset(&mut self);
}

impl ContactDetector for FootEvents {
    fn contact(&self) -> Option<bool> {
        FootEvents::contact(self)
    }
    fn may_change_contact(&self, w: f64) -> bool {
        FootEvents::may_change_contact(self, w)
    }
    fn reset(&mut self) {
        FootEvents::reset(self)
    }
}

impl ContactDetector for ShankEvents {
    fn contact(&self) -> Option<bool> {
        ShankEvents::contact(self)
    }
    fn may_change_contact(&self, w: f64) -> bool {
        ShankEvents::may_change_contact(self, w)
    }
    fn reset(&mut self) {
        ShankEvents::reset(self)
    }
}

/// A change of contact decided on one reading, waiting for the next.
#[derive(Debug, Clone, Copy)]
struct Held<D> {
    /// The detector before the sample that decided.
    before: D,
    /// What that sample decided.
    events: EventsAt,
    /// The change was into swing (else into stance).
    into_swing: bool,
    /// The rate before that sample and at it (rad/s).
    w_before: f64,
    w: f64,
}

/// A [`ContactDetector`] whose changes of contact are confirmed by the
/// next reading.
#[derive(Debug, Clone)]
pub struct ConfirmedEvents<D> {
    detector: D,
    held: Option<Held<D>>,
    last_w: Option<f64>,
    swing_rate: f64,
}

impl<D: ContactDetector> ConfirmedEvents<D> {
    /// `detector`, whose swings are decided above `swing_rate` (rad/s).
    pub fn new(detector: D, swing_rate: f64) -> Self {
        ConfirmedEvents {
            detector,
            held: None,
            last_w: None,
            swing_rate,
        }
    }

    /// Forgets the state, a held decision included.
    pub fn reset(&mut self) {
        self.detector.reset();
        self.held = None;
        self.last_w = None;
    }

    /// Contact state, a held decision's included.
    pub fn contact(&self) -> Option<bool> {
        self.detector.contact()
    }

    /// The events of the decision held for confirmation (none when nothing
    /// is held).
    pub fn held_events(&self) -> EventsAt {
        self.held
            .as_ref()
            .map_or_else(EventsAt::default, |h| h.events)
    }

    /// One sample of rate `w` (rad/s), which `step` gives the detector;
    /// returns the events confirmed at this sample.
    pub fn update(&mut self, w: f64, step: impl FnOnce(&mut D) -> EventsAt) -> EventsAt {
        let mut out = EventsAt::default();
        if let Some(h) = &self.held {
            if h.reversed_by(w, self.swing_rate) {
                self.detector = h.before;
                self.last_w = Some(h.w_before);
            } else {
                out = h.events;
            }
            self.held = None;
        }
        let contact = self.detector.contact();
        // The copy only where the contact can change: taken at every sample
        // (as `then_some` does, its argument being evaluated first) it cost
        // 113 more instructions per sample of two feet.
        let before = if self.detector.may_change_contact(w) {
            Some(self.detector)
        } else {
            None
        };
        let events = step(&mut self.detector);
        let into_swing = contact == Some(true) && self.detector.contact() == Some(false);
        let into_stance = contact == Some(false) && self.detector.contact() == Some(true);
        debug_assert!(before.is_some() || !(into_swing || into_stance));
        match (before, self.last_w) {
            (Some(before), Some(w_before)) if into_swing || into_stance => {
                self.held = Some(Held {
                    before,
                    events,
                    into_swing,
                    w_before,
                    w,
                });
            }
            _ => {
                debug_assert!(out.initial_contact.is_none() || events.initial_contact.is_none());
                debug_assert!(out.final_contact.is_none() || events.final_contact.is_none());
                out.initial_contact = out.initial_contact.or(events.initial_contact);
                out.final_contact = out.final_contact.or(events.final_contact);
            }
        }
        self.last_w = Some(w);
        out
    }
}

impl<D> Held<D> {
    /// The next reading `w` gives back more than half of the step that
    /// crossed and lies on the other side of the decision again.
    fn reversed_by(&self, w: f64, swing_rate: f64) -> bool {
        if self.into_swing {
            w <= swing_rate && self.w - w > 0.5 * (self.w - self.w_before)
        } else {
            w > swing_rate && w - self.w > 0.5 * (self.w_before - self.w)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One stride a second in `w` ([`super::super::foot_events::tests::w_of`]:
    /// push-off lobe with its minimum at 0.30 s, swing lobe, loading lobe).
    fn w_of(t: f64) -> f64 {
        super::super::foot_events::tests::w_of(t % 1.0)
    }

    /// Every event and every sample's contact of three strides, with `spike`
    /// added to the reading at the sample indices given.
    fn run(spikes: &[(usize, f64)]) -> (Vec<f64>, Vec<f64>, Vec<Option<bool>>) {
        let mut d = ConfirmedEvents::new(FootEvents::new(1.0, 0.15, 0.05), 1.0);
        let dt = 1.0 / 200.0;
        let (mut ic, mut fc, mut contact) = (vec![], vec![], vec![]);
        for k in 0..600 {
            let t = k as f64 * dt;
            let spike: f64 = spikes.iter().filter(|s| s.0 == k).map(|s| s.1).sum();
            let w = w_of(t) + spike;
            let rest = w_of(t) == 0.0 && spike == 0.0;
            let e = d.update(w, |f| f.update(t, dt, w, rest));
            ic.extend(e.initial_contact);
            fc.extend(e.final_contact);
            contact.push(d.contact());
        }
        (ic, fc, contact)
    }

    #[test]
    fn issue_18_a_spike_in_stance_or_swing_makes_no_event() {
        let clean = run(&[]);
        assert_eq!(clean.0.len(), 3, "initial contacts {:?}", clean.0);
        assert_eq!(clean.1.len(), 3, "final contacts {:?}", clean.1);
        // +3 rad/s at rest (0.10 s, 1.05 s), +5 rad/s in the push-off lobe
        // (0.25 s: w -2.83, -3.04 at the next sample) and -3 rad/s in late
        // swing (0.72 s, 1.72 s: w 1.40, 1.16 at the next sample)
        let spiked = run(&[(20, 3.0), (50, 5.0), (144, -3.0), (210, 3.0), (344, -3.0)]);
        assert_eq!(spiked.0, clean.0);
        assert_eq!(spiked.1, clean.1);
        // the contact column differs on the spike samples only
        let differ: Vec<usize> = (0..600).filter(|&k| spiked.2[k] != clean.2[k]).collect();
        assert_eq!(differ, vec![20, 50, 144, 210, 344]);
    }

    #[test]
    fn a_confirmed_decision_is_written_one_sample_later_with_its_time() {
        let mut plain = FootEvents::new(1.0, 0.15, 0.05);
        let mut held = ConfirmedEvents::new(FootEvents::new(1.0, 0.15, 0.05), 1.0);
        let dt = 1.0 / 200.0;
        let (mut a, mut b) = (vec![], vec![]);
        for k in 0..600 {
            let t = k as f64 * dt;
            let w = w_of(t);
            let rest = w == 0.0;
            let e = plain.update(t, dt, w, rest);
            let f = held.update(w, |d| d.update(t, dt, w, rest));
            assert_eq!(plain.contact(), held.contact(), "contact at sample {k}");
            a.extend(e.initial_contact.map(|x| (k, x)));
            a.extend(e.final_contact.map(|x| (k, -x)));
            b.extend(f.initial_contact.map(|x| (k - 1, x)));
            b.extend(f.final_contact.map(|x| (k - 1, -x)));
        }
        assert_eq!(a.len(), 6);
        assert_eq!(a, b);
    }

    /// A real initial contact whose rate comes back above zero, and a swing
    /// whose rate dips at the next sample, keeping more than half of its
    /// step: both stand (the nearest cases on the clean recordings).
    #[test]
    fn a_bounce_below_swing_rate_and_a_dip_keeping_half_the_step_stand() {
        let swing = Held {
            before: FootEvents::new(1.0, 0.15, 0.05),
            events: EventsAt::default(),
            into_swing: true,
            w_before: -0.5,
            w: 1.14,
        };
        assert!(!swing.reversed_by(0.75, 1.0));
        assert!(swing.reversed_by(0.3, 1.0));
        let stance = Held {
            into_swing: false,
            w_before: 0.5,
            w: -0.99,
            ..swing
        };
        assert!(!stance.reversed_by(0.27, 1.0));
        assert!(stance.reversed_by(1.2, 1.0));
    }

    /// The shank detector behind the same hold: a +3 rad/s spike in stance
    /// (its rate -1 rad/s) was a swing whose toe off was the sample before
    /// it; a -3 rad/s spike in late swing (rate 1.4 rad/s) an initial
    /// contact. Neither makes an event now.
    #[test]
    fn issue_18_a_shank_spike_makes_no_event() {
        use super::super::shank_events::{tests::w_of, ShankContact};
        let run = |spikes: &[(usize, f64)]| {
            let mut d =
                ConfirmedEvents::new(ShankEvents::new(1.0, 0.15, ShankContact::ZeroCrossing), 1.0);
            let (mut ic, mut fc) = (vec![], vec![]);
            for k in 0..2000 {
                let t = k as f64 * 0.002;
                let spike: f64 = spikes.iter().filter(|s| s.0 == k).map(|s| s.1).sum();
                let w = w_of(t) + spike;
                let e = d.update(w, |s| s.update(t, w));
                ic.extend(e.initial_contact);
                fc.extend(e.final_contact);
            }
            (ic, fc)
        };
        let clean = run(&[]);
        assert!(clean.0.len() >= 3 && clean.1.len() >= 3, "{clean:?}");
        // in stance at 1.3 s; in late swing at 2.034 s (w 1.44, then 1.31)
        let late_swing = (0..2000)
            .find(|&k| {
                let t = k as f64 * 0.002;
                t > 1.95 && w_of(t) < 1.5 && w_of(t) > 1.0 && w_of(t + 0.002) < w_of(t)
            })
            .unwrap();
        let spiked = run(&[(650, 3.0), (late_swing, -3.0)]);
        assert_eq!(spiked, clean);
    }
}
