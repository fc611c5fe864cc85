//! The leg stiffness measured from the weight support over a step
//! (configuration `continuous`; docs/GAIT_IMM.md, "Leg stiffness from the
//! weight support").
//!
//! Over one step of B-SLIP walking (MS to MS) the vertical impulse of the
//! stance legs equals the weight's plus the change of vertical momentum:
//! `integral sum_legs k (l0 - l_i) y / l_i dt = m (g T + vy_end - vy_start)`
//! (`y / l_i` is the leg's vertical direction cosine, the feet are on the
//! ground at height 0; SS1 loads the trailing leg, DS both, SS2 the leading
//! one). With the feet located from the data and the CoM estimate, the
//! one unknown is `k`:
//! `k = m (g T + vy_end - vy_start) / integral sum_legs (l0 - l_i) y / l_i dt`.
//! This is the stiffness of the legs the trial walks on, whatever gait
//! branch it is (the library's stiffness at a speed can be 8 or 16 kN/m
//! depending on the branch the gait search landed on; docs/RESULTS.md,
//! "Issue 19: off-grid speeds and other gait branches"). The estimator uses
//! the mean of the last stride's two steps (left and right), like the speed
//! (the one step until two are measured), on the ensemble CoM: the measured
//! CoM is unbiased but its noise made the first estimates jump and the
//! feet lose lock for a few steps (docs/GAIT_IMM.md).

/// Running weight-support integral of the current step and the stiffness
/// of the last two complete steps.
#[derive(Debug, Clone, Copy)]
pub(super) struct WeightSupport {
    /// `integral sum_legs (l0 - l_i) y / l_i dt` since the step's start (m s).
    integral: f64,
    /// The step's start: time (s) and vertical CoM velocity (m/s).
    start: Option<(f64, f64)>,
    /// The last sample: time (s) and its support term (m).
    last: Option<(f64, f64)>,
    /// Stiffness of the last two complete steps (N/m; newest first).
    steps: [Option<f64>; 2],
}

impl WeightSupport {
    /// No step started.
    pub fn new() -> Self {
        WeightSupport {
            integral: 0.0,
            start: None,
            last: None,
            steps: [None; 2],
        }
    }

    /// A step starts at `t` (MS) with vertical CoM velocity `vy`.
    pub fn start_step(&mut self, t: f64, vy: f64, support: f64) {
        self.integral = 0.0;
        self.start = Some((t, vy));
        self.last = Some((t, support));
    }

    /// Adds the sample at `t` whose loaded legs give
    /// `support = sum_legs (l0 - l_i) y / l_i` (m); trapezoidal rule.
    pub fn push(&mut self, t: f64, support: f64) {
        if let Some((t0, s0)) = self.last {
            if t > t0 && support.is_finite() {
                self.integral += 0.5 * (support + s0) * (t - t0);
            }
        }
        if support.is_finite() {
            self.last = Some((t, support));
        }
    }

    /// The step ends at `t` (MS) with vertical CoM velocity `vy`: its
    /// stiffness for `mass` (kg) and `gravity` (m/s^2) is kept when
    /// `counts` (the step's stance foot was located from the data) and it
    /// is finite and positive. The next step starts here.
    pub fn end_step(
        &mut self,
        t: f64,
        vy: f64,
        support: f64,
        mass: f64,
        gravity: f64,
        counts: bool,
    ) {
        if let (true, Some((t0, vy0))) = (counts, self.start) {
            let k = mass * (gravity * (t - t0) + vy - vy0) / self.integral;
            if k.is_finite() && k > 0.0 {
                self.steps = [Some(k), self.steps[0]];
            }
        }
        self.start_step(t, vy, support);
    }

    /// Mean stiffness of the last stride (two steps; the one step while
    /// only one was measured; N/m).
    pub fn stiffness(&self) -> Option<f64> {
        match self.steps {
            [Some(a), Some(b)] => Some(0.5 * (a + b)),
            [Some(a), None] => Some(a),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A leg held at constant compression `c` with the CoM at height `y`
    /// over the foot for a whole step supports the weight when
    /// `k c = m g`: the estimate returns that `k`.
    #[test]
    fn constant_support_gives_the_static_stiffness() {
        let (m, g, c) = (70.0, 9.81, 0.05);
        let mut w = WeightSupport::new();
        for step in 0..2 {
            let t0 = step as f64 * 0.5;
            w.start_step(t0, 0.0, c);
            for i in 1..=50 {
                w.push(t0 + i as f64 * 0.01, c);
            }
            w.end_step(t0 + 0.5, 0.0, c, m, g, true);
        }
        let k = w.stiffness().unwrap();
        assert!((k - m * g / c).abs() < 1e-6 * k, "{k}");
    }

    /// Steps whose foot was not located do not count.
    #[test]
    fn unlocated_steps_give_no_stiffness() {
        let mut w = WeightSupport::new();
        w.start_step(0.0, 0.0, 0.05);
        w.push(0.5, 0.05);
        w.end_step(0.5, 0.0, 0.05, 70.0, 9.81, false);
        w.push(1.0, 0.05);
        assert_eq!(w.stiffness(), None);
    }
}
