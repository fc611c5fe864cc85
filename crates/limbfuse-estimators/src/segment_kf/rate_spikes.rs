//! Single-sample gyroscope spikes told from the joint encoders (ours, not in
//! papers 000/001; docs/ROBUST_INPUT.md, "Gyroscope spikes beside the
//! encoders").
//!
//! A gyroscope spike of a few rad/s within the sensor gate's range and jump
//! bound steps the segment's integrated angle by its integral (3 rad/s at
//! 100 Hz: 1.7 deg). The papers' encoder rows, trusted little (0.5 deg),
//! hardly correct it at the spike's sample; from the next sample the
//! joint's encoder contradicts the moved segment beyond the innovation gate
//! and, after [`super::robust::GATE_LOCKOUT_S`] of refusals, the filter
//! restarts (`mjls`: seven restarts on the shared independent 1.2 m/s walk
//! with sixty +-3 rad/s spikes; docs/RESULTS.md, "Single-sample gyroscope
//! spikes").
//!
//! The encoders see the spike's absence. Joint `j` is `theta_j -
//! theta_(j+1)` (SPEC section 1), so at every sample the aligned sagittal
//! rates and the encoder agree up to noise and discretisation in the
//! residual
//!
//! ```text
//! r_j = (omega_j - omega_(j+1)) - (enc_j(k) - enc_j(k-1)) / dt        (backward)
//! r_j = (omega_j - omega_(j+1))(k) + (...)(k-1) - 2 (enc_j(k) - enc_j(k-1)) / dt   (trapezoid)
//! ```
//!
//! (the first is insensitive to encoder noise, twice as much as the
//! second, which is insensitive to the segments' angular acceleration;
//! each joint uses the one whose running mean square is smaller). A spike
//! `S` in segment `i`'s rate adds `S` times a fixed signature to the three
//! residuals: trunk `(+1, 0, 0)`, thigh `(-1, +1, 0)`, shank `(0, -1, +1)`,
//! foot `(0, 0, -1)`. The test is a generalised likelihood ratio test for a
//! jump in one of four known directions (A. S. Willsky and H. L. Jones, "A
//! generalized likelihood ratio approach to the detection and estimation of
//! jumps in linear systems", IEEE TAC 21(1):108-112, 1976): with each
//! residual scaled by its running root mean square (time constant
//! [`SCALE_TIME_S`]), the spike size of each hypothesis is its weighted
//! least-squares fit, and a reading is refused when
//!
//! * the best hypothesis explains more than [`INNOVATION_GATE_CHI2`]
//!   (chi-square, one degree of freedom, `1 - 1e-6`) of the residuals'
//!   normalised square,
//! * what it leaves is within [`FIT_GATE_CHI2`] (two degrees of freedom,
//!   `1 - 1e-6`: the residuals are one segment's spike, not a disagreement
//!   spread over the chain), and
//! * the fitted spike exceeds [`SPIKE_MIN_RATE`].
//!
//! A refused thigh or shank reading is replaced by the rate its neighbours
//! and encoders imply through the relation each joint was tested on
//! (`implied_rate`; the two joints weighed by the residuals' running mean
//! squares), as `robust::borrow_rates` lends a segment whose gyroscope is
//! gone; the filter integrates that. A reading the test wrongly refuses (an
//! impact the encoders and the gyroscope sample differently) is thus
//! replaced by the encoders' view of the same motion. A refused trunk or
//! foot reading becomes a missing one, which the filter holds: their
//! signature is one joint's residual, which a glitch or step of the hip or
//! ankle encoder makes too, and the encoders' rate would turn the segment by
//! the glitch. Refusals count as rejected gyroscope readings. Nothing is
//! tested before [`SCALE_TIME_S`] of residuals, across a time gap, or while
//! any of the four rates or three encoders is missing.

use super::chain::wrap;
use super::robust::{ExpWeights, GAP_STEP_RATIO, INNOVATION_GATE_CHI2};

