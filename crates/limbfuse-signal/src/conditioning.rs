//! Signal conditioning of paper 004 section 3.2: a 3rd-order Butterworth
//! low-pass in causal and zero-phase (forward-backward) form, numerical
//! differentiation of gyro signals, and the motion-acceleration
//! compensation of eq 3.1 (`a_motion = q_ddot L`).
//!
//! The filter is the bilinear transform, with the cutoff pre-warped, of the
//! analog 3rd-order Butterworth prototype (poles `-1`, `-1/2 +- j sqrt(3)/2`):
//! one first-order and one second-order (Q = 1) section in transposed
//! direct form II. The `biquad` crate offers second-order sections only and
//! no zero-phase form, so the 40 lines are written here and tested against
//! the analytic design: -3.01 dB and -135 deg at the cutoff (pre-warping
//! makes the digital response at `fc` equal the analog one), -6.02 dB and
//! zero phase for the forward-backward form.

/// A 3rd-order Butterworth low-pass for one channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Butterworth3 {
    /// First-order section `(b0, b1, a1)`.
    first: [f64; 3],
    /// Second-order section `(b0, b1, b2, a1, a2)`.
    second: [f64; 5],
    z_first: f64,
    z_second: [f64; 2],
}

/// Why a filter cannot be designed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("low-pass cutoff {cutoff_hz} Hz must be in (0, {nyquist} Hz) (half the sample rate {rate_hz} Hz)")]
pub struct CutoffError {
    /// Requested cutoff.
    pub cutoff_hz: f64,
    /// Sample rate.
    pub rate_hz: f64,
    /// Nyquist frequency.
    pub nyquist: f64,
}

impl Butterworth3 {
    /// Designs the filter for cutoff `cutoff_hz` at sample rate `rate_hz`.
    pub fn new(cutoff_hz: f64, rate_hz: f64) -> Result<Self, CutoffError> {
        let nyquist = rate_hz / 2.0;
        if !(cutoff_hz > 0.0 && cutoff_hz < nyquist && rate_hz.is_finite()) {
            return Err(CutoffError {
                cutoff_hz,
                rate_hz,
                nyquist,
            });
        }
        let k = (core::f64::consts::PI * cutoff_hz / rate_hz).tan();
        let a0 = 1.0 + k;
        let first = [k / a0, k / a0, (k - 1.0) / a0];
        let q = 1.0;
        let d0 = 1.0 + k / q + k * k;
        let second = [
            k * k / d0,
            2.0 * k * k / d0,
            k * k / d0,
            2.0 * (k * k - 1.0) / d0,
            (1.0 - k / q + k * k) / d0,
        ];
        Ok(Butterworth3 {
            first,
            second,
            z_first: 0.0,
            z_second: [0.0; 2],
        })
    }

    /// Sets the state to the steady state of a constant input `x` (no start-up transient).
    pub fn settle(&mut self, x: f64) {
        // At DC y = x, so the transposed-form state is z = y - b0 x.
        self.z_first = x - self.first[0] * x;
        let [_, _, b2, _, a2] = self.second;
        let z2 = (b2 - a2) * x;
        self.z_second = [x - self.second[0] * x, z2];
    }

    /// Filters one sample.
    #[inline]
    pub fn step(&mut self, x: f64) -> f64 {
        let [b0, b1, a1] = self.first;
        let y1 = b0 * x + self.z_first;
        self.z_first = b1 * x - a1 * y1;
        let [c0, c1, c2, d1, d2] = self.second;
        let y = c0 * y1 + self.z_second[0];
        self.z_second[0] = c1 * y1 - d1 * y + self.z_second[1];
        self.z_second[1] = c2 * y1 - d2 * y;
        y
    }

    /// Complex frequency response `(re, im)` at `f_hz` for sample rate `rate_hz`.
    pub fn response(&self, f_hz: f64, rate_hz: f64) -> (f64, f64) {
        let w = core::f64::consts::TAU * f_hz / rate_hz;
        let (c1, s1) = (w.cos(), -w.sin());
        let (c2, s2) = ((2.0 * w).cos(), -(2.0 * w).sin());
        let cmul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let cdiv = |a: (f64, f64), b: (f64, f64)| {
            let d = b.0 * b.0 + b.1 * b.1;
            ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let [b0, b1, a1] = self.first;
        let h1 = cdiv((b0 + b1 * c1, b1 * s1), (1.0 + a1 * c1, a1 * s1));
        let [e0, e1, e2, d1, d2] = self.second;
        let h2 = cdiv(
            (e0 + e1 * c1 + e2 * c2, e1 * s1 + e2 * s2),
            (1.0 + d1 * c1 + d2 * c2, d1 * s1 + d2 * s2),
        );
        cmul(h1, h2)
    }
}

/// Causal low-pass of a whole signal, started in steady state at its first value.
pub fn lowpass(x: &[f64], cutoff_hz: f64, rate_hz: f64) -> Result<Vec<f64>, CutoffError> {
    let mut f = Butterworth3::new(cutoff_hz, rate_hz)?;
    if let Some(x0) = x.first() {
        f.settle(*x0);
    }
    Ok(x.iter().map(|v| f.step(*v)).collect())
}

/// Zero-phase low-pass (forward, then backward; each pass settled at its
/// first value): squared magnitude, no delay.
pub fn lowpass_zero_phase(
    x: &[f64],
    cutoff_hz: f64,
    rate_hz: f64,
) -> Result<Vec<f64>, CutoffError> {
    let mut y = lowpass(x, cutoff_hz, rate_hz)?;
    y.reverse();
    let mut z = lowpass(&y, cutoff_hz, rate_hz)?;
    z.reverse();
    Ok(z)
}

/// Central-difference derivative of a uniformly sampled signal (one-sided at
/// the ends); latency 0 offline, one sample if used causally.
pub fn derivative(x: &[f64], dt: f64) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| match (k, n) {
            (_, 0 | 1) => 0.0,
            (0, _) => (x[1] - x[0]) / dt,
            (k, n) if k == n - 1 => (x[k] - x[k - 1]) / dt,
            (k, _) => (x[k + 1] - x[k - 1]) / (2.0 * dt),
        })
        .collect()
}

