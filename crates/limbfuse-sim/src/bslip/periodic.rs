//! Periodicity residuals of a step and the least-norm Newton corrector that
//! drives them to zero (the constraint `g(xi) <= eps` of paper 003 eq 2).
//!
//! A gait is periodic when the state at the end MS, relative to the leading
//! foot, is the mirror image of the initial MS state: lateral offset
//! `-lateral`, the same height and forward speed, zero lateral velocity (the
//! vertical velocity is zero at MS by the event). limbfuse adds the target
//! mean speed as an equality, so that each library gait has the speed it is
//! labelled with, and the step width of [`super::step_law`] (the paper found
//! step length and width constraints critical for convergence; without the
//! width the lateral motion is a neutral family and Newton wanders along it).
//! Energy conservation makes the forward-velocity residual redundant with the
//! height residual, so the system has rank 5: the Newton steps use the SVD
//! pseudo-inverse.

use limbfuse_models::bslip::GaitParameters;
use nalgebra::{DMatrix, DVector};

use super::step::{StepFailure, StepOutcome, StepSimulator};
use super::step_law;

/// Number of equality constraints (4 periodicity + mean speed + step width).
pub const N_CONSTRAINTS: usize = 7;

/// Scale of each gait parameter `[phi, theta, k, height, lateral, xdot0]`
/// used to normalise steps and finite differences.
pub const PARAM_SCALE: [f64; 6] = [0.1, 0.02, 2000.0, 0.01, 0.01, 0.1];

/// Periodicity (4), speed (1) and step-width (1) residuals of a simulated step.
pub fn residuals(
    gait: &GaitParameters,
    o: &StepOutcome,
    speed: f64,
    length: f64,
    width: f64,
) -> [f64; N_CONSTRAINTS] {
    let e = o.end_section();
    [
        e[0] + gait.lateral,
        e[1] - gait.height,
        e[2] - gait.forward_speed,
        e[3],
        o.mean_speed() - speed,
        o.step_width() - width,
        o.step_length() - length,
    ]
}

/// Largest absolute periodicity residual (m or m/s; the speed residual excluded).
pub fn periodicity_error(gait: &GaitParameters, o: &StepOutcome) -> f64 {
    residuals(gait, o, 0.0, 0.0, 0.0)[..4]
        .iter()
        .fold(0.0, |m, r| m.max(r.abs()))
}

/// Simulates `gait` and returns its residuals.
pub fn evaluate(
    sim: &StepSimulator,
    gait: &GaitParameters,
    speed: f64,
) -> Result<(StepOutcome, [f64; N_CONSTRAINTS]), StepFailure> {
    let o = sim.step(gait)?;
    let l0 = sim.body.rest_length;
    let r = residuals(
        gait,
        &o,
        speed,
        step_law::step_length(speed, l0),
        step_law::step_width(l0),
    );
    Ok((o, r))
}

/// Finite-difference Jacobian (central) of the residuals with respect to the
/// normalised free parameters.
fn jacobian(
    sim: &StepSimulator,
    gait: &GaitParameters,
    speed: f64,
    free: &[usize],
) -> Result<DMatrix<f64>, StepFailure> {
    let a = gait.to_array();
    let mut jac = DMatrix::<f64>::zeros(N_CONSTRAINTS, free.len());
    let h = 1e-5;
    for (col, &j) in free.iter().enumerate() {
        let mut ap = a;
        let mut am = a;
        ap[j] += h * PARAM_SCALE[j];
        am[j] -= h * PARAM_SCALE[j];
        let (_, rp) = evaluate(sim, &GaitParameters::from_array(ap), speed)?;
        let (_, rm) = evaluate(sim, &GaitParameters::from_array(am), speed)?;
        for i in 0..N_CONSTRAINTS {
            jac[(i, col)] = (rp[i] - rm[i]) / (2.0 * h);
        }
    }
    Ok(jac)
}

/// Least-norm solution `dx = J^T (J J^T)^-1 b` of the underdetermined `J dx = b`.
/// Computed with the SVD pseudo-inverse (singular values below 1e-9 of the
/// largest dropped), so redundant rows do not break it. `None` if the SVD fails.
pub fn least_norm(j: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let svd = j.clone().svd(true, true);
    let eps = svd.singular_values.max() * 1e-9;
    svd.solve(b, eps).ok()
}

/// Result of a Newton correction.
#[derive(Debug, Clone, Copy)]
pub struct Corrected {
    /// The corrected gait.
    pub gait: GaitParameters,
    /// Its step.
    pub outcome: StepOutcome,
    /// Largest absolute residual (periodicity and speed).
    pub residual: f64,
    /// Newton iterations used.
    pub iterations: usize,
}

/// All six gait parameters free.
pub const ALL_FREE: [usize; 6] = [0, 1, 2, 3, 4, 5];
/// Every parameter but the stiffness free (square 5 x 5 system).
pub const STIFFNESS_FIXED: [usize; 5] = [0, 1, 3, 4, 5];

/// Damped least-norm Newton iteration on the 5 equalities from `seed` over
/// the parameters listed in `free` (indices into `xi`), until the largest
/// residual is below `tol` (or `max_iter` iterations).
pub fn correct(
    sim: &StepSimulator,
    seed: &GaitParameters,
    speed: f64,
    free: &[usize],
    tol: f64,
    max_iter: usize,
) -> Result<Corrected, StepFailure> {
    let mut gait = *seed;
    let (mut outcome, mut r) = evaluate(sim, &gait, speed)?;
    let norm = |r: &[f64; N_CONSTRAINTS]| r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut it = 0;
    while norm(&r) > tol && it < max_iter {
        it += 1;
        let jac = jacobian(sim, &gait, speed, free)?;
        let b = -DVector::from_column_slice(&r);
        // Least-norm Newton step first, then Levenberg-Marquardt steps of
        // growing damping, each with backtracking on the residual norm.
        let jtj = jac.transpose() * &jac;
        let jtb = jac.transpose() * &b;
        let mut improved = false;
        for damping in [0.0, 1e-8, 1e-6, 1e-4, 1e-2, 1.0] {
            let dx = if damping == 0.0 {
                least_norm(&jac, &b)
            } else {
                let m = &jtj + DMatrix::identity(free.len(), free.len()) * (damping * jtj.trace());
                m.lu().solve(&jtb)
            };
            let Some(dx) = dx else { continue };
            // Trust region: at most one scale unit per parameter per step.
            let mut alpha = (1.0 / dx.amax().max(1e-300)).min(1.0);
            for _ in 0..8 {
                let mut a = gait.to_array();
                for (col, &j) in free.iter().enumerate() {
                    a[j] += alpha * dx[col] * PARAM_SCALE[j];
                }
                let trial = GaitParameters::from_array(a);
                if let Ok((o, rt)) = evaluate(sim, &trial, speed) {
                    if norm(&rt) < norm(&r) {
                        gait = trial;
                        outcome = o;
                        r = rt;
                        improved = true;
                        break;
                    }
                }
                alpha *= 0.5;
            }
            if improved {
                break;
            }
        }
        if !improved {
            break;
        }
    }
    Ok(Corrected {
        gait,
        outcome,
        residual: norm(&r),
        iterations: it,
    })
}
