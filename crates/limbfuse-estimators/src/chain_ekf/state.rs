//! The state vector of the chain EKF and a sparse measurement row.
//!
//! `x = [theta_0..3, omega_0..3, alpha_0..3, b_0..3, v_hx, v_hy, a_hx, a_hy,
//! v_m, o_hip, o_knee, o_ankle]` (docs/CHAIN.md, "State"): per segment
//! (trunk, thigh, shank, foot) the absolute sagittal angle, its rate and
//! angular acceleration, the gyro bias; the hip joint's world velocity and
//! acceleration; the slowly varying mean forward speed; the three encoder
//! offsets.

/// Number of states.
pub const N: usize = 24;

/// Index of segment `i`'s angle `theta_i` (rad).
pub const fn theta(i: usize) -> usize {
    i
}

/// Index of segment `i`'s rate `omega_i` (rad/s).
pub const fn omega(i: usize) -> usize {
    4 + i
}

/// Index of segment `i`'s angular acceleration `alpha_i` (rad/s^2).
pub const fn alpha(i: usize) -> usize {
    8 + i
}

/// Index of segment `i`'s gyro bias `b_i` (rad/s).
pub const fn gyro_bias(i: usize) -> usize {
    12 + i
}

/// Index of the hip velocity's world component `k` (0 = x forward, 1 = y up), m/s.
pub const fn hip_velocity(k: usize) -> usize {
    16 + k
}

/// Index of the hip acceleration's world component `k` (m/s^2).
pub const fn hip_acceleration(k: usize) -> usize {
    18 + k
}

/// Index of the mean forward speed `v_m` (m/s).
pub const MEAN_SPEED: usize = 20;

/// Index of encoder `j`'s offset (hip, knee, ankle), rad.
pub const fn encoder_offset(j: usize) -> usize {
    21 + j
}

/// Most non-zeros of one measurement row (the foot accelerometer: three
/// states of each of thigh, shank and foot, two of the hip acceleration).
pub const MAX_NONZEROS: usize = 12;

/// One row `H` of a scalar measurement, stored by its non-zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SparseRow {
    idx: [usize; MAX_NONZEROS],
    val: [f64; MAX_NONZEROS],
    len: usize,
}

impl Default for SparseRow {
    fn default() -> Self {
        Self::new()
    }
}

impl SparseRow {
    /// A row of zeros.
    pub const fn new() -> Self {
        SparseRow {
            idx: [0; MAX_NONZEROS],
            val: [0.0; MAX_NONZEROS],
            len: 0,
        }
    }

    /// Adds `value` at state `index` (entries at the same index add up).
    #[inline]
    pub fn add(&mut self, index: usize, value: f64) {
        for k in 0..self.len {
            if self.idx[k] == index {
                self.val[k] += value;
                return;
            }
        }
        debug_assert!(self.len < MAX_NONZEROS, "SparseRow: too many non-zeros");
        if self.len < MAX_NONZEROS {
            self.idx[self.len] = index;
            self.val[self.len] = value;
            self.len += 1;
        }
    }

    /// The non-zeros as `(index, value)`.
    #[inline]
    pub fn entries(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.idx[..self.len]
            .iter()
            .copied()
            .zip(self.val[..self.len].iter().copied())
    }

    /// The row as a dense array (tests, diagnostics).
    pub fn dense(&self) -> [f64; N] {
        let mut out = [0.0; N];
        for (i, v) in self.entries() {
            out[i] += v;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_cover_the_state_once() {
        let mut seen = [0u8; N];
        for i in 0..4 {
            for k in [theta(i), omega(i), alpha(i), gyro_bias(i)] {
                seen[k] += 1;
            }
        }
        for k in 0..2 {
            seen[hip_velocity(k)] += 1;
            seen[hip_acceleration(k)] += 1;
        }
        seen[MEAN_SPEED] += 1;
        for j in 0..3 {
            seen[encoder_offset(j)] += 1;
        }
        assert!(seen.iter().all(|&c| c == 1), "{seen:?}");
    }

    #[test]
    fn sparse_row_adds_repeated_indices() {
        let mut r = SparseRow::new();
        r.add(3, 1.0);
        r.add(5, 2.0);
        r.add(3, 0.5);
        let d = r.dense();
        assert_eq!((d[3], d[5]), (1.5, 2.0));
        assert_eq!(r.entries().count(), 2);
    }
}
