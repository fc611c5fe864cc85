//! Two-dimensional Nelder-Mead minimisation (the placement search of
//! [`super::Stance::fit`]).

/// Nelder-Mead minimisation in two dimensions (standard coefficients 1, 2,
/// 1/2, 1/2), `iters` iterations from `x0` with initial steps `step`.
pub(super) fn nelder_mead(
    f: impl Fn([f64; 2]) -> f64,
    x0: [f64; 2],
    step: [f64; 2],
    iters: usize,
) -> (f64, f64) {
    let mut p = [x0, [x0[0] + step[0], x0[1]], [x0[0], x0[1] + step[1]]];
    let mut v = p.map(&f);
    let lerp =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    for _ in 0..iters {
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        p = idx.map(|i| p[i]);
        v = idx.map(|i| v[i]);
        let c = lerp(p[0], p[1], 0.5);
        let r = lerp(c, p[2], -1.0);
        let fr = f(r);
        if fr < v[0] {
            let e = lerp(c, p[2], -2.0);
            let fe = f(e);
            (p[2], v[2]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < v[1] {
            (p[2], v[2]) = (r, fr);
        } else {
            let k = lerp(c, p[2], 0.5);
            let fk = f(k);
            if fk < v[2] {
                (p[2], v[2]) = (k, fk);
            } else {
                for i in 1..3 {
                    p[i] = lerp(p[0], p[i], 0.5);
                    v[i] = f(p[i]);
                }
            }
        }
    }
    let i = (0..3).min_by(|&a, &b| v[a].total_cmp(&v[b])).unwrap_or(0);
    (p[i][0], p[i][1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nelder_mead_finds_a_quadratic_minimum() {
        let (x, y) = nelder_mead(
            |p| (p[0] - 0.3).powi(2) + 2.0 * (p[1] + 0.1).powi(2),
            [0.0, 0.0],
            [0.1, 0.1],
            80,
        );
        assert!((x - 0.3).abs() < 1e-4 && (y + 0.1).abs() < 1e-4);
    }
}
