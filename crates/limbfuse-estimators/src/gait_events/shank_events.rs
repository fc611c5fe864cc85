//! Initial and final contact of one leg from a shank IMU (raw sensor
//! frame), for trials without a foot IMU: the landmarks of Aminian et al.
//! 2002 ("Spatio-temporal parameters of gait measured by an ambulatory
//! system using miniature gyroscopes", J. Biomech. 35(5)) and Salarian et
//! al. 2004 ("Gait assessment in Parkinson's disease: toward an ambulatory
//! system for long-term monitoring", IEEE TBME 51(8)), detected causally.
//!
//! **Sagittal rate.** The shank's medio-lateral axis is the principal
//! component of its angular rate ([`FootAxis`], averaged over every sample).
//! Its sign: in walking the shank swings forward fast (the mid-swing peak,
//! 3-6 rad/s for 0.3-0.4 s) and returns slowly over the stance (about
//! -1 rad/s for 0.6-0.7 s); over a stride the two lobes have equal areas
//! (the shank returns to its angle), so the third moment of the rate is
//! positive about the axis oriented so that the swing is positive (SPEC's
//! `d theta / dt`, distal end forward). The sign is the sign of that third
//! moment (exponentially averaged like the axis), decided after
//! [`SIGN_SETTLE_S`] of data.
//!
//! **Events**, from the alternating extrema of the signed rate (a valley
//! or peak counts when the rate has come back from it by [`PROMINENCE`]):
//! - *mid-swing*: a peak above `swing_rate`;
//! - *final contact (toe off)*: the last valley before the mid-swing peak
//!   (Aminian 2002, Salarian 2004: the minimum before mid-swing), decided
//!   when the rate exceeds `swing_rate`;
//! - *initial contact*, two landmarks ([`ShankContact`]):
//!   - `ZeroCrossing` (default): the downward zero crossing that ends the
//!     swing lobe (the rule of the real-time shank-gyroscope phase detector
//!     in Phys. Ther. 99(6):739-747, 2019, doi 10.1093/ptj/pzz040, fig. 3,
//!     after Behboodi et al. 2019, Sensors 19(11) 2517): the shank is then at its largest
//!     forward inclination, which it reaches at heel strike (the knee's
//!     extension peaks at initial contact), the same physics as the foot
//!     landmark of [`super::foot_events`]; decided one sample later;
//!   - `Valley`: the first valley after the mid-swing peak (Aminian 2002,
//!     Salarian 2004: the minimum after mid-swing, the shank's
//!     deceleration after heel strike), decided when the rate has risen
//!     [`PROMINENCE`] from it.
//!
//!   Either needs at least `min_swing_time` after the toe off. Measured
//!   (docs/RESULTS.md): on the shared gaittoolbox walk the zero crossing
//!   falls within 10 ms of the foot IMU's initial contacts and the valley
//!   50-60 ms after them.
//!
//! No stride length or speed: a shank has no zero-velocity instant of its
//! own. Allocation-free per sample.

use nalgebra::Vector3;

use super::foot_axis::FootAxis;
use super::foot_events::EventsAt;

/// Rise (rad/s) from a valley, or fall from a peak, that confirms it: 0.5,
/// an order of magnitude below the mid-swing peak (3-6 rad/s) and the depth
/// of the contact valleys (2-3 rad/s below their neighbours in walking, the
/// papers' figures), well above gyroscope noise (0.01 rad/s).
pub const PROMINENCE: f64 = 0.5;

/// Data (s) before the third-moment sign is trusted: 2, about two strides.
pub const SIGN_SETTLE_S: f64 = 2.0;

/// Which landmark of the shank rate is the initial contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShankContact {
    /// The downward zero crossing that ends the swing lobe.
    #[default]
    ZeroCrossing,
    /// The first valley after the mid-swing peak (Aminian 2002, Salarian 2004).
    Valley,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Looking {
    /// Tracking a valley (the rate falls).
    ForValley,
    /// Tracking a peak (the rate rises).
    ForPeak,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// No toe off seen yet.
    Unknown,
    /// After an initial contact.
    Stance,
    /// After a toe off.
    Swing,
}

