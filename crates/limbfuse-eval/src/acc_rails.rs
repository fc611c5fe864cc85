//! An accelerometer that looks clipped below the full scale the methods
//! assume: what `limbfuse estimate` says when a trial states no
//! `# acc_range_m_s2:` (16 g is then assumed) or a larger one than its
//! sensor has.
//!
//! The sensor gate rejects clipped accelerometer readings from 97 % of the
//! full scale it knows (docs/OUTPUTS.md "Sensor-range gate"): a 2 g sensor
//! in a trial that states no range is not seen, and `chain`'s knee came out
//! 1.7 deg off on the independent 1.6 m/s walk so clipped (0.15 deg with the
//! range stated; docs/RESULTS.md "Clipped accelerometers"). A raw sensor's
//! rail is one exact value: [`AccRailWatch`] counts, per accelerometer
//! axis, the readings equal to the axis's largest magnitude so far, on
//! every [`AccRailWatch::STRIDE`]-th sample (a rail holds for hundreds of
//! readings; every sample cost 3 % of a one-hour Python `estimate` call of
//! `mjls`). An axis whose largest magnitude is at least [`RAIL_FLOOR_M_S2`]
//! (1.5 g: above what any still or slowly moving segment reads, below the
//! smallest full scale in gait work, 2 g) and repeats on at least
//! [`RAIL_MIN_READINGS`] of the counted readings, while it lies below 97 %
//! of the assumed full scale, is reported. A calibrated sensor's rail, which its cross-axis terms spread,
//! does not repeat exactly and is not seen. None of the shared recordings
//! repeats its largest accelerometer reading at 1.5 g or more.

use std::fmt;

use limbfuse_core::runner::{BoxError, Observer};
use limbfuse_core::sample_gate::ACC_CLIPPED_FRACTION;
use limbfuse_core::{Estimate, Record, Sample, Segment};

use crate::strided::Strided;

/// Smallest magnitude (m/s^2, 1.5 g) a rail is looked for at.
pub const RAIL_FLOOR_M_S2: f64 = 1.5 * 9.80665;

/// Counted readings at exactly an axis's largest magnitude that make a
/// rail: ten (about 80 readings), where an unclipped axis reaches its
/// extreme once (a swing's peak is passed through, not held).
pub const RAIL_MIN_READINGS: u64 = 10;

/// One accelerometer axis that looks clipped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccRail {
    /// IMU slot: 0-3 this leg's trunk to foot, 4-7 the other leg's.
    pub imu: usize,
    /// Axis 0-2 (x, y, z).
    pub axis: usize,
    /// The rail's magnitude (m/s^2).
    pub value: f64,
    /// Readings exactly at it (either sign).
    pub readings: u64,
}

/// What [`AccRailWatch`] found: the axes that look clipped, and the full
/// scale the methods assumed.
#[derive(Debug, Clone, PartialEq)]
pub struct AccRails {
    /// The axes, by IMU slot then axis.
    pub rails: Vec<AccRail>,
    /// The full scale in use (m/s^2).
    pub full_scale: f64,
    /// Whether the trial stated it (`# acc_range_m_s2:`).
    pub stated: bool,
}

impl fmt::Display for AccRails {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // (one entry per IMU and rail value: the axes of a sensor clip at one rail)
        let mut names: Vec<String> = Vec::new();
        let mut k = 0;
        while k < self.rails.len() {
            let r = self.rails[k];
            let same = self.rails[k..]
                .iter()
                .take_while(|q| q.imu == r.imu && q.value == r.value)
                .count();
            let group = &self.rails[k..k + same];
            let axes: Vec<&str> = group.iter().map(|q| ["x", "y", "z"][q.axis]).collect();
            let readings: u64 = group.iter().map(|q| q.readings).sum();
            let segment = Segment::ALL[r.imu % 4].name();
            let leg = if r.imu < 4 { "" } else { "other leg's " };
            names.push(format!(
                "the {leg}{segment} accelerometer's {} at +-{} m/s^2 ({:.2} g; {readings} readings)",
                axes.join(", "),
                limbfuse_core::ShownNumber(r.value),
                r.value / 9.80665,
            ));
            k += same;
        }
        let assumed = if self.stated {
            format!(
                "the trial's `# acc_range_m_s2:` of {} m/s^2",
                limbfuse_core::ShownNumber(self.full_scale)
            )
        } else {
            "16 g, as the trial states no `# acc_range_m_s2:`".to_string()
        };
        write!(
            f,
            "accelerometer readings repeat exactly at their largest value: {}. These look clipped \
             there, below the full scale assumed ({assumed}), and were taken as measurements; a \
             clipped specific force points the wrong way: state the sensor's range, and the \
             methods reject such readings (`gait-events` and `lowback-speed` model them; \
             docs/OUTPUTS.md \"Sensor-range gate\")",
            names.join("; ")
        )
    }
}

/// Per accelerometer axis of both legs' IMUs: the largest magnitude so far
/// and how many readings were exactly at it.
#[derive(Debug, Clone, PartialEq)]
pub struct AccRailWatch {
    largest: [[f64; 3]; 8],
    at_largest: [[u64; 3]; 8],
    full_scale: f64,
    stated: bool,
    records: Strided,
}

impl AccRailWatch {
    /// Samples counted: sample 0, `STRIDE`, `2 STRIDE`, ... of a run.
    pub const STRIDE: usize = 8;

    /// A watch for a trial whose accelerometer full scale is `full_scale`
    /// (m/s^2), `stated` in its metadata or assumed.
    pub fn new(full_scale: f64, stated: bool) -> Self {
        AccRailWatch {
            largest: [[0.0; 3]; 8],
            at_largest: [[0; 3]; 8],
            full_scale,
            stated,
            records: Strided::default(),
        }
    }

