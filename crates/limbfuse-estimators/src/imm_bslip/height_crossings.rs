//! The stance foot located from the CoM's crossings of its mid height
//! (configuration `continuous`; docs/GAIT_IMM.md, "Configuration
//! `continuous`").
//!
//! A periodic B-SLIP step is symmetric in time about mid-stance (MS): the
//! CoM is over the stance foot, `y(t_MS + s) = y(t_MS - s)` and
//! `x(t_MS + s) - x_foot = -(x(t_MS - s) - x_foot)`. So if the CoM rises
//! through a height `h` at `(t_up, x_up)` and falls through it again at
//! `(t_down, x_down)`, MS is at `(t_up + t_down) / 2` and the stance foot at
//! `(x_up + x_down) / 2`, whatever `h` is. The level is taken halfway
//! between the last trough and apex, where the vertical velocity is
//! largest, so both crossings are located to a fraction of a sample. The
//! apex itself (`vy = 0`) is not used: it is ill-conditioned on flat-topped
//! gaits (0.4 m/s: `vy` below 5 mm/s for 0.2 s around MS) and has
//! near-tangencies before MS (0.9 m/s: `vy` within 1 mm/s of zero just
//! after lift-off), where filter noise fires it early.
//!
//! The rise counts only once the CoM is a quarter of the last step's
//! trough-to-apex excursion above the level (hysteresis), so noise around
//! the level, or wiggles of a noisy height estimate near a flat apex, do
//! not make pairs. If a step passes without a crossing (an apex lower than the
//! hysteresis, a trough above the level), the caller restarts the detector
//! from that step's extremes.

/// One located mid-stance: time and the stance foot's forward position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FootFix {
    /// Mid-stance time (s).
    pub t: f64,
    /// Stance foot `x` (m).
    pub x: f64,
}

/// Which side of the level the CoM is on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Level {
    /// Below the level (or not yet confirmed above it).
    Low,
    /// Confirmed above `level`; the up-crossing `(t, x)` if it was seen.
    High { level: f64, up: Option<(f64, f64)> },
}

/// The mid-height crossing detector (module docs).
#[derive(Debug, Clone, Copy)]
pub(super) struct HeightCrossings {
    /// The last apex height, once an apex and a trough have been seen.
    apex: Option<f64>,
    side: Level,
    /// Candidate up-crossing `(t, x)` while below the level.
    candidate: Option<(f64, f64)>,
    /// Lowest CoM height since the last down-crossing (the trough).
    low: f64,
    /// Highest CoM height since the last up-crossing (the apex).
    high: f64,
    /// The last step's trough-to-apex excursion (the hysteresis' scale).
    excursion: f64,
    /// Previous sample `(t, x, y)`.
    previous: Option<(f64, f64, f64)>,
    /// Crossings (confirmed rises and falls) so far.
    crossings: u32,
}

/// Where `y` crosses `h` between `(t0, x0, y0)` and `(t1, x1, y1)`, linearly.
fn crossing(p: (f64, f64, f64), t: f64, x: f64, y: f64, h: f64) -> (f64, f64) {
    let a = if y != p.2 { (h - p.2) / (y - p.2) } else { 1.0 };
    let a = a.clamp(0.0, 1.0);
    (p.0 + a * (t - p.0), p.1 + a * (x - p.1))
}

impl HeightCrossings {
    /// A detector at the start of a trial, before any apex or trough.
    pub fn new() -> Self {
        HeightCrossings {
            apex: None,
            side: Level::Low,
            candidate: None,
            low: f64::INFINITY,
            high: f64::NEG_INFINITY,
            excursion: 0.0,
            previous: None,
            crossings: 0,
        }
    }

    /// Starts over from a trough `low` and an apex `high` the caller has
    /// seen (the first lift-off; a step without a located foot), the CoM
    /// now at height `y`.
    pub fn restart(&mut self, low: f64, high: f64, y: f64) {
        if high.partial_cmp(&low) != Some(core::cmp::Ordering::Greater) {
            return;
        }
        let level = 0.5 * (high + low);
        self.apex = Some(high);
        self.candidate = None;
        self.side = if y < level {
            Level::Low
        } else {
            Level::High { level, up: None }
        };
        self.low = low.min(y);
        self.high = y;
        self.excursion = high - low;
    }