/// Per-leg shank event detector on the signed sagittal rate.
#[derive(Debug, Clone, Copy)]
pub struct ShankEvents {
    swing_rate: f64,
    min_swing_time: f64,
    landmark: ShankContact,
    previous: Option<(f64, f64)>,
    looking: Looking,
    /// Current extremum being tracked (time, value).
    current: (f64, f64),
    /// Last confirmed valley time.
    last_valley: Option<f64>,
    /// A mid-swing peak has been seen since the toe off.
    mid_swing: bool,
    phase: Phase,
    toe_off: f64,
    /// Time of the first sample (since the start or a reset).
    first: Option<f64>,
}

impl ShankEvents {
    /// A detector: mid-swing peaks exceed `swing_rate` (rad/s); an initial
    /// contact (at `landmark`) needs at least `min_swing_time` (s) after the toe off.
    pub fn new(swing_rate: f64, min_swing_time: f64, landmark: ShankContact) -> Self {
        ShankEvents {
            swing_rate,
            min_swing_time,
            landmark,
            previous: None,
            looking: Looking::ForValley,
            current: (0.0, 0.0),
            last_valley: None,
            mid_swing: false,
            phase: Phase::Unknown,
            toe_off: 0.0,
            first: None,
        }
    }

    /// Forgets the state (dropout, sign change).
    pub fn reset(&mut self) {
        *self = ShankEvents::new(self.swing_rate, self.min_swing_time, self.landmark);
    }

    /// Contact state: `Some(true)` in stance, `Some(false)` in swing, `None` before the first toe off.
    pub fn contact(&self) -> Option<bool> {
        match self.phase {
            Phase::Unknown => None,
            Phase::Stance => Some(true),
            Phase::Swing => Some(false),
        }
    }

    /// Whether a sample of rate `w` can change the contact between stance
    /// and swing ([`ShankEvents::update`]: a swing needs `w > swing_rate`;
    /// the end of one `w <= 0` at the zero crossing, any rate at a valley).
    pub fn may_change_contact(&self, w: f64) -> bool {
        match self.phase {
            Phase::Swing => self.landmark == ShankContact::Valley || w <= 0.0,
            Phase::Stance | Phase::Unknown => w > self.swing_rate,
        }
    }

    /// One sample of the signed sagittal rate `w` (rad/s) at time `t`.
    pub fn update(&mut self, t: f64, w: f64) -> EventsAt {
        let mut out = EventsAt::default();
        let previous = self.previous.replace((t, w));
        let Some(first) = self.first else {
            self.first = Some(t);
            self.current = (t, w);
            if w > self.swing_rate {
                // The readings start in a swing (the recording, or the
                // readings after a gap): its toe off came before them, so it
                // is not reported; the swing ends with its initial contact.
                self.phase = Phase::Swing;
                self.toe_off = f64::NEG_INFINITY;
                self.looking = Looking::ForPeak;
            }
            return out;
        };
        match self.looking {
            Looking::ForValley => {
                if w < self.current.1 {
                    self.current = (t, w);
                } else if w > self.current.1 + PROMINENCE {
                    let t_valley = self.current.0;
                    if self.landmark == ShankContact::Valley
                        && self.phase == Phase::Swing
                        && self.mid_swing
                        && t_valley - self.toe_off >= self.min_swing_time
                    {
                        // The heel-strike valley is not a toe-off candidate.
                        out.initial_contact = Some(t_valley);
                        self.phase = Phase::Stance;
                        self.mid_swing = false;
                        self.last_valley = None;
                    } else if t_valley > first {
                        self.last_valley = Some(t_valley);
                    }
                    // (A minimum at the first sample is where the readings
                    // start, not a valley: the rate only rose from there.)
                    self.looking = Looking::ForPeak;
                    self.current = (t, w);
                }
            }
            Looking::ForPeak => {
                if w > self.current.1 {
                    self.current = (t, w);
                } else if w < self.current.1 - PROMINENCE {
                    if self.current.1 > self.swing_rate && self.phase == Phase::Swing {
                        self.mid_swing = true;
                    }
                    self.looking = Looking::ForValley;
                    self.current = (t, w);
                }
            }
        }
        if let (ShankContact::ZeroCrossing, Phase::Swing, true, Some((t_prev, w_prev))) =
            (self.landmark, self.phase, self.mid_swing, previous)
        {
            if w_prev > 0.0 && w <= 0.0 {
                let t_ic = t_prev + (t - t_prev) * w_prev / (w_prev - w);
                if t_ic - self.toe_off >= self.min_swing_time {
                    out.initial_contact = Some(t_ic);
                    self.phase = Phase::Stance;
                    self.mid_swing = false;
                    self.last_valley = None;
                }
            }
        }
        if w > self.swing_rate && self.phase != Phase::Swing {
            if let Some(t_fc) = self.last_valley.take() {
                out.final_contact = Some(t_fc);
                self.toe_off = t_fc;
                self.phase = Phase::Swing;
                self.mid_swing = false;
            } else if self.phase == Phase::Unknown {
                // A swing with no valley since the readings started: its
                // toe off came before them (not reported).
                self.toe_off = f64::NEG_INFINITY;
                self.phase = Phase::Swing;
                self.mid_swing = false;
            }
        }
        out
    }
}

