//! Accelerometer reliability and the update criteria of papers 000 and 001,
//! as pure functions.
//!
//! * [`reliability`]: `rho_i = | ||a_i|| - g |` (001 eqs 11, 14; 000 eq 28
//!   prints it without the absolute value, SPEC section 6).
//! * [`mjls_select`]: the Markov mode `Xi = argmin_i rho_i` and its test
//!   `rho(k) <= zeta` (000 eqs 28-30, 001 eqs 11-13; note the `<=`).
//! * [`reliable_flags`], [`psi`], [`upsilon`]: the per-segment test
//!   `rho_i < zeta_i`, the count criterion `Psi_s` (001 eqs 15-18: at least
//!   `s` accelerometers pass) and the pair criteria `Upsilon_h/k/a`
//!   (001 eqs 26-28; note the strict `<`).

use limbfuse_core::Segment;
use nalgebra::Vector3;

/// `rho = | ||a|| - g |` (m/s^2): how far the specific-force magnitude is
/// from gravity (001 eq 11). Small values mean little dynamic acceleration.
#[inline]
pub fn reliability(acc: &Vector3<f64>, gravity: f64) -> f64 {
    libm::fabs(acc.norm() - gravity)
}

/// The Markov mode decision of the MJLS filter at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MjlsMode {
    /// `Xi(k) = argmin_i rho_i` over the segments whose accelerometer is
    /// present (000 eq 29, 001 eq 12); ties go to the most proximal segment.
    /// `None` when no accelerometer is present.
    pub most_reliable: Option<Segment>,
    /// `rho(k) = min_i rho_i` (000 eq 28, 001 eq 11).
    pub rho_min: Option<f64>,
    /// `Psi = rho(k) <= zeta_Xi` (000 eq 30, 001 eq 13): the selected
    /// accelerometer may be used.
    pub reliable: bool,
}

impl MjlsMode {
    /// The selected segment when it passes the test, else `None`.
    pub fn mode(&self) -> Option<Segment> {
        if self.reliable {
            self.most_reliable
        } else {
            None
        }
    }
}

/// Markov mode selection (000 eqs 28-30, 001 eqs 11-13). `zeta` is per
/// segment; the papers use one value, and the test here applies the
/// threshold of the selected segment.
pub fn mjls_select(rho: &[Option<f64>; 4], zeta: &[f64; 4]) -> MjlsMode {
    let mut best: Option<(usize, f64)> = None;
    for (i, r) in rho.iter().enumerate() {
        if let Some(r) = *r {
            let better = match best {
                None => true,
                Some((_, b)) => r < b,
            };
            if r.is_finite() && better {
                best = Some((i, r));
            }
        }
    }
    match best {
        Some((i, r)) => MjlsMode {
            most_reliable: Some(Segment::ALL[i]),
            rho_min: Some(r),
            reliable: r <= zeta[i],
        },
        None => MjlsMode {
            most_reliable: None,
            rho_min: None,
            reliable: false,
        },
    }
}

/// Per-segment test `rho_i < zeta_i` (001 eqs 15-18, 26-28); a missing
/// accelerometer is not reliable.
pub fn reliable_flags(rho: &[Option<f64>; 4], zeta: &[f64; 4]) -> [bool; 4] {
    let mut out = [false; 4];
    for i in 0..4 {
        out[i] = matches!(rho[i], Some(r) if r < zeta[i]);
    }
    out
}

/// Number of reliable accelerometers.
pub fn count_reliable(reliable: &[bool; 4]) -> u8 {
    reliable.iter().filter(|&&r| r).count() as u8
}

/// `Psi_s` (001 eqs 15-18): at least `s` of the four accelerometers are
/// reliable. `Psi_4` needs all four, `Psi_1` any one.
pub fn psi(reliable: &[bool; 4], s: u8) -> bool {
    count_reliable(reliable) >= s
}

/// `Upsilon_h, Upsilon_k, Upsilon_a` (001 eqs 26-28): both accelerometers of
/// the joint's two segments are reliable.
pub fn upsilon(reliable: &[bool; 4]) -> [bool; 3] {
    [
        reliable[0] && reliable[1],
        reliable[1] && reliable[2],
        reliable[2] && reliable[3],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reliability_is_absolute_distance_to_g() {
        assert!((reliability(&Vector3::new(0.0, 9.5, 0.0), 9.81) - 0.31).abs() < 1e-12);
        assert!((reliability(&Vector3::new(0.0, 10.5, 0.0), 9.81) - 0.69).abs() < 1e-12);
        assert!((reliability(&Vector3::new(3.0, 4.0, 0.0), 5.0)).abs() < 1e-15);
    }

    #[test]
    fn psi_and_upsilon_count_and_pair() {
        let r = [true, false, true, true];
        assert!(psi(&r, 3) && !psi(&r, 4) && psi(&r, 1));
        assert_eq!(upsilon(&r), [false, false, true]);
        let rho = [Some(0.1), None, Some(0.2), Some(0.19)];
        assert_eq!(reliable_flags(&rho, &[0.2; 4]), [true, false, false, true]);
    }

    #[test]
    fn mjls_ties_go_proximal_and_missing_is_skipped() {
        let m = mjls_select(&[None, Some(0.3), Some(0.3), None], &[0.3; 4]);
        assert_eq!(m.most_reliable, Some(Segment::Thigh));
        assert!(m.reliable);
        let m = mjls_select(&[None; 4], &[0.3; 4]);
        assert_eq!(
            m,
            MjlsMode {
                most_reliable: None,
                rho_min: None,
                reliable: false
            }
        );
        assert_eq!(m.mode(), None);
    }
}
