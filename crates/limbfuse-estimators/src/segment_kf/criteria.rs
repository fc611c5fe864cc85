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

    /// The `mode` diagnostic column: the index (trunk 0 .. foot 3) of
    /// [`MjlsMode::mode`], -1 when no segment passes.
    pub fn code(&self) -> f64 {
        self.mode().map_or(-1.0, |s| s.index() as f64)
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

/// Optional refinements of the accelerometer acceptance test, applied on
/// top of `rho_i < zeta_i` by all three filters. Both tests are off by
/// default ([`AccelGate::OFF`]), which keeps the papers' behaviour.
///
/// Why: `rho` is only second-order sensitive to an acceleration
/// perpendicular to gravity (`rho ~ a_perp^2 / (2 g)`), so `rho < zeta`
/// admits tilts up to `sqrt(2 zeta / g)` (16 deg for zeta = 0.4), see
/// `SegmentNoise::consumer_mems`. Both refinements are the usual tests of
/// stationary / quasi-static detectors (e.g. Skog et al., IEEE TBME 57(11),
/// 2010: window tests on the acceleration magnitude and on the angular-rate
/// energy):
///
/// * `hold_s`: while a segment accelerates, the norm of its specific force
///   often only *crosses* `g`; a quasi-static phase keeps it near `g` for a
///   while. A segment passes only when `rho < zeta` has held on every sample
///   of the last `hold_s` seconds (timestamps, not sample counts). On the
///   walking simulator at 100 Hz, `hold_s = 0.01` (two consecutive samples)
///   lowers the MJLS error at 1.0 and 1.6 m/s but raises local/global
///   errors, which lose too many updates (docs/RESULTS.md, "Accelerometer
///   gating").
/// * `max_rate`: the segment's angular rate `||omega||` (rad/s) must be
///   below `max_rate`; a missing gyro sample fails this test. No clear gain
///   on the walking simulator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelGate {
    /// Quasi-static duration (s), >= 0; 0 = off.
    pub hold_s: f64,
    /// Angular-rate bound (rad/s), > 0; infinity = off.
    pub max_rate: f64,
}

impl AccelGate {
    /// No refinement: the papers' test alone.
    pub const OFF: AccelGate = AccelGate {
        hold_s: 0.0,
        max_rate: f64::INFINITY,
    };

    /// True when both tests are off.
    pub fn is_off(&self) -> bool {
        self.hold_s == 0.0 && self.max_rate == f64::INFINITY
    }
}

impl Default for AccelGate {
    fn default() -> Self {
        AccelGate::OFF
    }
}

/// Tolerance (s) on the hold duration, for timestamps that are not exact
/// multiples of the sample period.
const HOLD_EPS_S: f64 = 1e-6;

/// State of the duration test of [`AccelGate`]: when the current run of
/// `rho < zeta` began, per segment. Fixed size, no allocation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AccelGateState {
    run_start: [Option<f64>; 4],
}

impl AccelGateState {
    /// Forgets every run.
    pub fn reset(&mut self) {
        self.run_start = [None; 4];
    }

    /// Per segment: `rho_i < zeta_i` and the `hold_s` and `max_rate` tests
    /// of `gate` at time `t` (s); `rate` is `||omega_i||` (rad/s), `None`
    /// when the gyro sample is missing. A missing accelerometer sample ends
    /// the run. Call once per sample, in time order.
    pub fn passes(
        &mut self,
        gate: &AccelGate,
        t: f64,
        rho: &[Option<f64>; 4],
        zeta: &[f64; 4],
        rate: &[Option<f64>; 4],
    ) -> [bool; 4] {
        let base = reliable_flags(rho, zeta);
        let mut out = [false; 4];
        for i in 0..4 {
            if !base[i] {
                self.run_start[i] = None;
                continue;
            }
            let start = *self.run_start[i].get_or_insert(t);
            let held = t - start >= gate.hold_s - HOLD_EPS_S;
            let still =
                gate.max_rate == f64::INFINITY || matches!(rate[i], Some(w) if w < gate.max_rate);
            out[i] = held && still;
        }
        out
    }