/// The residuals' signature of a spike in each segment's rate (trunk,
/// thigh, shank, foot) on the hip, knee and ankle residuals.
const SIGNATURE: [[f64; 3]; 4] = [
    [1.0, 0.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [0.0, 0.0, -1.0],
];

/// Chi-square threshold on what the best spike hypothesis leaves of the
/// three residuals (two degrees of freedom): `-2 ln(1e-6)`, the `1 - 1e-6`
/// quantile (the chi-square distribution with two degrees of freedom is
/// exponential).
pub const FIT_GATE_CHI2: f64 = 27.631;

/// Time constant (s) of the residuals' running mean square: a stride at
/// 1 Hz (the time constant of the rates' running power in
/// [`super::robust`]). Nothing is tested before this much time of
/// residuals.
pub const SCALE_TIME_S: f64 = 1.0;

/// Smallest residual scale (rad/s) a test divides by: the difference of two
/// gyroscopes' turn-on biases, `sqrt(2)` x 0.5 deg/s
/// ([`super::params::imu_spec::GYRO_TURN_ON_BIAS_DPS`]), which the residual
/// carries as an offset on any real sensor; below it a mean square measures
/// nothing about the noise (an ideal simulator).
pub const SCALE_FLOOR: f64 = core::f64::consts::SQRT_2
    * super::params::imu_spec::GYRO_TURN_ON_BIAS_DPS
    * core::f64::consts::PI
    / 180.0;

/// Smallest spike (rad/s) the test refuses: the margin of the sample gate's
/// jump check (an axis may change by `alpha dt + 1 rad/s` from one reading
/// to the next, docs/ROBUST_INPUT.md), so a reading is refused only as far
/// beyond the encoders' view of the motion as a jump check allows beyond
/// the last reading. Below it a spike moves the angle by less than 0.6 deg
/// at 100 Hz, within the encoder rows' reach; residuals of real motion
/// near it (up to 1.1 rad/s at heel strike on limbfuse's own walk upsampled
/// to 200 Hz by linear interpolation, where the interpolated rates and
/// angles disagree) stay applied but for the few beyond.
pub const SPIKE_MIN_RATE: f64 = 1.0;

/// The test's memory: the last sample's rates and encoders and the
/// residuals' running mean squares.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct RateSpikeTest {
    /// The last sample's rates as the filter used them (a refused reading
    /// as replaced).
    prev_rate: [Option<f64>; 4],
    /// The last sample's encoders.
    prev_encoder: [Option<f64>; 3],
    /// The last time step (s).
    prev_dt: Option<f64>,
    /// Running mean square per joint of the backward (`[0]`) and trapezoid
    /// (`[1]`) residuals, and how long (s) each has been averaged.
    mean_square: [[f64; 3]; 2],
    averaged_s: [f64; 2],
    weights: ExpWeights,
    /// Readings refused and replaced.
    refused: u64,
}

impl RateSpikeTest {
    /// Readings refused so far.
    pub fn refused(&self) -> u64 {
        self.refused
    }

    /// Tests this sample's rates against the encoders; a refused rate is
    /// replaced in `rate` (thigh, shank: by the one the encoders imply;
    /// trunk, foot: by none, a missing reading), and its segment is
    /// returned. `dt` is the step from the last sample (`None` on the
    /// first).
    pub fn check(
        &mut self,
        rate: &mut [Option<f64>; 4],
        encoder: &[Option<f64>; 3],
        dt: Option<f64>,
    ) -> Option<usize> {
        let refused = self.test(rate, encoder, dt);
        if let Some((i, implied)) = refused {
            self.refused += 1;
            rate[i] = implied;
        }
        self.prev_rate = *rate;
        self.prev_encoder = *encoder;
        self.prev_dt = dt.or(self.prev_dt);
        refused.map(|(i, _)| i)
    }

