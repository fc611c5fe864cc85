//! Sub-sample time of the push-off extremum (the final contact) from the
//! five samples around the lowest one, by whichever of two models explains
//! them better (docs/GAIT_EVENTS.md, "Final contact to sub-sample time"):
//!
//! - **Corner**: the foot's rate falls slowly while the toe drives the
//!   push-off and rises steeply once the toe is off the ground (the drive
//!   ends: the rate's derivative jumps). The trough is then the corner of
//!   two lines, `w = max(L, R)`: `L` through the two samples before the
//!   lowest, `R` through the two after it; the corner is where they meet.
//!   A symmetric low-pass (a sensor's or resampler's anti-alias filter)
//!   rounds the corner but keeps the lines away from it, so their meeting
//!   point stays near the unfiltered corner, while the minimum of the
//!   rounded trough moves towards the gentler side (earlier; test
//!   `a_low_passed_corner_keeps_its_lines`: 4 ms against 20 ms at 50 Hz
//!   for the shared walk's push-off slopes). For a V the
//!   corner lies between the lowest sample's two neighbours, so the
//!   meeting point is limited to that interval.
//! - **Parabola** through the lowest sample and its two neighbours: exact
//!   for a smooth trough (a vertex much wider than the sample period), where
//!   the corner's lines, drawn across the curved flanks, would meet only at
//!   the lowest sample.
//!
//! Each model is fitted exactly to some of the five samples and predicts the
//! others: the parabola (samples 1-3) predicts samples 0 and 4, the corner
//! (samples 0, 1 and 3, 4) predicts sample 2. The model with the smaller
//! mean squared prediction error gives the time; no threshold.

/// Samples `(t, w)` at offsets -2..=2 around a sampled minimum (index 2),
/// filled as they arrive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TroughSamples {
    samples: [Option<(f64, f64)>; 5],
    dt: f64,
}

/// Which model gave the time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TroughModel {
    /// Parabola through the lowest sample and its neighbours.
    Parabola,
    /// Corner of the lines through the two samples on each side.
    Corner,
}

impl TroughSamples {
    /// A new lowest sample `(t, w)`, step `dt` (s) from the previous one,
    /// with the two samples before it (latest last) when known.
    pub fn new(t: f64, w: f64, dt: f64, before: [Option<(f64, f64)>; 2]) -> Self {
        TroughSamples {
            samples: [before[0], before[1], Some((t, w)), None, None],
            dt,
        }
    }

    /// Time (s) of the lowest sample.
    pub fn t(&self) -> f64 {
        self.lowest().0
    }

    /// The lowest sample's value.
    pub fn value(&self) -> f64 {
        self.lowest().1
    }

    fn lowest(&self) -> (f64, f64) {
        // Always set by `new`.
        self.samples[2].unwrap_or((0.0, 0.0))
    }

    /// Takes the sample `(t, w)` if it is one of the two after the lowest.
    pub fn push_after(&mut self, t: f64, w: f64) {
        if t <= self.t() {
            return;
        }
        if self.samples[3].is_none() {
            self.samples[3] = Some((t, w));
        } else if self.samples[4].is_none() {
            self.samples[4] = Some((t, w));
        }
    }

    /// Both samples after the lowest have arrived.
    pub fn is_complete(&self) -> bool {
        self.samples[4].is_some()
    }

    /// Parabolic vertex through the lowest sample and its neighbours
    /// (uniform step `dt`; the sample before counts as 0 when unknown), within
    /// half a step of the lowest sample; the lowest sample's time without
    /// the sample after.
    fn parabola_time(&self) -> f64 {
        let (t, value) = self.lowest();
        let before = self.samples[1].map_or(0.0, |s| s.1);
        let Some((_, after)) = self.samples[3] else {
            return t;
        };
        let den = before - 2.0 * value + after;
        if den.abs() < 1e-12 {
            return t;
        }
        let offset = 0.5 * (before - after) / den;
        t + offset.clamp(-0.5, 0.5) * self.dt
    }

