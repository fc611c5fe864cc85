//! The paper segment filters started, or restarted, mid-walk
//! (docs/RESULTS.md, "The paper filters started mid-walk (2026-12-06)";
//! docs/SEGMENT_FILTERS.md, "Initialisation"). Before 2026-12-06 each
//! segment started at its first accelerometer sample, tens of degrees off
//! when the limb accelerates: `mjls` on walk-v1.2-s301 began 73 deg off. Each
//! test runs the filter with the default start and with the old one
//! (`first_sample_start`), prints both, and asserts the default's bound; the
//! old start's figures are in each test's comment. Skipped with a message
//! when `../shared/data` is absent (`LIMBFUSE_DATA` overrides the path).

use crate::shared_data_support::{data_dir, read};
use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::segment_kf::{
    CommonParams, GlobalKf, GlobalKfParams, LocalKf, LocalKfParams, MarkovJumpKf,
    MarkovJumpKfParams,
};

const TRIAL: &str = "independent-sim/walk-v1.2-s301.csv";

fn filter(method: &str, first_sample_start: bool) -> Box<dyn Estimator> {
    let common = CommonParams {
        first_sample_start,
        ..CommonParams::default()
    };
    match method {
        "mjls" => Box::new(
            MarkovJumpKf::new(MarkovJumpKfParams {
                common,
                ..MarkovJumpKfParams::default()
            })
            .unwrap(),
        ),
        "global" => Box::new(
            GlobalKf::new(GlobalKfParams {
                common,
                ..GlobalKfParams::default()
            })
            .unwrap(),
        ),
        _ => Box::new(
            LocalKf::new(LocalKfParams {
                common,
                ..LocalKfParams::default()
            })
            .unwrap(),
        ),
    }
}

/// Segment angles per record; the filter is `reset()` before record `reset_at`.
fn run(
    f: &mut dyn Estimator,
    records: &[Record],
    reset_at: Option<usize>,
) -> Vec<[Option<f64>; 4]> {
    records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            if reset_at == Some(k) {
                f.reset();
            }
            f.step(&r.sample).unwrap().segment
        })
        .collect()
}

/// Each segment's mean error (rad) over t >= 10 s: the filter's own steady offset.
fn steady_offset(records: &[Record], est: &[[Option<f64>; 4]]) -> [f64; 4] {
    core::array::from_fn(|i| {
        let e: Vec<f64> = records
            .iter()
            .zip(est)
            .filter(|(r, _)| r.sample.t >= 10.0)
            .filter_map(|(r, e)| Some(e[i]? - r.reference.segment[i]?))
            .collect();
        e.iter().sum::<f64>() / e.len() as f64
    })
}

/// Largest |estimate - reference - offset| (deg) of any segment over the
/// first 3 s from record `from` on.
fn peak_deg(records: &[Record], est: &[[Option<f64>; 4]], from: usize, off: &[f64; 4]) -> f64 {
    let t0 = records[from].sample.t;
    let mut peak = 0.0f64;
    for (r, e) in records[from..].iter().zip(&est[from..]) {
        if r.sample.t - t0 > 3.0 {
            break;
        }
        for i in 0..4 {
            if let (Some(x), Some(y)) = (e[i], r.reference.segment[i]) {
                peak = peak.max((x - y - off[i]).abs().to_degrees());
            }
        }
    }
    peak
}

/// Peak error over the first 3 s of the three filters on `records[cut..]`
/// (default start, old start), offsets from the uncut default run.
fn cut_peaks(records: &[Record], cut: usize) -> Vec<(&'static str, f64, f64)> {
    ["mjls", "global", "local"]
        .into_iter()
        .map(|m| {
            let off = steady_offset(records, &run(filter(m, false).as_mut(), records, None));
            let part = &records[cut..];
            let new = peak_deg(part, &run(filter(m, false).as_mut(), part, None), 0, &off);
            let old = peak_deg(part, &run(filter(m, true).as_mut(), part, None), 0, &off);
            println!(
                "{m}: start at {:.2} s, peak {new:.1} deg (first-sample start: {old:.1})",
                part[0].sample.t
            );
            (m, new, old)
        })
        .collect()
}

#[test]
fn segment_filters_started_at_the_first_row_of_a_mid_walk_recording_stay_near_their_steady_state() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    let records = read(&dir.join(TRIAL));
    // measured 2026-12-06: mjls 5.4 deg, global 18.6, local 17.6 (their
    // steady offsets on this walk are up to 11 deg: a start near the truth
    // counts as that far off); first-sample start: 73.6 / 75.8 / 74.8.
    for (m, new, _old) in cut_peaks(&records, 0) {
        let bound = if m == "mjls" { 10.0 } else { 25.0 };
        assert!(new < bound, "{m}: {new:.1} deg over the first 3 s");
    }
}

