//! A constant time offset between the thigh and the shank IMU streams
//! (ours, beyond paper 002): two unsynchronised sensors (consumer Bluetooth
//! IMUs) often deliver rows whose readings are 10-50 ms apart in time.
//!
//! The raw thigh and shank readings of the last rows are held in a
//! fixed-capacity ring ([`DelayLine`], allocated once). At the end of each
//! identification window, the joint-centre acceleration constraint of
//! paper 002 eq 3, `|a_1(t) - Gamma_1(o_1)| = |a_2(t + d) - Gamma_2(o_2)|`,
//! is fitted ([`fit_positions`], the window's own position fit) for every
//! candidate offset `d` in `-max..=max` samples, pairing the thigh reading
//! of a row with the shank reading `d` rows later, over the same thigh rows
//! for every candidate; the offset whose fit leaves the smallest RMS
//! residual `e_o` is taken when that RMS is below [`ADOPT_RATIO`] times the
//! one at the offset in use ([`DelayLine::search`]). (The hinge constraint
//! of eq 1/2 cannot tell the offsets apart when the knee moves in a plane:
//! both rates then lie along the axes and `e_j` is the noise at every
//! offset; measured on the shared independent walks, RMS `e_j` 0.0064
//! rad/s at offsets 0, +1, +2 and -2, RMS `e_o` 0.075, 0.31, 0.54, 0.56
//! m/s^2.) Every later row then pairs the thigh and
//! shank readings by that offset ([`DelayLine::paired`]): the stream that
//! runs ahead is delayed by `|d|` rows, so the output refers to the clock
//! of the stream that lags (a latency of `|d|` samples on the other one's).
//! With `d = 0` the pairing is the input row itself (bit-identical
//! outputs).

use alloc::vec::Vec;

use limbfuse_core::{ImuSample, Sample, Segment};
use nalgebra::Vector3;

use super::params::KneeSelfAlignParams;
use super::position_fit::fit_positions;
use super::window::{Ring, Slot};

/// A candidate offset is adopted when its RMS `e_o` is below this fraction
/// of the RMS at the offset in use. An offset of one sample leaves in `e_o`
/// the change of the specific force and of `Gamma` over one period (RMS
/// `e_o` 0.075 m/s^2 in sync against 0.31 one sample off on the shared
/// 1.2 m/s walk at 100 Hz); a window where the offsets are not told apart
/// (no motion: every candidate fits equally) keeps the offset in use.
/// 0.9 asks for a 10 % smaller residual.
pub const ADOPT_RATIO: f64 = 0.9;

/// ... and only a sharp minimum inside the range is an offset: the RMS at
/// the best offset must be at most this fraction of the larger RMS of its
/// two neighbours (one sample either way). Measured in sync, 100 Hz: 0.56,
/// 0.24 and 0.13 on the shared independent walks at 0.7, 1.2 and 1.6 m/s
/// (the V of a time offset); 0.98-0.99 on the real gaittoolbox walk
/// (hardware-synchronised IMUs: a flat curve whose minimum wanders by
/// soft-tissue motion), and minima at the range's end on the knee rig
/// (250 Hz, a residual drifting with the offset). 0.75 lies between.
pub const SHARPNESS: f64 = 0.75;

/// Thigh and shank readings of one input row.
#[derive(Debug, Clone, Copy, Default)]
struct RawRow {
    t: f64,
    imu: [ImuSample; 2],
}

/// The last rows, a fixed-capacity ring.
#[derive(Debug, Clone)]
struct Rows {
    rows: Vec<RawRow>,
    head: usize,
    len: usize,
}

impl Rows {
    /// The row `back` rows before the newest (0 the newest).
    fn get(&self, back: usize) -> Option<&RawRow> {
        (back < self.len).then(|| &self.rows[(self.head + self.len - 1 - back) % self.rows.len()])
    }

    /// The thigh reading of the row `back` rows before the newest paired
    /// with the shank reading `d` rows later, at the later row's time.
    fn pair(&self, back: usize, d: isize) -> Option<(f64, [ImuSample; 2])> {
        let shank_back = usize::try_from(back as isize - d).ok()?;
        let (thigh, shank) = (self.get(back)?, self.get(shank_back)?);
        let t = self.get(back.min(shank_back))?.t;
        Some((t, [thigh.imu[0], shank.imu[1]]))
    }
}