    /// Adds one sample's accelerometer readings (complete vectors and the
    /// cells of incomplete ones).
    pub fn push(&mut self, s: &Sample) {
        let imus = s.imu.iter().chain(s.other_leg_imu.iter());
        for (k, imu) in imus.enumerate() {
            for j in 0..3 {
                let cell = imu.acc.map_or(imu.acc_partial[j], |a| Some(a[j]));
                if let Some(v) = cell {
                    self.push_cell(k, j, v);
                }
            }
        }
    }

    /// Adds one reading `v` (m/s^2; NaN is ignored) of axis `j` of the
    /// accelerometer in IMU slot `k` (0-3 this leg's trunk to foot, 4-7 the
    /// other leg's).
    #[inline]
    pub fn push_cell(&mut self, k: usize, j: usize, v: f64) {
        let m = v.abs();
        let top = &mut self.largest[k][j];
        if m > *top {
            *top = m;
            self.at_largest[k][j] = 1;
        } else if m == *top {
            self.at_largest[k][j] += 1;
        }
    }

    /// Adds `count` readings of magnitude `largest`, the largest of a run
    /// of readings of axis `j` of IMU slot `k` (a column's: the same as
    /// pushing the run's cells one by one).
    pub fn push_largest(&mut self, k: usize, j: usize, largest: f64, count: u64) {
        let top = &mut self.largest[k][j];
        if largest > *top {
            *top = largest;
            self.at_largest[k][j] = count;
        } else if largest == *top {
            self.at_largest[k][j] += count;
        }
    }

    /// The axes that look clipped below the full scale in use; `None` when
    /// none does.
    pub fn rails(&self) -> Option<AccRails> {
        let mut rails = Vec::new();
        for k in 0..8 {
            for j in 0..3 {
                let (value, readings) = (self.largest[k][j], self.at_largest[k][j]);
                if value >= RAIL_FLOOR_M_S2
                    && readings >= RAIL_MIN_READINGS
                    && value < ACC_CLIPPED_FRACTION * self.full_scale
                {
                    rails.push(AccRail {
                        imu: k,
                        axis: j,
                        value,
                        readings,
                    });
                }
            }
        }
        (!rails.is_empty()).then_some(AccRails {
            rails,
            full_scale: self.full_scale,
            stated: self.stated,
        })
    }
}

impl Observer for AccRailWatch {
    /// Counts every [`AccRailWatch::STRIDE`]-th record.
    fn observe(&mut self, record: &Record, _estimate: &Estimate) -> Result<(), BoxError> {
        if self.records.due(Self::STRIDE) {
            self.push(&record.sample);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn sample(foot: [f64; 3], thigh: [f64; 3]) -> Sample {
        let mut s = Sample::empty(0.0);
        s.imu[Segment::Foot.index()].acc = Some(Vector3::from(foot));
        s.imu[Segment::Thigh.index()].acc = Some(Vector3::from(thigh));
        s
    }

    #[test]
    fn a_repeated_largest_value_above_1_5_g_is_a_rail() {
        let rail = 2.0 * 9.80665;
        let mut w = AccRailWatch::new(16.0 * 9.80665, false);
        for k in 0..200 {
            let swing = 25.0 * (k as f64 * 0.1).sin();
            // the foot's x clipped at 2 g; the thigh's y a smooth 1.2 g
            // peak and a still 1 g, repeated, below the floor
            let foot = [swing.clamp(-rail, rail), 9.81, 0.0];
            let thigh = [
                0.0,
                if k < 100 {
                    9.81
                } else {
                    11.8 * (k as f64 * 0.05).sin()
                },
                0.0,
            ];
            w.push(&sample(foot, thigh));
        }
        let r = w.rails().expect("the foot's x axis");
        assert_eq!(r.rails.len(), 1, "{r:?}");
        let x = r.rails[0];
        assert_eq!((x.imu, x.axis, x.value), (Segment::Foot.index(), 0, rail));
        assert!(x.readings >= 50, "{x:?}");
        let text = r.to_string();
        assert!(
            text.contains("the foot accelerometer's x at +-19.6133 m/s^2 (2.00 g; "),
            "{text}"
        );
        assert!(
            text.contains("(16 g, as the trial states no `# acc_range_m_s2:`)"),
            "{text}"
        );
        // The same rail stated as the full scale: the gate rejects it, no
        // warning; a larger stated full scale: the warning.
        let mut stated = AccRailWatch::new(rail, true);
        let mut larger = AccRailWatch::new(4.0 * 9.80665, true);
        for k in 0..200 {
            let swing = 25.0 * (k as f64 * 0.1).sin();
            let s = sample([swing.clamp(-rail, rail), 9.81, 0.0], [0.0; 3]);
            stated.push(&s);
            larger.push(&s);
        }
        assert_eq!(stated.rails(), None);
        assert!(larger
            .rails()
            .unwrap()
            .to_string()
            .contains("the trial's `# acc_range_m_s2:` of 39.2266 m/s^2"));
    }

    #[test]
    fn an_unclipped_swing_is_not_a_rail() {
        let mut w = AccRailWatch::new(16.0 * 9.80665, false);
        for k in 0..2000 {
            let t = k as f64 * 0.01;
            w.push(&sample(
                [40.0 * (6.0 * t).sin() + 0.3 * (37.0 * t).sin(), 9.81, 0.0],
                [0.0; 3],
            ));
        }
        assert_eq!(w.rails(), None);
    }
}
