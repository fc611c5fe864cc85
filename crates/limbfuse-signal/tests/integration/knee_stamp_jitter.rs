//! Jittered time stamps against truly uneven sampling for the knee-axis
//! methods (`knee_selfalign::stamp_clock`, docs/RESULTS.md "Time stamps
//! with jitter: the knee methods' derivative").
//!
//! Found (twenty-seventh session's audit, fixed 2026-12-05): with +-3 ms of
//! stamp jitter at 100 Hz (samples regular, stamps given by a receiver),
//! the five-point rate derivative took the stamps at their word and turned
//! the jitter into noise on the angular acceleration; on the shared 0.7 m/s
//! walk the accelerometer angle was never trusted and the knee was 25 deg
//! off (1.4 deg with the stamps as recorded). Truly uneven sampling (the
//! readings taken at the uneven times) must keep the stamps.

use std::path::PathBuf;

use limbfuse_core::{Joint, Record, Segment};

use crate::invariance_unseen::{knee_rmse, run};
use limbfuse_estimators::knee_gyro_axis::{KneeGyroAxis, KneeGyroAxisParams};
use limbfuse_estimators::knee_selfalign::stamp_clock::StampClock;
use limbfuse_estimators::knee_selfalign::window::Slot;
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_io::TrialReader;
use limbfuse_signal::recording_variants::jitter_times;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

const KNEE: usize = Joint::Knee.index();

fn shared_walk(name: &str) -> Option<Vec<Record>> {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    let path = dir.join("independent-sim").join(name);
    if !path.is_file() {
        println!("skipping: {} not found (set LIMBFUSE_DATA)", path.display());
        return None;
    }
    let mut r = TrialReader::open(&path).unwrap();
    let mut out = Vec::new();
    while let Some(rec) = r.next_record().unwrap() {
        out.push(rec);
    }
    Some(out)
}

fn selfalign(rec: &[Record]) -> f64 {
    selfalign_from(rec, 10.0)
}

fn gyro_axis(rec: &[Record]) -> f64 {
    gyro_axis_from(rec, 10.0)
}

/// `knee-selfalign`'s knee RMSE (deg) from `from_s` seconds into `rec`.
fn selfalign_from(rec: &[Record], from_s: f64) -> f64 {
    let est = run(
        KneeSelfAlign::new(KneeSelfAlignParams::default()).unwrap(),
        rec,
    );
    knee_rmse(rec, &est, from_s)
}

/// `knee-gyro-axis`' knee RMSE (deg) from `from_s` seconds into `rec`.
fn gyro_axis_from(rec: &[Record], from_s: f64) -> f64 {
    let est = run(
        KneeGyroAxis::new(KneeGyroAxisParams::default()).unwrap(),
        rec,
    );
    knee_rmse(rec, &est, from_s)
}

/// The shared 0.7 m/s walk with +-3 ms of stamp jitter: both knee methods
/// within 0.1 deg of the walk as recorded (25 deg off before the fix; 0.5
/// deg allowed until the clock recovered the sensor's grid from the stamps'
/// places, 2026-12-07).
#[test]
fn jittered_stamps_of_a_regular_recording_keep_the_knee() {
    let Some(rec) = shared_walk("walk-v0.7-s300.csv") else {
        return;
    };
    let mut jittered = rec.clone();
    jitter_times(&mut jittered, 0.003, 7);
    for (name, method) in [
        ("knee-selfalign", selfalign as fn(&[Record]) -> f64),
        ("knee-gyro-axis", gyro_axis),
    ] {
        let (regular, jit) = (method(&rec), method(&jittered));
        println!("{name}: knee RMSE from 10 s {regular:.3} deg as recorded, {jit:.3} deg with +-3 ms stamp jitter");
        assert!(
            jit < regular + 0.1,
            "{name}: jittered {jit:.3} vs regular {regular:.3} deg"
        );
    }
}