    /// The per-segment test of this sample: `rho_i < zeta_i`
    /// ([`reliable_flags`]) when `gate` is off, else
    /// [`AccelGateState::passes_sample`].
    pub fn reliable(
        &mut self,
        gate: &AccelGate,
        sample: &limbfuse_core::Sample,
        rho: &[Option<f64>; 4],
        zeta: &[f64; 4],
    ) -> [bool; 4] {
        if gate.is_off() {
            reliable_flags(rho, zeta)
        } else {
            self.passes_sample(gate, sample, rho, zeta)
        }
    }

    /// [`AccelGateState::passes`] with the rates `||gyr_i||` of `sample`.
    pub fn passes_sample(
        &mut self,
        gate: &AccelGate,
        sample: &limbfuse_core::Sample,
        rho: &[Option<f64>; 4],
        zeta: &[f64; 4],
    ) -> [bool; 4] {
        let mut rate = [None; 4];
        for (r, imu) in rate.iter_mut().zip(sample.imu.iter()) {
            *r = imu.gyr.map(|w| w.norm()).filter(|w| w.is_finite());
        }
        self.passes(gate, sample.t, rho, zeta, &rate)
    }
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

    #[test]
    fn hold_test_needs_the_whole_duration_on_the_timestamps() {
        let gate = AccelGate {
            hold_s: 0.02,
            ..AccelGate::OFF
        };
        let zeta = [0.4; 4];
        let rate = [Some(0.0); 4];
        let mut st = AccelGateState::default();
        // segment 0 at 100 Hz: rho passes except at k = 3
        let rho0 = [0.1, 0.1, 0.1, 0.5, 0.1, 0.1, 0.1, 0.1];
        let want = [false, false, true, false, false, false, true, true];
        for (k, (&r, &w)) in rho0.iter().zip(want.iter()).enumerate() {
            let rho = [Some(r), None, Some(0.5), Some(0.1)];
            let out = st.passes(&gate, k as f64 * 0.01, &rho, &zeta, &rate);
            assert_eq!(out[0], w, "k = {k}");
            assert!(!out[1] && !out[2]);
            assert_eq!(out[3], k >= 2, "k = {k}");
        }
        // irregular timestamps: what counts is the time, not the samples
        st.reset();
        let rho = [Some(0.1); 4];
        assert!(!st.passes(&gate, 1.0, &rho, &zeta, &rate)[0]);
        assert!(!st.passes(&gate, 1.015, &rho, &zeta, &rate)[0]);
        assert!(st.passes(&gate, 1.0199999995, &rho, &zeta, &rate)[0]);
        // a missing accelerometer sample ends the run
        assert!(!st.passes(&gate, 1.03, &[None; 4], &zeta, &rate)[0]);
        assert!(!st.passes(&gate, 1.04, &rho, &zeta, &rate)[0]);
    }

    #[test]
    fn rate_test_and_off_gate() {
        let zeta = [0.4; 4];
        let rho = [Some(0.1), Some(0.1), Some(0.1), Some(0.39)];
        let rate = [Some(0.5), Some(1.5), None, Some(0.9)];
        let gate = AccelGate {
            max_rate: 1.0,
            ..AccelGate::OFF
        };
        let mut st = AccelGateState::default();
        assert_eq!(
            st.passes(&gate, 0.0, &rho, &zeta, &rate),
            [true, false, false, true]
        );
        // everything off: the papers' test alone, missing gyro or not
        assert!(AccelGate::OFF.is_off() && AccelGate::default().is_off());
        let mut st = AccelGateState::default();
        let rho = [Some(0.1), Some(0.5), None, Some(0.39)];
        assert_eq!(
            st.passes(&AccelGate::OFF, 0.0, &rho, &zeta, &rate),
            reliable_flags(&rho, &zeta)
        );
        assert!(!gate.is_off());
    }
}