/// The shank's signed medio-lateral axis: principal component + third-moment sign.
#[derive(Debug, Clone)]
pub struct ShankAxis {
    axis: FootAxis,
    third_moment: f64,
    time_constant: f64,
    seen: f64,
}

impl ShankAxis {
    /// An axis tracker with averaging time constant `time_constant` (s).
    pub fn new(time_constant: f64) -> Self {
        ShankAxis {
            axis: FootAxis::new(time_constant),
            third_moment: 0.0,
            time_constant,
            seen: 0.0,
        }
    }

    /// Adds one sample.
    pub fn update(&mut self, gyr: &Vector3<f64>, dt: f64) {
        self.axis.update(gyr, dt);
        self.seen += dt;
        let x = self.axis.unsigned_axis().dot(gyr);
        let alpha = dt / self.seen.min(self.time_constant).max(dt);
        self.third_moment += (x * x * x - self.third_moment) * alpha;
    }

    /// +1 or -1 once settled, else 0.
    pub fn sign(&self) -> i32 {
        if self.seen < SIGN_SETTLE_S {
            return 0;
        }
        if self.third_moment > 0.0 {
            1
        } else if self.third_moment < 0.0 {
            -1
        } else {
            0
        }
    }

    /// The signed sagittal rate (rad/s), once the sign is known.
    pub fn sagittal_rate(&self, gyr: &Vector3<f64>) -> Option<f64> {
        match self.sign() {
            0 => None,
            s => Some(f64::from(s) * self.axis.unsigned_axis().dot(gyr)),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A synthetic shank stride of 1.1 s: stance -1 rad/s with a toe-off
    /// valley of -3 rad/s at 0.65 s, swing peak 5 rad/s at 0.85 s, heel-strike
    /// valley of -2 rad/s at 1.03 s (= 1.1 s + ... of the next stride).
    pub(crate) fn w_of(t: f64) -> f64 {
        use core::f64::consts::PI;
        let u = t % 1.1;
        let bump = |c: f64, width: f64, h: f64| {
            let x = (u - c) / width;
            if x.abs() < 1.0 {
                h * 0.5 * (1.0 + libm::cos(PI * x))
            } else {
                0.0
            }
        };
        -1.0 + bump(0.65, 0.06, -2.0) + bump(0.85, 0.15, 6.0) + bump(1.03, 0.04, -1.0)
    }

    fn events(landmark: ShankContact) -> (Vec<f64>, Vec<f64>) {
        let mut d = ShankEvents::new(1.0, 0.15, landmark);
        let dt = 0.002;
        let (mut ic, mut fc) = (vec![], vec![]);
        for k in 0..2000 {
            let t = f64::from(k) * dt;
            let e = d.update(t, w_of(t));
            ic.extend(e.initial_contact);
            fc.extend(e.final_contact);
        }
        (ic, fc)
    }

    /// The events of the synthetic walk seen from `t0` on.
    fn events_from(t0: f64, landmark: ShankContact) -> (Vec<f64>, Vec<f64>) {
        let mut d = ShankEvents::new(1.0, 0.15, landmark);
        let (mut ic, mut fc) = (vec![], vec![]);
        for k in 0..1000 {
            let t = t0 + f64::from(k) * 0.002;
            let e = d.update(t, w_of(t));
            ic.extend(e.initial_contact);
            fc.extend(e.final_contact);
        }
        (ic, fc)
    }

    /// A recording that starts in a swing ends it with its initial
    /// contact, and reports no toe off at its first sample: from just after
    /// the toe-off valley (0.72 s, the rate still negative but rising) to
    /// where the falling rate passes `swing_rate` (0.941 s; later, with the
    /// rate between 0 and `swing_rate`, the start is not told from a still
    /// leg). Before: a start before the mid-swing peak took its first
    /// sample for a toe-off valley (a toe off reported at the start), a
    /// start after the peak lost the initial contact.
    #[test]
    fn issue_19_a_start_in_mid_swing_ends_with_an_initial_contact_shank() {
        let x = libm::acos(1.0 / 3.0 - 1.0) / core::f64::consts::PI;
        let crossing = 0.85 + 0.15 * x;
        for t0 in [0.72, 0.78, 0.85, 0.9, 0.935] {
            let (ic, fc) = events_from(t0, ShankContact::ZeroCrossing);
            assert!((ic[0] - crossing).abs() < 1e-3, "start {t0}: {ic:?}");
            assert!(fc[0] > 1.1, "start {t0}: a toe off at {fc:?}");
            let (ic, _) = events_from(t0, ShankContact::Valley);
            assert!((ic[0] - 1.03).abs() < 2.5e-3, "start {t0}: {ic:?}");
        }
    }

    #[test]
    fn toe_off_is_the_valley_before_mid_swing() {
        for landmark in [ShankContact::ZeroCrossing, ShankContact::Valley] {
            let (_, fc) = events(landmark);
            assert_eq!(fc.len(), 3, "{fc:?}");
            for (i, &x) in fc.iter().enumerate() {
                assert!((x - (0.65 + 1.1 * i as f64)).abs() < 2.5e-3, "{fc:?}");
            }
        }
    }

    #[test]
    fn initial_contact_is_the_chosen_landmark() {
        let (ic, _) = events(ShankContact::Valley);
        assert_eq!(ic.len(), 3, "{ic:?}");
        for (i, &x) in ic.iter().enumerate() {
            assert!((x - (1.03 + 1.1 * i as f64)).abs() < 2.5e-3, "{ic:?}");
        }
        // The swing bump 6 cos^2 over 0.70-1.00 s on a -1 rad/s stance
        // crosses zero where 6 * 0.5 (1 + cos(pi x)) = 1, x = (u - 0.85) / 0.15.
        let x = libm::acos(1.0 / 3.0 - 1.0) / core::f64::consts::PI;
        let crossing = 0.85 + 0.15 * x;
        let (ic, _) = events(ShankContact::ZeroCrossing);
        assert_eq!(ic.len(), 3, "{ic:?}");
        for (i, &x) in ic.iter().enumerate() {
            assert!(
                (x - (crossing + 1.1 * i as f64)).abs() < 1e-3,
                "{ic:?} vs {crossing}"
            );
        }
    }

    #[test]
    fn the_swing_is_positive_whatever_the_mounting() {
        let axis = Vector3::new(0.3, -0.8, 0.6).normalize();
        for s in [1.0, -1.0] {
            let mut a = ShankAxis::new(10.0);
            let dt = 0.01;
            for k in 0..500 {
                let t = f64::from(k) * dt;
                a.update(&(axis * (s * w_of(t))), dt);
            }
            let peak = a.sagittal_rate(&(axis * (s * 5.0))).unwrap();
            assert!((peak - 5.0).abs() < 1e-3, "{peak}");
        }
    }
}
