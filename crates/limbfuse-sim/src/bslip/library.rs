//! Gait library construction (paper 003 sec II-C): a directly optimised
//! high-speed gait, then the predictor-corrector homotopy (eqs 3-6) down (or
//! up) to every requested speed, and the library's per-phase trajectories.

use limbfuse_models::bslip::{BslipParams, GaitParameters, GaitTemplate};

use super::periodic::{correct, STIFFNESS_FIXED};
use super::search::{
    objective, optimise_gait, predict_seed, FoundGait, SearchError, SearchSettings,
};
use super::step::{StepOutcome, StepSimulator};

/// Speed at which the homotopy starts with a direct optimisation (m/s): the
/// paper finds gaits above 0.8 m/s without special seeds.
pub const START_SPEED: f64 = 1.0;

/// Homotopy sub-step (m/s) between library speeds; halved on failure.
pub const HOMOTOPY_STEP: f64 = 0.05;

/// Seed of the direct optimisation at [`START_SPEED`] for a 1 m leg (scaled
/// with the leg length): Geyer et al. 2006's angle of attack (69 deg),
/// k = 20 kN/m, a 3 cm lateral offset.
pub fn start_seed(l0: f64) -> GaitParameters {
    GaitParameters {
        phi: 1.2,
        theta: 0.05,
        stiffness: 20_000.0 / l0,
        height: 0.97 * l0,
        lateral: 0.03 * l0,
        forward_speed: 0.9 * l0.sqrt(),
    }
}

/// The seed of [`start_seed`] for the 80 kg body at `gravity` 9.81 m/s^2,
/// made dynamically similar for `body`: the stiffness scaled so that
/// `k l0 / (m g)` is the 80 kg / 1 m / 9.81 seed's (dimensionless leg
/// stiffness; Geyer et al. 2006), the lengths and speed as [`start_seed`].
pub fn similar_start_seed(body: &BslipParams) -> GaitParameters {
    let reference = start_seed(body.rest_length);
    GaitParameters {
        stiffness: reference.stiffness * (body.mass / 80.0) * (body.gravity / 9.81),
        ..reference
    }
}

/// The gait the library search starts from: eqs 1-2 at [`START_SPEED`] from
/// [`start_seed`], or, when that finds no gait, from
/// [`similar_start_seed`]. (The first seed's 20 kN/m suits the 80 kg body
/// it was chosen for; for a body of 60 kg or less no step from it reached
/// mid-stance and `gait-library build --mass 60` failed. The first seed is
/// kept where it works, so every library it built is unchanged.)
pub fn start_gait(
    sim: &StepSimulator,
    settings: &SearchSettings,
) -> Result<FoundGait, SearchError> {
    let body = sim.body;
    optimise_gait(sim, &start_seed(body.rest_length), START_SPEED, settings).or_else(|first| {
        optimise_gait(sim, &similar_start_seed(&body), START_SPEED, settings).map_err(|_| first)
    })
}

/// One library gait: its target speed, parameters and step.
#[derive(Debug, Clone, Copy)]
pub struct LibraryGait {
    /// Mean forward speed (m/s).
    pub speed: f64,
    /// Gait parameters `xi`.
    pub gait: GaitParameters,
    /// The simulated step.
    pub step: StepOutcome,
    /// Largest periodicity residual (m, m/s).
    pub residual: f64,
    /// Eq 1's objective.
    pub objective: f64,
}

impl LibraryGait {
    /// The template the IMM and the trial simulator use.
    pub fn template(&self, body: &BslipParams) -> GaitTemplate {
        GaitTemplate {
            speed: self.speed,
            body: self.gait.model(body),
            gait: self.gait,
            step_length: self.step.step_length(),
            step_width: self.step.step_width(),
            step_time: self.step.t_end,
            t_touchdown: self.step.t_touchdown,
            t_lift_off: self.step.t_lift_off,
        }
    }

    /// Peak-to-peak vertical CoM excursion over a step (m).
    pub fn vertical_excursion(&self) -> f64 {
        self.step.height_range.1 - self.step.height_range.0
    }
}

/// Peak-to-peak lateral CoM excursion over a stride (m), from a sampled step
/// (left-trailing step; the next step is its mirror about the midline
/// `step_width / 2`).
pub fn lateral_excursion(template: &GaitTemplate, rows: &[Vec<[f64; 7]>; 3]) -> f64 {
    let mid = template.step_width / 2.0;
    rows.iter()
        .flatten()
        .map(|r| (r[3] - mid).abs())
        .fold(0.0, f64::max)
        * 2.0
}

