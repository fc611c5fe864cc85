//! Normative sagittal joint-angle curves and their dependence on walking speed.
//!
//! # Where the curves come from
//! The keypoints below are landmark values of the adult normative mean curves
//! at free walking speed (about 1.3 m/s), read (rounded to the degree) from
//! J. Perry & J. M. Burnfield, *Gait Analysis: Normal and Pathological
//! Function*, 2nd ed., SLACK 2010, ch. 4-6 (hip, knee, ankle figures), and
//! cross-checked against the mean curves of M. P. Kadaba, H. K. Ramakrishnan,
//! M. E. Wootten, "Measurement of lower extremity kinematics during level
//! walking", J. Orthop. Res. 8(3):383-392, 1990, and D. A. Winter,
//! *Biomechanics and Motor Control of Human Movement*, 4th ed., Wiley 2009.
//! They are landmarks, not a digitised data set: a periodic cubic Hermite
//! spline through them is sampled at 512 phases and fitted by least squares
//! with a truncated Fourier series ([`crate::fourier::Fourier::fit`]).
//!
//! Clinical signs: hip flexion +, knee flexion +, ankle dorsiflexion +; phase
//! 0 = heel strike of the simulated leg, toe-off at 60 %.

use core::f64::consts::TAU;

use crate::fourier::{grid, Fourier};

/// Samples per stride used by every set-up fit.
pub const GRID: usize = 512;
/// Harmonics kept for the joint curves.
pub const JOINT_ORDER: usize = 12;
/// Walking speed (m/s) the keypoint curves describe (free adult walking).
pub const REFERENCE_SPEED: f64 = 1.3;

/// Hip flexion keypoints (% stride, deg).
pub const HIP_KEYS: &[(f64, f64)] = &[
    (0.0, 25.0),
    (10.0, 22.0),
    (20.0, 14.0),
    (30.0, 4.0),
    (40.0, -6.0),
    (50.0, -14.0),
    (55.0, -13.0),
    (60.0, -7.0),
    (70.0, 8.0),
    (80.0, 21.0),
    (87.0, 27.0),
    (93.0, 26.5),
];
/// Knee flexion keypoints (% stride, deg).
pub const KNEE_KEYS: &[(f64, f64)] = &[
    (0.0, 5.0),
    (5.0, 12.0),
    (14.0, 19.0),
    (25.0, 13.0),
    (40.0, 5.0),
    (50.0, 10.0),
    (60.0, 38.0),
    (66.0, 54.0),
    (72.0, 62.0),
    (78.0, 57.0),
    (85.0, 38.0),
    (92.0, 15.0),
    (97.0, 3.0),
];
/// Ankle dorsiflexion keypoints (% stride, deg).
pub const ANKLE_KEYS: &[(f64, f64)] = &[
    (0.0, 0.0),
    (7.0, -6.0),
    (15.0, -1.0),
    (30.0, 5.0),
    (40.0, 8.0),
    (47.0, 10.0),
    (53.0, 6.0),
    (60.0, -12.0),
    (63.0, -17.0),
    (68.0, -12.0),
    (75.0, -5.0),
    (85.0, 0.0),
    (95.0, 1.0),
];

/// Periodic cubic Hermite interpolation (Catmull-Rom tangents on the
/// non-uniform knots) of `keys` at `x` percent of the stride.
pub fn periodic_hermite(keys: &[(f64, f64)], x: f64) -> f64 {
    let n = keys.len();
    if n == 0 {
        return 0.0;
    }
    let x = x.rem_euclid(100.0);
    let knot = |i: isize| -> (f64, f64) {
        let m = i.rem_euclid(n as isize) as usize;
        let wraps = (i - m as isize) / n as isize;
        (keys[m].0 + 100.0 * wraps as f64, keys[m].1)
    };
    // Interval [i, i+1] containing x (the last one wraps to the first knot + 100).
    let mut i = n as isize - 1;
    for (j, k) in keys.iter().enumerate() {
        if k.0 > x {
            i = j as isize - 1;
            break;
        }
    }
    let (x0, y0) = knot(i);
    let (x1, y1) = knot(i + 1);
    let (xm, ym) = knot(i - 1);
    let (xp, yp) = knot(i + 2);
    let m0 = (y1 - ym) / (x1 - xm);
    let m1 = (yp - y0) / (xp - x0);
    let h = x1 - x0;
    let t = (x - x0) / h;
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + t) * h * m0
        + (-2.0 * t3 + 3.0 * t2) * y1
        + (t3 - t2) * h * m1
}

/// Fourier fit (rad) of a keypoint table given in degrees.
pub fn fit_keys(keys: &[(f64, f64)], order: usize) -> Fourier {
    let y: Vec<f64> = grid(GRID)
        .map(|p| periodic_hermite(keys, p / TAU * 100.0).to_radians())
        .collect();
    Fourier::fit(&y, order)
}

