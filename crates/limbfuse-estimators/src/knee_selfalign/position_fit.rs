//! The sensor positions of one window (paper 002 section 2.2.2, Algorithm 2
//! on eq 3), with, ours (issue 15 item 3), the relative accelerometer scale
//! of [`super::acc_scale`] when the window identifies it, and the
//! information of the positions for [`super::position_fusion`].

use nalgebra::{Matrix6, SMatrix, Vector3, Vector6};

use super::acc_scale::{
    positions, scaled, significant_scale, LiftedScaledStart, ScaledPositionResiduals, ScaledState,
};
use super::param_ekf::{
    estimate_parameters, residual_sum, ParamEkfError, ParamEkfNoise, ParamEkfResult,
    WindowResiduals,
};
use super::params::KneeSelfAlignParams;
use super::position::position_residual;
use super::position_outliers::{mark_outliers, mark_rate_spikes, ResidualScreen};
use super::window::{Geometry, Ring};

/// Eq 3's residuals over the window, the shank's specific force scaled by
/// the relative scale `r` ([`super::acc_scale`]; 1: the paper's eq 3).
pub struct PositionResiduals<'a>(pub &'a Ring, pub f64);

impl WindowResiduals<6> for PositionResiduals<'_> {
    fn visit(&self, x: &Vector6<f64>, f: &mut dyn FnMut(f64, &Vector6<f64>)) {
        for i in 0..self.0.len() {
            if let Some([t, s]) = self.0.kinematics(i) {
                let s = if self.1 == 1.0 { s } else { scaled(&s, self.1) };
                if let Some((e, h)) = position_residual(&t, &s, x) {
                    f(e, &h);
                }
            }
        }
    }
}

/// The positions of one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionFit {
    /// Relative accelerometer scale (1: not identified, the paper's eq 3).
    pub r: f64,
    /// `[o_T, o_S]` (m).
    pub o: Vector6<f64>,
    /// RMS eq-3 residual at the solution (m/s^2).
    pub rms: f64,
    /// Information about the positions, `Cov^-1` (1/m^2); `None` when the
    /// covariance is singular.
    pub information: Option<Matrix6<f64>>,
}

/// The covariance of Algorithm 2's solution from its last posterior `P`:
/// with `R = r I` far below `(H^T H)^-1`'s scale (the paper's `r = 1e-3`
/// against `H^T H` of hundreds of samples), `P ~ r (H^T H)^-1`, so the
/// least-squares covariance `s^2 (H^T H)^-1` (`s^2 = sum e^2 / (N - n)`) is
/// `P s^2 / r`. No extra pass over the window.
fn covariance<const N: usize>(
    fit: &ParamEkfResult<N>,
    noise: &ParamEkfNoise,
) -> Option<SMatrix<f64, N, N>> {
    if fit.n_used <= N {
        return None;
    }
    let s2 = fit.rms_after * fit.rms_after * fit.n_used as f64 / (fit.n_used - N) as f64;
    let c = fit.p * (s2 / noise.r);
    c.iter().all(|v| v.is_finite()).then_some(c)
}

fn information_of(cov: &Matrix6<f64>) -> Option<Matrix6<f64>> {
    let info = cov.cholesky()?.inverse();
    info.iter().all(|v| v.is_finite()).then_some(info)
}

fn stack(o: &[Vector3<f64>; 2]) -> Vector6<f64> {
    Vector6::new(o[0].x, o[0].y, o[0].z, o[1].x, o[1].y, o[1].z)
}