/// Eq 3.1: removes the tangential motion acceleration `q_ddot L` of a sensor
/// `l_m` metres from the joint from its `acc_x`, with `q_ddot` the
/// derivative of the (low-passed) gyro rate.
pub fn compensate_motion(acc_x: &[f64], gyr_z: &[f64], l_m: f64, dt: f64) -> Vec<f64> {
    let q_ddot = derivative(gyr_z, dt);
    acc_x
        .iter()
        .zip(q_ddot)
        .map(|(a, qd)| a - qd * l_m)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn db(h: (f64, f64)) -> f64 {
        20.0 * (h.0 * h.0 + h.1 * h.1).sqrt().log10()
    }

    #[test]
    fn cutoff_gain_and_phase_match_the_analog_design() {
        for (fc, fs) in [(5.0, 100.0), (0.05 * 50.0, 100.0), (20.0, 1000.0)] {
            let f = Butterworth3::new(fc, fs).unwrap();
            let h = f.response(fc, fs);
            assert!((db(h) - -3.0103).abs() < 1e-3, "{}", db(h));
            let phase = h.1.atan2(h.0).to_degrees();
            assert!((phase - -135.0).abs() < 1e-9, "{phase}");
            assert!((db(f.response(0.0, fs))).abs() < 1e-12);
            // 3rd order: -60 dB/decade well above the cutoff (bilinear
            // compresses towards Nyquist, so check one octave: about -18 dB more).
            assert!(db(f.response(2.0 * fc, fs)) < -17.0);
        }
    }

    #[test]
    fn causal_filter_has_the_designed_response_on_a_sinusoid() {
        let (fs, fc, f0) = (100.0, 5.0, 5.0);
        let x: Vec<f64> = (0..4000)
            .map(|k| (core::f64::consts::TAU * f0 * k as f64 / fs).sin())
            .collect();
        let y = lowpass(&x, fc, fs).unwrap();
        // Amplitude from the RMS over whole periods (sampled peaks miss the crest).
        let amp = (2.0 * y[2000..].iter().map(|v| v * v).sum::<f64>() / 2000.0).sqrt();
        assert!(
            (amp - core::f64::consts::FRAC_1_SQRT_2).abs() < 1e-3,
            "{amp}"
        );
        let z = lowpass_zero_phase(&x, fc, fs).unwrap();
        // Zero phase: the output is in phase with the input, amplitude 1/2.
        let (mut num, mut den) = (0.0, 0.0);
        for k in 1000..3000 {
            num += z[k] * x[k];
            den += x[k] * x[k];
        }
        assert!((num / den - 0.5).abs() < 2e-3, "{}", num / den);
    }

    #[test]
    fn settled_filter_passes_a_constant_unchanged() {
        let y = lowpass(&[3.0; 50], 2.0, 100.0).unwrap();
        assert!(y.iter().all(|v| (v - 3.0).abs() < 1e-12));
    }

    #[test]
    fn eq_3_1_removes_the_tangential_acceleration() {
        // theta = 0.5 sin(2 t): acc_x = g sin theta + L theta_ddot.
        let (dt, l) = (0.001, 0.2);
        let th: Vec<f64> = (0..2000)
            .map(|k| 0.5 * (2.0 * k as f64 * dt).sin())
            .collect();
        let w: Vec<f64> = (0..2000).map(|k| (2.0 * k as f64 * dt).cos()).collect();
        let acc: Vec<f64> = (0..2000)
            .map(|k| 9.81 * th[k].sin() - l * 2.0 * (2.0 * k as f64 * dt).sin())
            .collect();
        let c = compensate_motion(&acc, &w, l, dt);
        for k in 1..1999 {
            assert!((c[k] - 9.81 * th[k].sin()).abs() < 1e-6);
        }
        assert!(Butterworth3::new(60.0, 100.0).is_err());
    }
}
