//! RK4 sub-stepping of eqs 4.14 and 4.16 between two samples (SPEC section
//! 6), sub-steps sized by a bound on the stiffness of the error dynamics.
//!
//! Each sub-step takes four evaluations of the model and the Riccati
//! right-hand side; the stiffness bound comes with the first and last of
//! them (`derivative_and_stiffness`), so checking the step size costs no
//! further model evaluation.

use limbfuse_models::SdcModel;
use nalgebra::{SMatrix, SVector};

use super::continuous::{derivative_and_stiffness, ContinuousTuning, FilterState, Linearisation};

/// RK4 is stable on the real axis for `h |lambda| < 2.78`; sub-steps keep
/// `h |lambda|` (bounded by [`stiffness_bound`], which includes the Riccati
/// equation's factor 2) at most 2.
const RK4_STABLE_STEP: f64 = 2.0;
/// Largest relative change of a diagonal entry of `P` a sub-step is sized
/// for, `h |P_dot_ii| / P_ii <= 0.5`: the stiffness bound keeps RK4 stable,
/// not accurate (at `h lambda = 2` it damps a mode by 0.33 per step where
/// the exact factor is 0.135), and while `P` settles from `p0` the fast
/// modes carry the transient (issue 16: 1.3e-3 deg of knee error from the
/// first interval alone, decaying over seconds through the bias states).
/// A sub-step that starts with `P` moving faster than twice this is cut.
const RICCATI_RELATIVE_STEP: f64 = 0.5;
/// Upper bound on sub-steps per interval (bounds the work per sample).
const MAX_SUBSTEPS: usize = 400;
/// Halvings of a trial sub-step while its end is stiffer than the step
/// allows (see [`propagate`]).
const MAX_STEP_CUTS: usize = 24;
/// Power-iteration steps of [`stiffness_bound`].
const BOUND_ITERATIONS: usize = 4;
/// Floor of the power-iteration vector relative to its largest entry (keeps
/// it positive, as the Collatz-Wielandt bound needs).
const BOUND_FLOOR: f64 = 1e-6;

/// An upper bound on the fastest rate of the Riccati equation whose error
/// dynamics are `m = A - K C`: twice an upper bound on the spectral radius
/// `rho(m)` (the Riccati equation's rates are sums of two eigenvalues of
/// `m`). The bound is the Collatz-Wielandt bound
/// `rho(m) <= rho(|m|) <= max_i (|m| v)_i / v_i` for any positive `v`
/// (Horn and Johnson, *Matrix Analysis*, 2nd ed., thm 8.1.26 and 8.1.18),
/// the smallest over `v = 1` (the row-sum norm, Gershgorin's bound) and a
/// few power-iteration steps from it, which approach `rho(|m|)`. Where
/// states of very different scales are coupled (the shank rate and the
/// gyro bias share the gyro's gain, the activation drives the rate by
/// `alpha F`), the row-sum norm overstates the fastest rate by a factor of
/// 2-3. NaN when `m` holds a NaN, infinite when it holds an infinity.
pub fn stiffness_bound<const N: usize>(m: &SMatrix<f64, N, N>) -> f64 {
    stiffness_bound_until(m, 0.0)
}

/// [`stiffness_bound`], stopping as soon as the bound is at most `enough`
/// (a sub-step's acceptance needs no tighter bound than that).
pub(crate) fn stiffness_bound_until<const N: usize>(m: &SMatrix<f64, N, N>, enough: f64) -> f64 {
    let abs = m.abs();
    let mut v = SVector::<f64, N>::repeat(1.0);
    let mut best = f64::INFINITY;
    for _ in 0..BOUND_ITERATIONS {
        let w = abs * v;
        // max_i w_i / v_i, compared by cross-multiplication (v > 0).
        let mut arg = 0;
        for i in 1..N {
            if w[i] * v[arg] > w[arg] * v[i] {
                arg = i;
            }
        }
        if w.iter().any(|x| x.is_nan()) {
            return f64::NAN;
        }
        best = best.min(w[arg] / v[arg]);
        if 2.0 * best <= enough {
            break;
        }
        let top = w.max();
        if !(top.is_finite() && top > 0.0) {
            break;
        }
        let scale = 1.0 / top;
        v = w.map(|x| (x * scale).max(BOUND_FLOOR));
    }
    2.0 * best
}

