//! Joint encoders: the SPEC joint angle plus a constant offset and white
//! noise, quantised to the encoder resolution; simulated at their own rate
//! (1 kHz by default) and resampled onto the IMU time base
//! ([`crate::config::EncoderResample`]).

use rand::Rng;
use rand_distr::StandardNormal;

use crate::config::EncoderSpec;

/// The three joint encoders.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoders {
    /// Constant offsets (rad): hip, knee, ankle.
    pub offset: [f64; 3],
    step: f64,
    noise: f64,
    on: bool,
}

impl Encoders {
    /// Draws the offsets (3 normals, always).
    pub fn draw<R: Rng>(rng: &mut R, spec: &EncoderSpec, on: bool) -> Self {
        let mut offset = [0.0; 3];
        for o in offset.iter_mut() {
            *o = rng.sample::<f64, _>(StandardNormal) * spec.offset_rad;
        }
        let step = if spec.bits == 0 {
            0.0
        } else {
            core::f64::consts::TAU / 2f64.powi(spec.bits as i32)
        };
        if on {
            Encoders {
                offset,
                step,
                noise: spec.noise_rad,
                on,
            }
        } else {
            Encoders {
                offset: [0.0; 3],
                step: 0.0,
                noise: 0.0,
                on,
            }
        }
    }

    /// Quantisation step (rad), 0 when not quantised.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// One reading of the true joint angles; draws 3 normals when the noise is on.
    #[inline]
    pub fn read<R: Rng>(&self, joint: &[f64; 3], rng: &mut R) -> [f64; 3] {
        if !self.on {
            return *joint;
        }
        let mut out = [0.0; 3];
        for i in 0..3 {
            let v = joint[i] + self.offset[i] + rng.sample::<f64, _>(StandardNormal) * self.noise;
            out[i] = if self.step > 0.0 {
                (v / self.step).round() * self.step
            } else {
                v
            };
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn readings_are_quantised_and_offset() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let e = Encoders::draw(&mut rng, &EncoderSpec::default(), true);
        let r = e.read(&[0.1, 0.2, 0.3], &mut rng);
        for (i, v) in r.iter().enumerate() {
            let k = v / e.step();
            assert!((k - k.round()).abs() < 1e-6);
            assert!((v - [0.1, 0.2, 0.3][i] - e.offset[i]).abs() < 5.0 * e.step());
        }
        let ideal = Encoders::draw(&mut rng, &EncoderSpec::default(), false);
        assert_eq!(ideal.read(&[0.1, 0.2, 0.3], &mut rng), [0.1, 0.2, 0.3]);
    }
}
