//! Initial and final contact of one foot from its sagittal angular rate
//! `w = d theta / dt` (positive toe-up), decided sample by sample.
//!
//! A walking stride of the foot is, in `w`: push-off (the heel rises, the
//! foot rotates toe-down: a negative lobe) -> swing (toe-up: a large positive
//! lobe) -> loading (after heel strike the ground moment rotates the foot
//! toe-down to flat: a negative lobe) -> foot flat (`w` near zero).
//!
//! - **Final contact (toe off)** = the negative extremum of the push-off lobe
//!   (Mariani et al. 2013, Gait & Posture 38(4), "toe-off ... minimum of the
//!   pitch angular velocity" before swing; Rampp et al. 2015 use the same
//!   landmark region): while the toe is on the ground, the plantarflexors
//!   accelerate the foot's rotation about the toe; once the toe leaves, that
//!   drive is gone and the rotation reverses. Located to sub-sample time
//!   from the extremum and the two samples on each side of it
//!   ([`super::trough_time`]: the corner of the push-off and release lines,
//!   or a parabola's vertex for a smooth trough). It is decided when `w`
//!   then rises above `swing_rate` (the foot is in swing), or at the next
//!   sample when the second sample after the extremum is that crossing
//!   itself, so its latency is the time from toe-off to that crossing (one
//!   sample more in that case).
//! - **Initial contact** = the downward zero crossing of `w` that ends the
//!   swing lobe: in terminal swing the foot is still turning toe-up; the
//!   heel's ground contact is what reverses it (the loading lobe), so the
//!   instant of maximal dorsiflexion is the contact. Located by linear
//!   interpolation; decided one sample after it.
//!
//! The push-off extremum is taken from the latest negative lobe before the
//! swing, so the loading lobe after the initial contact is never mistaken
//! for it. A lobe starts when `w` turns negative, or after the stance's
//! first foot flat (a rest of the foot that has lasted `min_rest_time`, as
//! for the stride integration, [`super::GaitEventsParams::min_rest_time`]):
//! the foot flat of mid-stance ends the loading response (loading response 0-10 % of the gait cycle,
//! mid-stance 10-30 % with the foot flat, heel rise in terminal stance
//! 30-50 %, push-off in pre-swing 50-60 %: Perry & Burnfield, Gait
//! Analysis, 2nd ed. 2010, ch. 2 and 4), so nothing before it is the
//! push-off. On straight walking `w` crosses zero between the two lobes
//! anyway; on a turning step it can stay slightly negative through the
//! foot flat (the pivoting foot's rotation leaks into the sagittal axis),
//! and the loading lobe's deeper extremum (the heel-strike impact) was
//! taken for the toe off, 25 ms after the initial contact (the shared
//! gaitmap walk, left stride at 16.16 s). Only the first foot flat after
//! the initial contact counts, and only a rest of `min_rest_time`: a slow
//! swing's start can hold still for a moment (0.02 s at 0.6-1 m/s, longer
//! at 0.4 m/s) after the push-off, before the rate passes `swing_rate`,
//! and such a rest would drop the push-off lobe. A stance without a foot
//! flat keeps the zero-crossing rule alone.
//!
//! The detector starts (and restarts after a gap) by waiting for a rest of
//! the foot, or, when it starts in swing (`w > swing_rate`), by ending that
//! swing with an initial contact once `min_swing_time` of it has been seen
//! (with less seen, a zero crossing is not told from a dip, and it waits
//! for a rest).

use super::trough_time::TroughSamples;

/// What the detector decided at one sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EventsAt {
    /// Time (s) of an initial contact decided at this sample.
    pub initial_contact: Option<f64>,
    /// Time (s) of a final contact (toe off) decided at this sample.
    pub final_contact: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    /// Not started: waits for a rest of the foot.
    Unknown,
    /// Foot on the ground.
    Stance,
    /// Foot in the air.
    Swing,
}

/// Per-foot contact detector.
#[derive(Debug, Clone, Copy)]
pub struct FootEvents {
    swing_rate: f64,
    min_swing_time: f64,
    state: State,
    previous: Option<(f64, f64)>,
    before_previous: Option<(f64, f64)>,
    lobe_min: Option<TroughSamples>,
    /// The push-off extremum of a swing already decided, waiting for its
    /// second sample after.
    pending_final_contact: Option<TroughSamples>,
    swing_start: f64,
    /// Shortest rest (s) that is a foot flat.
    min_rest_time: f64,
    /// How long (s) the foot has been at rest without a break.
    rest_time: f64,
    /// The current stance has had its foot flat (its loading is over).
    foot_flat_seen: bool,
    /// The current swing was entered from [`State::Unknown`] (its toe off
    /// not seen).
    swing_seen_from_start: bool,
}