impl From<FoundGait> for LibraryGait {
    fn from(f: FoundGait) -> Self {
        LibraryGait {
            speed: f.speed,
            gait: f.solution.gait,
            step: f.solution.outcome,
            residual: f.solution.residual,
            objective: f.objective,
        }
    }
}

/// Builds gaits at `speeds` (any order); `progress(done, total)` is called
/// after each library speed is reached.
pub fn build_library(
    body: &BslipParams,
    speeds: &[f64],
    settings: &SearchSettings,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<LibraryGait>, SearchError> {
    let sim = StepSimulator::new(*body).with_cancel(settings.cancel);
    let mut targets: Vec<f64> = speeds.to_vec();
    targets.sort_by(|a, b| b.total_cmp(a));
    let mut out: Vec<LibraryGait> = Vec::with_capacity(targets.len());
    let mut current = start_gait(&sim, settings)?;
    // Walk from the start speed to each target in turn (down, or up first).
    let mut order: Vec<f64> = targets
        .iter()
        .copied()
        .filter(|&v| v > START_SPEED)
        .collect();
    order.sort_by(f64::total_cmp);
    let mut rest: Vec<f64> = targets
        .iter()
        .copied()
        .filter(|&v| v <= START_SPEED)
        .collect();
    rest.sort_by(|a, b| b.total_cmp(a));
    let up_start = current;
    for (pass, list) in [order, rest].into_iter().enumerate() {
        if pass == 1 {
            current = up_start;
        }
        for target in list {
            let run = continue_towards(&sim, &current, target, settings);
            if let Some(cause) = run.failed {
                return Err(SearchError::Unreached {
                    target,
                    from: current.speed,
                    reached: run.last.speed,
                    cause: Box::new(cause),
                });
            }
            current = run.last;
            out.push(current.into());
            progress(out.len(), targets.len());
        }
    }
    out.sort_by(|a, b| a.speed.total_cmp(&b.speed));
    Ok(out)
}

/// Gaits continued from a library's end gait, as far as the search went.
#[derive(Debug, Clone)]
pub struct LibraryExtension {
    /// The gaits found, in the order of the speeds asked for.
    pub gaits: Vec<LibraryGait>,
    /// Where the continuation from the end gait failed, when the search
    /// then started again from [`START_SPEED`] (the failure).
    pub restarted: Option<SearchError>,
    /// Why the search stopped before the last speed (`None`: every speed
    /// was reached).
    pub stopped: Option<SearchError>,
}

/// Extends a library beyond its end gait `end` (mean speed `end_speed`,
/// periodic for `body`): the homotopy of [`build_library`] (predictor eq 6,
/// corrector eqs 1-2, [`HOMOTOPY_STEP`] sub-steps) from that gait to each of
/// `speeds` in turn (ordered outwards from `end_speed`), so the new gaits
/// continue the library's own branch. The end gait is first projected onto
/// `g = 0` at its own stiffness (a library built for another body and
/// rescaled by Froude similarity is periodic, but the step-length law is
/// not Froude-invariant). Where the homotopy finds no periodic gait at a
/// speed, the last gait it reached on the way is kept; if that does not get
/// to `reach` (the speed the extension must cover), the search starts once
/// more as [`build_library`] does (direct optimisation at [`START_SPEED`],
/// homotopy to the speed). It stops at the first speed not reached.
pub fn extend_library(
    body: &BslipParams,
    end: &GaitParameters,
    end_speed: f64,
    speeds: &[f64],
    reach: f64,
    settings: &SearchSettings,
) -> LibraryExtension {
    let sim = StepSimulator::new(*body).with_cancel(settings.cancel);
    let outwards = speeds.first().map_or(1.0, |v| (v - end_speed).signum());
    let covers = |v: f64| (v - reach) * outwards >= -1e-9;
    let mut out = LibraryExtension {
        gaits: Vec::with_capacity(speeds.len()),
        restarted: None,
        stopped: None,
    };
    let mut current = match project(&sim, end, end_speed, settings) {
        Ok(found) => Some(found),
        Err(e) => {
            out.restarted = Some(e);
            None
        }
    };
    let mut restart_used = false;
    let mut furthest = end_speed;
    for &target in speeds {
        let mut run = current.map(|from| continue_towards(&sim, &from, target, settings));
        // The first failure short of `reach`: once more from the start speed.
        let short = run
            .as_ref()
            .is_none_or(|r| r.failed.is_some() && r.partial().is_none_or(|p| !covers(p.speed)));
        if short && !restart_used {
            restart_used = true;
            if out.restarted.is_none() {
                out.restarted = run.as_ref().and_then(|r| r.failed.clone());
            }
            let start = start_gait(&sim, settings);
            match start {
                Ok(start) => run = Some(continue_towards(&sim, &start, target, settings)),
                Err(e) => {
                    out.stopped = Some(e);
                    break;
                }
            }
        }
        let Some(run) = run else {
            break;
        };
        match run.failed {
            None => {
                current = Some(run.last);
                furthest = run.last.speed;
                out.gaits.push(run.last.into());
            }
            Some(e) => {
                let beyond = (run.last.speed - furthest) * outwards > 1e-6;
                if run.moved && beyond {
                    out.gaits.push(run.last.into());
                }
                out.stopped = Some(e);
                break;
            }
        }
    }
    out
}

/// How far a homotopy ([`continue_towards`]) got.
#[derive(Debug, Clone)]
pub struct Continuation {
    /// The last gait reached: the target's when `failed` is `None`, else
    /// the last one before the failure (the start gait if none).
    pub last: FoundGait,
    /// Whether it got one sub-step or more beyond the start gait.
    pub moved: bool,
    /// Why it stopped short of the target.
    pub failed: Option<SearchError>,
}

impl Continuation {
    /// The gait reached beyond the start before a failure.
    pub fn partial(&self) -> Option<&FoundGait> {
        (self.failed.is_some() && self.moved).then_some(&self.last)
    }
}

/// `gait` (periodic or nearly) projected onto `g = 0` at `speed` with its
/// own stiffness.
fn project(
    sim: &StepSimulator,
    gait: &GaitParameters,
    speed: f64,
    settings: &SearchSettings,
) -> Result<FoundGait, SearchError> {
    let c = correct(
        sim,
        gait,
        speed,
        &STIFFNESS_FIXED,
        settings.periodic_tol,
        60,
    )
    .map_err(|failure| SearchError::Step { speed, failure })?;
    if c.residual > settings.periodic_tol {
        return Err(SearchError::NotPeriodic {
            speed,
            residual: c.residual,
            tol: settings.periodic_tol,
        });
    }
    Ok(FoundGait {
        speed,
        objective: objective(&c.outcome, &c.gait, speed, sim.body.rest_length, settings),
        solution: c,
    })
}

/// Homotopy from a found gait to `target` speed by predictor (eq 6) /
/// corrector (eqs 1-2) sub-steps.
pub fn continue_to(
    sim: &StepSimulator,
    from: &FoundGait,
    target: f64,
    settings: &SearchSettings,
) -> Result<FoundGait, SearchError> {
    let run = continue_towards(sim, from, target, settings);
    match run.failed {
        None => Ok(run.last),
        Some(e) => Err(e),
    }
}

/// [`continue_to`], saying how far it got when it failed.
pub fn continue_towards(
    sim: &StepSimulator,
    from: &FoundGait,
    target: f64,
    settings: &SearchSettings,
) -> Continuation {
    let mut current = *from;
    let mut moved = false;
    let mut step = HOMOTOPY_STEP;
    while (target - current.speed).abs() > 1e-9 {
        let dv = (target - current.speed).clamp(-step, step);
        let next_speed = if (target - current.speed).abs() <= step {
            target
        } else {
            current.speed + dv
        };
        let dv = next_speed - current.speed;
        // Predictor of eq 6; if its correction fails, the previous gait with
        // the forward speed shifted (natural continuation) as the seed.
        let predicted = predict_seed(sim, &current.solution.gait, dv);
        let attempt = match predicted {
            Ok(seed) => optimise_gait(sim, &seed, next_speed, settings),
            Err(failure) => Err(SearchError::Step {
                speed: next_speed,
                failure,
            }),
        };
        let attempt = attempt.or_else(|_| {
            let seed = GaitParameters {
                forward_speed: current.solution.gait.forward_speed + dv,
                ..current.solution.gait
            };
            optimise_gait(sim, &seed, next_speed, settings)
        });
        match attempt {
            Ok(found) => {
                current = found;
                moved = true;
                step = HOMOTOPY_STEP;
            }
            Err(e) => {
                step *= 0.5;
                if step < HOMOTOPY_STEP / 16.0 {
                    return Continuation {
                        last: current,
                        moved,
                        failed: Some(e),
                    };
                }
            }
        }
    }
    Continuation {
        last: current,
        moved,
        failed: None,
    }
}
