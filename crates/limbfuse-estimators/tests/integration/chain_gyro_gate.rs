//! `chain`'s gyroscope rows beside an encoder (docs/CHAIN.md, "Gyroscope
//! rows beside an encoder"; issue 18, glitches): a single-sample gyroscope
//! spike within the sensor gate's range and jump bound moved the segment's
//! angle by its integral, the joint encoder that contradicted it was then
//! refused by the encoder gate and, after `GATE_LOCKOUT_S`, re-adopted with
//! the spike's error as its offset (the shared independent 1.2 m/s walk
//! with sixty +-3 rad/s spikes: knee 0.064 -> 1.273 deg RMSE). Now the
//! gyroscope row is tested while an encoder beside it reads, and refused.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::chain_ekf::ChainParams;
use limbfuse_sim::{WalkingConfig, WalkingSimulator};

use crate::chain_encoder_gate::{knee_angles_with as run, largest_difference};

/// A 12 s simulated walk at 100 Hz (short: the test runs in debug builds).
pub(crate) fn walk() -> Vec<Record> {
    WalkingSimulator::new(WalkingConfig {
        duration_s: 12.0,
        seed: 2,
        speed_mps: 1.0,
        ..WalkingConfig::default()
    })
    .unwrap()
    .collect()
}

/// The rows (from 4 s, about 0.9 s apart) and segments (thigh, shank, foot
/// in turn) of the spikes.
pub(crate) fn spikes(records: &[Record]) -> Vec<(usize, usize)> {
    let i0 = records.iter().position(|r| r.sample.t >= 4.0).unwrap();
    (0..8).map(|k| (i0 + 93 * k, 1 + k % 3)).collect()
}

/// The walk with +-3 rad/s added to one gyroscope's z axis at each spike.
pub(crate) fn spiked(clean: &[Record]) -> Vec<Record> {
    let mut out = clean.to_vec();
    for (k, &(i, seg)) in spikes(clean).iter().enumerate() {
        let g = out[i].sample.imu[seg]
            .gyr
            .as_mut()
            .expect("the simulator writes every gyroscope");
        g.z += if k % 2 == 0 { 3.0 } else { -3.0 };
    }
    out
}

#[test]
fn issue_18_a_gyro_spike_beside_an_encoder_is_refused_not_adopted() {
    let clean = walk();
    let noisy = spiked(&clean);
    let from = spikes(&clean)[0].0;
    let (reference, ref_chain) = run(&clean, ChainParams::default());
    assert_eq!(
        ref_chain.rejected_readings(),
        [0, 0, 0],
        "a clean walk refuses nothing"
    );
    let (knee, chain) = run(&noisy, ChainParams::default());
    let (knee_before, chain_before) = run(
        &noisy,
        ChainParams {
            gyro_gate: f64::INFINITY,
            ..ChainParams::default()
        },
    );
    let now = largest_difference(&knee, &reference, from);
    let before = largest_difference(&knee_before, &reference, from);
    eprintln!(
        "knee, largest difference from the clean run: {before:.3} deg without the gyro gate \
         (rejected {:?}), {now:.3} deg with it (rejected {:?})",
        chain_before.rejected_readings(),
        chain.rejected_readings()
    );
    assert!(
        before > 1.0,
        "the spikes must matter without the gate: {before}"
    );
    assert!(now < 0.05, "{now} deg");
    assert_eq!(chain.rejected_readings(), [8, 0, 0]);
}

#[test]
fn without_encoders_the_gyro_rows_are_applied_as_before() {
    let strip = |records: &[Record]| -> Vec<Record> {
        let mut out = records.to_vec();
        for r in &mut out {
            r.sample.encoder = [None; 3];
        }
        out
    };
    let noisy = strip(&spiked(&walk()));
    let (knee, chain) = run(&noisy, ChainParams::default());
    let (knee_off, _) = run(
        &noisy,
        ChainParams {
            gyro_gate: f64::INFINITY,
            ..ChainParams::default()
        },
    );
    assert_eq!(chain.rejected_readings(), [0, 0, 0]);
    assert!(knee
        .iter()
        .zip(&knee_off)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
}