    /// The last step's lowest and highest CoM height (the caller's, at
    /// MS): the hysteresis is a quarter of that excursion, so noise on the
    /// height near the apex or the level cannot shrink it.
    pub fn set_excursion(&mut self, low: f64, high: f64) {
        if high.partial_cmp(&low) == Some(core::cmp::Ordering::Greater) {
            self.excursion = high - low;
        }
    }

    /// Whether an apex and a trough have been seen.
    pub fn started(&self) -> bool {
        self.apex.is_some()
    }

    /// Crossings (confirmed rises and falls) so far: a step without one
    /// means the detector is stuck (module docs).
    pub fn crossings(&self) -> u32 {
        self.crossings
    }

    /// The next CoM sample (time, forward position, height); a located MS
    /// when the CoM has just fallen through the level after rising through
    /// it. The level is halfway between the last apex and the trough since;
    /// the rise is confirmed a quarter of the last step's excursion above it.
    pub fn push(&mut self, t: f64, x: f64, y: f64) -> Option<FootFix> {
        let previous = self.previous.replace((t, x, y));
        let (apex, p) = (self.apex?, previous?);
        match self.side {
            Level::Low => {
                self.low = self.low.min(y);
                let h = 0.5 * (apex + self.low);
                if p.2 < h && y >= h {
                    self.candidate = Some(crossing(p, t, x, y, h));
                } else if y < h && p.2 >= h {
                    // Fell back below: the next rise gives the candidate.
                    self.candidate = None;
                }
                if y >= h + 0.25 * self.excursion {
                    self.side = Level::High {
                        level: h,
                        up: self.candidate.take(),
                    };
                    self.high = y;
                    self.crossings = self.crossings.wrapping_add(1);
                }
                None
            }
            Level::High { level, up } => {
                self.high = self.high.max(y);
                if !(p.2 >= level && y < level) {
                    return None;
                }
                let down = crossing(p, t, x, y, level);
                self.apex = Some(self.high);
                self.side = Level::Low;
                self.candidate = None;
                self.low = y;
                self.crossings = self.crossings.wrapping_add(1);
                let (t_up, x_up) = up?;
                Some(FootFix {
                    t: 0.5 * (t_up + down.0),
                    x: 0.5 * (x_up + down.1),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate alloc;

    use super::*;
    use alloc::vec::Vec;

    /// A CoM bobbing `y = 1 - 0.02 cos(2 pi x / L)` (apex over each foot at
    /// `x = (k + 1/2) L`), walking at 1 m/s, with a sample period that does
    /// not divide the step.
    #[test]
    fn the_foot_is_the_midpoint_of_the_level_crossings() {
        let l = 0.6;
        let mut c = HeightCrossings::new();
        let mut fixes = Vec::new();
        for k in 0..400 {
            let t = k as f64 * 0.0097;
            let x = t + 0.5 * l; // starts at an apex (MS)
            let y = 1.0 - 0.02 * libm::cos(2.0 * core::f64::consts::PI * x / l);
            if k == 40 {
                c.restart(0.98, 1.02, y);
            }
            fixes.extend(c.push(t, x, y));
        }
        assert!(fixes.len() >= 4, "{fixes:?}");
        for f in &fixes {
            // Apexes at x = (k + 1/2) l; the fix lies on one within
            // the interpolation error of a cosine sampled at ~1 cm.
            let k = (f.x / l - 0.5).round();
            assert!((f.x - (k + 0.5) * l).abs() < 2e-3, "{f:?}");
            assert!((f.t - (f.x - 0.5 * l)).abs() < 2e-3, "{f:?}");
        }
    }

    #[test]
    fn noise_at_the_level_does_not_make_pairs() {
        let mut c = HeightCrossings::new();
        c.restart(0.96, 1.0, 0.96); // level 0.98, band 0.01
        c.push(0.01, 0.01, 0.96);
        let mut fixes = 0;
        for k in 2..50 {
            // Chatter around the level, never past the band.
            let y = if k % 2 == 0 { 0.981 } else { 0.979 };
            fixes += usize::from(c.push(k as f64 * 0.01, k as f64 * 0.01, y).is_some());
        }
        assert_eq!(fixes, 0);
    }
}
