//! Gait optimisation (paper 003 eqs 1-2) and the linearisation-based
//! predictor-corrector seed search (eqs 3-6).
//!
//! **Eqs 1-2.** `min_xi ||J(xi)||^2 + c (k_max - k) / k_max  s.t.  g(xi) = 0`,
//! `J = [vertical excursion, L - L_des(v), W - W_des, x_CoM - x_foot at MS]`
//! (m), `g` = the periodicity, mean-speed and step-width residuals
//! ([`super::periodic`]; rank 5). That leaves one degree of freedom of the
//! six parameters; limbfuse takes the stiffness `k`: for each `k` a
//! least-norm Newton solve puts the other five on `g = 0` to
//! [`SearchSettings::periodic_tol`], and argmin's Brent minimiser
//! (`BrentOpt`) minimises eq 1's objective over `k` in a bracket around the
//! seed, capped at `k_max` (`g(xi) <= eps` of eq 2 with `eps = periodic_tol`).
//! The step-width deviation of `J` is then zero by construction.
//!
//! **Eqs 3-6.** From a converged gait, the Poincaré map `P(x, u)`
//! (`x = [lateral, height, vx, v_lateral]` at MS relative to the stance foot,
//! `u = [phi, theta, k]`) is linearised by central finite differences,
//! `A = dP/dx`, `B = dP/du`; the perturbation with `dvx` fixed to the desired
//! speed change that satisfies `(A - S) dx + B du = 0`, `S = diag(-1, 1, 1, 1)`
//! (as printed; see docs/GAIT_IMM.md), is the least-norm solution of those 4
//! equations in the other 6 unknowns (in normalised units). The predicted
//! seed is then corrected by eqs 1-2 at the new speed.

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::brent::BrentOpt;
use limbfuse_models::bslip::{GaitParameters, Side};
use nalgebra::{DMatrix, DVector, Matrix4, Vector4};

use super::periodic::{correct, least_norm, Corrected, ALL_FREE, PARAM_SCALE, STIFFNESS_FIXED};
use super::step::{initial_state, StepFailure, StepOutcome, StepSimulator};
use super::step_law;

/// Settings of the gait search.
#[derive(Debug, Clone, Copy)]
pub struct SearchSettings {
    /// Upper stiffness limit `k_max` (N/m).
    pub k_max: f64,
    /// Weight `c` of the stiffness term `c (k_max - k) / k_max` (m^2).
    pub stiffness_weight: f64,
    /// Periodicity / speed tolerance `eps` of eq 2 (m, m/s).
    pub periodic_tol: f64,
    /// Relative half-width of the stiffness bracket searched around the seed.
    pub k_bracket: f64,
    /// Brent iteration limit.
    pub max_iterations: u64,
    /// A cancellation hook, polled before every simulated step of the
    /// search (a few hundred microseconds each): once it returns true,
    /// every step fails with [`StepFailure::Cancelled`] and the search
    /// ends within milliseconds (Python's Ctrl-C; `None`: never).
    pub cancel: Option<fn() -> bool>,
}

impl Default for SearchSettings {
    /// `k_max` = 60 kN/m for the 80 kg / 1 m body (dimensionless
    /// `k l0 / (m g)` = 76: the 0.4 m/s gait with human step length and
    /// width needs ~50 kN/m); `c` = 1e-2 m^2 (the stiffness term then
    /// outweighs a few cm of vertical excursion, which drives `k` up as the
    /// paper intends); `eps` = 1e-8 (m, m/s).
    fn default() -> Self {
        SearchSettings {
            k_max: 60_000.0,
            stiffness_weight: 1e-2,
            periodic_tol: 1e-8,
            k_bracket: 0.3,
            max_iterations: 30,
            cancel: None,
        }
    }
}

/// The cost vector `J(xi)` of eq 1 (m).
pub fn cost_vector(o: &StepOutcome, speed: f64, l0: f64) -> [f64; 4] {
    [
        o.height_range.1 - o.height_range.0,
        o.step_length() - step_law::step_length(speed, l0),
        o.step_width() - step_law::step_width(l0),
        o.x_end[0] - o.leading_foot[0],
    ]
}

/// Eq 1's objective for a simulated step.
pub fn objective(
    o: &StepOutcome,
    gait: &GaitParameters,
    speed: f64,
    l0: f64,
    s: &SearchSettings,
) -> f64 {
    let j = cost_vector(o, speed, l0);
    j.iter().map(|v| v * v).sum::<f64>() + s.stiffness_weight * (s.k_max - gait.stiffness) / s.k_max
}

/// A periodic gait found by the search.
#[derive(Debug, Clone, Copy)]
pub struct FoundGait {
    /// Target mean speed (m/s).
    pub speed: f64,
    /// Its parameters and step.
    pub solution: Corrected,
    /// Eq 1's objective at the solution.
    pub objective: f64,
}

