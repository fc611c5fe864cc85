//! An exoskeleton controller's estimator loop (docs/STREAMING.md,
//! "Embedding an estimator in a controller"): each estimator built from its
//! parameters and the loop rate, behind the sensor gate as `limbfuse
//! estimate` runs it ([`limbfuse_core::Gated`]), stepped sample by sample
//! through the faults a real exoskeleton sees. The walking simulator stands
//! in for the sensor drivers; nothing is read or written.
//!
//! ```sh
//! cargo run --release -p limbfuse-estimators --example controller_loop
//! ```
//!
//! For each estimator and fault: the largest difference (deg) of its main
//! angle from the run without the fault, from the fault on, and the
//! readings the gate rejected. Only this loop uses `std` (printing, the
//! list of results); the loop itself is what a `no_std` controller runs.

use limbfuse_core::{Estimate, Estimator, Gated, Joint, Record, Segment, SensorRanges};
use limbfuse_estimators::chain_ekf::{ChainEkf, ChainGeometry, ChainParams};
use limbfuse_estimators::gait_events::{FootSource, GaitEvents, GaitEventsParams};
use limbfuse_estimators::knee_selfalign::{KneeSelfAlign, KneeSelfAlignParams};
use limbfuse_estimators::segment_kf::{GlobalKf, GlobalKfParams, MarkovJumpKf, MarkovJumpKfParams};
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

/// The controller's loop rate (Hz).
const RATE_HZ: f64 = 500.0;
/// When the fault happens (s).
const FAULT_T: f64 = 10.0;

/// A driver fault, applied to the records in place.
pub struct Fault {
    /// What happens.
    pub name: &'static str,
    apply: fn(&mut Vec<Record>, usize),
}

/// The faults: each at sample `i` = [`FAULT_T`].
pub const FAULTS: [Fault; 11] = [
    Fault {
        name: "none",
        apply: |_, _| {},
    },
    Fault {
        name: "knee encoder jumps by 2 pi for one sample",
        apply: |r, i| {
            r[i].sample.encoder[1] = r[i].sample.encoder[1].map(|x| x + std::f64::consts::TAU)
        },
    },
    Fault {
        name: "thigh IMU packet dropped (None)",
        apply: |r, i| r[i].sample.imu[Segment::Thigh.index()] = Default::default(),
    },
    Fault {
        name: "NaN in the shank gyro's z",
        apply: |r, i| {
            if let Some(g) = r[i].sample.imu[Segment::Shank.index()].gyr.as_mut() {
                g.z = f64::NAN;
            }
        },
    },
    Fault {
        name: "shank gyro saturated at 2000 deg/s for 20 ms",
        apply: |r, i| {
            for rec in &mut r[i..i + 10] {
                if let Some(g) = rec.sample.imu[Segment::Shank.index()].gyr.as_mut() {
                    g.z = 2000f64.to_radians();
                }
            }
        },
    },
    Fault {
        name: "a late sample (time stamp 40 % of a period late)",
        apply: |r, i| r[i].sample.t += 0.4 / RATE_HZ,
    },
    Fault {
        name: "a frame repeated (same time: refused)",
        apply: |r, i| {
            let again = r[i];
            r.insert(i + 1, again);
        },
    },
    Fault {
        name: "knee encoder stuck for 0.5 s (not a gate check)",
        apply: |r, i| {
            let stuck = r[i].sample.encoder[1];
            let n = (0.5 * RATE_HZ) as usize;
            for rec in &mut r[i..i + n] {
                rec.sample.encoder[1] = stuck;
            }
        },
    },
    Fault {
        name: "a 3 rad/s spike in the shank gyro's z for one sample (passes the gate)",
        apply: |r, i| {
            if let Some(g) = r[i].sample.imu[Segment::Shank.index()].gyr.as_mut() {
                g.z += 3.0;
            }
        },
    },
    Fault {
        name:
            "a 3 rad/s spike in the foot gyro's z for one sample, the foot flat (passes the gate)",
        apply: |r, i| {
            let foot = Segment::Foot.index();
            let flat = (i..r.len()).find(|&k| {
                (k - 5..=k + 5).all(|j| r[j].sample.imu[foot].gyr.is_some_and(|g| g.norm() < 0.5))
            });
            if let Some(g) = flat.and_then(|k| r[k].sample.imu[foot].gyr.as_mut()) {
                g.z += 3.0;
            }
        },
    },
    Fault {
        name: "reset after a fault",
        // (marked by a NaN time stamp; the loop resets on it)
        apply: |r, i| r[i].sample.t = f64::NAN,
    },
];

/// One estimator's run through one fault.
#[derive(Debug, Clone, Copy)]
pub struct FaultRun {
    /// Largest difference of the main angle from the run without the
    /// fault, from the fault on (deg; 0 for gait-events: contacts compared).
    pub max_dev_deg: f64,
    /// Time (s) after the fault when the main angle was last more than
    /// 1 deg from the run without the fault (0: never).
    pub settled_s: f64,
    /// Samples whose contact differs (gait-events).
    pub contact_diffs: usize,
    /// Samples refused (time not after the last one, or not finite).
    pub refused: usize,
    /// Readings rejected, `[gyro, acc, encoder]`.
    pub rejected: [u64; 3],
    /// Every output finite or missing.
    pub finite: bool,
}

