//! Which records a sampling observer counts: every `STRIDE`-th, the first
//! included (the unit checks and the fixed-thigh check look at shares, which
//! need no more; counting every sample cost 20 % of a Python `estimate` call,
//! docs/PERFORMANCE.md).

/// Counts the records seen and says which ones are due.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Strided {
    records: u64,
}

impl Strided {
    /// Whether this record is due (records 0, `stride`, `2 stride`, ...);
    /// counts it.
    pub fn due(&mut self, stride: usize) -> bool {
        let due = self.records.is_multiple_of(stride as u64);
        self.records += 1;
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stride_th_record_is_due_from_the_first() {
        let mut s = Strided::default();
        let due: Vec<usize> = (0..20).filter(|_| s.due(8)).collect();
        assert_eq!(due, vec![0, 8, 16]);
    }
}
