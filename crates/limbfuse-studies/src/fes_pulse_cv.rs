//! Issue 16 item 3 study support: the leave-one-pulse-out cross-validation
//! lives in `limbfuse_workflows::fes_pulse_cv` (re-exported here); this
//! module adds the parameter perturbation of the study (c), shared
//! by the examples `fes_model_study` and `fes_tune_cv`.

pub use limbfuse_workflows::fes_pulse_cv::*;

use limbfuse_models::KneeFesParams;

/// A uniform number in [-1, 1) from a 64-bit LCG (Knuth's MMIX constants).
fn uniform(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// `p` with every model parameter (`J, m, l_c, phi0, theta_eq, T_a, d1-d6,
/// c0-c3`) scaled by `1 + e u`, `u` uniform in [-1, 1), seeded.
pub fn perturbed(p: KneeFesParams, e: f64, seed: u64) -> KneeFesParams {
    let mut st = seed.wrapping_mul(0x9E3779B97F4A7C15) ^ 0xD1B54A32D192ED03;
    let mut f = |x: f64| x * (1.0 + e * uniform(&mut st));
    let mut q = p;
    q.inertia = f(p.inertia);
    q.mass = f(p.mass);
    q.l_c = f(p.l_c);
    q.phi0 = f(p.phi0);
    q.theta_eq = f(p.theta_eq);
    q.t_a = f(p.t_a);
    for k in 0..6 {
        q.d[k] = f(p.d[k]);
    }
    for k in 0..4 {
        q.c[k] = f(p.c[k]);
    }
    q
}