/// Propagates `st` over `dt` with RK4 sub-steps, `y`/`u` interpolated from
/// `(y0, u0)` at the start to `(y1, u1)` at the end (first-order hold).
///
/// The interval is split into equal sub-steps at most `max_substep` long
/// and short enough that `h * stiffness <= 2` at the start of the interval
/// ([`stiffness_bound`]). Each sub-step is accepted only when
/// `h * stiffness <= 2` at its last RK4 stage (the sub-step's end as RK4
/// predicts it); when that fails, the rest of the interval is integrated
/// with sub-steps chosen one at a time, halved until their last stage
/// passes. The check matters when the Riccati solution is far from its
/// steady state: from `P_22 = p0 = 0.01` the knee filters' default tuning
/// (`q_2 = 1e3`, `s_1 = 1e-5`) drives `P_22` to `sqrt(q_2 s_1) = 0.1`
/// within about 1e-4 s, and the gain `K = P C^T S^-1` (eq 4.15) with it, so
/// a step sized at the start of the interval was ten times too long for
/// RK4 (issue 16: a non-finite state and a restart at every sample). The
/// work per sample is bounded: at most `MAX_SUBSTEPS` sub-steps, the last
/// ones spreading what is left evenly (a divergence then shows as a
/// restart).
#[allow(clippy::too_many_arguments)]
pub fn propagate<Mdl, const N: usize, const M: usize, const U: usize>(
    model: &Mdl,
    lin: Linearisation,
    st: &mut FilterState<N>,
    dt: f64,
    (y0, y1): (&SVector<f64, M>, &SVector<f64, M>),
    (u0, u1): (&SVector<f64, U>, &SVector<f64, U>),
    s_inv: &SVector<f64, M>,
    tuning: &ContinuousTuning<N, M>,
) where
    Mdl: SdcModel<N, M, U>,
{
    if dt.is_nan() || dt <= 0.0 {
        return;
    }
    let shift = (tuning.a, tuning.a_states.as_ref());
    // Slope at fraction `s` of the interval, and the stiffness bound there
    // when `bound`.
    let eval = |st: &FilterState<N>, s: f64, bound: Option<f64>| {
        let y = y0 + (y1 - y0) * s;
        let u = u0 + (u1 - u0) * s;
        derivative_and_stiffness(model, lin, st, &y, &u, s_inv, &tuning.q, shift, bound)
    };
    // One RK4 sub-step of length `h` from `st` (slope `k1` at its start)
    // over the fractions `(s0, s1)` of the interval: its end, and the
    // stiffness bound at its last stage `st + h k3`.
    let stages = |st: &FilterState<N>, k1: &FilterState<N>, (s0, s1): (f64, f64), h: f64| {
        let sm = 0.5 * (s0 + s1);
        let k2 = eval(&add(st, k1, h / 2.0), sm, None).0;
        let k3 = eval(&add(st, &k2, h / 2.0), sm, None).0;
        let (k4, stiff) = eval(&add(st, &k3, h), s1, Some(RK4_STABLE_STEP / h));
        let p = st.p + (k1.p + (k2.p + k3.p) * 2.0 + k4.p) * (h / 6.0);
        let end = FilterState {
            x: st.x + (k1.x + (k2.x + k3.x) * 2.0 + k4.x) * (h / 6.0),
            p: (p + p.transpose()) * 0.5,
        };
        (end, stiff)
    };
    let fits = |stiff: f64, h: f64| stiff.is_finite() && h * stiff <= RK4_STABLE_STEP;
    // Equal sub-steps sized at the start of the interval.
    let (mut k1, stiff0) = eval(st, 0.0, Some(0.0));
    if !stiff0.is_finite() {
        return; // already diverged: the caller sees the non-finite state
    }
    let n = libm::ceil(dt / tuning.max_substep)
        .max(libm::ceil(dt * stiff0 / RK4_STABLE_STEP))
        .max(libm::ceil(
            dt * riccati_rate(st, &k1) / RICCATI_RELATIVE_STEP,
        ))
        .clamp(1.0, MAX_SUBSTEPS as f64);
    let h = dt / n;
    let count = n as usize;
    let mut done = 0;
    while done < count {
        let span = (done as f64 / n, (done as f64 + 1.0) / n);
        let (end, stiff) = stages(st, &k1, span, h);
        if !fits(stiff, h) {
            break;
        }
        *st = end;
        done += 1;
        if done < count {
            k1 = eval(st, span.1, None).0;
            if h * riccati_rate(st, &k1) > 2.0 * RICCATI_RELATIVE_STEP {
                break;
            }
        }
    }
    if done == count {
        return;
    }
    // Stiffer than at the start: sub-steps chosen one at a time.
    let mut t = dt * done as f64 / n;
    for i in done..MAX_SUBSTEPS {
        let remaining = dt - t;
        let s0 = t / dt;
        let (k, k0) = eval(st, s0, Some(0.0));
        if !k0.is_finite() {
            return;
        }
        // At most MAX_SUBSTEPS sub-steps: spread what is left over those left.
        let floor = remaining / (MAX_SUBSTEPS - i) as f64;
        let mut h = tuning.max_substep.min(remaining);
        if k0 > 0.0 {
            h = h.min(RK4_STABLE_STEP / k0);
        }
        let rate = riccati_rate(st, &k);
        if rate > 0.0 {
            h = h.min(RICCATI_RELATIVE_STEP / rate);
        }
        let span = |h: f64| {
            if h >= remaining * (1.0 - 1e-9) {
                (remaining, (s0, 1.0))
            } else {
                (h, (s0, (t + h) / dt))
            }
        };
        let mut taken = None;
        for _ in 0..MAX_STEP_CUTS {
            if h <= floor {
                break;
            }
            let (hh, sp) = span(h);
            let (end, stiff) = stages(st, &k, sp, hh);
            if fits(stiff, hh) {
                taken = Some((end, hh));
                break;
            }
            h *= 0.5;
        }
        let (end, hh) = taken.unwrap_or_else(|| {
            let (hh, sp) = span(h.max(floor));
            (stages(st, &k, sp, hh).0, hh)
        });
        *st = end;
        if hh >= remaining {
            return;
        }
        t += hh;
    }
}