#[test]
fn segment_filters_started_anywhere_in_two_strides_stay_near_their_steady_state() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    let records = read(&dir.join(TRIAL));
    // starts every 0.1 s over two strides (2 x 1.13 s); median / max of the
    // peaks measured 2026-12-06: mjls 4.5 / 8.8 deg, global 11.7 / 21.8,
    // local 12.9 / 20.1; first-sample start 16.4 / 73.4, 52.1 / 78.4,
    // 52.7 / 79.4 (segment_start_study).
    let mut peaks: [Vec<f64>; 3] = Default::default();
    for cut in (0..23).map(|j| j * 10) {
        for (k, (_, new, _)) in cut_peaks(&records, cut).into_iter().enumerate() {
            peaks[k].push(new);
        }
    }
    for (k, m) in ["mjls", "global", "local"].iter().enumerate() {
        let p = &mut peaks[k];
        p.sort_by(f64::total_cmp);
        let (median, max) = (p[p.len() / 2], p[p.len() - 1]);
        let (bm, bx) = if *m == "mjls" {
            (8.0, 15.0)
        } else {
            (16.0, 30.0)
        };
        assert!(
            median < bm && max < bx,
            "{m}: peaks median {median:.1}, max {max:.1} deg"
        );
    }
}

#[test]
fn global_reset_mid_stride_restarts_near_the_uncut_run() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    let records = read(&dir.join(TRIAL));
    let at = records.iter().position(|r| r.sample.t >= 20.3).unwrap();
    let clean = run(filter("global", false).as_mut(), &records, None);
    let off = steady_offset(&records, &clean);
    let new = peak_deg(
        &records,
        &run(filter("global", false).as_mut(), &records, Some(at)),
        at,
        &off,
    );
    let old = peak_deg(
        &records,
        &run(filter("global", true).as_mut(), &records, Some(at)),
        at,
        &off,
    );
    println!("global reset at 20.3 s: peak {new:.1} deg over 3 s (first-sample start: {old:.1})");
    // measured 2026-12-06: 16.2 deg; first-sample start 48.7
    assert!(new < 25.0, "{new:.1} deg over the 3 s after the reset");
}

/// The first record at which segment `i` has an estimate.
fn first_row(est: &[[Option<f64>; 4]], i: usize) -> Option<usize> {
    est.iter().position(|e| e[i].is_some())
}

/// A missing accelerometer axis broke the quasi-static hold (found
/// 2026-12-06 with 20 % of the IMU cells of the shared walks missing:
/// `mjls` then started from the 2 s window or a late lucky hold, 1.7-2.0 s
/// in, and carried that start's common offset, worst seed 0.82 deg
/// against 0.57 clean). A sample without its vector is no evidence either
/// way: the hold goes on through it. Here every third sample lacks the x
/// axis of all four accelerometers, so no six complete samples ever
/// follow each other: before the fix every filter waited for its window
/// (first estimate at row 200, 2 s); now each starts where the clean run
/// does, within 0.1 s.
#[test]
fn a_missing_accelerometer_axis_does_not_hold_back_the_quasi_static_start() {
    let Some(dir) = data_dir(&["independent-sim"]) else {
        return;
    };
    let records = read(&dir.join("independent-sim/walk-v0.7-s300.csv"));
    let masked: Vec<Record> = records
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let mut r = *r;
            if k % 3 == 0 {
                for imu in r.sample.imu.iter_mut() {
                    if let Some(a) = imu.acc.take() {
                        imu.acc_partial = [None, Some(a.y), Some(a.z)];
                    }
                }
            }
            r
        })
        .collect();
    for m in ["mjls", "global", "local"] {
        let clean = run(filter(m, false).as_mut(), &records, None);
        let gappy = run(filter(m, false).as_mut(), &masked, None);
        // the foot: flat on the ground in every stance, quasi-static at once
        let foot = limbfuse_core::Segment::Foot.index();
        let (c, g) = (first_row(&clean, foot), first_row(&gappy, foot));
        println!("{m}: foot's first estimate at row {c:?} clean, {g:?} with the gaps");
        let (c, g) = (c.expect("clean start"), g.expect("a start"));
        assert!(c < 20, "{m}: {c}");
        assert!(g <= c + 10, "{m}: started at row {g}, clean at {c}");
    }
}