/// The raw thigh and shank readings of the last rows and the offset in use.
#[derive(Debug, Clone)]
pub struct DelayLine {
    rows: Rows,
    /// The window re-paired for one candidate offset (allocated once).
    scratch: Ring,
    /// RMS `e_o` per candidate offset of the last search (allocated once).
    curve: Vec<f64>,
    max: usize,
    delay: isize,
}

/// What [`DelayLine::search`] found over one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DelaySearch {
    /// Offset (samples) with the smallest RMS `e_o`: positive when the
    /// shank's stream lags the thigh's (the shank reading of time `t`
    /// arrives `d` rows after the thigh's).
    pub best: isize,
    /// RMS `e_o` (m/s^2) at `best`.
    pub rms_best: f64,
    /// RMS `e_o` (m/s^2) at the offset in use.
    pub rms_current: f64,
    /// The larger RMS `e_o` (m/s^2) of the two offsets next to `best`
    /// (infinite at the range's end: no minimum inside the range).
    pub rms_neighbours: f64,
}

/// Whether a gyro reading has an axis at 99.9 % of `gyro_range` or beyond.
pub(super) fn saturated(g: &Option<Vector3<f64>>, gyro_range: f64) -> bool {
    let limit = 0.999 * gyro_range;
    g.is_some_and(|g| g.iter().any(|c| c.abs() >= limit))
}

/// The window slot of a thigh and shank reading pair at time `t`.
pub(super) fn slot(t: f64, imu: &[ImuSample; 2], gyro_range: f64) -> Slot {
    let [thigh, shank] = imu;
    let saturated = saturated(&thigh.gyr, gyro_range) || saturated(&shank.gyr, gyro_range);
    Slot {
        t,
        gyr: [thigh.gyr.unwrap_or_default(), shank.gyr.unwrap_or_default()],
        acc: [thigh.acc.unwrap_or_default(), shank.acc.unwrap_or_default()],
        gyr_ok: thigh.gyr.is_some() && shank.gyr.is_some() && !saturated,
        acc_ok: thigh.acc.is_some() && shank.acc.is_some(),
    }
}

impl DelayLine {
    /// A line for offsets up to `max` samples either way, searched over
    /// windows of `window` rows (holds `window + 2 max` rows and a window;
    /// nothing for `max = 0`, the search off).
    pub fn new(max: usize, window: usize) -> Self {
        let (cap, scratch) = if max == 0 {
            (0, 1)
        } else {
            (window + 2 * max, window)
        };
        DelayLine {
            rows: Rows {
                rows: alloc::vec![RawRow::default(); cap],
                head: 0,
                len: 0,
            },
            scratch: Ring::new(scratch),
            curve: alloc::vec![f64::INFINITY; 2 * max + 1],
            max,
            delay: 0,
        }
    }

    /// The offset in use (samples; positive: the shank lags).
    pub fn delay(&self) -> isize {
        self.delay
    }

    /// The largest offset searched (samples).
    pub fn max(&self) -> usize {
        self.max
    }

    /// Forgets every row and the offset.
    pub fn clear(&mut self) {
        self.rows.head = 0;
        self.rows.len = 0;
        self.delay = 0;
    }

    /// Appends the thigh and shank readings of a row.
    pub fn push(&mut self, s: &Sample) {
        let r = &mut self.rows;
        let cap = r.rows.len();
        if cap == 0 {
            return;
        }
        let idx = (r.head + r.len) % cap;
        r.rows[idx] = RawRow {
            t: s.t,
            imu: [*s.imu(Segment::Thigh), *s.imu(Segment::Shank)],
        };
        if r.len < cap {
            r.len += 1;
        } else {
            r.head = (r.head + 1) % cap;
        }
    }