/// Why the search failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SearchError {
    /// The Newton correction did not reach the tolerance.
    #[error("no periodic gait at {speed} m/s: residual {residual:e} > {tol:e}")]
    NotPeriodic {
        /// Target speed.
        speed: f64,
        /// Residual reached.
        residual: f64,
        /// Tolerance.
        tol: f64,
    },
    /// A step failed.
    #[error("gait at {speed} m/s: {failure}")]
    Step {
        /// Target speed.
        speed: f64,
        /// The failure.
        failure: StepFailure,
    },
    /// The optimiser failed.
    #[error("optimiser: {0}")]
    Optimiser(String),
    /// A library speed the continuation did not reach.
    #[error(
        "no gait at {target} m/s on the branch continued from {from} m/s: it ends at {reached} m/s ({cause})"
    )]
    Unreached {
        /// The library speed asked for (m/s).
        target: f64,
        /// Where the continuation started (m/s).
        from: f64,
        /// The last speed with a periodic gait on the way (m/s).
        reached: f64,
        /// Why the next sub-step failed.
        cause: Box<SearchError>,
    },
}

struct StiffnessProblem<'a> {
    sim: &'a StepSimulator,
    seed: GaitParameters,
    speed: f64,
    settings: SearchSettings,
}

impl StiffnessProblem<'_> {
    fn solve(&self, k: f64) -> Result<Corrected, StepFailure> {
        let seed = GaitParameters {
            stiffness: k,
            ..self.seed
        };
        correct(
            self.sim,
            &seed,
            self.speed,
            &STIFFNESS_FIXED,
            self.settings.periodic_tol,
            40,
        )
    }
}

impl CostFunction for StiffnessProblem<'_> {
    type Param = f64;
    type Output = f64;

    fn cost(&self, k: &f64) -> Result<f64, ArgminError> {
        Ok(match self.solve(*k) {
            Ok(c) if c.residual <= self.settings.periodic_tol => objective(
                &c.outcome,
                &c.gait,
                self.speed,
                self.sim.body.rest_length,
                &self.settings,
            ),
            _ => INFEASIBLE_COST,
        })
    }
}

/// Cost of a stiffness at which no periodic gait was found.
const INFEASIBLE_COST: f64 = 1e3;

/// Solves eqs 1-2 at `speed` from `seed`: a least-norm Newton projection
/// onto `g(xi) = 0`, then Brent's method (argmin) over the stiffness, each
/// cost evaluation projecting the other five parameters onto `g = 0`.
pub fn optimise_gait(
    sim: &StepSimulator,
    seed: &GaitParameters,
    speed: f64,
    settings: &SearchSettings,
) -> Result<FoundGait, SearchError> {
    // Project at the seed's stiffness (the family has a free direction, so
    // this keeps k where the seed put it); all six free if that fails.
    let feasible = match correct(
        sim,
        seed,
        speed,
        &STIFFNESS_FIXED,
        settings.periodic_tol,
        60,
    ) {
        Ok(c) if c.residual <= settings.periodic_tol => c,
        _ => correct(sim, seed, speed, &ALL_FREE, settings.periodic_tol, 60)
            .map_err(|failure| SearchError::Step { speed, failure })?,
    };
    if feasible.residual > settings.periodic_tol {
        return Err(SearchError::NotPeriodic {
            speed,
            residual: feasible.residual,
            tol: settings.periodic_tol,
        });
    }
    let seed = mirror_to_positive(&feasible.gait);
    let problem = StiffnessProblem {
        sim,
        seed,
        speed,
        settings: *settings,
    };
    let hi = (seed.stiffness * (1.0 + settings.k_bracket)).min(settings.k_max);
    let lo = (seed.stiffness * (1.0 - settings.k_bracket)).min(0.9 * hi);
    let solver = BrentOpt::new(lo, hi).set_tolerance(1e-5, 1.0);
    let res = Executor::new(problem, solver)
        .configure(|s| s.max_iters(settings.max_iterations))
        .run()
        .map_err(|e| SearchError::Optimiser(e.to_string()))?;
    let best_k = res.state().best_param.unwrap_or(seed.stiffness);
    let problem = StiffnessProblem {
        sim,
        seed,
        speed,
        settings: *settings,
    };
    // Keep the feasible start if the optimiser found nothing better.
    let c = match problem.solve(best_k) {
        Ok(c)
            if c.residual <= settings.periodic_tol
                && objective(&c.outcome, &c.gait, speed, sim.body.rest_length, settings)
                    <= objective(
                        &feasible.outcome,
                        &feasible.gait,
                        speed,
                        sim.body.rest_length,
                        settings,
                    ) =>
        {
            c
        }
        _ => feasible,
    };
    let gait = mirror_to_positive(&c.gait);
    let c = Corrected { gait, ..c };
    Ok(FoundGait {
        speed,
        objective: objective(&c.outcome, &c.gait, speed, sim.body.rest_length, settings),
        solution: c,
    })
}

