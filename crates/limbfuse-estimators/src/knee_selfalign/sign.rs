//! The pair of axis signs (SPEC section 6; a limbfuse decision, paper 002
//! does not choose signs): the evidence for it, its confidence, and the
//! choice.
//!
//! `e_j` (eq 2) and `e_o` (eq 3) do not depend on the signs of `j_T`, `j_S`.
//! Eqs 4 and 5-7 describe the same rotation only when both axes point to
//! the same side of the joint. With the shank axis flipped, eq 4 integrates
//! `theta_T + theta_S` (the sum of the segment rates) and eq 5, whose shank
//! basis is then mirrored, measures `theta_T + theta_S - 2 phi_a`, where
//! `phi_a` is the direction of the joint-centre acceleration in the joint
//! plane (gravity plus the knee's own acceleration). So with the right pair
//! `alpha_acc - integral(alpha_gyro')` is constant up to noise, with the
//! wrong pair it varies as `2 phi_a`: in walking the knee's horizontal and
//! vertical accelerations turn `phi_a` by tens of degrees each stride. The
//! evidence is the circular spread of that difference under both pairs.
//! With no joint acceleration besides gravity (`phi_a` constant, e.g. a
//! fixed thigh) the two pairs are indistinguishable and the confidence is 0.

use nalgebra::Vector3;

use super::angle::{accel_angle, gyro_angle_rate, wrap};
use super::params::AngleZero;
use super::position::correct_along_axes;
use super::window::{Geometry, Ring};

/// Circular mean of angles fed one by one (the sums [`SegmentedCircular`]
/// pools).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Circular {
    c: f64,
    s: f64,
    n: usize,
}

impl Circular {
    pub(crate) fn add(&mut self, a: f64) {
        let (s, c) = libm::sincos(a);
        self.s += s;
        self.c += c;
        self.n += 1;
    }
    pub(crate) fn mean(&self) -> f64 {
        libm::atan2(self.s, self.c)
    }
}

/// Readings of the two gyroscopes further apart than this (s), and more
/// than [`GAP_SPLIT_PERIODS`] sampling periods, split a window's gyro angle
/// (ours, robust input): the rotation across the gap is not known, so
/// `alpha_acc - integral(gyro rate)` takes a new constant after it. A
/// tenth of a second is about a tenth of a stride; a trapezoid across a
/// longer gap misses tens of degrees of knee motion.
pub const GAP_SPLIT_S: f64 = 0.1;

/// See [`GAP_SPLIT_S`].
pub const GAP_SPLIT_PERIODS: f64 = 2.5;

/// Circular statistics of angles taken in segments, each about its own
/// mean: the spread is `1 - sum |R_segment| / n` (also used by
/// `knee_gyro_axis`, whose gyro angle also takes a new constant after a
/// gap).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct SegmentedCircular {
    closed_resultant: f64,
    closed_n: usize,
    last_closed_mean: f64,
    current: Circular,
}

impl SegmentedCircular {
    pub(crate) fn add(&mut self, a: f64) {
        self.current.add(a);
    }

    /// Starts a new segment (nothing to close when the current one is empty).
    pub(crate) fn split(&mut self) {
        if self.current.n == 0 {
            return;
        }
        self.closed_resultant += libm::hypot(self.current.s, self.current.c);
        self.closed_n += self.current.n;
        self.last_closed_mean = self.current.mean();
        self.current = Circular::default();
    }

    pub(crate) fn count(&self) -> usize {
        self.closed_n + self.current.n
    }

    /// Circular mean of the latest segment with angles.
    pub(crate) fn mean(&self) -> f64 {
        if self.current.n > 0 {
            self.current.mean()
        } else {
            self.last_closed_mean
        }
    }

    /// 1 - mean resultant length about each segment's mean; 1 when empty.
    pub(crate) fn spread(&self) -> f64 {
        let n = self.count();
        if n == 0 {
            return 1.0;
        }
        let r = self.closed_resultant + libm::hypot(self.current.s, self.current.c);
        1.0 - r / n as f64
    }
}

