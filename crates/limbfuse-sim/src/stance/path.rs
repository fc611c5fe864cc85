//! The prescribed pelvis (hip joint centre) path of one stride.

use core::f64::consts::TAU;

use crate::gait_curves::SpeedLaw;

/// The prescribed path of the right hip joint centre, per stride, at a fixed
/// amplitude (see `docs/SIMULATOR.md` for the sources of the defaults):
/// `x = L phi / 2 pi - L eps / (4 pi) sin 2 (phi - phi_slow)` (forward speed
/// `v (1 - eps cos 2 (phi - phi_slow))`), `y = h0 + e/2 (cos 2 psi - b cos 4
/// psi)`, `psi = phi - phi_top`: highest at `phi_top` (mid-stance), lowest a
/// quarter stride later (double support), peak to peak `e` for `b <= 1/4`;
/// `b > 0` flattens the top and sharpens the trough.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathShape {
    /// Stride length `L` (m).
    pub stride_length: f64,
    /// Relative forward-speed fluctuation `eps`.
    pub fluctuation: f64,
    /// Phase of the slowest forward speed (rad; again half a stride later).
    pub slow_phase: f64,
    /// Vertical excursion `e`, peak to peak (m).
    pub excursion: f64,
    /// Phase of the highest point (rad; again half a stride later).
    pub top_phase: f64,
    /// Sharpness `b` of the trough (0: a pure sinusoid; at most 1/4).
    pub sharpness: f64,
}

impl PathShape {
    /// The path of `law` at amplitude 1.
    pub fn new(law: &SpeedLaw) -> Self {
        PathShape {
            stride_length: law.stride_length(),
            fluctuation: law.speed_fluctuation(),
            slow_phase: law.slow_phase(),
            excursion: law.vertical_excursion(),
            top_phase: law.top_phase(),
            sharpness: law.vertical_sharpness(),
        }
    }

    /// The path with stride length and vertical excursion scaled by `amp`.
    pub fn scaled(&self, amp: f64) -> Self {
        PathShape {
            stride_length: self.stride_length * amp,
            excursion: self.excursion * amp,
            ..*self
        }
    }

    /// Forward position (m) at phase `phi` (rad).
    pub fn x(&self, phi: f64) -> f64 {
        let l = self.stride_length;
        l * phi / TAU - l * self.fluctuation / (2.0 * TAU) * (2.0 * (phi - self.slow_phase)).sin()
    }

    /// Height above the mean `h0` (m) at phase `phi` (rad).
    pub fn y_offset(&self, phi: f64) -> f64 {
        let psi = phi - self.top_phase;
        0.5 * self.excursion * ((2.0 * psi).cos() - self.sharpness * (4.0 * psi).cos())
    }
}