    /// The time and the thigh and shank readings paired by the offset in
    /// use, `back` rows before the newest: the stream that runs ahead is
    /// taken `|d|` rows back, the time is the other stream's row's. `None`
    /// when those rows are not held.
    pub fn paired(&self, back: usize) -> Option<(f64, [ImuSample; 2])> {
        self.rows
            .pair(back + self.delay.max(0) as usize, self.delay)
    }

    /// Mean time step over the rows held (s; `None` with fewer than two).
    pub fn period(&self) -> Option<f64> {
        let n = self.rows.len;
        let (new, old) = (self.rows.get(0)?, self.rows.get(n.checked_sub(1)?)?);
        (n > 1).then(|| (new.t - old.t) / (n - 1) as f64)
    }

    /// Fits eq 3 ([`fit_positions`], no previous geometry: its lifted
    /// least-squares start) for every offset in `-max..=max` over the thigh
    /// rows `max..max + window` back (those whose shank partner is held for
    /// every offset). `None` when the search is off, too few rows are held,
    /// or no offset could be fitted.
    pub fn search(&mut self, p: &KneeSelfAlignParams) -> Option<DelaySearch> {
        let max = self.max;
        if max == 0 || self.rows.len < 2 * max + 5 {
            return None;
        }
        let n = p.window.min(self.rows.len - 2 * max);
        let scratch = &mut self.scratch;
        let mut best: Option<(isize, f64)> = None;
        let mut current = None;
        self.curve.fill(f64::INFINITY);
        for d in -(max as isize)..=max as isize {
            scratch.clear();
            for back in (max..max + n).rev() {
                if let Some((t, imu)) = self.rows.pair(back, d) {
                    scratch.push(slot(t, &imu, p.gyro_range));
                }
            }
            let Ok(fit) = fit_positions(scratch, None, p) else {
                continue;
            };
            self.curve[(d + max as isize) as usize] = fit.rms;
            if d == self.delay {
                current = Some(fit.rms);
            }
            if best.is_none_or(|(_, b)| fit.rms < b) {
                best = Some((d, fit.rms));
            }
        }
        let (best, rms_best) = best?;
        let i = (best + max as isize) as usize;
        let rms_neighbours = if i == 0 || i == 2 * max {
            f64::INFINITY
        } else {
            self.curve[i - 1].max(self.curve[i + 1])
        };
        Some(DelaySearch {
            best,
            rms_best,
            rms_current: current.unwrap_or(f64::INFINITY),
            rms_neighbours,
        })
    }

    /// Takes the search's best offset when it is a sharp minimum inside
    /// the range ([`SHARPNESS`]) that fits clearly better than the offset in
    /// use ([`ADOPT_RATIO`]); true when the offset changed.
    pub fn adopt(&mut self, s: &DelaySearch) -> bool {
        if s.best != self.delay
            && s.rms_best < ADOPT_RATIO * s.rms_current
            && s.rms_best <= SHARPNESS * s.rms_neighbours
        {
            self.delay = s.best;
            true
        } else {
            false
        }
    }
}