/// The normative clinical curves at [`REFERENCE_SPEED`] (rad).
#[derive(Debug, Clone, Copy)]
pub struct BaseCurves {
    /// Hip flexion.
    pub hip: Fourier,
    /// Knee flexion.
    pub knee: Fourier,
    /// Ankle dorsiflexion.
    pub ankle: Fourier,
}

impl BaseCurves {
    /// Fits the three keypoint tables.
    pub fn fit() -> Self {
        BaseCurves {
            hip: fit_keys(HIP_KEYS, JOINT_ORDER),
            knee: fit_keys(KNEE_KEYS, JOINT_ORDER),
            ankle: fit_keys(ANKLE_KEYS, JOINT_ORDER),
        }
    }
}

/// Scales a curve's excursion about its mean: `c0 + gain (f - c0)`.
pub fn scale_about_mean(f: &Fourier, gain: f64) -> Fourier {
    let mut g = Fourier::combine(&[(gain, f)]);
    g.c0 = f.c0;
    g
}

/// Speed-dependent walking parameters.
///
/// * Cadence from a constant *walk ratio* (step length / cadence), which holds
///   over ordinary walking speeds: T. Sekiya, H. Nagasaki, "Reproducibility of
///   the walking patterns of normal young adults: test-retest reliability of
///   the walk ratio (step-length/step-rate)", Gait Posture 7(3):225-227, 1998
///   (about 0.0064 m/(steps/min) in young men). We take 0.0064 at a body height
///   of 1.70 m and scale it in proportion to height (an assumption). Then
///   `v = W c^2 / 60`, so `c = sqrt(60 v / W)` steps/min.
/// * Knee and ankle excursions grow with speed (A. L. Lelas et al.,
///   "Predicting peak kinematic and kinetic parameters from gait speed", Gait
///   Posture 17(2):106-112, 2003; C. A. Fukuchi et al., "Effects of walking
///   speed on gait biomechanics in healthy participants: a systematic review
///   and meta-analysis", Syst. Rev. 8:153, 2019). We model this as a linear
///   gain on the excursion about the mean, `1 + k (v - 1.3)`, with `k = 0.15`
///   (knee) and `0.20` (ankle) per m/s, chosen so that the landmark trends of
///   those papers are reproduced over 0.4-1.8 m/s (peak swing knee flexion
///   ~57 deg at 0.4 m/s to ~65 deg at 1.8 m/s); the hip gain is not set here
///   but solved so that the normative foot positions fit the stance
///   ([`crate::stance::Normative::reach_gain`]).
/// * Trunk (pelvis) pitch relative to standing: a forward lean of
///   `1 + v` deg plus a pelvic-tilt oscillation at twice the stride frequency
///   of amplitude `1 + 0.5 v` deg, most anterior at 45 % and 95 % of the
///   stride (Perry & Burnfield 2010, ch. 8: total pelvic tilt excursion ~4 deg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedLaw {
    /// Walking speed (m/s).
    pub speed: f64,
    /// Body height (m).
    pub height: f64,
}

