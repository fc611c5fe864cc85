//! Stride-to-stride variability as smooth random modulations, so that every
//! derivative stays analytic.
//!
//! * **Cadence.** The stride frequency is `f(t) = f0 (1 + e(t))`, `e` a sum of
//!   [`N_FREQ`] sinusoids with random phases and log-uniform random
//!   frequencies between 1/30 and 1/2 cycle per stride, amplitudes set so that
//!   `std(e)` equals the requested stride-time coefficient of variation (healthy
//!   adults: 1-3 %, J. M. Hausdorff et al., "Walking is more like catching than
//!   tapping: gait in the elderly as a complex cognitive task", Exp. Brain Res.
//!   164:541-548, 2005; J. M. Hausdorff, "Gait variability: methods, modeling
//!   and meaning", J. NeuroEng. Rehabil. 2:19, 2005). The phase is its exact
//!   integral.
//! * **Amplitude.** Every segment-angle excursion about its mean (and the hip
//!   path, see [`crate::hip_path`]) is multiplied by `A(phi) = 1 + sum b_k
//!   sin(nu_k phi + chi_k)`, a function of the gait phase with 1/40 to 1/8
//!   cycle per stride, so stride length varies from stride to stride while the
//!   stance foot stays still (the hip path is a function of the phase too).

use core::f64::consts::TAU;

use rand::Rng;

use crate::fourier::D2;

/// Sinusoids in the cadence modulation.
pub const N_FREQ: usize = 6;
/// Sinusoids in the amplitude modulation.
pub const N_AMP: usize = 4;

#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Sine {
    amp: f64,
    freq: f64,
    phase: f64,
    /// `amp / freq * cos(phase)`: the integral's constant term (0 if `freq` is 0).
    offset: f64,
}

fn draw<R: Rng, const N: usize>(rng: &mut R, cv: f64, lo: f64, hi: f64, scale: f64) -> [Sine; N] {
    let amp = cv * (2.0 / N as f64).sqrt();
    let mut out = [Sine::default(); N];
    for s in out.iter_mut() {
        let u: f64 = rng.random();
        let freq = (lo.ln() + u * (hi.ln() - lo.ln())).exp() * scale;
        let phase = rng.random::<f64>() * TAU;
        let offset = if freq != 0.0 {
            amp / freq * phase.cos()
        } else {
            0.0
        };
        *s = Sine {
            amp,
            freq,
            phase,
            offset,
        };
    }
    out
}

/// The gait clock: phase of the simulated leg as a function of time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    f0: f64,
    phi0: f64,
    sines: [Sine; N_FREQ],
}

impl Clock {
    /// A clock at mean stride frequency `f0` (Hz, 0 holds the phase still),
    /// starting at phase `phi0`; `cv` = stride-time CV (0 = metronomic).
    /// Always consumes the same random draws, whatever `cv`.
    pub fn new<R: Rng>(rng: &mut R, f0: f64, phi0: f64, cv: f64) -> Self {
        // Frequencies in rad/s: cycles per stride x 2 pi f0.
        let sines = draw::<R, N_FREQ>(rng, cv, 1.0 / 30.0, 0.5, TAU * f0);
        Clock { f0, phi0, sines }
    }

    /// Phase (rad, unwrapped) and its first two time derivatives at `t` (s).
    pub fn phase(&self, t: f64) -> D2 {
        let w0 = TAU * self.f0;
        let mut v = t;
        let mut e = 0.0;
        let mut ed = 0.0;
        for s in &self.sines {
            if s.amp == 0.0 || s.freq == 0.0 {
                continue;
            }
            let (sn, cs) = (s.freq * t + s.phase).sin_cos();
            v += s.offset - s.amp / s.freq * cs;
            e += s.amp * sn;
            ed += s.amp * s.freq * cs;
        }
        D2 {
            v: self.phi0 + w0 * v,
            d1: w0 * (1.0 + e),
            d2: w0 * ed,
        }
    }

    /// Mean stride frequency (Hz).
    pub fn mean_frequency(&self) -> f64 {
        self.f0
    }
}

/// The amplitude modulation `A(phi)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modulation {
    sines: [Sine; N_AMP],
}

impl Modulation {
    /// Draws a modulation with coefficient of variation `cv` (0 = none).
    /// Always consumes the same random draws, whatever `cv`.
    pub fn new<R: Rng>(rng: &mut R, cv: f64) -> Self {
        Modulation {
            sines: draw::<R, N_AMP>(rng, cv, 1.0 / 40.0, 1.0 / 8.0, 1.0),
        }
    }

    /// `A`, `dA/dphi`, `d2A/dphi2`.
    pub fn amp(&self, phi: f64) -> D2 {
        let mut out = D2::constant(1.0);
        for s in &self.sines {
            let (sn, cs) = (s.freq * phi + s.phase).sin_cos();
            out.v += s.amp * sn;
            out.d1 += s.amp * s.freq * cs;
            out.d2 -= s.amp * s.freq * s.freq * sn;
        }
        out
    }

    /// `int_0^phi A(u) du`.
    pub fn integral(&self, phi: f64) -> f64 {
        let mut v = phi;
        for s in &self.sines {
            if s.amp != 0.0 && s.freq != 0.0 {
                v += s.offset - s.amp / s.freq * (s.freq * phi + s.phase).cos();
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn clock_derivatives_are_consistent() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let c = Clock::new(&mut rng, 0.9, 0.2, 0.05);
        let h = 1e-5;
        for t in [0.0, 3.3, 41.0] {
            let p = c.phase(t);
            let d1 = (c.phase(t + h).v - c.phase(t - h).v) / (2.0 * h);
            let d2 = (c.phase(t + h).d1 - c.phase(t - h).d1) / (2.0 * h);
            assert!((p.d1 - d1).abs() < 1e-6);
            assert!((p.d2 - d2).abs() < 1e-6);
        }
        assert_eq!(c.phase(0.0).v, 0.2);
    }

    #[test]
    fn modulation_integral_matches() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let m = Modulation::new(&mut rng, 0.05);
        let h = 1e-5;
        let phi = 17.0;
        let d = (m.integral(phi + h) - m.integral(phi - h)) / (2.0 * h);
        assert!((d - m.amp(phi).v).abs() < 1e-8);
        assert_eq!(m.integral(0.0), 0.0);
    }
}