/// The three shared walks with +-3 ms of stamp jitter, twenty jitter
/// patterns each: both knee methods within 0.1 deg of the walk as recorded
/// (measured since 2026-12-07, when the clock began to recover the
/// sensor's grid from the stamps' places: at most 0.032 deg over,
/// `knee-gyro-axis` on the 1.2 m/s walk; 2 deg allowed before, 1.6
/// measured)
/// (found 2026-12-06: on some patterns the clock's grid step settled a few
/// % short and the gyro angle integrated short; here the 0.7 m/s walk's
/// worst pattern gave 22.3 deg before the fix; `StampClock`'s step
/// counting).
#[test]
fn every_jitter_pattern_keeps_the_knee_on_the_shared_walks() {
    for walk in [
        "walk-v0.7-s300.csv",
        "walk-v1.2-s301.csv",
        "walk-v1.6-s302.csv",
    ] {
        let Some(rec) = shared_walk(walk) else {
            return;
        };
        let regular = [selfalign(&rec), gyro_axis(&rec)];
        let mut worst = [0.0f64; 2];
        for seed in 1..=20 {
            let mut jittered = rec.clone();
            jitter_times(&mut jittered, 0.003, seed);
            worst[0] = worst[0].max(selfalign(&jittered));
            worst[1] = worst[1].max(gyro_axis(&jittered));
        }
        println!(
            "{walk}: knee-selfalign {:.3} as recorded, worst jittered {:.3}; knee-gyro-axis {:.3}, {:.3} deg",
            regular[0], worst[0], regular[1], worst[1]
        );
        for k in 0..2 {
            assert!(
                worst[k] < regular[k] + 0.1,
                "{walk}: {worst:?} vs {regular:?}"
            );
        }
    }
}

/// Jittered stamps and lost rows together (found 2026-12-07 by a sweep of
/// the shared walks: +-30 % stamp jitter with 5 % of the rows removed at
/// random put the 0.7 m/s walk's knee 7.5-8.8 deg (`knee-selfalign`) and
/// 35-50 deg (`knee-gyro-axis`) off on two seeds of three, with 20 % removed
/// up to 12 / 73 deg; either alone was fine). The rate derivative told a
/// lost row among its five samples by their stamps' steps, which under
/// +-30 % jitter cannot tell one (a step over a lost row is 2 +- 0.6
/// periods, a step between neighbours 1 +- 0.6), and the stamp clock's
/// period, a mean of stamp steps, settled long with a fifth lost. Now the
/// clock recovers the sensor's grid from its first 64 stamps' places and
/// its count decides (`StampClock::consecutive`). Knee RMSE from 6 s (the
/// first window ends at 5.2-6.4 s), measured: within 0.65 deg of the walk
/// as recorded (the 20 % cases are what 20 % lost without jitter gives);
/// seed 1 with 5 % lost was 16.4 and 54.3 deg before.
#[test]
fn jittered_stamps_with_lost_rows_keep_the_knee() {
    let Some(rec) = shared_walk("walk-v0.7-s300.csv") else {
        return;
    };
    let regular = [selfalign_from(&rec, 6.0), gyro_axis_from(&rec, 6.0)];
    for lost in [0.05, 0.2] {
        for seed in 1..=3u64 {
            let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
            let mut thinned: Vec<Record> = rec
                .iter()
                .enumerate()
                .filter(|(k, _)| *k == 0 || lcg01(&mut state) >= lost)
                .map(|(_, r)| *r)
                .collect();
            jitter_times(&mut thinned, 0.003, seed);
            let got = [selfalign_from(&thinned, 6.0), gyro_axis_from(&thinned, 6.0)];
            println!(
                "{:.0} % lost, seed {seed}: {} of {} rows, +-3 ms: knee-selfalign {:.3} (as recorded {:.3}), knee-gyro-axis {:.3} ({:.3}) deg",
                100.0 * lost,
                thinned.len(),
                rec.len(),
                got[0],
                regular[0],
                got[1],
                regular[1]
            );
            for k in 0..2 {
                assert!(
                    got[k] < regular[k] + 1.0,
                    "{lost} lost, seed {seed}: {got:?} vs {regular:?}"
                );
            }
        }
    }
}