impl FootEvents {
    /// A detector: swing is confirmed when `w > swing_rate` (rad/s); an
    /// initial contact needs at least `min_swing_time` (s) after the toe off;
    /// a rest of the foot that has lasted `min_rest_time` (s) is a foot flat
    /// (the push-off lobe is looked for after it).
    pub fn new(swing_rate: f64, min_swing_time: f64, min_rest_time: f64) -> Self {
        FootEvents {
            swing_rate,
            min_swing_time,
            min_rest_time,
            rest_time: 0.0,
            foot_flat_seen: false,
            state: State::Unknown,
            previous: None,
            before_previous: None,
            lobe_min: None,
            pending_final_contact: None,
            swing_start: 0.0,
            swing_seen_from_start: false,
        }
    }

    /// Forgets the state (dropout, sign change): waits for the next rest.
    pub fn reset(&mut self) {
        *self = FootEvents::new(self.swing_rate, self.min_swing_time, self.min_rest_time);
    }

    /// Contact state: `Some(true)` in stance, `Some(false)` in swing, `None` before the start.
    pub fn contact(&self) -> Option<bool> {
        match self.state {
            State::Unknown => None,
            State::Stance => Some(true),
            State::Swing => Some(false),
        }
    }

    /// Whether a sample of rate `w` can change the contact between stance
    /// and swing ([`FootEvents::update`]: a swing needs `w > swing_rate`,
    /// the end of one `w <= 0`).
    pub fn may_change_contact(&self, w: f64) -> bool {
        match self.state {
            State::Stance => w > self.swing_rate,
            State::Swing => w <= 0.0,
            State::Unknown => false,
        }
    }

