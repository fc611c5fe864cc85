//! What a trial file holds, read once (`limbfuse inspect`): its time base
//! (duration, sample step, gaps), the share of missing readings per input
//! group, and the unit checks `estimate` makes
//! ([`crate::sample_interval`], [`crate::sensor_units`]) and whether the
//! thigh moves ([`crate::fixed_thigh`]). Which methods
//! can run on it is `limbfuse-methods::availability` (it needs the method
//! registry). Memory does not grow with the trial: the steps are held only
//! until the median of the first ones is known.

use limbfuse_core::runner::Observer;
use limbfuse_core::{Estimate, Record, Segment};
use limbfuse_io::{FileError, TrialLayout, TrialReader};

use crate::acc_rails::AccRailWatch;
use crate::fixed_thigh::FixedThighWatch;
use crate::sample_interval::{IntervalMismatch, SampleIntervalWatch, FIRST_INTERVALS};
use crate::sensor_units::{SensorUnitsWatch, UnitSuspect};

/// A step longer than this many median steps is a gap (a dropped sample
/// at the least: 2 steps; jitter stays well below). `limbfuse report` uses
/// the same rule.
pub const GAP_STEPS: f64 = 1.5;

/// The inputs a trial holds and how many of its rows miss each.
#[derive(Debug, Clone, PartialEq)]
pub struct InputGroup {
    /// Name, e.g. `thigh gyr`, `foot_left acc`, `knee_enc`, `com_meas`.
    pub name: String,
    /// Rows without a complete reading of the group.
    pub missing_rows: u64,
}

/// A trial's time base, inputs and unit checks.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialSummary {
    /// Data rows.
    pub rows: u64,
    /// First and last `t` (s).
    pub span: Option<(f64, f64)>,
    /// Median step of the first samples (s), see [`SampleIntervalWatch`].
    pub median_step: Option<f64>,
    /// The rate the metadata states (`# sample_rate_hz:`).
    pub stated_hz: Option<f64>,
    /// Steps longer than 1.5 median steps.
    pub gaps: u64,
    /// The longest step: where it starts (s) and its length (s).
    pub longest_step: Option<(f64, f64)>,
    /// The input groups the layout has, in SPEC order.
    pub inputs: Vec<InputGroup>,
    /// The time column does not look like seconds.
    pub interval: Option<IntervalMismatch>,
    /// IMU readings that do not look like m/s^2 or rad/s.
    pub units: Vec<UnitSuspect>,
    /// Both as `estimate` words them ([`crate::unit_warnings`]).
    pub warnings: Vec<String>,
    /// The angular deviation (deg) of the thigh accelerometer's direction
    /// ([`FixedThighWatch`]): whether the thigh moves.
    pub thigh_spread_deg: Option<f64>,
}

/// Reads every row of `reader` and summarises the trial.
pub fn summarise(reader: &mut TrialReader) -> Result<TrialSummary, FileError> {
    let layout = *reader.layout();
    let mut intervals = SampleIntervalWatch::for_trial(reader.meta());
    let stated_hz = intervals.stated_hz();
    let mut units = SensorUnitsWatch::default();
    let mut thigh = FixedThighWatch::default();
    // (a range that is not a number is `estimate`'s error to report; here
    // the default full scale)
    let mut rails = {
        let meta = reader.meta();
        let full_scale = meta
            .sensor_ranges()
            .ok()
            .and_then(|r| r.acc_full_scale_m_s2)
            .unwrap_or(f64::INFINITY);
        AccRailWatch::new(
            full_scale,
            meta.get(limbfuse_io::meta::ACC_RANGE_KEY).is_some(),
        )
    };
    let groups = input_groups(&layout);
    let mut missing = vec![0u64; groups.len()];
    // The first steps wait for the median; later ones are counted at once.
    let mut early: Vec<(f64, f64)> = Vec::with_capacity(FIRST_INTERVALS);
    let mut gaps = GapCount::default();
    let mut median: Option<f64> = None;
    let mut span: Option<(f64, f64)> = None;
    let mut rows = 0u64;
    let mut rec = Record::default();
    let none = Estimate::empty(0.0);
    while reader.read_into(&mut rec)? {
        let t = rec.sample.t;
        if let Some((_, last)) = span {
            let step = (last, t - last);
            if early.len() == FIRST_INTERVALS && median.is_none() {
                // (the watch has seen exactly these steps: its median is final)
                median = intervals.median_step();
            }
            match median {
                Some(m) => gaps.add(step, m),
                None => early.push(step),
            }
        }
        span = Some((span.map_or(t, |s| s.0), t));
        rows += 1;
        // (the watches never fail)
        let _ = intervals.observe(&rec, &none);
        let _ = units.observe(&rec, &none);
        let _ = thigh.observe(&rec, &none);
        let _ = rails.observe(&rec, &none);
        for ((_, has), m) in groups.iter().zip(missing.iter_mut()) {
            *m += u64::from(!has(&rec));
        }
    }
    let median_step = intervals.median_step();
    if let Some(m) = median_step {
        for step in early {
            gaps.add(step, m);
        }
    }
    let GapCount {
        count: gaps,
        longest: longest_step,
    } = gaps;
    Ok(TrialSummary {
        rows,
        span,
        median_step,
        stated_hz,
        gaps,
        longest_step,
        inputs: groups
            .into_iter()
            .zip(missing)
            .map(|((name, _), missing_rows)| InputGroup { name, missing_rows })
            .collect(),
        interval: intervals.mismatch(),
        units: units.suspects().collect(),
        warnings: crate::unit_warnings(&intervals, &units)
            .chain(rails.rails().map(|r| r.to_string()))
            .chain(reader.cut_last_line().map(|c| c.message(reader.path())))
            .collect(),
        thigh_spread_deg: thigh.spread_deg(),
    })
}