/// A fixed sequence of uniform numbers in [0, 1) (linear congruential).
fn lcg01(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// Readings linearly interpolated from a 1 kHz simulation at uneven times
/// `k / 100 s + U(-3, 3) ms` (the readings are where the stamps say): the
/// clock keeps the stamps, and `knee-selfalign` stays within 0.5 deg of
/// the same walk sampled regularly at 100 Hz; the same stamps on the
/// regular readings are taken as jitter (the grid, its step 10 ms).
/// (`knee-gyro-axis` loses 1.5 deg on such sampling with or without the
/// clock: docs/RESULTS.md.)
#[test]
fn truly_uneven_sampling_keeps_its_stamps() {
    let fine: Vec<Record> = WalkingSimulator::new(WalkingConfig {
        seed: 3,
        duration_s: 30.0,
        imu_rate_hz: 1000.0,
        encoder_rate_hz: 1000.0,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect();
    let regular: Vec<Record> = fine.iter().step_by(10).cloned().collect();
    let mut stamps_jittered: Vec<Record> = regular.clone();
    jitter_times(&mut stamps_jittered, 0.003, 11);
    let end = fine[fine.len() - 1].sample.t;
    let uneven: Vec<Record> = stamps_jittered
        .iter()
        .filter(|r| r.sample.t >= 0.0 && r.sample.t < end)
        .map(|r| interpolated(&fine, r.sample.t))
        .collect();
    assert_eq!(clock_over(&uneven).grid_step(), None);
    let step = clock_over(&stamps_jittered).grid_step().expect("grid");
    assert!((step - 0.01).abs() < 1e-5, "{step}");
    let (reg, unev) = (selfalign(&regular), selfalign(&uneven));
    println!("knee-selfalign: knee RMSE from 10 s {reg:.3} deg sampled regularly, {unev:.3} deg sampled unevenly");
    assert!(unev < reg + 0.5, "uneven {unev:.2} vs regular {reg:.2} deg");
}

fn clock_over(rec: &[Record]) -> StampClock {
    let mut c = StampClock::default();
    for r in rec {
        let [t, s] = [Segment::Thigh, Segment::Shank].map(|g| *r.sample.imu(g));
        c.observe(&Slot {
            t: r.sample.t,
            gyr: [t.gyr.unwrap(), s.gyr.unwrap()],
            acc: [t.acc.unwrap(), s.acc.unwrap()],
            gyr_ok: true,
            acc_ok: true,
        });
    }
    c
}

/// The thigh and shank readings and the reference knee angle of `fine`
/// (regular, 1 kHz) linearly interpolated at `t`.
fn interpolated(fine: &[Record], t: f64) -> Record {
    let dt = fine[1].sample.t - fine[0].sample.t;
    let i = ((t - fine[0].sample.t) / dt).floor() as usize;
    let (a, b) = (&fine[i], &fine[i + 1]);
    let w = (t - a.sample.t) / (b.sample.t - a.sample.t);
    let mut out = *a;
    out.sample.t = t;
    for seg in [Segment::Thigh, Segment::Shank] {
        let k = seg.index();
        let (ia, ib) = (&a.sample.imu[k], &b.sample.imu[k]);
        let o = &mut out.sample.imu[k];
        o.acc = ia.acc.zip(ib.acc).map(|(x, y)| x + (y - x) * w);
        o.gyr = ia.gyr.zip(ib.gyr).map(|(x, y)| x + (y - x) * w);
    }
    out.reference.joint[KNEE] = a.reference.joint[KNEE]
        .zip(b.reference.joint[KNEE])
        .map(|(x, y)| x + (y - x) * w);
    out
}
