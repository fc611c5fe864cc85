//! The robotic knee rig (`Trial_NN.csv`): two MPU6050 (sensor 1 thigh,
//! sensor 2 shank) and the knee angle derived from the knee stepper, logged at
//! 250 Hz with `Missed Packet(s)` lines for dropouts. See `docs/IMPORTERS.md`.

use std::path::Path;

use limbfuse_core::{Joint, Record, Sample, Segment};
use nalgebra::Vector3;

use super::{fmt, median, read_lines, split_cells, Header, ImportError, ImportedTrial};
use crate::layout::TrialLayout;
use crate::meta::TrialMeta;

/// g used to convert the accelerometer (g -> m/s^2), as SPEC section 1.
const G: f64 = limbfuse_core::STANDARD_GRAVITY;

/// Options of [`import_knee_rig_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeRigOptions {
    /// A `TIME` step within `gap_tolerance * interval` of `k * interval`
    /// (k >= 2) is a dropout of k - 1 samples.
    pub gap_tolerance: f64,
    /// Gaps longer than this (s) are kept as gaps in `t` instead of being
    /// filled with missing rows (bounds memory on corrupt files).
    pub max_filled_gap_s: f64,
}

impl Default for KneeRigOptions {
    fn default() -> Self {
        KneeRigOptions {
            gap_tolerance: 0.25,
            max_filled_gap_s: 1.0,
        }
    }
}

/// The median step (us) of the first rows' `TIME` cells (up to 1000
/// steps; `Missed Packet` lines and cells that do not parse are left to the
/// import's own errors), or `None` with fewer than two times.
fn median_time_step<'a>(
    rows: impl Iterator<Item = &'a (u64, String)>,
    time_col: usize,
) -> Option<f64> {
    let mut times = Vec::new();
    for (_, text) in rows {
        if times.len() > 1000 {
            break;
        }
        if text.trim().is_empty() || is_missed_packet(text) {
            continue;
        }
        if let Some(t) = split_cells(text)
            .get(time_col)
            .and_then(|c| c.trim().parse::<f64>().ok())
        {
            times.push(t);
        }
    }
    let steps: Vec<f64> = times
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    median(&steps)
}

/// Imports a knee-rig trial with default options.
pub fn import_knee_rig(file: &Path) -> Result<ImportedTrial, ImportError> {
    import_knee_rig_with(file, &KneeRigOptions::default())
}

fn is_missed_packet(text: &str) -> bool {
    text.trim()
        .to_ascii_lowercase()
        .starts_with("missed packet")
}