/// The mirror image of a gait with a negative lateral offset (the same gait
/// started on the other foot): `lateral` and `theta` change sign.
pub fn mirror_to_positive(g: &GaitParameters) -> GaitParameters {
    if g.lateral < 0.0 {
        GaitParameters {
            lateral: -g.lateral,
            theta: -g.theta,
            ..*g
        }
    } else {
        *g
    }
}

/// Symmetry matrix of eq 6 as printed: `S = diag(-1, 1, 1, 1)`.
pub fn symmetry() -> Matrix4<f64> {
    Matrix4::from_diagonal(&Vector4::new(-1.0, 1.0, 1.0, 1.0))
}

/// Scales of the Poincaré state `[lateral, height, vx, v_lateral]`.
const X_SCALE: [f64; 4] = [0.01, 0.01, 0.1, 0.01];
/// Indices of `u = [phi, theta, k]` in `xi`.
const U_INDEX: [usize; 3] = [0, 1, 2];

/// Poincaré map (eq 3): MS state `x` (relative to the stance foot, side
/// `Left`) and controls `u` -> next MS state relative to the leading foot.
pub fn poincare_map(
    sim: &StepSimulator,
    gait: &GaitParameters,
    x: &Vector4<f64>,
    u: &[f64; 3],
) -> Result<Vector4<f64>, StepFailure> {
    let mut g = *gait;
    g.phi = u[0];
    g.theta = u[1];
    g.stiffness = u[2];
    let mut x0 = initial_state(&g, Side::Left);
    x0[2] = x[0];
    x0[1] = x[1];
    x0[3] = x[2];
    x0[5] = x[3];
    let o = sim.step_from(&g, &x0, Side::Left)?;
    Ok(Vector4::from(o.end_section()))
}

/// Finite-difference Jacobians `A = dP/dx` (4x4) and `B = dP/du` (4x3) of
/// eq 5 at a gait's MS state, in normalised units.
pub fn linearise(
    sim: &StepSimulator,
    gait: &GaitParameters,
) -> Result<(DMatrix<f64>, DMatrix<f64>), StepFailure> {
    let x = Vector4::new(gait.lateral, gait.height, gait.forward_speed, 0.0);
    let u = [gait.phi, gait.theta, gait.stiffness];
    let h = 1e-5;
    let mut a = DMatrix::zeros(4, 4);
    let mut b = DMatrix::zeros(4, 3);
    for j in 0..4 {
        let mut xp = x;
        let mut xm = x;
        xp[j] += h * X_SCALE[j];
        xm[j] -= h * X_SCALE[j];
        let d = (poincare_map(sim, gait, &xp, &u)? - poincare_map(sim, gait, &xm, &u)?) / (2.0 * h);
        for i in 0..4 {
            a[(i, j)] = d[i] / X_SCALE[i];
        }
    }
    for j in 0..3 {
        let mut up = u;
        let mut um = u;
        up[j] += h * PARAM_SCALE[U_INDEX[j]];
        um[j] -= h * PARAM_SCALE[U_INDEX[j]];
        let d = (poincare_map(sim, gait, &x, &up)? - poincare_map(sim, gait, &x, &um)?) / (2.0 * h);
        for i in 0..4 {
            b[(i, j)] = d[i] / X_SCALE[i];
        }
    }
    Ok((a, b))
}

/// Predictor of eq 6: the seed for a gait `dv` faster (negative: slower).
pub fn predict_seed(
    sim: &StepSimulator,
    gait: &GaitParameters,
    dv: f64,
) -> Result<GaitParameters, StepFailure> {
    let (a, b) = linearise(sim, gait)?;
    let s = DMatrix::from_fn(4, 4, |i, j| symmetry()[(i, j)]);
    let a_s = a - s;
    // Unknowns (normalised): [d lateral, d height, d v_lateral, d phi, d theta, d k];
    // d vx = dv is fixed and moves to the right-hand side.
    let mut m = DMatrix::zeros(4, 6);
    for i in 0..4 {
        m[(i, 0)] = a_s[(i, 0)];
        m[(i, 1)] = a_s[(i, 1)];
        m[(i, 2)] = a_s[(i, 3)];
        for j in 0..3 {
            m[(i, 3 + j)] = b[(i, j)];
        }
    }
    let dvx = dv / X_SCALE[2];
    let rhs = DVector::from_fn(4, |i, _| -a_s[(i, 2)] * dvx);
    let d = least_norm(&m, &rhs).ok_or(StepFailure::InvalidParameters)?;
    // d v_lateral has no slot in xi (the step starts with zero lateral velocity).
    Ok(GaitParameters {
        lateral: gait.lateral + d[0] * X_SCALE[0],
        height: gait.height + d[1] * X_SCALE[1],
        forward_speed: gait.forward_speed + dv,
        phi: gait.phi + d[3] * PARAM_SCALE[0],
        theta: gait.theta + d[4] * PARAM_SCALE[1],
        stiffness: gait.stiffness + d[5] * PARAM_SCALE[2],
    })
}