/// 20 s of simulated walking at [`RATE_HZ`]: what the drivers deliver.
pub fn drivers() -> Vec<Record> {
    let cfg = WalkingConfig {
        imu_rate_hz: RATE_HZ,
        duration_s: 20.0,
        seed: 33,
        ..WalkingConfig::default()
    };
    WalkingSimulator::new(cfg).expect("valid config").collect()
}

/// The controller loop: step every sample, go on after a refused one,
/// reset after a fault (here: a sample refused for a non-finite time).
pub fn run_loop<E: Estimator>(filter: &mut Gated<E>, records: &[Record]) -> (Vec<Estimate>, usize) {
    let mut out = Vec::with_capacity(records.len());
    let mut estimate = Estimate::empty(0.0);
    let mut refused = 0;
    for r in records {
        match filter.step_into(&r.sample, &mut estimate) {
            Ok(()) => out.push(estimate),
            Err(_) => {
                refused += 1;
                if !r.sample.t.is_finite() {
                    filter.reset();
                }
            }
        }
    }
    (out, refused)
}

/// `filter` (made by `make`) through every fault of [`FAULTS`].
pub fn through_faults<E: Estimator>(
    make: impl Fn() -> Gated<E>,
    records: &[Record],
) -> Vec<FaultRun> {
    let (clean, _) = run_loop(&mut make(), records);
    let main = |e: &Estimate| e.joint[Joint::Knee.index()];
    FAULTS
        .iter()
        .map(|fault| {
            let mut recs = records.to_vec();
            let i = recs
                .iter()
                .position(|r| r.sample.t >= FAULT_T)
                .expect("long enough");
            (fault.apply)(&mut recs, i);
            let mut filter = make();
            let (out, refused) = run_loop(&mut filter, &recs);
            let mut run = FaultRun {
                max_dev_deg: 0.0,
                settled_s: 0.0,
                contact_diffs: 0,
                refused,
                rejected: filter.rejected_readings(),
                finite: true,
            };
            let mut j = 0;
            for e in &out {
                let all = e.segment.iter().chain(&e.joint).chain([&e.speed]);
                run.finite &= all.flatten().all(|x| x.is_finite());
                while j + 1 < clean.len() && clean[j].t < e.t - 0.5 / RATE_HZ {
                    j += 1;
                }
                if e.t < FAULT_T {
                    continue;
                }
                if let (Some(a), Some(b)) = (main(e), main(&clean[j])) {
                    let d = (a - b).abs().to_degrees();
                    run.max_dev_deg = run.max_dev_deg.max(d);
                    if d > 1.0 {
                        run.settled_s = e.t - FAULT_T;
                    }
                }
                run.contact_diffs += usize::from(e.contact != clean[j].contact);
            }
            run
        })
        .collect()
}

/// Every estimator through every fault: `(estimator, runs)`.
pub fn run() -> Vec<(&'static str, Vec<FaultRun>)> {
    let records = drivers();
    let ranges = SensorRanges::default();
    let mjls = || {
        Gated::new(
            MarkovJumpKf::new(MarkovJumpKfParams::default()).unwrap(),
            ranges,
        )
    };
    let global = || Gated::new(GlobalKf::new(GlobalKfParams::default()).unwrap(), ranges);
    // the user's height gives the segment lengths and typical IMU places
    let geometry = ChainGeometry::from_height(1.75);
    let chain = || {
        Gated::new(
            ChainEkf::new(ChainParams::default(), geometry, 9.81).unwrap(),
            ranges,
        )
    };
    // paper 002's 5 s window at the loop's rate (2500 samples at 500 Hz)
    let knee = || {
        Gated::new(
            KneeSelfAlign::new(KneeSelfAlignParams::at_rate(RATE_HZ).unwrap()).unwrap(),
            ranges,
        )
    };
    // gait-events keeps clipped gyroscope readings (`Gated` drops the
    // clipping test for it, as `limbfuse estimate` does)
    let gait = || {
        let p = GaitEventsParams::default();
        Gated::new(
            GaitEvents::new(p, [None, Some(FootSource::OwnLeg)]).unwrap(),
            ranges,
        )
    };
    vec![
        ("mjls", through_faults(mjls, &records)),
        ("global", through_faults(global, &records)),
        ("chain", through_faults(chain, &records)),
        ("knee-selfalign", through_faults(knee, &records)),
        ("gait-events", through_faults(gait, &records)),
    ]
}

fn main() {
    println!("estimator | fault | max knee difference (deg) | within 1 deg after (s) | contact samples differing | refused | rejected [gyro, acc, encoder]");
    for (name, runs) in run() {
        for (fault, r) in FAULTS.iter().zip(runs) {
            println!(
                "{name} | {} | {:.3} | {:.2} | {} | {} | {:?}{}",
                fault.name,
                r.max_dev_deg,
                r.settled_s,
                r.contact_diffs,
                r.refused,
                r.rejected,
                if r.finite { "" } else { " | NON-FINITE OUTPUT" }
            );
        }
    }
}
