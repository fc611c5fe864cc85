//! The FES filters' gyroscope spikes (`fes::gyro_spikes`, ours;
//! docs/ROBUST_INPUT.md, "Gyroscope spikes in the FES filters"; issue 18,
//! glitches). A single-sample shank gyroscope spike within the sensor gate's
//! range and jump bound was a measurement the continuous filters took at
//! face value: on the shared independent FES trial P2-R thirty +-3 rad/s
//! spikes took `sdre` from 0.073 to 18.5 deg knee RMSE after 1 s. Now each is
//! replaced by the median of the last three readings.

use limbfuse_core::{Estimator, Record};
use limbfuse_estimators::fes::{ExtendedKneeFilter, KneeFesFilter, KneePlant, Linearisation};
use limbfuse_models::{
    ExtendedKneeModel, KneeFesModel, KneeFesParams, KneeStateOptions, KneeSubject,
};
use limbfuse_sim::knee_fes::{simulate_knee_fes, KneeFesConfig};

use crate::chain_encoder_gate::largest_difference;

/// The knee over a run, and the readings rejected.
fn knee(records: &[Record], f: &mut dyn Estimator) -> (Vec<f64>, [u64; 3]) {
    let k = records
        .iter()
        .map(|r| f.step(&r.sample).unwrap().joint[1].unwrap_or(f64::NAN))
        .collect();
    (k, f.rejected_readings())
}

#[test]
fn issue_18_fes_filters_refuse_a_shank_gyro_spike() {
    let m = KneeFesModel::new(KneeFesParams::subject(KneeSubject::P1L)).unwrap();
    let clean = simulate_knee_fes(&KneeFesConfig {
        subject: KneeSubject::P1L,
        seed: 5,
        duration_s: 8.0,
        cycles: 1,
        ..KneeFesConfig::default()
    })
    .unwrap()
    .records;
    // six spikes from 2 s, 0.6 s apart, alternating +-2 rad/s
    let rows: Vec<usize> = (0..6).map(|k| 200 + 60 * k).collect();
    let mut spiked = clean.clone();
    for (k, &i) in rows.iter().enumerate() {
        let g = spiked[i].sample.imu[2]
            .gyr
            .as_mut()
            .expect("a shank gyroscope");
        g.z += if k % 2 == 0 { 2.0 } else { -2.0 };
    }
    let all = KneeStateOptions {
        activation: true,
        disturbance: false,
        gyro_bias: true,
        acc_bias: true,
    };
    let m5 = ExtendedKneeModel::<5>::new(m, all, 0.2).unwrap();
    type Make = Box<dyn Fn(bool) -> Box<dyn Estimator>>;
    let filters: [(&str, Make); 2] = [
        (
            "sdre (paper 004)",
            Box::new(move |on| {
                let t = limbfuse_estimators::fes::knee::knee_default_tuning(Linearisation::Sdc);
                Box::new(
                    KneeFesFilter::new(KneePlant::new(m), Linearisation::Sdc, t)
                        .with_gyro_spike_test(on),
                )
            }),
        ),
        (
            "sdre + activation and bias states",
            Box::new(move |on| {
                Box::new(
                    ExtendedKneeFilter::with_default_tuning(m5, Linearisation::Sdc)
                        .with_gyro_spike_test(on),
                )
            }),
        ),
    ];
    for (name, make) in filters {
        let (reference, rejected) = knee(&clean, make(true).as_mut());
        assert_eq!(rejected, [0, 0, 0], "{name}: a clean trial refuses nothing");
        let (off_clean, _) = knee(&clean, make(false).as_mut());
        assert_eq!(largest_difference(&off_clean, &reference, 0), 0.0, "{name}");
        let (now, rejected) = knee(&spiked, make(true).as_mut());
        let (before, _) = knee(&spiked, make(false).as_mut());
        let now_off = largest_difference(&now, &reference, rows[0]);
        let before_off = largest_difference(&before, &reference, rows[0]);
        eprintln!("{name}: knee off the clean run by {before_off:.3} deg without the test, {now_off:.3} with it");
        assert_eq!(rejected, [6, 0, 0], "{name}");
        assert!(
            before_off > 0.5,
            "{name}: the spikes must matter without the test"
        );
        assert!(now_off < 0.05, "{name}: {now_off} deg");
    }
}
