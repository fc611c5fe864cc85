//! When the walking body turns: only while the simulated foot is in the air.
//!
//! [`crate::body_path::turn`] turns the whole simulated body (trunk and leg)
//! about the vertical through the hip. Turned at any instant, the leg's
//! stance foot would turn and slide with it; a real foot stays planted in
//! stance and the walker changes heading between steps (a step turn: the
//! swing foot lands pointing the new way; the shared gaitmap walk's turn
//! rests on every step, docs/GAIT_EVENTS.md "Turning strides"). So a turn of
//! [`Turns`] (angle `A`, starting at `k * every_s`) is split equally over the
//! swings of the simulated leg (toe off at [`crate::stance::TOE_OFF`] of its
//! stride to the next heel strike) whose toe off falls in the turn's window
//! `[k every_s, k every_s + duration_s)`, or over the first swing after the
//! window's start when none does, and over as many of the next swings as
//! keep each swing's share within [`MAX_PER_SWING`]; within each swing the heading follows the
//! quintic smoothstep (zero rate and acceleration at toe off and heel strike,
//! so none in stance). The sensorless leg's stance overlaps those swings; it
//! is not simulated.

use crate::body_path::Turns;
use crate::fourier::D2;
use crate::stance::TOE_OFF;
use core::f64::consts::TAU;

/// The largest heading change of one swing of the simulated leg (rad, 90
/// deg): healthy adults turn 180 deg in at most four steps (Thigpen et al.
/// 2000, Phys Ther 80(12)), two strides, and the simulated leg's swing
/// carries its stride's change here.
pub const MAX_PER_SWING: f64 = core::f64::consts::FRAC_PI_2;

/// One swing's share of a turn.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    /// Toe off and the next heel strike (s).
    t0: f64,
    t1: f64,
    /// Heading before the swing, and its change over it (rad).
    psi0: f64,
    dpsi: f64,
}

/// The heading of a turning walk, swing by swing (module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TurnSchedule {
    /// The leg's heading: one piece per turning swing.
    pieces: Vec<Piece>,
    /// The trunk's heading: one piece per turning swing, over the stride
    /// centred on it.
    trunk: Vec<Piece>,
}

impl TurnSchedule {
    /// The schedule of `turns` over a walk of `end` s; `swing_after(t)` is
    /// the toe off and next heel strike of the simulated leg's first swing
    /// whose toe off is at or after `t` (None when there is none before
    /// `end`).
    pub fn new(turns: &Turns, end: f64, swing_after: impl Fn(f64) -> Option<(f64, f64)>) -> Self {
        let (mut pieces, mut trunk) = (Vec::new(), Vec::new());
        let (mut psi, mut free_from) = (0.0, 0.0_f64);
        let mut k = 1.0;
        while k * turns.every_s < end {
            let start = (k * turns.every_s).max(free_from);
            let window_end = k * turns.every_s + turns.duration_s;
            let mut swings = Vec::new();
            let mut t = start;
            while let Some((a, b)) = swing_after(t) {
                if a >= window_end && !swings.is_empty() {
                    break;
                }
                swings.push((a, b));
                t = b;
                if a >= window_end {
                    break;
                }
            }
            // At most MAX_PER_SWING per swing: more swings when the window holds too few.
            let needed = (turns.angle_rad.abs() / MAX_PER_SWING).ceil() as usize;
            while swings.len() < needed {
                let Some(&(_, t)) = swings.last() else {
                    break;
                };
                match swing_after(t) {
                    Some(s) => swings.push(s),
                    None => break,
                }
            }
            let Some(&(_, last)) = swings.last() else {
                break;
            };
            let share = turns.angle_rad / swings.len() as f64;
            for (t0, t1) in swings {
                // The trunk's share over the stride centred on the swing (the
                // swing is 40 % of it), after the trunk's previous share.
                let (mid, half) = (0.5 * (t0 + t1), 0.5 * (t1 - t0) / (1.0 - TOE_OFF));
                let after = trunk.last().map_or(f64::NEG_INFINITY, |p: &Piece| p.t1);
                trunk.push(Piece {
                    t0: (mid - half).max(after),
                    t1: mid + half,
                    psi0: psi,
                    dpsi: share,
                });
                pieces.push(Piece {
                    t0,
                    t1,
                    psi0: psi,
                    dpsi: share,
                });
                psi += share;
            }
            free_from = last;
            k += 1.0;
        }
        TurnSchedule { pieces, trunk }
    }

    /// The schedule of `turns` over a walk of `end` s whose unwrapped gait
    /// phase (rad, 0 = heel strike of the simulated leg; never decreasing)
    /// is `phase(t)`, at a mean stride frequency `f0` (Hz).
    pub fn on_gait(turns: &Turns, end: f64, phase: impl Fn(f64) -> f64, f0: f64) -> Self {
        if f0 <= 0.0 {
            return TurnSchedule::default();
        }
        let swing_after = |t: f64| {
            let cycles = phase(t) / TAU;
            let c = (cycles - TOE_OFF).ceil() + TOE_OFF;
            let a = time_of_cycles(&phase, f0, c, t, end)?;
            let b = time_of_cycles(&phase, f0, c.floor() + 1.0, a, end + 2.0 / f0)?;
            Some((a, b))
        };
        TurnSchedule::new(turns, end, swing_after)
    }