/// Imports a knee-rig trial: thigh/shank gyro (deg/s -> rad/s) and acc (g ->
/// m/s^2, calibration kept), `knee_ref` (deg -> rad, flexion positive), `t`
/// from `TIME` (microseconds, relative to the first sample), dropouts as rows
/// with every channel `None`.
pub fn import_knee_rig_with(
    file: &Path,
    opts: &KneeRigOptions,
) -> Result<ImportedTrial, ImportError> {
    let lines = read_lines(file)?;
    let expected_layout = "`LOG INTERVAL,<n>,microseconds` and other metadata lines, then a header row `TRANSFER #,TIME,TIME DELTA,G1X,...,ABS KNEE ANGLE,...`";
    if lines.iter().all(|(_, l)| l.trim().is_empty()) {
        return Err(ImportError::line(
            file,
            lines.len().max(1) as u64,
            "the file is empty",
            expected_layout,
        ));
    }
    let mut meta = TrialMeta::trial_v1();
    let mut rig_meta = Vec::new();
    let mut interval_us: Option<f64> = None;
    let mut interval_line = 0u64;
    let mut leading_missed = 0usize;
    let mut rest = lines.iter();
    let mut header = None;
    for (n, text) in rest.by_ref() {
        let cells = split_cells(text);
        if text.trim().is_empty() {
            continue;
        } else if is_missed_packet(text) {
            leading_missed += 1;
        } else if cells.contains(&"TIME") {
            header = Some(Header::new(file, *n, text));
            break;
        } else if cells[0].eq_ignore_ascii_case("LOG INTERVAL") {
            let value = cells.get(1).copied().unwrap_or("");
            let unit = cells.get(2).copied().unwrap_or("");
            let bad = |col: usize, found: &str| ImportError::Cell {
                path: file.to_path_buf(),
                line: *n,
                column: col,
                name: "LOG INTERVAL".into(),
                expected: "`LOG INTERVAL,<1 to 1e9>,microseconds`".into(),
                found: format!("`{found}`"),
            };
            match value.parse::<f64>() {
                Ok(v) if (1.0..=1e9).contains(&v) => {
                    interval_us = Some(v);
                    interval_line = *n;
                }
                _ => return Err(bad(2, value)),
            }
            if !unit.eq_ignore_ascii_case("microseconds") {
                return Err(bad(3, unit));
            }
        } else {
            let key: String = cells[0]
                .to_ascii_lowercase()
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            rig_meta.push((format!("rig_{key}"), cells[1..].join(" ")));
        }
    }
    let last_line = lines.last().map_or(1, |(n, _)| *n);
    let Some(h) = header else {
        return Err(ImportError::line(
            file,
            last_line,
            "no header row (a row with a `TIME` column)",
            expected_layout,
        ));
    };
    let Some(interval_us) = interval_us else {
        return Err(ImportError::line(
            file,
            h.line,
            "no `LOG INTERVAL` line before the header",
            "`LOG INTERVAL,<n>,microseconds` giving the sample interval",
        ));
    };

    let col = |name: &str| h.require(name, "knee-rig columns TIME, G1X..A2Z, ABS KNEE ANGLE");
    let time_col = col("TIME")?;
    let names = [
        "G1X", "G1Y", "G1Z", "A1X", "A1Y", "A1Z", "G2X", "G2Y", "G2Z", "A2X", "A2Y", "A2Z",
    ];
    let mut sensor_cols = [0usize; 12];
    for (c, name) in sensor_cols.iter_mut().zip(names) {
        *c = col(name)?;
    }
    let knee_col = col("ABS KNEE ANGLE")?;
    let needed = sensor_cols
        .iter()
        .copied()
        .chain([time_col, knee_col])
        .max()
        .unwrap_or(0);

    // The stated interval against the TIME column (an audit: `LOG
    // INTERVAL,1` on a 4000 us log filled 52 001 rows from 14, at 1 MHz).
    if let Some(step) = median_time_step(rest.clone(), time_col) {
        if (step - interval_us).abs() > opts.gap_tolerance * interval_us {
            return Err(ImportError::line(
                file,
                interval_line,
                format!(
                    "`LOG INTERVAL` says {interval_us} us, but the TIME column steps by {step} us \
                     (median of its first steps)"
                ),
                "the interval the TIME column is logged at",
            ));
        }
    }
    let interval_s = interval_us * 1e-6;
    let max_fill = (opts.max_filled_gap_s / interval_s).floor().clamp(0.0, 1e6) as u64;
    let mut records: Vec<Record> = Vec::new();
    let (mut missed_lines, mut missed_without_gap, mut pending_missed) = (0usize, 0usize, false);
    let (mut inserted, mut irregular, mut long_gaps) = (0u64, 0usize, 0usize);
    let mut first: Option<f64> = None;
    let mut previous: Option<(f64, u64)> = None;
    let (mut norm_thigh, mut norm_shank) = (Vec::new(), Vec::new());
    for (n, text) in rest {
        if text.trim().is_empty() {
            continue;
        }
        if is_missed_packet(text) {
            if records.is_empty() {
                leading_missed += 1;
            } else {
                missed_lines += 1;
                pending_missed = true;
            }
            continue;
        }
        let cells = h.cells(*n, text, needed)?;
        let time = h
            .number(*n, &cells, time_col, false)?
            .ok_or_else(|| h.bad_cell(*n, time_col, "", "TIME in microseconds"))?;
        let t0 = *first.get_or_insert(time);
        if let Some((prev, prev_line)) = previous {
            if time <= prev {
                return Err(h.bad_cell(
                    *n,
                    time_col,
                    cells[time_col],
                    format!("a TIME after {prev} us (line {prev_line}): time must increase"),
                ));
            }
            let dt = time - prev;
            let k = (dt / interval_us).round();
            let on_grid =
                k.is_finite() && (dt - k * interval_us).abs() <= opts.gap_tolerance * interval_us;
            if k >= 2.0 && on_grid && (k as u64 - 1) <= max_fill {
                let t_prev = (prev - t0) * 1e-6;
                for j in 1..k as u64 {
                    records.push(Record {
                        sample: Sample::empty(t_prev + j as f64 * interval_s),
                        ..Default::default()
                    });
                }
                inserted += k as u64 - 1;
                pending_missed = false;
            } else if k >= 2.0 && on_grid {
                long_gaps += 1;
            } else if !(k == 1.0 && on_grid) {
                irregular += 1;
            }
        }
        if pending_missed {
            missed_without_gap += 1;
            pending_missed = false;
        }
        previous = Some((time, *n));

        let mut v = [None; 12];
        for (o, &c) in v.iter_mut().zip(&sensor_cols) {
            *o = h.number(*n, &cells, c, false)?;
        }
        let vec3 = |i: usize, scale: f64| Some(Vector3::new(v[i]?, v[i + 1]?, v[i + 2]?) * scale);
        let t = (time - t0) * 1e-6;
        if records.last().is_some_and(|r| r.sample.t >= t) {
            let what = "TIME values small enough to resolve 1 us steps";
            return Err(h.bad_cell(*n, time_col, cells[time_col], what));
        }
        let mut r = Record {
            sample: Sample::empty(t),
            ..Default::default()
        };
        let (thigh, shank) = (Segment::Thigh.index(), Segment::Shank.index());
        r.sample.imu[thigh].gyr = vec3(0, 1f64.to_radians());
        r.sample.imu[thigh].acc = vec3(3, G);
        r.sample.imu[shank].gyr = vec3(6, 1f64.to_radians());
        r.sample.imu[shank].acc = vec3(9, G);
        norm_thigh.extend(r.sample.imu[thigh].acc.map(|a| a.norm() / G));
        norm_shank.extend(r.sample.imu[shank].acc.map(|a| a.norm() / G));
        r.reference.joint[Joint::Knee.index()] =
            h.number(*n, &cells, knee_col, false)?.map(f64::to_radians);
        records.push(r);
    }
    if records.is_empty() {
        return Err(ImportError::line(
            file,
            last_line,
            "no data rows",
            "at least one sample row after the header",
        ));
    }

    let mut layout = TrialLayout::default();
    for s in [Segment::Thigh, Segment::Shank] {
        layout.acc[s.index()] = true;
        layout.gyr[s.index()] = true;
    }
    layout.joint_ref[Joint::Knee.index()] = true;

    meta.set(
        "source",
        format!(
            "knee rig (KneeAngleAlgorithmComparison, 250 Hz test data) {}",
            file.display()
        ),
    );
    meta.set(
        "sample_rate_hz",
        fmt(1e6 / interval_us, 3)
            .trim_end_matches('0')
            .trim_end_matches('.'),
    );
    meta.set("leg", "right");
    meta.set("g", "9.81");
    meta.set(
        "segment_map",
        "thigh=sensor 1 (G1*, A1*), shank=sensor 2 (G2*, A2*); the rig has no trunk or foot",
    );
    meta.set(
        "units",
        "gyr deg/s -> rad/s (x pi/180); acc g -> m/s^2 (x 9.81, sensor calibration kept as recorded); ABS KNEE ANGLE deg -> rad",
    );
    meta.set("imu_frame", "raw sensor frames (unaligned)");
    let med = |v: &[f64]| median(v).map_or("n/a".to_string(), |m| fmt(m, 3));
    meta.set("thigh_acc_norm_median_g", med(&norm_thigh));
    meta.set("shank_acc_norm_median_g", med(&norm_shank));
    meta.set(
        "knee_ref_sign",
        "+1: ABS KNEE ANGLE is 0 with the knee straight (KNEE_CENTER_POS) and grows in flexion, so knee_ref = +ABS KNEE ANGLE (flexion positive)",
    );
    meta.set(
        "knee_ref_note",
        "commanded stepper angle, only approximately the real knee angle (belt slop)",
    );
    meta.set(
        "time_base",
        format!(
            "t = (TIME - first TIME) / 1e6; interval {interval_us} us; TIME DELTA ignored; steps within {} of k intervals (k >= 2) filled with k - 1 missing rows",
            opts.gap_tolerance
        ),
    );
    meta.set("missed_packet_lines", missed_lines);
    meta.set("missed_packet_lines_before_first_sample", leading_missed);
    meta.set("missed_packet_lines_without_gap", missed_without_gap);
    meta.set("inserted_missing_rows", inserted);
    meta.set("irregular_intervals", irregular);
    meta.set("long_gaps_kept", long_gaps);
    for (k, v) in rig_meta {
        meta.set(k, v);
    }
    meta.set(
        "not_imported",
        "TRANSFER #, TIME DELTA, HIP STEPPER, KNEE STEPPER, GAIT STAGE, IMPULSE HIT",
    );
    Ok(ImportedTrial {
        meta,
        layout,
        records,
    })
}