impl SpeedLaw {
    /// Walk ratio (m per step/min) at this body height.
    pub fn walk_ratio(&self) -> f64 {
        0.0064 * self.height / 1.70
    }
    /// Cadence (steps/min).
    pub fn cadence(&self) -> f64 {
        (60.0 * self.speed / self.walk_ratio()).sqrt()
    }
    /// Stride frequency (Hz) = cadence / 120.
    pub fn stride_frequency(&self) -> f64 {
        self.cadence() / 120.0
    }
    /// Required stride length (m) = speed / stride frequency.
    pub fn stride_length(&self) -> f64 {
        self.speed / self.stride_frequency()
    }
    /// Knee excursion gain.
    pub fn knee_gain(&self) -> f64 {
        1.0 + 0.15 * (self.speed - REFERENCE_SPEED)
    }
    /// Ankle excursion gain.
    pub fn ankle_gain(&self) -> f64 {
        1.0 + 0.20 * (self.speed - REFERENCE_SPEED)
    }
    /// Relative forward-speed fluctuation of the hip joint centre (`eps`:
    /// speed `v (1 - eps cos 2 (phi - phi_slow))`), 0.10 at every speed.
    /// Inverted-pendulum exchange of kinetic and potential energy with ~60 %
    /// recovery (G. A. Cavagna, H. Thys, A. Zamboni, "The sources of external
    /// work in level walking and running", J. Physiol. 262:639-657, 1976)
    /// and the vertical excursion below give `eps = R g e / (2 v^2)` of
    /// 0.05-0.10 at 1.0-1.6 m/s; lower-back accelerometers show
    /// antero-posterior RMS accelerations of about 1-1.5 m/s^2 at preferred
    /// speed (H. B. Menz, S. R. Lord, R. C. Fitzpatrick, Gait Posture
    /// 18:35-46, 2003), which a step-frequency oscillation of +-10 % gives.
    pub fn speed_fluctuation(&self) -> f64 {
        0.10
    }
    /// Phase of the slowest forward speed (rad): 25 % of the stride, just
    /// before the highest point (and again half a stride later).
    pub fn slow_phase(&self) -> f64 {
        0.25 * TAU
    }
    /// Vertical excursion of the hip joint centre, peak to peak (m):
    /// `(0.008 + 0.020 v) H / 1.75`, 1.6 cm at 0.4 m/s, 2.8 cm at 1.0 m/s,
    /// 4.0 cm at 1.6 m/s. The centre of mass rises by roughly 2.5-5 cm over
    /// 0.7-1.6 m/s, increasing with speed (M. S. Orendurff et al., "The effect
    /// of walking speed on center of mass displacement", J. Rehabil. Res.
    /// Dev. 41:829-834, 2004); we take the lower side of that band because
    /// larger excursions drive the stance knee and ankle of the normative
    /// curves outside their normal ranges (`docs/SIMULATOR.md`).
    pub fn vertical_excursion(&self) -> f64 {
        (0.008 + 0.020 * self.speed) * self.height / 1.75
    }
    /// Sharpness of the vertical path's trough (0.2): the height is
    /// `h0 + e/2 (cos 2 psi - 0.2 cos 4 psi)`, so the vertical acceleration
    /// is larger and briefer in double support (upward, the two legs
    /// redirecting the body) than in single support (downward, the body
    /// vaulting over the stance leg), as in the vertical ground reaction
    /// force of walking (peaks of about 1.1-1.2 body weights around the
    /// double supports, a trough of about 0.7-0.8 in mid-stance: D. A.
    /// Winter, *Biomechanics and Motor Control of Human Movement*, 4th ed.,
    /// Wiley 2009; J. Perry & J. M. Burnfield 2010, ch. 19).
    pub fn vertical_sharpness(&self) -> f64 {
        0.2
    }
    /// Lateral excursion of the hip joint centre, peak to peak (m):
    /// `(0.085 - 0.028 v) H / 1.75`, 7.4 cm at 0.4 m/s, 5.7 cm at 1.0 m/s,
    /// 4.0 cm at 1.6 m/s. The centre of mass sways a few centimetres
    /// sideways, less at higher speed (about 7 cm at 0.7 m/s to about 4 cm
    /// at 1.6 m/s in Orendurff et al. 2004, as we read it; approximate). Used
    /// to scale the stance-leg ab/adduction, from which the lateral path is
    /// derived ([`crate::hip_path`]).
    pub fn lateral_excursion(&self) -> f64 {
        (0.085 - 0.028 * self.speed) * self.height / 1.75
    }
    /// Phase of the highest point (rad): 30 % of the stride, mid-stance, and
    /// again at 80 % (Orendurff et al. 2004: maxima near 30 % and 80 %).
    pub fn top_phase(&self) -> f64 {
        0.30 * TAU
    }
    /// Trunk pitch curve (rad, SPEC sign: positive = leaning back).
    pub fn trunk(&self) -> Fourier {
        let lean = (1.0 + self.speed).to_radians();
        let amp = (1.0 + 0.5 * self.speed).to_radians();
        let y: Vec<f64> = grid(GRID)
            .map(|p| -lean - amp * (2.0 * (p - 0.45 * TAU)).cos())
            .collect();
        Fourier::fit(&y, 4)
    }
}

/// Smooth window (0..1) over the flat-foot part of stance: rises over
/// 4-10 %, equals 1 over 10-30 % (Perry's mid-stance), falls over 30-36 %
/// of the stride (heel rise opens terminal stance).
pub fn foot_flat_window(phi: f64) -> f64 {
    let x = (phi / TAU * 100.0).rem_euclid(100.0);
    let ramp = |u: f64| 0.5 - 0.5 * (core::f64::consts::PI * u.clamp(0.0, 1.0)).cos();
    if x < 10.0 {
        ramp((x - 4.0) / 6.0)
    } else if x <= 30.0 {
        1.0
    } else {
        1.0 - ramp((x - 30.0) / 6.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_passes_through_keys_and_wraps() {
        for k in KNEE_KEYS {
            assert!((periodic_hermite(KNEE_KEYS, k.0) - k.1).abs() < 1e-12);
        }
        let a = periodic_hermite(KNEE_KEYS, 99.999);
        let b = periodic_hermite(KNEE_KEYS, 0.0);
        assert!((a - b).abs() < 1e-2);
    }

    #[test]
    fn cadence_law_is_plausible() {
        let l = SpeedLaw {
            speed: 1.3,
            height: 1.70,
        };
        assert!((l.cadence() - 110.3).abs() < 0.5, "{}", l.cadence());
        assert!((l.stride_length() - 1.41).abs() < 0.02);
    }
}