    /// The leg's heading `psi` (rad; positive = to the left) with its first
    /// two time derivatives at `t` (s): it changes in the turning swings.
    pub fn heading(&self, t: f64) -> D2 {
        heading_of(&self.pieces, t)
    }

    /// The trunk's heading at `t`: each swing's share over the stride
    /// centred on that swing (the quintic smoothstep), so that the trunk
    /// turns at a walker's rate, step by step, while the leg turns in its
    /// swings; the difference is the hip's rotation about the vertical.
    pub fn trunk_heading(&self, t: f64) -> D2 {
        heading_of(&self.trunk, t)
    }

    /// The swings over which the heading changes: (toe off, heel strike) in s.
    pub fn turning_swings(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.pieces.iter().map(|p| (p.t0, p.t1))
    }
}

/// The time at which `phase` reaches `cycles` strides, searched from `from`
/// up to `until` (s; None past it).
fn time_of_cycles(
    phase: &impl Fn(f64) -> f64,
    f0: f64,
    cycles: f64,
    from: f64,
    until: f64,
) -> Option<f64> {
    let target = cycles * TAU;
    if phase(from) >= target {
        return Some(from);
    }
    let step = 0.25 / f0;
    let (mut lo, mut hi) = (from, from);
    while phase(hi) < target {
        lo = hi;
        hi += step;
        if hi > until + step {
            return None;
        }
    }
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if phase(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-12 {
            break;
        }
    }
    let t = 0.5 * (lo + hi);
    (t <= until).then_some(t)
}

/// The heading of `pieces` (sorted, not overlapping) at `t`: constant
/// between them, the quintic smoothstep within each.
fn heading_of(pieces: &[Piece], t: f64) -> D2 {
    let i = pieces.partition_point(|p| p.t0 <= t);
    let Some(p) = i.checked_sub(1).map(|j| pieces[j]) else {
        return D2::constant(0.0);
    };
    if t >= p.t1 {
        return D2::constant(p.psi0 + p.dpsi);
    }
    let d = p.t1 - p.t0;
    let u = (t - p.t0) / d;
    D2 {
        v: p.psi0 + p.dpsi * u * u * u * (10.0 + u * (-15.0 + 6.0 * u)),
        d1: p.dpsi / d * 30.0 * u * u * (1.0 - u) * (1.0 - u),
        d2: p.dpsi / (d * d) * 60.0 * u * (1.0 + u * (-3.0 + 2.0 * u)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Strides of 1 s from t = 0.3 s: toe off at 0.6 of each.
    fn swing_after(t: f64) -> Option<(f64, f64)> {
        let k = ((t - 0.3 - 0.6) / 1.0).ceil().max(0.0);
        let a = 0.3 + k + 0.6;
        (a < 30.0).then_some((a, a + 0.4))
    }

    #[test]
    fn the_heading_changes_only_in_the_swings_and_adds_up_to_each_turn() {
        let turns = Turns {
            every_s: 10.0,
            duration_s: 2.5,
            angle_rad: 3.0,
        };
        let s = TurnSchedule::new(&turns, 30.0, swing_after);
        let swings: Vec<_> = s.turning_swings().collect();
        // toe offs at 10.9, 11.9 (12.9 is past 12.5), 20.9, 21.9
        assert_eq!(swings.len(), 4, "{swings:?}");
        assert!((swings[0].0 - 10.9).abs() < 1e-12 && (swings[1].1 - 12.3).abs() < 1e-12);
        for t in [0.0, 10.5, 10.89, 11.3, 11.5, 20.0] {
            let h = s.heading(t);
            assert_eq!((h.d1, h.d2), (0.0, 0.0), "{t}");
        }
        assert_eq!(s.heading(11.5).v, 1.5);
        assert_eq!(s.heading(15.0).v, 3.0);
        // the trunk: each share over the stride around its swing, the same total
        assert!((s.trunk_heading(15.0).v - 3.0).abs() < 1e-12);
        assert!(s.trunk_heading(10.65).d1 > 0.0 && s.trunk_heading(10.55).d1 == 0.0);
        assert!((s.trunk_heading(11.1).v - 0.75).abs() < 1e-12);
        assert!((s.heading(29.0).v - 6.0).abs() < 1e-12);
        for &x in &[10.95, 11.1, 11.25, 12.0, 21.2] {
            let h = 1e-6;
            let (p, m, c) = (s.heading(x + h), s.heading(x - h), s.heading(x));
            assert!(((p.v - m.v) / (2.0 * h) - c.d1).abs() < 1e-5, "{x}");
            assert!(((p.d1 - m.d1) / (2.0 * h) - c.d2).abs() < 1e-3, "{x}");
        }
    }

    #[test]
    fn a_turn_shorter_than_a_stride_takes_the_next_swing() {
        let turns = Turns {
            every_s: 5.0,
            duration_s: 0.1,
            angle_rad: -1.0,
        };
        let s = TurnSchedule::new(&turns, 12.0, swing_after);
        let swings: Vec<_> = s.turning_swings().collect();
        assert_eq!(swings.len(), 2, "{swings:?}");
        assert!((swings[0].0 - 5.9).abs() < 1e-12 && (swings[1].0 - 10.9).abs() < 1e-12);
        assert_eq!(s.heading(7.0).v, -1.0);
    }
}