    /// The refused segment and what replaces its reading (the encoders'
    /// rate for thigh and shank, nothing for trunk and foot: [`implied_rate`]),
    /// if any; updates the mean squares when none is refused.
    fn test(
        &mut self,
        rate: &[Option<f64>; 4],
        encoder: &[Option<f64>; 3],
        dt: Option<f64>,
    ) -> Option<(usize, Option<f64>)> {
        let dt = dt.filter(|&d| d > 0.0)?;
        if self.prev_dt.is_some_and(|p| dt > GAP_STEP_RATIO * p) {
            return None;
        }
        let w = all(rate)?;
        let e = all(encoder)?;
        let e0 = all(&self.prev_encoder)?;
        let prev = all(&self.prev_rate);
        let enc_rate: [f64; 3] = core::array::from_fn(|j| wrap(e[j] - e0[j]) / dt);
        let mut residual = [[0.0; 3]; 2];
        for j in 0..3 {
            let relative = w[j] - w[j + 1];
            residual[0][j] = relative - enc_rate[j];
            residual[1][j] =
                prev.map_or(f64::NAN, |p| relative + p[j] - p[j + 1] - 2.0 * enc_rate[j]);
        }
        // A fitted spike is a weighted mean of residuals (their signs
        // aside): with none beyond SPIKE_MIN_RATE nothing can be refused,
        // and the test is not formed (most samples).
        let beyond = residual.iter().flatten().any(|v| v.abs() > SPIKE_MIN_RATE);
        let refused = beyond
            .then(|| self.hypothesis(&residual))
            .flatten()
            .map(|(i, c)| (i, implied_rate(i, &w, &enc_rate, prev, &c)));
        if refused.is_none() {
            let k = self.weights.weight(dt, SCALE_TIME_S);
            for (kind, r) in residual.iter().enumerate() {
                if r.iter().all(|v| v.is_finite()) {
                    let first = self.averaged_s[kind] == 0.0;
                    for (m, v) in self.mean_square[kind].iter_mut().zip(r) {
                        *m = if first { v * v } else { *m + k * (v * v - *m) };
                    }
                    self.averaged_s[kind] += dt;
                }
            }
        }
        refused
    }

    /// The generalised likelihood ratio test over the four segments: the
    /// refused segment and the residuals it was tested on.
    fn hypothesis(&self, residual: &[[f64; 3]; 2]) -> Option<(usize, Chosen)> {
        if self.averaged_s[0] < SCALE_TIME_S {
            return None;
        }
        let trapezoid_ready = self.averaged_s[1] >= SCALE_TIME_S;
        let ms = &self.mean_square;
        let trapezoid: [bool; 3] = core::array::from_fn(|j| {
            trapezoid_ready && residual[1][j].is_finite() && ms[1][j] < ms[0][j]
        });
        let kind = |j: usize| usize::from(trapezoid[j]);
        let c = Chosen {
            r: core::array::from_fn(|j| residual[kind(j)][j]),
            weight: core::array::from_fn(|j| 1.0 / ms[kind(j)][j].max(SCALE_FLOOR * SCALE_FLOOR)),
            trapezoid,
        };
        let (r, weight) = (c.r, c.weight);
        let chi0: f64 = (0..3).map(|j| r[j] * r[j] * weight[j]).sum();
        if chi0 <= INNOVATION_GATE_CHI2 {
            return None;
        }
        let (segment, explained, spike) = SIGNATURE
            .iter()
            .enumerate()
            .map(|(i, h)| {
                let hwr: f64 = (0..3).map(|j| h[j] * weight[j] * r[j]).sum();
                let hwh: f64 = (0..3).map(|j| h[j] * h[j] * weight[j]).sum();
                (i, hwr * hwr / hwh, hwr / hwh)
            })
            .fold((0, f64::NEG_INFINITY, 0.0), |best, c| {
                if c.1 > best.1 {
                    c
                } else {
                    best
                }
            });
        let left = chi0 - explained;
        (explained > INNOVATION_GATE_CHI2 && left < FIT_GATE_CHI2 && spike.abs() > SPIKE_MIN_RATE)
            .then_some((segment, c))
    }
}