    /// Sub-sample time (s) of the trough and the model that gave it.
    pub fn refined(&self) -> (f64, TroughModel) {
        let parabola = (self.parabola_time(), TroughModel::Parabola);
        let [Some(s0), Some(s1), Some(s2), Some(s3), Some(s4)] = self.samples else {
            return parabola;
        };
        let Some((corner_time, corner_error)) = corner(s0, s1, s2, s3, s4) else {
            return parabola;
        };
        let e0 = s0.1 - lagrange(s1, s2, s3, s0.0);
        let e4 = s4.1 - lagrange(s1, s2, s3, s4.0);
        let parabola_error = 0.5 * (e0 * e0 + e4 * e4);
        if corner_error < parabola_error {
            (corner_time, TroughModel::Corner)
        } else {
            parabola
        }
    }
}

/// Meeting time of the line `L` through `s0`, `s1` and the line `R` through
/// `s3`, `s4` (limited to `[t1, t3]`), and the squared error of `max(L, R)`
/// at `s2`; `None` unless `R` rises faster than `L` (a trough's corner).
fn corner(
    s0: (f64, f64),
    s1: (f64, f64),
    s2: (f64, f64),
    s3: (f64, f64),
    s4: (f64, f64),
) -> Option<(f64, f64)> {
    let slope_left = (s1.1 - s0.1) / (s1.0 - s0.0);
    let slope_right = (s4.1 - s3.1) / (s4.0 - s3.0);
    if !(slope_left.is_finite() && slope_right.is_finite()) || slope_right <= slope_left {
        return None;
    }
    // L(t) = w1 + sL (t - t1), R(t) = w3 + sR (t - t3); in u = t - t2:
    let u = (s3.1 - s1.1 + slope_right * (s2.0 - s3.0) - slope_left * (s2.0 - s1.0))
        / (slope_left - slope_right);
    let time = (s2.0 + u).clamp(s1.0, s3.0);
    let left_at = s1.1 + slope_left * (s2.0 - s1.0);
    let right_at = s3.1 + slope_right * (s2.0 - s3.0);
    let error = s2.1 - left_at.max(right_at);
    Some((time, error * error))
}

