//! The gain breakdown of paper 001 Fig. 6 (moved out of `chain` to keep
//! one concept per module).
#![allow(non_snake_case)]

use nalgebra::{SMatrix, SVector};

use super::model::angle_state;
use super::structured::Gain;

/// How a measurement row relates to the segments (for the gain breakdown
/// of 001 Fig. 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// An accelerometer-inclination row of segment `i`.
    Imu(usize),
    /// A joint row: encoder (MJLS) or accelerometer difference (global).
    Joint,
}

/// Breakdown of each segment's angle correction by source, as in 001
/// Fig. 6: the correction of segment `s` is `sum_j K[2s, j] e_j`; the share
/// of row `j` is `|K[2s, j] e_j| / sum_j |K[2s, j] e_j|`, summed over the
/// segment's own accelerometer row, the other segments' accelerometer rows
/// and the joint rows (encoders or accelerometer differences). `None` for a
/// segment whose correction is exactly zero.
#[inline]
pub fn gain_shares<const M: usize>(
    K: &SMatrix<f64, 8, M>,
    innovation: &SVector<f64, M>,
    kinds: &[RowKind; M],
) -> [[Option<f64>; 3]; 4] {
    let mut out = [[None; 3]; 4];
    for (s, o) in out.iter_mut().enumerate() {
        let mut parts = [0.0; 3];
        for j in 0..M {
            let c = libm::fabs(K[(angle_state(s), j)] * innovation[j]);
            let k = match kinds[j] {
                RowKind::Imu(i) if i == s => 0,
                RowKind::Imu(_) => 1,
                RowKind::Joint => 2,
            };
            parts[k] += c;
        }
        let total = parts[0] + parts[1] + parts[2];
        if total > 0.0 && total.is_finite() {
            *o = [
                Some(parts[0] / total),
                Some(parts[1] / total),
                Some(parts[2] / total),
            ];
        }
    }
    out
}

/// The rows that updated and the gain shares after [`super::chain::Chain::update`]
/// returned `made` with the rows `active` and wrote its gain into `last`
/// (the filter's kept gain): `active` and the shares of `last` after an
/// update; no row, no shares and a zero gain otherwise.
#[inline]
pub(crate) fn after_update<const M: usize>(
    made: bool,
    active: [bool; M],
    last: &mut Gain<M>,
    kinds: &[RowKind; M],
) -> ([bool; M], [[Option<f64>; 3]; 4]) {
    if made {
        (active, gain_shares(&last.K, &last.innovation, kinds))
    } else {
        *last = Gain::zero();
        ([false; M], [[None; 3]; 4])
    }
}

#[cfg(test)]
mod gain_share_tests {
    use super::*;
    use crate::segment_kf::model::bias_state;

    /// 001 Fig. 6 breakdown on a hand-built gain: rows = [IMU trunk,
    /// IMU thigh, joint]. Trunk correction parts: |0.5 * 0.2| = 0.1 (own),
    /// |0.1 * -0.5| = 0.05 (other), |0.25 * 0.2| = 0.05 (joint) -> 0.5 /
    /// 0.25 / 0.25. Thigh: |0.2 * 0.2| = 0.04 (other), |0.4 * -0.5| = 0.2
    /// (own), 0 (joint) -> own 0.2/0.24, other 0.04/0.24. Shank and foot have
    /// no gain: `None`.
    #[test]
    fn shares_match_a_hand_computed_breakdown() {
        let mut K = SMatrix::<f64, 8, 3>::zeros();
        K[(angle_state(0), 0)] = 0.5;
        K[(angle_state(0), 1)] = 0.1;
        K[(angle_state(0), 2)] = 0.25;
        K[(angle_state(1), 0)] = 0.2;
        K[(angle_state(1), 1)] = 0.4;
        // bias rows never count
        K[(bias_state(0), 0)] = 9.0;
        let e = SVector::<f64, 3>::new(0.2, -0.5, 0.2);
        let kinds = [RowKind::Imu(0), RowKind::Imu(1), RowKind::Joint];
        let s = gain_shares(&K, &e, &kinds);
        let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-15;
        assert!(close(s[0][0], 0.5) && close(s[0][1], 0.25) && close(s[0][2], 0.25));
        assert!(close(s[1][0], 0.2 / 0.24) && close(s[1][1], 0.04 / 0.24));
        assert!(close(s[1][2], 0.0));
        assert_eq!(s[2], [None; 3]);
        assert_eq!(s[3], [None; 3]);
    }
}
