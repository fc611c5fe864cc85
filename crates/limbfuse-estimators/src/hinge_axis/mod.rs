//! Hinge-joint axis identification from two gyros (paper 002 section 2.2.1,
//! after Seel et al. 2014): the one implementation of the axis cost, shared
//! by the self-aligning knee (`knee_selfalign`, online, per window) and the
//! walking-data sensor alignment of `limbfuse-signal` (`limbfuse align
//! --hinge`, batch, over a chain of hinges).
//!
//! For a hinge joint the angular rates of the two segments differ only by a
//! rotation about the common axis, so the part of each rate perpendicular to
//! the axis has the same norm in both sensor frames:
//! `e_j(k) = ||g_1(k) x j_1|| - ||g_2(k) x j_2||` (eq 2, [`hinge_residual`])
//! vanishes at the true axes `j_1`, `j_2` (each in its own sensor frame).
//! The sign of each axis is not identifiable from `e_j`; the callers choose
//! it (SPEC section 6, `docs/ALIGNMENT.md`). The gradient of each term with
//! respect to its axis is eq 11 ([`perpendicular_rate_gradient`]).
//!
//! | module | parametrisation of a unit axis | used by |
//! |---|---|---|
//! | [`spherical`] | `(phi, theta)` of eq 1, Jacobian eq 10 | the knee EKF (Algorithm 2) |
//! | [`chain_fit`] | two coordinates in the plane tangent to the current axis, re-normalised after each step | Levenberg-Marquardt over a chain of hinges (knee + ankle) |

pub mod chain_fit;
pub mod spherical;

use nalgebra::Vector3;

/// Rates whose component perpendicular to the axis is below this (rad/s)
/// give no usable gradient of `||g x j||` (eq 11 divides by it): the knee
/// EKF leaves such samples out of its window, the chain fit floors the norm
/// at this value.
pub const MIN_PERPENDICULAR_RATE: f64 = 1e-6;

/// The axis residual of eq 2, `e_j = ||g_1 x j_1|| - ||g_2 x j_2||`, for the
/// rates `g_1`, `g_2` of the two segments of a hinge and the axis `j_1`,
/// `j_2` in each sensor frame.
#[inline]
pub fn hinge_residual(
    g_1: &Vector3<f64>,
    j_1: &Vector3<f64>,
    g_2: &Vector3<f64>,
    j_2: &Vector3<f64>,
) -> f64 {
    g_1.cross(j_1).norm() - g_2.cross(j_2).norm()
}

/// Gradient of `||g x j||` with respect to `j` (eq 11):
/// `((g x j) x g)^T / ||g x j||`. `None` when `||g x j||` is below
/// [`MIN_PERPENDICULAR_RATE`].
pub fn perpendicular_rate_gradient(g: &Vector3<f64>, j: &Vector3<f64>) -> Option<Vector3<f64>> {
    let c = g.cross(j);
    let n = c.norm();
    (n >= MIN_PERPENDICULAR_RATE).then(|| c.cross(g) / n)
}
