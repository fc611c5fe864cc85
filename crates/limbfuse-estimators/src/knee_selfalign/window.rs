//! The identification of one window of Algorithm 3 (its samples in a
//! [`Ring`]): Algorithm 2 for the axes and for the positions, the choice of
//! the axis signs (SPEC section 6) and the correction of the positions along
//! the axes.

use nalgebra::{Vector3, Vector4};

use super::acc_scale::joint_accelerations;
use super::angle::{gyro_angle_rate, PlaneBasis};
use super::param_ekf::{
    estimate_parameters, residual_sum, ParamEkfError, ParamEkfResult, WindowResiduals,
};
use super::params::{AngleZero, KneeSelfAlignParams};
use super::position::Kinematics;
use super::position_fit::{fit_positions_screened, PositionResiduals};
use super::position_fusion::{fuse, FusedPositions};
use super::position_outliers::ResidualScreen;
pub use super::ring::{Ring, Slot};
use super::sign::{gyro_angle_moments, score_pairs, SignChoice};
use super::upright::{upright_axes, UprightAxes};
use crate::hinge_axis::spherical::{axes_of_state, axis_residual, axis_state};

struct AxisResiduals<'a>(&'a Ring);

impl WindowResiduals<4> for AxisResiduals<'_> {
    fn visit(&self, x: &Vector4<f64>, f: &mut dyn FnMut(f64, &Vector4<f64>)) {
        for i in 0..self.0.len() {
            let s = self.0.get(i);
            if s.gyr_ok {
                if let Some((e, h)) = axis_residual(&s.gyr[0], &s.gyr[1], x) {
                    f(e, &h);
                }
            }
        }
    }
}

fn normalise_axes(x: Vector4<f64>) -> Vector4<f64> {
    let (j_t, j_s) = axes_of_state(&x);
    axis_state(&j_t, &j_s)
}

/// Dominant rotation axis of one gyro over the window: the principal
/// eigenvector of `sum g g^T` (the starting point of the first window).
fn principal_axis(ring: &Ring, seg: usize) -> Vector3<f64> {
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    for i in 0..ring.len() {
        let s = ring.get(i);
        if s.gyr_ok {
            m.ger(1.0, &s.gyr[seg], &s.gyr[seg], 1.0);
        }
    }
    let eig = nalgebra::SymmetricEigen::new(m);
    let k = eig.eigenvalues.imax();
    eig.eigenvectors.column(k).into_owned()
}

/// Smallest eigenvalue of `H^T H / N` of the axis residuals with respect to
/// unit tangent displacements of the two axes (radians of turn), so that it
/// does not depend on where the axes lie in the spherical coordinates of
/// eq 1 (near `phi = +-pi/2` a step in `theta` moves the axis only by
/// `cos(phi)` times as much).
fn tangent_information(ring: &Ring, psi: &Vector4<f64>) -> f64 {
    let scale = Vector4::new(
        1.0,
        1.0 / libm::cos(psi[0]).abs().max(1e-9),
        1.0,
        1.0 / libm::cos(psi[2]).abs().max(1e-9),
    );
    let mut a = nalgebra::Matrix4::<f64>::zeros();
    let mut n = 0usize;
    AxisResiduals(ring).visit(psi, &mut |_, h| {
        let ht = h.component_mul(&scale);
        a.ger(1.0, &ht, &ht, 1.0);
        n += 1;
    });
    if n == 0 {
        return 0.0;
    }
    let eig = nalgebra::SymmetricEigen::new(a / n as f64);
    eig.eigenvalues.min()
}

/// A sample "moves" when either gyro reads at least this rate (rad/s):
/// 5 deg/s, ten times the 1-sigma turn-on bias of a consumer MEMS gyro
/// (0.5 deg/s, docs/SIMULATOR.md) and about 70 times its white noise per
/// sample at 100 Hz, yet far below the segment rates of any knee motion
/// that identifies the geometry (thigh and shank peak at 100-400 deg/s in
/// walking, Winter 2009; the knee rig's shank at 42 deg/s, 99th percentile).
pub const MOVING_RATE: f64 = 5.0 * core::f64::consts::PI / 180.0;

/// Complete samples of the window in which either segment turns at
/// [`MOVING_RATE`] or faster.
fn moving_samples(ring: &Ring) -> usize {
    (0..ring.len())
        .filter(|&i| {
            let s = ring.get(i);
            s.gyr_ok
                && s.acc_ok
                && (s.gyr[0].norm() >= MOVING_RATE || s.gyr[1].norm() >= MOVING_RATE)
        })
        .count()
}

fn mean_square_rate(ring: &Ring, seg: usize) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for i in 0..ring.len() {
        let x = ring.get(i);
        if x.gyr_ok {
            s += x.gyr[seg].norm_squared();
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        s / n as f64
    }
}

