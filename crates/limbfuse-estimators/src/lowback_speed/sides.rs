//! Which foot each initial contact of `lowback-speed` belongs to (ours,
//! beyond Zijlstra & Hof; issue 19): McCamley et al. 2012's left/right rule
//! with the band-pass of Ullrich et al. 2021.
//!
//! The trunk turns about the vertical at the stride frequency (the pelvis's
//! transverse rotation, about 4 deg either way in normal walking: Saunders,
//! Inman & Eberhart 1953, J Bone Joint Surg 35-A:543), so the sign of the
//! rate about the vertical at a contact tells the foot: McCamley et al.
//! 2012 (Gait & Posture 36(2):316-318) take the rate about the sensor's
//! vertical axis minus its mean; Ullrich et al. 2021 (IEEE EMBC, 9630653;
//! mobgap's `LrcMcCamley` default) band-pass it at 0.5-2 Hz with a
//! forward-backward 4th-order Butterworth filter; a positive value
//! (counter-clockwise seen from above) is a right contact, as mobgap reads it
//! (`lr_label = "right"` where the smoothed yaw rate is above 0).
//!
//! Here the rate is the one `lowback-speed` already integrates into its
//! heading: the gyroscope's component along the gravity direction, so the
//! rule holds for any mounting of the sensor. A forward-backward filter
//! needs the whole recording; its causal form with a delay is a symmetric
//! (linear-phase) FIR band-pass of the same band: a Hann-windowed sinc
//! ([`SIDE_FILTER_HALF_LENGTH_S`] = 2 s either side, `scipy.signal.firwin`'s
//! design, gain 1 at the band's centre): its gain is within 0.03 of the
//! forward-backward Butterworth's at 0.9-1.8 Hz (stride frequencies) and
//! within 0.25 everywhere (most apart at the 0.4-0.6 Hz edge), and it
//! rejects a turn's slow heading change (gain 0.05 at 0.2 Hz). A contact's side is decided when the
//! filter's window after it has arrived, 2 s after the contact, and written
//! then (`diag_ic_right` / `diag_ic_left` hold the contact's time, as
//! `gait-events` writes its back-dated events). A filtered rate of at most
//! `side_min_rate` (3 deg/s: an eighth of the 20-25 deg/s peak rate of a 4
//! deg rotation at a 0.8-1 Hz stride frequency) leaves the side unknown: a
//! trunk that does not turn with the stride (a planar simulation) or a
//! missing gyroscope gives no side. So does a contact within 2 s of the
//! start of the readings, of a gap that restarts the step detection, or of
//! the end.

use alloc::vec::Vec;
use core::f64::consts::PI;

/// Half the length (s) of the side filter's window: 2 s, so that the
/// window spans two strides either side of the contact at slow walking and
/// the 0.5 Hz band edge is resolved (transition ~0.5 Hz wide).
pub const SIDE_FILTER_HALF_LENGTH_S: f64 = 2.0;

/// The side filter's band (Hz): Ullrich et al. 2021 (mobgap `LrcMcCamley`).
pub const SIDE_BAND_HZ: (f64, f64) = (0.5, 2.0);

/// Contacts waiting for their side (at least `min_step_time` apart, so at
/// most `2 s / 0.25 s + 1` of them).
const PENDING: usize = 16;

/// The taps of the side filter for the sampling period `dt` (s) into `taps`
/// (cleared first): `2 M + 1` taps, `M = round(2 s / dt)` capped at
/// `max_half`; a Hann-windowed band-pass sinc scaled to gain 1 at the
/// band's centre frequency (`scipy.signal.firwin(2 M + 1, [0.5, 2],
/// pass_zero=False, fs=1/dt, window="hann")`). Returns `M`.
pub fn side_filter_taps(dt: f64, max_half: usize, taps: &mut Vec<f64>) -> usize {
    let half = (libm::round(SIDE_FILTER_HALF_LENGTH_S / dt) as usize).clamp(1, max_half);
    let n = 2 * half + 1;
    // Cut-offs as fractions of the Nyquist frequency.
    let (c1, c2) = (SIDE_BAND_HZ.0 * 2.0 * dt, SIDE_BAND_HZ.1 * 2.0 * dt);
    let sinc = |x: f64| {
        if x == 0.0 {
            1.0
        } else {
            libm::sin(PI * x) / (PI * x)
        }
    };
    taps.clear();
    for j in 0..n {
        let m = j as f64 - half as f64;
        let window = 0.5 - 0.5 * libm::cos(2.0 * PI * j as f64 / (n - 1) as f64);
        taps.push(window * (c2 * sinc(c2 * m) - c1 * sinc(c1 * m)));
    }
    let centre = 0.5 * (c1 + c2);
    let gain: f64 = taps
        .iter()
        .enumerate()
        .map(|(j, h)| h * libm::cos(PI * (j as f64 - half as f64) * centre))
        .sum();
    if gain != 0.0 {
        for h in taps.iter_mut() {
            *h /= gain;
        }
    }
    half
}