/// What the accelerometer angle and the gyro angle show over one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Agreement {
    /// Circular spread of `alpha_acc - integral(gyro rate)`: small when both
    /// angles agree up to a constant.
    pub spread: f64,
    /// Circular mean of `alpha_acc` (rad).
    pub level: f64,
    /// Circular spread of `integral(gyro rate)` itself: how much the knee
    /// moved (the agreement is evidence only when this is not small).
    pub motion: f64,
}

/// [`Agreement`] over the window; `None` when the accelerometer angle is
/// never defined.
pub fn agreement(ring: &Ring, g: &Geometry, zero: AngleZero) -> Option<Agreement> {
    let bases = g.bases(zero)?;
    let mut diff = SegmentedCircular::default();
    let mut level = Circular::default();
    let mut motion = SegmentedCircular::default();
    let mut integral = 0.0;
    let mut last: Option<(f64, f64)> = None;
    let mut period = f64::INFINITY;
    for i in 0..ring.len() {
        let s = ring.get(i);
        if !s.gyr_ok {
            continue;
        }
        let rate = gyro_angle_rate(&s.gyr[0], &s.gyr[1], &g.axis[0], &g.axis[1]);
        if let Some((t0, r0)) = last {
            let dt = s.t - t0;
            if dt > GAP_SPLIT_S && dt > GAP_SPLIT_PERIODS * period {
                // A gap: the angle after it has its own constant.
                diff.split();
                motion.split();
            } else {
                integral += 0.5 * (rate + r0) * dt;
                period = period.min(dt);
            }
        }
        last = Some((s.t, rate));
        if let Some([kt, ks]) = ring.kinematics(i) {
            let [at, as_] = g.joint_accelerations(&[kt, ks]);
            if let Some(a) = accel_angle(&at, &as_, &bases[0], &bases[1]) {
                diff.add(wrap(a - integral));
                level.add(a);
                motion.add(integral);
            }
        }
    }
    (diff.count() > 0).then(|| Agreement {
        spread: diff.spread(),
        level: level.mean(),
        motion: motion.spread(),
    })
}

/// Second and third central moments (rad^2, rad^3) of the gyro angle
/// `integral(g_T . j_T - g_S . j_S)` over the window: the evidence for the
/// axis signs when the accelerometer angle cannot give it (a limbfuse rule,
/// issue 15; priors from the anatomy of the leg, not measurements of the
/// joint):
/// - *relative sign*: with both axes on the same side eq 4 integrates the
///   knee angle `theta_T - theta_S`, with one flipped the sum `theta_T +
///   theta_S`. Thigh and shank swing mostly together (in walking the thigh
///   covers ~45 deg, the shank ~75 deg, the knee ~60 deg: Winter,
///   *Biomechanics and Motor Control of Human Movement*, 4th ed., 2009,
///   appendix A), so their difference varies less than their sum: the pair
///   with the smaller variance is taken.
/// - *flexion side*: the knee stops at full extension and flexes away from
///   it (to ~60 deg in the swing of walking, ~20 deg in stance: Perry, *Gait
///   Analysis*, 1992, ch. 5), so the angle's excursions from its mean are
///   longer towards flexion and the third moment is positive with the axes
///   on the flexion-positive side. A motion that spends most of its time
///   flexed gives the other sign.
pub fn gyro_angle_moments(ring: &Ring, g: &Geometry) -> (f64, f64) {
    let integral = |f: &mut dyn FnMut(f64)| {
        let (mut acc, mut last): (f64, Option<(f64, f64)>) = (0.0, None);
        for i in 0..ring.len() {
            let s = ring.get(i);
            if !s.gyr_ok {
                continue;
            }
            let rate = gyro_angle_rate(&s.gyr[0], &s.gyr[1], &g.axis[0], &g.axis[1]);
            if let Some((t0, r0)) = last {
                acc += 0.5 * (rate + r0) * (s.t - t0);
            }
            last = Some((s.t, rate));
            f(acc);
        }
    };
    let (mut sum, mut n) = (0.0, 0usize);
    integral(&mut |a| {
        sum += a;
        n += 1;
    });
    if n == 0 {
        return (0.0, 0.0);
    }
    let mean = sum / n as f64;
    let (mut m2, mut m3) = (0.0, 0.0);
    integral(&mut |a| {
        let d = a - mean;
        m2 += d * d;
        m3 += d * d * d;
    });
    (m2 / n as f64, m3 / n as f64)
}