/// The identified joint geometry, both axes pointing to the same side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Joint axis in the thigh and shank sensor frames (unit).
    pub axis: [Vector3<f64>; 2],
    /// Sensor positions relative to the joint centre, in their frames (m).
    pub position: [Vector3<f64>; 2],
    /// Relative scale `r` of the accelerometers (thigh over shank) applied to
    /// the shank's specific force in eqs 3 and 7 ([`super::acc_scale`]; 1
    /// unless a window identified it).
    pub acc_scale: f64,
}

impl Geometry {
    /// The joint-centre accelerations of eq 7 of both sensors.
    pub fn joint_accelerations(&self, kin: &[Kinematics; 2]) -> [Vector3<f64>; 2] {
        joint_accelerations(kin, &self.position, self.acc_scale)
    }

    /// The joint-plane bases of eq 6 for the chosen zero.
    pub fn bases(&self, zero: AngleZero) -> Option<[PlaneBasis; 2]> {
        match zero {
            AngleZero::SensorPositions => Some([
                PlaneBasis::from_reference(&self.axis[0], &self.position[0])?,
                PlaneBasis::from_reference(&self.axis[1], &(-self.position[1]))?,
            ]),
            AngleZero::PaperC => Some([
                PlaneBasis::from_cross(&self.axis[0], &Vector3::x())?,
                PlaneBasis::from_cross(&self.axis[1], &Vector3::x())?,
            ]),
        }
    }
}

/// What identifying one window gave.
#[derive(Debug, Clone, Copy, PartialEq)]
// Returned by value once per window; boxing the large variant would
// allocate in `step` (the estimators allocate nothing per sample).
#[allow(clippy::large_enum_variant)]
pub enum WindowOutcome {
    /// New geometry.
    Identified {
        /// The geometry.
        geometry: Geometry,
        /// RMS of `e_j` after Algorithm 2 (rad/s).
        rms_axis: f64,
        /// RMS of `e_o` after Algorithm 2 (m/s^2).
        rms_position: f64,
        /// Smallest eigenvalue of `H_j^T H_j / N` ((rad/s)^2).
        information: f64,
        /// Circular spread (0..1) of `alpha_acc - integral(alpha_gyro')`
        /// over the window with the chosen geometry: near 0 when the
        /// accelerometer angle follows the gyro angle up to a constant.
        spread: f64,
        /// Confidence (-1..1) in the relative axis sign,
        /// [`super::sign::confidence`].
        sign_confidence: f64,
        /// Whether the accelerometer angle follows the gyro angle in this
        /// window ([`SignChoice::acc_trusted`]; `None`: the knee hardly
        /// moved, no evidence): only then may it decide signs, the zero and
        /// correct the angle (Algorithm 1).
        acc_trusted: Option<bool>,
        /// [`UprightAxes::code`]: 0 eq 2's axes, 1 the upright prior's, 2
        /// the previous window's.
        axis_source: f64,
        /// The positions fused over the windows so far
        /// ([`super::position_fusion`]).
        fused: FusedPositions,
        /// The residual level of the window's position fit, whose
        /// outliers it left out ([`super::position_outliers`], ours).
        screen: Option<ResidualScreen>,
        /// How many samples that screen left out.
        outliers: usize,
    },
    /// Too few complete, unsaturated samples.
    TooFewSamples {
        /// Usable samples.
        usable: usize,
    },
    /// The window does not determine the axes (e.g. no motion).
    Unobservable {
        /// Smallest eigenvalue of `H_j^T H_j / N` ((rad/s)^2).
        information: f64,
    },
    /// Algorithm 2 failed numerically.
    Failed,
}