/// The residual each joint is tested on: the kind (backward or trapezoid)
/// whose running mean square is smaller, and the inverse of that mean square.
#[derive(Debug, Clone, Copy)]
struct Chosen {
    r: [f64; 3],
    weight: [f64; 3],
    trapezoid: [bool; 3],
}

/// Every entry, or `None` when one is missing.
fn all<const N: usize>(v: &[Option<f64>; N]) -> Option<[f64; N]> {
    let mut out = [0.0; N];
    for (o, x) in out.iter_mut().zip(v) {
        *o = (*x)?;
    }
    Some(out)
}

/// The rate that replaces segment `i`'s refused reading. Thigh and shank:
/// the rate their neighbours' rates `w` and the encoders imply, through each
/// joint `j` beside them by the relation its residual was tested on (SPEC
/// section 1: joint `j` is `theta_j - theta_(j+1)`): the backward difference
/// `(w_j - w_(j+1))(k) = d enc_j / dt`, or the trapezoid's `(w_j -
/// w_(j+1))(k) = 2 d enc_j / dt - (w_j - w_(j+1))(k-1)` (with which the
/// filter's trapezoidal integration turns the joint exactly by its
/// encoder's change), the two joints' values weighed by the inverse of the
/// residuals' running mean squares (that relation's error; each joint uses
/// the one with the smaller, the choice of [`RateSpikeTest::hypothesis`]).
/// The backward difference carries the segments' angular acceleration
/// (`alpha dt / 2`), the trapezoid twice the encoder noise: on limbfuse's own
/// walk with eight spikes the largest angle error is 0.13 deg with the
/// backward difference alone, 0.076 with the trapezoid alone (measured); on
/// the shared independent walk, whose encoders are noisier, the backward
/// difference is the better one.
///
/// Trunk and foot: `None`, a missing reading (the filter holds the segment's
/// own rate over it, as over any dropout). Their pattern is one joint's
/// residual, which a single-sample glitch or step of the hip or ankle
/// encoder makes too; the encoders' rate would then turn the segment by the
/// glitch (a hip encoder re-zeroed by 0.3 rad turned `mjls`'s trunk by 17
/// deg, measured), while the held rate is right in both cases. Thigh and
/// shank patterns need both of their encoders to disagree at once, in
/// opposite directions.
fn implied_rate(
    i: usize,
    w: &[f64; 4],
    enc_rate: &[f64; 3],
    prev: Option<[f64; 4]>,
    c: &Chosen,
) -> Option<f64> {
    if i == 0 || i == 3 {
        return None;
    }
    // the relative rate of joint `j` the encoder implies
    let relative = |j: usize| match prev {
        Some(p) if c.trapezoid[j] => 2.0 * enc_rate[j] - (p[j] - p[j + 1]),
        _ => enc_rate[j],
    };
    let (a, b) = (i - 1, i);
    let from_proximal = w[i - 1] - relative(a);
    let from_distal = w[i + 1] + relative(b);
    Some((c.weight[a] * from_proximal + c.weight[b] * from_distal) / (c.weight[a] + c.weight[b]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth chain: segment `i` turns as `a_i sin(2 pi t + phase_i)`, the
    /// encoders are the exact joint angles; returns (rates, encoders) at `t`.
    fn chain_at(t: f64) -> ([Option<f64>; 4], [Option<f64>; 3]) {
        let (a, phase) = ([0.1, 0.5, 0.7, 0.4], [0.0, 0.3, 1.2, 2.0]);
        let w = core::f64::consts::TAU;
        let theta: [f64; 4] = core::array::from_fn(|i| a[i] * libm::sin(w * t + phase[i]));
        let rate = core::array::from_fn(|i| Some(a[i] * w * libm::cos(w * t + phase[i])));
        let enc = core::array::from_fn(|j| Some(theta[j] - theta[j + 1]));
        (rate, enc)
    }

    /// Runs the test over `n` samples at 100 Hz, with `spike(k)` (segment,
    /// added rate) added to sample `k`'s rates; returns the refusals
    /// (sample, segment, the rate that replaced the reading, the true rate).
    fn run(
        n: usize,
        spike: impl Fn(usize) -> Option<(usize, f64)>,
    ) -> Vec<(usize, usize, Option<f64>, f64)> {
        let mut test = RateSpikeTest::default();
        let mut out = Vec::new();
        for k in 0..n {
            let t = k as f64 * 0.01;
            let (mut rate, enc) = chain_at(t);
            let truth = rate;
            // a little noise, as on any sensor: 0.02 rad/s, deterministic
            for (i, r) in rate.iter_mut().enumerate() {
                *r = r.map(|v| v + 0.02 * libm::sin(37.0 * t + i as f64));
            }
            if let Some((i, s)) = spike(k) {
                rate[i] = rate[i].map(|v| v + s);
            }
            let dt = (k > 0).then_some(0.01);
            if let Some(i) = test.check(&mut rate, &enc, dt) {
                out.push((k, i, rate[i], truth[i].unwrap()));
            }
        }
        out
    }

    #[test]
    fn a_clean_chain_is_never_refused() {
        assert!(run(1000, |_| None).is_empty());
    }

    #[test]
    fn each_segments_spike_is_told_and_replaced() {
        for segment in 0..4 {
            for s in [3.0, -2.0] {
                let refused = run(400, |k| (k == 250).then_some((segment, s)));
                assert_eq!(
                    refused.len(),
                    1,
                    "segment {segment}, spike {s}: {refused:?}"
                );
                let (k, i, replaced, truth) = refused[0];
                assert_eq!((k, i), (250, segment));
                match replaced {
                    // thigh and shank: the rate with which the trapezoid turns
                    // the joints by the encoders' change, within twice the
                    // previous sample's noise (0.02 rad/s) and the
                    // trapezoid's truncation
                    Some(r) => {
                        assert!(segment == 1 || segment == 2);
                        assert!((r - truth).abs() < 0.2, "{r} against {truth}");
                    }
                    // trunk and foot: a missing reading, held by the filter
                    None => assert!(segment == 0 || segment == 3),
                }
            }
        }
    }

    #[test]
    fn nothing_is_tested_before_a_second_of_residuals() {
        assert!(run(400, |k| (k == 50).then_some((1, 3.0))).is_empty());
        assert_eq!(run(400, |k| (k == 150).then_some((1, 3.0))).len(), 1);
    }

    #[test]
    fn a_spike_below_the_jump_margin_is_applied() {
        assert!(run(400, |k| (k == 250).then_some((2, 0.9))).is_empty());
        assert_eq!(run(400, |k| (k == 250).then_some((2, 1.2))).len(), 1);
    }

    #[test]
    fn a_disagreement_spread_over_the_chain_is_no_spike() {
        // thigh +3 and foot +3 at once: no one segment explains it
        let mut test = RateSpikeTest::default();
        let mut refused = 0;
        for k in 0..400 {
            let t = k as f64 * 0.01;
            let (mut rate, enc) = chain_at(t);
            if k == 250 {
                rate[1] = rate[1].map(|v| v + 3.0);
                rate[3] = rate[3].map(|v| v + 3.0);
            }
            refused += usize::from(
                test.check(&mut rate, &enc, (k > 0).then_some(0.01))
                    .is_some(),
            );
        }
        assert_eq!(refused, 0);
    }

    fn segment(test: &RateSpikeTest, residual: &[[f64; 3]; 2]) -> Option<usize> {
        test.hypothesis(residual).map(|(i, _)| i)
    }

    #[test]
    fn the_fit_of_each_hypothesis() {
        // equal weights (a unit mean square): residuals (-2, 2, 0) are a
        // thigh spike of 2 rad/s, explained fully
        let test = RateSpikeTest {
            mean_square: [[0.01; 3]; 2],
            averaged_s: [2.0, 2.0],
            ..RateSpikeTest::default()
        };
        assert_eq!(segment(&test, &[[-2.0, 2.0, 0.0]; 2]), Some(1));
        assert_eq!(segment(&test, &[[0.0, 0.0, -1.5]; 2]), Some(3));
        assert_eq!(segment(&test, &[[1.5, 0.0, 0.0]; 2]), Some(0));
        assert_eq!(segment(&test, &[[0.0, -1.5, 1.5]; 2]), Some(2));
        // (0, 2, 0): the thigh hypothesis explains 2^2 / 2 / 0.01 = 200 and
        // leaves 200, beyond the fit gate
        assert_eq!(segment(&test, &[[0.0, 2.0, 0.0]; 2]), None);
        // below the detection threshold: 0.45^2 / 0.01 = 20.25 < 23.93
        assert_eq!(segment(&test, &[[0.45, 0.0, 0.0]; 2]), None);
    }

    #[test]
    fn missing_inputs_and_time_gaps_are_not_tested() {
        let mut test = RateSpikeTest::default();
        for k in 0..200 {
            let (mut rate, enc) = chain_at(k as f64 * 0.01);
            test.check(&mut rate, &enc, (k > 0).then_some(0.01));
        }
        let (mut rate, mut enc) = chain_at(2.0);
        rate[1] = rate[1].map(|v| v + 3.0);
        enc[2] = None;
        assert_eq!(test.check(&mut rate, &enc, Some(0.01)), None);
        let (mut rate, enc) = chain_at(2.03);
        rate[1] = rate[1].map(|v| v + 3.0);
        assert_eq!(
            test.check(&mut rate, &enc, Some(0.02)),
            None,
            "a missing row: a gap"
        );
    }

    proptest::proptest! {
        /// Whatever the readings: a refusal needs every rate and encoder,
        /// a refused trunk or foot reading becomes missing, a refused thigh
        /// or shank reading a finite rate, and the others are untouched.
        #[test]
        fn a_refusal_needs_every_input_and_leaves_a_finite_rate_or_none(
            steps in proptest::collection::vec(
                (proptest::array::uniform4(-8.0f64..8.0), proptest::array::uniform3(-3.0f64..3.0), 0u8..20),
                1..300,
            ),
        ) {
            let mut test = RateSpikeTest::default();
            for (k, (w, e, missing)) in steps.iter().enumerate() {
                let mut rate: [Option<f64>; 4] = core::array::from_fn(|i| Some(w[i] * 0.05));
                let mut enc: [Option<f64>; 3] = core::array::from_fn(|j| Some(e[j] * 0.01));
                if k % 37 == 5 {
                    rate[k % 4] = rate[k % 4].map(|v| v + w[0]); // a spike, or not
                }
                match missing {
                    0 => rate[1] = None,
                    1 => enc[2] = None,
                    _ => {}
                }
                let before = rate;
                let complete = rate.iter().all(Option::is_some) && enc.iter().all(Option::is_some);
                let refused = test.check(&mut rate, &enc, (k > 0).then_some(0.01));
                if let Some(i) = refused {
                    proptest::prop_assert!(complete);
                    match i {
                        0 | 3 => proptest::prop_assert!(rate[i].is_none()),
                        _ => proptest::prop_assert!(rate[i].is_some_and(f64::is_finite)),
                    }
                }
                for j in 0..4 {
                    if Some(j) != refused {
                        proptest::prop_assert_eq!(rate[j], before[j]);
                    }
                }
            }
        }
    }
}