impl super::KneeSelfAlign {
    /// This sample's thigh and shank readings paired by the offset in use
    /// (this module; the input's own with the search off or no offset found).
    /// Before the sample that ends a window, the offset is searched over
    /// the window; a new offset re-pairs the samples of the window and of
    /// the rate derivative.
    pub(super) fn align(&mut self, sample: &Sample) -> [ImuSample; 2] {
        let raw = [*sample.imu(Segment::Thigh), *sample.imu(Segment::Shank)];
        if self.delay.max() == 0 {
            return raw;
        }
        self.delay.push(sample);
        if self.counter + 1 >= self.params.window && !self.fixed {
            let found = self.delay.search(&self.params);
            if found.is_some_and(|s| self.delay.adopt(&s)) {
                let range = self.params.gyro_range;
                for ring in [&mut self.window, &mut self.recent] {
                    let n = ring.len();
                    ring.clear();
                    for back in (1..=n).rev() {
                        if let Some((t, imu)) = self.delay.paired(back) {
                            ring.push(slot(t, &imu, range));
                        }
                    }
                }
            }
        }
        self.delay.paired(0).map_or(raw, |(_, imu)| imu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use limbfuse_core::Sample;

    /// A planar two-link leg (hip fixed, sensors on the segments' long
    /// axes, frames aligned with the segments), computed in closed form with
    /// central differences; the shank's readings `late` rows late.
    fn leg(rows: usize, late: usize) -> alloc::vec::Vec<Sample> {
        let dt = 0.01;
        let (len, r1, r2) = (0.43, 0.2, 0.2);
        let theta = |t: f64| {
            let th = 0.4 * libm::sin(core::f64::consts::TAU * t);
            let knee = 0.5 * (1.0 - libm::cos(core::f64::consts::TAU * t + 0.7));
            [th, th - knee]
        };
        let pos = |t: f64| {
            let [a, b] = theta(t);
            let down = |x: f64| Vector3::new(libm::sin(x), -libm::cos(x), 0.0);
            [down(a) * r1, down(a) * len + down(b) * r2]
        };
        let h = 1e-4;
        let reading = |t: f64, seg: usize| {
            let acc = (pos(t + h)[seg] - 2.0 * pos(t)[seg] + pos(t - h)[seg]) / (h * h);
            let f = acc + Vector3::new(0.0, 9.81, 0.0);
            let a = theta(t)[seg];
            let rate = (theta(t + h)[seg] - theta(t - h)[seg]) / (2.0 * h);
            let (s, c) = (libm::sin(a), libm::cos(a));
            let f_sensor = Vector3::new(c * f.x + s * f.y, -s * f.x + c * f.y, 0.0);
            ImuSample {
                acc: Some(f_sensor),
                gyr: Some(Vector3::new(0.0, 0.0, rate)),
                ..Default::default()
            }
        };
        (0..rows)
            .map(|k| {
                let t = k as f64 * dt;
                let mut s = Sample::empty(t);
                s.imu[Segment::Thigh.index()] = reading(t, 0);
                if k >= late {
                    s.imu[Segment::Shank.index()] = reading(t - late as f64 * dt, 1);
                }
                s
            })
            .collect()
    }

    fn params() -> KneeSelfAlignParams {
        KneeSelfAlignParams {
            window: 400,
            max_delay: 5,
            ..KneeSelfAlignParams::default()
        }
    }

    #[test]
    fn the_search_finds_the_offset_the_leg_was_built_with() {
        for late in [0usize, 1, 3] {
            let mut line = DelayLine::new(5, 400);
            for s in leg(500, late) {
                line.push(&s);
            }
            let found = line.search(&params()).unwrap();
            assert_eq!(found.best, late as isize, "{found:?}");
            assert!(
                found.rms_best <= SHARPNESS * found.rms_neighbours,
                "{found:?}"
            );
            assert_eq!(line.adopt(&found), late != 0);
            assert_eq!(line.delay(), late as isize);
        }
    }

    #[test]
    fn the_stream_that_runs_ahead_is_taken_back_by_the_offset() {
        let rows = leg(20, 0);
        let mut line = DelayLine::new(3, 40);
        for s in &rows {
            line.push(s);
        }
        let at = |k: usize, seg: Segment| rows[k].imu(seg).gyr;
        // Shank late by 2: this row's shank with the thigh of 2 rows back.
        line.delay = 2;
        let (t, [thigh, shank]) = line.paired(0).unwrap();
        assert_eq!(
            (t, thigh.gyr, shank.gyr),
            (rows[19].t, at(17, Segment::Thigh), at(19, Segment::Shank))
        );
        // Thigh late by 2 (offset -2): this row's thigh, the shank 2 back.
        line.delay = -2;
        let (t, [thigh, shank]) = line.paired(1).unwrap();
        assert_eq!(
            (t, thigh.gyr, shank.gyr),
            (rows[18].t, at(18, Segment::Thigh), at(16, Segment::Shank))
        );
        assert!(line.paired(18).is_none());
        assert!((line.period().unwrap() - 0.01).abs() < 1e-12);
    }

    #[test]
    fn a_bad_max_delay_is_named() {
        let e = KneeSelfAlignParams {
            window: 100,
            max_delay: 26,
            ..KneeSelfAlignParams::default()
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.name, "max_delay");
    }
}