/// Identifies the joint geometry from the window in `ring` (Algorithm 3,
/// one window): Algorithm 2 with `order` iterations for the axes and for
/// the positions, then the sign rules and the correction along the axes.
///
/// Signs (SPEC section 6; [`super::sign`]): `e_j` and `e_o` do not depend
/// on the axis signs. In the first window the shank axis is flipped if that
/// makes the accelerometer angle follow the integrated gyro angle better
/// (both axes must point to the same side for eqs 4 and 5 to describe the
/// same rotation); then both are flipped if the knee would flex to negative
/// angles (SPEC section 1; `flexion_side`). In later windows each axis
/// keeps the side of its `previous` axis, unless the relative sign is not
/// `committed` and the window's trusted accelerometer angle prefers the
/// other pair with at least `sign_commit` confidence. With
/// `acc_miscalibrated` (a rest read a norm off g, [`super::rest_gravity`])
/// no accelerometer angle is trusted.
///
/// The positions (and the relative accelerometer scale) are ours beyond the
/// paper: [`fit_positions_screened`] (the window's gross outliers left out,
/// [`super::position_outliers`]), then fused with `fused`, the positions of
/// the earlier windows ([`super::position_fusion`]).
pub fn identify(
    ring: &mut Ring,
    previous: Option<&Geometry>,
    fused: Option<&FusedPositions>,
    committed: bool,
    acc_miscalibrated: bool,
    p: &KneeSelfAlignParams,
) -> WindowOutcome {
    // A sensor that read a norm off g at rest ([`super::rest_gravity`]):
    // no window's agreement is evidence, it is chance.
    let trusted = |c: &SignChoice| {
        if acc_miscalibrated {
            Some(false)
        } else {
            c.acc_trusted(p.acc_max_spread, p.acc_min_motion)
        }
    };
    let usable = (0..ring.len())
        .filter(|&i| ring.get(i).gyr_ok && ring.get(i).acc_ok)
        .count();
    if usable == 0 || (usable as f64) < p.min_valid_fraction * p.window as f64 {
        return WindowOutcome::TooFewSamples { usable };
    }
    let axes = AxisResiduals(ring);
    let pca = axis_state(&principal_axis(ring, 0), &principal_axis(ring, 1));
    let start = match previous {
        Some(g) => {
            let prev = axis_state(&g.axis[0], &g.axis[1]);
            if residual_sum(&axes, &prev).0 <= residual_sum(&axes, &pca).0 {
                prev
            } else {
                pca
            }
        }
        None => pca,
    };
    let j = match estimate_parameters(&axes, start, p.order, &p.axis_noise, normalise_axes) {
        Ok(r) => r,
        // Every rate is parallel to its starting axis: planar rotation about
        // exactly those axes, which then solve eq 2 exactly. Their
        // information is the smaller mean squared rate (the scale of H).
        Err(ParamEkfError::NoResiduals) => ParamEkfResult {
            x: start,
            p: nalgebra::Matrix4::zeros(),
            n_used: 0,
            rms_before: 0.0,
            rms_after: 0.0,
            min_information: mean_square_rate(ring, 0).min(mean_square_rate(ring, 1)),
        },
        Err(ParamEkfError::Numerical) => return WindowOutcome::Failed,
    };
    let information = if j.n_used == 0 {
        j.min_information
    } else {
        tangent_information(ring, &j.x)
    };
    if information.is_nan() || information < p.min_information {
        return WindowOutcome::Unobservable { information };
    }
    // Ours (issue 15 item 3): a window that is mostly still holds the
    // previous geometry. Its few moving samples can pass the axis
    // information test, but `Gamma` of the still ones is zero, so the
    // positions (and with them the zero of the accelerometer angle) come
    // from the moving rest alone, and from sensor biases: on a hinge that
    // stopped 1 s into a window they moved the zero by 90 deg.
    if (moving_samples(ring) as f64) < p.min_valid_fraction * p.window as f64 {
        return WindowOutcome::Unobservable { information };
    }
    let (o, screen, outliers) = match fit_positions_screened(ring, previous, p) {
        Ok(o) => o,
        Err(ParamEkfError::NoResiduals) => return WindowOutcome::TooFewSamples { usable: 0 },
        Err(ParamEkfError::Numerical) => return WindowOutcome::Failed,
    };
    let ring: &Ring = ring;
    let flexion_side = |c: SignChoice| flexion_side(ring, c, trusted(&c) == Some(true), p.zero);
    let (j_t, j_s) = axes_of_state(&j.x);
    // Ours (issue 15): the upright-leg prior where eq 2's hinge does not fit.
    let source = p.axis_prior.map_or(UprightAxes::Hinge, |u| {
        upright_axes(ring, [j_t, j_s], j.rms_after, &u)
    });
    let [j_t, j_s] = match source {
        UprightAxes::Prior(jj) | UprightAxes::PriorOnBlocks(jj) => jj,
        UprightAxes::NoFlexion => previous.map_or([j_t, j_s], |g| g.axis),
        UprightAxes::Hinge => [j_t, j_s],
    };
    let (r, rms_position) = (o.r, o.rms);
    let fusion = fuse(fused, &PositionResiduals(ring, r), &o, [j_t, j_s]);
    let o_t: Vector3<f64> = fusion.position.fixed_rows::<3>(0).into_owned();
    let o_s: Vector3<f64> = fusion.position.fixed_rows::<3>(3).into_owned();
    let identified = |c: SignChoice| WindowOutcome::Identified {
        geometry: c.geometry,
        rms_axis: j.rms_after,
        rms_position,
        information,
        spread: c.spread,
        sign_confidence: c.confidence,
        acc_trusted: trusted(&c),
        axis_source: source.code(),
        fused: fusion,
        screen,
        outliers,
    };
    let o = [o_t, o_s];
    let score = |j, keep| score_pairs(ring, j, o, r, p.zero, p.sign_floor, keep);
    let Some(prev) = previous else {
        // First window: the pair the trusted accelerometer angle prefers
        // with at least `sign_commit` confidence, else the pair whose gyro
        // angle varies less ([`gyro_angle_moments`]); then the flexion side.
        let (Some(same), Some(flipped)) = (
            score([j_t, j_s], Some(true)),
            score([j_t, j_s], Some(false)),
        ) else {
            return WindowOutcome::TooFewSamples { usable: 0 };
        };
        let decisive = |c: &SignChoice| trusted(c) == Some(true) && c.confidence >= p.sign_commit;
        let pick = if decisive(&same) {
            same
        } else if decisive(&flipped) {
            flipped
        } else {
            let var = |c: &SignChoice| gyro_angle_moments(ring, &c.geometry).0;
            if var(&same) <= var(&flipped) {
                same
            } else {
                flipped
            }
        };
        return identified(flexion_side(pick));
    };
    // Continuity: a sensor does not turn its axis to the other side between
    // two windows (a re-mounting by less than 90 deg keeps j_new . j_old >
    // 0), so each axis keeps the side it had ...
    let side = |j: Vector3<f64>, old: &Vector3<f64>| if j.dot(old) < 0.0 { -j } else { j };
    let jj = [side(j_t, &prev.axis[0]), side(j_s, &prev.axis[1])];
    let Some(keep) = score(jj, Some(true)) else {
        return WindowOutcome::TooFewSamples { usable: 0 };
    };
    // ... unless the relative sign is not committed yet and this window's
    // trusted accelerometer angle says the other pair is right with at least
    // the commit confidence (issue 15: switching on weak evidence restarted
    // eq 4's integral every window on the gaittoolbox trial and the knee rig).
    if !committed && keep.confidence <= -p.sign_commit {
        if let Some(other) = score(jj, Some(false)) {
            if trusted(&other) == Some(true) {
                return identified(flexion_side(other));
            }
        }
    }
    // While the pair is not committed, the flexion side of the previous
    // windows may come from the gyro angle's skewness alone (an untrusted
    // accelerometer angle); a window whose accelerometer angle is trusted
    // re-reads it from the accelerometer level (issue 15 item 3: on free 3D
    // hinge motion the first window was untrusted, its skewness picked the
    // extension side, and the trusted second window committed the pair with
    // the knee flexing to negative angles).
    if !committed && trusted(&keep) == Some(true) {
        return identified(flexion_side(keep));
    }
    identified(keep)
}

