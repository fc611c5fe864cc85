//! Gaps in one foot's readings: empty cells (a dropped radio packet) or
//! missing rows. A gap no longer than the shortest swing (`min_swing_time`,
//! 0.15 s) cannot hide a whole swing, so the event sequence and the stride
//! integration continue across it, the next reading's step spanning the
//! gap (as a missing row always did). A longer gap may hide a contact or a
//! whole stride: the foot's pipeline restarts (events, rest detector and
//! stride integration; the axis is kept). An empty cell of a vector whose
//! other axes are there is held from that axis's last value ([`CellHold`]).

use nalgebra::Vector3;

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

/// The last value and time of each axis of one foot's accelerometer and
/// gyroscope (x, y, z each), for readings with some axes missing: an empty
/// cell (the trial reader keeps the present axes, issue 18 item 2). A
/// missing axis takes its last value when that is at most `max_age` old
/// (the same bound as the gap a step may span, [`ReadingGap::reading`]), so
/// that one empty cell does not drop the other five fresh ones: with 20 % of
/// the cells missing, three vectors in four lack some axis, and the stride
/// integration stepped over each such sample as over a gap (the shared
/// two-foot walk's stride length error 2.45 -> 17 %; 4.3 % with 5 % of the
/// cells missing). A vector missing as a whole (a dropped packet) stays
/// missing: it is a gap.
#[derive(Debug, Clone, Copy, Default)]
pub struct CellHold {
    last: [Option<(f64, f64)>; 6],
}

impl CellHold {
    /// The accelerometer and gyroscope vectors of `imu` at `t`, each
    /// completed from its present axes and the held ones, or `None`.
    pub fn complete(
        &mut self,
        t: f64,
        imu: &limbfuse_core::ImuSample,
        max_age: f64,
    ) -> (Option<Vector3<f64>>, Option<Vector3<f64>>) {
        let (held_acc, held_gyr) = self.last.split_at_mut(3);
        (
            complete_vector(t, imu.acc, &imu.acc_partial, held_acc, max_age),
            complete_vector(t, imu.gyr, &imu.gyr_partial, held_gyr, max_age),
        )
    }
}

/// One vector: `whole` when present (its axes remembered), else its
/// `present` axes with the `held` values of the others when every one is at
/// most `max_age` old; `None` when no axis is present.
fn complete_vector(
    t: f64,
    whole: Option<Vector3<f64>>,
    present: &[Option<f64>; 3],
    held: &mut [Option<(f64, f64)>],
    max_age: f64,
) -> Option<Vector3<f64>> {
    if let Some(v) = whole {
        for k in 0..3 {
            held[k] = Some((v[k], t));
        }
        return Some(v);
    }
    if present.iter().all(Option::is_none) {
        return None;
    }
    let mut v = Vector3::zeros();
    let mut complete = true;
    for k in 0..3 {
        match present[k] {
            Some(x) => {
                held[k] = Some((x, t));
                v[k] = x;
            }
            None => match held[k] {
                Some((x, t0)) if t - t0 <= max_age => v[k] = x,
                _ => complete = false,
            },
        }
    }
    complete.then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::ImuSample;

    fn sample(acc: [Option<f64>; 3], gyr: [Option<f64>; 3]) -> ImuSample {
        let whole = |c: [Option<f64>; 3]| Some(Vector3::new(c[0]?, c[1]?, c[2]?));
        let partial = |c: [Option<f64>; 3]| if whole(c).is_some() { [None; 3] } else { c };
        ImuSample {
            acc: whole(acc),
            gyr: whole(gyr),
            acc_partial: partial(acc),
            gyr_partial: partial(gyr),
            ..ImuSample::default()
        }
    }

    #[test]
    fn a_missing_axis_takes_its_last_value_within_the_age_bound() {
        let mut h = CellHold::default();
        let full = sample(
            [Some(1.0), Some(2.0), Some(3.0)],
            [Some(0.1), Some(0.2), Some(0.3)],
        );
        assert_eq!(
            h.complete(0.0, &full, 0.15).0,
            Some(Vector3::new(1.0, 2.0, 3.0))
        );
        // acc y missing at 0.01 s: held 2.0; the gyro complete
        let gappy = sample(
            [Some(1.5), None, Some(3.5)],
            [Some(0.4), Some(0.5), Some(0.6)],
        );
        let (a, g) = h.complete(0.01, &gappy, 0.15);
        assert_eq!(a, Some(Vector3::new(1.5, 2.0, 3.5)));
        assert_eq!(g, Some(Vector3::new(0.4, 0.5, 0.6)));
        // the x just read (1.5) is held next: x missing now
        let x_gone = sample(
            [None, Some(2.5), Some(3.6)],
            [Some(0.4), Some(0.5), Some(0.6)],
        );
        assert_eq!(
            h.complete(0.02, &x_gone, 0.15).0,
            Some(Vector3::new(1.5, 2.5, 3.6))
        );
        // too old: y last read at 0.02 s, now 0.2 s
        let y_gone = sample([Some(1.0), None, Some(3.0)], [None; 3]);
        let (a, g) = h.complete(0.2, &y_gone, 0.15);
        assert_eq!((a, g), (None, None));
        // a vector missing as a whole stays missing (a gap, not a cell)
        let none = sample([None; 3], [Some(0.1), Some(0.2), Some(0.3)]);
        assert_eq!(h.complete(0.21, &none, 0.15).0, None);
    }
}