/// `max_i |P_dot_ii| / P_ii` at slope `k` (1/s; NaN when `P` or its slope
/// is; diagonal entries that are not positive are skipped).
fn riccati_rate<const N: usize>(st: &FilterState<N>, k: &FilterState<N>) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..N {
        let p = st.p[(i, i)];
        if p > 0.0 {
            let r = libm::fabs(k.p[(i, i)]) / p;
            worst = if r.is_nan() || r > worst { r } else { worst };
        }
    }
    worst
}

/// `a + c k` for state and Riccati solution.
fn add<const N: usize>(a: &FilterState<N>, k: &FilterState<N>, c: f64) -> FilterState<N> {
    FilterState {
        x: a.x + k.x * c,
        p: a.p + k.p * c,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    /// The bound is never below the spectral radius and never above the
    /// row-sum norm; on a matrix whose rows mix scales (a large coupling
    /// one way, a small one back) it is well below the row-sum norm.
    /// Eigenvalues of the lower-triangular example: its diagonal.
    #[test]
    fn stiffness_bound_lies_between_spectral_radius_and_row_norm() {
        // Upper triangular: eigenvalues -10, -20, -1 (rho = 20).
        let m = Matrix3::new(-10.0, 250.0, 3.0, 0.0, -20.0, 0.0, 0.0, 5.0, -1.0);
        let b = stiffness_bound(&m) / 2.0;
        let row_norm = 10.0 + 250.0 + 3.0;
        assert!(b >= 20.0 && b <= row_norm, "{b}");
        assert!(b < 0.15 * row_norm, "{b}");
        // Rate and gyro bias sharing one gain: eigenvalues -(k + kb), 0.
        let (k, kb) = (255.0, 1.0);
        let m = SMatrix::<f64, 2, 2>::new(-k, -k, -kb, -kb);
        let b = stiffness_bound(&m) / 2.0;
        assert!(b >= k + kb - 1e-9 && b < 1.05 * (k + kb), "{b}");
        // Non-finite entries are reported.
        let mut bad = m;
        bad[(0, 1)] = f64::NAN;
        assert!(stiffness_bound(&bad).is_nan());
        bad[(0, 1)] = f64::INFINITY;
        assert!(stiffness_bound(&bad).is_infinite());
    }
}