/// Steps over [`GAP_STEPS`] median steps, and the longest step.
#[derive(Debug, Default)]
struct GapCount {
    count: u64,
    longest: Option<(f64, f64)>,
}

impl GapCount {
    fn add(&mut self, step: (f64, f64), median: f64) {
        self.count += u64::from(step.1 > GAP_STEPS * median);
        if self.longest.is_none_or(|l| step.1 > l.1) {
            self.longest = Some(step);
        }
    }
}

/// Whether a record holds a group's reading.
type Has = Box<dyn Fn(&Record) -> bool>;

/// The input groups of a layout with their tests, in SPEC order: each
/// IMU's accelerometer and gyroscope (this leg, then the other), encoders,
/// CoM measurements, stimulation.
fn input_groups(layout: &TrialLayout) -> Vec<(String, Has)> {
    let mut out: Vec<(String, Has)> = Vec::new();
    let other = layout.other_leg();
    for s in Segment::ALL {
        let i = s.index();
        let name = s.name();
        if layout.acc[i] {
            out.push((
                format!("{name} acc"),
                Box::new(move |r| r.sample.imu[i].acc.is_some()),
            ));
        }
        if layout.gyr[i] {
            out.push((
                format!("{name} gyr"),
                Box::new(move |r| r.sample.imu[i].gyr.is_some()),
            ));
        }
    }
    for s in Segment::ALL {
        let i = s.index();
        let prefix = limbfuse_io::layout::other_leg_prefix(s, other);
        let name = prefix.trim_end_matches('_');
        if layout.other_acc[i] {
            out.push((
                format!("{name} acc"),
                Box::new(move |r| r.sample.other_leg_imu[i].acc.is_some()),
            ));
        }
        if layout.other_gyr[i] {
            out.push((
                format!("{name} gyr"),
                Box::new(move |r| r.sample.other_leg_imu[i].gyr.is_some()),
            ));
        }
    }
    for (j, name) in ["hip_enc", "knee_enc", "ankle_enc"].into_iter().enumerate() {
        if layout.encoder[j] {
            out.push((
                name.into(),
                Box::new(move |r| r.sample.encoder[j].is_some()),
            ));
        }
    }
    if layout.com_meas.iter().any(|c| *c) {
        let cols = layout.com_meas;
        out.push((
            "com_meas".into(),
            Box::new(move |r| {
                r.sample
                    .com
                    .values()
                    .iter()
                    .zip(cols)
                    .all(|(v, has)| !has || v.is_some())
            }),
        ));
    }
    for (k, name) in ["u_ke", "u_kf", "u_he", "u_hf"].into_iter().enumerate() {
        if layout.stim[k] {
            out.push((
                name.into(),
                Box::new(move |r| r.sample.inputs.stim[k].is_some()),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 100 rows at 100 Hz with a 0.05 s step among the first 64 (held until
    /// the median is known) and a 0.1 s one after them; the knee encoder
    /// empty on 3 rows.
    #[test]
    fn gaps_before_and_after_the_median_is_known_and_missing_rows() {
        let mut text = String::from("# sample_rate_hz: 100\nt,knee_enc\n");
        let mut t = 0.0;
        for k in 0..100 {
            t += match k {
                10 => 0.05,
                80 => 0.1,
                0 => 0.0,
                _ => 0.01,
            };
            let knee = if (20..23).contains(&k) {
                String::new()
            } else {
                "0.1".into()
            };
            text += &format!("{t},{knee}\n");
        }
        let mut r = TrialReader::from_reader(
            std::path::Path::new("s.csv"),
            Box::new(std::io::Cursor::new(text.into_bytes())),
        )
        .unwrap();
        let s = summarise(&mut r).unwrap();
        assert_eq!(s.rows, 100);
        assert!((s.median_step.unwrap() - 0.01).abs() < 1e-9);
        assert_eq!(s.stated_hz, Some(100.0));
        assert_eq!(s.gaps, 2);
        let (at, len) = s.longest_step.unwrap();
        assert!(
            (len - 0.1).abs() < 1e-9 && (at - 0.83).abs() < 1e-9,
            "{at} {len}"
        );
        assert_eq!(
            s.inputs,
            vec![InputGroup {
                name: "knee_enc".into(),
                missing_rows: 3
            }]
        );
        assert!(s.warnings.is_empty() && s.interval.is_none() && s.units.is_empty());
    }
}