    /// One sample at time `t` with step `dt`: sagittal rate `w` (rad/s), foot at rest or not.
    pub fn update(&mut self, t: f64, dt: f64, w: f64, rest: bool) -> EventsAt {
        let mut out = EventsAt::default();
        let previous = self.previous.replace((t, w));
        let before_previous = core::mem::replace(&mut self.before_previous, previous);
        if let Some(m) = self.lobe_min.as_mut() {
            m.push_after(t, w);
        }
        if let Some(mut m) = self.pending_final_contact.take() {
            m.push_after(t, w);
            if m.is_complete() {
                let t_fc = m.refined().0;
                out.final_contact = Some(t_fc);
                self.swing_start = t_fc;
            } else {
                self.pending_final_contact = Some(m);
            }
        }
        self.rest_time = if rest { self.rest_time + dt } else { 0.0 };
        let foot_flat = rest && self.rest_time >= self.min_rest_time - 1e-9;
        let lobe_start = || TroughSamples::new(t, w, dt, [before_previous, previous]);
        match self.state {
            State::Unknown => {
                if rest {
                    self.state = State::Stance;
                    self.foot_flat_seen = false;
                } else if w > self.swing_rate {
                    // Started (or restarted after a gap) in swing: its toe
                    // off is not seen, but its end is an initial contact
                    // when `min_swing_time` of it has been seen.
                    self.state = State::Swing;
                    self.swing_start = t;
                    self.swing_seen_from_start = true;
                }
            }
            State::Stance => {
                let w_prev = previous.map_or(0.0, |p| p.1);
                if foot_flat && !self.foot_flat_seen {
                    // The loading response is over: the push-off lobe
                    // starts after the foot flat.
                    self.lobe_min = None;
                    self.foot_flat_seen = true;
                } else if w < 0.0 {
                    let new_lobe = w_prev >= 0.0 || self.lobe_min.is_none();
                    let lower = self.lobe_min.is_none_or(|m| w < m.value());
                    if new_lobe || lower {
                        self.lobe_min = Some(lobe_start());
                    }
                }
                if w > self.swing_rate {
                    match self.lobe_min.take() {
                        Some(m) if m.is_complete() => {
                            let t_fc = m.refined().0;
                            out.final_contact = Some(t_fc);
                            self.swing_start = t_fc;
                        }
                        Some(m) => {
                            // The release line needs the next sample.
                            self.pending_final_contact = Some(m);
                            self.swing_start = m.t();
                        }
                        None => {
                            out.final_contact = Some(t);
                            self.swing_start = t;
                        }
                    }
                    self.state = State::Swing;
                    self.swing_seen_from_start = false;
                }
            }
            State::Swing => {
                if let Some((t_prev, w_prev)) = previous {
                    let ends = w_prev > 0.0 && w <= 0.0;
                    if ends && t - self.swing_start >= self.min_swing_time {
                        let t_ic = t_prev + (t - t_prev) * w_prev / (w_prev - w);
                        out.initial_contact = Some(t_ic);
                        self.state = State::Stance;
                        self.foot_flat_seen = false;
                        self.lobe_min = Some(lobe_start());
                    } else if ends && self.swing_seen_from_start {
                        // Too little of a swing seen from the start to
                        // tell its end from a dip: wait for a rest, as
                        // any start does.
                        self.state = State::Unknown;
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A synthetic stride in `w`: flat, push-off lobe (min at 0.30 s), swing
    /// lobe (0.35-0.75 s), loading lobe, flat. Events at the lobe minimum and
    /// the swing's downward zero crossing.
    pub(crate) fn w_of(t: f64) -> f64 {
        use core::f64::consts::PI;
        if (0.2..0.35).contains(&t) {
            // push-off: -4 sin over [0.2, 0.35], but skewed: min at 0.30
            let u = if t < 0.30 {
                (t - 0.2) / 0.10 * 0.5
            } else {
                0.5 + (t - 0.30) / 0.05 * 0.5
            };
            -4.0 * libm::sin(PI * u)
        } else if (0.35..0.75).contains(&t) {
            6.0 * libm::sin(PI * (t - 0.35) / 0.40)
        } else if (0.75..0.85).contains(&t) {
            -2.0 * libm::sin(PI * (t - 0.75) / 0.10)
        } else {
            0.0
        }
    }

    #[test]
    fn events_are_at_the_landmarks() {
        let mut d = FootEvents::new(1.0, 0.15, 0.05);
        let dt = 1.0 / 500.0;
        let (mut ic, mut fc) = (None, None);
        for k in 0..600 {
            let t = k as f64 * dt;
            let w = w_of(t);
            let e = d.update(t, dt, w, w == 0.0 && t < 0.2);
            ic = ic.or(e.initial_contact);
            fc = fc.or(e.final_contact);
        }
        let fc = fc.expect("toe off found");
        let ic = ic.expect("initial contact found");
        assert!((fc - 0.30).abs() < 1.5e-3, "toe off at {fc}");
        assert!((ic - 0.75).abs() < 1e-3, "initial contact at {ic}");
        assert_eq!(d.contact(), Some(true));
    }

    /// At 50 Hz a sharp release can cross `swing_rate` at the first sample
    /// after the extremum: the swing is decided there (contact off), the
    /// toe off one sample later, when the release line's second sample is
    /// in, at the corner of the push-off and release lines.
    #[test]
    fn a_release_crossing_at_the_next_sample_waits_for_the_line() {
        let mut d = FootEvents::new(1.0, 0.15, 0.05);
        let dt = 0.02;
        let corner = 0.513;
        let w = |t: f64| {
            if t < 0.3 {
                0.0
            } else if t < corner {
                -5.0 - 20.0 * (t - corner)
            } else {
                (-5.0 + 1000.0 * (t - corner)).min(30.0)
            }
        };
        let mut fc = vec![];
        for k in 0..40 {
            let t = k as f64 * dt;
            let e = d.update(t, dt, w(t), t < 0.3);
            if let Some(t_fc) = e.final_contact {
                fc.push((t, t_fc));
            }
            if (0.52..0.53).contains(&t) {
                assert_eq!(d.contact(), Some(false), "swing decided at {t}");
            }
        }
        assert_eq!(fc.len(), 1, "{fc:?}");
        let (decided, t_fc) = fc[0];
        assert!((decided - 0.54).abs() < 1e-9, "decided at {decided}");
        assert!((t_fc - corner).abs() < 1e-9, "toe off at {t_fc}");
    }

    /// A synthetic turning stride whose loading and push-off lobes do not
    /// separate: `w` stays slightly negative (-0.1 rad/s) through the foot
    /// flat (rest at 0.65-0.85 s) between the loading lobe after the initial
    /// contact at 0.5 s (impact minimum -6.1 rad/s at 0.55 s) and the
    /// push-off (minimum -4 rad/s at 1.0 s), then the swing.
    fn turning_stride_w(t: f64) -> f64 {
        use core::f64::consts::PI;
        if (0.1..0.5).contains(&t) {
            6.0 * libm::sin(PI * (t - 0.1) / 0.4)
        } else if (0.5..0.6).contains(&t) {
            -0.1 - 6.0 * libm::sin(PI * (t - 0.5) / 0.1)
        } else if (0.6..0.9).contains(&t) {
            -0.1
        } else if (0.9..1.05).contains(&t) {
            // skewed like the push-off of `w_of`: minimum at 1.0
            let u = if t < 1.0 {
                (t - 0.9) / 0.10 * 0.5
            } else {
                0.5 + (t - 1.0) / 0.05 * 0.5
            };
            -0.1 - 3.9 * libm::sin(PI * u)
        } else if (1.05..1.45).contains(&t) {
            -0.1 + 6.1 * libm::sin(PI * (t - 1.05) / 0.40)
        } else {
            0.0
        }
    }

    /// The turning stride's toe offs between its initial contact and the
    /// next, and its initial contacts, with the foot at rest where `rest`.
    fn turning_stride_events(rest: impl Fn(f64) -> bool) -> (Vec<f64>, Vec<f64>) {
        let mut d = FootEvents::new(1.0, 0.15, 0.05);
        let dt = 1.0 / 500.0;
        let (mut ic, mut fc) = (vec![], vec![]);
        for k in 0..800 {
            let t = k as f64 * dt;
            let e = d.update(t, dt, turning_stride_w(t), t < 0.1 || rest(t));
            ic.extend(e.initial_contact);
            fc.extend(e.final_contact);
        }
        // The turning stride's contact (its swing lobe jumps to -0.1 rad/s:
        // the crossing is interpolated just before 0.5 s) and the next one.
        assert_eq!(ic.len(), 2, "{ic:?}");
        assert!((ic[0] - 0.5).abs() < 2e-3, "initial contact at {ic:?}");
        // The toe off of the swing that starts from the first rest (no
        // push-off lobe) is not the stride's.
        fc.retain(|&x| x > ic[0] && x < ic[1]);
        (ic, fc)
    }

    /// A turning step's toe off is the push-off extremum after the foot
    /// flat, not the deeper loading (impact) extremum of the same negative
    /// stretch of `w`. Before (the gaitmap walk's left stride at 16.16 s)
    /// the toe off was put at 0.55 s here, 50 ms after the initial contact.
    #[test]
    fn a_turning_step_toe_off_is_the_push_off_after_the_foot_flat() {
        let (_, fc) = turning_stride_events(|t| (0.65..=0.85).contains(&t));
        assert_eq!(fc.len(), 1, "{fc:?}");
        assert!((fc[0] - 1.0).abs() < 1.5e-3, "toe off at {fc:?}");
    }

    /// A moment of rest between the push-off and the swing, as a slow
    /// swing's start can hold still, is no foot flat: the push-off extremum
    /// stays the toe off, whether the moment is shorter than `min_rest_time`
    /// (0.01 s) or not (0.06 s, after the stance's foot flat). (With any
    /// rest sample taken for a foot flat the toe off went to the swing
    /// crossing, 160-170 ms late, on 8 of 35 strides of a simulated 0.6 m/s
    /// walk.)
    #[test]
    fn a_moment_of_rest_before_the_swing_keeps_the_push_off() {
        for moment in [1.055..1.065, 1.01..1.07] {
            let (_, fc) =
                turning_stride_events(|t| (0.65..=0.85).contains(&t) || moment.contains(&t));
            assert_eq!(fc.len(), 1, "{moment:?}: {fc:?}");
            assert!(
                (fc[0] - 1.0).abs() < 1.5e-3,
                "{moment:?}: toe off at {fc:?}"
            );
        }
    }

    /// Two synthetic strides (period 1 s) seen from `start` (s): the
    /// events decided, in order.
    fn events_from(start: f64) -> (Vec<f64>, Vec<f64>) {
        let mut d = FootEvents::new(1.0, 0.15, 0.05);
        let dt = 1.0 / 500.0;
        let (mut ic, mut fc) = (vec![], vec![]);
        let first = (start / dt).round() as usize;
        for k in first..1000 {
            let t = k as f64 * dt;
            let w = w_of(t % 1.0);
            let flat = w == 0.0 && !(0.75..0.9).contains(&(t % 1.0));
            let e = d.update(t, dt, w, flat);
            ic.extend(e.initial_contact);
            fc.extend(e.final_contact);
        }
        (ic, fc)
    }

    /// Issue 19 (2026-12-04): a detector started in mid-swing (a recording
    /// cut mid-walk, or a foot back from a gap in its readings) ends that
    /// swing with an initial contact once `min_swing_time` of it is seen;
    /// with less seen it waits for a rest, as before, and misses nothing
    /// after. Before, it always waited for a rest: the contact at 0.75 s
    /// was lost when starting at 0.45 s.
    #[test]
    fn issue_19_a_start_in_mid_swing_ends_with_an_initial_contact() {
        let near = |v: &[f64], want: &[f64]| {
            v.len() == want.len() && v.iter().zip(want).all(|(a, b)| (a - b).abs() < 1.5e-3)
        };
        let (ic, fc) = events_from(0.45);
        assert!(near(&ic, &[0.75, 1.75]), "{ic:?}");
        assert!(near(&fc, &[1.30]), "{fc:?}");
        // 0.1 s of swing seen: not told from a dip, no event until the rest.
        let (ic, fc) = events_from(0.65);
        assert!(near(&ic, &[1.75]), "{ic:?}");
        assert!(near(&fc, &[1.30]), "{fc:?}");
        // From the start: every event.
        let (ic, fc) = events_from(0.0);
        assert!(near(&ic, &[0.75, 1.75]), "{ic:?}");
        assert!(near(&fc, &[0.30, 1.30]), "{fc:?}");
    }
}