/// The flexion side's evidence pooled over the windows (ours): while the
/// relative sign is not committed and the accelerometer angle is not
/// trusted, the first window's gyro-angle skewness ([`gyro_angle_moments`])
/// had chosen the side for the whole trial. A window covers a few seconds,
/// which on a slow or irregular motion is part of a cycle: starting the
/// shared knee-rig trials 5.5 or 6.1 s later flipped the knee angle on all
/// five (offset-free 2.4 -> 20 deg, r -0.99; a generalisation audit). The
/// skewness (`m3 / m2^1.5`) of every such window is summed in the current
/// axes' sense, and both axes flip when the sum turns negative.
///
/// A window whose trusted accelerometer angle read the side from its level
/// (`identify`'s `flexion_side` with the sensor-position zero) *anchors* it
/// (ours, 2026-12-05): the skewness stops counting, and the side changes
/// only when another trusted window reads it again (or the open relative
/// sign changes the pair: its sum and anchor start again). The skewness is a prior
/// about legs, the level a measurement of the angle. Before, such a window
/// only turned the sum to the new side: after untrusted windows had pooled
/// `S` for the other side it left `-S`, and the next untrusted window, whose
/// skewness is added, flipped the knee back unless it alone outweighed `S`
/// (test `a_trusted_flexion_side_is_not_undone_by_earlier_skewness`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct FlexionEvidence {
    skew_sum: f64,
    anchored: bool,
}

impl FlexionEvidence {
    /// Pools the window in `ring` after `identify` gave it `geometry` and
    /// `acc_trusted` (`old`: the previous windows' axes, `None` for the
    /// first; `committed`: the relative sign before this window): the
    /// skewness counts in every window where it may choose the flexion
    /// side, an untrusted accelerometer angle, and in the first window also
    /// one without the motion to judge it (`flexion_side` reads the skewness
    /// unless the angle is trusted; else the first window's choice is not in
    /// the sum and the next window alone overturns it). A trusted window of
    /// an open pair with the sensor-position `zero` anchors the side.
    pub(crate) fn pool_window(
        &mut self,
        ring: &Ring,
        old: Option<&Geometry>,
        geometry: &mut Geometry,
        committed: bool,
        acc_trusted: Option<bool>,
        zero: AngleZero,
    ) {
        let anchors = !committed && acc_trusted == Some(true) && zero == AngleZero::SensorPositions;
        // Another pair of sides (an open relative sign that changed) has
        // its own evidence: the old pair's anchor goes, as its sum does.
        if old.is_some_and(|old| {
            let same = [0, 1].map(|k| old.axis[k].dot(&geometry.axis[k]) >= 0.0);
            same[0] != same[1]
        }) {
            self.anchored = false;
        }
        let counts = !committed
            && !anchors
            && !self.anchored
            && (acc_trusted == Some(false) || (old.is_none() && acc_trusted.is_none()));
        self.pool(ring, old, geometry, counts);
        self.anchored |= anchors;
    }

    /// Adds the window's skewness for `geometry` when it `counts`, after
    /// bringing the sum to `geometry`'s sense (`old`: the previous
    /// windows' axes), and flips both axes when the sum says the knee
    /// would flex to negative angles.
    fn pool(&mut self, ring: &Ring, old: Option<&Geometry>, geometry: &mut Geometry, counts: bool) {
        if let Some(old) = old {
            let same = [0, 1].map(|k| old.axis[k].dot(&geometry.axis[k]) >= 0.0);
            match same {
                [true, true] => {}
                [false, false] => self.skew_sum = -self.skew_sum,
                _ => self.skew_sum = 0.0, // another pair: its own evidence
            }
        }
        if !counts {
            return;
        }
        let (m2, m3) = gyro_angle_moments(ring, geometry);
        if m2 > 0.0 {
            self.skew_sum += m3 / (m2 * libm::sqrt(m2));
        }
        if self.skew_sum < 0.0 {
            geometry.axis = [-geometry.axis[0], -geometry.axis[1]];
            self.skew_sum = -self.skew_sum;
        }
    }
}

