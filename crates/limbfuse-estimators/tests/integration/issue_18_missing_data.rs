//! Issue 18 item 2 (missing data) on limbfuse's walking simulator: each
//! test fails without the fix it names (docs/ROBUST_INPUT.md, "Gyro
//! dropouts", "Gaps of every IMU"; docs/RESULTS.md, "Robust input").
//! Short runs (10-20 s at 100 Hz) so that they stay fast in debug builds.

use limbfuse_core::{Estimate, Estimator, Record, Segment};
use limbfuse_estimators::chain_ekf::{ChainDiag, ChainEkf, ChainGeometry, ChainParams};
use limbfuse_estimators::knee_gyro_axis::KneeGyroAxis;
use limbfuse_estimators::knee_selfalign::KneeSelfAlign;
use limbfuse_estimators::segment_kf::{CommonParams, MarkovJumpKf, MarkovJumpKfParams};
use limbfuse_sim::{KneeScenario, KneeSimulator, WalkingConfig, WalkingSimulator};

fn walking(duration_s: f64, seed: u64) -> Vec<Record> {
    WalkingSimulator::new(WalkingConfig {
        duration_s,
        seed,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect()
}

/// SplitMix64 uniform in [0, 1) (a seeded mask, reproducible).
struct SplitMix(u64);

impl SplitMix {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The angle error wrapped to [-pi, pi) (rad).
fn err(e: Option<f64>, truth: Option<f64>) -> Option<f64> {
    let d = e? - truth?;
    Some(libm::remainder(d, core::f64::consts::TAU))
}

/// RMSE (deg) of `channel(estimate, record)` over the records `keep` selects.
fn rmse(
    out: &[(Estimate, Record)],
    keep: impl Fn(f64) -> bool,
    channel: impl Fn(&Estimate, &Record) -> Option<f64>,
) -> f64 {
    let (mut sq, mut n) = (0.0, 0.0);
    for (e, r) in out {
        if keep(r.sample.t) {
            if let Some(d) = channel(e, r) {
                sq += d * d;
                n += 1.0;
            }
        }
    }
    assert!(n > 0.0, "nothing scored");
    (sq / n).sqrt().to_degrees()
}

/// The paper-002 knee scenario (random mountings) walking for `duration_s`.
fn knee_walk(duration_s: f64, seed: u64) -> Vec<Record> {
    KneeSimulator::new(KneeScenario {
        walking: WalkingConfig {
            duration_s,
            seed,
            ..KneeScenario::default().walking
        },
        ..KneeScenario::default()
    })
    .unwrap()
    .collect()
}

fn run(est: &mut dyn Estimator, records: &[Record]) -> Vec<(Estimate, Record)> {
    records
        .iter()
        .map(|r| (est.step(&r.sample).unwrap(), *r))
        .collect()
}

fn gap(records: &mut [Record], from: f64, to: f64) {
    for r in records.iter_mut() {
        if (from..to).contains(&r.sample.t) {
            for imu in r.sample.imu.iter_mut() {
                imu.acc = None;
                imu.gyr = None;
            }
        }
    }
}

/// A 1 s gap of every IMU (encoders present): before the fix the segment
/// filters held each segment's decaying rate, so the swinging leg stopped
/// in the estimate (thigh/shank/foot 23/38/48 deg RMSE over the gap in the
/// 10-minute soak). Now the stillest segment (the trunk) anchors the chain
/// and the leg follows it through the encoders.
#[test]
fn issue_18_mjls_follows_the_leg_through_the_encoders_in_a_gap_of_every_imu() {
    let mut records = walking(12.0, 5);
    gap(&mut records, 8.0, 9.0);
    let out = run(&mut MarkovJumpKf::default(), &records);
    let during = |s: Segment| {
        rmse(
            &out,
            |t| (8.0..9.0).contains(&t),
            |e, r| err(e.segment[s.index()], r.reference.segment[s.index()]),
        )
    };
    let before = |s: Segment| {
        rmse(
            &out,
            |t| (5.0..8.0).contains(&t),
            |e, r| err(e.segment[s.index()], r.reference.segment[s.index()]),
        )
    };
    for s in [Segment::Thigh, Segment::Shank, Segment::Foot] {
        let (d, b) = (during(s), before(s));
        println!("{s:?}: RMSE {b:.2} deg before the gap, {d:.2} during it");
        assert!(
            d < b + 3.0,
            "{s:?}: {d:.2} deg during the gap ({b:.2} before)"
        );
    }
}

/// Knee angle after a 1 s gap of both IMUs: before the fix the last knee
/// rate was held through the gap and the gyro angle carried the gap's
/// error until the next window re-anchored it (37 deg RMSE over the 5 s
/// after each gap in the 10-minute soak); now the held rate decays and the
/// fusion's variance grows, so the accelerometer angle takes over at once.
#[test]
fn issue_18_knee_selfalign_reanchors_after_a_gap() {
    let mut records = knee_walk(20.0, 2);
    gap(&mut records, 12.0, 13.0);
    let out = run(&mut KneeSelfAlign::default(), &records);
    let knee = |e: &Estimate, r: &Record| err(e.joint[1], r.reference.joint[1]);
    let before = rmse(&out, |t| (7.0..12.0).contains(&t), knee);
    let after = rmse(&out, |t| (14.0..19.0).contains(&t), knee);
    println!("knee RMSE {before:.2} deg before the gap, {after:.2} deg 1-6 s after it");
    // measured 1.4 -> 3.9 deg (the accelerometer angle's noise while the
    // fusion re-converges); before the fix tens of degrees
    assert!(
        after < before + 4.0,
        "{after:.2} deg after ({before:.2} before)"
    );
}

/// Chain: the stance anchor with the foot's vectors missing at random.
/// Before the fix a sample without a foot gyro or accelerometer reading
/// ended the stillness, so with half of them missing eight complete
/// readings in a row (`stance_min_s` = 0.08 s) were rare and the anchor
/// was almost never applied.
#[test]
fn issue_18_chain_stance_survives_random_foot_dropouts() {
    let clean = walking(12.0, 3);
    let mut rng = SplitMix(17);
    let masked: Vec<Record> = clean
        .iter()
        .map(|r| {
            let mut r = *r;
            let foot = &mut r.sample.imu[Segment::Foot.index()];
            if rng.uniform() < 0.5 {
                foot.gyr = None;
            }
            if rng.uniform() < 0.5 {
                foot.acc = None;
            }
            r
        })
        .collect();
    let stance = |records: &[Record]| {
        let mut ekf =
            ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
        let out = run(&mut ekf, records);
        let k = ChainDiag::Stance.index();
        out.iter().filter(|(e, _)| e.diag[k] == Some(1.0)).count() as f64 / out.len() as f64
    };
    let (c, m) = (stance(&clean), stance(&masked));
    println!("stance anchor applied on {c:.3} of the clean samples, {m:.3} with dropouts");
    assert!(c > 0.1, "clean stance share {c}");
    // with a gyro reading on half the samples the anchor applies on about half
    assert!(
        m > 0.35 * c,
        "stance share {m:.3} with dropouts vs {c:.3} clean"
    );
}

/// Chain start-up without the first sample's gyro readings: the filter
/// started the rate at 0 +- 0.1 rad/s, a moving segment a degree off for
/// seconds; now an unknown rate starts with a walking segment's rate
/// amplitude as its uncertainty.
#[test]
fn issue_18_chain_starts_without_first_gyro_readings() {
    let clean = walking(8.0, 4);
    let mut masked = clean.clone();
    for imu in masked[0].sample.imu.iter_mut() {
        imu.gyr = None;
    }
    let score = |records: &[Record]| {
        let mut ekf =
            ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
        let out = run(&mut ekf, records);
        let mut worst: f64 = 0.0;
        for i in 0..4 {
            worst = worst.max(rmse(
                &out,
                |t| (2.0..5.0).contains(&t),
                |e, r| err(e.segment[i], r.reference.segment[i]),
            ));
        }
        worst
    };
    let (c, m) = (score(&clean), score(&masked));
    println!("worst segment RMSE 2-5 s: clean {c:.3} deg, first gyros missing {m:.3} deg");
    assert!(m < c + 0.1, "{m:.3} deg vs {c:.3} clean");
}

/// Random gyro dropouts (each gyro vector missing with probability 0.5, as
/// 20 % of the cells missing makes them): the segment filters held the last
/// rate decaying at once (`e^(-tau / 0.16 s)`: 94 % of it after one 10 ms
/// sample), a bias towards zero rate at every dropout; now the rate is
/// extrapolated with its slope over the first 40 ms (99.8 % kept after one
/// sample). Mean 4-segment RMSE increase of `mjls` over the clean run.
#[test]
fn issue_18_mjls_predicts_a_briefly_missing_rate_from_its_slope() {
    let clean = walking(15.0, 7);
    let mut rng = SplitMix(23);
    let masked: Vec<Record> = clean
        .iter()
        .map(|r| {
            let mut r = *r;
            for imu in r.sample.imu.iter_mut() {
                if rng.uniform() < 0.5 {
                    imu.gyr = None;
                }
            }
            r
        })
        .collect();
    let score = |records: &[Record]| {
        // Started on the first sample (the start before 2026-12-06) in both
        // runs: this test measures the held rate, not the start. With the
        // default start (2026-12-06) both runs are better but further apart:
        // 0.651 deg clean, 0.800 masked (+23 %), because the masked run's
        // start window integrates held rates.
        let mut f = MarkovJumpKf::new(MarkovJumpKfParams {
            common: CommonParams {
                first_sample_start: true,
                ..CommonParams::default()
            },
            ..MarkovJumpKfParams::default()
        })
        .unwrap();
        let out = run(&mut f, records);
        Segment::ALL
            .iter()
            .map(|s| {
                rmse(
                    &out,
                    |t| t >= 3.0,
                    |e, r| err(e.segment[s.index()], r.reference.segment[s.index()]),
                )
            })
            .sum::<f64>()
            / 4.0
    };
    let (c, m) = (score(&clean), score(&masked));
    println!("mjls mean RMSE {c:.3} deg clean, {m:.3} with half the gyro vectors missing");
    // measured: +9 % (0.759 -> 0.827 deg); with the first-order decay +28 % (0.970)
    assert!(m < 1.18 * c, "{m:.3} deg with dropouts vs {c:.3} clean");
}

/// The shared independent walk at 1.6 m/s (`../shared/data`, skipped when
/// absent; `LIMBFUSE_DATA` overrides the path) with 20 % of the IMU cells
/// missing (seeded; a vector with a missing axis is missing, as in
/// `robust_input_study`). A sample without a foot gyro reading kept the
/// stance going but without the ankle acceleration anchor; now the chain's
/// own foot rate, still to within two sigma, stands in for the reading and
/// the anchor applies. Mean 4-segment RMSE over the clean run's.
#[test]
fn issue_18_chain_confirms_a_still_foot_from_its_own_rate() {
    let dir = std::env::var_os("LIMBFUSE_DATA")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| {
            std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"))
        });
    let path = dir.join("independent-sim/walk-v1.6-s302.csv");
    if !path.is_file() {
        println!("skipping: {} not found (set LIMBFUSE_DATA)", path.display());
        return;
    }
    let mut reader = limbfuse_io::TrialReader::open(&path).unwrap();
    let mut clean = Vec::new();
    while let Some(r) = reader.next_record().unwrap() {
        clean.push(r);
    }
    let mut rng = SplitMix(1u64.wrapping_mul(0x2545_F491_4F6C_DD1D));
    let masked: Vec<Record> = clean
        .iter()
        .map(|r| {
            let mut r = *r;
            for imu in r.sample.imu.iter_mut() {
                let acc_gone = (0..3).fold(false, |g, _| rng.uniform() < 0.2 || g);
                let gyr_gone = (0..3).fold(false, |g, _| rng.uniform() < 0.2 || g);
                if acc_gone {
                    imu.acc = None;
                }
                if gyr_gone {
                    imu.gyr = None;
                }
            }
            r
        })
        .collect();
    let score = |records: &[Record]| {
        let mut ekf =
            ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
        let out = run(&mut ekf, records);
        Segment::ALL
            .iter()
            .map(|s| {
                rmse(
                    &out,
                    |_| true,
                    |e, r| err(e.segment[s.index()], r.reference.segment[s.index()]),
                )
            })
            .sum::<f64>()
            / 4.0
    };
    let (c, m) = (score(&clean), score(&masked));
    println!("chain mean RMSE {c:.3} deg clean, {m:.3} with 20 % of the cells missing");
    // measured (default geometry, seed 1): +6.3 % (0.364 -> 0.387 deg);
    // without the stand-in +10.7 % (0.403)
    assert!(m < 1.085 * c, "{m:.3} deg with dropouts vs {c:.3} clean");
}

/// A 1 s gap of every IMU (encoders present): `chain` extrapolated its
/// rates and angular accelerations, so the whole chain turned (17 deg RMSE
/// over the gaps in the 10-minute soak). Now the trunk's rate and angular
/// acceleration are held about zero within their walking amplitudes and
/// the encoders carry the legs.
#[test]
fn issue_18_chain_holds_the_trunk_in_a_gap_of_every_imu() {
    let mut records = walking(12.0, 5);
    gap(&mut records, 8.0, 9.0);
    let mut ekf = ChainEkf::new(ChainParams::default(), ChainGeometry::default(), 9.81).unwrap();
    let out = run(&mut ekf, &records);
    let score = |s: Segment, from: f64, to: f64| {
        rmse(
            &out,
            |t| (from..to).contains(&t),
            |e, r| err(e.segment[s.index()], r.reference.segment[s.index()]),
        )
    };
    for s in Segment::ALL {
        let (d, b) = (score(s, 8.0, 9.0), score(s, 5.0, 8.0));
        println!("{s:?}: RMSE {b:.2} deg before the gap, {d:.2} during it");
        assert!(
            d < b + 3.0,
            "{s:?}: {d:.2} deg during the gap ({b:.2} before)"
        );
    }
}

/// A 0.5 s gap of every IMU inside the first identification window (ours,
/// found with `estimate --backfill`, 2026-12-04). The window's trust test
/// compared the accelerometer angle with a gyro angle integrated across
/// the gap (one trapezoid over 0.5 s), whose jump spread the difference:
/// the accelerometer angle was not trusted, the high-pass held the knee
/// about 50 deg off until the next window (the independent simulator's
/// 0.7 m/s walk: 50.4 deg RMSE over the second after identification). A gap
/// now splits the window's gyro angle: each part is compared about its own
/// constant.
#[test]
fn issue_18_knee_selfalign_trusts_the_accelerometer_after_a_gap_in_its_first_window() {
    let clean = knee_walk(12.0, 2);
    let mut gapped = clean.clone();
    gap(&mut gapped, 2.0, 2.5);
    let knee = |e: &Estimate, r: &Record| err(e.joint[1], r.reference.joint[1]);
    let mut plain = KneeSelfAlign::default();
    let reference = rmse(&run(&mut plain, &clean), |t| (5.0..10.0).contains(&t), knee);
    let mut est = KneeSelfAlign::default();
    let out = run(&mut est, &gapped);
    let after = rmse(&out, |t| (5.0..10.0).contains(&t), knee);
    println!("knee RMSE 5-10 s: {after:.2} deg with the gap, {reference:.2} without");
    let first = out.iter().find(|(e, _)| e.joint[1].is_some()).unwrap();
    assert!(est.acc_trusted(), "accelerometer angle not trusted");
    assert!(
        after < reference + 1.0,
        "{after:.2} deg with the gap ({reference:.2} without); first output at {} s",
        first.1.sample.t
    );
}

/// `knee-gyro-axis` after a 1 s gap of every IMU mid-walk (2026-12-04):
/// the relative knee rate was held constant through the gap and the PI
/// complementary filter (0.02 Hz) took tens of seconds to remove the
/// angle it had integrated (the independent simulator's 1.2 m/s walk, gap
/// at 20-21 s: 21.6 deg RMSE over the next 5 s, 3.8 over the 34 s after;
/// this simulated trial: 113 deg over 13.1-18 s).
/// Now the held rate decays (as in knee-selfalign) and, with the
/// inclination in use, the correction restarts at the first difference
/// after the gap (1.19 and 0.52 deg there).
#[test]
fn issue_18_knee_gyro_axis_reanchors_after_a_gap() {
    let clean = knee_walk(20.0, 2);
    let mut gapped = clean.clone();
    gap(&mut gapped, 12.0, 13.0);
    let knee = |e: &Estimate, r: &Record| err(e.joint[1], r.reference.joint[1]);
    let after = |records: &[Record]| {
        let out = run(&mut KneeGyroAxis::new(Default::default()).unwrap(), records);
        rmse(&out, |t| (13.1..18.0).contains(&t), knee)
    };
    // (From 0.1 s after the gap: the first difference comes a few samples
    // after it, when the accelerometer angle has its derivatives again.)
    let (with_gap, without) = (after(&gapped), after(&clean));
    println!("knee RMSE 13.1-18 s: {with_gap:.2} deg after the gap, {without:.2} without it");
    assert!(
        with_gap < without + 1.5,
        "{with_gap:.2} deg ({without:.2} without)"
    );
}

/// Knee RMSE (deg) over 12.6-18 s of the estimator `make` gives, on a 20 s
/// simulated knee walk with the rows of 12.0-12.5 s removed (a time gap)
/// and without them.
fn knee_rmse_after_a_time_gap(make: impl Fn() -> Box<dyn Estimator>) -> (f64, f64) {
    let clean = knee_walk(20.0, 2);
    let removed: Vec<Record> = clean
        .iter()
        .filter(|r| !(12.0..12.5).contains(&r.sample.t))
        .copied()
        .collect();
    let knee = |e: &Estimate, r: &Record| err(e.joint[1], r.reference.joint[1]);
    let after = |records: &[Record]| {
        let out = run(make().as_mut(), records);
        rmse(&out, |t| (12.6..18.0).contains(&t), knee)
    };
    let (with_gap, without) = (after(&removed), after(&clean));
    println!(
        "knee RMSE 12.6-18 s: {with_gap:.2} deg after 0.5 s of rows removed, {without:.2} without"
    );
    (with_gap, without)
}

/// Twenty-seventh session's generalisation audit: the same kind of gap as
/// rows removed (a time gap of 0.5 s, not empty cells). knee-gyro-axis
/// integrated the knee rate across it in one trapezoid and never
/// re-anchored, since its gap watch counted only samples without a
/// reading: the independent 0.7 m/s walk stayed 10-35 deg off for 10 s
/// (8.78 deg over the trial against 1.29 without the gap; here 19.45 deg
/// against 1.5). A step over `GAP_SPLIT_S` and `GAP_SPLIT_PERIODS` sampling
/// periods is now a gap like a dropout, and no knee angle is given until the
/// re-anchoring.
#[test]
fn knee_gyro_axis_reanchors_after_a_time_gap() {
    let (with_gap, without) =
        knee_rmse_after_a_time_gap(|| Box::new(KneeGyroAxis::new(Default::default()).unwrap()));
    assert!(
        with_gap < without + 1.0,
        "{with_gap:.2} deg ({without:.2} without)"
    );
}

/// The same for knee-selfalign: a time gap was integrated in one trapezoid
/// without the variance a dropout adds, so the accelerometer angle took ~2
/// s to pull the knee back (independent 0.7 m/s walk, 0.5 s of rows
/// removed: 30.6 deg over the 0.7 s after the gap, 8.6 over the next
/// second; here 4.87 deg against 1.29). A time gap now inflates Algorithm
/// 1's `P` as a dropout of its length does.
#[test]
fn knee_selfalign_reanchors_after_a_time_gap() {
    let (with_gap, without) =
        knee_rmse_after_a_time_gap(|| Box::new(KneeSelfAlign::new(Default::default()).unwrap()));
    assert!(
        with_gap < without + 1.0,
        "{with_gap:.2} deg ({without:.2} without)"
    );
}
