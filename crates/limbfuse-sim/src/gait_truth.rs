//! Foot contact and walking speed of the walking simulator as reference
//! columns (`limbfuse simulate walking --gait-reference`; SPEC
//! `contact_left_ref` / `contact_right_ref`, `speed_ref`), so that
//! `gait-events` and `lowback-speed` can be scored on a simulated trial
//! as on a recording with motion capture.
//!
//! - **Contact** of the simulated leg: on the ground from heel strike, at
//!   gait phase 0, to toe off at [`STANCE_FRACTION`] of the stride: the
//!   stance the simulator's stance leg is built over (docs/SIMULATOR.md
//!   item 5: inverse kinematics over 0-60 %, the heel pivot from 0 %). The
//!   other leg carries no sensor and is not simulated, but the pelvis path
//!   is that of a symmetric gait (two vertical oscillations per stride,
//!   item 4): its contact is the same, half a stride later, so that a
//!   method that finds both feet's contacts (`lowback-speed`) is scored
//!   against both. These are the placed events, which keep the normative
//!   curves' timing, not the instants the simulated foot meets or leaves
//!   the floor: outside single support its contact points follow the
//!   normative angles and differ from them by -119 to +48 ms
//!   (docs/SIMULATOR.md, "Known limitations";
//!   `examples/foot_floor_study.rs` in limbfuse-studies).
//! - **Speed** per stride (heel strike to the next heel strike of the same
//!   leg: the times at which the unwrapped phase crosses a multiple of
//!   `2 pi`, found by bisection on the gait clock): the horizontal distance
//!   the hip joint centre covers over the stride divided by the stride's
//!   duration, the per-stride definition of the gaitmap and Mobilise-D
//!   references. With stride-time variability the duration varies from
//!   stride to stride; on a turning path the distance is the chord.

use crate::WalkingSimulator;

/// Fraction of the stride the simulated foot is on the ground: heel strike
/// at phase 0, toe off at 60 % (docs/SIMULATOR.md item 5).
pub const STANCE_FRACTION: f64 = 0.6;

/// The gait references of a walking simulator, sample by sample.
#[derive(Debug, Clone)]
pub struct GaitTruth {
    sim: WalkingSimulator,
    /// The last stride: its index (phase / 2 pi, floored) and speed.
    stride: Option<(f64, f64)>,
}

impl GaitTruth {
    /// References of the trial `sim` simulates (a copy of it, whose truth
    /// does not touch the random streams).
    pub fn new(sim: WalkingSimulator) -> Self {
        GaitTruth { sim, stride: None }
    }

    /// Whether the simulated foot and the other one are on the ground at
    /// `t`, and the walking speed (m/s) over the stride of the simulated
    /// leg that contains `t` (0 when standing).
    pub fn at(&mut self, t: f64) -> ([bool; 2], f64) {
        let cycles = self.sim.gait_phase(t) / core::f64::consts::TAU;
        let k = cycles.floor();
        let other = cycles + 0.5;
        let contact = [
            cycles - k < STANCE_FRACTION,
            other - other.floor() < STANCE_FRACTION,
        ];
        let f0 = self.sim.stride_frequency();
        if f0 <= 0.0 {
            return (contact, 0.0);
        }
        if let Some((kk, v)) = self.stride {
            if kk == k {
                return (contact, v);
            }
        }
        let t0 = self.time_of(k, t, -2.0 / f0);
        let t1 = self.time_of(k + 1.0, t, 2.0 / f0);
        let (p0, p1) = (self.sim.truth(t0).hip.p, self.sim.truth(t1).hip.p);
        // World frame: y is up.
        let distance = (p1.x - p0.x).hypot(p1.z - p0.z);
        let v = distance / (t1 - t0);
        self.stride = Some((k, v));
        (contact, v)
    }

    /// The time at which the phase reaches `cycles` strides, searched from
    /// `t` over `reach` seconds (negative: backwards); the phase increases
    /// with time (the clock's rate is `2 pi f0 (1 + e)`, `|e|` a few %).
    fn time_of(&self, cycles: f64, t: f64, reach: f64) -> f64 {
        let target = cycles * core::f64::consts::TAU;
        let (mut lo, mut hi) = if reach < 0.0 {
            (t + reach, t)
        } else {
            (t, t + reach)
        };
        while self.sim.gait_phase(lo) > target {
            lo -= reach.abs();
        }
        while self.sim.gait_phase(hi) < target {
            hi += reach.abs();
        }
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if self.sim.gait_phase(mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 1e-12 {
                break;
            }
        }
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WalkingConfig;

    #[test]
    fn metronomic_strides_have_the_nominal_speed_and_a_60_percent_stance() {
        let cfg = WalkingConfig {
            speed_mps: 1.2,
            duration_s: 6.0,
            variability: None,
            ..WalkingConfig::default()
        };
        let sim = WalkingSimulator::new(cfg).unwrap();
        let (f0, nominal) = (sim.stride_frequency(), sim.nominal_speed());
        let mut truth = GaitTruth::new(sim);
        let n = 600;
        let mut stance = 0;
        for i in 0..n {
            let t = f64::from(i) * 0.01;
            let ([contact, other], v) = truth.at(t);
            stance += usize::from(contact);
            let shifted = truth.at(t + 0.5 / f0).0[0];
            assert_eq!(other, shifted, "{t}");
            assert!(
                (v - nominal).abs() < 1e-6 * nominal,
                "{t}: {v} vs {nominal}"
            );
        }
        let fraction = stance as f64 / f64::from(n);
        // 6 s hold 6 f0 strides: the stance share is 0.6 up to one stride's edges.
        assert!(
            (fraction - 0.6).abs() < 1.0 / (6.0 * f0 * 100.0) + 0.02,
            "{fraction}"
        );
    }

    #[test]
    fn the_stride_ends_where_the_phase_crosses_a_multiple_of_two_pi() {
        let sim = WalkingSimulator::new(WalkingConfig {
            duration_s: 10.0,
            ..WalkingConfig::default()
        })
        .unwrap();
        let truth = GaitTruth::new(sim.clone());
        let t = 3.3;
        let k = (sim.gait_phase(t) / core::f64::consts::TAU).floor();
        let t1 = truth.time_of(k + 1.0, t, 2.0 / sim.stride_frequency());
        let p = sim.gait_phase(t1) / core::f64::consts::TAU;
        assert!((p - (k + 1.0)).abs() < 1e-9, "{p} at {t1}");
        assert!(t1 > t && t1 - t < 1.5 / sim.stride_frequency());
    }
}