/// Confidence (-1..1) that the pair with spread `chosen` is right rather
/// than the pair with spread `other`: `1 - (chosen + floor) / (other +
/// floor)` when `chosen <= other`, the negative of the reverse otherwise.
/// `floor` is the spread noise alone can give (the accelerometer angle's
/// noise): evidence below it counts for nothing. 0 when the two pairs fit
/// equally well, near 1 when the chosen one fits much better.
pub fn confidence(chosen: f64, other: f64, floor: f64) -> f64 {
    let (a, b) = (chosen + floor, other + floor);
    if !(a.is_finite() && b.is_finite()) || a <= 0.0 || b <= 0.0 {
        return 0.0;
    }
    if a <= b {
        1.0 - a / b
    } else {
        -(1.0 - b / a)
    }
}

/// The geometry with both axes as given and the positions corrected along
/// them (paper 002 after eq 3).
fn geometry(j: [Vector3<f64>; 2], o: [Vector3<f64>; 2], acc_scale: f64) -> Geometry {
    let (ct, cs) = correct_along_axes(&o[0], &o[1], &j[0], &j[1]);
    Geometry {
        axis: j,
        position: [ct, cs],
        acc_scale,
    }
}

/// A pair of signs and what it rests on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SignChoice {
    /// The geometry with the chosen signs.
    pub geometry: Geometry,
    /// Spread of `alpha_acc - integral(alpha_gyro')` with it.
    pub spread: f64,
    /// [`confidence`] of the relative sign against the other pair.
    pub confidence: f64,
    /// Circular mean of the accelerometer angle with it (rad).
    pub level: f64,
    /// Circular spread of the gyro angle over the window (how much the knee
    /// moved).
    pub motion: f64,
}

impl SignChoice {
    /// Whether the window says the accelerometer angle is usable:
    /// `Some(true)` when it follows the gyro angle (`spread <= max_spread`)
    /// while the knee moved (`motion >= min_motion`),
    /// `Some(false)` when it does not follow it, `None` when the knee hardly
    /// moved (a still window agrees trivially: no evidence).
    pub fn acc_trusted(&self, max_spread: f64, min_motion: f64) -> Option<bool> {
        if self.spread > max_spread {
            Some(false)
        } else if self.motion >= min_motion {
            Some(true)
        } else {
            None
        }
    }
}

/// Scores both relative pairs `(j_T, j_S)` and `(j_T, -j_S)`; returns the
/// one `keep` says (`acc_scale`: [`Geometry::acc_scale`]) (`Some(true)`: the pair as given, `Some(false)`: shank
/// flipped) or, with `None`, the better-scoring one. `None` when the
/// accelerometer angle is never defined in the window.
pub fn score_pairs(
    ring: &Ring,
    j: [Vector3<f64>; 2],
    o: [Vector3<f64>; 2],
    acc_scale: f64,
    zero: AngleZero,
    floor: f64,
    keep: Option<bool>,
) -> Option<SignChoice> {
    let same = geometry(j, o, acc_scale);
    let flipped = geometry([j[0], -j[1]], o, acc_scale);
    let a = agreement(ring, &same, zero);
    let b = agreement(ring, &flipped, zero);
    let pick_same = match keep {
        Some(k) => k,
        None => match (a, b) {
            (Some(a), Some(b)) => a.spread <= b.spread,
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => return None,
        },
    };
    let (g, mine, theirs) = if pick_same {
        (same, a, b)
    } else {
        (flipped, b, a)
    };
    let m = mine.unwrap_or(Agreement {
        spread: 1.0,
        level: 0.0,
        motion: 0.0,
    });
    let spread = m.spread;
    let c = match theirs {
        Some(t) => confidence(spread, t.spread, floor),
        None => 0.0,
    };
    Some(SignChoice {
        geometry: g,
        spread,
        confidence: c,
        level: m.level,
        motion: m.motion,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn confidence_hand_values() {
        assert!((confidence(0.01, 0.04, 0.0) - 0.75).abs() < 1e-15);
        assert!((confidence(0.04, 0.01, 0.0) + 0.75).abs() < 1e-15);
        // Both spreads at the noise floor: no evidence.
        assert!(confidence(1e-6, 3e-6, 1e-3).abs() < 0.01);
        assert_eq!(confidence(0.0, 0.0, 0.0), 0.0);
        assert_eq!(confidence(f64::NAN, 0.1, 0.0), 0.0);
    }
}