/// The parabola through `a`, `b`, `c` at time `x`.
fn lagrange(a: (f64, f64), b: (f64, f64), c: (f64, f64), x: f64) -> f64 {
    a.1 * (x - b.0) * (x - c.0) / ((a.0 - b.0) * (a.0 - c.0))
        + b.1 * (x - a.0) * (x - c.0) / ((b.0 - a.0) * (b.0 - c.0))
        + c.1 * (x - a.0) * (x - b.0) / ((c.0 - a.0) * (c.0 - b.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The five samples of `f` around its lowest sample on the grid `k dt`.
    fn sampled(f: impl Fn(f64) -> f64, dt: f64) -> TroughSamples {
        let k = (-50..50)
            .min_by(|&a, &b| f(a as f64 * dt).total_cmp(&f(b as f64 * dt)))
            .unwrap();
        let s = |j: i32| {
            let t = (k + j) as f64 * dt;
            (t, f(t))
        };
        let mut out = TroughSamples::new(s(0).0, s(0).1, dt, [Some(s(-2)), Some(s(-1))]);
        out.push_after(s(1).0, s(1).1);
        assert!(!out.is_complete());
        out.push_after(s(2).0, s(2).1);
        assert!(out.is_complete());
        out
    }

    #[test]
    fn a_corner_is_found_exactly_at_any_sample_phase() {
        let dt = 0.02;
        for phase in [0.0, 0.13, 0.37, 0.5, 0.71, 0.94] {
            let c = 0.011 + phase * dt;
            // push-off: -0.02 rad/s per ms; release: +0.45 rad/s per ms
            let v = |t: f64| {
                if t < c {
                    -9.0 - 20.0 * (t - c)
                } else {
                    -9.0 + 450.0 * (t - c)
                }
            };
            let (t, model) = sampled(v, dt).refined();
            assert_eq!(model, TroughModel::Corner, "phase {phase}");
            assert!((t - c).abs() < 1e-9, "phase {phase}: {t} vs {c}");
        }
    }

    #[test]
    fn a_smooth_trough_is_the_parabola_vertex() {
        let dt = 0.02;
        for phase in [0.0, 0.2, 0.45, 0.8] {
            let c = 0.003 + phase * dt;
            let p = |t: f64| -6.5 + 400.0 * (t - c) * (t - c);
            let (t, model) = sampled(p, dt).refined();
            assert_eq!(model, TroughModel::Parabola, "phase {phase}");
            assert!((t - c).abs() < 1e-9, "phase {phase}: {t} vs {c}");
        }
    }

    #[test]
    fn without_the_samples_after_it_is_the_parabola() {
        let mut s = TroughSamples::new(1.0, -9.0, 0.01, [Some((0.98, -8.0)), Some((0.99, -8.5))]);
        assert_eq!(s.refined(), (1.0, TroughModel::Parabola));
        s.push_after(1.0, -20.0);
        s.push_after(1.01, -4.0);
        assert!(
            !s.is_complete(),
            "a sample at the lowest's time is not after it"
        );
        assert_eq!(s.refined().1, TroughModel::Parabola);
    }

    /// The push-off corner of the shared gaitmap walk (-0.02 rad/s per ms,
    /// then +0.45 rad/s per ms up to +4 rad/s) low-passed as `limbfuse
    /// resample` does for 50 Hz (Blackman-windowed sinc, cut-off 17.5 Hz,
    /// half-width 0.2 s) and sampled at 50 Hz at 10 phases: the parabola's
    /// vertex is about 20 ms early at every phase (the rounded trough's
    /// minimum is on the gentle side), the corner's meeting point 4 ms
    /// early on average, never 8 ms off.
    #[test]
    fn a_low_passed_corner_keeps_its_lines() {
        use core::f64::consts::PI;
        let (fc, half_width, rate) = (17.5, 0.2, 50.0);
        let step = 1e-4;
        let taps: Vec<(f64, f64)> = (-2000..=2000)
            .map(|i| {
                let x = i as f64 * step;
                let sinc = if i == 0 {
                    1.0
                } else {
                    (2.0 * PI * fc * x).sin() / (2.0 * PI * fc * x)
                };
                let c = PI * x / half_width;
                (x, sinc * (0.42 + 0.5 * c.cos() + 0.08 * (2.0 * c).cos()))
            })
            .collect();
        let norm: f64 = taps.iter().map(|t| t.1).sum();
        let (mut corner_sum, mut n) = (0.0, 0.0);
        for phase in 0..10 {
            let c = phase as f64 / 10.0 / rate;
            let v = |t: f64| {
                if t < c {
                    -9.0 - 20.0 * (t - c)
                } else {
                    (-9.0 + 450.0 * (t - c)).min(4.0)
                }
            };
            let filtered = |t: f64| taps.iter().map(|&(x, h)| h * v(t - x)).sum::<f64>() / norm;
            let samples = sampled(filtered, 1.0 / rate);
            let (t, model) = samples.refined();
            assert_eq!(model, TroughModel::Corner, "phase {phase}");
            assert!((t - c).abs() < 0.008, "phase {phase}: corner {t} vs {c}");
            let parabola = samples.parabola_time();
            assert!(
                c - parabola > 0.015,
                "phase {phase}: parabola {parabola} vs {c}"
            );
            corner_sum += t - c;
            n += 1.0;
        }
        let mean = corner_sum / n;
        assert!((-0.005..0.0).contains(&mean), "mean corner error {mean} s");
    }
}