/// Both axes flipped if the knee would flex to negative angles (SPEC
/// section 1): from the circular mean of the accelerometer angle when it is
/// trusted and the zero is the sensor positions, else from the skewness of
/// the gyro angle ([`gyro_angle_moments`]).
fn flexion_side(ring: &Ring, mut c: SignChoice, trusted: bool, zero: AngleZero) -> SignChoice {
    let flip = if trusted {
        match zero {
            AngleZero::SensorPositions => c.level < 0.0,
            AngleZero::PaperC => false,
        }
    } else {
        gyro_angle_moments(ring, &c.geometry).1 < 0.0
    };
    if flip {
        c.geometry.axis = [-c.geometry.axis[0], -c.geometry.axis[1]];
    }
    c
}

/// The gyro angles (eq 4, trapezoidal) of the samples in `recent` with the
/// geometry `g`, ending at 0 at the newest, placed as the estimator's last
/// five gyro angles (newest last), and the newest sample's rate (ours,
/// issue 15 item 3). When a window gives new axis sides, eq 4 restarts; the
/// accelerometer angle of the sample two steps back (the rate derivative's
/// latency) is compared with the gyro angle of that same sample, which the
/// restart had not recorded: the first two outputs were the bare gyro angle
/// from zero, up to 58 deg off on the shared 1.6 m/s walk at 40 Hz.
pub fn recent_gyro_angles(recent: &Ring, g: &Geometry) -> ([Option<f64>; 5], Option<f64>) {
    let mut out = [None; 5];
    let n = recent.len().min(5);
    if n == 0 {
        return (out, None);
    }
    let rate = |s: &Slot| {
        s.gyr_ok
            .then(|| gyro_angle_rate(&s.gyr[0], &s.gyr[1], &g.axis[0], &g.axis[1]))
    };
    let newest = recent.get(recent.len() - 1);
    let last_rate = rate(newest);
    let (mut angle, mut later) = (0.0, (newest.t, last_rate));
    out[4] = last_rate.map(|_| 0.0);
    for k in 1..n {
        let s = recent.get(recent.len() - 1 - k);
        let (Some(r), (t1, Some(r1))) = (rate(s), later) else {
            break;
        };
        angle -= 0.5 * (r + r1) * (t1 - s.t);
        out[4 - k] = Some(angle);
        later = (s.t, Some(r));
    }
    (out, last_rate)
}