/// The window's positions: first (ours) Algorithm 2 on `[o_T, o_S, r]` from
/// the lower-cost of the lifted scaled start and the previous window's
/// geometry; its solution when `r` is identified ([`significant_scale`]).
/// Otherwise the paper's Algorithm 2 on `[o_T, o_S]`, from the lower-cost
/// (`sum e_o^2`) of the previous window's positions (`o = 0` in the first
/// window) and the lifted least-squares solution with `r = 1`
/// ([`LiftedScaledStart::solve_unit_scale`]).
pub fn fit_positions(
    ring: &Ring,
    previous: Option<&Geometry>,
    p: &KneeSelfAlignParams,
) -> Result<PositionFit, ParamEkfError> {
    let mut lifted = LiftedScaledStart::default();
    for i in 0..ring.len() {
        if let Some([t, s]) = ring.kinematics(i) {
            lifted.add(&t, &s);
        }
    }
    let noise = &p.position_noise;
    let w7 = ScaledPositionResiduals(ring);
    let prev7 = previous.map(|g| {
        let mut x = ScaledState::zeros();
        x.fixed_rows_mut::<6>(0).copy_from(&stack(&g.position));
        x[6] = g.acc_scale;
        x
    });
    let start = match (lifted.solve(), prev7) {
        (Some(l), Some(q)) if residual_sum(&w7, &q).0 <= residual_sum(&w7, &l).0 => Some(q),
        (Some(l), _) => Some(l),
        (None, q) => q,
    };
    if let Some(fit) = start.and_then(|s| estimate_parameters(&w7, s, p.order, noise, |x| x).ok()) {
        if let Some(cov) = covariance(&fit, noise) {
            if let Some(r) = significant_scale(fit.x[6], cov[(6, 6)]) {
                let c6: Matrix6<f64> = cov.fixed_view::<6, 6>(0, 0).into_owned();
                return Ok(PositionFit {
                    r,
                    o: positions(&fit.x),
                    rms: fit.rms_after,
                    information: information_of(&c6),
                });
            }
        }
    }
    let w6 = PositionResiduals(ring, 1.0);
    let old = previous.map_or(Vector6::zeros(), |g| stack(&g.position));
    let o_start = match lifted.solve_unit_scale() {
        Some(l) if residual_sum(&w6, &l).0 < residual_sum(&w6, &old).0 => l,
        _ => old,
    };
    let fit = estimate_parameters(&w6, o_start, p.order, noise, |x| x)?;
    Ok(PositionFit {
        r: 1.0,
        o: fit.x,
        rms: fit.rms_after,
        information: covariance(&fit, noise).and_then(|c| information_of(&c)),
    })
}

/// Most fits of [`fit_positions_screened`] after its robust start.
pub const SCREEN_ROUNDS: usize = 4;

/// Ours (2026-12-07): [`fit_positions`] with the window's eq-3 outliers left
/// out ([`super::position_outliers`]). The window is screened first at the
/// previous window's geometry (when there is one: a spike's residual stands
/// out there, where a fit it has already pulled spreads it over the
/// window) and, when the fit-free pre-screen finds a reading that departs
/// from its neighbours ([`mark_rate_spikes`]), at the fit without those
/// readings; then fitted, screened at the solution, fitted again, until a
/// screen leaves no new sample out (at most [`SCREEN_ROUNDS`] fits after
/// that start). The samples
/// left out stay out of [`Ring::kinematics`] for the rest of the window's
/// identification. The screen returned is the last one (`None` when no
/// screen could be taken), with the number of samples left out.
pub fn fit_positions_screened(
    ring: &mut Ring,
    previous: Option<&Geometry>,
    p: &KneeSelfAlignParams,
) -> Result<(PositionFit, Option<ResidualScreen>, usize), ParamEkfError> {
    ring.clear_excluded();
    // A robust start: the fit without the readings the fit-free pre-screen
    // finds (a window of spikes with no trusted geometry before it, the
    // first one, pulled every fit far enough that no residual stood out).
    let robust = if mark_rate_spikes(ring) > 0 {
        let fit = fit_positions(ring, previous, p).ok();
        ring.clear_excluded();
        fit
    } else {
        None
    };
    let mut screen = previous.and_then(|g| mark_outliers(ring, &stack(&g.position), g.acc_scale));
    if let Some(s) = robust.and_then(|f| mark_outliers(ring, &f.o, f.r)) {
        screen = Some(s);
    }
    let mut fit = fit_positions(ring, previous, p)?;
    for _ in 1..SCREEN_ROUNDS {
        let Some((s, marked)) = mark_outliers(ring, &fit.o, fit.r) else {
            break;
        };
        screen = Some((s, marked));
        if marked == 0 {
            break;
        }
        fit = fit_positions(ring, previous, p)?;
    }
    let left_out = (0..ring.len()).filter(|&i| ring.is_excluded(i)).count();
    Ok((fit, screen.map(|(s, _)| s), left_out))
}