/// The side of a contact from its filtered rate about the vertical
/// (rad/s): `Some(true)` right (above `min_rate`), `Some(false)` left
/// (below `-min_rate`), `None` in between.
pub fn contact_side(filtered_rate: f64, min_rate: f64) -> Option<bool> {
    if filtered_rate > min_rate {
        Some(true)
    } else if filtered_rate < -min_rate {
        Some(false)
    } else {
        None
    }
}

/// Contacts waiting for the side filter's window after them: (history
/// index, time), oldest first, in a fixed ring (nothing allocated).
#[derive(Debug, Clone, Default)]
pub struct PendingContacts {
    slots: [(u64, f64); PENDING],
    start: usize,
    len: usize,
}

impl PendingContacts {
    /// Adds a contact; when full (not reached with `min_step_time` 0.25 s)
    /// the oldest is dropped, its side unknown.
    pub fn push(&mut self, index: u64, t: f64) {
        if self.len == PENDING {
            self.pop();
        }
        self.slots[(self.start + self.len) % PENDING] = (index, t);
        self.len += 1;
    }

    /// The oldest contact.
    pub fn front(&self) -> Option<(u64, f64)> {
        (self.len > 0).then(|| self.slots[self.start])
    }

    /// Removes the oldest contact.
    pub fn pop(&mut self) {
        if self.len > 0 {
            self.start = (self.start + 1) % PENDING;
            self.len -= 1;
        }
    }

    /// Forgets every contact (a restart of the step detection).
    pub fn clear(&mut self) {
        self.len = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    /// The taps against `scipy.signal.firwin(401, [0.5, 2],
    /// pass_zero=False, fs=100, window="hann")` (scipy 1.17.1), an
    /// independent implementation of the same design, and at 50 Hz
    /// (`firwin(201, ..., fs=50)`).
    #[test]
    fn taps_are_scipys_firwin() {
        let mut taps = Vec::new();
        let half = side_filter_taps(0.01, 2000, &mut taps);
        assert_eq!((half, taps.len()), (200, 401));
        for (j, want) in [
            (1, -9.300369366696227e-09),
            (150, -0.005453478459183471),
            (200, 0.030108147983524597),
            (250, -0.00545347845918347),
            (399, -9.300369366696227e-09),
        ] {
            assert!(
                (taps[j] - want).abs() < 1e-15,
                "tap {j}: {} vs {want}",
                taps[j]
            );
        }
        let half = side_filter_taps(0.02, 2000, &mut taps);
        assert_eq!(half, 100);
        assert!((taps[100] - 0.0602162958254106).abs() < 1e-15);
        assert!((taps[60] + 0.006144929325621887).abs() < 1e-15);
    }

    /// Gain at 0.2 / 0.9 / 1.25 / 1.8 / 3 Hz: scipy's `freqz` of the same
    /// taps gives 0.0512 / 0.99998 / 1 / 0.853 / 0.00075.
    #[test]
    fn gain_passes_the_stride_and_rejects_turns() {
        let mut taps = vec![];
        let half = side_filter_taps(0.01, 2000, &mut taps);
        let gain = |f: f64| {
            let (mut re, mut im) = (0.0, 0.0);
            for (j, h) in taps.iter().enumerate() {
                let phase = 2.0 * PI * f * (j as f64 - half as f64) * 0.01;
                re += h * libm::cos(phase);
                im += h * libm::sin(phase);
            }
            libm::sqrt(re * re + im * im)
        };
        for (f, want) in [
            (0.2, 0.0512),
            (0.9, 0.99998),
            (1.25, 1.0),
            (1.8, 0.853),
            (3.0, 0.00075),
        ] {
            assert!((gain(f) - want).abs() < 1e-3, "{f} Hz: {}", gain(f));
        }
    }

    #[test]
    fn the_half_length_is_capped() {
        let mut taps = vec![];
        assert_eq!(side_filter_taps(0.0001, 1000, &mut taps), 1000);
        assert_eq!(taps.len(), 2001);
    }

    #[test]
    fn side_needs_a_rate_beyond_the_threshold() {
        assert_eq!(contact_side(0.2, 0.05), Some(true));
        assert_eq!(contact_side(-0.2, 0.05), Some(false));
        assert_eq!(contact_side(0.05, 0.05), None);
        assert_eq!(contact_side(0.0, 0.0), None);
    }

    #[test]
    fn pending_contacts_keep_their_order_and_drop_the_oldest_when_full() {
        let mut p = PendingContacts::default();
        assert_eq!(p.front(), None);
        for k in 0..(PENDING as u64 + 2) {
            p.push(k, k as f64);
        }
        assert_eq!(p.front(), Some((2, 2.0)));
        p.pop();
        assert_eq!(p.front(), Some((3, 3.0)));
        p.clear();
        assert_eq!(p.front(), None);
    }
}
