//! Gaps in one foot's readings: empty cells (a dropped radio packet) or
//! missing rows. A gap no longer than the shortest swing (`min_swing_time`,
//! 0.15 s) cannot hide a whole swing, so the event sequence and the stride
//! integration continue across it, the next reading's step spanning the
//! gap (as a missing row always did). A longer gap may hide a contact or a
//! whole stride: the foot's pipeline restarts (events, rest detector and
//! stride integration; the axis is kept). An empty cell of a vector whose
//! other axes are there is held from that axis's last value
//! ([`crate::cell_hold::CellHold`]).

/// The time of one foot's last reading.
#[derive(Debug, Clone, Copy, Default)]
pub struct ReadingGap {
    last: Option<f64>,
}

impl ReadingGap {
    /// A reading at `t`, `dt` after the previous sample of the trial: the
    /// step (s) since this foot's previous reading, or `None` when that step
    /// is longer than `max_gap` (s) and the pipeline must restart. The first
    /// reading takes the trial's `dt`; when no reading was missed the step
    /// is `dt` bit for bit (the same two times subtracted). After `None` the
    /// caller restarts and steps by the trial's `dt`, as after a dropout.
    pub fn reading(&mut self, t: f64, dt: f64, max_gap: f64) -> Option<f64> {
        let step = self.last.replace(t).map_or(dt, |last| t - last);
        (step <= max_gap).then_some(step)
    }
}
